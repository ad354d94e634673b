//! Exact limit positions and limit normals at the vertices of a refined level, as stencils.
//!
//! For every vertex the limit position is one [`SparseRows`] row over the level's positions, and
//! the limit normal comes from one or more *tangent pairs* `(t1, t2)` (two more rows each): the
//! normal is `t1 × t2` normalised, or with several pairs the normalised sum of their unit normals.
//! So a drag only re-applies the rows ([`LimitStencils::evaluate`]). The rule of a vertex is that
//! of its level's sharp edges ([`Rule`]); a semi-sharp edge still sharp at this level counts as
//! sharp, as in OpenSubdiv's `PrimvarRefiner::Limit`.
//!
//! - Catmull–Clark, smooth or dart vertex of valence `n` on an all-quad level (spec
//!   `curve-mesh-gregory.md` §2, Halstead, Kass and DeRose 1993): `v* = (n² v + 4 Σ e_j + Σ f_j) /
//!   (n (n + 5))`, tangents `c2 = Σ A_n cos(2πj/n) e_j + (cos(2πj/n) + cos(2π(j+1)/n)) f_j`,
//!   `c3` the same one step round, `A_n = 1 + cos(2π/n) + cos(π/n) √(2 (9 + cos(2π/n)))`.
//! - Loop, smooth or dart vertex (`control-cage.md`): `p∞ = (1 − kχ) p + χ Σ p_j`, tangents
//!   `Σ cos(2πj/k) p_j` and `Σ sin(2πj/k) p_j` (Loop 1987; Hoppe et al. 1994).
//! - Crease and boundary vertices (both schemes): `(e_a + 4v + e_b)/6` along the two sharp edges
//!   (the limit of the cubic B-spline crease curve). Each *sector* of faces between the two sharp
//!   edges, from `e_a` to `e_b` counter-clockwise with `k` faces, gives the tangent pair
//!   `(e_a − e_b, t_across)`, `t_across` the cross-crease tangent mask pointing into the sector:
//!   for Catmull–Clark the mask of Biermann, Levin and Zorin (2000) that OpenSubdiv uses
//!   (`θ = π/k`; `k = 1`: `(e_a + e_b)/2 − v`), for Loop that of Hoppe et al. (1994). A boundary
//!   vertex has one sector; an interior crease two, whose unit normals are averaged (the surface
//!   has a tangent discontinuity there). These cross masks are exact for the regular cases
//!   (Catmull–Clark `k = 2`, Loop `k = 3`) and approximate otherwise, because the plain rules are
//!   used rather than Biermann et al.'s modified ones.
//! - Corners stay where they are; a corner has no tangent plane, so its normal is the average
//!   unit normal of the fan of triangles `(v, e_j, e_{j+1})` over its faces.
//! - Degenerate cases: an interior vertex of valence 2 (two faces glued along two edges) uses
//!   the pair `(e_0 − e_1, f_0 − f_1)` (Catmull–Clark) or the fan (Loop); where the geometry makes
//!   every pair vanish (zero-area faces) the normal is the zero vector. Isolated vertices keep
//!   their position and get a zero normal.

use super::crease::Rule;
use super::loop_limit::loop_limit_chi;
use super::rules::Scheme;
use super::sparse::{RowBuilder, SparseRows};
use crate::mesh::{EdgeId, HalfedgeId, PolyMesh, VertexId};
use crate::{DVec3, Error, Result};
use rayon::prelude::*;
use std::f64::consts::{PI, TAU};

/// Limit-position and tangent stencils of one level.
#[derive(Clone, Debug, Default)]
pub struct LimitStencils {
    /// Row `v`: the limit position of vertex `v`.
    pub positions: SparseRows,
    /// Rows `2p` and `2p + 1`: the two tangents of pair `p`.
    pub tangents: SparseRows,
    /// Vertex `v`'s pairs are `pair_offsets[v]..pair_offsets[v + 1]`.
    pub pair_offsets: Vec<u32>,
}

