//! The hierarchy of a [`SurfaceIndex`](super::SurfaceIndex): its nodes as built (`f64` boxes,
//! depth first, kept for refitting), their search layout ([`Wide`]: four grandchildren's boxes
//! in `f32` in two cache lines), the pending stack the searches share, and the parallel build over
//! Morton-ordered triangles (see the parent module).

use super::from_parry;
use crate::DVec3;
use parry3d_f64::math::Vector;
use rayon::prelude::*;

/// The most triangles in a leaf of the hierarchy.
pub(super) const LEAF: usize = 4;
/// Ranges of more triangles than this are planned on one thread; the subtrees below them are
/// built side by side.
pub(super) const PARALLEL: usize = 1 << 14;
/// Deeper than any tree the build makes: each split either consumes a bit of the 63-bit codes or
/// halves a range of more than [`LEAF`] equal codes (fewer than 29 times below [`MAX_TRIANGLES`]).
const MAX_DEPTH: usize = 96;
/// The most children a search keeps pending: all but one of a node's at each level of the
/// search layout, which is half as deep as the tree.
const MAX_PENDING: usize = (WIDTH - 1) * MAX_DEPTH.div_ceil(2);
/// The most triangles an index takes: a child reference keeps 29 bits for a slot.
pub(super) const MAX_TRIANGLES: usize = 1 << 29;
/// A child reference's index bits; the three above them hold a leaf's triangle count (0 for an
/// inner node).
pub(super) const INDEX_BITS: u32 = 29;
const _: () = assert!(LEAF < 1 << (32 - INDEX_BITS), "a leaf's count must fit above the index bits");

/// A node of the hierarchy, in depth-first order: an inner node's left child follows it, its
/// right child is `at` nodes further on; a leaf holds the `count` triangles from slot `at`.
#[derive(Clone, Copy, Debug)]
pub(super) struct Node {
    lo: DVec3,
    hi: DVec3,
    at: u32,
    count: u32,
}

impl Node {
    /// The parameter where the ray enters the box, if it meets it at some `t` in `0..=max`.
    fn entry(&self, origin: DVec3, inverse: DVec3, max: f64) -> Option<f64> {
        let (mut near, mut far) = (0.0f64, max);
        for k in 0..3 {
            let (o, inv) = (origin[k], inverse[k]);
            if inv.is_infinite() {
                // Parallel to this pair of planes: in between them or never.
                if o < self.lo[k] || o > self.hi[k] {
                    return None;
                }
                continue;
            }
            let (a, b) = ((self.lo[k] - o) * inv, (self.hi[k] - o) * inv);
            near = near.max(a.min(b));
            far = far.min(a.max(b));
        }
        (near <= far).then_some(near)
    }
}

/// Children of a node of the search layout: two levels of the binary tree in one.
pub(super) const WIDTH: usize = 4;
/// The reference of a child place left empty (a node of fewer than [`WIDTH`] children).
pub(super) const EMPTY: u32 = u32::MAX;

/// A node as the searches read it: the boxes of up to [`WIDTH`] children (the binary tree's
/// grandchildren, or a child that is a leaf) by coordinate, in `f32` rounded outwards (a box
/// never shrinks), and a reference to each ([`INDEX_BITS`]; [`EMPTY`] for none). Two cache lines.
#[derive(Clone, Copy, Debug)]
#[repr(C, align(64))]
pub(super) struct Wide {
    lo: [[f32; WIDTH]; 3],
    hi: [[f32; WIDTH]; 3],
    pub(super) child: [u32; WIDTH],
}

impl Wide {
    /// The squared distance from `p` to each child's box (a lower bound of the exact one;
    /// meaningless for an [`EMPTY`] child).
    #[inline]
    pub(super) fn distances_squared(&self, p: DVec3) -> [f64; WIDTH] {
        let mut d = [0.0; WIDTH];
        for (axis, &x) in p.to_array().iter().enumerate() {
            let (lo, hi) = (self.lo[axis].map(f64::from), self.hi[axis].map(f64::from));
            for k in 0..WIDTH {
                // Comparisons rather than `max`, which would also order NaNs: a NaN `x` gives 0.
                let (below, above) = (lo[k] - x, x - hi[k]);
                let e = if below > above { below } else { above };
                let e = if e > 0.0 { e } else { 0.0 };
                d[k] += e * e;
            }
        }
        d
    }

    /// Where the ray enters child `k`'s box, if it meets it at some `t` in `0..=max`.
    pub(super) fn entry(&self, k: usize, origin: DVec3, inverse: DVec3, max: f64) -> Option<f64> {
        let corner = |c: &[[f32; WIDTH]; 3]| DVec3::new(c[0][k].into(), c[1][k].into(), c[2][k].into());
        Node { lo: corner(&self.lo), hi: corner(&self.hi), at: 0, count: 0 }.entry(origin, inverse, max)
    }
}

