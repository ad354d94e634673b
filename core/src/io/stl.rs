//! STL import, binary and ASCII (3D Systems' StereoLithography format), the format most
//! scanners and CAD exports write.
//!
//! A binary file is an 80-byte header, a little-endian `u32` triangle count and 50 bytes per
//! triangle (a normal, three corners as `f32`, two attribute bytes). It is recognised by its
//! size (84 + 50 × count), because many binary files also begin with the word `solid`; a file
//! that starts with `solid` and does not have that size is read as ASCII (`facet normal … outer
//! loop vertex x y z … endloop endfacet`, any number of solids). Normals and attributes are
//! ignored (the cage's normals come from its faces). Every triangle has its own three corners,
//! so corners are merged by welding afterwards; STL writers repeat shared corners bit for bit.
//!
//! Hostile files: the count is checked against the bytes present before anything is read or
//! allocated, a truncated file is refused, extra bytes after the declared triangles are ignored
//! with a warning, non-finite coordinates are refused with the triangle's number.

use super::soup::Soup;
use crate::{DVec3, Error, Result};
use rayon::prelude::*;
use std::path::Path;

/// Bytes per triangle record of a binary STL.
const RECORD: usize = 50;
/// Bytes before the first record.
const HEADER: usize = 84;

/// Reads an STL file into a polygon soup (not yet welded).
pub(crate) fn read_stl(path: &Path) -> Result<Soup> {
    let bytes = super::file::read_regular_file(path)?;
    parse_stl(&bytes, path)
}

/// What an STL file holds: a binary file's triangles as their `f32` corners (welded by
/// [`weld_triangle_soup`](super::weld_soup::weld_triangle_soup) without a soup in between), or an
/// ASCII file's soup.
pub(crate) enum StlContent {
    Binary { triangles: Vec<[[f32; 3]; 3]>, warnings: Vec<String> },
    Ascii(Soup),
}

/// Reads an STL file as its triangles ([`StlContent`]).
pub(crate) fn read_stl_content(path: &Path) -> Result<StlContent> {
    let bytes = super::file::read_regular_file(path)?;
    parse_stl_content(&bytes, path)
}

/// Parses STL bytes; `origin` names the file in messages.
pub(crate) fn parse_stl(bytes: &[u8], origin: &Path) -> Result<Soup> {
    Ok(match parse_stl_content(bytes, origin)? {
        StlContent::Binary { triangles, warnings } => {
            let positions = triangles.iter().flatten().map(|p| DVec3::from_array(p.map(f64::from))).collect();
            let faces = (0..triangles.len() as u32).map(|t| [3 * t, 3 * t + 1, 3 * t + 2]).collect();
            Soup { positions, faces, warnings }
        }
        StlContent::Ascii(soup) => soup,
    })
}

fn parse_stl_content(bytes: &[u8], origin: &Path) -> Result<StlContent> {
    let fail = |m: String| Error::format(origin, m);
    if bytes.is_empty() {
        return Err(fail("the file is empty".into()));
    }
    let declared =
        (bytes.len() >= HEADER).then(|| u32::from_le_bytes([bytes[80], bytes[81], bytes[82], bytes[83]]) as usize);
    let binary_size = declared.map(|n| n.checked_mul(RECORD).and_then(|b| b.checked_add(HEADER)));
    // A text editor may have put a UTF-8 byte-order mark, and spaces, before the word `solid`.
    let text = bytes.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(bytes);
    let looks_ascii = text
        .iter()
        .take(512)
        .position(|b| !b.is_ascii_whitespace())
        .is_some_and(|k| text[k..].len() >= 5 && text[k..k + 5].eq_ignore_ascii_case(b"solid"))
        && !text.contains(&0);
    match (declared, binary_size) {
        (Some(n), Some(Some(size))) if size == bytes.len() || (!looks_ascii && size < bytes.len()) => {
            parse_binary(bytes, n, size, origin)
        }
        _ if looks_ascii => Ok(StlContent::Ascii(parse_ascii(&String::from_utf8_lossy(text), origin)?)),
        (Some(n), _) => Err(fail(format!(
            "truncated binary STL: the header declares {n} triangles ({} bytes) but the file has {} bytes",
            n.saturating_mul(RECORD).saturating_add(HEADER),
            bytes.len()
        ))),
        (None, _) => Err(fail(format!(
            "not an STL file: {} bytes is too short for a binary header and it does not start with 'solid'",
            bytes.len()
        ))),
    }
}

fn parse_binary(bytes: &[u8], count: usize, size: usize, origin: &Path) -> Result<StlContent> {
    let records = &bytes[HEADER..size];
    let f32_at = |r: &[u8], k: usize| f32::from_le_bytes([r[k], r[k + 1], r[k + 2], r[k + 3]]);
    let triangles: Vec<[[f32; 3]; 3]> = records
        .par_chunks_exact(RECORD)
        .map(|r| [0, 1, 2].map(|corner| [0, 1, 2].map(|axis| f32_at(r, 12 + 12 * corner + 4 * axis))))
        .collect();
    let finite = |t: &[[f32; 3]; 3]| t.iter().flatten().all(|x| x.is_finite());
    if let Some(t) = triangles.par_iter().position_first(|t| !finite(t)) {
        let p = triangles[t].iter().find(|p| !p.iter().all(|x| x.is_finite())).expect("a corner is not finite");
        return Err(Error::format(
            origin,
            format!(
                "triangle {t} has a non-finite corner ({:?}); every coordinate must be a finite number",
                p.map(f64::from)
            ),
        ));
    }
    let mut warnings = Vec::new();
    if size < bytes.len() {
        warnings.push(format!("ignored {} bytes after the {count} declared triangles", bytes.len() - size));
    }
    Ok(StlContent::Binary { triangles, warnings })
}

