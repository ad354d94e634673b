//! Exact limit positions and limit normals at the vertices of a refined level, as stencils.
//!
//! A smooth vertex (and a dart) is stored as its ring of columns with a weight table shared by
//! every vertex of its valence ([`RingMask`]: the position and both tangents, one gather); any
//! other vertex as one limit-position row and one or more *tangent pairs* `(t1, t2)` of rows. The
//! normal is `t1 × t2` normalised, or with several pairs the normalised sum of their unit normals.
//! So a drag only re-applies the masks ([`LimitStencils::evaluate`], or
//! [`LimitStencils::evaluate_some`] for the vertices it reaches). The rule of a vertex is that of
//! its level's sharp edges ([`Rule`]); a semi-sharp edge still sharp at this level counts as sharp,
//! as in OpenSubdiv's `PrimvarRefiner::Limit`, so the limit of a semi-sharp feature is exact only
//! once the refinement is deeper than its sharpness (a designer's `s ≤ levels`).
//!
//! - Catmull–Clark, smooth vertex of valence `n` on an all-quad level (`docs/subdivision.md`
//!   §2, Halstead, Kass and DeRose 1993): `v* = (n² v + 4 Σ e_j + Σ f_j) /
//!   (n (n + 5))`, tangents `c2 = Σ A_n cos(2πj/n) e_j + (cos(2πj/n) + cos(2π(j+1)/n)) f_j`,
//!   `c3` the same one step round, `A_n = 1 + cos(2π/n) + cos(π/n) √(2 (9 + cos(2π/n)))`.
//! - Loop, smooth vertex (`docs/subdivision.md` §2): `p∞ = (1 − kχ) p + χ Σ p_j`, tangents
//!   `Σ cos(2πj/k) p_j` and `Σ sin(2πj/k) p_j` (Loop 1987; Hoppe et al. 1994).
//! - Dart of an infinitely sharp edge (both schemes): the exact eigenvector masks of
//!   [`super::eigen_masks`] (OpenSubdiv uses the smooth masks, which are not exact there); a dart
//!   of a semi-sharp edge keeps the smooth masks.
//! - Crease and boundary vertices (both schemes): `(e_a + 4v + e_b)/6` along the two sharp edges
//!   (the limit of the cubic B-spline crease curve). Each *sector* of faces between the two sharp
//!   edges, from `e_a` to `e_b` counter-clockwise with `k` faces, gives the tangent pair
//!   `(e_a − e_b, t_across)`, `t_across` the exact cross-crease tangent of the sector pointing
//!   into it, from the eigenvectors of the sector's subdivision matrix ([`super::eigen_masks`];
//!   OpenSubdiv's closed-form masks are exact only for regular sectors). A boundary vertex has one
//!   sector; an interior crease two, whose unit normals are averaged (the surface has a tangent
//!   discontinuity there).
//! - Corners (three or more sharp edges, or a vertex sharpness still left at this level) stay
//!   where they are; a corner has no tangent plane, so its normal is the average
//!   unit normal of the fan of triangles `(v, e_j, e_{j+1})` over its faces.
//! - Degenerate cases: an interior vertex of valence 2 (two faces glued along two edges) uses
//!   the pair `(e_0 − e_1, f_0 − f_1)` (Catmull–Clark) or the fan (Loop); where the geometry makes
//!   every pair vanish (zero-area faces) the normal is the zero vector. Isolated vertices keep
//!   their position and get a zero normal.

use super::crease::Rule;
use super::eigen_masks::{cross_tangent_mask, dart_mask};
use super::loop_limit::loop_limit_chi;
use super::rules::Scheme;
use super::sparse::{RowBuilder, SparseRows, Users};
use super::topology::SplitTopology;
use crate::mesh::{EdgeId, HalfedgeId, PolyMesh, VertexId};
use crate::{DVec3, Error, Result};
use rayon::prelude::*;
use std::f64::consts::{PI, TAU};

