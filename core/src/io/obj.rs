//! Wavefront OBJ: reading a cage's polygons and writing a surface with vertex normals.
//!
//! The reader keeps the file's numbering: vertex *i* of the result is the *i*-th `v` line, unused
//! vertices included. Faces take `v`, `v/vt`, `v//vn` and `v/vt/vn` corners with absolute or
//! relative (negative) indices; every object and group of the file goes into one mesh. It reads
//! the bytes in one pass without copying the text and stores faces flat, so memory stays a small
//! multiple of the file's size whatever the shape of its lines (a single face line of hundreds of
//! megabytes included).
//!
//! Axes: OBJ has no rule, but Blender, Maya and most tools write Y up by default, so Taut reads
//! and writes OBJ as Y up unless told otherwise ([`UpAxis`]), converting to its own Z up: a model
//! goes to Blender and back standing up, with its coordinates unchanged.
//!
//! Writing uses Rust's shortest round-trip float formatting, so re-reading gives the same bits,
//! and `s 1` so other tools shade the surface smoothly with the written normals.
//! Weak spots: `\` line continuations, materials, texture coordinates and free-form geometry are
//! not read; points (`p`), lines (`l`) and faces with fewer than three corners are skipped with a
//! warning.

use super::UpAxis;
use super::soup::Soup;
use crate::mesh::PolyMesh;
use crate::{DVec3, Error, Result};
use std::path::Path;

/// Reads an OBJ file into a polygon soup in Taut's axes (not yet welded).
pub(crate) fn read_obj(path: &Path, up: UpAxis) -> Result<Soup> {
    let bytes = super::file::read_regular_file(path)?;
    if bytes.contains(&0) {
        return Err(Error::format(path, "not a text OBJ file: it contains binary data (NUL bytes)"));
    }
    let mut soup = parse_obj(&bytes, path)?;
    drop(bytes);
    for p in &mut soup.positions {
        *p = up.to_taut(*p);
    }
    Ok(soup)
}

/// A face corner's vertex as written: 1-based, or negative and relative to the vertices before.
fn corner_vertex(corner: &[u8]) -> std::result::Result<i64, String> {
    let text = || String::from_utf8_lossy(corner).into_owned();
    let mut parts = corner.split(|&b| b == b'/');
    let v = parts.next().unwrap_or_default();
    let rest: Vec<&[u8]> = parts.collect();
    if rest.len() > 2 {
        return Err(format!("face corner '{}' has more than 3 parts (v/vt/vn)", text()));
    }
    for part in &rest {
        if !part.is_empty() && std::str::from_utf8(part).ok().and_then(|s| s.parse::<i64>().ok()).is_none() {
            return Err(format!("cannot read face corner '{}' (expected v, v/vt, v//vn or v/vt/vn)", text()));
        }
    }
    std::str::from_utf8(v)
        .ok()
        .and_then(|s| s.parse::<i64>().ok())
        .ok_or_else(|| format!("cannot read face corner '{}' (expected v, v/vt, v//vn or v/vt/vn)", text()))
}

