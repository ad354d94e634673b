//! The spatial (3D) log-aesthetic filter's pass ([`super`], paper sec. 3.3): red–black moves of
//! each point towards the curvature and torsion the law asks in its window, along the normal and
//! the binormal of its Frenet frame. The planar pass is `filter_planar.rs`.

use super::*;
use crate::curve::derivatives::{first_derivative, second_derivative, third_derivative};

impl CurveFilter {
    /// One red–black pass of the spatial filter.
    pub(super) fn spatial_pass(&mut self, scratch: &mut Scratch) -> PassTotals {
        let n = self.points.len();
        scratch.before.clone_from(&self.points);
        let mut totals = PassTotals::default();
        let shape = self.shape();
        for c in 0..self.colours.len() {
            scratch.geometry.update(&self.points, shape);
            let geometry = &scratch.geometry;
            if c == 0 {
                totals.mean_gap = geometry.total / geometry.gaps.len() as f64;
            }
            // With the data term the torsion step weighs the targets of the points around each
            // point too: all of them first, from the same geometry.
            scratch.torsion_targets.clear();
            if self.settings.data_term.is_some()
                && let Some(beta) = self.settings.torsion_beta
            {
                let target = |i: usize| self.torsion_target(geometry, i, beta).unwrap_or(f64::NAN);
                if n >= PARALLEL_FROM {
                    (0..n).into_par_iter().map(target).collect_into_vec(&mut scratch.torsion_targets);
                } else {
                    scratch.torsion_targets.extend((0..n).map(target));
                }
            }
            let targets = &scratch.torsion_targets;
            let step = |&i: &usize| self.move_point(geometry, targets, i);
            if n >= PARALLEL_FROM {
                self.colours[c].par_iter().map(step).collect_into_vec(&mut scratch.moves);
            } else {
                scratch.moves.clear();
                scratch.moves.extend(self.colours[c].iter().map(step));
            }
            let held = self.settings.data_term.zip(self.prefit.as_ref());
            for (&i, m) in self.colours[c].iter().zip(&scratch.moves) {
                let kappa = geometry.local[i].kappa;
                match m.target {
                    Some(t) => {
                        totals.err2 += (kappa - t).powi(2);
                        totals.k2 += kappa.powi(2);
                    }
                    None => totals.held += 1,
                }
                totals.capped += m.capped as usize;
                let position = match held {
                    // ω ((1 − λ) (target − P) + λ (pre-fit − P)); the move holds ω already.
                    Some((term, fit)) => {
                        let p = self.points[i];
                        p + (1.0 - term.weight) * (m.position - p)
                            + self.settings.relaxation * term.weight * (fit.points[i] - p)
                    }
                    None => m.position,
                };
                let d2 = self.points[i].distance_squared(position);
                // Not f64::max: a NaN must be seen.
                if d2 > totals.largest2 || d2.is_nan() {
                    totals.largest2 = d2;
                }
                self.points[i] = position;
            }
        }
        let p = &self.points;
        let closing = if self.closed { p[n - 1].distance_squared(p[0]) } else { f64::INFINITY };
        totals.shortest2 = p.windows(2).map(|w| w[0].distance_squared(w[1])).fold(closing, f64::min);
        totals
    }

    fn neighbours(&self, i: usize) -> Option<(usize, usize)> {
        let n = self.points.len();
        if self.closed {
            Some((if i == 0 { n - 1 } else { i - 1 }, if i + 1 == n { 0 } else { i + 1 }))
        } else if i > 0 && i + 1 < n {
            Some((i - 1, i + 1))
        } else {
            None
        }
    }

    /// The window of 2m + 1 samples around `i` among the `defined` points from `first_defined`
    /// (all points of a closed curve), clamped inside them on an open curve.
    #[inline]
    fn window(&self, g: &Geometry, i: usize, first_defined: usize, defined: usize) -> Window {
        let n = self.points.len();
        let (start, len) = window_span(i, n, self.settings.window, self.closed, first_defined, defined);
        let window = Window { start, len, n, point: i, at: 0.0 };
        Window { at: window.local_arc_length(g, i), ..window }
    }

