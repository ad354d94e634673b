//! The bicubic Gregory patch (Gregory 1974; Chiyokura & Kimura 1983): a bicubic Bézier patch
//! whose four inner control points are doubled, so that the cross-boundary derivative along each
//! side depends on that side's own pair only (`docs/curve-mesh-gregory.md` §6, the seed
//! paper's eq. (12)).
//!
//! `S(u,v) = Σᵢ Σⱼ B³ᵢ(u) B³ⱼ(v) Qᵢⱼ(u,v)` with `Qᵢⱼ = Pᵢⱼ` on the rim and, inside,
//! ```text
//! Q11 = (u P110 + v P111)/(u + v)            Q21 = ((1−u) P210 + v P211)/((1−u) + v)
//! Q12 = (u P120 + (1−v) P121)/(u + (1−v))    Q22 = ((1−u) P220 + (1−v) P221)/((1−u) + (1−v))
//! ```
//! Point `k = 0` of each inner pair governs the `v = 0` or `v = 1` side, `k = 1` the `u = 0` or
//! `u = 1` side. Position and first derivatives are evaluated exactly everywhere, the corners
//! included: where a weight's denominator vanishes its Bernstein factor vanishes to second order,
//! so the limit does not depend on the (undefined) inner point and either is taken. The second
//! derivatives are exact away from the corners; at a corner the twist of a Gregory patch depends
//! on the direction of approach, and [`GregoryPatch::evaluate`] returns the value with the inner
//! weights frozen (documented, not a limit). The normal `S_u × S_v` is used as it is; where it
//! vanishes (two parallel first derivatives: a degenerate corner or a zero-length leg)
//! [`GregoryPatch::normal`] takes the limit towards the patch centre, measured one step of 1e-6
//! inside.

use super::bezier::{CubicBezier, bernstein3, bernstein3_d1, bernstein3_d2};
use crate::DVec3;

/// Below this `u + v` (or its mirror) a corner is taken as reached: the inner weight is frozen.
const CORNER: f64 = 1e-100;

/// A bicubic Gregory patch: 16 rim control points and 4 doubled inner ones (20 in all).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GregoryPatch {
    /// `rim[i][j]` is `Pᵢⱼ` (`i` along `u`, `j` along `v`); the entries with both `i` and `j` in
    /// `{1, 2}` are unused (kept equal to the average of the inner pair, for drawing the net).
    pub rim: [[DVec3; 4]; 4],
    /// `inner[i − 1][j − 1][k]` is `Pᵢⱼₖ` for `i, j ∈ {1, 2}`: `k = 0` governs the side `v = 0`
    /// or `v = 1`, `k = 1` the side `u = 0` or `u = 1`.
    pub inner: [[[DVec3; 2]; 2]; 2],
}

/// Position and derivatives of a patch at one parameter point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PatchDerivatives {
    /// `S(u, v)`.
    pub position: DVec3,
    /// `∂S/∂u`.
    pub du: DVec3,
    /// `∂S/∂v`.
    pub dv: DVec3,
    /// `∂²S/∂u²`.
    pub duu: DVec3,
    /// `∂²S/∂u∂v`.
    pub duv: DVec3,
    /// `∂²S/∂v²`.
    pub dvv: DVec3,
}

impl PatchDerivatives {
    /// `S_u × S_v`, normalised; `None` where it vanishes.
    pub fn unit_normal(&self) -> Option<DVec3> {
        let n = self.du.cross(self.dv);
        let scale = self.du.length() * self.dv.length();
        (n.length() > 1e-12 * scale && scale > 0.0).then(|| n.normalize())
    }
}

/// A surface patch over `[0, 1]²` that a continuity report can sample.
pub trait SurfacePatch {
    /// Position, first and second derivatives at `(u, v)`.
    fn evaluate(&self, u: f64, v: f64) -> PatchDerivatives;

    /// The unit normal at `(u, v)`, with the limit towards the patch centre where `S_u × S_v`
    /// vanishes; `None` only when that limit vanishes too.
    fn normal(&self, u: f64, v: f64) -> Option<DVec3> {
        if let Some(n) = self.evaluate(u, v).unit_normal() {
            return Some(n);
        }
        let step = 1e-6;
        let (u1, v1) = (u + step * (0.5 - u).signum(), v + step * (0.5 - v).signum());
        self.evaluate(u1, v1).unit_normal()
    }
}

