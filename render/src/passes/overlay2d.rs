//! The 2D overlay pass (`shaders/overlay2d.wgsl`): rectangles in pixels drawn over everything,
//! and the curvature [`Legend`] laid out with them.
//!
//! Text uses the public-domain 8 × 8 bitmap font of the `font8x8` crate (its basic table,
//! ASCII 32–126), uploaded once as an R8 atlas and drawn at an integer scale on whole pixels
//! with nearest texels, so digits stay crisp; Greek letters of quantity names show as their
//! Latin look-alikes, other characters the font lacks as `?`.

use super::{InstanceBuffer, InstancedPipeline, instanced_pipeline, shader_module};
use crate::colormap::ColorMap;
use crate::overlay::{Legend, format_number};
use bytemuck::{Pod, Zeroable};
use wgpu::util::DeviceExt;

/// Mirror of WGSL `Rect2d` in `shaders/overlay2d.wgsl` (a per-instance vertex input).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct Rect2d {
    pub min_px: [f32; 2],
    pub max_px: [f32; 2],
    pub uv_min: [f32; 2],
    pub uv_max: [f32; 2],
    pub color: [f32; 4],
    /// [`RECT_SOLID`], [`RECT_COLORMAP`] or [`RECT_GLYPH`].
    pub kind: u32,
}

pub const RECT_SOLID: u32 = 0;
/// The colour map at `t = uv.y`.
pub const RECT_COLORMAP: u32 = 1;
/// The glyph atlas at `uv` (in texels).
pub const RECT_GLYPH: u32 = 2;

/// A rectangle in pixels, origin at the top left.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PixelRect {
    pub min: [f32; 2],
    pub max: [f32; 2],
}

impl PixelRect {
    fn solid(self, color: [f32; 4]) -> Rect2d {
        Rect2d { min_px: self.min, max_px: self.max, uv_min: [0.0; 2], uv_max: [0.0; 2], color, kind: RECT_SOLID }
    }
}

/// A line of text: its top-left corner and the size of a glyph cell, in pixels.
#[derive(Clone, Debug, PartialEq)]
pub struct TextRun {
    pub text: String,
    pub origin: [f32; 2],
    pub glyph_px: f32,
}

impl TextRun {
    /// The box the text covers.
    pub fn bounds(&self) -> PixelRect {
        let [x, y] = self.origin;
        PixelRect { min: [x, y], max: [x + self.text.chars().count() as f32 * self.glyph_px, y + self.glyph_px] }
    }

    fn glyphs(&self, color: [f32; 4], out: &mut Vec<Rect2d>) {
        let [x, y] = self.origin;
        for (i, ch) in self.text.chars().enumerate() {
            if ch == ' ' {
                continue;
            }
            let min = [x + i as f32 * self.glyph_px, y];
            let cell = glyph_cell(ch);
            out.push(Rect2d {
                min_px: min,
                max_px: [min[0] + self.glyph_px, min[1] + self.glyph_px],
                uv_min: cell,
                uv_max: [cell[0] + GLYPH as f32, cell[1] + GLYPH as f32],
                color,
                kind: RECT_GLYPH,
            });
        }
    }
}

/// Where a legend's parts go in a viewport.
#[derive(Clone, Debug, PartialEq)]
pub struct LegendLayout {
    /// Translucent dark panel behind everything, so the legend reads on any background.
    pub panel: PixelRect,
    /// The colour-map bar: the map's end (`max`) at the top, its start (`min`) at the bottom.
    pub bar: PixelRect,
    pub title: TextRun,
    /// Value and label of each tick: `min`, 0 when inside the range and clear of the ends, `max`.
    pub labels: Vec<(f64, TextRun)>,
    pub ticks: Vec<PixelRect>,
}

