//! Creases and corners of the subdivision schemes (`taut_core::subdiv::crease`), against
//! references built here: a sharp edge loop is the cubic B-spline of its polygon, semi-sharp
//! values lie between their integer neighbours, corners stay; and bad input gets clear errors.

use taut_core::mesh::edit::Triangulation;
use taut_core::subdiv::{RefinedPositions, Refinement, Scheme, sharpness_from_pairs};
use taut_core::{DVec3, PolyMesh, VertexId};
use taut_tests::subdiv::{bumpy_grid, closed_bspline, refine, triangulate};
use taut_tests::{cube, prism};

/// The cube with the loop of edges around its top face creased with sharpness `s`.
fn creased_cube(s: f64) -> (PolyMesh, Vec<f64>, Vec<u32>) {
    let cage = cube();
    let polygon = vec![4, 5, 7, 6];
    let pairs: Vec<_> = (0..4).map(|k| (VertexId(polygon[k]), VertexId(polygon[(k + 1) % 4]), s)).collect();
    let sharpness = sharpness_from_pairs(&cage, &pairs).unwrap();
    (cage, sharpness, polygon)
}

#[test]
fn a_sharp_edge_loop_is_the_cubic_bspline_of_its_polygon() {
    for scheme in [Scheme::CatmullClark, Scheme::Loop] {
        let (mut cage, sharpness, polygon) = creased_cube(f64::INFINITY);
        let sharpness = if scheme == Scheme::Loop {
            // Split the faces without cutting the creased edges (a fan keeps every cage edge).
            cage = triangulate(&cage, Triangulation::Fan).unwrap();
            let pairs: Vec<_> =
                (0..4).map(|k| (VertexId(polygon[k]), VertexId(polygon[(k + 1) % 4]), f64::INFINITY)).collect();
            sharpness_from_pairs(&cage, &pairs).unwrap()
        } else {
            sharpness
        };
        let levels = 3;
        let (r, out) = refine(&cage, scheme, &sharpness, levels);
        let points: Vec<DVec3> = polygon.iter().map(|&v| cage.position(VertexId(v))).collect();
        for k in 0..4 {
            let (a, b) = (VertexId(polygon[k]), VertexId(polygon[(k + 1) % 4]));
            let e = cage.find_halfedge(a, b).unwrap().edge();
            let mut chain = r.cage_edge_chain(e, levels).unwrap();
            if chain[0] != a {
                chain.reverse();
            }
            for (j, v) in chain.iter().enumerate() {
                let expected = closed_bspline(&points, k, j as f64 / 8.0);
                assert!((out.limit[v.index()] - expected).length() < 1e-12, "{scheme:?}: span {k}, point {j}");
                // And the refined points themselves are the B-spline's control polygon refined:
                // they converge to it, staying within the polygon's plane z = ½.
                assert!((out.finest()[v.index()].z - 0.5).abs() < 1e-12);
            }
        }
        // The smooth side still shrinks: the bottom corners move inwards.
        assert!(out.limit[0].length() < 0.5 * 3f64.sqrt() - 0.1);
    }
}

#[test]
fn semi_sharp_creases_lie_between_their_integer_neighbours() {
    let limit = |s: f64| {
        let (cage, sharpness, _) = creased_cube(s);
        refine(&cage, Scheme::CatmullClark, &sharpness, 4).1.limit
    };
    let (one, half, two, sharp) = (limit(1.0), limit(1.5), limit(2.0), limit(f64::INFINITY));
    // On the crease loop (cage vertex 4 and the edge points of its loop edges at level 1) the
    // surface comes closer to the sharp one as s grows, and 1.5 lies strictly between 1 and 2.
    let cage = cube();
    let (r, _) = refine(&cage, Scheme::CatmullClark, &[], 1);
    let e = cage.find_halfedge(VertexId(4), VertexId(5)).unwrap().edge();
    for v in [VertexId(4), r.split(1).edge_point(e)] {
        let d = |p: &[DVec3]| (p[v.index()] - sharp[v.index()]).length();
        assert!(
            d(&one) > d(&half) && d(&half) > d(&two) && d(&two) > 1e-6,
            "{v:?}: {} {} {}",
            d(&one),
            d(&half),
            d(&two)
        );
        // Along the segment from s = 1 to s = 2, s = 1.5 projects strictly inside.
        let t = (half[v.index()] - one[v.index()]).dot(two[v.index()] - one[v.index()])
            / (two[v.index()] - one[v.index()]).length_squared();
        assert!(t > 0.0 && t < 1.0, "{v:?}: t = {t}");
    }
}

