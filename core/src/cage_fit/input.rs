//! The dense input of the cage fitter, cleaned as scans need: [`DenseMesh`].
//!
//! Scans and heavy exports come as triangles that are often not a clean surface: degenerate
//! triangles (a repeated corner), the same triangle twice, neighbours wound the opposite way,
//! edges shared by three or more triangles (fins), and vertices where separate fans touch
//! (bow-ties). The preparation, in order:
//! 1. drops triangles with a repeated or out-of-range corner and repeated triangles (the same
//!    three corners in either orientation);
//! 2. orients every connected piece consistently by a breadth-first walk over edges with two
//!    triangles, flipping neighbours that run the same way (when no two do, as on a clean
//!    surface, the walk would flip nothing, and the pieces are found by joining neighbours
//!    instead); a closed piece enclosing a negative volume is flipped as a whole, so every
//!    closed piece faces outward;
//! 3. cuts every edge that still is not manifold (three or more triangles, or two running the
//!    same way, as on a Möbius band): its triangles stop being neighbours there;
//! 4. splits every vertex whose triangles form several fans (joined only through cut edges or a
//!    bow-tie point) into one copy per fan, at the same position.
//!
//! The result is a manifold, consistently oriented triangle mesh whose geometry is the input's
//! (zero-area triangles with three distinct corners are kept: dropping them would open cracks).
//! Weak where a non-manifold configuration cannot be taken apart this way (a fan that closes
//! around a cut edge onto itself with the wrong orientation): that is refused with a message.

use super::surface_index::SurfaceIndex;
use crate::mesh::PolyMesh;
use crate::mesh::union_find::UnionFind;
use crate::{DVec3, Error, Result};
use rayon::prelude::*;
use serde::Serialize;
use std::collections::HashMap;

/// What the preparation found and changed.
#[derive(Clone, Debug, Default, PartialEq, Eq, Serialize)]
#[non_exhaustive]
pub struct InputReport {
    /// Triangles given.
    pub triangles_in: usize,
    /// Triangles dropped for a repeated corner.
    pub degenerate: usize,
    /// Triangles dropped as repeats of an earlier one.
    pub duplicates: usize,
    /// Triangles kept although their area is zero (three distinct collinear corners).
    pub zero_area: usize,
    /// Triangles flipped to agree with their neighbours or to face outward.
    pub flipped: usize,
    /// Edges cut because they were not manifold.
    pub cut_edges: usize,
    /// Vertex copies added to separate fans.
    pub split_vertices: usize,
    /// Connected pieces of the prepared mesh.
    pub components: usize,
    /// Edges on an open border of the prepared mesh.
    pub border_edges: usize,
}

impl InputReport {
    /// The notable findings as short phrases, for a designer's log (empty for a clean mesh).
    pub fn notes(&self) -> Vec<String> {
        let mut notes = Vec::new();
        let mut say = |n: usize, what: &str| {
            if n > 0 {
                notes.push(format!("{n} {what}"));
            }
        };
        say(self.degenerate, "degenerate triangles dropped");
        say(self.duplicates, "duplicate triangles dropped");
        say(self.zero_area, "zero-area triangles kept");
        say(self.flipped, "triangles flipped to a consistent orientation");
        say(self.cut_edges, "non-manifold edges cut");
        say(self.split_vertices, "vertices split where separate fans met");
        say(self.border_edges, "border edges (the mesh is open; its borders are locked)");
        if self.components > 1 {
            notes.push(format!("{} separate pieces", self.components));
        }
        notes
    }
}

/// A dense triangle mesh ready for fitting: manifold, consistently oriented.
#[derive(Clone, Debug)]
pub struct DenseMesh {
    pub(crate) positions: Vec<DVec3>,
    pub(crate) triangles: Vec<[u32; 3]>,
    pub(crate) report: InputReport,
    /// True when the mesh has no border: volumes are then meaningful.
    pub(crate) closed: bool,
    /// The surface indexed for closest points and ray casts (triangles numbered as here).
    pub(crate) index: std::sync::Arc<SurfaceIndex>,
}

