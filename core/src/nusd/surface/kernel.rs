//! One NUSD iteration on a level (`docs/nusd.md`, "One iteration"), in parallel and deterministic.
//!
//! 1. fixed `i`: `R_i ← ΔP_i / K_i` (eq. 4), written in place: no later read of this pass
//!    depends on another fixed vertex's R;
//! 2. moving `i`: `R_i' ← R_i + λ ΔR_i` (eq. 2), with tensioned neighbours' R replaced
//!    (sec. 5 / eq. 5), then `P_i' ← P_i + λ ΔP_i − λ K_i R_i'` (eq. 3, but with the `R` just
//!    updated where the paper's eq. 3 reads the previous `R_i`: the same fixed point; see
//!    `docs/nusd.md`, "Where we depart"), written to the second buffer.
//!
//! Every vertex reads only the previous iterate and writes only its own entries, so the result
//! is bit-identical for any number of threads; the largest step is a max-reduction, which is
//! order-independent too.
//!
//! Each sweep also reports the largest step of a vertex that *reversed* its direction (its step
//! points against its previous step, read from the second buffer before it is overwritten, so
//! it costs no extra pass). Modes of the iteration with a negative eigenvalue reverse every
//! sweep; in a stable iteration they die within a few sweeps (by 5× a sweep at λ = 0.6 without
//! tension), so when they carry the largest step for long the iteration is (nearly) unstable at
//! this λ: the oscillation that strong tension causes.

use super::operator::{Operator, Role, TensionOverride};
use crate::DVec3;
use crate::mesh::{PolyMesh, VertexId};
use rayon::prelude::*;

/// Vertices per parallel task; below twice this a level is iterated on one thread.
const CHUNK: usize = 4096;

/// Current and next iterate of a level.
#[derive(Clone, Debug, Default)]
pub struct State {
    pub p: Vec<DVec3>,
    pub r: Vec<DVec3>,
    p_next: Vec<DVec3>,
    r_next: Vec<DVec3>,
    /// The previous step of each vertex of a region iterated alone (in region order).
    region_steps: Vec<DVec3>,
    /// Scratch of a region's sweep and residual, kept between calls.
    region_moves: Vec<Option<(DVec3, DVec3, DVec3)>>,
    region_residuals: Vec<(DVec3, DVec3)>,
}

impl State {
    pub fn new(p: Vec<DVec3>, r: Vec<DVec3>) -> Self {
        let n = p.len();
        State {
            p,
            r,
            p_next: vec![DVec3::ZERO; n],
            r_next: vec![DVec3::ZERO; n],
            region_steps: Vec::new(),
            region_moves: Vec::new(),
            region_residuals: Vec::new(),
        }
    }
}

#[inline]
fn laplacian(op: &Operator, p: &[DVec3], i: usize) -> DVec3 {
    let (a, b) = (op.offsets[i] as usize, op.offsets[i + 1] as usize);
    let mut avg = DVec3::ZERO;
    for s in a..b {
        avg += op.weight_p[s] * p[op.neighbors[s] as usize];
    }
    avg - p[i]
}

/// Right-hand sides of a level's equations, for the multigrid coarse levels: the iteration then
/// solves `N(x) = f` instead of `N(x) = 0`, with the equations written per vertex divided by `K`
/// (so they mean the same on every level):
/// - moving `i`: `ΔR̃_i / K_i = f.r_i` and `ΔP_i / K_i − R_i = f.p_i`,
/// - fixed `i`: `ΔP_i / K_i − R_i = f.r_i` (its `P` is given).
#[derive(Clone, Debug, Default)]
pub struct Forcing {
    pub r: Vec<DVec3>,
    pub p: Vec<DVec3>,
}

impl Forcing {
    pub fn zeros(n: usize) -> Self {
        Forcing { r: vec![DVec3::ZERO; n], p: vec![DVec3::ZERO; n] }
    }
}

/// Recomputes `R = ΔP/K` of the fixed vertices (eq. 4).
pub fn update_fixed(op: &Operator, state: &mut State) {
    update_fixed_forced(op, state, None);
}

/// Recomputes `R = ΔP/K − f` of the fixed vertices.
pub fn update_fixed_forced(op: &Operator, state: &mut State, forcing: Option<&Forcing>) {
    update_fixed_of(op, state, forcing, &op.fixed);
}

