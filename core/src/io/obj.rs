//! Wavefront OBJ: reading a cage's polygons and writing a surface with vertex normals.
//!
//! Faces are parsed by `tobj` (relative indices, `v/vt/vn` corners), polygons kept as they are,
//! every object and group of the file merged into one mesh. `tobj` renumbers vertices in order
//! of first use, which would lose the file's numbering (and drop unused vertices), so Taut reads
//! the `v` lines itself and hands `tobj` each vertex's file index in place of its coordinates:
//! the index comes back exactly and vertex *i* of the result is the *i*-th `v` line of the file.
//! Only `v` and `f` lines reach `tobj`, which also keeps it away from its panicking paths
//! (texture-coordinate and normal indices out of range, malformed material files).
//!
//! Writing uses Rust's shortest round-trip float formatting, so re-reading gives the same bits.
//! Weak spots: `\` line continuations, materials, texture coordinates and free-form geometry are
//! not read; points (`p`), lines (`l`) and faces with fewer than three corners are skipped with a
//! warning.

use super::weld::Soup;
use crate::mesh::PolyMesh;
use crate::{DVec3, Error, Result};
use std::fmt::Write as _;
use std::path::Path;

/// Reads an OBJ file into a polygon soup (not yet welded).
pub(crate) fn read_obj(path: &Path) -> Result<Soup> {
    let bytes = std::fs::read(path).map_err(|e| Error::io(path, e))?;
    if bytes.contains(&0) {
        return Err(Error::format(path, "not a text OBJ file: it contains binary data (NUL bytes)"));
    }
    // Lossy: names and comments in Latin-1 are harmless; geometry is ASCII anyway.
    parse_obj(&String::from_utf8_lossy(&bytes), path)
}

/// Parses OBJ text; `origin` names the source in messages.
pub(crate) fn parse_obj(text: &str, origin: &Path) -> Result<Soup> {
    let mut soup = Soup::default();
    let mut for_tobj = String::with_capacity(text.len() / 2);
    let mut face_lines: Vec<(usize, usize)> = Vec::new(); // (line number, vertices before it)
    let (mut short_faces, mut lines_and_points) = (0usize, 0usize);
    for (k, line) in text.lines().enumerate() {
        let line_no = k + 1;
        let mut words = line.split_whitespace();
        match words.next() {
            Some("v") => {
                let p = parse_vertex(words).map_err(|m| Error::format(origin, format!("line {line_no}: {m}")))?;
                if !p.is_finite() {
                    return Err(Error::format(
                        origin,
                        format!(
                            "line {line_no}: vertex {} has a non-finite coordinate ({:?}); every coordinate must be a finite number",
                            soup.positions.len(),
                            p.to_array()
                        ),
                    ));
                }
                let _ = writeln!(for_tobj, "v {} 0 0", soup.positions.len());
                soup.positions.push(p);
            }
            Some("f") if words.clone().count() < 3 => short_faces += 1,
            Some("f") => {
                face_lines.push((line_no, soup.positions.len()));
                for_tobj.push_str("f ");
                for corner in words {
                    for_tobj.push_str(corner);
                    for_tobj.push(' ');
                }
                for_tobj.push('\n');
            }
            Some("l" | "p") => lines_and_points += 1,
            _ => {}
        }
    }
    if short_faces > 0 {
        soup.warnings.push(format!("skipped {short_faces} faces with fewer than 3 corners"));
    }
    if lines_and_points > 0 {
        soup.warnings.push(format!("skipped {lines_and_points} point and line elements (p, l)"));
    }

    let options =
        tobj::LoadOptions { single_index: false, triangulate: false, ignore_points: true, ignore_lines: true };
    let no_materials = |_: &Path| Err(tobj::LoadError::GenericFailure);
    let (models, _) = tobj::load_obj_buf(&mut for_tobj.as_bytes(), &options, no_materials).map_err(|e| {
        let detail = explain_face_error(text, &face_lines, soup.positions.len())
            .unwrap_or_else(|| format!("could not read the faces ({e})"));
        Error::format(origin, detail)
    })?;

    let n = soup.positions.len();
    for model in &models {
        let mesh = &model.mesh;
        // tobj drops the arities when every face is a triangle.
        let arities: Vec<usize> = if mesh.face_arities.is_empty() {
            vec![3; mesh.indices.len() / 3]
        } else {
            mesh.face_arities.iter().map(|&a| a as usize).collect()
        };
        let mut corners = mesh.indices.iter();
        for arity in arities {
            let mut face = Vec::with_capacity(arity);
            for &i in corners.by_ref().take(arity) {
                // Each "position" tobj returns is the file index we handed it as x.
                let file_index = mesh.positions.get(3 * i as usize).copied().unwrap_or(f64::NAN);
                if !(file_index >= 0.0 && file_index < n as f64) {
                    return Err(Error::format(origin, "could not read the faces (inconsistent vertex indices)"));
                }
                face.push(file_index as u32);
            }
            soup.faces.push(face);
        }
    }
    Ok(soup)
}

