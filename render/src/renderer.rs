//! [`Renderer`]: every pass, and the order they draw a [`Scene`] in: the reference images behind
//! the model, the surface, the depth-tested lines on it, the ghosts, the reference images in front
//! of the model, the lines on top, the points, and the 2D overlay (the legend).

use crate::camera::Camera;
use crate::frame::{FrameBinding, FrameUniform};
use crate::overlay::OverlayData;
use crate::passes::lines::LinesPass;
use crate::passes::overlay2d::Overlay2dPass;
use crate::passes::points::PointsPass;
use crate::passes::reference_images::ReferenceImagesPass;
use crate::passes::surface::{SurfaceMode, SurfacePass};
use crate::{Gpu, GpuSurface, TargetFormats};

/// What one frame shows.
#[derive(Clone, Copy, Debug)]
pub struct Scene<'a> {
    pub camera: Camera,
    pub surface: Option<&'a GpuSurface>,
    pub mode: SurfaceMode,
    /// Clear colour, linear RGBA.
    pub background: [f64; 4],
    /// Cage, wireframe, curves and legend over the surface.
    pub overlays: Option<&'a OverlayData>,
    /// The part of the target to draw into, `[x, y, width, height]` in pixels (the editor's
    /// viewport between its panels); the whole target when `None`.
    pub viewport: Option<[u32; 4]>,
    /// A second surface drawn as a translucent ghost of this colour (linear RGBA).
    pub ghost: Option<(&'a GpuSurface, [f32; 4])>,
    /// Another ghost beside the first, in its own colour (the editor's original mesh of a fitted
    /// cage, while the compare view shows the other scheme as the first).
    pub second_ghost: Option<(&'a GpuSurface, [f32; 4])>,
    /// The clipping plane `(n, d)` in display coordinates: the surfaces and the lines on them are
    /// cut away where `n·p > d` (the on-top overlays are not).
    pub clip_plane: Option<glam::Vec4>,
    /// Pictures behind or over the model ([`crate::reference_images`]).
    pub reference_images: &'a [crate::reference_images::ReferenceQuad<'a>],
}

impl<'a> Scene<'a> {
    /// A scene with the default background and no overlays.
    pub fn new(camera: Camera, surface: Option<&'a GpuSurface>, mode: SurfaceMode) -> Self {
        Scene {
            camera,
            surface,
            mode,
            background: [0.16, 0.17, 0.19, 1.0],
            overlays: None,
            viewport: None,
            ghost: None,
            second_ghost: None,
            clip_plane: None,
            reference_images: &[],
        }
    }

    /// The same scene with overlays.
    pub fn with_overlays(self, overlays: &'a OverlayData) -> Self {
        Scene { overlays: Some(overlays), ..self }
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
    lines: LinesPass,
    points: PointsPass,
    overlay2d: Overlay2dPass,
    reference_images: ReferenceImagesPass,
}

impl Renderer {
    pub fn new(gpu: &Gpu, targets: TargetFormats) -> Self {
        let frame = FrameBinding::new(&gpu.device);
        let surface = SurfacePass::new(&gpu.device, &gpu.queue, &targets, &frame.layout);
        let lines = LinesPass::new(&gpu.device, &targets, &frame.layout);
        let points = PointsPass::new(&gpu.device, &targets, &frame.layout);
        let overlay2d = Overlay2dPass::new(&gpu.device, &gpu.queue, &targets, &frame.layout);
        let reference_images = ReferenceImagesPass::new(&gpu.device, &targets, &frame.layout);
        Renderer { targets, frame, surface, lines, points, overlay2d, reference_images }
    }

