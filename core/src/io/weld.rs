//! Welding an imported polygon soup into a cage, and the report of what the import changed.
//!
//! Exporters split a vertex wherever its attributes differ (UV seams, hard edges, per-primitive
//! materials), so a closed surface arrives as patches that only touch. Welding merges vertices
//! whose positions are bit-for-bit equal (after mapping −0.0 to 0.0), keeping the first
//! occurrence of each position in its file order, so a file without duplicates keeps its
//! numbering exactly. Merging can shorten an edge to nothing; the documented repair removes
//! consecutive repeats of a vertex in a face (cyclically), drops faces left with fewer than three
//! vertices and drops faces that repeat an earlier face's vertex cycle (in either orientation).
//! A face that passes through one vertex twice with other vertices between is refused: it
//! pinches, and guessing how to split it would change the designer's surface.
//!
//! Weak where a file relies on nearly equal positions: welding is exact, with no tolerance, so
//! vertices that differ in the last bit stay apart and the surface stays torn there.

use crate::mesh::PolyMesh;
use crate::{DVec3, Error, Result};
use std::collections::HashMap;
use std::collections::hash_map::Entry;
use std::fmt;
use std::path::Path;

/// How many cases of one kind of repair are listed by face in the warnings.
const LISTED_CASES: usize = 5;

/// What an import changed on the way from the file to the cage, and what it skipped.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
#[non_exhaustive]
pub struct ImportReport {
    /// Vertices merged into an earlier vertex at the same position.
    pub welded: usize,
    /// Faces that lost a repeated vertex (a zero-length edge) but were kept.
    pub repaired_faces: usize,
    /// Faces dropped, for either reason: fewer than three distinct vertices were left, or an
    /// earlier face has the same vertex cycle.
    pub dropped_faces: usize,
    /// Of the dropped faces, those that repeated an earlier face's vertex cycle (in either
    /// orientation).
    pub duplicate_faces: usize,
    /// Everything else worth telling the designer (skipped primitives, listed repairs, ...).
    pub warnings: Vec<String>,
}

impl ImportReport {
    /// True when the file was read as it is, with nothing merged, repaired or skipped.
    pub fn is_clean(&self) -> bool {
        self.welded == 0 && self.repaired_faces == 0 && self.dropped_faces == 0 && self.warnings.is_empty()
    }
}

impl fmt::Display for ImportReport {
    /// One line, e.g. `welded 16 vertices, dropped 2 duplicate faces (1 warning)`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let plural = |n: usize, one: &str, many: &str| format!("{n} {}", if n == 1 { one } else { many });
        let mut parts = Vec::new();
        if self.welded > 0 {
            parts.push(format!("welded {}", plural(self.welded, "vertex", "vertices")));
        }
        if self.repaired_faces > 0 {
            parts.push(format!("repaired {}", plural(self.repaired_faces, "face", "faces")));
        }
        let degenerate = self.dropped_faces.saturating_sub(self.duplicate_faces);
        if degenerate > 0 {
            parts.push(format!("dropped {}", plural(degenerate, "degenerate face", "degenerate faces")));
        }
        if self.duplicate_faces > 0 {
            parts.push(format!("dropped {}", plural(self.duplicate_faces, "duplicate face", "duplicate faces")));
        }
        if parts.is_empty() {
            parts.push("nothing welded or repaired".to_string());
        }
        write!(f, "{}", parts.join(", "))?;
        if !self.warnings.is_empty() {
            write!(f, " ({})", plural(self.warnings.len(), "warning", "warnings"))?;
        }
        Ok(())
    }
}

/// Polygons as a file describes them, before welding: the common output of every reader.
#[derive(Clone, Debug, Default)]
pub(crate) struct Soup {
    pub positions: Vec<DVec3>,
    pub faces: Vec<Vec<u32>>,
    pub warnings: Vec<String>,
}

/// Welded positions and repaired faces.
#[derive(Clone, Debug)]
pub struct Welded {
    /// One position per distinct input position, in order of first occurrence.
    pub positions: Vec<DVec3>,
    /// The faces that survived, renumbered, in input order.
    pub faces: Vec<Vec<u32>>,
    /// Counts of what was merged, repaired and dropped (no format warnings).
    pub report: ImportReport,
}