impl GregoryPatch {
    /// The patch with the same rim and every inner pair collapsed onto the bicubic Bézier point
    /// `b[i][j]`: it *is* that Bézier patch.
    pub fn from_bezier(b: [[DVec3; 4]; 4]) -> Self {
        let mut inner = [[[DVec3::ZERO; 2]; 2]; 2];
        for i in 0..2 {
            for j in 0..2 {
                inner[i][j] = [b[i + 1][j + 1]; 2];
            }
        }
        GregoryPatch { rim: b, inner }
    }

    /// The four boundary curves, each in the direction of increasing parameter: `v = 0`
    /// (along `u`), `u = 1` (along `v`), `v = 1` (along `u`), `u = 0` (along `v`).
    pub fn boundary_curves(&self) -> [CubicBezier; 4] {
        let r = &self.rim;
        [
            CubicBezier::new(r[0][0], r[1][0], r[2][0], r[3][0]),
            CubicBezier::new(r[3][0], r[3][1], r[3][2], r[3][3]),
            CubicBezier::new(r[0][3], r[1][3], r[2][3], r[3][3]),
            CubicBezier::new(r[0][0], r[0][1], r[0][2], r[0][3]),
        ]
    }

    /// All 20 control points in a fixed order: the 12 rim points `P00, P10, P20, P30, P01, P31,
    /// P02, P32, P03, P13, P23, P33`, then `P110, P111, P120, P121, P210, P211, P220, P221`.
    pub fn control_points(&self) -> [DVec3; 20] {
        let r = &self.rim;
        let q = &self.inner;
        [
            r[0][0], r[1][0], r[2][0], r[3][0], r[0][1], r[3][1], r[0][2], r[3][2], r[0][3], r[1][3], r[2][3], r[3][3],
            q[0][0][0], q[0][0][1], q[0][1][0], q[0][1][1], q[1][0][0], q[1][0][1], q[1][1][0], q[1][1][1],
        ]
    }

    /// Sets the unused middle rim entries to the average of each inner pair (a drawable net).
    pub(crate) fn fill_middle(&mut self) {
        for i in 0..2 {
            for j in 0..2 {
                self.rim[i + 1][j + 1] = 0.5 * (self.inner[i][j][0] + self.inner[i][j][1]);
            }
        }
    }

    /// Position only (cheaper than [`SurfacePatch::evaluate`]).
    pub fn point(&self, u: f64, v: f64) -> DVec3 {
        let (bu, bv) = (bernstein3(u), bernstein3(v));
        let q = self.net(u, v);
        let mut s = DVec3::ZERO;
        for i in 0..4 {
            for j in 0..4 {
                s += (bu[i] * bv[j]) * q[i][j];
            }
        }
        s
    }

    /// Position and first derivatives only: `(S, S_u, S_v)`.
    pub fn first_derivatives(&self, u: f64, v: f64) -> (DVec3, DVec3, DVec3) {
        let (bu, bv) = (bernstein3(u), bernstein3(v));
        let (du, dv) = (bernstein3_d1(u), bernstein3_d1(v));
        self.first_derivatives_with(u, v, [&bu, &du], [&bv, &dv])
    }

    /// [`GregoryPatch::first_derivatives`] with the Bernstein values and first derivatives at
    /// `u` and at `v` given (a grid reuses them along its rows and columns).
    pub(crate) fn first_derivatives_with(
        &self,
        u: f64,
        v: f64,
        at_u: [&[f64; 4]; 2],
        at_v: [&[f64; 4]; 2],
    ) -> (DVec3, DVec3, DVec3) {
        let ([bu, du], [bv, dv]) = (at_u, at_v);
        let mut q = self.rim;
        let mut dq = [[(DVec3::ZERO, DVec3::ZERO); 2]; 2];
        for i in 0..2 {
            for j in 0..2 {
                let (p, pu, pv) = self.blend(i, j, u, v);
                q[i + 1][j + 1] = p;
                dq[i][j] = (pu, pv);
            }
        }
        let (mut s, mut su, mut sv) = (DVec3::ZERO, DVec3::ZERO, DVec3::ZERO);
        for i in 0..4 {
            for j in 0..4 {
                s += (bu[i] * bv[j]) * q[i][j];
                su += (du[i] * bv[j]) * q[i][j];
                sv += (bu[i] * dv[j]) * q[i][j];
            }
        }
        for i in 0..2 {
            for j in 0..2 {
                let b = bu[i + 1] * bv[j + 1];
                su += b * dq[i][j].0;
                sv += b * dq[i][j].1;
            }
        }
        (s, su, sv)
    }

