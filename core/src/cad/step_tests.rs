use std::collections::{BTreeMap, HashMap};

use super::*;
use crate::cad::brep::{BrepEdge, BrepFace, BrepShell};

const HEADER: StepHeader<'static> = StepHeader { name: "part", timestamp: "2026-12-03T10:00:00", author: "Designer" };

/// The clamped Bézier knot vector of `degree`.
fn bezier_knots(degree: usize) -> (Vec<f64>, Vec<usize>) {
    (vec![0.0, 1.0], vec![degree + 1, degree + 1])
}

fn line(start: usize, end: usize, vertices: &[DVec3]) -> BrepEdge {
    let (knots, multiplicities) = bezier_knots(1);
    let points = vec![vertices[start], vertices[end]];
    BrepEdge { start, end, curve: BSplineCurve { degree: 1, knots, multiplicities, points } }
}

fn surface(degree_u: usize, degree_v: usize, points: Vec<Vec<DVec3>>) -> BSplineSurface {
    let (knots_u, multiplicities_u) = bezier_knots(degree_u);
    let (knots_v, multiplicities_v) = bezier_knots(degree_v);
    BSplineSurface { degree_u, degree_v, knots_u, multiplicities_u, knots_v, multiplicities_v, points }
}

/// An axis-aligned box from `min` to `max` as 6 bilinear faces on 12 shared edges and 8
/// vertices, normals outward. Every other face has its u and v swapped, so its surface normal
/// points inward and `same_sense` is false.
fn cuboid(min: DVec3, max: DVec3) -> BrepModel {
    let vertices: Vec<DVec3> = (0..8)
        .map(|v| {
            let pick = |bit: usize, lo: f64, hi: f64| if v & bit == 0 { lo } else { hi };
            DVec3::new(pick(1, min.x, max.x), pick(2, min.y, max.y), pick(4, min.z, max.z))
        })
        .collect();
    // Corners counter-clockwise seen from outside.
    let quads = [[0, 2, 3, 1], [4, 5, 7, 6], [0, 1, 5, 4], [2, 6, 7, 3], [0, 4, 6, 2], [1, 3, 7, 5]];
    let mut edges = Vec::new();
    let mut edge_of = HashMap::new();
    let mut faces = Vec::new();
    for (f, quad) in quads.iter().enumerate() {
        let outer = (0..4)
            .map(|k| {
                let (a, b) = (quad[k], quad[(k + 1) % 4]);
                let e = *edge_of.entry((a.min(b), a.max(b))).or_insert_with(|| {
                    edges.push(line(a.min(b), a.max(b), &vertices));
                    edges.len() - 1
                });
                (e, edges[e].start == a)
            })
            .collect();
        let [c0, c1, c2, c3] = quad.map(|v| vertices[v]);
        let same_sense = f % 2 == 0;
        let points = if same_sense { vec![vec![c0, c3], vec![c1, c2]] } else { vec![vec![c0, c1], vec![c3, c2]] };
        faces.push(BrepFace { surface: surface(1, 1, points), outer, outer_uv: Vec::new(), same_sense });
    }
    BrepModel { vertices, edges, faces, shells: vec![BrepShell { faces: (0..6).collect(), closed: true }] }
}

/// One bicubic Bézier face, gently curved, bounded by its 4 boundary curves: an open shell.
fn bezier_patch() -> BrepModel {
    let grid: Vec<Vec<DVec3>> = (0..4)
        .map(|i| {
            (0..4)
                .map(|j| {
                    let (x, y) = (i as f64 * 10.0 / 3.0, j as f64 * 10.0 / 3.0);
                    DVec3::new(x, y, 0.1 * x * y - 0.25 * x + 1e-7)
                })
                .collect()
        })
        .collect();
    let cubic = |points: Vec<DVec3>, start: usize, end: usize| {
        let (knots, multiplicities) = bezier_knots(3);
        BrepEdge { start, end, curve: BSplineCurve { degree: 3, knots, multiplicities, points } }
    };
    let column = |i: usize| grid[i].clone();
    let row = |j: usize| grid.iter().map(|c| c[j]).collect::<Vec<_>>();
    // Vertices: the corners (u, v) = (0,0), (1,0), (1,1), (0,1).
    let vertices = vec![grid[0][0], grid[3][0], grid[3][3], grid[0][3]];
    let edges = vec![cubic(row(0), 0, 1), cubic(column(3), 1, 2), cubic(row(3), 3, 2), cubic(column(0), 0, 3)];
    let outer = vec![(0, true), (1, true), (2, false), (3, false)];
    let face = BrepFace { surface: surface(3, 3, grid), outer, outer_uv: Vec::new(), same_sense: true };
    BrepModel { vertices, edges, faces: vec![face], shells: vec![BrepShell { faces: vec![0], closed: false }] }
}

