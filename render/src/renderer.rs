//! [`Renderer`]: every pass, and the order they draw a [`Scene`] in.

use crate::camera::Camera;
use crate::frame::{FrameBinding, FrameUniform};
use crate::passes::surface::{SurfaceMode, SurfacePass};
use crate::{GpuSurface, Gpu, TargetFormats};

/// What one frame shows.
#[derive(Clone, Copy, Debug)]
pub struct Scene<'a> {
    pub camera: Camera,
    pub surface: Option<&'a GpuSurface>,
    pub mode: SurfaceMode,
    /// Clear colour, linear RGBA.
    pub background: [f64; 4],
}

impl<'a> Scene<'a> {
    /// A scene with the default background.
    pub fn new(camera: Camera, surface: Option<&'a GpuSurface>, mode: SurfaceMode) -> Self {
        Scene { camera, surface, mode, background: [0.16, 0.17, 0.19, 1.0] }
    }
}

/// The colour (multisampled when MSAA is on) and depth attachments for one viewport size.
#[derive(Debug)]
pub struct Attachments {
    pub width: u32,
    pub height: u32,
    /// Present only with MSAA: the multisampled colour target resolved into the final view.
    pub msaa: Option<wgpu::TextureView>,
    pub depth: wgpu::TextureView,
}

impl Attachments {
    pub fn new(device: &wgpu::Device, targets: &TargetFormats, width: u32, height: u32) -> Self {
        let size = wgpu::Extent3d { width: width.max(1), height: height.max(1), depth_or_array_layers: 1 };
        let texture = |label, format, samples| {
            device
                .create_texture(&wgpu::TextureDescriptor {
                    label: Some(label),
                    size,
                    mip_level_count: 1,
                    sample_count: samples,
                    dimension: wgpu::TextureDimension::D2,
                    format,
                    usage: wgpu::TextureUsages::RENDER_ATTACHMENT,
                    view_formats: &[],
                })
                .create_view(&Default::default())
        };
        let msaa = (targets.samples > 1).then(|| texture("msaa colour", targets.color, targets.samples));
        let depth = texture("depth", targets.depth, targets.samples);
        Attachments { width, height, msaa, depth }
    }
}

/// All passes, created once per device and target format.
#[derive(Debug)]
pub struct Renderer {
    pub targets: TargetFormats,
    frame: FrameBinding,
    surface: SurfacePass,
}

impl Renderer {
    pub fn new(gpu: &Gpu, targets: TargetFormats) -> Self {
        let frame = FrameBinding::new(&gpu.device);
        let surface = SurfacePass::new(&gpu.device, &gpu.queue, &targets, &frame.layout);
        Renderer { targets, frame, surface }
    }

    /// Records one frame of `scene` into `encoder`, drawing into `target` (the window's
    /// surface texture or an off-screen texture of the colour format).
    pub fn encode(
        &mut self,
        queue: &wgpu::Queue,
        encoder: &mut wgpu::CommandEncoder,
        target: &wgpu::TextureView,
        attachments: &Attachments,
        scene: &Scene<'_>,
    ) {
        self.frame.update(queue, &FrameUniform::new(&scene.camera, attachments.width, attachments.height));
        self.surface.set_mode(queue, scene.mode);
        let [r, g, b, a] = scene.background;
        let (view, resolve_target) = match &attachments.msaa {
            Some(msaa) => (msaa, Some(target)),
            None => (target, None),
        };
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("frame"),
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view,
                depth_slice: None,
                resolve_target,
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Clear(wgpu::Color { r, g, b, a }),
                    store: wgpu::StoreOp::Store,
                },
            })],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: &attachments.depth,
                depth_ops: Some(wgpu::Operations { load: wgpu::LoadOp::Clear(1.0), store: wgpu::StoreOp::Discard }),
                stencil_ops: None,
            }),
            timestamp_writes: None,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        if let Some(surface) = scene.surface {
            self.surface.draw(&mut pass, &self.frame.bind_group, surface);
        }
    }
}