/// Recomputes `R = ΔP/K − f` of the listed fixed vertices.
pub fn update_fixed_of(op: &Operator, state: &mut State, forcing: Option<&Forcing>, fixed: &[u32]) {
    for &i in fixed {
        let i = i as usize;
        let f = forcing.map_or(DVec3::ZERO, |f| f.r[i]);
        state.r[i] = laplacian(op, &state.p, i) / op.k[i] - f;
    }
}

/// The neighbour averages of `P` and of `R` (tensioned neighbours' `R` replaced) of a moving
/// vertex `i`.
#[inline]
fn averages(op: &Operator, mesh: &PolyMesh, p: &[DVec3], r: &[DVec3], i: usize) -> (DVec3, DVec3) {
    let (a, b) = (op.offsets[i] as usize, op.offsets[i + 1] as usize);
    let mut avg_p = DVec3::ZERO;
    let mut avg_r = DVec3::ZERO;
    for s in a..b {
        let j = op.neighbors[s] as usize;
        avg_p += op.weight_p[s] * p[j];
        avg_r += op.weight_r[s] * r[j];
    }
    if !op.override_offsets.is_empty() {
        let (oa, ob) = (op.override_offsets[i] as usize, op.override_offsets[i + 1] as usize);
        for o in &op.overrides[oa..ob] {
            let w = op.weight_r[o.slot as usize];
            if w != 0.0 {
                avg_r += w * (tensioned_r(op, mesh, p, i, o) - r[o.source as usize]);
            }
        }
    }
    (avg_p, avg_r)
}

/// The second derivative of `o.source` as seen across the slot, with tension.
fn tensioned_r(op: &Operator, mesh: &PolyMesh, p: &[DVec3], seer: usize, o: &TensionOverride) -> DVec3 {
    let j = o.source as usize;
    let lap = laplacian(op, p, j);
    let base = lap / op.k[j];
    let toward = p[seer] - p[j];
    if o.other != u32::MAX {
        // Polyline rule along an open boundary (eq. 5): R± = ΔP/K ± (β/2) Ṗ, with the seer on
        // the + side.
        let tangent = 0.5 * (toward / o.spacing + (p[j] - p[o.other as usize]) / o.other_spacing);
        return base + 0.5 * o.beta * tangent;
    }
    let len = lap.length();
    let scale = toward.length();
    let n = if len > 1e-9 * scale && len.is_finite() { lap / len } else { area_normal(mesh, p, j) };
    let tangential = toward - toward.dot(n) * n;
    base + o.beta * tangential / o.spacing
}

/// Area-weighted normal of vertex `j` at positions `p`: the fallback direction when `ΔP_j` is
/// too small to give one (a flat neighbourhood).
fn area_normal(mesh: &PolyMesh, p: &[DVec3], j: usize) -> DVec3 {
    let mut sum = DVec3::ZERO;
    for h in mesh.outgoing(VertexId(j as u32)) {
        let f = mesh.face(h);
        if f.is_valid() {
            for g in mesh.face_halfedges(f) {
                sum += p[mesh.from_vertex(g).index()].cross(p[mesh.to_vertex(g).index()]);
            }
        }
    }
    sum.normalize_or_zero()
}

/// What one sweep did.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sweep {
    /// Largest position step of a moving vertex (NaN if any value became non-finite).
    pub step: f64,
    /// Largest step of a moving vertex that points against its previous step.
    pub reversing: f64,
}

/// Max-reduction that lets NaN win, so that divergence is seen.
fn max_nan(a: f64, b: f64) -> f64 {
    if a.is_nan() || b.is_nan() { f64::NAN } else { a.max(b) }
}

/// One iteration.
pub fn iterate(op: &Operator, mesh: &PolyMesh, state: &mut State, lambda: f64) -> Sweep {
    iterate_forced(op, mesh, state, lambda, None)
}

