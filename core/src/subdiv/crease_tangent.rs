//! The limit tangent across a crease or boundary, from the eigenvectors of a sector's subdivision
//! matrix.
//!
//! At a crease (or boundary) vertex `v`, a *sector* is the fan of `k` faces between its two crease
//! edges, with edge neighbours `e_0 … e_k` (`e_0`, `e_k` on the crease) and, for Catmull–Clark,
//! the vertices `f_0 … f_{k−1}` across the quads. Under the crease rules the sector's points at the
//! next level depend only on these points, through a small matrix `S` (`2k + 2` points for
//! Catmull–Clark, `k + 2` for Loop). The limit tangents at `v` are the left eigenvectors of `S`
//! for its largest eigenvalues below 1 (Doo and Sabin 1978; Halstead et al. 1993): the tangent
//! along the crease is `e_0 − e_k` (eigenvalue ½, antisymmetric under the reflection of the
//! sector), and the tangent *across* is the dominant symmetric left eigenvector, which this file
//! computes by power iteration on symmetric masks with the limit position deflated.
//!
//! This makes the normals exact for the plain rules that [`super::rules`] uses, for every `k`.
//! OpenSubdiv instead uses the closed-form masks of Biermann, Levin and Zorin (2000), which are
//! exact for their modified rules and for the regular sectors (Catmull–Clark `k = 2`, Loop
//! `k = 3`) but about 1° off elsewhere (Catmull–Clark `k = 3` in `tests/tests/subdiv.rs`).
//! For `k = 1` (a corner face) the dominant symmetric eigenvalue of Catmull–Clark is a double
//! ¼ with a Jordan block, where power iteration converges slowly, so the exact eigenvector
//! `(e_0 + e_1)/2 − v` is used (for Loop `e_0 + e_1 − 2v`). Masks are computed once per `k` and
//! scheme and cached.

use super::rules::Scheme;
use std::sync::OnceLock;

/// Sectors of up to this many faces are cached.
const CACHED: usize = 32;

static CATMULL_CLARK: [OnceLock<Vec<f64>>; CACHED + 1] = [const { OnceLock::new() }; CACHED + 1];
static LOOP: [OnceLock<Vec<f64>>; CACHED + 1] = [const { OnceLock::new() }; CACHED + 1];

/// The cross tangent mask of a sector of `k ≥ 1` faces, as weights on the points
/// `[v, e_0 … e_k]` and, for Catmull–Clark, then `f_0 … f_{k−1}`; it points into the sector.
pub(crate) fn cross_tangent_mask(scheme: Scheme, k: usize) -> std::borrow::Cow<'static, [f64]> {
    let cache = match scheme {
        Scheme::CatmullClark => &CATMULL_CLARK,
        Scheme::Loop => &LOOP,
    };
    match cache.get(k) {
        Some(cell) => cell.get_or_init(|| compute(scheme, k)).as_slice().into(),
        None => compute(scheme, k).into(),
    }
}

