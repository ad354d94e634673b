//! The curve mesh behind the surface seam: the document's curve mesh ([`crate::gregory`], built
//! from the cage, with the document's curve-mesh edits) tessellated into one crack-free mesh with
//! the patches' exact normals, so zebra stripes show the Gregory patches themselves and run on
//! across every curve (the patches meet with G1 there and share the boundary vertices).
//!
//! Incremental: when only the curve-mesh edits changed, the new edit state is set on the curve
//! mesh ([`CurveMesh::set_edits`], which rebuilds only the patches whose inputs changed) and only
//! the vertices of those patches are re-tessellated ([`Tessellation::update`]); when the cage's
//! points moved, the curve mesh is rebuilt (the document's, from its cache when the edit that moved
//! them built it) and again only the patches that differ bit for bit are re-tessellated; a new
//! topology tessellates everything. Every path gives the values of a fresh build exactly.
//!
//! The drawn mesh: curve-mesh vertex `v` is vertex `v` (cage vertex `i` is curve-mesh vertex `i`),
//! then the samples along the curves, then the patch interiors ([`Tessellation`]). Each patch is
//! sampled 16 × 16, fewer where the patches would make more than [`MAX_SEAM_QUADS`] quads. The
//! curves along the cage edges are the Bézier curves (two per cage edge when the cage was
//! subdivided once first). The scheme offers no per-vertex field: what a designer checks on a
//! curve mesh is the continuity across the curves, which the editor draws on the curves
//! themselves (a per-vertex field would be zero off them).

use super::{Budget, FieldInfo, Phase, Progress, SchemeKind, SurfaceScheme};
use crate::document::Document;
use crate::gregory::build::BuildReport;
use crate::gregory::continuity::DEFAULT_BOUNDARY_SAMPLES;
use crate::gregory::tessellate::DEFAULT_SAMPLES;
use crate::gregory::{Changed, CurveMesh, Tessellation};
use crate::mesh::{EdgeId, FaceId, HalfedgeId, PolyMesh, VertexId};
use crate::{DVec3, Error, Result};
use std::sync::Arc;
use std::sync::atomic::{AtomicU64, Ordering};

pub(super) const FIELDS: &[FieldInfo] = &[];

/// Most quads the seam tessellates: beyond it each patch gets fewer than 16 × 16 samples.
pub const MAX_SEAM_QUADS: usize = 1 << 22;

static NEXT_ID: AtomicU64 = AtomicU64::new(1);

/// The curve mesh as a [`SurfaceScheme`].
#[derive(Debug)]
pub struct CurveMeshSurface {
    cage_topology: u64,
    cage_polygons: Vec<Vec<u32>>,
    cage_positions: Vec<DVec3>,
    curves: CurveMesh,
    report: Arc<BuildReport>,
    tessellation: Tessellation,
    /// Per cage edge, the curve-mesh halfedges along it from its first vertex to its second.
    edge_curves: Vec<Vec<HalfedgeId>>,
    /// What the latest update changed; `None` after a build (everything).
    last_changed: Option<Changed>,
    updates: u64,
    id: u64,
}

/// Samples per patch side for `patches` patches: 16, or fewer to stay within [`MAX_SEAM_QUADS`].
pub fn samples_for(patches: usize) -> usize {
    let mut k = DEFAULT_SAMPLES;
    while k > 1 && patches.saturating_mul(k * k) > MAX_SEAM_QUADS {
        k -= 1;
    }
    k
}

impl CurveMeshSurface {
    /// The document's curve mesh (with its edits), tessellated.
    pub fn new(doc: &Document) -> Result<Self> {
        let (mesh, report) = doc.curve_mesh()?;
        let curves = (*mesh).clone();
        let tessellation = Tessellation::new(&curves, samples_for(curves.patch_count()))?;
        let edge_curves = edge_curves(&doc.cage, &curves)?;
        Ok(CurveMeshSurface {
            cage_topology: doc.cage.topology_generation(),
            cage_polygons: doc.cage.polygons(),
            cage_positions: doc.cage.positions().to_vec(),
            curves,
            report,
            tessellation,
            edge_curves,
            last_changed: None,
            updates: 0,
            id: NEXT_ID.fetch_add(1, Ordering::Relaxed),
        })
    }

