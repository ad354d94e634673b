//! Tests of the cage, curve and legend overlays.

use super::*;

fn nusd<'a>(fixed: &'a [bool], vertex_tension: &'a [f64], edge_tension: &'a [f64]) -> CageControls<'a> {
    CageControls::Nusd { fixed, vertex_tension, edge_tension }
}

#[test]
fn crease_edges_are_drawn_apart_and_grow_with_sharpness() {
    let cage =
        PolyMesh::from_polygons(vec![DVec3::ZERO, DVec3::X, DVec3::new(1.0, 1.0, 0.0), DVec3::Y], &[[0, 1, 2, 3]])
            .unwrap();
    let sharpness = [0.0, 1.0, 2.5, f64::INFINITY];
    let (lines, points) = cage_overlay(
        &cage,
        CageControls::Creases { sharpness: &sharpness, corners: &[0.0, f64::INFINITY, 0.5, 0.0] },
        &CageSelection::default(),
        &DisplayFrame::IDENTITY,
    );
    assert_eq!(lines[0].color, EDGE_NEUTRAL);
    assert!(lines[1..].iter().all(|l| l.color == CREASE));
    assert!(lines[1].width_px < lines[2].width_px && lines[2].width_px < lines[3].width_px);
    // Subdivision cage vertices are rings; a corner is a filled dot in the crease colour,
    // larger when sharper.
    let marks = |v: u32| -> Vec<&PointMark> {
        let at = DisplayFrame::IDENTITY.point(cage.position(VertexId(v)));
        points.iter().filter(|p| (p.position - at).length() < 1e-6 && p.color[..3] != HALO_DARK[..3]).collect()
    };
    for v in [0, 3] {
        assert!(marks(v).iter().all(|p| p.style == PointStyle::Ring), "vertex {v}");
    }
    let (sharp, half) = (marks(1), marks(2));
    assert!(sharp.iter().any(|p| p.style == PointStyle::Filled && p.color == CREASE));
    assert!(half.iter().any(|p| p.style == PointStyle::Filled && p.color == CREASE));
    let size = |m: &[&PointMark]| m.iter().map(|p| p.radius_px).fold(0.0, f32::max);
    assert!(size(&sharp) > size(&half));
}

fn cube() -> PolyMesh {
    let p = (0..8).map(|i| DVec3::new((i & 1) as f64, ((i >> 1) & 1) as f64, ((i >> 2) & 1) as f64)).collect();
    let faces = [[0, 2, 3, 1], [4, 5, 7, 6], [0, 1, 5, 4], [2, 6, 7, 3], [0, 4, 6, 2], [1, 3, 7, 5]];
    PolyMesh::from_polygons(p, &faces).unwrap()
}

#[test]
fn hidden_parts_are_dimmed_and_drawn_first() {
    let cage = cube();
    let controls = nusd(&[], &[], &[]);
    let frame = &DisplayFrame::IDENTITY;
    let seen = CageSelection { face_dots: true, ..Default::default() };
    let (all_lines, all_points) = cage_overlay(&cage, controls, &seen, frame);
    // Vertex 7, its three edges and the three faces round it hidden; one hidden vertex is selected.
    let far = VertexId(7);
    let far_edges: Vec<usize> = cage
        .edges()
        .filter(|&e| {
            let (a, b) = cage.edge_vertices(e);
            a == far || b == far
        })
        .map(|e| e.index())
        .collect();
    let mut hidden = Hidden { vertices: vec![false; 8], edges: vec![false; cage.edge_count()], faces: vec![false; 6] };
    hidden.vertices[7] = true;
    far_edges.iter().for_each(|&e| hidden.edges[e] = true);
    for f in cage.faces().filter(|&f| cage.face_vertices(f).any(|v| v == far)) {
        hidden.faces[f.index()] = true;
    }
    let dimmed =
        CageSelection { face_dots: true, selected_vertices: vec![far], hidden: Some(hidden), ..Default::default() };
    let (lines, points) = cage_overlay(&cage, controls, &dimmed, frame);
    assert_eq!(lines.len(), all_lines.len());
    assert_eq!(points.len(), all_points.len());
    // The three hidden edges come first, at a quarter of the opacity; the rest as before.
    for (k, line) in lines.iter().enumerate() {
        let (a, b) = (line.a, line.b);
        let touches_far = [a, b].iter().any(|p| (p - frame.point(cage.position(far))).length() < 1e-6);
        assert_eq!(k < 3, touches_far, "line {k}");
        let alpha = if touches_far { EDGE_NEUTRAL[3] * HIDDEN_ALPHA } else { EDGE_NEUTRAL[3] };
        assert!((line.color[3] - alpha).abs() < 1e-6, "line {k}: {:?}", line.color);
    }
    // The hidden vertex keeps its selected colour, dimmed, under every plain mark.
    let far_marks: Vec<&PointMark> =
        points.iter().filter(|p| (p.position - frame.point(cage.position(far))).length() < 1e-6).collect();
    assert_eq!(far_marks.len(), 2);
    assert!(far_marks.iter().any(|p| p.color[..3] == SELECTED[..3] && (p.color[3] - HIDDEN_ALPHA).abs() < 1e-6));
    let first_plain = points.iter().position(|p| p.color[3] >= 0.5).unwrap();
    assert!(points[..first_plain].len() >= 2 + 2 * 3, "hidden vertex and face dots drawn first");
}

