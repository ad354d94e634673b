//! The curves of a document: sketched or imported point sequences, log-aesthetic segments kept
//! with their three control points and α, and Coons patches built from four of them, with what
//! the Curves workspace showed when the file was saved.
//!
//! A [`CurveSet`] is saved in the `.taut` file under the optional key `curves` (absent: none).
//! A Coons patch keeps a copy of its four boundary polylines and its sampling, and, as a surface
//! with history in Alias does, which curves it was built from ([`CoonsPatch::sources`], the
//! optional key `sources`: their places in the list of curves). The editor rebuilds a patch from
//! its sources whenever they change and keeps the copy when they no longer meet; a deleted
//! source ends the patch's history ([`CurveSet::remove_curve`]), and the patch keeps the shape
//! it had. Files written before `sources` existed open with patches without history. The patch
//! is drawn as an extra surface beside the cage's own; the cage is left alone.
//!
//! Where it is weak: curves are polylines only (a segment is stored sampled, with its controls to
//! edit it again); sources are places in the list, so every removal of a curve must go through
//! [`CurveSet::remove_curve`], which renumbers them.

use crate::aesthetic::{AestheticSegment, BoundaryCurve, coons_patch, grid_mesh};
use crate::curve::PointSequence;
use crate::mesh::PolyMesh;
use crate::{DVec3, Error, Result};
use serde::{Deserialize, Serialize};

/// Most curves a document may hold.
pub const MAX_CURVES: usize = 10_000;
/// Most points of one curve.
pub const MAX_POINTS: usize = 1_000_000;
/// Most samples a side of a Coons patch.
pub const MAX_PATCH_SAMPLES: usize = 512;
/// Points a log-aesthetic segment is sampled at.
pub const SEGMENT_SAMPLES: usize = 101;

/// A log-aesthetic segment's controls: the ends, where their tangents meet, and α.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SegmentControls {
    /// Start point, tangent-intersection point, end point.
    pub controls: [[f64; 3]; 3],
    /// Slope of the curvature graph.
    pub alpha: f64,
}

impl SegmentControls {
    /// The three control points.
    pub fn points(&self) -> [DVec3; 3] {
        self.controls.map(DVec3::from_array)
    }

    /// The segment these controls make: `Ok(None)` when no log-aesthetic segment with this α
    /// has these control points, `Err` for unusable control points.
    pub fn segment(&self) -> Result<Option<AestheticSegment>> {
        let [p0, p1, p2] = self.points();
        AestheticSegment::from_control_points(p0, p1, p2, self.alpha)
    }

    /// The segment's samples, or none when no segment exists.
    pub fn sample(&self) -> Result<Vec<DVec3>> {
        Ok(self.segment()?.map(|s| s.sample(SEGMENT_SAMPLES)).unwrap_or_default())
    }
}

/// One curve of the document.
#[derive(Clone, Debug, PartialEq)]
pub struct DocCurve {
    /// What the designer calls it.
    pub name: String,
    /// The points, in order (empty only for a segment whose controls have no segment).
    pub points: Vec<DVec3>,
    /// True when the last point joins back to the first.
    pub closed: bool,
    /// For a log-aesthetic segment, its controls.
    pub segment: Option<SegmentControls>,
}

impl DocCurve {
    /// An open or closed curve through `points`.
    pub fn new(name: impl Into<String>, points: Vec<DVec3>, closed: bool) -> Self {
        DocCurve { name: name.into(), points, closed, segment: None }
    }

    /// A log-aesthetic segment from its controls (sampled; no points when none exists).
    pub fn segment(name: impl Into<String>, controls: SegmentControls) -> Result<Self> {
        Ok(DocCurve { name: name.into(), points: controls.sample()?, closed: false, segment: Some(controls) })
    }

    /// The points as a sequence.
    pub fn sequence(&self) -> PointSequence {
        PointSequence::new(self.points.clone(), self.closed)
    }

    fn validate(&self, which: usize) -> Result<()> {
        let bad = |m: String| Err(Error::Input(format!("curve {which} ('{}'): {m}", self.name)));
        if self.name.chars().count() > 200 {
            return bad("its name is longer than 200 characters".into());
        }
        if self.points.len() > MAX_POINTS {
            return bad(format!("{} points is more than the {MAX_POINTS} a curve may have", self.points.len()));
        }
        if let Some(s) = &self.segment {
            if self.closed {
                return bad("a log-aesthetic segment cannot be closed".into());
            }
            if let Err(e) = s.segment() {
                return bad(e.to_string());
            }
            if self.points.is_empty() {
                return Ok(());
            }
        }
        self.sequence().validate(2).or_else(|e| bad(e.to_string()))
    }
}