    /// Records one frame of `scene` into `encoder`, drawing into `target` (the window's
    /// surface texture or an off-screen texture of the colour format). Uploads go through
    /// `queue` and take effect at the next submit, so submit before encoding another frame.
    pub fn encode(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        encoder: &mut wgpu::CommandEncoder,
        target: &wgpu::TextureView,
        attachments: &Attachments,
        scene: &Scene<'_>,
    ) {
        let [x, y, width, height] = match scene.viewport {
            Some([x, y, w, h]) => {
                let x = x.min(attachments.width.saturating_sub(1));
                let y = y.min(attachments.height.saturating_sub(1));
                [x, y, w.clamp(1, attachments.width - x), h.clamp(1, attachments.height - y)]
            }
            None => [0, 0, attachments.width, attachments.height],
        };
        let mut uniform = FrameUniform::new(&scene.camera, width, height);
        if let Some(plane) = scene.clip_plane {
            uniform.clip_plane = plane.to_array();
        }
        self.frame.update(queue, &uniform);
        self.surface.set_mode(queue, scene.mode);
        if let Some((_, color)) = scene.ghost {
            self.surface.set_ghost(queue, color);
        }
        if let Some((_, color)) = scene.second_ghost {
            self.surface.set_second_ghost(queue, color);
        }
        let none = OverlayData::default();
        let overlays = scene.overlays.unwrap_or(&none);
        self.lines.prepare(device, queue, &overlays.surface_lines, &overlays.on_top_lines);
        self.points.prepare(device, queue, &overlays.points);
        self.overlay2d.prepare(device, queue, overlays.legend.as_ref(), width, height);
        self.reference_images.prepare(device, queue, scene.reference_images);
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
        pass.set_viewport(x as f32, y as f32, width as f32, height as f32, 0.0, 1.0);
        pass.set_scissor_rect(x, y, width, height);
        let frame = &self.frame.bind_group;
        self.reference_images.draw(&mut pass, frame, false);
        if let Some(surface) = scene.surface {
            self.surface.draw(&mut pass, frame, surface);
        }
        self.lines.draw_surface_lines(&mut pass, frame);
        if let Some((ghost, _)) = scene.ghost {
            self.surface.draw_ghost(&mut pass, frame, ghost);
        }
        if let Some((ghost, _)) = scene.second_ghost {
            self.surface.draw_second_ghost(&mut pass, frame, ghost);
        }
        self.reference_images.draw(&mut pass, frame, true);
        self.lines.draw_on_top_lines(&mut pass, frame);
        self.points.draw(&mut pass, frame);
        self.overlay2d.draw(&mut pass, frame);
    }

    /// How many instance buffers the lines and points passes created so far (for tests).
    pub fn overlay_buffer_creations(&self) -> (u64, u64) {
        (self.lines.buffer_creations(), self.points.buffer_creations())
    }

