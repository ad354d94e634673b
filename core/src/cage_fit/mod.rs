//! A light Loop control cage from a dense mesh (a scan, a heavy export), whose subdivision
//! surface keeps the original's shape and volume (Kanaya, Nishio and Kobori, "A Method of Model
//! Simplification for Control Polygon", seed 002; read in `docs/control-cage.md`).
//!
//! The steps, each in its own file:
//! 1. [`simplify`]: quadric-error simplification to a ratio of the triangles or a face count
//!    (meshoptimizer, with optimal placement), borders locked where the input is open, finished
//!    by topology-checked collapses ([`collapse`]) where meshoptimizer would break the surface:
//!    the QEM cage `V_A`.
//! 2. The Loop limit-position matrix `M` of that cage ([`loop_limit_matrix`]): `V_B = M V_A`.
//! 3. [`correspond`]: a target `V_C` on the original for every limit point, by ray casts against
//!    a bounding-volume hierarchy ([`surface_index`]), made robust beyond the paper.
//! 4. [`solve`]: `M V_A' = V_C`, one sparse LU factorisation for the three coordinates.
//! 5. [`two_sided`]: further rounds (five by default) fit the sampled limit surface to the
//!    original both ways, farthest points weighted most, keeping the original's volume.
//! 6. [`evaluate`]: the paper's volume measure and sampled distances, for the QEM cage, the
//!    paper's round and the last round. A fitted cage is kept only when its limit surface is no farther from the
//!    original than the QEM cage's, in both the Hausdorff and the mean distance (of those, the
//!    smallest mean); otherwise the QEM cage is returned, and [`FitReport::verdict`] says why.
//!
//! Input comes through [`DenseMesh`], which makes scans manifold (see [`input`]). Everything
//! runs on the calling thread with rayon inside, reports progress and can be cancelled through
//! [`Progress`], and gives the same result on any number of threads. Steps that run on one
//! thread and do not depend on each other overlap: the simplification with indexing the
//! original, and the measures' preparation with the rounds and with the QEM cage's queries (as
//! tasks of rayon's pool, which report nothing).
//!
//! Weak spots: the Loop surface has no creases, so sharp edges of the original come out rounded;
//! the volume measure needs a closed original; the cage is a triangle cage (Loop), not quads.

pub mod collapse;
pub mod correspond;
pub mod evaluate;
pub mod input;
pub mod loop_step;
pub mod simplify;
pub mod solve;
pub mod surface_index;
pub mod two_sided;

pub use evaluate::{Evaluation, LimitSurface};
pub use input::{DenseMesh, InputReport};

use crate::mesh::PolyMesh;
use crate::subdiv::loop_limit_matrix;
use crate::{DVec3, Error, Result};
use correspond::Found;
use rayon::prelude::*;
use serde::Serialize;
use std::time::Instant;

/// How large the cage should be.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum CageSize {
    /// A fraction in (0, 1] of the input's triangles (the paper uses 0.25).
    Ratio(f64),
    /// About this many triangles.
    Faces(usize),
}

/// The settings of a fit.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub struct CageFitParams {
    /// Target size of the cage.
    pub size: CageSize,
    /// Fitting rounds: 1 is the paper's solve; each further round is a two-sided least-squares
    /// fit of the sampled limit surface ([`two_sided`]).
    pub rounds: u32,
}

impl Default for CageFitParams {
    fn default() -> Self {
        CageFitParams { size: CageSize::Ratio(0.25), rounds: DEFAULT_ROUNDS }
    }
}

impl CageFitParams {
    /// Settings for a size and a number of rounds.
    pub fn new(size: CageSize, rounds: u32) -> Self {
        CageFitParams { size, rounds }
    }

    /// The target face count for an input of `triangles`, or an error a designer can act on.
    pub fn target_faces(&self, triangles: usize) -> Result<usize> {
        let faces = match self.size {
            CageSize::Ratio(r) if r.is_finite() && r > 0.0 && r <= 1.0 => {
                ((r * triangles as f64).round() as usize).max(1)
            }
            CageSize::Ratio(r) => {
                return Err(Error::Input(format!(
                    "the ratio {r} is outside (0, 1]; use for example 0.25 for a quarter"
                )));
            }
            CageSize::Faces(0) => {
                return Err(Error::Input("a cage needs at least one face; ask for more faces".into()));
            }
            CageSize::Faces(n) if n > triangles => {
                return Err(Error::Input(format!(
                    "{n} faces asked for, but the input has only {triangles} triangles; ask for at most {triangles}"
                )));
            }
            CageSize::Faces(n) => n,
        };
        if !(1..=MAX_ROUNDS).contains(&self.rounds) {
            return Err(Error::Input(format!(
                "rounds must be between 1 and {MAX_ROUNDS}, not {} (the least-squares rounds settle within a few)",
                self.rounds
            )));
        }
        Ok(faces)
    }
}

