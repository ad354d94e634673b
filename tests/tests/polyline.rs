//! Properties of the NUSD curve solver, checked through `taut_core`'s public API against
//! references computed here, independently of the solver: natural and periodic cubic splines
//! (tridiagonal and cyclic systems solved in this file), the control polygon, similarity
//! transforms, and the paper's own stopping rule.
//!
//! Run with `--nocapture` to see the measured numbers.

use glam::{DQuat, DVec3};
use taut_core::Error;
use taut_core::nusd::Spacing;
use taut_core::nusd::polyline::{CurveSettings, CurveSolution, Polyline, smooth};

/// An open control polygon with segments of different lengths, not in a plane.
fn open_control() -> Vec<DVec3> {
    vec![
        DVec3::new(0.0, 0.0, 0.0),
        DVec3::new(1.0, 2.0, 0.0),
        DVec3::new(3.0, 2.5, 1.0),
        DVec3::new(4.0, 0.0, 0.5),
        DVec3::new(6.0, 1.0, -1.0),
    ]
}

/// A closed, irregular pentagon, not in a plane.
fn closed_control() -> Vec<DVec3> {
    vec![
        DVec3::new(0.0, 0.0, 0.0),
        DVec3::new(2.0, -0.5, 0.3),
        DVec3::new(3.0, 1.5, 0.0),
        DVec3::new(1.5, 2.5, -0.4),
        DVec3::new(-0.5, 1.2, 0.2),
    ]
}

fn solve(control: &Polyline, insert: usize, tol: f64, spacing: Spacing) -> CurveSolution {
    let settings = CurveSettings { insert, tol, spacing, ..CurveSettings::default() };
    let solution = smooth(control, &settings).expect("the solve must succeed");
    assert!(solution.converged, "not converged: {solution:?}");
    assert_eq!(solution.retries, 0, "no retry expected without tension");
    solution
}

fn diagonal(points: &[DVec3]) -> f64 {
    let lo = points.iter().fold(DVec3::INFINITY, |a, p| a.min(*p));
    let hi = points.iter().fold(DVec3::NEG_INFINITY, |a, p| a.max(*p));
    (hi - lo).length()
}

fn max_distance(a: &[DVec3], b: &[DVec3]) -> f64 {
    assert_eq!(a.len(), b.len());
    a.iter().zip(b).map(|(p, q)| p.distance(*q)).fold(0.0, f64::max)
}

fn distance_to_segment(p: DVec3, a: DVec3, b: DVec3) -> f64 {
    let ab = b - a;
    let t = ((p - a).dot(ab) / ab.length_squared()).clamp(0.0, 1.0);
    p.distance(a + t * ab)
}

/// Knot intervals `h_i` between consecutive points (the closing one too when `closed`).
fn intervals(points: &[DVec3], closed: bool, uniform: bool) -> Vec<f64> {
    let n = points.len();
    let segments = if closed { n } else { n - 1 };
    (0..segments).map(|i| if uniform { 1.0 } else { points[i].distance(points[(i + 1) % n]) }).collect()
}

/// Second derivatives `M` of the natural cubic spline (M = 0 at both ends) by the Thomas
/// algorithm on `h_{i−1} M_{i−1} + 2 (h_{i−1} + h_i) M_i + h_i M_{i+1} = 6 (d_i − d_{i−1})`.
fn natural_spline(points: &[DVec3], h: &[f64]) -> Vec<DVec3> {
    let n = points.len();
    let mut diag = vec![1.0; n];
    let mut upper = vec![0.0; n];
    let mut rhs = vec![DVec3::ZERO; n];
    for i in 1..n - 1 {
        let lower = h[i - 1];
        diag[i] = 2.0 * (h[i - 1] + h[i]);
        upper[i] = h[i];
        rhs[i] = 6.0 * ((points[i + 1] - points[i]) / h[i] - (points[i] - points[i - 1]) / h[i - 1]);
        // Eliminate the lower entry with the previous row.
        let m = lower / diag[i - 1];
        diag[i] -= m * upper[i - 1];
        rhs[i] = rhs[i] - m * rhs[i - 1];
    }
    let mut m = vec![DVec3::ZERO; n];
    for i in (1..n - 1).rev() {
        m[i] = (rhs[i] - upper[i] * m[i + 1]) / diag[i];
    }
    m
}