/// A bilinearly blended Coons patch, kept with its own boundaries.
#[derive(Clone, Debug, PartialEq)]
pub struct CoonsPatch {
    /// The four sides as a loop (each may run either way; see [`coons_patch`]).
    pub boundaries: [Vec<DVec3>; 4],
    /// Samples a side.
    pub samples: usize,
    /// The four curves the patch was built from (places in [`CurveSet::curves`]), which it
    /// follows; `None`: a patch without history.
    pub sources: Option<[usize; 4]>,
}

impl CoonsPatch {
    /// The patch as a quad mesh of `(samples + 1)²` vertices; `Err` when the sides do not meet.
    pub fn mesh(&self) -> Result<PolyMesh> {
        let sides = self.boundaries.clone().map(BoundaryCurve::Polyline);
        grid_mesh(&coons_patch(&sides, self.samples)?)
    }

    fn validate(&self, which: usize) -> Result<()> {
        if !(1..=MAX_PATCH_SAMPLES).contains(&self.samples) {
            return Err(Error::Input(format!(
                "Coons patch {which}: {} samples a side; use 1 to {MAX_PATCH_SAMPLES}",
                self.samples
            )));
        }
        if let Some(b) = self.boundaries.iter().find(|b| b.len() > MAX_POINTS) {
            return Err(Error::Input(format!("Coons patch {which}: a side has {} points, too many", b.len())));
        }
        // The sides checked as the patch checks them, on the coarsest grid: validation runs on
        // every edit of the document, and building the full mesh there would slow every drag.
        let sides = self.boundaries.clone().map(BoundaryCurve::Polyline);
        coons_patch(&sides, 1).map(|_| ()).map_err(|e| Error::Input(format!("Coons patch {which}: {e}")))
    }
}

/// Which workspace the editor showed.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Workspace {
    /// The cage and its surface.
    #[default]
    Surface,
    /// Curves, the filter, segments and Coons patches.
    Curves,
}

/// What the Curves workspace showed: saved with the file, not part of undo or of "unsaved".
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CurvesView {
    /// The workspace open when saved.
    #[serde(default)]
    pub workspace: Workspace,
    /// The selected curve.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub selected: Option<usize>,
}

/// The curves and Coons patches of a document.
#[derive(Clone, Debug, Default)]
pub struct CurveSet {
    /// The curves, in the order they were made.
    pub curves: Vec<DocCurve>,
    /// The Coons patches.
    pub patches: Vec<CoonsPatch>,
    /// What the workspace showed (not compared: it is no change of the design).
    pub view: CurvesView,
}

impl PartialEq for CurveSet {
    fn eq(&self, other: &Self) -> bool {
        self.curves == other.curves && self.patches == other.patches
    }
}

impl CurveSet {
    /// True without curves and patches.
    pub fn is_empty(&self) -> bool {
        self.curves.is_empty() && self.patches.is_empty()
    }

    /// Checks every curve and patch, and that the selected curve exists; messages name them.
    pub fn validate(&self) -> Result<()> {
        self.validate_content()?;
        if let Some(s) = self.view.selected.filter(|&s| s >= self.curves.len()) {
            return Err(Error::Input(format!("curve {s} is selected but there are {} curves", self.curves.len())));
        }
        Ok(())
    }

    /// Checks every curve and patch (not the view); messages name the curve or patch.
    pub fn validate_content(&self) -> Result<()> {
        if self.curves.len() > MAX_CURVES || self.patches.len() > MAX_CURVES {
            return Err(Error::Input(format!(
                "{} curves and {} patches: a document holds at most {MAX_CURVES} of each",
                self.curves.len(),
                self.patches.len()
            )));
        }
        self.curves.iter().enumerate().try_for_each(|(i, c)| c.validate(i))?;
        self.patches.iter().enumerate().try_for_each(|(i, p)| p.validate(i))?;
        for (i, p) in self.patches.iter().enumerate() {
            let Some(sources) = p.sources else { continue };
            if let Some(s) = sources.iter().find(|&&s| s >= self.curves.len()) {
                return Err(Error::Input(format!(
                    "Coons patch {i} was built from curve {s}, but there are {} curves",
                    self.curves.len()
                )));
            }
            if (0..4).any(|a| (a + 1..4).any(|b| sources[a] == sources[b])) {
                return Err(Error::Input(format!("Coons patch {i} names one curve twice among its four sources")));
            }
        }
        Ok(())
    }

