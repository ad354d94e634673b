//! A binary STL is welded straight from its `f32` corners (`io::weld_soup`), an ASCII STL through
//! the general weld of its soup: the same triangles must import the same either way, repairs,
//! warnings and all.

use std::fmt::Write as _;
use taut_core::io::import_triangles;

type Triangle = [[f32; 3]; 3];

fn binary(triangles: &[Triangle]) -> Vec<u8> {
    let mut bytes = vec![0u8; 80];
    bytes.extend((triangles.len() as u32).to_le_bytes());
    for t in triangles {
        bytes.extend([0u8; 12]);
        bytes.extend(t.iter().flatten().flat_map(|x| x.to_le_bytes()));
        bytes.extend([0u8; 2]);
    }
    bytes
}

fn ascii(triangles: &[Triangle]) -> String {
    let mut text = String::from("solid twin\n");
    for t in triangles {
        text.push_str(" facet normal 0 0 0\n  outer loop\n");
        for p in t {
            // Every coordinate here is a small dyadic number: exact in f32, f64 and decimal.
            writeln!(text, "   vertex {:?} {:?} {:?}", p[0], p[1], p[2]).unwrap();
        }
        text.push_str("  endloop\n endfacet\n");
    }
    text.push_str("endsolid twin\n");
    text
}

/// A closed grid of quads split in two, then every repair the weld makes.
fn soup() -> Vec<Triangle> {
    let n = 24u32;
    let at = |i: u32, j: u32| {
        let (a, b) = ((i % n) as f32, (j % n) as f32);
        [a * 0.5, b * 0.25, ((a * 7.0 + b * 3.0) % 5.0) * 0.125]
    };
    let mut out = Vec::new();
    for i in 0..n {
        for j in 0..n {
            out.push([at(i, j), at(i + 1, j), at(i + 1, j + 1)]);
            out.push([at(i, j), at(i + 1, j + 1), at(i, j + 1)]);
        }
    }
    for k in 0..6 {
        let p = [100.0 + k as f32, 0.0, 0.0];
        out.push([p, p, [100.0, 1.0, 0.0]]);
    }
    for f in [3usize, 40, 3, 100, 101] {
        let t = out[f];
        out.push(t);
        out.push([t[0], t[2], t[1]]);
    }
    let tet = |o: [f32; 3], s: f32| {
        let [a, b, c, d] = [o, [o[0] + s, o[1], o[2]], [o[0], o[1] + s, o[2]], [o[0], o[1], o[2] + s]];
        [[a, c, b], [a, b, d], [a, d, c], [b, c, d]]
    };
    out.extend(tet([-0.0, 50.0, 0.0], 1.0));
    out.extend(tet([0.0, 50.0, 0.0], -1.0));
    out
}

#[test]
fn a_binary_stl_imports_as_its_ascii_twin() {
    let dir = std::env::temp_dir().join(format!("taut-import-stl-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let triangles = soup();
    let (b, a) = (dir.join("twin_binary.stl"), dir.join("twin_ascii.stl"));
    std::fs::write(&b, binary(&triangles)).unwrap();
    std::fs::write(&a, ascii(&triangles)).unwrap();
    let from_binary = import_triangles(&b, &Default::default()).unwrap();
    let from_ascii = import_triangles(&a, &Default::default()).unwrap();
    let bits = |p: &[taut_core::DVec3]| p.iter().map(|q| q.to_array().map(f64::to_bits)).collect::<Vec<_>>();
    assert_eq!(bits(&from_binary.0), bits(&from_ascii.0));
    assert_eq!(from_binary.1, from_ascii.1);
    assert_eq!(from_binary.2, from_ascii.2);
    let report = &from_binary.2;
    assert_eq!((report.dropped_faces, report.duplicate_faces, report.kept_apart), (16, 10, 1), "{report}");
    // Every kept triangle is there once, on three distinct vertices.
    assert_eq!(from_binary.1.len(), triangles.len() - 16);
    assert!(from_binary.1.iter().all(|t| t[0] != t[1] && t[1] != t[2] && t[2] != t[0]));

    // Bytes after the declared triangles are ignored with a warning, listed first.
    let mut longer = binary(&triangles);
    longer.extend([7u8; 5]);
    std::fs::write(&b, longer).unwrap();
    let (_, _, report) = import_triangles(&b, &Default::default()).unwrap();
    assert!(report.warnings[0].starts_with("ignored 5 bytes after"), "{:?}", report.warnings);
    assert_eq!(report.warnings[1..], from_ascii.2.warnings[..]);

    // A non-finite corner names its triangle; nothing but degenerate triangles is no surface.
    let mut bad = triangles.clone();
    bad[7][2][1] = f32::NAN;
    std::fs::write(&b, binary(&bad)).unwrap();
    let e = import_triangles(&b, &Default::default()).unwrap_err().to_string();
    assert!(e.contains("triangle 7 has a non-finite corner"), "{e}");
    let p = [1.0f32, 2.0, 3.0];
    std::fs::write(&b, binary(&[[p, p, [0.0; 3]]])).unwrap();
    let e = import_triangles(&b, &Default::default()).unwrap_err().to_string();
    assert!(e.contains("no faces"), "{e}");
    std::fs::remove_dir_all(&dir).unwrap();
}
