//! The NUSD operator of one level: neighbour lists, weights, `K`, and tension overrides.
//!
//! Everything that depends on the domain, the flags and the tensions but not on the current
//! iterate is computed here once per edit, so the iteration itself only gathers and adds.
//!
//! Rules (`docs/nusd.md`, "Surfaces"):
//! - interior vertex: `w_ij = (1/s_ij) / Σ_k (1/s_ik)` over all neighbours,
//!   `K_i = Σ_k s_ik / Σ_k (1/s_ik)` (eq. 6);
//! - open-boundary vertex: only its two boundary neighbours, for `ΔP`, `ΔR` and the polyline
//!   `K_i = s_i,prev · s_i,next / 2` (eq. 1), so every boundary loop is a closed NUSD polyline;
//! - patch-boundary diffusion: a vertex on a cage edge diffuses `R` only along cage edges.
//!   The paper (sec. 4) writes this as `C_i ∩ E` and says in words that R is diffused "only
//!   between the vertices on that edge". The two differ inside triangular cage faces, where
//!   refinement joins vertices of two different cage edges across the face; we follow the words
//!   and keep only neighbours joined by an edge that lies on a cage edge (`docs/nusd.md`,
//!   "Patch-boundary diffusion");
//! - tension (sec. 5, scale-free): `β^v = τ^v / ℓ_v`, `β^e = τ^e / ℓ_e`, assigned to directed
//!   neighbour pairs. On an open boundary, the override seen by a boundary neighbour follows the
//!   polyline rule (eq. 5), so a tensioned boundary is still exactly the tensioned polyline.

use super::hierarchy::{LevelTopology, NOT_ON_CAGE_EDGE};
use crate::DVec3;
use crate::mesh::{EdgeId, HalfedgeId, PolyMesh, VertexId};
use crate::nusd::Spacing;

/// What the iteration does with a vertex.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[repr(u8)]
pub enum Role {
    /// Position solved (eqs. 2, 3).
    Moving,
    /// Position frozen, `R = ΔP/K` (eq. 4).
    Fixed,
    /// Used by no face: left as it is.
    Isolated,
}

/// A neighbour's `R` replaced by a tensioned second derivative when seen from one vertex.
#[derive(Clone, Copy, Debug)]
pub struct TensionOverride {
    /// The slot of the seeing vertex's neighbour list that is replaced.
    pub slot: u32,
    /// The tensioned neighbour `j`, whose `R` is replaced.
    pub source: u32,
    /// `β_j^i` (units 1/length).
    pub beta: f64,
    /// `s_ij`.
    pub spacing: f64,
    /// For the polyline rule: `j`'s other boundary neighbour; `u32::MAX` for the surface rule.
    pub other: u32,
    /// For the polyline rule: the spacing between `j` and `other`.
    pub other_spacing: f64,
}

/// The operator of one level in compressed rows.
#[derive(Clone, Debug, Default)]
pub struct Operator {
    pub role: Vec<Role>,
    pub k: Vec<f64>,
    pub offsets: Vec<u32>,
    pub neighbors: Vec<u32>,
    /// Weights of `ΔP` per slot (sum to one per vertex).
    pub weight_p: Vec<f64>,
    /// Weights of `ΔR` per slot (sum to one per vertex; zero for neighbours skipped by the
    /// patch-boundary rule).
    pub weight_r: Vec<f64>,
    /// Fixed vertices, for the `R = ΔP/K` pass.
    pub fixed: Vec<u32>,
    /// Tension overrides, grouped by the seeing vertex (`override_offsets` has one entry more
    /// than there are vertices, or is empty when there is no tension at all).
    pub override_offsets: Vec<u32>,
    pub overrides: Vec<TensionOverride>,
    /// The spacing clamp in force (`docs/nusd.md`, "Spacing": `1e-9 · bbox_diagonal`).
    min_spacing: f64,
    /// The smallest spacing of any edge before clamping (a lower bound after refreshes): while
    /// it stays above the clamp, a changed clamp changes no row.
    smallest_spacing: f64,
    /// Which cage vertices and edges have a nonzero β (vertices first): the pattern the
    /// overrides were laid out for.
    tension_pattern: Vec<bool>,
}

/// The designer's controls, resolved for the cage.
#[derive(Clone, Debug)]
pub struct Controls<'a> {
    pub fixed: &'a [bool],
    pub vertex_tension: &'a [f64],
    pub edge_tension: &'a [f64],
    pub spacing: Spacing,
}

