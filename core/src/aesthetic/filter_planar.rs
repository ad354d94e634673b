//! The planar log-aesthetic curve filter's pass ([`super::filter`], paper secs. 3.1–3.2, eqs. 2,
//! 3, 7 and 8), in the plane's own coordinates.
//!
//! The planar filter moves points only inside their plane, so a pass works on two coordinates,
//! `x` and `y` along the plane's axes, measured from its origin in units of the curve's size (the
//! diagonal of its bounding box). Every length is then between the `1e-12` of the smallest gap
//! [`crate::curve::PointSequence::validate`] admits and about 2, whatever the model's units, so
//! the curvature can be written as one quotient of lengths without overflow:
//! with `d0`, `d1` the segments before and after point i, `g0`, `g1` their lengths and `d = d0 + d1`
//! the chord of the neighbours,
//! `κ = 2 (d0 × d1) (g0 + g1)² / (g0 g1 |d|³)`, the paper's `|U × V| / |U|³` for the central
//! differences on chord-length parameters, signed about the plane's normal; the radius is the same
//! quotient turned over. The point goes to `P_ic + φ N` with `N = n × d / |d|`; its signed
//! curvature there is the target κ* when `φ = −κ* |d|² g0 g1 / (2 (g0 + g1)²)` (the first
//! derivative does not involve `P_i` and the second is affine in it), so the move is one division.
//!
//! A pass computes, per colour, the geometry of every point into flat arrays (segments, chord,
//! curvature, radius and the law value `ρ^α`), loops the compiler can run on several lanes at
//! once; then the target of every point of that colour from those arrays, one scan of its window
//! that both checks for an inflection and sums the least-squares line over the arc length added
//! up from the window's gaps; then the moves. Targets first and moves after keep the long chain of
//! dependent operations of one point from holding up the next. The model-space points are
//! written back only when the caller asks for them, and only the points that moved.
//! From [`PARALLEL_FROM`] points the geometry and the targets are computed on several threads;
//! every value is computed the same way on any thread, and the moves and their sums are made in
//! order, so the result does not depend on the thread count.
//!
//! Measured (`cargo bench -p taut-core --bench aesthetic`, two shared cores, alternating with the
//! same bench before this file): a pass over 20 points 1.0–1.5 → 0.6–1.0 µs, over 1,000 points
//! 55–61 → 30–37 µs, over 100,000 points 9.6–10.4 → 6.7–7.0 ms; a full fairing of 1,000 noisy
//! points 20.3–21.6 ms (371 passes) → 10.8–11.5 ms (370 passes), within one 16 ms frame, and
//! eight other draws of the noise (207 to 386 passes) at most 11.9 ms. While the host was busy
//! both ran slower (31.5 against 15.3 ms, the slowest draw 16.5 ms). Before the cap on targets
//! (see [`super::filter`]) the points differed from the former pass's by rounding only (about
//! 1e-15 of the curve's size after the same passes); the cap changes them where it binds.
//!
//! Where it is weak: the geometry is recomputed for every point each colour (every window of the
//! other colour holds points of both), and each window is summed afresh (sums slid from window to
//! window would lose digits on long curves).

use super::filter::{MAX_CURVATURE_RATIO, PassTotals, clothoid_share, law_limit};
use super::filter_geometry::{PARALLEL_FROM, window_span};
use super::law::{law_value, radius_from_law};
use crate::DVec3;
use crate::curve::Plane;
use rayon::prelude::*;

/// Points in a chunk of the parallel geometry loops.
const CHUNK: usize = 2048;

/// What a pass needs besides the points.
#[derive(Clone, Copy, Debug)]
pub(super) struct Rules<'a> {
    pub closed: bool,
    /// Half-width m of the windows.
    pub window: usize,
    /// α per point.
    pub alpha: &'a [f64],
    /// True when α is the same at every point.
    pub uniform_alpha: bool,
    /// Fit the signed curvature linearly in windows holding an inflection (else hold the point).
    pub clothoid: bool,
    /// Fraction of the way to its target a point moves.
    pub relaxation: f64,
    /// With the data term: where the law gives no positive radius, aim at its limit instead of
    /// holding the point ([`super::filter::law_limit`]), and pass from the law to the clothoid
    /// line gradually as a window nears an inflection.
    pub continuous: bool,
}

