//! Tests of `interaction.rs`, kept apart from the code they check.

use super::*;
use glam::Vec3;

fn rect() -> ViewportRect {
    ViewportRect { min: Vec2::new(40.0, 25.0), size: Vec2::new(800.0, 600.0) }
}

fn camera() -> Camera {
    Camera {
        target: Vec3::new(0.5, -0.25, 0.3),
        distance: 6.0,
        azimuth: 30.0,
        elevation: 25.0,
        fov_y: 35.0,
        orthographic: false,
    }
}

/// Independent pinhole model from the camera's frame and field of view (no matrices):
/// pixel and depth of `p`, or `None` behind the eye.
fn pinhole(c: &Camera, r: &ViewportRect, p: DVec3) -> Option<(DVec2, f64)> {
    let (eye, right, up, back) = (c.eye().as_dvec3(), c.right().as_dvec3(), c.up().as_dvec3(), c.backward().as_dvec3());
    let v = p - eye;
    let z = -v.dot(back);
    if z <= 0.0 {
        return None;
    }
    let tan = (0.5 * c.fov_y as f64).to_radians().tan();
    let aspect = r.size.x as f64 / r.size.y as f64;
    let ndc = DVec2::new(v.dot(right) / (z * tan * aspect), v.dot(up) / (z * tan));
    let (near, far) = (c.distance as f64 * 0.01, c.distance as f64 * 100.0);
    let depth = far * (z - near) / (z * (far - near));
    let pixel = r.min.as_dvec2() + DVec2::new(ndc.x + 1.0, 1.0 - ndc.y) * 0.5 * r.size.as_dvec2();
    Some((pixel, depth))
}

/// Independent ray under a pixel, from the same pinhole model.
fn pinhole_ray(c: &Camera, r: &ViewportRect, pixel: Vec2) -> (DVec3, DVec3) {
    let t = (pixel - r.min) / r.size;
    let tan = (0.5 * c.fov_y as f64).to_radians().tan();
    let aspect = r.size.x as f64 / r.size.y as f64;
    let (x, y) = ((2.0 * t.x as f64 - 1.0) * tan * aspect, (1.0 - 2.0 * t.y as f64) * tan);
    let d = -c.backward().as_dvec3() + x * c.right().as_dvec3() + y * c.up().as_dvec3();
    (c.eye().as_dvec3(), d.normalize())
}

fn distance_to_line(p: DVec3, (o, d): (DVec3, DVec3)) -> f64 {
    let v = p - o;
    (v - d * v.dot(d)).length()
}

fn pixel_of(c: &Camera, r: &ViewportRect, p: DVec3) -> Vec2 {
    project(c, r, p).expect("in front").0
}

#[test]
fn the_target_lands_at_the_centre_and_projection_matches_a_pinhole() {
    let (c, r) = (camera(), rect());
    let (pixel, depth) = project(&c, &r, c.target.as_dvec3()).unwrap();
    let centre = r.min + 0.5 * r.size;
    assert!(pixel.distance(centre) < 1e-3, "{pixel} vs {centre}");
    assert!(depth > 0.0 && depth < 1.0);
    for p in [DVec3::new(1.0, 0.5, -0.2), DVec3::new(-1.5, 1.0, 1.2), DVec3::new(0.2, -2.0, 0.0)] {
        let (got, got_depth) = project(&c, &r, p).unwrap();
        let (want, want_depth) = pinhole(&c, &r, p).unwrap();
        assert!(got.as_dvec2().distance(want) < 2e-3, "{p}: {got} vs {want}");
        assert!((got_depth as f64 - want_depth).abs() < 1e-5, "{p}: {got_depth} vs {want_depth}");
    }
}

