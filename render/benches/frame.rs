//! Display speed on the adapter the machine has (lavapipe on a CI machine), reported in the
//! issue note as ratios against references measured in the same run:
//! - the zebra view of a ~1 M-triangle surface at 1280 × 800, against an empty frame of the
//!   same size (clear, resolve and read-back alone);
//! - the upload when only positions change (a drag), against a full upload (new connectivity).
//!
//! Run with `cargo bench -p taut-render`.

use std::time::{Duration, Instant};
use taut_core::{DVec3, PolyMesh};
use taut_render::passes::surface::SurfaceMode;
use taut_render::{
    AdapterPreference, Camera, Gpu, GpuSurface, Renderer, Scene, SurfaceBuffers, TargetFormats, offscreen,
};

/// A wavy sheet of `n × n` quads (2 n² triangles).
fn sheet(n: u32, phase: f64) -> PolyMesh {
    let mut p = Vec::with_capacity(((n + 1) * (n + 1)) as usize);
    for j in 0..=n {
        for i in 0..=n {
            let (x, y) = (i as f64 / n as f64 - 0.5, j as f64 / n as f64 - 0.5);
            p.push(DVec3::new(x, y, 0.08 * ((7.0 * x + phase).sin() + (5.0 * y).cos())));
        }
    }
    let mut faces = Vec::with_capacity((n * n) as usize);
    for j in 0..n {
        for i in 0..n {
            let v = j * (n + 1) + i;
            faces.push([v, v + 1, v + n + 2, v + n + 1]);
        }
    }
    PolyMesh::from_polygons(p, &faces).unwrap()
}

fn median(repeats: usize, mut f: impl FnMut()) -> Duration {
    let mut times: Vec<Duration> = (0..repeats)
        .map(|_| {
            let t = Instant::now();
            f();
            t.elapsed()
        })
        .collect();
    times.sort();
    times[times.len() / 2]
}

fn main() {
    let gpu = Gpu::headless(AdapterPreference::Hardware).unwrap_or_else(|e| panic!("{e}"));
    println!("adapter: {}", gpu.description());
    let targets = TargetFormats::for_adapter(&gpu.adapter, wgpu::TextureFormat::Rgba8UnormSrgb);
    let mut renderer = Renderer::new(&gpu, targets);
    let mesh = sheet(708, 0.0);
    let triangles = mesh.triangles().len();
    let mut buffers = SurfaceBuffers::default();
    buffers.update(&mesh);
    let mut surface = GpuSurface::new(&gpu.device, &buffers);
    let mut camera = Camera::default();
    let (lo, hi) = mesh.bounding_box().unwrap();
    camera.frame(lo.as_vec3(), hi.as_vec3());
    let zebra = SurfaceMode::Zebra { stripes: 12.0, angle_degrees: 0.0, width_ratio: 0.5 };
    let (w, h) = (1280, 800);
    let repeats = 5;
    let empty = median(repeats, || {
        offscreen::render_image(&gpu, &mut renderer, &Scene::new(camera, None, zebra), w, h).unwrap();
    });
    let frame = median(repeats, || {
        offscreen::render_image(&gpu, &mut renderer, &Scene::new(camera, Some(&surface), zebra), w, h).unwrap();
    });
    println!(
        "zebra, {triangles} triangles at {w}x{h}: {:.1} ms a frame (with read-back); empty frame {:.1} ms; ratio {:.1}x",
        frame.as_secs_f64() * 1e3,
        empty.as_secs_f64() * 1e3,
        frame.as_secs_f64() / empty.as_secs_f64()
    );

    // Uploads: positions only (the same connectivity) against a rebuilt connectivity.
    let moved = sheet(708, 0.3);
    let mut dragged = mesh.clone();
    let wait = |gpu: &Gpu| {
        gpu.queue.submit([]);
        gpu.device.poll(wgpu::PollType::wait_indefinitely()).unwrap();
    };
    let mut flip = false;
    let positions_only = median(repeats, || {
        flip = !flip;
        dragged.positions_mut().copy_from_slice(if flip { moved.positions() } else { mesh.positions() });
        let changes = buffers.update(&dragged);
        assert!(!changes.indices);
        surface.upload(&gpu.device, &gpu.queue, &buffers, changes);
        wait(&gpu);
    });
    // Two separately built meshes: each switch is a new connectivity for the buffers.
    let rebuilt = [sheet(708, 0.3), sheet(708, 0.0)];
    let mut k = 0;
    let full = median(repeats, || {
        k += 1;
        let changes = buffers.update(&rebuilt[k % 2]);
        assert!(changes.indices);
        surface.upload(&gpu.device, &gpu.queue, &buffers, changes);
        wait(&gpu);
    });
    println!(
        "upload after a drag (positions and normals only) {:.1} ms; full upload with new indices {:.1} ms; ratio {:.2}",
        positions_only.as_secs_f64() * 1e3,
        full.as_secs_f64() * 1e3,
        positions_only.as_secs_f64() / full.as_secs_f64()
    );
}
