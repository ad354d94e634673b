//! Tests across the edits: properties follow the geometry (checked by positions, not ids), bad
//! requests leave the cage untouched, edits commute with similarity transforms, and random
//! sequences of edits keep the cage valid with truthful provenance.

use super::fixtures::{all, check, cube, grid, prism};
use super::*;
use crate::mesh::{EdgeId, FaceId, PolyMesh, VertexId};
use crate::{DVec3, Document};
use std::collections::HashMap;

fn key(a: DVec3, b: DVec3) -> [u64; 6] {
    let (a, b) = if a.to_array() <= b.to_array() { (a, b) } else { (b, a) };
    [a.x, a.y, a.z, b.x, b.y, b.z].map(f64::to_bits)
}

/// Edits that leave every old vertex where it was, for a fixture.
fn steady_edits(m: &PolyMesh) -> Vec<(&'static str, crate::Result<Edited>)> {
    let quad_edge = m.edges().find(|&e| {
        let f = m.face(e.halfedge(0));
        f.is_valid() && m.face_valence(f) == 4
    });
    let big_face = m.faces().find(|&f| m.face_valence(f) >= 4).unwrap();
    let corners: Vec<VertexId> = m.face_vertices(big_face).collect();
    let inner_edge = m.edges().find(|&e| !m.is_boundary_edge(e)).unwrap();
    let mut edits = vec![
        ("split", split_edges(m, &[EdgeId(0), EdgeId(3)], 0.3)),
        ("connect", connect_vertices(m, corners[0], corners[2])),
        ("delete faces", delete_faces(m, &[FaceId(0)])),
        ("delete vertices", delete_vertices(m, &[VertexId(1)])),
        ("dissolve edge", dissolve_edges(m, &[inner_edge])),
        ("triangulate", triangulate(m, None, Triangulation::ShortestDiagonal)),
        ("flip", flip_normals(m, None)),
    ];
    if let Some(e) = quad_edge {
        edits.push(("loop cut", loop_cut(m, e, 0.4)));
    }
    let open = delete_faces(m, &[big_face]).unwrap().mesh;
    let hole: Vec<EdgeId> = open.edges().filter(|&e| open.is_boundary_edge(e)).collect();
    if m.is_closed() {
        edits.push(("fill", fill_edges(&open, &hole)));
    }
    edits
}

#[test]
fn tension_and_fixed_flags_follow_the_edges_by_their_end_positions() {
    let mut tried = 0;
    for (name, m) in all() {
        for (edit, result) in steady_edits(&m) {
            let Ok(edited) = result else { continue };
            // The fill works on the cage with a face deleted: compare against that one.
            let old = if edited.provenance.old_counts == (m.vertex_count(), m.edge_count(), m.face_count()) {
                m.clone()
            } else {
                delete_faces(&m, &[m.faces().find(|&f| m.face_valence(f) >= 4).unwrap()]).unwrap().mesh
            };
            check(&old, &edited);
            tried += 1;
            let tension: Vec<f64> = old.edges().map(|e| 1.0 + e.0 as f64 / 8.0).collect();
            let fixed: Vec<bool> = old.vertices().map(|v| v.0 % 3 != 0).collect();
            let by_ends: HashMap<[u64; 6], f64> = old
                .edges()
                .map(|e| {
                    let (a, b) = old.edge_vertices(e);
                    (key(old.position(a), old.position(b)), tension[e.index()])
                })
                .collect();
            let vertex_at: HashMap<[u64; 3], bool> =
                old.vertices().map(|v| (old.position(v).to_array().map(f64::to_bits), fixed[v.index()])).collect();
            let new_tension = carry_edge_property(&tension, &edited.provenance, &CarryRule::new_elements(0.0)).unwrap();
            let new_fixed = carry_vertex_property(&fixed, &edited.provenance, &CarryRule::new_elements(true)).unwrap();
            let mesh = &edited.mesh;
            for v in mesh.vertices() {
                let expected = vertex_at.get(&mesh.position(v).to_array().map(f64::to_bits)).copied().unwrap_or(true);
                assert_eq!(new_fixed[v.index()], expected, "{name} / {edit}: fixed flag of {v:?}");
            }
            for e in mesh.edges() {
                let (a, b) = mesh.edge_vertices(e);
                let (pa, pb) = (mesh.position(a), mesh.position(b));
                // Old edge at the same place; or a piece of an old edge (a split half); or new.
                let expected = by_ends.get(&key(pa, pb)).copied().unwrap_or_else(|| {
                    old.edges()
                        .find(|&o| {
                            let (x, y) = old.edge_vertices(o);
                            let (px, py) = (old.position(x), old.position(y));
                            let on = |q: DVec3| {
                                let t = (q - px).dot(py - px) / (py - px).length_squared();
                                (px.lerp(py, t) - q).length() < 1e-12 && (-1e-12..=1.0 + 1e-12).contains(&t)
                            };
                            on(pa) && on(pb)
                        })
                        .map_or(0.0, |o| tension[o.index()])
                });
                assert_eq!(new_tension[e.index()], expected, "{name} / {edit}: tension of edge {pa} – {pb}");
            }
        }
    }
    assert!(tried >= 35, "only {tried} edits ran");
}