fn compute(scheme: Scheme, k: usize) -> Vec<f64> {
    let cc = scheme == Scheme::CatmullClark;
    let n = if cc { 2 * k + 2 } else { k + 2 };
    let (vi, e, f) = (0, |t: usize| 1 + t, |t: usize| k + 2 + t);
    if k == 1 {
        let mut x = vec![0.0; n];
        let w = if cc { 0.5 } else { 1.0 };
        (x[e(0)], x[e(1)], x[vi]) = (w, w, -2.0 * w);
        return x;
    }
    // Row i of `s`: the next level's point i from this level's points.
    let mut s = vec![vec![0.0; n]; n];
    s[vi][vi] = 0.75;
    s[vi][e(0)] = 0.125;
    s[vi][e(k)] = 0.125;
    for t in [0, k] {
        s[e(t)][vi] = 0.5;
        s[e(t)][e(t)] = 0.5;
    }
    for t in 1..k {
        if cc {
            // (v + e_t)/4 + (F_{t−1} + F_t)/4 with F_t = (v + e_t + f_t + e_{t+1})/4.
            s[e(t)][vi] = 0.25 + 0.125;
            s[e(t)][e(t)] = 0.25 + 0.125;
            s[e(t)][e(t - 1)] = 0.0625;
            s[e(t)][e(t + 1)] = 0.0625;
            s[e(t)][f(t - 1)] = 0.0625;
            s[e(t)][f(t)] = 0.0625;
        } else {
            s[e(t)][vi] = 0.375;
            s[e(t)][e(t)] = 0.375;
            s[e(t)][e(t - 1)] = 0.125;
            s[e(t)][e(t + 1)] = 0.125;
        }
    }
    if cc {
        // The new vertex across quad t is its face point.
        for t in 0..k {
            for p in [vi, e(t), e(t + 1), f(t)] {
                s[f(t)][p] = 0.25;
            }
        }
    }
    // The limit position mask, deflated from every iterate (its right eigenvector is all ones).
    let mut limit = vec![0.0; n];
    (limit[vi], limit[e(0)], limit[e(k)]) = (4.0 / 6.0, 1.0 / 6.0, 1.0 / 6.0);
    let mirror = |i: usize| match i {
        0 => 0,
        i if i <= k + 1 => e(k - (i - 1)),
        i => f(k - 1 - (i - k - 2)),
    };
    let mut x = vec![0.0; n];
    x[vi] = -((k - 1) as f64);
    for t in 1..k {
        x[e(t)] = 1.0;
    }
    let mut y = vec![0.0; n];
    for _ in 0..4000 {
        for (j, yj) in y.iter_mut().enumerate() {
            *yj = (0..n).map(|i| x[i] * s[i][j]).sum();
        }
        let total: f64 = y.iter().sum();
        for (yj, lj) in y.iter_mut().zip(&limit) {
            *yj -= total * lj;
        }
        let sym: Vec<f64> = (0..n).map(|i| 0.5 * (y[i] + y[mirror(i)])).collect();
        let scale = sym.iter().fold(0.0f64, |m, w| m.max(w.abs()));
        let change = sym.iter().zip(&x).fold(0.0f64, |m, (a, b)| m.max((a / scale - b).abs()));
        for (xi, w) in x.iter_mut().zip(&sym) {
            *xi = w / scale;
        }
        if change < 1e-15 {
            break;
        }
    }
    if x[vi] > 0.0 {
        x.iter_mut().for_each(|w| *w = -*w);
    }
    x
}

#[cfg(test)]
mod tests {
    use super::*;

    fn normalised(x: &[f64]) -> Vec<f64> {
        let m = x.iter().fold(0.0f64, |m, w| m.max(w.abs()));
        x.iter().map(|w| w / m).collect()
    }

    #[test]
    fn regular_sectors_give_the_known_masks() {
        // Catmull–Clark k = 2 is a regular boundary of the bicubic B-spline: the cross derivative
        // is ((f_0 + 4 e_1 + f_1) − (e_0 + 4 v + e_2)) / 6.
        let cc = cross_tangent_mask(Scheme::CatmullClark, 2);
        let expected = normalised(&[-4.0, -1.0, 4.0, -1.0, 1.0, 1.0]);
        for (a, b) in normalised(&cc).iter().zip(&expected) {
            assert!((a - b).abs() < 1e-12, "{cc:?}");
        }
        // Loop k = 2 by hand: the left eigenvector e_1 − v of eigenvalue 3/8.
        let lp = cross_tangent_mask(Scheme::Loop, 2);
        for (a, b) in normalised(&lp).iter().zip(&[-1.0, 0.0, 1.0, 0.0]) {
            assert!((a - b).abs() < 1e-12, "{lp:?}");
        }
        // Loop k = 3 (a regular boundary) by hand: e_1 + e_2 − v − (e_0 + e_3)/2 is a left
        // eigenvector of eigenvalue ½, the same as the tangent along the boundary. (Hoppe et al.'s
        // e_1 + e_2 − e_0 − e_3 is not one under the plain rules: it belongs to their modified edge
        // rules next to creases.)
        let lp = cross_tangent_mask(Scheme::Loop, 3);
        for (a, b) in normalised(&lp).iter().zip(&[-1.0, -0.5, 1.0, 1.0, -0.5]) {
            assert!((a - b).abs() < 1e-12, "{lp:?}");
        }
    }

    #[test]
    fn masks_sum_to_zero_are_symmetric_and_cached() {
        for scheme in [Scheme::CatmullClark, Scheme::Loop] {
            for k in 1..40 {
                let m = cross_tangent_mask(scheme, k);
                assert!(m.iter().sum::<f64>().abs() < 1e-12, "{scheme:?} {k}");
                assert!(m[0] < 0.0);
                for t in 0..=k {
                    assert!((m[1 + t] - m[1 + k - t]).abs() < 1e-12);
                }
            }
        }
        assert!(std::ptr::eq(
            cross_tangent_mask(Scheme::Loop, 5).as_ptr(),
            cross_tangent_mask(Scheme::Loop, 5).as_ptr()
        ));
    }
}
