//! Hostile outputs and the inputs behind the last NaNs, end to end through the real binary: an
//! output path naming a FIFO (as a device would) or a read-only file is refused by every
//! command and left as it was; a command with two outputs checks both before it writes either;
//! an almost straight segment, an absurd curve-mesh edit, `--iterations 0` and a model
//! 1e-320 across are refused in one line with nothing written; a refusal quoting a huge value
//! stays short; a note goes to stdout.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn taut(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_taut")).args(args).output().expect("the taut binary runs")
}

fn asset(name: &str) -> String {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../assets").join(name).to_string_lossy().into_owned()
}

struct Scratch(PathBuf);

impl Scratch {
    fn new(test: &str) -> Self {
        let dir = std::env::temp_dir().join(format!("taut-cli-outputs-{}-{test}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        Scratch(dir)
    }

    fn path(&self, name: &str) -> String {
        self.0.join(name).to_string_lossy().into_owned()
    }

    fn write(&self, name: &str, text: &str) -> String {
        std::fs::write(self.0.join(name), text).unwrap();
        self.path(name)
    }
}

impl Drop for Scratch {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

/// A failure: non-zero exit (not a signal) and exactly one line on stderr, naming the problem.
fn one_line_failure(out: &Output, expected: &str) {
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.code().is_some_and(|c| c != 0), "expected a clean failure: {:?}; stderr: {stderr}", out.status);
    assert_eq!(stderr.trim_end().lines().count(), 1, "not one line: {stderr:?}");
    assert!(stderr.starts_with("error: ") && stderr.contains(expected), "expected '{expected}' in {stderr:?}");
}

/// Every command with an output, with a small valid input each, and the output's extension.
fn commands(dir: &Scratch) -> Vec<(Vec<String>, &'static str)> {
    let points =
        dir.write("points.json", r#"{"points": [[0,0],[1,0.1],[2,0.4],[3,0.9],[4,1.6],[5,2.5],[6,3.6],[7,4.9]]}"#);
    let curve = dir.write("curve.json", r#"{"points": [[0,0,0],[1,1,0],[2,0,0]]}"#);
    let sides = dir.write(
        "sides.json",
        r#"{"curves": [{"points": [[0,0,0],[1,0,0]]}, {"points": [[1,0,0],[1,1,0]]},
                       {"points": [[1,1,0],[0,1,0]]}, {"points": [[0,1,0],[0,0,0]]}]}"#,
    );
    let grid = dir.write(
        "grid.json",
        r#"{"grid": [[[0,0,0],[1,0,0],[2,0,0]], [[0,1,0],[1,1,0.1],[2,1,0]], [[0,2,0],[1,2,0],[2,2,0]]]}"#,
    );
    let cube = asset("cube.obj");
    let v = |a: &[&str]| a.iter().map(|s| s.to_string()).collect::<Vec<_>>();
    vec![
        (v(&["smooth", &cube, "--levels", "1"]), "obj"),
        (v(&["subdivide", &cube, "--levels", "1"]), "obj"),
        (v(&["smooth-curve", &curve, "--insert", "1"]), "json"),
        (v(&["render", &cube, "--software"]), "png"),
        (v(&["cage", &cube, "--faces", "8"]), "obj"),
        (v(&["fair", &points, "--alpha", "1", "--window", "2"]), "json"),
        (v(&["aesthetic-curve", "--p0", "0,0", "--p1", "1,0", "--p2", "1.5,1.2", "--alpha", "1"]), "json"),
        (v(&["coons", &sides, "--samples", "2"]), "obj"),
        (v(&["fair-surface", &grid]), "json"),
        (v(&["lcg", &points]), "png"),
        (v(&["curve-mesh", &cube]), "obj"),
    ]
}

#[cfg(unix)]
#[test]
fn a_fifo_or_a_read_only_file_at_the_output_is_refused_by_every_command_and_left_alone() {
    use std::os::unix::fs::{FileTypeExt, PermissionsExt};
    let dir = Scratch::new("special");
    for (args, ext) in commands(&dir) {
        let name = &args[0];
        // A named pipe stands for any device node: a write would replace it with a plain file.
        let fifo = dir.path(&format!("{name}-fifo.{ext}"));
        let made = Command::new("mkfifo").arg(&fifo).status().expect("mkfifo runs");
        assert!(made.success());
        let mut call: Vec<&str> = args.iter().map(String::as_str).collect();
        call.extend(["-o", &fifo]);
        one_line_failure(&taut(&call), "not a regular file");
        let kind = std::fs::symlink_metadata(&fifo).unwrap().file_type();
        assert!(kind.is_fifo(), "{name}: the FIFO was replaced");

        let locked = dir.write(&format!("{name}-locked.{ext}"), "keep me");
        std::fs::set_permissions(&locked, std::fs::Permissions::from_mode(0o444)).unwrap();
        let mut call: Vec<&str> = args.iter().map(String::as_str).collect();
        call.extend(["-o", &locked]);
        one_line_failure(&taut(&call), "read-only");
        assert_eq!(std::fs::read_to_string(&locked).unwrap(), "keep me", "{name}: the read-only file changed");
    }
}

#[test]
fn a_second_output_in_a_missing_folder_stops_the_command_before_the_first_is_written() {
    let dir = Scratch::new("second");
    let cube = asset("cube.obj");
    let missing = dir.path("no/such/folder/extra.json");
    // A new main output: never created.
    let out = dir.path("patches.obj");
    one_line_failure(&taut(&["curve-mesh", &cube, "-o", &out, "--curves", &missing]), "does not exist");
    assert!(!Path::new(&out).exists(), "curve-mesh wrote its main output");
    let cage = dir.path("cage.obj");
    one_line_failure(&taut(&["cage", &cube, "-o", &cage, "--faces", "8", "--report", &missing]), "does not exist");
    assert!(!Path::new(&cage).exists(), "cage wrote its main output");
    // An existing main output: untouched.
    let kept = dir.write("kept.obj", "# the designer's file\n");
    one_line_failure(&taut(&["curve-mesh", &cube, "-o", &kept, "--curves", &missing]), "does not exist");
    assert_eq!(std::fs::read_to_string(&kept).unwrap(), "# the designer's file\n");
}

#[test]
fn an_almost_straight_segment_is_refused_instead_of_written_as_nan() {
    let dir = Scratch::new("straight");
    let out = dir.path("segment.json");
    let run = taut(&["aesthetic-curve", "--p0=0,0", "--p1=1,1e-12", "--p2=2,0", "--alpha", "0.5", "-o", &out]);
    one_line_failure(&run, "collinear");
    assert!(!Path::new(&out).exists());
}

#[test]
fn a_curve_mesh_edit_at_1e308_is_refused_when_the_document_is_read() {
    let dir = Scratch::new("far-edit");
    let doc = dir.path("cube.taut");
    assert!(taut(&["curve-mesh", &asset("cube.obj"), "-o", &doc]).status.success());
    let mut json: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&doc).unwrap()).unwrap();
    json["curve_mesh"] = serde_json::json!({
        "shape": [8, 12, 6],
        "vertices": [{"vertex": 0, "position": [1e308, 0.0, 0.0], "normal": [0.0, 0.0, 1.0]}],
        "curves": []
    });
    std::fs::write(&doc, serde_json::to_string(&json).unwrap()).unwrap();
    let out = dir.path("patches.obj");
    one_line_failure(&taut(&["curve-mesh", &doc, "-o", &out]), "cage sizes away");
    assert!(!Path::new(&out).exists());
}

