//! One interface for every way Taut makes a surface from a cage: the seam the editor, `taut
//! render`, the exports and the command line use, whatever the scheme.
//!
//! A [`SurfaceScheme`] takes the document's changes ([`update`](SurfaceScheme::update), cheap
//! when only positions moved), does its work within a budget ([`advance`](SurfaceScheme::advance):
//! NUSD iterates towards its fixed point over many calls, the subdivision schemes finish in one),
//! and gives the surface to draw and export: a mesh whose first vertices are the cage's, exact
//! per-vertex normals where the scheme has them (limit normals, analytic patch normals), the
//! surface's curves along the cage edges, and named per-vertex fields (NUSD's |R|).
//!
//! The schemes: [`nusd`] (nonuniform spline diffusion, interpolating the fixed cage vertices),
//! [`subdivision`] (Catmull–Clark and Loop with creases, the exact limit surface),
//! [`curve_mesh`] (a curve mesh on the Catmull–Clark limit surface filled with G1 Gregory
//! patches, with its edits). [`build`] makes the one a document asks for.

pub mod curve_mesh;
pub mod distance;
pub mod nusd;
pub mod subdivision;

use crate::document::Document;
use crate::mesh::PolyMesh;
use crate::{DVec3, Error, Result};

pub use crate::nusd::surface::{Budget, Phase};

pub use crate::document::{SchemeKind, SubdivSettings};

/// Where a scheme's work stands, for the status bar and for knowing when to redraw.
#[derive(Clone, Debug, PartialEq)]
pub struct Progress {
    pub phase: Phase,
    /// True when the surface is what the scheme promises (NUSD: every level converged).
    pub converged: bool,
    /// A short line for the status bar, e.g. "level 3/3  iterations 214  converged".
    pub summary: String,
    /// Grows with every unit of work since the last edit (an iteration, an evaluation), so a
    /// caller can tell whether the surface changed since it last looked.
    pub work: usize,
}

/// A per-vertex scalar a scheme offers for colouring (NUSD's |R|).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct FieldInfo {
    /// The key on the command line (`--view r`) and in the editor's state.
    pub key: &'static str,
    /// What the legend and the menus call it.
    pub title: &'static str,
}

/// What the colour view shows: a curvature of the drawn surface, a field of its scheme, or the
/// distance to another surface (the editor's compare view).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum ColourBy {
    Curvature(crate::curvature::CurvatureQuantity),
    Field(FieldInfo),
    Distance,
}

impl ColourBy {
    /// True for signed values (a diverging map centred at 0).
    pub fn is_signed(self) -> bool {
        match self {
            ColourBy::Curvature(q) => q.is_signed(),
            ColourBy::Field(_) | ColourBy::Distance => false,
        }
    }

    /// The name for menus.
    pub fn display_name(self) -> &'static str {
        match self {
            ColourBy::Curvature(q) => q.display_name(),
            ColourBy::Field(f) => f.title,
            ColourBy::Distance => "distance to the other scheme",
        }
    }

    /// Reads a command-line view name: a curvature (`mean`, `gaussian`, `kmin`, `kmax`, `kabs`)
    /// or a field key of `scheme` (`r` for NUSD).
    pub fn parse(name: &str, scheme: SchemeKind) -> Result<ColourBy> {
        if let Ok(q) = name.parse::<crate::curvature::CurvatureQuantity>() {
            return Ok(ColourBy::Curvature(q));
        }
        match fields_of(scheme).iter().find(|f| f.key == name) {
            Some(f) => Ok(ColourBy::Field(*f)),
            None => Err(Error::Input(format!(
                "'{name}' is not a view of the {} scheme: use mean, gaussian, kmin, kmax, kabs{}",
                scheme.display_name(),
                fields_of(scheme).iter().map(|f| format!(" or {} ({})", f.key, f.title)).collect::<String>()
            ))),
        }
    }

    /// The values of `self` on `surface` (its curvature estimated on its mesh).
    pub fn values(self, surface: &dyn SurfaceScheme) -> Result<Vec<f64>> {
        match self {
            ColourBy::Curvature(q) => Ok(crate::curvature::vertex_curvature(surface.mesh()).values(q)),
            ColourBy::Field(f) => surface.field(f.key).ok_or_else(|| {
                Error::Input(format!("the {} surface has no {}", surface.kind().display_name(), f.title))
            }),
            ColourBy::Distance => Err(Error::Input("the distance view needs a second surface to compare with".into())),
        }
    }
}

/// The fields a scheme offers (for choosing a view before a surface is built).
pub fn fields_of(scheme: SchemeKind) -> &'static [FieldInfo] {
    match scheme {
        SchemeKind::Nusd => nusd::FIELDS,
        SchemeKind::CatmullClark | SchemeKind::Loop => &[],
        SchemeKind::CurveMesh => curve_mesh::FIELDS,
    }
}

/// One way of making a surface from a document; see the [module docs](self).
pub trait SurfaceScheme: std::fmt::Debug + Send {
    /// Which scheme this is.
    fn kind(&self) -> SchemeKind;
    /// Takes the document as it is now: rebuilds what changed (a changed connectivity rebuilds
    /// all, a drag only re-evaluates positions). An error leaves the last good surface.
    fn update(&mut self, doc: &Document) -> Result<()>;
    /// Does work within `budget`.
    fn advance(&mut self, budget: Budget) -> Progress;
    /// Where the work stands, without doing any.
    fn progress(&self) -> Progress;
    /// The messages of the latest work (λ reduced, divergence), taken once.
    fn take_events(&mut self) -> Vec<String>;
    /// The surface: cage vertex `i` is vertex `i` (or its limit point).
    fn mesh(&self) -> &PolyMesh;
    /// Exact unit normals per vertex of [`mesh`](Self::mesh), where the scheme has them.
    fn normals(&self) -> Option<&[DVec3]>;
    /// The surface's curves along the cage edges, one point list per edge, in edge order.
    fn curves(&self) -> Vec<Vec<DVec3>>;
    /// The per-vertex fields this scheme offers.
    fn fields(&self) -> &'static [FieldInfo];
    /// A field's values, one per vertex of [`mesh`](Self::mesh).
    fn field(&self, key: &str) -> Option<Vec<f64>>;
    /// What the latest work did, a line each (the command line prints them).
    fn report(&self) -> Vec<String>;
    /// The curve-mesh scheme, for what only it has (its curves, vertices and patches to edit).
    fn as_curve_mesh(&self) -> Option<&curve_mesh::CurveMeshSurface> {
        None
    }
}

/// The scheme a document asks for, built for it (nothing advanced yet).
pub fn build(doc: &Document) -> Result<Box<dyn SurfaceScheme>> {
    Ok(match doc.scheme {
        SchemeKind::Nusd => Box::new(nusd::NusdSurface::new(doc)?),
        SchemeKind::CatmullClark | SchemeKind::Loop => Box::new(subdivision::SubdivSurface::new(doc, true)?),
        SchemeKind::CurveMesh => Box::new(curve_mesh::CurveMeshSurface::new(doc)?),
    })
}

/// Builds the document's scheme and works it to the end: the surface the command line writes.
pub fn solve(doc: &Document) -> Result<Box<dyn SurfaceScheme>> {
    let mut surface = build(doc)?;
    let progress = surface.advance(Budget::UNLIMITED);
    if progress.phase == Phase::Diverged {
        let events = surface.take_events().join("; ");
        return Err(Error::Solver(format!("the surface could not be computed: {events}")));
    }
    Ok(surface)
}
