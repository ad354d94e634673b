//! Welding an imported polygon soup into a cage, and the report of what the import changed.
//!
//! Exporters split a vertex wherever its attributes differ (UV seams, hard edges, per-primitive
//! materials), so a closed surface arrives as patches that only touch. Welding merges vertices
//! whose positions are bit-for-bit equal (after mapping −0.0 to 0.0), keeping the first
//! occurrence of each position in its file order, so a file without duplicates keeps its
//! numbering exactly. Merging can shorten an edge to nothing; the documented repair removes
//! consecutive repeats of a vertex in a face (cyclically), drops faces left with fewer than three
//! vertices and drops faces that repeat an earlier face's vertex cycle (in either orientation).
//!
//! Welding never makes the surface non-manifold. Two faces are joined across an edge only when,
//! after welding, that edge is used once in each direction; around every welded vertex the faces
//! joined that way form fans, and each fan keeps a vertex of its own. So two parts that only
//! touch at a point or along an edge (Blender's monkey: the eyes touch the head at two points)
//! stay two parts, and the report says which positions were left apart. Vertices that are one
//! vertex in the file are never split: a file that is non-manifold by itself is refused by the
//! mesh, as it should be.
//!
//! A face that passes through one file vertex twice with other vertices between is refused: it
//! pinches, and guessing how to split it would change the designer's surface.
//!
//! Memory: a few machine words per corner and per vertex; the pinch check runs while the faces are
//! read, before anything per corner is allocated, so one hostile face with millions of repeated
//! corners fails at once.
//!
//! A binary STL, whose every corner is a vertex of its own, is welded by
//! `io/weld_soup.rs` instead: the same result, found position by position in
//! parallel.
//!
//! Weak where a file relies on nearly equal positions: welding is exact, with no tolerance, so
//! vertices that differ in the last bit stay apart and the surface stays torn there.

use super::soup::{FaceList, Soup};
use crate::mesh::PolyMesh;
use crate::mesh::union_find::UnionFind;
use crate::{DVec3, Error, Result};
use rayon::prelude::*;
use std::fmt;
use std::path::Path;

/// How many cases of one kind of repair are listed by face in the warnings.
pub(super) const LISTED_CASES: usize = 5;

pub(super) const NONE: u32 = u32::MAX;

/// What an import changed on the way from the file to the cage, and what it skipped.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
#[non_exhaustive]
pub struct ImportReport {
    /// Vertices merged into an earlier vertex at the same position.
    pub welded: usize,
    /// Positions where welding was held back because it would have joined separate fans of faces
    /// at one vertex (parts that only touch): one more vertex for each fan kept apart.
    pub kept_apart: usize,
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
        self.welded == 0
            && self.kept_apart == 0
            && self.repaired_faces == 0
            && self.dropped_faces == 0
            && self.warnings.is_empty()
    }
}

impl fmt::Display for ImportReport {
    /// One line, e.g. `welded 16 vertices, dropped 2 duplicate faces; dropped face 6: it repeats
    /// face 2; ...` — the counts, then every warning's text.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let plural = |n: usize, one: &str, many: &str| format!("{n} {}", if n == 1 { one } else { many });
        let mut parts = Vec::new();
        if self.welded > 0 {
            parts.push(format!("welded {}", plural(self.welded, "vertex", "vertices")));
        }
        if self.kept_apart > 0 {
            parts.push(format!("kept {} apart where parts only touch", plural(self.kept_apart, "vertex", "vertices")));
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
        for warning in &self.warnings {
            write!(f, "; {warning}")?;
        }
        Ok(())
    }
}

/// Welded positions and repaired faces.
#[derive(Clone, Debug)]
pub struct Welded {
    /// One position per vertex of the cage, in order of the first file vertex each stands for.
    pub positions: Vec<DVec3>,
    /// The faces that survived, renumbered, in input order.
    pub faces: FaceList,
    /// Counts of what was merged, repaired and dropped (no format warnings).
    pub report: ImportReport,
}

/// Merges vertices at identical positions and repairs the faces as the module doc describes.
/// Faces are numbered from 0 in input order in messages. Fails on an index out of range or a
/// face that passes through one vertex twice, not consecutively.
pub fn weld<F: AsRef<[u32]>>(positions: &[DVec3], faces: &[F]) -> Result<Welded> {
    weld_faces(positions, &faces.iter().collect())
}

