//! Reference images drawn on lavapipe, checked by pixels where the camera puts them.

use super::*;
use crate::offscreen::render_image;
use crate::passes::surface::SurfaceMode;
use crate::{AdapterPreference, Camera, Gpu, GpuSurface, Renderer, Scene, SurfaceBuffers, TargetFormats};
use glam::Vec2;
use taut_core::document::{ReferenceImage, ReferencePlane};
use taut_core::{DVec3, PolyMesh};

const W: u32 = 320;
const H: u32 = 240;
const RED: [u8; 3] = [255, 0, 0];
const GREEN: [u8; 3] = [0, 255, 0];
const BLUE: [u8; 3] = [0, 0, 255];

fn gpu() -> Gpu {
    Gpu::headless(AdapterPreference::Software).unwrap_or_else(|e| panic!("{e}"))
}

/// Looking at the XZ plane from −Y: screen right is +X, up +Z.
fn front_camera() -> Camera {
    Camera { target: glam::Vec3::ZERO, distance: 4.0, azimuth: 0.0, elevation: 0.0, fov_y: 35.0, orthographic: false }
}

fn project(camera: &Camera, p: glam::Vec3) -> Vec2 {
    let clip = camera.clip_from_view(W as f32 / H as f32) * camera.view_from_world() * p.extend(1.0);
    let ndc = clip.truncate() / clip.w;
    Vec2::new((ndc.x * 0.5 + 0.5) * W as f32, (0.5 - ndc.y * 0.5) * H as f32)
}

fn pixel(image: &image::RgbaImage, at: Vec2) -> [u8; 3] {
    let p = image.get_pixel(at.x as u32, at.y as u32).0;
    [p[0], p[1], p[2]]
}

fn near(a: [u8; 3], b: [u8; 3], tolerance: u8) -> bool {
    a.iter().zip(&b).all(|(x, y)| x.abs_diff(*y) <= tolerance)
}

/// A square picture in quadrants: red top left, green top right, blue bottom left, white
/// bottom right.
fn quadrants(key: &str) -> Picture {
    let pixels = image::RgbaImage::from_fn(64, 64, |x, y| {
        image::Rgba(match (x < 32, y < 32) {
            (true, true) => [255, 0, 0, 255],
            (false, true) => [0, 255, 0, 255],
            (true, false) => [0, 0, 255, 255],
            (false, false) => [255, 255, 255, 255],
        })
    });
    Picture { key: PictureKey { path: key.into(), modified: None }, pixels: Arc::new(pixels) }
}

fn black(camera: Camera, surface: Option<&GpuSurface>) -> Scene<'_> {
    Scene { background: [0.0, 0.0, 0.0, 1.0], ..Scene::new(camera, surface, SurfaceMode::Shaded) }
}

/// A square of side 1 around the origin at `y`, facing the camera.
fn square(gpu: &Gpu, y: f64) -> GpuSurface {
    let p = [(-0.5, -0.5), (0.5, -0.5), (0.5, 0.5), (-0.5, 0.5)].map(|(x, z)| DVec3::new(x, y, z)).to_vec();
    let mesh = PolyMesh::from_polygons(p, &[[0, 1, 2, 3]]).unwrap();
    let mut buffers = SurfaceBuffers::default();
    buffers.update(&mesh);
    GpuSurface::new(&gpu.device, &buffers)
}

#[test]
fn a_front_picture_lies_on_its_plane_blends_at_its_opacity_and_uploads_once() {
    let gpu = gpu();
    let targets = TargetFormats::for_adapter(&gpu.adapter, wgpu::TextureFormat::Rgba8UnormSrgb);
    let mut renderer = Renderer::new(&gpu, targets);
    let camera = front_camera();
    let picture = quadrants("quadrants.png");
    let mut image = ReferenceImage::new("quadrants.png", ReferencePlane::Front, 2.0);
    let frame = crate::DisplayFrame::IDENTITY;
    let quads = [ReferenceQuad::new(&image, &picture, &frame)];
    let shot =
        render_image(&gpu, &mut renderer, &Scene { reference_images: &quads, ..black(camera, None) }, W, H).unwrap();
    let at = |x: f32, z: f32| project(&camera, glam::Vec3::new(x, 0.0, z));
    assert!(near(pixel(&shot, at(-0.5, 0.5)), RED, 2), "top left {:?}", pixel(&shot, at(-0.5, 0.5)));
    assert!(near(pixel(&shot, at(0.5, 0.5)), GREEN, 2), "top right {:?}", pixel(&shot, at(0.5, 0.5)));
    assert!(near(pixel(&shot, at(-0.5, -0.5)), BLUE, 2), "bottom left {:?}", pixel(&shot, at(-0.5, -0.5)));
    assert!(near(pixel(&shot, at(0.9, -0.9)), [255; 3], 2));
    // Just past the picture's corner, the background.
    assert_eq!(pixel(&shot, at(-1.05, 1.05)), [0; 3]);
    assert_eq!(pixel(&shot, at(1.1, 0.0)), [0; 3]);
    // Half opacity over black: half the linear red, 188 in sRGB.
    image.opacity = 0.5;
    let quads = [ReferenceQuad::new(&image, &picture, &frame)];
    let half =
        render_image(&gpu, &mut renderer, &Scene { reference_images: &quads, ..black(camera, None) }, W, H).unwrap();
    assert!(near(pixel(&half, at(-0.5, 0.5)), [188, 0, 0], 3), "{:?}", pixel(&half, at(-0.5, 0.5)));
    assert_eq!(renderer.reference_uploads(), 1, "the same picture is uploaded once");
    // Turned a quarter counter-clockwise, the red quadrant is at the bottom left.
    image.opacity = 1.0;
    image.rotation = 90.0;
    let quads = [ReferenceQuad::new(&image, &picture, &frame)];
    let turned =
        render_image(&gpu, &mut renderer, &Scene { reference_images: &quads, ..black(camera, None) }, W, H).unwrap();
    assert!(near(pixel(&turned, at(-0.5, -0.5)), RED, 2), "{:?}", pixel(&turned, at(-0.5, -0.5)));
    // Not drawn: nothing of it is kept; another picture is another upload.
    let other = quadrants("other.png");
    let quads = [ReferenceQuad::new(&image, &other, &frame)];
    render_image(&gpu, &mut renderer, &Scene { reference_images: &quads, ..black(camera, None) }, W, H).unwrap();
    assert_eq!(renderer.reference_uploads(), 2);
}

