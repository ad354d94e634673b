//! `taut subdivide / smooth / curve-mesh -o X.step`, read back by an independent CAD kernel:
//! OpenCascade (PyPI's `cadquery-ocp-novtk`, in the virtual environment `tests/run-all.sh`
//! makes) through `tests/cad/check_step.py`. Every file must read without failure, be a valid
//! B-rep, enclose one solid with no free edges for a closed cage, hold Taut's volume within
//! 0.1 %, lie within the tolerance of Taut's exact surface at samples the fit never saw, and keep
//! the normals of neighbouring faces within 0.1° except along sharp creases.

mod support;

use serde_json::Value;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use taut_core::Document;
use taut_core::cad;

fn taut(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_taut")).args(args).output().expect("the taut binary runs")
}

fn asset(name: &str) -> String {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../assets").join(name).to_string_lossy().into_owned()
}

struct Scratch(PathBuf);

impl Scratch {
    fn new(test: &str) -> Self {
        let dir = std::env::temp_dir().join(format!("taut-cli-step-{}-{test}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        Scratch(dir)
    }
    fn path(&self, name: &str) -> String {
        self.0.join(name).to_string_lossy().into_owned()
    }
}

impl Drop for Scratch {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

fn ok(out: &Output) -> String {
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    String::from_utf8_lossy(&out.stdout).into_owned()
}

/// What OpenCascade measures of `step` against Taut's `samples` of the same surface; `fitted`
/// says where each patch's `(u, v)` lies on the file's faces (regular regions are merged).
fn check(step: &str, samples: &cad::network::PatchNetwork, fitted: &cad::CadSurface, dir: &Scratch) -> Value {
    let (m, tolerance) = (samples.m, fitted.tolerance);
    let faces: Vec<Value> = samples
        .grids
        .iter()
        .zip(&fitted.placements)
        .map(|(g, place)| {
            let s: Vec<Value> = (0..=m)
                .flat_map(|j| (0..=m).map(move |i| (i, j)))
                .map(|(i, j)| {
                    let p = g[j * (m + 1) + i];
                    let (u, v) = place.map(i as f64 / m as f64, j as f64 / m as f64);
                    serde_json::json!([u, v, p.x, p.y, p.z])
                })
                .collect();
            serde_json::json!({ "samples": s })
        })
        .collect();
    // The middle of every sharp edge, on the surface.
    let layout = &samples.layout;
    let sharp: Vec<Value> = layout
        .edges()
        .filter(|e| samples.sharp[e.index()] && !layout.is_boundary_edge(*e))
        .map(|e| {
            let h = e.halfedge(0);
            let f = layout.face(h);
            let k = layout.face_halfedges(f).position(|x| x == h).unwrap();
            let p = samples.grids[f.index()][samples.at_side(k, m / 2, 0)];
            serde_json::json!([p.x, p.y, p.z])
        })
        .collect();
    let reference = serde_json::json!({ "faces": faces, "sharp_edge_midpoints": sharp, "match_tolerance": tolerance });
    let path = dir.path("reference.json");
    std::fs::write(&path, reference.to_string()).unwrap();
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("../tests/cad/check_step.py");
    let out = Command::new(support::reference_python())
        .arg(&script)
        .arg(step)
        .arg("--reference")
        .arg(&path)
        .output()
        .unwrap();
    assert!(out.status.success(), "check_step.py {step}: {}", String::from_utf8_lossy(&out.stderr));
    serde_json::from_slice(&out.stdout).unwrap()
}

/// The surface sampled `per_side` times per patch side, or half as often where the refinement
/// that takes would be too large (the fit was then checked at its own samples only).
fn samples_or_fewer(doc: &Document, per_side: usize) -> cad::network::PatchNetwork {
    cad::surface_samples(doc, per_side).or_else(|_| cad::surface_samples(doc, per_side / 2)).unwrap()
}

/// The volume the sampled grids enclose (a polyhedron of the surface).
fn volume(samples: &cad::network::PatchNetwork) -> f64 {
    volume_every(samples, 1)
}

/// The volume of the polyhedron through every `stride`-th sample of each grid side.
fn volume_every(samples: &cad::network::PatchNetwork, stride: usize) -> f64 {
    let m = samples.m;
    let n = m / stride;
    let mut v = 0.0;
    for g in &samples.grids {
        let p = |i: usize, j: usize| g[j * stride * (m + 1) + i * stride];
        for j in 0..n {
            for i in 0..n {
                v += p(i, j).dot(p(i + 1, j).cross(p(i + 1, j + 1))) + p(i, j).dot(p(i + 1, j + 1).cross(p(i, j + 1)));
            }
        }
    }
    (v / 6.0).abs()
}

/// Writes `input` as a `.taut` with `command` (which picks the scheme) and `extra` flags, then
/// as STEP from that document; measures the STEP file against the document's exact surface.
fn export_and_measure(dir: &Scratch, command: &str, input: &str, extra: &[&str]) -> (Document, Value, f64) {
    let name = Path::new(input).file_stem().unwrap().to_string_lossy().into_owned();
    let taut_file = dir.path(&format!("{command}-{name}.taut"));
    let mut args = vec![command, input, "-o", &taut_file];
    args.extend_from_slice(extra);
    ok(&taut(&args));
    let step = dir.path(&format!("{command}-{name}.step"));
    let printed = ok(&taut(&[command, &taut_file, "-o", &step]));
    assert!(printed.contains("wrote") && printed.contains("STEP AP214"), "{printed}");
    let doc = Document::load(Path::new(&taut_file)).unwrap();
    let fitted = cad::fit_document(&doc, None).unwrap();
    // Samples the fit never saw: twice as dense (Catmull–Clark: the next level's limit points;
    // curve mesh: 24 per side, between the fit's). NUSD's surface is its finest level: a finer
    // level is another discretisation, so its own points are the reference.
    let per_side = match doc.scheme {
        taut_core::surface::SchemeKind::CurveMesh => 24,
        taut_core::surface::SchemeKind::Nusd => fitted.samples,
        _ => 2 * fitted.samples,
    };
    let samples = samples_or_fewer(&doc, per_side);
    let measured = check(&step, &samples, &fitted, dir);
    assert_eq!(measured["read_status"], true, "{name}: {measured}");
    assert_eq!(measured["valid"], true, "{command} {name}: BRepCheck_Analyzer says invalid: {measured}");
    assert_eq!(measured["misoriented_edges"], 0, "{name}: {measured}");
    assert_eq!(measured["nonmanifold_edges"], 0, "{name}: {measured}");
    assert_eq!(measured["unmatched_reference_faces"], 0, "{name}: {measured}");
    assert_eq!(fitted.placements.len(), samples.grids.len(), "{name}: a place for every patch");
    assert_eq!(measured["faces"].as_u64().unwrap() as usize, fitted.model.faces.len(), "{name}: {measured}");
    assert_eq!(measured["step_faces_unmatched"], 0, "{name}: a STEP face holds no patch: {measured}");
    let distance = measured["max_sample_distance"].as_f64().unwrap();
    assert!(
        distance <= fitted.tolerance,
        "{command} {name}: {distance} from Taut's surface, tolerance {}",
        fitted.tolerance
    );
    let closed = samples.layout.is_closed();
    if closed {
        assert_eq!(measured["solids"], 1, "{name}: {measured}");
        assert_eq!(measured["free_edges"], 0, "{name}: {measured}");
        let step_volume = measured["volume"].as_f64().unwrap();
        let taut_volume = if doc.scheme == taut_core::surface::SchemeKind::Nusd {
            // NUSD's own finest surface is its finest level's points: the volume of the smooth
            // surface through them, extrapolated from the polyhedra through all of them and
            // through every other one (their error falls as the square of the spacing).
            let finest = cad::surface_samples(&doc, fitted.samples).unwrap();
            (4.0 * volume(&finest) - volume_every(&finest, 2)) / 3.0
        } else {
            // The exact surface's volume: the polyhedra of the fit's sampling and twice as
            // dense, extrapolated (their error falls as the square of the spacing).
            let coarse = volume(&cad::surface_samples(&doc, fitted.samples).unwrap());
            let fine = volume(&samples_or_fewer(&doc, 2 * fitted.samples));
            (4.0 * fine - coarse) / 3.0
        };
        assert!(step_volume > 0.0, "{name}: outward normals give a positive volume, not {step_volume}");
        let error = (step_volume - taut_volume).abs() / taut_volume;
        eprintln!("{command} {name}: volume {step_volume} against Taut's {taut_volume} ({error:.2e})");
        assert!(error < 1e-3, "{command} {name}: volume {step_volume} against Taut's {taut_volume} ({error:.2e})");
    } else {
        assert_eq!(measured["solids"], 0, "{name}: an open cage is a surface, not a solid: {measured}");
        assert!(measured["free_edges"].as_u64().unwrap() > 0, "{name}: {measured}");
    }
    (doc, measured, fitted.report.max_surface_gap_degrees)
}

/// The largest angle between neighbouring STEP faces' normals along smooth edges.
fn max_angle(measured: &Value) -> f64 {
    measured["max_normal_angle_deg"].as_f64().unwrap_or(0.0)
}

#[test]
fn catmull_clark_surfaces_of_every_bundled_cage_read_back_valid_within_tolerance_and_g1() {
    let dir = Scratch::new("cc");
    for cage in ["cube.obj", "torus.obj", "prism.obj", "knob.obj", "patch.obj", "prism30.obj"] {
        let (_, measured, _) = export_and_measure(&dir, "subdivide", &asset(cage), &["--scheme", "catmull-clark"]);
        let (faces, patches) = (measured["faces"].as_u64().unwrap(), measured["reference_faces"].as_u64().unwrap());
        eprintln!("{cage}: {patches} patches in {faces} STEP faces");
        if cage == "torus.obj" {
            // Every vertex of the torus is regular: its patches merge into a few large faces.
            assert!(faces * 4 <= patches, "{cage}: {patches} patches in {faces} faces: {measured}");
        }
        let angle = max_angle(&measured);
        assert!(angle <= 0.1, "{cage}: neighbouring faces' normals differ by {angle}° (at most 0.1°): {measured}");
    }
}

#[test]
fn sharp_creases_stay_sharp_and_semi_sharp_ones_smooth() {
    let dir = Scratch::new("crease");
    // The cube's top face ringed by infinitely sharp creases, one semi-sharp edge below.
    let (doc, measured, _) = export_and_measure(
        &dir,
        "subdivide",
        &asset("cube.obj"),
        &[
            "--scheme",
            "catmull-clark",
            "--crease",
            "2-3=inf",
            "--crease",
            "3-7=inf",
            "--crease",
            "7-6=inf",
            "--crease",
            "6-2=inf",
            "--crease",
            "0-1=1.5",
        ],
    );
    assert!(doc.crease.iter().filter(|s| s.is_infinite()).count() == 4, "{:?}", doc.crease);
    assert_eq!(measured["unmatched_sharp_midpoints"], 0, "{measured}");
    assert_eq!(measured["sharp_edges"], 4, "{measured}");
    let sharp = measured["max_sharp_edge_angle_deg"].as_f64().unwrap();
    assert!(sharp > 10.0, "a sharp crease is a G0 edge: its faces meet at {sharp}°");
    assert!(max_angle(&measured) <= 0.1, "{measured}");
}

#[test]
fn curve_mesh_patches_read_back_valid_within_tolerance_and_g1() {
    let dir = Scratch::new("curve-mesh");
    for cage in ["cube.obj", "torus.obj", "prism.obj", "knob.obj", "patch.obj"] {
        let (_, measured, _) = export_and_measure(&dir, "curve-mesh", &asset(cage), &[]);
        let angle = max_angle(&measured);
        assert!(angle <= 0.1, "{cage}: neighbouring faces' normals differ by {angle}° (at most 0.1°): {measured}");
    }
}

#[test]
fn nusd_surfaces_read_back_valid_within_tolerance_and_as_smooth_as_nusd_is() {
    let dir = Scratch::new("nusd");
    // The knob mixes triangles, quads and an octagon; the prism has pentagons.
    for cage in ["cube.obj", "torus.obj", "prism.obj", "patch.obj", "knob.obj"] {
        let (_, measured, own) = export_and_measure(&dir, "smooth", &asset(cage), &[]);
        let angle = max_angle(&measured);
        // NUSD's finest level is tangent continuous only in the limit: the faces may differ by
        // what its own normals differ by across the cage edges, and at most 0.1° more.
        assert!(angle <= own + 0.1, "{cage}: faces differ by {angle}°, NUSD's own normals by {own}°: {measured}");
    }
}

#[test]
fn the_file_declares_ap214_its_units_and_one_solid_of_b_spline_faces() {
    let dir = Scratch::new("golden");
    let step = dir.path("cube.step");
    ok(&taut(&["subdivide", &asset("cube.obj"), "-o", &step, "--scheme", "catmull-clark"]));
    let text = std::fs::read_to_string(&step).unwrap();
    assert!(text.starts_with("ISO-10303-21;\nHEADER;\n"), "{}", &text[..200.min(text.len())]);
    assert!(text.contains("FILE_SCHEMA(('AUTOMOTIVE_DESIGN { 1 0 10303 214 1 1 1 1 }'));"));
    assert!(text.contains("SI_UNIT(.MILLI.,.METRE.)"));
    assert!(text.trim_end().ends_with("END-ISO-10303-21;"));
    let count = |entity: &str| text.matches(&format!("={entity}(")).count();
    assert_eq!(count("B_SPLINE_SURFACE_WITH_KNOTS"), 6);
    assert_eq!(count("ADVANCED_FACE"), 6);
    assert_eq!(count("EDGE_CURVE"), 12);
    // Each edge's 3D curve and, on each of its two faces, its line in the parameter plane.
    assert_eq!(count("B_SPLINE_CURVE_WITH_KNOTS"), 12 + 24);
    assert_eq!(count("SURFACE_CURVE"), 12);
    assert_eq!(count("PCURVE"), 24);
    assert_eq!(count("DEFINITIONAL_REPRESENTATION"), 24);
    assert_eq!(count("ORIENTED_EDGE"), 24);
    assert_eq!(count("VERTEX_POINT"), 8);
    assert_eq!(count("CLOSED_SHELL"), 1);
    assert_eq!(count("MANIFOLD_SOLID_BREP"), 1);
    assert_eq!(count("ADVANCED_BREP_SHAPE_REPRESENTATION"), 1);
    // Inches are declared as a conversion of millimetres, and the same cage reads 25.4 times
    // larger in OpenCascade (whose unit is the millimetre).
    let inches = dir.path("cube-in.step");
    ok(&taut(&["subdivide", &asset("cube.obj"), "-o", &inches, "--scheme", "catmull-clark", "--units", "in"]));
    assert!(std::fs::read_to_string(&inches).unwrap().contains("CONVERSION_BASED_UNIT('INCH'"));
    let volume_of = |path: &str| {
        let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("../tests/cad/check_step.py");
        let out = Command::new(support::reference_python()).arg(&script).arg(path).output().unwrap();
        assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
        serde_json::from_slice::<Value>(&out.stdout).unwrap()["volume"].as_f64().unwrap()
    };
    let ratio = volume_of(&inches) / volume_of(&step);
    assert!((ratio - 25.4f64.powi(3)).abs() < 1e-6 * ratio, "inch / mm volume ratio {ratio}");
}

#[test]
fn refused_surfaces_write_nothing_and_say_why_in_one_line() {
    let dir = Scratch::new("refused");
    let cases: [(&[&str], &str); 4] = [
        (&["subdivide", "--scheme", "loop", "--triangulate"], "Loop"),
        (&["subdivide", "--scheme", "catmull-clark", "--tolerance", "0"], "tolerance"),
        (&["subdivide", "--scheme", "catmull-clark", "--tolerance", "NaN"], "tolerance"),
        (&["subdivide", "--scheme", "catmull-clark", "--units", "furlong"], "furlong"),
    ];
    for (i, (command, message)) in cases.iter().enumerate() {
        let out_path = dir.path(&format!("refused-{i}.step"));
        let input = asset("cube.obj");
        let mut args = vec![command[0], &input, "-o", &out_path];
        args.extend_from_slice(&command[1..]);
        let out = taut(&args);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success(), "{args:?} should fail");
        assert!(stderr.contains(message), "{args:?}: {stderr}");
        assert_eq!(stderr.trim_end().lines().count(), 1, "{args:?}: one line, not {stderr}");
        assert!(!Path::new(&out_path).exists(), "{args:?}: a failed export writes nothing");
    }
    // A read-only destination: the file there is left as it was.
    let kept = dir.path("kept.step");
    std::fs::write(&kept, "keep me").unwrap();
    let out =
        taut(&["subdivide", &asset("cube.obj"), "-o", &format!("{kept}/inside.step"), "--scheme", "catmull-clark"]);
    assert!(!out.status.success());
    assert_eq!(std::fs::read_to_string(&kept).unwrap(), "keep me");
}
