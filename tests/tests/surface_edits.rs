//! The surface solver as the editor drives it (issue 7): refusing cages whose fixed vertices
//! cannot hold the surface, warm starts after sequences of edits against fresh solves of the
//! final document, and cages of extreme size, each checked against an independent reference
//! (the method's own fixed point solved far tighter, a direct affine-hull measurement, a scaled
//! copy of the same solve).

use std::time::Duration;
use taut_core::nusd::surface::hierarchy::LevelTopology;
use taut_core::nusd::surface::kernel::{self, State};
use taut_core::nusd::surface::operator::{Controls, Operator};
use taut_core::nusd::surface::{Budget, Phase, SurfaceSolver, check_anchoring};
use taut_core::{DVec3, Document, Error, PolyMesh, VertexId};
use taut_tests::{cube, document, grid, prism, transformed};

fn default_scene() -> Document {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../assets/default.taut");
    Document::load(&path).expect("the bundled scene loads")
}

fn max_distance(a: &[DVec3], b: &[DVec3]) -> f64 {
    assert_eq!(a.len(), b.len());
    a.iter().zip(b).map(|(p, q)| (*p - *q).length()).fold(0.0, f64::max)
}

/// The editor's frames: `advance` within 12 ms, `count` times or until the solve stops.
fn frames(solver: &mut SurfaceSolver, count: usize) -> usize {
    for k in 0..count {
        if solver.advance(Budget::time(Duration::from_millis(12))).phase != Phase::Iterating {
            return k + 1;
        }
    }
    count
}

/// Solves one level of a document directly with the level's operator and kernel (the solver's
/// building blocks, bypassing its checks), from the refined cage, to a step of `1e-14` of the
/// size: the method's fixed point on that level.
fn fixed_point_of_level(doc: &Document, levels: usize) -> Vec<DVec3> {
    let mut level = LevelTopology::cage(&doc.cage);
    for _ in 0..levels {
        level = level.refine().unwrap();
    }
    let domain = level.mesh.positions().to_vec();
    let controls = Controls {
        fixed: &doc.fixed,
        vertex_tension: &doc.vertex_tension,
        edge_tension: &doc.edge_tension,
        spacing: doc.settings.spacing,
    };
    let op = Operator::build(&level, &domain, &doc.cage, &controls);
    let mut state = State::new(domain.clone(), vec![DVec3::ZERO; domain.len()]);
    let size = doc.cage.bounding_diagonal();
    for _ in 0..400_000 {
        if kernel::iterate(&op, &level.mesh, &mut state, 0.6).step < 1e-14 * size {
            return state.p;
        }
    }
    panic!("the level did not converge");
}

#[test]
fn a_cage_whose_fixed_vertices_cannot_hold_it_is_refused_with_the_vertices_to_fix() {
    let mut doc = document(cube(), 2, 1e-3);
    doc.fixed.iter_mut().for_each(|f| *f = false);
    let err = SurfaceSolver::new(&doc).unwrap_err();
    assert!(matches!(err, Error::Input(_)));
    assert!(err.to_string().starts_with("component of vertices 0–7 has no fixed vertex"), "{err}");
    doc.fixed[5] = true;
    let err = SurfaceSolver::new(&doc).unwrap_err().to_string();
    assert!(err.contains("has only vertex 5 fixed") && err.contains("shrink to that point"), "{err}");

    // An edit that would collapse the surface is refused and leaves the solver as it was.
    let mut doc = document(cube(), 2, 1e-3);
    let mut solver = SurfaceSolver::new(&doc).unwrap();
    solver.solve().unwrap();
    let before = solver.surface_positions().to_vec();
    for v in 4..8 {
        doc.fixed[v] = false;
    }
    let err = solver.update(&doc).unwrap_err().to_string();
    assert_eq!(
        err,
        "component of vertices 0–7 has fixed vertices 0, 1, 2, 3, all in one plane: its closed surface would \
         flatten into that plane; fix at least one of vertices 4, 5, 6, 7"
    );
    assert_eq!(solver.surface_positions(), &before[..]);
    assert_eq!(solver.status().phase, Phase::Done);
    // Moving a fixed vertex into the plane of the others is refused too.
    let mut doc = document(cube(), 2, 1e-3);
    doc.fixed[5] = false;
    doc.fixed[6] = false;
    doc.fixed[7] = false;
    let mut solver = SurfaceSolver::new(&doc).unwrap();
    doc.cage.set_position(VertexId(4), DVec3::new(-0.2, 0.1, -0.5));
    assert!(solver.update(&doc).unwrap_err().to_string().contains("all in one plane"));
    // The exported check says the same to the document's edit validator.
    assert_eq!(check_anchoring(&doc.cage, &doc.fixed).unwrap_err().to_string(), {
        let mut probe = doc.clone();
        probe.settings.levels = 1;
        SurfaceSolver::new(&probe).unwrap_err().to_string()
    });
}

