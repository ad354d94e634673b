//! Properties of the NUSD surface solver (docs/nusd.md, "Properties every implementation
//! must show"), each checked against an independent reference: the input cage, a transformed
//! copy of the same solve, a second thread count, a fresh solve.

use taut_core::nusd::Spacing;
use taut_core::nusd::surface::{Budget, LevelReport, Phase, SurfaceSolver};
use taut_core::{DVec3, Document, PolyMesh, VertexId};
use taut_tests::{cube, document, grid, prism, transformed};

fn solve(doc: &Document) -> (Vec<DVec3>, Vec<LevelReport>, PolyMesh) {
    let mut solver = SurfaceSolver::new(doc).expect("valid document");
    let reports = solver.solve().expect("converges");
    (solver.surface_positions().to_vec(), reports, solver.surface())
}

fn max_distance(a: &[DVec3], b: &[DVec3]) -> f64 {
    assert_eq!(a.len(), b.len());
    a.iter().zip(b).map(|(p, q)| (*p - *q).length()).fold(0.0, f64::max)
}

/// The refined cage without smoothing: the domain positions of the finest level.
fn domain(doc: &Document) -> Vec<DVec3> {
    let mut flat = document(doc.cage.clone(), doc.settings.levels, 1.0);
    flat.fixed.iter_mut().for_each(|f| *f = true);
    let mut solver = SurfaceSolver::new(&flat).unwrap();
    // Refinement happens level by level as the solve advances; the topology keeps D.
    while solver.advance(Budget::iterations(1)).phase == Phase::Iterating {}
    solver.surface_topology().positions().to_vec()
}

/// The surface's vertices that lie on the cage edge from `a` to `b` (domain positions on the
/// straight cage edge), in order from `a` to `b`.
fn on_cage_edge(doc: &Document, surface: &PolyMesh, a: u32, b: u32) -> Vec<VertexId> {
    let (pa, pb) = (doc.cage.position(VertexId(a)), doc.cage.position(VertexId(b)));
    let domain = domain(doc);
    assert_eq!(domain.len(), surface.vertex_count());
    let dir = pb - pa;
    let mut found: Vec<(f64, VertexId)> = surface
        .vertices()
        .filter_map(|v| {
            let d = domain[v.index()] - pa;
            let t = d.dot(dir) / dir.length_squared();
            ((d - t * dir).length() < 1e-9 * dir.length() && (-1e-12..=1.0 + 1e-12).contains(&t)).then_some((t, v))
        })
        .collect();
    found.sort_by(|x, y| x.0.total_cmp(&y.0));
    found.into_iter().map(|(_, v)| v).collect()
}

#[test]
fn fixed_points_are_reproduced_exactly() {
    let cages = [cube(), prism(5, 300.0, 300.0), grid(4, 3, 1.0, |x, y| (0.7 * x).sin() + 0.3 * y * y)];
    for cage in cages {
        let mut doc = document(cage.clone(), 3, 1e-3);
        doc.vertex_tension[1] = 2.0;
        let (p, _, surface) = solve(&doc);
        surface.validate().unwrap();
        for v in cage.vertices() {
            assert_eq!(p[v.index()], cage.position(v), "cage vertex {v:?} moved");
        }
        // And the surface really was smoothed: new vertices left the flat cage faces.
        assert!(p.len() > 16 * cage.face_count());
        assert!(max_distance(&p, &domain(&doc)) > 0.02 * cage.bounding_diagonal());
    }
}

