//! Files in and out of Taut: OBJ and glTF round trips, node hierarchies, welding of split
//! vertices, numbering, `.taut` documents, and a clear error (never a panic) for every kind of
//! bad file. Every test writes into its own temporary folder.

use glam::DVec3;
use serde_json::json;
use std::path::{Path, PathBuf};
use taut_core::io::{
    ImportOptions, MeshFormat, UpAxis, export_glb, export_mesh, export_obj, import_mesh, import_mesh_with,
};
use taut_core::nusd::Spacing;
use taut_core::{Document, PolyMesh, VertexId};
use taut_tests::files::{
    PlyKind, TempDir, ascii_stl_text, awkward_prism, binary_stl, bits, ply_bytes, refused, signed_volume,
};
use taut_tests::{cube, prism};

#[test]
fn obj_round_trip_is_exact_and_keeps_quads_and_ngons() {
    let dir = TempDir::new("obj-round-trip");
    let mesh = awkward_prism();
    let path = dir.path("prism.obj");
    export_obj(&mesh, &path).unwrap();
    let (back, report) = import_mesh(&path).unwrap();
    assert_eq!(bits(back.positions()), bits(mesh.positions()));
    assert_eq!(back.polygons(), mesh.polygons());
    assert!(back.polygons().iter().any(|f| f.len() == 7) && back.polygons().iter().any(|f| f.len() == 4));
    assert!(report.is_clean(), "{report}: {:?}", report.warnings);
    // The dispatch writes the same file, and upper-case extensions are recognised.
    let upper = dir.path("PRISM.OBJ");
    export_mesh(&mesh, &upper).unwrap();
    assert_eq!(std::fs::read(&upper).unwrap(), std::fs::read(&path).unwrap());
}

#[test]
fn glb_round_trip_keeps_f32_positions_and_triangles() {
    let dir = TempDir::new("glb-round-trip");
    let mesh = awkward_prism();
    let path = dir.path("prism.glb");
    export_mesh(&mesh, &path).unwrap();
    let (back, _) = import_mesh(&path).unwrap();
    assert_eq!(back.vertex_count(), mesh.vertex_count());
    for (a, b) in back.positions().iter().zip(mesh.positions()) {
        assert_eq!(*a, b.as_vec3().as_dvec3());
        assert!((*a - *b).length() <= b.length() * f64::from(f32::EPSILON));
    }
    let triangles: Vec<Vec<u32>> = mesh.triangles().iter().map(|t| t.to_vec()).collect();
    assert_eq!(back.polygons(), triangles);
    assert!(back.is_closed());
    export_glb(&back, &dir.path("again.glb")).unwrap();
}

/// The unit cube `[0, 1]³` as indexed triangles, outward.
fn cube_triangles() -> (Vec<[f32; 3]>, Vec<u32>) {
    let corners = (0..8).map(|i| [(i & 1) as f32, ((i >> 1) & 1) as f32, ((i >> 2) & 1) as f32]).collect();
    let quads = [[0, 2, 3, 1], [4, 5, 7, 6], [0, 1, 5, 4], [2, 6, 7, 3], [0, 4, 6, 2], [1, 3, 7, 5]];
    let indices = quads.iter().flat_map(|q| [q[0], q[1], q[2], q[0], q[2], q[3]]).collect();
    (corners, indices)
}