impl DenseMesh {
    /// Prepares indexed triangles as the module doc describes. Fails on non-finite positions, on
    /// an input with no usable triangle, and on a configuration the splitting cannot repair.
    pub fn from_triangles(positions: Vec<DVec3>, triangles: &[[u32; 3]]) -> Result<Self> {
        prepare(positions, triangles)
    }

    /// Prepares a polygon mesh, splitting each face into a fan of triangles.
    pub fn from_mesh(mesh: &PolyMesh) -> Result<Self> {
        prepare(mesh.positions().to_vec(), &mesh.triangles())
    }

    /// Vertex positions (split vertices appended after the input's).
    pub fn positions(&self) -> &[DVec3] {
        &self.positions
    }

    /// The prepared triangles.
    pub fn triangles(&self) -> &[[u32; 3]] {
        &self.triangles
    }

    /// What the preparation found and changed.
    pub fn report(&self) -> &InputReport {
        &self.report
    }

    /// True when the prepared mesh has no open border.
    pub fn is_closed(&self) -> bool {
        self.closed
    }

    /// Signed enclosed volume (sum of origin tetrahedra, positive for outward faces); only a
    /// volume when the mesh is closed.
    pub fn signed_volume(&self) -> f64 {
        signed_volume(&self.positions, &self.triangles)
    }
}

/// Signed volume of triangles about the centroid of their corners (the shift keeps the sum
/// accurate for shapes far from the origin; for a closed surface the value does not depend on it).
pub(crate) fn signed_volume(positions: &[DVec3], triangles: &[[u32; 3]]) -> f64 {
    if positions.is_empty() {
        return 0.0;
    }
    let centre = positions.iter().copied().sum::<DVec3>() / positions.len() as f64;
    triangles
        .iter()
        .map(|t| {
            let [a, b, c] = t.map(|i| positions[i as usize] - centre);
            a.dot(b.cross(c))
        })
        .sum::<f64>()
        / 6.0
}

/// The uses of undirected edges, grouped: each group lists the corners `(triangle, k)` whose
/// edge from corner `k` to corner `k + 1` is that edge. Built by sorting, so its order (and
/// everything decided from it) is the same on every run and thread count.
#[derive(Debug, PartialEq)]
struct EdgeUses {
    /// Corners as `3 t + k`, sorted by edge, then by corner.
    corners: Vec<u32>,
    /// Group `g` is `corners[offsets[g]..offsets[g + 1]]`.
    offsets: Vec<u32>,
    /// The group of each corner.
    group_of: Vec<u32>,
}

impl EdgeUses {
    /// `vertices`: more than any index in `triangles`.
    fn new(triangles: &[[u32; 3]], vertices: usize) -> Self {
        let mut entries: Vec<(u32, u32, u32)> = (0..triangles.len())
            .flat_map(|t| (0..3).map(move |k| (t, k)))
            .map(|(t, k)| {
                let (a, b) = (triangles[t][k], triangles[t][(k + 1) % 3]);
                (a.min(b), a.max(b), (3 * t + k) as u32)
            })
            .collect();
        crate::mesh::edge_sort::sort_sides(&mut entries, vertices);
        let mut offsets = Vec::with_capacity(entries.len() / 2 + 2);
        let mut group_of = vec![0u32; entries.len()];
        for (i, &(lo, hi, c)) in entries.iter().enumerate() {
            if i == 0 || (entries[i - 1].0, entries[i - 1].1) != (lo, hi) {
                offsets.push(i as u32);
            }
            group_of[c as usize] = (offsets.len() - 1) as u32;
        }
        offsets.push(entries.len() as u32);
        EdgeUses { corners: entries.into_iter().map(|(_, _, c)| c).collect(), offsets, group_of }
    }

