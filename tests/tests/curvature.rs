//! Curvature estimates (`taut_core::curvature`) against closed forms: spheres, ellipsoids,
//! cylinders, tori and an open graph surface tessellated here (regular, irregular, triangles,
//! quads and mixed) at three resolutions each, asserting that the error shrinks by a stated
//! factor per halving of the edge length and stays under a stated bound at the finest; then the
//! invariances (scale, rotation, thread count), the automatic colour range, and polyline
//! curvature.
//!
//! Errors are relative: curvature errors times the radius (or over the largest principal
//! curvature of the surface), Gaussian curvature errors times its square. Run with
//! `--nocapture` to see the measured numbers.

use glam::DQuat;
use std::f64::consts::{PI, TAU};
use taut_core::curvature::{
    Curvature, CurvatureQuantity, CurvatureSettings, VertexNormals, polyline_curvature, robust_range, vertex_curvature,
    vertex_curvature_with,
};
use taut_core::{DVec3, PolyMesh};
use taut_tests::shapes::{Jitter, cube_sphere, cylinder, icosphere, torus, uv_sphere};
use taut_tests::{grid, transformed};

/// Maximum and root-mean-square of `|value − exact|` over the vertices `keep` accepts.
fn errors(values: &[f64], exact: impl Fn(usize) -> f64, keep: impl Fn(usize) -> bool) -> (f64, f64) {
    let (mut max, mut sum, mut count) = (0.0f64, 0.0, 0);
    for (i, v) in values.iter().enumerate().filter(|(i, _)| keep(*i)) {
        let e = (v - exact(i)).abs();
        max = max.max(e);
        sum += e * e;
        count += 1;
    }
    assert!(count > 0, "no vertex measured");
    (max, (sum / count as f64).sqrt())
}

/// Relative maximum errors `[H, K, κ_min, κ_max]` on the sphere of radius `r`.
fn sphere_errors(mesh: &PolyMesh, r: f64) -> [f64; 4] {
    let c = vertex_curvature(mesh);
    assert!(c.estimated.iter().all(|&e| e));
    let all = |_| true;
    [
        errors(&c.mean, |_| 1.0 / r, all).0 * r,
        errors(&c.gaussian, |_| 1.0 / (r * r), all).0 * r * r,
        errors(&c.min_principal, |_| 1.0 / r, all).0 * r,
        errors(&c.max_principal, |_| 1.0 / r, all).0 * r,
    ]
}

/// Asserts that every error shrinks by at least `factor` from one resolution to the next (the
/// edge length halves) and ends below `bound`. `rows[i]` holds the errors at resolution `i`.
fn assert_converges<const N: usize>(what: &str, rows: &[[f64; N]], factor: f64, bound: f64) {
    for (i, row) in rows.iter().enumerate() {
        println!("{what} resolution {i}: {}", row.map(|e| format!("{e:.2e}")).join(" "));
    }
    for pair in rows.windows(2) {
        for k in 0..N {
            assert!(
                pair[0][k] / pair[1][k] >= factor,
                "{what}: error {k} shrank from {:e} to {:e}, less than {factor}×",
                pair[0][k],
                pair[1][k]
            );
        }
    }
    let finest = rows.last().unwrap();
    assert!(finest.iter().all(|&e| e < bound), "{what}: finest errors {finest:?} not below {bound:e}");
}

/// Exact `(H, K)` of the ellipsoid `x²/a² + y²/b² + z²/c² = 1` at a point on it (outward normals).
fn ellipsoid_exact(abc: DVec3, p: DVec3) -> (f64, f64) {
    let (a2, b2, c2) = (abc.x * abc.x, abc.y * abc.y, abc.z * abc.z);
    let s = p.x * p.x / (a2 * a2) + p.y * p.y / (b2 * b2) + p.z * p.z / (c2 * c2);
    let k = 1.0 / (a2 * b2 * c2 * s * s);
    let h = (a2 + b2 + c2 - p.length_squared()) / (2.0 * a2 * b2 * c2 * s.powf(1.5));
    (h, k)
}