/// Rows below this count are evaluated on one thread.
const PARALLEL_VERTICES: usize = 8192;

impl LimitStencils {
    /// The limit stencils of every vertex of `mesh` under `scheme`, with `sharpness` the
    /// effective sharpness of its edges (see [`super::crease::effective_sharpness`]). Catmull–Clark
    /// needs an all-quad mesh (any level ≥ 1), Loop a triangle mesh.
    pub fn new(scheme: Scheme, mesh: &PolyMesh, sharpness: &[f64]) -> Result<Self> {
        check_faces(scheme, mesh)?;
        assert_eq!(sharpness.len(), mesh.edge_count(), "one sharpness per edge");
        const CHUNK: usize = 4096;
        let n = mesh.vertex_count();
        let chunks: Vec<LimitStencils> = (0..n.div_ceil(CHUNK))
            .into_par_iter()
            .map(|c| {
                let mut out = LimitStencils {
                    positions: SparseRows::with_columns(n),
                    tangents: SparseRows::with_columns(n),
                    pair_offsets: Vec::new(),
                };
                let mut scratch = Scratch::default();
                for v in c * CHUNK..((c + 1) * CHUNK).min(n) {
                    let pairs = vertex_masks(scheme, mesh, |e| sharpness[e.index()], VertexId(v as u32), &mut scratch);
                    scratch.position.push_into(&mut out.positions);
                    for pair in &mut scratch.pairs[..pairs] {
                        pair[0].push_into(&mut out.tangents);
                        pair[1].push_into(&mut out.tangents);
                    }
                    out.pair_offsets.push(pairs as u32);
                }
                out
            })
            .collect();
        let mut out = LimitStencils {
            positions: SparseRows::with_columns(n),
            tangents: SparseRows::with_columns(n),
            pair_offsets: vec![0],
        };
        for chunk in &chunks {
            out.positions.append(&chunk.positions);
            out.tangents.append(&chunk.tangents);
            for &count in &chunk.pair_offsets {
                let last = *out.pair_offsets.last().unwrap();
                out.pair_offsets.push(last + count);
            }
        }
        Ok(out)
    }

    /// Number of vertices.
    pub fn vertex_count(&self) -> usize {
        self.positions.row_count()
    }

    /// Limit positions and unit limit normals of the level whose positions are `points`.
    pub fn evaluate(&self, points: &[DVec3], limit: &mut Vec<DVec3>, normals: &mut Vec<DVec3>) {
        self.positions.apply_into(points, limit);
        normals.resize(self.vertex_count(), DVec3::ZERO);
        let normal = |v: usize| {
            let (a, b) = (self.pair_offsets[v] as usize, self.pair_offsets[v + 1] as usize);
            let cross =
                |p: usize| self.tangents.apply_row(2 * p, points).cross(self.tangents.apply_row(2 * p + 1, points));
            if b == a + 1 {
                cross(a).normalize_or_zero()
            } else {
                (a..b).map(|p| cross(p).normalize_or_zero()).sum::<DVec3>().normalize_or_zero()
            }
        };
        if normals.len() < PARALLEL_VERTICES {
            for (v, n) in normals.iter_mut().enumerate() {
                *n = normal(v);
            }
        } else {
            normals.par_iter_mut().with_min_len(4096).enumerate().for_each(|(v, n)| *n = normal(v));
        }
    }
}

/// The Catmull–Clark limit position and unit limit normal of vertex `v` of an all-quad mesh
/// without creases (boundaries by the boundary rules). For the curve-mesh work, which needs a few
/// vertices at a time.
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
    let mut scratch = Scratch::default();
    let sharpness = |e: EdgeId| if mesh.is_boundary_edge(e) { f64::INFINITY } else { 0.0 };
    let pairs = vertex_masks(Scheme::CatmullClark, mesh, sharpness, v, &mut scratch);
    let mut rows = SparseRows::with_columns(mesh.vertex_count());
    scratch.position.push_into(&mut rows);
    for pair in &mut scratch.pairs[..pairs] {
        pair[0].push_into(&mut rows);
        pair[1].push_into(&mut rows);
    }
    let p = mesh.positions();
    let unit = |k: usize| rows.apply_row(1 + 2 * k, p).cross(rows.apply_row(2 + 2 * k, p)).normalize_or_zero();
    let normal = if pairs == 1 { unit(0) } else { (0..pairs).map(unit).sum::<DVec3>().normalize_or_zero() };
    Ok((rows.apply_row(0, p), normal))
}

