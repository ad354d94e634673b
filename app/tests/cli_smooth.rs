//! `taut smooth` run as a designer's script would: the real binary on the bundled cages.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use taut_core::{DVec3, Document, VertexId, io};

fn taut(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_taut")).args(args).output().expect("the taut binary runs")
}

fn asset(name: &str) -> String {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../assets").join(name).to_string_lossy().into_owned()
}

fn scratch(test: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("taut-cli-smooth-{}-{test}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

/// A failure: non-zero exit, one line on stderr naming the problem, no panic.
fn assert_clean_failure(out: &Output, expected: &str) {
    let stderr = text(&out.stderr);
    assert!(!out.status.success(), "expected failure, got success; stderr: {stderr}");
    assert!(!stderr.contains("panicked") && !stderr.contains("RUST_BACKTRACE"), "{stderr}");
    assert!(stderr.contains(expected), "expected '{expected}' in: {stderr}");
    assert_eq!(stderr.trim().lines().count(), 1, "more than one line: {stderr}");
}

#[test]
fn smooths_the_default_scene_to_obj_keeping_cage_vertices_first() {
    let dir = scratch("default");
    let out_path = dir.join("knob.obj");
    let out = taut(&["smooth", &asset("default.taut"), "-o", out_path.to_str().unwrap()]);
    let stdout = text(&out.stdout);
    assert!(out.status.success(), "{}", text(&out.stderr));
    // The document's own levels (4) unless --levels says otherwise.
    for level in 1..=4 {
        assert!(stdout.contains(&format!("level {level}:")) && stdout.contains("iterations, final step"), "{stdout}");
    }
    let cage = Document::load(Path::new(&asset("default.taut"))).unwrap().cage;
    let (surface, _) = io::import_mesh(&out_path).unwrap();
    // Level 1 turns a triangle into 4 triangles and an n-gon into n quads; each later level ×4.
    let level1: usize = cage.faces().map(|f| if cage.face_valence(f) == 3 { 4 } else { cage.face_valence(f) }).sum();
    assert_eq!(surface.face_count(), level1 * 64);
    for v in cage.vertices() {
        assert_eq!(surface.position(v), cage.position(v), "cage vertex {v:?} is not vertex {} of the output", v.0);
    }
    // Smoothed: vertices off the cage's flat faces.
    assert!(surface.positions()[cage.vertex_count()..].iter().any(|p| p.z > 86.0 || p.length() > 70.0));
}

#[test]
fn flags_change_the_surface_and_a_taut_output_keeps_them() {
    let dir = scratch("flags");
    let plain = dir.join("plain.obj");
    let tense = dir.join("tense.glb");
    let doc_path = dir.join("cage.taut");
    let cube = asset("cube.obj");
    assert!(taut(&["smooth", &cube, "-o", plain.to_str().unwrap(), "--levels", "2"]).status.success());
    let out = taut(&[
        "smooth",
        &cube,
        "-o",
        tense.to_str().unwrap(),
        "--levels",
        "2",
        "--lambda",
        "0.3",
        "--tension-vertex",
        "7=4",
        "--tension-edge",
        "0-1=4",
        "--spacing",
        "uniform",
    ]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let (a, _) = io::import_mesh(&plain).unwrap();
    let (b, _) = io::import_mesh(&tense).unwrap();
    assert_eq!(a.vertex_count(), b.vertex_count());
    let moved = a.positions().iter().zip(b.positions()).map(|(p, q)| (*p - *q).length()).fold(0.0, f64::max);
    assert!(moved > 1.0, "tension did not change the surface ({moved})");

    let out = taut(&[
        "smooth",
        &cube,
        "-o",
        doc_path.to_str().unwrap(),
        "--levels",
        "4",
        "--tol",
        "1e-5",
        "--max-iter",
        "900",
        "--tension-vertex",
        "7=3",
        "--tension-edge",
        "0-1=2",
        "--unfix",
        "5",
        "--spacing",
        "centripetal",
    ]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let doc = Document::load(&doc_path).unwrap();
    assert_eq!(doc.settings.levels, 4);
    assert_eq!(doc.settings.tol, 1e-5);
    assert_eq!(doc.settings.max_iterations, 900);
    assert_eq!(doc.vertex_tension[7], 3.0);
    assert_eq!(doc.edge_tension[doc.edge_between(VertexId(0), VertexId(1)).unwrap().index()], 2.0);
    assert!(!doc.fixed[5] && doc.fixed[4]);
    // The document smooths again with its own settings, and the unfixed vertex moves.
    let again = dir.join("again.obj");
    let out = taut(&["smooth", doc_path.to_str().unwrap(), "-o", again.to_str().unwrap(), "--levels", "2"]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let (surface, _) = io::import_mesh(&again).unwrap();
    assert_ne!(surface.position(VertexId(5)), doc.cage.position(VertexId(5)));
    assert_eq!(surface.position(VertexId(4)), doc.cage.position(VertexId(4)));
}

#[test]
fn every_sample_cage_smooths() {
    let dir = scratch("samples");
    for name in ["cube.obj", "prism.obj", "patch.obj", "torus.obj", "knob.obj", "default.taut"] {
        let out_path = dir.join(format!("{name}.glb"));
        let out = taut(&["smooth", &asset(name), "-o", out_path.to_str().unwrap()]);
        assert!(out.status.success(), "{name}: {}", text(&out.stderr));
        let (surface, _) = io::import_mesh(&out_path).unwrap();
        assert!(surface.positions().iter().all(|p: &DVec3| p.is_finite()));
    }
}

#[test]
fn bad_arguments_and_files_fail_with_one_clear_line() {
    let dir = scratch("bad");
    let out_path = dir.join("out.obj");
    let o = out_path.to_str().unwrap();
    let cube = asset("cube.obj");
    assert_clean_failure(&taut(&["smooth", &cube, "-o", o, "--tension-vertex", "99=1"]), "vertex 99 does not exist");
    assert_clean_failure(&taut(&["smooth", &cube, "-o", o, "--tension-vertex", "3"]), "expected V=TAU");
    assert_clean_failure(&taut(&["smooth", &cube, "-o", o, "--tension-vertex", "3=abc"]), "not a number");
    assert_clean_failure(&taut(&["smooth", &cube, "-o", o, "--tension-vertex", "3=-1"]), "≥ 0");
    assert_clean_failure(&taut(&["smooth", &cube, "-o", o, "--tension-edge", "0-7=1"]), "not joined by a cage edge");
    assert_clean_failure(&taut(&["smooth", &cube, "-o", o, "--tension-edge", "07=1"]), "V1-V2=TAU");
    assert_clean_failure(&taut(&["smooth", &cube, "-o", o, "--lambda", "1.5"]), "lambda");
    assert_clean_failure(&taut(&["smooth", &cube, "-o", o, "--levels", "12"]), "too many");
    assert_clean_failure(&taut(&["smooth", &cube, "-o", o, "--unfix", "8"]), "does not exist");
    assert_clean_failure(&taut(&["smooth", &cube, "-o", dir.join("x.stl").to_str().unwrap()]), "unsupported output");
    let missing = dir.join("missing.obj");
    assert_clean_failure(&taut(&["smooth", missing.to_str().unwrap(), "-o", o]), "missing.obj");

    let garbage = dir.join("garbage.taut");
    std::fs::write(&garbage, b"\x00\x01not json").unwrap();
    assert_clean_failure(&taut(&["smooth", garbage.to_str().unwrap(), "-o", o]), "garbage.taut");
    let nan = dir.join("nan.obj");
    std::fs::write(&nan, "v 0 0 0\nv 1 0 0\nv nan 1 0\nf 1 2 3\n").unwrap();
    assert_clean_failure(&taut(&["smooth", nan.to_str().unwrap(), "-o", o]), "nan.obj");
    let out_of_range = dir.join("range.obj");
    std::fs::write(&out_of_range, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n").unwrap();
    assert_clean_failure(&taut(&["smooth", out_of_range.to_str().unwrap(), "-o", o]), "range.obj");
    let nonmanifold = dir.join("fin.obj");
    std::fs::write(&nonmanifold, "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 -1 0\nv 0 0 1\nf 1 2 3\nf 2 1 4\nf 1 2 5\n").unwrap();
    assert_clean_failure(&taut(&["smooth", nonmanifold.to_str().unwrap(), "-o", o]), "non-manifold edge");
    assert!(!out_path.exists(), "a failed command must not write its output");
}
