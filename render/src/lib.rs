//! Taut's display: the wgpu passes that draw a surface shaded, as zebra stripes, in curvature
//! colour, by draft angle or with highlight lines ([`analysis`]), with overlays, into a window or off screen (`docs/rendering.md`).
//!
//! Long-lived objects (pipelines, layouts: the `passes`) are apart from per-frame data (the
//! [`FrameUniform`](frame::FrameUniform), uploaded buffers). One WGSL file per pass lives in
//! `shaders/`, each prefixed at load time with `shaders/common.wgsl`; every `#[repr(C)]` mirror
//! names its WGSL struct. The same [`Renderer`] draws the editor's viewport and the command
//! line's pictures.

pub mod analysis;
pub mod buffers;
pub mod cache;
pub mod camera;
pub mod colormap;
pub mod display;
pub mod frame;
pub mod gpu;
pub mod offscreen;
pub mod overlay;
pub mod passes;
pub mod picture;
pub mod reference_images;
pub mod renderer;

pub use buffers::{Changes, GpuSurface, SurfaceBuffers, SurfaceVertex};
pub use cache::{ShownMesh, SurfaceCache};
pub use camera::{Camera, StandardView};
pub use display::DisplayFrame;
pub use gpu::{AdapterPreference, Gpu};
pub use overlay::{CageControls, CageSelection, CombStyle, Legend, LineSegment, OverlayData, PointMark, PointStyle};
pub use renderer::{Renderer, Scene};

/// What can go wrong on the display side.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum RenderError {
    /// No adapter at all: the message says what to install.
    #[error("{0}")]
    NoAdapter(String),
    /// The adapter refused a device.
    #[error("the GPU refused to open a device: {0}")]
    Device(String),
    /// Reading a picture back or writing it failed.
    #[error("{0}")]
    Output(String),
}

/// The shared WGSL prelude (`shaders/common.wgsl`).
pub const COMMON_WGSL: &str = include_str!("../../shaders/common.wgsl");

/// A pass's WGSL with the shared prelude in front, as it is compiled.
pub fn shader_source(pass: &str) -> String {
    format!("{COMMON_WGSL}\n{pass}")
}

/// Formats and sample count of the targets every pass draws into.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct TargetFormats {
    pub color: wgpu::TextureFormat,
    pub depth: wgpu::TextureFormat,
    pub samples: u32,
}

impl TargetFormats {
    /// 4× MSAA when the adapter supports it for `color`, else none.
    pub fn for_adapter(adapter: &wgpu::Adapter, color: wgpu::TextureFormat) -> Self {
        let depth = wgpu::TextureFormat::Depth32Float;
        let supports = |f: wgpu::TextureFormat| adapter.get_texture_format_features(f).flags.sample_count_supported(4);
        let samples = if supports(color) && supports(depth) { 4 } else { 1 };
        TargetFormats { color, depth, samples }
    }
}
