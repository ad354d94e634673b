//! Reading and writing cages and surfaces: OBJ, glTF 2.0 (`.gltf`, `.glb`), STL and PLY (read
//! only), and `.taut`.
//!
//! [`import_mesh`] reads a mesh file by its extension into a polygon soup, welds vertices at
//! identical positions where the surface stays manifold and repairs what welding collapses
//! ([`weld()`]), then builds the cage; the [`ImportReport`] says what changed.
//! [`import_triangles`] stops before building the cage, for dense meshes (scans) that may not be
//! manifold: the control-cage fitter repairs those itself. [`export_mesh`]
//! writes a surface keeping its vertex order, so a refined surface's file starts with the cage's
//! vertices in input order. `.taut` documents are read and written by
//! [`Document`](crate::Document). Every reader reads only regular files ([`file`]).
//!
//! Axes: Taut models Z up. glTF is Y up by its specification, so glTF files are converted on the
//! way in and out; OBJ has no rule and is taken as Y up by default, as Blender and most tools
//! write it ([`UpAxis`]).

pub mod file;
pub mod glb;
pub mod gltf;
pub mod obj;
pub mod ply;
pub mod points;
pub mod soup;
pub mod stl;
pub mod weld;
mod weld_soup;

pub use glb::export_glb;
pub use obj::{export_obj, export_obj_with};
pub use soup::{FaceList, Soup};
pub use weld::{ImportReport, weld, weld_faces};

use crate::DVec3;

/// Which axis points up in a file. Taut's own axes are Z up.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum UpAxis {
    /// Y up (glTF's rule; OBJ as Blender, Maya and most tools write it): the file's `(x, y, z)`
    /// is Taut's `(x, −z, y)`.
    #[default]
    Y,
    /// Z up, as Taut models: no conversion.
    Z,
}

impl UpAxis {
    /// A point or direction of the file in Taut's axes (exact: a swap and a sign).
    #[inline]
    pub fn to_taut(self, p: DVec3) -> DVec3 {
        match self {
            UpAxis::Y => DVec3::new(p.x, -p.z, p.y),
            UpAxis::Z => p,
        }
    }

    /// A point or direction of Taut in the file's axes; the inverse of [`to_taut`](Self::to_taut).
    #[inline]
    pub fn from_taut(self, p: DVec3) -> DVec3 {
        match self {
            UpAxis::Y => DVec3::new(p.x, p.z, -p.y),
            UpAxis::Z => p,
        }
    }

    /// `"Y"` or `"Z"`.
    pub fn name(self) -> &'static str {
        match self {
            UpAxis::Y => "Y",
            UpAxis::Z => "Z",
        }
    }
}

impl std::str::FromStr for UpAxis {
    type Err = String;
    fn from_str(s: &str) -> std::result::Result<Self, String> {
        match s {
            "y" | "Y" => Ok(UpAxis::Y),
            "z" | "Z" => Ok(UpAxis::Z),
            other => Err(format!("unknown up axis '{other}' (use y or z)")),
        }
    }
}

/// How mesh files are read.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct ImportOptions {
    /// The up axis of OBJ files (glTF is always Y up).
    pub obj_up: UpAxis,
}

/// How a surface is written.
#[derive(Clone, Copy, Debug, Default)]
pub struct ExportOptions<'a> {
    /// Per-vertex unit normals to write (exact limit normals); area-weighted ones when `None`.
    pub normals: Option<&'a [DVec3]>,
    /// The up axis of OBJ files (glTF is always Y up).
    pub obj_up: UpAxis,
}

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
    /// STL, binary or ASCII (read only).
    Stl,
    /// PLY, ASCII or binary of either byte order (read only).
    Ply,
}

impl MeshFormat {
    /// The extensions [`MeshFormat::from_path`] recognises, for messages.
    pub const SUPPORTED: &str = ".obj, .gltf, .glb, .stl or .ply";

