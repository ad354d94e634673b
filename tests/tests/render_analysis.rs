//! The draft-angle and highlight-line views on Mesa's software rasteriser (lavapipe), against
//! closed forms and golden pictures: the draft classes of a cone of known half-angle, the
//! highlight lines of a cylinder where `atan(offset / height)` puts them, and the default scene
//! in both views. `UPDATE_SNAPSHOTS=1` rewrites the references (look at them first).
//!
//! These tests fail, never skip, when no adapter is found: the message says what to install.

use std::f64::consts::PI;
use std::path::Path;
use taut_core::{DVec3, Document, PolyMesh, surface};
use taut_render::analysis::{self, LightTubes, Pull};
use taut_render::overlay::OverlayData;
use taut_render::passes::surface::SurfaceMode;
use taut_render::picture::{Picture, View};
use taut_tests::golden::{DEFAULT_TOLERANCE, Display, check, display};

const SIZE: (u32, u32) = (480, 320);

/// The picture as `taut render` composes it, and its camera.
fn render(picture: &Picture<'_>) -> image::RgbaImage {
    let mut display = display().lock().unwrap_or_else(|e| e.into_inner());
    let Display { gpu, renderer } = &mut *display;
    picture.render(gpu, renderer, &OverlayData::default()).unwrap()
}

fn picture<'a>(mesh: &'a PolyMesh, normals: Option<&'a [DVec3]>, mode: SurfaceMode, view: (f32, f32)) -> Picture<'a> {
    Picture {
        mesh,
        normals,
        values: None,
        mode,
        view: View { azimuth: view.0, elevation: view.1, distance: None },
        width: SIZE.0,
        height: SIZE.1,
    }
}

/// A surface of revolution about `axis` (unit), open at both ends: `rings` circles of `n`
/// points, the point `(r, s)` of `profile` at radius r and height s, with exact normals from the
/// profile's direction.
fn revolved(axis: DVec3, n: u32, profile: &[(f64, f64)]) -> (PolyMesh, Vec<DVec3>) {
    let a = axis.any_orthonormal_vector();
    let b = axis.cross(a);
    let (mut points, mut normals) = (Vec::new(), Vec::new());
    let (r0, s0) = profile[0];
    let (r1, s1) = profile[profile.len() - 1];
    // A straight generator: the normal turns the profile's tangent (dr, ds) by −90°.
    let (dr, ds) = (r1 - r0, s1 - s0);
    let len = (dr * dr + ds * ds).sqrt();
    let (nr, ns) = (ds / len, -dr / len);
    for &(r, s) in profile {
        for k in 0..n {
            let t = 2.0 * PI * k as f64 / n as f64;
            let radial = t.cos() * a + t.sin() * b;
            points.push(r * radial + s * axis);
            normals.push(nr * radial + ns * axis);
        }
    }
    let mut faces = Vec::new();
    for j in 0..profile.len() as u32 - 1 {
        for k in 0..n {
            let (v, w) = (j * n + k, j * n + (k + 1) % n);
            faces.push([v, w, w + n, v + n]);
        }
    }
    (PolyMesh::from_polygons(points, &faces).unwrap(), normals)
}