/// [`weld`] on faces already in a [`FaceList`].
pub fn weld_faces(positions: &[DVec3], faces: &FaceList) -> Result<Welded> {
    let n = positions.len();
    if n >= NONE as usize || faces.corner_count() >= NONE as usize {
        return Err(Error::Input(format!("{n} vertices is more than Taut can index")));
    }
    // 1. The first file vertex at each position.
    let tentative = first_at_same_position(positions);

    // 2. Faces in tentative numbering, repeats removed; the file's own pinches are refused here.
    let mut report = ImportReport::default();
    let mut listed = Listed::default();
    let mut kept = Kept::default();
    let mut stamp = vec![NONE; n];
    let mut ring: Vec<(u32, u32)> = Vec::new();
    for (f, face) in faces.iter().enumerate() {
        // The file's own repeats: consecutive ones are zero-length edges (repaired below); any
        // other is a pinch, found at the first corner that proves it.
        let mut closing = false;
        for &v in face {
            if v as usize >= n {
                return Err(Error::Input(format!("face {f} refers to vertex {v}, but there are only {n} vertices")));
            }
            if closing {
                if v == ring[0].1 {
                    continue;
                }
                return Err(pinch(f, ring[0].1, None));
            }
            if ring.last().map(|&(_, o)| o) == Some(v) {
                continue;
            }
            if stamp[v as usize] == f as u32 {
                if ring[0].1 == v {
                    // Back at the first vertex: only repeats of it may follow.
                    closing = true;
                    continue;
                }
                return Err(pinch(f, v, None));
            }
            stamp[v as usize] = f as u32;
            ring.push((tentative[v as usize], v));
        }
        // Welding makes neighbours equal: remove those repeats too, cyclically.
        ring.dedup_by_key(|c| c.0);
        while ring.len() > 1 && ring.first().map(|c| c.0) == ring.last().map(|c| c.0) {
            ring.pop();
        }
        if ring.len() < 3 {
            report.dropped_faces += 1;
            note(&mut listed.dropped, || {
                format!("dropped face {f}: fewer than 3 distinct vertices are left once repeats are removed")
            });
        } else {
            if ring.len() != face.len() {
                report.repaired_faces += 1;
                note(&mut listed.repaired, || {
                    format!(
                        "repaired face {f}: removed {} repeated vertices (zero-length edges)",
                        face.len() - ring.len()
                    )
                });
            }
            kept.push(f as u32, &ring);
        }
        ring.clear();
    }
    drop(stamp);

    // 3. Faces repeating an earlier face's cycle (either way round) are dropped.
    let duplicates = find_duplicates(&kept);
    if !duplicates.is_empty() {
        for &(f, g, reversed) in &duplicates {
            listed.repeat(&mut report, f, g, reversed);
        }
        let gone: std::collections::HashSet<u32> = duplicates.iter().map(|d| d.0).collect();
        kept.retain(|source| !gone.contains(&source));
    }

    // 4. Fans: corners of one file vertex belong together, and so do the corners on either side of
    //    an edge used once each way.
    let corners = kept.t.len();
    let mut sets = UnionFind::new(corners);
    let mut corner_of_file_vertex = vec![NONE; n];
    for c in 0..corners {
        let v = kept.orig[c] as usize;
        match corner_of_file_vertex[v] {
            NONE => corner_of_file_vertex[v] = c as u32,
            other => sets.union(other, c as u32),
        }
    }
    let mut sides: Vec<(u32, u32, u32)> = Vec::with_capacity(corners); // (lo, hi, corner | direction bit)
    for face in 0..kept.len() {
        for c in kept.range(face) {
            let next = kept.next(face, c);
            let (a, b) = (kept.t[c], kept.t[next]);
            let backward = u32::from(a > b);
            sides.push((a.min(b), a.max(b), ((c as u32) << 1) | backward));
        }
    }
    crate::mesh::edge_sort::sort_sides(&mut sides, n);
    let mut k = 0;
    while k < sides.len() {
        let mut end = k + 1;
        while end < sides.len() && (sides[end].0, sides[end].1) == (sides[k].0, sides[k].1) {
            end += 1;
        }
        if end - k == 2 && (sides[k].2 & 1) != (sides[k + 1].2 & 1) {
            // Side c runs a → b in its face, side d runs b → a in its: glue a to a and b to b.
            let (c, d) = ((sides[k].2 >> 1) as usize, (sides[k + 1].2 >> 1) as usize);
            let (c_next, d_next) = (kept.next_corner(c), kept.next_corner(d));
            sets.union(c as u32, d_next as u32);
            sets.union(c_next as u32, d as u32);
        }
        k = end;
    }
    drop(sides);

    // 5. One cage vertex per fan, numbered by the first file vertex it stands for.
    let mut representative = vec![NONE; corners];
    for c in 0..corners {
        let root = sets.find(c as u32) as usize;
        representative[root] = representative[root].min(kept.orig[c]);
    }
    // Per file vertex: the fan it heads (if any); per position: the fan with the first file vertex.
    let mut heads = vec![false; n];
    for c in 0..corners {
        if sets.find(c as u32) as usize == c {
            heads[representative[c] as usize] = true;
        }
    }
    let mut used_positions = vec![false; n];
    for c in 0..corners {
        used_positions[kept.t[c] as usize] = true;
    }
    let mut new_index = vec![NONE; n];
    let mut out_positions = Vec::with_capacity(n);
    let mut fans_at_position = vec![0u32; n];
    for v in 0..n {
        let t = tentative[v] as usize;
        if heads[v] {
            new_index[v] = out_positions.len() as u32;
            out_positions.push(positions[v]);
            fans_at_position[t] += 1;
        } else if !used_positions[t] && t == v {
            // An unused position keeps one vertex, so numbering survives.
            new_index[v] = out_positions.len() as u32;
            out_positions.push(positions[v]);
        }
    }
    report.welded = n - out_positions.len();
    let apart: Vec<usize> = (0..n).filter(|&t| fans_at_position[t] > 1).collect();
    report.kept_apart = apart.iter().map(|&t| fans_at_position[t] as usize - 1).sum();
    listed.touching(apart.len(), apart.iter().map(|&t| positions[t].to_array()));

    let mut out_faces = FaceList::default();
    for face in 0..kept.len() {
        for c in kept.range(face) {
            let root = sets.find(c as u32) as usize;
            out_faces.push_corner(new_index[representative[root] as usize]);
        }
        out_faces.end_face();
    }
    // A weld can still make a face pass through one vertex twice (its own corners glued).
    let mut stamp = vec![NONE; out_positions.len()];
    for (k, face) in out_faces.iter().enumerate() {
        for &v in face {
            if stamp[v as usize] == k as u32 {
                return Err(pinch(kept.source[k] as usize, v, Some(out_positions[v as usize])));
            }
            stamp[v as usize] = k as u32;
        }
    }
    report.warnings = listed.finish(&report);
    Ok(Welded { positions: out_positions, faces: out_faces, report })
}

