//! The surface pass (`shaders/surface.wgsl`): shaded, zebra, curvature colour, draft angle or
//! highlight lines (the last two in [`crate::analysis`]).

use crate::analysis::{DRAFT_BELOW, DRAFT_NEGATIVE, DRAFT_POSITIVE, LightTubes, Pull};
use crate::colormap::{self, ColorMap};
use crate::{SurfaceVertex, shader_source};
use bytemuck::{Pod, Zeroable};
use wgpu::util::DeviceExt;

/// The ghost's default colour: a translucent amber (linear), apart from the clay grey, the
/// stripes and both colour maps.
pub const GHOST: [f32; 4] = [0.95, 0.45, 0.08, 0.38];

/// What the surface shows.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SurfaceMode {
    Shaded,
    Zebra {
        stripes: f32,
        angle_degrees: f32,
        width_ratio: f32,
    },
    Curvature {
        map: ColorMap,
        min: f32,
        max: f32,
    },
    /// The draft angle against `pull`, with faces within `angle_degrees` of 0 in their own band.
    Draft {
        pull: Pull,
        angle_degrees: f32,
    },
    /// Highlight lines of light tubes given in display coordinates.
    Highlight(LightTubes),
}

/// Mirror of WGSL `SurfaceStyle` in `shaders/surface.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct SurfaceStyle {
    pub mode: u32,
    pub stripes: f32,
    pub stripe_angle: f32,
    pub stripe_width: f32,
    pub range_min: f32,
    pub range_max: f32,
    pub draft_sin: f32,
    pub tube_count: f32,
    pub base_color: [f32; 4],
    pub stripe_dark: [f32; 4],
    pub stripe_light: [f32; 4],
    pub pull: [f32; 4],
    pub tube_direction: [f32; 4],
    pub tube_plane: [f32; 4],
    pub draft_positive: [f32; 4],
    pub draft_below: [f32; 4],
    pub draft_negative: [f32; 4],
}

/// An sRGB colour as the linear RGBA the shader mixes (the target encodes it back).
fn linear([r, g, b]: [u8; 3]) -> [f32; 4] {
    let f = |c: u8| {
        let c = c as f32 / 255.0;
        if c <= 0.04045 { c / 12.92 } else { ((c + 0.055) / 1.055).powf(2.4) }
    };
    [f(r), f(g), f(b), 1.0]
}

impl SurfaceStyle {
    pub fn new(mode: SurfaceMode) -> Self {
        let mut style = SurfaceStyle {
            mode: 0,
            stripes: 8.0,
            stripe_angle: 0.0,
            stripe_width: 0.5,
            range_min: -1.0,
            range_max: 1.0,
            draft_sin: 0.0,
            tube_count: 0.0,
            // A neutral clay grey, linear.
            base_color: [0.50, 0.52, 0.56, 1.0],
            stripe_dark: [0.0, 0.0, 0.0, 1.0],
            stripe_light: [1.0, 1.0, 1.0, 1.0],
            pull: [0.0, 0.0, 1.0, 0.0],
            tube_direction: [1.0, 0.0, 0.0, 1.0],
            tube_plane: [0.0, 0.0, 1.0, 1.0],
            draft_positive: linear(DRAFT_POSITIVE),
            draft_below: linear(DRAFT_BELOW),
            draft_negative: linear(DRAFT_NEGATIVE),
        };
        match mode {
            SurfaceMode::Shaded => {}
            SurfaceMode::Zebra { stripes, angle_degrees, width_ratio } => {
                style.mode = 1;
                style.stripes = stripes.max(0.5);
                style.stripe_angle = angle_degrees.to_radians();
                style.stripe_width = width_ratio.clamp(0.02, 0.98);
            }
            SurfaceMode::Curvature { min, max, .. } => {
                style.mode = 2;
                style.range_min = min;
                style.range_max = max;
            }
            SurfaceMode::Draft { pull, angle_degrees } => {
                style.mode = 4;
                style.pull = match pull {
                    Pull::Direction(p) => {
                        let p = p.try_normalize().unwrap_or(glam::DVec3::Z).as_vec3();
                        [p.x, p.y, p.z, 0.0]
                    }
                    Pull::View => [0.0, 0.0, 1.0, 1.0],
                };
                style.draft_sin = angle_degrees.clamp(0.0, 89.0).to_radians().sin();
            }
            SurfaceMode::Highlight(tubes) => {
                style.mode = 5;
                let (e, h) = (tubes.axis().as_vec3(), tubes.plane_normal().as_vec3());
                let spacing = if tubes.spacing > 0.0 && tubes.spacing.is_finite() { tubes.spacing } else { 1.0 };
                style.tube_direction = [e.x, e.y, e.z, spacing as f32];
                style.tube_plane = [h.x, h.y, h.z, tubes.height as f32];
                style.tube_count = tubes.count as f32;
                // Light clay under dark lines.
                style.base_color = [0.72, 0.73, 0.75, 1.0];
                style.stripe_dark = [0.01, 0.01, 0.03, 1.0];
            }
        }
        style
    }
}

