//! [`Refinement`]: a cage refined by Catmull–Clark or Loop to a number of levels, topology built
//! once, positions evaluated by the rules directly when fresh and through stencils after a drag.
//!
//! [`Refinement::new`] splits the cage level by level ([`SplitTopology`]: each level's halfedges
//! derived from the level above) and carries the crease sharpness down (uniform creasing,
//! [`super::crease`]); it builds no stencil. [`Refinement::evaluate`] applies the rules of
//! [`super::rules`] directly (face points first, then the edge and vertex points that read them)
//! and the limit masks of [`super::limit`] directly, writing into reusable buffers; for
//! Catmull–Clark the finest level's smooth rings are read from the level above
//! (`SplitTopology::quad_spokes`) rather than walked round the finest halfedges, which missed
//! the cache (limit masks of the level-3 torus about 9.4 → 7.8 ms on one thread).
//!
//! The stencils pay only when drags follow a topology, so they are lazy: one matrix per level
//! (level `l` from level `l − 1`) and the limit stencils of the finest level, with their
//! transposed patterns ([`Users`]), are built on the first [`Refinement::update`] (or by
//! [`Refinement::stencils`] and [`Refinement::limit_stencils`]) and kept. After a drag `update`
//! recomputes only the rows that read a moved vertex, found through the patterns, level by level
//! by the same direct rules and then the limit, so it gives the same bits as a full evaluation.
//! The level stencils agree with the direct rules to rounding (they expand every face point into
//! its face's corners), the limit stencils to the bit. Nothing depends on the thread count.
//!
//! Level-by-level stencils were chosen over stencils flattened onto the cage: for a level-3
//! Catmull–Clark torus the flattened matrix has 1.6 times the entries (1.72 M against 1.08 M)
//! and is no faster to apply (`benches/subdiv.rs` measures both), and level by level also gives
//! every intermediate level.
//!
//! Sizes: each level multiplies the face count by about 4. [`MAX_LEVELS`] levels at most, and the
//! finest level may have at most [`MAX_REFINED_FACES`] faces: a refinement takes about 400 bytes
//! per finest face and its [`RefinedPositions`] about 90 more (measured on a level-3
//! Catmull–Clark torus, [`Refinement::memory_bytes`]), so the bound keeps one under about 1 GB.

use super::crease::{Rule, child_sharpness, effective_sharpness, starting_corners};
use super::limit::{LimitStencils, check_faces, limit_into};
use super::rules::{Scheme, level_stencils, refine_into, refine_rows};
use super::sparse::{SparseRows, Users};
use super::topology::{SplitRule, SplitTopology};
use crate::mesh::{EdgeId, PolyMesh, VertexId};
use crate::{DVec3, Error, Result};
use rayon::prelude::*;
use std::sync::OnceLock;
use std::sync::atomic::{AtomicU64, Ordering};

/// Source of refinement identities, so [`Refinement::update`] knows whose positions it is given.
static NEXT_ID: AtomicU64 = AtomicU64::new(1);

/// The most levels a refinement may have.
pub const MAX_LEVELS: u32 = 10;
/// The most faces the finest level may have.
pub const MAX_REFINED_FACES: usize = 1 << 21;

/// The most weights the first level's stencils may hold. Around an n-sided face, each of its n
/// new edge points and n corners reads all n corners of the face (through the face point), so a
/// face costs about 2n² weights: a single 10,000-sided polygon asked for 2·10⁸ (2.5 GB). The bound
/// (about 400 MB of stencils) lets faces of a couple of thousand sides through.
pub const MAX_FIRST_LEVEL_WEIGHTS: usize = 1 << 24;

/// Faces with more sides than this count towards [`MAX_FIRST_LEVEL_WEIGHTS`].
const LARGE_POLYGON: usize = 16;

