//! Exact solves of the small neighbourhoods of extraordinary vertices, inside a multigrid cycle
//! (issue 22).
//!
//! The coarse grid's operator is the coarser level's own, which near an extraordinary vertex
//! (a valence other than four inside, other than two or three on an open boundary) does not
//! match the finer level's equations as well as it does on the regular grid. The error the
//! coarse correction leaves there is local and smooth within a ring or two, so the
//! Gauss–Seidel sweeps, which damp rough error, hardly touch it: on the default scene the
//! cycles of level 2 contracted by only 0.62 a cycle in the end, the error held at the valence-8
//! centre of the cage's octagon and its four neighbours, and the stopping rule (which assumes the
//! contraction it measured over the first cycles) stopped the level at 1.4 T from its fixed
//! point (`docs/nusd.md`, "Sweeps per level").
//!
//! The same happens along a sliver face, where a vertex's neighbours lie at very different
//! distances and the weights, which follow the spacing, couple it far more strongly one way than
//! the other: pointwise smoothing fails there as on any strongly anisotropic grid. On a cage
//! with an edge 1e-3 of its size the cycles of levels 2–5 contracted by about 0.97 in the end,
//! and levels stopped up to 12 T from their fixed points. So a moving vertex whose largest
//! neighbour weight exceeds [`STIFF_RATIO`] times its smallest gets a block too.
//!
//! So after the coarse correction each such vertex's neighbourhood (the moving vertices within
//! [`RINGS`] rings) is solved exactly with everything around it held: Newton's step on the
//! block's equations, which are linear without tension (the block's rows and columns of the
//! Jacobian of [`super::direct`], inverted once per operator). The blocks are taken one after
//! another, each from the state the earlier ones left (a multiplicative Schwarz step), in index
//! order, so the result does not depend on the thread count, and the fixed point is the
//! level's own (a block's step is zero there). A block costs about what a sweep of its vertices
//! does.

use super::direct::jacobian_rows;
use super::kernel::{self, Forcing, State};
use super::operator::{Operator, Role};
use crate::DVec3;
use crate::mesh::{PolyMesh, VertexId};
use faer::Par;
use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::lu::partial_pivoting::{factor, inverse};

/// Rings of neighbours around an extraordinary vertex solved with it.
pub const RINGS: usize = 3;
/// A moving vertex whose largest neighbour weight is more than this many times its smallest
/// gets a block.
pub const STIFF_RATIO: f64 = 30.0;

#[derive(Clone, Debug)]
struct Block {
    /// The moving vertices, ascending.
    vertices: Vec<u32>,
    /// The fixed vertices whose `R` reads a block vertex's `P`: brought up to date before the
    /// block's residual is taken.
    fixed: Vec<u32>,
    /// The inverse of the block's Jacobian, row-major (unknowns in pairs, `R` then `P`).
    inverse: Vec<f64>,
}

/// The blocks of a level, made once per operator.
#[derive(Clone, Debug, Default)]
pub struct IrregularBlocks {
    blocks: Vec<Block>,
}

/// True when interior vertex `v` has more around it than a regular grid: its faces' corner
/// shares (a quad's corner a quarter turn, a triangle's a sixth) add up to more than a turn (a
/// valence over four among quads, over six among triangles, over five where quads meet
/// triangles, or a face of five or more sides around it).
fn crowded(mesh: &PolyMesh, v: VertexId) -> bool {
    if mesh.is_boundary_vertex(v) {
        return false;
    }
    // In twelfths of a turn.
    let mut turn = 0;
    for h in mesh.outgoing(v) {
        let f = mesh.face(h);
        if !f.is_valid() {
            return false;
        }
        turn += match mesh.face_halfedges(f).count() {
            3 => 2,
            4 => 3,
            _ => return true,
        };
    }
    turn > 12
}

/// True when moving vertex `v`'s neighbours are weighted very unequally: one much closer than
/// another, along a sliver face (the weights follow the spacing).
fn stiff(op: &Operator, v: usize) -> bool {
    let weights = &op.weight_p[op.offsets[v] as usize..op.offsets[v + 1] as usize];
    let (low, high) = weights.iter().fold((f64::INFINITY, 0.0f64), |(l, h), &w| (l.min(w), h.max(w)));
    op.role[v] == Role::Moving && !weights.is_empty() && high > STIFF_RATIO * low
}

