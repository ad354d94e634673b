//! The refinement rules of Catmull–Clark and Loop with creases, written once for two uses
//! ([`Sink`]): applied directly to positions (a fresh evaluation, [`refine_into`], and the rows a
//! drag recomputes, [`refine_rows`]), or as stencils from one level to the next (one
//! [`SparseRows`] row per child vertex, in the child numbering of [`SplitTopology`]).
//!
//! Catmull–Clark (Catmull and Clark 1978; `docs/subdivision.md` §1, OpenSubdiv's
//! Catmark rules): face point = centroid; smooth edge point = `(a + b + F0 + F1)/4` with `F` the
//! new face points; smooth vertex point `((n−2)/n) v + (1/n²) Σ e_j + (1/n²) Σ F_j`.
//! Loop (Loop 1987): smooth edge point `3/8 (a + b) + 1/8 (c + d)` with `c, d` the opposite
//! corners, smooth vertex point `(1 − nβ_n) v + β_n Σ e_j` ([`loop_beta`]).
//! Both: a sharp edge (and every boundary edge) gets its midpoint, a crease vertex
//! `(e_a + 6v + e_b)/8` along its two sharp edges (the boundary rule), a corner stays; a
//! semi-sharp edge with `0 < s < 1` blends `s · midpoint + (1 − s) · smooth`, a vertex whose rule
//! changes blends its parent and child masks by the fractional weight ([`super::crease`]).
//!
//! The face points inside the Catmull–Clark edge and vertex rules are expanded into the parent
//! vertices, so one level is one matrix applied to the previous level's positions. These are the
//! plain rules: the valence-dependent weights have no special cases for triangles (OpenSubdiv's
//! `TRI_SUB_SMOOTH`) or for boundary vertices with many faces (the Biermann et al. modifications),
//! so, as with OpenSubdiv's defaults, triangles in a Catmull–Clark cage leave a slight pinch.

use super::crease::{Rule, child_sharpness, fractional_weight, sharp};
use super::loop_limit::loop_beta;
use super::sparse::{RowBuilder, SparseRows};
use super::topology::{SplitTopology, VertexOrigin};
use crate::DVec3;
use crate::mesh::{EdgeId, FaceId, HalfedgeId, PolyMesh, VertexId};
use rayon::prelude::*;

/// The subdivision scheme.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Scheme {
    /// Catmull–Clark: any polygons, quads after one level.
    CatmullClark,
    /// Loop: triangle meshes.
    Loop,
}

/// The stencils making the child level `split` from `parent` with edge sharpness `sharpness`
/// (effective values of the parent level: boundary edges infinite) and vertex sharpness
/// `corners` (one per parent vertex, or none).
pub(crate) fn level_stencils(
    scheme: Scheme,
    parent: &PolyMesh,
    sharpness: &[f64],
    corners: &[f64],
    split: &SplitTopology,
) -> SparseRows {
    let rows = split.mesh.vertex_count();
    SparseRows::build_parallel(parent.vertex_count(), rows, |i, b| {
        child_point(scheme, parent, sharpness, corners, split, i, b)
    })
}

/// The pair across a smooth edge point's edge: the new face points of its two faces
/// (Catmull–Clark) or the two parent vertices opposite it (Loop).
#[derive(Clone, Copy)]
pub(crate) enum Far {
    FacePoints([FaceId; 2]),
    Vertices([u32; 2]),
}

/// Where the rules write a child vertex: as stencil weights on the parent's vertices
/// ([`RowBuilder`]), or applied at once to positions ([`Gather`]).
pub(crate) trait Sink {
    /// Adds `weight` times parent vertex `column`.
    fn add(&mut self, column: u32, weight: f64);
    /// Adds `scale` times the new face point of parent face `f` (its centroid).
    fn add_face_point(&mut self, mesh: &PolyMesh, f: FaceId, scale: f64);

    /// Adds `weight` times each of the parent vertices `columns`.
    #[inline]
    fn add_equal(&mut self, columns: impl Iterator<Item = u32>, weight: f64) {
        for c in columns {
            self.add(c, weight);
        }
    }