    /// How many reference pictures were uploaded so far (for tests).
    pub fn reference_uploads(&self) -> u64 {
        self.reference_images.uploads()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::colormap::ColorMap;
    use crate::offscreen::{render_image, save_png};
    use crate::overlay::{Legend, LineSegment, PointMark, PointStyle};
    use crate::passes::overlay2d::legend_layout;
    use crate::{AdapterPreference, SurfaceBuffers};
    use glam::{Vec2, Vec3};
    use taut_core::{DVec3, PolyMesh};

    const W: u32 = 480;
    const H: u32 = 360;

    /// Lavapipe, or a failure saying what to install: a render test never skips.
    fn gpu() -> Gpu {
        Gpu::headless(AdapterPreference::Software).unwrap_or_else(|e| panic!("{e}"))
    }

    /// Looking at the XZ plane from −Y.
    fn front_camera() -> Camera {
        Camera { target: Vec3::ZERO, distance: 4.0, azimuth: 0.0, elevation: 0.0, fov_y: 35.0, orthographic: false }
    }

    /// The pixel `p` lands in, with the matrices the frame uniform uses.
    fn project(camera: &Camera, p: Vec3) -> Vec2 {
        let clip = camera.clip_from_view(W as f32 / H as f32) * camera.view_from_world() * p.extend(1.0);
        let ndc = clip.truncate() / clip.w;
        Vec2::new((ndc.x * 0.5 + 0.5) * W as f32, (0.5 - ndc.y * 0.5) * H as f32)
    }

    fn pixel(image: &image::RgbaImage, at: Vec2) -> [u8; 3] {
        let p = image.get_pixel(at.x as u32, at.y as u32).0;
        [p[0], p[1], p[2]]
    }

    fn linear_to_srgb(c: f32) -> f32 {
        if c <= 0.003_130_8 { 12.92 * c } else { 1.055 * c.powf(1.0 / 2.4) - 0.055 }
    }

    fn close(a: [u8; 3], b: [u8; 3], tolerance: u8) -> bool {
        a.iter().zip(&b).all(|(x, y)| x.abs_diff(*y) <= tolerance)
    }

    /// A flat square, two units wide, in the XZ plane.
    fn square(gpu: &Gpu) -> GpuSurface {
        let p = vec![
            DVec3::new(-1.0, 0.0, -1.0),
            DVec3::new(1.0, 0.0, -1.0),
            DVec3::new(1.0, 0.0, 1.0),
            DVec3::new(-1.0, 0.0, 1.0),
        ];
        let mesh = PolyMesh::from_polygons(p, &[[0, 1, 2, 3]]).unwrap();
        let mut buffers = SurfaceBuffers::default();
        buffers.update(&mesh);
        GpuSurface::new(&gpu.device, &buffers)
    }

    fn line(a: [f32; 3], b: [f32; 3], color: [f32; 4], width_px: f32) -> LineSegment {
        LineSegment { a: Vec3::from(a), b: Vec3::from(b), color, width_px }
    }

    fn save(image: &image::RgbaImage, name: &str) {
        let _ = save_png(image, &std::env::temp_dir().join(name));
    }

    /// A smaller square in front of the big one (nearer the camera by `offset`).
    fn square_at(gpu: &Gpu, size: f64, offset: f64) -> GpuSurface {
        let p = [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)]
            .map(|(x, z)| DVec3::new(size * x, -offset, size * z))
            .to_vec();
        let mesh = PolyMesh::from_polygons(p, &[[0, 1, 2, 3]]).unwrap();
        let mut buffers = SurfaceBuffers::default();
        buffers.update(&mesh);
        GpuSurface::new(&gpu.device, &buffers)
    }

    /// A ghost in front of the surface tints it and lets it show through; behind it, the surface
    /// hides the ghost (it tests depth without writing it).
    #[test]
    fn a_ghost_is_seen_through_and_hidden_behind() {
        use crate::passes::surface::GHOST;
        let gpu = gpu();
        let targets = TargetFormats::for_adapter(&gpu.adapter, wgpu::TextureFormat::Rgba8UnormSrgb);
        let mut renderer = Renderer::new(&gpu, targets);
        let surface = square(&gpu);
        let camera = front_camera();
        let plain =
            render_image(&gpu, &mut renderer, &Scene::new(camera, Some(&surface), SurfaceMode::Shaded), W, H).unwrap();
        let centre = project(&camera, Vec3::ZERO);
        let base = pixel(&plain, centre);
        let front = square_at(&gpu, 0.5, 0.5);
        let scene = Scene { ghost: Some((&front, GHOST)), ..Scene::new(camera, Some(&surface), SurfaceMode::Shaded) };
        let tinted = pixel(&render_image(&gpu, &mut renderer, &scene, W, H).unwrap(), centre);
        // Amber over grey: more red, less blue, still not the ghost's own colour.
        assert!(tinted[0] > base[0] + 10 && tinted[2] + 10 < base[2], "{tinted:?} over {base:?}");
        let beside = project(&camera, Vec3::new(0.8, 0.0, 0.8));
        let plain_beside = pixel(&plain, beside);
        let tinted_image = render_image(&gpu, &mut renderer, &scene, W, H).unwrap();
        assert!(close(pixel(&tinted_image, beside), plain_beside, 2), "outside the ghost nothing changes");
        let behind = square_at(&gpu, 0.5, -0.5);
        let scene = Scene { ghost: Some((&behind, GHOST)), ..Scene::new(camera, Some(&surface), SurfaceMode::Shaded) };
        let hidden = pixel(&render_image(&gpu, &mut renderer, &scene, W, H).unwrap(), centre);
        assert!(close(hidden, base, 2), "a ghost behind the surface shows: {hidden:?} vs {base:?}");
    }

