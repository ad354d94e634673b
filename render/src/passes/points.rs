//! The points pass (`shaders/points.wgsl`): discs and rings of a given pixel radius around
//! points, anti-aliased, always on top (the cage's vertices).

use super::{InstanceBuffer, InstancedPipeline, instanced_pipeline, shader_module};
use crate::overlay::{PointMark, PointStyle};
use bytemuck::{Pod, Zeroable};

/// Mirror of WGSL `PointInstance` in `shaders/points.wgsl` (a per-instance vertex input).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct PointInstance {
    pub position: [f32; 3],
    pub radius_px: f32,
    pub color: [f32; 4],
    /// Ring thickness in pixels; 0 for a filled disc.
    pub ring_px: f32,
}

impl From<&PointMark> for PointInstance {
    fn from(p: &PointMark) -> Self {
        let radius_px = if p.radius_px.is_finite() { p.radius_px.max(0.0) } else { 4.0 };
        let ring_px = match p.style {
            PointStyle::Filled => 0.0,
            PointStyle::Ring => (0.3 * radius_px).max(1.5),
        };
        PointInstance { position: p.position.to_array(), radius_px, color: p.color, ring_px }
    }
}

/// Pipeline and instance buffer of the points pass.
#[derive(Debug)]
pub struct PointsPass {
    pipeline: wgpu::RenderPipeline,
    instances: InstanceBuffer,
    staging: Vec<PointInstance>,
}

impl PointsPass {
    pub fn new(device: &wgpu::Device, targets: &crate::TargetFormats, frame_layout: &wgpu::BindGroupLayout) -> Self {
        let module = shader_module(device, "points.wgsl", include_str!("../../../shaders/points.wgsl"));
        let pipeline = instanced_pipeline(
            device,
            targets,
            InstancedPipeline {
                label: "points",
                module: &module,
                vertex_entry: "vs_main",
                layouts: &[Some(frame_layout)],
                instance_stride: std::mem::size_of::<PointInstance>() as u64,
                attributes: &wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32, 2 => Float32x4, 3 => Float32],
                depth_compare: wgpu::CompareFunction::Always,
            },
        );
        PointsPass { pipeline, instances: InstanceBuffer::new("point instances"), staging: Vec::new() }
    }

    /// Uploads this frame's marks.
    pub fn prepare(&mut self, device: &wgpu::Device, queue: &wgpu::Queue, points: &[PointMark]) {
        self.staging.clear();
        self.staging.extend(points.iter().map(PointInstance::from));
        self.instances.write(device, queue, &self.staging);
    }

    pub fn draw(&self, pass: &mut wgpu::RenderPass<'_>, frame: &wgpu::BindGroup) {
        let Some(buffer) = self.instances.buffer() else { return };
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, frame, &[]);
        pass.set_vertex_buffer(0, buffer.slice(..));
        pass.draw(0..6, 0..self.instances.len());
    }

    /// How many instance buffers were created (for tests).
    pub fn buffer_creations(&self) -> u64 {
        self.instances.creations()
    }
}