    /// Adds `centre` times parent vertex `v` and `weight` times each spoke's end of `ring` and,
    /// with `faces`, each valid spoke face's new face point.
    #[inline]
    fn add_ring(&mut self, mesh: &PolyMesh, v: u32, centre: f64, ring: &[(u32, FaceId)], faces: bool, weight: f64) {
        self.add(v, centre);
        for &(to, f) in ring {
            self.add(to, weight);
            if faces && f.is_valid() {
                self.add_face_point(mesh, f, weight);
            }
        }
    }

    /// Adds `end` times parent vertices `p` and `q` and `across` times each of the pair `far`.
    #[inline]
    fn add_edge(&mut self, mesh: &PolyMesh, [p, q]: [u32; 2], end: f64, far: Far, across: f64) {
        self.add(p, end);
        self.add(q, end);
        match far {
            Far::FacePoints(faces) => faces.map(|f| self.add_face_point(mesh, f, across)),
            Far::Vertices(vertices) => vertices.map(|v| self.add(v, across)),
        };
    }
}

impl Sink for RowBuilder {
    #[inline]
    fn add(&mut self, column: u32, weight: f64) {
        RowBuilder::add(self, column, weight);
    }

    /// A stencil is over the parent's vertices: the face point is expanded into its corners.
    #[inline]
    fn add_face_point(&mut self, mesh: &PolyMesh, f: FaceId, scale: f64) {
        centroid(mesh, f, scale, self);
    }
}

/// The rules applied to positions as they are written, reading face points already made at the
/// child level rather than summing each face again for every edge and vertex point around it
/// (OpenSubdiv's refiner does the same). Rounding therefore differs from applying the stencils
/// (by about 1e-16 relative); [`refine_into`] and [`refine_rows`] share it, so a drag gives the
/// same bits as a fresh evaluation.
struct Gather<'a> {
    points: &'a [DVec3],
    /// The child level's face points, in face-point order.
    face_points: &'a [DVec3],
    split: &'a SplitTopology,
    sum: DVec3,
}

impl Sink for Gather<'_> {
    #[inline]
    fn add(&mut self, column: u32, weight: f64) {
        self.sum += weight * self.points[column as usize];
    }

    #[inline]
    fn add_face_point(&mut self, _: &PolyMesh, f: FaceId, scale: f64) {
        self.sum += scale * self.face_point(f);
    }

    // Applied to positions, terms of equal weight are summed first and scaled once: a third
    // fewer operations for the smooth rules (nearly every child point) than a multiply and an
    // add per term.

    #[inline]
    fn add_equal(&mut self, columns: impl Iterator<Item = u32>, weight: f64) {
        let sum: DVec3 = columns.map(|c| self.points[c as usize]).fold(DVec3::ZERO, |s, x| s + x);
        self.sum += weight * sum;
    }

    #[inline]
    fn add_ring(&mut self, _: &PolyMesh, v: u32, centre: f64, ring: &[(u32, FaceId)], faces: bool, weight: f64) {
        let mut sum = DVec3::ZERO;
        for &(to, f) in ring {
            sum += self.points[to as usize];
            if faces && f.is_valid() {
                sum += self.face_point(f);
            }
        }
        self.sum += centre * self.points[v as usize] + weight * sum;
    }

    #[inline]
    fn add_edge(&mut self, _: &PolyMesh, [p, q]: [u32; 2], end: f64, far: Far, across: f64) {
        let ends = self.points[p as usize] + self.points[q as usize];
        let far = match far {
            Far::FacePoints([f0, f1]) => self.face_point(f0) + self.face_point(f1),
            Far::Vertices([c, d]) => self.points[c as usize] + self.points[d as usize],
        };
        self.sum += end * ends + across * far;
    }
}

