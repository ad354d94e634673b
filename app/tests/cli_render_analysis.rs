//! `taut render --view draft` and `--view highlight` run as a designer would: the draft classes
//! of a cone of known half-angle (in the picture and in the printed shares of the area), the
//! highlight options changing the lines, the options in `--help`, and one-line errors with
//! nothing written for bad values.

use std::path::{Path, PathBuf};
use std::process::Output;

mod support;
use support::{assert_clean_failure, asset};

fn taut(args: &[&str]) -> Output {
    support::taut_in("cli-analysis", args)
}

fn scratch(test: &str) -> PathBuf {
    support::scratch_in("cli-analysis", test)
}

/// Runs `taut`, expects success, and returns its standard output and the picture.
fn render(args: &[&str]) -> (String, image::RgbaImage) {
    let out = taut(args);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let path = args.iter().position(|&a| a == "-o").map(|k| args[k + 1]).unwrap();
    (String::from_utf8_lossy(&out.stdout).into_owned(), image::open(path).expect("a PNG was written").to_rgba8())
}

/// An open frustum of a cone of half-angle `alpha_deg` about +Z, narrowing upwards, as an OBJ
/// file of 96 × 6 quads (drawn as it is, with area-weighted normals).
fn frustum_obj(dir: &Path, alpha_deg: f64) -> String {
    let (n, rings) = (96, 6);
    let run = alpha_deg.to_radians().tan();
    let mut text = String::new();
    for j in 0..=rings {
        let s = j as f64 / rings as f64;
        for k in 0..n {
            let t = 2.0 * std::f64::consts::PI * k as f64 / n as f64;
            let r = 0.8 - s * run;
            text += &format!("v {} {} {}\n", r * t.cos(), r * t.sin(), s);
        }
    }
    for j in 0..rings {
        for k in 0..n {
            let (v, w) = (j * n + k + 1, j * n + (k + 1) % n + 1);
            text += &format!("f {v} {w} {} {}\n", w + n, v + n);
        }
    }
    let path = dir.join(format!("frustum-{alpha_deg}.obj"));
    std::fs::write(&path, text).unwrap();
    path.to_string_lossy().into_owned()
}

/// Pixels of each draft class (green, yellow, red) by hue.
fn classes(image: &image::RgbaImage) -> [usize; 3] {
    let mut counts = [0; 3];
    for p in image.pixels() {
        let (r, g, b) = (p[0] as i32, p[1] as i32, p[2] as i32);
        if g > r + 25 && g > b + 25 {
            counts[0] += 1;
        } else if r > b + 60 && g > b + 60 && (r - g).abs() < 60 {
            counts[1] += 1;
        } else if r > g + 50 && r > b + 50 {
            counts[2] += 1;
        }
    }
    counts
}

/// The printed share of the area in percent after `word` ("positive", "below", "undercut").
fn share(stdout: &str, word: &str) -> f64 {
    let line = stdout.lines().find(|l| l.starts_with("draft against")).unwrap_or_else(|| panic!("{stdout}"));
    let before = line.split(word).next().unwrap();
    let number = before.trim_end().trim_end_matches("% of the area").trim_end_matches('%').trim_end();
    number.rsplit(' ').next().unwrap().parse().unwrap_or_else(|_| panic!("{line}"))
}

/// The cone's faces all have draft 10° against +Z (−10° against −Z): a threshold of 8° passes
/// them all, 12° fails them all, and pulling down makes them undercuts.
#[test]
fn the_draft_of_a_cone_against_its_half_angle() {
    let dir = scratch("cone");
    let cone = frustum_obj(&dir, 10.0);
    let png = |name: &str| dir.join(name).to_string_lossy().into_owned();
    let run = |name: &str, extra: &[&str]| {
        // The frustum is written with Z as its axis: read it Z up.
        let base = ["render", &cone, "--up", "z", "--view", "draft", "--size", "320x240", "--software"];
        render(&[&base[..], &["-o", &png(name)], extra].concat())
    };
    let (stdout, passes) = run("passes.png", &["--pull", "0,0,1", "--draft-angle", "8"]);
    assert!(share(&stdout, "positive") > 99.9, "{stdout}");
    let [green, yellow, red] = classes(&passes);
    assert!(green > 10_000 && yellow + red < green / 100, "{green} green, {yellow} yellow, {red} red");

    let (stdout, fails) = run("fails.png", &["--pull", "0,0,2", "--draft-angle", "12"]);
    assert!(share(&stdout, "below") > 99.9, "{stdout}");
    let [green, yellow, red] = classes(&fails);
    assert!(yellow > 10_000 && green + red < yellow / 100, "{green} green, {yellow} yellow, {red} red");

    let (stdout, under) = run("under.png", &["--pull", "0,0,-1", "--draft-angle", "8"]);
    assert!(share(&stdout, "undercut") > 99.9, "{stdout}");
    let [green, yellow, red] = classes(&under);
    assert!(red > 10_000 && green + yellow < red / 100, "{green} green, {yellow} yellow, {red} red");

    // Defaults: pull +Z at 3°, which the 10° cone passes.
    let (stdout, _) = run("default.png", &[]);
    assert!(stdout.contains("threshold 3°") && share(&stdout, "positive") > 99.9, "{stdout}");
    // Towards the camera: the side facing it passes, the silhouette needs draft.
    let (_, view) = run("view.png", &["--pull", "view"]);
    let [green, yellow, _] = classes(&view);
    assert!(green > 5_000 && yellow > 40, "{green} green, {yellow} yellow");
}

