//! Mirror symmetry about an axis-aligned plane: finding partners, editing both halves at once,
//! and making the mirrored half real.
//!
//! The plane is `x = offset`, `y = offset` or `z = offset`. Tolerances are relative to the
//! cage's bounding-box diagonal ([`DEFAULT_MIRROR_TOLERANCE`] by default): a vertex within it of
//! the plane is *on* the plane, and two vertices pair when each is the other's nearest vertex
//! within it of its reflection (mutual nearest, so a crowded spot never pairs one vertex twice).
//! The search uses a uniform grid, linear for evenly spread vertices.
//!
//! [`apply_mirror`] duplicates the cage across the plane, welds the vertices on the plane (and
//! snaps them exactly onto it), and reverses the mirrored faces so the whole stays consistently
//! oriented; mirrored positions are the exact reflections of the originals. It needs one half:
//! a cage with vertices on both sides, a face lying in the plane, an edge in the plane that
//! already has two faces, or a vertex that touches the plane only at a point (the halves would
//! pinch there) is refused with the element named.
//!
//! [`mirror_moves`] turns a move of some vertices into the moves of their partners: a moved
//! vertex's partner goes to its reflection, a plane vertex keeps its normal coordinate on the
//! plane, and when both partners are moved the pair goes to the symmetric configuration nearest
//! to what was asked (the mean of one's target and the reflection of the other's).

use super::Edited;
use super::draft::Draft;
use super::provenance::{FaceOrigin, VertexOrigin};
use super::spatial::PointGrid;
use crate::mesh::{PolyMesh, VertexId};
use crate::{DVec3, Error, Result};
use std::collections::BTreeMap;

/// Default tolerance of the mirror helpers, relative to the bounding-box diagonal.
pub const DEFAULT_MIRROR_TOLERANCE: f64 = 1e-6;

/// A coordinate axis.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Axis {
    X,
    Y,
    Z,
}

impl Axis {
    fn index(self) -> usize {
        match self {
            Axis::X => 0,
            Axis::Y => 1,
            Axis::Z => 2,
        }
    }
    fn name(self) -> &'static str {
        ["x", "y", "z"][self.index()]
    }
}

/// The plane `axis = offset`.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct MirrorPlane {
    pub axis: Axis,
    pub offset: f64,
}

impl MirrorPlane {
    /// The plane through `offset` across `axis`.
    pub fn new(axis: Axis, offset: f64) -> Self {
        MirrorPlane { axis, offset }
    }
    /// Signed distance of a point from the plane.
    pub fn distance(&self, p: DVec3) -> f64 {
        p[self.axis.index()] - self.offset
    }
    /// The mirror image of a point.
    pub fn reflect(&self, p: DVec3) -> DVec3 {
        let mut q = p;
        q[self.axis.index()] = 2.0 * self.offset - p[self.axis.index()];
        q
    }
    /// The point moved onto the plane along its normal.
    pub fn project(&self, p: DVec3) -> DVec3 {
        let mut q = p;
        q[self.axis.index()] = self.offset;
        q
    }
    fn describe(&self) -> String {
        format!("{} = {:?}", self.axis.name(), self.offset)
    }
}

/// A vertex's counterpart across the plane.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MirrorPartner {
    /// The vertex lies on the plane and is its own mirror image.
    OnPlane,
    /// The vertex at the mirror image of this one.
    Partner(VertexId),
    /// No vertex lies at the mirror image.
    Unpaired,
}

fn absolute_tolerance(op: &str, mesh: &PolyMesh, plane: &MirrorPlane, tolerance: f64) -> Result<f64> {
    if !(tolerance.is_finite() && tolerance >= 0.0) {
        return Err(Error::Input(format!("{op}: the tolerance must be a finite number ≥ 0, not {tolerance:?}")));
    }
    if !plane.offset.is_finite() {
        return Err(Error::Input(format!("{op}: the mirror plane's offset must be finite, not {:?}", plane.offset)));
    }
    Ok(tolerance * mesh.bounding_diagonal())
}