fn pinch(f: usize, v: u32, welded_at: Option<DVec3>) -> Error {
    let cause = welded_at.map_or(String::new(), |p| {
        format!(" once vertices at the same position are welded (position {:?})", p.to_array())
    });
    Error::Topology(format!(
        "face {f} passes through vertex {v} twice{cause}; the polygon pinches at that vertex, which a cage \
         cannot represent: split the face in two or move one of its corners"
    ))
}

/// The kept faces: per corner the tentative (welded) vertex and the file vertex.
#[derive(Default)]
struct Kept {
    offsets: Vec<u32>,
    t: Vec<u32>,
    orig: Vec<u32>,
    /// The input face each kept face came from.
    source: Vec<u32>,
    /// The kept face of each corner.
    face_of: Vec<u32>,
}

impl Kept {
    fn push(&mut self, source: u32, ring: &[(u32, u32)]) {
        if self.offsets.is_empty() {
            self.offsets.push(0);
        }
        let face = self.source.len() as u32;
        for &(t, o) in ring {
            self.t.push(t);
            self.orig.push(o);
            self.face_of.push(face);
        }
        self.offsets.push(self.t.len() as u32);
        self.source.push(source);
    }

    fn len(&self) -> usize {
        self.source.len()
    }

    fn range(&self, face: usize) -> std::ops::Range<usize> {
        self.offsets[face] as usize..self.offsets[face + 1] as usize
    }

    fn next(&self, face: usize, c: usize) -> usize {
        if c + 1 == self.offsets[face + 1] as usize { self.offsets[face] as usize } else { c + 1 }
    }

    fn next_corner(&self, c: usize) -> usize {
        self.next(self.face_of[c] as usize, c)
    }

    fn cycle(&self, face: usize) -> &[u32] {
        &self.t[self.range(face)]
    }

