//! Hostile inputs that used to abort or run away, end to end through the real binary: `cage` on
//! meshes too small for the simplifier's asserts, on an open polygon whose fan corner has a
//! valence in the thousands, with absurd `--rounds`, and on two disjoint cubes (each fitted, each
//! part closed); `lcg` on 100 000 points; `subdivide` of a 10 000-sided polygon; `coons` beyond
//! its documented maximum. Each either gives a valid result within a bound that the old
//! quadratic code broke by far, or one clean line.

use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

fn taut(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_taut")).args(args).output().expect("the taut binary runs")
}

/// Runs `taut` and fails the test when it takes longer than `limit` (killing it).
fn taut_within(args: &[&str], limit: Duration) -> Output {
    let mut child = Command::new(env!("CARGO_BIN_EXE_taut"))
        .args(args)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("the taut binary runs");
    let start = Instant::now();
    while child.try_wait().unwrap().is_none() {
        if start.elapsed() > limit {
            let _ = child.kill();
            panic!("taut {} ran past {limit:?}", args.join(" "));
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    child.wait_with_output().unwrap()
}

struct Scratch(PathBuf);

impl Scratch {
    fn new(test: &str) -> Self {
        let dir = std::env::temp_dir().join(format!("taut-cli-cost-{}-{test}", std::process::id()));
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

fn one_line_failure(out: &Output, expected: &str) {
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.code().is_some_and(|c| c != 0), "expected a clean failure: {:?}; stderr: {stderr}", out.status);
    assert_eq!(stderr.trim_end().lines().count(), 1, "not one line: {stderr:?}");
    assert!(stderr.starts_with("error: ") && stderr.contains(expected), "expected '{expected}' in {stderr:?}");
}

/// Vertex and face counts of an OBJ and the Euler characteristic of each connected part.
fn parts_euler(obj: &str) -> Vec<i64> {
    let mut faces: Vec<Vec<usize>> = Vec::new();
    let mut vertices = 0;
    for line in obj.lines() {
        if line.starts_with("v ") {
            vertices += 1;
        } else if let Some(rest) = line.strip_prefix("f ") {
            faces.push(
                rest.split_whitespace().map(|w| w.split('/').next().unwrap().parse::<usize>().unwrap() - 1).collect(),
            );
        }
    }
    let mut parent: Vec<usize> = (0..vertices).collect();
    fn find(p: &mut [usize], mut v: usize) -> usize {
        while p[v] != v {
            p[v] = p[p[v]];
            v = p[v];
        }
        v
    }
    for f in &faces {
        for &v in &f[1..] {
            let (a, b) = (find(&mut parent, f[0]), find(&mut parent, v));
            parent[a] = b;
        }
    }
    // Per part: vertices, edges (as vertex pairs) and faces.
    type Part = (i64, std::collections::BTreeSet<(usize, usize)>, i64);
    let mut by_part: std::collections::BTreeMap<usize, Part> = Default::default();
    for v in 0..vertices {
        let r = find(&mut parent, v);
        by_part.entry(r).or_default().0 += 1;
    }
    for f in &faces {
        let r = find(&mut parent, f[0]);
        let part = by_part.entry(r).or_default();
        part.2 += 1;
        for k in 0..f.len() {
            let (a, b) = (f[k], f[(k + 1) % f.len()]);
            part.1.insert((a.min(b), a.max(b)));
        }
    }
    by_part.values().map(|(v, e, f)| v - e.len() as i64 + f).collect()
}

#[test]
fn cage_never_aborts_on_meshes_too_small_to_simplify() {
    let dir = Scratch::new("tiny");
    let cases = [
        ("triangle", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"),
        ("quad", "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n"),
        ("bowtie", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv -1 0 0\nv 0 -1 0\nf 1 2 3\nf 1 4 5\n"),
        ("collinear", "v 0 0 0\nv 1 0 0\nv 2 0 0\nv 3 0 0\nf 1 2 3\nf 2 3 4\n"),
        (
            "cone-and-stray",
            "v 0 0 1\nv 1 0 0\nv 0 1 0\nv -1 0 0\nv 0 -1 0\nv 5 5 5\nv 6 5 5\nv 5 6 5\n\
             f 1 2 3\nf 1 3 4\nf 1 4 5\nf 1 5 2\nf 2 5 4 3\nf 6 7 8\n",
        ),
    ];
    for (name, text) in cases {
        let input = dir.write(&format!("{name}.obj"), text);
        let out = dir.path(&format!("{name}-cage.obj"));
        let run = taut_within(&["cage", &input, "-o", &out], Duration::from_secs(30));
        let stderr = String::from_utf8_lossy(&run.stderr);
        assert!(run.status.code().is_some(), "{name}: killed by a signal: {stderr}");
        if run.status.success() {
            let obj = std::fs::read_to_string(&out).unwrap();
            assert!(obj.lines().any(|l| l.starts_with("f ")), "{name}: a cage without faces");
        } else {
            assert_eq!(stderr.trim_end().lines().count(), 1, "{name}: {stderr}");
            assert!(!Path::new(&out).exists(), "{name}: a failed run wrote its output");
        }
    }
}

#[test]
fn cage_rounds_are_bounded() {
    let dir = Scratch::new("rounds");
    let cube = Path::new(env!("CARGO_MANIFEST_DIR")).join("../assets/cube.obj");
    let out = dir.path("cage.obj");
    one_line_failure(
        &taut(&["cage", cube.to_str().unwrap(), "-o", &out, "--rounds", "4294967295"]),
        "between 1 and 10",
    );
    assert!(!Path::new(&out).exists());
}

#[test]
fn cage_fits_two_disjoint_cubes_and_a_lone_cube_at_the_default_size() {
    let dir = Scratch::new("two-cubes");
    let corners: Vec<[i32; 3]> = (0..8).map(|i| [i >> 2 & 1, i >> 1 & 1, i & 1]).collect();
    let faces = [[1, 3, 4, 2], [5, 6, 8, 7], [1, 2, 6, 5], [3, 7, 8, 4], [1, 5, 7, 3], [2, 4, 8, 6]];
    let mut obj = String::new();
    for offset in [0, 3] {
        for c in &corners {
            obj += &format!("v {} {} {}\n", c[0] + offset, c[1], c[2]);
        }
    }
    for base in [0, 8] {
        for f in &faces {
            obj += &format!("f {} {} {} {}\n", f[0] + base, f[1] + base, f[2] + base, f[3] + base);
        }
    }
    let input = dir.write("two.obj", &obj);
    let out = dir.path("two-cage.obj");
    let run = taut(&["cage", &input, "-o", &out]);
    assert!(run.status.success(), "{}", String::from_utf8_lossy(&run.stderr));
    let euler = parts_euler(&std::fs::read_to_string(&out).unwrap());
    assert_eq!(euler, vec![2, 2], "two closed parts, each a sphere");
    let cube = Path::new(env!("CARGO_MANIFEST_DIR")).join("../assets/cube.obj");
    let lone = dir.path("cube-cage.obj");
    let run = taut(&["cage", cube.to_str().unwrap(), "-o", &lone]);
    assert!(run.status.success(), "{}", String::from_utf8_lossy(&run.stderr));
    assert_eq!(parts_euler(&std::fs::read_to_string(&lone).unwrap()), vec![2]);
}

#[test]
fn cage_of_a_polygon_with_thousands_of_sides_stays_fast() {
    // An open 1,500-gon: its fan corner has valence 1,500 on the border. The crease-sector
    // masks took a dense 1,502² matrix through up to 20 000 power steps (minutes); now seconds.
    let dir = Scratch::new("ngon");
    let n = 1500;
    let mut obj = String::new();
    for i in 0..n {
        let a = std::f64::consts::TAU * i as f64 / n as f64;
        obj += &format!("v {} {} 0\n", a.cos(), a.sin());
    }
    obj += "f";
    for i in 1..=n {
        obj += &format!(" {i}");
    }
    obj += "\n";
    let input = dir.write("ngon.obj", &obj);
    let out = dir.path("ngon-cage.obj");
    let run = taut_within(&["cage", &input, "-o", &out], Duration::from_secs(40));
    assert!(run.status.success(), "{}", String::from_utf8_lossy(&run.stderr));
    // The same polygon cannot be subdivided as one face: refused up front, in one line.
    let sub = dir.path("ngon-sub.obj");
    let big: String = {
        let n = 10_000;
        let mut s = String::new();
        for i in 0..n {
            let a = std::f64::consts::TAU * i as f64 / n as f64;
            s += &format!("v {} {} 0\n", a.cos(), a.sin());
        }
        s += "f";
        for i in 1..=n {
            s += &format!(" {i}");
        }
        s + "\n"
    };
    let big = dir.write("big.obj", &big);
    let run = taut_within(&["subdivide", &big, "-o", &sub, "--levels", "3"], Duration::from_secs(20));
    one_line_failure(&run, "has 10000 sides");
    assert!(!Path::new(&sub).exists());
}

#[test]
fn lcg_of_100k_points_is_linear() {
    let dir = Scratch::new("lcg");
    let n = 100_000;
    let mut csv = String::new();
    for i in 0..n {
        let t = 3.0 * i as f64 / n as f64;
        let r = (0.3 * t).exp();
        csv += &format!("{},{}\n", r * t.cos(), r * t.sin());
    }
    let input = dir.write("spiral.csv", &csv);
    let out = dir.path("lcg.png");
    // The old check of planarity recomputed the bounding box per point: 7.7 s in release.
    let run = taut_within(&["lcg", &input, "-o", &out], Duration::from_secs(6));
    assert!(run.status.success(), "{}", String::from_utf8_lossy(&run.stderr));
    assert!(String::from_utf8_lossy(&run.stdout).contains("slope α = 1.0"), "{}", String::from_utf8_lossy(&run.stdout));
}

#[test]
fn coons_beyond_its_maximum_is_refused_in_one_line() {
    let dir = Scratch::new("coons");
    let sides = dir.write(
        "sides.json",
        r#"{"curves": [{"points": [[0,0,0],[1,0,0]]}, {"points": [[1,0,0],[1,1,0]]},
                       {"points": [[1,1,0],[0,1,0]]}, {"points": [[0,1,0],[0,0,0]]}]}"#,
    );
    let out = dir.path("patch.obj");
    one_line_failure(&taut(&["coons", &sides, "-o", &out, "--samples", "4096"]), "between 1 and 1024");
    assert!(!Path::new(&out).exists());
}
