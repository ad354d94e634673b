//! Step 1: quadric-error simplification of the dense mesh to the starting cage (Garland and
//! Heckbert 1997, the paper §2.1), through meshoptimizer's simplifier.
//!
//! meshoptimizer collapses edges in order of their quadric error while keeping the topology
//! (it never closes a hole or joins pieces) and, when asked, keeps every border vertex where it
//! is, which is what an open scan needs so the cage keeps its outline. It works in `f32`, so the
//! positions are shifted to their bounding-box centre first to keep the rounding relative to the
//! shape's size; the cage takes its vertices' `f64` positions from the input (simplification
//! only picks vertices, it does not move them).
//!
//! meshoptimizer can leave an edge shared by three triangles; the cage must be a manifold
//! surface, so then a few nearby targets (±2 %, ±4 %, … of the asked one) are tried in turn.
//!
//! Weak where the target is below what the topology allows (each closed piece needs at least a
//! few triangles, locked borders keep all their vertices): the cage then has more faces than
//! asked, and the report says so.

use super::input::DenseMesh;
use crate::mesh::PolyMesh;
use crate::{DVec3, Error, Result};

/// The starting cage and how close it came to the target.
#[derive(Clone, Debug)]
pub struct Simplified {
    /// The cage: the kept vertices in order of their first use, triangles as meshoptimizer left them.
    pub cage: PolyMesh,
    /// For each cage vertex, the dense vertex it is.
    pub dense_vertex: Vec<u32>,
    /// meshoptimizer's own error estimate, relative to the mesh's extent.
    pub relative_error: f64,
}

/// Simplifies to about `target_faces` triangles (never fewer than the topology allows).
pub fn simplify(dense: &DenseMesh, target_faces: usize) -> Result<Simplified> {
    let (lo, hi) = crate::mesh::bounding_box(&dense.positions).ok_or_else(|| Error::Input("no vertices".into()))?;
    let centre = 0.5 * (lo + hi);
    let local: Vec<[f32; 3]> = dense.positions.iter().map(|&p| (p - centre).as_vec3().to_array()).collect();
    let indices: Vec<u32> = dense.triangles.iter().flatten().copied().collect();
    let bytes: &[u8] = meshopt::typed_to_bytes(&local);
    let adapter = meshopt::VertexDataAdapter::new(bytes, std::mem::size_of::<[f32; 3]>(), 0)
        .map_err(|e| Error::Solver(format!("the simplifier refused the vertex data ({e})")))?;
    let mut options = meshopt::SimplifyOptions::RegularizeLight;
    if !dense.closed {
        options |= meshopt::SimplifyOptions::LockBorder;
    }
    // meshoptimizer keeps the topology of the surface but not always that of its edges: now and
    // then a collapse leaves an edge with three triangles (seen on Blender's monkey at 300
    // faces). Such a cage cannot be subdivided; a slightly different target collapses other
    // edges, so nearby targets are tried in turn, nearest first.
    let mut failure = None;
    for attempt in 0..RETRIES {
        let step = (attempt as f64 / 2.0).ceil() * RETRY_STEP * if attempt % 2 == 1 { -1.0 } else { 1.0 };
        let target = ((target_faces as f64) * (1.0 + step)).round().max(1.0) as usize;
        match simplify_to(dense, &indices, &adapter, options, target) {
            Ok(simplified) => return Ok(simplified),
            Err(e @ Error::Topology(_)) => failure = Some(e),
            Err(e) => return Err(e),
        }
    }
    Err(failure.unwrap_or_else(|| Error::Solver("the simplifier gave no cage".into())))
}

/// Targets tried when a simplified cage is not manifold (the asked one first).
const RETRIES: usize = 9;
/// How far apart the targets tried are, as a fraction of the asked one.
const RETRY_STEP: f64 = 0.02;

fn simplify_to(
    dense: &DenseMesh,
    indices: &[u32],
    adapter: &meshopt::VertexDataAdapter<'_>,
    options: meshopt::SimplifyOptions,
    target_faces: usize,
) -> Result<Simplified> {
    let mut error = 0.0f32;
    // No error bound (1 is the whole extent): the face count decides.
    let kept = meshopt::simplify(indices, adapter, 3 * target_faces.max(1), 1.0, options, Some(&mut error));
    if kept.is_empty() {
        return Err(Error::Solver("the simplifier removed every triangle; ask for more faces".into()));
    }

    let mut cage_vertex = vec![u32::MAX; dense.positions.len()];
    let mut dense_vertex = Vec::new();
    let mut positions: Vec<DVec3> = Vec::new();
    let faces: Vec<[u32; 3]> = kept
        .chunks_exact(3)
        .map(|t| {
            [0, 1, 2].map(|k| {
                let v = t[k] as usize;
                if cage_vertex[v] == u32::MAX {
                    cage_vertex[v] = dense_vertex.len() as u32;
                    dense_vertex.push(v as u32);
                    positions.push(dense.positions[v]);
                }
                cage_vertex[v]
            })
        })
        .collect();
    let cage = PolyMesh::from_polygons(positions, &faces).map_err(|e| {
        Error::Topology(format!("the simplified cage is not a manifold surface ({e}); ask for a different face count"))
    })?;
    Ok(Simplified { cage, dense_vertex, relative_error: f64::from(error) })
}
