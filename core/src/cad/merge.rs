//! Regular regions of the fitted B-rep merged into larger B-spline faces.
//!
//! Where the surface is one uniform bicubic B-spline across several patches (a regular region of
//! a Catmull–Clark surface: every face one span, the pieces C² across their sides), a grid of
//! such faces becomes one face whose surface has a simple knot at every former patch side and
//! whose outer loop is the grid's boundary edges: fewer, larger surfaces, as CAD users expect
//! from a regular region. The merged control points are found by collocation at the Greville
//! abscissae and the merge is kept only when the merged surface reproduces every patch it
//! replaces (at 25 points each) within [`EXACT`] of the model's size, so a fit that is only G¹
//! across a side (NUSD, the curve mesh) is never merged and the surface does not move.
//!
//! Grids are grown greedily from each face in order, trying its four turns and both growing
//! orders and keeping the largest; a grid's corner vertices are all distinct, so a merged face
//! is a disc (a ring of a torus does not close on itself). [`Placement`] says where each patch
//! went, so a patch's `(u, v)` can still be found on its merged face.

use super::assemble::side_uv;
use super::brep::{BSplineSurface, BrepFace, BrepModel, BrepShell};
use super::bspline::{self, DEGREE, Knots};
use crate::DVec3;
use crate::mesh::{FaceId, HalfedgeId, PolyMesh};

/// How far (a share of the model's bounding-box diagonal) a merged face may be from the patches
/// it replaces: rounding only.
pub const EXACT: f64 = 1e-10;

/// The most patches a merged face spans in each direction.
const MAX_BLOCK: usize = 64;

/// Where patch `f` of the network lies in the merged model: on face `face`, its own `(u, v)`
/// turned by `rotation` quarter turns and placed at `origin` in a grid of `size` patches.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Placement {
    pub face: usize,
    rotation: u8,
    origin: (usize, usize),
    size: (usize, usize),
}

impl Placement {
    /// The patch is a face of its own, parameters unchanged.
    pub fn alone(face: usize) -> Placement {
        Placement { face, rotation: 0, origin: (0, 0), size: (1, 1) }
    }

    /// The merged face's parameters of the patch's `(u, v)`.
    pub fn map(&self, u: f64, v: f64) -> (f64, f64) {
        let (s, t) = match self.rotation {
            0 => (u, v),
            1 => (v, 1.0 - u),
            2 => (1.0 - u, 1.0 - v),
            _ => (1.0 - v, u),
        };
        ((self.origin.0 as f64 + s) / self.size.0 as f64, (self.origin.1 as f64 + t) / self.size.1 as f64)
    }
}

/// A grid of patches: `cells[j][i]` is the halfedge of the patch in column `i`, row `j` that
/// runs along the grid's `u` on the patch's `v = 0` side.
struct Block {
    cells: Vec<Vec<HalfedgeId>>,
}

impl Block {
    fn area(&self) -> usize {
        self.cells.len() * self.cells[0].len()
    }
}

/// Merges the regular regions of `model` (one face per face of `layout`, as [`super::fit::fit`]
/// makes it; `sharp` per layout edge). Returns the merged model and each layout face's place.
pub fn merge_regular(model: BrepModel, layout: &PolyMesh, sharp: &[bool]) -> (BrepModel, Vec<Placement>) {
    let count = layout.face_count();
    let eligible: Vec<bool> = model.faces.iter().map(is_single_span).collect();
    let scale = diagonal(&model.vertices).max(f64::MIN_POSITIVE);
    let mut taken = vec![false; count];
    let mut placements: Vec<Option<Placement>> = vec![None; count];
    let mut faces = Vec::new();
    let mut new_index = vec![usize::MAX; count];
    for seed in layout.faces() {
        if taken[seed.index()] {
            continue;
        }
        taken[seed.index()] = true;
        let merged = if eligible[seed.index()] { best_block(layout, sharp, seed, &eligible, &taken) } else { None };
        let merged = merged.and_then(|block| merged_face(&model, layout, &block, scale).map(|face| (block, face)));
        let index = faces.len();
        match merged {
            Some((block, face)) => {
                let (a, b) = (block.cells[0].len(), block.cells.len());
                for (j, row) in block.cells.iter().enumerate() {
                    for (i, &h) in row.iter().enumerate() {
                        let f = layout.face(h);
                        taken[f.index()] = true;
                        new_index[f.index()] = index;
                        placements[f.index()] =
                            Some(Placement { face: index, rotation: turn(layout, h), origin: (i, j), size: (a, b) });
                    }
                }
                faces.push(face);
            }
            None => {
                new_index[seed.index()] = index;
                placements[seed.index()] = Some(Placement::alone(index));
                faces.push(model.faces[seed.index()].clone());
            }
        }
    }
    let shells = model
        .shells
        .iter()
        .map(|shell| {
            let mut ids: Vec<usize> = shell.faces.iter().map(|&f| new_index[f]).collect();
            ids.sort_unstable();
            ids.dedup();
            BrepShell { faces: ids, closed: shell.closed }
        })
        .collect();
    let placements = placements.into_iter().map(|p| p.expect("every face placed")).collect();
    (drop_unused(BrepModel { vertices: model.vertices, edges: model.edges, faces, shells }), placements)
}