#[test]
fn similarity_transforms_commute_with_smoothing() {
    // With every spacing: tension's β is divided by the cage edges' parameter length (their
    // spacing), so τ means the same at any size; with the geometric length uniform and
    // centripetal spacing were not invariant under scaling.
    for spacing in [Spacing::Chord, Spacing::Uniform, Spacing::Centripetal] {
        let mut doc = document(prism(5, 300.0, 300.0), 2, 1e-9);
        doc.settings.max_iterations = 100_000;
        doc.settings.spacing = spacing;
        doc.set_vertex_tension(VertexId(2), 3.0).unwrap();
        doc.set_edge_tension(VertexId(5), VertexId(6), 2.0).unwrap();
        doc.fixed[7] = false;
        let (base, _, _) = solve(&doc);
        let rotation = glam::DQuat::from_axis_angle(DVec3::new(1.0, -2.0, 0.5).normalize(), 0.9);
        let similarity = |p: DVec3| 0.013 * (rotation * p) + DVec3::new(40.0, -7.0, 1e3);
        let mut moved = doc.clone();
        moved.cage = transformed(&doc.cage, similarity);
        let (image, _, _) = solve(&moved);
        let expected: Vec<DVec3> = base.iter().map(|&p| similarity(p)).collect();
        let diagonal = moved.cage.bounding_diagonal();
        let error = max_distance(&image, &expected) / diagonal;
        assert!(error < 1e-7, "{spacing:?}: relative error {error:e}");
    }
}

#[test]
fn identical_bits_for_one_and_two_threads() {
    // 24 × 24 quads refined 3 times: 37 k vertices, enough for the parallel path.
    let mut doc = document(grid(24, 24, 1.0, |x, y| 0.1 * (x * y).sqrt()), 3, 1e-4);
    doc.set_vertex_tension(VertexId(30), 4.0).unwrap();
    doc.set_edge_tension(VertexId(100), VertexId(101), 3.0).unwrap();
    doc.fixed[200] = false;
    let run = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
        pool.install(|| solve(&doc))
    };
    let (one, r1, _) = run(1);
    let (two, r2, _) = run(2);
    assert!(one.len() > 30_000);
    assert_eq!(r1, r2);
    assert!(one.iter().zip(&two).all(|(a, b)| a.to_array().map(f64::to_bits) == b.to_array().map(f64::to_bits)));
}

#[test]
fn iterations_are_reported_per_level_and_stay_roughly_flat() {
    for cage in [cube(), prism(5, 300.0, 300.0)] {
        let threshold = 1e-3 * cage.bounding_diagonal();
        // Four levels: levels of up to 256 vertices are solved directly (the cube's first two).
        let (_, reports, _) = solve(&document(cage, 4, 1e-3));
        assert_eq!(reports.iter().map(|r| r.level).collect::<Vec<_>>(), vec![0, 1, 2, 3, 4]);
        assert!(reports.iter().all(|r| r.converged && r.remaining < threshold && r.last_step < threshold));
        let counts: Vec<usize> = reports[1..].iter().map(|r| r.iterations).collect();
        assert!(counts.iter().all(|&c| c > 0), "{counts:?}");
        // A level small enough to be solved directly reports its two residual passes; the
        // iterated levels above it stay within a factor of four of each other.
        let iterated: Vec<usize> = counts.iter().copied().filter(|&c| c > 2).collect();
        assert!(iterated.len() >= 2, "{counts:?}");
        for pair in iterated.windows(2) {
            assert!(pair[1] <= 4 * pair[0], "iterations grow too fast across levels: {counts:?}");
        }
    }
}

#[test]
fn vertex_tension_tautens_the_surface_monotonically() {
    // Tension at all eight corners of a cube: the faces bulge less and less.
    let bulge = |tau: f64| {
        let mut doc = document(cube(), 3, 1e-5);
        doc.settings.lambda = 0.3;
        doc.vertex_tension.iter_mut().for_each(|t| *t = tau);
        let (p, _, _) = solve(&doc);
        p.iter().map(|q| q.abs().max_element() - 0.5).fold(f64::MIN, f64::max)
    };
    let bulges: Vec<f64> = [0.0, 1.0, 4.0, 16.0].into_iter().map(bulge).collect();
    assert!(bulges.windows(2).all(|w| w[1] < 0.9 * w[0]), "{bulges:?}");

    // Tension at one corner pulls its neighbourhood towards the cage.
    let ring_bulge = |tau: f64| {
        let mut doc = document(cube(), 3, 1e-5);
        doc.settings.lambda = 0.3;
        doc.vertex_tension[7] = tau;
        let (p, _, surface) = solve(&doc);
        surface.vertex_neighbors(VertexId(7)).map(|v| p[v.index()].abs().max_element() - 0.5).fold(f64::MIN, f64::max)
    };
    let rings: Vec<f64> = [0.0, 2.0, 8.0].into_iter().map(ring_bulge).collect();
    assert!(rings.windows(2).all(|w| w[1] < w[0] - 0.005), "{rings:?}");
}

