//! The per-frame uniform every pass reads at `@group(0) @binding(0)` (`shaders/common.wgsl`).

use crate::camera::Camera;
use bytemuck::{Pod, Zeroable};
use wgpu::util::DeviceExt;

/// A clipping plane that cuts nothing.
pub const NO_CLIP: [f32; 4] = [0.0, 0.0, 0.0, 1.0];

/// Mirror of WGSL `Frame` in `shaders/common.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct FrameUniform {
    pub view_from_world: [[f32; 4]; 4],
    pub clip_from_view: [[f32; 4]; 4],
    pub camera_position: [f32; 4],
    pub viewport: [f32; 4],
    /// The clipping plane `(n, d)`: what lies where `n·p > d` is cut away; `n = 0` cuts nothing.
    pub clip_plane: [f32; 4],
}

impl FrameUniform {
    /// The uniform for a camera looking at a viewport of `width × height` pixels.
    pub fn new(camera: &Camera, width: u32, height: u32) -> Self {
        let aspect = width as f32 / height.max(1) as f32;
        let eye = camera.eye();
        FrameUniform {
            view_from_world: camera.view_from_world().to_cols_array_2d(),
            clip_from_view: camera.clip_from_view(aspect).to_cols_array_2d(),
            camera_position: [eye.x, eye.y, eye.z, 1.0],
            viewport: [width as f32, height as f32, 1.0 / width.max(1) as f32, 1.0 / height.max(1) as f32],
            clip_plane: NO_CLIP,
        }
    }
}

/// The frame uniform's buffer and bind group; one per viewport.
#[derive(Debug)]
pub struct FrameBinding {
    pub layout: wgpu::BindGroupLayout,
    pub buffer: wgpu::Buffer,
    pub bind_group: wgpu::BindGroup,
}

impl FrameBinding {
    pub fn new(device: &wgpu::Device) -> Self {
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("frame"),
            entries: &[wgpu::BindGroupLayoutEntry {
                binding: 0,
                visibility: wgpu::ShaderStages::VERTEX_FRAGMENT,
                ty: wgpu::BindingType::Buffer {
                    ty: wgpu::BufferBindingType::Uniform,
                    has_dynamic_offset: false,
                    min_binding_size: wgpu::BufferSize::new(std::mem::size_of::<FrameUniform>() as u64),
                },
                count: None,
            }],
        });
        let buffer = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("frame"),
            contents: bytemuck::bytes_of(&FrameUniform::zeroed()),
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
        });
        let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("frame"),
            layout: &layout,
            entries: &[wgpu::BindGroupEntry { binding: 0, resource: buffer.as_entire_binding() }],
        });
        FrameBinding { layout, buffer, bind_group }
    }

    pub fn update(&self, queue: &wgpu::Queue, uniform: &FrameUniform) {
        queue.write_buffer(&self.buffer, 0, bytemuck::bytes_of(uniform));
    }
}
