//! The fresh path's limit evaluation ([`super`]): every vertex's masks made and applied at once,
//! with the arithmetic of [`LimitStencils::evaluate`] on the stencils
//! [`LimitStencils::with_corners`] builds, so the same bits, without storing them.

use super::*;
use crate::subdiv::topology::VertexOrigin;

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
    if let (Scheme::CatmullClark, Some((parent, split))) = (scheme, split) {
        quad_limit_into(parent, split, sharpness, corners, mesh, points, limit, normals);
        return;
    }
    let sharp = |e: EdgeId| crate::subdiv::crease::sharp(sharpness, e);
    let vertex = |d: &mut DirectScratch, v: usize| {
        let corner = corners.get(v).is_some_and(|&s| s > 0.0);
        let v = VertexId(v as u32);
        d.ring.clear();
        let ring = if corner { None } else { smooth_ring(scheme, mesh, &sharp, v, &mut d.ring) };
        match ring {
            Some(slot) => {
                let ring = std::mem::take(&mut d.ring);
                let out = apply_ring(d.mask(scheme, slot), &ring, points);
                d.ring = ring;
                out
            }
            None => d.general(scheme, mesh, &sharp, corner, v, points),
        }
    };
    if limit.len() == n && normals.len() == n {
        limit
            .par_iter_mut()
            .zip(normals.par_iter_mut())
            .with_min_len(4096)
            .enumerate()
            .for_each_init(|| DirectScratch::new(n), |d, (v, (p, normal))| (*p, *normal) = vertex(d, v));
    } else {
        // Fresh buffers: each entry written once as it is collected, none cleared first.
        (0..n)
            .into_par_iter()
            .with_min_len(4096)
            .map_init(|| DirectScratch::new(n), vertex)
            .unzip_into_vecs(limit, normals);
    }
}

/// The most spokes a vertex may have to take [`quad_limit_into`]'s fast path.
const FAST_VALENCE: usize = 16;

