//! `taut cage` run as a designer would: the real binary on meshes the test writes itself.

use glam::DVec3;
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use taut_core::{Document, io};

fn taut(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_taut")).args(args).output().expect("the taut binary runs")
}

fn scratch(test: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("taut-cli-cage-{}-{test}", std::process::id()));
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
    assert!(!stderr.contains("panicked") && !stderr.contains("internal error"), "{stderr}");
    assert!(stderr.contains(expected), "expected '{expected}' in: {stderr}");
    assert_eq!(stderr.trim().lines().count(), 1, "more than one line: {stderr}");
}

/// A bumpy closed blob: an icosphere split `levels` times, pushed in and out.
fn blob(levels: u32) -> (Vec<DVec3>, Vec<[u32; 3]>) {
    let t = (1.0 + 5f64.sqrt()) / 2.0;
    let mut p: Vec<DVec3> = [
        [-1.0, t, 0.0],
        [1.0, t, 0.0],
        [-1.0, -t, 0.0],
        [1.0, -t, 0.0],
        [0.0, -1.0, t],
        [0.0, 1.0, t],
        [0.0, -1.0, -t],
        [0.0, 1.0, -t],
        [t, 0.0, -1.0],
        [t, 0.0, 1.0],
        [-t, 0.0, -1.0],
        [-t, 0.0, 1.0],
    ]
    .iter()
    .map(|&c| DVec3::from_array(c).normalize())
    .collect();
    let mut f: Vec<[u32; 3]> = vec![
        [0, 11, 5],
        [0, 5, 1],
        [0, 1, 7],
        [0, 7, 10],
        [0, 10, 11],
        [1, 5, 9],
        [5, 11, 4],
        [11, 10, 2],
        [10, 7, 6],
        [7, 1, 8],
        [3, 9, 4],
        [3, 4, 2],
        [3, 2, 6],
        [3, 6, 8],
        [3, 8, 9],
        [4, 9, 5],
        [2, 4, 11],
        [6, 2, 10],
        [8, 6, 7],
        [9, 8, 1],
    ];
    for _ in 0..levels {
        let mut mid = std::collections::HashMap::new();
        let mut next = Vec::with_capacity(f.len() * 4);
        for [a, b, c] in f {
            let mut m = |x: u32, y: u32| {
                *mid.entry((x.min(y), x.max(y))).or_insert_with(|| {
                    p.push(((p[x as usize] + p[y as usize]) / 2.0).normalize());
                    (p.len() - 1) as u32
                })
            };
            let (ab, bc, ca) = (m(a, b), m(b, c), m(c, a));
            next.extend([[a, ab, ca], [ab, b, bc], [ca, bc, c], [ab, bc, ca]]);
        }
        f = next;
    }
    let p = p.into_iter().map(|d| d * (1.0 + 0.3 * (3.0 * d.x).sin() * (2.0 * d.y + 1.0).sin())).collect();
    (p, f)
}

/// Binary STL written here, independently of Taut's readers.
fn write_stl(path: &Path, (p, t): &(Vec<DVec3>, Vec<[u32; 3]>)) {
    let mut bytes = vec![b' '; 80];
    bytes.extend((t.len() as u32).to_le_bytes());
    for tri in t {
        bytes.extend([0u8; 12]);
        for &i in tri {
            bytes.extend(p[i as usize].as_vec3().to_array().iter().flat_map(|c| c.to_le_bytes()));
        }
        bytes.extend([0u8; 2]);
    }
    std::fs::write(path, bytes).unwrap();
}