#[test]
fn fair_refuses_zero_iterations_and_keeps_stderr_for_errors() {
    let dir = Scratch::new("fair");
    let planar =
        dir.write("planar.json", r#"{"points": [[0,0],[1,0.1],[2,0.4],[3,0.9],[4,1.6],[5,2.5],[6,3.6],[7,4.9]]}"#);
    let out = dir.path("faired.json");
    one_line_failure(
        &taut(&["fair", &planar, "-o", &out, "--alpha", "1", "--window", "2", "--iterations", "0"]),
        "--iterations 0",
    );
    assert!(!Path::new(&out).exists());
    // Off its plane by a little: the projection note goes to stdout, stderr stays empty.
    let bent = dir.write(
        "bent.json",
        r#"{"points": [[0,0,0],[1,0.1,0.01],[2,0.4,-0.01],[3,0.9,0.01],[4,1.6,-0.01],[5,2.5,0.01],[6,3.6,-0.01],[7,4.9,0]]}"#,
    );
    let run = taut(&["fair", &bent, "-o", &out, "--alpha", "1", "--window", "2"]);
    assert!(run.status.success(), "{}", String::from_utf8_lossy(&run.stderr));
    assert_eq!(String::from_utf8_lossy(&run.stderr), "");
    assert!(String::from_utf8_lossy(&run.stdout).contains("note: the points were projected"));
}

#[test]
fn a_refusal_quotes_a_huge_value_briefly() {
    let dir = Scratch::new("huge");
    let value = "x".repeat(2_000_000);
    let doc =
        dir.write("huge.taut", &format!(r#"{{"format": "{value}", "version": 2, "positions": [], "faces": []}}"#));
    let run = taut(&["smooth", &doc, "-o", &dir.path("out.obj")]);
    one_line_failure(&run, "format");
    assert!(run.stderr.len() < 400, "{} bytes on stderr", run.stderr.len());
}

#[test]
fn a_model_1e_minus_320_across_is_refused() {
    let dir = Scratch::new("tiny");
    let cube = std::fs::read_to_string(asset("cube.obj")).unwrap();
    let tiny: String = cube
        .lines()
        .map(|l| match l.strip_prefix("v ") {
            Some(rest) => {
                let c: Vec<f64> = rest.split_whitespace().map(|x| x.parse::<f64>().unwrap() * 1e-320).collect();
                format!("v {:e} {:e} {:e}\n", c[0], c[1], c[2])
            }
            None => format!("{l}\n"),
        })
        .collect();
    let input = dir.write("tiny.obj", &tiny);
    let out = dir.path("out.obj");
    one_line_failure(&taut(&["subdivide", &input, "-o", &out, "--limit"]), "too small");
    assert!(!Path::new(&out).exists());
}
