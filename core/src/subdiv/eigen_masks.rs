//! Limit masks that have no closed form under the plain rules, from the eigenvectors of the
//! local subdivision matrix: the tangent across a crease or boundary, and the limit position and
//! tangents of a dart.
//!
//! Around a vertex `v` whose neighbourhood is refined by fixed rules, the next level's ring points
//! depend only on this level's through a small matrix `S`. The limit position mask is the left
//! eigenvector of `S` for the eigenvalue 1, the limit tangents those for its largest eigenvalues
//! below 1 (Doo and Sabin 1978; Halstead et al. 1993). A mask that is not such an eigenvector
//! gives a "limit" that depends on the level it is taken at.
//!
//! - Crease sector: at a crease (or boundary) vertex, the fan of `k` faces between its two crease
//!   edges, with edge neighbours `e_0 … e_k` (`e_0`, `e_k` on the crease) and, for Catmull–Clark,
//!   the vertices `f_0 … f_{k−1}` across the quads (`2k + 2` points for Catmull–Clark, `k + 2` for
//!   Loop). The tangent along the crease is `e_0 − e_k` (eigenvalue ½, antisymmetric under the
//!   reflection of the sector); the tangent *across* is the dominant symmetric left eigenvector,
//!   computed by power iteration on symmetric masks with the limit position deflated. OpenSubdiv
//!   uses the closed-form masks of Biermann, Levin and Zorin (2000) instead, which are exact for
//!   their modified rules and for regular sectors (Catmull–Clark `k = 2`, Loop `k = 3`) but about
//!   1° off elsewhere (Catmull–Clark `k = 3` in `tests/tests/subdiv.rs`). For `k = 1` (a corner
//!   face) the dominant symmetric eigenvalue of Catmull–Clark is a double ¼ with a Jordan block,
//!   where power iteration converges slowly, so the exact eigenvector `(e_0 + e_1)/2 − v` is used
//!   (for Loop `e_0 + e_1 − 2v`).
//! - Dart (one infinitely sharp edge at an interior vertex of valence `n`; a semi-sharp one runs
//!   out further down, and keeps the smooth masks, as OpenSubdiv does): the ring `v, e_0 … e_{n−1}` (and
//!   `f_0 … f_{n−1}` for Catmull–Clark) with the sharp edge to `e_0`, refined by the smooth vertex
//!   rule, the midpoint on the sharp edge and the smooth rules elsewhere. The limit position is the
//!   eigenvalue-1 eigenvector, the tangents the dominant symmetric (along the sharp edge) and
//!   antisymmetric (across it) ones under the reflection through the sharp edge. OpenSubdiv takes
//!   the smooth masks at darts, which are not eigenvectors there: its dart limit points move with
//!   the level (by 1.4 % of a unit cube's size at level 1 of a cube with one sharp edge end).
//!
//! Masks are computed once per size and scheme and cached.

