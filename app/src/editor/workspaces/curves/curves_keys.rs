//! The keys of the Curves workspace, read before the editor's shortcut table
//! ([`crate::editor::shortcuts`]) while that workspace is open and listed in Help ▸ Keyboard shortcuts.
//!
//! They reuse keys the cage modelling binds in the Surface workspace (Delete deletes cage
//! elements there): in the Curves workspace those cage actions do nothing
//! ([`crate::editor::shortcuts::Action::acts_on_the_cage`]), and this table gives the key its meaning
//! here. Modifiers match exactly, as in the main table.

use crate::editor::state::EditorState;
use egui::{Event, Key};

/// What a Curves-workspace key does.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CurveKeyAction {
    /// Delete the selected curve or Coons patch.
    DeleteSelected,
}

/// A plain key of the Curves workspace (no Ctrl, Shift or Alt).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct CurveKey {
    pub key: Key,
    pub action: CurveKeyAction,
    pub describe: &'static str,
}

/// Every key of the Curves workspace, in the order Help lists them.
pub const CURVE_KEYS: &[CurveKey] = &[CurveKey {
    key: Key::Delete,
    action: CurveKeyAction::DeleteSelected,
    describe: "Curves workspace: delete the selected curve or Coons patch",
}];

/// The Curves-workspace actions pressed this frame, their key events consumed so that the main
/// table does not see them.
pub fn pressed(input: &mut egui::InputState) -> Vec<CurveKeyAction> {
    let mut actions = Vec::new();
    input.events.retain(|event| {
        let Event::Key { key, pressed: true, modifiers, .. } = event else { return true };
        if modifiers.command || modifiers.shift || modifiers.alt {
            return true;
        }
        match CURVE_KEYS.iter().find(|k| k.key == *key) {
            Some(k) => {
                actions.push(k.action);
                false
            }
            None => true,
        }
    });
    actions
}

/// The rows Help adds for the Curves workspace: (key, what it does).
pub fn help_rows() -> impl Iterator<Item = (&'static str, &'static str)> {
    CURVE_KEYS.iter().map(|k| (crate::editor::shortcuts::key_name(k.key), k.describe))
}

impl EditorState {
    /// Runs a Curves-workspace key.
    pub(crate) fn run_curve_key(&mut self, action: CurveKeyAction) {
        match action {
            CurveKeyAction::DeleteSelected => self.delete_selected_curve_item(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::editor::shortcuts;

    #[test]
    fn curve_keys_are_bound_once_and_only_over_cage_actions() {
        // A key of this table either is free in the main table or does a cage action there,
        // which the Curves workspace switches off: so no key means two things at once.
        for (i, a) in CURVE_KEYS.iter().enumerate() {
            assert!(CURVE_KEYS[i + 1..].iter().all(|b| b.key != a.key), "{:?} is bound twice", a.key);
            let main = shortcuts::SHORTCUTS.iter().find(|s| s.key == a.key && !s.command && !s.shift && !s.alt);
            assert!(main.is_none_or(|s| s.action.acts_on_the_cage()), "{:?} also does {:?}", a.key, main);
        }
    }
}
