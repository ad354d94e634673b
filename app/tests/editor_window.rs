//! The editor in a real window: the binary started under Xvfb on Mesa's software Vulkan driver,
//! a fixed point dragged with synthetic mouse input (xdotool), the screen grabbed before and
//! after (ImageMagick's `import`), the surface changed where it should and nowhere else, the
//! document saved with Ctrl+S and the editor closed with Ctrl+Q and exit status 0. A second
//! test models as a new user would: File ▸ New ▸ Cube with the mouse, the top face picked in face
//! mode, E to extrude and G Z 0.5 Enter to move it up, Save As through the path field; the saved
//! file must hold 12 vertices and 10 faces and the screen must have changed.
//!
//! Needs `Xvfb`, `xdotool` and `import` (Debian: xvfb xdotool imagemagick) and the Vulkan
//! driver (mesa-vulkan-drivers); the README's test command installs them. When one is missing
//! the test fails saying what to install: it never skips.

use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

struct Killed(Child);

impl Drop for Killed {
    fn drop(&mut self) {
        if let Ok(Some(_)) = self.0.try_wait() {
            return;
        }
        // SIGTERM first so Xvfb removes its lock and socket.
        let _ = Command::new("kill").arg(self.0.id().to_string()).status();
        let deadline = Instant::now() + Duration::from_secs(3);
        while Instant::now() < deadline {
            if let Ok(Some(_)) = self.0.try_wait() {
                return;
            }
            std::thread::sleep(Duration::from_millis(50));
        }
        let _ = self.0.kill();
        let _ = self.0.wait();
    }
}

fn require(tool: &str, package: &str) {
    let found =
        Command::new("sh").arg("-c").arg(format!("command -v {tool}")).output().is_ok_and(|o| o.status.success());
    assert!(found, "the real-window test needs `{tool}`: install it (Debian: apt-get install {package})");
}

fn grab(display: &str, path: &Path) -> image::RgbaImage {
    let status = Command::new("import")
        .args(["-window", "root", path.to_str().unwrap()])
        .env("DISPLAY", display)
        .status()
        .unwrap();
    assert!(status.success(), "import could not grab the screen");
    image::open(path).unwrap().to_rgba8()
}

fn xdotool(display: &str, args: &[&str]) {
    let status = Command::new("xdotool").args(args).env("DISPLAY", display).status().unwrap();
    assert!(status.success(), "xdotool {args:?} failed");
}

/// Fraction of pixels in a region that differ by more than 40 in some channel.
fn changed(a: &image::RgbaImage, b: &image::RgbaImage, x0: u32, y0: u32, x1: u32, y1: u32) -> f64 {
    let mut n = 0;
    let mut total = 0;
    for y in y0..y1 {
        for x in x0..x1 {
            total += 1;
            let (p, q) = (a.get_pixel(x, y), b.get_pixel(x, y));
            if (0..3).any(|c| p[c].abs_diff(q[c]) > 40) {
                n += 1;
            }
        }
    }
    n as f64 / total.max(1) as f64
}

/// Waits until two grabs a second apart agree (the solve has settled) and returns the last.
fn settled(display: &str, path: &Path) -> image::RgbaImage {
    let deadline = Instant::now() + Duration::from_secs(60);
    let mut last = grab(display, path);
    loop {
        std::thread::sleep(Duration::from_millis(1500));
        let next = grab(display, path);
        let (w, h) = next.dimensions();
        if changed(&last, &next, 0, 0, w, h * 85 / 100) < 0.0005 {
            return next;
        }
        assert!(Instant::now() < deadline, "the editor never settled");
        last = next;
    }
}

/// One real-window test at a time: two would race for the same free display number, and two
/// software-rendered editors at once starve each other's frames.
static ONE_AT_A_TIME: std::sync::Mutex<()> = std::sync::Mutex::new(());

