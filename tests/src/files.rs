//! Files for the file tests: a temporary folder per test, bit patterns of positions, the
//! enclosed volume, an awkward prism, and the check that an import is refused with a message
//! naming the file.

use crate::prism;
use std::path::{Path, PathBuf};
use taut_core::io::import_mesh;
use taut_core::{DVec3, PolyMesh};

/// A fresh folder for one test, removed when the test ends.
#[derive(Debug)]
pub struct TempDir(PathBuf);

impl TempDir {
    pub fn new(test: &str) -> Self {
        let dir = std::env::temp_dir().join(format!("taut-files-{}-{test}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        TempDir(dir)
    }

    pub fn file(&self, name: &str, contents: impl AsRef<[u8]>) -> PathBuf {
        let path = self.0.join(name);
        std::fs::write(&path, contents).unwrap();
        path
    }

    pub fn path(&self, name: &str) -> PathBuf {
        self.0.join(name)
    }
}

impl Drop for TempDir {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

/// The bit patterns of the coordinates, for comparisons that must be exact.
pub fn bits(points: &[DVec3]) -> Vec<[u64; 3]> {
    points.iter().map(|p| p.to_array().map(f64::to_bits)).collect()
}

/// Signed volume enclosed by a closed mesh (sum of fan tetrahedra): positive when every face
/// winds counter-clockwise seen from outside.
pub fn signed_volume(mesh: &PolyMesh) -> f64 {
    let p = mesh.positions();
    mesh.triangles().iter().map(|&[a, b, c]| p[a as usize].dot(p[b as usize].cross(p[c as usize])) / 6.0).sum()
}

/// A prism with awkward coordinates (thirds, tiny and huge values): quads and two 7-gons.
pub fn awkward_prism() -> PolyMesh {
    let mut mesh = prism(7, 1.0 / 3.0, 0.1);
    mesh.positions_mut()[0] += DVec3::new(1e-17, -0.0, 0.0);
    mesh.positions_mut()[8] *= 12345.678901234567;
    mesh
}

/// Imports `path` and checks the error names the file and says `expected`.
pub fn refused(path: &Path, expected: &str) {
    let name = path.file_name().unwrap().to_string_lossy();
    match import_mesh(path) {
        Ok((mesh, report)) => panic!("{name} was accepted: {} vertices, {report}", mesh.vertex_count()),
        Err(e) => {
            let message = e.to_string();
            assert!(message.contains(&*name), "the error does not name {name}: {message}");
            assert!(message.contains(expected), "expected '{expected}' for {name}: {message}");
        }
    }
}

/// Binary STL written here, independently of Taut's reader: one record per fan triangle.
pub fn binary_stl(mesh: &PolyMesh) -> Vec<u8> {
    let triangles = mesh.triangles();
    let mut bytes = b"solid binary files often start like this".to_vec();
    bytes.resize(80, 0);
    bytes.extend((triangles.len() as u32).to_le_bytes());
    for t in &triangles {
        bytes.extend([0u8; 12]);
        for &i in t {
            bytes.extend(mesh.positions()[i as usize].as_vec3().to_array().iter().flat_map(|c| c.to_le_bytes()));
        }
        bytes.extend([0u8; 2]);
    }
    bytes
}

/// ASCII STL with exact (shortest round-trip) coordinates.
pub fn ascii_stl_text(mesh: &PolyMesh) -> String {
    let mut text = String::from("solid test\n");
    for t in mesh.triangles() {
        text += "  facet normal 0 0 0\n    outer loop\n";
        for i in t {
            let p = mesh.positions()[i as usize];
            text += &format!("      vertex {:?} {:?} {:?}\n", p.x, p.y, p.z);
        }
        text += "    endloop\n  endfacet\n";
    }
    text + "endsolid test\n"
}

/// Which encoding [`ply_bytes`] writes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum PlyKind {
    Ascii,
    Little,
    Big,
}

/// PLY with the polygons as they are, an extra colour property and an extra element.
pub fn ply_bytes(mesh: &PolyMesh, kind: PlyKind) -> Vec<u8> {
    let format = match kind {
        PlyKind::Ascii => "ascii",
        PlyKind::Little => "binary_little_endian",
        PlyKind::Big => "binary_big_endian",
    };
    let position = if kind == PlyKind::Big { "float" } else { "double" };
    let mut bytes = format!(
        "ply\nformat {format} 1.0\ncomment written by the test\nelement vertex {}\nproperty {position} x\n\
         property uchar red\nproperty {position} y\nproperty {position} z\nelement face {}\n\
         property list uchar int vertex_indices\nelement extra 1\nproperty short value\nend_header\n",
        mesh.vertex_count(),
        mesh.face_count()
    )
    .into_bytes();
    let big = kind == PlyKind::Big;
    let put = |bytes: &mut Vec<u8>, v: f64| match kind {
        PlyKind::Ascii => bytes.extend(format!("{v:?} ").into_bytes()),
        PlyKind::Little => bytes.extend(v.to_le_bytes()),
        PlyKind::Big => bytes.extend((v as f32).to_be_bytes()),
    };
    for p in mesh.positions() {
        put(&mut bytes, p.x);
        if kind == PlyKind::Ascii {
            bytes.extend(b"200 ")
        } else {
            bytes.push(200)
        }
        put(&mut bytes, p.y);
        put(&mut bytes, p.z);
        if kind == PlyKind::Ascii {
            bytes.push(b'\n');
        }
    }
    for face in mesh.polygons() {
        if kind == PlyKind::Ascii {
            let list: Vec<String> = face.iter().map(|v| v.to_string()).collect();
            bytes.extend(format!("{} {}\n", face.len(), list.join(" ")).into_bytes());
        } else {
            bytes.push(face.len() as u8);
            for v in face {
                bytes.extend(if big { (v as i32).to_be_bytes() } else { (v as i32).to_le_bytes() });
            }
        }
    }
    match kind {
        PlyKind::Ascii => bytes.extend(b"-7\n"),
        PlyKind::Little => bytes.extend((-7i16).to_le_bytes()),
        PlyKind::Big => bytes.extend((-7i16).to_be_bytes()),
    }
    bytes
}
