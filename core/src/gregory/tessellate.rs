//! Fixed `K × K` tessellation of a curve mesh's patches into one crack-free polygon mesh with
//! analytic normals (`docs/curve-mesh-gregory.md` §7: each patch `K × K`, default 16, with analytic
//! normals).
//!
//! Every sample on a curve is one vertex shared by the patches on both sides, so neighbours can
//! never crack apart: a curve-mesh vertex is one vertex (its position, its tangent-plane normal
//! oriented like the patches around it), a curve's `K − 1` inner samples are evaluated on the
//! curve itself at `t = k/K` (the exact common boundary of both patches) with the normalised sum
//! of both patches' unit normals there (equal up to rounding, as the patches meet with G1), and a
//! patch's `(K − 1)²` interior samples come from the patch alone with `S_u × S_v` normalised.
//!
//! Vertex numbering: curve-mesh vertex `v` is vertex `v`; then `K − 1` samples per curve in curve
//! order, running from the curve's first vertex to its second; then `(K − 1)²` interior samples
//! per patch, row by row (`i` along `u` fastest). Faces: `K²` quads per patch, patch after patch,
//! counter-clockwise in `(u, v)` (so outward like the patch normal). Every value is a pure
//! function of the curve mesh around it, so [`Tessellation::update`] after an edit gives exactly
//! the values of a fresh tessellation, and both are the same for any thread count.

use super::bezier::{bernstein3, bernstein3_d1};
use super::curve_mesh::{Changed, CurveMesh};
use super::patch::{GregoryPatch, SurfacePatch};
use crate::mesh::{EdgeId, FaceId, HalfedgeId, PolyMesh, VertexId};
use crate::{DVec3, Error, Result};
use rayon::prelude::*;
use std::collections::BTreeSet;
use std::ops::Range;

/// The default number of samples per patch side.
pub const DEFAULT_SAMPLES: usize = 16;
/// The largest number of samples per patch side.
pub const MAX_SAMPLES: usize = 256;
/// The most quads a tessellation may have (about 2 GB of mesh, normals and build buffers).
pub const MAX_QUADS: usize = 1 << 24;

/// The tessellated patches of a curve mesh: one polygon mesh and one unit normal per vertex.
#[derive(Clone, Debug)]
pub struct Tessellation {
    samples: usize,
    mesh: PolyMesh,
    normals: Vec<DVec3>,
    /// Per patch, its four halfedges (side `k` of the patch is `sides[k]`).
    sides: Vec<[HalfedgeId; 4]>,
}

impl Tessellation {
    /// Samples every patch `samples × samples` (1 ≤ samples ≤ [`MAX_SAMPLES`]).
    pub fn new(curves: &CurveMesh, samples: usize) -> Result<Self> {
        if !(1..=MAX_SAMPLES).contains(&samples) {
            return Err(Error::Input(format!("samples {samples}: use 1 to {MAX_SAMPLES} samples per patch side")));
        }
        if curves.patch_count().saturating_mul(samples * samples) > MAX_QUADS {
            return Err(Error::Input(format!(
                "{} patches at {samples} × {samples} samples exceed the {MAX_QUADS} quads a tessellation may have; use fewer samples",
                curves.patch_count()
            )));
        }
        let topology = curves.topology();
        let sides: Vec<[HalfedgeId; 4]> = topology
            .faces()
            .map(|f| {
                let h0 = topology.face_halfedge(f);
                [h0, topology.next(h0), topology.next(topology.next(h0)), topology.prev(h0)]
            })
            .collect();
        let layout = Layout { samples, vertices: curves.vertex_count(), curves: curves.curve_count() };
        let total = layout.interior_start() + curves.patch_count() * (samples - 1) * (samples - 1);
        let mut indices = Vec::with_capacity(curves.patch_count() * samples * samples * 4);
        for (p, hs) in sides.iter().enumerate() {
            let grid = |i: usize, j: usize| layout.grid_vertex(topology, p, hs, i, j);
            for j in 0..samples {
                for i in 0..samples {
                    indices.extend([grid(i, j), grid(i + 1, j), grid(i + 1, j + 1), grid(i, j + 1)].map(|v| v.0));
                }
            }
        }
        let offsets: Vec<u32> = (0..=indices.len() / 4).map(|k| 4 * k as u32).collect();
        let mesh = PolyMesh::from_face_list(vec![DVec3::ZERO; total], &offsets, &indices)?;
        let mut out = Tessellation { samples, mesh, normals: vec![DVec3::ZERO; total], sides };
        out.evaluate_all(curves);
        Ok(out)
    }