/// Second derivatives of the periodic cubic spline: the cyclic system, solved densely by Gaussian
/// elimination with partial pivoting (small n).
fn periodic_spline(points: &[DVec3], h: &[f64]) -> Vec<DVec3> {
    let n = points.len();
    let mut a = vec![vec![0.0; n]; n];
    let mut rhs = vec![DVec3::ZERO; n];
    for i in 0..n {
        let (prev, next) = ((i + n - 1) % n, (i + 1) % n);
        a[i][prev] += h[prev];
        a[i][i] += 2.0 * (h[prev] + h[i]);
        a[i][next] += h[i];
        rhs[i] = 6.0 * ((points[next] - points[i]) / h[i] - (points[i] - points[prev]) / h[prev]);
    }
    for col in 0..n {
        let pivot = (col..n).max_by(|&r, &s| a[r][col].abs().total_cmp(&a[s][col].abs())).unwrap();
        a.swap(col, pivot);
        rhs.swap(col, pivot);
        for row in col + 1..n {
            let f = a[row][col] / a[col][col];
            for c in col..n {
                a[row][c] -= f * a[col][c];
            }
            rhs[row] = rhs[row] - f * rhs[col];
        }
    }
    let mut m = vec![DVec3::ZERO; n];
    for row in (0..n).rev() {
        let mut acc = rhs[row];
        for c in row + 1..n {
            acc -= a[row][c] * m[c];
        }
        m[row] = acc / a[row][row];
    }
    m
}

/// The spline with second derivatives `m` sampled like the solver's output: every knot followed
/// by `insert` evenly spaced parameters on its interval.
fn sample_spline(points: &[DVec3], h: &[f64], m: &[DVec3], insert: usize, closed: bool) -> Vec<DVec3> {
    let n = points.len();
    let mut out = Vec::new();
    for i in 0..h.len() {
        let j_end = if !closed && i + 1 == h.len() { insert + 1 } else { insert };
        for j in 0..=j_end {
            let (b, a) = (j as f64 / (insert + 1) as f64, 1.0 - j as f64 / (insert + 1) as f64);
            let (p0, p1, m0, m1) = (points[i], points[(i + 1) % n], m[i], m[(i + 1) % n]);
            out.push(a * p0 + b * p1 + ((a * a * a - a) * m0 + (b * b * b - b) * m1) * h[i] * h[i] / 6.0);
        }
    }
    out
}

/// Measured error of the converged polyline against the spline, relative to the diagonal, for
/// each insert count; also checks that the control points are reproduced exactly.
fn errors_against_spline(control: &Polyline, inserts: &[usize], spacing: Spacing) -> Vec<f64> {
    let uniform = spacing == Spacing::Uniform;
    let h = intervals(&control.points, control.closed, uniform);
    let m = if control.closed { periodic_spline(&control.points, &h) } else { natural_spline(&control.points, &h) };
    let scale = diagonal(&control.points);
    inserts
        .iter()
        .map(|&insert| {
            let solution = solve(control, insert, 1e-7, spacing);
            for (k, p) in control.points.iter().enumerate() {
                assert_eq!(solution.curve.points[Polyline::refined_index(k, insert)], *p, "control point {k}");
            }
            let reference = sample_spline(&control.points, &h, &m, insert, control.closed);
            let error = max_distance(&solution.curve.points, &reference) / scale;
            eprintln!(
                "{spacing:?} closed={} insert {insert:2}: error/diag {error:.3e}, {} iterations",
                control.closed, solution.iterations
            );
            error
        })
        .collect()
}

/// Each doubling of the inserted points must divide the error by a clear factor (O(h²) gives
/// about 4; we ask for 2.8).
fn assert_second_order(errors: &[f64], finest_bound: f64) {
    for pair in errors.windows(2) {
        assert!(pair[0] > 2.8 * pair[1], "error does not shrink like h²: {errors:?}");
    }
    assert!(*errors.last().unwrap() < finest_bound, "{errors:?}");
}