/// One iteration of `N(x) = f` (see [`Forcing`]); with no forcing, the plain iteration:
/// `R' = R + λ (ΔR̃ − K f_r)`, `P' = P + λ (ΔP − K R' − K f_p)`.
pub fn iterate_forced(
    op: &Operator,
    mesh: &PolyMesh,
    state: &mut State,
    lambda: f64,
    forcing: Option<&Forcing>,
) -> Sweep {
    update_fixed_forced(op, state, forcing);
    let State { p, r, p_next, r_next, .. } = state;
    let (p, r) = (&p[..], &r[..]);
    let n = p.len();
    let run = |start: usize, pn: &mut [DVec3], rn: &mut [DVec3]| -> Sweep {
        let mut step = 0.0f64;
        let mut reversing = 0.0f64;
        for (k, (pi_out, ri_out)) in pn.iter_mut().zip(rn.iter_mut()).enumerate() {
            let i = start + k;
            if op.role[i] != Role::Moving {
                *pi_out = p[i];
                *ri_out = r[i];
                continue;
            }
            let (p_new, r_new, delta) = moved(op, mesh, p, r, i, lambda, forcing);
            // The second buffer still holds the previous iterate.
            let previous = p[i] - *pi_out;
            *pi_out = p_new;
            *ri_out = r_new;
            let d = delta.length();
            step = max_nan(step, d);
            if delta.dot(previous) < 0.0 {
                reversing = reversing.max(d);
            }
        }
        Sweep { step, reversing }
    };
    let sweep = if n < 2 * CHUNK {
        run(0, p_next, r_next)
    } else {
        p_next
            .par_chunks_mut(CHUNK)
            .zip(r_next.par_chunks_mut(CHUNK))
            .enumerate()
            .map(|(c, (pn, rn))| run(c * CHUNK, pn, rn))
            .reduce(
                || Sweep { step: 0.0, reversing: 0.0 },
                |a, b| Sweep { step: max_nan(a.step, b.step), reversing: a.reversing.max(b.reversing) },
            )
    };
    std::mem::swap(&mut state.p, &mut state.p_next);
    std::mem::swap(&mut state.r, &mut state.r_next);
    sweep
}

/// A level's vertices in colour classes: no two vertices of a class are neighbours. Greedy in
/// index order (each vertex takes the smallest colour none of its earlier neighbours has), so
/// the classes depend on the connectivity alone; each class lists its vertices in ascending
/// order. The quad-split levels take about five colours.
#[derive(Clone, Debug, Default)]
pub struct Coloring {
    offsets: Vec<u32>,
    vertices: Vec<u32>,
    /// Each vertex's colour.
    color: Vec<u32>,
}

impl Coloring {
    pub fn of(mesh: &PolyMesh) -> Coloring {
        let n = mesh.vertex_count();
        let mut color = vec![u32::MAX; n];
        let mut taken: Vec<bool> = Vec::new();
        let mut colors = 0;
        for v in 0..n {
            taken.clear();
            for h in mesh.outgoing(VertexId(v as u32)) {
                let c = color[mesh.to_vertex(h).index()];
                if c != u32::MAX {
                    if taken.len() <= c as usize {
                        taken.resize(c as usize + 1, false);
                    }
                    taken[c as usize] = true;
                }
            }
            let c = taken.iter().position(|&t| !t).unwrap_or(taken.len()) as u32;
            color[v] = c;
            colors = colors.max(c + 1);
        }
        // By colour, each class in index order (the sort is stable).
        let mut vertices: Vec<u32> = (0..n as u32).collect();
        vertices.sort_by_key(|&v| color[v as usize]);
        let offsets = (0..=colors).map(|c| vertices.partition_point(|&v| color[v as usize] < c) as u32).collect();
        Coloring { offsets, vertices, color }
    }

    /// The colour classes in order.
    pub fn classes(&self) -> impl Iterator<Item = &[u32]> + '_ {
        self.offsets.windows(2).map(|w| &self.vertices[w[0] as usize..w[1] as usize])
    }

    /// The number of colours.
    pub fn count(&self) -> usize {
        self.offsets.len() - 1
    }

    /// The colour of vertex `v`.
    pub fn color(&self, v: u32) -> u32 {
        self.color[v as usize]
    }
}