impl IrregularBlocks {
    /// The blocks of a level without tension (none with tension: its equations are not linear,
    /// and tensioned levels keep the cycles their fallback was measured with).
    pub fn new(op: &Operator, mesh: &PolyMesh) -> IrregularBlocks {
        if !op.overrides.is_empty() {
            return IrregularBlocks::default();
        }
        let n = mesh.vertex_count();
        let mut distance = vec![u32::MAX; n];
        let mut blocks = Vec::new();
        for seed in 0..n {
            if !crowded(mesh, VertexId(seed as u32)) && !stiff(op, seed) {
                continue;
            }
            // Breadth-first over the mesh's edges, RINGS + 1 deep (the outer ring only for the
            // fixed vertices that read the block).
            let mut order = vec![seed as u32];
            distance[seed] = 0;
            let mut head = 0;
            while head < order.len() {
                let v = order[head] as usize;
                head += 1;
                if distance[v] as usize > RINGS {
                    continue;
                }
                for h in mesh.outgoing(VertexId(v as u32)) {
                    let w = mesh.to_vertex(h).index();
                    if distance[w] == u32::MAX {
                        distance[w] = distance[v] + 1;
                        order.push(w as u32);
                    }
                }
            }
            let mut vertices: Vec<u32> = order
                .iter()
                .copied()
                .filter(|&v| distance[v as usize] as usize <= RINGS && op.role[v as usize] == Role::Moving)
                .collect();
            let mut fixed: Vec<u32> = order.iter().copied().filter(|&v| op.role[v as usize] == Role::Fixed).collect();
            for &v in &order {
                distance[v as usize] = u32::MAX;
            }
            if vertices.is_empty() {
                continue;
            }
            vertices.sort_unstable();
            fixed.sort_unstable();
            if let Some(inverse) = block_inverse(op, &vertices) {
                blocks.push(Block { vertices, fixed, inverse });
            }
        }
        IrregularBlocks { blocks }
    }

    /// The work of one pass over the blocks in sweeps of the level: a block's product with its
    /// inverse costs `3 (2m)²` multiply-adds for `m` vertices, a sweep `6` per slot of the
    /// operator (the `P` and `R` averages of three coordinates).
    pub fn work(&self, op: &Operator) -> f64 {
        let products: usize = self.blocks.iter().map(|b| 3 * (2 * b.vertices.len()).pow(2)).sum();
        products as f64 / (6 * op.neighbors.len().max(1)) as f64
    }

    pub fn is_empty(&self) -> bool {
        self.blocks.is_empty()
    }

    /// Solves each block exactly in turn (`N(x) = f` with `forcing`, `None`: `f = 0`), the rest
    /// held. Returns the largest position step (NaN if a value became non-finite).
    pub fn solve(&self, op: &Operator, mesh: &PolyMesh, state: &mut State, forcing: Option<&Forcing>) -> f64 {
        let mut largest = 0.0f64;
        let mut rhs: Vec<f64> = Vec::new();
        for block in &self.blocks {
            kernel::update_fixed_of(op, state, forcing, &block.fixed);
            let m = 2 * block.vertices.len();
            rhs.clear();
            rhs.resize(3 * m, 0.0);
            for (u, &v) in block.vertices.iter().enumerate() {
                let (r, p) = kernel::vertex_residual(op, mesh, &state.p, &state.r, forcing, v as usize);
                for c in 0..3 {
                    rhs[c * m + 2 * u] = r[c];
                    rhs[c * m + 2 * u + 1] = p[c];
                }
            }
            for (u, &v) in block.vertices.iter().enumerate() {
                let mut step = [DVec3::ZERO; 2];
                for (k, out) in step.iter_mut().enumerate() {
                    let row = &block.inverse[(2 * u + k) * m..(2 * u + k + 1) * m];
                    for c in 0..3 {
                        out[c] = row.iter().zip(&rhs[c * m..(c + 1) * m]).map(|(a, b)| a * b).sum();
                    }
                }
                state.r[v as usize] += step[0];
                state.p[v as usize] += step[1];
                let d = step[1].length();
                largest = if largest.is_nan() || d.is_nan() { f64::NAN } else { largest.max(d) };
            }
        }
        kernel::update_fixed_forced(op, state, forcing);
        largest
    }
}