/// Pipeline, style uniform and colour-map textures of the surface pass, and its ghost: a second
/// surface drawn translucent over the first (the editor's compare view, the original mesh under
/// a fitted cage), blended and depth-tested without writing depth.
#[derive(Debug)]
pub struct SurfacePass {
    pipeline: wgpu::RenderPipeline,
    style_buffer: wgpu::Buffer,
    bind_groups: [wgpu::BindGroup; 2],
    map: ColorMap,
    ghost_pipeline: wgpu::RenderPipeline,
    ghost_style_buffer: wgpu::Buffer,
    ghost_bind_group: wgpu::BindGroup,
    second_ghost_style_buffer: wgpu::Buffer,
    second_ghost_bind_group: wgpu::BindGroup,
}

/// The style of a ghost of colour `color` (linear RGBA; alpha is its opacity).
fn ghost_style(color: [f32; 4]) -> SurfaceStyle {
    SurfaceStyle { mode: 3, base_color: color, ..SurfaceStyle::new(SurfaceMode::Shaded) }
}

impl SurfacePass {
    pub fn new(
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        targets: &crate::TargetFormats,
        frame_layout: &wgpu::BindGroupLayout,
    ) -> Self {
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("surface.wgsl"),
            source: wgpu::ShaderSource::Wgsl(shader_source(include_str!("../../../shaders/surface.wgsl")).into()),
        });
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("surface style"),
            entries: &[
                wgpu::BindGroupLayoutEntry {
                    binding: 0,
                    visibility: wgpu::ShaderStages::FRAGMENT,
                    ty: wgpu::BindingType::Buffer {
                        ty: wgpu::BufferBindingType::Uniform,
                        has_dynamic_offset: false,
                        min_binding_size: None,
                    },
                    count: None,
                },
                wgpu::BindGroupLayoutEntry {
                    binding: 1,
                    visibility: wgpu::ShaderStages::FRAGMENT,
                    ty: wgpu::BindingType::Texture {
                        sample_type: wgpu::TextureSampleType::Float { filterable: true },
                        view_dimension: wgpu::TextureViewDimension::D2,
                        multisampled: false,
                    },
                    count: None,
                },
                wgpu::BindGroupLayoutEntry {
                    binding: 2,
                    visibility: wgpu::ShaderStages::FRAGMENT,
                    ty: wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Filtering),
                    count: None,
                },
            ],
        });
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("surface"),
            bind_group_layouts: &[Some(frame_layout), Some(&layout)],
            immediate_size: 0,
        });
        let pipeline_for = |ghost: bool| {
            device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                label: Some(if ghost { "surface ghost" } else { "surface" }),
                layout: Some(&pipeline_layout),
                vertex: wgpu::VertexState {
                    module: &module,
                    entry_point: Some("vs_main"),
                    compilation_options: Default::default(),
                    buffers: &[Some(wgpu::VertexBufferLayout {
                        array_stride: std::mem::size_of::<SurfaceVertex>() as u64,
                        step_mode: wgpu::VertexStepMode::Vertex,
                        attributes: &wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x3, 2 => Float32],
                    })],
                },
                primitive: wgpu::PrimitiveState { cull_mode: None, ..Default::default() },
                depth_stencil: Some(wgpu::DepthStencilState {
                    format: targets.depth,
                    // A ghost is seen through: it tests against the surface but hides nothing.
                    depth_write_enabled: Some(!ghost),
                    depth_compare: Some(if ghost {
                        wgpu::CompareFunction::LessEqual
                    } else {
                        wgpu::CompareFunction::Less
                    }),
                    stencil: Default::default(),
                    // Push the surface back a little so lines drawn on it win the depth test.
                    bias: wgpu::DepthBiasState { constant: 2, slope_scale: 1.0, clamp: 0.0 },
                }),
                multisample: wgpu::MultisampleState { count: targets.samples, ..Default::default() },
                fragment: Some(wgpu::FragmentState {
                    module: &module,
                    entry_point: Some("fs_main"),
                    compilation_options: Default::default(),
                    targets: &[Some(wgpu::ColorTargetState {
                        format: targets.color,
                        blend: ghost.then_some(wgpu::BlendState::ALPHA_BLENDING),
                        write_mask: wgpu::ColorWrites::ALL,
                    })],
                }),
                multiview_mask: None,
                cache: None,
            })
        };
        let pipeline = pipeline_for(false);
        let ghost_pipeline = pipeline_for(true);
        let style_buffer = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("surface style"),
            contents: bytemuck::bytes_of(&SurfaceStyle::new(SurfaceMode::Shaded)),
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
        });
        let sampler = device.create_sampler(&wgpu::SamplerDescriptor {
            label: Some("colour map"),
            mag_filter: wgpu::FilterMode::Linear,
            min_filter: wgpu::FilterMode::Linear,
            ..Default::default()
        });
        let group = |buffer: &wgpu::Buffer, map: ColorMap| {
            let view = colormap_texture(device, queue, map).create_view(&Default::default());
            device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("surface style"),
                layout: &layout,
                entries: &[
                    wgpu::BindGroupEntry { binding: 0, resource: buffer.as_entire_binding() },
                    wgpu::BindGroupEntry { binding: 1, resource: wgpu::BindingResource::TextureView(&view) },
                    wgpu::BindGroupEntry { binding: 2, resource: wgpu::BindingResource::Sampler(&sampler) },
                ],
            })
        };
        let bind_groups = [ColorMap::Diverging, ColorMap::Sequential].map(|map| group(&style_buffer, map));
        let ghost_style_buffer = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("surface ghost style"),
            contents: bytemuck::bytes_of(&ghost_style(GHOST)),
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
        });
        let ghost_bind_group = group(&ghost_style_buffer, ColorMap::Sequential);
        let second_ghost_style_buffer = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("surface second ghost style"),
            contents: bytemuck::bytes_of(&ghost_style(GHOST)),
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
        });
        let second_ghost_bind_group = group(&second_ghost_style_buffer, ColorMap::Sequential);
        SurfacePass {
            pipeline,
            style_buffer,
            bind_groups,
            map: ColorMap::Diverging,
            ghost_pipeline,
            ghost_style_buffer,
            ghost_bind_group,
            second_ghost_style_buffer,
            second_ghost_bind_group,
        }
    }

    /// Sets the colour of the ghost (linear RGBA, alpha its opacity).
    pub fn set_ghost(&mut self, queue: &wgpu::Queue, color: [f32; 4]) {
        queue.write_buffer(&self.ghost_style_buffer, 0, bytemuck::bytes_of(&ghost_style(color)));
    }

    /// Sets the colour of the second ghost.
    pub fn set_second_ghost(&mut self, queue: &wgpu::Queue, color: [f32; 4]) {
        queue.write_buffer(&self.second_ghost_style_buffer, 0, bytemuck::bytes_of(&ghost_style(color)));
    }

    /// Draws a second surface as a translucent ghost over what is drawn.
    pub fn draw_ghost(&self, pass: &mut wgpu::RenderPass<'_>, frame: &wgpu::BindGroup, mesh: &crate::GpuSurface) {
        self.draw_ghost_with(pass, frame, mesh, &self.ghost_bind_group);
    }

    /// Draws another surface as a ghost in the second ghost's colour.
    pub fn draw_second_ghost(
        &self,
        pass: &mut wgpu::RenderPass<'_>,
        frame: &wgpu::BindGroup,
        mesh: &crate::GpuSurface,
    ) {
        self.draw_ghost_with(pass, frame, mesh, &self.second_ghost_bind_group);
    }

    fn draw_ghost_with(
        &self,
        pass: &mut wgpu::RenderPass<'_>,
        frame: &wgpu::BindGroup,
        mesh: &crate::GpuSurface,
        style: &wgpu::BindGroup,
    ) {
        if mesh.index_count == 0 {
            return;
        }
        pass.set_pipeline(&self.ghost_pipeline);
        pass.set_bind_group(0, frame, &[]);
        pass.set_bind_group(1, style, &[]);
        pass.set_vertex_buffer(0, mesh.vertices.slice(..));
        pass.set_index_buffer(mesh.indices.slice(..), wgpu::IndexFormat::Uint32);
        pass.draw_indexed(0..mesh.index_count, 0, 0..1);
    }

    /// Sets what the next draws show.
    pub fn set_mode(&mut self, queue: &wgpu::Queue, mode: SurfaceMode) {
        if let SurfaceMode::Curvature { map, .. } = mode {
            self.map = map;
        }
        queue.write_buffer(&self.style_buffer, 0, bytemuck::bytes_of(&SurfaceStyle::new(mode)));
    }

    /// Draws a surface whose vertex and index buffers are bound by the caller's `mesh`.
    pub fn draw(&self, pass: &mut wgpu::RenderPass<'_>, frame: &wgpu::BindGroup, mesh: &crate::GpuSurface) {
        if mesh.index_count == 0 {
            return;
        }
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, frame, &[]);
        let group = match self.map {
            ColorMap::Diverging => &self.bind_groups[0],
            ColorMap::Sequential => &self.bind_groups[1],
        };
        pass.set_bind_group(1, group, &[]);
        pass.set_vertex_buffer(0, mesh.vertices.slice(..));
        pass.set_index_buffer(mesh.indices.slice(..), wgpu::IndexFormat::Uint32);
        pass.draw_indexed(0..mesh.index_count, 0, 0..1);
    }
}

