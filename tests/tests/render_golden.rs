//! Golden pictures of the bundled cages on Mesa's software rasteriser (lavapipe): zebra and
//! curvature views, chord against uniform spacing, with and without tension, and a crease that
//! must break the stripes. `UPDATE_SNAPSHOTS=1` rewrites the references (look at them first);
//! a failure writes `NAME.actual.png` and `NAME.diff.png` next to the reference.
//!
//! These tests fail, never skip, when no adapter is found: the message says what to install.

use std::path::Path;
use taut_core::curvature::{CurvatureQuantity, robust_range};
use taut_core::nusd::Spacing;
use taut_core::surface::{self, ColourBy, SchemeKind, SurfaceScheme};
use taut_core::{DVec3, Document, PolyMesh, VertexId, io};
use taut_render::DisplayFrame;
use taut_render::colormap::{ColorMap, normalize};
use taut_render::overlay::{self, CageControls, CageSelection, Legend, OverlayData};
use taut_render::passes::surface::SurfaceMode;
use taut_render::picture::{Picture, View};
use taut_tests::golden::{DEFAULT_TOLERANCE, Display, check, display};

const SIZE: (u32, u32) = (480, 320);

fn asset(name: &str) -> Document {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../assets").join(name);
    if name.ends_with(".taut") {
        Document::load(&path).unwrap()
    } else {
        Document::new(io::import_mesh(&path).unwrap().0)
    }
}

/// The document's surface, made to the end by its scheme.
fn smooth(doc: &Document) -> Box<dyn SurfaceScheme> {
    surface::solve(doc).unwrap()
}

/// A picture of a mesh as `taut render` composes it (framed to fill the picture left of the
/// legend), with its normals, colour values and overlays (built by `overlays` in the picture's
/// display frame).
fn picture_of(
    mesh: &PolyMesh,
    normals: Option<&[DVec3]>,
    mode: SurfaceMode,
    values: Option<&[f32]>,
    overlays: impl FnOnce(&DisplayFrame) -> OverlayData,
    (azimuth, elevation): (f32, f32),
) -> image::RgbaImage {
    let mut display = display().lock().unwrap_or_else(|e| e.into_inner());
    let Display { gpu, renderer } = &mut *display;
    let picture = Picture {
        mesh,
        normals,
        values,
        mode,
        view: View { azimuth, elevation, distance: None },
        width: SIZE.0,
        height: SIZE.1,
    };
    let data = overlays(&picture.frame());
    picture.render(gpu, renderer, &data).unwrap()
}

fn picture(surface: &dyn SurfaceScheme, mode: SurfaceMode, view: (f32, f32)) -> image::RgbaImage {
    picture_of(surface.mesh(), surface.normals(), mode, None, |_| OverlayData::default(), view)
}

const ZEBRA: SurfaceMode = SurfaceMode::Zebra { stripes: 10.0, angle_degrees: 0.0, width_ratio: 0.5 };
const VIEW: (f32, f32) = (30.0, 25.0);

fn golden(name: &str, image: &image::RgbaImage) {
    if let Err(message) = check(name, image, DEFAULT_TOLERANCE) {
        panic!("{message}");
    }
}

fn curvature_picture(doc: &Document, by: ColourBy, view: (f32, f32)) -> image::RgbaImage {
    let surface = smooth(doc);
    let values = by.values(surface.as_ref()).unwrap();
    let (min, max) = robust_range(&values, by.is_signed());
    let map = if by.is_signed() { ColorMap::Diverging } else { ColorMap::Sequential };
    let legend = Legend { map, min, max, title: overlay::legend_title(by).into() };
    let mode = SurfaceMode::Curvature { map, min: 0.0, max: 1.0 };
    let values = normalize(&values, min, max);
    picture_of(
        surface.mesh(),
        surface.normals(),
        mode,
        Some(&values),
        |_| OverlayData { legend: Some(legend), ..Default::default() },
        view,
    )
}

#[test]
fn zebra_of_every_bundled_cage() {
    for (name, view) in [
        ("default.taut", VIEW),
        ("cube.obj", VIEW),
        ("prism.obj", VIEW),
        ("patch.obj", (20.0, 50.0)),
        ("torus.obj", (30.0, 40.0)),
    ] {
        let surface = smooth(&asset(name));
        golden(&format!("zebra-{}", name.replace('.', "-")), &picture(surface.as_ref(), ZEBRA, view));
    }
}

#[test]
fn curvature_views_with_legends() {
    let curvature = ColourBy::Curvature;
    golden("mean-default", &curvature_picture(&asset("default.taut"), curvature(CurvatureQuantity::Mean), VIEW));
    golden(
        "gaussian-torus",
        &curvature_picture(&asset("torus.obj"), curvature(CurvatureQuantity::Gaussian), (30.0, 40.0)),
    );
    golden("kmax-prism", &curvature_picture(&asset("prism.obj"), curvature(CurvatureQuantity::MaxPrincipal), VIEW));
    let r = ColourBy::parse("r", SchemeKind::Nusd).unwrap();
    golden("r-default", &curvature_picture(&asset("default.taut"), r, VIEW));
}