    /// The uses once the triangles marked in `flipped` have had corners 1 and 2 swapped: exactly
    /// those [`EdgeUses::new`] lists for them (the same edges; a flipped triangle's edge from
    /// corner `k` is its edge from corner `2 − k`), without sorting every corner again.
    fn flipped(mut self, flipped: &[bool]) -> Self {
        let moved = |c: u32| {
            let (t, k) = (c / 3, c % 3);
            if flipped[t as usize] { 3 * t + 2 - k } else { c }
        };
        let group_of = &mut self.group_of;
        let mut regrouped = vec![0u32; group_of.len()];
        for (c, &g) in group_of.iter().enumerate() {
            regrouped[moved(c as u32) as usize] = g;
        }
        *group_of = regrouped;
        for w in self.offsets.windows(2) {
            let group = &mut self.corners[w[0] as usize..w[1] as usize];
            group.iter_mut().for_each(|c| *c = moved(*c));
            group.sort_unstable();
        }
        self
    }

    fn groups(&self) -> impl Iterator<Item = &[u32]> + '_ {
        self.offsets.windows(2).map(|w| &self.corners[w[0] as usize..w[1] as usize])
    }

    fn group_of_corner(&self, corner: u32) -> &[u32] {
        let g = self.group_of[corner as usize] as usize;
        &self.corners[self.offsets[g] as usize..self.offsets[g + 1] as usize]
    }
}

/// True for an edge with one triangle, or two running it opposite ways.
fn is_manifold(uses: &[u32], triangles: &[[u32; 3]]) -> bool {
    match uses {
        [_] => true,
        [c0, c1] => {
            let from = |c: u32| triangles[c as usize / 3][c as usize % 3];
            from(*c0) != from(*c1)
        }
        _ => false,
    }
}