/// A child reference's leaf triangle count (0 for an inner node) and its index ([`INDEX_BITS`]).
pub(super) fn decode(reference: u32) -> (usize, usize) {
    ((reference >> INDEX_BITS) as usize, (reference & ((1 << INDEX_BITS) - 1)) as usize)
}

/// The children a search met but has not visited yet, latest first, each with a lower bound of
/// what it can hold (a squared distance, a ray parameter) rounded down to an `f32` above it.
pub(super) struct Pending {
    entries: [u64; MAX_PENDING],
    depth: usize,
}

impl Pending {
    pub(super) fn new() -> Self {
        Pending { entries: [0; MAX_PENDING], depth: 0 }
    }

    /// Of a node's children `met` by a search ([`met`], in any order; [`NONE`] for the others):
    /// the nearest, to go on with, and the others pending, the nearer of them on top; `None`
    /// when none was met.
    pub(super) fn descend(&mut self, mut met: [u64; WIDTH]) -> Option<u32> {
        // A sorting network: the same comparisons whatever the bounds, no branch to mispredict.
        for (i, j) in [(0, 1), (2, 3), (0, 2), (1, 3), (1, 2)] {
            (met[i], met[j]) = (met[i].min(met[j]), met[i].max(met[j]));
        }
        let n = met.iter().filter(|&&m| m != NONE).count();
        for &m in met[1..n.max(1)].iter().rev() {
            self.entries[self.depth] = m;
            self.depth += 1;
        }
        (n > 0).then_some(met[0] as u32)
    }

    /// The latest pending child whose bound `keep` accepts, dropping those it does not; `None`
    /// when none is left.
    pub(super) fn pop(&mut self, keep: impl Fn(f64) -> bool) -> Option<u32> {
        while self.depth > 0 {
            self.depth -= 1;
            let entry = self.entries[self.depth];
            if keep(f64::from(f32::from_bits((entry >> 32) as u32))) {
                return Some(entry as u32);
            }
        }
        None
    }
}

const _: () = assert!(WIDTH == 4, "the sorting network of `Pending::descend` sorts four");

/// A child a search met, as it waits: its lower bound (a squared distance, a ray parameter)
/// rounded down to a non-negative `f32`, whose bits order as the numbers do, above its reference.
pub(super) fn met(reference: u32, bound: f64) -> u64 {
    u64::from(down(bound).max(0.0).to_bits()) << 32 | u64::from(reference)
}

/// A child a search did not meet: after every [`met`] one.
pub(super) const NONE: u64 = u64::MAX;

/// `x` rounded down to an `f32`.
pub(super) fn down(x: f64) -> f32 {
    let y = x as f32;
    if f64::from(y) > x { y.next_down() } else { y }
}

/// `x` rounded up to an `f32`.
pub(super) fn up(x: f64) -> f32 {
    let y = x as f32;
    if f64::from(y) < x { y.next_up() } else { y }
}

/// The search layout of a depth-first tree: one [`Wide`] per inner node at an even depth (the
/// root's is 0), in the same order, whose children are its children's children (or a child
/// that is a leaf).
fn widen(nodes: &[Node]) -> Vec<Wide> {
    let leaf = |n: &Node| n.count << INDEX_BITS | n.at;
    let empty = Wide { lo: [[f32::INFINITY; WIDTH]; 3], hi: [[f32::NEG_INFINITY; WIDTH]; 3], child: [EMPTY; WIDTH] };
    if nodes.len() == 1 {
        // One leaf: a root with it as the only child.
        let mut root = empty;
        root.child[0] = leaf(&nodes[0]);
        for axis in 0..3 {
            root.lo[axis][0] = down(nodes[0].lo[axis]);
            root.hi[axis][0] = up(nodes[0].hi[axis]);
        }
        return vec![root];
    }
    // Children follow their parent: depths (their parity) in one pass, then the even inner
    // nodes' places among themselves.
    let mut even = vec![false; nodes.len()];
    even[0] = true;
    let mut rank = vec![0u32; nodes.len()];
    let mut heads = 0;
    for k in 0..nodes.len() {
        if nodes[k].count == 0 {
            let odd = !even[k];
            even[k + 1] = odd;
            even[k + nodes[k].at as usize] = odd;
            if even[k] {
                rank[k] = heads;
                heads += 1;
            }
        }
    }
    let children = |k: usize| [k + 1, k + nodes[k].at as usize];
    nodes
        .par_iter()
        .enumerate()
        .filter(|&(k, n)| n.count == 0 && even[k])
        .map(|(k, _)| {
            let mut wide = empty;
            let below = children(k)
                .into_iter()
                .flat_map(|c| if nodes[c].count > 0 { [Some(c), None] } else { children(c).map(Some) });
            for (place, c) in below.flatten().enumerate() {
                let n = &nodes[c];
                wide.child[place] = if n.count > 0 { leaf(n) } else { rank[c] };
                for axis in 0..3 {
                    wide.lo[axis][place] = down(n.lo[axis]);
                    wide.hi[axis][place] = up(n.hi[axis]);
                }
            }
            wide
        })
        .collect()
}