const INSERTS: [usize; 4] = [3, 7, 15, 31]; // h halves from one to the next

#[test]
fn chord_spacing_converges_to_the_natural_chord_length_spline() {
    let errors = errors_against_spline(&Polyline::new(open_control(), false), &INSERTS, Spacing::Chord);
    assert_second_order(&errors, 1e-4);
}

#[test]
fn uniform_spacing_converges_to_the_uniform_knot_natural_spline() {
    let errors = errors_against_spline(&Polyline::new(open_control(), false), &INSERTS, Spacing::Uniform);
    assert_second_order(&errors, 1e-4);
}

#[test]
fn closed_curves_converge_to_the_periodic_chord_length_spline() {
    let errors = errors_against_spline(&Polyline::new(closed_control(), true), &INSERTS, Spacing::Chord);
    assert_second_order(&errors, 1e-4);
}

#[test]
fn chord_spacing_removes_the_bulge_of_uniform_spacing_at_a_short_segment() {
    // A peak with a very short flat top between two long flanks (the paper's Fig. 1 and 4
    // situation): the uniform-knot spline rushes through the short top and bulges above it.
    let control = Polyline::new(
        vec![
            DVec3::new(0.0, 0.0, 0.0),
            DVec3::new(5.0, 5.0, 0.0),
            DVec3::new(5.5, 5.0, 0.0),
            DVec3::new(10.0, 0.0, 0.0),
        ],
        false,
    );
    // How far the curve leaves the bounding box of its control points.
    let (lo, hi) = (DVec3::ZERO, DVec3::new(10.0, 5.0, 0.0));
    let protrusion = |solution: &CurveSolution| {
        let outside = |p: DVec3| ((lo - p).max(DVec3::ZERO) + (p - hi).max(DVec3::ZERO)).length();
        solution.curve.points.iter().map(|p| outside(*p)).fold(0.0, f64::max)
    };
    let chord = solve(&control, 15, 1e-7, Spacing::Chord);
    let uniform = solve(&control, 15, 1e-7, Spacing::Uniform);
    let (p_chord, p_uniform) = (protrusion(&chord), protrusion(&uniform));
    let apart = max_distance(&chord.curve.points, &uniform.curve.points);
    eprintln!("protrusion: chord {p_chord:.4}, uniform {p_uniform:.4}; the two results are {apart:.3} apart");
    assert!(apart > 0.3, "chord and uniform spacing must differ here");
    assert!(p_uniform > 0.5 && p_chord < 0.05, "chord {p_chord} vs uniform {p_uniform}");
}

/// Largest distance of the inserted points of each segment to that segment of the polygon.
fn deviation_from_polygon(control: &Polyline, solution: &CurveSolution, insert: usize, segments: &[usize]) -> f64 {
    let p = &control.points;
    let mut worst: f64 = 0.0;
    for &s in segments {
        for j in 1..=insert {
            let q = solution.curve.points[Polyline::refined_index(s, insert) + j];
            worst = worst.max(distance_to_segment(q, p[s], p[s + 1]));
        }
    }
    worst
}

#[test]
fn more_tension_gives_a_flatter_curve() {
    let insert = 16;
    let mut control = Polyline::new(open_control(), false);
    let mut last = f64::INFINITY;
    for tau in [0.0, 0.5, 1.0, 2.0, 5.0, 10.0, 30.0] {
        control.tension = vec![tau; control.points.len()];
        let solution = smooth(&control, &CurveSettings { insert, tol: 1e-7, ..CurveSettings::default() }).unwrap();
        assert!(solution.converged);
        let deviation = deviation_from_polygon(&control, &solution, insert, &[0, 1, 2, 3]);
        eprintln!("tau {tau:4}: max deviation from the polygon {deviation:.4e} ({} iterations)", solution.iterations);
        assert!(deviation < 0.95 * last, "tau {tau}: {deviation} not below {last}");
        last = deviation;
    }
}