/// A unit-sphere mesh stretched onto the ellipsoid with semi-axes `abc`: relative `[H, K]`
/// maximum errors over the largest principal curvature (and its square).
fn ellipsoid_errors(unit_sphere: &PolyMesh, abc: DVec3) -> [f64; 2] {
    let mesh = transformed(unit_sphere, |p| p / p.length() * abc);
    let c = vertex_curvature(&mesh);
    let exact: Vec<(f64, f64)> = mesh.positions().iter().map(|p| ellipsoid_exact(abc, *p)).collect();
    let scale = exact.iter().map(|(h, k)| h + (h * h - k).max(0.0).sqrt()).fold(0.0, f64::max);
    let all = |_| true;
    [errors(&c.mean, |i| exact[i].0, all).0 / scale, errors(&c.gaussian, |i| exact[i].1, all).0 / (scale * scale)]
}

#[test]
fn spheres_have_h_and_kappa_one_over_r() {
    let r = 2.0;
    // UV sphere: quads with triangle fans at the poles, thin quads next to them.
    let uv: Vec<[f64; 4]> = [8, 16, 32].iter().map(|&n| sphere_errors(&uv_sphere(r, n, 2 * n), r)).collect();
    assert_converges("UV sphere [H K κmin κmax]", &uv, 6.0, 2e-5);
    // Icosphere with every vertex moved tangentially by up to 30 % of the edge length.
    let ico: Vec<[f64; 4]> = [2, 3, 4].iter().map(|&l| sphere_errors(&icosphere(r, l, 0.3, 1), r)).collect();
    assert_converges("jittered icosphere [H K κmin κmax]", &ico, 2.5, 1.5e-3);
    // Cube sphere: quads with valence-3 corners, one side triangulated.
    let cube: Vec<[f64; 4]> = [8, 16, 32].iter().map(|&n| sphere_errors(&cube_sphere(r, n), r)).collect();
    assert_converges("cube sphere [H K κmin κmax]", &cube, 5.0, 2e-4);
}

#[test]
fn ellipsoids_converge_on_irregular_meshes() {
    // Not umbilic: the principal curvatures differ and vary, so the tensor's anisotropy is tested,
    // not only the normals.
    let abc = DVec3::new(3.0, 2.0, 1.5);
    let ico: Vec<[f64; 2]> = [3, 4, 5].iter().map(|&l| ellipsoid_errors(&icosphere(1.0, l, 0.3, 2), abc)).collect();
    assert_converges("jittered icosphere ellipsoid [H K]", &ico, 1.6, 0.025);
    let cube: Vec<[f64; 2]> = [16, 32, 64].iter().map(|&n| ellipsoid_errors(&cube_sphere(1.0, n), abc)).collect();
    assert_converges("cube-sphere ellipsoid [H K]", &cube, 3.0, 5e-3);
}

/// Relative maximum errors `[H, K, κ_min, κ_max]` on a cylinder of radius `r` along z, away from
/// the open ends (`z` within `margin` of the ends is left out).
fn cylinder_errors(mesh: &PolyMesh, r: f64, h: f64, margin: f64) -> [f64; 4] {
    let c = vertex_curvature(mesh);
    let z: Vec<f64> = mesh.positions().iter().map(|p| p.z).collect();
    let inside = |i: usize| z[i] > margin && z[i] < h - margin;
    [
        errors(&c.mean, |_| 0.5 / r, inside).0 * r,
        errors(&c.gaussian, |_| 0.0, inside).0 * r * r,
        errors(&c.min_principal, |_| 0.0, inside).0 * r,
        errors(&c.max_principal, |_| 1.0 / r, inside).0 * r,
    ]
}