#[test]
fn chord_and_uniform_spacing_differ_and_tension_shows() {
    let chord = asset("default.taut");
    let mut uniform = chord.clone();
    uniform.settings.spacing = Spacing::Uniform;
    let (a, b) = (smooth(&chord), smooth(&uniform));
    let picture_a = picture(a.as_ref(), ZEBRA, VIEW);
    let picture_b = picture(b.as_ref(), ZEBRA, VIEW);
    golden("zebra-default-uniform", &picture_b);
    // The two spacings give visibly different stripes on the default scene.
    let differing =
        picture_a.pixels().zip(picture_b.pixels()).filter(|(p, q)| (0..3).any(|c| p[c].abs_diff(q[c]) > 64)).count();
    assert!(differing > 2000, "chord and uniform pictures differ in only {differing} pixels");

    let mut tense = chord.clone();
    tense.settings.lambda = 0.3;
    let apex = VertexId(tense.cage.vertex_count() as u32 - 1);
    tense.set_vertex_tension(apex, 3.0).unwrap();
    for k in 0..8 {
        tense.set_edge_tension(VertexId(8 + k), VertexId(16 + k), 2.0).unwrap();
    }
    let t = smooth(&tense);
    let cage = |frame: &DisplayFrame| {
        let controls = CageControls::Nusd {
            fixed: &tense.fixed,
            vertex_tension: &tense.vertex_tension,
            edge_tension: &tense.edge_tension,
        };
        let (lines, points) = overlay::cage_overlay(&tense.cage, controls, &CageSelection::default(), frame);
        OverlayData { on_top_lines: lines, points, ..Default::default() }
    };
    golden("zebra-default-tension-cage", &picture_of(t.mesh(), t.normals(), ZEBRA, None, cage, VIEW));
}

/// A sheet bent about the y axis: `kink` folds it sharply along x = 0 (a crease), otherwise it
/// bends smoothly on a circular arc through the same end points.
fn bent_sheet(kink: bool) -> PolyMesh {
    let n = 80;
    let mut p = Vec::new();
    for j in 0..=n {
        for i in 0..=n {
            let (u, y) = (2.0 * i as f64 / n as f64 - 1.0, 2.0 * j as f64 / n as f64 - 1.0);
            let z = if kink { -0.35 * u.abs() } else { -0.175 * u * u };
            p.push(DVec3::new(u, y, z));
        }
    }
    let mut faces = Vec::new();
    for j in 0..n {
        for i in 0..n {
            let v = j * (n + 1) + i;
            faces.push([v, v + 1, v + n + 2, v + n + 1]);
        }
    }
    PolyMesh::from_polygons(p, &faces).unwrap()
}

/// How much more the picture changes across its centre column than beside it: the mean
/// difference between the columns 3 px left and right of the centre, over the mean difference
/// of column pairs the same 6 px apart further out on both sides, over the rows the surface
/// covers. About 1 where the picture is continuous, large where it jumps.
fn jump_across_centre(image: &image::RgbaImage) -> f64 {
    let (w, h) = image.dimensions();
    let c = w / 2;
    let rows: Vec<u32> = (2 * h / 5..3 * h / 5).collect();
    let change = |a: u32, b: u32| {
        rows.iter().map(|&y| (image.get_pixel(a, y)[0] as f64 - image.get_pixel(b, y)[0] as f64).abs()).sum::<f64>()
            / rows.len() as f64
    };
    let beside = 0.5 * (change(c - 15, c - 9) + change(c + 9, c + 15));
    change(c - 3, c + 3) / beside.max(1.0)
}

#[test]
fn a_crease_breaks_the_stripes_and_a_smooth_bend_does_not() {
    // Seen from the front and a little above, the fold line x = 0 is the picture's centre line.
    let view = (0.0, 35.0);
    let stripes = SurfaceMode::Zebra { stripes: 10.0, angle_degrees: 45.0, width_ratio: 0.5 };
    let none = |_: &DisplayFrame| OverlayData::default();
    let crease = picture_of(&bent_sheet(true), None, stripes, None, none, view);
    let smooth = picture_of(&bent_sheet(false), None, stripes, None, none, view);
    golden("zebra-crease", &crease);
    golden("zebra-smooth-bend", &smooth);
    let (jump_crease, jump_smooth) = (jump_across_centre(&crease), jump_across_centre(&smooth));
    eprintln!("jump across the centre: crease {jump_crease:.2}, smooth bend {jump_smooth:.2}");
    // Framed to fill the picture, each face shows a few wide bands: the fold changes the stripes
    // about twice as much as the same step beside it (measured 1.9; the bend 0.99).
    assert!(jump_smooth < 1.3, "the smooth bend's stripes jump at the centre: {jump_smooth:.2}");
    assert!(jump_crease > 1.6, "the crease does not break the stripes: {jump_crease:.2}");
}