/// The planar filter's points and the buffers its passes work in.
#[derive(Clone, Debug)]
pub(super) struct PlanarCurve {
    plane: Plane,
    /// Model length of one coordinate unit.
    scale: f64,
    x: Vec<f64>,
    y: Vec<f64>,
    /// Points whose coordinates changed since they were last written back.
    stale: Vec<bool>,
    /// The coordinates before the current pass, restored when it fails.
    before: (Vec<f64>, Vec<f64>),
    /// The data term: the pre-fit's coordinates and the weight λ pulling towards them.
    anchor: Option<(Vec<f64>, Vec<f64>, f64)>,
    /// Segment `e` joins point `e` to point `e + 1` (the closing one last on a closed curve).
    dx: Vec<f64>,
    dy: Vec<f64>,
    gap: Vec<f64>,
    /// Per point: the chord of its neighbours, the signed curvature (NaN at the ends of an open
    /// curve), the radius and the law value `ρ^α` for the point's own α.
    chord: Vec<f64>,
    kappa: Vec<f64>,
    rho: Vec<f64>,
    law: Vec<f64>,
    /// The target curvature of each point of the colour being moved (`None`: held).
    targets: Vec<Option<f64>>,
}

/// The curvature of a point from the segments before and after it: the chord of its neighbours,
/// the signed curvature and the radius (see the module docs).
#[inline(always)]
fn bend(dx0: f64, dy0: f64, g0: f64, dx1: f64, dy1: f64, g1: f64) -> (f64, f64, f64) {
    let (cx, cy) = (dx0 + dx1, dy0 + dy1);
    let c2 = cx * cx + cy * cy;
    let chord = c2.sqrt();
    let sum = g0 + g1;
    let num = 2.0 * (dx0 * dy1 - dy0 * dx1) * sum * sum;
    let den = g0 * g1 * c2 * chord;
    (chord, num / den, den / num.abs())
}

/// Segments `start..start + dx.len()` of the points `x`, `y` (the last one wrapping to point 0
/// when it is the closing segment).
fn segments_into(start: usize, x: &[f64], y: &[f64], dx: &mut [f64], dy: &mut [f64], gap: &mut [f64]) {
    let n = x.len();
    let end = start + dx.len();
    // The segments with both ends inside the arrays, in one loop the compiler vectorizes.
    let inner = end.min(n - 1) - start;
    let (x0, x1) = (&x[start..start + inner], &x[start + 1..start + inner + 1]);
    let (y0, y1) = (&y[start..start + inner], &y[start + 1..start + inner + 1]);
    for k in 0..inner {
        let (a, b) = (x1[k] - x0[k], y1[k] - y0[k]);
        dx[k] = a;
        dy[k] = b;
        gap[k] = (a * a + b * b).sqrt();
    }
    if inner < dx.len() {
        let (a, b) = (x[0] - x[n - 1], y[0] - y[n - 1]);
        dx[inner] = a;
        dy[inner] = b;
        gap[inner] = (a * a + b * b).sqrt();
    }
}

/// Chord, curvature and radius of the points `start..start + chord.len()`, all of which have a
/// segment before and after them among `dx`, `dy`, `gap` (segment `i − 1` before point i).
fn bends_into(
    start: usize,
    (dx, dy, gap): (&[f64], &[f64], &[f64]),
    chord: &mut [f64],
    kappa: &mut [f64],
    rho: &mut [f64],
) {
    let len = chord.len();
    let (dx0, dx1) = (&dx[start - 1..start - 1 + len], &dx[start..start + len]);
    let (dy0, dy1) = (&dy[start - 1..start - 1 + len], &dy[start..start + len]);
    let (g0, g1) = (&gap[start - 1..start - 1 + len], &gap[start..start + len]);
    let (kappa, rho) = (&mut kappa[..len], &mut rho[..len]);
    for k in 0..len {
        (chord[k], kappa[k], rho[k]) = bend(dx0[k], dy0[k], g0[k], dx1[k], dy1[k], g1[k]);
    }
}

/// The sums of a window's least-squares line over the arc length from its first sample, and
/// what decides whether the window holds an inflection: whether every curvature has the sign
/// of the point's, and the largest and smallest of them times that sign.
#[derive(Clone, Copy, Debug)]
struct WindowSums {
    /// Arc length of the next sample.
    s: f64,
    sx: f64,
    sxx: f64,
    sy: f64,
    sxy: f64,
    one_signed: bool,
    largest: f64,
    smallest: f64,
}

