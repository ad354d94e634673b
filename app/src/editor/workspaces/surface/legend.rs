//! The colour legend of the viewport (curvature, distance, curve-mesh continuity), drawn by egui
//! with the UI's font in a strip reserved at the viewport's right: the camera frames the model in
//! the rest of the viewport ([`EditorState::viewport_shape`]'s margin), so the legend never covers
//! it. The title and the numbers are labels, which screen readers and tests can find.
//!
//! [`EditorState::viewport_shape`]: crate::editor::state::EditorState::viewport_shape

use taut_render::Legend;
use taut_render::overlay::format_number;

/// The strip's width, in points.
pub const LEGEND_WIDTH: f32 = 130.0;
/// Significant digits of the numbers.
const DIGITS: usize = 3;
/// Steps of the colour bar's gradient.
const BAR_STEPS: usize = 48;

/// The strip a legend takes at the right of `viewport`.
pub fn legend_strip(viewport: egui::Rect) -> egui::Rect {
    let width = LEGEND_WIDTH.min(0.4 * viewport.width());
    egui::Rect::from_min_max(egui::pos2(viewport.right() - width, viewport.top()), viewport.max)
}

/// Draws `legend` in `strip`: the title at the top, the bar with its highest value at the top, the
/// lowest at the bottom and zero between when the range holds it.
pub fn draw_legend(ui: &mut egui::Ui, strip: egui::Rect, legend: &Legend) {
    let painter = ui.painter_at(strip);
    painter.rect_filled(strip, 0.0, ui.visuals().panel_fill);
    let margin = 8.0;
    let inner = strip.shrink(margin);
    let title_rect = egui::Rect::from_min_size(inner.min, egui::vec2(inner.width(), 48.0));
    let title = ui.put(title_rect, egui::Label::new(&legend.title).wrap().selectable(false));
    let row = ui.text_style_height(&egui::TextStyle::Body);
    let bar = egui::Rect::from_min_max(
        egui::pos2(inner.left(), title.rect.bottom() + 0.5 * row + margin),
        egui::pos2(inner.left() + 16.0, inner.bottom() - 0.5 * row),
    );
    if bar.height() < 2.0 * row {
        return;
    }
    let mut mesh = egui::Mesh::default();
    for k in 0..=BAR_STEPS {
        let t = k as f32 / BAR_STEPS as f32;
        let [r, g, b] = legend.map.color(t);
        let color = egui::Color32::from_rgb(r, g, b);
        let y = bar.bottom() - t * bar.height();
        mesh.colored_vertex(egui::pos2(bar.left(), y), color);
        mesh.colored_vertex(egui::pos2(bar.right(), y), color);
        if k > 0 {
            let i = (2 * k) as u32;
            mesh.add_triangle(i - 2, i - 1, i);
            mesh.add_triangle(i - 1, i + 1, i);
        }
    }
    painter.add(mesh);
    painter.rect_stroke(bar, 0.0, ui.visuals().widgets.noninteractive.bg_stroke, egui::StrokeKind::Outside);
    let mut values = vec![(0.0f32, legend.min), (1.0, legend.max)];
    if legend.min < 0.0 && legend.max > 0.0 {
        let t = (-legend.min / (legend.max - legend.min)) as f32;
        // Only where it does not crowd the end labels.
        if t * bar.height() > 1.5 * row && (1.0 - t) * bar.height() > 1.5 * row {
            values.push((t, 0.0));
        }
    }
    for (t, value) in values {
        let y = bar.bottom() - t * bar.height();
        painter.hline(bar.right()..=bar.right() + 4.0, y, ui.visuals().widgets.noninteractive.fg_stroke);
        let rect = egui::Rect::from_min_max(
            egui::pos2(bar.right() + 8.0, y - 0.5 * row),
            egui::pos2(inner.right(), y + 0.5 * row),
        );
        ui.put(rect, egui::Label::new(format_number(value, DIGITS)).selectable(false).truncate());
    }
}
