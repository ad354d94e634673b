//! Reading input files safely: only regular files, never more than the file's own size or a
//! declared length, and never outside the folder a glTF file may refer into.
//!
//! A path can name a device (`/dev/zero` never ends), a FIFO (reading blocks until a writer
//! comes) or a link to either; reading those grows memory without bound or hangs. Every reader
//! therefore goes through [`read_regular_file`], which asks the file system what the path is
//! (following links) before opening it, and checks the opened file again before reading.
//! [`resolve_inside`] confines the relative URIs of a `.gltf` file to its own folder.

use crate::{Error, Result};
use std::io::Read;
use std::path::{Component, Path, PathBuf};

/// What a path that is not a regular file is, in words; `None` for a regular file.
fn not_regular(metadata: &std::fs::Metadata) -> Option<&'static str> {
    let kind = metadata.file_type();
    if kind.is_file() {
        return None;
    }
    if kind.is_dir() {
        return Some("a folder");
    }
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        if kind.is_fifo() {
            return Some("a named pipe (FIFO)");
        } else if kind.is_char_device() || kind.is_block_device() {
            return Some("a device");
        } else if kind.is_socket() {
            return Some("a socket");
        }
    }
    Some("not a regular file")
}

/// Refuses anything that is not a regular file (after following links), with a message naming
/// what it is.
fn check_regular(path: &Path, metadata: &std::fs::Metadata) -> Result<()> {
    match not_regular(metadata) {
        None => Ok(()),
        Some(what) => Err(Error::format(path, format!("{what}, not a regular file: Taut reads only regular files"))),
    }
}

/// Checks, before anything is computed or written, that `path` can take an output: its folder
/// exists, and the path is either free or a regular file the user may write. A device, a FIFO or a
/// folder at the path is refused (an atomic write would replace a device node by a plain file),
/// and so is a read-only file: one without any write permission bit (which even the superuser's
/// rename would silently replace) or one this user cannot open for writing.
pub fn check_writable(path: &Path) -> Result<()> {
    let folder = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    match std::fs::metadata(folder) {
        Ok(m) if m.is_dir() => {}
        Ok(_) => return Err(Error::format(path, format!("{} is not a folder", folder.display()))),
        Err(_) => return Err(Error::format(path, format!("the folder {} does not exist", folder.display()))),
    }
    let metadata = match std::fs::metadata(path) {
        Ok(m) => m,
        // Nothing there yet (or a dangling link, which the rename replaces): free to write.
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(()),
        Err(e) => return Err(Error::format(path, format!("cannot check the output: {e}"))),
    };
    if let Some(what) = not_regular(&metadata) {
        return Err(Error::format(
            path,
            format!("{what}, not a regular file: Taut writes its output only to regular files; choose a file name"),
        ));
    }
    let read_only = || Error::format(path, "the file is read-only: Taut does not replace it; choose another name");
    if metadata.permissions().readonly() {
        return Err(read_only());
    }
    // Opening for writing without truncating changes nothing and asks the system the real question.
    std::fs::OpenOptions::new().write(true).open(path).map_err(|_| read_only())?;
    Ok(())
}

/// The whole contents of a regular file; anything else (a folder, device, FIFO, socket, or a link
/// to one) is refused before it is opened.
pub fn read_regular_file(path: &Path) -> Result<Vec<u8>> {
    read_regular_file_limited(path, None)
}

/// Like [`read_regular_file`] as text; invalid UTF-8 is an error naming the file.
pub fn read_regular_text(path: &Path) -> Result<String> {
    let bytes = read_regular_file(path)?;
    String::from_utf8(bytes).map_err(|_| Error::format(path, "the file is not UTF-8 text"))
}

/// The first `length` bytes of a regular file; a file shorter than that is an error.
pub fn read_regular_prefix(path: &Path, length: u64) -> Result<Vec<u8>> {
    read_regular_file_limited(path, Some(length))
}

fn read_regular_file_limited(path: &Path, length: Option<u64>) -> Result<Vec<u8>> {
    let cannot = |e: std::io::Error| Error::format(path, format!("cannot read it: {e}"));
    let metadata = std::fs::metadata(path).map_err(cannot)?;
    check_regular(path, &metadata)?;
    let file = std::fs::File::open(path).map_err(cannot)?;
    // The path may have been swapped between the two looks: check what was opened.
    let opened = file.metadata().map_err(cannot)?;
    check_regular(path, &opened)?;
    let size = opened.len();
    let want = match length {
        Some(n) if n > size => {
            return Err(Error::format(path, format!("the file has {size} bytes, fewer than the {n} declared")));
        }
        Some(n) => n,
        None => size,
    };
    let capacity = usize::try_from(want).map_err(|_| Error::format(path, "the file is too large to read"))?;
    let mut bytes = Vec::new();
    bytes
        .try_reserve_exact(capacity)
        .map_err(|_| Error::format(path, format!("not enough memory to read {want} bytes")))?;
    // Never more than was asked for, even if the file grows while it is read.
    file.take(want).read_to_end(&mut bytes).map_err(cannot)?;
    if (bytes.len() as u64) < want {
        return Err(Error::format(path, format!("the file has {} bytes, fewer than the {want} expected", bytes.len())));
    }
    Ok(bytes)
}