/// Merges vertices at identical positions and repairs the faces as the module doc describes.
/// Faces are numbered from 0 in input order in messages. Fails on an index out of range or a
/// face that passes through one vertex twice, not consecutively.
pub fn weld<F: AsRef<[u32]>>(positions: &[DVec3], faces: &[F]) -> Result<Welded> {
    let n = positions.len();
    let mut first: HashMap<[u64; 3], u32> = HashMap::with_capacity(n);
    let mut remap = Vec::with_capacity(n);
    let mut welded_positions = Vec::with_capacity(n);
    for &p in positions {
        // Adding 0.0 turns −0.0 into 0.0 and leaves every other value alone.
        let key = (p + DVec3::ZERO).to_array().map(f64::to_bits);
        let next = welded_positions.len() as u32;
        match first.entry(key) {
            Entry::Occupied(e) => remap.push(*e.get()),
            Entry::Vacant(e) => {
                e.insert(next);
                remap.push(next);
                welded_positions.push(p);
            }
        }
    }

    let mut report = ImportReport { welded: n - welded_positions.len(), ..ImportReport::default() };
    let mut listed = Listed::default();
    let mut seen_cycles: HashMap<Vec<u32>, usize> = HashMap::with_capacity(faces.len());
    let mut out_faces = Vec::with_capacity(faces.len());
    let mut ring: Vec<u32> = Vec::new();
    for (f, face) in faces.iter().enumerate() {
        let face = face.as_ref();
        ring.clear();
        for &v in face {
            let Some(&w) = remap.get(v as usize) else {
                return Err(Error::Input(format!("face {f} refers to vertex {v}, but there are only {n} vertices")));
            };
            if ring.last() != Some(&w) {
                ring.push(w);
            }
        }
        while ring.len() > 1 && ring.first() == ring.last() {
            ring.pop();
        }
        if ring.len() < 3 {
            report.dropped_faces += 1;
            note(&mut listed.dropped, || {
                format!("dropped face {f}: fewer than 3 distinct vertices are left once repeats are removed")
            });
            continue;
        }
        if let Some(v) = repeated_vertex(&ring) {
            let cause = if repeated_vertex(face).is_some() {
                String::new()
            } else {
                format!(
                    " once vertices at the same position are welded (position {:?})",
                    welded_positions[v as usize].to_array()
                )
            };
            return Err(Error::Topology(format!(
                "face {f} passes through vertex {v} twice{cause}; the polygon pinches at that vertex, which a cage \
                 cannot represent: split the face in two or move one of its corners"
            )));
        }
        if ring.len() != face.len() {
            report.repaired_faces += 1;
            note(&mut listed.repaired, || {
                format!("repaired face {f}: removed {} repeated vertices (zero-length edges)", face.len() - ring.len())
            });
        }
        let forward = canonical_cycle(ring.iter().copied());
        let backward = canonical_cycle(ring.iter().rev().copied());
        if let Some(&g) = seen_cycles.get(&forward) {
            report.dropped_faces += 1;
            report.duplicate_faces += 1;
            note(&mut listed.duplicate, || format!("dropped face {f}: it repeats face {g}"));
            continue;
        }
        if let Some(&g) = seen_cycles.get(&backward) {
            report.dropped_faces += 1;
            report.duplicate_faces += 1;
            note(&mut listed.duplicate, || format!("dropped face {f}: it is face {g} facing the other way"));
            continue;
        }
        seen_cycles.insert(forward, f);
        out_faces.push(ring.clone());
    }
    report.warnings = listed.finish(&report);
    Ok(Welded { positions: welded_positions, faces: out_faces, report })
}

/// Welds a soup read from `path` and builds the cage; every failure names the file.
pub(crate) fn into_mesh(path: &Path, soup: Soup) -> Result<(PolyMesh, ImportReport)> {
    let hint = if soup.warnings.is_empty() { String::new() } else { format!(" ({})", soup.warnings.join("; ")) };
    if soup.faces.is_empty() {
        return Err(Error::format(
            path,
            format!(
                "no faces: the file has {} vertices but no polygons to build a cage from{hint}",
                soup.positions.len()
            ),
        ));
    }
    let welded = weld(&soup.positions, &soup.faces).map_err(|e| Error::format(path, numbering_note(e, 0)))?;
    if welded.faces.is_empty() {
        return Err(Error::format(
            path,
            format!(
                "no faces: all {} faces collapse once vertices at the same position are welded{hint}",
                soup.faces.len()
            ),
        ));
    }
    let mut report = welded.report;
    let mesh = PolyMesh::from_polygons(welded.positions, &welded.faces)
        .map_err(|e| Error::format(path, numbering_note(e, report.welded)))?;
    let mut warnings = soup.warnings;
    warnings.append(&mut report.warnings);
    report.warnings = warnings;
    Ok((mesh, report))
}