fn check_faces(scheme: Scheme, mesh: &PolyMesh) -> Result<()> {
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
    match Rule::from_sharp_edges(sharp.iter().filter(|&&x| x).count()) {
        Rule::Smooth | Rule::Dart => {
            let nf = n as f64;
            match scheme {
                Scheme::CatmullClark => {
                    let d = nf * (nf + 5.0);
                    position.add(v.0, nf * nf / d);
                    for j in 0..n {
                        position.add(e(j), 4.0 / d);
                        position.add(f(j), 1.0 / d);
                    }
                    let [c2, c3] = pair(pairs, 0);
                    if n == 2 {
                        c2.add(e(0), 1.0);
                        c2.add(e(1), -1.0);
                        c3.add(f(0), 1.0);
                        c3.add(f(1), -1.0);
                        return 1;
                    }
                    let c = (TAU / nf).cos();
                    let a = 1.0 + c + (PI / nf).cos() * (2.0 * (9.0 + c)).sqrt();
                    for j in 0..n {
                        let (cj, cj1) = ((TAU * j as f64 / nf).cos(), (TAU * (j + 1) as f64 / nf).cos());
                        c2.add(e(j), a * cj);
                        c2.add(f(j), cj + cj1);
                        c3.add(e(j + 1), a * cj);
                        c3.add(f(j + 1), cj + cj1);
                    }
                    1
                }
                Scheme::Loop => {
                    let chi = loop_limit_chi(n);
                    position.add(v.0, 1.0 - nf * chi);
                    for j in 0..n {
                        position.add(e(j), chi);
                    }
                    if n == 2 {
                        return fan(mesh, v, ring, pairs);
                    }
                    let [t1, t2] = pair(pairs, 0);
                    for j in 0..n {
                        let (sin, cos) = (TAU * j as f64 / nf).sin_cos();
                        t1.add(e(j), cos);
                        t2.add(e(j), sin);
                    }
                    1
                }
            }
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

/// The tangent across a crease into a sector of `k` faces whose edge neighbours are `e(0..=k)`
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
    if k == 1 {
        let w = match scheme {
            Scheme::CatmullClark => 0.5,
            Scheme::Loop => 1.0,
        };
        t.add(e(0), w);
        t.add(e(1), w);
        t.add(v, -2.0 * w);
        return;
    }
    let theta = PI / k as f64;
    let (sin, cos) = theta.sin_cos();
    match scheme {
        Scheme::CatmullClark => {
            // Biermann, Levin and Zorin (2000), as in OpenSubdiv's Catmark crease tangents.
            let r = (cos + 1.0) / sin;
            t.add(v, 4.0 * r * (cos - 1.0));
            t.add(e(0), -r * (1.0 + 2.0 * cos));
            t.add(e(k), -r * (1.0 + 2.0 * cos));
            for i in 1..k {
                t.add(e(i), 4.0 * (i as f64 * theta).sin());
            }
            for i in 0..k {
                t.add(f(i), (i as f64 * theta).sin() + ((i + 1) as f64 * theta).sin());
            }
        }
        Scheme::Loop => {
            // Hoppe et al. (1994), negated so that it points into the sector.
            t.add(e(0), -sin);
            t.add(e(k), -sin);
            for i in 1..k {
                t.add(e(i), (2.0 - 2.0 * cos) * (i as f64 * theta).sin());
            }
        }
    }
}