/// A cube with its top face's four edges infinitely sharp, the others smooth.
fn creased_cube() -> Document {
    let mut doc = Document::new(taut_tests::cube()).with_scheme(SchemeKind::CatmullClark);
    let top: Vec<VertexId> = doc.cage.vertices().filter(|&v| doc.cage.position(v).z > 0.0).collect();
    for &a in &top {
        for &b in &top {
            if a < b && doc.cage.find_halfedge(a, b).is_some() {
                doc.set_crease(a, b, f64::INFINITY).unwrap();
            }
        }
    }
    doc
}

/// The subdivision schemes' limit surfaces with their exact normals: Catmull–Clark of the
/// default scene and of a cube with a creased top, Loop of the triangulated knob.
#[test]
fn subdivision_zebra_pictures() {
    let default = asset("default.taut").with_scheme(SchemeKind::CatmullClark);
    golden("zebra-default-catmull-clark", &picture(smooth(&default).as_ref(), ZEBRA, VIEW));
    let cube = smooth(&creased_cube());
    let creased = picture(cube.as_ref(), ZEBRA, VIEW);
    golden("zebra-creased-cube", &creased);
    let knob = asset("knob.obj");
    let triangles =
        taut_core::mesh::edit::triangulate(&knob.cage, None, taut_core::mesh::edit::Triangulation::ShortestDiagonal)
            .unwrap();
    let loop_doc = knob.with_edited_cage(triangles).unwrap().with_scheme(SchemeKind::Loop);
    golden("zebra-knob-loop", &picture(smooth(&loop_doc).as_ref(), ZEBRA, VIEW));
}

/// A Coons patch as the Curves workspace keeps it (four boundary polylines, two of them
/// log-aesthetic segments lifted out of the plane), in zebra with its boundaries over it: the
/// stripes run smoothly across the interior and bend with the curved sides.
#[test]
fn coons_patch_zebra() {
    use taut_core::aesthetic::AestheticSegment;
    use taut_core::curve::CoonsPatch;
    let segment = |p0: DVec3, p1: DVec3, p2: DVec3, alpha: f64| {
        AestheticSegment::from_control_points(p0, p1, p2, alpha).unwrap().expect("the segment exists").sample(41)
    };
    let lift = |points: Vec<DVec3>, h: f64| -> Vec<DVec3> {
        let n = points.len() - 1;
        points
            .into_iter()
            .enumerate()
            .map(|(k, p)| p + DVec3::Z * h * (std::f64::consts::PI * k as f64 / n as f64).sin())
            .collect()
    };
    let (p00, p10, p11, p01) =
        (DVec3::ZERO, DVec3::new(2.0, 0.0, 0.0), DVec3::new(2.0, 1.6, 0.0), DVec3::new(0.0, 1.6, 0.0));
    let bottom = lift(segment(p00, DVec3::new(1.2, -0.5, 0.0), p10, 1.0), 0.3);
    let right: Vec<DVec3> = (0..=20).map(|k| p10.lerp(p11, k as f64 / 20.0)).collect();
    let top = lift(segment(p11, DVec3::new(0.8, 2.1, 0.0), p01, -1.0), 0.5);
    let left: Vec<DVec3> = (0..=20).map(|k| p01.lerp(p00, k as f64 / 20.0)).collect();
    let patch = CoonsPatch { boundaries: [bottom, right, top, left], samples: 40, sources: None };
    let mesh = patch.mesh().unwrap();
    let image = picture_of(
        &mesh,
        None,
        ZEBRA,
        None,
        |frame| {
            let style = overlay::CombStyle { scale: 0.0, curve_width_px: 2.5, ..Default::default() };
            let surface_lines =
                patch.boundaries.iter().flat_map(|b| overlay::polyline_with_comb(b, false, &style, frame)).collect();
            OverlayData { surface_lines, ..Default::default() }
        },
        (25.0, 40.0),
    );
    golden("coons-patch-zebra", &image);
}

/// The default scene as a curve mesh (its Gregory patches with their exact normals, the stripes
/// running on across every curve), and the same with one curve-mesh vertex on the top rim pulled
/// up and out: only the patches around it bend.
#[test]
fn curve_mesh_zebra_pictures() {
    let doc = asset("default.taut").with_scheme(SchemeKind::CurveMesh);
    golden("zebra-default-curve-mesh", &picture(smooth(&doc).as_ref(), ZEBRA, VIEW));
    let mut edited = doc.clone();
    let (m, _) = edited.curve_mesh().unwrap();
    // The highest vertex nearest the camera's side (+x, −y at azimuth 30°).
    let v = m
        .topology()
        .vertices()
        .max_by(|&a, &b| {
            let score = |v| {
                let p = m.vertex_position(v);
                p.z + 0.6 * (p.x - p.y)
            };
            score(a).total_cmp(&score(b))
        })
        .unwrap();
    let lift = m.vertex_normal(v) * 0.03 * doc.cage.bounding_diagonal();
    edited.apply(taut_core::Edit::MoveCurveMeshVertices(vec![(v, m.vertex_position(v) + lift)])).unwrap();
    golden("zebra-default-curve-mesh-edited", &picture(smooth(&edited).as_ref(), ZEBRA, VIEW));
}