#[test]
fn large_tension_at_both_ends_of_a_segment_straightens_it() {
    let insert = 16;
    let mut control = Polyline::new(open_control(), false);
    let settings = CurveSettings { insert, tol: 1e-8, ..CurveSettings::default() };
    let plain = smooth(&control, &settings).unwrap();
    let bulge = deviation_from_polygon(&control, &plain, insert, &[1]);
    let mut last = bulge;
    for tau in [10.0, 30.0, 100.0] {
        control.tension = vec![0.0, tau, tau, 0.0, 0.0];
        let solution = smooth(&control, &settings).unwrap();
        assert!(solution.converged);
        let deviation = deviation_from_polygon(&control, &solution, insert, &[1]);
        eprintln!("tau {tau} at both ends of segment 1: deviation {deviation:.4e} (without tension {bulge:.4e})");
        assert!(deviation < last, "tau {tau}");
        last = deviation;
    }
    assert!(last < 0.05 * bulge, "large tension must nearly straighten the segment: {last} vs {bulge}");
}

#[test]
fn the_result_follows_translations_rotations_and_scalings() {
    let rotation = DQuat::from_axis_angle(DVec3::new(1.0, 2.0, -0.5).normalize(), 1.1);
    let cases = [
        (3.7, DVec3::new(5.0, -2.0, 1.0)),
        (0.01, DVec3::new(-0.3, 0.0, 0.2)),
        (250.0, DVec3::new(100.0, 40.0, -70.0)),
    ];
    let mut worst: f64 = 0.0;
    for closed in [false, true] {
        let points = if closed { closed_control() } else { open_control() };
        let mut control = Polyline::new(points, closed);
        control.tension = (0..control.points.len()).map(|i| [0.0, 2.0, 0.5][i % 3]).collect();
        for spacing in [Spacing::Chord, Spacing::Uniform, Spacing::Centripetal] {
            let settings = CurveSettings { insert: 9, tol: 1e-9, spacing, ..CurveSettings::default() };
            let base = smooth(&control, &settings).unwrap();
            for (scale, shift) in cases {
                let map = |p: DVec3| rotation * (p * scale) + shift;
                let moved = Polyline { points: control.points.iter().map(|p| map(*p)).collect(), ..control.clone() };
                let solution = smooth(&moved, &settings).unwrap();
                let expected: Vec<DVec3> = base.curve.points.iter().map(|p| map(*p)).collect();
                let error = max_distance(&solution.curve.points, &expected) / diagonal(&moved.points);
                assert!(error < 1e-9, "closed={closed} {spacing:?} scale {scale}: relative error {error:e}");
                worst = worst.max(error);
            }
        }
    }
    eprintln!("similarity: worst relative error {worst:.2e}");
}

/// The stopping point of the paper's rule: the first iteration whose largest step is under `T`,
/// found by capping the iterations (the solver is deterministic).
fn paper_rule(control: &Polyline, insert: usize, tol: f64) -> CurveSolution {
    for cap in 1.. {
        let settings = CurveSettings { insert, tol, max_iterations: cap, ..CurveSettings::default() };
        let solution = smooth(control, &settings).unwrap();
        if solution.last_step < solution.threshold {
            return solution;
        }
    }
    unreachable!()
}

#[test]
fn the_stopping_rule_stops_near_the_fixed_point_where_the_papers_rule_does_not() {
    let insert = 16;
    // (control, bound on our distance in units of T): on the symmetric square the rate estimate
    // is low by a few times (slowly decaying Jordan-like modes), so its bound is looser.
    let square = vec![DVec3::ZERO, DVec3::X, DVec3::new(1.0, 1.0, 0.0), DVec3::Y];
    let cases = [
        (Polyline::new(open_control(), false), 2.0),
        (Polyline::new(closed_control(), true), 2.0),
        (Polyline::new(square, true), 6.0),
    ];
    for (control, bound) in cases {
        let converged = solve(&control, insert, 1e-10, Spacing::Chord);
        let ours = solve(&control, insert, 1e-3, Spacing::Chord);
        let paper = paper_rule(&control, insert, 1e-3);
        let t = ours.threshold;
        let ours_off = max_distance(&ours.curve.points, &converged.curve.points) / t;
        let paper_off = max_distance(&paper.curve.points, &converged.curve.points) / t;
        eprintln!(
            "closed={}: converged in {} iterations; ours stops at {} ({ours_off:.2} T away, estimate {:.2} T), \
             the paper's at {} ({paper_off:.1} T away)",
            control.closed,
            converged.iterations,
            ours.iterations,
            ours.remaining_estimate / t,
            paper.iterations
        );
        assert!(ours.last_step < t && ours.remaining_estimate < t);
        assert!(ours_off < bound, "ours stops {ours_off} T away");
        assert!(paper_off > 10.0, "the paper's rule was expected to stop far away, {paper_off} T");
    }
}