#[test]
fn behind_stays_behind_the_model_and_in_front_covers_it() {
    let gpu = gpu();
    let targets = TargetFormats::for_adapter(&gpu.adapter, wgpu::TextureFormat::Rgba8UnormSrgb);
    let mut renderer = Renderer::new(&gpu, targets);
    let camera = front_camera();
    let picture = quadrants("quadrants.png");
    // The model is farther from the camera than the picture's plane: "behind" must still hide
    // the picture wherever the model is.
    let surface = square(&gpu, 1.0);
    let plain = render_image(&gpu, &mut renderer, &black(camera, Some(&surface)), W, H).unwrap();
    let on_model = project(&camera, glam::Vec3::new(-0.2, 1.0, 0.2));
    let model = pixel(&plain, on_model);
    let mut image = ReferenceImage::new("quadrants.png", ReferencePlane::Front, 4.0);
    let frame = crate::DisplayFrame::IDENTITY;
    let quads = [ReferenceQuad::new(&image, &picture, &frame)];
    let behind =
        render_image(&gpu, &mut renderer, &Scene { reference_images: &quads, ..black(camera, Some(&surface)) }, W, H)
            .unwrap();
    assert!(near(pixel(&behind, on_model), model, 2), "{:?} vs the model's {model:?}", pixel(&behind, on_model));
    let beside = project(&camera, glam::Vec3::new(-1.5, 0.0, 1.5));
    assert!(near(pixel(&behind, beside), RED, 2), "the picture shows beside the model");
    image.in_front = true;
    image.opacity = 0.5;
    let quads = [ReferenceQuad::new(&image, &picture, &frame)];
    let front =
        render_image(&gpu, &mut renderer, &Scene { reference_images: &quads, ..black(camera, Some(&surface)) }, W, H)
            .unwrap();
    let over = pixel(&front, on_model);
    // Half red over the model: redder than the model, and the model still shows (its green).
    assert!(over[0] > model[0] + 20 && over[1] > 20 && over[1] < model[1], "{over:?} over {model:?}");
}

#[test]
fn a_view_picture_faces_the_camera_from_any_side() {
    let gpu = gpu();
    let targets = TargetFormats::for_adapter(&gpu.adapter, wgpu::TextureFormat::Rgba8UnormSrgb);
    let mut renderer = Renderer::new(&gpu, targets);
    let picture = quadrants("quadrants.png");
    let image = ReferenceImage::new("quadrants.png", ReferencePlane::View, 2.0);
    let frame = crate::DisplayFrame::IDENTITY;
    let quads = [ReferenceQuad::new(&image, &picture, &frame)];
    for (azimuth, elevation) in [(0.0, 0.0), (120.0, 30.0), (-70.0, -60.0)] {
        let camera = Camera { azimuth, elevation, ..front_camera() };
        let shot = render_image(&gpu, &mut renderer, &Scene { reference_images: &quads, ..black(camera, None) }, W, H)
            .unwrap();
        let at = |r: f32, u: f32| project(&camera, camera.right() * r + camera.up() * u);
        assert!(near(pixel(&shot, at(-0.5, 0.5)), RED, 2), "{azimuth}°: {:?}", pixel(&shot, at(-0.5, 0.5)));
        assert!(near(pixel(&shot, at(0.5, -0.5)), [255; 3], 2), "{azimuth}°");
    }
}