#[test]
fn project_and_unproject_round_trip() {
    let (c, r) = (camera(), rect());
    for p in [DVec3::new(1.0, 0.5, -0.2), DVec3::new(-1.5, 1.0, 1.2), DVec3::new(3.0, 8.0, -1.0)] {
        let pixel = pixel_of(&c, &r, p);
        let (origin, direction) = unproject_ray(&c, &r, pixel);
        assert!((direction.length() - 1.0).abs() < 1e-12);
        assert!((p - origin).dot(direction) > 0.0, "the point is ahead on the ray");
        // f32 pixel rounding: well under a micrometre at these distances.
        assert!(distance_to_line(p, (origin, direction)) < 1e-4, "{p}");
    }
    for pixel in [Vec2::new(41.0, 26.0), Vec2::new(500.0, 300.0), Vec2::new(839.0, 624.0)] {
        let ray = unproject_ray(&c, &r, pixel);
        let reference = pinhole_ray(&c, &r, pixel);
        assert!(ray.0.distance(reference.0) < 1e-5 && ray.1.distance(reference.1) < 1e-6);
        let p = ray.0 + 4.0 * ray.1;
        assert!(pixel_of(&c, &r, p).distance(pixel) < 1e-3);
    }
}

#[test]
fn behind_the_camera_is_never_projected_picked_or_selected() {
    let (c, r) = (camera(), rect());
    let eye = c.eye().as_dvec3();
    let front = DVec3::new(0.8, 0.1, 0.4);
    // Mirrored through the eye: a naive divide by w puts it on the same pixel as `front`.
    let behind = eye - 0.5 * (front - eye);
    assert!(project(&c, &r, behind).is_none());
    let mouse = pixel_of(&c, &r, front);
    assert_eq!(pick_vertex(&c, &r, &[behind], mouse, 10.0), None);
    assert_eq!(pick_vertex(&c, &r, &[behind, front], mouse, 10.0), Some(VertexId(1)));
    let band = box_select(&c, &r, &[behind], mouse - Vec2::splat(20.0), mouse + Vec2::splat(20.0));
    assert!(band.is_empty());
}

#[test]
fn pick_prefers_the_nearer_of_two_overlapping_vertices_and_respects_the_radius() {
    let (c, r) = (camera(), rect());
    let (eye, p) = (c.eye().as_dvec3(), DVec3::new(0.3, 0.2, 0.1));
    let far = eye + 2.0 * (p - eye);
    let beside = DVec3::new(-1.0, 1.5, 0.8);
    let mouse = pixel_of(&c, &r, p) + Vec2::new(3.0, -2.0);
    for positions in [[far, p, beside], [p, far, beside]] {
        let want = positions.iter().position(|&q| q == p).unwrap();
        assert_eq!(pick_vertex(&c, &r, &positions, mouse, 6.0), Some(VertexId(want as u32)));
    }
    // 3.6 px away: outside a 3-pixel radius, inside a 4-pixel one.
    assert_eq!(pick_vertex(&c, &r, &[far, p], mouse, 3.0), None);
    assert!(pick_vertex(&c, &r, &[far, p], mouse, 4.0).is_some());
    // Strictly nearer on screen beats nearer in depth.
    let offside = pixel_of(&c, &r, far) + Vec2::new(10.0, 0.0);
    let slightly = unproject_ray(&c, &r, offside + Vec2::new(-3.0, 0.0));
    let back_but_closer = slightly.0 + 12.0 * slightly.1;
    assert_eq!(pick_vertex(&c, &r, &[p, back_but_closer], offside, 15.0), Some(VertexId(1)));
}

fn two_quads() -> PolyMesh {
    let positions = vec![
        DVec3::new(-1.0, -1.0, 0.0),
        DVec3::new(0.0, -1.0, 0.0),
        DVec3::new(1.0, -1.0, 0.0),
        DVec3::new(-1.0, 1.0, 0.0),
        DVec3::new(0.0, 1.0, 0.0),
        DVec3::new(1.0, 1.0, 0.0),
    ];
    PolyMesh::from_polygons(positions, &[[0u32, 1, 4, 3], [1, 2, 5, 4]]).unwrap()
}

#[test]
fn edge_pick_at_the_middle_of_each_segment() {
    let (c, r, mesh) = (camera(), rect(), two_quads());
    for e in mesh.edges() {
        let (a, b) = mesh.edge_vertices(e);
        let middle = 0.5 * (mesh.position(a) + mesh.position(b));
        let mouse = pixel_of(&c, &r, middle);
        assert_eq!(pick_edge(&c, &r, &mesh, mouse, 5.0), Some(e), "{a:?}-{b:?}");
    }
    let nowhere = pixel_of(&c, &r, DVec3::new(0.0, 0.0, 3.0));
    assert_eq!(pick_edge(&c, &r, &mesh, nowhere, 5.0), None);
}