    /// The clipping plane cuts the surface and the lines on it, in both projections; the
    /// on-top lines stay whole.
    #[test]
    fn the_clipping_plane_cuts_the_surface_and_its_lines_but_not_the_overlays_on_top() {
        let gpu = gpu();
        let surface = square(&gpu);
        let targets = TargetFormats::for_adapter(&gpu.adapter, wgpu::TextureFormat::Rgba8UnormSrgb);
        let mut renderer = Renderer::new(&gpu, targets);
        let (green, red) = ([0.0, 1.0, 0.0, 1.0], [1.0, 0.0, 0.0, 1.0]);
        let overlays = OverlayData {
            surface_lines: vec![line([-0.8, 0.0, 0.3], [0.8, 0.0, 0.3], green, 3.0)],
            on_top_lines: vec![line([-0.8, 0.0, -0.3], [0.8, 0.0, -0.3], red, 3.0)],
            ..Default::default()
        };
        for camera in [front_camera(), Camera { orthographic: true, ..front_camera() }] {
            let plain = Scene::new(camera, Some(&surface), SurfaceMode::Shaded).with_overlays(&overlays);
            let whole = render_image(&gpu, &mut renderer, &plain, W, H).unwrap();
            // Cut away x > 0.25.
            let cut = Scene { clip_plane: Some(glam::Vec4::new(1.0, 0.0, 0.0, 0.25)), ..plain };
            let image = render_image(&gpu, &mut renderer, &cut, W, H).unwrap();
            save(&image, &format!("taut-clip-{}.png", camera.orthographic));
            let background = [0.16f32, 0.17, 0.19].map(|c| (255.0 * linear_to_srgb(c)).round() as u8);
            let at = |p: [f32; 3]| project(&camera, Vec3::from(p));
            let kept = at([-0.5, 0.0, 0.7]);
            assert!(close(pixel(&image, kept), pixel(&whole, kept), 2), "the kept side is drawn as before");
            let gone = at([0.6, 0.0, 0.7]);
            assert!(
                close(pixel(&image, gone), background, 3),
                "the cut side shows the background: {:?}",
                pixel(&image, gone)
            );
            assert!(close(pixel(&image, at([-0.5, 0.0, 0.3])), [0, 255, 0], 2), "the surface line's kept part");
            assert!(close(pixel(&image, at([0.6, 0.0, 0.3])), background, 3), "the surface line is cut");
            assert!(close(pixel(&image, at([0.6, 0.0, -0.3])), [255, 0, 0], 2), "the on-top line is whole");
            // Near the plane: kept just before it, cut just past it.
            assert!(close(pixel(&image, at([0.2, 0.0, 0.7])), pixel(&whole, at([0.2, 0.0, 0.7])), 2));
            assert!(close(pixel(&image, at([0.3, 0.0, 0.7])), background, 3));
        }
    }

