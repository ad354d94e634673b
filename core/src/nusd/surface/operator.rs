//! The NUSD operator of one level: neighbour lists, weights, `K`, and tension overrides.
//!
//! Everything that depends on the domain, the flags and the tensions but not on the current
//! iterate is computed here once per edit, so the iteration itself only gathers and adds.
//!
//! Rules (spec: "Surfaces"):
//! - interior vertex: `w_ij = (1/s_ij) / Σ_k (1/s_ik)` over all neighbours,
//!   `K_i = Σ_k s_ik / Σ_k (1/s_ik)` (eq. 6);
//! - open-boundary vertex: only its two boundary neighbours, for `ΔP`, `ΔR` and the polyline
//!   `K_i = s_i,prev · s_i,next / 2` (eq. 1), so every boundary loop is a closed NUSD polyline;
//! - patch-boundary diffusion: a vertex on a cage edge diffuses `R` only along cage edges.
//!   The spec writes this as `C_i ∩ E`; the paper (sec. 4) says R is diffused "only between the
//!   vertices on that edge". The two differ on triangles, where the midpoints of a triangle's
//!   three cage edges are joined by edges inside the face; we follow the paper and keep only
//!   neighbours joined by an edge that lies on a cage edge;
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
}

/// The designer's controls, resolved for the cage.
#[derive(Clone, Debug)]
pub struct Controls<'a> {
    pub fixed: &'a [bool],
    pub vertex_tension: &'a [f64],
    pub edge_tension: &'a [f64],
    pub spacing: Spacing,
}

impl Operator {
    /// Builds the operator of `level` with domain positions `domain` (the cage's positions
    /// prolonged without smoothing) and the cage `cage` (for the tension length scales).
    pub fn build(level: &LevelTopology, domain: &[DVec3], cage: &PolyMesh, controls: &Controls<'_>) -> Operator {
        let mesh = &level.mesh;
        let n = mesh.vertex_count();
        let diagonal = crate::mesh::bounding_box(domain).map_or(0.0, |(lo, hi)| (hi - lo).length());
        let min_spacing = controls.spacing.min_spacing(diagonal);
        let spacing = |a: VertexId, b: VertexId| {
            controls.spacing.of_chord((domain[b.index()] - domain[a.index()]).length(), min_spacing)
        };
        let vertex_beta = vertex_betas(cage, controls.vertex_tension);
        let edge_beta = edge_betas(cage, controls.edge_tension);
        let any_tension = vertex_beta.iter().chain(&edge_beta).any(|&b| b != 0.0);

        let mut op = Operator {
            role: Vec::with_capacity(n),
            k: Vec::with_capacity(n),
            offsets: Vec::with_capacity(n + 1),
            neighbors: Vec::with_capacity(mesh.halfedge_count()),
            weight_p: Vec::with_capacity(mesh.halfedge_count()),
            weight_r: Vec::with_capacity(mesh.halfedge_count()),
            ..Default::default()
        };
        op.offsets.push(0);
        if any_tension {
            op.override_offsets.push(0);
        }
        let mut slots: Vec<(HalfedgeId, f64)> = Vec::new();
        for v in mesh.vertices() {
            slots.clear();
            let boundary = mesh.is_boundary_vertex(v);
            if boundary {
                let out = mesh.vertex_halfedge(v);
                let into = mesh.prev(out);
                slots.push((out, spacing(v, mesh.to_vertex(out))));
                slots.push((into.twin(), spacing(v, mesh.from_vertex(into))));
            } else {
                slots.extend(mesh.outgoing(v).map(|h| (h, spacing(v, mesh.to_vertex(h)))));
            }
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

            let inv_sum: f64 = slots.iter().map(|&(_, s)| 1.0 / s).sum();
            let k = if slots.is_empty() {
                1.0
            } else if boundary {
                slots[0].1 * slots[1].1 / 2.0
            } else {
                slots.iter().map(|&(_, s)| s).sum::<f64>() / inv_sum
            };
            op.k.push(k);

            // Patch-boundary diffusion: a vertex on a cage edge (cage vertices included) sees
            // only neighbours along cage edges when diffusing R.
            let on_cage_edge =
                v.index() < level.cage_vertices || level.vertex_on_cage_edge[v.index()] != NOT_ON_CAGE_EDGE;
            let r_mask =
                |h: HalfedgeId| boundary || !on_cage_edge || level.edge_on_cage[h.edge().index()] != NOT_ON_CAGE_EDGE;
            let inv_sum_r: f64 = slots.iter().filter(|&&(h, _)| r_mask(h)).map(|&(_, s)| 1.0 / s).sum();
            for &(h, s) in &slots {
                op.neighbors.push(mesh.to_vertex(h).0);
                op.weight_p.push((1.0 / s) / inv_sum);
                op.weight_r.push(if r_mask(h) { (1.0 / s) / inv_sum_r } else { 0.0 });
            }
            if any_tension {
                for (slot, &(h, s)) in slots.iter().enumerate() {
                    let source = mesh.to_vertex(h);
                    let beta = directed_beta(level, &vertex_beta, &edge_beta, source, h.twin());
                    if beta != 0.0 {
                        op.overrides.push(tension_override(
                            mesh,
                            &spacing,
                            (op.offsets.last().copied().unwrap_or(0) as usize + slot) as u32,
                            v,
                            source,
                            beta,
                            s,
                        ));
                    }
                }
                op.override_offsets.push(op.overrides.len() as u32);
            }
            op.offsets.push(op.neighbors.len() as u32);
        }
        op
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

/// `β^v = τ^v / ℓ_v`, with `ℓ_v` the mean length of the cage edges at `v`.
pub fn vertex_betas(cage: &PolyMesh, tension: &[f64]) -> Vec<f64> {
    cage.vertices()
        .map(|v| {
            let tau = tension[v.index()];
            if tau == 0.0 {
                return 0.0;
            }
            let lengths: Vec<f64> = cage.outgoing(v).map(|h| cage.edge_length(h.edge())).collect();
            let mean = lengths.iter().sum::<f64>() / lengths.len().max(1) as f64;
            if mean > 0.0 { tau / mean } else { 0.0 }
        })
        .collect()
}

/// `β^e = τ^e / ℓ_e`, with `ℓ_e` the length of the cage edge.
pub fn edge_betas(cage: &PolyMesh, tension: &[f64]) -> Vec<f64> {
    cage.edges()
        .map(|e: EdgeId| {
            let len = cage.edge_length(e);
            if tension[e.index()] == 0.0 || len <= 0.0 { 0.0 } else { tension[e.index()] / len }
        })
        .collect()
}
