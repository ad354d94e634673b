//! From a polygon cage to a curve mesh on its Catmull–Clark limit surface (the seed paper's §3
//! and §5; `docs/curve-mesh-gregory.md` §3–5).
//!
//! 1. A cage with any face that is not a quad is first subdivided once by Catmull–Clark, and the
//!    curve mesh gets that all-quad mesh's topology (§5, the paper's choice for its dog model);
//!    an all-quad cage keeps its own. Call that mesh `M`; cage vertex `i` is vertex `i` of `M`.
//! 2. `M` is subdivided twice more. Each edge of `M` is then a chain of 5 vertices; their limit
//!    points `v*₀..v*₄`, at parameters 0, ¼, ½, ¾, 1, give the edge's cubic by least squares with
//!    `P0 = v*₀`, `P3 = v*₄` ([`fit_with_fixed_ends`], §3).
//! 3. At every vertex of `M` the curve-mesh vertex is its limit point and its tangent plane the
//!    limit normal's. Each curve's inner point next to a vertex is projected onto that plane, and
//!    with the projected curve's unit end tangents held fixed the leg lengths are refitted to the
//!    three inner limit points ([`refit_with_tangents`], Hoschek, §4). A leg length ≤ 0 is
//!    replaced by the projected curve's own leg length (or a third of the chord when that
//!    vanishes) and reported as an [`AlphaGuard`].
//!
//! 4. The limit surface at every curve's middle (the middle of its level-2 chain) goes to the
//!    curve mesh: the patches' cross-boundary field turns through its normal, with the length
//!    fitted to its cross derivatives there ([`super::middle`],
//!    [`super::chiyokura_kimura::side_inner_points`]; `docs/curve-mesh-gregory.md`, "Where we
//!    depart").
//!
//! Limit points and normals come from [`crate::subdiv`] (its documentation gives the rules):
//! interior vertices by Halstead, Kass & DeRose's masks (`docs/subdivision.md` §2); **open
//! boundaries** by the edge-only boundary rules, so a boundary vertex's limit is
//! `(e_prev + 4v + e_next)/6` on the cubic B-spline of the boundary polygon and its normal is the
//! boundary tangent `e_next − e_prev` crossed with the exact cross-boundary tangent of the sector,
//! from the eigenvectors of its subdivision matrix (`k = 1` face: `(e_a + e_b)/2 − v`). Boundary
//! patches are built like all others: the Chiyokura–Kimura rule gives every side, the open ones
//! included, the cross derivative `k b + h C'` from its end normals and the neighbouring legs; an
//! open side has no partner to be G1 with. A single face's corner (valence 2 on the boundary) is
//! smoothed by the boundary rule, so its two curves leave it in opposite directions and that patch
//! corner is flat (180°; its normal there comes from the vertex's tangent plane).
//!
//! Every normal is turned to agree with the faces' winding (the area vector of the faces around
//! the vertex two levels down). Where the limit normal is undefined (zero-area faces around the
//! vertex) the area-weighted normal of those faces is used and the vertex reported; if that
//! vanishes too the build fails naming the vertex.

use super::bezier::{fit_with_fixed_ends, refit_with_tangents};
use super::closeness::{LimitCloseness, interior_closeness};
use super::curve_mesh::CurveMesh;
use crate::mesh::{EdgeId, PolyMesh, VertexId};
use crate::subdiv::{RefinedPositions, Refinement, Scheme};
use crate::{DVec3, Error, Result};
use rayon::prelude::*;

/// The parameters of the five limit points along an edge.
const PARAMS: [f64; 3] = [0.25, 0.5, 0.75];

/// A leg length the Hoschek refit gave as ≤ 0, and what replaced it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AlphaGuard {
    /// The curve (edge of the curve mesh).
    pub curve: EdgeId,
    /// The end vertex whose leg it is.
    pub end: VertexId,
    /// The refitted length `α` (≤ 0).
    pub alpha: f64,
    /// The length used instead.
    pub used: f64,
}

/// Edge curves fitted on a mesh's limit surface, before they become a curve mesh.
#[derive(Clone, Debug)]
pub struct EdgeCurves {
    /// Per vertex of the mesh: its limit point.
    pub positions: Vec<DVec3>,
    /// Per vertex: its unit limit normal (oriented with the faces' winding).
    pub normals: Vec<DVec3>,
    /// Per edge: the inner points `[P1, P2]` from the edge's first vertex to its second.
    pub inner: Vec<[DVec3; 2]>,
    /// The figures of the fit.
    pub report: FitReport,
}

