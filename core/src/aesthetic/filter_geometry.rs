//! The per-pass geometry of the space-curve log-aesthetic filter ([`super::filter`], paper sec.
//! 4.2): chord gaps, arc length and, per point, the discrete curvature (sec. 3.1 eqs. 1 and 3)
//! with the law value `ρ^α` the window fits use, the frame and the torsion. The planar filter
//! works in its plane's coordinates instead ([`super::filter_planar`]).
//!
//! The filter moves one colour of points and then needs the geometry of every point again (each
//! curvature involves a point of the other colour), so this runs once a colour, in buffers kept
//! from pass to pass (a pass allocates nothing). Points are independent, so from
//! [`PARALLEL_FROM`] points they are computed on several threads with the same result for any
//! count; the arc-length prefix sums stay sequential.

use super::law::law_value;
use crate::DVec3;
use crate::curve::derivatives::{first_derivative, second_derivative, third_derivative};
use rayon::prelude::*;

/// Points from which the geometry and the moves are computed on several threads (below it
/// threads cost more than they save). The result does not depend on it.
pub(super) const PARALLEL_FROM: usize = 4096;

/// Per point: the chord of its neighbours `|P_{i+1} − P_{i−1}|`, the curvature (NaN at the ends
/// of an open curve) and
/// `law_value(1/|κ|, α)` when α is the same everywhere (NaN otherwise).
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct Local {
    pub chord: f64,
    pub kappa: f64,
    pub law: f64,
}

/// Per point, for the space filter: the first derivative, the principal normal, the third
/// derivative and the torsion (NaN where it is undefined).
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct Spatial {
    pub u: DVec3,
    pub normal: DVec3,
    pub w: DVec3,
    pub tau: f64,
}

/// The geometry of the current points, in buffers reused from pass to pass.
#[derive(Clone, Debug, Default)]
pub(super) struct Geometry {
    /// Length of segment `e`, which joins point `e` to point `e + 1` (the closing one last on a
    /// closed curve).
    pub gaps: Vec<f64>,
    /// Cumulative arc length at each point.
    pub arc: Vec<f64>,
    /// Total length, the closing segment included.
    pub total: f64,
    pub local: Vec<Local>,
    pub spatial: Vec<Spatial>,
}

/// What the geometry is computed for.
#[derive(Clone, Copy, Debug)]
pub(super) struct Shape {
    pub closed: bool,
    /// α when it is the same at every point.
    pub uniform_alpha: Option<f64>,
}

/// Fills `out[i] = f(i)` for every i, on several threads when `parallel`.
fn fill<T: Send>(parallel: bool, out: &mut [T], f: impl Fn(usize) -> T + Sync) {
    if parallel {
        out.par_iter_mut().enumerate().for_each(|(i, o)| *o = f(i));
    } else {
        for (i, o) in out.iter_mut().enumerate() {
            *o = f(i);
        }
    }
}

impl Geometry {
    /// The gap of the segment before point `i` (the closing one before point 0).
    #[inline]
    pub fn gap_before(&self, i: usize) -> f64 {
        self.gaps[if i == 0 { self.gaps.len() - 1 } else { i - 1 }]
    }