use super::limit::RingMask;
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
    let mut s = Rows::new(n);
    s.add(vi, vi, 0.75);
    s.add(vi, e(0), 0.125);
    s.add(vi, e(k), 0.125);
    for t in [0, k] {
        s.add(e(t), vi, 0.5);
        s.add(e(t), e(t), 0.5);
    }
    for t in 1..k {
        if cc {
            // (v + e_t)/4 + (F_{t−1} + F_t)/4 with F_t = (v + e_t + f_t + e_{t+1})/4.
            s.add(e(t), vi, 0.25 + 0.125);
            s.add(e(t), e(t), 0.25 + 0.125);
            s.add(e(t), e(t - 1), 0.0625);
            s.add(e(t), e(t + 1), 0.0625);
            s.add(e(t), f(t - 1), 0.0625);
            s.add(e(t), f(t), 0.0625);
        } else {
            s.add(e(t), vi, 0.375);
            s.add(e(t), e(t), 0.375);
            s.add(e(t), e(t - 1), 0.125);
            s.add(e(t), e(t + 1), 0.125);
        }
    }
    if cc {
        // The new vertex across quad t is its face point.
        for t in 0..k {
            for p in [vi, e(t), e(t + 1), f(t)] {
                s.add(f(t), p, 0.25);
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
    let s = s.merged();
    let mut x = dominant_left(&s, x, |y| {
        deflate(y, &limit);
        symmetrize(y, mirror, 1.0);
    });
    if x[vi] > 0.0 {
        x.iter_mut().for_each(|w| *w = -*w);
    }
    x
}

/// `y − (Σ y) ℓ`: removes the component along the eigenvalue-1 left eigenvector `ℓ`.
fn deflate(y: &mut [f64], limit: &[f64]) {
    let total: f64 = y.iter().sum();
    for (w, l) in y.iter_mut().zip(limit) {
        *w -= total * l;
    }
}

/// The symmetric (`sign = 1`) or antisymmetric (`−1`) part of `y` under the reflection `mirror`.
fn symmetrize(y: &mut [f64], mirror: impl Fn(usize) -> usize, sign: f64) {
    let copy = y.to_vec();
    for (i, w) in y.iter_mut().enumerate() {
        *w = 0.5 * (copy[i] + sign * copy[mirror(i)]);
    }
}

/// The local subdivision matrix by rows, each row a few `(column, weight)` pairs: a sector of
/// `k` faces has `2k + 2` points but every row reads at most `k + 2` of them (the centre's) and
/// most rows four to six, so a dense matrix cost `k²` memory and time per power step (a
/// 10,000-sided polygon's corner took minutes and 800 MB).
#[derive(Debug)]
struct Rows(Vec<Vec<(usize, f64)>>);

impl Rows {
    fn new(n: usize) -> Self {
        Rows(vec![Vec::new(); n])
    }

    /// Adds `w` to entry `(i, j)` (entries start at 0).
    fn add(&mut self, i: usize, j: usize, w: f64) {
        self.0[i].push((j, w));
    }

    /// Each entry once, its additions summed in the order they were made (as a dense matrix's
    /// `+=` would), so the masks are the same bits as the dense computation's.
    fn merged(self) -> Rows {
        Rows(
            self.0
                .into_iter()
                .map(|row| {
                    let mut out: Vec<(usize, f64)> = Vec::with_capacity(row.len());
                    let mut at: std::collections::HashMap<usize, usize> =
                        std::collections::HashMap::with_capacity(row.len());
                    for (j, w) in row {
                        match at.get(&j) {
                            Some(&k) => out[k].1 += w,
                            None => {
                                at.insert(j, out.len());
                                out.push((j, w));
                            }
                        }
                    }
                    out
                })
                .collect(),
        )
    }
}

/// The dominant left eigenvector of `s` (rows: next-level points) within the subspace that
/// `project` keeps, by power iteration from `x`, scaled to a largest weight of 1.
fn dominant_left(s: &Rows, mut x: Vec<f64>, project: impl Fn(&mut [f64])) -> Vec<f64> {
    let n = x.len();
    let mut y = vec![0.0; n];
    project(&mut x);
    for _ in 0..20_000 {
        // y_j = Σ_i x_i s_ij, the rows taken in order as the dense sum over i was.
        y.iter_mut().for_each(|w| *w = 0.0);
        for (xi, row) in x.iter().zip(&s.0) {
            for &(j, w) in row {
                y[j] += xi * w;
            }
        }
        project(&mut y);
        let scale = y.iter().fold(0.0f64, |m, w| m.max(w.abs()));
        let change = y.iter().zip(&x).fold(0.0f64, |m, (a, b)| m.max((a / scale - b).abs()));
        for (xi, w) in x.iter_mut().zip(&y) {
            *xi = w / scale;
        }
        if change < 1e-15 {
            break;
        }
    }
    x
}

static CATMULL_CLARK_DART: [OnceLock<RingMask>; CACHED + 1] = [const { OnceLock::new() }; CACHED + 1];
static LOOP_DART: [OnceLock<RingMask>; CACHED + 1] = [const { OnceLock::new() }; CACHED + 1];

/// The limit masks of a dart of valence `n ≥ 3` over its ring `[v, e_0, f_0, e_1, f_1, …]`
/// (Catmull–Clark) or `[v, e_0, e_1, …]` (Loop), counter-clockwise from the sharp edge's `e_0`.
pub(crate) fn dart_mask(scheme: Scheme, n: usize) -> RingMask {
    let cache = match scheme {
        Scheme::CatmullClark => &CATMULL_CLARK_DART,
        Scheme::Loop => &LOOP_DART,
    };
    match cache.get(n) {
        Some(cell) => cell.get_or_init(|| compute_dart(scheme, n)).clone(),
        None => compute_dart(scheme, n),
    }
}

fn compute_dart(scheme: Scheme, n: usize) -> RingMask {
    let cc = scheme == Scheme::CatmullClark;
    let size = if cc { 2 * n + 1 } else { n + 1 };
    let vi = 0;
    let e = |j: usize| if cc { 1 + 2 * (j % n) } else { 1 + j % n };
    let f = |j: usize| 2 + 2 * (j % n);
    let nf = n as f64;
    let mut s = Rows::new(size);
    match scheme {
        Scheme::CatmullClark => {
            // v' = ((n−2)/n) v + Σ e_j / n² + Σ F_j / n², F_j = (v + e_j + f_j + e_{j+1})/4.
            let w = 1.0 / (nf * nf);
            s.add(vi, vi, (nf - 2.0) / nf);
            for j in 0..n {
                s.add(vi, e(j), w);
                for p in [vi, e(j), f(j), e(j + 1)] {
                    s.add(vi, p, 0.25 * w);
                }
                // f_j' is the face point F_j.
                for p in [vi, e(j), f(j), e(j + 1)] {
                    s.add(f(j), p, 0.25);
                }
            }
            s.add(e(0), vi, 0.5);
            s.add(e(0), e(0), 0.5);
            for j in 1..n {
                // (v + e_j)/4 + (F_{j−1} + F_j)/4.
                let r = e(j);
                s.add(r, vi, 0.25);
                s.add(r, e(j), 0.25);
                for (a, b) in [(j + n - 1, j), (j, j + 1)] {
                    for p in [vi, e(a), f(a), e(b)] {
                        s.add(r, p, 0.0625);
                    }
                }
            }
        }
        Scheme::Loop => {
            let beta = super::loop_limit::loop_beta(n);
            s.add(vi, vi, 1.0 - nf * beta);
            for j in 0..n {
                s.add(vi, e(j), beta);
            }
            s.add(e(0), vi, 0.5);
            s.add(e(0), e(0), 0.5);
            for j in 1..n {
                let r = e(j);
                s.add(r, vi, 0.375);
                s.add(r, e(j), 0.375);
                s.add(r, e(j + n - 1), 0.125);
                s.add(r, e(j + 1), 0.125);
            }
        }
    }
    // The reflection through the sharp edge: e_j ↔ e_{−j}, f_j ↔ f_{−1−j}.
    let mirror = |i: usize| {
        if i == vi {
            vi
        } else if !cc {
            e(n - (i - 1))
        } else if i % 2 == 1 {
            e(n - (i - 1) / 2)
        } else {
            f(2 * n - 1 - (i - 2) / 2)
        }
    };
    let mut start = vec![0.0; size];
    start[vi] = 1.0;
    let s = s.merged();
    let mut limit = dominant_left(&s, start, |_| {});
    let total: f64 = limit.iter().sum();
    limit.iter_mut().for_each(|w| *w /= total);
    let mut along = vec![0.0; size];
    (along[e(0)], along[vi]) = (1.0, -1.0);
    let mut along = dominant_left(&s, along, |y| {
        deflate(y, &limit);
        symmetrize(y, mirror, 1.0);
    });
    let mut across = vec![0.0; size];
    (across[e(1)], across[e(n - 1)]) = (1.0, -1.0);
    let mut across = dominant_left(&s, across, |y| symmetrize(y, mirror, -1.0));
    // Orientation: along points to e_0, across to e_1 (counter-clockwise of it), so that
    // along × across is the outward normal.
    if along[e(0)] < along[vi] {
        along.iter_mut().for_each(|w| *w = -*w);
    }
    if across[e(1)] < 0.0 {
        across.iter_mut().for_each(|w| *w = -*w);
    }
    RingMask::from_weights((0..size).map(|i| [limit[i], along[i], across[i]]).collect())
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

    #[test]
    fn dart_masks_are_affine_and_mirror_symmetric() {
        for (scheme, stride) in [(Scheme::CatmullClark, 2), (Scheme::Loop, 1)] {
            for n in 3..12 {
                let m = dart_mask(scheme, n);
                let sum = |k: usize| m.weights.iter().map(|w| w[k]).sum::<f64>();
                assert!((sum(0) - 1.0).abs() < 1e-13 && sum(1).abs() < 1e-12 && sum(2).abs() < 1e-12);
                // e_j and e_{n−j} mirror each other through the sharp edge to e_0.
                for j in 1..n {
                    let (a, b) = (m.weights[1 + stride * j], m.weights[1 + stride * (n - j)]);
                    assert!((a[0] - b[0]).abs() < 1e-12 && (a[1] - b[1]).abs() < 1e-12 && (a[2] + b[2]).abs() < 1e-12);
                }
                // Darts differ from the smooth masks (the point of computing them).
                let smooth = RingMask::smooth(scheme, n);
                assert!(m.weights.iter().zip(&smooth.weights).any(|(a, b)| (a[0] - b[0]).abs() > 1e-6));
            }
        }
    }
}