#[test]
fn gltf_node_hierarchy_is_placed_and_mirrors_stay_outward() {
    let dir = TempDir::new("gltf-hierarchy");
    let (corners, indices) = cube_triangles();
    let mut bin: Vec<u8> = corners.iter().flatten().flat_map(|c| c.to_le_bytes()).collect();
    bin.extend(indices.iter().flat_map(|&i| (i as u16).to_le_bytes()));
    dir.file("cube data.bin", &bin);
    let s = std::f64::consts::FRAC_1_SQRT_2;
    let gltf = json!({
        "asset": { "version": "2.0", "generator": "hand" },
        "scene": 0,
        "scenes": [{ "nodes": [0, 2] }],
        "nodes": [
            { "name": "parent", "translation": [10, 0, 0], "children": [1] },
            { "name": "child", "rotation": [0, 0, s, s], "scale": [2, 2, 2], "mesh": 0 },
            { "name": "mirror", "translation": [-10, 0, 0], "scale": [-1, 1, 1], "mesh": 0 }
        ],
        "meshes": [{ "name": "cube", "primitives": [{ "attributes": { "POSITION": 0 }, "indices": 1 }] }],
        "accessors": [
            { "bufferView": 0, "componentType": 5126, "count": 8, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 1] },
            { "bufferView": 1, "componentType": 5123, "count": 36, "type": "SCALAR" }
        ],
        "bufferViews": [
            { "buffer": 0, "byteLength": 96 },
            { "buffer": 0, "byteOffset": 96, "byteLength": 72 }
        ],
        "buffers": [{ "byteLength": bin.len(), "uri": "cube%20data.bin" }]
    });
    let path = dir.file("scene.gltf", serde_json::to_vec_pretty(&gltf).unwrap());
    let (mesh, report) = import_mesh(&path).unwrap();
    assert!(report.is_clean(), "{report}: {:?}", report.warnings);
    assert_eq!((mesh.vertex_count(), mesh.face_count()), (16, 24));
    // By hand, in the file's Y-up axes: the child doubles, turns 90° about z ((x, y) -> (-y, x))
    // and moves by (10, 0, 0); the mirror negates x and moves by (-10, 0, 0).
    let in_file: Vec<DVec3> = mesh.positions().iter().map(|&p| UpAxis::Y.from_taut(p)).collect();
    for (k, c) in corners.iter().enumerate() {
        let [x, y, z] = c.map(f64::from);
        let child = DVec3::new(10.0 - 2.0 * y, 2.0 * x, 2.0 * z);
        let mirror = DVec3::new(-10.0 - x, y, z);
        assert!((in_file[k] - child).length() < 1e-12, "child corner {k}");
        assert!((in_file[8 + k] - mirror).length() < 1e-12, "mirrored corner {k}");
    }
    // Volumes 8 and 1, both positive: a mirror that kept its winding would count -1.
    assert!((signed_volume(&mesh) - 9.0).abs() < 1e-9, "{}", signed_volume(&mesh));
    assert!(mesh.is_closed());
}

#[test]
fn a_cube_with_split_vertices_is_welded() {
    let dir = TempDir::new("weld");
    // Each face on its own four vertices with its own normal, as exporters write hard edges;
    // one corner is written as -0.
    let corner = |i: u32| [(i & 1) as f64, ((i >> 1) & 1) as f64, ((i >> 2) & 1) as f64];
    let quads = [[0, 2, 3, 1], [4, 5, 7, 6], [0, 1, 5, 4], [2, 6, 7, 3], [0, 4, 6, 2], [1, 3, 7, 5]];
    let mut text = String::from("# split cube\nvn 0 0 1\n");
    for (f, q) in quads.iter().enumerate() {
        for &i in q {
            let [x, y, z] = corner(i);
            let x = if f == 5 && x == 0.0 { "-0".to_string() } else { x.to_string() };
            text += &format!("v {x} {y} {z}\n");
        }
    }
    for f in 0..6 {
        text += &format!("f {}//1 {}//1 {}//1 {}//1\n", 4 * f + 1, 4 * f + 2, 4 * f + 3, 4 * f + 4);
    }
    let path = dir.file("split.obj", text);
    let (mesh, report) = import_mesh(&path).unwrap();
    assert_eq!(report.welded, 16);
    assert_eq!(mesh.vertex_count(), 8);
    assert!(mesh.is_closed());
    assert_eq!(mesh.euler_characteristic(), 2);
    assert!((signed_volume(&mesh) - 1.0).abs() < 1e-12);
    assert!(report.to_string().contains("welded 16 vertices"), "{report}");
    // First appearances keep their order: the first face's corners are vertices 0..4.
    assert_eq!(mesh.polygons()[0], vec![0, 1, 2, 3]);
}