#[test]
fn the_refused_cases_are_what_the_method_really_does() {
    // A cube with only its bottom four vertices fixed, solved anyway: flat to 1e-9.
    let mut doc = document(cube(), 1, 1e-3);
    for v in 4..8 {
        doc.fixed[v] = false;
    }
    let p = fixed_point_of_level(&doc, 1);
    let height = p.iter().map(|q| (q.z + 0.5).abs()).fold(0.0, f64::max);
    assert!(height < 1e-9, "the surface of a cube fixed at its bottom face is {height:e} off that plane");
    // Fixing one top vertex more anchors it: the surface leaves the plane by a good fraction.
    doc.fixed[7] = true;
    check_anchoring(&doc.cage, &doc.fixed).unwrap();
    let p = fixed_point_of_level(&doc, 1);
    let height = p.iter().map(|q| q.z + 0.5).fold(0.0, f64::max);
    assert!(height > 0.5, "{height}");

    // An open patch whose boundary has two fixed vertices: the boundary collapses onto their
    // line (every boundary point ends on it to 1e-9), so the check refuses it.
    let patch = grid(3, 2, 1.0, |x, y| 0.3 * x * x - 0.2 * y * y);
    let mut doc = document(patch, 1, 1e-3);
    doc.fixed.iter_mut().for_each(|f| *f = false);
    doc.fixed[0] = true;
    doc.fixed[11] = true;
    let err = check_anchoring(&doc.cage, &doc.fixed).unwrap_err().to_string();
    assert!(err.contains("has fixed vertices 0, 11, all on one line"), "{err}");
    let p = fixed_point_of_level(&doc, 1);
    let (a, b) = (p[0], p[11]);
    let dir = (b - a).normalize();
    let mut level = LevelTopology::cage(&doc.cage);
    level = level.refine().unwrap();
    let off_line = level
        .mesh
        .vertices()
        .filter(|&v| level.mesh.is_boundary_vertex(v))
        .map(|v| {
            let d = p[v.index()] - a;
            (d - d.dot(dir) * dir).length()
        })
        .fold(0.0, f64::max);
    assert!(off_line < 1e-9, "the boundary is {off_line:e} off the line through its two fixed vertices");
}

/// The recipe: the default scene, a vertex and an edge at τ = 8, then the 16 vertices of
/// the two middle rings unfixed, with 12 ms frames between the edits as in the editor. Before the
/// fix the warm-started solve sat in an oscillation of the explicit iteration (λ = 0.6 is unstable
/// there; the tension term bounds the growth, so the divergence guard never fired) until the
/// iteration cap on levels 1–3, while a fresh solve stopped early looking converged. The recipe
/// is at the three levels the default scene had then: at four, where τ = 8 sends these levels to
/// the plain iteration at λ = 0.3, the stopping estimate says 0.15 where the surface is 0.4 from
/// the fixed point (fresh solves as well as warm ones), a known weakness of the estimate under
/// such slow contraction.
#[test]
fn the_editors_warm_started_solve_converges_to_the_fresh_solves_fixed_point() {
    let mut doc = default_scene();
    doc.settings.levels = 3;
    let mut solver = SurfaceSolver::new(&doc).unwrap();
    frames(&mut solver, 4);
    doc.set_vertex_tension(VertexId(9), 8.0).unwrap();
    solver.update(&doc).unwrap();
    frames(&mut solver, 4);
    doc.set_edge_tension(VertexId(38), VertexId(39), 8.0).unwrap();
    solver.update(&doc).unwrap();
    frames(&mut solver, 4);
    for v in 16..24 {
        doc.fixed[v] = false;
    }
    solver.update(&doc).unwrap();
    frames(&mut solver, 2);
    for v in 24..32 {
        doc.fixed[v] = false;
    }
    solver.update(&doc).unwrap();
    frames(&mut solver, 2_000);
    let status = solver.status();
    let events = solver.take_events();
    assert!(status.converged(solver.reports()), "{status:?} {:?} {events:?}", solver.reports());
    assert!(status.total_iterations < 10_000, "{} iterations", status.total_iterations);

    // The method's fixed point of the final document, solved far tighter and with a λ at which
    // the iteration is stable.
    let mut tight = doc.clone();
    tight.settings.tol = 1e-9;
    tight.settings.lambda = 0.15;
    tight.settings.max_iterations = 200_000;
    let mut reference = SurfaceSolver::new(&tight).unwrap();
    reference.solve().unwrap();
    let error = max_distance(solver.surface_positions(), reference.surface_positions());
    assert!(error < 2.0 * status.threshold, "{error} from the fixed point, threshold {}", status.threshold);
}