    /// Two ghosts at once, each in its own colour (the compare view's and the editor's original
    /// mesh): where only one covers the surface, that one's tint shows; where both do, both.
    #[test]
    fn two_ghosts_keep_their_own_colours() {
        use crate::passes::surface::GHOST;
        const BLUE: [f32; 4] = [0.10, 0.45, 0.95, 0.30];
        let gpu = gpu();
        let targets = TargetFormats::for_adapter(&gpu.adapter, wgpu::TextureFormat::Rgba8UnormSrgb);
        let mut renderer = Renderer::new(&gpu, targets);
        let surface = square(&gpu);
        let camera = front_camera();
        let plain =
            render_image(&gpu, &mut renderer, &Scene::new(camera, Some(&surface), SurfaceMode::Shaded), W, H).unwrap();
        // The amber ghost covers the middle, the blue one the middle and more.
        let amber = square_at(&gpu, 0.3, 0.5);
        let blue = square_at(&gpu, 0.7, 0.3);
        let scene = Scene {
            ghost: Some((&amber, GHOST)),
            second_ghost: Some((&blue, BLUE)),
            ..Scene::new(camera, Some(&surface), SurfaceMode::Shaded)
        };
        let image = render_image(&gpu, &mut renderer, &scene, W, H).unwrap();
        save(&image, "taut-two-ghosts.png");
        let only_blue = project(&camera, Vec3::new(0.5, 0.0, 0.5));
        let (base, tinted) = (pixel(&plain, only_blue), pixel(&image, only_blue));
        assert!(tinted[2] > base[2] + 10 && tinted[0] + 10 < base[0], "blue over grey: {tinted:?} over {base:?}");
        let both = project(&camera, Vec3::ZERO);
        let tinted = pixel(&image, both);
        // Amber under blue: redder than blue alone, bluer than the grey under amber alone.
        let amber_only =
            Scene { ghost: Some((&amber, GHOST)), ..Scene::new(camera, Some(&surface), SurfaceMode::Shaded) };
        let amber_pixel = pixel(&render_image(&gpu, &mut renderer, &amber_only, W, H).unwrap(), both);
        assert!(tinted[0] > pixel(&image, only_blue)[0] + 5, "the amber ghost shows under the blue: {tinted:?}");
        assert!(tinted[2] > amber_pixel[2] + 5, "the blue ghost shows over the amber: {tinted:?} vs {amber_pixel:?}");
        let outside = project(&camera, Vec3::new(0.9, 0.0, 0.9));
        assert!(close(pixel(&image, outside), pixel(&plain, outside), 2), "outside both nothing changes");
    }