/// Spreads the low 21 bits of `x` to every third bit.
pub(super) fn spread(x: u64) -> u64 {
    let mut x = x & 0x1f_ffff;
    x = (x | x << 32) & 0x001f_0000_0000_ffff;
    x = (x | x << 16) & 0x001f_0000_ff00_00ff;
    x = (x | x << 8) & 0x100f_00f0_0f00_f00f;
    x = (x | x << 4) & 0x10c3_0c30_c30c_30c3;
    (x | x << 2) & 0x1249_2492_4924_9249
}

/// The 63-bit Morton code of `p` in the box from `lo` scaled by `scale`; non-finite coordinates
/// saturate.
pub(super) fn morton(p: DVec3, lo: DVec3, scale: f64) -> u64 {
    let top = f64::from((1u32 << 21) - 1);
    let q = ((p - lo) * scale).to_array().map(|c| if c.is_nan() { 0 } else { c.clamp(0.0, top) as u64 });
    spread(q[0]) | spread(q[1]) << 1 | spread(q[2]) << 2
}

/// Where the sorted `keys` split: after the last key with the highest differing bit clear, or in
/// the middle when all are equal. Both halves are non-empty for at least two keys.
pub(super) fn split(keys: &[u64]) -> usize {
    let (first, last) = (keys[0], keys[keys.len() - 1]);
    if first == last {
        return keys.len() / 2;
    }
    let bit = 63 - (first ^ last).leading_zeros();
    keys.partition_point(|&k| k >> bit & 1 == 0)
}

/// A subtree built on its own: its nodes (offsets relative) and its box.
pub(super) type Subtree = (Vec<Node>, (DVec3, DVec3));

/// A part of the tree above the subtrees that are built side by side.
pub(super) enum Plan {
    Inner(usize, usize),
    Subtree(usize, usize),
}

/// Plans the range `start..end` of the sorted keys into `plan`; returns its entry.
pub(super) fn plan(keys: &[u64], start: usize, end: usize, plan_out: &mut Vec<Plan>) -> usize {
    if end - start <= PARALLEL {
        plan_out.push(Plan::Subtree(start, end));
        return plan_out.len() - 1;
    }
    let mid = start + split(&keys[start..end]);
    let left = plan(keys, start, mid, plan_out);
    let right = plan(keys, mid, end, plan_out);
    plan_out.push(Plan::Inner(left, right));
    plan_out.len() - 1
}

/// The triangles by slot (the leaves' order) as the searches read them: each slot's corners as
/// places in `vertices`, the positions the triangles use, numbered by their first use in slot
/// order. A leaf's triangles share most of their corners and lie together in the space, so
/// their vertices lie together in memory, and the whole takes a third of the memory of three
/// corners a triangle: the searches wait on memory far more than they compute.
#[derive(Clone, Debug, Default)]
pub(super) struct Corners {
    slots: Vec<[u32; 3]>,
    vertices: Vec<Vector>,
    /// The position each vertex is, for moving them.
    position_of: Vec<u32>,
}

impl Corners {
    /// The corners of `triangles` (over `positions`) taken in the order `ids`.
    pub(super) fn new(triangles: &[[u32; 3]], ids: &[u32], positions: &[DVec3]) -> Self {
        let mut number = vec![u32::MAX; positions.len()];
        let mut position_of = Vec::new();
        let slots = ids
            .iter()
            .map(|&t| {
                triangles[t as usize].map(|v| {
                    if number[v as usize] == u32::MAX {
                        number[v as usize] = position_of.len() as u32;
                        position_of.push(v);
                    }
                    number[v as usize]
                })
            })
            .collect();
        let mut corners = Corners { slots, vertices: Vec::new(), position_of };
        corners.set_positions(positions);
        corners
    }

    /// Moves the vertices to `positions` (numbered as given to [`new`](Self::new)).
    pub(super) fn set_positions(&mut self, positions: &[DVec3]) {
        self.vertices = self.position_of.par_iter().map(|&v| super::to_parry(positions[v as usize])).collect();
    }

    /// The corners of the triangle at `slot`.
    #[inline]
    pub(super) fn get(&self, slot: usize) -> [Vector; 3] {
        self.slots[slot].map(|v| self.vertices[v as usize])
    }

