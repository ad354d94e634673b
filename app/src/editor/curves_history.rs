//! Coons patches with history, as surfaces built from curves are in Alias: a patch keeps which
//! four curves it was built from ([`CoonsPatch::sources`]) and is rebuilt from them whenever they
//! change: on every edit of the curves (a committed filter run, a segment's control point dragged
//! or its α slid, each frame of the drag), and live while the filter runs on one of them (the
//! viewport draws the patch from the running filter's points). The rebuild orders and snaps the
//! sides exactly as building the patch did ([`super::curves`]' loop of sides).
//!
//! When the sources no longer meet (a corner pulled apart by more than the snap), the patch keeps
//! its last shape and its history, and the notice strip says so: pulling the curve back makes it
//! follow again. Deleting a source ends the history ([`taut_core::curve::CurveSet::remove_curve`]);
//! the patch keeps the shape it had and the notice strip names the curve. Undo restores curves and
//! patches together (they are one document snapshot).
//!
//! Where it is weak: a rebuild resamples the whole patch from its sides, so a patch on curves of
//! many points costs its full Coons evaluation on every frame of a drag; the patch follows the
//! curves' points only, never the other way (editing a patch does not move its curves).

use super::curves::loop_of_sides;
use super::state::EditorState;
use taut_core::DVec3;
use taut_core::curve::{CoonsPatch, CurveSet};

/// The boundaries a patch built from `sources` gets from these curve points, checked by building
/// its mesh; `Err` says why not, in one line.
pub(super) fn boundaries_from(
    points: impl Fn(usize) -> Vec<DVec3>,
    sources: [usize; 4],
    samples: usize,
    names: impl Fn(usize) -> String,
) -> Result<[Vec<DVec3>; 4], String> {
    let sides: Vec<Vec<DVec3>> = sources.iter().map(|&i| points(i)).collect();
    if let Some(k) = sides.iter().position(|s| s.len() < 2) {
        return Err(format!("curve '{}' has no points (no such segment)", names(sources[k])));
    }
    let boundaries = loop_of_sides(sides)?;
    let patch = CoonsPatch { boundaries, samples, sources: Some(sources) };
    patch.mesh().map_err(|e| e.to_string())?;
    Ok(patch.boundaries)
}

/// Rebuilds the patches of `set` whose source curves differ from those of `old`; returns a
/// one-line notice for the patches that keep their last shape because their curves no longer
/// make one.
pub(super) fn follow_sources(set: &mut CurveSet, old: &CurveSet) -> Option<String> {
    let mut kept = Vec::new();
    for k in 0..set.patches.len() {
        let patch = &set.patches[k];
        let Some(sources) = patch.sources else { continue };
        if sources.iter().any(|&s| s >= set.curves.len()) {
            continue;
        }
        let unchanged = sources.iter().all(|&s| old.curves.get(s).map(|c| &c.points) == Some(&set.curves[s].points))
            && old.patches.get(k).is_some_and(|p| p.sources == patch.sources);
        if unchanged {
            continue;
        }
        let curves = &set.curves;
        match boundaries_from(|i| curves[i].points.clone(), sources, patch.samples, |i| curves[i].name.clone()) {
            Ok(boundaries) => set.patches[k].boundaries = boundaries,
            Err(e) => kept.push(format!("Coons patch {} keeps its last shape ({e})", k + 1)),
        }
    }
    (!kept.is_empty()).then(|| kept.join("; "))
}

impl EditorState {
    /// The boundaries patch `k` is drawn with now: rebuilt from the running filter's points when
    /// it runs on one of the patch's sources (and they still make a patch), else the patch's own.
    pub(super) fn shown_patch(&self, k: usize) -> CoonsPatch {
        let set = self.curve_set();
        let patch = set.patches[k].clone();
        let (Some(run), Some(sources)) = (&self.curves.run, patch.sources) else { return patch };
        if !sources.contains(&run.curve) || sources.iter().any(|&s| s >= set.curves.len()) {
            return patch;
        }
        let points = |i: usize| self.shown_points(i).to_vec();
        match boundaries_from(points, sources, patch.samples, |i| set.curves[i].name.clone()) {
            Ok(boundaries) => CoonsPatch { boundaries, ..patch },
            Err(_) => patch,
        }
    }
}

#[cfg(test)]
#[path = "curves_history_tests.rs"]
mod tests;