/// Parses OBJ bytes in the file's own axes; `origin` names the source in messages.
pub(crate) fn parse_obj(bytes: &[u8], origin: &Path) -> Result<Soup> {
    let fail = |line: usize, m: String| Error::format(origin, format!("line {line}: {m}"));
    let mut soup = Soup::default();
    let (mut short_faces, mut lines_and_points) = (0usize, 0usize);
    // Absolute indices may refer to `v` lines further down: checked once the count is known.
    let mut largest_absolute: Option<(i64, usize)> = None;
    for (k, line) in bytes.split(|&b| b == b'\n').enumerate() {
        let line_no = k + 1;
        let mut words = line.split(|b| b.is_ascii_whitespace()).filter(|w| !w.is_empty());
        match words.next() {
            Some(b"v") => {
                let p = parse_vertex(words).map_err(|m| fail(line_no, m))?;
                if !p.is_finite() {
                    return Err(fail(
                        line_no,
                        format!(
                            "vertex {} has a non-finite coordinate ({:?}); every coordinate must be a finite number",
                            soup.positions.len(),
                            p.to_array()
                        ),
                    ));
                }
                soup.positions.push(p);
            }
            Some(b"f") => {
                // Corners go straight into the face list: no copy of a long face line.
                let mut count = 0usize;
                let before = soup.positions.len() as i64;
                for corner in words {
                    let index = corner_vertex(corner).map_err(|m| fail(line_no, m))?;
                    let resolved = match index {
                        0 => {
                            return Err(fail(
                                line_no,
                                format!(
                                    "face corner '{}' uses index 0; OBJ indices start at 1",
                                    String::from_utf8_lossy(corner)
                                ),
                            ));
                        }
                        i if i < 0 => {
                            let r = before + i;
                            if r < 0 {
                                return Err(fail(
                                    line_no,
                                    format!(
                                        "face refers to vertex {i}, but the file has {before} vertices before this line"
                                    ),
                                ));
                            }
                            r
                        }
                        i => {
                            if largest_absolute.is_none_or(|(m, _)| i > m) {
                                largest_absolute = Some((i, line_no));
                            }
                            i - 1
                        }
                    };
                    if resolved >= u32::MAX as i64 / 2 {
                        return Err(fail(line_no, format!("face refers to vertex {index}, more than Taut can index")));
                    }
                    soup.faces.push_corner(resolved as u32);
                    count += 1;
                }
                if count < 3 {
                    soup.faces.discard_open_face();
                    short_faces += 1;
                } else {
                    soup.faces.end_face();
                }
            }
            Some(b"l" | b"p") => lines_and_points += 1,
            _ => {}
        }
    }
    let total = soup.positions.len();
    if let Some((index, line_no)) = largest_absolute.filter(|&(i, _)| i > total as i64) {
        return Err(fail(
            line_no,
            format!("face refers to vertex {index}, but the file has {total} vertices (v lines, counted from 1)"),
        ));
    }
    if short_faces > 0 {
        soup.warnings.push(format!("skipped {short_faces} faces with fewer than 3 corners"));
    }
    if lines_and_points > 0 {
        soup.warnings.push(format!("skipped {lines_and_points} point and line elements (p, l)"));
    }
    Ok(soup)
}

/// Reads the coordinates of a `v` line: x y z, then either a homogeneous weight w or colour
/// values (ignored).
fn parse_vertex<'a>(mut words: impl Iterator<Item = &'a [u8]>) -> std::result::Result<DVec3, String> {
    let number = |word: &[u8]| std::str::from_utf8(word).ok().and_then(|s| s.parse::<f64>().ok());
    let mut xyz = [0.0; 3];
    for (c, slot) in xyz.iter_mut().enumerate() {
        let word = words.next().ok_or_else(|| format!("a vertex needs 3 coordinates, found {c}"))?;
        *slot = number(word)
            .ok_or_else(|| format!("cannot read vertex coordinate '{}' as a number", String::from_utf8_lossy(word)))?;
    }
    let rest: Vec<&[u8]> = words.collect();
    let mut p = DVec3::from_array(xyz);
    if let [w] = rest[..] {
        let w = number(w)
            .ok_or_else(|| format!("cannot read the vertex weight '{}' as a number", String::from_utf8_lossy(w)))?;
        if w == 0.0 {
            return Err("the vertex weight w is 0 (a point at infinity)".to_string());
        }
        p /= w;
    }
    Ok(p)
}

/// Vertices or faces encoded per task when the OBJ text is made in parallel.
const OBJ_CHUNK: usize = 8192;

