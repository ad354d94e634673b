//! The window and what goes to the GPU each frame.

pub mod window;
