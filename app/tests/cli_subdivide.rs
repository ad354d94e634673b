//! `taut subdivide`, and `smooth` / `render` with another scheme, run as a designer would.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use taut_core::surface::SchemeKind;
use taut_core::{Document, io};

fn taut(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_taut")).args(args).output().expect("the taut binary runs")
}

fn asset(name: &str) -> String {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../assets").join(name).to_string_lossy().into_owned()
}

struct Scratch(PathBuf);

impl Scratch {
    fn new(test: &str) -> Self {
        let dir = std::env::temp_dir().join(format!("taut-cli-subdivide-{}-{test}", std::process::id()));
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
    assert_eq!(String::from_utf8_lossy(&out.stderr), "", "stderr must stay empty on success");
    String::from_utf8_lossy(&out.stdout).into_owned()
}

fn one_line_failure(out: &Output, expected: &str) {
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success(), "expected a failure");
    assert_eq!(stderr.trim_end().lines().count(), 1, "{stderr:?}");
    assert!(stderr.contains(expected), "expected '{expected}' in {stderr:?}");
}

#[test]
fn catmull_clark_levels_count_and_cage_first_numbering() {
    let dir = Scratch::new("cc");
    let out = dir.path("cube.obj");
    let stdout =
        ok(&taut(&["subdivide", &asset("cube.obj"), "-o", &out, "--scheme", "catmull-clark", "--levels", "2"]));
    assert!(stdout.contains("level 2: 98 vertices, 96 faces"), "{stdout}");
    let (mesh, _) = io::import_mesh(Path::new(&out)).unwrap();
    // 6 · 4² quads; the cube's 8 corners come first, moved by the vertex rule (inwards).
    assert_eq!((mesh.vertex_count(), mesh.face_count()), (98, 96));
    let (cube, _) = io::import_mesh(Path::new(&asset("cube.obj"))).unwrap();
    for v in cube.vertices() {
        let (p, q) = (mesh.position(v), cube.position(v));
        assert!(p.length() < q.length() && p.normalize().dot(q.normalize()) > 0.999, "corner {v:?}: {p} vs {q}");
    }
    // --limit: every vertex on the limit surface; the file carries the limit normals.
    let limit = dir.path("limit.obj");
    ok(&taut(&["subdivide", &asset("cube.obj"), "-o", &limit, "--levels", "2", "--limit"]));
    let (on_limit, _) = io::import_mesh(Path::new(&limit)).unwrap();
    assert!(on_limit.position(taut_core::VertexId(0)).length() < mesh.position(taut_core::VertexId(0)).length());
    let text = std::fs::read_to_string(&limit).unwrap();
    assert_eq!(text.lines().filter(|l| l.starts_with("vn ")).count(), 98);
}

#[test]
fn loop_needs_triangles_and_creases_and_taut_output_are_kept() {
    let dir = Scratch::new("loop");
    one_line_failure(
        &taut(&["subdivide", &asset("cube.obj"), "-o", &dir.path("x.obj"), "--scheme", "loop"]),
        "triangulate",
    );
    let out = dir.path("loop.glb");
    let stdout =
        ok(&taut(&["subdivide", &asset("cube.obj"), "-o", &out, "--scheme", "loop", "--triangulate", "--levels", "1"]));
    assert!(stdout.contains("note: triangulated 6 faces into 12"), "{stdout}");
    let (mesh, _) = io::import_mesh(Path::new(&out)).unwrap();
    assert_eq!(mesh.face_count(), 48);
    // A .taut output keeps the scheme, levels and creases for the editor.
    let doc_path = dir.path("creased.taut");
    ok(&taut(&[
        "subdivide",
        &asset("cube.obj"),
        "-o",
        &doc_path,
        "--levels",
        "2",
        "--crease",
        "0-1=inf",
        "--crease",
        "1-3=1.5",
    ]));
    let doc = Document::load(Path::new(&doc_path)).unwrap();
    assert_eq!(doc.scheme, SchemeKind::CatmullClark);
    assert_eq!(doc.subdiv.levels, 2);
    let sharp = doc.edge_between(taut_core::VertexId(0), taut_core::VertexId(1)).unwrap();
    assert_eq!(doc.crease[sharp.index()], f64::INFINITY);
    one_line_failure(
        &taut(&["subdivide", &asset("cube.obj"), "-o", &dir.path("y.obj"), "--crease", "0-7=1"]),
        "not joined by a cage edge",
    );
    one_line_failure(&taut(&["subdivide", &asset("cube.obj"), "-o", &dir.path("y.obj"), "--crease", "0-1=-2"]), "≥ 0");
    one_line_failure(
        &taut(&["subdivide", &asset("cube.obj"), "-o", &dir.path("y.obj"), "--scheme", "nusd"]),
        "use taut smooth",
    );
    one_line_failure(
        &taut(&["subdivide", &asset("cube.obj"), "-o", &dir.path("y.obj"), "--scheme", "bezier"]),
        "unknown scheme",
    );
    // The creased document renders with its scheme.
    let png = dir.path("creased.png");
    let render = Command::new(env!("CARGO_BIN_EXE_taut"))
        .args([
            "render",
            &doc_path,
            "-o",
            &png,
            "--view",
            "zebra",
            "--size",
            "200x150",
            "--software",
            "--overlay",
            "cage",
        ])
        .output()
        .unwrap();
    let stdout = ok(&render);
    assert!(stdout.contains("Catmull–Clark level 2"), "{stdout}");
    // And `smooth` takes the scheme from the file as well.
    let smoothed = dir.path("smoothed.obj");
    assert!(ok(&taut(&["smooth", &doc_path, "-o", &smoothed])).contains("Catmull–Clark"));
}

