//! Writing a curve mesh out: its tessellated patches as OBJ or GLB with the analytic normals,
//! and its curves and Gregory control points as JSON.
//!
//! - OBJ: every vertex once (`v`, `vn`), `s 1`, then one group `g patch_F` per patch with its
//!   `K²` quads (`f a//a b//b …`). Shared boundary samples are one vertex, so importing welds
//!   nothing and the surface is closed where the curve mesh is.
//! - GLB: **one merged mesh** (one primitive) rather than one primitive per patch, so boundary
//!   vertices are shared and no viewer shows cracks; patch `F`'s triangles are the contiguous
//!   range `2K²·F .. 2K²·(F + 1)` of the index buffer (each quad split along its first
//!   diagonal). Positions and normals are f32, as glTF stores them.
//! - JSON (`--curves`): per vertex its position and normal, per curve its end vertices and four
//!   Bézier points, per patch its corner vertices, its curves and its 20 Gregory points in the
//!   order named in the file's `patch_point_order`.

use super::curve_mesh::CurveMesh;
use super::tessellate::Tessellation;
use crate::io::UpAxis;
use crate::{Error, Result};
use serde::Serialize;
use std::fmt::Write;
use std::path::Path;

/// The names of a patch's 20 points, in [`GregoryPatch::control_points`](super::GregoryPatch::control_points) order.
pub const PATCH_POINT_ORDER: [&str; 20] = [
    "P00", "P10", "P20", "P30", "P01", "P31", "P02", "P32", "P03", "P13", "P23", "P33", "P110", "P111", "P120", "P121",
    "P210", "P211", "P220", "P221",
];

/// The tessellation as OBJ text in the axes `up`: shared vertices with analytic normals, one
/// group per patch.
pub fn obj_text(tessellation: &Tessellation, up: UpAxis) -> String {
    let mesh = tessellation.mesh();
    let mut out = String::with_capacity(64 * mesh.vertex_count() + 48 * mesh.face_count());
    let k = tessellation.samples();
    let patches = mesh.face_count() / (k * k);
    let _ = writeln!(
        out,
        "# Taut curve mesh: {patches} Gregory patches at {k} x {k} samples, {} vertices, {} faces",
        mesh.vertex_count(),
        mesh.face_count()
    );
    for &p in mesh.positions() {
        let p = up.from_taut(p);
        // `{:?}` is Rust's shortest representation that reads back to the same f64.
        let _ = writeln!(out, "v {:?} {:?} {:?}", p.x, p.y, p.z);
    }
    for &n in tessellation.normals() {
        let n = up.from_taut(n);
        let _ = writeln!(out, "vn {:?} {:?} {:?}", n.x, n.y, n.z);
    }
    out.push_str("s 1\n");
    for patch in 0..patches {
        let _ = writeln!(out, "g patch_{patch}");
        for f in patch * k * k..(patch + 1) * k * k {
            out.push('f');
            for v in mesh.face_vertices(crate::FaceId(f as u32)) {
                let _ = write!(out, " {0}//{0}", v.0 + 1);
            }
            out.push('\n');
        }
    }
    out
}

/// Writes the tessellation as OBJ (in the axes `obj_up`) or GLB (Y up) by the path's extension,
/// atomically.
pub fn export_tessellation(tessellation: &Tessellation, path: &Path, obj_up: UpAxis) -> Result<()> {
    if tessellation.mesh().face_count() == 0 {
        return Err(Error::Input(format!(
            "{}: the curve mesh has no patches; there is nothing to export",
            path.display()
        )));
    }
    crate::io::check_finite_output(tessellation.mesh().positions(), Some(tessellation.normals()))
        .map_err(|e| Error::format(path, e.to_string()))?;
    match crate::io::MeshFormat::from_path(path)? {
        crate::io::MeshFormat::Obj => crate::io::write_atomic(path, obj_text(tessellation, obj_up).as_bytes()),
        crate::io::MeshFormat::Glb => {
            let bytes = crate::io::glb::glb_bytes(tessellation.mesh(), Some(tessellation.normals()))
                .map_err(|e| Error::format(path, e.to_string()))?;
            crate::io::write_atomic(path, &bytes)
        }
        crate::io::MeshFormat::Gltf => {
            Err(Error::format(path, "Taut exports glTF as binary .glb only; choose a .glb (or .obj) file name"))
        }
        crate::io::MeshFormat::Stl | crate::io::MeshFormat::Ply => {
            Err(Error::format(path, "Taut reads STL and PLY but exports .obj and .glb only; choose one of those"))
        }
    }
}

#[derive(Serialize)]
struct CurvesFile {
    format: &'static str,
    version: u32,
    patch_point_order: [&'static str; 20],
    vertices: Vec<VertexJson>,
    curves: Vec<CurveJson>,
    patches: Vec<PatchJson>,
}

#[derive(Serialize)]
struct VertexJson {
    position: [f64; 3],
    normal: [f64; 3],
}

#[derive(Serialize)]
struct CurveJson {
    vertices: [u32; 2],
    points: [[f64; 3]; 4],
}

#[derive(Serialize)]
struct PatchJson {
    corners: [u32; 4],
    curves: [u32; 4],
    points: Vec<[f64; 3]>,
}

/// The curve mesh's vertices, curves (four Bézier points each) and patches (20 Gregory points
/// each) as JSON.
pub fn curves_json(curves: &CurveMesh) -> String {
    let t = curves.topology();
    let file = CurvesFile {
        format: "taut-curve-mesh",
        version: 1,
        patch_point_order: PATCH_POINT_ORDER,
        vertices: t
            .vertices()
            .map(|v| VertexJson {
                position: curves.vertex_position(v).to_array(),
                normal: curves.vertex_normal(v).to_array(),
            })
            .collect(),
        curves: t
            .edges()
            .map(|e| {
                let (a, b) = t.edge_vertices(e);
                CurveJson { vertices: [a.0, b.0], points: curves.curve(e).points.map(|p| p.to_array()) }
            })
            .collect(),
        patches: t
            .faces()
            .map(|f| {
                let hs: Vec<_> = t.face_halfedges(f).collect();
                PatchJson {
                    corners: std::array::from_fn(|k| t.from_vertex(hs[k]).0),
                    curves: std::array::from_fn(|k| hs[k].edge().0),
                    points: curves.patch(f).control_points().iter().map(|p| p.to_array()).collect(),
                }
            })
            .collect(),
    };
    serde_json::to_string(&file).expect("plain numbers and strings always serialise")
}

/// Writes [`curves_json`] to `path`, atomically.
pub fn export_curves_json(curves: &CurveMesh, path: &Path) -> Result<()> {
    crate::io::write_atomic(path, curves_json(curves).as_bytes())
}
