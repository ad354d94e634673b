//! Tests of [`super`].

use super::*;

fn settings(insert: usize, tol: f64) -> CurveSettings {
    CurveSettings { insert, tol, ..CurveSettings::default() }
}

fn max_distance(a: &[DVec3], b: &[DVec3]) -> f64 {
    a.iter().zip(b).map(|(p, q)| p.distance(*q)).fold(0.0, f64::max)
}

#[test]
fn a_straight_polyline_stays_straight_and_unbent() {
    // Collinear control points with very unequal segments: with chord spacing the initial
    // placement is already the fixed point (R = 0, ΔP = 0), so nothing may move.
    let dir = DVec3::new(1.0, -2.0, 0.5).normalize();
    let control = Polyline::new([0.0, 0.1, 3.0, 3.2, 7.0].iter().map(|t| dir * *t).collect(), false);
    let solution = smooth(&control, &settings(5, 1e-9)).unwrap();
    let initial = control.with_inserted(5).unwrap();
    assert!(max_distance(&solution.curve.points, &initial.points) < 1e-12);
    assert!(solution.second_derivatives.iter().all(|r| r.length() < 1e-9));
    assert!(solution.converged);
}

#[test]
fn two_segments_converge_to_the_closed_form_natural_spline() {
    // Natural cubic spline through three points with chord knots 0, h0, h0 + h1: its second
    // derivative is zero at the ends and M1 = 3 (d1 − d0) / (h0 + h1) at the middle, where d
    // are the chord slopes; on each interval it is the cubic with those end values.
    let p = [DVec3::ZERO, DVec3::new(1.0, 2.0, 0.0), DVec3::new(4.0, 2.0, 1.0)];
    let (h0, h1) = (p[0].distance(p[1]), p[1].distance(p[2]));
    let m1 = 3.0 * ((p[2] - p[1]) / h1 - (p[1] - p[0]) / h0) / (h0 + h1);
    let spline = |seg: usize, u: f64| {
        let (a, b, h, ma, mb) =
            if seg == 0 { (p[0], p[1], h0, DVec3::ZERO, m1) } else { (p[1], p[2], h1, m1, DVec3::ZERO) };
        let (x, y) = (1.0 - u, u);
        x * a + y * b + ((x * x * x - x) * ma + (y * y * y - y) * mb) * h * h / 6.0
    };
    let diagonal = (p[2] - p[0]).abs().length();
    let mut errors = Vec::new();
    for insert in [7, 15] {
        let solution = smooth(&Polyline::new(p.to_vec(), false), &settings(insert, 1e-9)).unwrap();
        let mut error: f64 = 0.0;
        for seg in 0..2 {
            for j in 0..=insert + 1 {
                let q = solution.curve.points[seg * (insert + 1) + j];
                error = error.max(q.distance(spline(seg, j as f64 / (insert + 1) as f64)));
            }
        }
        let r1 = solution.second_derivatives[insert + 1];
        assert!((r1 - m1).length() < 0.05 * m1.length(), "R at the middle {r1} vs {m1}");
        errors.push(error / diagonal);
    }
    assert!(errors[1] < 1e-3, "{errors:?}");
    assert!(errors[0] > 3.0 * errors[1], "halving h must divide the error by about 4: {errors:?}");
}

#[test]
fn a_regular_polygon_keeps_its_symmetry_and_lies_near_its_circle() {
    let sides = 12;
    let angle = std::f64::consts::TAU / sides as f64;
    let points = (0..sides).map(|k| DVec3::new((k as f64 * angle).cos(), (k as f64 * angle).sin(), 0.0)).collect();
    let insert = 6;
    let solution = smooth(&Polyline::new(points, true), &settings(insert, 1e-9)).unwrap();
    let out = &solution.curve.points;
    assert_eq!(out.len(), sides * (insert + 1));
    let rotation = glam::DQuat::from_rotation_z(angle);
    for i in 0..out.len() {
        // The periodic spline of a regular 12-gon stays within 1e-3 of its circle: the
        // classical bound (5/384) h⁴ max|x⁗| for 30° chords is 9e-4 (we measure 2.3e-4).
        assert!((out[i].length() - 1.0).abs() < 1e-3, "radius {} at {i}", out[i].length());
        let image = rotation * out[i];
        assert!(image.distance(out[(i + insert + 1) % out.len()]) < 1e-9, "symmetry broken at {i}");
    }
}

#[test]
fn the_result_does_not_depend_on_the_direction_of_travel() {
    // Jacobi updates: walking the curve backwards is the same computation, so even a loosely
    // converged result must match the reversed one to roundoff (an in-place, Gauss–Seidel
    // sweep would differ by about the tolerance).
    let points = vec![DVec3::ZERO, DVec3::new(1.0, 2.0, 0.0), DVec3::new(3.0, 2.5, 1.0), DVec3::new(4.0, 0.0, 0.5)];
    let mut forward = Polyline::new(points, false);
    forward.tension = vec![0.0, 3.0, 0.5, 0.0];
    let mut backward = forward.clone();
    backward.points.reverse();
    backward.tension.reverse();
    let a = smooth(&forward, &settings(7, 1e-2)).unwrap();
    let mut b = smooth(&backward, &settings(7, 1e-2)).unwrap();
    b.curve.points.reverse();
    assert_eq!(a.iterations, b.iterations);
    assert!(max_distance(&a.curve.points, &b.curve.points) < 1e-12);
}