/// Rounds a fit takes unless asked otherwise: the paper's solve and five two-sided rounds, after
/// which the distances measured on real scans change by a few per cent a round.
pub const DEFAULT_ROUNDS: u32 = 6;

/// Most fitting rounds asked for: each round costs a fit as large as the first, and the fit
/// settles within a few.
pub const MAX_ROUNDS: u32 = 10;

/// Most conjugate-gradient steps of one two-sided round.
const ROUND_ITERATIONS: usize = 200;

/// Receives progress and may cancel: `update` is called with the step's name and the fraction
/// of it done, on the thread that runs the fit; returning `false` cancels the fit.
pub trait Progress {
    /// Reports progress; return `false` to cancel.
    fn update(&mut self, step: &str, fraction: f64) -> bool;
}

impl<F: FnMut(&str, f64) -> bool> Progress for F {
    fn update(&mut self, step: &str, fraction: f64) -> bool {
        self(step, fraction)
    }
}

/// A [`Progress`] that shows nothing and never cancels.
#[derive(Clone, Copy, Debug, Default)]
pub struct Silent;

impl Progress for Silent {
    fn update(&mut self, _: &str, _: f64) -> bool {
        true
    }
}

/// Queries per progress report in long parallel steps.
const CHUNK: usize = 1 << 14;

/// Tracks the current step, its time and cancellation.
pub struct Monitor<'a> {
    progress: &'a mut dyn Progress,
    step: &'static str,
    started: Instant,
    steps: Vec<StepTime>,
}

impl std::fmt::Debug for Monitor<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "Monitor({})", self.step)
    }
}

impl<'a> Monitor<'a> {
    fn new(progress: &'a mut dyn Progress) -> Self {
        Monitor { progress, step: "", started: Instant::now(), steps: Vec::new() }
    }

    /// Ends the current step (recording its time) and starts the next; false when cancelled.
    fn begin(&mut self, step: &'static str) -> bool {
        self.finish();
        self.step = step;
        self.started = Instant::now();
        self.progress.update(step, 0.0)
    }

    fn finish(&mut self) {
        if !self.step.is_empty() {
            self.steps.push(StepTime { step: self.step.to_string(), seconds: self.started.elapsed().as_secs_f64() });
            self.step = "";
        }
    }

    /// `f(0..n)` in parallel, in chunks with a progress report after each; `None` when cancelled.
    pub fn map<T: Send>(&mut self, n: usize, f: impl Fn(usize) -> T + Sync) -> Option<Vec<T>> {
        let mut out = Vec::with_capacity(n);
        let mut start = 0;
        while start < n {
            let end = (start + CHUNK).min(n);
            out.par_extend((start..end).into_par_iter().map(&f));
            start = end;
            if !self.progress.update(self.step, start as f64 / n as f64) {
                return None;
            }
        }
        Some(out)
    }

