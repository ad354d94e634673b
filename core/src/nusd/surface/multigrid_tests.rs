//! Tests of the multigrid cycles and transfers (kept apart so each file holds one idea).

use super::super::level::Level;
use super::*;
use crate::mesh::PolyMesh;
use crate::nusd::surface::operator::Controls;

/// An open 3 × 2 patch of quads plus a triangle fan and a pentagon: every kind of vertex.
fn mixed() -> PolyMesh {
    let mut p = Vec::new();
    for j in 0..3 {
        for i in 0..4 {
            p.push(DVec3::new(i as f64, j as f64, 0.2 * (i * j) as f64 - 0.1 * (i * i) as f64));
        }
    }
    p.push(DVec3::new(1.5, 2.8, 0.6)); // 12: apex of a fan over the top row
    p.push(DVec3::new(4.0, 1.0, 0.3)); // 13, 14: a pentagon on the right
    p.push(DVec3::new(4.5, 2.0, 0.1));
    let mut faces: Vec<Vec<u32>> = vec![];
    for j in 0..2u32 {
        for i in 0..3u32 {
            let v = j * 4 + i;
            faces.push(vec![v, v + 1, v + 5, v + 4]);
        }
    }
    faces.push(vec![8, 9, 12]);
    faces.push(vec![9, 10, 12]);
    faces.push(vec![3, 13, 14, 11, 7]);
    PolyMesh::from_polygons(p, &faces).unwrap()
}

fn levels(cage: &PolyMesh, fixed: &[bool], tension: f64, count: usize) -> Vec<Level> {
    let mut vt = vec![0.0; cage.vertex_count()];
    vt[5] = tension;
    let et = vec![0.0; cage.edge_count()];
    let controls = Controls { fixed, vertex_tension: &vt, edge_tension: &et, spacing: Default::default() };
    let mut out = vec![Level::cage(cage, &controls)];
    for _ in 0..count {
        let finer = out.last().unwrap().refine(cage, &controls, false).unwrap();
        out.push(finer);
    }
    out
}

#[test]
fn restriction_is_normalised_full_weighting_within_each_kind_of_equation() {
    let cage = mixed();
    let fixed = vec![true; cage.vertex_count()];
    let ls = levels(&cage, &fixed, 0.0, 2);
    let (coarse, fine) = (&ls[1], &ls[2]);
    let transfer = fine.transfer.as_ref().unwrap();
    let n = coarse.vertex_count();
    assert_eq!(transfer.r_offsets.len(), n + 1);
    for (offsets, entries, kind) in [
        (&transfer.r_offsets, &transfer.r_entries, &kind_r as &dyn Fn(&LevelTopology, usize) -> u8),
        (&transfer.p_offsets, &transfer.p_entries, &kind_p),
    ] {
        for c in 0..n {
            let row = &entries[offsets[c] as usize..offsets[c + 1] as usize];
            // The vertex itself is always in its row, with the largest weight.
            assert!(row.iter().any(|&(v, _)| v as usize == c));
            assert!((row.iter().map(|e| e.1).sum::<f64>() - 1.0).abs() < 1e-14);
            assert!(row.iter().all(|&(v, _)| kind(&fine.topology, v as usize) == kind(&fine.topology, c)));
        }
    }
    // An interior quad-grid vertex gets the classic 1/4, 1/8, 1/16 stencil.
    let c = 5; // cage vertex 5 is inside the patch, on four cage edges: its R row is 1-D
    let row = &transfer.p_entries[transfer.p_offsets[c] as usize..transfer.p_offsets[c + 1] as usize];
    let mut weights: Vec<f64> = row.iter().map(|e| e.1).collect();
    weights.sort_by(f64::total_cmp);
    assert_eq!(weights.len(), 9);
    assert!((weights[8] - 0.25).abs() < 1e-14 && (weights[0] - 1.0 / 16.0).abs() < 1e-14, "{weights:?}");
}

/// Runs whole cycles on the top level by hand.
fn run_cycles(ls: &mut [Level], count: usize, relax_top: bool) -> f64 {
    let top = ls.len() - 1;
    let mut change = 0.0;
    for _ in 0..count {
        let before = ls[top].state.p.clone();
        for op in cycle(top, 1, GAMMA, relax_top) {
            match op {
                Op::Smooth(k, l) => {
                    smooth(&mut ls[k].grid(k == top), l);
                }
                Op::Relax(k, l) => {
                    relax(&mut ls[k].grid(k == top), l);
                }
                Op::Restrict(k) => {
                    let (c, f) = ls.split_at_mut(k);
                    restrict(&mut f[0].grid(k == top), &mut c[k - 1].grid(false));
                }
                Op::Coarse(c) => {
                    for _ in 0..COARSE_SWEEPS {
                        smooth(&mut ls[c].grid(false), 0.6);
                    }
                }
                Op::Correct(k) => {
                    let (c, f) = ls.split_at_mut(k);
                    correct(&mut c[k - 1].grid(false), &mut f[0].grid(k == top));
                }
                Op::Blocks(k) => {
                    let level = &mut ls[k];
                    let blocks = super::super::irregular::IrregularBlocks::new(&level.operator, &level.topology.mesh);
                    blocks.solve(&level.operator, &level.topology.mesh, &mut level.state, None);
                }
            }
        }
        change = largest_change(&ls[top].operator, &before, &ls[top].state.p);
    }
    change
}