#[test]
fn a_document_carries_its_controls_through_an_edit() {
    let mut doc = Document::new(cube());
    doc.fixed[3] = false;
    doc.vertex_tension[7] = 1.5;
    doc.set_edge_tension(VertexId(5), VertexId(7), 2.0).unwrap();
    let top = FaceId(1);
    let edited = extrude_faces(&doc.cage, &[top], FaceGrouping::Region, 0.5).unwrap();
    let next = doc.with_edited_cage(edited).unwrap();
    // Vertex 7 and its copy on the cap keep τ = 1.5; edge 5-7 and its copy keep τ = 2.
    let at = |p: DVec3| next.cage.vertices().find(|&v| next.cage.position(v) == p).unwrap();
    assert_eq!(next.vertex_tension[at(DVec3::ONE).index()], 1.5);
    assert_eq!(next.vertex_tension[at(DVec3::new(1.0, 1.0, 1.5)).index()], 1.5);
    for z in [1.0, 1.5] {
        let (a, b) = (at(DVec3::new(1.0, 0.0, z)), at(DVec3::new(1.0, 1.0, z)));
        assert_eq!(next.edge_tension[next.edge_between(a, b).unwrap().index()], 2.0);
    }
    let back = Document::from_json(&next.to_json(), std::path::Path::new("mem.taut")).unwrap();
    assert_eq!(back, next);
}

#[test]
fn bad_requests_leave_the_cage_untouched_with_one_line() {
    let cube = cube();
    let (polygons, positions, generation) = (cube.polygons(), cube.positions().to_vec(), cube.generation());
    let tri = triangulate(&cube, None, Triangulation::Fan).unwrap().mesh;
    let all_faces: Vec<FaceId> = cube.faces().collect();
    let results: Vec<(&str, crate::Result<Edited>)> = vec![
        ("extrude nothing", extrude_faces(&cube, &[], FaceGrouping::Region, 1.0)),
        ("extrude out of range", extrude_faces(&cube, &[FaceId(40)], FaceGrouping::Individual, 1.0)),
        ("inset out of range", inset_faces(&cube, &[FaceId(u32::MAX - 1)], FaceGrouping::Region, 0.1)),
        ("loop cut into a triangle", loop_cut(&tri, EdgeId(0), 0.5)),
        ("split out of range", split_edges(&cube, &[EdgeId(12)], 0.5)),
        ("connect out of range", connect_vertices(&cube, VertexId(0), VertexId(8))),
        ("delete everything", delete_faces(&cube, &all_faces)),
        ("delete nothing", delete_edges(&cube, &[])),
        ("dissolve out of range", dissolve_vertices(&cube, &[VertexId(8)])),
        ("delete out of range", delete_vertices(&cube, &[VertexId(8)])),
        ("merge non-manifold", merge_vertices(&cube, &[VertexId(0), VertexId(7)], MergeAt::Centre)),
        ("merge fold", merge_vertices(&cube, &[VertexId(1), VertexId(2)], MergeAt::First)),
        ("merge NaN", merge_by_distance(&cube, &[VertexId(0)], f64::NAN)),
        ("fill interior", fill_vertices(&cube, &[VertexId(0), VertexId(1), VertexId(2)])),
        ("flip part", flip_normals(&cube, Some(&[FaceId(3)]))),
        ("triangulate out of range", triangulate(&cube, Some(&[FaceId(6)]), Triangulation::Fan)),
        ("join out of range", join_triangles(&cube, Some(&[EdgeId(99)]), &JoinParams::default())),
        ("mirror both sides", apply_mirror(&cube, MirrorPlane::new(Axis::Y, 0.5), 1e-6)),
    ];
    for (what, result) in results {
        let err = result.expect_err(what).to_string();
        assert!(!err.is_empty() && !err.contains('\n') && err.len() < 300, "{what}: {err}");
    }
    let err = dissolve_vertices(&cube, &[VertexId(8)]).unwrap_err().to_string();
    assert!(err.ends_with("vertex 8 does not exist (the cage has 8 vertices, numbered from 0)"), "{err}");
    assert_eq!((cube.polygons(), cube.positions().to_vec(), cube.generation()), (polygons, positions, generation));
}