fn parse_ascii(text: &str, origin: &Path) -> Result<Soup> {
    let fail = |line: usize, m: String| Error::format(origin, format!("line {line}: {m}"));
    let mut soup = Soup::default();
    let mut facet: Option<Vec<u32>> = None;
    let mut short = 0usize;
    for (k, line) in text.lines().enumerate() {
        let line_no = k + 1;
        let mut words = line.split_whitespace();
        match words.next().map(str::to_ascii_lowercase).as_deref() {
            Some("outer") => facet = Some(Vec::with_capacity(3)),
            Some("vertex") => {
                let Some(corners) = facet.as_mut() else {
                    return Err(fail(line_no, "a vertex outside 'outer loop' … 'endloop'".into()));
                };
                let mut xyz = [0.0; 3];
                for (c, slot) in xyz.iter_mut().enumerate() {
                    let word = words
                        .next()
                        .ok_or_else(|| fail(line_no, format!("a vertex needs 3 coordinates, found {c}")))?;
                    *slot = word
                        .parse::<f64>()
                        .map_err(|_| fail(line_no, format!("cannot read vertex coordinate '{word}' as a number")))?;
                }
                let p = DVec3::from_array(xyz);
                if !p.is_finite() {
                    return Err(fail(line_no, format!("a vertex has a non-finite coordinate ({xyz:?})")));
                }
                corners.push(soup.positions.len() as u32);
                soup.positions.push(p);
            }
            Some("endloop") => match facet.take() {
                Some(corners) if corners.len() >= 3 => soup.faces.push(corners),
                Some(_) => short += 1,
                None => return Err(fail(line_no, "'endloop' without 'outer loop'".into())),
            },
            _ => {}
        }
    }
    if facet.is_some() {
        return Err(Error::format(origin, "the file ends inside a facet (truncated ASCII STL)"));
    }
    if short > 0 {
        soup.warnings.push(format!("skipped {short} facets with fewer than 3 vertices"));
    }
    Ok(soup)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(bytes: &[u8]) -> Result<Soup> {
        parse_stl(bytes, Path::new("t.stl"))
    }

    #[test]
    fn a_binary_file_starting_with_solid_is_read_as_binary() {
        let mut bytes = b"solid but binary".to_vec();
        bytes.resize(80, b' ');
        bytes.extend(1u32.to_le_bytes());
        for v in [[0.0f32, 0.0, 1.0], [0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.5]] {
            bytes.extend(v.iter().flat_map(|c| c.to_le_bytes()));
        }
        bytes.extend([0, 0]);
        let soup = parse(&bytes).unwrap();
        assert_eq!(soup.positions, vec![DVec3::ZERO, DVec3::X, DVec3::new(0.0, 1.0, 0.5)]);
        assert_eq!(soup.faces.to_vecs(), vec![vec![0, 1, 2]]);
    }

    #[test]
    fn ascii_after_a_byte_order_mark_and_spaces() {
        let body = "  solid bom\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nendloop\nendfacet\nendsolid\n";
        for prefix in ["\u{FEFF}", "\u{FEFF}   ", "\t \n"] {
            let text = format!("{prefix}{body}");
            let soup = parse_stl(text.as_bytes(), Path::new("bom.stl")).unwrap();
            assert_eq!((soup.positions.len(), soup.faces.len()), (3, 1), "{prefix:?}");
        }
    }

    #[test]
    fn ascii_with_odd_case_and_several_solids() {
        let text = "solid a\n facet normal 0 0 1\n  OUTER LOOP\n   vertex 0 0 0\n   vertex 1 0 0\n   vertex 0 1 0\n  endloop\n endfacet\nendsolid a\n\
                    solid b\nfacet normal 0 0 0\nouter loop\nvertex 1e0 -2.5 3\nvertex 4 5 6\nvertex 7 8 9\nendloop\nendfacet\nendsolid\n";
        let soup = parse(text.as_bytes()).unwrap();
        assert_eq!(soup.faces.to_vecs(), vec![vec![0, 1, 2], vec![3, 4, 5]]);
        assert_eq!(soup.positions[3], DVec3::new(1.0, -2.5, 3.0));
    }

    #[test]
    fn damaged_files_are_named_errors() {
        let mut huge = vec![0u8; 80];
        huge.extend(u32::MAX.to_le_bytes());
        let cases: Vec<(Vec<u8>, &str)> = vec![
            (vec![], "empty"),
            (b"hello".to_vec(), "not an STL file"),
            (huge, "declares 4294967295 triangles"),
            (b"solid x\nfacet\nouter loop\nvertex 0 0\n".to_vec(), "line 4: a vertex needs 3 coordinates"),
            (b"solid x\nouter loop\nvertex 0 0 nan\n".to_vec(), "non-finite"),
            (b"solid x\nouter loop\nvertex 0 0 0\n".to_vec(), "truncated ASCII STL"),
            (b"solid x\nvertex 0 0 0\n".to_vec(), "outside 'outer loop'"),
        ];
        for (bytes, expected) in cases {
            let err = parse(&bytes).unwrap_err().to_string();
            assert!(err.starts_with("t.stl: ") && err.contains(expected), "expected '{expected}' in: {err}");
        }
    }
}
