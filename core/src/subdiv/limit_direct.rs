//! The fresh path's limit evaluation ([`super`]): every vertex's masks made and applied at once,
//! with the arithmetic of [`LimitStencils::evaluate`] on the stencils
//! [`LimitStencils::with_corners`] builds, so the same bits, without storing them.

use super::*;

/// Limit positions and unit limit normals of every vertex of `mesh` (positions `points`),
/// computed directly: each vertex's masks are made and applied at once, with the arithmetic
/// [`LimitStencils::evaluate`] performs on the stencils [`LimitStencils::with_corners`] builds
/// (so the same bits), without storing them. `mesh` must pass the checks `with_corners` makes.
///
/// `split`: the parent level and the split that made `mesh` from it, when `mesh` is a
/// Catmull–Clark level; the smooth rings are then read from the parent
/// ([`SplitTopology::quad_spokes`], the same columns in the same order).
pub(crate) fn limit_into(
    scheme: Scheme,
    mesh: &PolyMesh,
    split: Option<(&PolyMesh, &SplitTopology)>,
    sharpness: &[f64],
    corners: &[f64],
    points: &[DVec3],
    limit: &mut Vec<DVec3>,
    normals: &mut Vec<DVec3>,
) {
    let n = mesh.vertex_count();
    limit.resize(n, DVec3::ZERO);
    normals.resize(n, DVec3::ZERO);
    let sharp = |e: EdgeId| sharpness[e.index()];
    limit.par_iter_mut().zip(normals.par_iter_mut()).with_min_len(4096).enumerate().for_each_init(
        || DirectScratch::new(n),
        |d, (v, (p, normal))| {
            let corner = corners.get(v).is_some_and(|&s| s > 0.0);
            let v = VertexId(v as u32);
            d.ring.clear();
            let ring = match (corner, split) {
                (true, _) => None,
                (false, Some((parent, split))) => derived_smooth_ring(parent, split, sharpness, v, &mut d.ring),
                (false, None) => smooth_ring(scheme, mesh, &sharp, v, &mut d.ring),
            };
            (*p, *normal) = match ring {
                Some(slot) => {
                    let ring = std::mem::take(&mut d.ring);
                    let out = apply_ring(d.mask(scheme, slot), &ring, points);
                    d.ring = ring;
                    out
                }
                None => d.general(scheme, mesh, &sharp, corner, v, points),
            };
        },
    );
}

/// One thread's buffers for [`limit_into`]: the ring, the masks made so far, and one general
/// vertex's rows.
struct DirectScratch {
    ring: Vec<u32>,
    /// Smooth masks and dart masks by valence, made on first use.
    masks: [Vec<Option<RingMask>>; 2],
    scratch: Scratch,
    position: SparseRows,
    tangents: SparseRows,
}

impl DirectScratch {
    fn new(vertices: usize) -> Self {
        DirectScratch {
            ring: Vec::new(),
            masks: Default::default(),
            scratch: Scratch::default(),
            position: SparseRows::with_columns(vertices),
            tangents: SparseRows::with_columns(vertices),
        }
    }

    /// The shared mask of a ring vertex's slot (as [`LimitStencils`] stores it).
    fn mask(&mut self, scheme: Scheme, slot: u32) -> &RingMask {
        let (dart, k) = (slot & DART != 0, (slot & !DART) as usize);
        let masks = &mut self.masks[usize::from(dart)];
        if masks.len() <= k {
            masks.resize(k + 1, None);
        }
        masks[k].get_or_insert_with(|| if dart { dart_mask(scheme, k) } else { RingMask::smooth(scheme, k) })
    }

    /// The limit position and normal of a general vertex, from its rows built as
    /// [`LimitStencils::with_corners`] builds them.
    fn general(
        &mut self,
        scheme: Scheme,
        mesh: &PolyMesh,
        sharpness: &impl Fn(EdgeId) -> f64,
        corner: bool,
        v: VertexId,
        points: &[DVec3],
    ) -> (DVec3, DVec3) {
        for rows in [&mut self.position, &mut self.tangents] {
            rows.offsets.truncate(1);
            rows.columns.clear();
            rows.weights.clear();
        }
        let pairs = vertex_masks(scheme, mesh, sharpness, corner, v, &mut self.scratch);
        self.scratch.position.push_into(&mut self.position);
        for pair in &mut self.scratch.pairs[..pairs] {
            pair[0].push_into(&mut self.tangents);
            pair[1].push_into(&mut self.tangents);
        }
        let normal = if pairs == 0 { DVec3::ZERO } else { pairs_normal(&self.tangents, 0..pairs, points) };
        (self.position.apply_row(0, points), normal)
    }
}