#[test]
fn corners_keep_their_vertex_in_the_limit_are_saved_and_bad_ones_refused() {
    let dir = Scratch::new("corners");
    let (cube, _) = io::import_mesh(Path::new(&asset("cube.obj"))).unwrap();
    let out = dir.path("cornered.obj");
    let args = ["subdivide", &asset("cube.obj"), "-o", &out, "--levels", "3", "--limit", "--corner", "0=inf"];
    ok(&taut(&args));
    let (mesh, _) = io::import_mesh(Path::new(&out)).unwrap();
    let moved = |v: u32| (mesh.position(taut_core::VertexId(v)) - cube.position(taut_core::VertexId(v))).length();
    assert!(moved(0) < 1e-12, "a sharp corner stays at its cage vertex: {}", moved(0));
    assert!(moved(1) > 0.1, "a smooth corner moves in: {}", moved(1));
    // Semi-sharp: between the smooth and the sharp limit.
    let semi = dir.path("semi.obj");
    ok(&taut(&["subdivide", &asset("cube.obj"), "-o", &semi, "--levels", "3", "--limit", "--corner", "0=1.5"]));
    let (semi_mesh, _) = io::import_mesh(Path::new(&semi)).unwrap();
    let semi_moved = (semi_mesh.position(taut_core::VertexId(0)) - cube.position(taut_core::VertexId(0))).length();
    assert!(semi_moved > 1e-3 && semi_moved < moved(1), "{semi_moved}");
    // A .taut output keeps the corners.
    let doc_path = dir.path("cornered.taut");
    ok(&taut(&["subdivide", &asset("cube.obj"), "-o", &doc_path, "--corner", "3=2.5", "--corner", "5=inf"]));
    let doc = Document::load(Path::new(&doc_path)).unwrap();
    assert_eq!((doc.corner[3], doc.corner[5], doc.corner[0]), (2.5, f64::INFINITY, 0.0));
    let bad = |spec: &str, expected: &str| {
        let path = dir.path("bad.obj");
        one_line_failure(&taut(&["subdivide", &asset("cube.obj"), "-o", &path, "--corner", spec]), expected);
        assert!(!Path::new(&path).exists());
    };
    // Under NUSD the flag is kept in a .taut output but says it shapes only the subdivision schemes.
    let nusd = dir.path("nusd.taut");
    let stdout = ok(&taut(&["smooth", &asset("cube.obj"), "-o", &nusd, "--corner", "0=2"]));
    assert!(stdout.contains("note: --crease and --corner shape the Catmull–Clark and Loop surfaces"), "{stdout}");
    assert_eq!(Document::load(Path::new(&nusd)).unwrap().corner[0], 2.0);
    bad("99=1", "vertex 99 does not exist");
    bad("0=-1", "≥ 0");
    bad("0=soft", "not a number");
    bad("x=1", "not a vertex index");
}