    /// The 16 points `Qᵢⱼ(u, v)`: the rim with the four inner blends in the middle.
    #[inline]
    fn net(&self, u: f64, v: f64) -> [[DVec3; 4]; 4] {
        let mut q = self.rim;
        for i in 0..2 {
            for j in 0..2 {
                q[i + 1][j + 1] = self.blend(i, j, u, v).0;
            }
        }
        q
    }

    /// The blend `Q = (α A + β B)/(α + β)` of inner pair `(i, j)` and its first derivatives,
    /// with `α = u` or `1 − u` and `β = v` or `1 − v` (so `α_u = ±1`, `β_v = ±1`).
    #[inline]
    fn blend(&self, i: usize, j: usize, u: f64, v: f64) -> (DVec3, DVec3, DVec3) {
        let [a, b] = self.inner[i][j];
        let (alpha, au) = if i == 0 { (u, 1.0) } else { (1.0 - u, -1.0) };
        let (beta, bv) = if j == 0 { (v, 1.0) } else { (1.0 - v, -1.0) };
        let s = alpha + beta;
        if s < CORNER {
            return (a, DVec3::ZERO, DVec3::ZERO);
        }
        let d = a - b;
        let inv = 1.0 / s;
        let inv2 = inv * inv;
        (b + (alpha * inv) * d, (au * beta * inv2) * d, (-alpha * bv * inv2) * d)
    }

    /// [`GregoryPatch::blend`]'s derivatives with the second derivatives too.
    fn weight(&self, i: usize, j: usize, u: f64, v: f64) -> InnerBlend {
        let (_, qu, qv) = self.blend(i, j, u, v);
        let [a, b] = self.inner[i][j];
        let (alpha, au) = if i == 0 { (u, 1.0) } else { (1.0 - u, -1.0) };
        let (beta, bv) = if j == 0 { (v, 1.0) } else { (1.0 - v, -1.0) };
        let s = alpha + beta;
        if s < CORNER {
            return InnerBlend { qu, qv, quu: DVec3::ZERO, quv: DVec3::ZERO, qvv: DVec3::ZERO };
        }
        let d = a - b;
        let s3 = s * s * s;
        InnerBlend {
            qu,
            qv,
            quu: (-2.0 * beta / s3) * d,
            quv: (au * bv * (alpha - beta) / s3) * d,
            qvv: (2.0 * alpha / s3) * d,
        }
    }
}

/// The partial derivatives of an inner blend `Q`.
struct InnerBlend {
    qu: DVec3,
    qv: DVec3,
    quu: DVec3,
    quv: DVec3,
    qvv: DVec3,
}

impl SurfacePatch for GregoryPatch {
    fn evaluate(&self, u: f64, v: f64) -> PatchDerivatives {
        let (bu, bv) = (bernstein3(u), bernstein3(v));
        let (du, dv) = (bernstein3_d1(u), bernstein3_d1(v));
        let (ddu, ddv) = (bernstein3_d2(u), bernstein3_d2(v));
        let mut out = PatchDerivatives {
            position: DVec3::ZERO,
            du: DVec3::ZERO,
            dv: DVec3::ZERO,
            duu: DVec3::ZERO,
            duv: DVec3::ZERO,
            dvv: DVec3::ZERO,
        };
        let net = self.net(u, v);
        for i in 0..4 {
            for j in 0..4 {
                let q = net[i][j];
                out.position += (bu[i] * bv[j]) * q;
                out.du += (du[i] * bv[j]) * q;
                out.dv += (bu[i] * dv[j]) * q;
                out.duu += (ddu[i] * bv[j]) * q;
                out.duv += (du[i] * dv[j]) * q;
                out.dvv += (bu[i] * ddv[j]) * q;
            }
        }
        // The product rule's terms in the derivatives of the inner blends.
        for i in 0..2 {
            for j in 0..2 {
                let w = self.weight(i, j, u, v);
                let (bi, bj, di, dj) = (bu[i + 1], bv[j + 1], du[i + 1], dv[j + 1]);
                out.du += (bi * bj) * w.qu;
                out.dv += (bi * bj) * w.qv;
                out.duu += (2.0 * di * bj) * w.qu + (bi * bj) * w.quu;
                out.duv += (di * bj) * w.qv + (bi * dj) * w.qu + (bi * bj) * w.quv;
                out.dvv += (2.0 * bi * dj) * w.qv + (bi * bj) * w.qvv;
            }
        }
        out
    }
}