/// A similarity transform: scale, rotation about an oblique axis, translation.
fn similarity(p: DVec3) -> DVec3 {
    let r = glam::DQuat::from_axis_angle(DVec3::new(1.0, 2.0, 2.0).normalize(), 0.7);
    2.5 * (r * p) + DVec3::new(-3.0, 0.25, 7.0)
}

fn transformed(m: &PolyMesh) -> PolyMesh {
    PolyMesh::from_polygons(m.positions().iter().map(|&p| similarity(p)).collect(), &m.polygons()).unwrap()
}

#[test]
fn edits_commute_with_similarity_transforms() {
    let s = 2.5;
    type Op = Box<dyn Fn(&PolyMesh, f64) -> crate::Result<Edited>>;
    let boundary = |m: &PolyMesh| m.edges().filter(|&e| m.is_boundary_edge(e)).collect::<Vec<_>>();
    let cases: Vec<(&str, PolyMesh, Op)> = vec![
        (
            "extrude region",
            cube(),
            Box::new(|m, k| extrude_faces(m, &[FaceId(1), FaceId(2)], FaceGrouping::Region, 0.4 * k)),
        ),
        (
            "extrude each",
            prism(5),
            Box::new(|m, k| extrude_faces(m, &[FaceId(0), FaceId(3)], FaceGrouping::Individual, 0.4 * k)),
        ),
        (
            "inset region",
            grid(3),
            Box::new(|m, k| inset_faces(m, &[FaceId(0), FaceId(1), FaceId(4)], FaceGrouping::Region, 0.2 * k)),
        ),
        ("inset each", prism(6), Box::new(|m, k| inset_faces(m, &[FaceId(1)], FaceGrouping::Individual, 0.3 * k))),
        ("extrude edges", grid(3), Box::new(move |m, k| extrude_boundary_edges(m, &boundary(m)[..5], 0.5 * k))),
        (
            "loop cut",
            prism(5),
            Box::new(|m, _| loop_cut(m, m.find_halfedge(VertexId(0), VertexId(5)).unwrap().edge(), 0.3)),
        ),
        ("merge at centre", cube(), Box::new(|m, _| merge_vertices(m, &[VertexId(0), VertexId(1)], MergeAt::Centre))),
        ("triangulate", prism(7), Box::new(|m, _| triangulate(m, None, Triangulation::ShortestDiagonal))),
    ];
    for (name, mesh, op) in cases {
        let direct = op(&mesh, 1.0).unwrap();
        let moved = op(&transformed(&mesh), s).unwrap();
        assert_eq!(moved.mesh.polygons(), direct.mesh.polygons(), "{name}");
        assert_eq!(moved.provenance, direct.provenance, "{name}");
        for (p, q) in direct.mesh.positions().iter().zip(moved.mesh.positions()) {
            assert!((similarity(*p) - *q).length() < 1e-12 * 10.0, "{name}: {p} → {q}");
        }
    }
}