fn prepare(mut positions: Vec<DVec3>, input: &[[u32; 3]]) -> Result<DenseMesh> {
    if let Some(v) = positions.iter().position(|p| !p.is_finite()) {
        return Err(Error::Input(format!(
            "vertex {v} has a non-finite coordinate ({:?}); every coordinate must be a finite number",
            positions[v].to_array()
        )));
    }
    let n = positions.len();
    let mut report = InputReport { triangles_in: input.len(), ..InputReport::default() };
    if let Some((t, &v)) =
        input.iter().enumerate().find_map(|(t, tri)| tri.iter().find(|&&v| v as usize >= n).map(|v| (t, v)))
    {
        return Err(Error::Input(format!("triangle {t} refers to vertex {v}, but there are only {n} vertices")));
    }
    let degenerate = |[a, b, c]: [u32; 3]| a == b || b == c || c == a;
    // A triangle on the same three corners as an earlier one (either orientation) is a repeat:
    // sorted by corners, then by position in the input, each group's first is the one kept.
    let mut keys: Vec<([u32; 3], u32)> = input
        .par_iter()
        .enumerate()
        .filter(|(_, tri)| !degenerate(**tri))
        .map(|(t, tri)| {
            let mut sorted = *tri;
            sorted.sort_unstable();
            (sorted, t as u32)
        })
        .collect();
    keys.par_sort_unstable();
    let mut repeated = vec![false; input.len()];
    for w in keys.windows(2) {
        if w[0].0 == w[1].0 {
            repeated[w[1].1 as usize] = true;
        }
    }
    drop(keys);
    let mut triangles = Vec::with_capacity(input.len());
    for (t, tri) in input.iter().enumerate() {
        if degenerate(*tri) {
            report.degenerate += 1;
            continue;
        }
        if repeated[t] {
            report.duplicates += 1;
            continue;
        }
        let [pa, pb, pc] = tri.map(|i| positions[i as usize]);
        if (pb - pa).cross(pc - pa) == DVec3::ZERO {
            report.zero_area += 1;
        }
        triangles.push(*tri);
    }
    if triangles.is_empty() {
        return Err(Error::Input(format!(
            "no usable triangles: all {} are degenerate or repeated; a cage needs a surface to fit",
            input.len()
        )));
    }
    if report.zero_area == triangles.len() {
        return Err(Error::Input(format!(
            "the surface has no area: its {} triangles all have their corners on a line; a cage needs a surface to fit",
            triangles.len()
        )));
    }

    // The fit's index of the surface is built while the triangles are oriented and split into
    // fans (one thread, mostly): neither changes where the surface is, nor the triangles' order.
    let (index, prepared) = rayon::join(
        || SurfaceIndex::new(&positions, &triangles),
        || -> Result<_> {
            let mut triangles = triangles.clone();
            let mut copies: Vec<DVec3> = Vec::new();
            let uses;
            (report.flipped, uses) = orient(&positions, &mut triangles);
            // Neighbour across corner edge k of triangle t, if that edge is manifold and shared.
            let mut across = vec![[u32::MAX; 3]; triangles.len()];
            for list in uses.groups() {
                if !is_manifold(list, &triangles) {
                    report.cut_edges += 1;
                } else if let [c0, c1] = *list {
                    across[c0 as usize / 3][c0 as usize % 3] = c1 / 3;
                    across[c1 as usize / 3][c1 as usize % 3] = c0 / 3;
                }
            }

            // Split vertices into fans: corners (t, k) at the same vertex are one fan when joined by a
            // chain of manifold edges around it. Union–find over corners.
            let mut fans = UnionFind::new(3 * triangles.len());
            for (t, tri) in triangles.iter().enumerate() {
                for k in 0..3 {
                    let u = across[t][k];
                    if u == u32::MAX || (u as usize) < t {
                        continue;
                    }
                    // The edge runs from corner k to k + 1; both of its ends are shared with u.
                    let other = &triangles[u as usize];
                    for end in [k, (k + 1) % 3] {
                        let v = tri[end];
                        let j =
                            other.iter().position(|&w| w == v).expect("a shared edge has both ends in both triangles");
                        fans.union((3 * t + end) as u32, 3 * u + j as u32);
                    }
                }
            }
            let mut fan_vertex: HashMap<u32, u32> = HashMap::new();
            let mut first_fan = vec![u32::MAX; n];
            for t in 0..triangles.len() {
                for k in 0..3 {
                    let root = fans.find((3 * t + k) as u32);
                    let v = triangles[t][k];
                    if first_fan[v as usize] == u32::MAX {
                        first_fan[v as usize] = root;
                    }
                    if first_fan[v as usize] != root {
                        let copy = *fan_vertex.entry(root).or_insert_with(|| {
                            copies.push(positions[v as usize]);
                            (n + copies.len() - 1) as u32
                        });
                        triangles[t][k] = copy;
                    }
                }
            }
            report.split_vertices = fan_vertex.len();

            // Pieces and borders of the prepared mesh: with no vertex split the triangles are those the
            // uses above were listed from.
            let uses = if fan_vertex.is_empty() { uses } else { EdgeUses::new(&triangles, n + copies.len()) };
            report.border_edges = uses.groups().filter(|u| u.len() == 1).count();
            if let Some(list) = uses.groups().find(|u| !is_manifold(u, &triangles)) {
                let c = list[0] as usize;
                let (a, b) = (triangles[c / 3][c % 3], triangles[c / 3][(c % 3 + 1) % 3]);
                return Err(Error::Topology(format!(
                    "the edge between vertices {a} and {b} is used by {} triangles that cannot be separated; \
                     remove the fin or flip the inconsistent triangles there and try again",
                    list.len()
                )));
            }
            drop(uses);
            report.components = components(&triangles, n + copies.len());
            Ok((triangles, copies))
        },
    );
    let (triangles, copies) = prepared?;
    positions.extend(copies);
    let index = std::sync::Arc::new(index?);
    let closed = report.border_edges == 0;
    Ok(DenseMesh { positions, triangles, report, closed, index })
}

