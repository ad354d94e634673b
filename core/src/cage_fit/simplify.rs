//! Step 1: quadric-error simplification of the dense mesh to the starting cage (Garland and
//! Heckbert 1997, the paper §2.1), through meshoptimizer's simplifier.
//!
//! meshoptimizer collapses edges in order of their quadric error while keeping the topology of
//! borders (it never closes a hole or joins pieces) and, when asked, keeps every border vertex
//! where it is, which is what an open scan needs so the cage keeps its outline. Each kept vertex
//! moves to where its merged quadric is least (optimal placement, as MeshLab's simplifier does).
//! It works in `f32`, so the positions are shifted to their bounding-box centre first to keep the
//! rounding relative to the shape's size; a vertex it did not move keeps its exact `f64` position.
//!
//! meshoptimizer can leave an edge shared by three triangles, or flatten a handle into two
//! triangles on the same corners; the cage must be a manifold surface, so then a few nearby
//! targets (±2 %, ±4 %, … of the asked one) are tried in turn, and then larger ones up to the
//! whole input ([`retry_targets`]); the first valid larger cage is collapsed on to the asked
//! count by topology-checked collapses ([`collapse`](super::collapse)).
//!
//! Weak where the target is below what the topology allows (each closed piece needs at least a
//! few triangles, locked borders keep all their vertices): the cage then has more faces than
//! asked, and the report says so.

use super::input::DenseMesh;
use crate::mesh::PolyMesh;
use crate::{DVec3, Error, Result};
use rayon::prelude::*;

/// The starting cage and how close it came to the target.
#[derive(Clone, Debug)]
pub struct Simplified {
    /// The cage: the kept vertices in order of their first use, triangles as meshoptimizer left them.
    pub cage: PolyMesh,
    /// For each cage vertex, the dense vertex it was made from (moved by optimal placement).
    pub dense_vertex: Vec<u32>,
    /// meshoptimizer's own error estimate, relative to the mesh's extent.
    pub relative_error: f64,
}

/// Simplifies to about `target_faces` triangles (never fewer than the topology allows).
pub fn simplify(dense: &DenseMesh, target_faces: usize) -> Result<Simplified> {
    simplify_staged(dense, target_faces, STAGED_ABOVE, PART_TRIANGLES)
}

/// Inputs of more triangles than this are simplified in two stages (see [`first_stage`]).
pub const STAGED_ABOVE: usize = 200_000;

/// About how many triangles each part of the first stage has: meshoptimizer goes through a part
/// this small several times faster a triangle than through half of a million-triangle mesh,
/// whose arrays are far larger than the processor's caches.
pub const PART_TRIANGLES: usize = 1 << 16;

/// [`simplify`], in two stages when the input has more than `staged_above` triangles: parts of
/// about `part_triangles` (at least two) side by side to an intermediate mesh, then that mesh
/// to the target. Should the second stage find no valid cage, the input is simplified in one
/// stage.
pub fn simplify_staged(
    dense: &DenseMesh,
    target_faces: usize,
    staged_above: usize,
    part_triangles: usize,
) -> Result<Simplified> {
    if dense.triangles.len() > staged_above
        && let Some(intermediate) = first_stage(dense, target_faces, part_triangles)?
        && let Ok(mut simplified) =
            simplify_mesh(&intermediate.positions, &intermediate.triangles, dense.closed, target_faces)
    {
        simplified.dense_vertex.iter_mut().for_each(|v| *v = intermediate.dense_vertex[*v as usize]);
        return Ok(simplified);
    }
    simplify_mesh(&dense.positions, &dense.triangles, dense.closed, target_faces)
}

/// The mesh the first stage leaves: vertices in order of first use, each with its dense vertex.
struct Intermediate {
    positions: Vec<DVec3>,
    triangles: Vec<[u32; 3]>,
    dense_vertex: Vec<u32>,
}

/// A triangle the first stage kept: its dense vertices, and each one's position if it moved.
type KeptTriangle = ([u32; 3], [Option<[f32; 3]>; 3]);

