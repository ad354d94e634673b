//! Golden-image comparison: a rendered picture against a stored PNG under `tests/snapshots/`.
//!
//! A pixel differs when any channel differs by more than `channel_tolerance`; the picture
//! fails when more than `max_fraction` of its pixels differ. On failure the actual picture and a
//! diff (differing pixels in magenta over a dimmed copy of the reference) are written next to the
//! reference as `NAME.actual.png` and `NAME.diff.png`. `UPDATE_SNAPSHOTS=1` rewrites the
//! references instead; look at every picture before committing it.

use image::{Rgba, RgbaImage};
use std::path::PathBuf;

/// How close a picture must be to its reference.
#[derive(Clone, Copy, Debug)]
pub struct Tolerance {
    pub channel_tolerance: u8,
    pub max_fraction: f64,
}

/// The tolerance of Taut's golden images: anti-aliasing and rounding differences between
/// software rasterisers pass, a moved stripe or a changed colour does not.
pub const DEFAULT_TOLERANCE: Tolerance = Tolerance { channel_tolerance: 24, max_fraction: 0.004 };

/// Directory of the reference pictures.
pub fn snapshot_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("snapshots")
}

/// Compares `actual` with `tests/snapshots/NAME.png`; `Err` says why and where the pictures are.
pub fn check(name: &str, actual: &RgbaImage, tolerance: Tolerance) -> Result<(), String> {
    let dir = snapshot_dir();
    std::fs::create_dir_all(&dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    let reference_path = dir.join(format!("{name}.png"));
    let actual_path = dir.join(format!("{name}.actual.png"));
    let diff_path = dir.join(format!("{name}.diff.png"));
    if std::env::var_os("UPDATE_SNAPSHOTS").is_some_and(|v| v == "1") {
        actual.save(&reference_path).map_err(|e| format!("{}: {e}", reference_path.display()))?;
        let _ = std::fs::remove_file(&actual_path);
        let _ = std::fs::remove_file(&diff_path);
        return Ok(());
    }
    let reference = match image::open(&reference_path) {
        Ok(image) => image.to_rgba8(),
        Err(e) => {
            let _ = actual.save(&actual_path);
            return Err(format!(
                "no usable reference {} ({e}); the picture is in {}: look at it, then run with UPDATE_SNAPSHOTS=1",
                reference_path.display(),
                actual_path.display()
            ));
        }
    };
    if reference.dimensions() != actual.dimensions() {
        let _ = actual.save(&actual_path);
        return Err(format!(
            "{name}: size {:?} differs from the reference's {:?}; actual picture in {}",
            actual.dimensions(),
            reference.dimensions(),
            actual_path.display()
        ));
    }
    let mut diff = RgbaImage::new(actual.width(), actual.height());
    let mut differing = 0usize;
    for (x, y, a) in actual.enumerate_pixels() {
        let r = reference.get_pixel(x, y);
        let worst = (0..4).map(|c| a[c].abs_diff(r[c])).max().unwrap_or(0);
        if worst > tolerance.channel_tolerance {
            differing += 1;
            diff.put_pixel(x, y, Rgba([255, 0, 255, 255]));
        } else {
            diff.put_pixel(x, y, Rgba([r[0] / 3, r[1] / 3, r[2] / 3, 255]));
        }
    }
    let fraction = differing as f64 / (actual.width() as f64 * actual.height() as f64);
    if fraction > tolerance.max_fraction {
        let _ = actual.save(&actual_path);
        let _ = diff.save(&diff_path);
        return Err(format!(
            "{name}: {differing} pixels ({:.3} %) differ by more than {} (allowed {:.3} %); see {} and {}",
            100.0 * fraction,
            tolerance.channel_tolerance,
            100.0 * tolerance.max_fraction,
            actual_path.display(),
            diff_path.display()
        ));
    }
    let _ = std::fs::remove_file(&actual_path);
    let _ = std::fs::remove_file(&diff_path);
    Ok(())
}

/// The software device and renderer a test binary's pictures share (lavapipe is slow to open).
#[allow(missing_debug_implementations)]
pub struct Display {
    pub gpu: taut_render::Gpu,
    pub renderer: taut_render::Renderer,
}

/// The test binary's one software display, opened on first use. Without a GPU adapter the test
/// fails, saying what to install.
pub fn display() -> &'static std::sync::Mutex<Display> {
    static DISPLAY: std::sync::OnceLock<std::sync::Mutex<Display>> = std::sync::OnceLock::new();
    DISPLAY.get_or_init(|| {
        let gpu = taut_render::Gpu::headless(taut_render::AdapterPreference::Software).unwrap_or_else(|e| {
            panic!("render tests need a GPU adapter (on Debian: apt-get install mesa-vulkan-drivers libvulkan1): {e}")
        });
        let targets = taut_render::TargetFormats::for_adapter(&gpu.adapter, wgpu::TextureFormat::Rgba8UnormSrgb);
        let renderer = taut_render::Renderer::new(&gpu, targets);
        std::sync::Mutex::new(Display { gpu, renderer })
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn picture(shade: u8) -> RgbaImage {
        RgbaImage::from_pixel(20, 10, Rgba([shade, shade, shade, 255]))
    }

    #[test]
    fn small_differences_pass_and_large_ones_fail_with_pictures_written() {
        let name = format!("selftest-{}", std::process::id());
        let reference = picture(100);
        std::fs::create_dir_all(snapshot_dir()).unwrap();
        reference.save(snapshot_dir().join(format!("{name}.png"))).unwrap();
        assert!(check(&name, &picture(110), DEFAULT_TOLERANCE).is_ok());
        let mut changed = picture(100);
        for x in 0..5 {
            changed.put_pixel(x, 0, Rgba([200, 100, 100, 255]));
        }
        let err = check(&name, &changed, DEFAULT_TOLERANCE).unwrap_err();
        assert!(err.contains("5 pixels"), "{err}");
        assert!(snapshot_dir().join(format!("{name}.diff.png")).exists());
        assert!(snapshot_dir().join(format!("{name}.actual.png")).exists());
        for suffix in ["png", "actual.png", "diff.png"] {
            let _ = std::fs::remove_file(snapshot_dir().join(format!("{name}.{suffix}")));
        }
        assert!(check(&name, &picture(1), DEFAULT_TOLERANCE).unwrap_err().contains("no usable reference"));
        let _ = std::fs::remove_file(snapshot_dir().join(format!("{name}.actual.png")));
    }
}