/// Reads the coordinates of a `v` line: x y z, then either a homogeneous weight w or colour
/// values (ignored).
fn parse_vertex(mut words: std::str::SplitWhitespace<'_>) -> std::result::Result<DVec3, String> {
    let mut xyz = [0.0; 3];
    for (c, slot) in xyz.iter_mut().enumerate() {
        let word = words.next().ok_or_else(|| format!("a vertex needs 3 coordinates, found {c}"))?;
        *slot = word.parse::<f64>().map_err(|_| format!("cannot read vertex coordinate '{word}' as a number"))?;
    }
    let rest: Vec<&str> = words.collect();
    let mut p = DVec3::from_array(xyz);
    if let [w] = rest[..] {
        let w: f64 = w.parse().map_err(|_| format!("cannot read the vertex weight '{w}' as a number"))?;
        if w == 0.0 {
            return Err("the vertex weight w is 0 (a point at infinity)".to_string());
        }
        p /= w;
    }
    Ok(p)
}

/// Finds the face line `tobj` refused and says what is wrong with it, in the file's own terms.
fn explain_face_error(text: &str, face_lines: &[(usize, usize)], total: usize) -> Option<String> {
    let lines: Vec<&str> = text.lines().collect();
    for &(line_no, before) in face_lines {
        let line = lines.get(line_no - 1)?;
        for corner in line.split_whitespace().skip(1) {
            for (slot, part) in corner.split('/').enumerate() {
                if slot > 2 {
                    return Some(format!("line {line_no}: face corner '{corner}' has more than 3 parts (v/vt/vn)"));
                }
                if part.is_empty() && slot > 0 {
                    continue;
                }
                let Ok(index) = part.parse::<i64>() else {
                    return Some(format!(
                        "line {line_no}: cannot read face corner '{corner}' (expected v, v/vt, v//vn or v/vt/vn)"
                    ));
                };
                if slot > 0 {
                    continue;
                }
                let resolved = match index {
                    0 => {
                        return Some(format!(
                            "line {line_no}: face corner '{corner}' uses index 0; OBJ indices start at 1"
                        ));
                    }
                    i if i < 0 => before as i64 + i,
                    i => i - 1,
                };
                if resolved < 0 || resolved >= total as i64 {
                    return Some(format!(
                        "line {line_no}: face refers to vertex {index}, but the file has {} vertices{}",
                        if index < 0 { before } else { total },
                        if index < 0 { " before this line" } else { " (v lines, counted from 1)" }
                    ));
                }
            }
        }
    }
    None
}

/// The mesh as OBJ text: `v` positions, `vn` area-weighted vertex normals and `f v//vn`
/// polygons, vertex *i* of the mesh being vertex *i* + 1 of the file.
pub fn obj_text(mesh: &PolyMesh) -> String {
    let mut out = String::with_capacity(64 * mesh.vertex_count() + 32 * mesh.halfedge_count());
    let _ = writeln!(out, "# Taut surface: {} vertices, {} faces", mesh.vertex_count(), mesh.face_count());
    for p in mesh.positions() {
        // `{:?}` is Rust's shortest representation that reads back to the same f64.
        let _ = writeln!(out, "v {:?} {:?} {:?}", p.x, p.y, p.z);
    }
    for n in mesh.vertex_normals() {
        let _ = writeln!(out, "vn {:?} {:?} {:?}", n.x, n.y, n.z);
    }
    for f in mesh.faces() {
        out.push('f');
        for v in mesh.face_vertices(f) {
            let _ = write!(out, " {0}//{0}", v.0 + 1);
        }
        out.push('\n');
    }
    out
}