#[test]
fn edge_pick_uses_the_visible_part_of_an_edge_crossing_the_near_plane() {
    let (c, r) = (camera(), rect());
    let eye = c.eye().as_dvec3();
    let inside = c.target.as_dvec3() + DVec3::new(0.2, 0.0, 0.1);
    // From in front of the camera to well behind it, passing beside the eye.
    let behind = eye + 1.5 * (eye - inside) + c.right().as_dvec3() * 0.5;
    let off = DVec3::new(0.0, 0.0, -3.0);
    let mesh = PolyMesh::from_polygons(vec![inside, behind, inside + off], &[[0u32, 1, 2]]).unwrap();
    let e = mesh
        .edges()
        .find(|&e| {
            mesh.edge_vertices(e) == (VertexId(0), VertexId(1)) || mesh.edge_vertices(e) == (VertexId(1), VertexId(0))
        })
        .unwrap();
    // A point on the edge a little way from `inside`, still well in front.
    let on_edge = inside + 0.1 * (behind - inside);
    let mouse = pixel_of(&c, &r, on_edge);
    assert_eq!(pick_edge(&c, &r, &mesh, mouse, 3.0), Some(e));
    // Projected without clipping, `behind` lands on the other side of `inside` (its mirror
    // through the eye); the middle of that naive segment is far from the visible part,
    // which starts at `inside` and runs the other way, so nothing may be picked there.
    let m = c.clip_from_view(r.aspect()) * c.view_from_world();
    let q = m * behind.as_vec3().extend(1.0);
    let naive = r.min + Vec2::new(q.x / q.w + 1.0, 1.0 - q.y / q.w) * 0.5 * r.size;
    let naive_middle = 0.5 * (naive + pixel_of(&c, &r, inside));
    let (start, run) = (pixel_of(&c, &r, inside), (mouse - pixel_of(&c, &r, inside)).normalize());
    let to_visible = naive_middle - (start + run * (naive_middle - start).dot(run).max(0.0));
    assert!(to_visible.length() > 10.0, "the naive middle is away from the visible edge");
    assert_ne!(pick_edge(&c, &r, &mesh, naive_middle, 3.0), Some(e));
}

#[test]
fn box_select_in_any_corner_order() {
    let (c, r) = (camera(), rect());
    let positions = [DVec3::new(0.0, 0.0, 0.0), DVec3::new(0.6, -0.2, 0.5), DVec3::new(-2.0, 3.0, 2.0)];
    let (p0, p1) = (pixel_of(&c, &r, positions[0]), pixel_of(&c, &r, positions[1]));
    let (lo, hi) = (p0.min(p1) - Vec2::splat(2.0), p0.max(p1) + Vec2::splat(2.0));
    assert!(!(lo.cmple(pixel_of(&c, &r, positions[2])).all() && pixel_of(&c, &r, positions[2]).cmple(hi).all()));
    let want = vec![VertexId(0), VertexId(1)];
    let (other_a, other_b) = (Vec2::new(lo.x, hi.y), Vec2::new(hi.x, lo.y));
    for (a, b) in [(lo, hi), (hi, lo), (other_a, other_b), (other_b, other_a)] {
        assert_eq!(box_select(&c, &r, &positions, a, b), want, "{a} {b}");
    }
    assert!(box_select(&c, &r, &positions, lo, lo).is_empty());
}

fn selection() -> Vec<(VertexId, DVec3)> {
    vec![
        (VertexId(3), DVec3::new(0.2, 0.1, 0.0)),
        (VertexId(7), DVec3::new(1.0, -0.4, 0.6)),
        (VertexId(9), DVec3::new(-0.3, 0.5, 0.9)),
    ]
}

fn centroid(points: &[(VertexId, DVec3)]) -> DVec3 {
    points.iter().map(|&(_, p)| p).sum::<DVec3>() / points.len() as f64
}