/// Limit-position and tangent stencils of one level.
///
/// Smooth and dart vertices of valence ≥ 3 (nearly all of a refined level) are stored as their
/// ring of columns, `[v, e_0, f_0, e_1, f_1, …]` for Catmull–Clark and `[v, e_0, e_1, …]` for Loop,
/// with one weight table per valence shared by all of them ([`RingMask`]): evaluating one gathers
/// each ring point once for the position and both tangents. Every other vertex has a general
/// position row and tangent pairs in [`SparseRows`].
#[derive(Clone, Debug, Default, PartialEq)]
pub struct LimitStencils {
    /// Per vertex: its ring's columns are `ring_columns[ring_offsets[v]..ring_offsets[v + 1]]`
    /// (empty for a general vertex).
    ring_offsets: Vec<u32>,
    ring_columns: Vec<u32>,
    /// Per vertex: its valence (the index of its shared smooth mask), `DART | valence`, or
    /// `GENERAL | index` for the `index`-th general vertex.
    slot: Vec<u32>,
    /// Shared smooth masks, indexed by valence (empty below 3).
    masks: Vec<RingMask>,
    /// Shared dart masks, indexed by valence (empty below 3).
    dart_masks: Vec<RingMask>,
    /// The general vertices in vertex order: one limit position row each.
    general_positions: SparseRows,
    /// Rows `2p`, `2p + 1`: the tangents of pair `p` of the general vertices.
    general_tangents: SparseRows,
    /// General vertex `g`'s pairs are `general_pairs[g]..general_pairs[g + 1]`.
    general_pairs: Vec<u32>,
}

/// Marks a general vertex in [`LimitStencils::slot`].
const GENERAL: u32 = 1 << 31;
/// Marks a dart in [`LimitStencils::slot`].
const DART: u32 = 1 << 30;

/// The weights of the limit position and both tangents over a smooth vertex's ring.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct RingMask {
    /// Per ring column: the weights of the limit position, the first tangent and the second
    /// (`t1 × t2` is the outward normal for counter-clockwise faces).
    pub weights: Vec<[f64; 3]>,
    /// Whether this is the smooth mask of a regular vertex (valence 4 for Catmull–Clark, 6 for
    /// Loop), applied by [`regular_quad_sums`] or [`regular_triangle_sums`].
    regular: Option<Scheme>,
}

impl RingMask {
    /// A mask of the given weights, applied term by term.
    pub(crate) fn from_weights(weights: Vec<[f64; 3]>) -> Self {
        RingMask { weights, regular: None }
    }
}

impl RingMask {
    /// The mask of a smooth vertex of valence `n ≥ 2` (see the module documentation; at `n = 2`
    /// the tangents vanish).
    pub fn smooth(scheme: Scheme, n: usize) -> Self {
        let nf = n as f64;
        let angle = |j: usize| TAU * (j % n) as f64 / nf;
        let mut weights = Vec::with_capacity(2 * n + 1);
        match scheme {
            Scheme::CatmullClark => {
                let d = nf * (nf + 5.0);
                let c = (TAU / nf).cos();
                let a = 1.0 + c + (PI / nf).cos() * (2.0 * (9.0 + c)).sqrt();
                weights.push([nf * nf / d, 0.0, 0.0]);
                for j in 0..n {
                    // c2 weighs e_j by A cos(2πj/n) and f_j by cos(2πj/n) + cos(2π(j+1)/n); c3 is
                    // the same mask one step round.
                    let (cj, cj1) = (angle(j).cos(), angle(j + 1).cos());
                    let (cp, cp1) = (angle(j + n - 1).cos(), cj);
                    weights.push([4.0 / d, a * cj, a * cp]);
                    weights.push([1.0 / d, cj + cj1, cp + cp1]);
                }
            }
            Scheme::Loop => {
                let chi = loop_limit_chi(n);
                weights.push([1.0 - nf * chi, 0.0, 0.0]);
                for j in 0..n {
                    let (sin, cos) = angle(j).sin_cos();
                    weights.push([chi, cos, sin]);
                }
            }
        }
        let regular = match (scheme, n) {
            (Scheme::CatmullClark, 4) | (Scheme::Loop, 6) => Some(scheme),
            _ => None,
        };
        RingMask { weights, regular }
    }
}

/// Vertices below this count are evaluated on one thread.
const PARALLEL_VERTICES: usize = 8192;

