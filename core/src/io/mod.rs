//! Reading and writing cages and surfaces: OBJ, glTF 2.0 (`.gltf`, `.glb`) and `.taut`.
//!
//! [`import_mesh`] reads a mesh file by its extension into a polygon soup, welds vertices at
//! identical positions and repairs what welding collapses ([`weld()`]), then builds the cage;
//! the [`ImportReport`] says what changed. [`export_mesh`] writes a surface keeping its vertex
//! order, so a refined surface's file starts with the cage's vertices in input order. `.taut`
//! documents are read and written by [`Document`](crate::Document); [`points`] reads and writes
//! the JSON and CSV point files of the curve commands.

pub mod glb;
pub mod gltf;
pub mod obj;
pub mod points;
pub mod weld;

pub use glb::export_glb;
pub use obj::export_obj;
pub use weld::{ImportReport, weld};

use crate::mesh::PolyMesh;
use crate::{Error, Result};
use std::io::Write;
use std::path::Path;

/// The mesh file formats Taut imports and exports, told apart by extension (any case).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum MeshFormat {
    /// Wavefront `.obj` (read and written).
    Obj,
    /// glTF 2.0 JSON `.gltf` with external or embedded buffers (read only).
    Gltf,
    /// Binary glTF 2.0 `.glb` (read and written).
    Glb,
}

impl MeshFormat {
    /// The extensions [`MeshFormat::from_path`] recognises, for messages.
    pub const SUPPORTED: &str = ".obj, .gltf or .glb";

    /// The format of a file, from its extension.
    pub fn from_path(path: &Path) -> Result<Self> {
        let ext = path.extension().map(|e| e.to_string_lossy().to_ascii_lowercase());
        match ext.as_deref() {
            Some("obj") => Ok(MeshFormat::Obj),
            Some("gltf") => Ok(MeshFormat::Gltf),
            Some("glb") => Ok(MeshFormat::Glb),
            other => Err(Error::format(
                path,
                format!(
                    "{} is not a mesh format Taut knows; use {} (cages with tensions are .taut documents)",
                    other.map_or("a file without an extension".to_string(), |e| format!("'.{e}'")),
                    Self::SUPPORTED
                ),
            )),
        }
    }
}

/// Imports a mesh file as a cage: reads it by extension, welds vertices at identical positions,
/// repairs the faces welding collapses, and reports what it changed. Vertex *i* of an OBJ
/// without duplicate positions is its *i*-th `v` line.
pub fn import_mesh(path: &Path) -> Result<(PolyMesh, ImportReport)> {
    let soup = match MeshFormat::from_path(path)? {
        MeshFormat::Obj => obj::read_obj(path)?,
        MeshFormat::Gltf | MeshFormat::Glb => self::gltf::read_gltf(path)?,
    };
    weld::into_mesh(path, soup)
}

/// Exports a mesh by extension (`.obj` or `.glb`), atomically, keeping its vertex order.
pub fn export_mesh(mesh: &PolyMesh, path: &Path) -> Result<()> {
    match MeshFormat::from_path(path)? {
        MeshFormat::Obj => export_obj(mesh, path),
        MeshFormat::Glb => export_glb(mesh, path),
        MeshFormat::Gltf => {
            Err(Error::format(path, "Taut exports glTF as binary .glb only; choose a .glb (or .obj) file name"))
        }
    }
}

/// Writes a file atomically: the bytes go to a temporary file in the same folder, which is
/// flushed to disk and then renamed over the target, so a crash never leaves a half-written file.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<()> {
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d.to_path_buf(),
        _ => std::path::PathBuf::from("."),
    };
    let name = path.file_name().ok_or_else(|| Error::Input(format!("{} is not a file name", path.display())))?;
    let tmp = dir.join(format!(".{}.tmp-{}", name.to_string_lossy(), std::process::id()));
    let result = (|| {
        let mut file = std::fs::File::create(&tmp)?;
        file.write_all(bytes)?;
        file.sync_all()?;
        std::fs::rename(&tmp, path)
    })();
    if let Err(e) = result {
        let _ = std::fs::remove_file(&tmp);
        return Err(Error::io(path, e));
    }
    Ok(())
}
