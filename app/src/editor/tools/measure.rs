//! D: the measure tool. Each click takes a point: a cage vertex under the cursor (exactly), else
//! the nearest point of a cage edge under it, else the surface where the cursor's ray meets it.
//! Two points give their distance and its components, three the angle at the middle one (a
//! fourth click starts again). A click that lands on the surface also shows the radii of
//! curvature there (the principal radii, 1/κ, at the nearest surface vertex) with both
//! principal directions drawn. The numbers are in the header; the measurement stays on screen
//! until Esc or a right click clears it, and Ctrl+C copies the numbers. Nothing of the document
//! changes, so the tool leaves no undo step.

use crate::editor::interaction::{self, ViewportRect};
use crate::editor::shortcuts::take_plain;
use crate::editor::state::EditorState;
use crate::editor::tools::tool::{End, Flow, Pointer, Tool};
use egui::{Color32, Key, Pos2, Stroke};
use taut_core::curvature::vertex_curvature;
use taut_core::{DVec3, PolyMesh};

/// The principal curvatures at a surface point: radii (1/κ, signed; infinite where flat) and
/// the unit directions they bend along.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Radii {
    pub at: DVec3,
    pub min_radius: f64,
    pub max_radius: f64,
    pub min_direction: DVec3,
    pub max_direction: DVec3,
}

/// The principal radii of `mesh` at its vertex nearest `point` (model coordinates).
pub fn principal_radii(mesh: &PolyMesh, point: DVec3) -> Option<Radii> {
    let nearest = mesh.vertices().min_by(|&a, &b| {
        (mesh.position(a) - point).length_squared().total_cmp(&(mesh.position(b) - point).length_squared())
    })?;
    let c = vertex_curvature(mesh);
    let i = nearest.index();
    let radius = |k: f64| if k == 0.0 { f64::INFINITY } else { 1.0 / k };
    Some(Radii {
        at: mesh.position(nearest),
        min_radius: radius(c.min_principal[i]),
        max_radius: radius(c.max_principal[i]),
        min_direction: c.min_direction[i],
        max_direction: c.max_direction[i],
    })
}

/// The measure tool's points and what the last surface click found.
#[derive(Clone, Debug, Default)]
pub struct Measure {
    /// The points taken, in model coordinates (at most three).
    pub points: Vec<DVec3>,
    /// The curvature where the last click met the surface.
    pub radii: Option<Radii>,
}

/// Starts measuring.
pub(crate) fn start(_editor: &mut EditorState, _mouse: Option<glam::Vec2>) -> Option<Box<dyn Tool>> {
    Some(Box::new(Measure::default()))
}

impl Measure {
    /// Adds a point (a fourth starts again).
    pub fn take(&mut self, point: DVec3, radii: Option<Radii>) {
        if self.points.len() == 3 {
            self.points.clear();
        }
        self.points.push(point);
        self.radii = radii;
    }

    /// The numbers: distance and components for two points, the angle at the middle one for
    /// three, the radii of curvature of a surface point.
    /// Lengths carry the document's `unit`.
    pub fn numbers(&self, unit: taut_core::document::LengthUnit) -> String {
        let n = |x: f64| unit.length(x);
        let mut parts = Vec::new();
        match self.points.as_slice() {
            [] => parts.push("click a vertex, an edge or the surface".to_string()),
            [p] => parts.push(format!("point {} {} {}", n(p.x), n(p.y), n(p.z))),
            [a, b] => {
                let d = *b - *a;
                parts.push(format!("distance {}  ΔX {}  ΔY {}  ΔZ {}", n(d.length()), n(d.x), n(d.y), n(d.z)));
            }
            [a, b, c, ..] => {
                let (u, v) = (*a - *b, *c - *b);
                let angle = u.cross(v).length().atan2(u.dot(v)).to_degrees();
                parts.push(format!("angle {angle:.3}°  sides {} {}", n(u.length()), n(v.length())));
            }
        }
        if let Some(r) = self.radii {
            parts.push(format!("radii of curvature {} and {}", n(r.min_radius), n(r.max_radius)));
        }
        parts.join("  ·  ")
    }
}