#[test]
fn corners_stay_and_semi_sharp_edges_blend_by_hand() {
    // Three sharp edges at cube vertex 0: a corner, fixed at every level and in the limit.
    let cage = cube();
    let pairs: Vec<_> = [1, 2, 4].iter().map(|&u| (VertexId(0), VertexId(u), f64::INFINITY)).collect();
    let sharpness = sharpness_from_pairs(&cage, &pairs).unwrap();
    let (_, out) = refine(&cage, Scheme::CatmullClark, &sharpness, 3);
    for level in &out.levels {
        assert_eq!(level[0], cage.position(VertexId(0)));
    }
    assert_eq!(out.limit[0], cage.position(VertexId(0)));

    // One interior grid edge of sharpness ¼: its edge point is ¼ midpoint + ¾ smooth rule, and
    // its end vertices (darts) follow the smooth rule.
    let cage = bumpy_grid(4);
    let (a, b) = (VertexId(6), VertexId(7));
    let sharpness = sharpness_from_pairs(&cage, &[(a, b, 0.25)]).unwrap();
    let (r, out) = refine(&cage, Scheme::CatmullClark, &sharpness, 1);
    let (_, smooth) = refine(&cage, Scheme::CatmullClark, &[], 1);
    let e = cage.find_halfedge(a, b).unwrap().edge();
    let m = r.split(1).edge_point(e).index();
    let mid = 0.5 * (cage.position(a) + cage.position(b));
    assert!((out.levels[1][m] - (0.25 * mid + 0.75 * smooth.levels[1][m])).length() < 1e-15);
    assert_eq!(out.levels[1][a.index()], smooth.levels[1][a.index()]);
    // Sharpness 1 is a crease for exactly one level: the first level is the sharp one's, the
    // second blends nothing more (its halves are smooth).
    let sharpness1 = sharpness_from_pairs(&cage, &[(a, b, 1.0)]).unwrap();
    let sharp_inf = sharpness_from_pairs(&cage, &[(a, b, f64::INFINITY)]).unwrap();
    let (_, one) = refine(&cage, Scheme::CatmullClark, &sharpness1, 1);
    let (_, inf) = refine(&cage, Scheme::CatmullClark, &sharp_inf, 1);
    assert_eq!(one.levels[1][m], inf.levels[1][m]);
    assert_eq!(one.levels[1][m], mid);
}

#[test]
fn bad_input_gets_clear_errors_or_documented_handling() {
    let cage = cube();
    let err = |r: taut_core::Result<Refinement>| r.unwrap_err().to_string();
    let mut s = vec![0.0; cage.edge_count()];
    s[3] = f64::NAN;
    assert!(err(Refinement::new(&cage, Scheme::CatmullClark, &s, 2)).contains("use a number ≥ 0"));
    s[3] = -1.0;
    assert!(err(Refinement::new(&cage, Scheme::CatmullClark, &s, 2)).contains("sharpness -1"));
    assert!(err(Refinement::new(&cage, Scheme::CatmullClark, &[1.0], 2)).contains("one per cage edge"));
    assert!(err(Refinement::new(&cage, Scheme::CatmullClark, &[], 11)).contains("at most 10"));
    let e = err(Refinement::new(&cage, Scheme::CatmullClark, &[], 10));
    assert!(e.contains("faces") && e.contains("fewer levels"), "{e}");
    assert!(
        sharpness_from_pairs(&cage, &[(VertexId(0), VertexId(7), 1.0)])
            .unwrap_err()
            .to_string()
            .contains("no cage edge")
    );
    let prism = prism(5, 1.0, 1.0);
    assert!(err(Refinement::new(&prism, Scheme::CatmullClark, &[], 0)).contains("subdivide at least once"));
    let r = Refinement::new(&cage, Scheme::CatmullClark, &[], 1).unwrap();
    let mut out = RefinedPositions::default();
    let mut bad = cage.positions().to_vec();
    bad[2].y = f64::INFINITY;
    assert!(r.evaluate(&bad, &mut out).unwrap_err().to_string().contains("cage vertex 2"));
    assert!(r.evaluate(&bad[..3], &mut out).unwrap_err().to_string().contains("3 cage positions"));

    // An isolated vertex is kept in place; a zero-area face and a valence-2 vertex are refined by
    // the same rules, with finite positions and unit (or, where undefined, zero) normals.
    let mut p = cage.positions().to_vec();
    p.push(DVec3::splat(7.0));
    // The top face becomes a fan around the midpoint of its edge 4–5: triangle (4, 5, 9) has
    // zero area.
    p.push(0.5 * (cage.position(VertexId(4)) + cage.position(VertexId(5))));
    let mut faces = cage.polygons();
    let top = faces.remove(1);
    for k in 0..4 {
        faces.push(vec![top[k], top[(k + 1) % 4], 9]);
    }
    let mesh = PolyMesh::from_polygons(p, &faces).unwrap();
    let (r, out) = refine(&mesh, Scheme::CatmullClark, &[], 2);
    assert_eq!(out.finest()[8], DVec3::splat(7.0));
    assert_eq!(out.limit[8], DVec3::splat(7.0));
    assert_eq!(out.normals[8], DVec3::ZERO);
    for (p, n) in out.limit.iter().zip(&out.normals) {
        assert!(p.is_finite() && ((n.length() - 1.0).abs() < 1e-12 || *n == DVec3::ZERO));
    }
    assert_eq!(r.mesh(2).euler_characteristic(), mesh.euler_characteristic());
    // Two quads glued along all four edges: every vertex has valence 2.
    let pillow = PolyMesh::from_polygons(cage.positions()[..4].to_vec(), &[[0, 1, 3, 2], [0, 2, 3, 1]]).unwrap();
    let (_, out) = refine(&pillow, Scheme::CatmullClark, &[], 2);
    assert!(out.limit.iter().all(|p| p.is_finite()));
    assert!(out.normals.iter().all(|n| n.is_finite()));
}