/// Refuses, before anything is built, a cage whose large polygons' first-level stencils would exceed
/// [`MAX_FIRST_LEVEL_WEIGHTS`], naming the largest face.
fn check_first_level_weights(cage: &PolyMesh) -> Result<()> {
    let mut weights = 0usize;
    let mut largest = None::<(usize, crate::mesh::FaceId)>;
    for f in cage.faces() {
        let n = cage.face_vertices(f).count();
        // Ordinary faces cost a few weights per corner, like any mesh; only large polygons grow.
        if n > LARGE_POLYGON {
            weights = weights.saturating_add(2 * n * n);
        }
        if largest.is_none_or(|(m, _)| n > m) {
            largest = Some((n, f));
        }
    }
    match largest {
        Some((n, f)) if weights > MAX_FIRST_LEVEL_WEIGHTS => Err(Error::Input(format!(
            "face {} has {n} sides: the first subdivision level would need about {weights} stencil weights \
             (they grow with the square of a face's sides), more than the {MAX_FIRST_LEVEL_WEIGHTS} Taut allows; \
             split the largest polygons into smaller ones first",
            f.0
        ))),
        _ => Ok(()),
    }
}

/// Runs `f` on one of rayon's worker threads (at once when called from one). Building and
/// evaluating a refinement is a chain of a few dozen parallel loops; started from a thread outside
/// the pool, each of them was handed to the pool and waited for, the caller sleeping and waking
/// once per loop, which cost about 0.3 ms of a fresh level-3 torus (about 8 ms on 2 threads).
/// From a worker each loop starts at once.
fn on_workers<R: Send>(f: impl FnOnce() -> R + Send) -> R {
    if rayon::current_thread_index().is_some() { f() } else { rayon::scope(|_| f()) }
}

/// The largest of `values` (0 for none).
fn largest(values: &[f64]) -> f64 {
    values.iter().copied().fold(0.0, f64::max)
}

/// One level below the cage.
#[derive(Clone, Debug)]
struct Level {
    split: SplitTopology,
    /// Effective sharpness of this level's edges; on a level with no sharp edge or corner (all
    /// 0), made on first use: the fresh path reads no table there ([`Refinement::rule_topology`]).
    sharpness: OnceLock<Vec<f64>>,
    /// Sharpness of this level's vertices (corners), made on first use where all are 0.
    corners: OnceLock<Vec<f64>>,
    /// This level's stencils, built on first use ([`Refinement::stencils`]).
    stencils: OnceLock<LevelStencils>,
}

/// The stencils of one level, what a drag needs.
#[derive(Clone, Debug)]
struct LevelStencils {
    /// This level's positions from the previous level's.
    rows: SparseRows,
    /// For every vertex of the previous level, the rows of `rows` that read it.
    users: Users,
}

/// A cage refined by a subdivision scheme.
#[derive(Clone, Debug)]
pub struct Refinement {
    scheme: Scheme,
    cage: PolyMesh,
    cage_sharpness: Vec<f64>,
    cage_corners: Vec<f64>,
    levels: Vec<Level>,
    /// The largest edge and vertex sharpness of the cage (boundary edges infinite): a level
    /// whose largest, carried down, are 0 has no sharp edge or corner.
    cage_largest: (f64, f64),
    /// The finest level's limit stencils and, for every vertex of that level, the vertices whose
    /// limit reads it; built on first use ([`Refinement::limit_stencils`]).
    limit: OnceLock<(LimitStencils, Users)>,
    /// Unique per built refinement (clones share it: they hold the same stencils).
    id: u64,
}

/// The positions of every level, the limit positions and limit normals of the finest level.
#[derive(Clone, Debug, Default)]
pub struct RefinedPositions {
    /// `levels[l]`: the positions of level `l` (`levels[0]` is the cage).
    pub levels: Vec<Vec<DVec3>>,
    /// The limit position of every vertex of the finest level.
    pub limit: Vec<DVec3>,
    /// The unit limit normal of every vertex of the finest level (zero where undefined).
    pub normals: Vec<DVec3>,
    /// The refinement whose complete evaluation these are (0: none).
    source: u64,
    /// Scratch for [`Refinement::update`]: per-vertex marks, the current mark, two dirty lists.
    marks: Vec<u32>,
    mark: u32,
    dirty: Vec<u32>,
    next: Vec<u32>,
}

