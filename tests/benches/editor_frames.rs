//! The editor's frame while a designer drags a cage point (issue 13), on the GPU wgpu picks
//! (Mesa lavapipe on a machine without one, as in CI), at NUSD levels 3, 4 and 5 of the default
//! scene.
//!
//! A frame here is what the editor's frame does besides egui's panels (about a millisecond):
//! the edit reaches the document (`Document::apply`), the scheme takes it
//! (`SurfaceScheme::update`: the NUSD warm start propagates the change to every level at once),
//! advances within the editor's budget of 12 ms, the surface buffers are rebuilt and uploaded,
//! and the viewport (zebra stripes, the cage overlay) is drawn at 1280 × 800 and waited for.
//! Each frame of the drag moves the apex by 0.1 % of the diagonal, 60 frames in all; then the
//! mouse is released and the surface settles, a frame at a time, until every level has
//! converged. Reported: the median, 95th percentile and longest frame of the drag (the picture
//! freezes when one frame is long), its parts, and the frames and time to settle.
//!
//! Run with `cargo bench -p taut-tests --bench editor_frames`.

use std::time::{Duration, Instant};
use taut_core::surface::{self, Budget, Phase};
use taut_core::{DVec3, Document, Edit, VertexId};
use taut_render::overlay::{self, CageControls, CageSelection, OverlayData};
use taut_render::passes::surface::SurfaceMode;
use taut_render::renderer::Attachments;
use taut_render::{
    AdapterPreference, Camera, DisplayFrame, Gpu, GpuSurface, Renderer, Scene, SurfaceBuffers, TargetFormats,
};

/// The editor's solver budget per frame (app/src/editor/state.rs `SOLVER_BUDGET`).
const SOLVER_BUDGET: Duration = Duration::from_millis(12);
const DRAG_FRAMES: usize = 60;
const WIDTH: u32 = 1280;
const HEIGHT: u32 = 800;

#[derive(Default)]
struct Parts {
    update: Duration,
    advance: Duration,
    upload: Duration,
    draw: Duration,
}

fn ms(d: Duration) -> f64 {
    d.as_secs_f64() * 1e3
}

fn percentile(times: &[Duration], q: f64) -> Duration {
    let mut sorted = times.to_vec();
    sorted.sort();
    sorted[((sorted.len() - 1) as f64 * q).round() as usize]
}

struct Viewport {
    gpu: Gpu,
    renderer: Renderer,
    attachments: Attachments,
    view: wgpu::TextureView,
    buffers: SurfaceBuffers,
    gpu_surface: Option<GpuSurface>,
}

impl Viewport {
    fn new() -> Viewport {
        let gpu = Gpu::headless(AdapterPreference::Hardware).unwrap_or_else(|e| {
            panic!("no GPU adapter: {e}; install Mesa's software Vulkan driver (Debian: mesa-vulkan-drivers)")
        });
        let format = wgpu::TextureFormat::Rgba8UnormSrgb;
        let mut targets = TargetFormats::for_adapter(&gpu.adapter, format);
        if gpu.adapter.get_info().device_type == wgpu::DeviceType::Cpu {
            targets.samples = 1; // as the editor does on a software rasteriser
        }
        let renderer = Renderer::new(&gpu, targets);
        let attachments = Attachments::new(&gpu.device, &targets, WIDTH, HEIGHT);
        let texture = gpu.device.create_texture(&wgpu::TextureDescriptor {
            label: Some("frame"),
            size: wgpu::Extent3d { width: WIDTH, height: HEIGHT, depth_or_array_layers: 1 },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT,
            view_formats: &[],
        });
        let view = texture.create_view(&Default::default());
        Viewport { gpu, renderer, attachments, view, buffers: SurfaceBuffers::default(), gpu_surface: None }
    }

    fn upload(&mut self, scheme: &dyn surface::SurfaceScheme, frame: &DisplayFrame) {
        let changes = self.buffers.update_with(scheme.mesh(), scheme.normals(), frame);
        match &mut self.gpu_surface {
            Some(g) => g.upload(&self.gpu.device, &self.gpu.queue, &self.buffers, changes),
            None => self.gpu_surface = Some(GpuSurface::new(&self.gpu.device, &self.buffers)),
        }
    }

    fn draw(&mut self, camera: Camera, overlays: &OverlayData) {
        let mode = SurfaceMode::Zebra { stripes: 12.0, angle_degrees: 0.0, width_ratio: 0.5 };
        let scene = Scene::new(camera, self.gpu_surface.as_ref(), mode).with_overlays(overlays);
        let mut encoder = self.gpu.device.create_command_encoder(&Default::default());
        self.renderer.encode(&self.gpu.device, &self.gpu.queue, &mut encoder, &self.view, &self.attachments, &scene);
        self.gpu.queue.submit([encoder.finish()]);
        self.gpu.device.poll(wgpu::PollType::wait_indefinitely()).expect("the frame finishes");
    }
}