impl Gather<'_> {
    /// The child level's face point of parent face `f`.
    #[inline]
    fn face_point(&self, f: FaceId) -> DVec3 {
        let rank = self.split.face_point_rank(f).expect("Catmull–Clark splits every face into quads");
        self.face_points[rank]
    }
}

/// Child points made per rayon task at the least. Small, so that the first levels (thousands of
/// points, a few microseconds of work per task) are still shared between the threads: with
/// 4,096, level 2 of a 2,048-face cage took as long on two threads as on one.
const REFINE_CHUNK: usize = 1024;

/// The positions of the child level `split` from the parent's positions `points`, by the rules
/// applied directly (face points first, then the edge and vertex points that read them), into
/// `out`. Equal to [`level_stencils`] applied to `points` up to rounding.
///
/// `quads`: every face of `parent` is a quad (a level below a Catmull–Clark cage). When it is
/// also closed and smooth (no sharpness tables), each point takes [`smooth_quad_point`], the
/// same terms in the same order without the checks that cannot fire there, so the same bits.
#[allow(clippy::too_many_arguments)]
pub(crate) fn refine_into(
    scheme: Scheme,
    parent: &PolyMesh,
    sharpness: &[f64],
    corners: &[f64],
    split: &SplitTopology,
    quads: bool,
    points: &[DVec3],
    out: &mut Vec<DVec3>,
) {
    let (n, first_face_point) = (split.mesh.vertex_count(), split.first_face_point());
    let smooth_quads = scheme == Scheme::CatmullClark
        && quads
        && sharpness.is_empty()
        && corners.is_empty()
        && parent.halfedge_count() == 4 * parent.face_count();
    let point = |i: usize, face_points: &[DVec3]| {
        let mut gather = Gather { points, face_points, split, sum: DVec3::ZERO };
        if smooth_quads {
            smooth_quad_point(parent, split, i, &mut gather);
        } else {
            child_point(scheme, parent, sharpness, corners, split, i, &mut gather);
        }
        gather.sum
    };
    if out.len() == n {
        // Re-evaluated in place.
        let (near, face_points) = out.split_at_mut(first_face_point);
        face_points
            .par_iter_mut()
            .with_min_len(REFINE_CHUNK)
            .enumerate()
            .for_each(|(k, o)| *o = point(first_face_point + k, &[]));
        let face_points = &*face_points;
        near.par_iter_mut().with_min_len(REFINE_CHUNK).enumerate().for_each(|(i, o)| *o = point(i, face_points));
        return;
    }
    // A fresh buffer: every point written once as it is collected, none cleared first (clearing a
    // fine level's megabytes cost as much as a fifth of its rules); the face points go aside
    // first, since the others read them, and are appended after.
    let face_points: Vec<DVec3> =
        (first_face_point..n).into_par_iter().with_min_len(REFINE_CHUNK).map(|i| point(i, &[])).collect();
    out.clear();
    out.par_extend((0..first_face_point).into_par_iter().with_min_len(REFINE_CHUNK).map(|i| point(i, &face_points)));
    out.par_extend(face_points.par_iter().with_min_len(1 << 14).copied());
}

/// Recomputes rows `rows` (ascending) of the child level `out` as [`refine_into`] computes them:
/// the face points among them first, since the others read them.
#[allow(clippy::too_many_arguments)]
pub(crate) fn refine_rows(
    scheme: Scheme,
    parent: &PolyMesh,
    sharpness: &[f64],
    corners: &[f64],
    split: &SplitTopology,
    points: &[DVec3],
    out: &mut [DVec3],
    rows: &[u32],
) {
    let first_face_point = split.first_face_point();
    let (near_rows, face_rows) = rows.split_at(rows.partition_point(|&r| (r as usize) < first_face_point));
    let (near, face_points) = out.split_at_mut(first_face_point);
    for &r in face_rows {
        let mut gather = Gather { points, face_points: &[], split, sum: DVec3::ZERO };
        child_point(scheme, parent, sharpness, corners, split, r as usize, &mut gather);
        face_points[r as usize - first_face_point] = gather.sum;
    }
    for &r in near_rows {
        let mut gather = Gather { points, face_points, split, sum: DVec3::ZERO };
        child_point(scheme, parent, sharpness, corners, split, r as usize, &mut gather);
        near[r as usize] = gather.sum;
    }
}