/// Says how vertices and faces are numbered in a message about the welded cage.
fn numbering_note(e: Error, welded: usize) -> String {
    if welded == 0 {
        format!("{e} (vertices and faces are numbered from 0 in file order)")
    } else {
        format!(
            "{e} (vertices are numbered from 0 after welding {welded} duplicates, in order of first appearance; \
             faces from 0 among the faces kept)"
        )
    }
}

/// The first vertex that appears twice in a face, if any.
fn repeated_vertex(face: &[u32]) -> Option<u32> {
    if face.len() <= 16 {
        return face.iter().enumerate().find(|&(k, v)| face[..k].contains(v)).map(|(_, &v)| v);
    }
    let mut seen = std::collections::HashSet::with_capacity(face.len());
    face.iter().copied().find(|&v| !seen.insert(v))
}

/// A vertex cycle rotated to start at its smallest index, so equal cycles compare equal.
fn canonical_cycle(cycle: impl Iterator<Item = u32> + Clone) -> Vec<u32> {
    let ring: Vec<u32> = cycle.collect();
    let start = ring.iter().enumerate().min_by_key(|&(_, v)| v).map_or(0, |(k, _)| k);
    ring[start..].iter().chain(&ring[..start]).copied().collect()
}

/// The first few repairs of each kind, listed by face.
#[derive(Default)]
struct Listed {
    repaired: Vec<String>,
    dropped: Vec<String>,
    duplicate: Vec<String>,
}

/// Lists one more case unless enough of its kind are listed already.
fn note(list: &mut Vec<String>, message: impl FnOnce() -> String) {
    if list.len() < LISTED_CASES {
        list.push(message());
    }
}

