//! Camera, shading, opaque and transparent compositing, PNG output.