/// How much smaller than its input each part of the first stage is made.
const FIRST_STAGE_RATIO: usize = 16;

/// The most parts of the first stage.
const MOST_PARTS: usize = 1 << 10;

/// The triangles split into `parts` compact parts: the triangles' indices, part `k` holding
/// `order[k n / parts .. (k + 1) n / parts]` in ascending order. Each split is at the median of
/// the part's centroids along the longest side of their box, by (centroid, index): a total
/// order, so the parts depend neither on the sort nor on the number of threads. (The centroids
/// are sums of the corners in `f32`: they only decide where a part ends.)
fn split_into_parts(dense: &DenseMesh, parts: usize) -> Vec<u32> {
    let n = dense.triangles.len();
    let mut keyed: Vec<([f32; 3], u32)> = dense
        .triangles
        .par_iter()
        .enumerate()
        .map(|(t, tri)| {
            (tri.iter().map(|&v| dense.positions[v as usize]).sum::<DVec3>().as_vec3().to_array(), t as u32)
        })
        .collect();
    // Parts `first..last` over `keyed`, which starts at slot `start`: part `k` begins at slot
    // `k n / parts`, so each split falls where the parts it separates meet.
    fn split(keyed: &mut [([f32; 3], u32)], start: usize, first: usize, last: usize, n: usize, parts: usize) {
        if last - first <= 1 || keyed.len() < 2 {
            return;
        }
        let (lo, hi) = keyed.iter().fold(([f32::INFINITY; 3], [f32::NEG_INFINITY; 3]), |(lo, hi), (c, _)| {
            (std::array::from_fn(|k| lo[k].min(c[k])), std::array::from_fn(|k| hi[k].max(c[k])))
        });
        let axis = (0..3).max_by(|&a, &b| (hi[a] - lo[a]).total_cmp(&(hi[b] - lo[b])).then(b.cmp(&a))).unwrap_or(0);
        let half = (first + last) / 2;
        let middle = half * n / parts - start;
        if middle < keyed.len() {
            keyed.select_nth_unstable_by(middle, |a, b| a.0[axis].total_cmp(&b.0[axis]).then(a.1.cmp(&b.1)));
        }
        let (left, right) = keyed.split_at_mut(middle);
        rayon::join(
            || split(left, start, first, half, n, parts),
            || split(right, start + middle, half, last, n, parts),
        );
    }
    split(&mut keyed, 0, 0, parts, n, parts);
    // Each triangle's part, then the parts' triangles gathered in ascending order.
    let mut part = vec![0u32; n];
    for k in 0..parts {
        keyed[k * n / parts..(k + 1) * n / parts].iter().for_each(|&(_, t)| part[t as usize] = k as u32);
    }
    drop(keyed);
    let mut next: Vec<usize> = (0..parts).map(|k| k * n / parts).collect();
    let mut order = vec![0u32; n];
    for (t, &k) in part.iter().enumerate() {
        order[next[k as usize]] = t as u32;
        next[k as usize] += 1;
    }
    order
}