/// True for a face of one bicubic span (a Bézier patch).
fn is_single_span(face: &BrepFace) -> bool {
    let s = &face.surface;
    s.degree_u == DEGREE && s.degree_v == DEGREE && s.knots_u.len() == 2 && s.knots_v.len() == 2
}

fn diagonal(points: &[DVec3]) -> f64 {
    let (lo, hi) = points.iter().fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(lo, hi), &p| (lo.min(p), hi.max(p)));
    if points.is_empty() { 0.0 } else { (hi - lo).length() }
}

/// How many quarter turns halfedge `h` is from its face's first halfedge.
fn turn(layout: &PolyMesh, h: HalfedgeId) -> u8 {
    let mut k = layout.face_halfedge(layout.face(h));
    for r in 0..4 {
        if k == h {
            return r;
        }
        k = layout.next(k);
    }
    unreachable!("a halfedge belongs to its face")
}

/// The neighbour's cell one step along the grid's `u` (across the patch's `u = 1` side), or one
/// step along `v` (across `v = 1`), when the side is smooth and inside the surface.
fn step(layout: &PolyMesh, sharp: &[bool], h: HalfedgeId, along_u: bool) -> Option<HalfedgeId> {
    let side = if along_u { layout.next(h) } else { layout.next(layout.next(h)) };
    let across = side.twin();
    if sharp[side.edge().index()] || layout.is_boundary_halfedge(across) {
        return None;
    }
    Some(if along_u { layout.next(across) } else { across })
}

/// The largest grid of eligible, untaken faces that starts at `seed` (its lower-left patch),
/// over the seed's four turns and both growing orders; `None` when no grid has two patches.
fn best_block(layout: &PolyMesh, sharp: &[bool], seed: FaceId, eligible: &[bool], taken: &[bool]) -> Option<Block> {
    let mut best: Option<Block> = None;
    let mut h = layout.face_halfedge(seed);
    for _ in 0..4 {
        for rows_first in [false, true] {
            let block = grow(layout, sharp, h, rows_first, eligible, taken);
            if block.area() > best.as_ref().map_or(1, Block::area) {
                best = Some(block);
            }
        }
        h = layout.next(h);
    }
    best
}

/// Grows a grid from `start`: a first line along `u` (along `v` when `columns_first`), then
/// whole lines beside it while every patch of the next line is free, eligible, new and meets its
/// neighbours as a grid, and the grid's corner vertices stay distinct.
fn grow(
    layout: &PolyMesh,
    sharp: &[bool],
    start: HalfedgeId,
    columns_first: bool,
    eligible: &[bool],
    taken: &[bool],
) -> Block {
    let free = |h: HalfedgeId, used: &[usize]| {
        let f = layout.face(h).index();
        eligible[f] && (!taken[f] || layout.face(h) == layout.face(start)) && !used.contains(&f)
    };
    // Corner vertices of a cell (lower-left, lower-right, upper-right, upper-left).
    let corners = |h: HalfedgeId| {
        let n = layout.next(h);
        let nn = layout.next(n);
        [layout.from_vertex(h), layout.from_vertex(n), layout.from_vertex(nn), layout.from_vertex(layout.next(nn))]
    };
    // The first line, then more lines beside it; `first` steps along the line, `second` across.
    let (first, second) = if columns_first { (false, true) } else { (true, false) };
    let mut used = vec![layout.face(start).index()];
    let mut vertices: Vec<_> = corners(start).to_vec();
    let mut line = vec![start];
    while line.len() < MAX_BLOCK {
        let Some(next) = step(layout, sharp, *line.last().expect("a line has a cell"), first) else { break };
        let new = if first { [corners(next)[1], corners(next)[2]] } else { [corners(next)[2], corners(next)[3]] };
        if !free(next, &used) || new.iter().any(|v| vertices.contains(v)) {
            break;
        }
        used.push(layout.face(next).index());
        vertices.extend(new);
        line.push(next);
    }
    let mut lines = vec![line];
    'grow: while lines.len() < MAX_BLOCK {
        let last = lines.last().expect("a first line");
        let mut line = Vec::with_capacity(last.len());
        let mut added = Vec::new();
        let mut new_vertices = Vec::new();
        for (k, &h) in last.iter().enumerate() {
            let Some(next) = step(layout, sharp, h, second) else { break 'grow };
            // The new line's cells must be neighbours of each other too.
            if k > 0 && step(layout, sharp, line[k - 1], first) != Some(next) {
                break 'grow;
            }
            let mut taken_now = used.clone();
            taken_now.extend(&added);
            if !free(next, &taken_now) {
                break 'grow;
            }
            let c = corners(next);
            let fresh: &[_] = if first {
                if k == 0 { &[c[3], c[2]] } else { &[c[2]] }
            } else if k == 0 {
                &[c[1], c[2]]
            } else {
                &[c[2]]
            };
            for v in fresh {
                if vertices.contains(v) || new_vertices.contains(v) {
                    break 'grow;
                }
                new_vertices.push(*v);
            }
            added.push(layout.face(next).index());
            line.push(next);
        }
        used.extend(added);
        vertices.extend(new_vertices);
        lines.push(line);
    }
    // Lines along u are rows; lines along v are columns: turn them into rows.
    let cells = if columns_first {
        (0..lines[0].len()).map(|j| lines.iter().map(|column| column[j]).collect()).collect()
    } else {
        lines
    };
    Block { cells }
}