    /// The curve mesh drawn (with the document's edits).
    pub fn curve_mesh(&self) -> &CurveMesh {
        &self.curves
    }
    /// Its tessellation.
    pub fn tessellation(&self) -> &Tessellation {
        &self.tessellation
    }
    /// The figures of the curve mesh's build from the cage.
    pub fn build_report(&self) -> &BuildReport {
        &self.report
    }
    /// What the latest update changed (`None` right after a build: everything).
    pub fn last_changed(&self) -> Option<&Changed> {
        self.last_changed.as_ref()
    }
    /// Counts the updates that changed something since the build.
    pub fn updates(&self) -> u64 {
        self.updates
    }
    /// Unique per build: a new id means everything may have changed.
    pub fn id(&self) -> u64 {
        self.id
    }
    /// The curve-mesh halfedges along cage edge `e`, from its first vertex to its second.
    pub fn curves_along_cage_edge(&self, e: EdgeId) -> &[HalfedgeId] {
        self.edge_curves.get(e.index()).map_or(&[], |c| c)
    }

    fn apply(&mut self, changed: Changed) -> Result<()> {
        if changed.patches.is_empty() && changed.vertices.is_empty() {
            return Ok(());
        }
        self.tessellation.update(&self.curves, &changed)?;
        self.last_changed = Some(changed);
        self.updates += 1;
        Ok(())
    }
}

/// Per cage edge, the curve-mesh halfedges along it: the edge itself when the curve mesh has the
/// cage's topology, else its two halves through its edge point (curve-mesh vertex
/// `cage vertices + e`, [`crate::subdiv::SplitTopology`]'s numbering).
fn edge_curves(cage: &PolyMesh, curves: &CurveMesh) -> Result<Vec<Vec<HalfedgeId>>> {
    let t = curves.topology();
    if t.vertex_count() == cage.vertex_count() {
        return Ok(cage.edges().map(|e| vec![e.halfedge(0)]).collect());
    }
    cage.edges()
        .map(|e| {
            let (a, b) = cage.edge_vertices(e);
            let m = VertexId((cage.vertex_count() + e.index()) as u32);
            match (t.find_halfedge(a, m), t.find_halfedge(m, b)) {
                (Some(h0), Some(h1)) => Ok(vec![h0, h1]),
                _ => Err(Error::Topology(format!("cage edge {} has no curves along it in its curve mesh", e.0))),
            }
        })
        .collect()
}

fn bits(p: DVec3) -> [u64; 3] {
    p.to_array().map(f64::to_bits)
}

/// The patches and vertices of `new` that differ from `old`'s bit for bit (same topology).
fn differences(old: &CurveMesh, new: &CurveMesh) -> Changed {
    let patches = (0..new.patch_count() as u32)
        .map(FaceId)
        .filter(|&f| old.patch(f).control_points().map(bits) != new.patch(f).control_points().map(bits))
        .collect();
    let vertices = new
        .topology()
        .vertices()
        .filter(|&v| {
            bits(old.vertex_position(v)) != bits(new.vertex_position(v))
                || bits(old.vertex_normal(v)) != bits(new.vertex_normal(v))
        })
        .collect();
    let curves =
        new.topology().edges().filter(|&e| old.curve(e).points.map(bits) != new.curve(e).points.map(bits)).collect();
    Changed { vertices, curves, patches }
}

impl SurfaceScheme for CurveMeshSurface {
    fn kind(&self) -> SchemeKind {
        SchemeKind::CurveMesh
    }

