//! glTF 2.0 export: a surface as a binary `.glb`.
//!
//! Follows the spec's GLB layout: positions and normals as f32, indices as u32 from the fan
//! triangulation of each polygon, with the `min`/`max` bounds the spec requires on positions.
//! Weak spot: f32 storage rounds positions (vertices closer than that precision become one
//! position, and importing the file again welds them).

use crate::mesh::PolyMesh;
use crate::{DVec3, Error, Result};
use ::gltf::json::accessor::{ComponentType, GenericComponentType, Type};
use ::gltf::json::mesh::{Mode, Semantic};
use ::gltf::json::validation::{Checked, USize64};
use ::gltf::json::{self, Index};
use std::borrow::Cow;
use std::collections::BTreeMap;
use std::path::Path;

/// The mesh as GLB bytes: one node, one mesh, one triangle primitive; vertex *i* of the file is
/// vertex *i* of the mesh.
pub fn glb_bytes(mesh: &PolyMesh) -> Result<Vec<u8>> {
    glb_bytes_with_normals(mesh, &mesh.vertex_normals())
}

/// Like [`glb_bytes`], with the given unit normal per vertex (for example exact normals of the
/// surface the mesh samples) instead of area-weighted ones.
pub fn glb_bytes_with_normals(mesh: &PolyMesh, normals: &[DVec3]) -> Result<Vec<u8>> {
    if normals.len() != mesh.vertex_count() {
        return Err(Error::Input(format!("{} normals given for {} vertices", normals.len(), mesh.vertex_count())));
    }
    if mesh.face_count() == 0 {
        return Err(Error::Input("the mesh has no faces; there is nothing to export".into()));
    }
    let positions: Vec<[f32; 3]> = mesh.positions().iter().map(|p| p.as_vec3().to_array()).collect();
    if let Some(v) = positions.iter().position(|p| !p.iter().all(|c| c.is_finite())) {
        return Err(Error::Input(format!(
            "vertex {v} at {:?} is beyond the range of the 32-bit floats glTF stores",
            mesh.positions()[v].to_array()
        )));
    }
    // The spec wants unit normals; isolated or degenerate vertices get +Z.
    let normals: Vec<[f32; 3]> =
        normals.iter().map(|n| if *n == DVec3::ZERO { [0.0, 0.0, 1.0] } else { n.as_vec3().to_array() }).collect();
    let indices: Vec<u32> = mesh.triangles().into_iter().flatten().collect();
    let mut bin = Vec::with_capacity(24 * positions.len() + 4 * indices.len());
    bin.extend(positions.iter().flatten().flat_map(|c| c.to_le_bytes()));
    bin.extend(normals.iter().flatten().flat_map(|c| c.to_le_bytes()));
    bin.extend(indices.iter().flat_map(|i| i.to_le_bytes()));
    if bin.len() > (u32::MAX as usize) - (1 << 20) {
        return Err(Error::Input("the mesh is too large for a binary glTF file (4 GiB)".into()));
    }

    let (lo, hi) = positions.iter().fold(([f32::INFINITY; 3], [f32::NEG_INFINITY; 3]), |(lo, hi), p| {
        (std::array::from_fn(|k| lo[k].min(p[k])), std::array::from_fn(|k| hi[k].max(p[k])))
    });
    let mut root = json::Root {
        asset: json::Asset { generator: Some("Taut".into()), ..Default::default() },
        ..Default::default()
    };
    let buffer = root.push(json::Buffer {
        byte_length: USize64::from(bin.len()),
        name: None,
        uri: None,
        extensions: None,
        extras: Default::default(),
    });
    let n = positions.len();
    let mut view = |offset: usize, length: usize, target: json::buffer::Target| {
        root.push(json::buffer::View {
            buffer,
            byte_length: USize64::from(length),
            byte_offset: Some(USize64::from(offset)),
            byte_stride: None,
            name: None,
            target: Some(Checked::Valid(target)),
            extensions: None,
            extras: Default::default(),
        })
    };
    use json::buffer::Target::{ArrayBuffer, ElementArrayBuffer};
    let views = [
        view(0, 12 * n, ArrayBuffer),
        view(12 * n, 12 * n, ArrayBuffer),
        view(24 * n, 4 * indices.len(), ElementArrayBuffer),
    ];
    let mut accessor =
        |view: Index<json::buffer::View>, count: usize, component, ty, bounds: Option<([f32; 3], [f32; 3])>| {
            root.push(json::Accessor {
                buffer_view: Some(view),
                byte_offset: None,
                count: USize64::from(count),
                component_type: Checked::Valid(GenericComponentType(component)),
                extensions: None,
                extras: Default::default(),
                type_: Checked::Valid(ty),
                min: bounds.map(|(lo, _)| json::Value::from(lo.to_vec())),
                max: bounds.map(|(_, hi)| json::Value::from(hi.to_vec())),
                name: None,
                normalized: false,
                sparse: None,
            })
        };
    let position_accessor = accessor(views[0], n, ComponentType::F32, Type::Vec3, Some((lo, hi)));
    let normal_accessor = accessor(views[1], n, ComponentType::F32, Type::Vec3, None);
    let index_accessor = accessor(views[2], indices.len(), ComponentType::U32, Type::Scalar, None);
    let primitive = json::mesh::Primitive {
        attributes: BTreeMap::from([
            (Checked::Valid(Semantic::Positions), position_accessor),
            (Checked::Valid(Semantic::Normals), normal_accessor),
        ]),
        extensions: None,
        extras: Default::default(),
        indices: Some(index_accessor),
        material: None,
        mode: Checked::Valid(Mode::Triangles),
        targets: None,
    };
    let mesh_index = root.push(json::Mesh {
        extensions: None,
        extras: Default::default(),
        name: Some("surface".into()),
        primitives: vec![primitive],
        weights: None,
    });
    let node = root.push(json::Node { mesh: Some(mesh_index), ..Default::default() });
    let scene = root.push(json::Scene { extensions: None, extras: Default::default(), name: None, nodes: vec![node] });
    root.scene = Some(scene);

    let json = json::serialize::to_vec(&root).map_err(|e| Error::Input(format!("cannot encode the glTF JSON: {e}")))?;
    let glb = ::gltf::binary::Glb {
        header: ::gltf::binary::Header { magic: *b"glTF", version: 2, length: 0 }, // the writer fills in the length
        json: Cow::Owned(json),
        bin: Some(Cow::Owned(bin)),
    };
    glb.to_vec().map_err(|e| Error::Input(format!("cannot encode the binary glTF: {e}")))
}