/// The mesh as OBJ text in the axes `up`: `v` positions, `vn` normals (the given ones, or
/// area-weighted vertex normals), `s 1` and `f v//vn` polygons, vertex *i* of the mesh being
/// vertex *i* + 1 of the file.
///
/// Numbers are written in the shortest form that reads back to the same f64 (`zmij`, the
/// formatter serde_json uses; indices by `itoa`), in chunks of [`OBJ_CHUNK`] lines encoded in
/// parallel and joined in order, so the text is the same on any number of threads.
pub fn obj_text(mesh: &PolyMesh, normals: Option<&[DVec3]>, up: UpAxis) -> String {
    use rayon::prelude::*;
    let header = format!(
        "# Taut {} surface: {} vertices, {} faces, {} up\n",
        env!("CARGO_PKG_VERSION"),
        mesh.vertex_count(),
        mesh.face_count(),
        up.name()
    );
    let computed;
    let normals = match normals {
        Some(n) if n.len() == mesh.vertex_count() => n,
        _ => {
            computed = mesh.vertex_normals();
            &computed
        }
    };
    let points = |tag: &'static [u8], points: &[DVec3]| -> Vec<Vec<u8>> {
        points
            .par_chunks(OBJ_CHUNK)
            .map(|chunk| {
                let mut text = Vec::with_capacity(chunk.len() * 64);
                let mut float = zmij::Buffer::new();
                for &p in chunk {
                    let p = up.from_taut(p);
                    text.extend_from_slice(tag);
                    for c in [p.x, p.y, p.z] {
                        text.push(b' ');
                        text.extend_from_slice(float.format(c).as_bytes());
                    }
                    text.push(b'\n');
                }
                text
            })
            .collect()
    };
    let faces: Vec<Vec<u8>> = (0..mesh.face_count().div_ceil(OBJ_CHUNK))
        .into_par_iter()
        .map(|k| {
            let range = k * OBJ_CHUNK..((k + 1) * OBJ_CHUNK).min(mesh.face_count());
            let mut text = Vec::with_capacity(range.len() * 40);
            let mut int = itoa::Buffer::new();
            for f in range {
                text.push(b'f');
                for v in mesh.face_vertices(crate::FaceId(f as u32)) {
                    let index = int.format(v.0 + 1).as_bytes();
                    text.push(b' ');
                    text.extend_from_slice(index);
                    text.extend_from_slice(b"//");
                    text.extend_from_slice(index);
                }
                text.push(b'\n');
            }
            text
        })
        .collect();
    let (positions, normals) = (points(b"v", mesh.positions()), points(b"vn", normals));
    let body: usize = [&positions, &normals, &faces].iter().flat_map(|c| c.iter()).map(Vec::len).sum();
    let mut bytes = Vec::with_capacity(header.len() + body + 4);
    bytes.extend_from_slice(header.as_bytes());
    positions.iter().chain(&normals).for_each(|c| bytes.extend_from_slice(c));
    bytes.extend_from_slice(b"s 1\n");
    faces.iter().for_each(|c| bytes.extend_from_slice(c));
    String::from_utf8(bytes).expect("OBJ text is ASCII")
}

/// Writes the mesh as an OBJ file (atomically), keeping its vertex order.
pub fn export_obj(mesh: &PolyMesh, path: &Path) -> Result<()> {
    export_obj_with(mesh, path, None, UpAxis::default())
}