    fn update(&mut self, doc: &Document) -> Result<()> {
        if doc.scheme != SchemeKind::CurveMesh {
            return Err(Error::Input(format!(
                "the document's scheme is {}, not Curve mesh",
                doc.scheme.display_name()
            )));
        }
        let same_topology =
            doc.cage.topology_generation() == self.cage_topology || doc.cage.polygons() == self.cage_polygons;
        let same_positions = doc.cage.positions().len() == self.cage_positions.len()
            && doc.cage.positions().iter().zip(&self.cage_positions).all(|(a, b)| bits(*a) == bits(*b));
        if same_topology && same_positions {
            let changed = self.curves.set_edits(&doc.curve_mesh)?;
            self.cage_topology = doc.cage.topology_generation();
            return self.apply(changed);
        }
        if !same_topology {
            *self = CurveMeshSurface::new(doc)?;
            return Ok(());
        }
        let (mesh, report) = doc.curve_mesh()?;
        let new = (*mesh).clone();
        if new.shape() != self.curves.shape() {
            *self = CurveMeshSurface::new(doc)?;
            return Ok(());
        }
        let changed = differences(&self.curves, &new);
        self.curves = new;
        self.report = report;
        self.cage_topology = doc.cage.topology_generation();
        self.cage_positions = doc.cage.positions().to_vec();
        self.apply(changed)
    }

    fn advance(&mut self, _budget: Budget) -> Progress {
        self.progress()
    }

    fn progress(&self) -> Progress {
        let k = self.tessellation.samples();
        let edits = self.curves.edits();
        Progress {
            phase: Phase::Done,
            converged: true,
            summary: format!(
                "Curve mesh: {} Gregory patches, {k} × {k} samples, {} edited vertices, {} edited curves",
                self.curves.patch_count(),
                edits.vertices.len(),
                edits.curves.len()
            ),
            work: self.updates as usize,
        }
    }

    fn take_events(&mut self) -> Vec<String> {
        Vec::new()
    }

    fn mesh(&self) -> &PolyMesh {
        self.tessellation.mesh()
    }

    fn normals(&self) -> Option<&[DVec3]> {
        Some(self.tessellation.normals())
    }

    fn curves(&self) -> Vec<Vec<DVec3>> {
        let k = self.tessellation.samples();
        self.edge_curves
            .iter()
            .map(|halves| {
                let mut points = Vec::with_capacity(halves.len() * k + 1);
                for (i, &h) in halves.iter().enumerate() {
                    let curve = self.curves.curve_along(h);
                    points.extend((usize::from(i > 0)..=k).map(|s| curve.point(s as f64 / k as f64)));
                }
                points
            })
            .collect()
    }

    fn fields(&self) -> &'static [FieldInfo] {
        FIELDS
    }

    fn field(&self, _key: &str) -> Option<Vec<f64>> {
        None
    }

    fn report(&self) -> Vec<String> {
        let r = &self.report;
        let mesh = self.tessellation.mesh();
        let (shared, continuity) = self.curves.continuity(DEFAULT_BOUNDARY_SAMPLES);
        let edits = self.curves.edits();
        vec![
            format!(
                "curve mesh: {} vertices, {} curves, {} Gregory patches{}",
                self.curves.vertex_count(),
                self.curves.curve_count(),
                self.curves.patch_count(),
                if r.subdivided_first { " (the cage has faces other than quads: subdivided once first)" } else { "" }
            ),
            format!(
                "edits: {} vertices and {} curves edited; tessellated {k} × {k} per patch: {} vertices, {} faces",
                edits.vertices.len(),
                edits.curves.len(),
                mesh.vertex_count(),
                mesh.face_count(),
                k = self.tessellation.samples()
            ),
            format!(
                "as built: largest limit-point-to-curve distance {:.6}, interior limit points to their patch {:.6}, α ≤ 0 guards {}",
                r.fit.max_limit_to_curve,
                r.closeness.max_distance,
                r.fit.alpha_guards.len()
            ),
            format!(
                "largest normal angle across {} shared boundaries {:.3e} rad, largest normal-curvature jump {:.4e} per unit length",
                shared.len(),
                continuity.max_normal_angle,
                continuity.max_curvature_jump
            ),
            self.progress().summary,
        ]
    }

    fn as_curve_mesh(&self) -> Option<&CurveMeshSurface> {
        Some(self)
    }
}