impl Default for WindowSums {
    fn default() -> Self {
        let (s, sx, sxx, sy, sxy) = (0.0, 0.0, 0.0, 0.0, 0.0);
        WindowSums { s, sx, sxx, sy, sxy, one_signed: true, largest: 0.0, smallest: f64::INFINITY }
    }
}

impl WindowSums {
    /// Adds consecutive samples: the gap after each, its curvature and its law value
    /// (`law(k)` for the k-th of them).
    #[inline(always)]
    fn add_run(&mut self, sign: f64, gap: &[f64], kappa: &[f64], law: impl Fn(usize) -> f64) {
        // Slices of one length, so that the loop has no bounds checks.
        let len = gap.len();
        let kappa = &kappa[..len];
        let WindowSums { mut s, mut sx, mut sxx, mut sy, mut sxy, mut one_signed, mut largest, mut smallest } = *self;
        for j in 0..len {
            let v = kappa[j] * sign;
            one_signed &= v > 0.0;
            // Not f64::max: its NaN rule costs more than the pass needs (a NaN clears
            // `one_signed` already).
            largest = if v > largest { v } else { largest };
            smallest = if v < smallest { v } else { smallest };
            let y = law(j);
            sx += s;
            sxx += s * s;
            sy += y;
            sxy += s * y;
            s += gap[j];
        }
        *self = WindowSums { s, sx, sxx, sy, sxy, one_signed, largest, smallest };
    }
}

/// The sum of `values`, in four running sums (a quarter of the latency of one).
fn sum(values: &[f64]) -> f64 {
    let mut parts = [0.0; 4];
    let chunks = values.chunks_exact(4);
    let rest: f64 = chunks.remainder().iter().sum();
    for c in chunks {
        for k in 0..4 {
            parts[k] += c[k];
        }
    }
    (parts[0] + parts[1]) + (parts[2] + parts[3]) + rest
}

/// The smallest of `values`, NaN when one is NaN.
fn smallest(values: impl Iterator<Item = f64>) -> f64 {
    // A plain comparison and a separate NaN flag: one loop-carried chain of minima.
    let (mut least, mut nan) = (f64::INFINITY, false);
    for v in values {
        least = if v < least { v } else { least };
        nan |= v.is_nan();
    }
    if nan { f64::NAN } else { least }
}

/// Runs `f(offset, chunk)` over `out` in chunks, on several threads when `parallel`; each
/// element gets the same value either way.
fn chunked<T: Send>(parallel: bool, out: &mut [T], f: impl Fn(usize, &mut [T]) + Sync) {
    if parallel {
        out.par_chunks_mut(CHUNK).enumerate().for_each(|(k, chunk)| f(k * CHUNK, chunk));
    } else {
        f(0, out);
    }
}

impl PlanarCurve {
    /// The points, which must lie in `plane`.
    pub fn new(points: &[DVec3], plane: Plane) -> PlanarCurve {
        let scale = crate::mesh::bounding_box(points).map_or(1.0, |(lo, hi)| (hi - lo).length());
        let coordinate = |p: &DVec3, axis: DVec3| (*p - plane.origin).dot(axis) / scale;
        let n = points.len();
        PlanarCurve {
            plane,
            scale,
            x: points.iter().map(|p| coordinate(p, plane.axis_u)).collect(),
            y: points.iter().map(|p| coordinate(p, plane.axis_v)).collect(),
            stale: vec![false; n],
            anchor: None,
            before: (Vec::with_capacity(n), Vec::with_capacity(n)),
            dx: Vec::new(),
            dy: Vec::new(),
            gap: Vec::new(),
            chord: Vec::new(),
            kappa: Vec::new(),
            rho: Vec::new(),
            law: Vec::new(),
            targets: Vec::new(),
        }
    }

    /// Holds the points to `anchor` (in the plane) with weight λ: each move becomes
    /// `ω ((1 − λ) (target − P) + λ (anchor − P))`.
    pub fn hold_to(&mut self, anchor: &[DVec3], weight: f64) {
        let coordinate = |p: &DVec3, axis: DVec3| (*p - self.plane.origin).dot(axis) / self.scale;
        let x = anchor.iter().map(|p| coordinate(p, self.plane.axis_u)).collect();
        let y = anchor.iter().map(|p| coordinate(p, self.plane.axis_v)).collect();
        self.anchor = Some((x, y, weight));
    }

