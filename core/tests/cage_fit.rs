//! The control-cage fitter on shapes with known answers (issue 10's tests): a finely tessellated
//! sphere and a non-convex closed blob must come out with a volume error at least 2× smaller
//! than QEM alone and a Hausdorff distance no worse; the fitted cage's limit points lie on the
//! original; scans' defects are handled; the result does not depend on the thread count.

use taut_core::cage_fit::{CageFit, CageFitParams, CageSize, DenseMesh, Silent, fit_cage};
use taut_core::{DVec3, PolyMesh};

/// An icosphere: the icosahedron with every triangle split in four `levels` times, projected to
/// the unit sphere, then each vertex mapped by `shape` (written here, independent of the core).
fn icosphere(levels: u32, shape: impl Fn(DVec3) -> DVec3) -> (Vec<DVec3>, Vec<[u32; 3]>) {
    let t = (1.0 + 5f64.sqrt()) / 2.0;
    let mut p: Vec<DVec3> = [
        [-1.0, t, 0.0],
        [1.0, t, 0.0],
        [-1.0, -t, 0.0],
        [1.0, -t, 0.0],
        [0.0, -1.0, t],
        [0.0, 1.0, t],
        [0.0, -1.0, -t],
        [0.0, 1.0, -t],
        [t, 0.0, -1.0],
        [t, 0.0, 1.0],
        [-t, 0.0, -1.0],
        [-t, 0.0, 1.0],
    ]
    .iter()
    .map(|&c| DVec3::from_array(c).normalize())
    .collect();
    let mut f: Vec<[u32; 3]> = vec![
        [0, 11, 5],
        [0, 5, 1],
        [0, 1, 7],
        [0, 7, 10],
        [0, 10, 11],
        [1, 5, 9],
        [5, 11, 4],
        [11, 10, 2],
        [10, 7, 6],
        [7, 1, 8],
        [3, 9, 4],
        [3, 4, 2],
        [3, 2, 6],
        [3, 6, 8],
        [3, 8, 9],
        [4, 9, 5],
        [2, 4, 11],
        [6, 2, 10],
        [8, 6, 7],
        [9, 8, 1],
    ];
    for _ in 0..levels {
        let mut mid = std::collections::HashMap::new();
        let mut midpoint = |a: u32, b: u32, p: &mut Vec<DVec3>| {
            *mid.entry((a.min(b), a.max(b))).or_insert_with(|| {
                p.push(((p[a as usize] + p[b as usize]) / 2.0).normalize());
                (p.len() - 1) as u32
            })
        };
        let mut next = Vec::with_capacity(f.len() * 4);
        for [a, b, c] in f {
            let (ab, bc, ca) = (midpoint(a, b, &mut p), midpoint(b, c, &mut p), midpoint(c, a, &mut p));
            next.extend([[a, ab, ca], [ab, b, bc], [ca, bc, c], [ab, bc, ca]]);
        }
        f = next;
    }
    (p.into_iter().map(shape).collect(), f)
}

fn blob(d: DVec3) -> DVec3 {
    d * (1.0 + 0.3 * (3.0 * d.x).sin() * (2.0 * d.y + 1.0).sin() + 0.2 * (4.0 * d.z).cos())
}

