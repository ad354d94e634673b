//! Tests of [`super`].

use super::*;
use crate::io::glb::glb_bytes;
use crate::mesh::PolyMesh;
use serde_json::{Value, json};

fn base64(bytes: &[u8]) -> String {
    const ALPHABET: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut out = String::new();
    for chunk in bytes.chunks(3) {
        let n = chunk.iter().enumerate().fold(0u32, |n, (k, &b)| n | u32::from(b) << (16 - 8 * k));
        for k in 0..4 {
            out.push(if k <= chunk.len() { ALPHABET[(n >> (18 - 6 * k) & 63) as usize] as char } else { '=' });
        }
    }
    out
}

/// A glTF with one mesh whose positions (and indices, if any) live in a data: URI.
fn document(positions: &[[f32; 3]], indices: Option<&[u32]>, mode: u32, nodes: Value, scenes: Value) -> Value {
    let mut bin: Vec<u8> = positions.iter().flatten().flat_map(|c| c.to_le_bytes()).collect();
    let position_bytes = bin.len();
    bin.extend(indices.unwrap_or(&[]).iter().flat_map(|i| i.to_le_bytes()));
    let mut primitive = json!({ "attributes": { "POSITION": 0 }, "mode": mode });
    let mut accessors = vec![json!({ "bufferView": 0, "componentType": 5126, "count": positions.len(), "type": "VEC3",
                                     "min": [-1e9, -1e9, -1e9], "max": [1e9, 1e9, 1e9] })];
    let mut views = vec![json!({ "buffer": 0, "byteLength": position_bytes })];
    if let Some(indices) = indices {
        primitive["indices"] = json!(1);
        accessors.push(json!({ "bufferView": 1, "componentType": 5125, "count": indices.len(), "type": "SCALAR" }));
        views.push(json!({ "buffer": 0, "byteOffset": position_bytes, "byteLength": 4 * indices.len() }));
    }
    json!({
        "asset": { "version": "2.0" },
        "buffers": [{ "byteLength": bin.len(), "uri": format!("data:application/octet-stream;base64,{}", base64(&bin)) }],
        "bufferViews": views, "accessors": accessors,
        "meshes": [{ "primitives": [primitive] }],
        "nodes": nodes, "scenes": scenes, "scene": 0
    })
}

fn parse(doc: &Value) -> Result<Soup> {
    parse_gltf(&serde_json::to_vec(doc).unwrap(), Path::new("test.gltf"), false)
}

const TRIANGLE: [[f32; 3]; 3] = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];

