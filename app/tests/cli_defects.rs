//! The command line against what a designer, a Blender user and a hostile file found: outputs
//! written over inputs, errors that take several lines, noise from the GPU loader, renders of
//! extreme coordinates, unchecked zebra options, and memory that grows with a single line.

use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};

fn taut(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_taut")).args(args).output().expect("the taut binary runs")
}

fn asset(name: &str) -> String {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../assets").join(name).to_string_lossy().into_owned()
}

struct Scratch(PathBuf);

impl Scratch {
    fn new(test: &str) -> Self {
        let dir = std::env::temp_dir().join(format!("taut-cli-defects-{}-{test}", std::process::id()));
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

/// A failure: non-zero exit and exactly one line on stderr, naming the problem.
fn one_line_failure(out: &Output, expected: &str) {
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success(), "expected a failure; stderr: {stderr}");
    assert_eq!(stderr.trim_end().lines().count(), 1, "not one line: {stderr:?}");
    assert!(stderr.starts_with("error: ") && stderr.contains(expected), "expected '{expected}' in {stderr:?}");
}

#[test]
fn an_output_that_is_the_input_is_refused_unless_forced() {
    let dir = Scratch::new("overwrite");
    let cage = dir.path("cage.obj");
    std::fs::copy(asset("cube.obj"), &cage).unwrap();
    let original = std::fs::read(&cage).unwrap();
    one_line_failure(&taut(&["smooth", &cage, "-o", &cage]), "is the input file");
    // The same file under another name: a link, a hard link, a path with a detour.
    #[cfg(unix)]
    {
        std::os::unix::fs::symlink(&cage, dir.path("link.obj")).unwrap();
        std::fs::hard_link(&cage, dir.path("hard.obj")).unwrap();
        one_line_failure(&taut(&["smooth", &cage, "-o", &dir.path("link.obj")]), "is the input file");
        one_line_failure(&taut(&["smooth", &dir.path("hard.obj"), "-o", &cage]), "is the input file");
    }
    let detour = format!("{}/../{}/cage.obj", dir.0.display(), dir.0.file_name().unwrap().to_string_lossy());
    one_line_failure(&taut(&["smooth", &cage, "-o", &detour]), "add --force");
    assert_eq!(std::fs::read(&cage).unwrap(), original, "the cage was changed");
    let curve = dir.path("curve.json");
    std::fs::write(&curve, r#"{"points": [[0,0,0],[1,1,0],[2,0,0]]}"#).unwrap();
    one_line_failure(&taut(&["smooth-curve", &curve, "-o", &curve, "--insert", "3"]), "is the input file");
    // --force writes it, as asked.
    let forced = taut(&["smooth", &cage, "-o", &cage, "--force", "--levels", "1"]);
    assert!(forced.status.success(), "{}", String::from_utf8_lossy(&forced.stderr));
    assert_ne!(std::fs::read(&cage).unwrap(), original);
}

#[test]
fn argument_errors_are_one_line() {
    one_line_failure(&taut(&["smooth", &asset("cube.obj")]), "--output");
    one_line_failure(&taut(&["smooth", &asset("cube.obj"), "-o", "x.obj", "--bogus"]), "--bogus");
    one_line_failure(&taut(&["render", &asset("cube.obj"), "-o", "x.png", "--stripes", "many"]), "many");
    one_line_failure(&taut(&["smooth", &asset("cube.obj"), "-o", "x.obj", "--up", "x"]), "up axis");
    let help = taut(&["smooth", "--help"]);
    assert!(help.status.success() && String::from_utf8_lossy(&help.stdout).contains("--force"));
}

#[test]
fn zebra_options_are_checked() {
    let dir = Scratch::new("zebra");
    let png = dir.path("z.png");
    let cube = asset("cube.obj");
    let zebra = |extra: &[&str]| {
        let mut args = vec!["render", cube.as_str(), "-o", png.as_str(), "--view", "zebra"];
        args.extend_from_slice(extra);
        taut(&args)
    };
    one_line_failure(&zebra(&["--stripe-angle", "nan"]), "--stripe-angle NaN");
    one_line_failure(&zebra(&["--stripe-angle", "inf"]), "--stripe-angle inf");
    for width in ["0", "1", "1.5", "-0.2"] {
        one_line_failure(&zebra(&["--stripe-width", width]), "strictly between 0 and 1");
    }
    assert!(!Path::new(&png).exists());
}

/// A render on the software rasteriser with no runtime folder in the environment.
fn render_without_runtime_dir(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_taut"))
        .args(args)
        .arg("--software")
        .env_remove("XDG_RUNTIME_DIR")
        .output()
        .expect("the taut binary runs")
}

#[test]
fn a_render_without_a_runtime_folder_prints_nothing_on_stderr() {
    let dir = Scratch::new("runtime");
    let png = dir.path("c.png");
    let out = render_without_runtime_dir(&["render", &asset("cube.obj"), "-o", &png, "--size", "160x100"]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    assert_eq!(String::from_utf8_lossy(&out.stderr), "", "stderr must stay empty on success");
    // A failure is still exactly one line.
    let bad = render_without_runtime_dir(&["render", &asset("cube.obj"), "-o", &dir.path("c.jpg")]);
    one_line_failure(&bad, ".png");
}

/// A cube with its corners at `centre ± size`, written as a Z-up OBJ.
fn cube_file(dir: &Scratch, name: &str, centre: f64, size: f64) -> String {
    let mut text = String::new();
    for i in 0..8 {
        let c = |bit: i32| centre + if i & bit == 0 { -size } else { size };
        text += &format!("v {:e} {:e} {:e}\n", c(1), c(2), c(4));
    }
    for f in [[1, 3, 4, 2], [5, 6, 8, 7], [1, 2, 6, 5], [3, 7, 8, 4], [1, 5, 7, 3], [2, 4, 8, 6]] {
        text += &format!("f {} {} {} {}\n", f[0], f[1], f[2], f[3]);
    }
    let path = dir.path(name);
    std::fs::write(&path, text).unwrap();
    path
}

#[test]
fn extreme_coordinates_render_like_ordinary_ones() {
    let dir = Scratch::new("extreme");
    let picture = |name: &str, centre: f64, size: f64| {
        let cube = cube_file(&dir, &format!("{name}.obj"), centre, size);
        let png = dir.path(&format!("{name}.png"));
        let args = ["render", &cube, "-o", &png, "--up", "z", "--view", "zebra", "--size", "200x150", "--software"];
        let out = taut(&args);
        assert!(out.status.success(), "{name}: {}", String::from_utf8_lossy(&out.stderr));
        image::open(&png).unwrap().to_rgba8()
    };
    let reference = picture("unit", 0.0, 1.0);
    let distinct: std::collections::HashSet<[u8; 4]> = reference.pixels().map(|p| p.0).collect();
    assert!(distinct.len() > 20, "the reference is not a picture of a cube");
    for (name, centre, size) in [("tiny", 0.0, 1e-200), ("subnormal-ish", 1e-300, 1e-300), ("huge", 1e307, 1e306)] {
        let image = picture(name, centre, size);
        let differing = image
            .pixels()
            .zip(reference.pixels())
            .filter(|(a, b)| (0..3).any(|k| (a[k] as i32 - b[k] as i32).abs() > 24))
            .count();
        let fraction = differing as f64 / (200.0 * 150.0);
        assert!(fraction < 0.01, "{name}: {:.1} % of the pixels differ from the unit cube's picture", 100.0 * fraction);
    }
    // A camera a billion billion times the model's size away is refused, not drawn as nothing.
    let unit = cube_file(&dir, "far.obj", 0.0, 1.0);
    let out = taut(&["render", &unit, "-o", &dir.path("far.png"), "--up", "z", "--camera", "0,0,1e30"]);
    one_line_failure(&out, "--camera 0,0,1e30");
}

/// The most memory the command held, from the kernel's high-water mark, read until it exits.
fn peak_memory_bytes(args: &[&str]) -> (u64, std::process::ExitStatus) {
    let mut child = Command::new(env!("CARGO_BIN_EXE_taut"))
        .args(args)
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .expect("the taut binary runs");
    let status_file = format!("/proc/{}/status", child.id());
    let mut peak = 0u64;
    loop {
        if let Ok(text) = std::fs::read_to_string(&status_file)
            && let Some(line) = text.lines().find(|l| l.starts_with("VmHWM:"))
        {
            let kb: u64 = line.split_whitespace().nth(1).and_then(|v| v.parse().ok()).unwrap_or(0);
            peak = peak.max(kb * 1024);
        }
        if let Some(status) = child.try_wait().unwrap() {
            return (peak, status);
        }
        std::thread::sleep(std::time::Duration::from_millis(2));
    }
}

#[test]
#[cfg(target_os = "linux")]
fn one_huge_face_line_takes_memory_in_proportion_to_the_file() {
    // One face line of 24 MB that repeats three vertices: it took sixteen times the file's size
    // before it was refused; now the text and its indices, and it fails on the fourth corner.
    let dir = Scratch::new("memory");
    let path = dir.path("line.obj");
    let mut text = String::from("v 0 0 0\nv 1 0 0\nv 0 1 0\nf");
    text.push_str(&" 1 2 3".repeat(4_000_000));
    text.push('\n');
    std::fs::write(&path, &text).unwrap();
    let size = text.len() as u64;
    drop(text);
    let (peak, status) = peak_memory_bytes(&["smooth", &path, "-o", &dir.path("out.obj")]);
    assert!(!status.success(), "the pinched face must be refused");
    let bound = 4 * size + (48 << 20);
    assert!(peak > 0 && peak < bound, "peak {} MB for a {} MB file (bound {} MB)", peak >> 20, size >> 20, bound >> 20);
}

#[test]
fn notes_go_to_stdout_so_stderr_is_only_errors() {
    let dir = Scratch::new("notes");
    // Blender's monkey: welding and the parts kept apart are reported as a note.
    let monkey = Path::new(env!("CARGO_MANIFEST_DIR")).join("../tests/fixtures/blender/monkey.glb");
    let out = taut(&["smooth", &monkey.to_string_lossy(), "-o", &dir.path("m.obj"), "--levels", "1"]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    assert_eq!(String::from_utf8_lossy(&out.stderr), "");
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(stdout.contains("note: ") && stdout.contains("parts only touch at"), "{stdout}");
}