    /// `f` at every one of `points`, where `f(p, before)` is given `before`, the answer at a
    /// nearby point, whose closeness it may use (a bounded search) but whose answer must not
    /// depend on it. The points are taken in [`surface_index::coherent_order`], in blocks of
    /// [`surface_index::BLOCK`] (the first of each without a `before`), blocks in parallel; the
    /// blocks do not depend on the number of threads. Progress runs over `span` of the step.
    /// `None` when cancelled.
    pub fn map_near<T: Send + Clone>(
        &mut self,
        span: std::ops::Range<f64>,
        points: &[DVec3],
        f: impl Fn(DVec3, Option<&T>) -> T + Sync,
    ) -> Option<Vec<T>> {
        let order = surface_index::coherent_order(points);
        let blocks = order.chunks(surface_index::BLOCK).collect::<Vec<_>>();
        let mut answers: Vec<Option<T>> = vec![None; points.len()];
        let mut start = 0;
        while start < blocks.len() {
            let end = (start + CHUNK / surface_index::BLOCK).min(blocks.len());
            let done: Vec<Vec<T>> = blocks[start..end]
                .par_iter()
                .map(|block| {
                    let mut out: Vec<T> = Vec::with_capacity(block.len());
                    for &i in block.iter() {
                        let answer = f(points[i as usize], out.last());
                        out.push(answer);
                    }
                    out
                })
                .collect();
            for (block, done) in blocks[start..end].iter().zip(done) {
                for (&i, answer) in block.iter().zip(done) {
                    answers[i as usize] = Some(answer);
                }
            }
            start = end;
            let done = (start * surface_index::BLOCK).min(points.len()) as f64 / points.len().max(1) as f64;
            if !self.progress.update(self.step, span.start + done * (span.end - span.start)) {
                return None;
            }
        }
        Some(answers.into_iter().map(|a| a.expect("every point is in one block")).collect())
    }
}

/// The wall time of one step.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct StepTime {
    pub step: String,
    pub seconds: f64,
}

/// One fitting round.
#[derive(Clone, Debug, PartialEq, Serialize)]
#[non_exhaustive]
pub struct RoundReport {
    /// 1 for the paper's solve, 2… for the least-squares rounds.
    pub round: u32,
    /// How the targets were found: by a ray within one edge length, by the closest point, or
    /// (border vertices) kept in place; for least-squares rounds every sample takes its closest point.
    pub ray_hits: usize,
    pub closest_points: usize,
    pub border: usize,
    /// Conjugate-gradient iterations of a least-squares round (0 for round 1).
    pub iterations: usize,
    /// The cage of this round measured; `None` when the round failed, and for the rounds between
    /// the first and the last, which are not measured (each costs about a round).
    pub evaluation: Option<Evaluation>,
    /// Why the round failed, if it did.
    pub failure: Option<String>,
}

/// What a fit did and measured; serialises as the command's report JSON.
#[derive(Clone, Debug, PartialEq, Serialize)]
#[non_exhaustive]
pub struct FitReport {
    pub input: InputReport,
    /// Triangles of the prepared input.
    pub input_triangles: usize,
    pub target_faces: usize,
    pub cage_faces: usize,
    pub cage_vertices: usize,
    /// meshoptimizer's error estimate of the simplification, relative to the mesh's extent.
    pub simplifier_error: f64,
    /// The QEM cage measured.
    pub qem: Evaluation,
    pub rounds: Vec<RoundReport>,
    /// The round whose cage was kept, 0 for the QEM cage.
    pub kept_round: u32,
    /// One sentence on what was kept and why.
    pub verdict: String,
    pub steps: Vec<StepTime>,
}

impl FitReport {
    /// The measures of the best fitted round (kept or not), if any round succeeded.
    pub fn fitted(&self) -> Option<&Evaluation> {
        let chosen = if self.kept_round > 0 { Some(self.kept_round) } else { None };
        let best = self.rounds.iter().filter_map(|r| r.evaluation.as_ref().map(|e| (r.round, e)));
        match chosen {
            Some(k) => best.into_iter().find(|(r, _)| *r == k).map(|(_, e)| e),
            None => best.min_by(|a, b| a.1.mean.total_cmp(&b.1.mean)).map(|(_, e)| e),
        }
    }
}

/// The result of a fit.
#[derive(Clone, Debug)]
#[non_exhaustive]
pub struct CageFit {
    /// The kept cage: the fitted one, or the QEM cage when fitting did not improve on it.
    pub cage: PolyMesh,
    /// The QEM cage the fit started from.
    pub qem_cage: PolyMesh,
    /// The kept cage's sampled limit surface with per-vertex distances to the original.
    pub surface: LimitSurface,
    pub report: FitReport,
}

