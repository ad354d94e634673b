//! Clamped cubic B-splines on `[0, 1]` with dyadic knots: the only kind the CAD export writes.
//!
//! A knot vector ([`Knots`]) is `n` equal spans, plus, where a patch corner needs it, the knots
//! `2^-1, 2^-2, …, 2^-K` (or their mirror images near 1) inside the first span: a Catmull–Clark
//! patch at an extraordinary vertex is a polynomial on each of those rings, so such knots make
//! it exact everywhere but the last small square at the vertex. All knots are dyadic rationals,
//! exact in `f64`, so the knots of an edge's curve are a subset of those of each face on it and
//! a face's boundary row is the edge's curve with the missing knots inserted ([`refine`]),
//! exactly (Boehm's knot insertion).

use crate::DVec3;

/// The cubic degree every curve and surface of the export has.
pub const DEGREE: usize = 3;

/// The distinct knots of a clamped cubic B-spline on `[0, 1]`, increasing, `0` and `1`
/// included (each end counts `DEGREE + 1` times in the full vector).
#[derive(Clone, Debug, PartialEq)]
pub struct Knots {
    breaks: Vec<f64>,
}

impl Knots {
    /// `spans` equal spans.
    pub fn uniform(spans: usize) -> Knots {
        Knots { breaks: (0..=spans).map(|k| k as f64 / spans as f64).collect() }
    }

    /// `spans` equal spans, refined towards 0 with the knots `2^-k`, `k ≤ start`, and towards 1
    /// with `1 − 2^-k`, `k ≤ end`.
    pub fn graded(spans: usize, start: u32, end: u32) -> Knots {
        let mut breaks = Knots::uniform(spans).breaks;
        breaks.extend((1..=start).map(|k| 0.5f64.powi(k as i32)));
        breaks.extend((1..=end).map(|k| 1.0 - 0.5f64.powi(k as i32)));
        breaks.sort_by(f64::total_cmp);
        breaks.dedup();
        Knots { breaks }
    }

    /// The knots `breaks` (increasing, from 0 to 1), as a STEP file lists them.
    pub fn from_breaks(breaks: Vec<f64>) -> Knots {
        Knots { breaks }
    }

    /// Number of spans.
    pub fn spans(&self) -> usize {
        self.breaks.len() - 1
    }

    /// Number of control points.
    pub fn count(&self) -> usize {
        self.spans() + DEGREE
    }

    /// The distinct knots.
    pub fn breaks(&self) -> &[f64] {
        &self.breaks
    }

    /// The distinct knots and their multiplicities (what STEP writes).
    pub fn with_multiplicities(&self) -> (Vec<f64>, Vec<usize>) {
        let mut mult = vec![1; self.breaks.len()];
        mult[0] = DEGREE + 1;
        *mult.last_mut().expect("two knots at least") = DEGREE + 1;
        (self.breaks.clone(), mult)
    }

    /// The full knot vector (ends repeated).
    pub fn full(&self) -> Vec<f64> {
        let mut k = vec![0.0; DEGREE];
        k.extend_from_slice(&self.breaks);
        k.extend(std::iter::repeat_n(1.0, DEGREE));
        k
    }

    /// The knots of the same spline read from 1 to 0.
    pub fn reversed(&self) -> Knots {
        Knots { breaks: self.breaks.iter().rev().map(|t| 1.0 - t).collect() }
    }

    /// Width of the first span.
    pub fn first_width(&self) -> f64 {
        self.breaks[1] - self.breaks[0]
    }

    /// Width of the last span.
    pub fn last_width(&self) -> f64 {
        let n = self.breaks.len();
        self.breaks[n - 1] - self.breaks[n - 2]
    }

    /// The knots of both.
    pub fn union(&self, other: &Knots) -> Knots {
        let mut breaks = self.breaks.clone();
        breaks.extend_from_slice(&other.breaks);
        breaks.sort_by(f64::total_cmp);
        breaks.dedup();
        Knots { breaks }
    }

