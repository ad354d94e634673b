//! The multigrid solve of each level (issue 13): the same fixed point as the plain NUSD
//! iteration, in a flat number of sweeps per level, with an honest stopping estimate, and warm
//! starts after a drag that cost a cycle or two. References: the plain iteration run to 1e-11,
//! solves run to 1e-12, and fresh solves of the same document.

use taut_core::nusd::Spacing;
use taut_core::nusd::surface::multigrid::RELAX_SWEEPS;
use taut_core::nusd::surface::{Budget, Phase, SurfaceSolver};
use taut_core::{DVec3, Document, PolyMesh, VertexId};
use taut_tests::{cube, document, grid};

fn asset(name: &str) -> std::path::PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../assets").join(name)
}

fn default_scene() -> Document {
    Document::load(&asset("default.taut")).expect("the bundled scene loads")
}

fn mesh_asset(name: &str) -> PolyMesh {
    taut_core::io::import_mesh(&asset(name)).expect("a bundled cage loads").0
}

fn max_distance(a: &[DVec3], b: &[DVec3]) -> f64 {
    assert_eq!(a.len(), b.len());
    a.iter().zip(b).map(|(p, q)| (*p - *q).length()).fold(0.0, f64::max)
}

fn solved(doc: &Document, multigrid: bool) -> SurfaceSolver {
    let mut solver = SurfaceSolver::new(doc).unwrap();
    solver.set_multigrid(multigrid);
    solver.solve().unwrap_or_else(|e| panic!("{e}"));
    solver
}

/// A closed cage of quads, triangles and a hexagon with one edge 1e-3 of the size long.
fn mixed_with_a_short_edge() -> PolyMesh {
    let angles = [0.0, 1.0, 2.0, 3.0, 4.0, 4.0 + 2e-3];
    let mut p = Vec::new();
    for z in [0.0, 1.0] {
        for &a in &angles {
            let a = a * std::f64::consts::TAU / 6.0;
            p.push(DVec3::new(a.cos() * (1.0 - 0.3 * z), a.sin(), z));
        }
    }
    p.push(DVec3::new(0.1, 0.0, 1.4)); // 12: apex of a fan of triangles over the top
    let mut faces: Vec<Vec<u32>> = vec![(0..6).rev().collect()];
    for k in 0..6u32 {
        let k1 = (k + 1) % 6;
        faces.push(vec![k, k1, 6 + k1, 6 + k]);
        faces.push(vec![6 + k, 6 + k1, 12]);
    }
    PolyMesh::from_polygons(p, &faces).unwrap()
}

/// The cases the issue lists: every bundled cage, mixed faces with a very short edge, an open
/// patch, a pulled cube with tension 0–64, and the partly unfixed default scene.
fn cases() -> Vec<(String, Document)> {
    let mut out = Vec::new();
    for name in ["cube.obj", "prism.obj", "patch.obj", "torus.obj", "knob.obj"] {
        out.push((name.to_string(), document(mesh_asset(name), 3, 1e-3)));
    }
    let mut scene = default_scene();
    scene.settings.levels = 3;
    out.push(("default.taut".into(), scene.clone()));
    for v in 16..32 {
        scene.fixed[v] = false;
    }
    out.push(("default.taut, two rings unfixed".into(), scene.clone()));
    // With uniform spacing every level's spacings were 1, so level k's R was 4^-k of the
    // cage's and the levels' R disagreed: multigrid stalled at level 3 here and the plain
    // fallback stopped it 4.8 T from its fixed point.
    scene.settings.spacing = Spacing::Uniform;
    out.push(("default.taut, two rings unfixed, uniform spacing".into(), scene));
    out.push(("mixed faces, a short edge".into(), document(mixed_with_a_short_edge(), 3, 1e-3)));
    out.push(("open patch".into(), document(grid(4, 3, 1.0, |x, y| 0.4 * (1.3 * x).sin() - 0.1 * y * y), 3, 1e-3)));
    for tau in [0.0, 4.0, 16.0, 64.0] {
        let mut cage = cube();
        cage.set_position(VertexId(7), DVec3::splat(1.5));
        let mut doc = document(cage, 3, 1e-3);
        doc.vertex_tension[7] = tau;
        out.push((format!("pulled cube, τ = {tau}"), doc));
    }
    out
}