/// [`child_point`] of a Catmull–Clark level whose parent is closed, all quads and smooth: the
/// terms [`child_point`] adds there, in its order, without looking up sharpness, boundaries,
/// the point's origin or the face's valence.
#[inline]
fn smooth_quad_point(parent: &PolyMesh, split: &SplitTopology, i: usize, b: &mut Gather) {
    let (nv, first_face_point) = (split.parent_vertex_count(), split.first_face_point());
    let from = |h: HalfedgeId| parent.to_vertex(h.twin()).0;
    if i >= first_face_point {
        // A face point: faces split into quads have theirs in face order (`face_point_rank`).
        let h0 = parent.face_halfedge(FaceId((i - first_face_point) as u32));
        let h1 = parent.next(h0);
        let h2 = parent.next(h1);
        let h3 = parent.next(h2);
        b.add_equal([from(h0), from(h1), from(h2), from(h3)].into_iter(), 0.25);
    } else if i >= nv {
        let e = EdgeId((i - nv) as u32);
        let (h0, h1) = (e.halfedge(0), e.halfedge(1));
        let far = Far::FacePoints([parent.face(h0), parent.face(h1)]);
        b.add_edge(parent, [from(h0), parent.to_vertex(h0).0], 0.25, far, 0.25);
    } else {
        let v = VertexId(i as u32);
        let mut ring = [(0u32, FaceId::INVALID); SPOKES];
        let mut spokes = 0;
        if !parent.is_isolated(v) {
            for h in parent.outgoing(v) {
                if spokes == SPOKES {
                    // More spokes than the ring holds: the general rule.
                    return child_point(Scheme::CatmullClark, parent, &[], &[], split, i, b);
                }
                ring[spokes] = (parent.to_vertex(h).0, parent.face(h));
                spokes += 1;
            }
        }
        if spokes == 0 {
            return b.add(v.0, 1.0);
        }
        ring_smooth_vertex(Scheme::CatmullClark, parent, v, &ring[..spokes], spokes, b);
    }
}

/// The rule of child vertex `i`, written to `b`.
#[inline]
fn child_point(
    scheme: Scheme,
    parent: &PolyMesh,
    sharpness: &[f64],
    corners: &[f64],
    split: &SplitTopology,
    i: usize,
    b: &mut impl Sink,
) {
    match split.origin(VertexId(i as u32)) {
        VertexOrigin::Vertex(v) => {
            let corner = corners.get(v.index()).copied().unwrap_or(0.0);
            vertex_point(scheme, parent, sharpness, corner, v, b)
        }
        VertexOrigin::Edge(e) => edge_point(scheme, parent, sharpness, e, b),
        VertexOrigin::Face(f) => centroid(parent, f, 1.0, b),
    }
}

fn centroid(mesh: &PolyMesh, f: FaceId, scale: f64, b: &mut impl Sink) {
    let w = scale / mesh.face_valence(f) as f64;
    b.add_equal(mesh.face_vertices(f).map(|v| v.0), w);
}