impl RefinedPositions {
    /// The positions of the finest level.
    pub fn finest(&self) -> &[DVec3] {
        self.levels.last().map_or(&[], |l| l)
    }
}

impl Refinement {
    /// Refines `cage` by `scheme` to `levels` levels. `sharpness` holds one crease sharpness per
    /// cage edge (`0` smooth, `f64::INFINITY` sharp), or nothing for a smooth cage.
    ///
    /// Errors: Loop on a cage with faces other than triangles (triangulate first:
    /// [`crate::mesh::edit::triangulate()`]), Catmull–Clark with 0 levels on a cage that is not all quads (no
    /// limit stencils there), a negative or NaN sharpness or one value per edge missing, more than
    /// [`MAX_LEVELS`] levels or more than [`MAX_REFINED_FACES`] faces at the finest level.
    /// Isolated vertices are kept in place at every level; degenerate (zero-area) faces and
    /// valence-2 vertices are refined by the same rules (their normals may be zero, see
    /// [`LimitStencils`]).
    pub fn new(cage: &PolyMesh, scheme: Scheme, sharpness: &[f64], levels: u32) -> Result<Self> {
        Refinement::with_corners(cage, scheme, sharpness, &[], levels)
    }

    /// [`Refinement::new`] with vertex sharpness too: `corners` holds one sharpness per cage
    /// vertex (`0` smooth, `f64::INFINITY` a sharp corner that stays where it is), or nothing.
    pub fn with_corners(
        cage: &PolyMesh,
        scheme: Scheme,
        sharpness: &[f64],
        corners: &[f64],
        levels: u32,
    ) -> Result<Self> {
        on_workers(|| Refinement::build(cage, scheme, sharpness, corners, levels))
    }

    fn build(cage: &PolyMesh, scheme: Scheme, sharpness: &[f64], corners: &[f64], levels: u32) -> Result<Self> {
        let cage_sharpness = effective_sharpness(cage, sharpness)?;
        let cage_corners = starting_corners(cage, &cage_sharpness, corners)?;
        if levels > MAX_LEVELS {
            return Err(Error::Input(format!(
                "{levels} subdivision levels asked for; at most {MAX_LEVELS} are possible"
            )));
        }
        let rule = match scheme {
            Scheme::CatmullClark => SplitRule::Quads,
            Scheme::Loop => SplitRule::Triangles,
        };
        let faces = refined_face_count(cage, rule, levels);
        if faces > MAX_REFINED_FACES as f64 {
            return Err(Error::Input(format!(
                "{levels} levels of this {}-face cage would make about {faces:.0} faces, more than the {MAX_REFINED_FACES} \
                 Taut refines (about 1 GB of memory); use fewer levels",
                cage.face_count()
            )));
        }
        check_first_level_weights(cage)?;
        let cage_largest = (largest(&cage_sharpness), largest(&cage_corners));
        let mut out = Refinement {
            scheme,
            cage: cage.clone(),
            cage_sharpness,
            cage_largest,
            cage_corners,
            levels: Vec::new(),
            limit: OnceLock::new(),
            id: NEXT_ID.fetch_add(1, Ordering::Relaxed),
        };
        for _ in 0..levels {
            let split = match out.levels.last() {
                Some(above) => SplitTopology::split_again(&above.split, rule)?,
                None => SplitTopology::split(&out.cage, rule)?,
            };
            let level = out.levels.len() as u32 + 1;
            let (sharpness, corners) = if out.is_smooth(level) {
                (OnceLock::new(), OnceLock::new())
            } else {
                // Child vertices come first as their parents, child edges first as the halves of
                // theirs (`SplitTopology`'s numbering), and nothing else is sharp.
                let (parent_sharpness, parent_corners) = (out.sharpness(level - 1), out.corners(level - 1));
                let corners: Vec<f64> = (0..split.mesh.vertex_count())
                    .into_par_iter()
                    .with_min_len(4096)
                    .map(|v| parent_corners.get(v).map_or(0.0, |&s| child_sharpness(s)))
                    .collect();
                let sharpness: Vec<f64> = (0..split.mesh.edge_count())
                    .into_par_iter()
                    .with_min_len(4096)
                    .map(|e| parent_sharpness.get(e / 2).map_or(0.0, |&s| child_sharpness(s)))
                    .collect();
                (OnceLock::from(sharpness), OnceLock::from(corners))
            };
            out.levels.push(Level { split, sharpness, corners, stencils: OnceLock::new() });
        }
        // Below the cage every face is a quad (Catmull–Clark) or a triangle (Loop) by construction.
        if levels == 0 {
            check_faces(scheme, cage)?;
        }
        Ok(out)
    }