/// [`iterate_colored`] of the vertices of `region` only, the others held (a local solve, see
/// [`super::local`]): class by class, each class's vertices of the region moved together from
/// the present state, as [`iterate_on`] moves all of them.
pub fn iterate_colored_on(
    op: &Operator,
    mesh: &PolyMesh,
    state: &mut State,
    lambda: f64,
    forcing: Option<&Forcing>,
    region: &super::local::Region,
    coloring: &Coloring,
) -> Sweep {
    let mut step = 0.0f64;
    let mut class: Vec<u32> = Vec::with_capacity(region.len());
    for c in 0..coloring.count() as u32 {
        class.clear();
        class.extend(region.vertices.iter().copied().filter(|&v| coloring.color(v) == c));
        update_fixed_of(op, state, forcing, &region.fixed);
        let State { p, r, region_moves, .. } = state;
        let (pr, rr) = (&p[..], &r[..]);
        super::local::map_vertices_into(&class, region_moves, |i| {
            (op.role[i as usize] == Role::Moving).then(|| moved(op, mesh, pr, rr, i as usize, lambda, forcing))
        });
        for (&i, value) in class.iter().zip(region_moves.iter()) {
            let Some((p_new, r_new, delta)) = *value else { continue };
            p[i as usize] = p_new;
            r[i as usize] = r_new;
            step = max_nan(step, delta.length());
        }
    }
    Sweep { step, reversing: 0.0 }
}

/// One Gauss–Seidel sweep of `N(x) = f` by colour classes ([`Coloring`]): the fixed vertices'
/// `R` is brought up to date, then every moving vertex of the class takes the update of
/// [`iterate_forced`] from the present state, and the next class sees it. Each vertex is updated
/// once a sweep, so a sweep costs what a Jacobi sweep does, but the later classes read values
/// already updated, which damps the rough error about twice as fast. A class's new values are
/// all computed before any is written (a tensioned neighbour's `R` reads its own neighbours,
/// which may be in the class), so the result does not depend on the thread count. The fixed
/// point is that of the plain iteration. `reversing` is not measured (it is zero).
pub fn iterate_colored(
    op: &Operator,
    mesh: &PolyMesh,
    state: &mut State,
    lambda: f64,
    forcing: Option<&Forcing>,
    coloring: &Coloring,
) -> Sweep {
    let mut step = 0.0f64;
    let mut updates: Vec<Option<(DVec3, DVec3, f64)>> = Vec::new();
    for class in coloring.classes() {
        update_fixed_forced(op, state, forcing);
        let (p, r) = (&state.p[..], &state.r[..]);
        let update = |&i: &u32| {
            let i = i as usize;
            (op.role[i] == Role::Moving).then(|| {
                let (p_new, r_new, delta) = moved(op, mesh, p, r, i, lambda, forcing);
                (p_new, r_new, delta.length())
            })
        };
        updates.clear();
        if class.len() < 2 * CHUNK {
            updates.extend(class.iter().map(update));
        } else {
            updates.par_extend(class.par_iter().with_min_len(CHUNK).map(update));
        }
        for (&i, new) in class.iter().zip(&updates) {
            if let Some((p_new, r_new, d)) = *new {
                state.p[i as usize] = p_new;
                state.r[i as usize] = r_new;
                step = max_nan(step, d);
            }
        }
    }
    Sweep { step, reversing: 0.0 }
}

/// The new `P`, `R` and step of a moving vertex `i` (see [`iterate_forced`]).
#[inline]
fn moved(
    op: &Operator,
    mesh: &PolyMesh,
    p: &[DVec3],
    r: &[DVec3],
    i: usize,
    lambda: f64,
    forcing: Option<&Forcing>,
) -> (DVec3, DVec3, DVec3) {
    let (avg_p, avg_r) = averages(op, mesh, p, r, i);
    let (r_new, delta) = match forcing {
        None => {
            let r_new = r[i] + lambda * (avg_r - r[i]);
            (r_new, lambda * (avg_p - p[i]) - lambda * op.k[i] * r_new)
        }
        Some(f) => {
            let r_new = r[i] + lambda * (avg_r - r[i] - op.k[i] * f.r[i]);
            (r_new, lambda * (avg_p - p[i]) - lambda * op.k[i] * (r_new + f.p[i]))
        }
    };
    (p[i] + delta, r_new, delta)
}