#[test]
fn cylinders_bend_one_way_only() {
    let (r, h) = (2.0, 6.0);
    // Quads: by symmetry every normal is exact (two rows or more from the open ends, whose
    // normals come from one-sided fits) and each face fits the cylinder exactly.
    for n in [12, 48] {
        let mesh = cylinder(r, h, n, n / 2, false, 0.0);
        let e = cylinder_errors(&mesh, r, h, 1.5 * h / (n / 2) as f64);
        println!("quad cylinder {n}: {}", e.map(|e| format!("{e:.1e}")).join(" "));
        assert!(e.iter().all(|&e| e < 1e-12), "quad cylinder {n}: {e:?}");
        let c = vertex_curvature(&mesh);
        let ends = cylinder_errors(&mesh, r, h, -1.0);
        println!("quad cylinder {n}, ends included: {}", ends.map(|e| format!("{e:.1e}")).join(" "));
        for (d, p) in c.max_direction.iter().zip(mesh.positions()) {
            assert!(d.z.abs() < 1e-9 && d.dot(*p).abs() < 1e-9, "κmax runs around the cylinder: {d} at {p}");
        }
    }
    // Irregular triangles (random diagonals, vertices jittered by 25 % of the spacing).
    let tri: Vec<[f64; 4]> =
        [16, 32, 64].iter().map(|&n| cylinder_errors(&cylinder(r, h, n, n / 2, true, 0.25), r, h, 1.0)).collect();
    assert_converges("irregular triangle cylinder [H K κmin κmax]", &tri, 2.2, 2e-3);
}

#[test]
fn tori_match_the_closed_forms_around_the_tube() {
    // Ring radius R, tube radius r, tube angle v: K = cos v / (r (R + r cos v)),
    // H = (R + 2r cos v) / (2r (R + r cos v)), κmax = 1/r (around the tube).
    let (big, small) = (3.0, 1.0);
    for grading in [0.0, 0.5] {
        let mut rows = Vec::new();
        for n in [16, 32, 64] {
            let (mesh, v) = torus(big, small, 2 * n, n, grading);
            let c = vertex_curvature(&mesh);
            let k = |i: usize| v[i].cos() / (small * (big + small * v[i].cos()));
            let h = |i: usize| (big + 2.0 * small * v[i].cos()) / (2.0 * small * (big + small * v[i].cos()));
            let all = |_| true;
            let (h_max, h_rms) = errors(&c.mean, h, all);
            let (k_max, k_rms) = errors(&c.gaussian, k, all);
            let (kmax_max, _) = errors(&c.max_principal, |_| 1.0 / small, all);
            // κmax runs around the tube: orthogonal to the ring direction (z × p).
            let turn = c
                .max_direction
                .iter()
                .zip(mesh.positions())
                .map(|(d, p)| d.dot(DVec3::Z.cross(*p).normalize()).abs())
                .fold(0.0, f64::max);
            assert!(turn < 1e-9, "κmax does not run around the tube: {turn}");
            rows.push([h_max * small, h_rms * small, k_max * small * small, k_rms * small * small, kmax_max * small]);
        }
        assert_converges(&format!("torus grading {grading} [H max, H rms, K max, K rms, κmax]"), &rows, 3.5, 3e-3);
    }
}

#[test]
fn total_curvature_matches_gauss_bonnet() {
    // Σ area·K approximates ∫K dA = 2π·χ: 4π on a sphere, 0 on a torus; Σ area·H on the torus
    // approximates ∫H dA = 2π²R.
    let sphere = icosphere(1.5, 4, 0.3, 3);
    let c = vertex_curvature(&sphere);
    let total_k: f64 = c.area.iter().zip(&c.gaussian).map(|(a, k)| a * k).sum();
    let surface: f64 = sphere.faces().map(|f| sphere.face_area_vector(f).length()).sum();
    println!(
        "sphere: Σ area·K = {total_k:.6} (4π = {:.6}), Σ area − mesh area = {:e}",
        4.0 * PI,
        c.area.iter().sum::<f64>() - surface
    );
    assert!((total_k / (4.0 * PI) - 1.0).abs() < 5e-3);
    assert!((c.area.iter().sum::<f64>() / surface - 1.0).abs() < 1e-12);
    let (big, small) = (3.0, 1.0);
    let mut previous = f64::INFINITY;
    for n in [16, 32, 64] {
        let (torus, _) = torus(big, small, 2 * n, n, 0.5);
        let c = vertex_curvature(&torus);
        let total_k: f64 = c.area.iter().zip(&c.gaussian).map(|(a, k)| a * k).sum();
        let total_h: f64 = c.area.iter().zip(&c.mean).map(|(a, h)| a * h).sum();
        let h_error = (total_h / (2.0 * PI * PI * big) - 1.0).abs();
        println!("torus {n}: Σ area·K = {total_k:.2e}, Σ area·H relative error {h_error:.2e}");
        // Both are second order: about 160/n² and 4/n² here.
        assert!(total_k.abs() < 200.0 / (n * n) as f64 && h_error < 5.0 / (n * n) as f64);
        assert!(h_error < previous / 3.5);
        previous = h_error;
    }
}