    /// Keeps the faces whose source passes `keep`, in order.
    fn retain(&mut self, keep: impl Fn(u32) -> bool) {
        let old = std::mem::take(self);
        let mut ring = Vec::new();
        for face in 0..old.len() {
            if keep(old.source[face]) {
                ring.clear();
                ring.extend(old.range(face).map(|c| (old.t[c], old.orig[c])));
                self.push(old.source[face], &ring);
            }
        }
    }
}

/// `(face, earlier face, reversed)` for every kept face whose cycle repeats an earlier one's.
fn find_duplicates(kept: &Kept) -> Vec<(u32, u32, bool)> {
    let mut keyed: Vec<(u64, u32)> =
        (0..kept.len()).into_par_iter().map(|f| (cycle_hash(kept.cycle(f)), f as u32)).collect();
    keyed.par_sort_unstable();
    let mut out = Vec::new();
    let mut dropped = vec![false; kept.len()];
    let mut k = 0;
    while k < keyed.len() {
        let mut end = k + 1;
        while end < keyed.len() && keyed[end].0 == keyed[k].0 {
            end += 1;
        }
        for later in k + 1..end {
            let f = keyed[later].1 as usize;
            let earlier = (k..later)
                .map(|e| keyed[e].1 as usize)
                .filter(|&g| !dropped[g])
                .find_map(|g| same_cycle(kept.cycle(g), kept.cycle(f)).map(|reversed| (g, reversed)));
            if let Some((g, reversed)) = earlier {
                dropped[f] = true;
                out.push((kept.source[f], kept.source[g], reversed));
            }
        }
        k = end;
    }
    out.sort_unstable();
    out
}

/// A hash of a cycle that is the same for every rotation and both orientations.
fn cycle_hash(cycle: &[u32]) -> u64 {
    let mut sorted_pairs: u64 = 0;
    let mut sum: u64 = 0;
    for (k, &v) in cycle.iter().enumerate() {
        let w = cycle[(k + 1) % cycle.len()];
        let (a, b) = (u64::from(v.min(w)), u64::from(v.max(w)));
        sorted_pairs = sorted_pairs.wrapping_add(mix(a << 32 | b));
        sum = sum.wrapping_add(u64::from(v).wrapping_mul(0x9E37_79B9_7F4A_7C15));
    }
    sorted_pairs ^ sum.rotate_left(17) ^ (cycle.len() as u64)
}

/// Per vertex, the first vertex (lowest index) at a bit-for-bit equal position (after mapping
/// −0.0 to 0.0). The positions are bucketed by a hash of their bits (a counting sort, which
/// keeps index order); within a bucket, a few positions in index order, each vertex's first is
/// the earliest one at its position, found among the bucket's distinct positions so far (a
/// bucket with many distinct positions is sorted by bits and index instead). The same answer as
/// one sort of all the positions, in linear time, on any number of threads.
fn first_at_same_position(positions: &[DVec3]) -> Vec<u32> {
    first_at_same_position_searching(positions, 16)
}

/// [`first_at_same_position`] searching at most `linear` distinct positions of a bucket one by
/// one before sorting it instead.
fn first_at_same_position_searching(positions: &[DVec3], linear: usize) -> Vec<u32> {
    let n = positions.len();
    // Adding 0.0 turns −0.0 into 0.0 and leaves every other value alone.
    let bits = |v: u32| (positions[v as usize] + DVec3::ZERO).to_array().map(f64::to_bits);
    let buckets_log2 = (n / 2).max(1).ilog2().min(31);
    let bucket = |b: &[u64; 3]| {
        (mix(b[0] ^ mix(b[1] ^ mix(b[2]))) >> 32 >> (32 - buckets_log2)).min((1 << buckets_log2) - 1) as usize
    };
    let of: Vec<u32> = (0..n as u32).into_par_iter().map(|v| bucket(&bits(v)) as u32).collect();
    let count = 1usize << buckets_log2;
    let (start, mut order) = crate::mesh::edge_sort::bucket_sort(n, count, |v| of[v] as usize, |v| v as u32, 0);
    drop(of);
    // `first[k]` the first vertex at `order[k]`'s position.
    let mut first = vec![0u32; n];
    let mut slices: Vec<(&mut [u32], &mut [u32])> = Vec::with_capacity(count);
    let (mut rest, mut rest_first): (&mut [u32], &mut [u32]) = (&mut order, &mut first);
    for b in 0..count {
        let len = (start[b + 1] - start[b]) as usize;
        let (slice, tail) = rest.split_at_mut(len);
        let (slice_first, tail_first) = rest_first.split_at_mut(len);
        slices.push((slice, slice_first));
        (rest, rest_first) = (tail, tail_first);
    }
    slices.into_par_iter().with_min_len(1 << 12).for_each_init(Vec::new, |heads, (slice, first)| {
        heads.clear();
        for k in 0..slice.len() {
            let key = bits(slice[k]);
            first[k] = match heads.iter().find(|(b, _)| *b == key) {
                Some(&(_, head)) => head,
                None if heads.len() < linear => {
                    heads.push((key, slice[k]));
                    slice[k]
                }
                None => {
                    slice.sort_unstable_by_key(|&v| (bits(v), v));
                    let mut group = 0;
                    for k in 0..slice.len() {
                        if bits(slice[k]) != bits(slice[group]) {
                            group = k;
                        }
                        first[k] = slice[group];
                    }
                    return;
                }
            };
        }
    });
    let mut tentative = vec![0u32; n];
    for (&v, &f) in order.iter().zip(&first) {
        tentative[v as usize] = f;
    }
    tentative
}