/// Fits a Loop cage to a dense mesh; `Ok(None)` when `progress` cancelled it.
pub fn fit_cage(dense: &DenseMesh, params: &CageFitParams, progress: &mut dyn Progress) -> Result<Option<CageFit>> {
    let target = params.target_faces(dense.triangles.len())?;
    let mut monitor = Monitor::new(progress);
    macro_rules! step {
        ($name:literal) => {
            if !monitor.begin($name) {
                return Ok(None);
            }
        };
    }

    step!("simplify original");
    // The original was indexed as it was prepared ([`DenseMesh`]).
    // A closed piece cannot go below a tetrahedron's four faces.
    let index = &*dense.index;
    let simplified = simplify::simplify(dense, target.max(4 * dense.report.components))?;
    let qem_cage = simplified.cage;

    step!("limit matrix");
    let matrix = loop_limit_matrix(&qem_cage)?;
    let limit = matrix.apply(qem_cage.positions());

    step!("sample original");
    let volume = dense.closed.then(|| dense.signed_volume());
    let original = evaluate::Original::new(index, &dense.positions, dense.triangles.len(), volume);

    step!("correspondence");
    let lengths = correspond::local_edge_lengths(&qem_cage);
    let normals = qem_cage.vertex_normals();
    let border: Vec<bool> = qem_cage.vertices().map(|v| qem_cage.is_boundary_vertex(v)).collect();
    let a = qem_cage.positions();
    let Some(found) =
        monitor.map(a.len(), |i| correspond::target(index, a[i], limit[i], normals[i], lengths[i], border[i]))
    else {
        return Ok(None);
    };
    let count = |kind: Found| found.iter().filter(|(_, f)| *f == kind).count();
    let targets: Vec<DVec3> = found.iter().map(|(x, _)| *x).collect();
    let mut first = RoundReport {
        round: 1,
        ray_hits: count(Found::Ray),
        closest_points: count(Found::Closest),
        border: count(Found::Border),
        iterations: 0,
        evaluation: None,
        failure: None,
    };

    step!("solve");
    let tolerance = 1e-9 * original.diagonal.max(f64::MIN_POSITIVE);
    let solved = solve::Factorised::new(&matrix).and_then(|f| f.solve(&targets, tolerance));
    let mut cages: Vec<(RoundReport, Option<PolyMesh>)> = Vec::new();
    match solved {
        Ok(x) => {
            let mut cage = qem_cage.clone();
            cage.positions_mut().copy_from_slice(&x);
            cages.push((first, Some(cage)));
        }
        Err(e) => {
            first.failure = Some(e.to_string());
            cages.push((first, None));
        }
    }

    // Preparing a measure (refining the cage, one Loop step, indexing the sampled surface) runs on
    // one thread; the QEM cage's and the paper's round's are prepared beside the rounds, which
    // leave a core idle in their own one-thread parts (the samples' hierarchy, the volume steps,
    // the least squares).
    let round_one = cages[0].1.clone();
    let mut prepared: Option<Result<(evaluate::Prepared, Option<evaluate::Prepared>)>> = None;
    let rounds_done = rayon::in_place_scope(|s| {
        // A task of rayon's own pool, not a thread more: on a busy machine it only waits its turn.
        s.spawn(|_| {
            prepared = Some((|| {
                let qem = evaluate::prepare(&qem_cage, &original)?;
                let first = round_one.as_ref().map(|c| evaluate::prepare(c, &original)).transpose()?;
                Ok((qem, first))
            })());
        });
        (|| -> Result<Option<()>> {
            if params.rounds > 1 && cages[0].1.is_some() {
                step!("two-sided rounds");
                let sampling = two_sided::Sampling::new(&qem_cage, two_sided::LEVELS)?;
                let stride = original.samples.len().div_ceil(two_sided::POINTS).max(1);
                let points: Vec<DVec3> = original.samples.iter().step_by(stride).copied().collect();
                let mut x =
                    cages.last().and_then(|(_, c)| c.as_ref()).map(|c| c.positions().to_vec()).unwrap_or_default();
                let mut memory = two_sided::Memory::default();
                for round in 2..=params.rounds {
                    let Some((_, iterations)) = two_sided::round(
                        &sampling,
                        &original,
                        &points,
                        &mut x,
                        ROUND_ITERATIONS,
                        if round == params.rounds {
                            two_sided::LAST_ROUND_TOLERANCE
                        } else {
                            two_sided::ROUND_TOLERANCE
                        },
                        true,
                        &mut memory,
                        &mut monitor,
                    )?
                    else {
                        return Ok(None);
                    };
                    let report = RoundReport {
                        round,
                        ray_hits: 0,
                        closest_points: sampling.rows.row_count() + original.samples.len(),
                        border: 0,
                        iterations,
                        evaluation: None,
                        failure: None,
                    };
                    let mut cage = qem_cage.clone();
                    cage.positions_mut().copy_from_slice(&x);
                    cages.push((report, Some(cage)));
                }
            }
            Ok(Some(()))
        })()
    });
    if rounds_done?.is_none() {
        return Ok(None);
    }
    let (qem_prepared, mut first_prepared) = prepared.expect("the scope ran its task")?;

    step!("evaluate QEM cage");
    // The last round's measure is prepared while the QEM cage's queries run.
    let last_cage = cages.last().filter(|(r, _)| r.round != 1).and_then(|(_, c)| c.as_ref());
    let mut last_prepared = None;
    let measured = rayon::in_place_scope(|s| {
        s.spawn(|_| last_prepared = Some(last_cage.map(|c| evaluate::prepare(c, &original)).transpose()));
        evaluate::measure(qem_prepared, &original, &mut monitor)
    });
    let Some((qem, qem_surface)) = measured? else {
        return Ok(None);
    };
    let mut last_prepared = last_prepared.expect("the scope ran its task")?;
    step!("evaluate fitted cage");
    // Candidates no worse than the QEM cage in either distance; of those the smallest mean.
    let mut best: Option<(u32, PolyMesh, LimitSurface, Evaluation)> = None;
    let mut closest_rejected: Option<(u32, Evaluation)> = None;
    // The paper's round and the last are measured in full; the rounds between only lead there.
    let last = cages.len() as u32;
    for (report, cage) in &mut cages {
        let Some(cage) = cage.take() else { continue };
        if report.round != 1 && report.round != last {
            continue;
        }
        let ready = if report.round == 1 { first_prepared.take() } else { last_prepared.take() };
        let prepared = match ready {
            Some(p) => p,
            None => evaluate::prepare(&cage, &original)?,
        };
        let Some((evaluation, surface)) = evaluate::measure(prepared, &original, &mut monitor)? else {
            return Ok(None);
        };
        report.evaluation = Some(evaluation.clone());
        let no_worse = evaluation.hausdorff <= qem.hausdorff && evaluation.mean <= qem.mean;
        if no_worse && best.as_ref().is_none_or(|b| evaluation.mean < b.3.mean) {
            best = Some((report.round, cage, surface, evaluation));
        } else if !no_worse && closest_rejected.as_ref().is_none_or(|b| evaluation.mean < b.1.mean) {
            closest_rejected = Some((report.round, evaluation));
        }
    }
    monitor.finish();

    let rounds: Vec<RoundReport> = cages.into_iter().map(|(r, _)| r).collect();
    let (kept_round, cage, surface, verdict) = match (best, closest_rejected) {
        (Some((round, cage, surface, e)), _) => {
            let verdict = format!(
                "kept the fitted cage (round {round}): its limit surface is no farther from the original than the \
                 QEM cage's (Hausdorff {:.3e} vs {:.3e}, mean {:.3e} vs {:.3e} of the diagonal)",
                e.hausdorff, qem.hausdorff, e.mean, qem.mean
            );
            (round, cage, surface, verdict)
        }
        (None, Some((round, e))) => {
            let worse = if e.hausdorff > qem.hausdorff { "Hausdorff" } else { "mean" };
            let verdict = format!(
                "kept the QEM cage: the fitted cage (round {round}) came out worse in {worse} distance (Hausdorff \
                 {:.3e} vs {:.3e}, mean {:.3e} vs {:.3e} of the diagonal)",
                e.hausdorff, qem.hausdorff, e.mean, qem.mean
            );
            (0, qem_cage.clone(), qem_surface, verdict)
        }
        (None, None) => {
            let why = rounds.iter().find_map(|r| r.failure.clone()).unwrap_or_default();
            (0, qem_cage.clone(), qem_surface, format!("kept the QEM cage: fitting failed ({why})"))
        }
    };
    let report = FitReport {
        input: dense.report.clone(),
        input_triangles: dense.triangles.len(),
        target_faces: target,
        cage_faces: qem_cage.face_count(),
        cage_vertices: qem_cage.vertex_count(),
        simplifier_error: simplified.relative_error,
        qem,
        rounds,
        kept_round,
        verdict,
        steps: monitor.steps,
    };
    Ok(Some(CageFit { cage, qem_cage, surface, report }))
}