const PANEL: [f32; 4] = [0.0, 0.0, 0.0, 0.8];
const TEXT: [f32; 4] = [0.92, 0.92, 0.92, 1.0];
const BAR_FRAME: [f32; 4] = [0.75, 0.75, 0.75, 1.0];
/// Significant digits of the tick labels.
const LABEL_DIGITS: usize = 3;

/// Lays a legend out at the right of a `width × height` viewport: a bar 12 px wide per glyph
/// scale (24 px at 2×) and 60 % of the height, labels right-aligned to its left, the title
/// above. Glyphs are drawn 2× (16 px) from 320 px of height, 1× below.
pub fn legend_layout(legend: &Legend, width: u32, height: u32) -> LegendLayout {
    let (w, h) = (width as f32, height as f32);
    let s = if height >= 600 { 2.0 } else { 1.0 };
    let g = GLYPH as f32 * s;
    let (margin, pad) = (6.0 * s, 4.0 * s);
    let bar_max_x = w - margin - pad;
    let bar_min_y = (0.2 * h).round() + g;
    let bar = PixelRect { min: [bar_max_x - 12.0 * s, bar_min_y], max: [bar_max_x, bar_min_y + (0.6 * h).round()] };
    let bar_h = bar.max[1] - bar.min[1];
    let label_right = bar.min[0] - 6.0 * s;

    let mut values = vec![(0.0f32, legend.min)];
    if legend.min < 0.0 && legend.max > 0.0 {
        let t = (-legend.min / (legend.max - legend.min)) as f32;
        // Only where it does not collide with the end labels.
        if t * bar_h >= g + 2.0 && (1.0 - t) * bar_h >= g + 2.0 {
            values.push((t, 0.0));
        }
    }
    values.push((1.0, legend.max));
    let (mut labels, mut ticks) = (Vec::new(), Vec::new());
    for (t, value) in values {
        let y = (bar.max[1] - t * bar_h).round();
        let text = format_number(value, LABEL_DIGITS);
        let x = label_right - text.chars().count() as f32 * g;
        labels.push((value, TextRun { text, origin: [x, (y - g / 2.0).round()], glyph_px: g }));
        let tick_y = (y - s / 2.0).floor().clamp(bar.min[1], bar.max[1] - s);
        ticks.push(PixelRect { min: [bar.min[0] - 4.0 * s, tick_y], max: [bar.min[0], tick_y + s] });
    }
    // A long title is drawn at the small size so the panel stays narrow.
    let title_glyph = if legend.title.chars().count() as f32 * g > 0.3 * w { GLYPH as f32 } else { g };
    let title_width = legend.title.chars().count() as f32 * title_glyph;
    let title = TextRun {
        text: legend.title.clone(),
        origin: [bar.max[0] - title_width, bar.min[1] - g / 2.0 - 4.0 * s - title_glyph],
        glyph_px: title_glyph,
    };
    let left = labels.iter().map(|(_, l)| l.origin[0]).fold(title.origin[0], f32::min);
    let panel =
        PixelRect { min: [left - pad, title.origin[1] - pad], max: [bar.max[0] + pad, bar.max[1] + g / 2.0 + pad] };
    LegendLayout { panel, bar, title, labels, ticks }
}

/// How many pixels at the right of a `width × height` viewport the legend covers, its margin
/// included: the model is framed in the rest so the legend never covers it.
pub fn legend_margin(legend: &Legend, width: u32, height: u32) -> u32 {
    let layout = legend_layout(legend, width, height);
    let s = if height >= 600 { 2.0 } else { 1.0 };
    (width as f32 - layout.panel.min[0] + 6.0 * s).ceil().clamp(0.0, width as f32 * 0.5) as u32
}