/// The mark drawn last for a vertex of a single-vertex-styled cage (its own colour, not halo).
fn vertex_mark(points: &[PointMark], at: Vec3) -> PointMark {
    *points.iter().rev().find(|p| p.position == at).unwrap()
}

#[test]
fn fixed_moving_selected_and_hovered_vertices_look_different() {
    let cage = cube();
    let fixed = [true, false, true, false, false, false, false, false];
    let selection = CageSelection {
        selected_vertices: vec![VertexId(2), VertexId(3)],
        hovered_vertex: Some(VertexId(4)),
        ..Default::default()
    };
    let (_, points) = cage_overlay(&cage, nusd(&fixed, &[0.0; 8], &[0.0; 12]), &selection, &DisplayFrame::IDENTITY);
    let at = |v: u32| cage.position(VertexId(v)).as_vec3();
    let (fixed_mark, moving, selected_fixed, selected_moving, hovered) = (
        vertex_mark(&points, at(0)),
        vertex_mark(&points, at(1)),
        vertex_mark(&points, at(2)),
        vertex_mark(&points, at(3)),
        vertex_mark(&points, at(4)),
    );
    assert_eq!(fixed_mark.style, PointStyle::Filled);
    assert_eq!(moving.style, PointStyle::Ring);
    assert_eq!((selected_fixed.style, selected_moving.style), (PointStyle::Filled, PointStyle::Ring));
    let colors = [fixed_mark.color, moving.color, selected_fixed.color, hovered.color];
    for i in 0..colors.len() {
        for j in i + 1..colors.len() {
            assert_ne!(colors[i], colors[j], "{i} and {j}");
        }
    }
    assert_eq!(selected_fixed.color, SELECTED);
    assert!(hovered.radius_px > moving.radius_px);
    // Selected and hovered marks come after all plain ones, hovered last.
    assert_eq!(points.last().unwrap().position, at(4));
    let first_selected = points.iter().position(|p| p.color == SELECTED).unwrap();
    assert!(points[first_selected..].iter().all(|p| [at(2), at(3), at(4)].contains(&p.position)));
}