#[test]
fn multigrid_reaches_the_plain_iterations_fixed_point() {
    for (name, mut doc) in cases() {
        doc.settings.tol = 1e-11;
        doc.settings.max_iterations = 400_000;
        let plain = solved(&doc, false);
        let multigrid = solved(&doc, true);
        let size = doc.cage.bounding_diagonal();
        let error = max_distance(plain.surface_positions(), multigrid.surface_positions()) / size;
        assert!(error < 1e-9, "{name}: multigrid and the plain iteration differ by {error:e} of the size");
    }
}

#[test]
fn sweeps_per_level_stay_flat_up_to_level_5() {
    // Bound, in sweeps of a level (smoothing sweeps and residual passes). Without tension a cycle
    // relaxes its top level by RELAX_SWEEPS Gauss–Seidel sweeps, 2 + 1 + 1 = 4 sweeps a cycle,
    // and after its coarse correction solves the neighbourhoods of the valence-8 vertices
    // exactly; a level of at most `direct::MAX_VERTICES` vertices (level 1 here) is solved
    // directly, its two residual passes counted; each new level starts from the coarser
    // solution plus half the coarser level's own correction (`level::START_EXTRAPOLATION`):
    // measured 2, 12, 12, 12, 12 in both cases (the cage, level 0, is moving with the waist
    // unfixed). Without that extrapolation, 2, 16, 16, 12, 12 and 2, 16, 12, 12, 12; before the
    // direct and block solves, 17, 16, 16, 12, 12 and 16, 16, 16, 12, 12, with levels 2 stopped
    // 1.4 T and 1.2 T from their fixed points. With the plain iteration's Chebyshev schedule,
    // 3 + 3 sweeps and a residual pass, 7 a cycle, it was 17, 28, 28, 21, 21 and 35, 35, 28,
    // 21, 21. The plain iteration takes 17, 63, 115, 120 and 55 on the default scene. Issue 22
    // asks at most 12 a level with the cage fixed and at most 20 unfixed.
    let mut scene = default_scene();
    scene.settings.levels = 5;
    let mut unfixed = scene.clone();
    for v in 16..32 {
        unfixed.fixed[v] = false;
    }
    for (name, doc) in [("default scene", scene), ("two rings unfixed", unfixed)] {
        let solver = solved(&doc, true);
        let sweeps: Vec<usize> = solver.timings().iter().map(|t| t.sweeps).collect();
        assert_eq!(sweeps.len(), 6);
        let cycle = RELAX_SWEEPS.0 + 1 + RELAX_SWEEPS.1;
        let bounds = [2, 3 * cycle, 3 * cycle, 3 * cycle, 3 * cycle];
        assert!(
            sweeps[1..].iter().zip(bounds).all(|(&s, b)| s <= b),
            "{name}: sweeps per level {sweeps:?}, bounds {bounds:?}"
        );
        assert!(solver.status().converged(solver.reports()), "{name}");
        let plain = solved(&doc, false);
        let plain_sweeps: Vec<usize> = plain.timings().iter().map(|t| t.sweeps).collect();
        assert!(sweeps[5] * 2 < plain_sweeps[5], "{name}: {sweeps:?} against plain {plain_sweeps:?}");
    }
}