/// The ring columns of `v` into `ring` when it is a smooth or dart vertex of valence ≥ 3 (its
/// limit comes from a shared [`RingMask`]), a dart's ring starting at its sharp edge; its slot
/// (valence, or `DART | valence` for an infinitely sharp dart edge), or `None` for a general
/// vertex.
fn smooth_ring(
    scheme: Scheme,
    mesh: &PolyMesh,
    sharpness: &impl Fn(EdgeId) -> f64,
    v: VertexId,
    ring: &mut Vec<u32>,
) -> Option<u32> {
    if mesh.is_isolated(v) || mesh.is_boundary_vertex(v) {
        return None;
    }
    // One walk round the vertex gathers the ring and counts the sharp edges.
    let mut walk = RingWalk::new(scheme, v, ring);
    for h in mesh.outgoing(v) {
        walk.spoke(ring, sharpness(h.edge()), mesh.to_vertex(h).0, mesh.to_vertex(mesh.next(h)).0);
    }
    walk.finish(ring)
}

/// [`smooth_ring`] of vertex `v` of a Catmull–Clark level split from `parent` by `split`, its
/// spokes read from the parent ([`SplitTopology::quad_spokes`]) instead of walked round the level.
fn derived_smooth_ring(
    parent: &PolyMesh,
    split: &SplitTopology,
    sharpness: &[f64],
    v: VertexId,
    ring: &mut Vec<u32>,
) -> Option<u32> {
    let mut walk = RingWalk::new(Scheme::CatmullClark, v, ring);
    let sharp = |e: Option<EdgeId>| e.map_or(0.0, |e| super::crease::sharp(sharpness, e));
    if !split.quad_spokes(parent, v, |e, to, across| walk.spoke(ring, sharp(e), to, across)) {
        ring.truncate(walk.first);
        return None;
    }
    walk.finish(ring)
}

/// A smooth ring being gathered spoke by spoke, counting the sharp edges on the way.
struct RingWalk {
    /// Where the ring starts in the columns.
    first: usize,
    /// Columns per spoke: the edge neighbour, and for Catmull–Clark the quad's far corner.
    stride: usize,
    spokes: usize,
    sharp: usize,
    /// The last sharp spoke, and whether it is infinitely sharp.
    start: usize,
    infinite: bool,
}

impl RingWalk {
    fn new(scheme: Scheme, v: VertexId, ring: &mut Vec<u32>) -> Self {
        let first = ring.len();
        ring.push(v.0);
        let stride = if scheme == Scheme::CatmullClark { 2 } else { 1 };
        RingWalk { first, stride, spokes: 0, sharp: 0, start: 0, infinite: false }
    }

    /// The next spoke: its edge's sharpness, its end and the vertex across the face after it.
    #[inline]
    fn spoke(&mut self, ring: &mut Vec<u32>, sharpness: f64, to: u32, across: u32) {
        if sharpness > 0.0 {
            self.sharp += 1;
            self.start = self.spokes;
            self.infinite = sharpness == f64::INFINITY;
        }
        ring.push(to);
        if self.stride == 2 {
            ring.push(across);
        }
        self.spokes += 1;
    }

    fn finish(self, ring: &mut Vec<u32>) -> Option<u32> {
        let n = self.spokes;
        if n < 3 || self.sharp > 1 {
            ring.truncate(self.first);
            return None;
        }
        // A dart's ring starts at its sharp edge.
        ring[self.first + 1..].rotate_left(self.stride * self.start);
        // A semi-sharp dart edge runs out further down, so its limit is nearer the smooth one.
        Some(if self.infinite { DART | n as u32 } else { n as u32 })
    }
}

#[inline]
fn apply_ring(mask: &RingMask, columns: &[u32], points: &[DVec3]) -> (DVec3, DVec3) {
    let (p, cross) = ring_sums(mask, columns, points);
    (p, cross.normalize_or_zero())
}

/// The limit position and the tangents' cross product (not yet normalised, its length
/// arbitrary) of a ring.
#[inline]
fn ring_sums(mask: &RingMask, columns: &[u32], points: &[DVec3]) -> (DVec3, DVec3) {
    match mask.regular {
        Some(Scheme::CatmullClark) => return regular_quad_sums(columns, points),
        Some(Scheme::Loop) => return regular_triangle_sums(mask, columns, points),
        None => {}
    }
    let (mut p, mut t1, mut t2) = (DVec3::ZERO, DVec3::ZERO, DVec3::ZERO);
    for (&c, w) in columns.iter().zip(&mask.weights) {
        let x = points[c as usize];
        p += w[0] * x;
        t1 += w[1] * x;
        t2 += w[2] * x;
    }
    (p, t1.cross(t2))
}