/// The model's DATA section, one `(id, instance text)` per entity.
fn entities(text: &str) -> Vec<(usize, String)> {
    let data = text.split_once("\nDATA;\n").unwrap().1.split_once("ENDSEC;").unwrap().0;
    data.split(";\n")
        .filter(|s| !s.trim().is_empty())
        .map(|s| {
            let (id, body) = s.trim().strip_prefix('#').unwrap().split_once('=').unwrap();
            (id.parse().unwrap(), body.to_string())
        })
        .collect()
}

/// How many instances of each entity type (complex instances counted under each part).
fn entity_counts(text: &str) -> BTreeMap<String, usize> {
    let mut counts = BTreeMap::new();
    for (_, body) in entities(text) {
        let names: Vec<&str> = match body.strip_prefix('(') {
            // A complex instance: the names of its parts, which sit at depth 1.
            Some(_) => {
                let mut depth = 0;
                let mut names = Vec::new();
                let mut start = None;
                for (k, c) in body.char_indices() {
                    match c {
                        'A'..='Z' | '_' if depth == 1 => start = start.or(Some(k)),
                        '(' => {
                            if let Some(s) = start.take() {
                                names.push(&body[s..k]);
                            }
                            depth += 1;
                        }
                        ')' => depth -= 1,
                        _ => start = None,
                    }
                }
                names
            }
            None => vec![body.split_once('(').unwrap().0],
        };
        for name in names {
            *counts.entry(name.to_string()).or_default() += 1;
        }
    }
    counts
}

fn count(text: &str, name: &str) -> usize {
    entity_counts(text).get(name).copied().unwrap_or(0)
}

#[test]
fn header_and_entity_counts_of_an_open_bezier_face() {
    let text = step_text(&bezier_patch(), LengthUnit::Millimetre, 1e-6, &HEADER).unwrap();
    let version = env!("CARGO_PKG_VERSION");
    let head: Vec<&str> = text.lines().take(7).collect();
    assert_eq!(
        head,
        [
            "ISO-10303-21;",
            "HEADER;",
            "FILE_DESCRIPTION(('Taut surface'),'2;1');",
            &format!("FILE_NAME('part','2026-12-03T10:00:00',('Designer'),(''),'Taut {version}','Taut','');"),
            "FILE_SCHEMA(('AUTOMOTIVE_DESIGN { 1 0 10303 214 1 1 1 1 }'));",
            "ENDSEC;",
            "DATA;",
        ]
    );
    assert!(text.ends_with("ENDSEC;\nEND-ISO-10303-21;\n"));
    let expected: BTreeMap<String, usize> = [
        // 4 vertices + 4 curves × 4 + 16 surface points + the origin.
        ("CARTESIAN_POINT", 37),
        ("VERTEX_POINT", 4),
        ("B_SPLINE_CURVE_WITH_KNOTS", 4),
        ("EDGE_CURVE", 4),
        ("B_SPLINE_SURFACE_WITH_KNOTS", 1),
        ("ORIENTED_EDGE", 4),
        ("EDGE_LOOP", 1),
        ("FACE_OUTER_BOUND", 1),
        ("ADVANCED_FACE", 1),
        ("OPEN_SHELL", 1),
        ("SHELL_BASED_SURFACE_MODEL", 1),
        ("MANIFOLD_SURFACE_SHAPE_REPRESENTATION", 1),
        ("DIRECTION", 2),
        ("AXIS2_PLACEMENT_3D", 1),
        ("LENGTH_UNIT", 1),
        ("NAMED_UNIT", 3),
        ("SI_UNIT", 3),
        ("PLANE_ANGLE_UNIT", 1),
        ("SOLID_ANGLE_UNIT", 1),
        ("UNCERTAINTY_MEASURE_WITH_UNIT", 1),
        ("GEOMETRIC_REPRESENTATION_CONTEXT", 1),
        ("GLOBAL_UNCERTAINTY_ASSIGNED_CONTEXT", 1),
        ("GLOBAL_UNIT_ASSIGNED_CONTEXT", 1),
        ("REPRESENTATION_CONTEXT", 1),
        ("APPLICATION_CONTEXT", 1),
        ("APPLICATION_PROTOCOL_DEFINITION", 1),
        ("PRODUCT_CONTEXT", 1),
        ("PRODUCT", 1),
        ("PRODUCT_DEFINITION_FORMATION", 1),
        ("PRODUCT_DEFINITION_CONTEXT", 1),
        ("PRODUCT_DEFINITION", 1),
        ("PRODUCT_DEFINITION_SHAPE", 1),
        ("SHAPE_DEFINITION_REPRESENTATION", 1),
        ("PRODUCT_RELATED_PRODUCT_CATEGORY", 1),
    ]
    .into_iter()
    .map(|(name, n)| (name.to_string(), n))
    .collect();
    assert_eq!(entity_counts(&text), expected);
    assert!(text.contains("ORIENTED_EDGE('',*,*,#"));
    assert!(text.contains("FACE_OUTER_BOUND('',#"));
    assert!(text.contains("'distance_accuracy_value','confusion accuracy')"));
    assert!(text.contains("UNCERTAINTY_MEASURE_WITH_UNIT(LENGTH_MEASURE(1.E-6)"), "{text}");
    assert!(text.contains("PRODUCT('part','part','',(#"));
}