fn cage_lines(doc: &Document, frame: &DisplayFrame, apex: VertexId) -> OverlayData {
    let selection = CageSelection { selected_vertices: vec![apex], ..Default::default() };
    let controls =
        CageControls::Nusd { fixed: &doc.fixed, vertex_tension: &doc.vertex_tension, edge_tension: &doc.edge_tension };
    let (lines, points) = overlay::cage_overlay(&doc.cage, controls, &selection, frame);
    OverlayData { on_top_lines: lines, points, ..Default::default() }
}

fn level_bench(viewport: &mut Viewport, base: &Document, levels: u32) {
    let mut doc = base.clone();
    doc.settings.levels = levels;
    let diagonal = doc.cage.bounding_diagonal();
    let apex = (0..doc.cage.vertex_count())
        .map(|i| VertexId(i as u32))
        .filter(|&v| doc.fixed[v.index()])
        .max_by(|&a, &b| doc.cage.position(a).z.total_cmp(&doc.cage.position(b).z))
        .expect("the default scene has fixed vertices");
    let mut scheme = surface::build(&doc).unwrap();
    let started = Instant::now();
    while scheme.advance(Budget { iterations: usize::MAX, time: Some(SOLVER_BUDGET) }).phase == Phase::Iterating {}
    let first_solve = started.elapsed();
    let (lo, hi) = doc.cage.bounding_box().unwrap();
    let frame = DisplayFrame::for_bounds(lo, hi);
    let mut camera = Camera::default();
    let points: Vec<glam::Vec3> = scheme.mesh().positions().iter().map(|&p| frame.point(p)).collect();
    camera.frame_points(&points, WIDTH as f32 / HEIGHT as f32);
    viewport.upload(scheme.as_ref(), &frame);
    viewport.draw(camera, &cage_lines(&doc, &frame, apex));

    let step = DVec3::new(0.6, 0.3, 1.0).normalize() * (1e-3 * diagonal);
    let (mut frames, mut parts) = (Vec::new(), Parts::default());
    for _ in 0..DRAG_FRAMES {
        let t0 = Instant::now();
        let to = doc.cage.position(apex) + step;
        doc.apply(Edit::MoveVertices(vec![(apex, to)])).unwrap();
        scheme.update(&doc).unwrap();
        let t1 = Instant::now();
        scheme.advance(Budget { iterations: usize::MAX, time: Some(SOLVER_BUDGET) });
        let t2 = Instant::now();
        viewport.upload(scheme.as_ref(), &frame);
        let overlays = cage_lines(&doc, &frame, apex);
        let t3 = Instant::now();
        viewport.draw(camera, &overlays);
        let t4 = Instant::now();
        parts.update += t1 - t0;
        parts.advance += t2 - t1;
        parts.upload += t3 - t2;
        parts.draw += t4 - t3;
        frames.push(t4 - t0);
    }
    let (mut settle_frames, settle_start) = (0usize, Instant::now());
    let mut longest_settle = Duration::ZERO;
    let overlays = cage_lines(&doc, &frame, apex);
    while scheme.progress().phase == Phase::Iterating {
        let t0 = Instant::now();
        scheme.advance(Budget { iterations: usize::MAX, time: Some(SOLVER_BUDGET) });
        viewport.upload(scheme.as_ref(), &frame);
        viewport.draw(camera, &overlays);
        longest_settle = longest_settle.max(t0.elapsed());
        settle_frames += 1;
    }
    let settle = settle_start.elapsed();
    let n = DRAG_FRAMES as f64;
    println!(
        "level {levels}: {} vertices; first solve {:.0} ms\n  drag frame median {:.1} ms, 95th percentile {:.1} ms, longest {:.1} ms \
         (per frame: edit + warm start {:.2}, solver {:.2}, buffers {:.2}, draw {:.2} ms)\n  after release: {} frames, {:.0} ms to \
         converge every level (longest frame {:.1} ms); {}",
        scheme.mesh().vertex_count(),
        ms(first_solve),
        ms(percentile(&frames, 0.5)),
        ms(percentile(&frames, 0.95)),
        ms(*frames.iter().max().unwrap()),
        ms(parts.update) / n,
        ms(parts.advance) / n,
        ms(parts.upload) / n,
        ms(parts.draw) / n,
        settle_frames,
        ms(settle),
        ms(longest_settle),
        scheme.progress().summary
    );
}

fn main() {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../assets/default.taut");
    let base = Document::load(&path).unwrap();
    let mut viewport = Viewport::new();
    println!(
        "threads: {}, GPU: {}, {WIDTH}x{HEIGHT} zebra with the cage",
        rayon::current_num_threads(),
        viewport.gpu.description()
    );
    for levels in [3, 4, 5] {
        level_bench(&mut viewport, &base, levels);
    }
}