#[test]
fn with_strong_tension_the_solve_still_converges_to_the_fixed_point() {
    // The partly unfixed default scene with a vertex and an edge at τ = 8: where multigrid
    // diverges on a level it falls back to the plain iteration (and that to a smaller λ).
    let mut doc = default_scene();
    for v in 16..32 {
        doc.fixed[v] = false;
    }
    doc.set_vertex_tension(VertexId(9), 8.0).unwrap();
    doc.set_edge_tension(VertexId(38), VertexId(39), 8.0).unwrap();
    let mut solver = solved(&doc, true);
    assert!(solver.status().converged(solver.reports()), "{:?}", solver.reports());
    let mut tight = doc.clone();
    tight.settings.tol = 1e-9;
    tight.settings.max_iterations = 400_000;
    let reference = solved(&tight, true);
    let error = max_distance(solver.surface_positions(), reference.surface_positions());
    // Multigrid diverges on levels 2–4 here and they are solved by the plain iteration, whose
    // step estimate is low by a few times on this scene (see nusd::convergence); levels with
    // tension also need the block estimate (nusd::surface::solver::blocks) under half the
    // threshold, which brings it to within 1.15× of the threshold: the bound is 1.5×.
    let events = solver.take_events();
    assert!(events.iter().any(|e| e.contains("solving it by the plain iteration")), "{events:?}");
    let threshold = solver.status().threshold;
    assert!(error < 1.5 * threshold, "{error:e} from the fixed point (threshold {threshold:e})");
}

#[test]
fn the_stopping_estimate_stays_true_under_multigrid() {
    let mut unfixed = default_scene();
    for v in 16..32 {
        unfixed.fixed[v] = false;
    }
    let torus = document(mesh_asset("torus.obj"), 3, 1e-3);
    let patch = document(grid(5, 4, 1.0, |x, y| 0.3 * (x * y).sqrt() + 0.2 * (0.9 * x).cos()), 3, 1e-3);
    for (name, base) in
        [("default scene", default_scene()), ("two rings unfixed", unfixed), ("torus", torus), ("patch", patch)]
    {
        let mut exact_doc = base.clone();
        exact_doc.settings.tol = 1e-12;
        exact_doc.settings.max_iterations = 400_000;
        let exact = solved(&exact_doc, true);
        for tol in [1e-3, 1e-5] {
            let mut doc = base.clone();
            doc.settings.tol = tol;
            let solver = solved(&doc, true);
            let status = solver.status();
            let error = max_distance(solver.surface_positions(), exact.surface_positions());
            assert!(status.remaining < status.threshold);
            assert!(
                error < status.threshold,
                "{name}, tol {tol}: {error:e} from the fixed point, the estimate said {:e} (threshold {:e})",
                status.remaining,
                status.threshold
            );
        }
    }
}

