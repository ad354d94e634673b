//! The pivot of rotate and scale (and where the gizmo sits), and the 3D cursor, as in Blender:
//! the median centre of the selected vertices, the centre of their bounding box, the 3D cursor,
//! or the active vertex (the one picked last). Shift+S cycles them; the toolbar has a combo.
//!
//! The 3D cursor is a point of the editor state (not of the document: it is not saved). A
//! Shift+right-click places it where the ray under the mouse first meets the smoothed surface
//! (or the cage where there is no surface yet), by a Möller–Trumbore test against every
//! triangle of a fan triangulation of the faces; a ray that misses everything puts it in the
//! plane facing the camera through where it was. The test is linear in the faces, fine for a
//! click (a 20 000-face surface takes well under a frame) but not something to run every frame.

use crate::editor::interaction::{self, ViewportRect};
use crate::editor::state::EditorState;
use glam::Vec2;
use taut_core::{DVec3, PolyMesh, VertexId};

/// What rotate, scale and the gizmo turn about.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Pivot {
    /// The mean of the selected vertices.
    #[default]
    Median,
    /// The centre of the selected vertices' bounding box.
    BoundingBox,
    /// The 3D cursor.
    Cursor,
    /// The vertex picked last.
    Active,
}

impl Pivot {
    pub const ALL: [Pivot; 4] = [Pivot::Median, Pivot::BoundingBox, Pivot::Cursor, Pivot::Active];

    pub fn name(self) -> &'static str {
        match self {
            Pivot::Median => "Median",
            Pivot::BoundingBox => "Bounding box",
            Pivot::Cursor => "3D cursor",
            Pivot::Active => "Active vertex",
        }
    }

    /// The next choice (Shift+S).
    pub fn next(self) -> Pivot {
        let k = Pivot::ALL.iter().position(|&p| p == self).unwrap_or(0);
        Pivot::ALL[(k + 1) % Pivot::ALL.len()]
    }
}

/// The pivot of `points` (model coordinates, not empty) for `pivot`; `cursor` is the 3D cursor
/// and `active` the active vertex's position, where there is one (else the median is used).
pub fn pivot_point(pivot: Pivot, points: &[DVec3], cursor: DVec3, active: Option<DVec3>) -> DVec3 {
    let median = || points.iter().copied().sum::<DVec3>() / points.len().max(1) as f64;
    match pivot {
        Pivot::Median => median(),
        Pivot::BoundingBox => match taut_core::mesh::bounding_box(points) {
            Some((lo, hi)) => lo * 0.5 + hi * 0.5,
            None => median(),
        },
        Pivot::Cursor => cursor,
        Pivot::Active => active.unwrap_or_else(median),
    }
}

/// The first hit of the ray `origin + t·direction` (t > 0) with the faces of `mesh` (fan
/// triangles): the parameter `t`, or `None` when it misses.
pub fn ray_cast(mesh: &PolyMesh, origin: DVec3, direction: DVec3) -> Option<f64> {
    ray_cast_where(mesh, origin, direction, |_| true)
}

/// [`ray_cast`] among the hits `keep` accepts (by ray parameter): the first hit the clipping
/// plane leaves.
pub fn ray_cast_where(mesh: &PolyMesh, origin: DVec3, direction: DVec3, keep: impl Fn(f64) -> bool) -> Option<f64> {
    let p = mesh.positions();
    let mut best: Option<f64> = None;
    for [a, b, c] in mesh.triangles() {
        let (a, b, c) = (p[a as usize], p[b as usize], p[c as usize]);
        let (e1, e2) = (b - a, c - a);
        let q = direction.cross(e2);
        let det = e1.dot(q);
        if det.abs() <= 1e-300 || !det.is_finite() {
            continue;
        }
        let s = origin - a;
        let u = s.dot(q) / det;
        if !(0.0..=1.0).contains(&u) {
            continue;
        }
        let r = s.cross(e1);
        let v = direction.dot(r) / det;
        if v < 0.0 || u + v > 1.0 {
            continue;
        }
        let t = e2.dot(r) / det;
        if t > 0.0 && t.is_finite() && best.is_none_or(|b| t < b) && keep(t) {
            best = Some(t);
        }
    }
    best
}

impl EditorState {
    /// The active vertex: the vertex picked last, or the first corner of the edge or face picked
    /// last.
    pub fn active_vertex(&self) -> Option<VertexId> {
        let cage = &self.document.doc().cage;
        let s = &self.view.selection;
        s.vertices
            .last()
            .copied()
            .or_else(|| s.edges.last().map(|&e| cage.edge_vertices(e).0))
            .or_else(|| s.faces.last().and_then(|&f| cage.face_vertices(f).next()))
            .filter(|v| v.index() < cage.vertex_count())
    }

    /// The pivot of the given selected vertices by the toolbar's choice, in model coordinates.
    pub fn pivot_of(&self, vertices: &[VertexId]) -> DVec3 {
        let cage = &self.document.doc().cage;
        let points: Vec<DVec3> = vertices.iter().map(|&v| cage.position(v)).collect();
        let active = self.active_vertex().map(|v| cage.position(v));
        pivot_point(self.gizmo.pivot, &points, self.gizmo.cursor, active)
    }

