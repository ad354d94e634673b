//! `taut curve-mesh` run as a designer's script would: the real binary on the bundled cages.

use serde_json::Value;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use taut_core::gregory::CurveMesh;
use taut_core::{DVec3, Document, io};

fn taut(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_taut")).args(args).output().expect("the taut binary runs")
}

fn asset(name: &str) -> String {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../assets").join(name).to_string_lossy().into_owned()
}

fn scratch(test: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("taut-cli-curve-mesh-{}-{test}", std::process::id()));
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

/// The number after `label` in the command's output.
fn figure(stdout: &str, label: &str) -> f64 {
    let line = stdout.lines().find(|l| l.starts_with(label)).unwrap_or_else(|| panic!("no '{label}' in {stdout}"));
    line[label.len()..].split_whitespace().next().unwrap().parse().unwrap_or_else(|_| panic!("{line}"))
}

fn point(v: &Value) -> DVec3 {
    let a: Vec<f64> = v.as_array().unwrap().iter().map(|c| c.as_f64().unwrap()).collect();
    DVec3::new(a[0], a[1], a[2])
}

#[test]
fn the_default_scene_to_obj_with_curves_and_report() {
    let dir = scratch("default");
    let (obj, json) = (dir.join("knob.obj"), dir.join("curves.json"));
    let out = taut(&[
        "curve-mesh",
        &asset("default.taut"),
        "-o",
        obj.to_str().unwrap(),
        "--curves",
        json.to_str().unwrap(),
        "--report",
    ]);
    let stdout = text(&out.stdout);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let cage = Document::load(Path::new(&asset("default.taut"))).unwrap().cage;
    let (mesh, report) = CurveMesh::from_cage(&cage).unwrap();
    assert!(stdout.contains("subdivided once first"), "{stdout}");

    // The report's figures are the core's.
    let angle = figure(&stdout, "largest normal angle across shared boundaries:");
    assert!(angle <= 1e-6, "{angle}");
    let fit = figure(&stdout, "largest limit-point-to-curve distance:");
    assert!((fit - report.fit.max_limit_to_curve).abs() < 1e-6, "{fit}");
    let close =
        figure(&stdout, "largest distance from interior Catmull–Clark limit points (two levels down) to their patch:");
    assert!((close - report.closeness.max_distance).abs() < 1e-6, "{close}");
    assert_eq!(figure(&stdout, "α ≤ 0 guards taken:"), 0.0);

    // The OBJ: one closed surface (shared boundary samples), a group per patch, unit normals.
    let body = std::fs::read_to_string(&obj).unwrap();
    let groups = body.lines().filter(|l| l.starts_with("g patch_")).count();
    assert_eq!(groups, mesh.patch_count());
    assert!(body.lines().any(|l| l == "s 1"));
    let v = body.lines().filter(|l| l.starts_with("v ")).count();
    let normals: Vec<DVec3> = body
        .lines()
        .filter(|l| l.starts_with("vn "))
        .map(|l| {
            let c: Vec<f64> = l[3..].split_whitespace().map(|x| x.parse().unwrap()).collect();
            DVec3::new(c[0], c[1], c[2])
        })
        .collect();
    assert_eq!(normals.len(), v);
    assert!(normals.iter().all(|n| (n.length() - 1.0).abs() < 1e-12));
    let (surface, import) = io::import_mesh(&obj).unwrap();
    assert!(import.is_clean(), "{import}");
    assert_eq!(surface.face_count(), mesh.patch_count() * 256);
    assert!(surface.is_closed() && surface.euler_characteristic() == cage.euler_characteristic());

    // The JSON: four Bézier points per curve, 20 Gregory points per patch, exactly the core's.
    let doc: Value = serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    assert_eq!(doc["format"], "taut-curve-mesh");
    let curves = doc["curves"].as_array().unwrap();
    assert_eq!(curves.len(), mesh.curve_count());
    for (e, c) in mesh.topology().edges().zip(curves) {
        let points: Vec<DVec3> = c["points"].as_array().unwrap().iter().map(point).collect();
        assert_eq!(points, mesh.curve(e).points.to_vec());
    }
    let patches = doc["patches"].as_array().unwrap();
    assert_eq!(patches.len(), mesh.patch_count());
    assert_eq!(doc["patch_point_order"].as_array().unwrap().len(), 20);
    for (f, p) in mesh.topology().faces().zip(patches) {
        let points: Vec<DVec3> = p["points"].as_array().unwrap().iter().map(point).collect();
        assert_eq!(points, mesh.patch(f).control_points().to_vec());
        let corner = p["corners"][0].as_u64().unwrap() as u32;
        assert_eq!(points[0], mesh.vertex_position(taut_core::VertexId(corner)));
    }
}