/// Closest point of triangle `abc` to `p` (Ericson, Real-Time Collision Detection §5.1.5),
/// written here as an independent reference for the core's spatial index.
fn closest_on_triangle(p: DVec3, a: DVec3, b: DVec3, c: DVec3) -> DVec3 {
    let (ab, ac, ap) = (b - a, c - a, p - a);
    let (d1, d2) = (ab.dot(ap), ac.dot(ap));
    if d1 <= 0.0 && d2 <= 0.0 {
        return a;
    }
    let bp = p - b;
    let (d3, d4) = (ab.dot(bp), ac.dot(bp));
    if d3 >= 0.0 && d4 <= d3 {
        return b;
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        return a + ab * (d1 / (d1 - d3));
    }
    let cp = p - c;
    let (d5, d6) = (ab.dot(cp), ac.dot(cp));
    if d6 >= 0.0 && d5 <= d6 {
        return c;
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        return a + ac * (d2 / (d2 - d6));
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && d4 - d3 >= 0.0 && d5 - d6 >= 0.0 {
        return b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
    }
    let denom = 1.0 / (va + vb + vc);
    a + ab * (vb * denom) + ac * (vc * denom)
}

/// Brute-force distance from `p` to a triangle set.
fn brute_distance(p: DVec3, positions: &[DVec3], triangles: &[[u32; 3]]) -> f64 {
    triangles
        .iter()
        .map(|t| {
            let [a, b, c] = t.map(|i| positions[i as usize]);
            (closest_on_triangle(p, a, b, c) - p).length()
        })
        .fold(f64::INFINITY, f64::min)
}

/// The Loop limit point of every cage vertex of a closed triangle cage, from the mask written
/// out here (β_k, χ_k of `docs/control-cage.md`, step 2), independent of the core's matrix.
fn limit_points(cage: &PolyMesh) -> Vec<DVec3> {
    cage.vertices()
        .map(|v| {
            let ring: Vec<DVec3> = cage.vertex_neighbors(v).map(|u| cage.position(u)).collect();
            let k = ring.len() as f64;
            let c = 3.0 / 8.0 + 0.25 * (std::f64::consts::TAU / k).cos();
            let beta = (5.0 / 8.0 - c * c) / k;
            let chi = 1.0 / (k + 3.0 / (8.0 * beta));
            (1.0 - k * chi) * cage.position(v) + chi * ring.iter().sum::<DVec3>()
        })
        .collect()
}

fn fit(dense: &DenseMesh, size: CageSize, rounds: u32) -> CageFit {
    fit_cage(dense, &CageFitParams::new(size, rounds), &mut Silent).unwrap().expect("not cancelled")
}

#[test]
fn sphere_and_blob_fits_halve_the_volume_error_and_keep_limit_points_on_the_original() {
    for (name, (p, t)) in [("sphere", icosphere(5, |d| d)), ("blob", icosphere(5, blob))] {
        let dense = DenseMesh::from_triangles(p.clone(), &t).unwrap();
        assert!(dense.is_closed() && dense.report().notes().is_empty());
        for size in [CageSize::Ratio(0.25), CageSize::Faces(500)] {
            let result = fit(&dense, size, 1);
            let r = &result.report;
            let (qem, fitted) = (&r.qem, &r.rounds[0].evaluation.clone().unwrap());
            let (vq, vf) = (qem.volume_change.unwrap(), fitted.volume_change.unwrap());
            assert!(vf * 2.0 <= vq, "{name} {size:?}: volume error {vf:.3e} fitted vs {vq:.3e} QEM");
            assert!(fitted.hausdorff <= qem.hausdorff, "{name} {size:?}: {fitted:?} vs {qem:?}");
            assert_eq!(r.kept_round, 1, "{name} {size:?}: {}", r.verdict);
            assert!(result.cage.is_closed() && result.cage.euler_characteristic() == 2);
            if let CageSize::Faces(n) = size {
                assert_eq!(r.cage_faces, n, "{name}");
            }
            // Stated tolerance: every limit point within 1e-9 of the diagonal of the original,
            // checked against a brute-force distance on a sample of the cage's vertices.
            let diagonal = 2.0 * 3f64.sqrt() * p.iter().map(|q| q.abs().max_element()).fold(0.0, f64::max);
            let limits = limit_points(&result.cage);
            for q in limits.iter().step_by(limits.len() / 150 + 1) {
                let d = brute_distance(*q, &p, &t);
                assert!(d <= 1e-9 * diagonal, "{name} {size:?}: a limit point is {d:.3e} off the original");
            }
            // The per-vertex distances of the returned surface are its vertices' distances.
            let s = &result.surface;
            assert_eq!(s.distance.len(), s.mesh.vertex_count());
            for v in (0..s.mesh.vertex_count()).step_by(997) {
                let d = brute_distance(s.mesh.positions()[v], &p, &t);
                assert!((d - s.distance[v]).abs() <= 1e-9 * diagonal, "{d} vs {}", s.distance[v]);
            }
        }
    }
}

#[test]
fn further_rounds_are_measured_and_never_worse_than_qem() {
    let (p, t) = icosphere(4, blob);
    let dense = DenseMesh::from_triangles(p, &t).unwrap();
    let result = fit(&dense, CageSize::Faces(300), 3);
    let r = &result.report;
    assert_eq!(r.rounds.iter().map(|x| x.round).collect::<Vec<_>>(), vec![1, 2, 3]);
    assert!(r.rounds[1..].iter().all(|x| x.iterations > 0), "{:?}", r.rounds);
    // The paper's round and the last are measured; the one between is not.
    let measured: Vec<bool> = r.rounds.iter().map(|x| x.evaluation.is_some()).collect();
    assert_eq!(measured, [true, false, true]);
    let kept = r.fitted().unwrap();
    assert!(r.kept_round >= 1 && kept.hausdorff <= r.qem.hausdorff && kept.mean <= r.qem.mean, "{}", r.verdict);
    // The two-sided rounds lower the mean distance and the Hausdorff distance.
    let (e1, e3) = (r.rounds[0].evaluation.as_ref().unwrap(), r.rounds[2].evaluation.as_ref().unwrap());
    assert!(e3.mean < e1.mean && e3.hausdorff < e1.hausdorff, "{e1:?} vs {e3:?}");
}

#[test]
fn scaling_by_a_power_of_two_scales_the_cage_exactly() {
    let (p, t) = icosphere(4, blob);
    let rounds = taut_core::cage_fit::DEFAULT_ROUNDS;
    let a = fit(&DenseMesh::from_triangles(p.clone(), &t).unwrap(), CageSize::Ratio(0.2), rounds);
    let b = fit(
        &DenseMesh::from_triangles(p.iter().map(|q| 4.0 * *q).collect(), &t).unwrap(),
        CageSize::Ratio(0.2),
        rounds,
    );
    assert_eq!(a.cage.polygons(), b.cage.polygons());
    for (x, y) in a.cage.positions().iter().zip(b.cage.positions()) {
        assert!((4.0 * *x - *y).length() <= 1e-12 * y.length().max(1.0), "{x} {y}");
    }
    let (ea, eb) = (&a.report.qem, &b.report.qem);
    assert!((ea.hausdorff - eb.hausdorff).abs() <= 1e-9 * ea.hausdorff);
    assert!((ea.volume_change.unwrap() - eb.volume_change.unwrap()).abs() <= 1e-9 * ea.volume_change.unwrap());
}

#[test]
fn one_and_two_threads_give_bit_identical_cages_and_reports() {
    let (p, t) = icosphere(4, blob);
    let dense = DenseMesh::from_triangles(p, &t).unwrap();
    let run = |threads| {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
        pool.install(|| fit(&dense, CageSize::Faces(400), taut_core::cage_fit::DEFAULT_ROUNDS))
    };
    let (one, two) = (run(1), run(2));
    let bits = |m: &PolyMesh| m.positions().iter().map(|q| q.to_array().map(f64::to_bits)).collect::<Vec<_>>();
    assert_eq!(bits(&one.cage), bits(&two.cage));
    assert_eq!(one.report.qem, two.report.qem);
    assert_eq!(one.report.rounds, two.report.rounds);
    assert_eq!(
        one.surface.distance.iter().map(|d| d.to_bits()).collect::<Vec<_>>(),
        two.surface.distance.iter().map(|d| d.to_bits()).collect::<Vec<_>>()
    );
}

#[test]
fn an_open_mesh_keeps_its_border_and_reports_no_volume() {
    // The upper half of the sphere (z > -0.05): open along one border loop.
    let (p, t) = icosphere(4, |d| d);
    let t: Vec<[u32; 3]> = t.into_iter().filter(|tri| tri.iter().all(|&i| p[i as usize].z > -0.05)).collect();
    let dense = DenseMesh::from_triangles(p.clone(), &t).unwrap();
    assert!(!dense.is_closed() && dense.report().border_edges > 0);
    let result = fit(&dense, CageSize::Ratio(0.25), 1);
    let r = &result.report;
    assert!(r.qem.volume_change.is_none());
    assert!(r.rounds[0].border > 0);
    // Border vertices of the dense mesh stay, in place, on the QEM cage's border, and the
    // fitted cage's boundary limit points (p_prev + 4 p + p_next) / 6 land on them.
    let (qem, cage) = (&result.qem_cage, &result.cage);
    let border: Vec<_> = qem.vertices().filter(|&v| qem.is_boundary_vertex(v)).collect();
    assert_eq!(border.len(), r.rounds[0].border);
    for &v in &border {
        let q = qem.position(v);
        assert!(p.contains(&q) && q.z > -0.05 && q.z < 0.2, "{q}");
        let out = cage.vertex_halfedge(v);
        let (next, prev) = (cage.to_vertex(out), cage.from_vertex(cage.prev(out)));
        let limit = (cage.position(prev) + 4.0 * cage.position(v) + cage.position(next)) / 6.0;
        assert!((limit - q).length() < 1e-12, "{limit} vs {q}");
    }
    assert!(r.kept_round <= 1 && r.fitted().is_some(), "{}", r.verdict);
}

#[test]
fn scans_defects_are_repaired_and_fitted() {
    // Two spheres apart (two pieces), one triangle flipped, a duplicate, a degenerate triangle,
    // and a fin on an edge of the first sphere.
    let (p, t) = icosphere(3, |d| d);
    let n = p.len() as u32;
    let mut positions: Vec<DVec3> = p.iter().copied().chain(p.iter().map(|q| *q + DVec3::new(3.0, 0.0, 0.0))).collect();
    let mut triangles: Vec<[u32; 3]> = t.iter().copied().chain(t.iter().map(|tri| tri.map(|i| i + n))).collect();
    triangles[5].swap(0, 1);
    triangles.push(triangles[7]);
    triangles.push([0, 0, 1]);
    positions.push(DVec3::new(0.0, 0.0, 2.0));
    let [a, b, _] = t[0];
    triangles.push([a, b, positions.len() as u32 - 1]);
    let dense = DenseMesh::from_triangles(positions, &triangles).unwrap();
    let notes = dense.report().notes().join("; ");
    let rep = dense.report();
    assert_eq!((rep.degenerate, rep.duplicates, rep.cut_edges), (1, 1, 1), "{notes}");
    assert!(rep.flipped >= 1 && rep.split_vertices >= 1 && rep.components == 3, "{notes}");
    let result = fit(&dense, CageSize::Ratio(0.3), 1);
    assert!(result.cage.validate().is_ok());
    assert!(result.report.fitted().is_some(), "{}", result.report.verdict);
}

#[test]
fn bad_settings_are_clear_errors() {
    let (p, t) = icosphere(2, |d| d);
    let dense = DenseMesh::from_triangles(p, &t).unwrap();
    let cases = [
        (CageFitParams::new(CageSize::Ratio(0.0), 1), "outside (0, 1]"),
        (CageFitParams::new(CageSize::Ratio(1.5), 1), "outside (0, 1]"),
        (CageFitParams::new(CageSize::Ratio(f64::NAN), 1), "outside (0, 1]"),
        (CageFitParams::new(CageSize::Faces(0), 1), "at least one face"),
        (CageFitParams::new(CageSize::Faces(100_000), 1), "only 320 triangles"),
        (CageFitParams::new(CageSize::Ratio(0.5), 0), "rounds must be between 1 and 10"),
    ];
    for (params, expected) in cases {
        let err = fit_cage(&dense, &params, &mut Silent).unwrap_err().to_string();
        assert!(err.contains(expected), "{params:?}: {err}");
    }
    // A face count the topology cannot go below: more faces than asked, said in the report.
    let small = fit(&dense, CageSize::Faces(1), 1);
    assert!(small.report.cage_faces >= 4 && small.cage.is_closed());
}

#[test]
fn progress_names_every_step_and_cancelling_stops_the_fit() {
    let (p, t) = icosphere(3, |d| d);
    let dense = DenseMesh::from_triangles(p, &t).unwrap();
    let mut seen: Vec<(String, f64)> = Vec::new();
    let mut record = |step: &str, f: f64| {
        seen.push((step.to_string(), f));
        true
    };
    let result = fit_cage(&dense, &CageFitParams::default(), &mut record).unwrap().unwrap();
    let steps: Vec<&str> = result.report.steps.iter().map(|s| s.step.as_str()).collect();
    let mut started: Vec<&str> = seen.iter().filter(|(_, f)| *f == 0.0).map(|(s, _)| s.as_str()).collect();
    started.dedup();
    assert_eq!(steps, started);
    assert!(seen.iter().all(|(_, f)| (0.0..=1.0).contains(f)));
    assert!(result.report.steps.iter().all(|s| s.seconds >= 0.0));
    let mut cancel = |step: &str, _: f64| step != "solve";
    assert!(fit_cage(&dense, &CageFitParams::default(), &mut cancel).unwrap().is_none());
}

/// Blender's monkey at 300 faces: meshoptimizer's first cage has an edge with three triangles;
/// the fitter tries nearby targets and comes back with a manifold cage near the size asked for.
#[test]
fn a_simplification_leaving_a_non_manifold_edge_is_retried_nearby() {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../tests/fixtures/blender/monkey.obj");
    let (positions, triangles, _) = taut_core::io::import_triangles(&path, &Default::default()).unwrap();
    let dense = DenseMesh::from_triangles(positions, &triangles).unwrap();
    for faces in [250, 300, 400] {
        let fit = fit(&dense, CageSize::Faces(faces), 1);
        let cage = &fit.cage;
        // A manifold triangle cage: every edge borders one or two faces, every face a triangle.
        assert!(cage.faces().all(|f| cage.face_valence(f) == 3));
        let n = cage.face_count() as f64;
        assert!((n - faces as f64).abs() <= 0.1 * faces as f64, "{n} faces for {faces} asked");
        let qem = &fit.report.qem;
        let kept = fit.report.fitted().filter(|_| fit.report.kept_round > 0).unwrap_or(qem);
        assert!(kept.hausdorff <= qem.hausdorff && kept.mean <= qem.mean);
    }
}

/// The first parameter `t ≤ max` where `origin + t·direction` meets triangle `abc`
/// (Möller–Trumbore, written here as an independent reference), counting a hit on an edge.
fn ray_triangle(origin: DVec3, direction: DVec3, max: f64, a: DVec3, b: DVec3, c: DVec3) -> Option<f64> {
    let (e1, e2) = (b - a, c - a);
    let h = direction.cross(e2);
    let det = e1.dot(h);
    if det.abs() < 1e-300 {
        return None;
    }
    let s = origin - a;
    let u = s.dot(h) / det;
    let q = s.cross(e1);
    let v = direction.dot(q) / det;
    let t = e2.dot(q) / det;
    (u >= 0.0 && v >= 0.0 && u + v <= 1.0 && t >= 0.0 && t <= max).then_some(t)
}

#[test]
fn the_surface_index_answers_as_brute_force_on_any_thread_count() {
    use taut_core::cage_fit::surface_index::SurfaceIndex;
    // 20,480 triangles: more than one of the index's parallel subtrees.
    let (p, t) = icosphere(5, blob);
    // Points around the surface, on it (corners and edge midpoints), inside and far away.
    let mut points: Vec<DVec3> = (0..160)
        .map(|k| {
            let s = k as f64 * 0.61;
            let dir = DVec3::new(s.sin() * (0.7 * s).cos(), s.cos() * (0.7 * s).cos(), (0.7 * s).sin());
            dir * (0.3 + 2.5 * ((k * 37) % 100) as f64 / 100.0)
        })
        .collect();
    points.extend(
        t.iter().step_by(997).flat_map(|tri| [p[tri[0] as usize], 0.5 * (p[tri[1] as usize] + p[tri[2] as usize])]),
    );
    points.push(DVec3::new(40.0, -30.0, 7.0));
    let run = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
        pool.install(|| {
            let index = SurfaceIndex::new(&p, &t).unwrap();
            let closest: Vec<_> = points.iter().map(|&q| index.closest_on_triangle(q)).collect();
            let rays: Vec<_> = points
                .iter()
                .enumerate()
                .map(|(k, &q)| {
                    let s = k as f64 * 1.3;
                    let dir = DVec3::new(s.cos(), (0.5 * s).sin(), (0.3 * s).cos()).normalize();
                    index.cast_to_triangle(q, dir, 10.0)
                })
                .collect();
            (index, closest, rays)
        })
    };
    let (index, closest, rays) = run(2);
    for (k, &q) in points.iter().enumerate() {
        let (x, triangle, w) = closest[k];
        let brute = brute_distance(q, &p, &t);
        let d = (x - q).length();
        assert!((d - brute).abs() <= 1e-12 * (1.0 + brute), "point {k}: {d} vs brute force {brute}");
        // The point is where the weights put it on the triangle named.
        let [a, b, c] = t[triangle].map(|i| p[i as usize]);
        assert!((w[0] * a + w[1] * b + w[2] * c - x).length() < 1e-12, "point {k}");
        assert!(w.iter().all(|&v| v >= -1e-12) && (w.iter().sum::<f64>() - 1.0).abs() < 1e-12);
        // Bounded: the same answer above the distance, none below it.
        assert_eq!(index.closest_point_within(q, d * (1.0 + 1e-9) + 1e-300), Some(x), "point {k}");
        if d > 0.0 {
            assert_eq!(index.closest_point_within(q, 0.5 * d), None, "point {k}");
        }
        // Rays from off the surface (from on it, rounding decides whether the start counts): the
        // first hit of brute force over every triangle.
        if d < 1e-9 {
            continue;
        }
        let s = k as f64 * 1.3;
        let dir = DVec3::new(s.cos(), (0.5 * s).sin(), (0.3 * s).cos()).normalize();
        let brute_hit = t
            .iter()
            .enumerate()
            .filter_map(|(i, tri)| {
                let [a, b, c] = tri.map(|v| p[v as usize]);
                ray_triangle(q, dir, 10.0, a, b, c).map(|h| (h, i))
            })
            .min_by(|a, b| a.0.total_cmp(&b.0));
        match (rays[k], brute_hit) {
            (Some((h, i)), Some((bh, _))) => {
                assert!((h - bh).abs() <= 1e-9, "ray {k}: {h} vs brute force {bh}");
                let [a, b, c] = t[i].map(|v| p[v as usize]);
                assert!(ray_triangle(q, dir, 10.0, a, b, c).is_some_and(|th| (th - h).abs() <= 1e-9), "ray {k}");
            }
            (None, None) => {}
            (ours, theirs) => panic!("ray {k}: {ours:?} vs brute force {theirs:?}"),
        }
    }
    // The hierarchy is a function of the triangles alone: one thread answers bit for bit alike.
    let (_, closest_one, rays_one) = run(1);
    assert_eq!(closest_one, closest);
    assert_eq!(rays_one, rays);
    // Non-finite queries find nothing and do not panic.
    assert_eq!(index.closest_point_within(DVec3::NAN, 1.0), None);
    assert!(index.cast(DVec3::NAN, DVec3::X, 1.0).is_none());
    assert!(SurfaceIndex::new(&p, &[]).is_err());
    assert!(SurfaceIndex::new(&p[..3], &t[..10]).is_err());
}

