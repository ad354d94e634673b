//! `taut edit --script`: a script of modelling edits replayed on a bundled cage by the real
//! binary, checked against the same edits applied one by one through the core's validator; bad
//! scripts and outputs fail in one line and write nothing.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use taut_core::document::modelling::{MeshEdit, Script};
use taut_core::surface::SchemeKind;
use taut_core::{Document, EdgeId, Edit, VertexId};

fn taut(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_taut")).args(args).output().expect("the taut binary runs")
}

fn asset(name: &str) -> String {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../assets").join(name).to_string_lossy().into_owned()
}

fn scratch(test: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("taut-cli-edit-{}-{test}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

const SCRIPT: &str = r#"{"taut_edit_script": 1, "edits": [
  {"op":"set_scheme","scheme":"catmull-clark"},
  {"op":"extrude_faces","faces":[1],"distance":40.0},
  {"op":"loop_cut","edge":0,"fraction":0.25},
  {"op":"set_crease","edges":[3,4],"sharpness":"inf"},
  {"op":"set_corner","vertices":[2],"sharpness":1.5},
  {"op":"move_vertices","moves":[[9,[10.5,-20.25,130.0]]]},
  {"op":"inset","faces":[4],"distance":3.0},
  {"op":"triangulate","faces":[2]},
  {"op":"delete_vertices","vertices":[5]}
]}"#;

#[test]
fn a_script_replayed_on_a_cage_gives_the_edits_applied_one_by_one() {
    let dir = scratch("replay");
    let (script_path, out) = (dir.join("edits.json"), dir.join("edited.taut"));
    std::fs::write(&script_path, SCRIPT).unwrap();
    let cube = asset("cube.obj");
    let run = taut(&["edit", &cube, "--script", script_path.to_str().unwrap(), "-o", out.to_str().unwrap()]);
    let stdout = String::from_utf8_lossy(&run.stdout);
    assert!(run.status.success(), "{}", String::from_utf8_lossy(&run.stderr));
    assert!(stdout.contains("replayed 9 edits"), "{stdout}");
    let written = Document::load(&out).unwrap();

    // The same edits, by hand, through the validator every edit goes through.
    let (cage, _) = taut_core::io::import_mesh_with(Path::new(&cube), &Default::default()).unwrap();
    let mut doc = Document::new(cage);
    let edits = vec![
        Edit::SetScheme(SchemeKind::CatmullClark),
        Edit::Mesh(MeshEdit::ExtrudeFaces { faces: vec![1], distance: 40.0 }),
        Edit::Mesh(MeshEdit::LoopCut { edge: 0, fraction: 0.25 }),
        Edit::SetCrease(vec![EdgeId(3), EdgeId(4)], f64::INFINITY),
        Edit::SetCorner(vec![VertexId(2)], 1.5),
        Edit::MoveVertices(vec![(VertexId(9), taut_core::DVec3::new(10.5, -20.25, 130.0))]),
        Edit::Mesh(MeshEdit::Inset { faces: vec![4], distance: 3.0 }),
        Edit::Mesh(MeshEdit::Triangulate { faces: Some(vec![2]) }),
        Edit::Mesh(MeshEdit::DeleteVertices { vertices: vec![5] }),
    ];
    for edit in edits {
        assert!(doc.apply(edit).unwrap());
    }
    assert_eq!(written.cage.polygons(), doc.cage.polygons());
    assert_eq!(written.to_json(), doc.to_json(), "the file holds the same document");
    // The script's own reading agrees too.
    let mut replayed = Document::new(taut_core::io::import_mesh_with(Path::new(&cube), &Default::default()).unwrap().0);
    Script::from_json(SCRIPT).unwrap().replay(&mut replayed).unwrap();
    assert_eq!(replayed.to_json(), doc.to_json());

    // An OBJ output is the edited cage's polygons.
    let obj = dir.join("edited.obj");
    let run = taut(&["edit", &cube, "--script", script_path.to_str().unwrap(), "-o", obj.to_str().unwrap()]);
    assert!(run.status.success(), "{}", String::from_utf8_lossy(&run.stderr));
    let (mesh, _) = taut_core::io::import_mesh_with(&obj, &Default::default()).unwrap();
    assert_eq!(mesh.face_count(), doc.cage.face_count());
}

#[test]
fn a_bad_script_or_output_fails_in_one_line_and_writes_nothing() {
    let dir = scratch("bad");
    let cube = asset("cube.obj");
    let cases: [(&str, &str, &str); 5] = [
        (r#"{"taut_edit_script": 1, "edits": [{"op":"explode"}]}"#, "out.taut", "cannot be read"),
        (r#"{"taut_edit_script": 3, "edits": []}"#, "out.taut", "version 3"),
        (
            r#"{"taut_edit_script": 1, "edits": [{"op":"delete_faces","faces":[0]},{"op":"inset","faces":[9],"distance":1}]}"#,
            "out.taut",
            "edit 2 of the script",
        ),
        (
            r#"{"taut_edit_script": 1, "edits": [{"op":"extrude_faces","faces":[1],"distance":1e999}]}"#,
            "out.taut",
            "cannot be read",
        ),
        (r#"{"taut_edit_script": 1, "edits": []}"#, "out.step", "use .taut, .obj or .glb"),
    ];
    for (k, (script, output, said)) in cases.iter().enumerate() {
        let script_path = dir.join(format!("bad-{k}.json"));
        std::fs::write(&script_path, script).unwrap();
        let out = dir.join(format!("{k}-{output}"));
        let run = taut(&["edit", &cube, "--script", script_path.to_str().unwrap(), "-o", out.to_str().unwrap()]);
        let stderr = String::from_utf8_lossy(&run.stderr);
        assert!(!run.status.success(), "case {k} should fail");
        assert!(stderr.contains(said), "case {k}: {stderr}");
        assert_eq!(stderr.trim().lines().count(), 1, "case {k}: {stderr}");
        assert!(!out.exists(), "case {k}: a failed edit writes nothing");
    }
    // The script itself is never the output.
    let script_path = dir.join("edits.json");
    std::fs::write(&script_path, r#"{"taut_edit_script": 1, "edits": []}"#).unwrap();
    let s = script_path.to_str().unwrap();
    let run = taut(&["edit", &cube, "--script", s, "-o", s]);
    assert!(!run.status.success());
    assert_eq!(std::fs::read_to_string(&script_path).unwrap(), r#"{"taut_edit_script": 1, "edits": []}"#);
}