#[test]
fn area_weighted_normals_leave_an_error_that_does_not_shrink() {
    // Why the default normals are fitted: with the mesh's area-weighted normals the tensor fit
    // differentiates first-order normal errors, and the error on an icosphere stays at ~6 %.
    let settings = CurvatureSettings { normals: VertexNormals::AreaWeighted };
    let mut area_errors = Vec::new();
    for levels in [2, 3, 4] {
        let mesh = icosphere(1.0, levels, 0.0, 1);
        let area = errors(&vertex_curvature_with(&mesh, &settings).mean, |_| 1.0, |_| true).0;
        let fitted = errors(&vertex_curvature(&mesh).mean, |_| 1.0, |_| true).0;
        println!("icosphere level {levels}: H error {area:.2e} (area-weighted normals), {fitted:.2e} (fitted)");
        assert!(fitted < area / 20.0);
        area_errors.push(area);
    }
    assert!(area_errors.iter().all(|&e| e > 0.03), "{area_errors:?}");
}

#[test]
fn boundary_vertices_are_estimated_from_their_faces() {
    // z = f(x, y) on an open grid of quads centred at the origin; normals +z, so a bowl has H < 0.
    let f = |x: f64, y: f64| 0.15 * x * x - 0.1 * x * y + 0.05 * y * y + 0.01 * x * x * x;
    let exact = |p: DVec3| {
        let (fx, fy) = (0.3 * p.x - 0.1 * p.y + 0.03 * p.x * p.x, -0.1 * p.x + 0.1 * p.y);
        let (fxx, fxy, fyy) = (0.3 + 0.06 * p.x, -0.1, 0.1);
        let w = 1.0 + fx * fx + fy * fy;
        let k = (fxx * fyy - fxy * fxy) / (w * w);
        let h = ((1.0 + fx * fx) * fyy - 2.0 * fx * fy * fxy + (1.0 + fy * fy) * fxx) / (2.0 * w.powf(1.5));
        (-h, k)
    };
    // Per resolution: [H, K] errors at least two rings in, [H, K] one ring in, [H, K] on the
    // boundary, relative to the largest |κ| (about 0.43).
    let (mut deep, mut near, mut edge) = (Vec::new(), Vec::new(), Vec::new());
    for n in [10u32, 20, 40] {
        let spacing = 4.0 / n as f64;
        let mesh = transformed(&grid(n, n, spacing, |_, _| 0.0), |p| {
            let (x, y) = (p.x - 2.0, p.y - 2.0);
            DVec3::new(x, y, f(x, y))
        });
        let c = vertex_curvature(&mesh);
        assert!(c.estimated.iter().all(|&e| e) && c.mean.iter().all(|h| h.is_finite()));
        let hk: Vec<(f64, f64)> = mesh.positions().iter().map(|p| exact(*p)).collect();
        let scale = hk.iter().map(|(h, k)| h.abs() + (h * h - k).max(0.0).sqrt()).fold(0.0, f64::max);
        let (n1, n) = (n as usize + 1, n as usize);
        let rings_in = |v: usize| (v % n1).min(v / n1).min(n - v % n1).min(n - v / n1);
        let measure = |keep: &dyn Fn(usize) -> bool| {
            [errors(&c.mean, |i| hk[i].0, keep).0 / scale, errors(&c.gaussian, |i| hk[i].1, keep).0 / (scale * scale)]
        };
        deep.push(measure(&|v| rings_in(v) >= 2));
        near.push(measure(&|v| rings_in(v) == 1));
        edge.push(measure(&|v| rings_in(v) == 0));
        assert!(mesh.vertices().all(|v| mesh.is_boundary_vertex(v) == (rings_in(v.index()) == 0)));
    }
    assert_converges("open grid, two rings in or more [H K]", &deep, 3.5, 2e-3);
    // The normals on the boundary come from one-sided fits: first order there and next to it.
    assert_converges("open grid, one ring in [H K]", &near, 1.8, 0.02);
    assert_converges("open grid, on the boundary [H K]", &edge, 1.8, 0.05);
}