    /// The box of the triangles at `slots`, widened by `pad`.
    fn bounds(&self, slots: std::ops::Range<usize>, pad: f64) -> (DVec3, DVec3) {
        slots
            .map(|slot| triangle_box(&self.get(slot), pad))
            .fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(lo, hi), (a, b)| (lo.min(a), hi.max(b)))
    }
}

/// The slots' triangles, whose boxes (widened by `pad`) the leaves take.
pub(super) struct Boxes<'a> {
    corners: &'a Corners,
    pad: f64,
}

/// The tree over slots `start..end` in depth-first order, appended to `out` (its own node
/// offsets are relative, so it can be moved as a block).
pub(super) fn build(keys: &[u64], boxes: &Boxes<'_>, start: usize, end: usize, out: &mut Vec<Node>) -> (DVec3, DVec3) {
    if end - start <= LEAF {
        let (lo, hi) = boxes.corners.bounds(start..end, boxes.pad);
        out.push(Node { lo, hi, at: start as u32, count: (end - start) as u32 });
        return (lo, hi);
    }
    let at = out.len();
    out.push(Node { lo: DVec3::ZERO, hi: DVec3::ZERO, at: 0, count: 0 });
    let mid = start + split(&keys[start..end]);
    let (a, b) = build(keys, boxes, start, mid, out);
    let right = out.len();
    let (c, d) = build(keys, boxes, mid, end, out);
    let (lo, hi) = (a.min(c), b.max(d));
    out[at] = Node { lo, hi, at: (right - at) as u32, count: 0 };
    (lo, hi)
}

/// Appends the planned entry `entry` to `out`, with the subtrees built beforehand; returns its box.
pub(super) fn assemble(
    plan: &[Plan],
    entry: usize,
    subtrees: &mut [Option<Subtree>],
    out: &mut Vec<Node>,
) -> (DVec3, DVec3) {
    match plan[entry] {
        Plan::Subtree(..) => {
            let (nodes, bounds) = subtrees[entry].take().expect("each subtree is placed once");
            out.extend_from_slice(&nodes);
            bounds
        }
        Plan::Inner(left, right) => {
            let at = out.len();
            out.push(Node { lo: DVec3::ZERO, hi: DVec3::ZERO, at: 0, count: 0 });
            let (a, b) = assemble(plan, left, subtrees, out);
            let right_at = out.len();
            let (c, d) = assemble(plan, right, subtrees, out);
            let (lo, hi) = (a.min(c), b.max(d));
            out[at] = Node { lo, hi, at: (right_at - at) as u32, count: 0 };
            (lo, hi)
        }
    }
}

/// The box of a triangle's corners widened by `pad`.
pub(super) fn triangle_box(c: &[Vector; 3], pad: f64) -> (DVec3, DVec3) {
    let [a, b, c] = c.map(from_parry);
    (a.min(b).min(c) - DVec3::splat(pad), a.max(b).max(c) + DVec3::splat(pad))
}

/// The hierarchy over the slots' triangles (`corners`, their sorted Morton `keys`), boxes widened
/// by `pad`: the depth-first nodes, and their search layout.
pub(super) fn hierarchy(keys: &[u64], corners: &Corners, pad: f64) -> (Vec<Node>, Vec<Wide>) {
    let boxes = Boxes { corners, pad };
    let mut planned = Vec::new();
    let root = plan(keys, 0, keys.len(), &mut planned);
    let mut subtrees: Vec<Option<Subtree>> = planned
        .par_iter()
        .map(|p| match *p {
            Plan::Subtree(start, end) => {
                let mut nodes = Vec::with_capacity(2 * (end - start).div_ceil(LEAF));
                let bounds = build(keys, &boxes, start, end, &mut nodes);
                Some((nodes, bounds))
            }
            Plan::Inner(..) => None,
        })
        .collect();
    let mut nodes = Vec::with_capacity(subtrees.iter().flatten().map(|s| s.0.len()).sum::<usize>() + planned.len());
    assemble(&planned, root, &mut subtrees, &mut nodes);
    let wide = widen(&nodes);
    (nodes, wide)
}

/// Refits the boxes of `nodes` to the slots' moved `corners` (widened by `pad`); returns the new
/// search layout.
pub(super) fn refit(nodes: &mut [Node], corners: &Corners, pad: f64) -> Vec<Wide> {
    nodes.par_iter_mut().filter(|n| n.count > 0).for_each(|n| {
        (n.lo, n.hi) = corners.bounds(n.at as usize..(n.at + n.count) as usize, pad);
    });
    // Children follow their parent: from the last node back, both are refitted before it.
    for k in (0..nodes.len()).rev() {
        if nodes[k].count == 0 {
            let (left, right) = (nodes[k + 1], nodes[k + nodes[k].at as usize]);
            nodes[k].lo = left.lo.min(right.lo);
            nodes[k].hi = left.hi.max(right.hi);
        }
    }
    widen(nodes)
}