/// SplitMix64: a small deterministic generator for the random test.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }
    fn below(&mut self, n: usize) -> usize {
        (self.next() % n.max(1) as u64) as usize
    }
    fn unit(&mut self) -> f64 {
        (self.next() >> 11) as f64 / (1u64 << 53) as f64
    }
    fn pick<T: Copy>(&mut self, items: &[T], k: usize) -> Vec<T> {
        if items.is_empty() {
            return Vec::new();
        }
        (0..k).map(|_| items[self.below(items.len())]).collect()
    }
}

fn random_edit(m: &PolyMesh, rng: &mut Rng) -> (usize, crate::Result<Edited>) {
    let k = 1 + rng.below(3);
    let faces = rng.pick(&m.faces().collect::<Vec<_>>(), k);
    let edges = rng.pick(&m.edges().collect::<Vec<_>>(), k);
    let vertices = rng.pick(&m.vertices().collect::<Vec<_>>(), k + 1);
    let grouping = if rng.below(2) == 0 { FaceGrouping::Region } else { FaceGrouping::Individual };
    let t = 0.05 + 0.9 * rng.unit();
    let boundary: Vec<EdgeId> = m.edges().filter(|&e| m.is_boundary_edge(e)).collect();
    let op = rng.below(18);
    let result = match op {
        0 => extrude_faces(m, &faces, grouping, 0.2 + rng.unit()),
        1 => inset_faces(m, &faces, grouping, 0.05 * t),
        2 => extrude_boundary_edges(m, &rng.pick(&boundary, k), 0.3),
        3 => loop_cut(m, edges[0], t),
        4 => split_edges(m, &edges, t),
        5 => {
            // Usually two corners of one face, two apart; sometimes any two vertices.
            let corners: Vec<VertexId> = m.face_vertices(faces[0]).collect();
            if corners.len() >= 4 && rng.below(4) != 0 {
                let i = rng.below(corners.len());
                connect_vertices(m, corners[i], corners[(i + 2) % corners.len()])
            } else {
                connect_vertices(m, vertices[0], vertices[1])
            }
        }
        6 => delete_faces(m, &faces),
        7 => delete_vertices(m, &vertices[..1]),
        8 => dissolve_edges(m, &edges),
        9 => dissolve_vertices(m, &vertices[..1]),
        10 => merge_vertices(m, &vertices, [MergeAt::Centre, MergeAt::First, MergeAt::Last][rng.below(3)]),
        11 => merge_by_distance(m, &m.vertices().collect::<Vec<_>>(), 0.3 * t),
        12 => fill_edges(m, &boundary),
        13 => flip_normals(m, if rng.below(2) == 0 { None } else { Some(&faces) }),
        14 => triangulate(m, Some(&faces), [Triangulation::Fan, Triangulation::ShortestDiagonal][rng.below(2)]),
        15 => join_triangles(m, None, &JoinParams::default()),
        16 => dissolve_faces(m, &faces),
        _ => {
            let axis = [Axis::X, Axis::Y, Axis::Z][rng.below(3)];
            let lo = m.bounding_box().map_or(0.0, |(lo, _)| lo[axis as usize]);
            apply_mirror(m, MirrorPlane::new(axis, lo), DEFAULT_MIRROR_TOLERANCE)
        }
    };
    (op, result)
}

#[test]
fn random_edit_sequences_keep_the_cage_valid() {
    let mut rng = Rng(0x7a07);
    let mut applied = [0usize; 18];
    for _ in 0..200 {
        let mut mesh = cube();
        for _ in 0..14 {
            if mesh.face_count() > 400 {
                break;
            }
            let (op, result) = random_edit(&mesh, &mut rng);
            match result {
                Ok(edited) => {
                    check(&mesh, &edited);
                    let tension = vec![1.0; mesh.edge_count()];
                    let carried = carry_edge_property(&tension, &edited.provenance, &CarryRule::new_elements(0.0));
                    assert_eq!(carried.unwrap().len(), edited.mesh.edge_count());
                    applied[op] += 1;
                    mesh = edited.mesh;
                }
                Err(e) => {
                    let text = e.to_string();
                    assert!(!text.is_empty() && !text.contains('\n'), "op {op}: {text}");
                }
            }
        }
    }
    // Every kind of edit succeeded somewhere in the sequences.
    assert!(applied.iter().all(|&n| n > 0), "applied per op: {applied:?}");
}