#[test]
fn tension_at_both_ends_of_an_edge_straightens_it() {
    let curve_deviation = |tau: f64| {
        let mut doc = document(prism(5, 300.0, 300.0), 3, 1e-5);
        doc.settings.lambda = 0.3;
        doc.vertex_tension[0] = tau;
        doc.vertex_tension[1] = tau;
        let (p, _, surface) = solve(&doc);
        let (a, b) = (p[0], p[1]);
        let devs: Vec<f64> = on_cage_edge(&doc, &surface, 0, 1)
            .iter()
            .map(|v| {
                let d = p[v.index()] - a;
                let dir = (b - a).normalize();
                (d - d.dot(dir) * dir).length()
            })
            .collect();
        devs.into_iter().fold(0.0, f64::max)
    };
    // Beyond τ ≈ 4 the method over-flattens (the curve bends inwards): the paper's tension
    // saturates; the designer's range is the monotone one.
    let deviations: Vec<f64> = [0.0, 1.0, 2.0, 4.0].into_iter().map(curve_deviation).collect();
    assert!(deviations[0] > 1.0, "{deviations:?}");
    assert!(deviations.windows(2).all(|w| w[1] < 0.7 * w[0]), "{deviations:?}");
}

#[test]
fn edge_tension_tautens_across_the_edge_but_keeps_the_curve_along_it() {
    let base_doc = document(cube(), 3, 1e-7);
    let (base, _, surface) = solve(&base_doc);
    let along = on_cage_edge(&base_doc, &surface, 0, 1);
    assert_eq!(along.len(), 9);
    // Vertices next to the edge but not on it.
    let across: Vec<VertexId> = along
        .iter()
        .flat_map(|&v| surface.vertex_neighbors(v).collect::<Vec<_>>())
        .filter(|v| !along.contains(v))
        .collect();
    for tau in [2.0, 8.0] {
        let mut doc = base_doc.clone();
        doc.settings.lambda = 0.3;
        doc.set_edge_tension(VertexId(0), VertexId(1), tau).unwrap();
        let (p, _, _) = solve(&doc);
        let change = |vs: &[VertexId]| vs.iter().map(|v| (p[v.index()] - base[v.index()]).length()).fold(0.0, f64::max);
        let (along_change, across_change) = (change(&along), change(&across));
        assert!(across_change > 0.02, "tension {tau} barely moved the surface: {across_change}");
        assert!(along_change < 0.15 * across_change, "curve along the edge moved {along_change} vs {across_change}");
        // Across the edge the surface is pulled inwards, towards the cage.
        let bulge = |q: &[DVec3]| across.iter().map(|v| q[v.index()].abs().max_element()).fold(0.0, f64::max);
        assert!(bulge(&p) < bulge(&base));
    }
}

