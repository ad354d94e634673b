//! The reference-image pass (`shaders/reference_image.wgsl`): each picture a textured quad on its
//! plane or facing the camera, alpha blended at its opacity; those behind the model are drawn
//! before the surface, those in front after it (neither writes or tests depth, so a picture is
//! wholly behind or wholly over the model, as Alias's canvas planes and Blender's references
//! are).
//!
//! A picture's texture (with its mipmaps, so a large picture seen small does not shimmer) is
//! uploaded once per [`PictureKey`] and kept while a frame still draws it; the per-image values
//! are one small uniform slot each, rewritten every frame.

use super::shader_module;
use crate::reference_images::{PictureKey, ReferenceQuad};
use bytemuck::{Pod, Zeroable};
use std::collections::HashMap;
use wgpu::util::DeviceExt;

/// Mirror of WGSL `ReferenceImage` in `shaders/reference_image.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct ReferenceImageUniform {
    pub centre: [f32; 4],
    pub right: [f32; 4],
    pub up: [f32; 4],
    pub billboard: [f32; 4],
}

impl From<&ReferenceQuad<'_>> for ReferenceImageUniform {
    fn from(q: &ReferenceQuad<'_>) -> Self {
        let [hw, hh] = q.half_size;
        let c = q.centre;
        let (right, up, facing) = match q.axes {
            Some((r, u)) => (r * hw, u * hh, 0.0),
            None => (glam::Vec3::ZERO, glam::Vec3::ZERO, 1.0),
        };
        let (sin, cos) = q.rotation.sin_cos();
        ReferenceImageUniform {
            centre: [c.x, c.y, c.z, q.opacity],
            right: [right.x, right.y, right.z, facing],
            up: [up.x, up.y, up.z, 0.0],
            billboard: [hw, hh, cos, sin],
        }
    }
}

/// A picture on the GPU.
#[derive(Debug)]
struct GpuPicture {
    bind_group: wgpu::BindGroup,
}

/// Pipeline, uploaded pictures and the per-image uniform slots.
#[derive(Debug)]
pub struct ReferenceImagesPass {
    pipeline: wgpu::RenderPipeline,
    uniform_layout: wgpu::BindGroupLayout,
    picture_layout: wgpu::BindGroupLayout,
    sampler: wgpu::Sampler,
    /// One slot per image drawn, `stride` bytes apart (the device's uniform offset alignment).
    uniforms: Option<(wgpu::Buffer, wgpu::BindGroup, u64)>,
    stride: u64,
    pictures: HashMap<PictureKey, GpuPicture>,
    /// This frame's draws: slot, picture and whether it is in front.
    draws: Vec<(u32, PictureKey, bool)>,
    uploads: u64,
}