/// Highlight lines: dark lines over light clay; the count, the spacing and the direction of the
/// tubes each change them.
#[test]
fn highlight_options_change_the_lines() {
    let dir = scratch("highlight");
    let cage = asset("default.taut");
    let png = |name: &str| dir.join(name).to_string_lossy().into_owned();
    let run = |name: &str, extra: &[&str]| {
        let base = ["render", &cage, "--view", "highlight", "--size", "320x200", "--software"];
        render(&[&base[..], &["-o", &png(name)], extra].concat()).1
    };
    let dark = |img: &image::RgbaImage| img.pixels().filter(|p| p[1] < 60).count();
    let default = run("default.png", &[]);
    assert!(dark(&default) > 300, "the default tubes draw lines: {} dark pixels", dark(&default));
    let one = run("one.png", &["--tube-count", "1"]);
    assert!(dark(&one) < dark(&default) / 3, "one tube draws fewer lines: {} vs {}", dark(&one), dark(&default));
    // An even count: no tube in the middle, so tubes far apart light nothing.
    let wide = run("wide.png", &["--tube-spacing", "1e9", "--tube-count", "2"]);
    assert!(dark(&wide) < dark(&default) / 3, "tubes far apart miss the model: {} dark pixels", dark(&wide));
    let along_y = run("y.png", &["--tube-direction", "0,1,0"]);
    let moved = default.pixels().zip(along_y.pixels()).filter(|(a, b)| a[1].abs_diff(b[1]) > 80).count();
    assert!(moved > 500, "tubes along Y light other lines: {moved} pixels changed");
}

#[test]
fn help_lists_the_analysis_options() {
    let out = taut(&["render", "--help"]);
    let help = String::from_utf8_lossy(&out.stdout);
    for option in
        ["--pull", "--draft-angle", "--tube-direction", "--tube-spacing", "--tube-count", "draft", "highlight"]
    {
        assert!(help.contains(option), "{option} missing from:\n{help}");
    }
}

#[test]
fn bad_analysis_values_fail_with_one_clear_line_and_write_nothing() {
    let dir = scratch("bad");
    let png = dir.join("x.png").to_string_lossy().into_owned();
    let cage = asset("default.taut");
    let draft = ["render", &cage, "-o", &png, "--view", "draft"];
    let highlight = ["render", &cage, "-o", &png, "--view", "highlight"];
    for (base, flags, said) in [
        (&draft, &["--pull", "0,0,0"][..], "--pull 0,0,0: the direction must not be zero"),
        (&draft, &["--pull", "1,2"], "--pull 1,2: expected three numbers"),
        (&draft, &["--pull", "up"], "--pull up: expected three numbers"),
        (&draft, &["--pull", "1,inf,0"], "expected three numbers"),
        (&draft, &["--draft-angle", "90"], "--draft-angle 90: must be 0 to 89 degrees"),
        (&draft, &["--draft-angle", "-1"], "--draft-angle -1"),
        (&draft, &["--draft-angle", "NaN"], "--draft-angle NaN"),
        (&draft, &["--tube-count", "3"], "--tube-count goes with --view highlight"),
        (&highlight, &["--tube-count", "0"], "--tube-count 0: must be 1 to 500"),
        (&highlight, &["--tube-count", "501"], "--tube-count 501"),
        (&highlight, &["--tube-spacing", "0"], "--tube-spacing 0: must be a positive distance"),
        (&highlight, &["--tube-spacing", "-2"], "--tube-spacing -2"),
        (&highlight, &["--tube-direction", "0,0,0"], "--tube-direction 0,0,0: the direction must not be zero"),
        (&highlight, &["--pull", "0,0,1"], "--pull goes with --view draft"),
        (&highlight, &["--legend"], "--legend goes with a colour view"),
    ] {
        assert_clean_failure(&taut(&[&base[..], flags].concat()), said);
        assert!(!Path::new(&png).exists(), "{flags:?} wrote a picture");
    }
    let zebra = ["render", &cage, "-o", &png, "--view", "zebra", "--draft-angle", "3"];
    assert_clean_failure(&taut(&zebra), "--draft-angle goes with --view draft");
    assert!(!Path::new(&png).exists());
}