#[test]
fn glb_output_and_samples() {
    let dir = scratch("glb");
    let glb = dir.join("cube.glb");
    let out = taut(&["curve-mesh", &asset("cube.obj"), "-o", glb.to_str().unwrap(), "--samples", "5"]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let bytes = std::fs::read(&glb).unwrap();
    assert_eq!(&bytes[..4], b"glTF");
    let json_length = u32::from_le_bytes(bytes[12..16].try_into().unwrap()) as usize;
    let doc: Value = serde_json::from_slice(&bytes[20..20 + json_length]).unwrap();
    let primitives = doc["meshes"][0]["primitives"].as_array().unwrap();
    assert_eq!(primitives.len(), 1, "one merged mesh");
    assert!(primitives[0]["attributes"]["NORMAL"].is_u64());
    // 6 patches × 5² quads × 2 triangles; vertices: 8 corners + 12 curves × 4 + 6 × 4².
    let indices = &doc["accessors"][primitives[0]["indices"].as_u64().unwrap() as usize];
    assert_eq!(indices["count"].as_u64().unwrap(), 3 * 2 * 6 * 25);
    let positions = &doc["accessors"][primitives[0]["attributes"]["POSITION"].as_u64().unwrap() as usize];
    assert_eq!(positions["count"].as_u64().unwrap(), 8 + 12 * 4 + 6 * 16);
    let (surface, _) = io::import_mesh(&glb).unwrap();
    assert_eq!(surface.face_count(), 2 * 6 * 25);
    assert!(surface.is_closed());
}

#[test]
fn the_papers_prism_report_names_the_cage_edge_figures() {
    let dir = scratch("prism");
    let out = taut(&["curve-mesh", &asset("prism30.obj"), "-o", dir.join("p.obj").to_str().unwrap(), "--report"]);
    let stdout = text(&out.stdout);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let line = stdout.lines().find(|l| l.starts_with("on the cage's own edges")).expect(&stdout);
    assert!(line.contains("level-2 vertex to limit point 0.84") && line.contains("longest cage edge 35.2"), "{line}");
}

#[test]
fn bad_arguments_and_inputs_fail_cleanly() {
    let dir = scratch("bad");
    let out_obj = dir.join("x.obj");
    let o = out_obj.to_str().unwrap();
    assert_clean_failure(
        &taut(&["curve-mesh", &asset("cube.obj"), "-o", dir.join("x.stl").to_str().unwrap()]),
        "use .obj, .glb, .step or .taut",
    );
    assert_clean_failure(&taut(&["curve-mesh", &asset("cube.obj"), "-o", o, "--samples", "0"]), "--samples 0");
    assert_clean_failure(
        &taut(&["curve-mesh", &asset("cube.obj"), "-o", o, "--curves", dir.join("c.txt").to_str().unwrap()]),
        ".json",
    );
    assert_clean_failure(&taut(&["curve-mesh", dir.join("missing.obj").to_str().unwrap(), "-o", o]), "missing.obj");
    // A non-manifold edge (three faces on one edge).
    let nonmanifold = dir.join("fin.obj");
    std::fs::write(&nonmanifold, "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 -1 0\nv 0 0 1\nf 1 2 3\nf 2 1 4\nf 1 2 5\n").unwrap();
    let out = taut(&["curve-mesh", nonmanifold.to_str().unwrap(), "-o", o]);
    assert_clean_failure(&out, "fin.obj");
    assert!(!out_obj.exists(), "nothing is written on failure");
    // A file with no faces.
    let points = dir.join("points.obj");
    std::fs::write(&points, "v 0 0 0\nv 1 0 0\n").unwrap();
    assert!(!taut(&["curve-mesh", points.to_str().unwrap(), "-o", o]).status.success());
}

#[test]
fn valence_two_vertices_and_isolated_vertices_are_handled() {
    // A cube with one edge split by a vertex of valence 2 and an unused vertex: built, closed.
    let dir = scratch("odd");
    let cage = dir.join("odd.obj");
    std::fs::write(
        &cage,
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nv 0 0 1\nv 1 0 1\nv 0 1 1\nv 1 1 1\nv 0.5 0 0\nv 5 5 5\n\
         f 1 3 4 2 9\nf 5 6 8 7\nf 1 9 2 6 5\nf 3 7 8 4\nf 1 5 7 3\nf 2 4 8 6\n",
    )
    .unwrap();
    let obj = dir.join("odd-out.obj");
    let out = taut(&["curve-mesh", cage.to_str().unwrap(), "-o", obj.to_str().unwrap(), "--report"]);
    let stdout = text(&out.stdout);
    assert!(out.status.success(), "{}", text(&out.stderr));
    assert!(figure(&stdout, "largest normal angle across shared boundaries:") <= 1e-6, "{stdout}");
    let (surface, _) = io::import_mesh(&obj).unwrap();
    assert!(surface.positions().iter().all(|p| p.is_finite()));
}

#[test]
fn a_taut_output_is_the_document_in_curve_mesh_scheme_and_keeps_the_edits() {
    use taut_core::Edit;
    use taut_core::surface::SchemeKind;
    let dir = scratch("taut");
    let first = dir.join("cube.taut");
    let out = taut(&["curve-mesh", &asset("cube.obj"), "-o", first.to_str().unwrap()]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let doc = Document::load(&first).expect("a .taut that opens");
    assert_eq!(doc.scheme, SchemeKind::CurveMesh);
    assert!(doc.curve_mesh.is_empty(), "nothing edited yet");
    let (mesh, _) = doc.curve_mesh().unwrap();
    let (built, _) = CurveMesh::from_cage(&doc.cage).unwrap();
    let bits = |m: &CurveMesh| -> Vec<u64> {
        m.patches().iter().flat_map(|p| p.control_points()).flat_map(|q| q.to_array()).map(f64::to_bits).collect()
    };
    assert_eq!(bits(&mesh), bits(&built), "the document's curve mesh is the cage's, bit for bit");

    // An edited document through the command again: the edits reach the .taut and the .obj.
    let mut edited = doc.clone();
    let target = mesh.vertex_position(taut_core::VertexId(0)) + DVec3::new(0.05, -0.02, 0.03);
    edited.apply(Edit::MoveCurveMeshVertices(vec![(taut_core::VertexId(0), target)])).unwrap();
    let edited_path = dir.join("edited.taut");
    edited.save(&edited_path).unwrap();
    let second = dir.join("again.taut");
    let out = taut(&["curve-mesh", edited_path.to_str().unwrap(), "-o", second.to_str().unwrap()]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let again = Document::load(&second).unwrap();
    assert_eq!(again.curve_mesh, edited.curve_mesh, "the edits are carried through, bit for bit");
    assert_eq!(bits(&again.curve_mesh().unwrap().0), bits(&edited.curve_mesh().unwrap().0));
    let export = |input: &Path, name: &str| {
        let obj = dir.join(name);
        let out = taut(&["curve-mesh", input.to_str().unwrap(), "-o", obj.to_str().unwrap(), "--samples", "4"]);
        assert!(out.status.success(), "{}", text(&out.stderr));
        io::import_mesh(&obj).unwrap().0.positions().to_vec()
    };
    let (plain, moved) = (export(&first, "plain.obj"), export(&edited_path, "edited.obj"));
    assert_eq!(plain.len(), moved.len());
    let changed = plain.iter().zip(&moved).filter(|(a, b)| a != b).count();
    // The three patches around the moved corner change (4 × 4 quads each); the other three not.
    assert!(changed > 0 && changed <= 3 * 25, "{changed} of {} exported vertices moved", plain.len());
}