    /// The plane the points lie in.
    pub fn plane(&self) -> Plane {
        self.plane
    }

    /// Writes the points that moved since the last call into `points` (model space).
    pub fn write_back(&mut self, points: &mut [DVec3]) {
        let (origin, u, v) = (self.plane.origin, self.plane.axis_u * self.scale, self.plane.axis_v * self.scale);
        for (i, stale) in self.stale.iter_mut().enumerate() {
            if std::mem::take(stale) {
                points[i] = origin + self.x[i] * u + self.y[i] * v;
            }
        }
    }

    /// Puts back the points as they were before the last pass.
    pub fn restore(&mut self) {
        std::mem::swap(&mut self.x, &mut self.before.0);
        std::mem::swap(&mut self.y, &mut self.before.1);
    }

    /// One red–black pass over the free points of each colour in turn.
    pub fn pass(&mut self, colours: &[Vec<usize>], rules: &Rules) -> PassTotals {
        self.before.0.clone_from(&self.x);
        self.before.1.clone_from(&self.y);
        let mut totals = PassTotals::default();
        for (c, colour) in colours.iter().enumerate() {
            self.update_geometry(rules);
            if c == 0 {
                totals.mean_gap = sum(&self.gap) / self.gap.len() as f64;
            }
            // First every target of the colour (independent of each other, so the processor
            // overlaps them), then the moves, in order.
            let mut targets = std::mem::take(&mut self.targets);
            let target = |&i: &usize| self.target(i, rules);
            if self.x.len() >= PARALLEL_FROM {
                colour.par_iter().map(target).collect_into_vec(&mut targets);
            } else {
                targets.clear();
                targets.extend(colour.iter().map(target));
            }
            // The largest move and, apart, whether one was NaN (one blend a point would make the
            // loop wait on it).
            let (mut largest2, mut nan) = (totals.largest2, false);
            let law_share = self.anchor.as_ref().map_or(1.0, |a| 1.0 - a.2);
            for (&i, &target) in colour.iter().zip(&targets) {
                // A NaN target (from a NaN curvature) moves the point to NaN, and the pass fails.
                let (x, y) = match target {
                    Some(target) => {
                        totals.err2 += (self.kappa[i] - target).powi(2);
                        totals.k2 += self.kappa[i].powi(2);
                        let (x, y, capped) = self.moved(i, target, rules.relaxation * law_share);
                        totals.capped += capped as usize;
                        (x, y)
                    }
                    None if self.anchor.is_some() => {
                        totals.held += 1;
                        (self.x[i], self.y[i])
                    }
                    None => {
                        totals.held += 1;
                        continue;
                    }
                };
                // The data term: ω λ of the way back to the pre-fit.
                let (x, y) = match &self.anchor {
                    Some((ax, ay, weight)) => {
                        let pull = rules.relaxation * weight;
                        (x + pull * (ax[i] - self.x[i]), y + pull * (ay[i] - self.y[i]))
                    }
                    None => (x, y),
                };
                let d2 = (x - self.x[i]).powi(2) + (y - self.y[i]).powi(2);
                largest2 = if d2 > largest2 { d2 } else { largest2 };
                nan |= d2.is_nan();
                if x != self.x[i] || y != self.y[i] {
                    (self.x[i], self.y[i]) = (x, y);
                    self.stale[i] = true;
                }
            }
            self.targets = targets;
            totals.largest2 = if nan { f64::NAN } else { largest2 };
        }
        let (x, y, n) = (&self.x, &self.y, self.x.len());
        let closing = if rules.closed { (x[0] - x[n - 1]).powi(2) + (y[0] - y[n - 1]).powi(2) } else { f64::INFINITY };
        let steps = x.windows(2).zip(y.windows(2)).map(|(x, y)| (x[1] - x[0]).powi(2) + (y[1] - y[0]).powi(2));
        totals.shortest2 = smallest(steps.chain([closing]));
        totals
    }