/// The face that replaces `block`'s patches, when its surface reproduces each of them.
fn merged_face(model: &BrepModel, layout: &PolyMesh, block: &Block, scale: f64) -> Option<BrepFace> {
    let (a, b) = (block.cells[0].len(), block.cells.len());
    // The patches' Bézier control points side by side: (3a + 1) × (3b + 1).
    let mut bezier = vec![vec![DVec3::ZERO; 3 * b + 1]; 3 * a + 1];
    for (j, row) in block.cells.iter().enumerate() {
        for (i, &h) in row.iter().enumerate() {
            let points = &model.faces[layout.face(h).index()].surface.points;
            let r = turn(layout, h);
            for p in 0..=3 {
                for q in 0..=3 {
                    let (pi, qi) = match r {
                        0 => (p, q),
                        1 => (3 - q, p),
                        2 => (3 - p, 3 - q),
                        _ => (q, 3 - p),
                    };
                    bezier[3 * i + p][3 * j + q] = points[pi][qi];
                }
            }
        }
    }
    let (knots_u, knots_v) = (Knots::uniform(a), Knots::uniform(b));
    let along_u: Vec<Vec<DVec3>> =
        (0..=3 * b).map(|q| simple_knots(&(0..=3 * a).map(|p| bezier[p][q]).collect::<Vec<_>>(), &knots_u)).collect();
    let points: Vec<Vec<DVec3>> = (0..a + DEGREE)
        .map(|k| simple_knots(&along_u.iter().map(|row| row[k]).collect::<Vec<_>>(), &knots_v))
        .collect();
    // Kept only when it is each patch.
    let one = Knots::uniform(1);
    for (j, row) in block.cells.iter().enumerate() {
        for (i, &h) in row.iter().enumerate() {
            let face = &model.faces[layout.face(h).index()];
            let place = Placement { face: 0, rotation: turn(layout, h), origin: (i, j), size: (a, b) };
            for p in 0..=4 {
                for q in 0..=4 {
                    let (u, v) = (p as f64 / 4.0, q as f64 / 4.0);
                    let own = bspline::surface_point(&one, &one, &face.surface.points, u, v).0;
                    let (mu, mv) = place.map(u, v);
                    let merged = bspline::surface_point(&knots_u, &knots_v, &points, mu, mv).0;
                    let apart = (own - merged).length();
                    if apart.is_nan() || apart > EXACT * scale {
                        return None;
                    }
                }
            }
        }
    }
    // The outer loop: the grid's boundary, counter-clockwise as each patch's own loop; each side
    // with the place of its patch, to put the edge on the merged surface.
    let place = |i: usize, j: usize| Placement {
        face: 0,
        rotation: turn(layout, block.cells[j][i]),
        origin: (i, j),
        size: (a, b),
    };
    let mut sides = Vec::with_capacity(2 * (a + b));
    sides.extend(block.cells[0].iter().enumerate().map(|(i, &h)| (h, place(i, 0))));
    sides.extend(block.cells.iter().enumerate().map(|(j, row)| (layout.next(row[a - 1]), place(a - 1, j))));
    sides.extend(
        block.cells[b - 1].iter().enumerate().rev().map(|(i, &h)| (layout.next(layout.next(h)), place(i, b - 1))),
    );
    sides.extend(block.cells.iter().enumerate().rev().map(|(j, row)| (layout.prev(row[0]), place(0, j))));
    let mut outer: Vec<(usize, bool)> = sides
        .iter()
        .map(|&(h, _)| (h.edge().index(), layout.from_vertex(h) == layout.edge_vertices(h.edge()).0))
        .collect();
    let mut outer_uv: Vec<[[f64; 2]; 2]> = sides
        .iter()
        .map(|&(h, place)| {
            side_uv(layout, h).map(|[u, v]| {
                let (s, t) = place.map(u, v);
                [s, t]
            })
        })
        .collect();
    let same_sense = model.faces[layout.face(block.cells[0][0]).index()].same_sense;
    if !same_sense {
        outer.reverse();
        outer_uv.reverse();
        for entry in &mut outer {
            entry.1 = !entry.1;
        }
    }
    let surface = BSplineSurface::bicubic(&knots_u, &knots_v, points);
    Some(BrepFace { surface, outer, outer_uv, same_sense })
}