#[test]
fn shared_obj_vertices_keep_the_file_numbering() {
    let dir = TempDir::new("numbering");
    // The cube's corners in a scrambled order; faces name them out of order and with negative
    // (relative) indices; vertex 9 is used by no face and is kept.
    let order = [5, 2, 7, 0, 3, 6, 1, 4];
    let unit = cube();
    let mut text = String::from("o scrambled\n");
    for &i in &order {
        let p = unit.positions()[i];
        text += &format!("v {} {} {}\n", p.x, p.y, p.z);
    }
    text += "v 9 9 9\n";
    let file_index = |i: u32| order.iter().position(|&o| o == i as usize).unwrap() as u32;
    let expected: Vec<Vec<u32>> = unit.polygons().iter().map(|f| f.iter().map(|&i| file_index(i)).collect()).collect();
    for (k, face) in expected.iter().enumerate() {
        let corners: Vec<String> =
            face.iter().map(|&v| if k % 2 == 0 { (v + 1).to_string() } else { format!("{}", v as i64 - 9) }).collect();
        text += &format!("{}f {}\n", if k == 3 { "g second\n" } else { "" }, corners.join(" "));
    }
    // Written in Taut's own axes: read as a Z-up file.
    let path = dir.file("scrambled.obj", &text);
    let (mesh, report) = import_mesh_with(&path, &ImportOptions { obj_up: UpAxis::Z }).unwrap();
    assert!(report.is_clean(), "{report}");
    assert_eq!(mesh.vertex_count(), 9);
    assert!(mesh.is_isolated(VertexId(8)));
    for (k, &i) in order.iter().enumerate() {
        assert_eq!(mesh.positions()[k], unit.positions()[i]);
    }
    assert_eq!(mesh.polygons(), expected);
}

#[test]
fn a_zero_length_edge_is_repaired_and_reported() {
    let dir = TempDir::new("repair");
    // Vertex 5 repeats vertex 2: the pentagon's edge 2-5 has zero length.
    let text = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 2 0 0\nv 1 1 0\nf 1 2 3 6 4\nf 2 5 3\n";
    let (mesh, report) = import_mesh(&dir.file("seam.obj", text)).unwrap();
    assert_eq!(mesh.polygons(), vec![vec![0, 1, 2, 3], vec![1, 4, 2]]);
    assert_eq!((report.welded, report.repaired_faces, report.dropped_faces), (1, 1, 0));
    assert!(report.warnings.iter().any(|w| w.contains("repaired face 0")), "{:?}", report.warnings);
}

#[test]
fn taut_documents_round_trip_exactly() {
    let dir = TempDir::new("taut");
    let mut doc = Document::new(awkward_prism());
    doc.set_fixed(VertexId(3), false).unwrap();
    doc.set_vertex_tension(VertexId(1), 0.1 + 0.2).unwrap();
    doc.set_edge_tension(VertexId(0), VertexId(1), std::f64::consts::E).unwrap();
    doc.settings.levels = 2;
    doc.settings.lambda = 0.55;
    doc.settings.tol = 1e-7;
    doc.settings.max_iterations = 777;
    doc.settings.spacing = Spacing::Centripetal;
    let path = dir.path("prism.taut");
    doc.save(&path).unwrap();
    let back = Document::load(&path).unwrap();
    assert_eq!(back, doc);
    assert_eq!(bits(back.cage.positions()), bits(doc.cage.positions()));
    assert_eq!(back.to_json(), doc.to_json());
    assert!(!back.fixed[3] && back.fixed[2]);
}