/// Each vertex's partner across the plane (see the module docs for the tolerance).
pub fn mirror_partners(mesh: &PolyMesh, plane: MirrorPlane, tolerance: f64) -> Result<Vec<MirrorPartner>> {
    let tol = absolute_tolerance("mirror", mesh, &plane, tolerance)?;
    let diagonal = mesh.bounding_diagonal();
    let cell = (8.0 * tol).max(diagonal / 1024.0).max(f64::MIN_POSITIVE);
    let off_plane: Vec<bool> = mesh.positions().iter().map(|&p| plane.distance(p).abs() > tol).collect();
    let grid = PointGrid::new(mesh.positions(), mesh.vertices().filter(|v| off_plane[v.index()]).map(|v| v.0), cell);
    let nearest = |v: VertexId| -> Option<VertexId> {
        let target = plane.reflect(mesh.position(v));
        let side = plane.distance(mesh.position(v)).signum();
        let mut best: Option<(f64, u32)> = None;
        grid.near(target, tol, |w| {
            let p = mesh.position(VertexId(w));
            let d = p.distance(target);
            if w != v.0 && d <= tol && plane.distance(p).signum() != side && best.is_none_or(|b| (d, w) < b) {
                best = Some((d, w));
            }
        });
        best.map(|(_, w)| VertexId(w))
    };
    let candidate: Vec<Option<VertexId>> =
        mesh.vertices().map(|v| if off_plane[v.index()] { nearest(v) } else { None }).collect();
    Ok(mesh
        .vertices()
        .map(|v| {
            if !off_plane[v.index()] {
                return MirrorPartner::OnPlane;
            }
            match candidate[v.index()] {
                Some(w) if candidate[w.index()] == Some(v) => MirrorPartner::Partner(w),
                _ => MirrorPartner::Unpaired,
            }
        })
        .collect())
}

/// Makes the mirrored half real (see the module docs): old elements stay
/// ([`VertexOrigin::Same`]), the mirror images are [`VertexOrigin::MirrorOf`] them.
pub fn apply_mirror(mesh: &PolyMesh, plane: MirrorPlane, tolerance: f64) -> Result<Edited> {
    const OP: &str = "apply mirror";
    let tol = absolute_tolerance(OP, mesh, &plane, tolerance)?;
    let on_plane: Vec<bool> = mesh.positions().iter().map(|&p| plane.distance(p).abs() <= tol).collect();
    let mut sides: [Option<VertexId>; 2] = [None, None];
    for v in mesh.vertices().filter(|v| !on_plane[v.index()]) {
        let s = usize::from(plane.distance(mesh.position(v)) > 0.0);
        sides[s].get_or_insert(v);
    }
    match sides {
        [Some(a), Some(b)] => {
            return Err(Error::Topology(format!(
                "{OP}: the cage has vertices on both sides of the plane {} (vertices {} and {}); delete one half \
                 first",
                plane.describe(),
                a.0,
                b.0
            )));
        }
        [None, None] => {
            return Err(Error::Topology(format!(
                "{OP}: the whole cage lies in the plane {}, so it has no half to mirror",
                plane.describe()
            )));
        }
        _ => {}
    }
    if let Some(f) = mesh.faces().find(|&f| mesh.face_vertices(f).all(|v| on_plane[v.index()])) {
        return Err(Error::Topology(format!(
            "{OP}: face {} lies in the plane {}, so its mirror image would coincide with it",
            f.0,
            plane.describe()
        )));
    }
    let in_plane = |e: crate::EdgeId| {
        let (a, b) = mesh.edge_vertices(e);
        on_plane[a.index()] && on_plane[b.index()]
    };
    if let Some(e) = mesh.edges().find(|&e| in_plane(e) && !mesh.is_boundary_edge(e)) {
        let (a, b) = mesh.edge_vertices(e);
        return Err(Error::Topology(format!(
            "{OP}: edge {}-{} lies in the plane with faces on both sides already, so mirroring would give it four",
            a.0, b.0
        )));
    }
    for v in mesh.vertices().filter(|v| on_plane[v.index()] && !mesh.is_isolated(*v)) {
        let glued = mesh.is_boundary_vertex(v) && {
            let out = mesh.vertex_halfedge(v);
            in_plane(out.edge()) || in_plane(mesh.prev(out).edge())
        };
        if !glued {
            return Err(Error::Topology(format!(
                "{OP}: vertex {} touches the plane {} without an open edge lying in it, so the two halves would \
                 meet only at that point; move it off the plane or open the cage along the plane",
                v.0,
                plane.describe()
            )));
        }
    }

    let mut draft = Draft::new(mesh, OP);
    let mut image = vec![0u32; mesh.vertex_count()];
    for v in mesh.vertices() {
        image[v.index()] = if on_plane[v.index()] {
            draft.positions[v.index()] = plane.project(mesh.position(v));
            v.0
        } else {
            draft.add_vertex(plane.reflect(mesh.position(v)), VertexOrigin::MirrorOf(v))
        };
    }
    for f in mesh.faces() {
        draft.keep_face(f);
    }
    let mut ring: Vec<u32> = Vec::new();
    for f in mesh.faces() {
        ring.clear();
        ring.extend(mesh.face_vertices(f).map(|v| image[v.index()]));
        ring.reverse();
        draft.push_face(ring.iter().copied(), FaceOrigin::MirrorOf(f));
    }
    draft.finish()
}