/// The inverse of the Jacobian of the equations of `vertices` (ascending) in their own
/// unknowns, the rest held; `None` when it is singular.
fn block_inverse(op: &Operator, vertices: &[u32]) -> Option<Vec<f64>> {
    let m = 2 * vertices.len();
    let index = |j: usize| vertices.binary_search(&(j as u32)).ok();
    let mut a = faer::Mat::<f64>::zeros(m, m);
    for (u, &v) in vertices.iter().enumerate() {
        jacobian_rows(op, v as usize, u, index, |row, col, value| a[(row, col)] += value);
    }
    let (mut perm, mut perm_inv) = (vec![0usize; m], vec![0usize; m]);
    let scratch = factor::lu_in_place_scratch::<usize, f64>(m, m, Par::Seq, Default::default())
        .or(inverse::inverse_scratch::<usize, f64>(m, Par::Seq));
    let mut buffer = MemBuffer::try_new(scratch).ok()?;
    let (_, row_perm) = factor::lu_in_place(
        a.as_mut(),
        &mut perm,
        &mut perm_inv,
        Par::Seq,
        MemStack::new(&mut buffer),
        Default::default(),
    );
    let mut out = faer::Mat::<f64>::zeros(m, m);
    inverse::inverse(out.as_mut(), a.as_ref(), a.as_ref(), row_perm, Par::Seq, MemStack::new(&mut buffer));
    let values: Vec<f64> = (0..m).flat_map(|i| (0..m).map(move |j| (i, j))).map(|(i, j)| out[(i, j)]).collect();
    values.iter().all(|x| x.is_finite()).then_some(values)
}

#[cfg(test)]
mod tests {
    use super::super::direct::DirectSolve;
    use super::super::kernel;
    use super::super::level::Level;
    use super::super::operator::Controls;
    use super::*;

    fn default_levels(levels: usize) -> Vec<Level> {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../assets/default.taut");
        let doc = crate::Document::load(&path).unwrap();
        let controls = Controls {
            fixed: &doc.fixed,
            vertex_tension: &doc.vertex_tension,
            edge_tension: &doc.edge_tension,
            spacing: doc.settings.spacing,
        };
        let mut out = vec![Level::cage(&doc.cage, &controls)];
        for _ in 0..levels {
            let finer = out.last().unwrap().refine(&doc.cage, &controls, false).unwrap();
            out.push(finer);
        }
        out
    }

    #[test]
    fn blocks_surround_the_crowded_vertices_only() {
        // The default scene's cage has one vertex of valence 8 among quads and an octagon (whose
        // centre has valence 8 from level 1 on); its triangles meet quads at valence-5 vertices,
        // which are regular there, and its valence-3 corners have less around them, not more.
        for level in &default_levels(3)[1..] {
            let blocks = IrregularBlocks::new(&level.operator, &level.topology.mesh);
            assert_eq!(blocks.blocks.len(), 2);
            for block in &blocks.blocks {
                // Three rings around a valence-8 vertex: 1 + 8 + 16 + 24 among quads, fewer
                // where a ring reaches a fixed vertex.
                assert!(block.vertices.len() <= 49 && block.vertices.len() > 25, "{}", block.vertices.len());
                assert!(block.vertices.iter().all(|&v| level.operator.role[v as usize] == Role::Moving));
            }
        }
    }

    #[test]
    fn a_block_solve_satisfies_its_equations_and_keeps_the_fixed_point() {
        let mut levels = default_levels(2);
        let level = &mut levels[2];
        let (op, mesh) = (&level.operator, &level.topology.mesh);
        let blocks = IrregularBlocks::new(op, mesh);
        // From the refined start: the last block solved has a zero residual (the blocks are
        // apart, so the earlier ones too).
        let mut state = level.state.clone();
        blocks.solve(op, mesh, &mut state, None);
        for block in &blocks.blocks {
            for &v in &block.vertices {
                let (r, p) = kernel::vertex_residual(op, mesh, &state.p, &state.r, None, v as usize);
                assert!(r.length() < 1e-9 && p.length() < 1e-9, "vertex {v}: residual {r} {p}");
            }
        }
        // At the level's fixed point (a direct solve, the level is small) nothing moves.
        let mut direct = DirectSolve::new_unbounded(op).expect("the level has no tension");
        let mut exact = level.state.clone();
        direct.step(op, mesh, &mut exact, None);
        direct.step(op, mesh, &mut exact, None);
        let before = exact.p.clone();
        let step = blocks.solve(op, mesh, &mut exact, None);
        let moved = before.iter().zip(&exact.p).map(|(a, b)| (*a - *b).length()).fold(0.0, f64::max);
        assert!(step < 1e-12 && moved < 1e-12, "the blocks moved the fixed point by {moved:e}");
    }
}