#[test]
fn closed_cube_is_one_solid() {
    let cube = cuboid(DVec3::ZERO, DVec3::splat(10.0));
    let text = step_text(&cube, LengthUnit::Millimetre, 1e-6, &HEADER).unwrap();
    let counts = entity_counts(&text);
    for (name, n) in [
        // 8 vertices + 12 lines × 2 + 6 faces × 4 + the origin.
        ("CARTESIAN_POINT", 57),
        ("VERTEX_POINT", 8),
        ("EDGE_CURVE", 12),
        ("B_SPLINE_CURVE_WITH_KNOTS", 12),
        ("ORIENTED_EDGE", 24),
        ("EDGE_LOOP", 6),
        ("FACE_OUTER_BOUND", 6),
        ("ADVANCED_FACE", 6),
        ("B_SPLINE_SURFACE_WITH_KNOTS", 6),
        ("CLOSED_SHELL", 1),
        ("MANIFOLD_SOLID_BREP", 1),
        ("ADVANCED_BREP_SHAPE_REPRESENTATION", 1),
        ("OPEN_SHELL", 0),
        ("SHELL_BASED_SURFACE_MODEL", 0),
        ("MANIFOLD_SURFACE_SHAPE_REPRESENTATION", 0),
    ] {
        assert_eq!(counts.get(name).copied().unwrap_or(0), n, "{name}");
    }
    let faces: Vec<String> =
        entities(&text).into_iter().map(|(_, body)| body).filter(|b| b.starts_with("ADVANCED_FACE")).collect();
    assert_eq!(faces.iter().filter(|b| b.ends_with(",.T.)")).count(), 3);
    assert_eq!(faces.iter().filter(|b| b.ends_with(",.F.)")).count(), 3);
}

#[test]
fn two_closed_shells_are_two_solids_and_a_mix_is_a_surface_model() {
    let mut model = cuboid(DVec3::ZERO, DVec3::ONE);
    let other = cuboid(DVec3::splat(2.0), DVec3::splat(3.0));
    let (v, e, f) = (model.vertices.len(), model.edges.len(), model.faces.len());
    model.vertices.extend(other.vertices);
    model.edges.extend(other.edges.into_iter().map(|edge| BrepEdge {
        start: edge.start + v,
        end: edge.end + v,
        ..edge
    }));
    model.faces.extend(
        other.faces.into_iter().map(|face| BrepFace {
            outer: face.outer.iter().map(|&(edge, sense)| (edge + e, sense)).collect(),
            ..face
        }),
    );
    model.shells.push(BrepShell { faces: (f..f + 6).collect(), closed: true });
    let text = step_text(&model, LengthUnit::Millimetre, 1e-6, &HEADER).unwrap();
    assert_eq!(count(&text, "MANIFOLD_SOLID_BREP"), 2);
    assert_eq!(count(&text, "CLOSED_SHELL"), 2);

    model.shells[1].closed = false;
    let text = step_text(&model, LengthUnit::Millimetre, 1e-6, &HEADER).unwrap();
    assert_eq!(count(&text, "MANIFOLD_SOLID_BREP"), 0);
    assert_eq!(count(&text, "CLOSED_SHELL"), 1);
    assert_eq!(count(&text, "OPEN_SHELL"), 1);
    assert_eq!(count(&text, "SHELL_BASED_SURFACE_MODEL"), 1);
    assert_eq!(count(&text, "MANIFOLD_SURFACE_SHAPE_REPRESENTATION"), 1);
}