fn edge_point(scheme: Scheme, mesh: &PolyMesh, sharpness: &[f64], e: EdgeId, b: &mut impl Sink) {
    let (p, q) = mesh.edge_vertices(e);
    let crease = sharp(sharpness, e).min(1.0);
    if crease >= 1.0 || mesh.is_boundary_edge(e) {
        b.add(p.0, 0.5);
        b.add(q.0, 0.5);
        return;
    }
    let smooth = 1.0 - crease;
    let (h0, h1) = (e.halfedge(0), e.halfedge(1));
    if crease == 0.0 {
        // Smooth: the same weights as below.
        match scheme {
            Scheme::CatmullClark => {
                b.add_edge(mesh, [p.0, q.0], 0.25, Far::FacePoints([mesh.face(h0), mesh.face(h1)]), 0.25)
            }
            Scheme::Loop => {
                let far = [mesh.to_vertex(mesh.next(h0)).0, mesh.to_vertex(mesh.next(h1)).0];
                b.add_edge(mesh, [p.0, q.0], 0.375, Far::Vertices(far), 0.125)
            }
        }
        return;
    }
    match scheme {
        Scheme::CatmullClark => {
            let end = 0.5 * crease + 0.25 * smooth;
            b.add(p.0, end);
            b.add(q.0, end);
            b.add_face_point(mesh, mesh.face(h0), 0.25 * smooth);
            b.add_face_point(mesh, mesh.face(h1), 0.25 * smooth);
        }
        Scheme::Loop => {
            let end = 0.5 * crease + 0.375 * smooth;
            b.add(p.0, end);
            b.add(q.0, end);
            b.add(mesh.to_vertex(mesh.next(h0)).0, 0.125 * smooth);
            b.add(mesh.to_vertex(mesh.next(h1)).0, 0.125 * smooth);
        }
    }
}

fn vertex_point(scheme: Scheme, mesh: &PolyMesh, sharpness: &[f64], corner: f64, v: VertexId, b: &mut impl Sink) {
    if mesh.is_isolated(v) {
        b.add(v.0, 1.0);
        return;
    }
    let edge_sharpness = || mesh.outgoing(v).map(|h| sharp(sharpness, h.edge()));
    // One walk round `v` counts its spokes, faces and sharp edges and keeps the first
    // `SPOKES` spokes' ends and faces, so a smooth vertex (nearly every one) applies its mask
    // without walking again.
    let (mut spokes, mut faces, mut sharp_edges) = (0, 0, 0);
    let mut ring = [(0u32, FaceId::INVALID); SPOKES];
    for h in mesh.outgoing(v) {
        if spokes < SPOKES {
            ring[spokes] = (mesh.to_vertex(h).0, mesh.face(h));
        }
        spokes += 1;
        faces += usize::from(!mesh.is_boundary_halfedge(h));
        sharp_edges += usize::from(sharp(sharpness, h.edge()) > 0.0);
    }
    let parent_rule = Rule::of(corner, sharp_edges);
    if matches!(parent_rule, Rule::Smooth | Rule::Dart) {
        if spokes <= SPOKES {
            ring_smooth_vertex(scheme, mesh, v, &ring[..spokes], faces, b);
        } else {
            counted_smooth_vertex(scheme, mesh, v, spokes, faces, 1.0, b);
        }
        return;
    }
    let child_corner = child_sharpness(corner);
    let child_rule = Rule::of(child_corner, edge_sharpness().filter(|&s| child_sharpness(s) > 0.0).count());
    if child_rule == parent_rule {
        rule_mask(scheme, mesh, v, parent_rule, |s| s > 0.0, sharpness, 1.0, b);
        return;
    }
    let w = fractional_weight(corner, edge_sharpness());
    rule_mask(scheme, mesh, v, parent_rule, |s| s > 0.0, sharpness, w, b);
    rule_mask(scheme, mesh, v, child_rule, |s| child_sharpness(s) > 0.0, sharpness, 1.0 - w, b);
}

/// The mask of `rule` at `v`, scaled; `is_sharp` picks the crease edges at the level the rule
/// belongs to (parent or child).
fn rule_mask(
    scheme: Scheme,
    mesh: &PolyMesh,
    v: VertexId,
    rule: Rule,
    is_sharp: impl Fn(f64) -> bool,
    sharpness: &[f64],
    scale: f64,
    b: &mut impl Sink,
) {
    match rule {
        Rule::Smooth | Rule::Dart => smooth_vertex(scheme, mesh, v, scale, b),
        Rule::Crease => {
            b.add(v.0, 0.75 * scale);
            for h in mesh.outgoing(v).filter(|h| is_sharp(sharp(sharpness, h.edge()))) {
                b.add(mesh.to_vertex(h).0, 0.125 * scale);
            }
        }
        Rule::Corner => b.add(v.0, scale),
    }
}

