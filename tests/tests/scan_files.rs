//! Scans come as STL and PLY: round trips of binary and ASCII STL and of ASCII and binary PLY
//! against files written here independently of Taut's readers, and their damaged forms refused
//! by name.

use taut_core::DVec3;
use taut_core::PolyMesh;
use taut_core::io::import_mesh;
use taut_tests::files::{
    PlyKind, TempDir, ascii_stl_text, awkward_prism, binary_stl, bits, ply_bytes, refused, signed_volume,
};

#[test]
fn stl_round_trips_binary_and_ascii() {
    let dir = TempDir::new("stl");
    let mesh = awkward_prism();
    let triangles = mesh.triangles();
    let as_corners = |m: &PolyMesh| -> Vec<[[u64; 3]; 3]> {
        m.triangles().iter().map(|t| t.map(|i| m.positions()[i as usize].to_array().map(f64::to_bits))).collect()
    };
    // ASCII: exact coordinates; welding restores the shared corners and the numbering.
    let (back, report) = import_mesh(&dir.file("prism.stl", ascii_stl_text(&mesh))).unwrap();
    assert_eq!(report.welded, 3 * triangles.len() - mesh.vertex_count());
    assert_eq!(as_corners(&back), as_corners(&PolyMesh::from_polygons(mesh.positions().to_vec(), &triangles).unwrap()));
    assert!(back.is_closed());
    assert!((signed_volume(&back) - signed_volume(&mesh)).abs() < 1e-12);
    // Binary: f32 corners, even though the header starts with "solid".
    let (back, _) = import_mesh(&dir.file("binary.stl", binary_stl(&mesh))).unwrap();
    assert_eq!(back.face_count(), triangles.len());
    for (a, t) in back.triangles().iter().zip(&triangles) {
        for k in 0..3 {
            assert_eq!(back.positions()[a[k] as usize], mesh.positions()[t[k] as usize].as_vec3().as_dvec3());
        }
    }
    // A binary file cut short, and one with trailing bytes (read, with a warning).
    let bytes = binary_stl(&mesh);
    refused(&dir.file("cut.stl", &bytes[..bytes.len() - 10]), "truncated binary STL");
    let mut longer = bytes.clone();
    longer.extend([0u8; 7]);
    let (_, report) = import_mesh(&dir.file("long.stl", &longer)).unwrap();
    assert!(report.warnings.iter().any(|w| w.contains("ignored 7 bytes")), "{:?}", report.warnings);
    // Not a regular file.
    std::fs::create_dir_all(dir.path("folder.stl")).unwrap();
    refused(&dir.path("folder.stl"), "a folder");
}

#[test]
fn ply_round_trips_ascii_and_both_byte_orders() {
    let dir = TempDir::new("ply");
    let mesh = awkward_prism();
    for (kind, name) in [(PlyKind::Ascii, "a.ply"), (PlyKind::Little, "le.ply"), (PlyKind::Big, "be.ply")] {
        let (back, report) = import_mesh(&dir.file(name, ply_bytes(&mesh, kind))).unwrap();
        assert!(report.is_clean(), "{name}: {report}");
        assert_eq!(back.polygons(), mesh.polygons(), "{name}");
        if kind == PlyKind::Big {
            let f32s: Vec<DVec3> = mesh.positions().iter().map(|p| p.as_vec3().as_dvec3()).collect();
            assert_eq!(bits(back.positions()), bits(&f32s));
        } else {
            assert_eq!(bits(back.positions()), bits(mesh.positions()), "{name}");
        }
    }
    let bytes = ply_bytes(&mesh, PlyKind::Little);
    refused(&dir.file("cut.ply", &bytes[..bytes.len() - 40]), "truncated PLY");
}