#[test]
fn staged_simplification_keeps_the_topology_and_the_closeness_of_one_stage() {
    use taut_core::cage_fit::simplify::simplify_staged;
    let (p, t) = icosphere(5, blob);
    let dense = DenseMesh::from_triangles(p.clone(), &t).unwrap();
    let one = simplify_staged(&dense, 300, usize::MAX, usize::MAX).unwrap();
    // Closeness both ways, by brute force: the cage's vertices to the original, and every 20th
    // original vertex to the cage's triangles.
    let closeness = |cage: &PolyMesh| {
        let vertices: f64 =
            cage.positions().iter().map(|&q| brute_distance(q, &p, &t)).sum::<f64>() / cage.vertex_count() as f64;
        let triangles = cage.triangles();
        let sampled: Vec<DVec3> = p.iter().step_by(20).copied().collect();
        let back: f64 = sampled.iter().map(|&q| brute_distance(q, cage.positions(), &triangles)).sum::<f64>()
            / sampled.len() as f64;
        (vertices, back)
    };
    let single_stage = closeness(&one.cage);
    let bits = |m: &PolyMesh| m.positions().iter().map(|q| q.to_array().map(f64::to_bits)).collect::<Vec<_>>();
    // The 20,480 triangles in two parts (halves), and in eight.
    for part in [10_240, 2_560] {
        let run = |threads: usize| {
            let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
            pool.install(|| simplify_staged(&dense, 300, 1000, part).unwrap())
        };
        let two = run(2);
        // Both stages ran and reached the target with a closed surface of the sphere's topology
        // (V − E + F = 2).
        for s in [&one, &two] {
            let cage = &s.cage;
            assert_eq!(cage.face_count(), 300);
            assert_eq!(cage.vertex_count() as i64 - cage.edge_count() as i64 + cage.face_count() as i64, 2);
            assert!(cage.vertices().all(|v| !cage.is_boundary_vertex(v)));
            // Each cage vertex names a dense vertex of its own.
            let mut named = s.dense_vertex.clone();
            named.sort_unstable();
            named.dedup();
            assert_eq!(named.len(), cage.vertex_count());
            assert!(named.iter().all(|&d| (d as usize) < p.len()));
        }
        // Two stages stay within a third of one stage.
        let (a, b) = (single_stage, closeness(&two.cage));
        assert!(b.0 <= 1.33 * a.0 && b.1 <= 1.33 * a.1, "parts of {part}: two stages {b:?} vs one {a:?}");
        // The parts run side by side; one thread gives the same cage bit for bit.
        assert_ne!(bits(&one.cage), bits(&two.cage), "the first stage ran");
        let single = run(1);
        assert_eq!(bits(&single.cage), bits(&two.cage));
        assert_eq!(single.dense_vertex, two.dense_vertex);
    }
}