#[test]
fn the_same_edit_gives_the_same_result() {
    let mut rng = Rng(42);
    let mesh = super::fixtures::house();
    for _ in 0..40 {
        let state = rng.0;
        let (_, first) = random_edit(&mesh, &mut rng);
        rng.0 = state;
        let (_, second) = random_edit(&mesh, &mut rng);
        match (first, second) {
            (Ok(a), Ok(b)) => {
                assert_eq!(a.mesh.polygons(), b.mesh.polygons());
                assert_eq!(a.mesh.positions(), b.mesh.positions());
                assert_eq!(a.provenance, b.provenance);
            }
            (Err(a), Err(b)) => assert_eq!(a.to_string(), b.to_string()),
            _ => panic!("an edit succeeded once and failed once"),
        }
    }
}

#[test]
fn every_edit_on_every_fixture_has_the_expected_counts() {
    for (name, m) in all() {
        let (v, e, f) = (m.vertex_count() as i64, m.edge_count() as i64, m.face_count() as i64);
        let chi = m.euler_characteristic();
        let closed = m.is_closed();
        let expect = |what: &str, result: crate::Result<Edited>, dv: i64, de: i64, df: i64, stays_closed: bool| {
            let edited = result.unwrap_or_else(|err| panic!("{name} / {what}: {err}"));
            check(&m, &edited);
            let got = &edited.mesh;
            let counts = (got.vertex_count() as i64, got.edge_count() as i64, got.face_count() as i64);
            assert_eq!(counts, (v + dv, e + de, f + df), "{name} / {what}");
            if stays_closed {
                assert_eq!(got.euler_characteristic(), chi, "{name} / {what}: Euler characteristic");
                assert_eq!(got.is_closed(), closed, "{name} / {what}: closedness");
            }
        };
        let k = m.face_valence(FaceId(0)) as i64;
        expect("extrude region", extrude_faces(&m, &[FaceId(0)], FaceGrouping::Region, 0.1), k, 2 * k, k, true);
        expect("extrude each", extrude_faces(&m, &[FaceId(0)], FaceGrouping::Individual, -0.1), k, 2 * k, k, true);
        expect("inset", inset_faces(&m, &[FaceId(0)], FaceGrouping::Individual, 0.05), k, 2 * k, k, true);
        expect("split", split_edges(&m, &[EdgeId(1)], 0.5), 1, 1, 0, true);
        let big = m.faces().find(|&g| m.face_valence(g) >= 4).unwrap();
        let corners: Vec<VertexId> = m.face_vertices(big).collect();
        expect("connect", connect_vertices(&m, corners[0], corners[2]), 0, 1, 1, true);
        let inner = m
            .edges()
            .find(|&x| {
                let (a, b) = (m.face(x.halfedge(0)), m.face(x.halfedge(1)));
                a.is_valid() && b.is_valid() && {
                    let shared = m.face_halfedges(a).filter(|h| m.face(h.twin()) == b).count();
                    shared == 1
                }
            })
            .unwrap();
        expect("dissolve edge", dissolve_edges(&m, &[inner]), 0, -1, -1, true);
        let tris = m.faces().map(|g| m.face_valence(g) as i64 - 2).sum::<i64>();
        expect("triangulate", triangulate(&m, None, Triangulation::ShortestDiagonal), 0, tris - f, tris - f, true);
        expect("flip", flip_normals(&m, None), 0, 0, 0, true);
        // A ring of n quads: n + 1 vertices if it ends on the boundary, n if it closes.
        let ring_edge = m.edges().find(|&x| loop_cut(&m, x, 0.5).is_ok()).unwrap();
        let cut = loop_cut(&m, ring_edge, 0.5).unwrap();
        let n = cut.provenance.faces.iter().filter(|o| matches!(o, FaceOrigin::SplitFrom(_))).count() as i64 / 2;
        let new = cut.mesh.vertex_count() as i64 - v;
        assert!(new == n || new == n + 1, "{name}: {new} vertices for {n} quads");
        expect("loop cut", Ok(cut), new, new + n, n, true);
        let lost_edges = m.face_halfedges(FaceId(0)).filter(|h| m.is_boundary_halfedge(h.twin())).count() as i64;
        let edited = delete_faces(&m, &[FaceId(0)]).unwrap();
        check(&m, &edited);
        assert_eq!(edited.mesh.face_count() as i64, f - 1, "{name} / delete");
        assert_eq!(edited.mesh.edge_count() as i64, e - lost_edges, "{name} / delete");
        assert!(!edited.mesh.is_closed(), "{name} / delete opens the cage");
    }
}

