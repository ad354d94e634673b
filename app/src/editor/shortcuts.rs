//! The editor's keyboard shortcuts: one table that the key handling, the menus and
//! Help ▸ Keyboard shortcuts all read, so what a menu says is what a key does.
//!
//! Modifiers match exactly: Ctrl+Shift+Z is redo and never undo, Ctrl+Shift+S is Save As and
//! never Save, and a plain key (F, Home, 1) does nothing while Ctrl, Shift or Alt is held. egui's
//! own `consume_key` ignores extra Shift and Alt, which is how Ctrl+Shift+S once saved over the
//! current file; here every key event is compared with the whole modifier set it came with.
//! (Ctrl is the platform's command key: ⌘ on a Mac.)

use super::mesh_ops::MeshOp;
use super::transform::TransformKind;
use egui::{Event, Key, Modifiers};

/// What a shortcut does.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Action {
    Undo,
    Redo,
    Save,
    SaveAs,
    Open,
    Quit,
    SelectAll,
    SelectNone,
    FrameAll,
    FrameSelection,
    ViewFront,
    ViewRight,
    ViewTop,
    /// The three-quarter view a new document opens in.
    ViewThreeQuarter,
    /// Numpad 5: orthographic (parallel) or perspective projection.
    ToggleOrthographic,
    ShowShortcuts,
    /// Subdivision schemes: drag the crease sharpness of the selected edges with the mouse.
    Crease,
    /// Subdivision schemes: drag the corner sharpness of the selected vertices with the mouse.
    Corner,
    /// Vertex → edge → face select mode.
    CycleSelectMode,
    SelectLinked,
    SelectMore,
    SelectLess,
    /// A cage-modelling operation (Mesh menu).
    Mesh(MeshOp),
    /// G, R, S: move, rotate or scale the selection.
    Transform(TransformKind),
    /// W: show or hide the transform gizmo.
    ToggleGizmo,
    /// Shift+S: the next pivot.
    CyclePivot,
    /// Mirror modelling on or off (Mesh ▸ Mirror chooses the plane).
    ToggleMirror,
    /// X-ray: the back of the cage drawn and picked too, or dimmed and left alone.
    ToggleXray,
    /// A tool of the listing (`crate::editor::tools::TOOLS`), by its name: what its entry
    /// there says it is and does. A new tool needs no new variant here.
    Tool(&'static str),
}

impl Action {
    /// Whether the action works on the cage and its selection, which only the Surface workspace
    /// shows: in the Curves workspace its key does nothing (Delete there must not delete cage
    /// vertices nobody can see).
    pub fn acts_on_the_cage(self) -> bool {
        matches!(
            self,
            Action::SelectAll
                | Action::SelectNone
                | Action::Crease
                | Action::Corner
                | Action::CycleSelectMode
                | Action::SelectLinked
                | Action::SelectMore
                | Action::SelectLess
                | Action::Mesh(_)
                | Action::Transform(_)
                | Action::ToggleGizmo
                | Action::CyclePivot
                | Action::ToggleMirror
                | Action::Tool(_)
        )
    }
}

/// A key with the exact modifiers it needs.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Shortcut {
    pub key: Key,
    pub command: bool,
    pub shift: bool,
    pub alt: bool,
    pub action: Action,
}

const fn plain(key: Key, action: Action) -> Shortcut {
    Shortcut { key, command: false, shift: false, alt: false, action }
}

const fn ctrl(key: Key, action: Action) -> Shortcut {
    Shortcut { key, command: true, shift: false, alt: false, action }
}

const fn shift(key: Key, action: Action) -> Shortcut {
    Shortcut { key, command: false, shift: true, alt: false, action }
}

const fn alt(key: Key, action: Action) -> Shortcut {
    Shortcut { key, command: false, shift: false, alt: true, action }
}

const fn ctrl_shift(key: Key, action: Action) -> Shortcut {
    Shortcut { key, command: true, shift: true, alt: false, action }
}

