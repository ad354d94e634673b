//! Catmull–Clark and Loop behind the surface seam: the exact limit surface of a creased cage.
//!
//! The [`Refinement`] (topology, crease sharpness down the levels, stencils and limit stencils)
//! is built when the cage's connectivity, its creases, the scheme or the number of levels change;
//! a drag only re-evaluates the positions that read a moved cage vertex ([`Refinement::update`]).
//! The surface shown is the finest level with its vertices moved to their limit positions and the
//! exact limit normals, so zebra stripes show the limit surface itself; with `limit` off (the
//! command line's `taut subdivide` without `--limit`) it is the plain refined mesh, as Blender's
//! subdivision modifier gives it.

use super::{Budget, FieldInfo, Phase, Progress, SchemeKind, SurfaceScheme};
use crate::document::Document;
use crate::mesh::PolyMesh;
use crate::subdiv::{RefinedPositions, Refinement, Scheme};
use crate::{DVec3, Error, Result};

/// What a refinement was built for: a change of any of it rebuilds.
#[derive(Clone, Debug, PartialEq)]
struct Built {
    kind: SchemeKind,
    topology: u64,
    polygons: Vec<Vec<u32>>,
    crease: Vec<f64>,
    corner: Vec<f64>,
    levels: u32,
}

/// Catmull–Clark or Loop as a [`SurfaceScheme`].
#[derive(Debug)]
pub struct SubdivSurface {
    limit: bool,
    built: Built,
    refinement: Refinement,
    positions: RefinedPositions,
    mesh: PolyMesh,
    evaluations: usize,
}

fn scheme_of(kind: SchemeKind) -> Result<Scheme> {
    match kind {
        SchemeKind::CatmullClark => Ok(Scheme::CatmullClark),
        SchemeKind::Loop => Ok(Scheme::Loop),
        other => Err(Error::Input(format!("{} is not a subdivision scheme", other.display_name()))),
    }
}

impl SubdivSurface {
    /// The refinement of a document's cage by its subdivision scheme, evaluated; `limit` shows
    /// the limit surface (positions and normals), otherwise the plain finest level.
    pub fn new(doc: &Document, limit: bool) -> Result<Self> {
        doc.check_scheme(doc.scheme)?;
        let built = Built {
            kind: doc.scheme,
            topology: doc.cage.topology_generation(),
            polygons: doc.cage.polygons(),
            crease: doc.crease.clone(),
            corner: doc.corner.clone(),
            levels: doc.subdiv.levels,
        };
        let refinement =
            Refinement::with_corners(&doc.cage, scheme_of(doc.scheme)?, &doc.crease, &doc.corner, doc.subdiv.levels)?;
        let mut positions = RefinedPositions::default();
        refinement.evaluate(doc.cage.positions(), &mut positions)?;
        let shown = if limit { &positions.limit } else { positions.finest() };
        let mesh = refinement.surface(shown);
        Ok(SubdivSurface { limit, built, refinement, positions, mesh, evaluations: 1 })
    }

    /// The refinement (levels, stencils, the chains along cage edges).
    pub fn refinement(&self) -> &Refinement {
        &self.refinement
    }

    fn show(&mut self) {
        let shown = if self.limit { &self.positions.limit } else { self.positions.finest() };
        self.mesh.positions_mut().copy_from_slice(shown);
        self.evaluations += 1;
    }
}

impl SurfaceScheme for SubdivSurface {
    fn kind(&self) -> SchemeKind {
        self.built.kind
    }

    fn update(&mut self, doc: &Document) -> Result<()> {
        let same = doc.scheme == self.built.kind
            && doc.subdiv.levels == self.built.levels
            && doc.crease == self.built.crease
            && doc.corner == self.built.corner
            && (doc.cage.topology_generation() == self.built.topology || doc.cage.polygons() == self.built.polygons);
        if !same {
            *self = SubdivSurface::new(doc, self.limit)?;
            return Ok(());
        }
        if doc.cage.positions() != self.positions.levels.first().map_or(&[][..], |p| p) {
            self.refinement.update(doc.cage.positions(), &mut self.positions)?;
            self.show();
        }
        Ok(())
    }

    fn advance(&mut self, _budget: Budget) -> Progress {
        self.progress()
    }

    fn progress(&self) -> Progress {
        let levels = self.refinement.level_count();
        let faces = self.mesh.face_count();
        let what = if self.limit { "limit surface" } else { "refined mesh" };
        Progress {
            phase: Phase::Done,
            converged: true,
            summary: format!("{} level {levels}: {faces} faces, {what}", self.built.kind.display_name()),
            work: self.evaluations,
        }
    }

    fn take_events(&mut self) -> Vec<String> {
        Vec::new()
    }

    fn mesh(&self) -> &PolyMesh {
        &self.mesh
    }

    fn normals(&self) -> Option<&[DVec3]> {
        self.limit.then_some(&self.positions.normals[..])
    }

    fn curves(&self) -> Vec<Vec<DVec3>> {
        let levels = self.refinement.level_count();
        let positions = self.mesh.positions();
        let cage = self.refinement.mesh(0);
        cage.edges()
            .map(|e| {
                self.refinement
                    .cage_edge_chain(e, levels)
                    .map(|chain| chain.iter().map(|v| positions[v.index()]).collect())
                    .unwrap_or_default()
            })
            .collect()
    }

    fn fields(&self) -> &'static [FieldInfo] {
        &[]
    }

    fn field(&self, _key: &str) -> Option<Vec<f64>> {
        None
    }

    fn report(&self) -> Vec<String> {
        (0..=self.refinement.level_count())
            .map(|l| {
                let m = self.refinement.mesh(l);
                format!("level {l}: {} vertices, {} faces", m.vertex_count(), m.face_count())
            })
            .chain(std::iter::once(self.progress().summary))
            .collect()
    }
}