impl LegendLayout {
    /// The rectangles that draw it, back to front.
    pub fn rects(&self) -> Vec<Rect2d> {
        let mut out = vec![self.panel.solid(PANEL)];
        let frame = PixelRect {
            min: [self.bar.min[0] - 1.0, self.bar.min[1] - 1.0],
            max: [self.bar.max[0] + 1.0, self.bar.max[1] + 1.0],
        };
        out.push(frame.solid(BAR_FRAME));
        out.push(Rect2d {
            min_px: self.bar.min,
            max_px: self.bar.max,
            uv_min: [0.0, 1.0],
            uv_max: [0.0, 0.0],
            color: [1.0; 4],
            kind: RECT_COLORMAP,
        });
        out.extend(self.ticks.iter().map(|t| t.solid(TEXT)));
        self.title.glyphs(TEXT, &mut out);
        for (_, label) in &self.labels {
            label.glyphs(TEXT, &mut out);
        }
        out
    }
}

/// Pixels of a glyph's side in the font.
const GLYPH: u32 = 8;
/// Glyph cells across the atlas.
const ATLAS_COLUMNS: u32 = 16;
const FIRST_CHAR: u32 = 32;
const LAST_CHAR: u32 = 126;

/// The atlas's top-left texel of a character's cell. The Greek letters of Taut's quantity
/// names are drawn as their Latin look-alikes (κ as k, λ as l, τ as t); other characters the
/// font lacks as `?`.
fn glyph_cell(ch: char) -> [f32; 2] {
    let ch = match ch {
        'κ' => 'k',
        'λ' => 'l',
        'τ' => 't',
        'β' => 'b',
        other => other,
    };
    let code = if (FIRST_CHAR..=LAST_CHAR).contains(&(ch as u32)) { ch as u32 } else { '?' as u32 };
    let i = code - FIRST_CHAR;
    [((i % ATLAS_COLUMNS) * GLYPH) as f32, ((i / ATLAS_COLUMNS) * GLYPH) as f32]
}

/// The glyph atlas: width, height, and one coverage byte a texel (255 inked, 0 not).
pub fn glyph_atlas() -> (u32, u32, Vec<u8>) {
    let count = LAST_CHAR - FIRST_CHAR + 1;
    let (width, height) = (ATLAS_COLUMNS * GLYPH, count.div_ceil(ATLAS_COLUMNS) * GLYPH);
    let mut texels = vec![0u8; (width * height) as usize];
    for code in FIRST_CHAR..=LAST_CHAR {
        // `BASIC_LEGACY` is the table `BASIC_FONTS` is made of, indexed by code point (the
        // workspace builds font8x8 without its `unicode` feature).
        let rows = font8x8::legacy::BASIC_LEGACY[code as usize];
        let [cx, cy] = glyph_cell(char::from_u32(code).unwrap_or('?')).map(|c| c as u32);
        for (y, row) in rows.iter().enumerate() {
            for x in 0..GLYPH {
                // Bit 0 is the leftmost pixel of a row.
                if row >> x & 1 == 1 {
                    texels[((cy + y as u32) * width + cx + x) as usize] = 255;
                }
            }
        }
    }
    (width, height, texels)
}

/// Pipeline, glyph atlas and colour maps of the 2D overlay pass.
#[derive(Debug)]
pub struct Overlay2dPass {
    pipeline: wgpu::RenderPipeline,
    /// One per colour map, both with the atlas.
    bind_groups: [wgpu::BindGroup; 2],
    map: ColorMap,
    instances: InstanceBuffer,
}