/// Every shortcut, in the order Help lists them. An action may have several keys; the first is
/// the one menus show.
pub const SHORTCUTS: &[Shortcut] = &[
    ctrl(Key::Z, Action::Undo),
    ctrl_shift(Key::Z, Action::Redo),
    ctrl(Key::Y, Action::Redo),
    ctrl(Key::O, Action::Open),
    ctrl(Key::S, Action::Save),
    ctrl_shift(Key::S, Action::SaveAs),
    ctrl(Key::Q, Action::Quit),
    ctrl(Key::A, Action::SelectAll),
    plain(Key::Escape, Action::SelectNone),
    plain(Key::Home, Action::FrameAll),
    plain(Key::A, Action::FrameAll),
    plain(Key::Period, Action::FrameSelection),
    plain(Key::Num1, Action::ViewFront),
    plain(Key::Num3, Action::ViewRight),
    plain(Key::Num7, Action::ViewTop),
    plain(Key::Num0, Action::ViewThreeQuarter),
    plain(Key::Num5, Action::ToggleOrthographic),
    plain(Key::F1, Action::ShowShortcuts),
    shift(Key::E, Action::Crease),
    shift(Key::V, Action::Corner),
    plain(Key::Tab, Action::CycleSelectMode),
    ctrl(Key::L, Action::SelectLinked),
    ctrl(Key::Plus, Action::SelectMore),
    ctrl(Key::Equals, Action::SelectMore),
    ctrl(Key::Minus, Action::SelectLess),
    plain(Key::E, Action::Mesh(MeshOp::Extrude)),
    plain(Key::I, Action::Mesh(MeshOp::Inset)),
    ctrl(Key::R, Action::Mesh(MeshOp::LoopCut)),
    plain(Key::X, Action::Mesh(MeshOp::Delete)),
    plain(Key::Delete, Action::Mesh(MeshOp::Delete)),
    plain(Key::M, Action::Mesh(MeshOp::MergeAtCentre)),
    plain(Key::F, Action::Mesh(MeshOp::Fill)),
    plain(Key::G, Action::Transform(TransformKind::Grab)),
    plain(Key::R, Action::Transform(TransformKind::Rotate)),
    plain(Key::S, Action::Transform(TransformKind::Scale)),
    plain(Key::W, Action::ToggleGizmo),
    shift(Key::S, Action::CyclePivot),
    shift(Key::M, Action::ToggleMirror),
    alt(Key::Z, Action::ToggleXray),
    plain(Key::D, Action::Tool("measure")),
];

impl Shortcut {
    /// True when `modifiers` are exactly the ones this shortcut needs.
    pub fn matches(&self, modifiers: Modifiers) -> bool {
        modifiers.command == self.command && modifiers.shift == self.shift && modifiers.alt == self.alt
    }

    /// How the menus and Help write it, e.g. `Ctrl+Shift+Z`.
    pub fn label(&self) -> String {
        let mut parts = Vec::new();
        if self.command {
            parts.push("Ctrl".to_string());
        }
        if self.alt {
            parts.push("Alt".to_string());
        }
        if self.shift {
            parts.push("Shift".to_string());
        }
        parts.push(key_name(self.key).to_string());
        parts.join("+")
    }
}

/// The name of a key as Help and the menus print it.
pub(super) fn key_name(key: Key) -> &'static str {
    match key {
        Key::Num1 => "1",
        Key::Num3 => "3",
        Key::Num5 => "5",
        Key::Num7 => "7",
        Key::Escape => "Esc",
        Key::Period => ".",
        Key::Plus => "Plus",
        Key::Equals => "=",
        Key::Minus => "Minus",
        other => other.name(),
    }
}

/// The label of an action's first shortcut (for menus), or an empty string.
pub fn label(action: Action) -> String {
    SHORTCUTS.iter().find(|s| s.action == action).map_or_else(String::new, Shortcut::label)
}

/// All keys of an action, joined with " or " (for Help).
pub fn all_labels(action: Action) -> String {
    SHORTCUTS.iter().filter(|s| s.action == action).map(Shortcut::label).collect::<Vec<_>>().join(" or ")
}

