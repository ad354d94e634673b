//! Inset: a smaller copy of the selected faces inside them, joined to the old border by a ring of
//! quads.
//!
//! The topology is the lift of [`super::lift`]; only the copied border vertices move, inward in
//! the tangent plane of their fan (the mean plane of the selected faces at the vertex) so that
//! each new border edge runs parallel to its old edge at `thickness` from it: the corner moves
//! along the bisector of the two edges' inward normals by `thickness / cos(half the angle
//! between them)` (Blender's "even thickness"), capped at [`MAX_MITRE`] times the thickness at
//! needle-sharp corners. In a region the vertices inside stay. An inset is refused when it
//! would turn a face inside out (its area vector reverses) or reverse an inner edge, which is
//! where a thickness past about the face's inradius leads; warped faces inset in their mean
//! plane, so their copies are flattened a little towards it.

use super::draft::face_normal;
use super::extrude::MAX_MITRE;
use super::lift::lift;
use super::provenance::{EdgeOrigin, FaceOrigin, VertexOrigin};
use super::{Edited, FaceGrouping};
use crate::mesh::{FaceId, PolyMesh};
use crate::{Error, Result};

/// Insets faces by `thickness` (> 0), as one region or individually. The inner faces keep the
/// origins of the faces they were ([`FaceOrigin::Same`]), the ring quads are swept from the
/// border edges, the inner border is made of copies.
pub fn inset_faces(mesh: &PolyMesh, faces: &[FaceId], grouping: FaceGrouping, thickness: f64) -> Result<Edited> {
    const OP: &str = "inset faces";
    if !(thickness.is_finite() && thickness > 0.0) {
        return Err(Error::Input(format!(
            "{OP}: the thickness must be a finite number greater than 0, not {thickness:?}"
        )));
    }
    let mut lift = lift(mesh, faces, grouping, OP)?;
    if let Some(f) = mesh.faces().find(|&f| lift.mask[f.index()] && face_normal(mesh, f).is_none()) {
        return Err(Error::Topology(format!("{OP}: face {} has no area, so no plane to inset in", f.0)));
    }
    for c in &lift.copies {
        let v = c.source;
        if !c.incoming.is_valid() || !c.outgoing.is_valid() {
            return Err(Error::Topology(format!("{OP}: no border edges found at vertex {} of the selection", v.0)));
        }
        let n = c.area.normalize_or_zero();
        let p = mesh.position(v);
        let d_in = (p - mesh.position(mesh.from_vertex(c.incoming))).normalize_or_zero();
        let d_out = (mesh.position(mesh.to_vertex(c.outgoing)) - p).normalize_or_zero();
        let (n1, n2) = (n.cross(d_in).normalize_or_zero(), n.cross(d_out).normalize_or_zero());
        let dir = (n1 + n2).normalize_or_zero();
        let cos = dir.dot(n1);
        if n == glam::DVec3::ZERO || dir == glam::DVec3::ZERO || cos <= 1e-9 {
            return Err(Error::Topology(format!(
                "{OP}: the border of the selection folds back on itself at vertex {}, so there is no inward \
                 direction there; inset the faces individually",
                v.0
            )));
        }
        lift.draft.positions[c.vertex as usize] += thickness * (1.0 / cos).min(MAX_MITRE) * dir;
    }
    let edited = lift.draft.finish()?;
    check_not_folded(mesh, &edited, &lift.mask, thickness)?;
    Ok(edited)
}