/// One iteration of the vertices of `region` only, the others held (a local solve, see
/// [`super::local`]): the same arithmetic per vertex as [`iterate_forced`], so bit-identical
/// for any number of threads.
pub fn iterate_on(
    op: &Operator,
    mesh: &PolyMesh,
    state: &mut State,
    lambda: f64,
    forcing: Option<&Forcing>,
    region: &super::local::Region,
) -> Sweep {
    update_fixed_of(op, state, forcing, &region.fixed);
    if state.region_steps.len() != region.len() {
        state.region_steps = vec![DVec3::ZERO; region.len()];
    }
    let State { p, r, region_steps, region_moves, .. } = state;
    let (pr, rr) = (&p[..], &r[..]);
    super::local::map_vertices_into(&region.vertices, region_moves, |i| {
        (op.role[i as usize] == Role::Moving).then(|| moved(op, mesh, pr, rr, i as usize, lambda, forcing))
    });
    let mut sweep = Sweep { step: 0.0, reversing: 0.0 };
    for ((&i, value), previous) in region.vertices.iter().zip(region_moves.iter()).zip(region_steps.iter_mut()) {
        let Some((p_new, r_new, delta)) = *value else { continue };
        p[i as usize] = p_new;
        r[i as usize] = r_new;
        let d = delta.length();
        sweep.step = max_nan(sweep.step, d);
        if delta.dot(*previous) < 0.0 {
            sweep.reversing = sweep.reversing.max(d);
        }
        *previous = delta;
    }
    sweep
}

/// The residual `f − N(x)` of moving vertex `i`'s `R` and `P` equations (see [`Forcing`]),
/// with the fixed vertices' `R` as they stand.
#[inline]
pub fn vertex_residual(
    op: &Operator,
    mesh: &PolyMesh,
    p: &[DVec3],
    r: &[DVec3],
    forcing: Option<&Forcing>,
    i: usize,
) -> (DVec3, DVec3) {
    let (avg_p, avg_r) = averages(op, mesh, p, r, i);
    let (fr, fp) = forcing.map_or((DVec3::ZERO, DVec3::ZERO), |f| (f.r[i], f.p[i]));
    let ki = op.k[i];
    (fr - (avg_r - r[i]) / ki, fp - ((avg_p - p[i]) / ki - r[i]))
}

/// [`residual`] of the vertices of `region` only; `out` is written there only.
pub fn residual_on(
    op: &Operator,
    mesh: &PolyMesh,
    state: &mut State,
    forcing: Option<&Forcing>,
    out: &mut Forcing,
    region: &super::local::Region,
) -> f64 {
    update_fixed_of(op, state, forcing, &region.fixed);
    let State { p, r, region_residuals, .. } = state;
    let (p, r) = (&p[..], &r[..]);
    super::local::map_vertices_into(&region.vertices, region_residuals, |i| {
        let i = i as usize;
        if op.role[i] != Role::Moving {
            return (DVec3::ZERO, DVec3::ZERO);
        }
        vertex_residual(op, mesh, p, r, forcing, i)
    });
    let mut largest = 0.0f64;
    for (&i, &(vr, vp)) in region.vertices.iter().zip(region_residuals.iter()) {
        out.r[i as usize] = vr;
        out.p[i as usize] = vp;
        largest = max_nan(largest, (op.k[i as usize] * vp).length());
    }
    largest
}

/// The residual `f − N(x)` of every equation (see [`Forcing`]), written into `out`; fixed
/// vertices' `R` are brought up to date first (their residual is then zero). Returns the
/// largest residual of a moving vertex's `P` equation times `K` (a length: the size of the
/// step the plain iteration would take, over λ).
pub fn residual(
    op: &Operator,
    mesh: &PolyMesh,
    state: &mut State,
    forcing: Option<&Forcing>,
    out: &mut Forcing,
) -> f64 {
    update_fixed_forced(op, state, forcing);
    let (p, r) = (&state.p[..], &state.r[..]);
    let run = |start: usize, out_r: &mut [DVec3], out_p: &mut [DVec3]| -> f64 {
        let mut largest = 0.0f64;
        for (k, (or, opp)) in out_r.iter_mut().zip(out_p.iter_mut()).enumerate() {
            let i = start + k;
            if op.role[i] != Role::Moving {
                *or = DVec3::ZERO;
                *opp = DVec3::ZERO;
                continue;
            }
            (*or, *opp) = vertex_residual(op, mesh, p, r, forcing, i);
            largest = max_nan(largest, (op.k[i] * *opp).length());
        }
        largest
    };
    let n = p.len();
    if n < 2 * CHUNK {
        run(0, &mut out.r, &mut out.p)
    } else {
        out.r
            .par_chunks_mut(CHUNK)
            .zip(out.p.par_chunks_mut(CHUNK))
            .enumerate()
            .map(|(c, (a, b))| run(c * CHUNK, a, b))
            .reduce(|| 0.0, max_nan)
    }
}