/// What the designer sees in Help ▸ Keyboard shortcuts and in the menus.
pub fn describe(action: Action) -> &'static str {
    match action {
        Action::Undo => "Undo",
        Action::Redo => "Redo",
        Action::Save => "Save",
        Action::SaveAs => "Save as…",
        Action::Open => "Open…",
        Action::Quit => "Quit",
        Action::SelectAll => "Select all",
        Action::SelectNone => "Select none (while dragging: cancel the drag)",
        Action::FrameAll => "Frame all",
        Action::FrameSelection => "Frame the selection (in the Curves workspace: the selected curve or patch)",
        Action::ViewFront => "Front view",
        Action::ViewRight => "Right view",
        Action::ViewTop => "Top view",
        Action::ViewThreeQuarter => "Three-quarter view",
        Action::ToggleOrthographic => "Orthographic / perspective",
        Action::ShowShortcuts => "Keyboard shortcuts",
        Action::Crease => "Crease the selected edges (move the mouse, click or Enter to set, Esc cancels)",
        Action::Corner => {
            "Sharpen the selected vertices into corners (move the mouse, click or Enter to set, Esc cancels)"
        }
        Action::CycleSelectMode => "Select mode: vertex, edge, face in turn",
        Action::SelectLinked => "Select linked (everything connected to the selection)",
        Action::SelectMore => "Select more (one ring of neighbours)",
        Action::SelectLess => "Select less",
        Action::Mesh(op) => op.label(),
        Action::Transform(TransformKind::Grab) => {
            "Move the selection (X, Y, Z lock an axis, Shift+X, Y, Z a plane, Ctrl snaps, type a distance)"
        }
        Action::Transform(TransformKind::Rotate) => {
            "Rotate the selection about the pivot (X, Y, Z axis, Ctrl snaps to 5°, type degrees)"
        }
        Action::Transform(TransformKind::Scale) => {
            "Scale the selection about the pivot (X, Y, Z axis, Shift+X, Y, Z a plane, Ctrl snaps, type a factor)"
        }
        Action::ToggleGizmo => "Show or hide the transform gizmo",
        Action::CyclePivot => "Pivot: median, bounding box, 3D cursor, active vertex in turn",
        Action::ToggleMirror => "Mirror modelling on or off (the plane last chosen in the Mesh menu's Mirror entry)",
        Action::ToggleXray => "X-ray on or off: off, the back of the cage is dimmed and cannot be picked",
        // Its description is in the tools' listing; Help reads it there (`menus::help_text`).
        Action::Tool(name) => name,
    }
}

/// The actions whose keys were pressed this frame with exactly their modifiers; their key events
/// are consumed so no widget sees them too.
pub fn pressed(input: &mut egui::InputState) -> Vec<Action> {
    let mut actions = Vec::new();
    input.events.retain(|event| {
        let Event::Key { key, pressed: true, modifiers, .. } = event else { return true };
        match SHORTCUTS.iter().find(|s| s.key == *key && s.matches(*modifiers)) {
            Some(s) => {
                actions.push(s.action);
                false
            }
            None => true,
        }
    });
    actions
}

/// The digits, '.' (and '-' when `signed`) and Backspace typed while a gesture runs (a typed
/// distance, angle, factor or thickness), taken from the input into `typed`.
pub fn take_typed_number(input: &mut egui::InputState, typed: &mut String, signed: bool) {
    const KEYS: [(Key, char); 12] = [
        (Key::Num0, '0'),
        (Key::Num1, '1'),
        (Key::Num2, '2'),
        (Key::Num3, '3'),
        (Key::Num4, '4'),
        (Key::Num5, '5'),
        (Key::Num6, '6'),
        (Key::Num7, '7'),
        (Key::Num8, '8'),
        (Key::Num9, '9'),
        (Key::Period, '.'),
        (Key::Minus, '-'),
    ];
    // One frame may hold several keys (typed fast): they are applied in the order they came,
    // each press once, so "0", ".", "5" reads 0.5 and "5", "5" reads 55.
    input.events.retain(|event| {
        let Event::Key { key, pressed: true, modifiers, .. } = event else { return true };
        if modifiers.command || modifiers.shift || modifiers.alt {
            return true;
        }
        if *key == Key::Backspace {
            typed.pop();
            return false;
        }
        match KEYS.iter().find(|(k, c)| k == key && (signed || *c != '-')) {
            Some(&(_, c)) => {
                typed.push(c);
                false
            }
            None => true,
        }
    });
}

pub fn take_plain(input: &mut egui::InputState, key: Key) -> bool {
    let mut found = false;
    input.events.retain(|event| match event {
        Event::Key { key: k, pressed: true, modifiers, .. }
            if *k == key && !modifiers.command && !modifiers.shift && !modifiers.alt =>
        {
            found = true;
            false
        }
        _ => true,
    });
    found
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn no_two_shortcuts_share_a_key_and_modifiers() {
        for (i, a) in SHORTCUTS.iter().enumerate() {
            for b in &SHORTCUTS[i + 1..] {
                assert!(
                    !(a.key == b.key && a.command == b.command && a.shift == b.shift && a.alt == b.alt),
                    "{} is bound twice",
                    a.label()
                );
            }
        }
    }

    #[test]
    fn labels_name_the_modifiers() {
        assert_eq!(label(Action::Redo), "Ctrl+Shift+Z");
        assert_eq!(all_labels(Action::Redo), "Ctrl+Shift+Z or Ctrl+Y");
        assert_eq!(label(Action::SaveAs), "Ctrl+Shift+S");
        assert_eq!(label(Action::ViewTop), "7");
    }
}