impl EditorState {
    /// The point a measuring click at `mouse` takes: a cage vertex, else the nearest point of a
    /// cage edge, else the surface (with its radii); model coordinates.
    fn measured_point(&self, view: &ViewportRect, mouse: glam::Vec2) -> Option<(DVec3, Option<Radii>)> {
        let cage = &self.document.doc().cage;
        let display = self.display_cage();
        if let Some(v) = self.pick_cage_vertex(view, &display, mouse, 8.0) {
            return Some((cage.position(v), None));
        }
        let frame = self.view.display_frame;
        let (origin, direction) = interaction::unproject_ray(&self.view.camera, view, mouse);
        if let Some(e) = self.pick_cage_edge(view, &display, mouse, 8.0) {
            // The point of the edge nearest the cursor's ray.
            let (a, b) = display.edge_vertices(e);
            let (p, q) = (display.position(a), display.position(b));
            let (u, w) = (q - p, p - origin);
            let (uu, ud, ww) = (u.dot(u), u.dot(direction), 1.0);
            let den = uu * ww - ud * ud;
            let s = if den > 1e-300 { ((ud * direction.dot(w)) - ww * u.dot(w)) / den } else { 0.5 };
            return Some((frame.to_model(p + s.clamp(0.0, 1.0) * u), None));
        }
        let point = self.surface_under(view, mouse)?;
        Some((point, principal_radii(self.surface_mesh()?, point)))
    }
}

impl Tool for Measure {
    /// Esc clears the measurement and ends the tool; Ctrl+C copies the numbers.
    fn keys(&mut self, editor: &mut EditorState, ctx: &egui::Context) -> Flow {
        let copy = ctx.input_mut(|i| {
            i.events.iter().any(|e| matches!(e, egui::Event::Copy)) || i.consume_key(egui::Modifiers::COMMAND, Key::C)
        });
        if copy {
            ctx.copy_text(self.numbers(editor.document.doc().units));
        }
        if ctx.input_mut(|i| take_plain(i, Key::Escape)) { Flow::Cancel } else { Flow::Continue }
    }

    fn pointer(&mut self, editor: &mut EditorState, pointer: &Pointer) -> Flow {
        if pointer.clicked()
            && let Some(m) = pointer.mouse
        {
            match editor.measured_point(&pointer.view, m) {
                Some((point, radii)) => self.take(point, radii),
                None => editor.notify("nothing to measure there: click a cage vertex, an edge or the surface", true),
            }
        }
        if pointer.right_clicked() { Flow::Cancel } else { Flow::Continue }
    }

    /// The points, the lines between them, and the principal directions.
    fn overlay(&self, editor: &EditorState, painter: &egui::Painter, view: &ViewportRect) {
        let frame = editor.view.display_frame;
        let px = |p: DVec3| {
            interaction::project(&editor.view.camera, view, frame.to_display_f64(p)).map(|(q, _)| Pos2::new(q.x, q.y))
        };
        let colour = Color32::from_rgb(255, 220, 60);
        let screen: Vec<Pos2> = self.points.iter().filter_map(|&p| px(p)).collect();
        for w in screen.windows(2) {
            painter.line_segment([w[0], w[1]], Stroke::new(2.0, colour));
        }
        for &p in &screen {
            painter.circle_filled(p, 4.5, colour);
        }
        if let Some(r) = self.radii {
            let size = 0.08 * editor.document.doc().cage.bounding_diagonal();
            for (d, c) in
                [(r.min_direction, Color32::from_rgb(80, 170, 255)), (r.max_direction, Color32::from_rgb(255, 90, 90))]
            {
                if let (Some(a), Some(b)) = (px(r.at - d * size), px(r.at + d * size)) {
                    painter.line_segment([a, b], Stroke::new(2.0, c));
                }
            }
        }
    }

    fn readout(&self, editor: &EditorState) -> Option<String> {
        Some(self.numbers(editor.document.doc().units))
    }

    fn status(&self, _editor: &EditorState) -> String {
        "measure: click points (two: distance, three: angle; on the surface: radii of curvature), \
         Ctrl+C copies, Esc clears"
            .into()
    }

    fn end(self: Box<Self>, _editor: &mut EditorState, _end: End) {}