    /// Recomputes everything for the points `p`.
    pub fn update(&mut self, p: &[DVec3], shape: Shape) {
        let n = p.len();
        let closed = shape.closed;
        let parallel = n >= PARALLEL_FROM;
        let count = if closed { n } else { n - 1 };
        self.gaps.resize(count, 0.0);
        fill(parallel, &mut self.gaps, |e| p[if e + 1 == n { 0 } else { e + 1 }].distance(p[e]));
        self.arc.clear();
        let mut total = 0.0;
        for g in &self.gaps {
            self.arc.push(total);
            total += g;
        }
        if self.arc.len() < n {
            self.arc.push(total);
        }
        self.total = total;
        let gaps = &self.gaps;
        let neighbours = |i: usize| {
            if i > 0 && i + 1 < n {
                Some((i - 1, i + 1))
            } else if closed {
                Some((if i == 0 { n - 1 } else { i - 1 }, if i + 1 == n { 0 } else { i + 1 }))
            } else {
                None
            }
        };
        let law = |kappa: f64| shape.uniform_alpha.map_or(f64::NAN, |alpha| law_value(1.0 / kappa.abs(), alpha));
        let undefined = Local { chord: 0.0, kappa: f64::NAN, law: f64::NAN };
        self.local.resize(n, undefined);
        self.spatial.resize(n, Spatial::default());
        let gap_before = |i: usize| gaps[if i == 0 { count - 1 } else { i - 1 }];
        let spatial = |i: usize| -> (Local, Spatial) {
            let none = Spatial { tau: f64::NAN, ..Spatial::default() };
            let Some((a, b)) = neighbours(i) else { return (undefined, none) };
            let (h0, h1) = (gap_before(i), gaps[i]);
            let u = first_derivative(p[a], p[b], h0, h1);
            let v = second_derivative(p[a], p[i], p[b], h0, h1);
            let cross = u.cross(v);
            let kappa = cross.length() / (u.length_squared() * u.length());
            let t = u / u.length();
            // Principal normal: the part of V across the tangent.
            let mut s = Spatial { u, normal: (v - v.dot(t) * t).normalize_or_zero(), ..none };
            if let (Some((aa, _)), Some((_, bb))) = (neighbours(a), neighbours(b))
                && aa != b
                && bb != a
            {
                let t4 = [-(h0 + gap_before(a)), -h0, h1, h1 + gaps[b]];
                s.w = third_derivative([p[aa], p[a], p[b], p[bb]], t4);
                let b2 = cross.length_squared();
                if b2 > 0.0 {
                    s.tau = cross.dot(s.w) / b2;
                }
            }
            (Local { chord: p[b].distance(p[a]), kappa, law: law(kappa) }, s)
        };
        if parallel {
            self.local.par_iter_mut().zip(self.spatial.par_iter_mut()).enumerate().for_each(|(i, (l, s))| {
                (*l, *s) = spatial(i);
            });
        } else {
            for (i, (l, s)) in self.local.iter_mut().zip(self.spatial.iter_mut()).enumerate() {
                (*l, *s) = spatial(i);
            }
        }
    }
}

/// The window of point `i` among the `defined` points from `first_defined` (all `n` points of a
/// closed curve): its first sample and its length, 2m + 1 samples centred on the point where
/// they fit, shifted inside the defined points near the ends of an open curve.
#[inline]
pub(super) fn window_span(
    i: usize,
    n: usize,
    m: usize,
    closed: bool,
    first_defined: usize,
    defined: usize,
) -> (usize, usize) {
    let len = (2 * m + 1).min(defined);
    let start = if closed {
        (i + n - m.min(n)) % n
    } else {
        i.saturating_sub(m).clamp(first_defined, first_defined + defined - len)
    };
    (start, len)
}

/// A window of consecutive samples: `len` of them from `start` (mod `n`); `at` is the arc
/// length from its first sample to the point it serves, `point`.
#[derive(Clone, Copy, Debug)]
pub(super) struct Window {
    pub start: usize,
    pub len: usize,
    pub n: usize,
    pub point: usize,
    pub at: f64,
}

impl Window {
    /// Arc length from the window's first sample to point `j` (across the seam of a closed
    /// curve).
    #[inline]
    pub fn local_arc_length(&self, g: &Geometry, j: usize) -> f64 {
        let d = g.arc[j] - g.arc[self.start];
        if d < 0.0 { d + g.total } else { d }
    }

    /// Calls `f(arc length from the window's first sample, data[j])` for every sample j in
    /// order: over at most two contiguous runs (the second after the seam of a closed curve), so
    /// that the loops carry no wrapping and no bounds checks.
    #[inline]
    pub fn for_each<S>(&self, g: &Geometry, data: &[S], mut f: impl FnMut(f64, &S)) {
        let origin = g.arc[self.start];
        let end = self.start + self.len;
        let first = end.min(self.n);
        for (s, d) in g.arc[self.start..first].iter().zip(&data[self.start..first]) {
            f(s - origin, d);
        }
        if end > self.n {
            let shift = g.total - origin;
            for (s, d) in g.arc[..end - self.n].iter().zip(&data[..end - self.n]) {
                f(s + shift, d);
            }
        }
    }
}