#[test]
fn free_drag_keeps_the_centroid_under_the_cursor_in_the_view_plane() {
    let (c, r, start) = (camera(), rect(), selection());
    let grab = pixel_of(&c, &r, centroid(&start));
    for delta in [Vec2::new(37.0, -21.0), Vec2::new(-250.0, 180.0), Vec2::new(0.5, 0.0)] {
        let moved = drag_positions(&c, &r, &start, grab, grab + delta, None);
        let offset = moved[0].1 - start[0].1;
        for (&(v0, p0), &(v1, p1)) in start.iter().zip(&moved) {
            assert_eq!(v0, v1);
            assert!(((p1 - p0) - offset).length() < 1e-12, "one rigid offset");
        }
        // Checked against the pinhole reference, not against the code's own projection.
        let (now, _) = pinhole(&c, &r, centroid(&moved)).unwrap();
        assert!(now.distance((grab + delta).as_dvec2()) < 2e-3, "{delta}: {now}");
        assert!(offset.dot(c.backward().as_dvec3()).abs() < 1e-6 * offset.length().max(1.0), "{offset}");
    }
    // Grabbed beside the centroid, the centroid's projection follows the cursor's motion.
    let beside = grab + Vec2::new(12.0, 8.0);
    let moved = drag_positions(&c, &r, &start, beside, beside + Vec2::new(-40.0, 30.0), None);
    let (now, _) = pinhole(&c, &r, centroid(&moved)).unwrap();
    assert!(now.distance((grab + Vec2::new(-40.0, 30.0)).as_dvec2()) < 2e-3, "{now}");
}

#[test]
fn a_drag_that_has_not_moved_returns_the_start_positions_exactly() {
    let (c, r, start) = (camera(), rect(), selection());
    let mouse = Vec2::new(321.5, 200.25);
    for axis in [None, Some(Axis::X), Some(Axis::Y), Some(Axis::Z)] {
        assert_eq!(drag_positions(&c, &r, &start, mouse, mouse, axis), start);
    }
    assert!(drag_positions(&c, &r, &[], mouse, mouse + Vec2::ONE, None).is_empty());
}

#[test]
fn axis_drag_changes_only_that_coordinate_and_follows_the_cursor() {
    let (c, r, start) = (camera(), rect(), selection());
    let grab = pixel_of(&c, &r, centroid(&start));
    for (axis, index) in [(Axis::X, 0), (Axis::Y, 1), (Axis::Z, 2)] {
        let now = grab + Vec2::new(45.0, -30.0);
        let moved = drag_positions(&c, &r, &start, grab, now, Some(axis));
        for (&(_, p0), &(_, p1)) in start.iter().zip(&moved) {
            for k in 0..3 {
                if k == index {
                    assert!((p1[k] - p0[k]).abs() > 1e-3, "{axis:?} moves");
                } else {
                    assert_eq!(p1[k], p0[k], "{axis:?} keeps coordinate {k}");
                }
            }
        }
        // The moved centroid is the axis point closest to the reference mouse ray: the
        // shortest segment between them is perpendicular to the axis.
        let moved_centroid = centroid(&moved);
        let (o, d) = pinhole_ray(&c, &r, now);
        let foot = o + d * (moved_centroid - o).dot(d);
        let gap = moved_centroid - foot;
        assert!(gap.dot(axis.direction()).abs() < 1e-5, "{axis:?}: {gap}");
    }
}