    /// Samples per patch side.
    pub fn samples(&self) -> usize {
        self.samples
    }
    /// The tessellated surface.
    pub fn mesh(&self) -> &PolyMesh {
        &self.mesh
    }
    /// Unit normal per vertex of [`Tessellation::mesh`].
    pub fn normals(&self) -> &[DVec3] {
        &self.normals
    }
    /// The faces of [`Tessellation::mesh`] that tessellate patch `f` (a contiguous range of
    /// `samples²` quads).
    pub fn patch_faces(&self, f: FaceId) -> Range<usize> {
        let k = self.samples * self.samples;
        f.index() * k..(f.index() + 1) * k
    }
    /// The vertex at grid point `(i, j)` of patch `f` (`u = i/K`, `v = j/K`, `0 ≤ i, j ≤ K`).
    pub fn grid_vertex(&self, curves: &CurveMesh, f: FaceId, i: usize, j: usize) -> VertexId {
        self.layout(curves).grid_vertex(curves.topology(), f.index(), &self.sides[f.index()], i, j)
    }

    fn layout(&self, curves: &CurveMesh) -> Layout {
        Layout { samples: self.samples, vertices: curves.vertex_count(), curves: curves.curve_count() }
    }

    /// Re-evaluates the vertices of the changed patches (their corners, the samples on their
    /// curves, their interiors) after an edit of `curves`; the result equals a fresh
    /// [`Tessellation::new`] bit for bit. Returns the rewritten vertex index ranges, ascending
    /// (what an editor re-uploads).
    pub fn update(&mut self, curves: &CurveMesh, changed: &Changed) -> Result<Vec<Range<usize>>> {
        if self.sides.len() != curves.patch_count() || self.layout(curves).interior_start() > self.normals.len() {
            return Err(Error::Input("this tessellation belongs to another curve mesh; tessellate it anew".into()));
        }
        let topology = curves.topology();
        let (mut vertices, mut edges) = (BTreeSet::new(), BTreeSet::new());
        for &f in &changed.patches {
            for &h in &self.sides[f.index()] {
                vertices.insert(topology.from_vertex(h));
                edges.insert(h.edge());
            }
        }
        vertices.extend(changed.vertices.iter().copied());
        let layout = self.layout(curves);
        let k = self.samples;
        let vertex_list: Vec<VertexId> = vertices.iter().copied().collect();
        let edge_list: Vec<EdgeId> = edges.iter().copied().collect();
        let mut updates: Vec<(usize, DVec3, DVec3)> = vertex_list
            .par_iter()
            .map(|&v| {
                let (p, n) = corner_sample(curves, v);
                (v.index(), p, n)
            })
            .collect();
        updates.par_extend(edge_list.par_iter().flat_map_iter(|&e| {
            (1..k).map(move |s| {
                let (p, n) = curve_sample(curves, e, s, k);
                (layout.curve_sample(e, s), p, n)
            })
        }));
        let interiors: Vec<(FaceId, Vec<(DVec3, DVec3)>)> =
            changed.patches.par_iter().map(|&f| (f, interior_samples(curves, f, k))).collect();
        let mut ranges: Vec<Range<usize>> = vertices.iter().map(|v| v.index()..v.index() + 1).collect();
        ranges.extend(
            edges.iter().filter(|_| k > 1).map(|&e| layout.curve_sample(e, 1)..layout.curve_sample(e, k - 1) + 1),
        );
        let positions = self.mesh.positions_mut();
        for (index, p, n) in updates {
            positions[index] = p;
            self.normals[index] = n;
        }
        for (f, samples) in interiors {
            let start = layout.interior_start() + f.index() * (k - 1) * (k - 1);
            ranges.push(start..start + samples.len());
            for (offset, (p, n)) in samples.into_iter().enumerate() {
                positions[start + offset] = p;
                self.normals[start + offset] = n;
            }
        }
        ranges.retain(|r| !r.is_empty());
        ranges.sort_by_key(|r| r.start);
        Ok(ranges)
    }

    fn evaluate_all(&mut self, curves: &CurveMesh) {
        let k = self.samples;
        let layout = self.layout(curves);
        let mut values = vec![(DVec3::ZERO, DVec3::ZERO); self.normals.len()];
        let (corner, rest) = values.split_at_mut(layout.vertices);
        let (along, inside) = rest.split_at_mut(layout.curves * (k - 1));
        corner.par_iter_mut().enumerate().for_each(|(v, out)| *out = corner_sample(curves, VertexId(v as u32)));
        if k > 1 {
            along.par_chunks_mut(k - 1).enumerate().for_each(|(e, out)| {
                for (s, slot) in out.iter_mut().enumerate() {
                    *slot = curve_sample(curves, EdgeId(e as u32), s + 1, k);
                }
            });
            inside.par_chunks_mut((k - 1) * (k - 1)).enumerate().for_each(|(f, out)| {
                out.copy_from_slice(&interior_samples(curves, FaceId(f as u32), k));
            });
        }
        let positions = self.mesh.positions_mut();
        for (i, (p, n)) in values.into_iter().enumerate() {
            positions[i] = p;
            self.normals[i] = n;
        }
    }
}

/// Where each sample's vertex is.
#[derive(Clone, Copy)]
struct Layout {
    samples: usize,
    vertices: usize,
    curves: usize,
}

impl Layout {
    fn interior_start(&self) -> usize {
        self.vertices + self.curves * (self.samples - 1)
    }