/// Writes the mesh as an OBJ file (atomically), keeping its vertex order.
pub fn export_obj(mesh: &PolyMesh, path: &Path) -> Result<()> {
    if mesh.face_count() == 0 {
        return Err(Error::Input(format!("{}: the mesh has no faces; there is nothing to export", path.display())));
    }
    super::write_atomic(path, obj_text(mesh).as_bytes())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(text: &str) -> Result<Soup> {
        parse_obj(text, Path::new("test.obj"))
    }

    #[test]
    fn file_numbering_survives_faces_that_use_vertices_out_of_order() {
        // Faces reference the vertices backwards, across two objects, with a relative index, a
        // v/vt/vn corner and an unused vertex 5.
        let text = "o a\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 2 2 2\nv 9 9 9\nvt 0 0\nvn 0 0 1\n\
                    f 4 3/1/1 2//1 1\ng b\nusemtl red\nf 5 -3 -2\n";
        let soup = parse(text).unwrap();
        assert_eq!(soup.positions.len(), 6);
        assert_eq!(soup.positions[4], DVec3::splat(2.0));
        assert_eq!(soup.faces, vec![vec![3, 2, 1, 0], vec![4, 3, 4]]);
        assert!(soup.warnings.is_empty());
    }

    #[test]
    fn homogeneous_weight_and_colours() {
        let soup = parse("v 2 4 6 2\nv 1 2 3 0.5 0.5 0.5\nv 0 0 1\nf 1 2 3\n").unwrap();
        assert_eq!(soup.positions, vec![DVec3::new(1.0, 2.0, 3.0), DVec3::new(1.0, 2.0, 3.0), DVec3::Z]);
    }

    #[test]
    fn lines_points_and_short_faces_are_skipped_with_a_warning() {
        let soup = parse("v 0 0 0\nv 1 0 0\nv 0 1 0\nl 1 2\np 1\nf 1 2\nf 1 2 3\n").unwrap();
        assert_eq!(soup.faces, vec![vec![0, 1, 2]]);
        assert_eq!(soup.warnings.len(), 2, "{:?}", soup.warnings);
    }

    #[test]
    fn bad_lines_are_named() {
        let cases = [
            ("v 0 0 0\nv 1 0\n", "line 2: a vertex needs 3 coordinates"),
            ("v 0 0 zero\n", "line 1: cannot read vertex coordinate 'zero'"),
            ("v 0 0 0\nv 1 0 NaN\n", "line 2: vertex 1 has a non-finite"),
            ("v 0 0 inf\n", "non-finite"),
            ("v 0 0 0 0\n", "weight w is 0"),
            (
                "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 2 4\n",
                "line 5: face refers to vertex 4, but the file has 3 vertices",
            ),
            ("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 0\n", "uses index 0"),
            ("v 0 0 0\nv 1 0 0\nf -3 1 2\nv 0 1 0\n", "vertex -3, but the file has 2 vertices before this line"),
            ("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 x\n", "line 4: cannot read face corner 'x'"),
            ("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3/1/1/1\n", "more than 3 parts"),
            ("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 99999999999999999999999\n", "line 4"),
        ];
        for (text, expected) in cases {
            let err = parse(text).unwrap_err().to_string();
            assert!(err.starts_with("test.obj: ") && err.contains(expected), "expected '{expected}' in: {err}");
        }
    }

    #[test]
    fn hostile_texture_and_normal_indices_do_not_panic() {
        // tobj would index its texture-coordinate array with these; we never give it one.
        let soup = parse("v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvn 0 0 1\nf 1/0/0 2/-99/99 3/9999999999/1\n").unwrap();
        assert_eq!(soup.faces, vec![vec![0, 1, 2]]);
    }

    #[test]
    fn export_text_is_one_based_with_exact_floats() {
        let p = vec![DVec3::new(0.1, 1.0 / 3.0, -0.0), DVec3::new(1e-300, 2.0, 0.0), DVec3::new(0.0, 1e300, 5.0)];
        let mesh = PolyMesh::from_polygons(p.clone(), &[[0, 1, 2]]).unwrap();
        let text = obj_text(&mesh);
        assert!(text.contains("\nf 1//1 2//2 3//3\n"), "{text}");
        let back = parse(&text).unwrap();
        let bits = |v: &[DVec3]| v.iter().map(|p| p.to_array().map(f64::to_bits)).collect::<Vec<_>>();
        assert_eq!(bits(&back.positions), bits(&p));
        assert_eq!(back.faces, vec![vec![0, 1, 2]]);
        // A lone triangle's vertex normal is its plane's normal: compare with the cross product.
        let expected = (p[1] - p[0]).cross(p[2] - p[0]).normalize();
        let vn: Vec<f64> = text.lines().find(|l| l.starts_with("vn ")).unwrap()[3..]
            .split_whitespace()
            .map(|w| w.parse().unwrap())
            .collect();
        assert!((DVec3::from_slice(&vn) - expected).length() < 1e-12);
    }
}