/// A colour map as a 256 × 1 sRGB texture (shared with the legend).
pub fn colormap_texture(device: &wgpu::Device, queue: &wgpu::Queue, map: ColorMap) -> wgpu::Texture {
    let table = map.table();
    device.create_texture_with_data(
        queue,
        &wgpu::TextureDescriptor {
            label: Some("colour map"),
            size: wgpu::Extent3d { width: colormap::SIZE as u32, height: 1, depth_or_array_layers: 1 },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: wgpu::TextureFormat::Rgba8UnormSrgb,
            usage: wgpu::TextureUsages::TEXTURE_BINDING,
            view_formats: &[],
        },
        wgpu::util::TextureDataOrder::LayerMajor,
        bytemuck::cast_slice(&table),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The Rust mirror and the WGSL struct have the same size, so no field is read from the
    /// wrong place (naga lays the WGSL struct out as the GPU does).
    #[test]
    fn the_style_mirror_matches_the_wgsl_layout() {
        let source = shader_source(include_str!("../../../shaders/surface.wgsl"));
        let module = naga::front::wgsl::parse_str(&source).unwrap();
        let mut layouter = naga::proc::Layouter::default();
        layouter.update(module.to_ctx()).unwrap();
        let (handle, _) = module.types.iter().find(|(_, t)| t.name.as_deref() == Some("SurfaceStyle")).unwrap();
        assert_eq!(layouter[handle].size as usize, std::mem::size_of::<SurfaceStyle>());
    }

    #[test]
    fn the_analysis_modes_set_their_uniforms() {
        let draft = SurfaceStyle::new(SurfaceMode::Draft {
            pull: Pull::Direction(glam::DVec3::new(0.0, 0.0, 4.0)),
            angle_degrees: 30.0,
        });
        assert_eq!((draft.mode, draft.pull), (4, [0.0, 0.0, 1.0, 0.0]));
        assert!((draft.draft_sin - 0.5).abs() < 1e-6);
        let view = SurfaceStyle::new(SurfaceMode::Draft { pull: Pull::View, angle_degrees: 3.0 });
        assert_eq!(view.pull[3], 1.0);
        let tubes = LightTubes { spacing: 0.4, count: 7, ..LightTubes::default() };
        let lines = SurfaceStyle::new(SurfaceMode::Highlight(tubes));
        assert_eq!((lines.mode, lines.tube_count), (5, 7.0));
        assert_eq!(lines.tube_direction, [1.0, 0.0, 0.0, 0.4]);
        assert_eq!(lines.tube_plane, [0.0, 0.0, 1.0, 1.5]);
    }
}