/// The file a relative URI names, resolved against `folder`, provided it stays inside `folder`
/// once links are followed. Absolute paths, drive prefixes and paths that climb out with `..` are
/// refused, as are links that lead out of the folder.
pub fn resolve_inside(folder: &Path, relative: &str) -> std::result::Result<PathBuf, String> {
    let candidate = Path::new(relative);
    if candidate.as_os_str().is_empty() {
        return Err("it is empty".into());
    }
    if candidate.components().any(|c| matches!(c, Component::RootDir | Component::Prefix(_))) {
        return Err("it is an absolute path; a glTF file may only refer to files in its own folder".into());
    }
    let folder = if folder.as_os_str().is_empty() { Path::new(".") } else { folder };
    let root = folder.canonicalize().map_err(|e| format!("its folder {} cannot be read: {e}", folder.display()))?;
    let joined = root.join(candidate);
    let resolved = joined.canonicalize().map_err(|e| format!("it cannot be read ({}): {e}", joined.display()))?;
    if !resolved.starts_with(&root) {
        return Err(format!(
            "it leads outside the glTF file's folder ({}); a glTF file may only refer to files in its own folder",
            resolved.display()
        ));
    }
    Ok(resolved)
}

/// True when both paths name one existing file, once links are followed (hard links included):
/// the check that keeps an output from replacing an input.
pub fn same_file(a: &Path, b: &Path) -> bool {
    let (Ok(ma), Ok(mb)) = (std::fs::metadata(a), std::fs::metadata(b)) else { return false };
    #[cfg(unix)]
    {
        use std::os::unix::fs::MetadataExt;
        ma.dev() == mb.dev() && ma.ino() == mb.ino()
    }
    #[cfg(not(unix))]
    {
        let _ = (ma, mb);
        matches!((a.canonicalize(), b.canonicalize()), (Ok(x), Ok(y)) if x == y)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn temp(name: &str) -> PathBuf {
        let dir = std::env::temp_dir().join(format!("taut-file-{}-{name}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        dir
    }

    #[test]
    fn devices_folders_and_fifos_are_refused_before_reading() {
        let dir = temp("kinds");
        let err = read_regular_file(Path::new("/dev/zero")).unwrap_err().to_string();
        assert!(err.contains("a device, not a regular file"), "{err}");
        let err = read_regular_file(&dir).unwrap_err().to_string();
        assert!(err.contains("a folder"), "{err}");
        #[cfg(unix)]
        {
            let link = dir.join("zero.obj");
            std::os::unix::fs::symlink("/dev/zero", &link).unwrap();
            let err = read_regular_file(&link).unwrap_err().to_string();
            assert!(err.contains("a device"), "{err}");
            let fifo = dir.join("pipe.obj");
            let made = std::process::Command::new("mkfifo").arg(&fifo).status().map(|s| s.success());
            assert_eq!(made.ok(), Some(true), "mkfifo is needed for this test");
            // This would block forever if the FIFO were opened for reading.
            let err = read_regular_file(&fifo).unwrap_err().to_string();
            assert!(err.contains("named pipe"), "{err}");
        }
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn the_same_file_is_found_through_links() {
        let dir = temp("same");
        let a = dir.join("a.obj");
        std::fs::write(&a, b"x").unwrap();
        std::fs::write(dir.join("b.obj"), b"x").unwrap();
        assert!(same_file(&a, &dir.join("./a.obj")));
        assert!(!same_file(&a, &dir.join("b.obj")));
        assert!(!same_file(&a, &dir.join("missing.obj")));
        #[cfg(unix)]
        {
            std::os::unix::fs::symlink(&a, dir.join("link.obj")).unwrap();
            std::fs::hard_link(&a, dir.join("hard.obj")).unwrap();
            assert!(same_file(&a, &dir.join("link.obj")));
            assert!(same_file(&a, &dir.join("hard.obj")));
        }
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn prefixes_are_exact_and_short_files_are_errors() {
        let dir = temp("prefix");
        let path = dir.join("data.bin");
        std::fs::write(&path, [1u8, 2, 3, 4, 5]).unwrap();
        assert_eq!(read_regular_prefix(&path, 3).unwrap(), vec![1, 2, 3]);
        assert_eq!(read_regular_file(&path).unwrap().len(), 5);
        let err = read_regular_prefix(&path, 9).unwrap_err().to_string();
        assert!(err.contains("fewer than the 9 declared"), "{err}");
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn uris_stay_inside_the_folder() {
        let dir = temp("inside");
        let sub = dir.join("model");
        std::fs::create_dir_all(sub.join("parts")).unwrap();
        std::fs::write(sub.join("parts/a.bin"), b"x").unwrap();
        std::fs::write(dir.join("secret.bin"), b"x").unwrap();
        assert!(resolve_inside(&sub, "parts/a.bin").unwrap().ends_with("parts/a.bin"));
        assert!(resolve_inside(&sub, "parts/../parts/a.bin").is_ok());
        assert!(resolve_inside(&sub, "../secret.bin").unwrap_err().contains("outside"));
        assert!(resolve_inside(&sub, "/etc/passwd").unwrap_err().contains("absolute"));
        #[cfg(unix)]
        {
            std::os::unix::fs::symlink(dir.join("secret.bin"), sub.join("link.bin")).unwrap();
            assert!(resolve_inside(&sub, "link.bin").unwrap_err().contains("outside"));
        }
        let _ = std::fs::remove_dir_all(&dir);
    }
}
