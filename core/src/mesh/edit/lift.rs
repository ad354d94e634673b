//! The topology extrude and inset share: selected faces are lifted off their neighbours onto
//! copies of their border vertices, and a wall of quads is built along the border.
//!
//! In a region, a vertex is copied once per *fan* — a run of selected faces around it joined
//! through selected faces — that touches the region's border; a vertex whose whole ring is
//! selected stays (it moves with the region). The border is every edge with a selected face on
//! exactly one side, the cage's open boundary included, so two regions that touch at a single
//! vertex get a copy each and stay manifold. Individually, every corner of a selected face is
//! copied and every edge of it is border. The wall on border halfedge `a → b` of a lifted face
//! is the quad `a, b, b', a'`, which runs opposite to both the lifted face and the face left
//! behind, so the result is consistently oriented. Linear in the size of the cage.

use super::FaceGrouping;
use super::draft::{Corners, Draft, face_mask};
use super::provenance::{FaceOrigin, VertexOrigin};
use crate::mesh::{FaceId, HalfedgeId, PolyMesh, VertexId};
use crate::{DVec3, Error, Result};

/// A copy of a border vertex, made for one fan.
#[derive(Debug)]
pub(super) struct Copy {
    /// Its draft vertex.
    pub vertex: u32,
    pub source: VertexId,
    /// The border halfedges into and out of the source within the fan.
    pub incoming: HalfedgeId,
    pub outgoing: HalfedgeId,
    /// Sum of the area vectors of the fan's faces.
    pub area: DVec3,
    pub region: u32,
}

#[derive(Debug)]
pub(super) struct Lift<'m> {
    pub draft: Draft<'m>,
    pub copies: Vec<Copy>,
    /// Old vertices inside a region (their whole ring selected), with their region.
    pub interior: Vec<(u32, u32)>,
    /// Region of each old face (`u32::MAX` when not selected).
    pub region_of_face: Vec<u32>,
    pub region_count: usize,
    pub mask: Vec<bool>,
}

pub(super) fn lift<'m>(
    mesh: &'m PolyMesh,
    faces: &[FaceId],
    grouping: FaceGrouping,
    op: &'static str,
) -> Result<Lift<'m>> {
    let mask = face_mask(op, mesh, faces)?;
    let corners = Corners::new(mesh);
    let region = grouping == FaceGrouping::Region;
    let selected = |f: FaceId| f.is_valid() && mask[f.index()];
    let border = |h: HalfedgeId| selected(mesh.face(h)) && (!region || !selected(mesh.face(h.twin())));
    let (fan, fan_count) = corners.fans(mesh, &mask, |_| region);

    // Regions: faces joined through non-border edges.
    let mut region_of_face = vec![u32::MAX; mesh.face_count()];
    let mut region_count = 0usize;
    let mut stack = Vec::new();
    for f in mesh.faces().filter(|&f| mask[f.index()]) {
        if region_of_face[f.index()] != u32::MAX {
            continue;
        }
        let r = region_count as u32;
        region_count += 1;
        region_of_face[f.index()] = r;
        stack.push(f);
        let mut has_border = false;
        while let Some(g) = stack.pop() {
            for h in mesh.face_halfedges(g) {
                if border(h) {
                    has_border = true;
                    continue;
                }
                let n = mesh.face(h.twin());
                if region_of_face[n.index()] == u32::MAX {
                    region_of_face[n.index()] = r;
                    stack.push(n);
                }
            }
        }
        if !has_border {
            return Err(Error::Topology(format!(
                "{op}: the selected faces around face {} close on themselves, so they have no border to \
                 build walls on; deselect a face or work on them individually",
                f.0
            )));
        }
    }

    let mut draft = Draft::new(mesh, op);
    let mut copy_of_fan = vec![u32::MAX; fan_count];
    let mut copies: Vec<Copy> = Vec::new();
    for f in mesh.faces().filter(|&f| mask[f.index()]) {
        for c in corners.of_face(f) {
            let h = corners.halfedge[c];
            let (into, out) = (mesh.prev(h), h);
            if !(border(into) || border(out)) {
                continue;
            }
            let k = fan[c] as usize;
            if copy_of_fan[k] == u32::MAX {
                let v = mesh.from_vertex(h);
                copy_of_fan[k] = copies.len() as u32;
                copies.push(Copy {
                    vertex: draft.add_vertex(mesh.position(v), VertexOrigin::CopyOf(v)),
                    source: v,
                    incoming: HalfedgeId::INVALID,
                    outgoing: HalfedgeId::INVALID,
                    area: DVec3::ZERO,
                    region: region_of_face[f.index()],
                });
            }
            let copy = &mut copies[copy_of_fan[k] as usize];
            if border(into) {
                copy.incoming = into;
            }
            if border(out) {
                copy.outgoing = out;
            }
        }
    }
    // Area of each copy's fan (every selected face at the copied vertex in the fan).
    for f in mesh.faces().filter(|&f| mask[f.index()]) {
        let area = mesh.face_area_vector(f);
        for c in corners.of_face(f) {
            let k = copy_of_fan[fan[c] as usize];
            if k != u32::MAX {
                copies[k as usize].area += area;
            }
        }
    }

    let corner_vertex = |c: usize| {
        let k = copy_of_fan[fan[c] as usize];
        if k == u32::MAX { mesh.from_vertex(corners.halfedge[c]).0 } else { copies[k as usize].vertex }
    };
    let mut interior = Vec::new();
    let mut seen = vec![false; mesh.vertex_count()];
    for f in mesh.faces() {
        if !mask[f.index()] {
            draft.keep_face(f);
            continue;
        }
        let range = corners.of_face(f);
        draft.push_face(range.clone().map(corner_vertex), FaceOrigin::Same(f));
        for c in range {
            let v = mesh.from_vertex(corners.halfedge[c]);
            if copy_of_fan[fan[c] as usize] == u32::MAX && !seen[v.index()] {
                seen[v.index()] = true;
                interior.push((v.0, region_of_face[f.index()]));
            }
        }
    }
    for f in mesh.faces().filter(|&f| mask[f.index()]) {
        for c in corners.of_face(f) {
            let h = corners.halfedge[c];
            if border(h) {
                let (a, b) = (mesh.from_vertex(h).0, mesh.to_vertex(h).0);
                let (a2, b2) = (corner_vertex(c), corner_vertex(corners.of_halfedge[mesh.next(h).index()] as usize));
                draft.push_face([a, b, b2, a2], FaceOrigin::SweptFrom(h.edge()));
            }
        }
    }
    Ok(Lift { draft, copies, interior, region_of_face, region_count, mask })
}