    /// Removes curve `index`, renumbering the sources of the patches; the patches built from it
    /// lose their history and keep their shape. Returns those patches.
    pub fn remove_curve(&mut self, index: usize) -> Vec<usize> {
        if index >= self.curves.len() {
            return Vec::new();
        }
        self.curves.remove(index);
        let mut orphaned = Vec::new();
        for (k, patch) in self.patches.iter_mut().enumerate() {
            let Some(sources) = &mut patch.sources else { continue };
            if sources.contains(&index) {
                patch.sources = None;
                orphaned.push(k);
            } else {
                sources.iter_mut().filter(|s| **s > index).for_each(|s| *s -= 1);
            }
        }
        if let Some(s) = self.view.selected {
            self.view.selected = match s.cmp(&index) {
                std::cmp::Ordering::Less => Some(s),
                std::cmp::Ordering::Equal => None,
                std::cmp::Ordering::Greater => Some(s - 1),
            };
        }
        orphaned
    }

    /// The set as it is written in a `.taut` file (`None` when there is nothing to write).
    pub(crate) fn to_file(&self) -> Option<CurvesFile> {
        if self.is_empty() && self.view == CurvesView::default() {
            return None;
        }
        let points = |p: &[DVec3]| p.iter().map(|p| p.to_array()).collect();
        Some(CurvesFile {
            curves: self
                .curves
                .iter()
                .map(|c| CurveFile {
                    name: c.name.clone(),
                    points: points(&c.points),
                    closed: c.closed,
                    segment: c.segment,
                })
                .collect(),
            patches: self
                .patches
                .iter()
                .map(|p| PatchFile {
                    boundaries: p.boundaries.clone().map(|b| points(&b)),
                    samples: p.samples,
                    sources: p.sources,
                })
                .collect(),
            view: self.view,
        })
    }

    /// The set read from a `.taut` file, checked.
    pub(crate) fn from_file(file: CurvesFile) -> Result<Self> {
        let points = |p: Vec<[f64; 3]>| p.into_iter().map(DVec3::from_array).collect();
        let set = CurveSet {
            curves: file
                .curves
                .into_iter()
                .map(|c| DocCurve { name: c.name, points: points(c.points), closed: c.closed, segment: c.segment })
                .collect(),
            patches: file
                .patches
                .into_iter()
                .map(|p| CoonsPatch { boundaries: p.boundaries.map(points), samples: p.samples, sources: p.sources })
                .collect(),
            view: file.view,
        };
        set.validate()?;
        Ok(set)
    }
}

/// The `curves` key of a `.taut` file.
#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct CurvesFile {
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    curves: Vec<CurveFile>,
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    patches: Vec<PatchFile>,
    #[serde(default)]
    view: CurvesView,
}

#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct CurveFile {
    #[serde(default)]
    name: String,
    points: Vec<[f64; 3]>,
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    closed: bool,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    segment: Option<SegmentControls>,
}

#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct PatchFile {
    boundaries: [Vec<[f64; 3]>; 4],
    samples: usize,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    sources: Option<[usize; 4]>,
}

#[cfg(test)]
mod tests {
    use super::*;

    fn square_sides() -> [Vec<DVec3>; 4] {
        let c = [DVec3::ZERO, DVec3::X, DVec3::new(1.0, 1.0, 0.0), DVec3::Y];
        std::array::from_fn(|k| vec![c[k], c[k].lerp(c[(k + 1) % 4], 0.5), c[(k + 1) % 4]])
    }

    #[test]
    fn bad_curves_and_patches_are_named() {
        let mut set = CurveSet::default();
        set.curves.push(DocCurve::new("a", vec![DVec3::ZERO, DVec3::new(f64::NAN, 0.0, 0.0)], false));
        let e = set.validate().unwrap_err().to_string();
        assert!(e.contains("curve 0 ('a')") && e.contains("non-finite"), "{e}");
        set.curves[0].points[1] = DVec3::X;
        set.validate().unwrap();
        let mut sides = square_sides();
        sides[2][2] += DVec3::splat(0.5);
        set.patches.push(CoonsPatch { boundaries: sides, samples: 4, sources: None });
        let e = set.validate().unwrap_err().to_string();
        assert!(e.starts_with("Coons patch 0"), "{e}");
        set.patches[0] = CoonsPatch { boundaries: square_sides(), samples: 0, sources: None };
        assert!(set.validate().unwrap_err().to_string().contains("0 samples"));
        set.patches[0].samples = 3;
        set.view.selected = Some(4);
        assert!(set.validate().unwrap_err().to_string().contains("curve 4 is selected"));
    }

    #[test]
    fn a_segment_keeps_its_controls_and_has_points_only_where_it_exists() {
        // The middle point swept from near the start's side to near the end's: for α = 2 the
        // feasible band of start angles is narrow, so both outcomes occur.
        let (mut with, mut without) = (0, 0);
        for k in 1..20 {
            let x = k as f64 / 20.0;
            let controls = SegmentControls { controls: [[0.0, 0.0, 0.0], [x, 0.6, 0.0], [1.0, 0.0, 0.0]], alpha: 2.0 };
            let curve = DocCurve::segment("s", controls).unwrap();
            if curve.points.is_empty() {
                without += 1;
            } else {
                with += 1;
                assert!(curve.points[0].distance(DVec3::ZERO) < 1e-9);
                assert!(curve.points[curve.points.len() - 1].distance(DVec3::X) < 1e-9);
            }
            let set = CurveSet { curves: vec![curve], ..Default::default() };
            set.validate().unwrap();
        }
        assert!(with > 0 && without > 0, "{with} with a segment, {without} without");
    }