/// The control points, on `knots` (simple inner knots), of the curve whose Bézier pieces are
/// `bezier` (`3·spans + 1` points, one piece a span): collocation at the Greville abscissae,
/// exact when the pieces are C² at the knots.
fn simple_knots(bezier: &[DVec3], knots: &Knots) -> Vec<DVec3> {
    let spans = knots.spans();
    let n = knots.count();
    let full = knots.full();
    let one = Knots::uniform(1);
    let mut a = vec![vec![0.0; n]; n];
    let mut rhs = vec![DVec3::ZERO; n];
    for k in 0..n {
        let xi = (full[k + 1] + full[k + 2] + full[k + 3]) / 3.0;
        let (first, basis) = knots.basis(xi, false);
        a[k][first..first + 4].copy_from_slice(&basis);
        let piece = ((xi * spans as f64).floor() as usize).min(spans - 1);
        let local = xi * spans as f64 - piece as f64;
        rhs[k] = bspline::curve_point(&one, &bezier[3 * piece..3 * piece + 4], local);
    }
    solve(a, rhs)
}

/// Solves the square system `a x = b` by Gaussian elimination with partial pivoting.
fn solve(mut a: Vec<Vec<f64>>, mut b: Vec<DVec3>) -> Vec<DVec3> {
    let n = b.len();
    for c in 0..n {
        let pivot = (c..n).max_by(|&i, &j| a[i][c].abs().total_cmp(&a[j][c].abs())).expect("a row");
        a.swap(c, pivot);
        b.swap(c, pivot);
        for r in c + 1..n {
            let factor = a[r][c] / a[c][c];
            if factor != 0.0 {
                for k in c..n {
                    a[r][k] -= factor * a[c][k];
                }
                b[r] = b[r] - factor * b[c];
            }
        }
    }
    let mut x = vec![DVec3::ZERO; n];
    for r in (0..n).rev() {
        let sum: DVec3 = (r + 1..n).map(|k| a[r][k] * x[k]).sum();
        x[r] = (b[r] - sum) / a[r][r];
    }
    x
}

/// The model without the edges no face uses and the vertices no edge uses, renumbered in order.
fn drop_unused(model: BrepModel) -> BrepModel {
    let mut edge_used = vec![false; model.edges.len()];
    for face in &model.faces {
        for &(e, _) in &face.outer {
            edge_used[e] = true;
        }
    }
    let mut vertex_used = vec![false; model.vertices.len()];
    for (e, edge) in model.edges.iter().enumerate() {
        if edge_used[e] {
            vertex_used[edge.start] = true;
            vertex_used[edge.end] = true;
        }
    }
    let renumber = |used: &[bool]| {
        let mut next = 0;
        used.iter()
            .map(|&u| {
                let id = next;
                next += usize::from(u);
                if u { id } else { usize::MAX }
            })
            .collect::<Vec<_>>()
    };
    let (edge_id, vertex_id) = (renumber(&edge_used), renumber(&vertex_used));
    let vertices = model.vertices.iter().zip(&vertex_used).filter(|(_, u)| **u).map(|(p, _)| *p).collect();
    let edges = model
        .edges
        .into_iter()
        .zip(&edge_used)
        .filter(|(_, u)| **u)
        .map(|(mut edge, _)| {
            edge.start = vertex_id[edge.start];
            edge.end = vertex_id[edge.end];
            edge
        })
        .collect();
    let faces = model
        .faces
        .into_iter()
        .map(|mut face| {
            for entry in &mut face.outer {
                entry.0 = edge_id[entry.0];
            }
            face
        })
        .collect();
    BrepModel { vertices, edges, faces, shells: model.shells }
}

#[cfg(test)]
#[path = "merge_tests.rs"]
mod tests;
