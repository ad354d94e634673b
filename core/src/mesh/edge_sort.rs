//! Sorting the sides of a large triangle or polygon list by the edge they run along, and the
//! counting sort it is made of.
//!
//! Importers and the scan preparation group a mesh's sides by undirected edge: entries
//! `(lo, hi, tag)` with `lo ≤ hi` the edge's vertices and `tag` unique per side. A comparison
//! sort of millions of them was the largest single cost of reading a 1 M-triangle scan. Here the
//! entries are bucketed by `lo` (a counting sort, stable, in two linear passes) and each bucket,
//! a vertex's few edges, is then sorted on its own: the result is exactly the comparison sort's
//! (every entry differs in `tag`), whatever the thread count.

use rayon::prelude::*;

/// A stable counting sort of the items `item(0..len)` by `key(i) < buckets`: the items by key,
/// equal keys in index order, and where each key's run starts (`starts[k]..starts[k + 1]`).
pub fn bucket_sort<T: Copy>(
    len: usize,
    buckets: usize,
    key: impl Fn(usize) -> usize,
    item: impl Fn(usize) -> T,
    fill: T,
) -> (Vec<u32>, Vec<T>) {
    let mut starts = vec![0u32; buckets + 1];
    for i in 0..len {
        starts[key(i) + 1] += 1;
    }
    for k in 0..buckets {
        starts[k + 1] += starts[k];
    }
    let mut next = starts.clone();
    let mut out = vec![fill; len];
    for i in 0..len {
        let slot = &mut next[key(i)];
        out[*slot as usize] = item(i);
        *slot += 1;
    }
    (starts, out)
}

/// Sorts `entries` by `(lo, hi, tag)`, every `lo` and `hi` below `vertices`. Identical to
/// `entries.sort_unstable()` when no two entries are equal.
pub fn sort_sides(entries: &mut Vec<(u32, u32, u32)>, vertices: usize) {
    if entries.len() < 1 << 12 {
        entries.sort_unstable();
        return;
    }
    // Bucketed by `lo`, each bucket in input order, then each bucket sorted on its own.
    let (starts, mut out) = bucket_sort(entries.len(), vertices, |i| entries[i].0 as usize, |i| entries[i], (0, 0, 0));
    let mut buckets: Vec<&mut [(u32, u32, u32)]> = Vec::with_capacity(vertices);
    let mut rest: &mut [(u32, u32, u32)] = &mut out;
    for v in 0..vertices {
        let (bucket, tail) = rest.split_at_mut((starts[v + 1] - starts[v]) as usize);
        if bucket.len() > 1 {
            buckets.push(bucket);
        }
        rest = tail;
    }
    buckets.par_iter_mut().with_min_len(1 << 10).for_each(|b| b.sort_unstable());
    *entries = out;
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_same_order_as_a_comparison_sort() {
        // Pseudo-random sides of 5,000 vertices, many sharing an edge, in scrambled order.
        let mut state = 0x2545_f491_4f6c_dd1du64;
        let mut next = || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            state
        };
        let n = 5_000u32;
        let mut entries: Vec<(u32, u32, u32)> = (0..40_000u32)
            .map(|tag| {
                let a = (next() % u64::from(n)) as u32;
                let b = (a + 1 + (next() % 7) as u32) % n;
                (a.min(b), a.max(b), tag)
            })
            .collect();
        let mut expected = entries.clone();
        expected.sort_unstable();
        sort_sides(&mut entries, n as usize);
        assert_eq!(entries, expected);
        // Small lists and an empty one too.
        let mut few = vec![(3, 4, 1), (0, 2, 0), (3, 4, 0)];
        sort_sides(&mut few, 5);
        assert_eq!(few, vec![(0, 2, 0), (3, 4, 0), (3, 4, 1)]);
        let mut none: Vec<(u32, u32, u32)> = Vec::new();
        sort_sides(&mut none, 0);
        assert!(none.is_empty());
    }
}