/// The first stage: the triangles are split into compact parts of about `part_triangles` (at
/// least two parts, [`split_into_parts`]), and meshoptimizer simplifies each part on its own,
/// the parts side by side, with the vertices the parts share locked so they still meet, to a
/// sixteenth of its size plus two triangles for each locked vertex (the seam stays dense, and
/// the rest of the part is left as fine as with fewer, larger parts; never below twice the
/// target in all). meshoptimizer is sequential, so parts side by side take a fraction of the
/// time of the whole on two cores, and parts this small fit in the processor's caches; the
/// second stage is then small. `None` when the first stage leaves nothing to gain (a part would
/// not shrink).
fn first_stage(dense: &DenseMesh, target_faces: usize, part_triangles: usize) -> Result<Option<Intermediate>> {
    let (lo, hi) = crate::mesh::bounding_box(&dense.positions).ok_or_else(|| Error::Input("no vertices".into()))?;
    let centre = 0.5 * (lo + hi);
    let n = dense.triangles.len();
    // At least two parts, and none of fewer than two triangles.
    let parts = n.div_ceil(part_triangles.max(1)).clamp(2, MOST_PARTS).min(n / 2).max(1);
    let order = split_into_parts(dense, parts);
    let range = |k: usize| &order[k * n / parts..(k + 1) * n / parts];
    // The part that uses each vertex, or `SHARED` when several do.
    const UNUSED: u32 = u32::MAX;
    const SHARED: u32 = u32::MAX - 1;
    let mut owner = vec![UNUSED; dense.positions.len()];
    for k in 0..parts {
        for &t in range(k) {
            for &v in &dense.triangles[t as usize] {
                let o = &mut owner[v as usize];
                *o = if *o == UNUSED || *o == k as u32 { k as u32 } else { SHARED };
            }
        }
    }
    let mut options = meshopt::SimplifyOptions::RegularizeLight;
    if !dense.closed {
        options |= meshopt::SimplifyOptions::LockBorder;
    }
    let least = (2 * target_faces).div_ceil(parts);
    // `local_of`: a scratch numbering over the dense vertices, left all unset after each part.
    let part = |local_of: &mut Vec<u32>, k: usize| -> Option<Vec<KeptTriangle>> {
        let triangles = range(k);
        // The part's own numbering, in order of first use.
        local_of.resize(dense.positions.len(), u32::MAX);
        let mut dense_of = Vec::new();
        let mut indices = Vec::with_capacity(3 * triangles.len());
        for &t in triangles {
            for &v in &dense.triangles[t as usize] {
                if local_of[v as usize] == u32::MAX {
                    local_of[v as usize] = dense_of.len() as u32;
                    dense_of.push(v);
                }
                indices.push(local_of[v as usize]);
            }
        }
        dense_of.iter().for_each(|&v| local_of[v as usize] = u32::MAX);
        let local: Vec<[f32; 3]> =
            dense_of.iter().map(|&v| (dense.positions[v as usize] - centre).as_vec3().to_array()).collect();
        let locked: Vec<meshopt::SimplifyVertex> = dense_of
            .iter()
            .map(|&v| {
                if owner[v as usize] == SHARED { meshopt::SimplifyVertex::Lock } else { meshopt::SimplifyVertex::None }
            })
            .collect();
        let seam = locked.iter().filter(|&&l| matches!(l, meshopt::SimplifyVertex::Lock)).count();
        let target = (triangles.len() / FIRST_STAGE_RATIO + 2 * seam).max(least);
        if target >= triangles.len() {
            return None;
        }
        let mut moved = local.clone();
        let count = meshopt::simplify_with_update(
            &mut indices,
            &mut moved,
            &mut [],
            &[],
            0,
            Some(&locked),
            3 * target,
            1.0,
            options,
            None,
        );
        indices.truncate(count);
        // Each kept corner as its dense vertex, with its new position if meshoptimizer moved it.
        let corner = |l: u32| {
            let l = l as usize;
            (dense_of[l], (moved[l] != local[l]).then_some(moved[l]))
        };
        Some(
            indices
                .chunks_exact(3)
                .map(|t| {
                    let [a, b, c] = [corner(t[0]), corner(t[1]), corner(t[2])];
                    ([a.0, b.0, c.0], [a.1, b.1, c.1])
                })
                .collect(),
        )
    };
    let kept: Vec<Option<Vec<KeptTriangle>>> = (0..parts).into_par_iter().map_init(Vec::new, part).collect();
    let Some(kept) = kept.into_iter().collect::<Option<Vec<_>>>() else { return Ok(None) };
    // A vertex the parts share is locked in all of them; any other is in one part only.
    let mut number = vec![u32::MAX; dense.positions.len()];
    let mut intermediate = Intermediate { positions: Vec::new(), triangles: Vec::new(), dense_vertex: Vec::new() };
    for (tri, moved) in kept.iter().flatten() {
        let t = [0, 1, 2].map(|k| {
            let v = tri[k] as usize;
            if number[v] == u32::MAX {
                number[v] = intermediate.dense_vertex.len() as u32;
                intermediate.dense_vertex.push(tri[k]);
                intermediate.positions.push(match moved[k] {
                    Some(m) => centre + glam::Vec3::from_array(m).as_dvec3(),
                    None => dense.positions[v],
                });
            }
            number[v]
        });
        intermediate.triangles.push(t);
    }
    Ok(Some(intermediate))
}