#[test]
fn hostile_parameters_give_a_valid_cage_or_one_line() {
    let (cube, g) = (cube(), grid(3));
    let huge = 1e308;
    let results: Vec<(&str, &PolyMesh, crate::Result<Edited>)> = vec![
        ("extrude huge", &cube, extrude_faces(&cube, &[FaceId(0)], FaceGrouping::Region, huge)),
        ("extrude tiny", &cube, extrude_faces(&cube, &[FaceId(0)], FaceGrouping::Region, 1e-300)),
        ("edge extrude huge", &g, extrude_boundary_edges(&g, &[EdgeId(0)], -huge)),
        ("inset huge", &cube, inset_faces(&cube, &[FaceId(0)], FaceGrouping::Region, huge)),
        ("inset tiny", &cube, inset_faces(&cube, &[FaceId(0)], FaceGrouping::Region, 1e-300)),
        ("loop cut far edge", &cube, loop_cut(&cube, EdgeId(u32::MAX - 1), 0.5)),
        ("split nearly at an end", &cube, split_edges(&cube, &[EdgeId(0)], 1e-300)),
        ("merge by a huge distance", &cube, merge_by_distance(&cube, &cube.vertices().collect::<Vec<_>>(), huge)),
        ("merge by a tiny distance", &g, merge_by_distance(&g, &g.vertices().collect::<Vec<_>>(), 1e-300)),
        ("mirror far away", &g, apply_mirror(&g, MirrorPlane::new(Axis::Z, -huge), 0.0)),
        ("mirror huge tolerance", &g, apply_mirror(&g, MirrorPlane::new(Axis::X, 0.0), huge)),
        ("join with no fold", &g, join_triangles(&g, None, &JoinParams { max_fold: 0.0 })),
        ("join with any fold", &cube, join_triangles(&cube, None, &JoinParams { max_fold: 1e9 })),
    ];
    for (what, old, result) in results {
        match result {
            Ok(edited) => check(old, &edited),
            Err(e) => {
                let text = e.to_string();
                assert!(!text.is_empty() && !text.contains('\n') && text.len() < 300, "{what}: {text}");
            }
        }
    }
}

#[test]
fn the_smoothed_surface_of_a_mirrored_cage_is_mirror_symmetric() {
    // An uneven open half-box (open at x = 0) with a tension here and there.
    let mut half = delete_faces(&cube(), &[FaceId(4)]).unwrap().mesh;
    for (v, d) in [(1u32, DVec3::new(0.3, -0.1, 0.0)), (7, DVec3::new(0.2, 0.15, 0.4)), (6, DVec3::new(0.0, 0.2, 0.1))]
    {
        let p = half.position(VertexId(v));
        half.set_position(VertexId(v), p + d);
    }
    let mut doc = Document::new(half);
    doc.fixed[5] = false;
    doc.vertex_tension[3] = 0.8;
    doc.set_edge_tension(VertexId(1), VertexId(3), 1.5).unwrap();
    doc.settings.levels = 2;
    let plane = MirrorPlane::new(Axis::X, 0.0);
    let edited = apply_mirror(&doc.cage, plane, DEFAULT_MIRROR_TOLERANCE).unwrap();
    let mirrored = doc.with_edited_cage(edited).unwrap();
    let mut solver = crate::nusd::surface::SurfaceSolver::new(&mirrored).unwrap();
    solver.solve().unwrap();
    let surface = solver.surface_positions();
    let diagonal = mirrored.cage.bounding_diagonal();
    assert!(surface.len() > 100);
    for &q in surface {
        let image = plane.reflect(q);
        let nearest = surface.iter().map(|&r| r.distance(image)).fold(f64::INFINITY, f64::min);
        assert!(nearest <= 1e-9 * diagonal, "{q}: its mirror image is {nearest} from the surface's vertices");
    }
}
