//! Loops, rings, more / less / linked and mode conversion checked against the geometry of grids,
//! tubes and cubes (rows and columns found by coordinates, not by the walks), and face picking
//! checked against which faces of a convex cage face the camera.

use super::*;
use crate::editor::interaction::project;
use crate::editor::primitives;
use taut_render::StandardView;

fn midpoint(cage: &PolyMesh, e: EdgeId) -> DVec3 {
    let (a, b) = cage.edge_vertices(e);
    0.5 * (cage.position(a) + cage.position(b))
}

fn is_along_x(cage: &PolyMesh, e: EdgeId) -> bool {
    let (a, b) = cage.edge_vertices(e);
    (cage.position(a).y - cage.position(b).y).abs() < 1e-12
}

#[test]
fn a_loop_on_a_grid_is_one_row_and_a_ring_is_one_column() {
    let cage = primitives::grid_patch(5, 4).cage;
    // An interior edge along x, not on the border: its row line is y = its y.
    let e = cage
        .edges()
        .find(|&e| is_along_x(&cage, e) && !cage.is_boundary_edge(e) && midpoint(&cage, e).x > -0.9)
        .unwrap();
    let y = midpoint(&cage, e).y;
    let row: Vec<EdgeId> =
        cage.edges().filter(|&f| is_along_x(&cage, f) && (midpoint(&cage, f).y - y).abs() < 1e-12).collect();
    let mut walked = edge_loop(&cage, e);
    walked.sort();
    assert_eq!(walked, row, "the loop is the whole row of 5 edges at y = {y}");
    assert_eq!(row.len(), 5);

    let x = midpoint(&cage, e).x;
    let column: Vec<EdgeId> =
        cage.edges().filter(|&f| is_along_x(&cage, f) && (midpoint(&cage, f).x - x).abs() < 1e-12).collect();
    let (mut ring, faces) = edge_ring(&cage, e);
    ring.sort();
    assert_eq!(ring, column, "the ring crosses every quad of the column at x = {x}");
    assert_eq!(faces.len(), 4);
}

#[test]
fn loops_round_a_tube_close_and_stop_at_its_open_ends() {
    let cage = primitives::cylinder(8, 3).cage;
    // A ring edge in the middle (both ends at the same height, not on a boundary).
    let e = cage
        .edges()
        .find(|&e| {
            let (a, b) = cage.edge_vertices(e);
            (cage.position(a).z - cage.position(b).z).abs() < 1e-12 && !cage.is_boundary_edge(e)
        })
        .unwrap();
    assert_eq!(edge_loop(&cage, e).len(), 8, "round the tube");
    let (ring, faces) = edge_ring(&cage, e);
    assert_eq!((ring.len(), faces.len()), (4, 3), "along the tube, end to end");
}

#[test]
fn mode_conversion_more_less_and_linked_follow_the_vertices() {
    let cube = primitives::cube().cage;
    let top: Vec<VertexId> = cube.vertices().filter(|&v| cube.position(v).z > 0.0).collect();
    let mut s = Selection { vertices: top.clone(), ..Default::default() };
    set_mode(&cube, &mut s, SelectMode::Face);
    assert_eq!(s.faces.len(), 1);
    assert!(cube.face_vertices(s.faces[0]).all(|v| cube.position(v).z > 0.0));
    set_mode(&cube, &mut s, SelectMode::Edge);
    assert_eq!(s.edges.len(), 4);
    set_mode(&cube, &mut s, SelectMode::Vertex);
    let mut back = s.vertices.clone();
    back.sort();
    assert_eq!(back, top);

    // More from one interior grid vertex: it and its four neighbours; less: it alone again.
    let grid = primitives::grid_patch(4, 4).cage;
    let centre = grid.vertices().find(|&v| grid.position(v).truncate().length() < 1e-12).unwrap();
    let mut s = Selection { vertices: vec![centre], ..Default::default() };
    select_more(&grid, &mut s);
    assert_eq!(s.vertices.len(), 5);
    let cell = 0.5;
    assert!(s.vertices.iter().all(|&v| grid.position(v).truncate().length() <= cell + 1e-12));
    select_less(&grid, &mut s);
    assert_eq!(s.vertices, vec![centre]);

    // Linked: one vertex of a cube reaches all of it; faces in face mode.
    let mut s = Selection { vertices: vec![VertexId(0)], ..Default::default() };
    select_linked(&cube, &mut s);
    assert_eq!(s.vertices.len(), 8);
    let mut s = Selection { faces: vec![FaceId(0)], mode: SelectMode::Face, ..Default::default() };
    select_linked(&cube, &mut s);
    assert_eq!(s.faces.len(), 6);
    select_less(&cube, &mut s);
    assert_eq!(s.faces.len(), 6, "a closed cage has no border to shrink from");
}

#[test]
fn alt_click_selects_loops_in_every_mode() {
    let grid = primitives::grid_patch(3, 3).cage;
    let e = grid.edges().find(|&e| is_along_x(&grid, e) && !grid.is_boundary_edge(e)).unwrap();
    let mut s = Selection::default();
    select_loop_or_ring(&grid, &mut s, e, false, false);
    assert_eq!(s.vertices.len(), 4, "a row of 3 edges has 4 vertices");
    s.mode = SelectMode::Edge;
    select_loop_or_ring(&grid, &mut s, e, false, false);
    assert_eq!((s.vertices.len(), s.edges.len()), (0, 3));
    s.mode = SelectMode::Face;
    select_loop_or_ring(&grid, &mut s, e, false, false);
    assert_eq!(s.faces.len(), 3, "the faces of the column the edge crosses");
    select_loop_or_ring(&grid, &mut s, e, true, true);
    assert_eq!(s.faces.len(), 3, "adding the same ring adds nothing new");
}

#[test]
fn a_face_centre_picks_that_face_exactly_when_it_faces_the_camera() {
    let cube = primitives::cube().cage;
    let rect = ViewportRect { min: Vec2::ZERO, size: Vec2::new(800.0, 600.0) };
    for view in [StandardView::Front, StandardView::Right, StandardView::Top, StandardView::Perspective] {
        let mut camera = Camera::default();
        camera.set_view(view);
        let eye = camera.view_from_world().as_dmat4().inverse().w_axis.truncate();
        let mut front_facing = 0;
        for f in cube.faces() {
            let ring: Vec<DVec3> = cube.face_vertices(f).map(|v| cube.position(v)).collect();
            let centre = ring.iter().copied().sum::<DVec3>() / ring.len() as f64;
            let normal = cube.face_area_vector(f);
            let Some((pixel, _)) = project(&camera, &rect, centre) else { continue };
            let faces_eye = normal.dot(eye - centre) > 1e-9;
            front_facing += usize::from(faces_eye);
            let picked = pick_face(&camera, &rect, &cube, pixel);
            if faces_eye {
                assert_eq!(picked, Some(f), "{view:?}: the centre of {f:?}");
            } else {
                assert_ne!(picked, Some(f), "{view:?}: {f:?} is behind another face");
            }
        }
        assert!(front_facing >= 1);
    }
    // Beside the cage, nothing.
    let camera = Camera::default();
    assert_eq!(pick_face(&camera, &rect, &cube, Vec2::new(1.0, 1.0)), None);
}