    /// The target of a log-aesthetic law `value^exponent = c s + d` (value = a radius, 1/|x|)
    /// fitted over a window of signed samples `x(data[j])`, at point `i`. Where the samples change
    /// sign (an inflection, or ρ → ∞) the target is `None`, or with `clothoid` the value of the
    /// least-squares line of `x` itself (α = −1). `None` also where the law gives no positive
    /// radius. `law`, when given, gives the law values of `1/|x|` precomputed.
    #[allow(clippy::too_many_arguments)]
    fn law_target<S>(
        &self,
        g: &Geometry,
        window: Window,
        data: &[S],
        x: impl Fn(&S) -> f64,
        law: Option<impl Fn(&S) -> f64>,
        exponent: f64,
        clothoid: bool,
    ) -> Option<f64> {
        let sign = x(&data[window.point]).signum();
        let (mut largest, mut smallest, mut one_signed) = (0.0f64, f64::INFINITY, true);
        window.for_each(g, data, |_, d| {
            let v = x(d) * sign;
            one_signed &= v > 0.0;
            if v > largest {
                largest = v;
            }
            if v < smallest {
                smallest = v;
            }
        });
        let sharpest = largest.max(-smallest);
        if self.settings.data_term.is_some() && clothoid {
            // With the data term the law's line gives way to the clothoid's gradually, as in the
            // planar filter: a target that jumps when one sample crosses the threshold kept
            // points of twenty-point space curves cycling until the pass cap.
            let share = clothoid_share(one_signed, largest, smallest);
            let law = if share < 1.0 {
                let (c, d) = match &law {
                    Some(l) => fit_window(g, window, data, l)?,
                    None => fit_window(g, window, data, |d| law_value(1.0 / (x(d) * sign), exponent))?,
                };
                let value = c * window.at + d;
                match radius_from_law(value, exponent) {
                    Some(r) => (1.0 / r).min(largest),
                    None => law_limit(value, exponent, largest)?,
                }
            } else {
                0.0
            };
            let line = if share > 0.0 {
                let (c, d) = fit_window(g, window, data, &x)?;
                (c * window.at + d).clamp(-sharpest, sharpest)
            } else {
                0.0
            };
            return Some((1.0 - share) * sign * law + share * line);
        }
        // ρ → ∞ counts as an inflection too: a sample of nearly zero curvature would dominate the
        // line through ρ^α (α > 0) and throw the target off.
        one_signed &= smallest * MAX_CURVATURE_RATIO > largest;
        // Only the one line that is used is fitted.
        // A target never bends more sharply than the window's samples (module docs).
        if !one_signed {
            if !clothoid {
                return None;
            }
            let (c, d) = fit_window(g, window, data, &x)?;
            return Some((c * window.at + d).clamp(-sharpest, sharpest));
        }
        let (c, d) = match &law {
            Some(l) => fit_window(g, window, data, l)?,
            None => fit_window(g, window, data, |d| law_value(1.0 / (x(d) * sign), exponent))?,
        };
        let value = c * window.at + d;
        match radius_from_law(value, exponent) {
            Some(r) => Some(sign * (1.0 / r).min(largest)),
            None if self.settings.data_term.is_some() => law_limit(value, exponent, largest).map(|k| sign * k),
            None => None,
        }
    }

