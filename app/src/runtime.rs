//! A private `XDG_RUNTIME_DIR` for sessions that have none (CI shells, `env -i`, cron): Mesa's
//! Vulkan window-system code prints "XDG_RUNTIME_DIR is invalid or not set" twice otherwise,
//! on stderr, which must hold only the one line of an error.

use std::path::PathBuf;

/// Removes the folder when the command ends.
#[derive(Debug)]
pub struct RuntimeDir(PathBuf);

impl Drop for RuntimeDir {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

/// Makes and announces a private runtime folder unless the session has a usable one.
#[allow(unsafe_code)]
pub fn ensure_runtime_dir() -> Option<RuntimeDir> {
    if std::env::var_os("XDG_RUNTIME_DIR").is_some_and(|d| std::path::Path::new(&d).is_dir()) {
        return None;
    }
    let nanos = std::time::SystemTime::now().duration_since(std::time::UNIX_EPOCH).map_or(0, |d| d.as_nanos());
    let dir = std::env::temp_dir().join(format!("taut-runtime-{}-{nanos}", std::process::id()));
    let mut builder = std::fs::DirBuilder::new();
    #[cfg(unix)]
    std::os::unix::fs::DirBuilderExt::mode(&mut builder, 0o700);
    builder.create(&dir).ok()?;
    // SAFETY: `set_var` is unsound only while another thread reads or writes the
    // environment. This runs in `main` right after the arguments are parsed, before the
    // command starts: no thread other than the main one exists yet (rayon's pool, wgpu and
    // winit are all started later by the command itself).
    unsafe { std::env::set_var("XDG_RUNTIME_DIR", &dir) };
    Some(RuntimeDir(dir))
}