#[test]
fn fixed_points_are_reproduced_bit_for_bit_far_from_the_origin() {
    let offset = DVec3::new(1e6 + 0.1, -3e5 + 0.3, 7.7);
    let points: Vec<DVec3> = [[0.0, 0.0], [1.0, 2.0], [3.0, 2.5], [4.0, 0.0]]
        .iter()
        .map(|[x, y]| offset + DVec3::new(*x, *y, 0.0) * 0.1)
        .collect();
    let solution = smooth(&Polyline::new(points.clone(), false), &settings(6, 1e-6)).unwrap();
    for (k, p) in points.iter().enumerate() {
        assert_eq!(solution.curve.points[Polyline::refined_index(k, 6)], *p);
    }
    assert!(solution.converged, "{solution:?}");
}

#[test]
fn without_moving_points_nothing_is_iterated() {
    let control = Polyline::new(vec![DVec3::ZERO, DVec3::X, DVec3::ONE], false);
    let solution = smooth(&control, &settings(0, 1e-3)).unwrap();
    assert_eq!((solution.iterations, solution.converged, solution.last_step), (0, true, 0.0));
    assert_eq!(solution.curve, control);
    // R at the middle is still reported: the three-point second difference.
    let (h0, h1) = (1.0, 2.0_f64.sqrt());
    let r = 2.0 / (h0 + h1) * ((DVec3::ONE - DVec3::X) / h1 - DVec3::X / h0);
    assert!((solution.second_derivatives[1] - r).length() < 1e-12);
}

#[test]
fn the_iteration_cap_is_reported_as_not_converged() {
    let control = Polyline::new(vec![DVec3::ZERO, DVec3::X, DVec3::ONE], false);
    let capped = CurveSettings { max_iterations: 5, ..settings(8, 1e-6) };
    let solution = smooth(&control, &capped).unwrap();
    assert_eq!(solution.iterations, 5);
    assert!(!solution.converged);
    assert!(solution.last_step > solution.threshold);
}

#[test]
fn tension_at_the_ends_of_an_open_curve_has_no_effect() {
    let mut control = Polyline::new(vec![DVec3::ZERO, DVec3::X, DVec3::new(2.0, 1.0, 0.0)], false);
    let plain = smooth(&control, &settings(4, 1e-9)).unwrap();
    control.tension = vec![5.0, 0.0, 5.0];
    let tensed = smooth(&control, &settings(4, 1e-9)).unwrap();
    assert_eq!(plain.curve.points, tensed.curve.points);
}

#[test]
fn extreme_tension_is_retried_with_a_smaller_lambda_or_refused() {
    let points = vec![DVec3::ZERO, DVec3::new(1.0, 2.0, 0.0), DVec3::new(3.0, 2.5, 1.0), DVec3::new(4.0, 0.0, 0.5)];
    let mut control = Polyline::new(points, false);
    control.tension = vec![0.0, 1e3, 1e3, 0.0];
    let solution = smooth(&control, &settings(2, 1e-7)).unwrap();
    assert!(solution.retries > 0 && solution.lambda_used < DEFAULT_LAMBDA_CURVE, "{solution:?}");
    assert!(solution.converged && solution.curve.points.iter().all(|p| p.is_finite()));
    control.tension = vec![0.0, 1e5, 1e5, 0.0];
    match smooth(&control, &settings(1, 1e-7)) {
        Err(Error::Solver(m)) => assert!(m.contains("diverged") && m.contains("lambda"), "{m}"),
        other => panic!("expected a solver error, got {other:?}"),
    }
}

#[test]
fn repeated_points_are_clamped_not_divided_by_zero() {
    let points = vec![DVec3::ZERO, DVec3::X, DVec3::X, DVec3::new(2.0, 1.0, 0.0)];
    let solution = smooth(&Polyline::new(points, false), &settings(4, 1e-6)).unwrap();
    assert!(solution.converged && solution.curve.points.iter().all(|p| p.is_finite()));
    assert!(solution.second_derivatives.iter().all(|r| r.is_finite()));
}

#[test]
fn a_moving_control_point_only_contributes_its_spacing() {
    // With uniform spacing the spacings do not depend on positions, so where a moving control
    // point starts must not change the converged curve.
    let square = vec![DVec3::ZERO, DVec3::X, DVec3::new(1.0, 1.0, 0.0), DVec3::Y];
    let mut control = Polyline::new(square, true);
    control.fixed[3] = false;
    let uniform = CurveSettings { spacing: Spacing::Uniform, ..settings(3, 1e-10) };
    let a = smooth(&control, &uniform).unwrap();
    control.points[3] += DVec3::new(0.3, -0.2, 0.5);
    let b = smooth(&control, &uniform).unwrap();
    assert!(a.converged && b.converged);
    assert!(max_distance(&a.curve.points, &b.curve.points) < 1e-7);
    assert!(a.curve.points[12].distance(DVec3::Y) > 0.1, "the moving point must move off (0, 1, 0)");
}
