//! glTF 2.0 export: a surface as a binary `.glb`.
//!
//! Follows the spec's GLB layout: positions and normals as f32, indices as u32 from the fan
//! triangulation of each polygon, with the `min`/`max` bounds the spec requires on positions.
//! glTF is Y up (spec §3.4): Taut's Z-up coordinates are turned on the way out, so the file
//! stands upright in Blender and every other viewer. The generator string names Taut's version.
//! Weak spot: f32 storage rounds positions (vertices closer than that precision become one
//! position, and importing the file again welds them).

use super::UpAxis;
use crate::mesh::PolyMesh;
use crate::{DVec3, Error, Result};
use ::gltf::json::accessor::{ComponentType, GenericComponentType, Type};
use ::gltf::json::mesh::{Mode, Semantic};
use ::gltf::json::validation::{Checked, USize64};
use ::gltf::json::{self, Index};
use std::collections::BTreeMap;
use std::path::Path;

/// The mesh as GLB bytes: one node, one mesh, one triangle primitive; vertex *i* of the file is
/// vertex *i* of the mesh.
pub fn glb_bytes(mesh: &PolyMesh, normals: Option<&[DVec3]>) -> Result<Vec<u8>> {
    if mesh.face_count() == 0 {
        return Err(Error::Input("the mesh has no faces; there is nothing to export".into()));
    }
    let up = UpAxis::Y;
    let positions: Vec<[f32; 3]> = mesh.positions().iter().map(|&p| up.from_taut(p).as_vec3().to_array()).collect();
    if let Some(v) = positions.iter().position(|p| !p.iter().all(|c| c.is_finite())) {
        return Err(Error::Input(format!(
            "vertex {v} at {:?} is beyond the range of the 32-bit floats glTF stores",
            mesh.positions()[v].to_array()
        )));
    }
    // The spec wants unit normals; isolated or degenerate vertices get +Z.
    let computed;
    let given = match normals {
        Some(n) if n.len() == mesh.vertex_count() => n,
        _ => {
            computed = mesh.vertex_normals();
            &computed
        }
    };
    let normals: Vec<[f32; 3]> = given
        .iter()
        .map(|&n| {
            let n = up.from_taut(n).normalize_or_zero().as_vec3();
            if n == glam::Vec3::ZERO || !n.is_finite() { [0.0, 1.0, 0.0] } else { n.to_array() }
        })
        .collect();
    let triangles = mesh.triangles();
    let bin_len = 24 * positions.len() + 12 * triangles.len();
    if bin_len > (u32::MAX as usize) - (1 << 20) {
        return Err(Error::Input("the mesh is too large for a binary glTF file (4 GiB)".into()));
    }

    let (lo, hi) = positions.iter().fold(([f32::INFINITY; 3], [f32::NEG_INFINITY; 3]), |(lo, hi), p| {
        (std::array::from_fn(|k| lo[k].min(p[k])), std::array::from_fn(|k| hi[k].max(p[k])))
    });
    let mut root = json::Root {
        asset: json::Asset { generator: Some(format!("Taut {}", env!("CARGO_PKG_VERSION"))), ..Default::default() },
        ..Default::default()
    };
    let buffer = root.push(json::Buffer {
        byte_length: USize64::from(bin_len),
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
        view(24 * n, 12 * triangles.len(), ElementArrayBuffer),
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
    let index_accessor = accessor(views[2], 3 * triangles.len(), ComponentType::U32, Type::Scalar, None);
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
    // The container (spec §4.4): a 12-byte header, then the JSON chunk padded with spaces and the
    // BIN chunk padded with zeros to 4 bytes, each behind its length and type. Written in one
    // buffer of its final size, the arrays copied in as they lie in memory (little-endian).
    let (json_padded, bin_padded) = (json.len().next_multiple_of(4), bin_len.next_multiple_of(4));
    let total = 12 + 8 + json_padded + 8 + bin_padded;
    let mut glb = Vec::with_capacity(total);
    glb.extend_from_slice(b"glTF");
    glb.extend_from_slice(&2u32.to_le_bytes());
    glb.extend_from_slice(&(total as u32).to_le_bytes());
    glb.extend_from_slice(&(json_padded as u32).to_le_bytes());
    glb.extend_from_slice(b"JSON");
    glb.extend_from_slice(&json);
    glb.resize(20 + json_padded, b' ');
    glb.extend_from_slice(&(bin_padded as u32).to_le_bytes());
    glb.extend_from_slice(b"BIN\0");
    extend_le(&mut glb, bytemuck::cast_slice::<[f32; 3], f32>(&positions));
    extend_le(&mut glb, bytemuck::cast_slice::<[f32; 3], f32>(&normals));
    extend_le(&mut glb, bytemuck::cast_slice::<[u32; 3], u32>(&triangles));
    glb.resize(total, 0);
    Ok(glb)
}

/// Appends 4-byte numbers in little-endian order: a plain copy on little-endian machines.
fn extend_le<T: bytemuck::Pod + LittleEndian>(out: &mut Vec<u8>, values: &[T]) {
    if cfg!(target_endian = "little") {
        out.extend_from_slice(bytemuck::cast_slice(values));
    } else {
        values.iter().for_each(|v| out.extend_from_slice(&v.le_bytes()));
    }
}

/// A 4-byte number's little-endian bytes.
trait LittleEndian {
    fn le_bytes(&self) -> [u8; 4];
}

impl LittleEndian for f32 {
    fn le_bytes(&self) -> [u8; 4] {
        self.to_le_bytes()
    }
}

impl LittleEndian for u32 {
    fn le_bytes(&self) -> [u8; 4] {
        self.to_le_bytes()
    }
}

/// Writes the mesh as a binary glTF (`.glb`) file, atomically, keeping its vertex order.
/// Positions are rounded to f32: vertices closer than that precision become one position, and
/// importing the file again welds them.
pub fn export_glb(mesh: &PolyMesh, path: &Path) -> Result<()> {
    export_glb_with(mesh, path, None)
}

/// [`export_glb`] with given unit normals (exact limit normals) instead of area-weighted ones.
pub fn export_glb_with(mesh: &PolyMesh, path: &Path, normals: Option<&[DVec3]>) -> Result<()> {
    let bytes = glb_bytes(mesh, normals).map_err(|e| Error::format(path, e.to_string()))?;
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
        let bytes = glb_bytes(&mesh, None).unwrap();
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
        // glTF is Y up: Taut's (x, y, z) is written as (x, z, −y).
        let in_file = |v: &DVec3| glam::Vec3::new(v.x as f32, v.z as f32, -v.y as f32);
        let lo = p.iter().map(in_file).fold(glam::Vec3::INFINITY, glam::Vec3::min);
        let hi = p.iter().map(in_file).fold(glam::Vec3::NEG_INFINITY, glam::Vec3::max);
        assert_eq!(hi.y, 7.0, "the highest point in Taut (z = 7) is the highest in the file (y)");
        let generator = doc["asset"]["generator"].as_str().unwrap();
        assert_eq!(generator, format!("Taut {}", env!("CARGO_PKG_VERSION")));
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
        assert_eq!(soup.faces.to_vecs(), triangles);
    }
}