#[test]
fn colour_classes_hold_every_vertex_once_and_no_two_neighbours() {
    let cage = mixed();
    let fixed = vec![true; cage.vertex_count()];
    for level in levels(&cage, &fixed, 0.0, 3) {
        let mesh = &level.topology.mesh;
        let coloring = level.topology.coloring();
        let mut seen = vec![0; mesh.vertex_count()];
        for (c, class) in coloring.classes().enumerate() {
            assert!(class.windows(2).all(|w| w[0] < w[1]));
            for &v in class {
                seen[v as usize] += 1;
                assert_eq!(coloring.color(v), c as u32);
                for h in mesh.outgoing(crate::mesh::VertexId(v)) {
                    assert_ne!(coloring.color(mesh.to_vertex(h).0), c as u32, "{v} and a neighbour");
                }
            }
        }
        assert!(seen.iter().all(|&k| k == 1));
        assert!(coloring.count() <= 8, "{} colours", coloring.count());
    }
}

#[test]
fn gauss_seidel_sweeps_keep_the_plain_iterations_fixed_point_and_reach_it() {
    let cage = mixed();
    let mut fixed = vec![true; cage.vertex_count()];
    fixed[6] = false;
    for tension in [0.0, 2.0] {
        let mut ls = levels(&cage, &fixed, tension, 2);
        let l = &mut ls[2];
        let start = l.state.clone();
        for _ in 0..200_000 {
            if kernel::iterate(&l.operator, &l.topology.mesh, &mut l.state, 0.6).step < 1e-14 {
                break;
            }
        }
        let exact = l.state.p.clone();
        let coloring = l.topology.coloring().clone();
        let moved = kernel::iterate_colored(&l.operator, &l.topology.mesh, &mut l.state, 0.9, None, &coloring);
        assert!(moved.step < 1e-11, "τ {tension}: a sweep moved the fixed point by {:e}", moved.step);
        // From the start: the same fixed point, in far fewer sweeps than the plain iteration.
        l.state = start.clone();
        let mut sweeps = 0;
        while kernel::iterate_colored(&l.operator, &l.topology.mesh, &mut l.state, 0.9, None, &coloring).step > 1e-14 {
            sweeps += 1;
            assert!(sweeps < 100_000, "τ {tension}: no convergence");
        }
        let error = largest_change(&l.operator, &exact, &l.state.p);
        assert!(error < 1e-10, "τ {tension}: {error:e} from the plain iteration's fixed point");
        // A region's sweeps hold the rest and reach the same point from a state disturbed
        // inside it only.
        let inside: Vec<u32> = (0..l.vertex_count() as u32).filter(|&v| v % 3 != 0).collect();
        let region = Region {
            seeds_id: 0,
            width: 0,
            band: vec![0; inside.len()],
            fixed: inside.iter().copied().filter(|&v| l.operator.role[v as usize] == Role::Fixed).collect(),
            vertices: inside.clone(),
        };
        for &v in &inside {
            if l.operator.role[v as usize] == Role::Moving {
                l.state.p[v as usize] += DVec3::new(0.01, -0.02, 0.005);
            }
        }
        let outside: Vec<DVec3> = (0..l.vertex_count()).filter(|v| v % 3 == 0).map(|v| l.state.p[v]).collect();
        for _ in 0..100_000 {
            let op = &l.operator;
            if kernel::iterate_colored_on(op, &l.topology.mesh, &mut l.state, 0.9, None, &region, &coloring).step
                < 1e-14
            {
                break;
            }
        }
        let held: Vec<DVec3> = (0..l.vertex_count()).filter(|v| v % 3 == 0).map(|v| l.state.p[v]).collect();
        assert_eq!(held, outside);
        let error = largest_change(&l.operator, &exact, &l.state.p);
        assert!(error < 1e-10, "τ {tension}: the region settled {error:e} from the fixed point");
    }
}

#[test]
fn the_fixed_point_is_left_alone_and_other_states_are_drawn_to_it() {
    let cage = mixed();
    let mut fixed = vec![true; cage.vertex_count()];
    fixed[6] = false;
    for (tension, relax_top) in [(0.0, false), (2.0, false), (0.0, true)] {
        let mut ls = levels(&cage, &fixed, tension, 3);
        let top = 3;
        let start = ls[top].state.clone();
        for _ in 0..200_000 {
            let l = &mut ls[top];
            if kernel::iterate(&l.operator, &l.topology.mesh, &mut l.state, 0.6).step < 1e-14 {
                break;
            }
        }
        let exact = ls[top].state.p.clone();
        // A cycle from the plain iteration's fixed point stays there (to the precision the
        // plain iteration reached): the coarse levels only add a correction of the fine
        // residual, which is zero.
        let change = run_cycles(&mut ls, 1, relax_top);
        assert!(change < 1e-10, "τ {tension}: a cycle moved the fixed point by {change:e}");
        // From the prolonged start, cycles contract the error by at least 0.4 each, and after
        // as many sweeps of the top level the plain iteration is far behind.
        ls[top].state = start.clone();
        run_cycles(&mut ls, 4, relax_top);
        let after4 = largest_change(&ls[top].operator, &exact, &ls[top].state.p);
        run_cycles(&mut ls, 4, relax_top);
        let after8 = largest_change(&ls[top].operator, &exact, &ls[top].state.p);
        assert!(after8 < 0.4f64.powi(4) * after4, "τ {tension}: {after4:e} → {after8:e} in 4 cycles");
        ls[top].state = start;
        for _ in 0..8 * (2 * SWEEPS + 1) {
            let l = &mut ls[top];
            kernel::iterate(&l.operator, &l.topology.mesh, &mut l.state, 0.6);
        }
        let plain = largest_change(&ls[top].operator, &exact, &ls[top].state.p);
        assert!(after8 < 0.01 * plain, "τ {tension}: multigrid {after8:e}, plain {plain:e}");
    }
}