/// Everything a row depends on besides the level's connectivity.
struct Context<'a> {
    level: &'a LevelTopology,
    domain: &'a [DVec3],
    spacing: Spacing,
    min_spacing: f64,
    vertex_beta: Vec<f64>,
    edge_beta: Vec<f64>,
}

impl Context<'_> {
    fn new<'a>(level: &'a LevelTopology, domain: &'a [DVec3], cage: &PolyMesh, controls: &Controls<'_>) -> Context<'a> {
        // The domain is made of averages of the cage's positions, so its box is the cage's:
        // computed from the cage vertices (the first of every level), not the whole level.
        let corners = &domain[..level.cage_vertices.min(domain.len())];
        let diagonal = crate::mesh::bounding_box(corners).map_or(0.0, |(lo, hi)| crate::mesh::diagonal_length(lo, hi));
        Context {
            level,
            domain,
            spacing: controls.spacing,
            min_spacing: controls.spacing.min_spacing(diagonal),
            vertex_beta: vertex_betas(cage, controls.vertex_tension, controls.spacing),
            edge_beta: edge_betas(cage, controls.edge_tension, controls.spacing),
        }
    }

    /// The spacing of the edge from `a` to `b`, and the unclamped value.
    fn spacing(&self, a: VertexId, b: VertexId) -> (f64, f64) {
        let chord = (self.domain[b.index()] - self.domain[a.index()]).length();
        let raw = self.spacing.of_level_chord(chord, self.level.depth);
        (raw.max(self.min_spacing), raw)
    }

    fn any_tension(&self) -> bool {
        self.vertex_beta.iter().chain(&self.edge_beta).any(|&b| b != 0.0)
    }

    fn tension_pattern(&self) -> Vec<bool> {
        self.vertex_beta.iter().chain(&self.edge_beta).map(|&b| b != 0.0).collect()
    }

    /// The neighbour slots of `v` (only its two boundary neighbours on an open boundary) with
    /// their spacings; returns the smallest unclamped spacing.
    fn slots(&self, v: VertexId, out: &mut Vec<(HalfedgeId, f64)>) -> f64 {
        let mesh = &self.level.mesh;
        out.clear();
        let mut smallest = f64::INFINITY;
        let mut push = |h: HalfedgeId, other: VertexId| {
            let (s, raw) = self.spacing(v, other);
            smallest = smallest.min(if raw.is_finite() { raw } else { 0.0 });
            out.push((h, s));
        };
        if mesh.is_boundary_vertex(v) {
            let out_h = mesh.vertex_halfedge(v);
            let into = mesh.prev(out_h);
            push(out_h, mesh.to_vertex(out_h));
            push(into.twin(), mesh.from_vertex(into));
        } else {
            for h in mesh.outgoing(v) {
                push(h, mesh.to_vertex(h));
            }
        }
        smallest
    }

    /// `K`, and the `ΔP` and `ΔR` weights of the slots, of vertex `v`.
    fn row(&self, v: VertexId, slots: &[(HalfedgeId, f64)], weight_p: &mut [f64], weight_r: &mut [f64]) -> f64 {
        let level = self.level;
        let boundary = level.mesh.is_boundary_vertex(v);
        let inv_sum: f64 = slots.iter().map(|&(_, s)| 1.0 / s).sum();
        let k = if slots.is_empty() {
            1.0
        } else if boundary {
            slots[0].1 * slots[1].1 / 2.0
        } else {
            slots.iter().map(|&(_, s)| s).sum::<f64>() / inv_sum
        };
        // Patch-boundary diffusion: a vertex on a cage edge (cage vertices included) sees only
        // neighbours along cage edges when diffusing R.
        let on_cage_edge = v.index() < level.cage_vertices || level.vertex_on_cage_edge[v.index()] != NOT_ON_CAGE_EDGE;
        let r_mask =
            |h: HalfedgeId| boundary || !on_cage_edge || level.edge_on_cage[h.edge().index()] != NOT_ON_CAGE_EDGE;
        let inv_sum_r: f64 = slots.iter().filter(|&&(h, _)| r_mask(h)).map(|&(_, s)| 1.0 / s).sum();
        for (k, &(h, s)) in slots.iter().enumerate() {
            weight_p[k] = (1.0 / s) / inv_sum;
            weight_r[k] = if r_mask(h) { (1.0 / s) / inv_sum_r } else { 0.0 };
        }
        k
    }

    /// The tension overrides seen by `v` through its slots, starting at slot index `first`.
    fn overrides(&self, v: VertexId, slots: &[(HalfedgeId, f64)], first: usize, out: &mut Vec<TensionOverride>) {
        let mesh = &self.level.mesh;
        for (slot, &(h, s)) in slots.iter().enumerate() {
            let source = mesh.to_vertex(h);
            let beta = directed_beta(self.level, &self.vertex_beta, &self.edge_beta, source, h.twin());
            if beta != 0.0 {
                let spacing = |a: VertexId, b: VertexId| self.spacing(a, b).0;
                out.push(tension_override(mesh, &spacing, (first + slot) as u32, v, source, beta, s));
            }
        }
    }
}