#[test]
fn a_scan_becomes_a_fitted_cage_with_a_table_and_a_report() {
    let dir = scratch("fit");
    let input = dir.join("blob.stl");
    write_stl(&input, &blob(4));
    let (cage, report) = (dir.join("cage.obj"), dir.join("report.json"));
    let out = taut(&[
        "cage",
        input.to_str().unwrap(),
        "-o",
        cage.to_str().unwrap(),
        "--faces",
        "300",
        "--report",
        report.to_str().unwrap(),
    ]);
    let stdout = text(&out.stdout);
    assert!(out.status.success(), "{}", text(&out.stderr));
    for row in ["QEM only", "fitted", "volume change, 1 Loop step", "Hausdorff / diagonal", "time: import"] {
        assert!(stdout.contains(row), "no '{row}' in: {stdout}");
    }
    let (mesh, _) = io::import_mesh(&cage).unwrap();
    assert_eq!(mesh.face_count(), 300);
    assert!(mesh.is_closed());
    let json: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&report).unwrap()).unwrap();
    let fit = &json["fit"];
    let qem_volume = fit["qem"]["volume_change"].as_f64().unwrap();
    let fitted = &fit["rounds"][0]["evaluation"];
    assert!(fitted["volume_change"].as_f64().unwrap() * 2.0 <= qem_volume, "{fit}");
    assert_eq!(fit["kept_round"], 1, "{}", fit["verdict"]);
    assert!(fit["steps"].as_array().unwrap().iter().any(|s| s["step"] == "solve"));
    assert_eq!(fit["cage_faces"], 300);
    // The limit points of the written cage lie on the original (stated: 1e-9 of the diagonal).
    assert!(fitted["limit_points_max"].as_f64().unwrap() < 1e-9);

    // The same as a .taut document, with a ratio.
    let doc_path = dir.join("cage.taut");
    let out = taut(&["cage", input.to_str().unwrap(), "-o", doc_path.to_str().unwrap(), "--ratio", "0.1"]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let doc = Document::load(&doc_path).unwrap();
    assert_eq!(doc.cage.face_count(), 512);
    let leftovers: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .filter_map(|e| e.ok())
        .filter(|e| e.file_name().to_string_lossy().contains(".tmp-"))
        .collect();
    assert!(leftovers.is_empty());
}

#[test]
fn bad_requests_are_one_line_errors() {
    let dir = scratch("bad");
    let input = dir.join("blob.stl");
    write_stl(&input, &blob(2));
    let inp = input.to_str().unwrap();
    let cage = dir.join("cage.obj");
    let out_path = cage.to_str().unwrap();
    assert_clean_failure(&taut(&["cage", inp, "-o", out_path, "--ratio", "1.5"]), "outside (0, 1]");
    assert_clean_failure(&taut(&["cage", inp, "-o", out_path, "--ratio", "0"]), "outside (0, 1]");
    assert_clean_failure(&taut(&["cage", inp, "-o", out_path, "--faces", "5000"]), "only 320 triangles");
    assert_clean_failure(&taut(&["cage", inp, "-o", out_path, "--rounds", "0"]), "rounds must be at least 1");
    assert_clean_failure(&taut(&["cage", inp, "-o", dir.join("c.stl").to_str().unwrap()]), "unsupported cage file");
    let missing = dir.join("missing.ply");
    assert_clean_failure(&taut(&["cage", missing.to_str().unwrap(), "-o", out_path]), "missing.ply");
    let junk = dir.join("junk.ply");
    std::fs::write(&junk, b"ply\nformat ascii 1.0\nelement vertex 3\n").unwrap();
    assert_clean_failure(&taut(&["cage", junk.to_str().unwrap(), "-o", out_path]), "end_header");
    assert!(!taut(&["cage", inp, "-o", out_path, "--ratio", "0.5", "--faces", "10"]).status.success());
    assert!(!cage.exists());
}

#[test]
fn ctrl_c_cancels_and_leaves_no_file() {
    let dir = scratch("interrupt");
    let input = dir.join("big.stl");
    write_stl(&input, &blob(7));
    let cage = dir.join("cage.glb");
    let child = Command::new(env!("CARGO_BIN_EXE_taut"))
        .args(["cage", input.to_str().unwrap(), "-o", cage.to_str().unwrap(), "--ratio", "0.01"])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    std::thread::sleep(std::time::Duration::from_millis(400));
    let kill = Command::new("kill").args(["-INT", &child.id().to_string()]).status().unwrap();
    assert!(kill.success());
    let out = child.wait_with_output().unwrap();
    assert_clean_failure(&out, "cancelled (Ctrl+C); nothing was written");
    let files: Vec<String> =
        std::fs::read_dir(&dir).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().into_owned()).collect();
    assert_eq!(files, vec!["big.stl".to_string()]);
}