/// [`ring_sums`] of a smooth Catmull–Clark vertex of valence 4, ring `[v, e_0, f_0, …, e_3, f_3]`:
/// the mask of [`RingMask::smooth`] with its weights' exact values (`A_4 = 4`, the cosines 0 and
/// ±1) and the equal terms gathered, `v* = (16 v + 4 Σ e_j + Σ f_j) / 36`, `c2 = 4 (e_0 − e_2) +
/// (f_0 − f_2) + (f_3 − f_1)`, `c3 = 4 (e_1 − e_3) + (f_0 − f_2) − (f_3 − f_1)`: a third of the
/// arithmetic of the general sum, for nearly every vertex of a refined level.
#[inline]
fn regular_quad_sums(columns: &[u32], points: &[DVec3]) -> (DVec3, DVec3) {
    let &[v, e0, f0, e1, f1, e2, f2, e3, f3] = columns else { unreachable!("a valence-4 ring has 9 columns") };
    let x = |c: u32| points[c as usize];
    let (e0, e1, e2, e3) = (x(e0), x(e1), x(e2), x(e3));
    let (f0, f1, f2, f3) = (x(f0), x(f1), x(f2), x(f3));
    let p = ((4.0 * x(v) + ((e0 + e1) + (e2 + e3))) * 4.0 + ((f0 + f1) + (f2 + f3))) * (1.0 / 36.0);
    let (across, turn) = (f0 - f2, f3 - f1);
    let c2 = 4.0 * (e0 - e2) + (across + turn);
    let c3 = 4.0 * (e1 - e3) + (across - turn);
    (p, c2.cross(c3))
}

/// [`ring_sums`] of a smooth Loop vertex of valence 6, ring `[v, e_0, …, e_5]`: the mask of
/// [`RingMask::smooth`] with the cosines' and sines' exact values and the equal terms gathered,
/// `p∞ = (1 − 6χ) v + χ Σ e_j`, tangents `(e_0 − e_3) + ½ ((e_1 − e_2) + (e_5 − e_4))` and
/// `(e_1 + e_2) − (e_4 + e_5)` (the second's factor `√3/2` dropped: only the normal's direction
/// is used).
#[inline]
fn regular_triangle_sums(mask: &RingMask, columns: &[u32], points: &[DVec3]) -> (DVec3, DVec3) {
    let &[v, e0, e1, e2, e3, e4, e5] = columns else { unreachable!("a valence-6 ring has 7 columns") };
    let x = |c: u32| points[c as usize];
    let (e0, e1, e2, e3, e4, e5) = (x(e0), x(e1), x(e2), x(e3), x(e4), x(e5));
    let (centre, chi) = (mask.weights[0][0], mask.weights[1][0]);
    let p = centre * x(v) + chi * (((e0 + e1) + (e2 + e3)) + (e4 + e5));
    let t1 = (e0 - e3) + 0.5 * ((e1 - e2) + (e5 - e4));
    let t2 = (e1 + e2) - (e4 + e5);
    (p, t1.cross(t2))
}

/// The unit normal from tangent pairs `pairs` of `tangents` (rows `2p`, `2p + 1`).
#[inline]
fn pairs_normal(tangents: &SparseRows, pairs: std::ops::Range<usize>, points: &[DVec3]) -> DVec3 {
    let cross = |p: usize| tangents.apply_row(2 * p, points).cross(tangents.apply_row(2 * p + 1, points));
    if pairs.len() == 1 {
        cross(pairs.start).normalize_or_zero()
    } else {
        pairs.map(|p| cross(p).normalize_or_zero()).sum::<DVec3>().normalize_or_zero()
    }
}