/// Simplifies triangles over positions to about `target_faces` (the retries of the module doc);
/// `dense_vertex` numbers the input's vertices.
fn simplify_mesh(positions: &[DVec3], triangles: &[[u32; 3]], closed: bool, target_faces: usize) -> Result<Simplified> {
    let (lo, hi) = crate::mesh::bounding_box(positions).ok_or_else(|| Error::Input("no vertices".into()))?;
    let centre = 0.5 * (lo + hi);
    let local: Vec<[f32; 3]> = positions.iter().map(|&p| (p - centre).as_vec3().to_array()).collect();
    let indices: Vec<u32> = triangles.iter().flatten().copied().collect();
    let mut options = meshopt::SimplifyOptions::RegularizeLight;
    if !closed {
        options |= meshopt::SimplifyOptions::LockBorder;
    }
    // meshoptimizer keeps the topology of the surface but not always that of its edges: now and
    // then a collapse leaves an edge with three triangles (seen on Blender's monkey at 300
    // faces). Such a cage cannot be subdivided; a slightly different target collapses other
    // edges, so nearby targets are tried in turn, nearest first.
    let mut failure = None;
    let all = triangles.len();
    let mut tried = Vec::new();
    for (attempt, target) in retry_targets(target_faces, all).into_iter().enumerate() {
        if tried.contains(&target) {
            continue;
        }
        tried.push(target);
        match simplify_to(positions, &indices, &local, centre, options, target) {
            // Past the nearby targets, meshoptimizer reached a valid cage only above the asked
            // count: collapse on from there, keeping the topology (see `collapse`).
            Ok(simplified) if attempt >= RETRIES && simplified.cage.face_count() > target_faces => {
                return finish(simplified, closed, target_faces);
            }
            Ok(simplified) => return Ok(simplified),
            Err(e @ Error::Topology(_)) => failure = Some(e),
            Err(e) => return Err(e),
        }
    }
    Err(failure.unwrap_or_else(|| Error::Solver("the simplifier gave no cage".into())))
}

/// Collapses a valid cage on to `target_faces` with the topology-checked collapses, border
/// vertices locked on an open input; the cage as it was if the result were not valid.
fn finish(simplified: Simplified, closed: bool, target_faces: usize) -> Result<Simplified> {
    let cage = &simplified.cage;
    let locked: Vec<bool> = cage.vertices().map(|v| !closed && cage.is_boundary_vertex(v)).collect();
    let (positions, kept) = super::collapse::collapse_to(cage.positions(), &cage.triangles(), &locked, target_faces);
    let slots: Vec<u32> = kept.iter().flatten().copied().collect();
    match assemble(&slots, |v| positions[v], |v| simplified.dense_vertex[v], cage.vertex_count()) {
        Ok((cage, dense_vertex)) => Ok(Simplified { cage, dense_vertex, relative_error: simplified.relative_error }),
        Err(_) => Ok(simplified),
    }
}

/// The targets tried in turn: the asked one, then nearby ones (±2 %, ±4 %, …, at least a face
/// or two apart), then twice, four times … the asked one up to the whole input, which is a
/// manifold surface itself. A small closed piece (a cube asked to become a tetrahedron) often
/// cannot be collapsed to the asked count without a non-manifold edge, and a few more faces do.
fn retry_targets(target_faces: usize, all: usize) -> Vec<usize> {
    let asked = target_faces.clamp(1, all.max(1));
    let step = ((asked as f64) * RETRY_STEP).round().max(2.0);
    let mut targets: Vec<usize> = (0..RETRIES)
        .map(|attempt| {
            let k = (attempt as f64 / 2.0).ceil() * if attempt % 2 == 1 { -1.0 } else { 1.0 };
            ((asked as f64) + k * step).round().clamp(1.0, all.max(1) as f64) as usize
        })
        .collect();
    let mut larger = asked;
    while larger < all {
        larger = (2 * larger).min(all);
        targets.push(larger);
    }
    targets
}