#[test]
fn node_transforms_accumulate_and_mirrors_keep_orientation() {
    let h = std::f32::consts::FRAC_1_SQRT_2;
    let nodes = json!([
        { "translation": [10, 0, 0], "children": [1] },
        { "rotation": [0, 0, h, h], "scale": [2, 2, 2], "mesh": 0 },
        { "scale": [-1, 1, 1], "mesh": 0 }
    ]);
    let soup = parse(&document(&TRIANGLE, None, 4, nodes, json!([{ "nodes": [0, 2] }]))).unwrap();
    // By hand: scale by 2, turn 90° about z ((x, y) -> (-y, x)), move 10 along x; and mirror x.
    let expected =
        [[10.0, 0.0, 0.0], [10.0, 2.0, 0.0], [8.0, 0.0, 0.0], [0.0, 0.0, 0.0], [-1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
    // The soup is in Taut's axes: glTF's (x, y, z) is Taut's (x, −z, y).
    let in_file: Vec<DVec3> = soup.positions.iter().map(|&p| UpAxis::Y.from_taut(p)).collect();
    for (p, e) in in_file.iter().zip(expected) {
        assert!((*p - DVec3::from_array(e)).length() < 1e-6, "{p} vs {e:?}");
    }
    assert!((soup.positions[1] - DVec3::new(10.0, 0.0, 2.0)).length() < 1e-6, "glTF +Y is Taut's up");
    assert_eq!(soup.faces.to_vecs(), vec![vec![0, 1, 2], vec![3, 5, 4]]);
    for face in soup.faces.iter() {
        let [a, b, c] = [0, 1, 2].map(|k| in_file[face[k] as usize]);
        assert!((b - a).cross(c - a).z > 0.0, "face {face:?} faces the wrong way");
    }
}

#[test]
fn matrices_scenes_and_meshes_without_nodes() {
    // A column-major matrix moving by (0, 0, 5); no default scene: every scene is read.
    let m = json!([1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 5, 1]);
    let mut doc =
        document(&TRIANGLE, Some(&[0, 1, 2]), 4, json!([{ "matrix": m, "mesh": 0 }]), json!([{ "nodes": [0] }]));
    doc.as_object_mut().unwrap().remove("scene");
    let soup = parse(&doc).unwrap();
    assert_eq!(soup.positions[1], DVec3::new(1.0, -5.0, 0.0));
    // No scenes at all: the mesh is read where it is.
    doc.as_object_mut().unwrap().remove("scenes");
    assert_eq!(parse(&doc).unwrap().positions[1], DVec3::X);
}

#[test]
fn strips_fans_and_skipped_primitives() {
    assert_eq!(triangles(Mode::TriangleStrip, &[0, 1, 2, 3, 4]), vec![[0, 1, 2], [1, 3, 2], [2, 3, 4]]);
    // A restart by one repeated vertex flips the parity of what follows (spec p_i formula).
    assert_eq!(triangles(Mode::TriangleStrip, &[0, 1, 2, 2, 3, 4]), vec![[0, 1, 2], [2, 4, 3]]);
    assert_eq!(triangles(Mode::TriangleFan, &[0, 1, 2, 3]), vec![[1, 2, 0], [2, 3, 0]]);
    let nodes = json!([{ "mesh": 0 }]);
    let soup = parse(&document(&TRIANGLE, None, 1, nodes, json!([{ "nodes": [0] }]))).unwrap();
    assert!(soup.faces.is_empty());
    assert!(soup.warnings[0].contains("skipped mesh 0 primitive 0"), "{:?}", soup.warnings);
}

#[test]
fn hostile_documents_are_errors_not_panics() {
    let scenes = json!([{ "nodes": [0] }]);
    let good = document(&TRIANGLE, Some(&[0, 1, 2]), 4, json!([{ "mesh": 0 }]), scenes.clone());
    let edit = |f: &dyn Fn(&mut Value)| {
        let mut d = good.clone();
        f(&mut d);
        d
    };
    let cases: Vec<(Value, &str)> = vec![
        (edit(&|d| d["meshes"][0]["primitives"][0]["attributes"]["POSITION"] = json!(7)), "accessor 7 does not exist"),
        (edit(&|d| d["accessors"][0]["count"] = json!(4)), "runs past the end of buffer view 0"),
        (edit(&|d| d["accessors"][0]["count"] = json!(u64::MAX)), "runs past the end"),
        (edit(&|d| d["accessors"][1]["count"] = json!(0)), ""),
        (edit(&|d| d["bufferViews"][0]["byteOffset"] = json!(1u64 << 62)), "runs past the end of buffer 0"),
        (edit(&|d| d["accessors"][0]["type"] = json!("VEC2")), "expected Vec3"),
        (edit(&|d| d["accessors"][0]["componentType"] = json!(5123)), "float positions only"),
        (
            edit(&|d| {
                d["accessors"][0]["sparse"] = json!({"count": 1, "indices": {"bufferView": 0, "componentType": 5125}, "values": {"bufferView": 0}})
            }),
            "sparse",
        ),
        (edit(&|d| d["meshes"][0]["primitives"][0]["mode"] = json!(9)), ""),
        (edit(&|d| d["nodes"] = json!([{ "mesh": 0, "children": [0] }])), "appears twice"),
        (edit(&|d| d["nodes"] = json!([{ "mesh": 3 }])), "mesh 3, which does not exist"),
        (edit(&|d| d["scenes"] = json!([{ "nodes": [4] }])), "node 4, which does not exist"),
        (edit(&|d| d["scene"] = json!(2)), "default scene 2 does not exist"),
        (edit(&|d| d["nodes"][0]["rotation"] = json!([0, 0, 0, 0])), "cannot be normalised"),
        (edit(&|d| d["buffers"][0]["uri"] = json!("%FF%FE.bin")), "not a valid percent-encoded path"),
        (
            edit(&|d| d["buffers"][0]["uri"] = json!("https://example.com/x.bin")),
            "relative file paths and data: URIs only",
        ),
        (edit(&|d| d["buffers"][0]["uri"] = json!("data:application/octet-stream;base64,@@@")), "cannot decode"),
        (edit(&|d| d["buffers"][0]["byteLength"] = json!(4096)), "truncated?"),
        (edit(&|d| d["asset"]["version"] = json!("1.0")), "glTF version 1.0 is not supported"),
        (
            edit(&|d| d["extensionsRequired"] = json!(["KHR_draco_mesh_compression"])),
            "requires the glTF extension KHR_draco_mesh_compression",
        ),
        (json!({ "hello": "world" }), "not a glTF 2.0 file: missing field `asset`"),
    ];
    for (doc, expected) in cases {
        match parse(&doc) {
            Err(e) => assert!(e.to_string().contains(expected), "expected '{expected}' in: {e}"),
            Ok(soup) => assert!(expected.is_empty() && soup.faces.is_empty(), "accepted {doc}"),
        }
    }
    let nan = [[0.0, 0.0, 0.0], [f32::NAN, 0.0, 0.0], [0.0, f32::INFINITY, 0.0]];
    let err = parse(&document(&nan, None, 4, json!([{ "mesh": 0 }]), scenes.clone())).unwrap_err().to_string();
    assert!(err.contains("mesh 0 primitive 0: vertex 1 has a non-finite coordinate"), "{err}");
    let index_out_of_range = document(&TRIANGLE, Some(&[0, 1, 3]), 4, json!([{ "mesh": 0 }]), scenes);
    assert!(
        parse(&index_out_of_range)
            .unwrap_err()
            .to_string()
            .contains("index 3 refers to a vertex beyond its 3 positions")
    );
}

#[test]
fn damaged_glb_files_are_errors_not_panics() {
    let mesh =
        PolyMesh::from_polygons(TRIANGLE.iter().map(|p| DVec3::from_array(p.map(f64::from))).collect(), &[[0, 1, 2]])
            .unwrap();
    let good = glb_bytes(&mesh, None).unwrap();
    let with_word = |k: usize, v: u32| {
        let mut b = good.clone();
        b[k..k + 4].copy_from_slice(&v.to_le_bytes());
        b
    };
    let cases: Vec<(Vec<u8>, &str)> = vec![
        (good[..good.len() - 8].to_vec(), "truncated binary glTF: the header announces"),
        (good[..10].to_vec(), "too short"),
        (with_word(8, 4), "total length of 4 bytes"),
        (with_word(4, 1), "version 1 is not supported"),
        (with_word(12, 1 << 30), "truncated binary glTF: a chunk is longer"),
        (with_word(16, 0x1234_5678), "invalid binary glTF"),
        (b"solid cube\nfacet normal 0 0 1\n".to_vec(), "does not start with the bytes 'glTF'"),
    ];
    for (bytes, expected) in cases {
        let err = parse_gltf(&bytes, Path::new("bad.glb"), true).unwrap_err().to_string();
        assert!(err.starts_with("bad.glb: ") && err.contains(expected), "expected '{expected}' in: {err}");
    }
}
