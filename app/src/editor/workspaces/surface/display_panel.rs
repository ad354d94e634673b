//! The Display panel: how the surface is drawn (shaded, zebra, curvature colour and its range,
//! draft angle with its legend, highlight lines, the compare view, overlays, X-ray), each
//! control with a tooltip.

use super::analysis_views::{PullAxis, draft_legend};
use crate::editor::live::CompareMode;
use crate::editor::state::{DisplayMode, EditorState};
use taut_core::curvature::CurvatureQuantity;
use taut_core::surface::{ColourBy, fields_of};

impl EditorState {
    pub(crate) fn display_panel(&mut self, ui: &mut egui::Ui) {
        ui.heading("Display");
        let before = self.view.display.clone();
        let range = self.value_range();
        let scheme = self.document.doc().scheme;
        let other = self.other_scheme();
        let d = &mut self.view.display;
        ui.horizontal_wrapped(|ui| {
            ui.radio_value(&mut d.mode, DisplayMode::Shaded, "shaded").on_hover_text("Plain shading");
            ui.radio_value(&mut d.mode, DisplayMode::Zebra, "zebra").on_hover_text(
                "Reflection lines: a break in the stripes is a break in tangent, a kink a break in curvature",
            );
            ui.radio_value(&mut d.mode, DisplayMode::Curvature, "curvature")
                .on_hover_text("Colour by a curvature quantity, with a legend");
            ui.radio_value(&mut d.mode, DisplayMode::Draft, "draft").on_hover_text(
                "Colour by the draft angle against the pull direction: green leaves the mould, yellow needs \
                 more draft, red is an undercut",
            );
            ui.radio_value(&mut d.mode, DisplayMode::Highlight, "highlight").on_hover_text(
                "Highlight lines of parallel light tubes over the model: fixed to the model, unlike zebra; a \
                 break in the lines is a break in tangent, a kink a break in curvature",
            );
        });
        match d.mode {
            DisplayMode::Shaded => {}
            DisplayMode::Zebra => {
                ui.add(egui::Slider::new(&mut d.stripes, 2.0..=40.0).text("stripes"))
                    .on_hover_text("Black and white stripe pairs across half a turn of reflected directions");
                ui.add(egui::Slider::new(&mut d.stripe_angle, -90.0..=90.0).text("angle °"))
                    .on_hover_text("The direction of the stripes on screen (0: horizontal)");
                ui.add(egui::Slider::new(&mut d.stripe_width, 0.1..=0.9).text("black share"))
                    .on_hover_text("The fraction of each stripe pair that is black");
            }
            DisplayMode::Draft => {
                let a = &mut d.analysis;
                ui.horizontal(|ui| {
                    ui.label("pull");
                    for (axis, name) in
                        [(PullAxis::X, "x"), (PullAxis::Y, "y"), (PullAxis::Z, "z"), (PullAxis::View, "view")]
                    {
                        ui.radio_value(&mut a.pull, axis, name)
                            .on_hover_text("The direction the mould opens: a model axis, or towards the camera");
                    }
                });
                if a.pull != PullAxis::View {
                    ui.checkbox(&mut a.pull_negative, "negative (the other mould half)")
                        .on_hover_text("Pull along the negative axis");
                }
                ui.add(egui::Slider::new(&mut a.draft_angle, 0.0..=30.0).text("draft angle °"))
                    .on_hover_text("The least draft a face needs; faces with less, on either side, are yellow");
                draft_legend(ui, a.draft_angle);
            }
            DisplayMode::Highlight => {
                let a = &mut d.analysis;
                ui.horizontal(|ui| {
                    ui.label("tubes along");
                    for (axis, name) in ["x", "y", "z"].into_iter().enumerate() {
                        ui.radio_value(&mut a.tube_axis, axis, name).on_hover_text(
                            "The direction of the light tubes; they hang above the model (in front of it when vertical)",
                        );
                    }
                });
                ui.add(egui::DragValue::new(&mut a.tube_spacing).range(0.0..=f64::MAX).speed(0.1).prefix("spacing "))
                    .on_hover_text("Model units between the tubes; 0 spaces them by an eighth of the model's size");
                ui.add(egui::Slider::new(&mut a.tube_count, 1..=60).text("tubes"))
                    .on_hover_text("How many tubes, centred over the model");
            }
            DisplayMode::Curvature => {
                let mut choices: Vec<ColourBy> =
                    CurvatureQuantity::ALL.iter().map(|&q| ColourBy::Curvature(q)).collect();
                choices.extend(fields_of(scheme).iter().map(|&f| ColourBy::Field(f)));
                if !choices.contains(&d.colour_by) {
                    d.colour_by = choices[0];
                }
                egui::ComboBox::from_label("quantity")
                    .selected_text(d.colour_by.display_name())
                    .show_ui(ui, |ui| {
                        for c in choices {
                            ui.selectable_value(&mut d.colour_by, c, c.display_name());
                        }
                    })
                    .response
                    .on_hover_text("Mean, Gaussian, principal curvatures, or what the scheme offers (NUSD's |R|)");
                let mut automatic = d.fixed_range.is_none();
                if ui
                    .checkbox(&mut automatic, "automatic range (2–98 %)")
                    .on_hover_text(
                        "Colour from the 2nd to the 98th percentile, symmetric about 0 for signed quantities",
                    )
                    .changed()
                {
                    d.fixed_range = if automatic { None } else { Some(range) };
                }
                if let Some((min, max)) = &mut d.fixed_range {
                    ui.horizontal(|ui| {
                        let name = ui.label("min");
                        ui.add(egui::DragValue::new(min).speed(0.001))
                            .labelled_by(name.id)
                            .on_hover_text("The value at the bottom of the colour bar");
                        let name = ui.label("max");
                        ui.add(egui::DragValue::new(max).speed(0.001))
                            .labelled_by(name.id)
                            .on_hover_text("The value at the top of the colour bar");
                    });
                    if *max <= *min {
                        *max = *min + 1e-9_f64.max(min.abs() * 1e-6);
                    }
                }
            }
        }
        ui.separator();
        ui.checkbox(&mut d.show_cage, "cage").on_hover_text("The cage's edges and vertices, with tension shown");
        ui.checkbox(&mut d.xray, "X-ray (Alt+Z)")
            .on_hover_text("Off: the back of the cage is drawn dimmer and cannot be picked. On: all of it is");
        ui.checkbox(&mut d.show_wire, "refined wireframe").on_hover_text("The edges of the smoothed surface");
        ui.checkbox(&mut d.show_curves, "curves with curvature combs")
            .on_hover_text("The surface's curves along the cage edges, with their curvature combs");
        if d.show_curves {
            ui.add(egui::Slider::new(&mut d.comb_length, 0.01..=0.5).logarithmic(true).text("comb length"))
                .on_hover_text("The longest tooth of the combs, as a fraction of the model's size");
            ui.add(egui::Slider::new(&mut d.comb_density, 1..=8).text("every n-th point"))
                .on_hover_text("A tooth at every n-th point of each curve");
        }
        let mut on = d.sections.is_some();
        ui.checkbox(&mut on, "sections with curvature combs")
            .on_hover_text("Where parallel planes cut the surface, each section with its curvature comb");
        match (on, &mut d.sections) {
            (false, s) => *s = None,
            (true, None) => d.sections = Some(Default::default()),
            (true, Some(s)) => {
                ui.horizontal(|ui| {
                    for (axis, name) in ["x", "y", "z"].into_iter().enumerate() {
                        ui.radio_value(&mut s.axis, axis, name).on_hover_text("The axis the planes are normal to");
                    }
                });
                ui.add(egui::Slider::new(&mut s.count, 1..=50).text("planes")).on_hover_text("How many sections");
                ui.add(egui::DragValue::new(&mut s.spacing).range(0.0..=f64::MAX).speed(0.1).prefix("spacing "))
                    .on_hover_text("Model units between the planes; 0 spreads them over the surface");
            }
        }
        let mut compare = d.compare;
        self.clip_controls(ui);
        ui.separator();
        ui.label(format!("compare with {}", other.display_name()));
        ui.horizontal(|ui| {
            ui.radio_value(&mut compare, CompareMode::Off, "off").on_hover_text("Only this scheme's surface");
            ui.radio_value(&mut compare, CompareMode::Ghost, "ghost")
                .on_hover_text("The other scheme's surface drawn as a translucent ghost over this one");
            ui.radio_value(&mut compare, CompareMode::Distance, "distance")
                .on_hover_text("This surface coloured by its distance to the other scheme's, with a legend");
        });
        let compare_changed = compare != self.view.display.compare;
        if compare_changed {
            self.set_compare(compare);
        }
        if self.view.display != before {
            self.invalidate_values();
        }
    }
}