#[test]
fn an_axis_along_the_view_gives_finite_bounded_positions() {
    let r = rect();
    let mut c = camera();
    c.target = Vec3::ZERO;
    // Front view: the eye looks along +Y, straight down the Y axis; then nearly along it.
    for (azimuth, elevation) in [(0.0, 0.0), (1.0, 0.5), (0.0, 4.0), (180.0, 0.0), (0.0, 6.0)] {
        c.azimuth = azimuth;
        c.elevation = elevation;
        let start = vec![(VertexId(0), DVec3::new(0.0, 0.0, 0.0)), (VertexId(1), DVec3::new(0.0, 0.2, 0.0))];
        let grab = pixel_of(&c, &r, centroid(&start));
        let limit = MAX_DRAG_IN_DISTANCES * c.distance as f64;
        for dx in [-1.0e5, -300.0, -1.0, 0.0, 2.0, 300.0, 1.0e5] {
            for dy in [-1.0e5, -250.0, -1.0, 0.0, 1.0, 250.0, 1.0e5] {
                let moved = drag_positions(&c, &r, &start, grab, grab + Vec2::new(dx, dy), Some(Axis::Y));
                for (&(_, p0), &(_, p1)) in start.iter().zip(&moved) {
                    assert!(p1.is_finite(), "{azimuth} {elevation} {dx} {dy}");
                    assert!((p1 - p0).length() <= limit * (1.0 + 1e-9), "{azimuth} {elevation} {dx} {dy}: {p1}");
                    assert_eq!((p1.x, p1.z), (p0.x, p0.z));
                }
                // The selection stays in front of the camera.
                let depth = (centroid(&moved) - c.eye().as_dvec3()).dot(-c.backward().as_dvec3());
                assert!(depth >= 0.0099 * c.distance as f64, "{azimuth} {elevation} {dx} {dy}: {depth}");
            }
        }
        // A few pixels move the selection a little, not across the scene.
        let nudge = drag_positions(&c, &r, &start, grab, grab + Vec2::new(0.0, -3.0), Some(Axis::Y));
        let step = (nudge[0].1 - start[0].1).length();
        assert!(step < 0.5 * c.distance as f64, "{azimuth} {elevation}: {step}");
    }
}

#[test]
fn a_selection_behind_the_camera_drags_to_finite_positions() {
    let (c, r) = (camera(), rect());
    let eye = c.eye().as_dvec3();
    let start = vec![(VertexId(0), eye + 2.0 * c.backward().as_dvec3())];
    for axis in [None, Some(Axis::X), Some(Axis::Z)] {
        let moved =
            drag_positions(&c, &r, &start, r.min + 0.5 * r.size, r.min + 0.5 * r.size + Vec2::new(30.0, 10.0), axis);
        assert!(moved[0].1.is_finite(), "{axis:?}");
    }
}

#[test]
fn orbit_turns_the_scene_as_if_grabbed() {
    let r = rect();
    let c = camera();
    // A point on the near side of the target, between it and the eye.
    let near_side = (c.target + 0.5 * c.backward()).as_dvec3();
    let before = pixel_of(&c, &r, near_side);
    let (d_azimuth, d_elevation) = orbit_from_drag(Vec2::new(50.0, 0.0));
    assert_eq!(d_elevation, 0.0);
    assert!((d_azimuth.abs() - 50.0 * ORBIT_DEGREES_PER_PIXEL).abs() < 1e-6);
    let mut turned = c;
    turned.orbit(d_azimuth, d_elevation);
    assert!(pixel_of(&turned, &r, near_side).x > before.x + 1.0, "dragging right moves the near side right");
    let (d_azimuth, d_elevation) = orbit_from_drag(Vec2::new(0.0, 40.0));
    assert_eq!(d_azimuth, 0.0);
    let mut tilted = c;
    tilted.orbit(d_azimuth, d_elevation);
    assert!(tilted.elevation > c.elevation, "dragging down looks more from above");
    assert!(pixel_of(&tilted, &r, near_side).y > before.y + 1.0, "dragging down moves the near side down");
}

#[test]
fn zoom_notches_compose() {
    assert_eq!(zoom_factor(0.0), 1.0);
    assert!((zoom_factor(1.0) - ZOOM_PER_NOTCH).abs() < 1e-7);
    assert!(zoom_factor(1.0) < 1.0, "scrolling away from the designer zooms in");
    assert!((zoom_factor(-1.0) * zoom_factor(1.0) - 1.0).abs() < 1e-6);
    assert!((zoom_factor(0.5) * zoom_factor(0.5) - zoom_factor(1.0)).abs() < 1e-6);
    assert_eq!(zoom_factor(f32::NAN), 1.0);
    assert!(zoom_factor(1e9).is_finite() && zoom_factor(1e9) > 0.0);
}