    /// The format of a file, from its extension.
    pub fn from_path(path: &Path) -> Result<Self> {
        let ext = path.extension().map(|e| e.to_string_lossy().to_ascii_lowercase());
        match ext.as_deref() {
            Some("obj") => Ok(MeshFormat::Obj),
            Some("gltf") => Ok(MeshFormat::Gltf),
            Some("glb") => Ok(MeshFormat::Glb),
            Some("stl") => Ok(MeshFormat::Stl),
            Some("ply") => Ok(MeshFormat::Ply),
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
    import_mesh_with(path, &ImportOptions::default())
}

/// [`import_mesh`] with options (the up axis of OBJ files).
pub fn import_mesh_with(path: &Path, options: &ImportOptions) -> Result<(PolyMesh, ImportReport)> {
    weld::into_mesh(path, read_soup(path, options)?)
}

/// Imports a mesh file as welded triangles without building a cage, so a surface that is not
/// manifold still arrives (for [`DenseMesh`](crate::cage_fit::DenseMesh), which repairs it).
/// Polygons are split into fans of triangles from their first corner.
pub fn import_triangles(path: &Path, options: &ImportOptions) -> Result<(Vec<DVec3>, Vec<[u32; 3]>, ImportReport)> {
    if MeshFormat::from_path(path)? == MeshFormat::Stl {
        // A binary STL's corners are welded as they are; its `f32` extent is never below
        // [`MIN_MODEL_SIZE`].
        let soup = match stl::read_stl_content(path)? {
            stl::StlContent::Binary { triangles, warnings } => {
                let faces = triangles.len();
                let (positions, triangles, mut report) =
                    weld_soup::weld_triangle_soup(&triangles).map_err(|e| Error::format(path, e.to_string()))?;
                if triangles.is_empty() {
                    return Err(Error::format(path, format!("no faces: the file has {faces} usable polygons")));
                }
                let mut all = warnings;
                all.append(&mut report.warnings);
                report.warnings = all;
                return Ok((positions, triangles, report));
            }
            stl::StlContent::Ascii(soup) => soup,
        };
        check_size(path, &soup.positions)?;
        return triangles_of(path, soup);
    }
    triangles_of(path, read_soup(path, options)?)
}

/// Welds a soup and splits its polygons into fans of triangles (see [`import_triangles`]).
fn triangles_of(path: &Path, soup: Soup) -> Result<(Vec<DVec3>, Vec<[u32; 3]>, ImportReport)> {
    let faces = soup.faces.len();
    let welded = weld_faces(&soup.positions, &soup.faces).map_err(|e| Error::format(path, e.to_string()))?;
    drop(soup.faces);
    let mut triangles = Vec::with_capacity(welded.faces.len());
    for face in welded.faces.iter() {
        for k in 1..face.len() - 1 {
            triangles.push([face[0], face[k], face[k + 1]]);
        }
    }
    if triangles.is_empty() {
        return Err(Error::format(path, format!("no faces: the file has {faces} usable polygons")));
    }
    let mut report = welded.report;
    let mut warnings = soup.warnings;
    warnings.append(&mut report.warnings);
    report.warnings = warnings;
    Ok((welded.positions, triangles, report))
}

/// Reads a mesh file by extension into a polygon soup in Taut's axes.
fn read_soup(path: &Path, options: &ImportOptions) -> Result<Soup> {
    let soup = match MeshFormat::from_path(path)? {
        MeshFormat::Obj => obj::read_obj(path, options.obj_up),
        MeshFormat::Gltf | MeshFormat::Glb => self::gltf::read_gltf(path),
        MeshFormat::Stl => stl::read_stl(path),
        MeshFormat::Ply => ply::read_ply(path),
    }?;
    check_size(path, &soup.positions)?;
    Ok(soup)
}

/// The smallest model size Taut works at: the smallest normal double (about 2.2e-308). Below it
/// coordinates are subnormal and keep only a few significant bits (a cube 1e-320 across holds
/// about ten), so such a file is refused. Everything above works at any scale: normals,
/// curvature and the display are computed on the model scaled to unit size.
pub const MIN_MODEL_SIZE: f64 = f64::MIN_POSITIVE;

/// Refuses a mesh whose extent is positive but below [`MIN_MODEL_SIZE`].
fn check_size(path: &Path, positions: &[DVec3]) -> Result<()> {
    let Some((lo, hi)) = crate::mesh::bounding_box(positions) else { return Ok(()) };
    let size = (hi - lo).max_element();
    if size > 0.0 && size < MIN_MODEL_SIZE {
        return Err(Error::format(
            path,
            format!(
                "the mesh is {size:e} across: too small for double-precision geometry (below {MIN_MODEL_SIZE:.1e} \
                 numbers lose their precision); scale it up"
            ),
        ));
    }
    Ok(())
}

/// Refuses a surface with a coordinate or normal that is not a finite number before it is written
/// (an OBJ would otherwise hold `NaN` or `inf`, which no tool reads back).
pub(crate) fn check_finite_output(positions: &[DVec3], normals: Option<&[DVec3]>) -> Result<()> {
    if let Some(v) = positions.iter().position(|p| !p.is_finite()) {
        return Err(Error::Input(format!("the surface's vertex {v} is not a finite point; nothing was written")));
    }
    if let Some(v) = normals.and_then(|n| n.iter().position(|n| !n.is_finite())) {
        return Err(Error::Input(format!("the surface's normal at vertex {v} is not finite; nothing was written")));
    }
    Ok(())
}

/// Exports a mesh by extension (`.obj` or `.glb`), atomically, keeping its vertex order.
pub fn export_mesh(mesh: &PolyMesh, path: &Path) -> Result<()> {
    export_mesh_with(mesh, path, &ExportOptions::default())
}

/// [`export_mesh`] with options (normals to write, the up axis of OBJ files).
pub fn export_mesh_with(mesh: &PolyMesh, path: &Path, options: &ExportOptions<'_>) -> Result<()> {
    match MeshFormat::from_path(path)? {
        MeshFormat::Obj => export_obj_with(mesh, path, options.normals, options.obj_up),
        MeshFormat::Glb => glb::export_glb_with(mesh, path, options.normals),
        MeshFormat::Gltf => {
            Err(Error::format(path, "Taut exports glTF as binary .glb only; choose a .glb (or .obj) file name"))
        }
        MeshFormat::Stl | MeshFormat::Ply => {
            Err(Error::format(path, "Taut reads STL and PLY but exports .obj and .glb only; choose one of those"))
        }
    }
}

/// Writes a file atomically: the bytes go to a temporary file in the same folder, which is
/// flushed to disk and then renamed over the target, so a crash never leaves a half-written file.
/// A device, FIFO, folder or read-only file at the path is refused first ([`file::check_writable`]).
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<()> {
    file::check_writable(path)?;
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