/// The positions to give vertices when `moves` (vertex, new position) are made under mirror
/// editing: the moved vertices (plane vertices kept on the plane, partners moved together
/// symmetrically) and their partners, sorted by vertex. A vertex listed twice takes its last
/// position.
pub fn mirror_moves(
    partners: &[MirrorPartner],
    plane: MirrorPlane,
    moves: &[(VertexId, DVec3)],
) -> Result<Vec<(VertexId, DVec3)>> {
    let mut wanted: BTreeMap<u32, DVec3> = BTreeMap::new();
    for &(v, p) in moves {
        if v.index() >= partners.len() {
            return Err(Error::Input(format!(
                "mirror: vertex {} does not exist (the cage has {} vertices)",
                v.0,
                partners.len()
            )));
        }
        if !p.is_finite() {
            return Err(Error::Input(format!("mirror: the new position of vertex {} is not finite ({p:?})", v.0)));
        }
        wanted.insert(v.0, p);
    }
    let mut out: BTreeMap<u32, DVec3> = BTreeMap::new();
    for (&v, &p) in &wanted {
        match partners[v as usize] {
            MirrorPartner::OnPlane => {
                out.insert(v, plane.project(p));
            }
            MirrorPartner::Unpaired => {
                out.insert(v, p);
            }
            MirrorPartner::Partner(w) => match wanted.get(&w.0) {
                // Both moved: handled once, from the partner with the lower number.
                Some(_) if w.0 < v => {}
                Some(&q) => {
                    let mid = 0.5 * (p + plane.reflect(q));
                    out.insert(v, mid);
                    out.insert(w.0, plane.reflect(mid));
                }
                None => {
                    out.insert(v, p);
                    out.insert(w.0, plane.reflect(p));
                }
            },
        }
    }
    Ok(out.into_iter().map(|(v, p)| (VertexId(v), p)).collect())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::FaceId;
    use crate::mesh::edit::fixtures::{check, counts, cube, grid};
    use crate::mesh::edit::{EdgeOrigin, delete_faces};

    fn volume(m: &PolyMesh) -> f64 {
        m.triangles()
            .iter()
            .map(|t| {
                let [a, b, c] = t.map(|v| m.position(VertexId(v)));
                a.dot(b.cross(c)) / 6.0
            })
            .sum()
    }

    #[test]
    fn partners_on_the_plane_and_across_it() {
        let g = grid(3); // x = 0, 1, 2, 3
        let plane = MirrorPlane::new(Axis::X, 1.0);
        let partners = mirror_partners(&g, plane, DEFAULT_MIRROR_TOLERANCE).unwrap();
        for v in g.vertices() {
            let p = g.position(v);
            let expected = match p.x as i32 {
                1 => MirrorPartner::OnPlane,
                0 => MirrorPartner::Partner(VertexId(v.0 + 2)),
                2 => MirrorPartner::Partner(VertexId(v.0 - 2)),
                _ => MirrorPartner::Unpaired,
            };
            assert_eq!(partners[v.index()], expected, "{v:?} at {p}");
        }
        // A symmetric cube about its middle: everything pairs, within a loose tolerance too.
        let mut c = cube();
        c.set_position(VertexId(1), DVec3::new(1.0 + 1e-9, 0.0, 0.0));
        let partners = mirror_partners(&c, MirrorPlane::new(Axis::X, 0.5), 1e-6).unwrap();
        assert!(partners.iter().all(|p| matches!(p, MirrorPartner::Partner(_))));
        assert_eq!(partners[0], MirrorPartner::Partner(VertexId(1)));
        let strict = mirror_partners(&c, MirrorPlane::new(Axis::X, 0.5), 0.0).unwrap();
        assert_eq!(strict[0], MirrorPartner::Unpaired);
    }

    #[test]
    fn applying_a_mirror_closes_half_a_box() {
        let half = delete_faces(&cube(), &[FaceId(4)]).unwrap().mesh; // open at x = 0
        let plane = MirrorPlane::new(Axis::X, 0.0);
        let edited = apply_mirror(&half, plane, DEFAULT_MIRROR_TOLERANCE).unwrap();
        check(&half, &edited);
        let m = &edited.mesh;
        assert_eq!(counts(m), (12, 20, 10));
        assert!(m.is_closed());
        assert!((volume(m) - 2.0).abs() < 1e-12);
        for v in m.vertices() {
            if let VertexOrigin::MirrorOf(s) = edited.provenance.vertices[v.index()] {
                assert_eq!(m.position(v), plane.reflect(half.position(s)));
            }
        }
        // Mirrored edges carry the tension of their source, found by reflected positions.
        let tension: Vec<f64> = half.edges().map(|e| 1.0 + e.0 as f64).collect();
        let carried = crate::mesh::edit::carry_edge_property(
            &tension,
            &edited.provenance,
            &crate::mesh::edit::CarryRule::new_elements(0.0),
        )
        .unwrap();
        let at = |p: DVec3| m.vertices().find(|&v| m.position(v) == p).unwrap();
        for e in half.edges() {
            let (a, b) = half.edge_vertices(e);
            for image in [|p: DVec3| p, |p: DVec3| MirrorPlane::new(Axis::X, 0.0).reflect(p)] {
                let (x, y) = (at(image(half.position(a))), at(image(half.position(b))));
                let there = m.find_halfedge(x, y).unwrap().edge();
                assert_eq!(carried[there.index()], tension[e.index()]);
            }
        }
        // The edges on the plane are the old ones, now with a face on each side.
        let in_plane = m.edges().filter(|&e| {
            let (a, b) = m.edge_vertices(e);
            m.position(a).x == 0.0 && m.position(b).x == 0.0
        });
        for e in in_plane {
            assert!(matches!(edited.provenance.edges[e.index()], EdgeOrigin::Same(_)));
        }
        // A grid mirrored about its edge x = 0 becomes a 6 × 3 grid; near-plane vertices are snapped.
        let mut g = grid(3);
        g.set_position(VertexId(4), DVec3::new(1e-9, 1.0, 0.0));
        let edited = apply_mirror(&g, plane, 1e-6).unwrap();
        check(&g, &edited);
        assert_eq!(counts(&edited.mesh), (28, 45, 18));
        assert_eq!(edited.mesh.position(VertexId(4)).x, 0.0);
        let total: DVec3 = edited.mesh.faces().map(|f| edited.mesh.face_area_vector(f)).sum();
        assert!((total - DVec3::new(0.0, 0.0, 18.0)).length() < 1e-9, "mirrored faces look the same way");
    }

    #[test]
    fn halves_that_cannot_be_mirrored_are_refused() {
        let plane = MirrorPlane::new(Axis::X, 0.0);
        let book = PolyMesh::from_polygons(
            vec![
                DVec3::ZERO,
                DVec3::Y,
                DVec3::new(1.0, 0.0, 1.0),
                DVec3::new(1.0, 1.0, 1.0),
                DVec3::new(1.0, 0.0, -1.0),
                DVec3::new(1.0, 1.0, -1.0),
            ],
            &[[0, 2, 3, 1], [1, 5, 4, 0]],
        )
        .unwrap();
        let point =
            PolyMesh::from_polygons(vec![DVec3::ZERO, DVec3::X, DVec3::new(1.0, 1.0, 0.0)], &[[0, 1, 2]]).unwrap();
        let flat = crate::mesh::primitives::quad_grid(2, 2, 1.0, 1.0).unwrap();
        let boxed = cube();
        let cases = [
            (apply_mirror(&boxed, MirrorPlane::new(Axis::X, 0.5), 1e-6).err(), "both sides"),
            (apply_mirror(&flat, MirrorPlane::new(Axis::Z, 0.0), 1e-6).err(), "whole cage lies in the plane"),
            (apply_mirror(&boxed, plane, 1e-6).err(), "lies in the plane"),
            (apply_mirror(&book, plane, 1e-6).err(), "would give it four"),
            (apply_mirror(&point, plane, 1e-6).err(), "only at that point"),
            (apply_mirror(&point, plane, f64::NAN).err(), "tolerance"),
            (apply_mirror(&point, MirrorPlane::new(Axis::Y, f64::INFINITY), 1e-6).err(), "offset"),
        ];
        for (err, expected) in cases {
            let err = err.expect("refused").to_string();
            assert!(err.contains(expected) && !err.contains('\n'), "expected '{expected}' in: {err}");
        }
    }

    #[test]
    fn moves_follow_across_the_plane() {
        let g = grid(3);
        let plane = MirrorPlane::new(Axis::X, 1.0);
        let partners = mirror_partners(&g, plane, DEFAULT_MIRROR_TOLERANCE).unwrap();
        let moves = [
            (VertexId(0), DVec3::new(-0.5, 0.2, 0.3)), // partner 2 follows
            (VertexId(5), DVec3::new(1.4, 1.0, 0.7)),  // on the plane: stays on it
            (VertexId(3), DVec3::new(3.0, 0.0, 1.0)),  // unpaired: moves alone
            (VertexId(8), DVec3::new(0.1, 2.0, 0.0)),  // both 8 and its partner 10 move
            (VertexId(10), DVec3::new(2.0, 2.0, 0.4)),
        ];
        let out = mirror_moves(&partners, plane, &moves).unwrap();
        let got: BTreeMap<u32, DVec3> = out.iter().map(|&(v, p)| (v.0, p)).collect();
        assert_eq!(got.len(), 6);
        assert_eq!(got[&2], DVec3::new(2.5, 0.2, 0.3));
        assert_eq!(got[&5], DVec3::new(1.0, 1.0, 0.7));
        assert_eq!(got[&3], DVec3::new(3.0, 0.0, 1.0));
        // 8 wanted x = 0.1 and its partner x = 2.0 (mirror 0.0): they meet half way, symmetric.
        assert!((got[&8] - DVec3::new(0.05, 2.0, 0.2)).length() < 1e-15);
        assert_eq!(got[&10], plane.reflect(got[&8]));
        let err = mirror_moves(&partners, plane, &[(VertexId(99), DVec3::ZERO)]).unwrap_err().to_string();
        assert!(err.contains("vertex 99 does not exist"), "{err}");
        let err = mirror_moves(&partners, plane, &[(VertexId(0), DVec3::NAN)]).unwrap_err().to_string();
        assert!(err.contains("not finite"), "{err}");
    }
}