impl Operator {
    /// Builds the operator of `level` with domain positions `domain` (the cage's positions
    /// prolonged without smoothing) and the cage `cage` (for the tension length scales).
    pub fn build(level: &LevelTopology, domain: &[DVec3], cage: &PolyMesh, controls: &Controls<'_>) -> Operator {
        let cx = Context::new(level, domain, cage, controls);
        let mesh = &level.mesh;
        let n = mesh.vertex_count();
        let any_tension = cx.any_tension();
        let mut op = Operator {
            role: Vec::with_capacity(n),
            k: Vec::with_capacity(n),
            offsets: Vec::with_capacity(n + 1),
            neighbors: Vec::with_capacity(mesh.halfedge_count()),
            weight_p: Vec::with_capacity(mesh.halfedge_count()),
            weight_r: Vec::with_capacity(mesh.halfedge_count()),
            min_spacing: cx.min_spacing,
            smallest_spacing: f64::INFINITY,
            tension_pattern: cx.tension_pattern(),
            ..Default::default()
        };
        op.offsets.push(0);
        if any_tension {
            op.override_offsets.push(0);
        }
        let mut slots: Vec<(HalfedgeId, f64)> = Vec::new();
        for v in mesh.vertices() {
            op.smallest_spacing = op.smallest_spacing.min(cx.slots(v, &mut slots));
            let role = if slots.is_empty() {
                Role::Isolated
            } else if v.index() < level.cage_vertices && controls.fixed[v.index()] {
                Role::Fixed
            } else {
                Role::Moving
            };
            if role == Role::Fixed {
                op.fixed.push(v.0);
            }
            op.role.push(role);
            let first = op.neighbors.len();
            op.neighbors.extend(slots.iter().map(|&(h, _)| mesh.to_vertex(h).0));
            op.weight_p.resize(first + slots.len(), 0.0);
            op.weight_r.resize(first + slots.len(), 0.0);
            let k = cx.row(v, &slots, &mut op.weight_p[first..], &mut op.weight_r[first..]);
            op.k.push(k);
            if any_tension {
                cx.overrides(v, &slots, first, &mut op.overrides);
                op.override_offsets.push(op.overrides.len() as u32);
            }
            op.offsets.push(op.neighbors.len() as u32);
        }
        op
    }

    /// Brings the operator up to date after the domain moved at the vertices listed in
    /// `moved` (same connectivity, fixed flags and tension *pattern*: which tensions are zero).
    /// Only the rows that see a moved vertex are recomputed, and every tension override
    /// (there are few). The result is bit for bit what [`build`](Self::build) gives. Returns
    /// false, changing nothing, when that cannot be done in place (the spacing clamp now
    /// reaches an edge, or a tension override appeared or vanished): then build anew.
    pub fn refresh(
        &mut self,
        level: &LevelTopology,
        domain: &[DVec3],
        cage: &PolyMesh,
        controls: &Controls<'_>,
        moved: &[u32],
    ) -> bool {
        let cx = Context::new(level, domain, cage, controls);
        if cx.min_spacing != self.min_spacing && self.smallest_spacing <= cx.min_spacing.max(self.min_spacing) {
            return false;
        }
        if cx.tension_pattern() != self.tension_pattern {
            return false;
        }
        let mesh = &level.mesh;
        // The overrides first (only vertices that have some: the pattern is unchanged): if one
        // appeared or vanished, nothing has been touched yet.
        let mut slots: Vec<(HalfedgeId, f64)> = Vec::new();
        if !self.override_offsets.is_empty() {
            let mut fresh = Vec::with_capacity(self.overrides.len());
            for v in 0..mesh.vertex_count() {
                let (a, b) = (self.override_offsets[v] as usize, self.override_offsets[v + 1] as usize);
                if a == b {
                    continue;
                }
                cx.slots(VertexId(v as u32), &mut slots);
                cx.overrides(VertexId(v as u32), &slots, self.offsets[v] as usize, &mut fresh);
                if fresh.len() != b {
                    return false;
                }
            }
            self.overrides = fresh;
        }
        // A row sees its own vertex and its neighbours: the moved vertices and their rings.
        let mut stale: Vec<u32> = moved.to_vec();
        for &v in moved {
            stale.extend(mesh.outgoing(VertexId(v)).map(|h| mesh.to_vertex(h).0));
        }
        stale.sort_unstable();
        stale.dedup();
        for v in stale {
            let v = VertexId(v);
            self.smallest_spacing = self.smallest_spacing.min(cx.slots(v, &mut slots));
            let first = self.offsets[v.index()] as usize;
            let end = self.offsets[v.index() + 1] as usize;
            self.k[v.index()] = cx.row(v, &slots, &mut self.weight_p[first..end], &mut self.weight_r[first..end]);
        }
        self.min_spacing = cx.min_spacing;
        true
    }
}

