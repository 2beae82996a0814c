//! Acceleration structures: BVH over links and spline segments.