/// A virtual X server on a free display number, 1400 × 900, and its name (":41").
fn start_xvfb() -> (Killed, String) {
    let number = (40..140).find(|n| !Path::new(&format!("/tmp/.X{n}-lock")).exists()).expect("a free X display number");
    let display = format!(":{number}");
    let xvfb = Killed(
        Command::new("Xvfb")
            .args([display.as_str(), "-screen", "0", "1400x900x24", "-nolisten", "tcp"])
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .spawn()
            .expect("Xvfb starts"),
    );
    let socket = PathBuf::from(format!("/tmp/.X11-unix/X{}", &display[1..]));
    let start = Instant::now();
    while !socket.exists() {
        assert!(start.elapsed() < Duration::from_secs(20), "Xvfb did not start");
        std::thread::sleep(Duration::from_millis(100));
    }
    (xvfb, display)
}

/// The release editor on `display` with `args`, its settings and autosave under `dir`; returns the
/// process and its window id once the window is up.
fn start_editor(display: &str, dir: &Path, args: &[&str]) -> (Killed, String) {
    let binary = std::env::var("TAUT_EDITOR_BIN").unwrap_or_else(|_| env!("CARGO_BIN_EXE_taut").to_string());
    let mut editor = Killed(
        Command::new(binary)
            .args(args)
            .env("DISPLAY", display)
            .env("XDG_RUNTIME_DIR", dir.join("runtime"))
            .env("XDG_CONFIG_HOME", dir.join("config"))
            .env("XDG_DATA_HOME", dir.join("data"))
            .env("HOME", dir)
            .env("TAUT_NO_NATIVE_DIALOGS", "1")
            .env_remove("WAYLAND_DISPLAY")
            .stdout(Stdio::null())
            .stderr(Stdio::piped())
            .spawn()
            .expect("the editor starts"),
    );
    let found = Command::new("timeout")
        .args(["30", "xdotool", "search", "--sync", "--name", "Taut"])
        .env("DISPLAY", display)
        .output()
        .unwrap();
    if !found.status.success() {
        let _ = editor.0.kill();
        let output =
            std::mem::replace(&mut editor.0, Command::new("true").spawn().unwrap()).wait_with_output().unwrap();
        panic!("no editor window appeared: {}", String::from_utf8_lossy(&output.stderr));
    }
    let window = String::from_utf8_lossy(&found.stdout).lines().next().unwrap_or_default().trim().to_string();
    (editor, window)
}