    #[test]
    fn overlays_draw_where_the_camera_puts_them() {
        let gpu = gpu();
        let surface = square(&gpu);
        let (red, green, blue, yellow, magenta) = (
            [1.0, 0.0, 0.0, 1.0],
            [0.0, 1.0, 0.0, 1.0],
            [0.0, 0.0, 1.0, 1.0],
            [1.0, 1.0, 0.0, 1.0],
            [1.0, 0.0, 1.0, 1.0],
        );
        let overlays = OverlayData {
            // Behind the square (hidden) and on it (visible).
            surface_lines: vec![
                line([-0.6, 0.3, 0.2], [0.6, 0.3, 0.2], green, 3.0),
                line([-0.6, 0.0, -0.2], [0.6, 0.0, -0.2], blue, 3.0),
            ],
            // Behind the square, yet on top.
            on_top_lines: vec![line([-0.6, 0.5, 0.6], [0.6, 0.5, 0.6], red, 3.0)],
            points: vec![
                PointMark {
                    position: Vec3::new(-0.4, 0.0, -0.6),
                    color: yellow,
                    radius_px: 8.0,
                    style: PointStyle::Filled,
                },
                PointMark {
                    position: Vec3::new(0.4, 0.0, -0.6),
                    color: magenta,
                    radius_px: 10.0,
                    style: PointStyle::Ring,
                },
            ],
            legend: Some(Legend { map: ColorMap::Diverging, min: -0.5, max: 1.5, title: "Mean H".into() }),
        };
        let msaa = TargetFormats::for_adapter(&gpu.adapter, wgpu::TextureFormat::Rgba8UnormSrgb);
        // Both projections: orthographic pulls lines on the surface along the view, not about
        // the eye, and must still keep them on their pixels.
        let (perspective, orthographic) = (front_camera(), Camera { orthographic: true, ..front_camera() });
        for (camera, targets) in
            [(perspective, msaa), (perspective, TargetFormats { samples: 1, ..msaa }), (orthographic, msaa)]
        {
            let mut renderer = Renderer::new(&gpu, targets);
            let plain = Scene::new(camera, Some(&surface), SurfaceMode::Shaded);
            let reference = render_image(&gpu, &mut renderer, &plain, W, H).unwrap();
            let image = render_image(&gpu, &mut renderer, &plain.with_overlays(&overlays), W, H).unwrap();
            let projection = if camera.orthographic { "ortho" } else { "persp" };
            save(&image, &format!("taut-overlays-{}x-{projection}.png", targets.samples));
            let at = |p: [f32; 3]| project(&camera, Vec3::from(p));
            let samples = format!("{}x {projection}", targets.samples);

            assert!(close(pixel(&image, at([0.0, 0.5, 0.6])), [255, 0, 0], 2), "{samples}x: on-top line");
            for x in [-0.3, 0.0, 0.3] {
                let hidden = at([x, 0.3, 0.2]);
                assert!(close(pixel(&image, hidden), pixel(&reference, hidden), 2), "{samples}x: hidden line shows");
                assert!(close(pixel(&image, at([x, 0.0, -0.2])), [0, 0, 255], 2), "{samples}x: line on the surface");
            }
            assert!(close(pixel(&image, at([-0.4, 0.0, -0.6])), [255, 255, 0], 2), "{samples}x: filled point");
            let ring = at([0.4, 0.0, -0.6]);
            assert!(close(pixel(&image, ring), pixel(&reference, ring), 2), "{samples}x: ring centre filled");
            // The ring is 3 px thick, from 7 to 10 px out.
            for offset in [Vec2::new(8.5, 0.0), Vec2::new(0.0, -8.5), Vec2::new(-6.0, 6.0)] {
                assert!(close(pixel(&image, ring + offset), [255, 0, 255], 2), "{samples}x: ring at {offset}");
            }

            let layout = legend_layout(overlays.legend.as_ref().unwrap(), W, H);
            let centre_x = (layout.bar.min[0] + layout.bar.max[0]) / 2.0;
            let top = pixel(&image, Vec2::new(centre_x, layout.bar.min[1] + 0.5));
            let bottom = pixel(&image, Vec2::new(centre_x, layout.bar.max[1] - 0.5));
            assert!(close(top, ColorMap::Diverging.color(1.0), 3), "{samples}x: bar top {top:?}");
            assert!(close(bottom, ColorMap::Diverging.color(0.0), 3), "{samples}x: bar bottom {bottom:?}");
            for (_, label) in &layout.labels {
                let b = label.bounds();
                let (mut ink, mut panel) = (0, 0);
                for y in b.min[1] as u32..b.max[1] as u32 {
                    for x in b.min[0] as u32..b.max[0] as u32 {
                        let p = image.get_pixel(x, y).0;
                        if p[..3].iter().all(|&c| c > 220) {
                            ink += 1;
                        } else if p[..3].iter().all(|&c| c < 150) {
                            panel += 1;
                        }
                    }
                }
                assert!(
                    ink > 20
                        && panel > 20
                        && ink + panel == (b.max[0] - b.min[0]) as usize * (b.max[1] - b.min[1]) as usize,
                    "{samples}x: label {:?}: {ink} inked, {panel} panel",
                    label.text
                );
            }
        }
    }

