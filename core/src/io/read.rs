//! Opening a mesh file for reading: the one place the STL and PLY readers get their bytes.
//!
//! Only a regular file is read (a symbolic link is followed to what it names): a folder, a
//! device, a FIFO or a socket is refused before any byte is read, since reading one can block
//! forever or never end. The whole file is then read into memory, so every later size check is
//! against the bytes that really exist.

use crate::{Error, Result};
use std::path::Path;

/// The bytes of a regular file, or a clear error naming it.
pub(crate) fn read_regular_file(path: &Path) -> Result<Vec<u8>> {
    let meta = std::fs::metadata(path).map_err(|e| Error::io(path, e))?;
    if !meta.is_file() {
        let what = if meta.is_dir() { "a folder" } else { "not a regular file (a device, pipe or socket)" };
        return Err(Error::format(path, format!("{what}; choose a mesh file")));
    }
    std::fs::read(path).map_err(|e| Error::io(path, e))
}