    /// The four basis functions that do not vanish at `t` (clamped to `[0, 1]`), and the index
    /// of the first: `N_{first..first+4}(t)`; with `derivative` their first derivatives.
    pub fn basis(&self, t: f64, derivative: bool) -> (usize, [f64; 4]) {
        let t = t.clamp(0.0, 1.0);
        let span = self.breaks.partition_point(|&b| b <= t).saturating_sub(1).min(self.spans() - 1);
        let knots = self.full();
        // Index into the full knot vector of the span's left knot.
        let k = span + DEGREE;
        // Cox–de Boor, as in The NURBS Book (A2.2; A2.3 for the first derivative).
        let mut n = [[0.0; 4]; 4];
        n[0][0] = 1.0;
        let mut left = [0.0; 4];
        let mut right = [0.0; 4];
        for j in 1..=DEGREE {
            left[j] = t - knots[k + 1 - j];
            right[j] = knots[k + j] - t;
            let mut saved = 0.0;
            for r in 0..j {
                n[j][r] = right[r + 1] + left[j - r];
                let temp = n[r][j - 1] / n[j][r];
                n[r][j] = saved + right[r + 1] * temp;
                saved = left[j - r] * temp;
            }
            n[j][j] = saved;
        }
        let mut out = [0.0; 4];
        if !derivative {
            for (r, o) in out.iter_mut().enumerate() {
                *o = n[r][DEGREE];
            }
        } else {
            // N'_{i,3} = 3 (N_{i,2} / (t_{i+3} − t_i) − N_{i+1,2} / (t_{i+4} − t_{i+1})).
            let lower = |idx: usize| if idx == 0 || idx > DEGREE { 0.0 } else { n[idx - 1][DEGREE - 1] };
            for (r, o) in out.iter_mut().enumerate() {
                let i = span + r;
                let a = knots[i + DEGREE] - knots[i];
                let b = knots[i + DEGREE + 1] - knots[i + 1];
                let first = if a > 0.0 { lower(r) / a } else { 0.0 };
                let second = if b > 0.0 { lower(r + 1) / b } else { 0.0 };
                *o = DEGREE as f64 * (first - second);
            }
        }
        (span, out)
    }
}

/// The point of a curve at `t`.
pub fn curve_point(knots: &Knots, points: &[DVec3], t: f64) -> DVec3 {
    let (first, n) = knots.basis(t, false);
    (0..4).map(|r| n[r] * points[first + r]).sum()
}

/// The surface of `points[i][j]` (`i` along u) at `(u, v)`: position, `∂u`, `∂v`.
pub fn surface_point(ku: &Knots, kv: &Knots, points: &[Vec<DVec3>], u: f64, v: f64) -> (DVec3, DVec3, DVec3) {
    let (fu, nu) = ku.basis(u, false);
    let (_, du) = ku.basis(u, true);
    let (fv, nv) = kv.basis(v, false);
    let (_, dv) = kv.basis(v, true);
    let (mut p, mut pu, mut pv) = (DVec3::ZERO, DVec3::ZERO, DVec3::ZERO);
    for a in 0..4 {
        for b in 0..4 {
            let q = points[fu + a][fv + b];
            p += (nu[a] * nv[b]) * q;
            pu += (du[a] * nv[b]) * q;
            pv += (nu[a] * dv[b]) * q;
        }
    }
    (p, pu, pv)
}