#[test]
fn degenerate_faces_and_isolated_vertices_give_zeros_not_nan() {
    // A good triangle, a zero-area triangle on its edge 0–1 (corners on the x axis) and an
    // isolated vertex: vertex 3 has only the degenerate face, vertex 4 none.
    let p = vec![DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::new(2.0, 0.0, 0.0), DVec3::new(5.0, 5.0, 5.0)];
    let mesh = PolyMesh::from_polygons(p, &[[0u32, 1, 2], [1, 0, 3]]).unwrap();
    let c = vertex_curvature(&mesh);
    for values in [&c.mean, &c.gaussian, &c.min_principal, &c.max_principal, &c.max_absolute, &c.area] {
        assert!(values.iter().all(|v| v.is_finite()), "{values:?}");
    }
    assert!(c.normal.iter().chain(&c.max_direction).all(|n| n.is_finite()));
    assert_eq!(c.estimated, vec![true, true, true, false, false]);
    assert_eq!(c.unestimated().map(|v| v.0).collect::<Vec<_>>(), vec![3, 4]);
    assert_eq!((c.mean[3], c.gaussian[4], c.max_absolute[4], c.area[3]), (0.0, 0.0, 0.0, 0.0));
    assert!(c.mean[..3].iter().all(|h| h.abs() < 1e-12), "a flat triangle has no curvature");
}

#[test]
fn scaling_divides_and_rigid_motions_keep_the_curvature() {
    let mesh = icosphere(1.3, 3, 0.3, 4);
    let base = vertex_curvature(&mesh);
    // A power of two scales every intermediate exactly: the result is exact to the bit.
    let scaled = vertex_curvature(&transformed(&mesh, |p| 4.0 * p));
    for (a, b) in base.mean.iter().zip(&scaled.mean) {
        assert_eq!((a / 4.0).to_bits(), b.to_bits());
    }
    for (a, b) in base.gaussian.iter().zip(&scaled.gaussian) {
        assert_eq!((a / 16.0).to_bits(), b.to_bits());
    }
    assert_eq!(base.max_direction, scaled.max_direction);
    // Any other factor: up to rounding.
    let s = 3.7;
    let scaled = vertex_curvature(&transformed(&mesh, |p| s * p));
    for (a, b) in base.min_principal.iter().zip(&scaled.min_principal) {
        assert!((a / s - b).abs() < 1e-12 * a.abs(), "{a} / {s} vs {b}");
    }
    // Rotation and translation.
    let q = DQuat::from_axis_angle(DVec3::new(1.0, -2.0, 0.5).normalize(), 0.83);
    let offset = DVec3::new(10.0, -3.0, 7.0);
    let moved = vertex_curvature(&transformed(&mesh, |p| q * p + offset));
    let worst = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(x, y)| (x - y).abs()).fold(0.0, f64::max);
    assert!(worst(&base.mean, &moved.mean) < 1e-9);
    assert!(worst(&base.gaussian, &moved.gaussian) < 1e-9);
    assert!(worst(&base.max_principal, &moved.max_principal) < 1e-9);
    for (a, b) in base.normal.iter().zip(&moved.normal) {
        assert!((q * *a - *b).length() < 1e-9);
    }
}

