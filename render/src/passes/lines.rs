//! The lines pass (`shaders/lines.wgsl`): segments of a given pixel width, anti-aliased, as
//! instanced screen-space quads. Two pipelines share one instance buffer: depth-tested lines
//! (the wireframe, curves and combs lying on the surface) and lines on top of everything (the
//! cage).

use super::{InstanceBuffer, InstancedPipeline, instanced_pipeline, shader_module};
use crate::overlay::LineSegment;
use bytemuck::{Pod, Zeroable};

/// Mirror of WGSL `LineInstance` in `shaders/lines.wgsl` (a per-instance vertex input).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct LineInstance {
    pub a: [f32; 3],
    pub width_px: f32,
    pub b: [f32; 3],
    pub color: [f32; 4],
}

impl From<&LineSegment> for LineInstance {
    fn from(l: &LineSegment) -> Self {
        let width_px = if l.width_px.is_finite() { l.width_px.max(0.0) } else { 1.0 };
        LineInstance { a: l.a.to_array(), width_px, b: l.b.to_array(), color: l.color }
    }
}

/// Pipelines and instance buffer of the lines pass.
#[derive(Debug)]
pub struct LinesPass {
    depth_tested: wgpu::RenderPipeline,
    on_top: wgpu::RenderPipeline,
    instances: InstanceBuffer,
    staging: Vec<LineInstance>,
    /// Instances `0..surface_count` are depth-tested, the rest on top.
    surface_count: u32,
}

impl LinesPass {
    pub fn new(device: &wgpu::Device, targets: &crate::TargetFormats, frame_layout: &wgpu::BindGroupLayout) -> Self {
        let module = shader_module(device, "lines.wgsl", include_str!("../../../shaders/lines.wgsl"));
        let attributes = wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32, 2 => Float32x3, 3 => Float32x4];
        let pipeline = |label, vertex_entry, depth_compare| {
            instanced_pipeline(
                device,
                targets,
                InstancedPipeline {
                    label,
                    module: &module,
                    vertex_entry,
                    layouts: &[Some(frame_layout)],
                    instance_stride: std::mem::size_of::<LineInstance>() as u64,
                    attributes: &attributes,
                    depth_compare,
                },
            )
        };
        LinesPass {
            depth_tested: pipeline("surface lines", "vs_surface", wgpu::CompareFunction::LessEqual),
            on_top: pipeline("on-top lines", "vs_on_top", wgpu::CompareFunction::Always),
            instances: InstanceBuffer::new("line instances"),
            staging: Vec::new(),
            surface_count: 0,
        }
    }

    /// Uploads this frame's lines.
    pub fn prepare(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        surface: &[LineSegment],
        on_top: &[LineSegment],
    ) {
        self.staging.clear();
        self.staging.extend(surface.iter().chain(on_top).map(LineInstance::from));
        self.surface_count = surface.len() as u32;
        self.instances.write(device, queue, &self.staging);
    }

    /// Draws the depth-tested lines (after the surface).
    pub fn draw_surface_lines(&self, pass: &mut wgpu::RenderPass<'_>, frame: &wgpu::BindGroup) {
        self.draw(pass, frame, &self.depth_tested, 0..self.surface_count);
    }

    /// Draws the lines that are always visible.
    pub fn draw_on_top_lines(&self, pass: &mut wgpu::RenderPass<'_>, frame: &wgpu::BindGroup) {
        self.draw(pass, frame, &self.on_top, self.surface_count..self.instances.len());
    }

    fn draw(
        &self,
        pass: &mut wgpu::RenderPass<'_>,
        frame: &wgpu::BindGroup,
        pipeline: &wgpu::RenderPipeline,
        range: std::ops::Range<u32>,
    ) {
        let Some(buffer) = self.instances.buffer() else { return };
        if range.is_empty() {
            return;
        }
        pass.set_pipeline(pipeline);
        pass.set_bind_group(0, frame, &[]);
        pass.set_vertex_buffer(0, buffer.slice(..));
        pass.draw(0..6, range);
    }

    /// How many instance buffers were created (for tests).
    pub fn buffer_creations(&self) -> u64 {
        self.instances.creations()
    }
}