/// The message of the input error `smooth` must return.
fn input_error(curve: Polyline, settings: &CurveSettings) -> String {
    match smooth(&curve, settings) {
        Err(Error::Input(m)) => m,
        other => panic!("expected an input error, got {other:?}"),
    }
}

#[test]
fn bad_input_is_refused_with_a_clear_message() {
    let p3 = vec![DVec3::ZERO, DVec3::X, DVec3::Y];
    let ok = CurveSettings { insert: 2, ..CurveSettings::default() };
    assert!(input_error(Polyline::new(vec![DVec3::ZERO], false), &ok).contains("at least 2 points"));
    assert!(input_error(Polyline::new(p3[..2].to_vec(), true), &ok).contains("at least 3 points"));
    let mut c = Polyline::new(p3.clone(), false);
    c.fixed.pop();
    assert!(input_error(c, &ok).contains("`fixed` has 2 entries"));
    let mut c = Polyline::new(p3.clone(), false);
    c.tension.push(0.0);
    assert!(input_error(c, &ok).contains("`tension` has 4 entries"));
    let mut c = Polyline::new(p3.clone(), false);
    c.points[1].y = f64::NAN;
    assert!(input_error(c, &ok).contains("point 1 has a non-finite"));
    for bad in [-1.0, f64::NAN, f64::INFINITY] {
        let mut c = Polyline::new(p3.clone(), false);
        c.tension[2] = bad;
        assert!(input_error(c, &ok).contains("tension of point 2"));
    }
    let mut c = Polyline::new(p3.clone(), false);
    c.fixed[2] = false;
    assert!(input_error(c, &ok).contains("point 2 is an end of the open curve"));
    let mut c = Polyline::new(p3.clone(), true);
    c.fixed = vec![false, true, false];
    assert!(input_error(c, &ok).contains("at least 2 fixed points"));
    assert!(input_error(Polyline::new(vec![DVec3::ONE; 3], false), &ok).contains("coincide"));
    // Tiny and huge curves are solved, not refused: scaled inside by a power of two, exactly, so
    // the result is the unit curve's scaled (the squares of 1e-200 underflow, and a plain length
    // once called such a curve a point).
    let unit = smooth(&Polyline::new(p3.clone(), false), &ok).unwrap();
    for size in [1e-150, 1e150, 1e-200, 1e-300, 1e300, 1.5e308] {
        let c = Polyline::new(p3.iter().map(|&p| p * size).collect(), false);
        let solved = smooth(&c, &ok).unwrap_or_else(|e| panic!("{size:e}: {e}"));
        assert_eq!(solved.iterations, unit.iterations, "{size:e}");
        for (a, b) in solved.curve.points.iter().zip(&unit.curve.points) {
            assert!((*a / size - *b).length() < 1e-12, "{size:e}: {a} vs {}", *b * size);
        }
        for (k, p) in c.points.iter().enumerate() {
            assert_eq!(solved.curve.points[Polyline::refined_index(k, ok.insert)], *p, "fixed points stay exact");
        }
    }
    let c = Polyline::new(p3.clone(), false);
    for lambda in [0.0, 1.0, f64::NAN] {
        assert!(input_error(c.clone(), &CurveSettings { lambda, ..ok }).contains("lambda"));
    }
    for tol in [0.0, -1.0, f64::INFINITY] {
        assert!(input_error(c.clone(), &CurveSettings { tol, ..ok }).contains("tolerance"));
    }
    assert!(input_error(c.clone(), &CurveSettings { max_iterations: 0, ..ok }).contains("cap"));
    assert!(input_error(c, &CurveSettings { insert: usize::MAX, ..ok }).contains("more than"));
}
