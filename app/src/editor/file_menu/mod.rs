//! The File menu's work: new cages, making a cage from a mesh, the STEP export.

pub mod cage_from_mesh;
pub mod cage_job;
pub mod new_primitive;
pub mod primitives;
pub mod step_export;