    /// The stencils of level `l ≥ 1` (0-based index `l − 1` into `levels`), built on first use.
    fn level_stencils(&self, index: usize) -> &LevelStencils {
        self.levels[index].stencils.get_or_init(|| {
            let (parent, sharpness, corners) = self.topology(index as u32);
            let rows = level_stencils(self.scheme, parent, sharpness, corners, &self.levels[index].split);
            let users = rows.users();
            LevelStencils { rows, users }
        })
    }

    /// The finest level's limit stencils and their users, built on first use.
    fn limit(&self) -> &(LimitStencils, Users) {
        self.limit.get_or_init(|| {
            let (finest, sharpness, corners) = self.finest_topology();
            let limit = LimitStencils::with_corners(self.scheme, finest, sharpness, corners)
                .expect("the finest level was checked when the refinement was built");
            let users = limit.users();
            (limit, users)
        })
    }

    /// The mesh, edge sharpness and vertex sharpness of `level`.
    fn topology(&self, level: u32) -> (&PolyMesh, &[f64], &[f64]) {
        (self.mesh(level), self.sharpness(level), self.corners(level))
    }

    fn finest_topology(&self) -> (&PolyMesh, &[f64], &[f64]) {
        self.topology(self.level_count())
    }

    /// [`Refinement::topology`] for the rules and limit masks applied directly: on a level with
    /// no sharp edge or corner, no sharpness tables (empty, read as all 0: the same values, not
    /// looked up).
    fn rule_topology(&self, level: u32) -> (&PolyMesh, &[f64], &[f64]) {
        if self.is_smooth(level) { (self.mesh(level), &[], &[]) } else { self.topology(level) }
    }

    /// Whether `level` has no sharp edge or corner: the cage's largest edge and vertex sharpness,
    /// carried down to it, are 0.
    fn is_smooth(&self, level: u32) -> bool {
        let (mut edges, mut corners) = self.cage_largest;
        for _ in 0..level {
            (edges, corners) = (child_sharpness(edges), child_sharpness(corners));
        }
        edges == 0.0 && corners == 0.0
    }

    /// The sharpness of every vertex of `level` (corners; 0 elsewhere).
    pub fn corners(&self, level: u32) -> &[f64] {
        match level {
            0 => &self.cage_corners,
            l => {
                let level = &self.levels[l as usize - 1];
                level.corners.get_or_init(|| vec![0.0; level.split.mesh.vertex_count()])
            }
        }
    }

    /// The scheme.
    pub fn scheme(&self) -> Scheme {
        self.scheme
    }

    /// Number of levels below the cage.
    pub fn level_count(&self) -> u32 {
        self.levels.len() as u32
    }

    /// The mesh of `level` (0 is the cage); its positions are the linear prolongation of the cage,
    /// not the subdivided ones (those come from [`Refinement::evaluate`]).
    pub fn mesh(&self, level: u32) -> &PolyMesh {
        match level {
            0 => &self.cage,
            l => &self.levels[l as usize - 1].split.mesh,
        }
    }

    /// How `level ≥ 1` was split from the level above.
    pub fn split(&self, level: u32) -> &SplitTopology {
        &self.levels[level as usize - 1].split
    }