/// A bicubic Bézier patch, for tests and comparisons.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BezierPatch {
    /// `points[i][j]`, `i` along `u`.
    pub points: [[DVec3; 4]; 4],
}

impl SurfacePatch for BezierPatch {
    fn evaluate(&self, u: f64, v: f64) -> PatchDerivatives {
        let b = [bernstein3(u), bernstein3_d1(u), bernstein3_d2(u)];
        let c = [bernstein3(v), bernstein3_d1(v), bernstein3_d2(v)];
        let sum = |x: usize, y: usize| {
            let mut s = DVec3::ZERO;
            for i in 0..4 {
                for j in 0..4 {
                    s += (b[x][i] * c[y][j]) * self.points[i][j];
                }
            }
            s
        };
        PatchDerivatives {
            position: sum(0, 0),
            du: sum(1, 0),
            dv: sum(0, 1),
            duu: sum(2, 0),
            duv: sum(1, 1),
            dvv: sum(0, 2),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A deterministic pseudo-random point (a small LCG; no dependency needed for test data).
    fn rng(seed: &mut u64) -> DVec3 {
        let mut next = || {
            *seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            ((*seed >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
        };
        DVec3::new(next(), next(), next())
    }

    fn random_patch(seed: u64) -> GregoryPatch {
        let mut s = seed;
        let mut rim = [[DVec3::ZERO; 4]; 4];
        for i in 0..4 {
            for j in 0..4 {
                rim[i][j] = DVec3::new(i as f64, j as f64, 0.0) + 0.3 * rng(&mut s);
            }
        }
        let mut inner = [[[DVec3::ZERO; 2]; 2]; 2];
        for i in 0..2 {
            for j in 0..2 {
                let base = DVec3::new(i as f64 + 1.0, j as f64 + 1.0, 0.0);
                inner[i][j] = [base + 0.4 * rng(&mut s), base + 0.4 * rng(&mut s)];
            }
        }
        let mut p = GregoryPatch { rim, inner };
        p.fill_middle();
        p
    }

    /// Independent evaluation: the formula of eq. (12) written directly, one `Q` at a time.
    fn direct(p: &GregoryPatch, u: f64, v: f64) -> DVec3 {
        let q = |i: usize, j: usize| -> DVec3 {
            let [a, b] = p.inner[i - 1][j - 1];
            match (i, j) {
                (1, 1) => (u * a + v * b) / (u + v),
                (2, 1) => ((1.0 - u) * a + v * b) / ((1.0 - u) + v),
                (1, 2) => (u * a + (1.0 - v) * b) / (u + (1.0 - v)),
                _ => ((1.0 - u) * a + (1.0 - v) * b) / ((1.0 - u) + (1.0 - v)),
            }
        };
        let binom = [1.0, 3.0, 3.0, 1.0];
        let b = |k: usize, t: f64| binom[k] * t.powi(k as i32) * (1.0 - t).powi(3 - k as i32);
        let mut s = DVec3::ZERO;
        for i in 0..4 {
            for j in 0..4 {
                let point = if (1..3).contains(&i) && (1..3).contains(&j) { q(i, j) } else { p.rim[i][j] };
                s += b(i, u) * b(j, v) * point;
            }
        }
        s
    }

    #[test]
    fn position_matches_the_direct_formula() {
        let p = random_patch(7);
        for k in 0..50 {
            let (u, v) = (0.013 + 0.019 * k as f64, 0.97 - 0.0191 * k as f64);
            assert!(p.point(u, v).distance(direct(&p, u, v)) < 1e-13);
            assert!(p.evaluate(u, v).position.distance(direct(&p, u, v)) < 1e-13);
        }
    }

    #[test]
    fn derivatives_match_central_differences() {
        let p = random_patch(11);
        let h = 1e-5;
        for k in 0..40 {
            let (u, v) = (0.05 + 0.0227 * k as f64, 0.1 + 0.0203 * k as f64);
            let e = p.evaluate(u, v);
            let fu = (p.point(u + h, v) - p.point(u - h, v)) / (2.0 * h);
            let fv = (p.point(u, v + h) - p.point(u, v - h)) / (2.0 * h);
            assert!(fu.distance(e.du) < 1e-7, "u {u} v {v}");
            assert!(fv.distance(e.dv) < 1e-7, "u {u} v {v}");
            let d = |a: f64, b: f64| p.evaluate(a, b);
            let fuu = (d(u + h, v).du - d(u - h, v).du) / (2.0 * h);
            let fuv = (d(u, v + h).du - d(u, v - h).du) / (2.0 * h);
            let fvu = (d(u + h, v).dv - d(u - h, v).dv) / (2.0 * h);
            let fvv = (d(u, v + h).dv - d(u, v - h).dv) / (2.0 * h);
            assert!(fuu.distance(e.duu) < 1e-5, "{fuu} {}", e.duu);
            assert!(fuv.distance(e.duv) < 1e-5 && fvu.distance(e.duv) < 1e-5);
            assert!(fvv.distance(e.dvv) < 1e-5);
            let (s, su, sv) = p.first_derivatives(u, v);
            assert_eq!((s, su, sv), (e.position, e.du, e.dv));
        }
    }

    #[test]
    fn corners_take_the_limit_of_the_degenerate_denominators() {
        let p = random_patch(3);
        let curves = p.boundary_curves();
        for (u, v) in [(0.0, 0.0), (1.0, 0.0), (0.0, 1.0), (1.0, 1.0)] {
            let e = p.evaluate(u, v);
            assert!(e.position.is_finite() && e.du.is_finite() && e.dv.is_finite(), "({u}, {v})");
            assert_eq!(e.position, p.rim[3 * u as usize][3 * v as usize]);
            // The first derivatives at a corner are the legs of the two rim curves.
            let (cu, cv) = (curves[if v == 0.0 { 0 } else { 2 }], curves[if u == 0.0 { 3 } else { 1 }]);
            assert!(e.du.distance(cu.derivative(u)) < 1e-12, "({u}, {v}) {} {}", e.du, cu.derivative(u));
            assert!(e.dv.distance(cv.derivative(v)) < 1e-12);
            // …and the limit approached from inside, along several directions.
            for dir in [(1.0, 1.0), (1.0, 0.1), (0.1, 1.0)] {
                let t = 1e-7;
                let (a, b) = ((u - t * dir.0).abs(), (v - t * dir.1).abs());
                let near = p.evaluate(a, b);
                assert!(near.position.distance(e.position) < 1e-5);
                assert!(near.du.distance(e.du) < 1e-5 && near.dv.distance(e.dv) < 1e-5);
            }
        }
    }

    #[test]
    fn each_side_depends_on_its_own_inner_pair_only() {
        // The cross-boundary derivative along v = 0 ignores P111 (which governs u = 0).
        let p = random_patch(5);
        let mut q = p;
        q.inner[0][0][1] += DVec3::new(0.3, -0.2, 0.5);
        q.inner[1][0][1] += DVec3::new(-0.1, 0.4, 0.2);
        for k in 1..10 {
            let u = k as f64 / 10.0;
            assert!(p.evaluate(u, 0.0).dv.distance(q.evaluate(u, 0.0).dv) < 1e-14);
            assert_ne!(p.evaluate(0.0, u).du, q.evaluate(0.0, u).du);
        }
    }

    #[test]
    fn a_gregory_patch_with_collapsed_pairs_is_its_bezier() {
        let g = random_patch(9);
        let b = BezierPatch { points: g.rim };
        let collapsed = GregoryPatch::from_bezier(g.rim);
        for k in 0..30 {
            let (u, v) = (k as f64 / 29.0, (k * 7 % 29) as f64 / 29.0);
            let (x, y) = (collapsed.evaluate(u, v), b.evaluate(u, v));
            for (a, c) in [(x.position, y.position), (x.du, y.du), (x.dv, y.dv)] {
                assert!(a.distance(c) < 1e-13);
            }
            if (u, v) != (0.0, 0.0) && (u, v) != (1.0, 1.0) && (u, v) != (0.0, 1.0) && (u, v) != (1.0, 0.0) {
                for (a, c) in [(x.duu, y.duu), (x.duv, y.duv), (x.dvv, y.dvv)] {
                    assert!(a.distance(c) < 1e-12);
                }
            }
        }
    }

    #[test]
    fn the_normal_survives_a_degenerate_corner() {
        // A zero-length leg at (0, 0): S_u vanishes there, the normal comes from inside.
        let mut p = random_patch(13);
        p.rim[1][0] = p.rim[0][0];
        assert!(p.evaluate(0.0, 0.0).unit_normal().is_none());
        let n = p.normal(0.0, 0.0).unwrap();
        let inside = p.evaluate(1e-4, 1e-4).unit_normal().unwrap();
        assert!(n.dot(inside) > 0.99, "{n} {inside}");
    }
}