#[test]
fn every_unit_is_written() {
    let cube = cuboid(DVec3::ZERO, DVec3::ONE);
    let text = |unit| step_text(&cube, unit, 1e-6, &HEADER).unwrap();
    let millimetre = "( LENGTH_UNIT() NAMED_UNIT(*) SI_UNIT(.MILLI.,.METRE.) )";
    assert!(text(LengthUnit::Millimetre).contains(millimetre));
    assert!(text(LengthUnit::Centimetre).contains("( LENGTH_UNIT() NAMED_UNIT(*) SI_UNIT(.CENTI.,.METRE.) )"));
    assert!(text(LengthUnit::Metre).contains("( LENGTH_UNIT() NAMED_UNIT(*) SI_UNIT($,.METRE.) )"));
    let inch = text(LengthUnit::Inch);
    assert!(inch.contains(millimetre));
    assert!(inch.contains("LENGTH_MEASURE_WITH_UNIT(LENGTH_MEASURE(25.4),#"));
    assert!(inch.contains("DIMENSIONAL_EXPONENTS(1.,0.,0.,0.,0.,0.,0.)"));
    assert!(inch.contains("( CONVERSION_BASED_UNIT('INCH',#"));
    assert_eq!(count(&inch, "LENGTH_UNIT"), 2);
    for unit in [LengthUnit::Millimetre, LengthUnit::Centimetre, LengthUnit::Metre, LengthUnit::Inch] {
        let text = text(unit);
        assert!(text.contains("( NAMED_UNIT(*) PLANE_ANGLE_UNIT() SI_UNIT($,.RADIAN.) )"));
        assert!(text.contains("( NAMED_UNIT(*) SI_UNIT($,.STERADIAN.) SOLID_ANGLE_UNIT() )"));
        assert_eq!(count(&text, "GLOBAL_UNIT_ASSIGNED_CONTEXT"), 1);
    }
}

#[test]
fn entities_are_numbered_in_order_and_refer_only_backwards() {
    for model in [bezier_patch(), cuboid(DVec3::ZERO, DVec3::ONE)] {
        let text = step_text(&model, LengthUnit::Inch, 1e-6, &HEADER).unwrap();
        assert_eq!(text, step_text(&model, LengthUnit::Inch, 1e-6, &HEADER).unwrap());
        for (k, (id, body)) in entities(&text).into_iter().enumerate() {
            assert_eq!(id, k + 1);
            // Outside strings (`'Context #1'` is no reference).
            let code: String = body.split('\'').step_by(2).collect();
            for reference in code.split('#').skip(1) {
                let digits: String = reference.chars().take_while(char::is_ascii_digit).collect();
                let target: usize = digits.parse().unwrap();
                assert!(target < id, "#{id} refers forward to #{target}");
            }
        }
    }
}

/// Reals in Part 21 form read back bit for bit.
#[test]
fn reals_round_trip_bit_for_bit() {
    let mut values = vec![
        0.0,
        -0.0,
        1.0,
        -1.0,
        0.5,
        0.1,
        25.4,
        1e-7,
        -2.5e-7,
        1e22,
        1e16,
        123456789012345680.0,
        f64::MAX,
        f64::MIN_POSITIVE,
        5e-324,
        f64::EPSILON,
        1.0 / 3.0,
        -1e300,
    ];
    let mut state = 0x2545_f491_4f6c_dd1d_u64;
    while values.len() < 5000 {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        let x = f64::from_bits(state);
        if x.is_finite() {
            values.push(x);
        }
    }
    for x in values {
        let text = Real(x).to_string();
        let (mantissa, exponent) = text.split_once('E').map_or((&*text, None), |(m, e)| (m, Some(e)));
        let (whole, _fraction) = mantissa.split_once('.').expect("a decimal point");
        let whole = whole.strip_prefix('-').unwrap_or(whole);
        assert!(!whole.is_empty() && whole.chars().all(|c| c.is_ascii_digit()), "{text}");
        if let Some(exponent) = exponent {
            let digits = exponent.strip_prefix('-').unwrap_or(exponent);
            assert!(!digits.is_empty() && digits.chars().all(|c| c.is_ascii_digit()), "{text}");
        }
        assert_eq!(text.parse::<f64>().unwrap().to_bits(), x.to_bits(), "{text}");
    }
    assert_eq!(Real(1.0).to_string(), "1.");
    assert_eq!(Real(0.5).to_string(), "0.5");
}