/// [`limit_into`] on a Catmull–Clark level `mesh` split from `parent` by `split`. A vertex with
/// no sharp spoke, no corner sharpness and 3 to [`FAST_VALENCE`] spokes (nearly all of them) has
/// its ring read from the parent straight into a fixed buffer, by its kind: a parent vertex's
/// spokes walked round it in the parent, an edge point's four and a face point's from its edge
/// and face without a walk; the columns and the valence's shared mask are those
/// [`SplitTopology::quad_spokes`] and [`RingMask::smooth`] give, in the same order, so the bits
/// are those of the stencils. Every other vertex takes the general path.
#[allow(clippy::too_many_arguments)]
fn quad_limit_into(
    parent: &PolyMesh,
    split: &SplitTopology,
    sharpness: &[f64],
    corners: &[f64],
    mesh: &PolyMesh,
    points: &[DVec3],
    limit: &mut Vec<DVec3>,
    normals: &mut Vec<DVec3>,
) {
    let n = mesh.vertex_count();
    let masks: Vec<RingMask> = (0..=FAST_VALENCE).map(|k| RingMask::smooth(Scheme::CatmullClark, k.max(3))).collect();
    let sharp = |e: EdgeId| crate::subdiv::crease::sharp(sharpness, e);
    let (nv, first_face_point) = (split.parent_vertex_count() as u32, split.first_face_point() as u32);
    let edge_point = |h: HalfedgeId| nv + (h.0 >> 1);
    let face_point = |h: HalfedgeId| split.face_point(parent.face(h)).map_or(u32::MAX, |p| p.0);
    // The ring of a smooth vertex of valence 3..=FAST_VALENCE, or its valence as 0 otherwise.
    let fast_ring = |v: u32, ring: &mut [u32; 2 * FAST_VALENCE + 1]| -> usize {
        ring[0] = v;
        let mut k = 0;
        let mut push = |to: u32, across: u32| {
            if k < FAST_VALENCE {
                ring[1 + 2 * k] = to;
                ring[2 + 2 * k] = across;
            }
            k += 1;
        };
        if v < nv {
            let start = parent.vertex_halfedge(VertexId(v));
            if !start.is_valid() || parent.is_boundary_halfedge(start) {
                return 0;
            }
            for h in parent.outgoing(VertexId(v)) {
                // The half of h's edge at v is child edge h.
                if sharp(EdgeId(h.0)) > 0.0 {
                    return 0;
                }
                push(edge_point(h), face_point(h));
            }
        } else if v < first_face_point {
            let e = EdgeId(v - nv);
            let (a, b) = (e.halfedge(0), e.halfedge(1));
            if parent.is_boundary_halfedge(a) || parent.is_boundary_halfedge(b) {
                return 0;
            }
            if sharp(EdgeId(a.0)) > 0.0 || sharp(EdgeId(b.0)) > 0.0 {
                return 0;
            }
            push(parent.to_vertex(b).0, edge_point(parent.next(b)));
            push(face_point(b), edge_point(parent.prev(b)));
            push(parent.to_vertex(a).0, edge_point(parent.next(a)));
            push(face_point(a), edge_point(parent.prev(a)));
        } else {
            let VertexOrigin::Face(f) = split.origin(VertexId(v)) else { unreachable!("face points come last") };
            for h in parent.face_halfedges(f) {
                push(edge_point(h), parent.to_vertex(h).0);
            }
        }
        if (3..=FAST_VALENCE).contains(&k) { k } else { 0 }
    };
    // A vertex's limit position and normal, and whether the normal is still to be normalised
    // (the fast path's).
    let vertex = |d: &mut DirectScratch, ring: &mut [u32; 2 * FAST_VALENCE + 1], v: usize| {
        let corner = corners.get(v).is_some_and(|&s| s > 0.0);
        let k = if corner { 0 } else { fast_ring(v as u32, ring) };
        if k > 0 {
            let (p, normal) = ring_sums(&masks[k], &ring[..2 * k + 1], points);
            return (p, normal, true);
        }
        let v = VertexId(v as u32);
        d.ring.clear();
        let (p, normal) =
            match if corner { None } else { derived_smooth_ring(parent, split, sharpness, v, &mut d.ring) } {
                Some(slot) => {
                    let ring = std::mem::take(&mut d.ring);
                    let out = apply_ring(d.mask(Scheme::CatmullClark, slot), &ring, points);
                    d.ring = ring;
                    out
                }
                None => d.general(Scheme::CatmullClark, mesh, &sharp, corner, v, points),
            };
        (p, normal, false)
    };
    if limit.len() != n || normals.len() != n {
        // Fresh buffers: each entry written once as it is collected, none cleared first (clearing
        // a fine level's limit and normals cost a tenth of computing them).
        (0..n)
            .into_par_iter()
            .with_min_len(4096)
            .map_init(
                || (DirectScratch::new(n), [0u32; 2 * FAST_VALENCE + 1]),
                |(d, ring), v| {
                    let (p, normal, fast) = vertex(d, ring, v);
                    (p, if fast { normal.normalize_or_zero() } else { normal })
                },
            )
            .unzip_into_vecs(limit, normals);
        return;
    }
    // Re-evaluated in place, by chunks: the fast vertices' normals are normalised in a second
    // loop over the chunk, where the square roots and divisions of independent vertices overlap
    // instead of each waiting at the end of a long ring walk (the same operations, so the same
    // bits).
    const CHUNK: usize = 4096;
    limit.par_chunks_mut(CHUNK).zip(normals.par_chunks_mut(CHUNK)).enumerate().for_each_init(
        || (DirectScratch::new(n), [0u32; 2 * FAST_VALENCE + 1], Vec::with_capacity(CHUNK)),
        |(d, ring, fast), (c, (limit, normals))| {
            fast.clear();
            for (i, (p, normal)) in limit.iter_mut().zip(normals.iter_mut()).enumerate() {
                let is_fast;
                (*p, *normal, is_fast) = vertex(d, ring, c * CHUNK + i);
                if is_fast {
                    fast.push(i as u32);
                }
            }
            for &i in fast.iter() {
                normals[i as usize] = normals[i as usize].normalize_or_zero();
            }
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