    #[test]
    fn lines_behind_the_camera_are_cut_or_dropped() {
        let gpu = gpu();
        let camera = front_camera();
        let targets = TargetFormats::for_adapter(&gpu.adapter, wgpu::TextureFormat::Rgba8UnormSrgb);
        let mut renderer = Renderer::new(&gpu, targets);
        let white = [1.0; 4];
        // The eye is at y = −4: one segment crosses the near plane, one is wholly behind.
        let (behind, front) = (Vec3::new(-0.5, -9.0, -0.2), Vec3::new(0.5, 2.0, 0.3));
        let overlays = OverlayData {
            surface_lines: vec![LineSegment { a: behind, b: front, color: white, width_px: 2.0 }],
            on_top_lines: vec![
                LineSegment { a: front, b: behind, color: white, width_px: 2.0 },
                line([-1.0, -6.0, 0.0], [1.0, -8.0, 0.5], white, 4.0),
            ],
            points: vec![PointMark {
                position: Vec3::new(0.0, -5.0, 0.0),
                color: white,
                radius_px: 20.0,
                style: PointStyle::Filled,
            }],
            legend: None,
        };
        let scene = Scene::new(camera, None, SurfaceMode::Shaded);
        let empty = render_image(&gpu, &mut renderer, &scene, W, H).unwrap();
        let image = render_image(&gpu, &mut renderer, &scene.with_overlays(&overlays), W, H).unwrap();
        save(&image, "taut-overlays-behind-camera.png");
        // What is drawn lies along the projection of the visible part (from y = −3 on).
        let (p, q) = (project(&camera, behind.lerp(front, 6.0 / 11.0)), project(&camera, front));
        let dir = (q - p).normalize();
        let mut drawn = 0;
        for (x, y, px) in image.enumerate_pixels() {
            if px.0[..3] != empty.get_pixel(x, y).0[..3] {
                drawn += 1;
                let d = Vec2::new(x as f32 + 0.5, y as f32 + 0.5) - p;
                let off = (d - dir * d.dot(dir)).length();
                assert!(off < 3.0, "pixel ({x}, {y}) is {off} px off the visible line");
            }
        }
        assert!(drawn > 100, "{drawn} pixels drawn");
    }

    #[test]
    fn instance_buffers_are_reused_until_they_must_grow_and_empty_layers_draw_nothing() {
        let gpu = gpu();
        let targets = TargetFormats::for_adapter(&gpu.adapter, wgpu::TextureFormat::Rgba8UnormSrgb);
        let mut renderer = Renderer::new(&gpu, targets);
        let scene = Scene::new(front_camera(), None, SurfaceMode::Shaded);
        let lines = |n: usize| OverlayData {
            on_top_lines: (0..n).map(|i| line([i as f32 * 0.01, 0.0, 0.0], [0.0, 0.0, 0.5], [1.0; 4], 1.0)).collect(),
            points: (0..n)
                .map(|i| PointMark {
                    position: Vec3::splat(i as f32 * 0.01),
                    color: [1.0; 4],
                    radius_px: 3.0,
                    style: PointStyle::Ring,
                })
                .collect(),
            ..Default::default()
        };
        let empty = render_image(&gpu, &mut renderer, &scene, 64, 48).unwrap();
        for (n, creations) in [(10, 1), (5, 1), (10, 1), (0, 1), (1000, 2), (3, 2)] {
            let overlays = lines(n);
            let image = render_image(&gpu, &mut renderer, &scene.with_overlays(&overlays), 64, 48).unwrap();
            assert_eq!(renderer.overlay_buffer_creations(), (creations, creations), "{n} lines");
            assert_eq!(image == empty, n == 0, "{n} lines");
        }
        let nothing = OverlayData::default();
        assert!(render_image(&gpu, &mut renderer, &scene.with_overlays(&nothing), 64, 48).unwrap() == empty);
    }

    /// A height-field grid over [−1, 1]², `n × n` quads.
    fn grid(n: u32, height: impl Fn(f64, f64) -> f64) -> PolyMesh {
        let at = |i: u32| -1.0 + 2.0 * i as f64 / n as f64;
        let p = (0..=n)
            .flat_map(|j| (0..=n).map(move |i| (at(i), at(j))))
            .map(|(x, y)| DVec3::new(x, y, height(x, y)))
            .collect();
        let faces: Vec<[u32; 4]> = (0..n)
            .flat_map(|j| (0..n).map(move |i| j * (n + 1) + i))
            .map(|v| [v, v + 1, v + n + 2, v + n + 1])
            .collect();
        PolyMesh::from_polygons(p, &faces).unwrap()
    }