#[test]
fn tension_widens_edges_and_warms_them_monotonically() {
    let cage = cube();
    let taus = [0.0, 0.5, 1.0, 2.0, 3.0, 4.0, 8.0, 20.0, f64::NAN, -1.0, 0.0, 0.0];
    let (lines, _) = cage_overlay(&cage, nusd(&[], &[], &taus), &CageSelection::default(), &DisplayFrame::IDENTITY);
    assert_eq!(lines.len(), 12);
    let (w, red): (Vec<f32>, Vec<f32>) = lines[..8].iter().map(|l| (l.width_px, l.color[0])).unzip();
    assert!(w.windows(2).all(|p| p[1] >= p[0]) && w[5] > w[0], "{w:?}");
    assert!(red.windows(2).all(|p| p[1] >= p[0]) && red[5] > red[0], "{red:?}");
    // Saturated from τ = 4, and nonsense tensions read as none.
    assert_eq!(lines[5], LineSegment { a: lines[5].a, b: lines[5].b, ..lines[7] });
    assert_eq!((lines[8].width_px, lines[9].width_px), (lines[0].width_px, lines[0].width_px));
    assert_eq!(lines[0].color, EDGE_NEUTRAL);
    assert_eq!(lines[5].color, TENSION_WARM);

    // Vertex tension enlarges the mark and adds a warm ring.
    let (_, calm) =
        cage_overlay(&cage, nusd(&[false; 8], &[0.0; 8], &[]), &CageSelection::default(), &DisplayFrame::IDENTITY);
    let (_, tense) =
        cage_overlay(&cage, nusd(&[false; 8], &[4.0; 8], &[]), &CageSelection::default(), &DisplayFrame::IDENTITY);
    assert!(tense.len() > calm.len());
    assert!(vertex_mark(&tense, Vec3::ZERO).radius_px > vertex_mark(&calm, Vec3::ZERO).radius_px);
    assert!(tense.iter().any(|p| p.color[..3] == TENSION_WARM[..3]));
}

#[test]
fn selected_and_hovered_edges_stand_out_and_come_last() {
    let cage = cube();
    let selection =
        CageSelection { selected_edges: vec![EdgeId(0)], hovered_edge: Some(EdgeId(1)), ..Default::default() };
    let (lines, _) = cage_overlay(&cage, nusd(&[], &[], &[]), &selection, &DisplayFrame::IDENTITY);
    let (plain, selected, hovered) = (lines[0], lines[10], lines[11]);
    assert_eq!(selected.color, SELECTED);
    assert!(selected.width_px > plain.width_px && hovered.width_px > plain.width_px);
    assert!(hovered.color != plain.color && hovered.color != selected.color);
    let (a, b) = cage.edge_vertices(EdgeId(1));
    assert_eq!((hovered.a, hovered.b), (cage.position(a).as_vec3(), cage.position(b).as_vec3()));
}

#[test]
fn selected_and_hovered_faces_light_their_edges_and_mark_their_centres() {
    let cage = cube();
    let (f, g) = (FaceId(0), FaceId(1));
    let selection = CageSelection { selected_faces: vec![f], hovered_face: Some(g), ..Default::default() };
    let controls = nusd(&[false; 8], &[0.0; 8], &[0.0; 12]);
    let (lines, points) = cage_overlay(&cage, controls, &selection, &DisplayFrame::IDENTITY);
    let centre = |f: FaceId| {
        let ring: Vec<DVec3> = cage.face_vertices(f).map(|v| cage.position(v)).collect();
        (ring.iter().copied().sum::<DVec3>() / ring.len() as f64).as_vec3()
    };
    // Every edge of the selected face is drawn selected; no other edge is.
    let face_edge = |face: FaceId, l: &LineSegment| {
        let corners: Vec<Vec3> = cage.face_vertices(face).map(|v| cage.position(v).as_vec3()).collect();
        corners.contains(&l.a) && corners.contains(&l.b)
    };
    for l in &lines {
        assert_eq!(l.color == SELECTED, face_edge(f, l) && !face_edge(g, l), "{l:?}");
    }
    let dot = |f: FaceId| points.iter().rev().find(|p| p.position == centre(f)).copied();
    assert_eq!(dot(f).map(|p| p.color), Some(SELECTED));
    assert!(dot(g).is_some_and(|p| p.color != SELECTED && p.color != EDGE_NEUTRAL), "the hovered face is lit");
    assert!(dot(FaceId(2)).is_none(), "no dots outside face mode");
    let dots = CageSelection { face_dots: true, ..Default::default() };
    let (_, points) = cage_overlay(&cage, nusd(&[false; 8], &[0.0; 8], &[0.0; 12]), &dots, &DisplayFrame::IDENTITY);
    assert_eq!(points.len(), 8 * 2 + 6 * 2, "a halo and a mark per vertex and per face");
}