impl LimitStencils {
    /// The limit stencils of every vertex of `mesh` under `scheme`, with `sharpness` the
    /// effective sharpness of its edges (see [`super::crease::effective_sharpness`]). Catmull–Clark
    /// needs an all-quad mesh (any level ≥ 1), Loop a triangle mesh.
    pub fn new(scheme: Scheme, mesh: &PolyMesh, sharpness: &[f64]) -> Result<Self> {
        LimitStencils::with_corners(scheme, mesh, sharpness, &[])
    }

    /// [`LimitStencils::new`] with vertex sharpness `corners` (one per vertex, or none): a vertex
    /// still sharp at this level is a corner and stays where it is.
    pub fn with_corners(scheme: Scheme, mesh: &PolyMesh, sharpness: &[f64], corners: &[f64]) -> Result<Self> {
        check_faces(scheme, mesh)?;
        if sharpness.len() != mesh.edge_count() {
            return Err(Error::Input(format!(
                "{} sharpness values for a level of {} edges; give one per edge",
                sharpness.len(),
                mesh.edge_count()
            )));
        }
        const CHUNK: usize = 4096;
        let n = mesh.vertex_count();
        let sharp = |e: EdgeId| sharpness[e.index()];
        let chunks: Vec<LimitStencils> = (0..n.div_ceil(CHUNK))
            .into_par_iter()
            .map(|c| {
                let mut out = LimitStencils {
                    general_positions: SparseRows::with_columns(n),
                    general_tangents: SparseRows::with_columns(n),
                    ..Default::default()
                };
                let mut scratch = Scratch::default();
                for v in c * CHUNK..((c + 1) * CHUNK).min(n) {
                    let before = out.ring_columns.len();
                    let corner = corners.get(v).is_some_and(|&s| s > 0.0);
                    let ring = if corner {
                        None
                    } else {
                        smooth_ring(scheme, mesh, &sharp, VertexId(v as u32), &mut out.ring_columns)
                    };
                    if let Some(slot) = ring {
                        out.slot.push(slot);
                    } else {
                        out.slot.push(GENERAL | out.general_pairs.len() as u32);
                        let pairs = vertex_masks(scheme, mesh, sharp, corner, VertexId(v as u32), &mut scratch);
                        scratch.position.push_into(&mut out.general_positions);
                        for pair in &mut scratch.pairs[..pairs] {
                            pair[0].push_into(&mut out.general_tangents);
                            pair[1].push_into(&mut out.general_tangents);
                        }
                        out.general_pairs.push(pairs as u32);
                    }
                    out.ring_offsets.push((out.ring_columns.len() - before) as u32);
                }
                out
            })
            .collect();
        let mut out = LimitStencils {
            ring_offsets: vec![0],
            general_positions: SparseRows::with_columns(n),
            general_tangents: SparseRows::with_columns(n),
            general_pairs: vec![0],
            ..Default::default()
        };
        for chunk in &chunks {
            let general_base = out.general_pairs.len() as u32 - 1;
            for (&slot, &len) in chunk.slot.iter().zip(&chunk.ring_offsets) {
                out.slot.push(if slot & GENERAL != 0 { slot + general_base } else { slot });
                let last = *out.ring_offsets.last().unwrap();
                out.ring_offsets.push(last + len);
            }
            out.ring_columns.extend_from_slice(&chunk.ring_columns);
            out.general_positions.append(&chunk.general_positions);
            out.general_tangents.append(&chunk.general_tangents);
            for &count in &chunk.general_pairs {
                let last = *out.general_pairs.last().unwrap();
                out.general_pairs.push(last + count);
            }
        }
        let max_valence = |dart: bool| {
            let slots = out.slot.iter().filter(|&&s| s & GENERAL == 0 && (s & DART != 0) == dart);
            slots.map(|&s| (s & !DART) as usize).max().unwrap_or(0)
        };
        let (smooth, darts) = (max_valence(false), max_valence(true));
        out.masks =
            (0..=smooth).map(|k| if k < 3 { RingMask::default() } else { RingMask::smooth(scheme, k) }).collect();
        out.dart_masks = (0..=darts).map(|k| if k < 3 { RingMask::default() } else { dart_mask(scheme, k) }).collect();
        Ok(out)
    }

    /// Number of vertices.
    pub fn vertex_count(&self) -> usize {
        self.slot.len()
    }