/// Orients each piece consistently (breadth first from its lowest triangle) and flips closed
/// pieces with negative volume; returns the number of triangles flipped and the edge uses of the
/// oriented triangles.
fn orient(positions: &[DVec3], triangles: &mut [[u32; 3]]) -> (usize, EdgeUses) {
    let uses = EdgeUses::new(triangles, positions.len());
    let mut flipped = vec![false; triangles.len()];
    // Each triangle's piece, named by its lowest triangle: triangles joined through edges of two.
    let piece: Vec<u32> = if uses.groups().all(|list| list.len() != 2 || is_manifold(list, triangles)) {
        // No two neighbours run their edge the same way (a clean surface): the walk would flip
        // nothing, and only the pieces are wanted.
        let mut sets = UnionFind::new(triangles.len());
        for list in uses.groups() {
            if let [c0, c1] = *list {
                sets.union(c0 / 3, c1 / 3);
            }
        }
        (0..triangles.len() as u32).map(|t| sets.find(t)).collect()
    } else {
        walk(&uses, triangles, &mut flipped)
    };
    // A piece whose every edge has two triangles encloses a volume: make it positive. Volumes
    // are summed over each piece's triangles in their order, about the centroid of the vertices.
    let mut border = vec![false; triangles.len()];
    for list in uses.groups() {
        if list.len() != 2 {
            for &c in list {
                border[piece[c as usize / 3] as usize] = true;
            }
        }
    }
    let centre = positions.iter().copied().sum::<DVec3>() / positions.len().max(1) as f64;
    let mut volume = vec![0.0; triangles.len()];
    for (tri, &p) in triangles.iter().zip(&piece) {
        if !border[p as usize] {
            let [a, b, c] = tri.map(|i| positions[i as usize] - centre);
            volume[p as usize] += a.dot(b.cross(c));
        }
    }
    for (t, &p) in piece.iter().enumerate() {
        if !border[p as usize] && volume[p as usize] < 0.0 {
            triangles[t].swap(1, 2);
            flipped[t] = !flipped[t];
        }
    }
    let count = flipped.iter().filter(|&&f| f).count();
    (count, uses.flipped(&flipped))
}

/// The breadth-first walk of [`orient`] over triangles whose neighbours may run their edges the
/// same way: from each piece's lowest triangle, every neighbour across an edge of two triangles
/// that runs it the same way is flipped (marked in `flipped`). Returns each triangle's piece,
/// named by its lowest triangle.
fn walk(uses: &EdgeUses, triangles: &mut [[u32; 3]], flipped: &mut [bool]) -> Vec<u32> {
    let original = triangles.to_vec();
    let mut piece = vec![u32::MAX; triangles.len()];
    let mut queue = std::collections::VecDeque::new();
    for start in 0..triangles.len() {
        if piece[start] != u32::MAX {
            continue;
        }
        piece[start] = start as u32;
        queue.push_back(start);
        while let Some(t) = queue.pop_front() {
            for k in 0..3 {
                // The uses were listed before any flip: read corners from the original.
                let list = uses.group_of_corner((3 * t + k) as u32);
                if list.len() != 2 {
                    continue;
                }
                let c = if list[0] as usize / 3 == t { list[1] } else { list[0] };
                let (u, j) = (c as usize / 3, c as usize % 3);
                if piece[u] != u32::MAX {
                    continue;
                }
                // t runs the edge from `a`; consistent neighbours run it from the other end.
                let a = if flipped[t] { original[t][(k + 1) % 3] } else { original[t][k] };
                if original[u][j] == a {
                    triangles[u].swap(1, 2);
                    flipped[u] = true;
                }
                piece[u] = start as u32;
                queue.push_back(u);
            }
        }
    }
    piece
}