/// Every level, not only the finest, stops within its threshold of its own fixed point: the
/// editor shows a settled coarse level while finer ones are solved, and each level starts the
/// next. (The relaxed cycles once stopped level 2 of the default scene 1.4 T away: their
/// contraction at the valence-8 vertex fell to 0.62 a cycle after the three the rule measured.)
#[test]
fn every_level_stops_within_its_threshold_of_its_own_fixed_point() {
    let mut scene = default_scene();
    scene.settings.levels = 4;
    let mut unfixed = scene.clone();
    for v in 16..32 {
        unfixed.fixed[v] = false;
    }
    let mut all =
        vec![("default scene, level 4".to_string(), scene), ("two rings unfixed, level 4".to_string(), unfixed)];
    // Uniform and centripetal spacing: before each level's spacings shared the level's own unit
    // (`Spacing::of_level_chord`) levels 4 stopped 6.4 T (uniform, multigrid abandoned) and
    // 2.2 T (centripetal) from their fixed points.
    for spacing in [Spacing::Uniform, Spacing::Centripetal] {
        let mut doc = all[1].1.clone();
        doc.settings.spacing = spacing;
        all.push((format!("two rings unfixed, level 4, {spacing:?} spacing"), doc));
    }
    // Among them the mixed cage with an edge 1e-3 of its size: before the block solves along its
    // sliver faces its levels 2–3 stopped up to 12 T away (a mode the cycles contracted by 0.97,
    // which their first changes did not show).
    all.extend(cases());
    let mut failures = Vec::new();
    for (name, base) in all {
        let mut exact_doc = base.clone();
        exact_doc.settings.tol = 1e-12;
        exact_doc.settings.max_iterations = 400_000;
        let exact = solved(&exact_doc, true);
        let solver = solved(&base, true);
        let threshold = solver.status().threshold;
        for report in solver.reports() {
            let l = report.level;
            let error =
                max_distance(solver.level_surface(l).unwrap().positions(), exact.level_surface(l).unwrap().positions());
            if !(report.remaining < threshold && error < threshold) {
                failures.push(format!(
                    "{name}, level {l}: {:.2} T from its fixed point, the estimate said {:.2} T",
                    error / threshold,
                    report.remaining / threshold
                ));
            }
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

#[test]
fn a_drag_re_converges_in_a_cycle_or_two_of_the_finest_level() {
    let mut doc = document(mesh_asset("torus.obj"), 4, 1e-4);
    let mut solver = solved(&doc, true);
    let fresh = solver.timings()[4];
    let diagonal = doc.cage.bounding_diagonal();
    for (k, v) in [3u32, 17, 3].into_iter().enumerate() {
        let p = doc.cage.position(VertexId(v));
        let sign = if k % 2 == 0 { 1.0 } else { -1.0 };
        doc.cage.set_position(VertexId(v), p + sign * 0.01 * diagonal * DVec3::new(0.6, 0.0, 0.8));
        solver.update(&doc).unwrap();
        solver.solve().unwrap();
        let warm = solver.timings()[4];
        // One cycle leaves the change under the threshold, one more confirms it (a third when the
        // measured contraction is over a half): at most 3 cycles. A fresh solve of the level takes 3 (12 sweeps of 4); the warm one here takes 2, 8
        // sweeps, two thirds of a fresh solve's work (22.5 against 34 sweeps of the level, with
        // the coarse levels' share).
        let cycle = RELAX_SWEEPS.0 + 1 + RELAX_SWEEPS.1;
        assert!(
            warm.cycles <= 3 && warm.sweeps <= 3 * cycle,
            "drag {k}: {} cycles, {} sweeps on level 4 (a fresh solve took {})",
            warm.cycles,
            warm.sweeps,
            fresh.sweeps
        );
        assert!(
            warm.cycles < fresh.cycles && warm.work < fresh.work,
            "drag {k}: the warm solve took {warm:?} on level 4, a fresh solve {fresh:?}"
        );
        let fresh = solved(&doc, true);
        let distance = max_distance(solver.surface_positions(), fresh.surface_positions());
        assert!(distance < 2.0 * 1e-4 * diagonal, "drag {k}: {distance:e} from a fresh solve");
    }
}

#[test]
fn the_editor_can_show_each_level_as_it_converges() {
    let mut doc = default_scene();
    doc.settings.levels = 4;
    let mut solver = SurfaceSolver::new(&doc).unwrap();
    assert_eq!(solver.converged_level(), None);
    let mut seen = Vec::new();
    while solver.advance(Budget::iterations(5)).phase == Phase::Iterating {
        if seen.last() != Some(&solver.converged_level()) {
            seen.push(solver.converged_level());
        }
    }
    seen.push(solver.converged_level());
    // Level by level, in order, each as soon as it converged.
    assert!(seen.windows(2).all(|w| w[1] == Some(w[0].map_or(0, |l| l + 1))), "{seen:?}");
    assert_eq!(seen.last(), Some(&Some(4)));
    let timings = solver.timings();
    assert_eq!(
        timings.iter().map(|t| t.sweeps).sum::<usize>(),
        solver.status().total_iterations,
        "{timings:?} {:?}",
        solver.status()
    );
    assert!(timings.iter().all(|t| t.seconds >= 0.0 && t.work >= t.sweeps as f64 * 0.99));
    // Any level's surface, coarser ones included.
    let coarse = solver.level_surface(2).unwrap();
    assert_eq!(coarse.vertex_count(), solver.reports()[2].vertices);
    for v in doc.cage.vertices() {
        assert_eq!(coarse.position(v), doc.cage.position(v));
    }
    assert!(solver.level_surface(5).is_none());
    // After an edit, the settled level starts over.
    doc.cage.set_position(VertexId(40), doc.cage.position(VertexId(40)) + DVec3::new(0.0, 0.0, 1.0));
    solver.update(&doc).unwrap();
    assert_eq!(solver.converged_level(), None);
}