    /// Where the spatial filter moves point `i` (`torsion_targets`: every point's torsion target,
    /// NaN where it has none, with the data term; empty without).
    fn move_point(&self, g: &Geometry, torsion_targets: &[f64], i: usize) -> Move {
        let stay = Move { position: self.points[i], target: None, capped: false };
        let Some((a, b)) = self.neighbours(i) else { return stay };
        let n = self.points.len();
        let (first, defined) = if self.closed { (0, n) } else { (1, n - 2) };
        let window = self.window(g, i, first, defined);
        let clothoid = self.settings.inflection == InflectionRule::Clothoid;
        let local = &g.local;
        let precomputed = matches!(self.settings.alpha, Alpha::Uniform(_)).then_some(|l: &Local| l.law);
        let Some(target) = self.law_target(g, window, local, |l| l.kappa, precomputed, self.alpha[i], clothoid) else {
            return stay;
        };
        let (h0, h1) = (g.gap_before(i), g.gaps[i]);
        let centre = (self.points[a] + self.points[b]) * 0.5;
        let k = 2.0 / (h0 * h1);
        let half_chord = 0.5 * g.local[i].chord;
        let s = &g.spatial[i];
        if s.normal == DVec3::ZERO {
            return stay;
        }
        // The principal normal points from the point towards P_ic (V = −k (P − P_ic)); at −φ N
        // the curvature is k |φ| / |U|².
        let (mut phi, normal, binormal) =
            (-target.abs() * s.u.length_squared() / k, s.normal, s.u.normalize().cross(s.normal));
        let mut capped = false;
        if phi.abs() > half_chord {
            phi = half_chord.copysign(phi);
            capped = true;
        }
        let mut position = centre + phi * normal;
        if !torsion_targets.is_empty() {
            if let Some(psi) = self.block_torsion_step(torsion_targets, i, position, binormal, half_chord) {
                position += psi * binormal;
            }
        } else if let Some(beta) = self.settings.torsion_beta
            && let Some(psi) = self.binormal_offset(g, i, phi, beta, k * g.spatial[i].u.length())
        {
            position += psi.clamp(-half_chord, half_chord) * binormal;
        }
        let position = self.points[i].lerp(position, self.settings.relaxation);
        Move { position, target: Some(target), capped }
    }

    /// The torsion target of point `i`: the law `μ^β = g s + h` fitted over its window, `None`
    /// where the torsion is undefined in the window, changes sign, or the law gives no radius.
    fn torsion_target(&self, g: &Geometry, i: usize, beta: f64) -> Option<f64> {
        let spatial = &g.spatial;
        if spatial[i].tau.is_nan() {
            return None;
        }
        let n = self.points.len();
        let (first, defined) = if self.closed { (0, n) } else { (2, n - 4) };
        let window = self.window(g, i, first, defined);
        let mut undefined = false;
        window.for_each(g, spatial, |_, s| undefined |= s.tau.is_nan());
        if undefined {
            return None;
        }
        // With the data term a window whose torsion changes sign is fitted by the line of τ
        // itself, as the curvature is at an inflection, so the target does not come and go as
        // noise flips a sign in the window.
        let linear = self.settings.data_term.is_some();
        self.law_target(g, window, spatial, |s| s.tau, None::<fn(&Spatial) -> f64>, beta, linear)
    }

    /// ψ from the torsion target (sec. 4.2): with the displacement (φ, ψ) from `P_ic` in the
    /// (N, B) frame, `U × V = k|U| (ψ N − φ B)`, so `τ = −(φ W_B − ψ W_N) / (k|U| (φ² + ψ²))` and
    /// `τ* = τ` is the quadratic `τ* k|U| ψ² − W_N ψ + τ* k|U| φ² + φ W_B = 0`.
    fn binormal_offset(&self, g: &Geometry, i: usize, phi: f64, beta: f64, k_u: f64) -> Option<f64> {
        let spatial = &g.spatial;
        let tau = self.torsion_target(g, i, beta)?;
        let normal = spatial[i].normal;
        let binormal = spatial[i].u.normalize().cross(normal);
        let (w_n, w_b) = (spatial[i].w.dot(normal), spatial[i].w.dot(binormal));
        let (qa, qb, qc) = (tau * k_u, -w_n, tau * k_u * phi * phi + phi * w_b);
        smaller_root(qa, qb, qc)
    }