    fn srgb(linear: [f32; 4]) -> [u8; 3] {
        let encode = |c: f32| if c <= 0.0031308 { 12.92 * c } else { 1.055 * c.powf(1.0 / 2.4) - 0.055 };
        [0, 1, 2].map(|i| (encode(linear[i]) * 255.0).round() as u8)
    }

    /// A designer's view: a curvature-coloured surface with its wireframe, the cage (fixed,
    /// moving, tense, selected, hovered), a curve with its comb and the legend.
    #[test]
    fn a_cage_with_comb_and_legend_renders_its_accents() {
        use crate::overlay::{CageSelection, CombStyle, SELECTED, cage_overlay, polyline_with_comb, wireframe};
        use taut_core::{EdgeId, VertexId};
        let gpu = gpu();
        let bump = |x: f64, y: f64| 0.25 * (2.0 * x).sin() * (2.0 * y).cos();
        let smooth = grid(24, bump);
        let mut buffers = SurfaceBuffers::default();
        buffers.update(&smooth);
        buffers.set_values(&smooth.positions().iter().map(|p| p.z as f32).collect::<Vec<_>>());
        let surface = GpuSurface::new(&gpu.device, &buffers);
        let cage = grid(4, |x, y| 1.3 * bump(x, y) + 0.1);
        let fixed: Vec<bool> = (0..25).map(|v| [0, 4, 20, 24, 12].contains(&v)).collect();
        let vertex_tension: Vec<f64> = (0..25).map(|v| if v == 7 { 3.0 } else { 0.0 }).collect();
        let edge_tension: Vec<f64> = (0..cage.edge_count()).map(|e| (e % 7) as f64).collect();
        let selection = CageSelection {
            selected_vertices: vec![VertexId(12), VertexId(13)],
            selected_edges: vec![EdgeId(3)],
            hovered_vertex: Some(VertexId(18)),
            hovered_edge: Some(EdgeId(20)),
            ..Default::default()
        };
        let identity = crate::DisplayFrame::IDENTITY;
        let (on_top_lines, points) = cage_overlay(
            &cage,
            crate::CageControls::Nusd { fixed: &fixed, vertex_tension: &vertex_tension, edge_tension: &edge_tension },
            &selection,
            &identity,
        );
        let curve: Vec<DVec3> =
            (0..=40).map(|i| -1.0 + i as f64 / 20.0).map(|x| DVec3::new(x, -0.5, bump(x, -0.5))).collect();
        let mut surface_lines = wireframe(&smooth, [0.0, 0.0, 0.0, 0.35], 1.0, &identity);
        surface_lines.extend(polyline_with_comb(
            &curve,
            false,
            &CombStyle { scale: 0.15, density: 2, ..Default::default() },
            &identity,
        ));
        let legend = Some(Legend { map: ColorMap::Diverging, min: -0.25, max: 0.25, title: "Height".into() });
        let overlays = OverlayData { surface_lines, on_top_lines, points, legend };

        let mut camera = Camera::default();
        let (lo, hi) = smooth.bounding_box().unwrap();
        camera.frame(lo.as_vec3(), hi.as_vec3());
        let targets = TargetFormats::for_adapter(&gpu.adapter, wgpu::TextureFormat::Rgba8UnormSrgb);
        let mut renderer = Renderer::new(&gpu, targets);
        let mode = SurfaceMode::Curvature { map: ColorMap::Diverging, min: -0.25, max: 0.25 };
        let scene = Scene::new(camera, Some(&surface), mode).with_overlays(&overlays);
        let image = render_image(&gpu, &mut renderer, &scene, W, H).unwrap();
        save(&image, "taut-overlays-cage.png");
        // The selected fixed vertex (12) is an orange disc.
        let centre = project(&camera, cage.position(VertexId(12)).as_vec3());
        assert!(close(pixel(&image, centre), srgb(SELECTED), 3), "{:?}", pixel(&image, centre));
    }
}
