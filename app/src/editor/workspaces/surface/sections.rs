//! Section curves in the viewport (Display ▸ sections), as Rhino's Contour or Alias's cross
//! sections: the surface cut by parallel planes across one axis, each section drawn with its
//! curvature comb (on the section resampled evenly, `SectionCurve::evenly`). The planes are `count` of them `spacing` apart, centred on the surface's box
//! (a spacing of 0 spreads them evenly over its extent). The curves are cut again only when the
//! surface or the settings change (`SectionCache`), not every frame.

use crate::editor::state::{EditorState, comb_style};
use taut_core::DVec3;
use taut_core::mesh::sections::sections;
use taut_render::overlay::{self, OverlayData};

/// What the sections show.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SectionSettings {
    /// 0, 1 or 2: the planes are normal to x, y or z.
    pub axis: usize,
    pub count: usize,
    /// Model units between planes; 0 spreads them over the surface's extent.
    pub spacing: f64,
}

impl Default for SectionSettings {
    fn default() -> Self {
        SectionSettings { axis: 2, count: 8, spacing: 0.0 }
    }
}

impl SectionSettings {
    /// The planes' offsets along the axis for a surface spanning `lo..hi` on it.
    pub fn offsets(&self, lo: f64, hi: f64) -> Vec<f64> {
        let count = self.count.clamp(1, 200);
        let step = if self.spacing > 0.0 { self.spacing } else { (hi - lo) / count as f64 };
        let centre = 0.5 * (lo + hi);
        (0..count).map(|k| centre + (k as f64 - 0.5 * (count - 1) as f64) * step).collect()
    }
}

/// The last sections cut: of which surface (its generations) with which settings.
#[derive(Debug, Default)]
pub struct SectionCache {
    key: Option<(u64, u64, [u64; 3])>,
    curves: Vec<(Vec<DVec3>, bool)>,
}

impl EditorState {
    /// Adds the section curves with their combs when Display ▸ sections is on.
    pub(crate) fn section_overlays(&self, data: &mut OverlayData) {
        let Some(settings) = self.view.display.sections else { return };
        let Some(mesh) = self.surface_mesh() else { return };
        let key = (
            mesh.topology_generation(),
            mesh.generation(),
            [settings.axis as u64, settings.count as u64, settings.spacing.to_bits()],
        );
        let mut cache = self.sections.borrow_mut();
        if cache.key != Some(key) {
            let mut normal = DVec3::ZERO;
            normal[settings.axis.min(2)] = 1.0;
            let along = mesh.positions().iter().map(|p| p[settings.axis.min(2)]);
            let (lo, hi) = along.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), x| (a.min(x), b.max(x)));
            let offsets = if lo <= hi { settings.offsets(lo, hi) } else { Vec::new() };
            let step = taut_core::mesh::sections::comb_step(mesh);
            cache.curves =
                sections(mesh, normal, &offsets).into_iter().flatten().map(|c| (c.evenly(step), c.closed)).collect();
            cache.key = Some(key);
        }
        let points: Vec<Vec<DVec3>> = cache.curves.iter().map(|(p, _)| p.clone()).collect();
        let style = comb_style(
            &points,
            mesh.bounding_diagonal(),
            self.view.display.comb_length,
            self.view.display.comb_density,
        );
        for (p, closed) in &cache.curves {
            data.surface_lines.extend(overlay::polyline_with_comb(p, *closed, &style, &self.view.display_frame));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn planes_are_spread_over_the_extent_or_spaced_as_asked_about_its_centre() {
        let even = SectionSettings { axis: 2, count: 4, spacing: 0.0 }.offsets(0.0, 8.0);
        assert_eq!(even, vec![1.0, 3.0, 5.0, 7.0]);
        let spaced = SectionSettings { axis: 0, count: 3, spacing: 0.5 }.offsets(-1.0, 1.0);
        assert_eq!(spaced, vec![-0.5, 0.0, 0.5]);
    }

    #[test]
    fn display_sections_draw_one_closed_loop_per_plane_of_a_closed_surface() {
        let mut h = crate::editor::panel_tests::cube_editor();
        for _ in 0..10 {
            crate::editor::panel_tests::frames(&mut h);
        }
        let editor = &mut h.state_mut().editor;
        let without = editor.overlays().surface_lines.len();
        editor.view.display.sections = Some(SectionSettings { axis: 2, count: 3, spacing: 0.0 });
        let with = editor.overlays().surface_lines.len();
        let curves = editor.sections.borrow().curves.clone();
        assert_eq!(curves.len(), 3, "three planes across the closed surface");
        assert!(curves.iter().all(|(points, closed)| *closed && points.len() > 8));
        assert!(with > without + 3 * 8, "the sections and their teeth are drawn: {without} -> {with}");
        // The same surface and settings: the curves are not cut again.
        let key = editor.sections.borrow().key;
        editor.overlays();
        assert_eq!(editor.sections.borrow().key, key);
    }
}