#[test]
fn wireframe_has_one_segment_per_edge() {
    let cage = cube();
    let lines = wireframe(&cage, [1.0; 4], 1.0, &DisplayFrame::IDENTITY);
    assert_eq!(lines.len(), cage.edge_count());
    let mut keys: Vec<_> = lines
        .iter()
        .map(|l| {
            let (a, b) = (l.a.to_array().map(f32::to_bits), l.b.to_array().map(f32::to_bits));
            if a < b { (a, b) } else { (b, a) }
        })
        .collect();
    keys.sort();
    keys.dedup();
    assert_eq!(keys.len(), 12);
}

#[test]
fn comb_teeth_on_a_circle_have_length_scale_over_radius_and_point_outward() {
    let (radius, n) = (2.5, 40usize);
    let centre = DVec3::new(1.0, -2.0, 0.5);
    // A circle in a tilted plane, spanned by the unit vectors (1, 0, 0) and (0, 0.6, 0.8).
    let circle: Vec<DVec3> = (0..n)
        .map(|i| {
            let t = i as f64 / n as f64 * std::f64::consts::TAU;
            centre + radius * (t.cos() * DVec3::X + t.sin() * DVec3::new(0.0, 0.6, 0.8))
        })
        .collect();
    for inward in [false, true] {
        let comb = CombStyle { scale: 0.7, density: 3, inward, ..Default::default() };
        let teeth = comb_teeth(&circle, true, &comb);
        assert_eq!(teeth.len(), n.div_ceil(3));
        for (p, tip) in &teeth {
            let tooth = *tip - *p;
            assert!((tooth.length() - 0.7 / radius).abs() < 1e-9, "{}", tooth.length());
            let outward = tooth.normalize().dot((*p - centre).normalize());
            assert!((outward - if inward { -1.0 } else { 1.0 }).abs() < 1e-9, "{outward}");
        }
        let lines = polyline_with_comb(&circle, true, &comb, &DisplayFrame::IDENTITY);
        // The curve, the teeth, and a closed envelope.
        assert_eq!(lines.len(), n + 2 * teeth.len());
    }
}

#[test]
fn open_curves_comb_to_their_last_point_and_straight_ones_have_flat_teeth() {
    let line: Vec<DVec3> = (0..7).map(|i| DVec3::new(i as f64, 0.0, 0.0)).collect();
    let comb = CombStyle { density: 4, ..Default::default() };
    let teeth = comb_teeth(&line, false, &comb);
    assert_eq!(teeth.iter().map(|t| t.0.x).collect::<Vec<_>>(), [0.0, 4.0, 6.0]);
    assert!(teeth.iter().all(|(p, tip)| p == tip));
    assert_eq!(polyline_with_comb(&line, false, &comb, &DisplayFrame::IDENTITY).len(), 6 + 3 + 2);
    assert_eq!(polyline_with_comb(&line[..2], false, &comb, &DisplayFrame::IDENTITY).len(), 1);
    assert!(polyline_with_comb(&[], true, &comb, &DisplayFrame::IDENTITY).is_empty());
}

#[test]
fn legend_numbers_are_short_and_keep_their_digits() {
    let cases = [
        (0.0123, "0.0123"),
        (-4.5e-5, "-4.5e-5"),
        (12.3, "12.3"),
        (12.34, "12.3"),
        (0.5, "0.5"),
        (1.0, "1"),
        (-2.0, "-2"),
        (100.0, "100"),
        (1234.0, "1230"),
        (0.001, "0.001"),
        (0.00099, "9.9e-4"),
        (9.996, "10"),
        (99999.0, "1e5"),
        (123456.0, "1.23e5"),
        (-0.0, "0"),
        (0.0, "0"),
        (f64::NAN, "nan"),
        (f64::NEG_INFINITY, "-inf"),
    ];
    for (x, want) in cases {
        assert_eq!(format_number(x, 3), want, "{x}");
    }
    assert_eq!(format_number(std::f64::consts::PI, 5), "3.1416");
    assert_eq!(format_number(std::f64::consts::PI, 0), "3");
}