    /// The effective sharpness of every edge of `level` (boundary edges infinite).
    pub fn sharpness(&self, level: u32) -> &[f64] {
        match level {
            0 => &self.cage_sharpness,
            l => {
                let level = &self.levels[l as usize - 1];
                level.sharpness.get_or_init(|| vec![0.0; level.split.mesh.edge_count()])
            }
        }
    }

    /// The rule of vertex `v` of `level` (from its sharpness and the sharp edges at it; boundary
    /// edges count as sharp).
    pub fn vertex_rule(&self, level: u32, v: VertexId) -> Rule {
        let (mesh, sharpness) = (self.mesh(level), self.sharpness(level));
        let corner = self.corners(level)[v.index()];
        Rule::of(corner, mesh.outgoing(v).filter(|h| sharpness[h.edge().index()] > 0.0).count())
    }

    /// The stencils making `level ≥ 1` from the level above (built on the first call, or the
    /// first [`Refinement::update`]). Applied to the level above, they give the same bits as
    /// [`Refinement::evaluate`].
    pub fn stencils(&self, level: u32) -> &SparseRows {
        &self.level_stencils(level as usize - 1).rows
    }

    /// Approximate bytes of everything built so far: every level's mesh and split bookkeeping,
    /// sharpness, and the stencils and limit stencils (with their transposed patterns) once they
    /// have been built.
    pub fn memory_bytes(&self) -> usize {
        let mesh = |m: &PolyMesh| 28 * m.vertex_count() + 16 * m.halfedge_count() + 4 * m.face_count();
        let levels: usize = self
            .levels
            .iter()
            .map(|l| {
                let m = &l.split.mesh;
                mesh(m)
                    + 12 * m.edge_count()
                    + 4 * m.face_count()
                    + l.sharpness.get().map_or(0, |s| 8 * s.len())
                    + l.corners.get().map_or(0, |c| 8 * c.len())
                    + l.stencils.get().map_or(0, |s| s.rows.memory_bytes() + s.users.memory_bytes())
            })
            .sum();
        let limit = self.limit.get().map_or(0, |(l, u)| l.memory_bytes() + u.memory_bytes());
        mesh(&self.cage) + levels + limit
    }

    /// The limit stencils of the finest level (built on the first call, or the first
    /// [`Refinement::update`]).
    pub fn limit_stencils(&self) -> &LimitStencils {
        &self.limit().0
    }

    /// Limit stencils of another level (built on request; Catmull–Clark needs `level ≥ 1` unless
    /// the cage is all quads).
    pub fn limit_stencils_at(&self, level: u32) -> Result<LimitStencils> {
        if level > self.level_count() {
            return Err(Error::Input(format!(
                "level {level} asked for, but the refinement has {}",
                self.level_count()
            )));
        }
        LimitStencils::with_corners(self.scheme, self.mesh(level), self.sharpness(level), self.corners(level))
    }

    /// Every level's positions and the finest level's limit positions and normals from new cage
    /// positions, into `out` (whose buffers are reused).
    pub fn evaluate(&self, cage_positions: &[DVec3], out: &mut RefinedPositions) -> Result<()> {
        on_workers(|| {
            self.evaluate_levels(cage_positions, out)?;
            self.evaluate_limit(out);
            out.source = self.id;
            Ok(())
        })
    }

    /// The limit positions and normals of the finest level: through the limit stencils once a
    /// drag has built them (faster to apply), by the masks applied directly before (no build to
    /// wait for); both give the same bits.
    fn evaluate_limit(&self, out: &mut RefinedPositions) {
        let points = out.levels.last().expect("level 0 is always there");
        if let Some((limit, _)) = self.limit.get() {
            limit.evaluate(points, &mut out.limit, &mut out.normals);
            return;
        }
        let (finest, sharpness, corners) = self.rule_topology(self.level_count());
        // Catmull–Clark rings are read from the level above (`SplitTopology::quad_spokes`).
        let split = match (self.scheme, self.levels.len()) {
            (Scheme::CatmullClark, l @ 1..) => Some((self.mesh(l as u32 - 1), self.split(l as u32))),
            _ => None,
        };
        limit_into(self.scheme, finest, split, sharpness, corners, points, &mut out.limit, &mut out.normals);
    }