    /// Bytes of the stored arrays.
    pub fn memory_bytes(&self) -> usize {
        4 * (self.ring_offsets.len() + self.ring_columns.len() + self.slot.len() + self.general_pairs.len())
            + self.general_positions.memory_bytes()
            + self.general_tangents.memory_bytes()
    }

    /// The limit-position matrix: row `v` maps the level's positions to vertex `v`'s limit.
    pub fn position_rows(&self) -> SparseRows {
        let columns = self.general_positions.column_count;
        SparseRows::build_parallel(columns, self.vertex_count(), |v, b| {
            let slot = self.slot[v];
            if slot & GENERAL != 0 {
                for (c, w) in self.general_positions.row((slot & !GENERAL) as usize) {
                    b.add(c, w);
                }
            } else {
                let cols = &self.ring_columns[self.ring_offsets[v] as usize..self.ring_offsets[v + 1] as usize];
                for (&c, w) in cols.iter().zip(&self.ring_mask(slot).weights) {
                    b.add(c, w[0]);
                }
            }
        })
    }

    /// For every vertex of the level, the vertices whose limit position or normal reads it.
    pub fn users(&self) -> Users {
        // The columns each vertex reads, without repeats: a general vertex's position and
        // tangent rows may share columns.
        Users::from_rows(self.vertex_count(), self.vertex_count(), |v, out| {
            let slot = self.slot[v];
            out.extend_from_slice(&self.ring_columns[self.ring_offsets[v] as usize..self.ring_offsets[v + 1] as usize]);
            if slot & GENERAL != 0 {
                let g = (slot & !GENERAL) as usize;
                out.extend(self.general_positions.row(g).map(|(c, _)| c));
                for t in 2 * self.general_pairs[g] as usize..2 * self.general_pairs[g + 1] as usize {
                    out.extend(self.general_tangents.row(t).map(|(c, _)| c));
                }
                out.sort_unstable();
                out.dedup();
            }
        })
    }

    /// Recomputes the limit position and normal of the vertices `dirty` only.
    pub fn evaluate_some(&self, points: &[DVec3], dirty: &[u32], limit: &mut [DVec3], normals: &mut [DVec3]) {
        for &v in dirty {
            (limit[v as usize], normals[v as usize]) = self.vertex(v as usize, points);
        }
    }

    /// The shared mask of a ring vertex's slot.
    #[inline]
    fn ring_mask(&self, slot: u32) -> &RingMask {
        if slot & DART != 0 { &self.dart_masks[(slot & !DART) as usize] } else { &self.masks[slot as usize] }
    }

    /// The limit position and unit limit normal of vertex `v`.
    #[inline]
    fn vertex(&self, v: usize, points: &[DVec3]) -> (DVec3, DVec3) {
        let slot = self.slot[v];
        if slot & GENERAL == 0 {
            let cols = &self.ring_columns[self.ring_offsets[v] as usize..self.ring_offsets[v + 1] as usize];
            apply_ring(self.ring_mask(slot), cols, points)
        } else {
            let g = (slot & !GENERAL) as usize;
            let pairs = self.general_pairs[g] as usize..self.general_pairs[g + 1] as usize;
            let normal =
                if pairs.is_empty() { DVec3::ZERO } else { pairs_normal(&self.general_tangents, pairs, points) };
            (self.general_positions.apply_row(g, points), normal)
        }
    }

    /// Limit positions and unit limit normals of the level whose positions are `points`.
    pub fn evaluate(&self, points: &[DVec3], limit: &mut Vec<DVec3>, normals: &mut Vec<DVec3>) {
        assert_eq!(points.len(), self.general_positions.column_count, "limit stencils applied to another level");
        limit.resize(self.vertex_count(), DVec3::ZERO);
        normals.resize(self.vertex_count(), DVec3::ZERO);
        if limit.len() < PARALLEL_VERTICES {
            for (v, (p, n)) in limit.iter_mut().zip(normals.iter_mut()).enumerate() {
                (*p, *n) = self.vertex(v, points);
            }
        } else {
            limit.par_iter_mut().zip(normals.par_iter_mut()).with_min_len(4096).enumerate().for_each(|(v, (p, n))| {
                (*p, *n) = self.vertex(v, points);
            });
        }
    }
}

