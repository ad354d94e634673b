//! `taut smooth-curve` end to end: the real binary on JSON files in a scratch folder.

use serde_json::{Value, json};
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// A fresh folder under the system temp dir, removed when dropped.
struct Scratch(PathBuf);

impl Scratch {
    fn new(name: &str) -> Scratch {
        let dir = std::env::temp_dir().join(format!("taut-cli-curve-{}-{name}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        Scratch(dir)
    }

    fn write(&self, file: &str, text: &str) -> PathBuf {
        let path = self.0.join(file);
        std::fs::write(&path, text).unwrap();
        path
    }
}

impl Drop for Scratch {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

fn taut(input: &Path, output: &Path, extra: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_taut"))
        .arg("smooth-curve")
        .arg(input)
        .arg("-o")
        .arg(output)
        .args(extra)
        .output()
        .expect("the taut binary runs")
}

fn read_json(path: &Path) -> Value {
    serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap()
}

fn point(v: &Value) -> [f64; 3] {
    let a = v.as_array().unwrap();
    assert_eq!(a.len(), 3);
    [a[0].as_f64().unwrap(), a[1].as_f64().unwrap(), a[2].as_f64().unwrap()]
}

/// Runs a bad input and checks the failure is clean: non-zero status, one line on stderr
/// mentioning `expected`, no panic, no output file. Returns the message.
fn assert_refused(name: &str, input_text: Option<&str>, extra: &[&str], expected: &str) -> String {
    let dir = Scratch::new(name);
    let input = match input_text {
        Some(text) => dir.write("in.json", text),
        None => dir.0.join("missing.json"),
    };
    let output = dir.0.join("out.json");
    let run = taut(&input, &output, extra);
    let stderr = String::from_utf8_lossy(&run.stderr).to_string();
    assert!(!run.status.success(), "{name}: must fail");
    assert_eq!(stderr.trim_end().lines().count(), 1, "{name}: one line expected, got {stderr:?}");
    assert!(!stderr.contains("panicked") && !stderr.contains("internal error"), "{name}: {stderr}");
    assert!(stderr.contains(expected), "{name}: {stderr:?} should mention {expected:?}");
    assert!(!output.exists(), "{name}: no output may be written");
    stderr
}

#[test]
fn an_open_curve_gives_every_point_in_order_with_the_input_points_exact() {
    let dir = Scratch::new("open");
    let control = [[0.0, 0.0, 0.0], [1.0, 2.0, 0.0], [3.0, 2.5, 1.0], [4.1, 0.3, 0.5]];
    let input = dir.write("in.json", &json!({ "points": control, "tension": [0.0, 1.5, 0.0, 0.0] }).to_string());
    let output = dir.0.join("out.json");
    let run = taut(&input, &output, &["--insert", "3"]);
    let stdout = String::from_utf8_lossy(&run.stdout);
    assert!(run.status.success(), "{}", String::from_utf8_lossy(&run.stderr));
    assert!(stdout.contains("iterations") && stdout.contains("final step"), "{stdout}");

    let out = read_json(&output);
    let points: Vec<[f64; 3]> = out["points"].as_array().unwrap().iter().map(point).collect();
    assert_eq!(points.len(), 3 * 4 + 1);
    let fixed: Vec<bool> = out["fixed"].as_array().unwrap().iter().map(|v| v.as_bool().unwrap()).collect();
    let tension: Vec<f64> = out["tension"].as_array().unwrap().iter().map(|v| v.as_f64().unwrap()).collect();
    assert_eq!((fixed.len(), tension.len()), (points.len(), points.len()));
    for (i, p) in points.iter().enumerate() {
        let is_input = i % 4 == 0;
        assert_eq!(fixed[i], is_input, "fixed flag of point {i}");
        if is_input {
            assert_eq!(*p, control[i / 4], "input point {} must be reproduced exactly", i / 4);
        }
        assert_eq!(tension[i], if i == 4 { 1.5 } else { 0.0 }, "tension of point {i}");
    }
    // In order: each inserted point lies near the segment it was inserted on, between its ends.
    for (i, p) in points.iter().enumerate().filter(|(i, _)| i % 4 != 0) {
        let (a, b) = (control[i / 4], control[i / 4 + 1]);
        let t = (i % 4) as f64 / 4.0;
        let on_segment: Vec<f64> = (0..3).map(|c| a[c] + t * (b[c] - a[c])).collect();
        let d = (0..3).map(|c| (p[c] - on_segment[c]).powi(2)).sum::<f64>().sqrt();
        assert!(d < 1.0, "point {i} is {d} away from its place on the segment");
    }
    assert_eq!(out["closed"], json!(false));
    assert!(out["iterations"].as_u64().unwrap() > 0);
    assert_eq!(out["converged"], json!(true));
    assert!(out["last_step"].as_f64().unwrap() < out["threshold"].as_f64().unwrap());
}

#[test]
fn a_closed_curve_includes_the_closing_segment() {
    let dir = Scratch::new("closed");
    let square = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0]];
    let input = dir.write("in.json", &json!({ "points": square, "closed": true }).to_string());
    let output = dir.0.join("out.json");
    let run = taut(&input, &output, &["--insert", "2", "--spacing", "uniform", "--tol", "1e-6"]);
    assert!(run.status.success(), "{}", String::from_utf8_lossy(&run.stderr));
    let out = read_json(&output);
    let points: Vec<[f64; 3]> = out["points"].as_array().unwrap().iter().map(point).collect();
    assert_eq!(points.len(), 4 * 3);
    for k in 0..4 {
        assert_eq!(points[3 * k], square[k]);
    }
    // The closing segment from (0, 1) back to (0, 0) bulges out to x < 0.
    assert!(points[10][0] < -0.01 && points[11][0] < -0.01, "{:?}", &points[9..]);
    assert_eq!(out["closed"], json!(true));
}

#[test]
fn the_output_replaces_an_existing_file() {
    let dir = Scratch::new("replace");
    let input = dir.write("in.json", r#"{"points": [[0,0,0],[1,1,0],[2,0,0]]}"#);
    let output = dir.write("out.json", "old contents");
    assert!(taut(&input, &output, &["--insert", "1"]).status.success());
    assert_eq!(read_json(&output)["points"].as_array().unwrap().len(), 5);
    let leftovers: Vec<_> = std::fs::read_dir(&dir.0).unwrap().map(|e| e.unwrap().file_name()).collect();
    assert_eq!(leftovers.len(), 2, "no temporary file may remain: {leftovers:?}");
}

#[test]
fn garbage_json_is_refused() {
    assert_refused("garbage", Some("{ this is not json"), &["--insert", "2"], "not a valid curve file");
}

#[test]
fn an_overflowing_number_is_refused() {
    // 1e999 does not fit an f64; it must not turn into an infinite coordinate.
    let text = r#"{"points": [[0,0,0],[1e999,1,0],[2,0,0]]}"#;
    assert_refused("overflow", Some(text), &["--insert", "2"], "out of range");
}

#[test]
fn mismatched_lengths_are_refused() {
    let text = r#"{"points": [[0,0,0],[1,1,0],[2,0,0]], "fixed": [true, true]}"#;
    assert_refused("fixed-length", Some(text), &["--insert", "2"], "`fixed` has 2 entries but the curve has 3 points");
    let text = r#"{"points": [[0,0,0],[1,1,0],[2,0,0]], "tension": [0, 0, 0, 1]}"#;
    assert_refused("tension-length", Some(text), &["--insert", "2"], "`tension` has 4 entries");
}

#[test]
fn an_open_curve_with_a_moving_end_is_refused() {
    let text = r#"{"points": [[0,0,0],[1,1,0],[2,0,0]], "fixed": [true, true, false]}"#;
    assert_refused("moving-end", Some(text), &["--insert", "2"], "must be fixed");
}

#[test]
fn a_missing_file_is_refused() {
    let message = assert_refused("missing", None, &["--insert", "2"], "cannot read");
    assert!(message.contains("missing.json"), "{message}");
}

#[test]
fn unknown_keys_and_wrong_types_are_refused() {
    let text = r#"{"points": [[0,0,0],[1,1,0],[2,0,0]], "tensions": [0, 0, 0]}"#;
    assert_refused("unknown-key", Some(text), &["--insert", "2"], "unknown field `tensions`");
    let text = r#"{"points": [[0,0,0],[1,1],[2,0,0]]}"#;
    assert_refused("two-coordinates", Some(text), &["--insert", "2"], "invalid length 2");
    let text = r#"{"points": [[0,0,0],[1,1,0],[2,0,0]], "closed": "yes"}"#;
    assert_refused("closed-string", Some(text), &["--insert", "2"], "invalid type");
    assert_refused("no-points", Some(r#"{"closed": true}"#), &["--insert", "2"], "missing field `points`");
}

#[test]
fn bad_settings_and_values_are_refused() {
    let text = r#"{"points": [[0,0,0],[1,1,0],[2,0,0]], "tension": [0, -1, 0]}"#;
    assert_refused("negative-tension", Some(text), &["--insert", "2"], "tension of point 1");
    let good = r#"{"points": [[0,0,0],[1,1,0],[2,0,0]]}"#;
    assert_refused("lambda", Some(good), &["--insert", "2", "--lambda", "1.5"], "lambda");
    assert_refused("tol", Some(good), &["--insert", "2", "--tol", "0"], "tolerance");
    assert_refused("huge-insert", Some(good), &["--insert", "1000000000000"], "more than");
    assert_refused("one-point", Some(r#"{"points": [[0,0,0]]}"#), &["--insert", "2"], "at least 2 points");
}