    /// Level `index + 1`'s positions from level `index`'s in `out`, by the rules applied directly.
    fn refine_level(&self, index: usize, out: &mut RefinedPositions) {
        let (parent, sharpness, corners) = self.rule_topology(index as u32);
        let (coarse, fine) = out.levels.split_at_mut(index + 1);
        // Below the cage, a Catmull–Clark level is all quads.
        let quads = self.scheme == Scheme::CatmullClark && index > 0;
        let split = &self.levels[index].split;
        refine_into(self.scheme, parent, sharpness, corners, split, quads, &coarse[index], &mut fine[0]);
    }

    /// After a drag: brings `out` (last filled by [`Refinement::evaluate`] or `update` of this
    /// refinement; anything else is evaluated in full) to new cage positions, recomputing only the rows that read a moved cage vertex,
    /// level by level, then the limit positions and normals that read a changed finest vertex.
    /// The result is bit-identical to [`Refinement::evaluate`]. Falls back to a full evaluation
    /// when `out` does not hold this refinement's complete evaluation or when more than a quarter
    /// of a level changes. Returns the number of rows recomputed.
    pub fn update(&self, cage_positions: &[DVec3], out: &mut RefinedPositions) -> Result<usize> {
        self.check_cage_positions(cage_positions)?;
        let finest = self.mesh(self.level_count()).vertex_count();
        let fits = out.source == self.id
            && out.levels.len() == self.levels.len() + 1
            && (0..=self.level_count()).all(|l| out.levels[l as usize].len() == self.mesh(l).vertex_count())
            && out.limit.len() == finest
            && out.normals.len() == finest;
        if !fits {
            self.evaluate(cage_positions, out)?;
            return Ok(self.total_rows());
        }
        out.dirty.clear();
        for (v, (old, new)) in out.levels[0].iter_mut().zip(cage_positions).enumerate() {
            if old.to_array().map(f64::to_bits) != new.to_array().map(f64::to_bits) {
                *old = *new;
                out.dirty.push(v as u32);
            }
        }
        out.marks.resize(finest.max(self.cage.vertex_count()), 0);
        let mut recomputed = 0;
        for l in 0..self.levels.len() {
            let stencils = self.level_stencils(l);
            collect_users(&stencils.users, out);
            if 4 * out.next.len() > stencils.rows.row_count() {
                // Most of the surface moves: evaluate the rest in full, in parallel.
                for k in l..self.levels.len() {
                    self.refine_level(k, out);
                }
                self.limit();
                self.evaluate_limit(out);
                return Ok(recomputed + self.rows_from(l));
            }
            let (parent, sharpness, corners) = self.rule_topology(l as u32);
            let (coarse, fine) = out.levels.split_at_mut(l + 1);
            let split = &self.levels[l].split;
            refine_rows(self.scheme, parent, sharpness, corners, split, &coarse[l], &mut fine[0], &out.next);
            recomputed += out.next.len();
            std::mem::swap(&mut out.dirty, &mut out.next);
        }
        let (limit, users) = self.limit();
        collect_users(users, out);
        let finest = out.levels.last().expect("level 0 is always there");
        limit.evaluate_some(finest, &out.next, &mut out.limit, &mut out.normals);
        Ok(recomputed + out.next.len())
    }

    /// Rows of every level from `level` (0-based index into the levels below the cage) down,
    /// and the limit.
    fn rows_from(&self, level: usize) -> usize {
        let vertices = |l: &Level| l.split.mesh.vertex_count();
        self.levels[level..].iter().map(vertices).sum::<usize>() + self.finest_topology().0.vertex_count()
    }

    fn total_rows(&self) -> usize {
        self.rows_from(0)
    }

