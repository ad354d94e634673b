//! Tests of [`super`].

use super::*;

#[test]
fn smaller_roots() {
    assert_eq!(smaller_root(1.0, -3.0, 2.0), Some(1.0));
    assert_eq!(smaller_root(1.0, 3.0, 2.0), Some(-1.0));
    assert_eq!(smaller_root(0.0, 2.0, -1.0), Some(0.5));
    assert_eq!(smaller_root(1.0, 0.0, 1.0), None);
    // Nearly linear: the small root stays accurate.
    let r = smaller_root(1e-12, 1.0, -1.0).unwrap();
    assert!((r - 1.0).abs() < 1e-11, "{r}");
}

#[test]
fn a_circle_is_a_fixed_point() {
    // Evenly spaced points on a circle: every discrete curvature is equal, every window fit is
    // that constant, and the point on the normal through the chord with that curvature is the
    // point itself.
    let circle: Vec<DVec3> =
        (0..40).map(|i| i as f64 * std::f64::consts::TAU / 40.0).map(|t| DVec3::new(t.cos(), t.sin(), 0.0)).collect();
    for alpha in [-1.0, 0.0, 0.5, 2.0] {
        let settings = FilterSettings { alpha: Alpha::Uniform(alpha), ..FilterSettings::default() };
        let mut filter = CurveFilter::new(&PointSequence::new(circle.clone(), true), settings).unwrap();
        filter.run(5).unwrap();
        let moved = filter.points().iter().zip(&circle).map(|(a, b)| a.distance(*b)).fold(0.0, f64::max);
        assert!(moved < 1e-12, "α = {alpha}: {moved}");
    }
}

#[test]
fn too_few_points_and_straight_lines_are_refused() {
    let points: Vec<DVec3> = (0..6).map(|i| DVec3::new(i as f64, (i * i) as f64, 0.0)).collect();
    let err = CurveFilter::new(&PointSequence::new(points, false), FilterSettings::default()).unwrap_err();
    assert!(err.to_string().contains("2m + 1 = 7"), "{err}");
    let line: Vec<DVec3> = (0..9).map(|i| DVec3::X * i as f64).collect();
    let err = CurveFilter::new(&PointSequence::new(line, false), FilterSettings::default()).unwrap_err();
    assert!(err.to_string().contains("straight line"), "{err}");
}