/// How well the curves fit the limit surface (`docs/curve-mesh-gregory.md` §3–4 and §7).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct FitReport {
    /// Largest distance from an inner limit point (`v*₁..v*₃`) to its curve (closest point).
    pub max_limit_to_curve: f64,
    /// The curve where it occurs.
    pub worst_curve: Option<EdgeId>,
    /// Largest `|C(tₖ) − v*ₖ|` at the fit's own parameters ¼, ½, ¾.
    pub max_residual: f64,
    /// Largest distance from a vertex two levels down on an edge chain to its limit point (the
    /// paper's "level-2 vertex to limit point" figure).
    pub max_chain_to_limit: f64,
    /// Largest distance from any vertex two levels down to its limit point.
    pub max_level2_to_limit: f64,
    /// Longest edge of the mesh the curves were fitted on.
    pub longest_edge: f64,
    /// Largest distance the tangent-plane projection moved an inner point (§4 step 1).
    pub max_projection: f64,
    /// Leg lengths the refit gave as ≤ 0 (§4 step 2).
    pub alpha_guards: Vec<AlphaGuard>,
    /// Vertices whose limit normal was undefined and replaced by the area-weighted normal.
    pub fallback_normals: Vec<VertexId>,
}

/// What building a curve mesh from a cage did and measured.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct BuildReport {
    /// True when the cage had faces other than quads and was subdivided once first (§5).
    pub subdivided_first: bool,
    /// The curve fit on the curve mesh's own edges.
    pub fit: FitReport,
    /// Closeness of the patches to the limit surface (§7).
    pub closeness: LimitCloseness,
}

/// Fits one cubic per edge of `mesh` (any polygons; the limit is taken two Catmull–Clark levels
/// down) with the tangent-plane correction and Hoschek refit of §4.
pub fn fit_edge_curves(mesh: &PolyMesh) -> Result<EdgeCurves> {
    Ok(fit_on_refinement(mesh)?.0)
}

/// [`fit_edge_curves`] and the refinement it used, with its positions.
fn fit_on_refinement(mesh: &PolyMesh) -> Result<(EdgeCurves, Refinement, RefinedPositions)> {
    check_cage(mesh)?;
    let refinement = Refinement::new(mesh, Scheme::CatmullClark, &[], 2)?;
    let mut refined = RefinedPositions::default();
    refinement.evaluate(mesh.positions(), &mut refined)?;
    let fine = refinement.mesh(2);
    let level2 = refined.finest();
    let mut report =
        FitReport { longest_edge: mesh.edges().map(|e| mesh.edge_length(e)).fold(0.0, f64::max), ..Default::default() };
    report.max_level2_to_limit = level2.iter().zip(&refined.limit).map(|(p, l)| p.distance(*l)).fold(0.0, f64::max);

    // Vertex positions and normals: level-2 vertex v is mesh vertex v.
    let n = mesh.vertex_count();
    let positions = refined.limit[..n].to_vec();
    let mut normals = Vec::with_capacity(n);
    for v in mesh.vertices() {
        if mesh.is_isolated(v) {
            normals.push(DVec3::Z);
            continue;
        }
        let area: DVec3 =
            fine.outgoing(v).filter(|&h| fine.face(h).is_valid()).map(|h| face_area_vector(fine, level2, h)).sum();
        let limit = refined.normals[v.index()];
        let normal = if limit.length() > 0.5 {
            if limit.dot(area) < 0.0 { -limit } else { limit }
        } else if area.length() > 0.0 {
            report.fallback_normals.push(v);
            area.normalize()
        } else {
            return Err(Error::Input(format!(
                "the limit surface has no tangent plane at cage vertex {} (the faces around it have no area); move its neighbours apart",
                v.0
            )));
        };
        normals.push(normal);
    }

    let fits: Vec<EdgeFit> = mesh
        .edges()
        .collect::<Vec<_>>()
        .par_iter()
        .map(|&e| fit_edge(mesh, &refinement, &refined, &positions, &normals, e))
        .collect::<Result<_>>()?;
    let mut inner = Vec::with_capacity(fits.len());
    for (e, fit) in fits.into_iter().enumerate() {
        let e = EdgeId(e as u32);
        inner.push(fit.inner);
        if fit.distance > report.max_limit_to_curve || report.worst_curve.is_none() {
            report.max_limit_to_curve = fit.distance;
            report.worst_curve = Some(e);
        }
        report.max_residual = report.max_residual.max(fit.residual);
        report.max_chain_to_limit = report.max_chain_to_limit.max(fit.chain_to_limit);
        report.max_projection = report.max_projection.max(fit.projection);
        report.alpha_guards.extend(fit.guards);
    }
    Ok((EdgeCurves { positions, normals, inner, report }, refinement, refined))
}

/// Refuses a cage without faces or with a zero-length edge.
fn check_cage(mesh: &PolyMesh) -> Result<()> {
    if mesh.face_count() == 0 {
        return Err(Error::Input("the cage has no faces; a curve mesh needs at least one face".into()));
    }
    for e in mesh.edges() {
        if mesh.edge_length(e) == 0.0 {
            let (a, b) = mesh.edge_vertices(e);
            return Err(Error::Input(format!(
                "cage edge {}–{} has zero length (both vertices at {}); merge the two vertices or move one apart",
                a.0,
                b.0,
                mesh.position(a)
            )));
        }
    }
    Ok(())
}

/// The area vector of the face left of `h` at positions `p`.
fn face_area_vector(mesh: &PolyMesh, p: &[DVec3], h: crate::mesh::HalfedgeId) -> DVec3 {
    let f = mesh.face(h);
    0.5 * mesh
        .face_halfedges(f)
        .map(|g| p[mesh.from_vertex(g).index()].cross(p[mesh.to_vertex(g).index()]))
        .sum::<DVec3>()
}

