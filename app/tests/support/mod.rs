//! What the command-line tests share: the binary run with a runtime directory (Mesa's software
//! rasteriser wants one, as a desktop session has), the bundled assets, a scratch folder per
//! test, and the Python of the reference kernels (OpenCascade, MeshLab).

#![allow(dead_code)]

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// Runs `taut` with `args`; `tag` names its runtime folder.
pub fn taut_in(tag: &str, args: &[&str]) -> Output {
    let runtime = std::env::temp_dir().join(format!("taut-{tag}-runtime-{}", std::process::id()));
    std::fs::create_dir_all(&runtime).unwrap();
    Command::new(env!("CARGO_BIN_EXE_taut"))
        .args(args)
        .env("XDG_RUNTIME_DIR", runtime)
        .output()
        .expect("the taut binary runs")
}

/// A bundled asset's path.
pub fn asset(name: &str) -> String {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../assets").join(name).to_string_lossy().into_owned()
}

/// An empty scratch folder for `test` of the file `tag`.
pub fn scratch_in(tag: &str, test: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("taut-{tag}-{}-{test}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// `out` failed with exactly one line of its own, naming `expected`, and no panic.
pub fn assert_clean_failure(out: &Output, expected: &str) {
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success(), "expected failure; stderr: {stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
    let ours: Vec<&str> = stderr.lines().filter(|l| l.starts_with("error:")).collect();
    assert_eq!(ours.len(), 1, "{stderr}");
    assert!(ours[0].contains(expected), "expected '{expected}' in: {stderr}");
}

/// The Python of `.venv-cad`, which `tests/run-all.sh` makes with OpenCascade and pymeshlab (or
/// `TAUT_CAD_PYTHON`); a clear failure naming what to run when it is missing.
pub fn reference_python() -> PathBuf {
    let python = std::env::var_os("TAUT_CAD_PYTHON")
        .map(PathBuf::from)
        .unwrap_or_else(|| Path::new(env!("CARGO_MANIFEST_DIR")).join("../.venv-cad/bin/python"));
    assert!(
        python.exists(),
        "no Python with OpenCascade and pymeshlab at {}: run `bash tests/run-all.sh`, which installs \
         cadquery-ocp-novtk and pymeshlab into .venv-cad (or set TAUT_CAD_PYTHON)",
        python.display()
    );
    python
}