/// `β_j^i` for the directed pair `j → i`, where `h` runs from `j` to `i`.
fn directed_beta(level: &LevelTopology, vertex_beta: &[f64], edge_beta: &[f64], j: VertexId, h: HalfedgeId) -> f64 {
    if j.index() < level.cage_vertices {
        return vertex_beta[j.index()];
    }
    let on = level.vertex_on_cage_edge[j.index()];
    if on == NOT_ON_CAGE_EDGE || edge_beta[on as usize] == 0.0 {
        return 0.0;
    }
    // Across the edge only: neighbours along the same cage edge see the plain R.
    if level.edge_on_cage[h.edge().index()] == on { 0.0 } else { edge_beta[on as usize] }
}

fn tension_override(
    mesh: &PolyMesh,
    spacing: &impl Fn(VertexId, VertexId) -> f64,
    slot: u32,
    seer: VertexId,
    source: VertexId,
    beta: f64,
    s: f64,
) -> TensionOverride {
    let mut o = TensionOverride { slot, source: source.0, beta, spacing: s, other: u32::MAX, other_spacing: 0.0 };
    if mesh.is_boundary_vertex(source) && mesh.is_boundary_vertex(seer) {
        let out = mesh.vertex_halfedge(source);
        let (next, prev) = (mesh.to_vertex(out), mesh.from_vertex(mesh.prev(out)));
        let other = if next == seer {
            Some(prev)
        } else if prev == seer {
            Some(next)
        } else {
            None
        };
        if let Some(other) = other {
            o.other = other.0;
            o.other_spacing = spacing(source, other);
        }
    }
    o
}

/// `β^v = τ^v / ℓ_v`, with `ℓ_v` the mean parameter length (spacing) of the cage edges at `v`:
/// their mean length with chord spacing, 1 with uniform spacing. `β` multiplies a difference of
/// `P` over a spacing and is added to `R`, a difference over a spacing squared, so it must be in
/// the spacing's units for `τ` to mean the same on any model and with any spacing (as on a
/// polyline, whose `ℓ` is also the parameter length).
pub fn vertex_betas(cage: &PolyMesh, tension: &[f64], spacing: Spacing) -> Vec<f64> {
    cage.vertices()
        .map(|v| {
            let tau = tension[v.index()];
            if tau == 0.0 {
                return 0.0;
            }
            let lengths: Vec<f64> =
                cage.outgoing(v).map(|h| spacing.of_level_chord(cage.edge_length(h.edge()), 0)).collect();
            let mean = lengths.iter().sum::<f64>() / lengths.len().max(1) as f64;
            if mean > 0.0 { tau / mean } else { 0.0 }
        })
        .collect()
}

/// `β^e = τ^e / ℓ_e`, with `ℓ_e` the parameter length (spacing) of the cage edge (see
/// [`vertex_betas`]).
pub fn edge_betas(cage: &PolyMesh, tension: &[f64], spacing: Spacing) -> Vec<f64> {
    cage.edges()
        .map(|e: EdgeId| {
            let len = spacing.of_level_chord(cage.edge_length(e), 0);
            if tension[e.index()] == 0.0 || len <= 0.0 { 0.0 } else { tension[e.index()] / len }
        })
        .collect()
}