    /// Sample `s` (`1 ≤ s < K`) of curve `e` in its own direction.
    fn curve_sample(&self, e: EdgeId, s: usize) -> usize {
        self.vertices + e.index() * (self.samples - 1) + s - 1
    }

    fn grid_vertex(&self, topology: &PolyMesh, patch: usize, sides: &[HalfedgeId; 4], i: usize, j: usize) -> VertexId {
        let k = self.samples;
        // Which side the grid point is on, and how far along that side's halfedge.
        let on_side = if j == 0 {
            Some((0, i))
        } else if i == k {
            Some((1, j))
        } else if j == k {
            Some((2, k - i))
        } else if i == 0 {
            Some((3, k - j))
        } else {
            None
        };
        let Some((side, s)) = on_side else {
            let index = self.interior_start() + patch * (k - 1) * (k - 1) + (j - 1) * (k - 1) + (i - 1);
            return VertexId(index as u32);
        };
        let h = sides[side];
        if s == 0 {
            return topology.from_vertex(h);
        }
        if s == k {
            return topology.to_vertex(h);
        }
        let e = h.edge();
        let along = if h == e.halfedge(0) { s } else { k - s };
        VertexId(self.curve_sample(e, along) as u32)
    }
}

/// The parameter point of a patch at position `s` of `K` along its side `side`.
fn side_parameter(side: usize, s: usize, k: usize) -> (f64, f64) {
    let t = s as f64 / k as f64;
    let back = (k - s) as f64 / k as f64;
    match side {
        0 => (t, 0.0),
        1 => (1.0, t),
        2 => (back, 1.0),
        _ => (0.0, back),
    }
}

/// A curve-mesh vertex: its position and its normal, turned to agree with the patches there.
fn corner_sample(curves: &CurveMesh, v: VertexId) -> (DVec3, DVec3) {
    let topology = curves.topology();
    let n = curves.vertex_normal(v);
    let mut sum = DVec3::ZERO;
    for h in topology.outgoing(v) {
        let f = topology.face(h);
        if !f.is_valid() {
            continue;
        }
        // Patch side k is the face's k-th halfedge from `face_halfedge(f)` and starts at corner k.
        let side = topology.face_halfedges(f).position(|x| x == h).expect("h is a halfedge of its face");
        let (u, w) = [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)][side];
        sum += patch_normal(curves.patch(f), u, w);
    }
    (curves.vertex_position(v), if sum.dot(n) < 0.0 { -n } else { n })
}

/// Sample `s` of curve `e` (`t = s/K` in the curve's own direction).
fn curve_sample(curves: &CurveMesh, e: EdgeId, s: usize, k: usize) -> (DVec3, DVec3) {
    let topology = curves.topology();
    let position = curves.curve(e).point(s as f64 / k as f64);
    let mut sum = DVec3::ZERO;
    for side_of_edge in 0..2 {
        let h = e.halfedge(side_of_edge);
        let f = topology.face(h);
        if !f.is_valid() {
            continue;
        }
        let side = topology.face_halfedges(f).position(|x| x == h).expect("h is a halfedge of its face");
        let along = if side_of_edge == 0 { s } else { k - s };
        let (u, v) = side_parameter(side, along, k);
        sum += patch_normal(curves.patch(f), u, v);
    }
    (position, sum.normalize_or(DVec3::Z))
}

/// The `(K − 1)²` interior samples of patch `f`, row by row.
fn interior_samples(curves: &CurveMesh, f: FaceId, k: usize) -> Vec<(DVec3, DVec3)> {
    let patch = curves.patch(f);
    let basis: Vec<([f64; 4], [f64; 4])> = (0..=k)
        .map(|i| {
            let t = i as f64 / k as f64;
            (bernstein3(t), bernstein3_d1(t))
        })
        .collect();
    let mut out = Vec::with_capacity((k - 1) * (k - 1));
    for j in 1..k {
        let v = j as f64 / k as f64;
        for i in 1..k {
            let u = i as f64 / k as f64;
            let (p, su, sv) =
                patch.first_derivatives_with(u, v, [&basis[i].0, &basis[i].1], [&basis[j].0, &basis[j].1]);
            // A patch collapsed to a line or point has no normal at all: +Z keeps the file valid.
            out.push((p, unit_normal(patch, u, v, su, sv).normalize_or(DVec3::Z)));
        }
    }
    out
}

/// `S_u × S_v` normalised, or the patch's limit normal where it vanishes.
fn unit_normal(patch: &GregoryPatch, u: f64, v: f64, su: DVec3, sv: DVec3) -> DVec3 {
    let n = su.cross(sv);
    let area = n.length_squared();
    if area > 1e-24 * su.length_squared() * sv.length_squared() && area > 0.0 {
        n / area.sqrt()
    } else {
        patch.normal(u, v).unwrap_or(DVec3::ZERO)
    }
}

/// The unit normal of a patch at `(u, v)` from its first derivatives.
fn patch_normal(patch: &GregoryPatch, u: f64, v: f64) -> DVec3 {
    let (_, su, sv) = patch.first_derivatives(u, v);
    unit_normal(patch, u, v, su, sv)
}