    fn check_cage_positions(&self, cage_positions: &[DVec3]) -> Result<()> {
        if cage_positions.len() != self.cage.vertex_count() {
            return Err(Error::Input(format!(
                "{} cage positions given for a cage of {} vertices",
                cage_positions.len(),
                self.cage.vertex_count()
            )));
        }
        if let Some(v) = cage_positions.iter().position(|p| !p.is_finite()) {
            return Err(Error::Input(format!(
                "cage vertex {v} has a non-finite coordinate; every coordinate must be finite"
            )));
        }
        Ok(())
    }

    /// Like [`Refinement::evaluate`], without the limit positions and normals.
    pub fn evaluate_levels(&self, cage_positions: &[DVec3], out: &mut RefinedPositions) -> Result<()> {
        self.check_cage_positions(cage_positions)?;
        // The limit is left behind: the next update must evaluate in full.
        out.source = 0;
        out.levels.resize_with(self.levels.len() + 1, Vec::new);
        out.levels[0].clear();
        out.levels[0].extend_from_slice(cage_positions);
        on_workers(|| {
            for l in 0..self.levels.len() {
                self.refine_level(l, out);
            }
        });
        Ok(())
    }

    /// The finest level's mesh with positions `positions` (for example
    /// [`RefinedPositions::limit`]).
    pub fn surface(&self, positions: &[DVec3]) -> PolyMesh {
        let mut mesh = self.mesh(self.level_count()).clone();
        mesh.positions_mut().copy_from_slice(positions);
        mesh
    }

    /// The vertices of `level` along cage edge `e`, from its first end vertex
    /// (`cage.edge_vertices(e).0`) to its second: `2^level + 1` of them.
    pub fn cage_edge_chain(&self, e: EdgeId, level: u32) -> Result<Vec<VertexId>> {
        if e.index() >= self.cage.edge_count() || level > self.level_count() {
            return Err(Error::Input(format!(
                "edge {} at level {level} asked for, but the cage has {} edges and {} levels",
                e.0,
                self.cage.edge_count(),
                self.level_count()
            )));
        }
        let (a, b) = self.cage.edge_vertices(e);
        // Directed edges along the chain: (edge, from, to).
        let mut chain = vec![(e, a, b)];
        for l in 1..=level {
            let split = self.split(l);
            let parent = self.mesh(l - 1);
            chain = chain
                .iter()
                .flat_map(|&(e, from, to)| {
                    let m = split.edge_point(e);
                    let halves = split.edge_children(e);
                    let at_from = usize::from(parent.edge_vertices(e).0 != from);
                    [(halves[at_from], from, m), (halves[1 - at_from], m, to)]
                })
                .collect();
        }
        Ok(std::iter::once(a).chain(chain.iter().map(|&(_, _, to)| to)).collect())
    }
}

/// `out.next`: every row of `users` reached from `out.dirty`, once each, in ascending order.
fn collect_users(users: &Users, out: &mut RefinedPositions) {
    out.mark = out.mark.wrapping_add(1);
    if out.mark == 0 {
        out.marks.iter_mut().for_each(|m| *m = 0);
        out.mark = 1;
    }
    out.next.clear();
    for &d in &out.dirty {
        for &r in users.of(d as usize) {
            if out.marks[r as usize] != out.mark {
                out.marks[r as usize] = out.mark;
                out.next.push(r);
            }
        }
    }
    // Ascending order keeps the writes local; the values do not depend on it.
    out.next.sort_unstable();
}

/// The face count of `levels` levels of `cage` by `rule` (as a float: it may overflow).
fn refined_face_count(cage: &PolyMesh, rule: SplitRule, levels: u32) -> f64 {
    if levels == 0 {
        return cage.face_count() as f64;
    }
    let first: usize = cage
        .faces()
        .map(|f| match (rule, cage.face_valence(f)) {
            (SplitRule::Quads, n) => n,
            (_, 3) => 4,
            (_, n) => n,
        })
        .sum();
    first as f64 * 4f64.powi(levels as i32 - 1)
}

#[cfg(test)]
#[path = "refinement_tests.rs"]
mod tests;