    /// Segments and per point chord, curvature, radius and law value.
    fn update_geometry(&mut self, rules: &Rules) {
        let n = self.x.len();
        let closed = rules.closed;
        let parallel = n >= PARALLEL_FROM;
        let count = if closed { n } else { n - 1 };
        self.dx.resize(count, 0.0);
        self.dy.resize(count, 0.0);
        self.gap.resize(count, 0.0);
        let (x, y) = (&self.x, &self.y);
        if parallel {
            let chunks =
                self.dx.par_chunks_mut(CHUNK).zip(self.dy.par_chunks_mut(CHUNK)).zip(self.gap.par_chunks_mut(CHUNK));
            chunks.enumerate().for_each(|(k, ((dx, dy), gap))| segments_into(k * CHUNK, x, y, dx, dy, gap));
        } else {
            segments_into(0, x, y, &mut self.dx, &mut self.dy, &mut self.gap);
        }

        self.chord.resize(n, 0.0);
        self.kappa.resize(n, f64::NAN);
        self.rho.resize(n, f64::NAN);
        let segments = (&self.dx[..], &self.dy[..], &self.gap[..]);
        {
            // Points 1..n − 1 have both segments in order; the ends are done below.
            let (chord, kappa, rho) = (&mut self.chord[1..n - 1], &mut self.kappa[1..n - 1], &mut self.rho[1..n - 1]);
            if parallel {
                chord
                    .par_chunks_mut(CHUNK)
                    .zip(kappa.par_chunks_mut(CHUNK))
                    .zip(rho.par_chunks_mut(CHUNK))
                    .enumerate()
                    .for_each(|(k, ((chord, kappa), rho))| bends_into(1 + k * CHUNK, segments, chord, kappa, rho));
            } else {
                bends_into(1, segments, chord, kappa, rho);
            }
        }
        for i in [0, n - 1] {
            (self.chord[i], self.kappa[i], self.rho[i]) = if closed {
                let (a, b) = (if i == 0 { n - 1 } else { i - 1 }, i);
                bend(self.dx[a], self.dy[a], self.gap[a], self.dx[b], self.dy[b], self.gap[b])
            } else {
                (0.0, f64::NAN, f64::NAN)
            };
        }
        // The law values; for α = 1 they are the radii themselves.
        if !(rules.uniform_alpha && rules.alpha[0] == 1.0) {
            self.law.resize(n, 0.0);
            let (law, rho, alpha) = (&mut self.law[..n], &self.rho[..n], &rules.alpha[..n]);
            if rules.uniform_alpha {
                let a = alpha[0];
                chunked(parallel, law, |start, out| {
                    for (l, r) in out.iter_mut().zip(&rho[start..]) {
                        *l = law_value(*r, a);
                    }
                });
            } else {
                chunked(parallel, law, |start, out| {
                    for ((l, r), a) in out.iter_mut().zip(&rho[start..]).zip(&alpha[start..]) {
                        *l = law_value(*r, *a);
                    }
                });
            }
        }
    }