#[test]
fn thread_count_does_not_change_the_result() {
    // Big enough (2562 vertices, 5120 faces) for the work to be split between threads.
    let mesh = icosphere(1.0, 4, 0.3, 5);
    let run = |threads| {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
        pool.install(|| vertex_curvature(&mesh))
    };
    let (one, two, three) = (run(1), run(2), run(3));
    let bits = |c: &Curvature| -> Vec<u64> {
        let scalars = [&c.mean, &c.gaussian, &c.min_principal, &c.max_principal, &c.max_absolute, &c.area];
        let vectors = [&c.min_direction, &c.max_direction, &c.normal];
        scalars
            .iter()
            .flat_map(|v| v.iter().map(|x| x.to_bits()))
            .chain(vectors.iter().flat_map(|v| v.iter().flat_map(|d| d.to_array().map(f64::to_bits))))
            .collect()
    };
    assert!(bits(&one) == bits(&two) && bits(&one) == bits(&three), "the result depends on the thread count");
}

#[test]
fn quantities_select_values() {
    let mesh = cube_sphere(2.0, 6);
    let c = vertex_curvature(&mesh);
    for q in CurvatureQuantity::ALL {
        assert_eq!(q.cli_name().parse::<CurvatureQuantity>().unwrap(), q);
        assert!(!q.to_string().is_empty());
    }
    let names: Vec<&str> = CurvatureQuantity::ALL.iter().map(|q| q.cli_name()).collect();
    assert_eq!(names, ["mean", "gaussian", "kmin", "kmax", "kabs"]);
    assert!("H".parse::<CurvatureQuantity>().is_err());
    let signed: Vec<bool> = CurvatureQuantity::ALL.iter().map(|q| q.is_signed()).collect();
    assert_eq!(signed, [true, true, true, true, false]);
    assert_eq!(c.values(CurvatureQuantity::Mean), c.mean);
    assert_eq!(c.values(CurvatureQuantity::MinPrincipal), c.min_principal);
    let kabs = c.values(CurvatureQuantity::MaxAbsolute);
    for i in 0..c.len() {
        assert_eq!(kabs[i], c.min_principal[i].abs().max(c.max_principal[i].abs()));
        assert!(c.min_principal[i] <= c.max_principal[i]);
        assert!((c.gaussian[i] - c.min_principal[i] * c.max_principal[i]).abs() < 1e-15);
    }
}

#[test]
fn robust_range_ignores_outliers_and_never_collapses() {
    // 0..=100 with two wild outliers and non-finite values: the 2nd..98th percentiles of the
    // finite values.
    let mut values: Vec<f64> = (0..=100).map(f64::from).collect();
    values.extend([1e9, -1e9, f64::NAN, f64::INFINITY, f64::NEG_INFINITY]);
    let (lo, hi) = robust_range(&values, false);
    // 103 finite values: ranks 102·0.02 = 2.04 and 102·0.98 = 99.96 of (−1e9, 0, 1, …, 100, 1e9).
    assert!((lo - 1.04).abs() < 1e-9 && (hi - 98.96).abs() < 1e-9, "({lo}, {hi})");
    // The order does not matter.
    values.reverse();
    assert_eq!(robust_range(&values, false), (lo, hi));
    // Signed: symmetric about 0, from the larger of |p2| and |p98|.
    let skewed: Vec<f64> = (0..=100).map(|i| i as f64 - 20.0).collect();
    assert_eq!(robust_range(&skewed, true), (-78.0, 78.0));
    let negative: Vec<f64> = (0..=100).map(|i| -(i as f64)).collect();
    assert_eq!(robust_range(&negative, true), (-98.0, 98.0));
    // Never zero width: constants, zeros, nothing finite, nothing at all.
    for (values, signed) in [
        (vec![0.5; 10], false),
        (vec![0.5; 10], true),
        (vec![0.0; 7], true),
        (vec![f64::NAN; 3], false),
        (vec![], true),
    ] {
        let (lo, hi) = robust_range(&values, signed);
        assert!(hi > lo && lo.is_finite() && hi.is_finite(), "{values:?}: ({lo}, {hi})");
        if signed {
            assert_eq!(lo, -hi);
        }
    }
    let (lo, hi) = robust_range(&[0.5; 10], false);
    assert!(lo < 0.5 && hi > 0.5 && hi - lo < 1e-6);
    // Scales with the data: a curvature map of a tiny or a huge part gets a sensible range.
    let tiny: Vec<f64> = (0..=100).map(|i| 1e-7 * i as f64).collect();
    assert_eq!(robust_range(&tiny, true).1, 1e-7 * 98.0);
}