#[test]
fn bad_files_are_clear_errors_not_panics() {
    let dir = TempDir::new("bad");
    let junk: Vec<u8> = (0..4096u32).map(|i| (i.wrapping_mul(2654435761) >> 13) as u8).collect();
    let tri = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
    let cases: Vec<(&str, Vec<u8>, &str)> = vec![
        ("junk.obj", junk.clone(), "binary data"),
        ("junk.glb", junk.clone(), "does not start with the bytes 'glTF'"),
        ("junk.gltf", junk.clone(), "not a glTF 2.0 file"),
        ("empty.obj", vec![], "no faces"),
        ("points.obj", format!("{tri}p 1 2 3\n").into_bytes(), "no faces"),
        ("empty.glb", vec![], "the file is empty"),
        ("empty.gltf", vec![], "the file is empty"),
        ("other.gltf", br#"{"name": "not a scene", "items": [1, 2]}"#.to_vec(), "missing field `asset`"),
        ("nan.obj", format!("{tri}v nan 0 0\nf 1 2 3\n").into_bytes(), "line 4: vertex 3 has a non-finite coordinate"),
        ("inf.obj", format!("{tri}v 0 -inf 0\nf 1 2 3\n").into_bytes(), "non-finite"),
        ("range.obj", format!("{tri}f 1 2 4\n").into_bytes(), "line 4: face refers to vertex 4, but the file has 3"),
        ("negative.obj", format!("{tri}f 1 2 -4\n").into_bytes(), "vertex -4"),
        ("words.obj", format!("{tri}f one two three\n").into_bytes(), "cannot read face corner 'one'"),
        (
            "pinch.obj",
            format!("{tri}v 2 0 0\nv 0 2 0\nf 1 2 3 1 4 5\n").into_bytes(),
            "face 0 passes through vertex 0 twice",
        ),
        (
            "nonmanifold.obj",
            format!("{tri}v 0 0 1\nv 0 0 -1\nf 1 2 3\nf 2 1 4\nf 1 2 5\n").into_bytes(),
            "non-manifold edge",
        ),
        ("flipped.obj", format!("{tri}v 1 1 0\nf 1 2 3\nf 2 3 4\n").into_bytes(), "inconsistently"),
        (
            "cube.3ds",
            b"solid cube\nendsolid\n".to_vec(),
            "'.3ds' is not a mesh format Taut knows; use .obj, .gltf, .glb, .stl or .ply",
        ),
        ("empty.stl", vec![], "the file is empty"),
        ("solid.stl", b"solid cube\nendsolid\n".to_vec(), "no faces"),
        ("short.stl", b"hello".to_vec(), "not an STL file"),
        (
            "nan.stl",
            b"solid x\nfacet\nouter loop\nvertex 0 0 0\nvertex 1 0 nan\nvertex 0 1 0\nendloop\n".to_vec(),
            "non-finite",
        ),
        ("empty.ply", vec![], "does not start with the word 'ply'"),
        ("header.ply", b"ply\nformat ascii 1.0\nelement vertex 3\n".to_vec(), "no 'end_header'"),
        (
            "range.ply",
            b"ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n\
              element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n"
                .to_vec(),
            "face 0 refers to vertex 7, but there are only 3 vertices",
        ),
        ("no_extension", tri.as_bytes().to_vec(), "without an extension"),
    ];
    for (name, bytes, expected) in cases {
        refused(&dir.file(name, bytes), expected);
    }
    refused(&dir.path("missing.obj"), "missing.obj");

    // A valid GLB cut short, and a .gltf whose .bin is missing.
    let glb = dir.path("whole.glb");
    export_glb(&cube(), &glb).unwrap();
    let bytes = std::fs::read(&glb).unwrap();
    refused(&dir.file("cut.glb", &bytes[..bytes.len() / 2]), "truncated binary glTF");
    refused(&dir.file("header.glb", &bytes[..12]), "truncated");
    let gltf = json!({
        "asset": { "version": "2.0" },
        "meshes": [{ "primitives": [{ "attributes": { "POSITION": 0 } }] }],
        "accessors": [{ "bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0] }],
        "bufferViews": [{ "buffer": 0, "byteLength": 36 }],
        "buffers": [{ "byteLength": 36, "uri": "gone.bin" }]
    });
    let path = dir.file("lonely.gltf", serde_json::to_vec(&gltf).unwrap());
    refused(&path, "buffer 0 refers to 'gone.bin', which Taut will not read: it cannot be read");
    dir.file("gone.bin", [0u8; 20]);
    refused(
        &path,
        "buffer 0 refers to 'gone.bin', which cannot be read: the file has 20 bytes, fewer than the 36 declared",
    );
}

#[test]
fn export_refuses_what_it_cannot_write() {
    let dir = TempDir::new("export");
    let mesh = cube();
    for (name, expected) in [
        ("cube.gltf", "binary .glb only"),
        ("cube.ply", "exports .obj and .glb only"),
        ("cube.x3d", "'.x3d' is not a mesh format"),
    ] {
        let err = export_mesh(&mesh, &dir.path(name)).unwrap_err().to_string();
        assert!(err.contains(name) && err.contains(expected), "{err}");
        assert!(!dir.path(name).exists());
    }
    let err = export_obj(&mesh, &dir.path("no/such/folder/cube.obj")).unwrap_err().to_string();
    assert!(err.contains("cube.obj"), "{err}");
    assert_eq!(MeshFormat::from_path(Path::new("A.GlB")).unwrap(), MeshFormat::Glb);
}

/// What an import accepts is a valid cage: connectivity checked, finite coordinates, faces.
fn accepted_is_valid(result: taut_core::Result<(PolyMesh, taut_core::io::ImportReport)>) {
    if let Ok((mesh, report)) = result {
        mesh.validate().unwrap_or_else(|e| panic!("accepted an invalid mesh ({report}): {e}"));
        assert!(mesh.face_count() > 0 && mesh.positions().iter().all(|p| p.is_finite()), "{report}");
    }
}

#[test]
fn damaged_copies_of_good_files_never_panic_and_what_they_accept_is_valid() {
    let dir = TempDir::new("damaged");
    let glb = dir.path("good.glb");
    export_glb(&prism(5, 1.0, 1.0), &glb).unwrap();
    let obj = dir.path("good.obj");
    export_obj(&prism(5, 1.0, 1.0), &obj).unwrap();
    let (corners, indices) = cube_triangles();
    let mut bin: Vec<u8> = corners.iter().flatten().flat_map(|c| c.to_le_bytes()).collect();
    bin.extend(indices.iter().flat_map(|&i| (i as u8).to_le_bytes()));
    dir.file("cube.bin", &bin);
    let gltf = format!(
        r#"{{"asset":{{"version":"2.0"}},"scene":0,"scenes":[{{"nodes":[0]}}],"nodes":[{{"mesh":0,"scale":[1,2,3]}}],
        "meshes":[{{"primitives":[{{"attributes":{{"POSITION":0}},"indices":1}}]}}],
        "accessors":[{{"bufferView":0,"componentType":5126,"count":8,"type":"VEC3","min":[0,0,0],"max":[1,1,1]}},
                     {{"bufferView":1,"componentType":5121,"count":36,"type":"SCALAR"}}],
        "bufferViews":[{{"buffer":0,"byteLength":96}},{{"buffer":0,"byteOffset":96,"byteLength":36}}],
        "buffers":[{{"byteLength":{},"uri":"cube.bin"}}]}}"#,
        bin.len()
    );
    let gltf_path = dir.file("good.gltf", &gltf);
    import_mesh(&gltf_path).unwrap();

    let mut seed = 0x9E37_79B9_7F4A_7C15u64;
    let mut random = move |n: usize| {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        (seed % n as u64) as usize
    };
    let stl = dir.path("good.stl");
    std::fs::write(&stl, binary_stl(&prism(5, 1.0, 1.0))).unwrap();
    let ascii_stl = dir.path("good_ascii.stl");
    std::fs::write(&ascii_stl, ascii_stl_text(&prism(5, 1.0, 1.0))).unwrap();
    let ply_le = dir.path("good_le.ply");
    std::fs::write(&ply_le, ply_bytes(&prism(5, 1.0, 1.0), PlyKind::Little)).unwrap();
    let ply_ascii = dir.path("good_ascii.ply");
    std::fs::write(&ply_ascii, ply_bytes(&prism(5, 1.0, 1.0), PlyKind::Ascii)).unwrap();
    for good in [&glb, &obj, &gltf_path, &stl, &ascii_stl, &ply_le, &ply_ascii] {
        let bytes = std::fs::read(good).unwrap();
        let name = format!("damaged.{}", good.extension().unwrap().to_string_lossy());
        for cut in (0..bytes.len()).step_by(7) {
            accepted_is_valid(import_mesh(&dir.file(&name, &bytes[..cut])));
        }
        for _ in 0..400 {
            let mut damaged = bytes.clone();
            for _ in 0..1 + random(4) {
                let k = random(damaged.len());
                damaged[k] = match random(3) {
                    0 => random(256) as u8,
                    1 => b"0123456789-.e,:[]{}\"/ "[random(22)],
                    _ => damaged[k] ^ (1 << random(8)),
                };
            }
            accepted_is_valid(import_mesh(&dir.file(&name, &damaged)));
        }
    }
}

/// A one-triangle glTF whose buffer lives at `uri`, with extra top-level JSON merged in.
fn triangle_gltf(uri: &str, extra: serde_json::Value) -> Vec<u8> {
    let mut doc = json!({
        "asset": { "version": "2.0" },
        "meshes": [{ "primitives": [{ "attributes": { "POSITION": 0 } }] }],
        "accessors": [{ "bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0] }],
        "bufferViews": [{ "buffer": 0, "byteLength": 36 }],
        "buffers": [{ "byteLength": 36, "uri": uri }]
    });
    for (k, v) in extra.as_object().unwrap() {
        doc[k] = v.clone();
    }
    serde_json::to_vec(&doc).unwrap()
}

fn triangle_bytes() -> Vec<u8> {
    [[0.0f32, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]].iter().flatten().flat_map(|c| c.to_le_bytes()).collect()
}

#[test]
fn a_gltf_reads_nothing_outside_its_own_folder() {
    let outer = TempDir::new("sandbox");
    let secret = outer.file("secret.bin", [0x41u8; 64]);
    let model = outer.path("model");
    std::fs::create_dir_all(&model).unwrap();
    std::fs::write(model.join("good.bin"), triangle_bytes()).unwrap();
    let write = |name: &str, bytes: Vec<u8>| {
        let path = model.join(name);
        std::fs::write(&path, bytes).unwrap();
        path
    };
    // A relative URI inside the folder is read.
    import_mesh(&write("good.gltf", triangle_gltf("good.bin", json!({})))).unwrap();
    let absolute = secret.to_string_lossy().into_owned();
    let cases = [
        ("absolute.gltf", absolute.as_str(), "absolute path"),
        ("climb.gltf", "../secret.bin", "leads outside the glTF file's folder"),
        ("zero.gltf", "/dev/zero", "absolute path"),
    ];
    for (name, uri, expected) in cases {
        let path = write(name, triangle_gltf(uri, json!({})));
        refused(&path, expected);
        let message = import_mesh(&path).unwrap_err().to_string();
        assert!(!message.contains("1094795585") && !message.contains("AAAA"), "bytes of the file leak: {message}");
    }
    #[cfg(unix)]
    {
        std::os::unix::fs::symlink(&secret, model.join("link.bin")).unwrap();
        refused(&write("link.gltf", triangle_gltf("link.bin", json!({}))), "leads outside");
        std::os::unix::fs::symlink("/dev/zero", model.join("zero.bin")).unwrap();
        refused(&write("device.gltf", triangle_gltf("zero.bin", json!({}))), "leads outside");
        // A buffer file longer than declared is read only up to byteLength.
        let mut long = triangle_bytes();
        long.extend([0xFFu8; 1000]);
        std::fs::write(model.join("long.bin"), long).unwrap();
        import_mesh(&write("long.gltf", triangle_gltf("long.bin", json!({})))).unwrap();
    }
    // Images are never read, wherever they point.
    let images = json!({ "images": [{ "uri": "/dev/zero" }, { "uri": "../secret.bin" }] });
    import_mesh(&write("images.gltf", triangle_gltf("good.bin", images))).unwrap();
}

#[test]
fn inputs_that_are_not_regular_files_are_refused_before_reading() {
    let dir = TempDir::new("special");
    std::fs::create_dir_all(dir.path("folder.obj")).unwrap();
    refused(&dir.path("folder.obj"), "a folder, not a regular file");
    #[cfg(unix)]
    {
        std::os::unix::fs::symlink("/dev/zero", dir.path("zero.obj")).unwrap();
        refused(&dir.path("zero.obj"), "a device, not a regular file");
        let fifo = dir.path("pipe.glb");
        assert!(std::process::Command::new("mkfifo").arg(&fifo).status().unwrap().success());
        refused(&fifo, "a named pipe");
        let fifo = dir.path("pipe.taut");
        assert!(std::process::Command::new("mkfifo").arg(&fifo).status().unwrap().success());
        let err = Document::load(&fifo).unwrap_err().to_string();
        assert!(err.contains("named pipe"), "{err}");
    }
}

#[test]
fn required_extensions_and_broken_triangle_lists_are_refused_by_name() {
    let dir = TempDir::new("required");
    dir.file("t.bin", triangle_bytes());
    let required =
        json!({ "extensionsRequired": ["KHR_materials_variants"], "extensionsUsed": ["KHR_materials_variants"] });
    refused(
        &dir.file("variants.gltf", triangle_gltf("t.bin", required)),
        "requires the glTF extension KHR_materials_variants",
    );
    let mut bin = triangle_bytes();
    bin.extend([0u32, 1, 2, 0].iter().flat_map(|i| i.to_le_bytes()));
    dir.file("four.bin", &bin);
    let four = json!({
        "asset": { "version": "2.0" },
        "meshes": [{ "primitives": [{ "attributes": { "POSITION": 0 }, "indices": 1 }] }],
        "accessors": [
            { "bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0] },
            { "bufferView": 1, "componentType": 5125, "count": 4, "type": "SCALAR" }
        ],
        "bufferViews": [{ "buffer": 0, "byteLength": 36 }, { "buffer": 0, "byteOffset": 36, "byteLength": 16 }],
        "buffers": [{ "byteLength": 52, "uri": "four.bin" }]
    });
    refused(&dir.file("four.gltf", serde_json::to_vec(&four).unwrap()), "from 4 indices, which is not a multiple of 3");
}

/// The Blender fixtures: where they are, and Suzanne's bounding box in Blender's own (Z-up)
/// coordinates, which are Taut's.
fn blender_fixture(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("fixtures/blender").join(name)
}

#[test]
fn blender_files_open_upright_and_welded_where_they_should_be() {
    // Suzanne: ears ±1.367 along x, the face looking along −y (±0.852), ±0.984 tall along z.
    let monkey = (DVec3::new(-1.367188, -0.851562, -0.984375), DVec3::new(1.367188, 0.851562, 0.984375));
    for name in ["monkey.obj", "monkey_smooth.obj", "monkey.glb", "monkey_smooth.glb"] {
        let (mesh, report) = import_mesh(&blender_fixture(name)).unwrap_or_else(|e| panic!("{name}: {e}"));
        mesh.validate().unwrap();
        let (lo, hi) = mesh.bounding_box().unwrap();
        assert!((lo - monkey.0).length() < 1e-6 && (hi - monkey.1).length() < 1e-6, "{name} lies {lo} .. {hi}");
        // The eyes touch the head at two points and stay parts of their own.
        assert_eq!(report.kept_apart, 2, "{name}: {report}");
        assert_eq!(mesh.vertex_count(), 507, "{name}: {report}");
        // Suzanne looks along −y: the face, with most of the detail, is on that side.
        let front = mesh.positions().iter().filter(|p| p.y < 0.0).count();
        let back = mesh.positions().iter().filter(|p| p.y > 0.0).count();
        assert!(front > 2 * back, "{name}: {front} vertices in front, {back} behind");
    }
    for name in ["uv_sphere.obj", "uv_sphere_smooth.obj", "uv_sphere.glb", "uv_sphere_smooth.glb"] {
        let (mesh, report) = import_mesh(&blender_fixture(name)).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert!(mesh.is_closed(), "{name}: {report}");
        assert_eq!(mesh.euler_characteristic(), 2, "{name}");
        assert_eq!(report.kept_apart, 0);
        // Blender's UV sphere has its poles on its z axis.
        let top = mesh.positions().iter().max_by(|a, b| a.z.total_cmp(&b.z)).unwrap();
        assert!((*top - DVec3::Z).length() < 1e-6, "{name}: the top pole is at {top}");
    }
}

/// Taut's OBJ and GLB files read back in place, and OBJ is written Y up with smooth shading.
#[test]
fn written_files_are_y_up_and_read_back_in_place() {
    let dir = TempDir::new("axes");
    let mut tall = prism(5, 1.0, 3.0);
    for p in tall.positions_mut() {
        p.z += 10.0;
    }
    let obj = dir.path("tall.obj");
    export_obj(&tall, &obj).unwrap();
    let text = std::fs::read_to_string(&obj).unwrap();
    assert!(text.contains("\ns 1\n"), "OBJ output must ask for smooth shading");
    let first = text.lines().find(|l| l.starts_with("v ")).unwrap();
    let y: f64 = first.split_whitespace().nth(2).unwrap().parse().unwrap();
    assert_eq!(y, tall.positions()[0].z, "Taut's height is the file's y");
    let (back, _) = import_mesh(&obj).unwrap();
    assert_eq!(bits(back.positions()), bits(tall.positions()));
    let glb = dir.path("tall.glb");
    export_glb(&tall, &glb).unwrap();
    let (back, _) = import_mesh(&glb).unwrap();
    for (a, b) in back.positions().iter().zip(tall.positions()) {
        assert!((*a - *b).length() < 1e-5, "{a} vs {b}");
    }
}
