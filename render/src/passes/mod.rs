//! One module per pass, each paired with its WGSL file in `shaders/`, plus what the overlay
//! passes share: a growable instance buffer and the pipeline they all use (instanced quads,
//! alpha blended, no depth writes).

pub mod lines;
pub mod overlay2d;
pub mod points;
pub mod reference_images;
pub mod surface;

use bytemuck::Pod;

/// A vertex buffer of per-instance records, rewritten in place every frame and re-created only
/// when the records no longer fit (it then grows to the next power of two, so a layer growing
/// a little at a time does not re-create it each frame).
#[derive(Debug)]
pub struct InstanceBuffer {
    label: &'static str,
    buffer: Option<wgpu::Buffer>,
    capacity: u64,
    len: u32,
    creations: u64,
}

impl InstanceBuffer {
    pub fn new(label: &'static str) -> Self {
        InstanceBuffer { label, buffer: None, capacity: 0, len: 0, creations: 0 }
    }

    /// Replaces the records; an empty slice leaves nothing to draw.
    pub fn write<T: Pod>(&mut self, device: &wgpu::Device, queue: &wgpu::Queue, records: &[T]) {
        self.len = records.len() as u32;
        let bytes: &[u8] = bytemuck::cast_slice(records);
        if bytes.is_empty() {
            return;
        }
        if self.buffer.is_none() || bytes.len() as u64 > self.capacity {
            self.capacity = (bytes.len() as u64).next_power_of_two().max(256);
            self.buffer = Some(device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(self.label),
                size: self.capacity,
                usage: wgpu::BufferUsages::VERTEX | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            }));
            self.creations += 1;
        }
        if let Some(buffer) = &self.buffer {
            queue.write_buffer(buffer, 0, bytes);
        }
    }

    /// Number of records written last.
    pub fn len(&self) -> u32 {
        self.len
    }

    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// The buffer, when there is something to draw.
    pub fn buffer(&self) -> Option<&wgpu::Buffer> {
        self.buffer.as_ref().filter(|_| self.len > 0)
    }

    /// How many GPU buffers were created (for tests and statistics).
    pub fn creations(&self) -> u64 {
        self.creations
    }
}

/// What differs between the overlay pipelines.
pub(crate) struct InstancedPipeline<'a> {
    pub label: &'a str,
    pub module: &'a wgpu::ShaderModule,
    pub vertex_entry: &'a str,
    pub layouts: &'a [Option<&'a wgpu::BindGroupLayout>],
    pub instance_stride: u64,
    pub attributes: &'a [wgpu::VertexAttribute],
    pub depth_compare: wgpu::CompareFunction,
}

/// A pipeline drawing 6 vertices (a quad) per instance, alpha blended over what is there, with
/// no depth writes; `fs_main` is the fragment entry.
pub(crate) fn instanced_pipeline(
    device: &wgpu::Device,
    targets: &crate::TargetFormats,
    desc: InstancedPipeline<'_>,
) -> wgpu::RenderPipeline {
    let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label: Some(desc.label),
        bind_group_layouts: desc.layouts,
        immediate_size: 0,
    });
    device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: Some(desc.label),
        layout: Some(&layout),
        vertex: wgpu::VertexState {
            module: desc.module,
            entry_point: Some(desc.vertex_entry),
            compilation_options: Default::default(),
            buffers: &[Some(wgpu::VertexBufferLayout {
                array_stride: desc.instance_stride,
                step_mode: wgpu::VertexStepMode::Instance,
                attributes: desc.attributes,
            })],
        },
        primitive: wgpu::PrimitiveState { cull_mode: None, ..Default::default() },
        depth_stencil: Some(wgpu::DepthStencilState {
            format: targets.depth,
            depth_write_enabled: Some(false),
            depth_compare: Some(desc.depth_compare),
            stencil: Default::default(),
            bias: Default::default(),
        }),
        multisample: wgpu::MultisampleState { count: targets.samples, ..Default::default() },
        fragment: Some(wgpu::FragmentState {
            module: desc.module,
            entry_point: Some("fs_main"),
            compilation_options: Default::default(),
            targets: &[Some(wgpu::ColorTargetState {
                format: targets.color,
                blend: Some(wgpu::BlendState::ALPHA_BLENDING),
                write_mask: wgpu::ColorWrites::ALL,
            })],
        }),
        multiview_mask: None,
        cache: None,
    })
}

/// Compiles a pass's WGSL with the shared prelude in front.
pub(crate) fn shader_module(device: &wgpu::Device, label: &str, pass_wgsl: &str) -> wgpu::ShaderModule {
    device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some(label),
        source: wgpu::ShaderSource::Wgsl(crate::shader_source(pass_wgsl).into()),
    })
}

#[cfg(test)]
mod tests {
    use crate::shader_source;
    use naga::valid::{Capabilities, ValidationFlags, Validator};

    /// Every pass's WGSL, found by listing `shaders/` so a new file cannot be forgotten, parses
    /// and validates with the shared prelude in front (which validates the prelude with it).
    #[test]
    fn every_shader_parses_and_validates() {
        let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../shaders");
        let mut names: Vec<_> = std::fs::read_dir(&dir)
            .unwrap()
            .map(|entry| entry.unwrap().path())
            .filter(|p| p.extension().is_some_and(|e| e == "wgsl"))
            .collect();
        names.sort();
        let passes: Vec<_> = names.iter().filter(|p| p.file_name().is_some_and(|n| n != "common.wgsl")).collect();
        assert!(names.len() > passes.len(), "shaders/common.wgsl is missing");
        assert!(passes.len() >= 4, "expected the surface, lines, points and overlay2d shaders: {names:?}");
        for path in passes {
            let source = shader_source(&std::fs::read_to_string(path).unwrap());
            let module = naga::front::wgsl::parse_str(&source)
                .unwrap_or_else(|e| panic!("{}:\n{}", path.display(), e.emit_to_string(&source)));
            Validator::new(ValidationFlags::all(), Capabilities::default())
                .validate(&module)
                .unwrap_or_else(|e| panic!("{}:\n{}", path.display(), e.emit_to_string(&source)));
        }
    }
}