    /// The law values the window fits use.
    fn law_values<'s>(&'s self, rules: &Rules) -> &'s [f64] {
        if rules.uniform_alpha && rules.alpha[0] == 1.0 { &self.rho } else { &self.law }
    }

    /// The target curvature of point `i`: the log-aesthetic law `ρ^α = c s + d` fitted over its
    /// window at the point, or in a window where the curvature changes sign (or varies more than
    /// [`MAX_CURVATURE_RATIO`]-fold) the line of the signed curvature (α = −1) or nothing;
    /// `None` also where the law gives no positive radius.
    fn target(&self, i: usize, rules: &Rules) -> Option<f64> {
        let n = self.x.len();
        let (first, defined) = if rules.closed { (0, n) } else { (1, n - 2) };
        let (start, len) = window_span(i, n, rules.window, rules.closed, first, defined);
        let alpha = rules.alpha[i];
        // The window's samples as at most two runs of indices, the second after the seam of a
        // closed curve.
        let end = start + len;
        let runs = [(start, end.min(n)), (0, end.saturating_sub(n))];
        let sign = self.kappa[i].signum();
        let law = self.law_values(rules);
        // Windows whose points do not all share the point's α fit law values made for its α.
        let own_alpha =
            rules.uniform_alpha || runs.iter().all(|&(lo, hi)| rules.alpha[lo..hi].iter().all(|a| *a == alpha));
        // The window's samples, with the arc length s from its first sample added up from the
        // gaps (more accurate than differences of the arc length from the curve's start).
        let mut window = WindowSums::default();
        for &(lo, hi) in &runs {
            let len = hi - lo;
            let (gap, kappa, law, rho) = (&self.gap[lo..hi], &self.kappa[lo..hi], &law[lo..hi], &self.rho[lo..hi]);
            if own_alpha {
                let law = &law[..len];
                window.add_run(sign, gap, kappa, |k| law[k]);
            } else {
                let rho = &rho[..len];
                window.add_run(sign, gap, kappa, |k| law_value(rho[k], alpha));
            }
        }
        let WindowSums { largest, smallest, one_signed, sx, sxx, sy, sxy, .. } = window;
        // Arc length from the window's first sample to the point.
        let at: f64 = if i >= start {
            self.gap[start..i].iter().sum()
        } else {
            self.gap[start..].iter().chain(&self.gap[..i]).sum()
        };
        // The least-squares line's value at the point, `(sxx sy − sx sxy + at (n sxy − sx sy)) /
        // det`: one division.
        let n = len as f64;
        let det = n * sxx - sx * sx;
        if det.is_nan() || det <= 1e-14 * n * sxx {
            return None;
        }
        let line_at = |sy: f64, sxy: f64| (sxx * sy - sx * sxy + at * (n * sxy - sx * sy)) / det;
        // ρ → ∞ counts as an inflection too: a sample of nearly zero curvature would dominate the
        // line through ρ^α (α > 0) and throw the target off.
        // A target never bends more sharply than the window's samples (see `filter`'s docs).
        // The line of the signed curvature itself.
        let clothoid = || {
            let (mut s, mut sk, mut sxk) = (0.0, 0.0, 0.0);
            for &(lo, hi) in &runs {
                for (gap, kappa) in self.gap[lo..hi].iter().zip(&self.kappa[lo..hi]) {
                    sk += kappa;
                    sxk += s * kappa;
                    s += gap;
                }
            }
            let sharpest = largest.max(-smallest);
            line_at(sk, sxk).clamp(-sharpest, sharpest)
        };
        let law_window = one_signed && smallest * MAX_CURVATURE_RATIO > largest;
        if rules.continuous && (rules.clothoid || law_window) {
            // With the data term the law's line gives way to the clothoid's gradually, as the
            // window's curvature ratio goes from half MAX_CURVATURE_RATIO to all of it (or a sign
            // changes): a target that jumps when one sample crosses the threshold can keep a
            // point cycling between the two for ever.
            // Under InflectionRule::Hold only law windows get here, and they keep the law.
            let share = if rules.clothoid { clothoid_share(one_signed, largest, smallest) } else { 0.0 };
            let law = if share < 1.0 {
                let value = line_at(sy, sxy);
                match radius_from_law(value, alpha) {
                    Some(r) => Some((1.0 / r).min(largest)),
                    None => law_limit(value, alpha, largest),
                }
            } else {
                Some(0.0)
            };
            return match (law, share > 0.0) {
                (Some(law), true) => Some((1.0 - share) * sign * law + share * clothoid()),
                (Some(law), false) => Some(sign * law),
                (None, _) => None,
            };
        }
        if law_window {
            return radius_from_law(line_at(sy, sxy), alpha).map(|r| sign * (1.0 / r).min(largest));
        }
        if !rules.clothoid {
            return None;
        }
        Some(clothoid())
    }

    /// Where point `i` moves to bring its curvature `relaxation` of the way to `target`, and
    /// whether the move was cut back to the half chord.
    #[inline]
    fn moved(&self, i: usize, target: f64, relaxation: f64) -> (f64, f64, bool) {
        let n = self.x.len();
        let (a, b) = (if i == 0 { n - 1 } else { i - 1 }, if i + 1 == n { 0 } else { i + 1 });
        let (h0, h1) = (self.gap[a], self.gap[i]);
        let (cx, cy) = (self.x[b] - self.x[a], self.y[b] - self.y[a]);
        // φ / |d| (module docs); the normal is (−cy, cx) / |d|, the left normal in the plane.
        let sum = h0 + h1;
        let mut t = -target * self.chord[i] * (0.5 * h0 * h1) / (sum * sum);
        // A target that asks for more than the half chord would fold the curve.
        let capped = t.abs() > 0.5;
        if capped {
            t = 0.5f64.copysign(t);
        }
        let (tx, ty) = (0.5 * (self.x[a] + self.x[b]) - t * cy, 0.5 * (self.y[a] + self.y[b]) + t * cx);
        let (x, y) = (self.x[i], self.y[i]);
        (x + (tx - x) * relaxation, y + (ty - y) * relaxation, capped)
    }
}