/// [`export_obj`] with given normals and axes.
pub fn export_obj_with(mesh: &PolyMesh, path: &Path, normals: Option<&[DVec3]>, up: UpAxis) -> Result<()> {
    if mesh.face_count() == 0 {
        return Err(Error::Input(format!("{}: the mesh has no faces; there is nothing to export", path.display())));
    }
    super::check_finite_output(mesh.positions(), normals).map_err(|e| Error::format(path, e.to_string()))?;
    super::write_atomic(path, obj_text(mesh, normals, up).as_bytes())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(text: &str) -> Result<Soup> {
        parse_obj(text.as_bytes(), Path::new("test.obj"))
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
        assert_eq!(soup.faces.to_vecs(), vec![vec![3, 2, 1, 0], vec![4, 3, 4]]);
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
        assert_eq!(soup.faces.to_vecs(), vec![vec![0, 1, 2]]);
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
        assert_eq!(soup.faces.to_vecs(), vec![vec![0, 1, 2]]);
    }

    #[test]
    fn export_text_is_one_based_with_exact_floats() {
        let p = vec![DVec3::new(0.1, 1.0 / 3.0, -0.0), DVec3::new(1e-300, 2.0, 0.0), DVec3::new(0.0, 1e300, 5.0)];
        let mesh = PolyMesh::from_polygons(p.clone(), &[[0, 1, 2]]).unwrap();
        let text = obj_text(&mesh, None, UpAxis::Z);
        assert!(text.contains("\ns 1\nf 1//1 2//2 3//3\n"), "{text}");
        let back = parse(&text).unwrap();
        let bits = |v: &[DVec3]| v.iter().map(|p| p.to_array().map(f64::to_bits)).collect::<Vec<_>>();
        assert_eq!(bits(&back.positions), bits(&p));
        assert_eq!(back.faces.to_vecs(), vec![vec![0, 1, 2]]);
        // A lone triangle's vertex normal is its plane's normal: compare with the cross product.
        let expected = (p[1] - p[0]).cross(p[2] - p[0]).normalize();
        let vn: Vec<f64> = text.lines().find(|l| l.starts_with("vn ")).unwrap()[3..]
            .split_whitespace()
            .map(|w| w.parse().unwrap())
            .collect();
        assert!((DVec3::from_slice(&vn) - expected).length() < 1e-12);
    }

    #[test]
    fn a_text_of_many_chunks_is_the_same_on_any_thread_count_and_reads_back_exactly() {
        // 200 × 100 quads: more vertices and faces than two chunks, with awkward coordinates.
        let mut mesh = crate::mesh::primitives::quad_grid(200, 100, 13.0, 1e-3).unwrap();
        for (i, p) in mesh.positions_mut().iter_mut().enumerate() {
            p.z = (i as f64).sqrt() * 1e-7 - 3.0e5 * (i % 7) as f64;
        }
        assert!(mesh.vertex_count() > 2 * OBJ_CHUNK && mesh.face_count() > OBJ_CHUNK);
        let on = |threads: usize| {
            let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
            pool.install(|| obj_text(&mesh, None, UpAxis::Z))
        };
        let text = on(1);
        assert_eq!(on(4), text);
        let back = parse(&text).unwrap();
        let bits = |v: &[DVec3]| v.iter().map(|p| p.to_array().map(f64::to_bits)).collect::<Vec<_>>();
        assert_eq!(bits(&back.positions), bits(mesh.positions()));
        assert_eq!(back.faces.to_vecs(), mesh.polygons());
        assert_eq!(text.lines().filter(|l| l.starts_with("vn ")).count(), mesh.vertex_count());
    }

    #[test]
    fn y_up_files_are_turned_to_z_up_and_back_exactly() {
        // Blender writes (x, z, −y) for its own (x, y, z): a point up in the file is up in Taut.
        let soup = parse("v 1 2 3\nv 0 1 0\nv 0 0 1\nf 1 2 3\n").unwrap();
        let taut: Vec<DVec3> = soup.positions.iter().map(|&p| UpAxis::Y.to_taut(p)).collect();
        assert_eq!(taut[0], DVec3::new(1.0, -3.0, 2.0));
        assert_eq!(taut[1], DVec3::Z);
        let mesh = PolyMesh::from_polygons(taut.clone(), &[[0, 1, 2]]).unwrap();
        let text = obj_text(&mesh, None, UpAxis::Y);
        assert!(text.contains("\nv 1.0 2.0 3.0\n"), "{text}");
        let back = parse(&text).unwrap();
        let again: Vec<DVec3> = back.positions.iter().map(|&p| UpAxis::Y.to_taut(p)).collect();
        let bits = |v: &[DVec3]| v.iter().map(|p| p.to_array().map(f64::to_bits)).collect::<Vec<_>>();
        assert_eq!(bits(&again), bits(&taut));
    }

    #[test]
    fn one_huge_face_line_fails_fast_on_its_first_repeat() {
        // The text is parsed without copies; the pinch is found at the fourth corner by the weld.
        let mut text = String::from("v 0 0 0\nv 1 0 0\nv 0 1 0\nf");
        for _ in 0..200_000 {
            text.push_str(" 1 2 3");
        }
        let soup = parse(&text).unwrap();
        assert_eq!(soup.faces.corner_count(), 600_000);
        let err = super::super::weld::weld_faces(&soup.positions, &soup.faces).unwrap_err().to_string();
        assert!(err.contains("face 0 passes through vertex 0 twice"), "{err}");
    }
}