#[test]
fn chord_spacing_removes_the_bulge_at_a_short_edge() {
    // A strip whose second column is very narrow (0.05 wide next to unit-wide columns).
    let xs = [0.0, 1.0, 1.05, 2.0, 3.0];
    let mut positions = Vec::new();
    for j in 0..3 {
        for &x in &xs {
            positions.push(DVec3::new(x, j as f64, if x > 0.5 && x < 2.5 { 0.5 } else { 0.0 }));
        }
    }
    let mut faces = Vec::new();
    for j in 0..2u32 {
        for i in 0..4u32 {
            let v = j * 5 + i;
            faces.push([v, v + 1, v + 6, v + 5]);
        }
    }
    let cage = PolyMesh::from_polygons(positions, &faces).unwrap();
    let overshoot = |spacing: Spacing| {
        let mut doc = document(cage.clone(), 3, 1e-6);
        doc.settings.spacing = spacing;
        let (p, _, surface) = solve(&doc);
        // Along the short edge 6–7 in the middle row: how far the curve leaves its chord.
        let (a, b) = (p[6], p[7]);
        let dir = (b - a).normalize();
        on_cage_edge(&doc, &surface, 6, 7)
            .iter()
            .map(|v| {
                let d = p[v.index()] - a;
                (d - d.dot(dir) * dir).length()
            })
            .fold(0.0, f64::max)
    };
    let (chord, uniform) = (overshoot(Spacing::Chord), overshoot(Spacing::Uniform));
    assert!(uniform > 3.0 * chord, "chord {chord}, uniform {uniform}");
}

#[test]
fn a_diverging_tension_is_rolled_back_and_retried_with_a_smaller_lambda() {
    // The measurement: a cube with one pulled corner diverges at λ = 0.6 for τ ≥ 32.
    let mut cage = cube();
    cage.set_position(VertexId(7), DVec3::splat(1.5));
    let mut doc = document(cage, 3, 1e-4);
    doc.vertex_tension[7] = 64.0;
    let mut solver = SurfaceSolver::new(&doc).unwrap();
    let reports = solver.solve().expect("a smaller λ converges");
    let events = solver.take_events();
    assert!(events.iter().any(|e| e.contains("retried with λ = 0.3")), "{events:?}");
    assert!(reports.iter().all(|r| r.converged));
    let p = solver.surface_positions().to_vec();
    assert!(p.iter().all(|q| q.is_finite()));
    // Same result as asking for λ = 0.3 from the start.
    let mut slow = doc.clone();
    slow.settings.lambda = 0.3;
    let (q, _, _) = solve(&slow);
    assert!(max_distance(&p, &q) < 20.0 * 1e-4 * doc.cage.bounding_diagonal());
}

#[test]
fn warm_start_after_an_edit_matches_a_fresh_solve_with_less_work() {
    let mut doc = document(prism(6, 1.0, 1.2), 3, 1e-5);
    let mut solver = SurfaceSolver::new(&doc).unwrap();
    solver.solve().unwrap();
    doc.cage.set_position(VertexId(8), doc.cage.position(VertexId(8)) + DVec3::new(0.1, 0.05, 0.15));
    doc.set_vertex_tension(VertexId(3), 1.5).unwrap();
    solver.update(&doc).unwrap();
    // The edit reaches the finest level at once (prolonged), before any iteration.
    assert_eq!(solver.surface_positions()[8], doc.cage.position(VertexId(8)));
    let status = solver.advance(Budget::iterations(3));
    assert_eq!((status.phase, status.total_iterations), (Phase::Iterating, 3));
    solver.solve().unwrap();
    let warm_work = solver.status().total_iterations;
    let mut fresh = SurfaceSolver::new(&doc).unwrap();
    fresh.solve().unwrap();
    let diagonal = doc.cage.bounding_diagonal();
    assert!(max_distance(solver.surface_positions(), fresh.surface_positions()) < 10.0 * 1e-5 * diagonal);
    assert!(warm_work < fresh.status().total_iterations, "{warm_work} vs {}", fresh.status().total_iterations);
}

#[test]
fn time_budget_bounds_one_call() {
    let doc = document(grid(20, 20, 1.0, |x, y| (0.3 * x).sin() * (0.2 * y).cos()), 3, 1e-6);
    let mut solver = SurfaceSolver::new(&doc).unwrap();
    let status = solver.advance(Budget::time(std::time::Duration::ZERO));
    // A zero budget still makes progress (one iteration) and returns.
    assert_eq!(status.total_iterations, 1);
    assert_eq!(status.phase, Phase::Iterating);
}

