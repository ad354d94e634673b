//! Disjoint sets over `0..n` with path halving, the smaller index the root of each set: the
//! welds of the importers and the scan preparation join corners and triangles with it, and the
//! roots (each set's smallest member) do not depend on the order of the unions.

/// Disjoint sets over `0..n`; the smallest member of each set is its root.
#[derive(Clone, Debug, Default)]
pub(crate) struct UnionFind {
    parent: Vec<u32>,
}

impl UnionFind {
    /// `n` sets of one.
    #[inline]
    pub(crate) fn new(n: usize) -> Self {
        UnionFind { parent: (0..n as u32).collect() }
    }

    /// Back to `n` sets of one, keeping the buffer.
    #[inline]
    pub(crate) fn reset(&mut self, n: usize) {
        self.parent.clear();
        self.parent.extend(0..n as u32);
    }

    /// True when `x` is the root of its set.
    #[inline]
    pub(crate) fn is_root(&self, x: u32) -> bool {
        self.parent[x as usize] == x
    }

    /// The root of `x`'s set.
    #[inline]
    pub(crate) fn find(&mut self, mut x: u32) -> u32 {
        while self.parent[x as usize] != x {
            let grand = self.parent[self.parent[x as usize] as usize];
            self.parent[x as usize] = grand;
            x = grand;
        }
        x
    }

    /// Joins the sets of `a` and `b`.
    #[inline]
    pub(crate) fn union(&mut self, a: u32, b: u32) {
        let (a, b) = (self.find(a), self.find(b));
        if a != b {
            let (lo, hi) = (a.min(b), a.max(b));
            self.parent[hi as usize] = lo;
        }
    }
}
