//! `taut fair`, `aesthetic-curve`, `coons`, `fair-surface` and `lcg` end to end: the real binary
//! on files in a scratch folder.

use serde_json::{Value, json};
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// A fresh folder under the system temp dir, removed when dropped.
struct Scratch(PathBuf);

impl Scratch {
    fn new(name: &str) -> Scratch {
        let dir = std::env::temp_dir().join(format!("taut-cli-aesthetic-{}-{name}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        Scratch(dir)
    }

    fn write(&self, file: &str, text: &str) -> PathBuf {
        let path = self.0.join(file);
        std::fs::write(&path, text).unwrap();
        path
    }

    fn path(&self, file: &str) -> PathBuf {
        self.0.join(file)
    }
}

impl Drop for Scratch {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

fn taut(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_taut")).args(args).output().expect("the taut binary runs")
}

fn s(path: &Path) -> &str {
    path.to_str().unwrap()
}

fn read_json(path: &Path) -> Value {
    serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap()
}

fn points(v: &Value) -> Vec<[f64; 3]> {
    v["points"]
        .as_array()
        .unwrap()
        .iter()
        .map(|p| {
            let a: Vec<f64> = p.as_array().unwrap().iter().map(|x| x.as_f64().unwrap()).collect();
            [a[0], a[1], a.get(2).copied().unwrap_or(0.0)]
        })
        .collect()
}

/// A failure must be one line on stderr, a non-zero status, no panic and no output file.
fn assert_refused(run: &Output, output: &Path, expected: &str) {
    let stderr = String::from_utf8_lossy(&run.stderr).to_string();
    assert!(!run.status.success(), "must fail: {stderr}");
    assert_eq!(stderr.trim_end().lines().count(), 1, "one line expected, got {stderr:?}");
    assert!(!stderr.contains("panicked") && !stderr.contains("internal error"), "{stderr}");
    assert!(stderr.contains(expected), "{stderr:?} should mention {expected:?}");
    assert!(!output.exists(), "no output may be written");
}

/// A noisy sample of the segment of `aesthetic-curve` (0.5 % of its length), as JSON text.
fn noisy_points(segment: &Value) -> Vec<[f64; 2]> {
    let pts = points(segment);
    let length = segment["length"].as_f64().unwrap();
    let mut state = 0x1234_5678_u64;
    let mut noise = || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        ((state >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0) * 0.005 * length
    };
    let n = pts.len();
    pts.iter()
        .enumerate()
        .map(|(i, p)| if i == 0 || i + 1 == n { [p[0], p[1]] } else { [p[0] + noise(), p[1] + noise()] })
        .collect()
}

#[test]
fn an_aesthetic_segment_meets_its_control_points() {
    let dir = Scratch::new("segment");
    let out = dir.path("seg.json");
    let run = taut(&[
        "aesthetic-curve",
        "--p0",
        "0,0",
        "--p1",
        "1,0",
        "--p2",
        "1.5,1.2",
        "--alpha",
        "-1",
        "-o",
        s(&out),
        "--samples",
        "50",
    ]);
    assert!(run.status.success(), "{}", String::from_utf8_lossy(&run.stderr));
    assert!(String::from_utf8_lossy(&run.stdout).contains("α = -1"));
    let v = read_json(&out);
    let p = points(&v);
    assert_eq!(p.len(), 50);
    assert_eq!(v["points"][0].as_array().unwrap().len(), 2, "2D control points give 2D points");
    assert!(p[0].iter().all(|c| c.abs() < 1e-12));
    assert!((p[49][0] - 1.5).abs() < 1e-12 && (p[49][1] - 1.2).abs() < 1e-12);
    // The first chord leaves along P0 → P1 (the x axis), the last arrives along P1 → P2.
    assert!((p[1][1] / p[1][0]).abs() < 0.05);
    let (dx, dy) = (p[49][0] - p[48][0], p[49][1] - p[48][1]);
    assert!((dy / dx - 2.4).abs() < 0.2, "{}", dy / dx);
    let curvature: Vec<f64> = v["curvature"].as_array().unwrap().iter().map(|k| k.as_f64().unwrap()).collect();
    assert!(curvature.windows(2).all(|w| w[1] != w[0]), "monotone curvature");

    // α = 2 cannot make a segment in a triangle this thin: one line says why and what to do.
    let bad = dir.path("bad.json");
    let run = taut(&["aesthetic-curve", "--p0", "0,0", "--p1", "1,0", "--p2", "1,0.1", "--alpha", "2", "-o", s(&bad)]);
    assert_refused(&run, &bad, "no log-aesthetic segment with α = 2");
    let run = taut(&["aesthetic-curve", "--p0", "0,0", "--p1", "1,0", "--p2", "2,0", "--alpha", "1", "-o", s(&bad)]);
    assert_refused(&run, &bad, "collinear");
    let run = taut(&["aesthetic-curve", "--p0", "0,0", "--p1", "1", "--p2", "2,1", "--alpha", "1", "-o", s(&bad)]);
    assert_refused(&run, &bad, "expected X,Y or X,Y,Z");
}

#[test]
fn fair_prints_alpha_and_the_lcg_residual_and_writes_json_and_csv() {
    let dir = Scratch::new("fair");
    let seg = dir.path("seg.json");
    let run = taut(&[
        "aesthetic-curve",
        "--p0",
        "0,0",
        "--p1",
        "1,0",
        "--p2",
        "1.5,1.2",
        "--alpha",
        "1",
        "-o",
        s(&seg),
        "--samples",
        "25",
    ]);
    assert!(run.status.success());
    let noisy = noisy_points(&read_json(&seg));
    let input = dir.write("noisy.json", &json!({ "points": noisy }).to_string());
    let out = dir.path("faired.json");
    // The paper's filter (--paper): the curve is pulled to the law until its curvature graph is
    // straight.
    let run = taut(&["fair", s(&input), "-o", s(&out), "--alpha", "1", "--tolerance", "1e-6", "--paper"]);
    let stdout = String::from_utf8_lossy(&run.stdout).to_string();
    assert!(run.status.success(), "{}", String::from_utf8_lossy(&run.stderr));
    assert!(
        stdout.contains("α = 1 (given)") && stdout.contains("LCG residual") && stdout.contains("converged"),
        "{stdout}"
    );
    let v = read_json(&out);
    assert_eq!(points(&v).len(), 25);
    let (before, after) = (v["lcg_residual_before"].as_f64().unwrap(), v["lcg_residual_after"].as_f64().unwrap());
    assert!(after * 100.0 < before, "LCG residual {before} → {after}");
    assert!((v["lcg_slope_after"].as_f64().unwrap() - 1.0).abs() < 0.1);
    // The ends stay exactly.
    assert_eq!(points(&v)[0], [noisy[0][0], noisy[0][1], 0.0]);

    // The default keeps the shape: the faired points lie nearer the exact segment than the noisy
    // ones did (the noise is taken out, the curve is not moved).
    let exact = points(&read_json(&seg));
    let kept = dir.path("kept.json");
    let run = taut(&["fair", s(&input), "-o", s(&kept), "--alpha", "1"]);
    assert!(run.status.success(), "{}", String::from_utf8_lossy(&run.stderr));
    let mean_gap = |pts: &[[f64; 3]]| {
        pts.iter().zip(&exact).map(|(p, q)| ((p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2)).sqrt()).sum::<f64>()
            / pts.len() as f64
    };
    let noisy3: Vec<[f64; 3]> = noisy.iter().map(|p| [p[0], p[1], 0.0]).collect();
    let (before, after) = (mean_gap(&noisy3), mean_gap(&points(&read_json(&kept))));
    assert!(after < 0.75 * before, "faired {after} against the noisy input's {before} from the exact segment");

    // CSV in, α estimated, CSV out with the same two columns.
    let csv: String =
        std::iter::once("x,y\n".to_string()).chain(noisy.iter().map(|p| format!("{},{}\n", p[0], p[1]))).collect();
    let input = dir.write("noisy.csv", &csv);
    let out = dir.path("faired.csv");
    let run = taut(&["fair", s(&input), "-o", s(&out), "--estimate-alpha"]);
    let stdout = String::from_utf8_lossy(&run.stdout).to_string();
    assert!(run.status.success(), "{}", String::from_utf8_lossy(&run.stderr));
    assert!(stdout.contains("α estimated per piece") && stdout.contains("piece 1: points 0–"), "{stdout}");
    let text = std::fs::read_to_string(&out).unwrap();
    assert!(text.starts_with("x,y\n") && text.lines().count() == 26, "{text}");
    assert!(text.lines().skip(1).all(|l| l.split(',').count() == 2 && l.split(',').all(|f| f.parse::<f64>().is_ok())));

    // A space curve with --space keeps three columns.
    let helix: Vec<[f64; 3]> = (0..30).map(|i| i as f64 * 0.2).map(|t| [t.cos(), t.sin(), 0.3 * t]).collect();
    let input = dir.write("helix.json", &json!({ "points": helix }).to_string());
    let out = dir.path("helix-out.json");
    let run = taut(&["fair", s(&input), "-o", s(&out), "--alpha", "1", "--space", "--torsion-beta", "1"]);
    assert!(run.status.success(), "{}", String::from_utf8_lossy(&run.stderr));
    let p = points(&read_json(&out));
    assert!(p.iter().zip(&helix).all(|(a, b)| (a[2] - b[2]).abs() < 1e-3));
}

#[test]
fn fair_refuses_bad_curves_with_one_line() {
    let dir = Scratch::new("fair-bad");
    let out = dir.path("out.json");
    let curve = |n: usize| (0..n).map(|i| i as f64 / n as f64).map(|t| [t, t * t]).collect::<Vec<_>>();
    let few = dir.write("few.json", &json!({ "points": curve(6) }).to_string());
    assert_refused(&taut(&["fair", s(&few), "-o", s(&out), "--alpha", "1"]), &out, "2m + 1 = 7");
    let mut repeated = curve(12);
    repeated[5] = repeated[4];
    let rep = dir.write("rep.json", &json!({ "points": repeated }).to_string());
    assert_refused(
        &taut(&["fair", s(&rep), "-o", s(&out), "--alpha", "1"]),
        &out,
        "points 4 and 5 are at the same place",
    );
    let nan = dir.write("nan.csv", "0,0\n0.1,0.01\n0.2,NaN\n0.3,0.09\n0.4,0.16\n0.5,0.25\n0.6,0.36\n0.7,0.49\n");
    assert_refused(
        &taut(&["fair", s(&nan), "-o", s(&out), "--alpha", "1"]),
        &out,
        "point 2 has a non-finite coordinate",
    );
    let bad_row = dir.write("bad.csv", "x,y\n0,0\n0.1,0.01\n0.2;0.04\n");
    assert_refused(&taut(&["fair", s(&bad_row), "-o", s(&out), "--alpha", "1"]), &out, "row 4");
    let columns = dir.write("cols.csv", "0,0\n1,1,1\n");
    assert_refused(&taut(&["fair", s(&columns), "-o", s(&out), "--alpha", "1"]), &out, "row 2 has 3 columns");
    let good = dir.write("good.json", &json!({ "points": curve(12) }).to_string());
    assert_refused(
        &taut(&["fair", s(&good), "-o", s(&dir.path("out.txt")), "--alpha", "1"]),
        &dir.path("out.txt"),
        "use .json or .csv",
    );
    assert_refused(&taut(&["fair", s(&dir.path("missing.json")), "-o", s(&out)]), &out, "missing.json");
    assert_refused(&taut(&["fair", s(&good), "-o", s(&out), "--alpha", "1", "--window", "0"]), &out, "window");
}

#[test]
fn coons_writes_a_mesh_and_a_cage() {
    let dir = Scratch::new("coons");
    let curves = json!({ "curves": [
        { "p0": [0, 0, 0], "p1": [1, 0, 0], "p2": [1.4, 1.0, 0], "alpha": 2 },
        { "points": [[1.4, 1.0, 0], [1.4, 1.0, 1]] },
        { "p0": [0, 0, 1], "p1": [1, 0, 1], "p2": [1.4, 1.0, 1], "alpha": 2 },
        { "points": [[0, 0, 1], [0, 0, 0]] }
    ]});
    let input = dir.write("curves.json", &curves.to_string());
    let obj = dir.path("patch.obj");
    let run = taut(&["coons", s(&input), "-o", s(&obj), "--samples", "6"]);
    assert!(run.status.success(), "{}", String::from_utf8_lossy(&run.stderr));
    let (mesh, _) = taut_core::io::import_mesh(&obj).unwrap();
    assert_eq!((mesh.vertex_count(), mesh.face_count()), (49, 36));
    let cage = dir.path("patch.taut");
    assert!(taut(&["coons", s(&input), "-o", s(&cage), "--samples", "4"]).status.success());
    let doc = taut_core::Document::load(&cage).unwrap();
    assert_eq!((doc.cage.vertex_count(), doc.cage.face_count()), (25, 16));
    assert!(doc.cage.polygons().iter().all(|f| f.len() == 4));

    let open = json!({ "curves": [
        { "points": [[0, 0], [1, 0]] }, { "points": [[1, 0], [1, 1]] },
        { "points": [[1, 1], [0, 1]] }, { "points": [[0, 1], [0, 0.5]] }
    ]});
    let input = dir.write("open.json", &open.to_string());
    let out = dir.path("open.obj");
    assert_refused(&taut(&["coons", s(&input), "-o", s(&out)]), &out, "loop does not close");
    let three = dir.write("three.json", &json!({ "curves": [{ "points": [[0, 0], [1, 0]] }] }).to_string());
    assert_refused(&taut(&["coons", s(&three), "-o", s(&out)]), &out, "exactly 4 boundary curves");
}

#[test]
fn fair_surface_evens_the_gaussian_curvature_of_a_noisy_cap() {
    let dir = Scratch::new("surface");
    let n = 11;
    let mut state = 99u64;
    let mut noise = || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        ((state >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0) * 0.001
    };
    let grid: Vec<Vec<[f64; 3]>> = (0..n)
        .map(|i| {
            (0..n)
                .map(|j| {
                    let (x, y) = (-0.5 + i as f64 / 10.0, -0.5 + j as f64 / 10.0);
                    let interior = i > 0 && j > 0 && i + 1 < n && j + 1 < n;
                    [x, y, (4.0 - x * x - y * y).sqrt() + if interior { noise() } else { 0.0 }]
                })
                .collect()
        })
        .collect();
    let input = dir.write("grid.json", &json!({ "grid": grid }).to_string());
    // By default the noise goes and the cap stays where the points were: the interior ends
    // nearer the sphere of radius 2 than the noisy points.
    let out = dir.path("kept.json");
    let run = taut(&["fair-surface", s(&input), "-o", s(&out)]);
    assert!(run.status.success(), "{}", String::from_utf8_lossy(&run.stderr));
    let stdout = String::from_utf8_lossy(&run.stdout);
    assert!(stdout.contains("pre-fit: smoothing") && stdout.contains("(converged)"), "{stdout}");
    let off = |rows: &[Vec<[f64; 3]>]| {
        let inside: Vec<f64> = rows[1..n - 1]
            .iter()
            .flat_map(|r| &r[1..n - 1])
            .map(|p| ((p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt() - 2.0).abs())
            .collect();
        inside.iter().sum::<f64>() / inside.len() as f64
    };
    let kept: Vec<Vec<[f64; 3]>> = serde_json::from_value(read_json(&out)["grid"].clone()).unwrap();
    assert!(off(&kept) < 0.5 * off(&grid), "{} against {}", off(&kept), off(&grid));
    // The paper's filter evens the curvature of the points as given.
    let out = dir.path("out.json");
    let run = taut(&["fair-surface", s(&input), "-o", s(&out), "--paper"]);
    assert!(run.status.success(), "{}", String::from_utf8_lossy(&run.stderr));
    let stdout = String::from_utf8_lossy(&run.stdout);
    assert!(stdout.contains("Gaussian curvature before") && !stdout.contains("pre-fit"), "{stdout}");
    let v = read_json(&out);
    let (before, after) = (
        v["gaussian_curvature_before"]["std_dev"].as_f64().unwrap(),
        v["gaussian_curvature_after"]["std_dev"].as_f64().unwrap(),
    );
    assert!(after * 5.0 < before, "{before} → {after}");
    assert_eq!(v["grid"].as_array().unwrap().len(), n);
    assert_eq!(v["grid"][0], json!(grid[0]), "the boundary stays");
    let ragged = dir.write("ragged.json", r#"{"grid": [[[0,0,0],[1,0,0]],[[0,1,0]]]}"#);
    let out = dir.path("ragged-out.json");
    assert_refused(&taut(&["fair-surface", s(&ragged), "-o", s(&out)]), &out, "row 1 has 1 points");
}

#[test]
fn lcg_draws_both_plots_into_a_png() {
    let dir = Scratch::new("lcg");
    let seg = dir.path("seg.json");
    assert!(
        taut(&["aesthetic-curve", "--p0", "0,0", "--p1", "1,0", "--p2", "1.5,1.2", "--alpha", "0.5", "-o", s(&seg)])
            .status
            .success()
    );
    let png = dir.path("plot.png");
    let run = taut(&["lcg", s(&seg), "-o", s(&png), "--size", "800x400"]);
    let stdout = String::from_utf8_lossy(&run.stdout).to_string();
    assert!(run.status.success(), "{}", String::from_utf8_lossy(&run.stderr));
    // The segment's LCG is a line of slope 0.5.
    let slope: f64 = stdout.split("slope α = ").nth(1).unwrap().split(',').next().unwrap().parse().unwrap();
    assert!((slope - 0.5).abs() < 0.01, "{stdout}");
    let image = image::open(&png).unwrap().to_rgb8();
    assert_eq!(image.dimensions(), (800, 400));
    // Both halves have a plot in colour: blue curvature on the left, red LCG points on the right.
    let count = |x0: u32, x1: u32, colour: fn(&image::Rgb<u8>) -> bool| {
        (x0..x1).flat_map(|x| (0..400).map(move |y| (x, y))).filter(|&(x, y)| colour(image.get_pixel(x, y))).count()
    };
    assert!(count(0, 400, |p| p[2] > 200 && p[0] < 80) > 200, "the curvature plot");
    assert!(count(400, 800, |p| p[0] > 200 && p[1] < 80) > 50, "the LCG points");
    let bad = dir.path("plot.jpg");
    assert_refused(&taut(&["lcg", s(&seg), "-o", s(&bad)]), &bad, "use a .png file name");
}