impl ReferenceImagesPass {
    pub fn new(device: &wgpu::Device, targets: &crate::TargetFormats, frame_layout: &wgpu::BindGroupLayout) -> Self {
        let module =
            shader_module(device, "reference_image.wgsl", include_str!("../../../shaders/reference_image.wgsl"));
        let uniform_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("reference image"),
            entries: &[wgpu::BindGroupLayoutEntry {
                binding: 0,
                visibility: wgpu::ShaderStages::VERTEX_FRAGMENT,
                ty: wgpu::BindingType::Buffer {
                    ty: wgpu::BufferBindingType::Uniform,
                    has_dynamic_offset: true,
                    min_binding_size: wgpu::BufferSize::new(std::mem::size_of::<ReferenceImageUniform>() as u64),
                },
                count: None,
            }],
        });
        let picture_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("reference picture"),
            entries: &[
                wgpu::BindGroupLayoutEntry {
                    binding: 0,
                    visibility: wgpu::ShaderStages::FRAGMENT,
                    ty: wgpu::BindingType::Texture {
                        sample_type: wgpu::TextureSampleType::Float { filterable: true },
                        view_dimension: wgpu::TextureViewDimension::D2,
                        multisampled: false,
                    },
                    count: None,
                },
                wgpu::BindGroupLayoutEntry {
                    binding: 1,
                    visibility: wgpu::ShaderStages::FRAGMENT,
                    ty: wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Filtering),
                    count: None,
                },
            ],
        });
        let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("reference images"),
            bind_group_layouts: &[Some(frame_layout), Some(&uniform_layout), Some(&picture_layout)],
            immediate_size: 0,
        });
        let pipeline = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("reference images"),
            layout: Some(&layout),
            vertex: wgpu::VertexState {
                module: &module,
                entry_point: Some("vs_main"),
                compilation_options: Default::default(),
                buffers: &[],
            },
            primitive: wgpu::PrimitiveState { cull_mode: None, ..Default::default() },
            depth_stencil: Some(wgpu::DepthStencilState {
                format: targets.depth,
                depth_write_enabled: Some(false),
                depth_compare: Some(wgpu::CompareFunction::Always),
                stencil: Default::default(),
                bias: Default::default(),
            }),
            multisample: wgpu::MultisampleState { count: targets.samples, ..Default::default() },
            fragment: Some(wgpu::FragmentState {
                module: &module,
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
        });
        let sampler = device.create_sampler(&wgpu::SamplerDescriptor {
            label: Some("reference picture"),
            mag_filter: wgpu::FilterMode::Linear,
            min_filter: wgpu::FilterMode::Linear,
            mipmap_filter: wgpu::MipmapFilterMode::Linear,
            ..Default::default()
        });
        let alignment = device.limits().min_uniform_buffer_offset_alignment as u64;
        let stride = (std::mem::size_of::<ReferenceImageUniform>() as u64).div_ceil(alignment) * alignment;
        ReferenceImagesPass {
            pipeline,
            uniform_layout,
            picture_layout,
            sampler,
            uniforms: None,
            stride,
            pictures: HashMap::new(),
            draws: Vec::new(),
            uploads: 0,
        }
    }

    /// Uploads the pictures not yet on the GPU, drops those no longer drawn, and writes this
    /// frame's placements.
    pub fn prepare(&mut self, device: &wgpu::Device, queue: &wgpu::Queue, quads: &[ReferenceQuad<'_>]) {
        self.draws.clear();
        self.pictures.retain(|key, _| quads.iter().any(|q| q.picture.key == *key));
        if quads.is_empty() {
            return;
        }
        for q in quads {
            if !self.pictures.contains_key(&q.picture.key) {
                let bind_group = self.upload(device, queue, &q.picture.pixels);
                self.pictures.insert(q.picture.key.clone(), GpuPicture { bind_group });
            }
        }
        let needed = self.stride * quads.len() as u64;
        if self.uniforms.as_ref().is_none_or(|(_, _, capacity)| *capacity < needed) {
            let capacity = needed.next_power_of_two();
            let buffer = device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("reference images"),
                size: capacity,
                usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            });
            let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("reference images"),
                layout: &self.uniform_layout,
                entries: &[wgpu::BindGroupEntry {
                    binding: 0,
                    resource: wgpu::BindingResource::Buffer(wgpu::BufferBinding {
                        buffer: &buffer,
                        offset: 0,
                        size: wgpu::BufferSize::new(std::mem::size_of::<ReferenceImageUniform>() as u64),
                    }),
                }],
            });
            self.uniforms = Some((buffer, bind_group, capacity));
        }
        let mut bytes = vec![0u8; needed as usize];
        for (slot, q) in quads.iter().enumerate() {
            let at = slot * self.stride as usize;
            let uniform = ReferenceImageUniform::from(q);
            bytes[at..at + std::mem::size_of::<ReferenceImageUniform>()].copy_from_slice(bytemuck::bytes_of(&uniform));
            self.draws.push((slot as u32, q.picture.key.clone(), q.in_front));
        }
        if let Some((buffer, _, _)) = &self.uniforms {
            queue.write_buffer(buffer, 0, &bytes);
        }
    }

    /// The picture as an sRGB texture with its mipmaps (each level half the last, averaged).
    fn upload(&mut self, device: &wgpu::Device, queue: &wgpu::Queue, pixels: &image::RgbaImage) -> wgpu::BindGroup {
        let (width, height) = pixels.dimensions();
        let mut data = pixels.as_raw().clone();
        let mut level = pixels.clone();
        let mut levels = 1;
        while level.width() > 1 || level.height() > 1 {
            let (w, h) = ((level.width() / 2).max(1), (level.height() / 2).max(1));
            level = image::imageops::resize(&level, w, h, image::imageops::FilterType::Triangle);
            data.extend_from_slice(level.as_raw());
            levels += 1;
        }
        let texture = device.create_texture_with_data(
            queue,
            &wgpu::TextureDescriptor {
                label: Some("reference picture"),
                size: wgpu::Extent3d { width, height, depth_or_array_layers: 1 },
                mip_level_count: levels,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format: wgpu::TextureFormat::Rgba8UnormSrgb,
                usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
                view_formats: &[],
            },
            wgpu::util::TextureDataOrder::LayerMajor,
            &data,
        );
        self.uploads += 1;
        let view = texture.create_view(&Default::default());
        device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("reference picture"),
            layout: &self.picture_layout,
            entries: &[
                wgpu::BindGroupEntry { binding: 0, resource: wgpu::BindingResource::TextureView(&view) },
                wgpu::BindGroupEntry { binding: 1, resource: wgpu::BindingResource::Sampler(&self.sampler) },
            ],
        })
    }

    /// Draws the pictures behind the model (call before the surface) or in front of it (after).
    pub fn draw(&self, pass: &mut wgpu::RenderPass<'_>, frame: &wgpu::BindGroup, in_front: bool) {
        let Some((_, uniforms, _)) = &self.uniforms else { return };
        let mut bound = false;
        for (slot, key, front) in &self.draws {
            let Some(picture) = self.pictures.get(key).filter(|_| *front == in_front) else { continue };
            if !bound {
                pass.set_pipeline(&self.pipeline);
                pass.set_bind_group(0, frame, &[]);
                bound = true;
            }
            pass.set_bind_group(1, uniforms, &[(*slot as u64 * self.stride) as u32]);
            pass.set_bind_group(2, &picture.bind_group, &[]);
            pass.draw(0..6, 0..1);
        }
    }

    /// How many pictures were uploaded so far (for tests: once per picture, not per frame).
    pub fn uploads(&self) -> u64 {
        self.uploads
    }
}