/// The same curve on the finer knots `to` (which must hold every knot of `from`), exactly:
/// Boehm's insertion of each missing knot in turn.
pub fn refine(from: &Knots, points: &[DVec3], to: &Knots) -> Vec<DVec3> {
    let mut knots = from.full();
    let mut pts = points.to_vec();
    for &t in to.breaks() {
        if from.breaks().contains(&t) {
            continue;
        }
        // The span [knots[k], knots[k+1]) that holds t.
        let k = knots.iter().rposition(|&x| x <= t).expect("t lies in (0, 1)");
        let mut next = Vec::with_capacity(pts.len() + 1);
        for i in 0..=pts.len() {
            if i + DEGREE <= k {
                next.push(pts[i]);
            } else if i > k {
                next.push(pts[i - 1]);
            } else {
                let a = (t - knots[i]) / (knots[i + DEGREE] - knots[i]);
                next.push((1.0 - a) * pts[i - 1] + a * pts[i]);
            }
        }
        knots.insert(k + 1, t);
        pts = next;
    }
    debug_assert_eq!(pts.len(), to.count());
    pts
}

impl super::brep::BSplineSurface {
    /// The bicubic surface on `knots_u` × `knots_v` with `points[i][j]` (the `i`-th along u).
    pub fn bicubic(knots_u: &Knots, knots_v: &Knots, points: Vec<Vec<DVec3>>) -> Self {
        let (knots_u, multiplicities_u) = knots_u.with_multiplicities();
        let (knots_v, multiplicities_v) = knots_v.with_multiplicities();
        Self { degree_u: DEGREE, degree_v: DEGREE, knots_u, multiplicities_u, knots_v, multiplicities_v, points }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn basis_is_a_partition_of_unity_and_its_derivative_sums_to_zero() {
        for knots in [Knots::uniform(1), Knots::uniform(4), Knots::graded(2, 5, 3), Knots::graded(8, 0, 6)] {
            for k in 0..=200 {
                let t = k as f64 / 200.0;
                let (_, n) = knots.basis(t, false);
                let (_, d) = knots.basis(t, true);
                assert!((n.iter().sum::<f64>() - 1.0).abs() < 1e-14, "{knots:?} {t}");
                assert!(d.iter().sum::<f64>().abs() < 1e-9, "{knots:?} {t}");
            }
        }
    }

    #[test]
    fn one_span_is_the_bezier_curve_and_its_end_derivative_is_three_legs_over_the_first_span() {
        let p = [DVec3::ZERO, DVec3::new(1.0, 2.0, 0.0), DVec3::new(3.0, 2.0, 1.0), DVec3::new(4.0, 0.0, 0.0)];
        let one = Knots::uniform(1);
        for k in 0..=10 {
            let t = k as f64 / 10.0;
            let s = 1.0 - t;
            let bez = s * s * s * p[0] + 3.0 * s * s * t * p[1] + 3.0 * s * t * t * p[2] + t * t * t * p[3];
            assert!((curve_point(&one, &p, t) - bez).length() < 1e-14);
        }
        let graded = Knots::graded(1, 3, 0);
        assert_eq!(graded.breaks(), &[0.0, 0.125, 0.25, 0.5, 1.0]);
        let (_, d) = graded.basis(0.0, true);
        assert!((d[0] + 24.0).abs() < 1e-12 && (d[1] - 24.0).abs() < 1e-12, "{d:?}");
    }

    #[test]
    fn refining_keeps_the_curve_and_reversing_reads_it_backwards() {
        let from = Knots::graded(2, 2, 0);
        let p: Vec<DVec3> =
            (0..from.count()).map(|i| DVec3::new(i as f64, ((i * 7) % 5) as f64, ((i * 3) % 4) as f64)).collect();
        let to = Knots::graded(8, 5, 4);
        let q = refine(&from, &p, &to);
        assert_eq!(q.len(), to.count());
        let back: Vec<DVec3> = p.iter().rev().copied().collect();
        for k in 0..=97 {
            let t = k as f64 / 97.0;
            assert!((curve_point(&from, &p, t) - curve_point(&to, &q, t)).length() < 1e-12, "t = {t}");
            assert!((curve_point(&from, &p, t) - curve_point(&from.reversed(), &back, 1.0 - t)).length() < 1e-12);
        }
    }
}
