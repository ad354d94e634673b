//! The editor's settings of the two analysis views beside zebra and curvature colour: the draft
//! angle against a pull direction and highlight lines of parallel light tubes
//! (`taut_render::analysis` explains both). The Display panel edits them; here they become the
//! renderer's [`SurfaceMode`], with lengths in the viewport's display coordinates.

use crate::editor::state::EditorState;
use taut_core::DVec3;
use taut_render::analysis::{self, LightTubes, Pull};
use taut_render::passes::surface::SurfaceMode;

/// Where the mould is pulled: along a model axis or towards the camera.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PullAxis {
    X,
    Y,
    Z,
    /// The view direction, following the camera.
    View,
}

/// The draft and highlight views' settings.
#[derive(Clone, Debug, PartialEq)]
pub struct AnalysisSettings {
    pub pull: PullAxis,
    /// Pull along the negative axis (the other mould half); ignored for [`PullAxis::View`].
    pub pull_negative: bool,
    /// The least draft a face needs, degrees.
    pub draft_angle: f64,
    /// The tubes' axis: 0 x, 1 y, 2 z.
    pub tube_axis: usize,
    /// Model units between the tubes; 0 spaces them by an eighth of the model's largest extent.
    pub tube_spacing: f64,
    pub tube_count: u32,
}

impl Default for AnalysisSettings {
    fn default() -> Self {
        AnalysisSettings {
            pull: PullAxis::Z,
            pull_negative: false,
            draft_angle: analysis::DEFAULT_DRAFT_DEGREES,
            tube_axis: 0,
            tube_spacing: 0.0,
            tube_count: analysis::DEFAULT_TUBE_COUNT,
        }
    }
}

impl AnalysisSettings {
    /// The pull of the draft view.
    pub fn pull(&self) -> Pull {
        let sign = if self.pull_negative { -1.0 } else { 1.0 };
        match self.pull {
            PullAxis::X => Pull::Direction(sign * DVec3::X),
            PullAxis::Y => Pull::Direction(sign * DVec3::Y),
            PullAxis::Z => Pull::Direction(sign * DVec3::Z),
            PullAxis::View => Pull::View,
        }
    }

    /// The draft view's mode.
    pub fn draft_mode(&self) -> SurfaceMode {
        SurfaceMode::Draft { pull: self.pull(), angle_degrees: self.draft_angle as f32 }
    }

    /// The highlight view's mode, the spacing converted with `frame`.
    pub fn highlight_mode(&self, frame: &taut_render::DisplayFrame) -> SurfaceMode {
        let spacing =
            if self.tube_spacing > 0.0 { frame.length(self.tube_spacing) } else { analysis::DEFAULT_TUBE_SPACING };
        SurfaceMode::Highlight(LightTubes {
            direction: [DVec3::X, DVec3::Y, DVec3::Z][self.tube_axis.min(2)],
            spacing,
            count: self.tube_count.max(1),
            height: analysis::TUBE_HEIGHT,
        })
    }
}

impl EditorState {
    /// The surface mode of the draft view.
    pub fn draft_mode(&self) -> SurfaceMode {
        self.view.display.analysis.draft_mode()
    }

    /// The surface mode of the highlight view, in the viewport's display frame.
    pub fn highlight_mode(&self) -> SurfaceMode {
        self.view.display.analysis.highlight_mode(&self.view.display_frame)
    }
}

/// The draft view's legend: a swatch and its words per class, for `threshold` degrees. Labels,
/// so screen readers and tests find them.
pub fn draft_legend(ui: &mut egui::Ui, threshold: f64) {
    for class in analysis::DraftClass::ALL {
        ui.horizontal(|ui| {
            let [r, g, b] = class.color();
            let (rect, _) = ui.allocate_exact_size(egui::vec2(14.0, 14.0), egui::Sense::hover());
            ui.painter().rect_filled(rect, 2.0, egui::Color32::from_rgb(r, g, b));
            ui.label(class.label(threshold));
        });
    }
}

#[cfg(test)]
#[path = "analysis_views_tests.rs"]
mod tests;
