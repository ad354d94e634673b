//! One module per pass, each paired with its WGSL file in `shaders/`.

pub mod surface;
