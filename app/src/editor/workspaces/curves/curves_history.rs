//! Coons patches built from four picked curves ([`EditorState::build_coons`]: the sides ordered
//! into a loop, each may run either way, ends that nearly meet snapped), drawn as one mesh
//! ([`EditorState::patches_mesh`]), and with history, as surfaces built from curves are in
//! Alias: a patch keeps which four curves it was built from ([`CoonsPatch::sources`]) and is rebuilt from them whenever they
//! change: on every edit of the curves (a committed filter run, a segment's control point dragged
//! or its α slid, each frame of the drag), and live while the filter runs on one of them (the
//! viewport draws the patch from the running filter's points). The rebuild orders and snaps the
//! sides exactly as building the patch did ([`loop_of_sides`]).
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

use crate::editor::curves::SNAP_FRACTION;
use crate::editor::state::EditorState;
use taut_core::curve::{CoonsPatch, CurveSet};
use taut_core::{DVec3, PolyMesh};

/// The boundaries a patch built from `sources` gets from these curve points, checked by building
/// its mesh; `Err` says why not, in one line.
pub(crate) fn boundaries_from(
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
pub(crate) fn follow_sources(set: &mut CurveSet, old: &CurveSet) -> Option<String> {
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
    pub(crate) fn shown_patch(&self, k: usize) -> CoonsPatch {
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

impl EditorState {
    /// Builds a Coons patch from the four picked curves (snapping ends that nearly meet).
    pub fn build_coons(&mut self) {
        let picked = self.curves.picked.clone();
        let Ok(sources) = <[usize; 4]>::try_from(picked.as_slice()) else {
            self.notify(format!("pick four curves for a Coons patch ({} picked)", picked.len()), true);
            return;
        };
        let set = self.curve_set();
        if sources.iter().any(|&s| s >= set.curves.len()) || (1..4).any(|a| sources[..a].contains(&sources[a])) {
            self.notify("pick four different curves for a Coons patch", true);
            return;
        }
        let samples = self.curves.patch_samples;
        let built = crate::editor::curves_history::boundaries_from(
            |i| set.curves[i].points.clone(),
            sources,
            samples,
            |i| set.curves[i].name.clone(),
        );
        match built {
            Ok(boundaries) => {
                let patch = CoonsPatch { boundaries, samples, sources: Some(sources) };
                let mut set = self.curve_set().clone();
                set.patches.push(patch);
                self.set_curves(set);
                self.curves.picked.clear();
                self.notify("built a Coons patch from the four curves", false);
            }
            Err(e) => self.notify(format!("cannot build the Coons patch: {e}"), true),
        }
    }

    /// Every Coons patch of the document as one mesh (for the viewport), if there are any.
    pub fn patches_mesh(&self) -> Option<PolyMesh> {
        let mut positions = Vec::new();
        let mut faces: Vec<Vec<u32>> = Vec::new();
        for k in 0..self.curve_set().patches.len() {
            let Ok(mesh) = self.shown_patch(k).mesh() else { continue };
            let offset = positions.len() as u32;
            positions.extend_from_slice(mesh.positions());
            faces.extend(mesh.polygons().into_iter().map(|f| f.into_iter().map(|v| v + offset).collect()));
        }
        if faces.is_empty() { None } else { PolyMesh::from_polygons(positions, &faces).ok() }
    }
}

/// Orders four curves into a loop (each may run either way) and snaps ends that nearly meet.
pub(crate) fn loop_of_sides(mut sides: Vec<Vec<DVec3>>) -> Result<[Vec<DVec3>; 4], String> {
    let all: Vec<DVec3> = sides.iter().flatten().copied().collect();
    let size = taut_core::mesh::bounding_box(&all).map_or(0.0, |(lo, hi)| lo.distance(hi));
    let tolerance = SNAP_FRACTION * size;
    let ends = |s: &Vec<DVec3>| (s[0], s[s.len() - 1]);
    let mut ordered = vec![sides.remove(0)];
    while !sides.is_empty() {
        let tail = ends(ordered.last().expect("one side at least")).1;
        // The side with the end nearest the loop's tail, turned to start there.
        let (k, reversed, d) = sides
            .iter()
            .enumerate()
            .flat_map(|(k, s)| {
                let (a, b) = ends(s);
                [(k, false, a.distance(tail)), (k, true, b.distance(tail))]
            })
            .min_by(|x, y| x.2.total_cmp(&y.2))
            .expect("sides left");
        if d > tolerance {
            return Err(format!(
                "the curves do not meet: an end is {d:.3} from the nearest other end (at most {tolerance:.3}); \
                 draw or move them so that they form a loop"
            ));
        }
        let mut s = sides.remove(k);
        if reversed {
            s.reverse();
        }
        ordered.push(s);
    }
    let closing = ends(&ordered[3]).1.distance(ends(&ordered[0]).0);
    if closing > tolerance {
        return Err(format!("the four curves do not close into a loop (a gap of {closing:.3})"));
    }
    // Each corner: the mean of the two ends that meet there; each side bent linearly along its
    // arc length onto its two corners.
    let corners: Vec<DVec3> = (0..4).map(|k| 0.5 * (ends(&ordered[(k + 3) % 4]).1 + ends(&ordered[k]).0)).collect();
    for (k, side) in ordered.iter_mut().enumerate() {
        let (a, b) = ends(side);
        let (da, db) = (corners[k] - a, corners[(k + 1) % 4] - b);
        let arc = taut_core::curve::sequence::arc_lengths(side);
        let total = arc[arc.len() - 1].max(f64::MIN_POSITIVE);
        for (p, s) in side.iter_mut().zip(&arc) {
            let t = s / total;
            *p += (1.0 - t) * da + t * db;
        }
        let last = side.len() - 1;
        side[0] = corners[k];
        side[last] = corners[(k + 1) % 4];
    }
    let [a, b, c, d]: [Vec<DVec3>; 4] = ordered.try_into().expect("four sides");
    Ok([a, b, c, d])
}

#[cfg(test)]
#[path = "curves_history_tests.rs"]
mod tests;