/// Refuses an inset whose faces turned inside out or whose inner edges reversed.
fn check_not_folded(old: &PolyMesh, edited: &Edited, mask: &[bool], thickness: f64) -> Result<()> {
    const OP: &str = "inset faces";
    let new = &edited.mesh;
    let too_thick = |f: FaceId| {
        Error::Topology(format!(
            "{OP}: a thickness of {thickness:?} turns face {} inside out (its inset copy would fold over); use a \
             smaller thickness",
            f.0
        ))
    };
    for g in new.faces() {
        if let FaceOrigin::Same(f) = edited.provenance.faces[g.index()]
            && mask[f.index()]
            && new.face_area_vector(g).dot(old.face_area_vector(f)) <= 0.0
        {
            return Err(too_thick(f));
        }
    }
    for e in new.edges() {
        if let EdgeOrigin::CopyOf(old_e) = edited.provenance.edges[e.index()] {
            let (a, b) = new.edge_vertices(e);
            let (oa, ob) = old.edge_vertices(old_e);
            let source = |v: crate::VertexId| match edited.provenance.vertices[v.index()] {
                VertexOrigin::CopyOf(s) | VertexOrigin::Same(s) => s,
                _ => crate::VertexId::INVALID,
            };
            let sign = if source(a) == oa && source(b) == ob { 1.0 } else { -1.0 };
            let (d_new, d_old) = (new.position(b) - new.position(a), old.position(ob) - old.position(oa));
            if sign * d_new.dot(d_old) <= 0.0 {
                let selected = |h: crate::HalfedgeId| Some(old.face(h)).filter(|f| f.is_valid() && mask[f.index()]);
                let f = selected(old_e.halfedge(0)).or(selected(old_e.halfedge(1))).unwrap_or(FaceId(0));
                return Err(too_thick(f));
            }
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::DVec3;
    use crate::mesh::edit::fixtures::{check, counts, cube, grid, prism};
    use crate::mesh::edit::provenance::{CarryRule, carry_edge_property};

    #[test]
    fn an_inset_square_keeps_its_edges_at_the_thickness() {
        let cube = cube();
        let top = FaceId(1); // z = 1
        let edited = inset_faces(&cube, &[top], FaceGrouping::Individual, 0.25).unwrap();
        check(&cube, &edited);
        let m = &edited.mesh;
        assert_eq!(counts(m), (12, 20, 10));
        assert!(m.is_closed());
        // The inner square is [0.25, 0.75]² at z = 1, by the closed form of a square's inset.
        for v in m.vertices().skip(8) {
            let p = m.position(v);
            assert!((p.z - 1.0).abs() < 1e-15);
            for c in [p.x, p.y] {
                assert!((c - 0.25).abs() < 1e-12 || (c - 0.75).abs() < 1e-12, "{p}");
            }
        }
        // Inner edges take the tension of the outer edge they are parallel to.
        let tension: Vec<f64> = cube.edges().map(|e| 1.0 + e.0 as f64).collect();
        let carried = carry_edge_property(&tension, &edited.provenance, &CarryRule::new_elements(0.0)).unwrap();
        for e in m.edges() {
            let (a, b) = m.edge_vertices(e);
            let (pa, pb) = (m.position(a), m.position(b));
            if a.index() >= 8 && b.index() >= 8 {
                // Its outer edge: the top edge of the old cube at distance 0.25, same direction.
                let outer = cube
                    .edges()
                    .find(|&o| {
                        let (x, y) = cube.edge_vertices(o);
                        let (px, py) = (cube.position(x), cube.position(y));
                        px.z == 1.0
                            && py.z == 1.0
                            && (py - px).normalize().cross((pb - pa).normalize()).length() < 1e-12
                            && ((pa + pb) / 2.0 - (px + py) / 2.0).length() - 0.25 < 1e-12
                    })
                    .unwrap();
                assert_eq!(carried[e.index()], tension[outer.index()]);
            }
        }
    }

    #[test]
    fn region_inset_leaves_inside_vertices_and_insets_the_border() {
        let g = grid(3);
        let all: Vec<FaceId> = g.faces().collect();
        let edited = inset_faces(&g, &all, FaceGrouping::Region, 0.25).unwrap();
        check(&g, &edited);
        assert_eq!(counts(&edited.mesh), (28, 48, 21));
        assert_eq!(edited.mesh.positions()[..16], g.positions()[..]);
        let (lo, hi) = crate::mesh::bounding_box(&edited.mesh.positions()[16..]).unwrap();
        assert!((lo - DVec3::new(0.25, 0.25, 0.0)).length() < 1e-12);
        assert!((hi - DVec3::new(2.75, 2.75, 0.0)).length() < 1e-12);
        // A pentagon cap of a prism, individually: 5 copies.
        let p = prism(5);
        let edited = inset_faces(&p, &[FaceId(1)], FaceGrouping::Individual, 0.1).unwrap();
        check(&p, &edited);
        assert_eq!(counts(&edited.mesh), (15, 25, 12));
    }

    #[test]
    fn too_thick_an_inset_is_refused() {
        let cube = cube();
        for (t, expected) in [(0.6, "inside out"), (0.0, "greater than 0"), (f64::INFINITY, "finite")] {
            let err = inset_faces(&cube, &[FaceId(1)], FaceGrouping::Individual, t).unwrap_err().to_string();
            assert!(err.contains(expected), "{t}: {err}");
        }
        let err = inset_faces(&cube, &[FaceId(9)], FaceGrouping::Region, 0.1).unwrap_err().to_string();
        assert!(err.contains("face 9 does not exist"), "{err}");
    }
}