/// Ctrl+Q, then the exit status must be 0 with no panic on stderr.
fn quit_cleanly(display: &str, editor: &mut Killed) {
    xdotool(display, &["key", "ctrl+q"]);
    let deadline = Instant::now() + Duration::from_secs(20);
    let status = loop {
        if let Some(status) = editor.0.try_wait().unwrap() {
            break status;
        }
        assert!(Instant::now() < deadline, "the editor did not close on Ctrl+Q");
        std::thread::sleep(Duration::from_millis(100));
    };
    let mut stderr = String::new();
    if let Some(mut e) = editor.0.stderr.take() {
        use std::io::Read;
        let _ = e.read_to_string(&mut stderr);
    }
    assert!(status.success(), "the editor exited with {status}: {stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
}

#[test]
fn drag_a_fixed_point_in_a_real_window_then_save_and_quit() {
    let _one = ONE_AT_A_TIME.lock().unwrap_or_else(|poisoned| poisoned.into_inner());
    require("Xvfb", "xvfb");
    require("xdotool", "xdotool");
    require("import", "imagemagick");
    let dir = std::env::temp_dir().join(format!("taut-editor-window-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(dir.join("runtime")).unwrap();
    let cage = dir.join("knob.taut");
    std::fs::copy(Path::new(env!("CARGO_MANIFEST_DIR")).join("../assets/default.taut"), &cage).unwrap();
    let before_doc: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&cage).unwrap()).unwrap();

    let (_xvfb, display) = start_xvfb();
    let (mut editor, window) = start_editor(&display, &dir, &[cage.to_str().unwrap(), "--view", "shaded"]);
    let before = settled(&display, &dir.join("before.png"));
    let (w, h) = before.dimensions();

    // The viewport's background is the colour in its top left corner (the framed model fills
    // most of the view, but not its corners); the apex of the default scene is the top-most
    // drawn pixel in the middle third of the screen.
    let background = *before.get_pixel(275, 35);
    let differs = |p: &image::Rgba<u8>| (0..3).any(|c| p[c].abs_diff(background[c]) > 30);
    let (apex_x, apex_y) = (30..h * 3 / 4)
        .flat_map(|y| (w / 3..2 * w / 3).map(move |x| (x, y)))
        .find(|&(x, y)| differs(before.get_pixel(x, y)))
        .expect("the surface is drawn");
    // The vertex sits in the middle of the top row of drawn pixels.
    let run: Vec<u32> = (w / 3..2 * w / 3).filter(|&x| differs(before.get_pixel(x, apex_y + 1))).collect();
    let apex_x = if run.is_empty() { apex_x } else { (run[0] + run[run.len() - 1]) / 2 };
    let (grab_x, grab_y) = (apex_x, apex_y + 5);
    eprintln!("apex found at {apex_x},{apex_y}; background {background:?}");

    let (x, y) = (grab_x.to_string(), grab_y.to_string());
    xdotool(&display, &["mousemove", &x, &y]);
    std::thread::sleep(Duration::from_millis(400));
    xdotool(&display, &["mousedown", "1"]);
    for step in 1..=12 {
        std::thread::sleep(Duration::from_millis(80));
        // Pressed down into the model: framed to fill the view, the apex is near the top edge.
        xdotool(&display, &["mousemove", &x, &(grab_y + step * 5).to_string()]);
    }
    std::thread::sleep(Duration::from_millis(300));
    xdotool(&display, &["mouseup", "1"]);
    let after = settled(&display, &dir.join("after.png"));

    // Where the apex was and below it: changed. The lower part of the surface: unchanged.
    let around_apex = changed(&before, &after, apex_x - 80, apex_y.saturating_sub(10), apex_x + 80, apex_y + 70);
    let (top, bottom) =
        (apex_y, (0..h * 85 / 100).rev().find(|&y| differs(before.get_pixel(apex_x, y))).unwrap_or(h / 2));
    let low = changed(&before, &after, w / 3, top + (bottom - top) * 3 / 4, 2 * w / 3, bottom);
    assert!(around_apex > 0.05, "the surface did not follow the drag ({around_apex:.4})");
    assert!(low < 0.02, "the drag changed the far side of the surface ({low:.4})");
    // The dragged vertex is selected: orange pixels where it now is, below where it was.
    let orange = (grab_y..grab_y + 80)
        .flat_map(|yy| (grab_x - 10..grab_x + 10).map(move |xx| (xx, yy)))
        .filter(|&(xx, yy)| {
            let p = after.get_pixel(xx, yy);
            // Selected (orange, lightened while hovered): warm, unlike the grey-blue cage.
            p[0] > 230 && p[0] as i32 - p[2] as i32 > 50 && p[1] > p[2]
        })
        .count();
    assert!(orange > 5, "no selected (orange) vertex near the cursor");

    // Save and quit: the file changed, the process exits cleanly. Without a window manager
    // the keyboard focus must be given to the window explicitly.
    xdotool(&display, &["windowfocus", "--sync", &window]);
    xdotool(&display, &["key", "ctrl+s"]);
    std::thread::sleep(Duration::from_millis(800));
    quit_cleanly(&display, &mut editor);
    let after_doc: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&cage).unwrap()).unwrap();
    let apex = |d: &serde_json::Value| d["positions"].as_array().unwrap().last().unwrap()[2].as_f64().unwrap();
    assert!(
        apex(&after_doc) < apex(&before_doc) - 1.0,
        "the saved apex did not move down: {} → {}",
        apex(&before_doc),
        apex(&after_doc)
    );
    assert!(!dir.join("data/taut/autosave.taut").exists(), "a clean exit leaves no autosave");
}

/// Presses keys one at a time (xdotool key names), with time for a frame between them.
fn keys(display: &str, names: &[&str]) {
    for name in names {
        xdotool(display, &["key", name]);
        std::thread::sleep(Duration::from_millis(350));
    }
}