/// Number of pieces joined through shared vertices.
fn components(triangles: &[[u32; 3]], n: usize) -> usize {
    let mut sets = UnionFind::new(n);
    for tri in triangles {
        sets.union(tri[0], tri[1]);
        sets.union(tri[0], tri[2]);
    }
    let mut used = vec![false; n];
    for tri in triangles {
        for &v in tri {
            used[v as usize] = true;
        }
    }
    (0..n).filter(|&v| used[v] && sets.is_root(v as u32)).count()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tetra() -> (Vec<DVec3>, Vec<[u32; 3]>) {
        let p = vec![DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::Z];
        (p, vec![[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]])
    }

    #[test]
    fn the_uses_orient_returns_are_those_of_the_oriented_triangles() {
        // A sphere with every third triangle reversed, an inside-out tetrahedron and an open
        // strip: orientation flips triangles of each kind.
        let sphere = crate::mesh::primitives::icosphere(2, 1.0).unwrap();
        let mut p = sphere.positions().to_vec();
        let mut t: Vec<[u32; 3]> = sphere.triangles();
        for (k, tri) in t.iter_mut().enumerate() {
            if k % 3 == 0 {
                tri.swap(0, 1);
            }
        }
        let (tp, tt) = tetra();
        let base = p.len() as u32;
        p.extend(tp.iter().map(|q| *q + DVec3::splat(3.0)));
        t.extend(tt.iter().map(|tri| [tri[0] + base, tri[2] + base, tri[1] + base]));
        let base = p.len() as u32;
        p.extend([
            DVec3::new(5.0, 0.0, 0.0),
            DVec3::new(6.0, 0.0, 0.0),
            DVec3::new(5.0, 1.0, 0.0),
            DVec3::new(6.0, 1.0, 0.0),
        ]);
        t.extend([[base, base + 1, base + 2], [base + 1, base + 2, base + 3]]);
        let mut oriented = t.clone();
        let (flipped, uses) = orient(&p, &mut oriented);
        assert!(flipped > t.len() / 4, "{flipped}");
        assert_ne!(oriented, t);
        assert_eq!(uses, EdgeUses::new(&oriented, p.len()));
    }

    #[test]
    fn a_clean_surface_is_oriented_as_the_walk_would_without_walking() {
        // An outward sphere, an inside-out tetrahedron (consistent, but enclosing a negative
        // volume) and an open strip: no two neighbours run an edge the same way.
        let sphere = crate::mesh::primitives::icosphere(2, 1.0).unwrap();
        let mut p = sphere.positions().to_vec();
        let mut t: Vec<[u32; 3]> = sphere.triangles();
        let (tp, tt) = tetra();
        let (tetra_from, base) = (t.len(), p.len() as u32);
        p.extend(tp.iter().map(|q| *q + DVec3::splat(3.0)));
        t.extend(tt.iter().map(|tri| [tri[0] + base, tri[2] + base, tri[1] + base]));
        let (strip_from, base) = (t.len(), p.len() as u32);
        p.extend([DVec3::new(5.0, 0.0, 0.0), DVec3::new(6.0, 0.0, 0.0), DVec3::new(5.0, 1.0, 0.0)]);
        p.push(DVec3::new(6.0, 1.0, 0.0));
        t.extend([[base, base + 1, base + 2], [base + 1, base + 3, base + 2]]);
        let uses = EdgeUses::new(&t, p.len());
        assert!(uses.groups().all(|list| list.len() != 2 || is_manifold(list, &t)), "a clean surface");
        // The walk flips nothing here and names the pieces by their lowest triangles.
        let (mut walked, mut flipped) = (t.clone(), vec![false; t.len()]);
        let pieces = walk(&uses, &mut walked, &mut flipped);
        assert!(flipped.iter().all(|f| !f) && walked == t);
        let named = |k: usize| {
            if k < tetra_from {
                0
            } else if k < strip_from {
                tetra_from
            } else {
                strip_from
            }
        };
        assert_eq!(pieces, (0..t.len()).map(|k| named(k) as u32).collect::<Vec<_>>());
        // The short way flips the inside-out tetrahedron alone, as the walk's volumes would.
        let mut oriented = t.clone();
        let (count, uses) = orient(&p, &mut oriented);
        assert_eq!(count, 4);
        for (k, (a, b)) in t.iter().zip(&oriented).enumerate() {
            assert_eq!(a == b, !(tetra_from..strip_from).contains(&k), "triangle {k}");
        }
        assert_eq!(uses, EdgeUses::new(&oriented, p.len()));
        let dense = DenseMesh::from_triangles(p, &t).unwrap();
        assert_eq!((dense.report.flipped, dense.report.components, dense.report.border_edges), (4, 3, 4));
    }

    #[test]
    fn a_clean_tetrahedron_passes_unchanged() {
        let (p, t) = tetra();
        let m = DenseMesh::from_triangles(p, &t).unwrap();
        assert_eq!(m.triangles(), &t[..]);
        assert!(m.is_closed());
        assert!((m.signed_volume() - 1.0 / 6.0).abs() < 1e-15);
        assert!(m.report().notes().is_empty(), "{:?}", m.report().notes());
    }

    #[test]
    fn a_surface_without_area_is_refused() {
        let p = vec![DVec3::ZERO, DVec3::X, DVec3::X * 2.0, DVec3::X * 3.0];
        let err = DenseMesh::from_triangles(p.clone(), &[[0, 1, 2], [1, 2, 3]]).unwrap_err().to_string();
        assert!(err.contains("no area") && err.contains("2 triangles"), "{err}");
        // One flat triangle beside a real one is kept (dropping it would open a crack).
        let mut q = p;
        q.push(DVec3::Y);
        let dense = DenseMesh::from_triangles(q, &[[0, 1, 2], [0, 1, 4]]).unwrap();
        assert_eq!(dense.report.zero_area, 1);
    }

    #[test]
    fn flipped_degenerate_and_duplicate_triangles_are_handled() {
        let (p, mut t) = tetra();
        // All inward, one flipped back, plus a degenerate and a duplicate facing the other way.
        for tri in &mut t {
            tri.swap(1, 2);
        }
        t[2].swap(1, 2);
        t.push([1, 1, 2]);
        t.push([3, 2, 1]);
        let m = DenseMesh::from_triangles(p, &t).unwrap();
        let r = m.report();
        assert_eq!((r.degenerate, r.duplicates, r.components, r.border_edges), (1, 1, 1, 0));
        assert!((m.signed_volume() - 1.0 / 6.0).abs() < 1e-15, "{}", m.signed_volume());
        PolyMesh::from_polygons(m.positions().to_vec(), m.triangles()).unwrap();
    }

    #[test]
    fn a_fin_and_a_bow_tie_are_split_into_a_valid_mesh() {
        // Two triangles sharing edge 0-1 plus a fin on the same edge; a second pair touching
        // vertex 2 only (a bow-tie).
        let p = vec![
            DVec3::ZERO,
            DVec3::X,
            DVec3::Y,
            -DVec3::Y,
            DVec3::Z,
            DVec3::new(1.0, 2.0, 0.0),
            DVec3::new(0.0, 2.0, 1.0),
        ];
        let t = vec![[0, 1, 2], [1, 0, 3], [0, 1, 4], [2, 5, 6]];
        let m = DenseMesh::from_triangles(p.clone(), &t).unwrap();
        let r = m.report().clone();
        assert_eq!(r.cut_edges, 1);
        assert!(r.split_vertices >= 2, "{r:?}");
        let mesh = PolyMesh::from_polygons(m.positions().to_vec(), m.triangles()).unwrap();
        mesh.validate().unwrap();
        // Geometry kept: every triangle's corners are at the input's positions.
        for (a, b) in m.triangles().iter().zip(&t) {
            let pa = a.map(|i| m.positions()[i as usize]);
            let pb = b.map(|i| p[i as usize]);
            assert!(pa == pb || pa == [pb[0], pb[2], pb[1]], "{pa:?} vs {pb:?}");
        }
    }

    #[test]
    fn bad_input_is_refused_clearly() {
        let err = DenseMesh::from_triangles(vec![DVec3::ZERO; 3], &[[0, 1, 3]]).unwrap_err().to_string();
        assert!(err.contains("only 3 vertices"), "{err}");
        let err = DenseMesh::from_triangles(vec![DVec3::ZERO, DVec3::X], &[[0, 1, 1]]).unwrap_err().to_string();
        assert!(err.contains("no usable triangles"), "{err}");
        let err =
            DenseMesh::from_triangles(vec![DVec3::NAN, DVec3::X, DVec3::Y], &[[0, 1, 2]]).unwrap_err().to_string();
        assert!(err.contains("non-finite"), "{err}");
    }
}