#[test]
fn staged_simplification_of_an_open_mesh_keeps_its_border_in_place() {
    use taut_core::cage_fit::simplify::simplify_staged;
    // The upper half of a 20,480-triangle sphere: one border loop, cut across by the parts.
    let (p, t) = icosphere(5, |d| d);
    let t: Vec<[u32; 3]> = t.into_iter().filter(|tri| tri.iter().all(|&i| p[i as usize].z > -0.05)).collect();
    let dense = DenseMesh::from_triangles(p.clone(), &t).unwrap();
    assert!(!dense.is_closed());
    let one = simplify_staged(&dense, 400, usize::MAX, usize::MAX).unwrap();
    let bits = |m: &PolyMesh| m.positions().iter().map(|q| q.to_array().map(f64::to_bits)).collect::<Vec<_>>();
    let halves = simplify_staged(&dense, 400, 1000, 5_000).unwrap();
    let eighths = simplify_staged(&dense, 400, 1000, 1_250).unwrap();
    for two in [&halves, &eighths] {
        assert_ne!(bits(&one.cage), bits(&two.cage), "the first stage ran");
    }
    // Every border vertex of the input is a border vertex of both cages, at its exact position.
    let dense_border: std::collections::BTreeSet<[u64; 3]> = {
        let mesh = PolyMesh::from_polygons(p.clone(), &t).unwrap();
        mesh.vertices()
            .filter(|&v| mesh.is_boundary_vertex(v))
            .map(|v| mesh.position(v).to_array().map(f64::to_bits))
            .collect()
    };
    for s in [&one, &halves, &eighths] {
        let cage = &s.cage;
        let border: std::collections::BTreeSet<[u64; 3]> = cage
            .vertices()
            .filter(|&v| cage.is_boundary_vertex(v))
            .map(|v| cage.position(v).to_array().map(f64::to_bits))
            .collect();
        assert_eq!(border, dense_border);
        // A disc: V − E + F = 1.
        assert_eq!(cage.vertex_count() as i64 - cage.edge_count() as i64 + cage.face_count() as i64, 1);
    }
}