/// Writes the mesh as a binary glTF (`.glb`) file, atomically, keeping its vertex order.
/// Positions are rounded to f32: vertices closer than that precision become one position, and
/// importing the file again welds them.
pub fn export_glb(mesh: &PolyMesh, path: &Path) -> Result<()> {
    let bytes = glb_bytes(mesh).map_err(|e| Error::format(path, e.to_string()))?;
    super::write_atomic(path, &bytes)
}

#[cfg(test)]
mod tests {
    use super::super::gltf::parse_gltf;
    use super::*;
    use serde_json::Value;

    #[test]
    fn glb_export_follows_the_spec_layout_and_reads_back() {
        let p = vec![
            DVec3::new(0.1, 0.2, 0.3),
            DVec3::new(1.0 / 3.0, 0.0, 0.0),
            DVec3::Y,
            DVec3::new(0.0, 0.0, 1.0),
            DVec3::splat(7.0),
        ];
        let mesh =
            PolyMesh::from_polygons(p.clone(), &[vec![0, 2, 1], vec![0, 1, 3], vec![1, 2, 3], vec![0, 3, 2]]).unwrap();
        let bytes = glb_bytes(&mesh).unwrap();
        let word = |k: usize| u32::from_le_bytes(bytes[k..k + 4].try_into().unwrap()) as usize;
        assert_eq!(&bytes[..4], b"glTF");
        assert_eq!((word(4), word(8)), (2, bytes.len()));
        let json_length = word(12);
        assert_eq!((&bytes[16..20], json_length % 4), (&b"JSON"[..], 0));
        assert_eq!(&bytes[24 + json_length..28 + json_length], b"BIN\0");
        let doc: Value = serde_json::from_slice(&bytes[20..20 + json_length]).unwrap();
        let position_accessor =
            &doc["accessors"][doc["meshes"][0]["primitives"][0]["attributes"]["POSITION"].as_u64().unwrap() as usize];
        let as_f32 = |v: &DVec3| v.as_vec3();
        let lo = p.iter().map(as_f32).fold(glam::Vec3::INFINITY, glam::Vec3::min);
        let hi = p.iter().map(as_f32).fold(glam::Vec3::NEG_INFINITY, glam::Vec3::max);
        let read = |v: &Value| {
            glam::Vec3::from_slice(
                &v.as_array().unwrap().iter().map(|c| c.as_f64().unwrap() as f32).collect::<Vec<_>>(),
            )
        };
        assert_eq!((read(&position_accessor["min"]), read(&position_accessor["max"])), (lo, hi));

        let soup = parse_gltf(&bytes, Path::new("test.glb"), true).unwrap();
        let expected: Vec<DVec3> = p.iter().map(|v| as_f32(v).as_dvec3()).collect();
        assert_eq!(soup.positions, expected);
        let triangles: Vec<Vec<u32>> = mesh.triangles().iter().map(|t| t.to_vec()).collect();
        assert_eq!(soup.faces, triangles);
    }
}