#[test]
fn polyline_curvature_of_circles_is_one_over_r() {
    let (r, centre) = (2.5, DVec3::new(1.0, -2.0, 0.5));
    let on_circle = |t: f64| centre + r * DVec3::new(t.cos(), t.sin(), 0.0);
    // Evenly and unevenly spaced: three points on a circle always give that circle.
    let even: Vec<DVec3> = (0..40).map(|i| on_circle(TAU * i as f64 / 40.0)).collect();
    let mut rng = Jitter(11);
    let uneven: Vec<DVec3> = (0..40).map(|i| on_circle(TAU * (i as f64 + 0.4 * rng.draw()) / 40.0)).collect();
    for (points, name) in [(&even, "even"), (&uneven, "uneven")] {
        let c = polyline_curvature(points, true);
        for (i, k) in c.curvature.iter().enumerate() {
            assert!((k.length() - 1.0 / r).abs() < 1e-12, "{name} {i}: |κ| = {}", k.length());
            // Pointing to the centre.
            assert!((k.normalize() - (centre - points[i]) / r).length() < 1e-9, "{name} {i}: {k}");
        }
        // Counter-clockwise seen from +z: positive; from −z: negative.
        assert!(c.signed(DVec3::Z).iter().all(|&k| (k - 1.0 / r).abs() < 1e-12));
        assert!(c.signed(-2.0 * DVec3::Z).iter().all(|&k| (k + 1.0 / r).abs() < 1e-12));
        let chords: f64 = (0..40).map(|i| (points[(i + 1) % 40] - points[i]).length()).sum();
        assert!((c.total_length - chords).abs() < 1e-12);
        assert_eq!(c.arc_length[0], 0.0);
        assert!((c.arc_length[39] + (points[0] - points[39]).length() - c.total_length).abs() < 1e-12);
    }
    // Open arc: the ends copy their neighbours, so they read 1/R as well.
    let arc = polyline_curvature(&even[..10], false);
    assert_eq!(arc.curvature[0], arc.curvature[1]);
    assert_eq!(arc.curvature[9], arc.curvature[8]);
    assert!(arc.magnitude().iter().all(|k| (k - 1.0 / r).abs() < 1e-12));
}

#[test]
fn polyline_curvature_of_lines_and_helices() {
    let line: Vec<DVec3> = (0..7).map(|i| DVec3::new(1.0, 2.0, 3.0) * (i * i) as f64).collect();
    let c = polyline_curvature(&line, false);
    assert!(c.curvature.iter().all(|k| *k == DVec3::ZERO) && c.signed(DVec3::Z).iter().all(|&k| k == 0.0));
    assert!((c.arc_length[6] - 36.0 * DVec3::new(1.0, 2.0, 3.0).length()).abs() < 1e-12);
    // Helix (a cos t, a sin t, b t): κ = a / (a² + b²), second-order accurate in the spacing.
    let (a, b) = (2.0, 0.7);
    let exact = a / (a * a + b * b);
    let mut previous = f64::INFINITY;
    for n in [16, 32, 64] {
        let dt = TAU / n as f64;
        let helix: Vec<DVec3> = (0..=2 * n)
            .map(|i| {
                let t = i as f64 * dt;
                DVec3::new(a * t.cos(), a * t.sin(), b * t)
            })
            .collect();
        let c = polyline_curvature(&helix, false);
        let error = c.magnitude().iter().map(|k| (k - exact).abs()).fold(0.0, f64::max) / exact;
        println!("helix, {n} points a turn: relative error {error:.2e}");
        assert!(error < previous / 3.8 && error < 0.05 * dt * dt, "{error}");
        previous = error;
        // The curvature vector points to the axis, horizontally.
        let middle = helix[n];
        let k = c.curvature[n];
        assert!(k.z.abs() < 1e-12 && k.normalize().dot(-DVec3::new(middle.x, middle.y, 0.0).normalize()) > 1.0 - 1e-12);
    }
}