    /// Shift+right-click: the 3D cursor goes where the mouse ray meets the surface (or the cage),
    /// else into the view plane through its old place.
    pub fn place_cursor(&mut self, view: &ViewportRect, mouse: Vec2) {
        let (origin, direction) = interaction::unproject_ray(&self.view.camera, view, mouse);
        let frame = self.view.display_frame;
        let display = self.display_cage();
        let hit = self
            .surface_mesh()
            .and_then(|mesh| {
                // The surface is in model coordinates: cast in display coordinates all the same.
                let mut m = mesh.clone();
                m.positions_mut().iter_mut().for_each(|p| *p = frame.to_display_f64(*p));
                ray_cast(&m, origin, direction)
            })
            .or_else(|| ray_cast(&display, origin, direction));
        let point = match hit {
            Some(t) => origin + t * direction,
            None => {
                let old = frame.to_display_f64(self.gizmo.cursor);
                let forward = (self.view.camera.target.as_dvec3() - origin).normalize();
                let depth = (old - origin).dot(forward);
                let along = direction.dot(forward);
                if depth > 0.0 && along > 0.0 { origin + direction * (depth / along) } else { old }
            }
        };
        // No notice: the cursor is drawn where it went (a notice strip would resize the view).
        if point.is_finite() {
            self.gizmo.cursor = frame.to_model(point);
        }
    }

    /// Draws the 3D cursor: a red and white ring with a cross, as Blender draws it.
    pub(crate) fn draw_cursor(&self, painter: &egui::Painter, view: &ViewportRect) {
        let p = self.view.display_frame.to_display_f64(self.gizmo.cursor);
        let Some((c, _)) = interaction::project(&self.view.camera, view, p) else { return };
        let c = egui::pos2(c.x, c.y);
        let red = egui::Color32::from_rgb(230, 50, 50);
        let white = egui::Color32::WHITE;
        for k in 0..8 {
            let a0 = k as f32 * std::f32::consts::FRAC_PI_4;
            let a1 = a0 + std::f32::consts::FRAC_PI_4;
            let points: Vec<egui::Pos2> = (0..=6)
                .map(|i| a0 + (a1 - a0) * i as f32 / 6.0)
                .map(|a| c + 10.0 * egui::vec2(a.cos(), a.sin()))
                .collect();
            painter.add(egui::Shape::line(points, egui::Stroke::new(2.0, if k % 2 == 0 { red } else { white })));
        }
        let stroke = egui::Stroke::new(1.0, egui::Color32::BLACK);
        for d in [egui::vec2(1.0, 0.0), egui::vec2(0.0, 1.0)] {
            painter.line_segment([c + 5.0 * d, c + 16.0 * d], stroke);
            painter.line_segment([c - 5.0 * d, c - 16.0 * d], stroke);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pivots_of_three_corners_of_a_square_match_their_closed_forms() {
        let points = [DVec3::new(0.0, 0.0, 0.0), DVec3::new(3.0, 0.0, 0.0), DVec3::new(3.0, 1.0, 0.0)];
        let cursor = DVec3::new(-1.0, 2.0, 5.0);
        assert_eq!(pivot_point(Pivot::Median, &points, cursor, None), DVec3::new(2.0, 1.0 / 3.0, 0.0));
        assert_eq!(pivot_point(Pivot::BoundingBox, &points, cursor, None), DVec3::new(1.5, 0.5, 0.0));
        assert_eq!(pivot_point(Pivot::Cursor, &points, cursor, None), cursor);
        assert_eq!(pivot_point(Pivot::Active, &points, cursor, Some(points[1])), points[1]);
        assert_eq!(pivot_point(Pivot::Active, &points, cursor, None), DVec3::new(2.0, 1.0 / 3.0, 0.0));
        let mut p = Pivot::Median;
        for _ in 0..4 {
            p = p.next();
        }
        assert_eq!(p, Pivot::Median, "Shift+S cycles through all four");
    }

    #[test]
    fn a_ray_meets_the_cube_on_its_near_face_and_misses_beside_it() {
        let cube = crate::editor::primitives::cube().cage;
        // The cube spans [-0.5, 0.5]³ (the primitive's doc); a ray down from above hits the top.
        let (lo, hi) = cube.bounding_box().unwrap();
        let origin = DVec3::new(0.1, -0.2, 10.0);
        let t = ray_cast(&cube, origin, -DVec3::Z).expect("a hit");
        assert!((origin.z - t - hi.z).abs() < 1e-12, "{t}");
        let slanted = (DVec3::new(lo.x, 0.0, 0.0) - DVec3::new(-10.0, 0.0, 0.0)).normalize();
        let t = ray_cast(&cube, DVec3::new(-10.0, 0.0, 0.0), slanted).unwrap();
        assert!((t - (10.0 + lo.x)).abs() < 1e-12);
        assert_eq!(ray_cast(&cube, DVec3::new(hi.x + 0.1, 0.0, 10.0), -DVec3::Z), None);
        assert_eq!(ray_cast(&cube, origin, DVec3::Z), None, "nothing behind the origin");
    }
}