/// splitmix64's finaliser: a cheap hash whose every output bit depends on every input bit.
pub(super) fn mix(mut x: u64) -> u64 {
    x = (x ^ (x >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    x = (x ^ (x >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    x ^ (x >> 31)
}

/// `Some(false)` when `b` is `a` rotated, `Some(true)` when it is `a` reversed, else `None`.
fn same_cycle(a: &[u32], b: &[u32]) -> Option<bool> {
    let n = a.len();
    if b.len() != n {
        return None;
    }
    let start = b.iter().position(|&v| v == a[0])?;
    if (0..n).all(|k| a[k] == b[(start + k) % n]) {
        return Some(false);
    }
    if (0..n).all(|k| a[k] == b[(start + n - k) % n]) {
        return Some(true);
    }
    None
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
    let face_count = soup.faces.len();
    let welded = weld_faces(&soup.positions, &soup.faces).map_err(|e| Error::format(path, numbering_note(e, 0)))?;
    drop(soup.faces);
    if welded.faces.is_empty() {
        return Err(Error::format(
            path,
            format!("no faces: all {face_count} faces collapse once vertices at the same position are welded{hint}"),
        ));
    }
    let mut report = welded.report;
    let changed = report.welded + report.kept_apart;
    let mesh = PolyMesh::from_face_list(welded.positions, welded.faces.offsets(), welded.faces.indices())
        .map_err(|e| Error::format(path, numbering_note(e, changed)))?;
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

/// The first few repairs of each kind, listed by face.
#[derive(Default)]
pub(super) struct Listed {
    pub(super) repaired: Vec<String>,
    pub(super) dropped: Vec<String>,
    pub(super) duplicate: Vec<String>,
    pub(super) apart: Vec<String>,
}

/// Lists one more case unless enough of its kind are listed already.
pub(super) fn note(list: &mut Vec<String>, message: impl FnOnce() -> String) {
    if list.len() < LISTED_CASES {
        list.push(message());
    }
}

impl Listed {
    /// Counts face `f` as dropped for repeating face `g`, and lists it among the first few.
    pub(super) fn repeat(&mut self, report: &mut ImportReport, f: u32, g: u32, reversed: bool) {
        report.dropped_faces += 1;
        report.duplicate_faces += 1;
        note(&mut self.duplicate, || {
            if reversed {
                format!("dropped face {f}: it is face {g} facing the other way")
            } else {
                format!("dropped face {f}: it repeats face {g}")
            }
        });
    }

    /// Lists the first few of `count` positions where parts only touch.
    pub(super) fn touching(&mut self, count: usize, positions: impl Iterator<Item = [f64; 3]>) {
        if count == 0 {
            return;
        }
        let shown: Vec<String> = positions.take(LISTED_CASES).map(|p| format!("{p:?}")).collect();
        let more = if count > LISTED_CASES { format!(" and {} more", count - LISTED_CASES) } else { String::new() };
        self.apart
            .push(format!("parts only touch at {}{more}: each keeps a vertex of its own there", shown.join(", ")));
    }

    pub(super) fn finish(self, report: &ImportReport) -> Vec<String> {
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
        out.extend(self.apart);
        out
    }
}

#[cfg(test)]
#[path = "weld_tests.rs"]
mod tests;