/// The Catmull–Clark limit position and unit limit normal of vertex `v` of an all-quad mesh
/// without creases (boundaries by the boundary rules). For the curve-mesh work, which needs a few
/// vertices at a time; the same masks as [`LimitStencils`].
pub fn catmull_clark_limit(mesh: &PolyMesh, v: VertexId) -> Result<(DVec3, DVec3)> {
    if v.index() >= mesh.vertex_count() {
        return Err(Error::Input(format!("vertex {} is not in a mesh of {} vertices", v.0, mesh.vertex_count())));
    }
    if let Some(h) = mesh.outgoing(v).find(|&h| mesh.face(h).is_valid() && mesh.face_valence(mesh.face(h)) != 4) {
        return Err(Error::Topology(format!(
            "the Catmull–Clark limit at vertex {} needs quads around it, but face {} has {} sides; subdivide once first",
            v.0,
            mesh.face(h).0,
            mesh.face_valence(mesh.face(h))
        )));
    }
    let sharpness = |e: EdgeId| if mesh.is_boundary_edge(e) { f64::INFINITY } else { 0.0 };
    let p = mesh.positions();
    let mut ring = Vec::new();
    if let Some(n) = smooth_ring(Scheme::CatmullClark, mesh, &sharpness, v, &mut ring) {
        return Ok(apply_ring(&RingMask::smooth(Scheme::CatmullClark, n as usize), &ring, p));
    }
    let mut scratch = Scratch::default();
    let pairs = vertex_masks(Scheme::CatmullClark, mesh, sharpness, false, v, &mut scratch);
    let mut position = SparseRows::with_columns(mesh.vertex_count());
    scratch.position.push_into(&mut position);
    let mut tangents = SparseRows::with_columns(mesh.vertex_count());
    for pair in &mut scratch.pairs[..pairs] {
        pair[0].push_into(&mut tangents);
        pair[1].push_into(&mut tangents);
    }
    let normal = if pairs == 0 { DVec3::ZERO } else { pairs_normal(&tangents, 0..pairs, p) };
    Ok((position.apply_row(0, p), normal))
}

/// Whether `mesh` is a level limit stencils can be made on: all quads (Catmull–Clark) or all
/// triangles (Loop).
pub(crate) fn check_faces(scheme: Scheme, mesh: &PolyMesh) -> Result<()> {
    let (sides, name, fix) = match scheme {
        Scheme::CatmullClark => (4, "Catmull–Clark limit positions need an all-quad level", "subdivide at least once"),
        Scheme::Loop => (3, "Loop subdivision needs a triangle cage", "triangulate the cage first"),
    };
    match mesh.faces().find(|&f| mesh.face_valence(f) != sides) {
        Some(f) => Err(Error::Topology(format!("{name}, but face {} has {} sides; {fix}", f.0, mesh.face_valence(f)))),
        None => Ok(()),
    }
}

/// Reusable row builders for one vertex's masks.
#[derive(Default)]
struct Scratch {
    ring: Vec<HalfedgeId>,
    sharp: Vec<bool>,
    position: RowBuilder,
    pairs: Vec<[RowBuilder; 2]>,
}

/// The builders of pair `k`, made when missing.
fn pair(pairs: &mut Vec<[RowBuilder; 2]>, k: usize) -> &mut [RowBuilder; 2] {
    if pairs.len() <= k {
        pairs.resize_with(k + 1, Default::default);
    }
    &mut pairs[k]
}