/// A frustum of a cone of half-angle `alpha_deg` about +Z, narrowing upwards (apex up).
fn frustum(alpha_deg: f64) -> (PolyMesh, Vec<DVec3>) {
    let height = 1.0;
    let run = height * alpha_deg.to_radians().tan();
    let profile: Vec<(f64, f64)> = (0..=8).map(|j| j as f64 / 8.0).map(|t| (0.8 - t * run, t * height)).collect();
    revolved(DVec3::Z, 128, &profile)
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Class {
    Positive,
    Below,
    Negative,
}

/// The draft class a pixel shows, by hue (shading darkens, but keeps the hue): `None` for the
/// grey background and blends at class edges.
fn class_of(p: &image::Rgba<u8>) -> Option<Class> {
    let (r, g, b) = (p[0] as i32, p[1] as i32, p[2] as i32);
    if g > r + 25 && g > b + 25 {
        Some(Class::Positive)
    } else if r > b + 60 && g > b + 60 && (r - g).abs() < 60 {
        Some(Class::Below)
    } else if r > g + 50 && r > b + 50 {
        Some(Class::Negative)
    } else {
        None
    }
}

fn class_counts(image: &image::RgbaImage) -> [usize; 3] {
    let mut counts = [0; 3];
    for p in image.pixels() {
        if let Some(c) = class_of(p) {
            counts[c as usize] += 1;
        }
    }
    counts
}

/// A cone of half-angle 10° has draft +10° against +Z and −10° against −Z on every face: with a
/// threshold below 10° it is all green, or all red pulled the other way; above 10° all yellow.
/// Pulled towards a camera that looks at its side, the part facing the camera passes and the
/// silhouette (where the surface runs along the view) needs draft.
#[test]
fn a_cone_of_known_half_angle_shows_the_draft_classes() {
    let (mesh, normals) = frustum(10.0);
    let draft = |pull, angle_degrees| {
        let image =
            render(&picture(&mesh, Some(normals.as_slice()), SurfaceMode::Draft { pull, angle_degrees }, (30.0, 25.0)));
        (class_counts(&image), image)
    };
    let ([green, yellow, red], passes) = draft(Pull::Direction(DVec3::Z), 9.0);
    assert!(green > 20_000 && yellow + red < green / 200, "pulled up at 9°: {green} green, {yellow} yellow, {red} red");
    golden("draft-cone-passes", &passes);
    let ([green, yellow, red], _) = draft(Pull::Direction(DVec3::Z), 11.0);
    assert!(
        yellow > 20_000 && green + red < yellow / 200,
        "pulled up at 11°: {green} green, {yellow} yellow, {red} red"
    );
    let ([green, yellow, red], _) = draft(Pull::Direction(-DVec3::Z), 9.0);
    assert!(red > 20_000 && green + yellow < red / 200, "pulled down at 9°: {green} green, {yellow} yellow, {red} red");
    // A pull tilted 15° towards +X: the generator on +X has draft 25°, the one on −X −5°.
    let tilt = 15.0_f64.to_radians();
    let ([green, yellow, red], tilted) = draft(Pull::Direction(DVec3::new(tilt.sin(), 0.0, tilt.cos())), 3.0);
    assert!(green > 5_000 && yellow > 500 && red > 500, "tilted pull: {green} green, {yellow} yellow, {red} red");
    golden("draft-cone-tilted", &tilted);
    let ([green, yellow, _], _) = draft(Pull::View, 5.0);
    assert!(green > 10_000 && yellow > 200, "pulled towards the camera: {green} green, {yellow} yellow");
}

/// Where along the column `x` of `image`, between the rows `rows`, dark lines cross it: the
/// darkness-weighted centres of runs of dark pixels, in pixel coordinates (a pixel's centre at
/// +0.5).
fn dark_line_centres(image: &image::RgbaImage, x: u32, rows: std::ops::Range<u32>) -> Vec<f64> {
    let darkness = |y: u32| (140.0 - image.get_pixel(x, y)[1] as f64).max(0.0);
    let mut centres = Vec::new();
    let mut run: Vec<(f64, f64)> = Vec::new();
    for y in rows {
        let d = darkness(y);
        if d > 0.0 {
            run.push((y as f64 + 0.5, d));
        } else if !run.is_empty() {
            let weight: f64 = run.iter().map(|r| r.1).sum();
            centres.push(run.iter().map(|r| r.0 * r.1).sum::<f64>() / weight);
            run.clear();
        }
    }
    centres
}

/// A cylinder of radius R along the tubes (X), seen from the top: its normal lines pass through
/// the axis, so the line of the tube at offset c across the tubes lies at the angle
/// `θ = atan(c / h)` from the top, h the tubes' height above the axis: at `R sin θ` across. The
/// lines found in the picture lie within a pixel of those points projected by the picture's camera.
#[test]
fn highlight_lines_on_a_cylinder_lie_where_the_closed_form_puts_them() {
    // Radius 1 and length 2.4 about the origin: the display frame's unit is the length's half.
    let (radius, half_length) = (1.0, 1.2);
    let profile: Vec<(f64, f64)> =
        (0..=12).map(|j| (radius, -half_length + 2.0 * half_length * j as f64 / 12.0)).collect();
    let (mesh, normals) = revolved(DVec3::X, 256, &profile);
    let tubes = LightTubes { direction: DVec3::X, spacing: 0.2, count: 11, height: 1.5 };
    let top = (0.0, 90.0);
    let pic = picture(&mesh, Some(normals.as_slice()), SurfaceMode::Highlight(tubes), top);
    let image = render(&pic);
    golden("highlight-cylinder", &image);
    let frame = pic.frame();
    assert!((frame.scale - half_length).abs() < 1e-12 && frame.origin.length() < 1e-12);
    let camera = pic.camera(0).unwrap();
    let clip_from_world = camera.clip_from_view(SIZE.0 as f32 / SIZE.1 as f32) * camera.view_from_world();
    let pixel = |p: DVec3| {
        let c = clip_from_world * p.as_vec3().extend(1.0);
        let (x, y) = (c.x / c.w, c.y / c.w);
        ((x as f64 * 0.5 + 0.5) * SIZE.0 as f64, (0.5 - y as f64 * 0.5) * SIZE.1 as f64)
    };
    let r = radius / frame.scale;
    let expected: Vec<(f64, f64)> = (0..tubes.count)
        .map(|k| {
            let theta = (tubes.offset(k) / tubes.height).atan();
            // Across the tubes is D = E × H = −Y.
            pixel(DVec3::new(0.0, -r * theta.sin(), r * theta.cos()))
        })
        .collect();
    let column = expected[0].0.floor() as u32;
    // Between 50° either side of the top, past the outermost lines (34°).
    let edge = |theta: f64| pixel(DVec3::new(0.0, -r * theta.sin(), r * theta.cos())).1;
    let (y0, y1) = (edge(-50f64.to_radians()), edge(50f64.to_radians()));
    let rows = y0.min(y1).round() as u32..y0.max(y1).round() as u32;
    let mut found = dark_line_centres(&image, column, rows);
    found.sort_by(f64::total_cmp);
    let mut want: Vec<f64> = expected.iter().map(|e| e.1).collect();
    want.sort_by(f64::total_cmp);
    assert!(want.windows(2).all(|w| w[1] - w[0] > 6.0), "lines a few pixels apart: {want:?}");
    assert_eq!(found.len(), want.len(), "found lines at {found:?}, the closed form puts them at {want:?}");
    for (f, w) in found.iter().zip(&want) {
        assert!((f - w).abs() < 1.0, "a line at {f:.2} px, the closed form puts it at {w:.2} px ({found:?})");
    }
}

fn golden(name: &str, image: &image::RgbaImage) {
    if let Err(message) = check(name, image, DEFAULT_TOLERANCE) {
        panic!("{message}");
    }
}

/// The default scene in both views, as `taut render` draws them by default.
#[test]
fn draft_and_highlight_of_the_default_scene() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../assets/default.taut");
    let doc = Document::load(&path).unwrap();
    let surface = surface::solve(&doc).unwrap();
    let draft = SurfaceMode::Draft { pull: Pull::Direction(DVec3::Z), angle_degrees: 3.0 };
    let image = render(&picture(surface.mesh(), surface.normals(), draft, (30.0, 25.0)));
    let [green, yellow, red] = class_counts(&image);
    assert!(green > 1000 && yellow > 1000, "{green} green, {yellow} yellow, {red} red");
    golden("draft-default", &image);
    let highlight = SurfaceMode::Highlight(LightTubes::default());
    let image = render(&picture(surface.mesh(), surface.normals(), highlight, (30.0, 25.0)));
    assert_eq!(LightTubes::default().count, analysis::DEFAULT_TUBE_COUNT);
    golden("highlight-default", &image);
}