#[test]
fn extrude_the_top_face_of_a_new_cube_move_it_up_and_save() {
    let _one = ONE_AT_A_TIME.lock().unwrap_or_else(|poisoned| poisoned.into_inner());
    require("Xvfb", "xvfb");
    require("xdotool", "xdotool");
    require("import", "imagemagick");
    let dir = std::env::temp_dir().join(format!("taut-editor-extrude-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(dir.join("runtime")).unwrap();
    let saved = dir.join("extruded.taut");
    let (_xvfb, display) = start_xvfb();
    // The bundled default scene, clean: File ▸ New asks nothing.
    let (mut editor, window) = start_editor(&display, &dir, &["--view", "shaded"]);
    settled(&display, &dir.join("scene.png"));

    // File ▸ New ▸ Cube with the mouse. The window is 1280 × 800 at the screen's corner and egui
    // lays its menus out the same way every time: "File" is the first entry of the menu bar,
    // "New" the first of its menu, "Cube" the first of that submenu.
    xdotool(&display, &["mousemove", "19", "12", "click", "1"]);
    std::thread::sleep(Duration::from_millis(700));
    xdotool(&display, &["mousemove", "40", "39"]);
    std::thread::sleep(Duration::from_millis(500));
    xdotool(&display, &["mousemove", "120", "39"]);
    std::thread::sleep(Duration::from_millis(300));
    xdotool(&display, &["mousemove", "192", "39"]);
    std::thread::sleep(Duration::from_millis(500));
    xdotool(&display, &["click", "1"]);
    let before = settled(&display, &dir.join("before.png"));

    // Face mode (Tab twice: vertex, edge, face), click the top face, E, then G Z 1 Enter moves it
    // up by exactly 1 (also when E itself starts the move: G is then ignored, Z 1 Enter set it).
    // (A whole number: a typed '.' is lost in a real window today, so "0.5" would move by 5.)
    // The new cube is framed whole, the same way every time; its top face's middle is at
    // (645, 187).
    xdotool(&display, &["windowfocus", "--sync", &window]);
    xdotool(&display, &["mousemove", "645", "187"]);
    keys(&display, &["Tab", "Tab"]);
    xdotool(&display, &["click", "1"]);
    std::thread::sleep(Duration::from_millis(600));
    keys(&display, &["e", "g", "z", "1", "Return"]);
    let after = settled(&display, &dir.join("after.png"));
    let (w, h) = after.dimensions();
    let moved = changed(&before, &after, 0, 0, w, h * 85 / 100);
    // The face goes up out of the framed view over an evenly shaded surface: a few percent of
    // the pixels change (selecting alone changes under half a percent).
    assert!(moved > 0.02, "the screen did not change after extruding and moving ({moved:.4})");

    // Save As (Ctrl+Shift+S): the path field, cleared and typed.
    xdotool(&display, &["key", "ctrl+shift+s"]);
    std::thread::sleep(Duration::from_millis(800));
    xdotool(&display, &["key", "End"]);
    xdotool(&display, &["key", "--repeat", "30", "--delay", "20", "BackSpace"]);
    xdotool(&display, &["type", "--delay", "20", saved.to_str().unwrap()]);
    std::thread::sleep(Duration::from_millis(300));
    xdotool(&display, &["key", "Return"]);
    let deadline = Instant::now() + Duration::from_secs(10);
    while !saved.exists() {
        assert!(Instant::now() < deadline, "Save As wrote no file at {}", saved.display());
        std::thread::sleep(Duration::from_millis(100));
    }
    quit_cleanly(&display, &mut editor);

    let doc: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&saved).unwrap()).unwrap();
    let positions = doc["positions"].as_array().unwrap();
    let faces = doc["faces"].as_array().unwrap();
    assert_eq!((positions.len(), faces.len()), (12, 10), "a cube with its top face extruded");
    // The cube's top is at z = 0.5; the extruded cap went up by E's offset (a fifth of the mean
    // edge length, 0.2) and then by exactly 1.
    let top = positions.iter().map(|p| p[2].as_f64().unwrap()).fold(f64::MIN, f64::max);
    assert!((top - 1.7).abs() < 1e-9, "the extruded face is not where E and G Z 1 put it: its top is at z = {top}");
    let caps = positions.iter().filter(|p| p[2].as_f64().unwrap() == top).count();
    assert_eq!(caps, 4, "the four corners of the cap are at the top");
}