/// Nearby targets tried when a simplified cage is not manifold (the asked one first).
const RETRIES: usize = 9;
/// How far apart the targets tried are, as a fraction of the asked one.
const RETRY_STEP: f64 = 0.02;

fn simplify_to(
    positions: &[DVec3],
    indices: &[u32],
    local: &[[f32; 3]],
    centre: DVec3,
    options: meshopt::SimplifyOptions,
    target_faces: usize,
) -> Result<Simplified> {
    let mut error = 0.0f32;
    // meshoptimizer asserts (aborting the process) on a target above the index count, which a
    // tiny input or a retry above the asked target would otherwise reach; and on indices past
    // the vertex data or a count that is not whole triangles.
    let target_indices = (3 * target_faces.max(1)).min(indices.len());
    if !indices.len().is_multiple_of(3) || indices.iter().any(|&i| i as usize >= positions.len()) {
        return Err(Error::Input("the triangles refer to vertices the mesh does not have".into()));
    }
    // No error bound (1 is the whole extent): the face count decides. meshoptimizer places each
    // kept vertex where the collapsed edges' quadrics are least (Garland and Heckbert's optimal
    // placement), updating the positions in place; locked border vertices stay.
    let mut kept = indices.to_vec();
    let mut moved = local.to_vec();
    let count = meshopt::simplify_with_update(
        &mut kept,
        &mut moved,
        &mut [],
        &[],
        0,
        None,
        target_indices,
        1.0,
        options,
        Some(&mut error),
    );
    kept.truncate(count);
    if kept.is_empty() {
        return Err(Error::Solver("the simplifier removed every triangle; ask for more faces".into()));
    }

    // A vertex meshoptimizer did not move keeps its exact position.
    let position = |v: usize| {
        if moved[v] == local[v] { positions[v] } else { centre + glam::Vec3::from_array(moved[v]).as_dvec3() }
    };
    let (cage, dense_vertex) = assemble(&kept, position, |v| v as u32, positions.len())?;
    Ok(Simplified { cage, dense_vertex, relative_error: f64::from(error) })
}

/// The cage on the vertices `slots` (three per triangle, numbered among `count`) uses, in order
/// of first use, with each vertex's position and dense vertex; an error when it is not a
/// manifold surface a Loop refinement can take.
fn assemble(
    slots: &[u32],
    position: impl Fn(usize) -> DVec3,
    dense: impl Fn(usize) -> u32,
    count: usize,
) -> Result<(PolyMesh, Vec<u32>)> {
    let mut cage_vertex = vec![u32::MAX; count];
    let mut dense_vertex = Vec::new();
    let mut positions: Vec<DVec3> = Vec::new();
    let faces: Vec<[u32; 3]> = slots
        .chunks_exact(3)
        .map(|t| {
            [0, 1, 2].map(|k| {
                let v = t[k] as usize;
                if cage_vertex[v] == u32::MAX {
                    cage_vertex[v] = dense_vertex.len() as u32;
                    dense_vertex.push(dense(v));
                    positions.push(position(v));
                }
                cage_vertex[v]
            })
        })
        .collect();
    // Two triangles on the same three corners (a piece collapsed flat, both sides) pass as a
    // manifold but refine into a non-manifold surface: try another target.
    let mut corners: Vec<[u32; 3]> = faces
        .iter()
        .map(|f| {
            let mut c = *f;
            c.sort_unstable();
            c
        })
        .collect();
    corners.sort_unstable();
    if corners.windows(2).any(|w| w[0] == w[1]) {
        return Err(Error::Topology("the simplified cage has two triangles on the same corners".into()));
    }
    let cage = PolyMesh::from_polygons(positions, &faces).map_err(|e| {
        Error::Topology(format!("the simplified cage is not a manifold surface ({e}); ask for a different face count"))
    })?;
    Ok((cage, dense_vertex))
}