    fn navigates(&self) -> bool {
        true
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::editor::defects_mode_tests::click;
    use crate::editor::gizmo_tests::pixel_of;
    use crate::editor::panel_tests::{cube_editor, frames, settle};
    use egui_kittest::kittest::Queryable;
    use taut_core::VertexId;

    fn measured<'a>(h: &'a egui_kittest::Harness<'static, crate::editor::panel_tests::App>) -> &'a Measure {
        h.state().ui.tool.get::<Measure>().expect("measuring")
    }

    #[test]
    fn two_vertices_give_their_distance_and_three_the_angle_exactly_and_esc_clears() {
        let mut h = cube_editor();
        settle(&mut h);
        h.key_press(Key::D);
        frames(&mut h);
        let cage = h.state().editor.document.doc().cage.clone();
        let [a, b] = [VertexId(7), VertexId(6)].map(|v| cage.position(v));
        // A third corner of the top face (seen from above), next to b: a square corner at b.
        let c = cage
            .positions()
            .iter()
            .copied()
            .find(|&p| p.z == b.z && (p - b).length() == 1.0 && p != a)
            .expect("the top face's corner");
        // Each vertex is taken exactly, from its pixel.
        for (i, p) in [a, b, c].into_iter().enumerate() {
            let at = pixel_of(&h, p);
            click(&mut h, at);
            assert_eq!(measured(&h).points[i], p, "point {i} is the vertex itself");
            if i == 1 {
                let d = b - a;
                let f = |x: f64| format!("{:.4} mm", if x == 0.0 { 0.0 } else { x });
                let text = format!("distance {}  ΔX {}  ΔY {}  ΔZ {}", f(d.length()), f(d.x), f(d.y), f(d.z));
                assert_eq!(measured(&h).numbers(taut_core::document::LengthUnit::Millimetre), text);
                frames(&mut h);
                h.get_by_label(&text);
            }
        }
        let (u, v) = (a - b, c - b);
        let angle = u.cross(v).length().atan2(u.dot(v)).to_degrees();
        assert!(
            measured(&h).numbers(Default::default()).starts_with(&format!("angle {angle:.3}°")),
            "{}",
            measured(&h).numbers(Default::default())
        );
        assert!((angle - 90.0).abs() < 1e-9, "a cube's corner is square: {angle}");
        h.key_press(Key::Escape);
        frames(&mut h);
        assert!(h.state().ui.tool.get::<Measure>().is_none(), "Esc clears");
        assert!(!h.state().editor.document.can_undo(), "measuring changes nothing");
    }

    #[test]
    fn the_radii_of_curvature_of_a_sphere_are_its_radius() {
        // A UV sphere of radius 2: 48 bands by 96 segments.
        let (r, rings, segments) = (2.0, 48u32, 96u32);
        let mut points = vec![DVec3::new(0.0, 0.0, r)];
        for i in 1..rings {
            let t = std::f64::consts::PI * f64::from(i) / f64::from(rings);
            for j in 0..segments {
                let p = std::f64::consts::TAU * f64::from(j) / f64::from(segments);
                points.push(r * DVec3::new(t.sin() * p.cos(), t.sin() * p.sin(), t.cos()));
            }
        }
        points.push(DVec3::new(0.0, 0.0, -r));
        let at = |i: u32, j: u32| 1 + (i - 1) * segments + j % segments;
        let south = points.len() as u32 - 1;
        let mut faces: Vec<Vec<u32>> = Vec::new();
        for j in 0..segments {
            faces.push(vec![0, at(1, j), at(1, j + 1)]);
            faces.push(vec![south, at(rings - 1, j + 1), at(rings - 1, j)]);
        }
        for i in 1..rings - 1 {
            for j in 0..segments {
                faces.push(vec![at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)]);
            }
        }
        let sphere = PolyMesh::from_polygons(points, &faces).unwrap();
        let probe = r * DVec3::new(0.3, -0.5, 0.2).normalize();
        let radii = principal_radii(&sphere, probe).unwrap();
        for radius in [radii.min_radius, radii.max_radius] {
            assert!((radius.abs() - r).abs() < 0.02 * r, "radius {radius} on a sphere of radius {r}");
        }
        let normal = radii.at.normalize();
        for d in [radii.min_direction, radii.max_direction] {
            assert!(d.dot(normal).abs() < 1e-6 && (d.length() - 1.0).abs() < 1e-9, "a unit tangent");
        }
        assert!(radii.min_direction.dot(radii.max_direction).abs() < 1e-6, "at right angles");
    }
}