/// The control points of the file's surface are the model's, bit for bit.
#[test]
fn surface_points_read_back_exactly() {
    let model = bezier_patch();
    let text = step_text(&model, LengthUnit::Millimetre, 1e-6, &HEADER).unwrap();
    let entities: HashMap<usize, String> = entities(&text).into_iter().collect();
    let point = |id: usize| {
        let body = &entities[&id];
        let inner = body.strip_prefix("CARTESIAN_POINT('',(").unwrap().strip_suffix("))").unwrap();
        let c: Vec<f64> = inner.split(',').map(|x| x.parse().unwrap()).collect();
        DVec3::new(c[0], c[1], c[2])
    };
    let surface = entities.values().find(|b| b.starts_with("B_SPLINE_SURFACE_WITH_KNOTS")).unwrap();
    let grid = surface.split_once(",3,3,(").unwrap().1.split_once("),.UNSPECIFIED.").unwrap().0;
    let rows: Vec<Vec<DVec3>> = grid
        .split(')')
        .map(|row| row.trim_matches(|c: char| c == ',' || c == '(' || c.is_whitespace()))
        .filter(|row| !row.is_empty())
        .map(|row| {
            let ids = row.split(',').map(|r| r.trim_start_matches('#').parse().unwrap());
            ids.map(point).collect()
        })
        .collect();
    assert_eq!(rows, model.faces[0].surface.points);
}

#[test]
fn strings_are_escaped() {
    let header = StepHeader { name: "Bob's wing \\ Ü 🙂", timestamp: "2026-12-03T10:00:00", author: "" };
    let text = step_text(&bezier_patch(), LengthUnit::Millimetre, 1e-6, &header).unwrap();
    let name = r"'Bob''s wing \\ \X2\00DC\X0\ \X2\D83DDE42\X0\'";
    assert!(text.contains(&format!("FILE_NAME({name},")), "{text}");
    assert!(text.contains(&format!("PRODUCT({name},{name},")));
    assert!(text.is_ascii());
}

#[test]
fn bad_input_is_refused_with_a_message() {
    let error = |model: &BrepModel, tolerance: f64| match step_text(model, LengthUnit::Millimetre, tolerance, &HEADER) {
        Err(Error::Input(message)) => message,
        other => panic!("expected an input error, got {other:?}"),
    };
    let good = bezier_patch();
    assert!(error(&BrepModel::default(), 1e-6).contains("empty"));
    assert!(error(&good, 0.0).contains("tolerance"));
    assert!(error(&good, f64::NAN).contains("tolerance"));

    let mut model = good.clone();
    model.vertices[2].y = f64::INFINITY;
    assert!(error(&model, 1e-6).contains("vertex 2"));

    let mut model = good.clone();
    model.edges[1].curve.points[2].z = f64::NAN;
    assert!(error(&model, 1e-6).contains("edge 1: control point 2"));

    let mut model = good.clone();
    model.faces[0].surface.knots_v[1] = f64::NAN;
    assert!(error(&model, 1e-6).contains("face 0: v knot 1 is not finite"));

    let mut model = good.clone();
    model.faces[0].outer[2].0 = 9;
    let message = error(&model, 1e-6);
    assert!(message.contains("edge 9"), "{message}");

    let mut model = good.clone();
    model.edges[0].curve.multiplicities = vec![4, 3];
    let message = error(&model, 1e-6);
    assert!(message.contains("edge 0: multiplicities sum to 7"), "{message}");

    let mut model = good.clone();
    model.faces[0].surface.multiplicities_u = vec![4, 1, 4];
    assert!(error(&model, 1e-6).contains("face 0: u 2 knots with 3 multiplicities"));

    let mut model = good.clone();
    model.faces[0].outer[1].1 = false;
    assert!(error(&model, 1e-6).contains("does not join"));

    let mut model = good.clone();
    model.shells[0].faces = vec![3];
    assert!(error(&model, 1e-6).contains("shell 0 refers to face 3"));

    let mut model = good;
    model.faces[0].surface.points[1].pop();
    assert!(error(&model, 1e-6).contains("row 1 has 3 points"));
}
