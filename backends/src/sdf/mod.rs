//! SDF output: level models, doors, lifts and worlds in the three flavours users have
//! (generator.md §2 and §3).

pub mod crowd;
pub mod doors;
pub mod level;
pub mod lifts;
pub mod navmesh;
#[rustfmt::skip]
mod template_trees;
pub mod world;
pub mod xml;

/// The simulator a world is written for.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Flavour {
    /// Gazebo classic (`building_map_generator gazebo` before 2024-05).
    Classic,
    /// Ignition Gazebo, Fortress era (`building_map_generator ignition` before 2024-05).
    Ignition,
    /// gz-sim, Harmonic onwards (`building_map_generator gazebo` today).
    Gz,
}

pub use world::world_files_untextured;