struct EdgeFit {
    inner: [DVec3; 2],
    distance: f64,
    residual: f64,
    chain_to_limit: f64,
    projection: f64,
    guards: Vec<AlphaGuard>,
}

fn fit_edge(
    mesh: &PolyMesh,
    refinement: &Refinement,
    refined: &RefinedPositions,
    positions: &[DVec3],
    normals: &[DVec3],
    e: EdgeId,
) -> Result<EdgeFit> {
    let chain = refinement.cage_edge_chain(e, 2)?;
    let limits: Vec<DVec3> = chain.iter().map(|w| refined.limit[w.index()]).collect();
    let chain_to_limit =
        chain.iter().map(|w| refined.finest()[w.index()].distance(refined.limit[w.index()])).fold(0.0, f64::max);
    let (a, b) = mesh.edge_vertices(e);
    let (p0, p3) = (positions[a.index()], positions[b.index()]);
    let inside = &limits[1..4];
    let free = fit_with_fixed_ends(p0, p3, inside, &PARAMS)
        .expect("three distinct parameters determine a cubic's inner points");
    // §4 step 1: the inner points onto the end vertices' tangent planes.
    let (na, nb) = (normals[a.index()], normals[b.index()]);
    let q1 = free.points[1] - (free.points[1] - p0).dot(na) * na;
    let q2 = free.points[2] - (free.points[2] - p3).dot(nb) * nb;
    let projection = q1.distance(free.points[1]).max(q2.distance(free.points[2]));
    // §4 step 2: hold the unit end tangents, refit the two leg lengths.
    let chord = p3 - p0;
    let t1 = tangent_in_plane(q1 - p0, chord, na);
    let t2 = tangent_in_plane(p3 - q2, chord, nb);
    let refit = refit_with_tangents(p0, p3, t1, t2, inside, &PARAMS);
    let mut guards = Vec::new();
    let mut guard = |alpha: f64, projected: f64, end: VertexId| {
        if alpha > 0.0 {
            return alpha;
        }
        let used = if projected > 1e-9 * chord.length() { projected } else { chord.length() / 3.0 };
        guards.push(AlphaGuard { curve: e, end, alpha, used });
        used
    };
    let alpha1 = guard(refit.alpha_start, (q1 - p0).length(), a);
    let alpha2 = guard(refit.alpha_end, (p3 - q2).length(), b);
    let curve = super::CubicBezier::new(p0, p0 + alpha1 * t1, p3 - alpha2 * t2, p3);
    let distance = inside.iter().map(|&p| curve.distance_to(p).1).fold(0.0, f64::max);
    let residual = inside.iter().zip(PARAMS).map(|(&p, t)| curve.point(t).distance(p)).fold(0.0, f64::max);
    Ok(EdgeFit { inner: [curve.points[1], curve.points[2]], distance, residual, chain_to_limit, projection, guards })
}

/// The unit direction of `leg` in the plane with normal `n`, else of the chord's projection,
/// else any direction in the plane (a curve whose ends coincide along the normal).
fn tangent_in_plane(leg: DVec3, chord: DVec3, n: DVec3) -> DVec3 {
    let scale = chord.length().max(leg.length());
    for d in [leg, chord - chord.dot(n) * n] {
        if d.length() > 1e-9 * scale && d.length() > 0.0 {
            return d.normalize();
        }
    }
    n.any_orthonormal_vector()
}

impl CurveMesh {
    /// Builds the curve mesh of a cage: one Catmull–Clark step first when the cage has faces
    /// other than quads, then the edge curves of §3–4 on the limit surface, then the patches.
    /// Errors: no faces, a zero-length cage edge, a vertex without a tangent plane; the
    /// subdivision's own checks (size, non-finite positions).
    pub fn from_cage(cage: &PolyMesh) -> Result<(CurveMesh, BuildReport)> {
        check_cage(cage)?;
        let subdivided_first = cage.faces().any(|f| cage.face_valence(f) != 4);
        let quads = if subdivided_first {
            let once = Refinement::new(cage, Scheme::CatmullClark, &[], 1)?;
            let mut positions = RefinedPositions::default();
            once.evaluate_levels(cage.positions(), &mut positions)?;
            once.surface(positions.finest())
        } else {
            cage.clone()
        };
        let (curves, refinement, refined) = fit_on_refinement(&quads)?;
        let mut topology = quads;
        topology.positions_mut().copy_from_slice(&curves.positions);
        // The limit surface at every curve's middle (its normal and cross derivatives), read
        // with the curves in place.
        let mesh = CurveMesh::from_parts(topology, curves.normals, curves.inner)?;
        let middles = super::middle::limit_middles(&mesh, &refinement, &refined)?;
        let mesh = mesh.with_middles(middles)?;
        let closeness = interior_closeness(&mesh, &refinement, &refined.limit)?;
        Ok((mesh, BuildReport { subdivided_first, fit: curves.report, closeness }))
    }
}