fn smooth_vertex(scheme: Scheme, mesh: &PolyMesh, v: VertexId, scale: f64, b: &mut impl Sink) {
    let faces = mesh.outgoing(v).filter(|&h| !mesh.is_boundary_halfedge(h)).count();
    counted_smooth_vertex(scheme, mesh, v, mesh.valence(v), faces, scale, b);
}

/// The most spokes [`vertex_point`] keeps from its counting walk.
const SPOKES: usize = 16;

/// [`counted_smooth_vertex`] (unscaled) from `v`'s spokes' ends and faces in rotation order, as
/// the walk round `v` gives them: the same terms added in the same order, so the same bits.
#[inline]
fn ring_smooth_vertex(
    scheme: Scheme,
    mesh: &PolyMesh,
    v: VertexId,
    ring: &[(u32, FaceId)],
    faces: usize,
    b: &mut impl Sink,
) {
    let n = ring.len();
    match scheme {
        Scheme::CatmullClark => {
            let w = 1.0 / (n * n) as f64;
            b.add_ring(mesh, v.0, 1.0 - (n + faces) as f64 * w, ring, true, w);
        }
        Scheme::Loop => {
            let beta = loop_beta(n);
            b.add_ring(mesh, v.0, 1.0 - n as f64 * beta, ring, false, beta);
        }
    }
}

/// [`smooth_vertex`] with `v`'s valence `n` and its number of faces already counted.
fn counted_smooth_vertex(
    scheme: Scheme,
    mesh: &PolyMesh,
    v: VertexId,
    n: usize,
    faces: usize,
    scale: f64,
    b: &mut impl Sink,
) {
    match scheme {
        Scheme::CatmullClark => {
            let w = scale / (n * n) as f64;
            b.add(v.0, scale - (n + faces) as f64 * w);
            for h in mesh.outgoing(v) {
                b.add(mesh.to_vertex(h).0, w);
                let f = mesh.face(h);
                if f.is_valid() {
                    b.add_face_point(mesh, f, w);
                }
            }
        }
        Scheme::Loop => {
            let beta = loop_beta(n);
            b.add(v.0, scale * (1.0 - n as f64 * beta));
            for u in mesh.vertex_neighbors(v) {
                b.add(u.0, scale * beta);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::DVec3;
    use crate::subdiv::crease::effective_sharpness;
    use crate::subdiv::topology::SplitRule;

    fn cube() -> PolyMesh {
        let p = (0..8).map(|i| DVec3::new((i & 1) as f64, ((i >> 1) & 1) as f64, ((i >> 2) & 1) as f64)).collect();
        let faces = [[0, 2, 3, 1], [4, 5, 7, 6], [0, 1, 5, 4], [2, 6, 7, 3], [0, 4, 6, 2], [1, 3, 7, 5]];
        PolyMesh::from_polygons(p, &faces).unwrap()
    }

    #[test]
    fn every_row_is_affine() {
        let quads = cube();
        let triangles =
            crate::mesh::edit::triangulate(&quads, None, crate::mesh::edit::Triangulation::Fan).unwrap().mesh;
        for (scheme, rule, cage) in
            [(Scheme::CatmullClark, SplitRule::Quads, quads), (Scheme::Loop, SplitRule::Triangles, triangles)]
        {
            let mut s = vec![0.0; cage.edge_count()];
            s[0] = 0.5;
            s[3] = 2.5;
            s[5] = f64::INFINITY;
            let eff = effective_sharpness(&cage, &s).unwrap();
            let split = SplitTopology::split(&cage, rule).unwrap();
            let rows = level_stencils(scheme, &cage, &eff, &[], &split);
            assert_eq!(rows.row_count(), split.mesh.vertex_count());
            for sum in rows.row_sums() {
                assert!((sum - 1.0).abs() < 1e-15, "{scheme:?}: {sum}");
            }
        }
    }
}
