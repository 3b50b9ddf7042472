//! Shared by the sim crate's integration tests.
pub mod gen;
pub mod warehouse;