impl Listed {
    fn finish(self, report: &ImportReport) -> Vec<String> {
        let mut out = Vec::new();
        for (list, total) in [
            (self.repaired, report.repaired_faces),
            (self.dropped, report.dropped_faces - report.duplicate_faces),
            (self.duplicate, report.duplicate_faces),
        ] {
            let shown = list.len();
            out.extend(list);
            if total > shown {
                out.push(format!("... and {} more like the above", total - shown));
            }
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The unit cube with every face on its own four vertices, as exporters write it with hard
    /// edges: 24 vertices, each corner appearing three times.
    fn split_cube() -> (Vec<DVec3>, Vec<[u32; 4]>) {
        let corner = |i: u32| DVec3::new((i & 1) as f64, ((i >> 1) & 1) as f64, ((i >> 2) & 1) as f64);
        let shared = [[0, 2, 3, 1], [4, 5, 7, 6], [0, 1, 5, 4], [2, 6, 7, 3], [0, 4, 6, 2], [1, 3, 7, 5]];
        let mut positions = Vec::new();
        let mut faces = Vec::new();
        for face in shared {
            let base = positions.len() as u32;
            positions.extend(face.iter().map(|&i| corner(i)));
            faces.push([base, base + 1, base + 2, base + 3]);
        }
        (positions, faces)
    }

    #[test]
    fn split_cube_welds_to_eight_corners_in_first_appearance_order() {
        let (positions, faces) = split_cube();
        let w = weld(&positions, &faces).unwrap();
        assert_eq!(w.report.welded, 16);
        assert_eq!(w.positions.len(), 8);
        // Independent reference: the distinct positions in order of first appearance.
        let mut expected: Vec<DVec3> = Vec::new();
        for p in &positions {
            if !expected.contains(p) {
                expected.push(*p);
            }
        }
        assert_eq!(w.positions, expected);
        for (face, original) in w.faces.iter().zip(&faces) {
            let a: Vec<DVec3> = face.iter().map(|&v| w.positions[v as usize]).collect();
            let b: Vec<DVec3> = original.iter().map(|&v| positions[v as usize]).collect();
            assert_eq!(a, b);
        }
        let mesh = PolyMesh::from_polygons(w.positions, &w.faces).unwrap();
        assert!(mesh.is_closed());
        assert_eq!(mesh.euler_characteristic(), 2);
        assert_eq!(w.report.to_string(), "welded 16 vertices");
    }

    #[test]
    fn distinct_positions_keep_their_numbering() {
        let positions = vec![DVec3::Y, DVec3::ZERO, DVec3::X, DVec3::ONE];
        let faces = [[2, 1, 0], [3, 2, 0]];
        let w = weld(&positions, &faces).unwrap();
        assert_eq!(w.positions, positions);
        assert_eq!(w.faces, vec![vec![2, 1, 0], vec![3, 2, 0]]);
        assert!(w.report.is_clean());
        assert_eq!(w.report.to_string(), "nothing welded or repaired");
    }

    #[test]
    fn negative_zero_welds_with_zero() {
        let positions = vec![DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::new(-0.0, 0.0, -0.0)];
        let w = weld(&positions, &[[0, 1, 2], [3, 2, 1]]).unwrap();
        assert_eq!(w.report.welded, 1);
        assert_eq!(w.positions.len(), 3);
        // The second face became [0, 2, 1]: the first facing the other way.
        assert_eq!((w.report.dropped_faces, w.report.duplicate_faces), (1, 1));
        assert_eq!(w.faces, vec![vec![0, 1, 2]]);
    }

    #[test]
    fn collapsed_edges_are_removed_cyclically() {
        // Vertex 4 sits on vertex 0: the pentagon's closing edge has length zero.
        let positions = vec![DVec3::ZERO, DVec3::X, DVec3::ONE, DVec3::Y, DVec3::ZERO];
        let w = weld(&positions, &[[0, 1, 2, 3, 4]]).unwrap();
        assert_eq!(w.faces, vec![vec![0, 1, 2, 3]]);
        assert_eq!((w.report.welded, w.report.repaired_faces, w.report.dropped_faces), (1, 1, 0));
        assert!(w.report.warnings[0].contains("repaired face 0"), "{:?}", w.report.warnings);
    }

    #[test]
    fn faces_left_with_two_vertices_are_dropped() {
        let positions = vec![DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::X, DVec3::ONE];
        // Face 1 collapses (vertex 3 is vertex 1); face 2 survives, renumbered to [1, 3, 2].
        let faces = vec![vec![0, 1, 2], vec![1, 3, 2], vec![1, 4, 2]];
        let w = weld(&positions, &faces).unwrap();
        assert_eq!(w.faces, vec![vec![0, 1, 2], vec![1, 3, 2]]);
        assert_eq!(w.report.dropped_faces, 1);
        assert_eq!(w.report.to_string(), "welded 1 vertex, dropped 1 degenerate face (1 warning)");
    }

    #[test]
    fn a_pinched_face_is_refused_by_number() {
        // Vertex 3 lands on vertex 1, which is not next to it in face 1.
        let positions = vec![DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::X, DVec3::ONE, DVec3::Z];
        let faces = vec![vec![0, 1, 2], vec![1, 4, 3, 5]];
        let err = weld(&positions, &faces).unwrap_err().to_string();
        assert!(err.contains("face 1 passes through vertex 1 twice once vertices"), "{err}");
    }

    #[test]
    fn duplicate_faces_are_dropped_and_listed() {
        let (positions, faces) = split_cube();
        let mut faces = faces.to_vec();
        faces.push(faces[2]);
        faces.push([faces[3][1], faces[3][2], faces[3][3], faces[3][0]]);
        let w = weld(&positions, &faces).unwrap();
        assert_eq!(w.faces.len(), 6);
        assert_eq!((w.report.dropped_faces, w.report.duplicate_faces), (2, 2));
        assert_eq!(w.report.to_string(), "welded 16 vertices, dropped 2 duplicate faces (2 warnings)");
        assert_eq!(w.report.warnings, vec!["dropped face 6: it repeats face 2", "dropped face 7: it repeats face 3"]);
    }

    #[test]
    fn out_of_range_indices_are_an_error_not_a_panic() {
        let err = weld(&[DVec3::ZERO], &[[0, 1, 2]]).unwrap_err().to_string();
        assert!(err.contains("only 1 vertices"), "{err}");
    }
}