/// Fills `s.position` and the first pairs of `s.pairs` with the masks of `v`; returns the number
/// of pairs.
fn vertex_masks(
    scheme: Scheme,
    mesh: &PolyMesh,
    sharpness: impl Fn(EdgeId) -> f64,
    corner: bool,
    v: VertexId,
    s: &mut Scratch,
) -> usize {
    let Scratch { ring, sharp, position, pairs } = s;
    if mesh.is_isolated(v) {
        position.add(v.0, 1.0);
        return 0;
    }
    ring.clear();
    ring.extend(mesh.outgoing(v));
    sharp.clear();
    sharp.extend(ring.iter().map(|h| sharpness(h.edge()) > 0.0));
    let n = ring.len();
    let e = |j: usize| mesh.to_vertex(ring[j % n]).0;
    // The vertex across the face after edge j from v (a quad's diagonal, a triangle's e_{j+1}).
    let f = |j: usize| mesh.to_vertex(mesh.next(ring[j % n])).0;
    match Rule::of(if corner { 1.0 } else { 0.0 }, sharp.iter().filter(|&&x| x).count()) {
        Rule::Smooth | Rule::Dart => {
            // Valence ≥ 3 takes the shared ring masks ([`smooth_ring`]); what reaches here is an
            // interior vertex of valence 2 (two faces glued along two edges), whose smooth
            // tangent masks vanish: the position mask is kept, the tangents are stand-ins.
            let mask = RingMask::smooth(scheme, n);
            position.add(v.0, mask.weights[0][0]);
            let stride = if scheme == Scheme::CatmullClark { 2 } else { 1 };
            for j in 0..n {
                position.add(e(j), mask.weights[1 + stride * j][0]);
                if scheme == Scheme::CatmullClark {
                    position.add(f(j), mask.weights[2 + stride * j][0]);
                }
            }
            if scheme == Scheme::Loop || n != 2 {
                return fan(mesh, v, ring, pairs);
            }
            let [t1, t2] = pair(pairs, 0);
            t1.add(e(0), 1.0);
            t1.add(e(1), -1.0);
            t2.add(f(0), 1.0);
            t2.add(f(1), -1.0);
            1
        }
        Rule::Crease => {
            position.add(v.0, 4.0 / 6.0);
            for j in (0..n).filter(|&j| sharp[j]) {
                position.add(e(j), 1.0 / 6.0);
            }
            let mut count = 0;
            for i in (0..n).filter(|&i| sharp[i]) {
                // The sector runs counter-clockwise from sharp edge i to the next sharp edge; the
                // gap outside a boundary is no sector.
                if mesh.is_boundary_halfedge(ring[i]) {
                    continue;
                }
                let k = (1..=n).find(|&t| sharp[(i + t) % n]).unwrap_or(n);
                let [along, across] = pair(pairs, count);
                along.add(e(i), 1.0);
                along.add(e(i + k), -1.0);
                cross_crease_tangent(scheme, v.0, k, |t| e(i + t), |t| f(i + t), across);
                count += 1;
            }
            count
        }
        Rule::Corner => {
            position.add(v.0, 1.0);
            fan(mesh, v, ring, pairs)
        }
    }
}

/// The tangent pairs `(e_j − v, e_{j+1} − v)` of every face at `v`.
fn fan(mesh: &PolyMesh, v: VertexId, ring: &[HalfedgeId], pairs: &mut Vec<[RowBuilder; 2]>) -> usize {
    let n = ring.len();
    let mut count = 0;
    for j in 0..n {
        if mesh.is_boundary_halfedge(ring[j]) {
            continue;
        }
        let (a, b) = (mesh.to_vertex(ring[j]).0, mesh.to_vertex(ring[(j + 1) % n]).0);
        let [t1, t2] = pair(pairs, count);
        t1.add(a, 1.0);
        t1.add(v.0, -1.0);
        t2.add(b, 1.0);
        t2.add(v.0, -1.0);
        count += 1;
    }
    count
}

/// Adds the cross-crease tangent of a sector of `k` faces whose edge neighbours are `e(0..=k)`
/// (`e(0)`, `e(k)` on the crease) and whose face `t` (between `e(t)` and `e(t+1)`) has the vertex
/// `f(t)` across from `v` (Catmull–Clark only).
fn cross_crease_tangent(
    scheme: Scheme,
    v: u32,
    k: usize,
    e: impl Fn(usize) -> u32,
    f: impl Fn(usize) -> u32,
    t: &mut RowBuilder,
) {
    let mask = cross_tangent_mask(scheme, k);
    t.add(v, mask[0]);
    for i in 0..=k {
        t.add(e(i), mask[1 + i]);
    }
    if scheme == Scheme::CatmullClark {
        for i in 0..k {
            t.add(f(i), mask[k + 2 + i]);
        }
    }
}

#[path = "limit_direct.rs"]
mod direct;
pub(crate) use direct::limit_into;