impl Overlay2dPass {
    pub fn new(
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        targets: &crate::TargetFormats,
        frame_layout: &wgpu::BindGroupLayout,
    ) -> Self {
        let module = shader_module(device, "overlay2d.wgsl", include_str!("../../../shaders/overlay2d.wgsl"));
        let texture_entry = |binding| wgpu::BindGroupLayoutEntry {
            binding,
            visibility: wgpu::ShaderStages::FRAGMENT,
            ty: wgpu::BindingType::Texture {
                sample_type: wgpu::TextureSampleType::Float { filterable: true },
                view_dimension: wgpu::TextureViewDimension::D2,
                multisampled: false,
            },
            count: None,
        };
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("overlay 2d"),
            entries: &[
                texture_entry(0),
                wgpu::BindGroupLayoutEntry {
                    binding: 1,
                    visibility: wgpu::ShaderStages::FRAGMENT,
                    ty: wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Filtering),
                    count: None,
                },
                texture_entry(2),
            ],
        });
        let pipeline = instanced_pipeline(
            device,
            targets,
            InstancedPipeline {
                label: "overlay 2d",
                module: &module,
                vertex_entry: "vs_main",
                layouts: &[Some(frame_layout), Some(&layout)],
                instance_stride: std::mem::size_of::<Rect2d>() as u64,
                attributes: &wgpu::vertex_attr_array![
                    0 => Float32x2, 1 => Float32x2, 2 => Float32x2, 3 => Float32x2, 4 => Float32x4, 5 => Uint32
                ],
                depth_compare: wgpu::CompareFunction::Always,
            },
        );
        let (width, height, texels) = glyph_atlas();
        let atlas = device
            .create_texture_with_data(
                queue,
                &wgpu::TextureDescriptor {
                    label: Some("glyph atlas"),
                    size: wgpu::Extent3d { width, height, depth_or_array_layers: 1 },
                    mip_level_count: 1,
                    sample_count: 1,
                    dimension: wgpu::TextureDimension::D2,
                    format: wgpu::TextureFormat::R8Unorm,
                    usage: wgpu::TextureUsages::TEXTURE_BINDING,
                    view_formats: &[],
                },
                wgpu::util::TextureDataOrder::LayerMajor,
                &texels,
            )
            .create_view(&Default::default());
        let sampler = device.create_sampler(&wgpu::SamplerDescriptor {
            label: Some("colour map"),
            mag_filter: wgpu::FilterMode::Linear,
            min_filter: wgpu::FilterMode::Linear,
            ..Default::default()
        });
        let bind_groups = [ColorMap::Diverging, ColorMap::Sequential].map(|map| {
            let view = super::surface::colormap_texture(device, queue, map).create_view(&Default::default());
            device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("overlay 2d"),
                layout: &layout,
                entries: &[
                    wgpu::BindGroupEntry { binding: 0, resource: wgpu::BindingResource::TextureView(&view) },
                    wgpu::BindGroupEntry { binding: 1, resource: wgpu::BindingResource::Sampler(&sampler) },
                    wgpu::BindGroupEntry { binding: 2, resource: wgpu::BindingResource::TextureView(&atlas) },
                ],
            })
        });
        Overlay2dPass { pipeline, bind_groups, map: ColorMap::Diverging, instances: InstanceBuffer::new("2d rects") }
    }

    /// Lays out and uploads this frame's legend (none: nothing to draw).
    pub fn prepare(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        legend: Option<&Legend>,
        width: u32,
        height: u32,
    ) {
        let rects = legend.map(|l| {
            self.map = l.map;
            legend_layout(l, width, height).rects()
        });
        self.instances.write(device, queue, rects.as_deref().unwrap_or(&[]));
    }

    pub fn draw(&self, pass: &mut wgpu::RenderPass<'_>, frame: &wgpu::BindGroup) {
        let Some(buffer) = self.instances.buffer() else { return };
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, frame, &[]);
        let group = match self.map {
            ColorMap::Diverging => &self.bind_groups[0],
            ColorMap::Sequential => &self.bind_groups[1],
        };
        pass.set_bind_group(1, group, &[]);
        pass.set_vertex_buffer(0, buffer.slice(..));
        pass.draw(0..6, 0..self.instances.len());
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn legend(min: f64, max: f64) -> Legend {
        Legend { map: ColorMap::Diverging, min, max, title: "Mean H".into() }
    }

    #[test]
    fn the_atlas_holds_every_printable_ascii_glyph() {
        let (w, h, texels) = glyph_atlas();
        assert_eq!((w, h), (128, 48));
        let ink = |ch: char| {
            let [cx, cy] = glyph_cell(ch).map(|c| c as u32);
            (0..64).filter(|k| texels[((cy + k / 8) * w + cx + k % 8) as usize] > 0).count()
        };
        assert_eq!(ink(' '), 0);
        for ch in ['0', '1', '8', '-', '.', 'e', 'H', 'K', '~'] {
            assert!(ink(ch) > 3, "{ch}");
        }
        // '1' and '7' differ; κ reads as k; unknown characters are '?'.
        assert_ne!(ink('1'), ink('7'));
        assert_eq!(glyph_cell('κ'), glyph_cell('k'));
        assert_eq!(glyph_cell('∂'), glyph_cell('?'));
        // The top row of '-' is empty and its middle row is inked (bit order and row order).
        let [cx, cy] = glyph_cell('-').map(|c| c as u32);
        assert!((0..8).all(|x| texels[(cy * w + cx + x) as usize] == 0));
        assert!(texels[((cy + 3) * w + cx + 2) as usize] == 255);
    }

    #[test]
    fn legend_sits_at_the_right_with_min_zero_and_max_labels() {
        let layout = legend_layout(&legend(-0.5, 1.5), 1066, 800);
        assert_eq!(layout.bar.max[1] - layout.bar.min[1], 480.0);
        assert_eq!(layout.bar.max[0] - layout.bar.min[0], 24.0);
        assert!(layout.bar.max[0] < 1066.0 && layout.bar.min[0] > 986.0);
        let texts: Vec<&str> = layout.labels.iter().map(|(_, l)| l.text.as_str()).collect();
        assert_eq!(texts, ["-0.5", "0", "1.5"]);
        // The zero label sits a quarter of the way up, labels right-aligned left of the bar.
        let zero = &layout.labels[1].1;
        let centre = zero.origin[1] + zero.glyph_px / 2.0;
        assert!((centre - (layout.bar.max[1] - 120.0)).abs() <= 1.0, "{centre}");
        for (_, l) in &layout.labels {
            assert_eq!(l.bounds().max[0], layout.bar.min[0] - 12.0);
            assert_eq!(l.origin.map(f32::fract), [0.0, 0.0], "whole pixels keep glyphs crisp");
        }
        // Everything is inside the panel, which is inside the viewport.
        let inside = |r: PixelRect, outer: PixelRect| {
            r.min[0] >= outer.min[0] && r.min[1] >= outer.min[1] && r.max[0] <= outer.max[0] && r.max[1] <= outer.max[1]
        };
        let viewport = PixelRect { min: [0.0, 0.0], max: [1066.0, 800.0] };
        assert!(inside(layout.panel, viewport));
        for r in layout.labels.iter().map(|(_, l)| l.bounds()).chain([layout.title.bounds(), layout.bar]) {
            assert!(inside(r, layout.panel), "{r:?} {:?}", layout.panel);
        }
        // One glyph rectangle per visible character.
        let glyphs = layout.rects().iter().filter(|r| r.kind == RECT_GLYPH).count();
        assert_eq!(glyphs, "Mean H-0.501.5".chars().filter(|c| *c != ' ').count());
    }

    #[test]
    fn zero_is_left_out_when_outside_the_range_or_crowding_an_end() {
        let texts = |l: &LegendLayout| l.labels.iter().map(|(_, t)| t.text.clone()).collect::<Vec<_>>();
        assert_eq!(texts(&legend_layout(&legend(0.1, 2.0), 640, 480)), ["0.1", "2"]);
        assert_eq!(texts(&legend_layout(&legend(-0.001, 1.0), 640, 480)), ["-0.001", "1"]);
        // Small viewports use 1× glyphs.
        assert_eq!(legend_layout(&legend(-1.0, 1.0), 200, 150).title.glyph_px, 8.0);
    }
}