/// Independent parallel projection from the camera's frame and scale (no matrices): the pixel of
/// `p`, where half the view's height is `distance · tan(fov / 2)` whatever the depth.
fn parallel(c: &Camera, r: &ViewportRect, p: DVec3) -> DVec2 {
    let v = p - c.target.as_dvec3();
    let h = c.distance as f64 * (0.5 * c.fov_y as f64).to_radians().tan();
    let aspect = r.size.x as f64 / r.size.y as f64;
    let ndc = DVec2::new(v.dot(c.right().as_dvec3()) / (h * aspect), v.dot(c.up().as_dvec3()) / h);
    r.min.as_dvec2() + DVec2::new(ndc.x + 1.0, 1.0 - ndc.y) * 0.5 * r.size.as_dvec2()
}

#[test]
fn orthographic_projection_is_parallel_and_its_rays_run_along_the_view() {
    let r = rect();
    let c = Camera { orthographic: true, ..camera() };
    let forward = -c.backward().as_dvec3();
    for p in [DVec3::new(1.0, 0.5, -0.2), DVec3::new(-1.5, 1.0, 1.2), DVec3::new(0.2, -2.0, 0.0)] {
        let (got, depth) = project(&c, &r, p).expect("the whole display box is in front");
        assert!(got.as_dvec2().distance(parallel(&c, &r, p)) < 2e-3, "{p}: {got}");
        assert!((0.0..1.0).contains(&depth));
        // Nearer and farther along the view: the same pixel, another depth.
        for along in [-1.5, 2.5] {
            let (moved, moved_depth) = project(&c, &r, p + forward * along).unwrap();
            assert!(moved.distance(got) < 2e-3, "{p} moved {along}: {moved} vs {got}");
            assert_eq!(moved_depth > depth, along > 0.0);
        }
        // The ray under the pixel runs along the view and passes through the point.
        let (origin, direction) = unproject_ray(&c, &r, got);
        assert!(direction.distance(forward) < 1e-6, "{direction}");
        assert!(distance_to_line(p, (origin, direction)) < 1e-3, "{p}");
        assert!((p - origin).dot(direction) > 0.0, "the point is ahead of the ray's start");
    }
    // Perspective and orthographic agree at the target's depth, so toggling does not jump.
    let across = c.target.as_dvec3() + 0.7 * c.right().as_dvec3() - 0.4 * c.up().as_dvec3();
    let persp = Camera { orthographic: false, ..c };
    assert!(pixel_of(&c, &r, across).distance(pixel_of(&persp, &r, across)) < 2e-3);
}

#[test]
fn orthographic_drags_follow_the_cursor_in_the_view_plane_and_along_an_axis() {
    let (r, start) = (rect(), selection());
    let c = Camera { orthographic: true, ..camera() };
    let grab = pixel_of(&c, &r, centroid(&start));
    for delta in [Vec2::new(37.0, -21.0), Vec2::new(-250.0, 180.0)] {
        let moved = drag_positions(&c, &r, &start, grab, grab + delta, None);
        let offset = moved[0].1 - start[0].1;
        // Checked against the parallel reference, not against the code's own projection.
        assert!(parallel(&c, &r, centroid(&moved)).distance((grab + delta).as_dvec2()) < 2e-3, "{delta}");
        assert!(offset.dot(c.backward().as_dvec3()).abs() < 1e-6 * offset.length().max(1.0), "in the view plane");
    }
    // Along X the centroid moves to the point of the axis line whose projection is nearest the
    // cursor: the cursor's offset from it on screen is perpendicular to the axis's screen image.
    let now = grab + Vec2::new(45.0, -30.0);
    let moved = centroid(&drag_positions(&c, &r, &start, grab, now, Some(Axis::X)));
    let screen_axis = parallel(&c, &r, moved + DVec3::X) - parallel(&c, &r, moved);
    let gap = now.as_dvec2() - parallel(&c, &r, moved);
    assert!(gap.dot(screen_axis.normalize()).abs() < 1e-2, "{gap} along {screen_axis}");
    assert!((moved - centroid(&start)).x.abs() > 1e-3);
}