#[test]
fn degenerate_cages_give_clear_errors_or_finite_surfaces() {
    // All vertices at one point.
    let flat = PolyMesh::from_polygons(vec![DVec3::ZERO; 3], &[[0, 1, 2]]).unwrap();
    let err = SurfaceSolver::new(&Document::new(flat)).unwrap_err().to_string();
    assert!(err.contains("no extent"), "{err}");
    // A zero-length edge: the spacing is clamped, the surface stays finite.
    let mut cage = cube();
    cage.set_position(VertexId(1), cage.position(VertexId(0)));
    let (p, _, _) = solve(&document(cage, 2, 1e-3));
    assert!(p.iter().all(|q| q.is_finite()));
    // A cage without faces.
    let empty = PolyMesh::from_polygons(vec![DVec3::ZERO, DVec3::X], &[] as &[[u32; 3]]).unwrap();
    assert!(SurfaceSolver::new(&Document::new(empty)).is_err());
}

/// Vertices of the boundary loop through `start`, in the order of its boundary halfedges.
fn boundary_loop(mesh: &PolyMesh, start: VertexId) -> Vec<VertexId> {
    let first = mesh.vertex_halfedge(start);
    assert!(mesh.is_boundary_halfedge(first));
    let mut out = vec![start];
    let mut h = mesh.next(first);
    while h != first {
        out.push(mesh.from_vertex(h));
        h = mesh.next(h);
    }
    out
}

#[test]
fn an_open_boundary_is_the_nusd_polyline_of_the_boundary() {
    use taut_core::nusd::polyline::{CurveSettings, Polyline, smooth as smooth_curve};
    let cage = grid(4, 3, 1.0, |x, y| 0.4 * (1.3 * x).sin() + 0.2 * x * y - 0.1 * y * y);
    let mut doc = document(cage.clone(), 3, 1e-10);
    doc.settings.max_iterations = 200_000;
    let (p, _, surface) = solve(&doc);
    let refined: Vec<DVec3> = boundary_loop(&surface, VertexId(0)).iter().map(|v| p[v.index()]).collect();

    let control: Vec<DVec3> = boundary_loop(&cage, VertexId(0)).iter().map(|&v| cage.position(v)).collect();
    let settings = CurveSettings { insert: 7, tol: 1e-11, max_iterations: 1_000_000, ..Default::default() };
    let curve = smooth_curve(&Polyline::new(control.clone(), true), &settings).unwrap();
    assert_eq!(refined.len(), 8 * control.len());
    assert_eq!(curve.curve.points.len(), refined.len());
    let error = max_distance(&refined, &curve.curve.points) / cage.bounding_diagonal();
    assert!(error < 1e-7, "boundary differs from the polyline by {error:e} of the diagonal");
    // And the boundary really is curved (not the straight cage edges).
    let straight: Vec<DVec3> = (0..refined.len())
        .map(|k| {
            let (a, b) = (control[k / 8], control[(k / 8 + 1) % control.len()]);
            a.lerp(b, (k % 8) as f64 / 8.0)
        })
        .collect();
    assert!(max_distance(&refined, &straight) > 0.01 * cage.bounding_diagonal());
}

#[test]
fn a_vertex_fixed_again_is_interpolated_again() {
    let mut doc = document(cube(), 3, 1e-4);
    let mut solver = SurfaceSolver::new(&doc).unwrap();
    solver.solve().unwrap();
    doc.fixed[7] = false;
    solver.update(&doc).unwrap();
    solver.solve().unwrap();
    let free = (solver.surface_positions()[7] - doc.cage.position(VertexId(7))).length();
    assert!(free > 0.05, "a moving vertex leaves the corner ({free})");
    doc.fixed[7] = true;
    solver.update(&doc).unwrap();
    solver.solve().unwrap();
    assert_eq!(solver.surface_positions()[7], doc.cage.position(VertexId(7)));
}