    /// With the data term, how far point `i` (already moved to `position` by its curvature
    /// step) moves along the `binormal`: one damped Gauss–Newton step on `Σ_j (τ_j − τ*_j)²`
    /// over the five points whose torsion it takes part in (j = i − 2 … i + 2),
    /// `ψ = −Σ J_j r_j / (Σ J_j² + (t / h)²)`, the slopes `J_j = ∂τ_j/∂ψ` measured by moving the
    /// point, `h` the half chord and `t` the largest target, so a move of a half chord is what it
    /// takes to change the torsion by its own size; at most a half chord.
    ///
    /// The paper solves `τ_i = τ*_i` at the point alone, a quadratic in ψ. But the torsion at a
    /// point hardly depends on the point (its third derivative leaves the point out, and near a
    /// helix it has no normal part): the roots are large and far apart, and the smaller one threw
    /// points aside every pass; a damped Newton step on the point's own torsion still never
    /// settled (a 20-point spiral with 0.5 % noise: moves of 1e-3 to 5e-3 of the spacing to the
    /// pass cap), because a point's move changes its neighbours' torsion more than its own. The
    /// block step sees all five.
    fn block_torsion_step(
        &self,
        targets: &[f64],
        i: usize,
        position: DVec3,
        binormal: DVec3,
        half_chord: f64,
    ) -> Option<f64> {
        let n = self.points.len();
        // Points i − 4 … i + 4 (wrapping on a closed curve), the moved point in the middle.
        let index = |d: isize| -> Option<usize> {
            let j = i as isize + d;
            if self.closed {
                Some(j.rem_euclid(n as isize) as usize)
            } else {
                (0..n as isize).contains(&j).then_some(j as usize)
            }
        };
        let mut near: [Option<DVec3>; 9] = std::array::from_fn(|k| index(k as isize - 4).map(|j| self.points[j]));
        near[4] = Some(position);
        let torsions =
            |near: &[Option<DVec3>; 9]| -> [Option<f64>; 5] { std::array::from_fn(|c| local_torsion(near, c + 2)) };
        let h = 1e-4 * half_chord;
        let before = torsions(&near);
        near[4] = Some(position + h * binormal);
        let after = torsions(&near);
        let (mut jr, mut jj, mut largest) = (0.0, 0.0, 0.0f64);
        for (c, (b, a)) in before.iter().zip(&after).enumerate() {
            let target = index(c as isize - 2).map_or(f64::NAN, |j| targets[j]);
            if let (Some(b), Some(a), false) = (b, a, target.is_nan()) {
                let slope = (a - b) / h;
                jr += slope * (b - target);
                jj += slope * slope;
                largest = largest.max(target.abs());
            }
        }
        if jj == 0.0 {
            return None;
        }
        let damping = largest / half_chord;
        let psi = (-jr / (jj + damping * damping)).clamp(-half_chord, half_chord);
        psi.is_finite().then_some(psi)
    }
}

/// The torsion at `near[c]` from the points two either side, as the filter's geometry measures
/// it (`None` where a point is missing or the curve is straight there).
fn local_torsion(near: &[Option<DVec3>; 9], c: usize) -> Option<f64> {
    let [aa, a, p, b, bb] = std::array::from_fn(|k| near[c + k - 2]);
    let (aa, a, p, b, bb) = (aa?, a?, p?, b?, bb?);
    let (h0, h1) = (p.distance(a), b.distance(p));
    let u = first_derivative(a, b, h0, h1);
    let v = second_derivative(a, p, b, h0, h1);
    let w = third_derivative([aa, a, b, bb], [-(h0 + a.distance(aa)), -h0, h1, h1 + bb.distance(b)]);
    let cross = u.cross(v);
    let b2 = cross.length_squared();
    (b2 > 0.0).then(|| cross.dot(w) / b2)
}

/// The least-squares line `y = c s + d` of the samples `y(data[j])` of a window over their arc
/// length `s` from its first sample.
#[inline]
fn fit_window<S>(g: &Geometry, window: Window, data: &[S], y: impl Fn(&S) -> f64) -> Option<(f64, f64)> {
    let mut sums = LineSums::default();
    window.for_each(g, data, |s, d| sums.add_from_zero(s, y(d)));
    sums.line()
}

/// Where the spatial filter moves one point in a pass.
#[derive(Clone, Copy, Debug)]
pub(super) struct Move {
    position: DVec3,
    target: Option<f64>,
    capped: bool,
}
