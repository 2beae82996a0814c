//! Voxelization of round cones: conservative cover and occupancy fractions.

mod conservative;
mod occupancy;