/// A small deterministic generator for the edit sequences.
struct Lcg(u64);

impl Lcg {
    fn next(&mut self) -> f64 {
        self.0 = self.0.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
    fn below(&mut self, n: usize) -> usize {
        ((self.next() * n as f64) as usize).min(n - 1)
    }
}

#[test]
fn after_any_sequence_of_edits_the_solver_reaches_the_fresh_solves_surface() {
    let tol = 1e-6;
    for seed in 1..=4u64 {
        let mut rng = Lcg(seed);
        let mut doc = document(prism(5, 1.0, 1.1), 2, tol);
        doc.settings.max_iterations = 100_000;
        let diagonal = doc.cage.bounding_diagonal();
        let mut solver = SurfaceSolver::new(&doc).unwrap();
        let mut refused = 0;
        for _ in 0..12 {
            let mut next = doc.clone();
            let v = VertexId(rng.below(next.cage.vertex_count()) as u32);
            match rng.below(5) {
                0 | 1 => {
                    let offset = DVec3::new(rng.next() - 0.5, rng.next() - 0.5, rng.next() - 0.5) * 0.1 * diagonal;
                    next.cage.set_position(v, next.cage.position(v) + offset);
                }
                2 => next.set_vertex_tension(v, 3.0 * rng.next()).unwrap(),
                3 => {
                    let e = taut_core::EdgeId(rng.below(next.cage.edge_count()) as u32);
                    next.edge_tension[e.index()] = 3.0 * rng.next();
                }
                _ => next.fixed[v.index()] = !next.fixed[v.index()],
            }
            match solver.update(&next) {
                Ok(()) => doc = next,
                Err(e) => {
                    // Only an unanchored cage may be refused, and the solver stays usable.
                    assert!(e.to_string().contains("fix at least"), "{e}");
                    refused += 1;
                }
            }
            solver.advance(Budget::iterations(rng.below(400)));
        }
        solver.solve().unwrap();
        let mut fresh = SurfaceSolver::new(&doc).unwrap();
        fresh.solve().unwrap();
        let distance = max_distance(solver.surface_positions(), fresh.surface_positions()) / diagonal;
        // Each is within the tolerance of the fixed point, so they are within twice it.
        assert!(distance < 2.0 * tol, "seed {seed}: {distance:e} of the diagonal apart ({refused} edits refused)");
    }
}

#[test]
fn cages_of_any_finite_size_are_smoothed_and_scale_exactly() {
    let unit = {
        let mut doc = document(cube(), 2, 1e-4);
        doc.vertex_tension[3] = 1.5;
        doc.fixed[6] = false;
        doc
    };
    let mut solver = SurfaceSolver::new(&unit).unwrap();
    solver.solve().unwrap();
    let base = solver.surface_positions().to_vec();
    for scale in [1e-200, 1e-300, 1e200, 1e300, 1.5e308] {
        let mut doc = unit.clone();
        doc.cage = transformed(&unit.cage, |p| p * scale);
        let mut solver =
            SurfaceSolver::new(&doc).unwrap_or_else(|e| panic!("a cage {scale:e} across was refused: {e}"));
        let reports = solver.solve().unwrap_or_else(|e| panic!("{scale:e}: {e}"));
        assert!(reports.iter().all(|r| r.converged), "{scale:e}: {reports:?}");
        let scaled: Vec<DVec3> = solver.surface_positions().iter().map(|&p| p / scale).collect();
        let error = max_distance(&scaled, &base);
        assert!(error < 1e-9, "a cage {scale:e} across differs from the unit one by {error:e} of its size");
        for v in unit.cage.vertices().filter(|v| unit.fixed[v.index()]) {
            assert_eq!(solver.surface_positions()[v.index()], doc.cage.position(v), "fixed vertex {v:?} moved");
        }
        assert!((solver.status().threshold / scale / (1e-4 * 3f64.sqrt()) - 1.0).abs() < 1e-12);
    }
    // A cage that really is one point is still told so.
    let point = PolyMesh::from_polygons(vec![DVec3::splat(1e-200); 3], &[[0, 1, 2]]).unwrap();
    assert!(SurfaceSolver::new(&Document::new(point)).unwrap_err().to_string().contains("no extent"));
}