    #[test]
    fn curves_round_trip_through_the_taut_file_and_are_optional() {
        use crate::document::Document;
        use std::path::Path;
        let cage = crate::mesh::PolyMesh::from_polygons(vec![DVec3::ZERO, DVec3::X, DVec3::Y], &[[0, 1, 2]]).unwrap();
        let plain = Document::new(cage);
        let text = plain.to_json();
        assert!(!text.contains("\"curves\""), "an empty set is not written");
        let mut doc = plain.clone();
        let noisy: Vec<DVec3> =
            (0..7).map(|i| DVec3::new(i as f64 / 3.0, (0.1 * i as f64).sin() + 1e-17, 0.1)).collect();
        doc.curves.curves.push(DocCurve::new("sketch", noisy, false));
        let controls = SegmentControls { controls: [[0.0, 0.0, 0.0], [0.5, 0.5, 0.0], [1.0, 0.0, 0.0]], alpha: 1.0 };
        doc.curves.curves.push(DocCurve::segment("segment", controls).unwrap());
        doc.curves.patches.push(CoonsPatch { boundaries: square_sides(), samples: 3, sources: None });
        doc.curves.view = CurvesView { workspace: Workspace::Curves, selected: Some(1) };
        let text = doc.to_json();
        let back = Document::from_json(&text, Path::new("c.taut")).unwrap();
        assert_eq!(back, doc);
        assert_eq!(back.curves.view, doc.curves.view);
        assert_eq!(back.to_json(), text);
        assert_ne!(back, plain);
        let bad = text.replace("\"samples\": 3", "\"samples\": 3, \"extra\": 1");
        let e = Document::from_json(&bad, Path::new("c.taut")).unwrap_err().to_string();
        assert!(e.contains("unknown field"), "{e}");
        let bad = text.replace("\"samples\": 3", "\"samples\": 0");
        let e = Document::from_json(&bad, Path::new("c.taut")).unwrap_err().to_string();
        assert!(e.contains("Coons patch 0"), "{e}");
    }

    #[test]
    fn removing_a_curve_renumbers_the_sources_and_ends_the_history_of_its_patches() {
        let sides = square_sides();
        let mut set = CurveSet::default();
        set.curves.push(DocCurve::new("extra", vec![DVec3::ZERO, DVec3::Z], false));
        for (k, side) in sides.iter().enumerate() {
            set.curves.push(DocCurve::new(format!("side {k}"), side.clone(), false));
        }
        let patch = CoonsPatch { boundaries: sides.clone(), samples: 2, sources: Some([1, 2, 3, 4]) };
        set.patches.push(patch.clone());
        set.patches.push(CoonsPatch { sources: None, ..patch });
        set.view.selected = Some(3);
        set.validate().unwrap();
        assert_eq!(set.remove_curve(0), Vec::<usize>::new());
        assert_eq!(set.patches[0].sources, Some([0, 1, 2, 3]));
        assert_eq!(set.view.selected, Some(2));
        assert_eq!(set.remove_curve(2), vec![0]);
        assert_eq!((set.patches[0].sources, set.view.selected), (None, None));
        assert_eq!(set.patches[0].boundaries, sides, "the patch keeps its shape");
        set.validate().unwrap();
        // Sources that name no curve or one curve twice are refused, and round-trip when valid.
        set.patches[1].sources = Some([0, 1, 2, 5]);
        assert!(set.validate().unwrap_err().to_string().contains("built from curve 5"));
        set.patches[1].sources = Some([0, 1, 1, 2]);
        assert!(set.validate().unwrap_err().to_string().contains("twice"));
        set.patches[1].sources = Some([2, 1, 0, 2]);
        assert!(set.validate().is_err());
        set.patches[1].sources = Some([2, 1, 0, 1]);
        assert!(set.validate().is_err());
        set.curves.push(DocCurve::new("fourth", vec![DVec3::ZERO, DVec3::Y], false));
        set.patches[1].sources = Some([3, 1, 0, 2]);
        let file = serde_json::to_string(&set.to_file().unwrap()).unwrap();
        assert!(file.contains("\"sources\":[3,1,0,2]"), "{file}");
        let back = CurveSet::from_file(serde_json::from_str(&file).unwrap()).unwrap();
        assert_eq!(back, set);
    }
}
