//! Welding a soup of triangles whose every corner is a vertex of its own (a binary STL) straight
//! from the file's `f32` corners, in parallel: the same vertices, triangles and report as
//! [`weld_faces`](super::weld::weld_faces) on that soup (see [`super::weld`] for what welding
//! merges, repairs and keeps apart), at a fraction of its time and memory on a million triangles.
//!
//! The general weld follows each corner through one arbitrary polygon at a time; here every face
//! is a triangle and every corner a file vertex, so everything it decides is local to one
//! position:
//! 1. Corners are bucketed by a hash of their position's bits (about two thousand corners a
//!    bucket, small enough to sort in cache) and each bucket is sorted by bits, then by corner.
//!    A run of equal bits is one position; its first corner is the vertex every corner there
//!    welds to, as in the general weld.
//! 2. A triangle with two corners at one position has fewer than three distinct vertices left
//!    and is dropped.
//! 3. Two triangles on the same three positions meet at the smallest of them with the same two
//!    other positions next to it: there, of each such set the first triangle in the file is kept,
//!    and the rest are dropped as its repeats (facing the other way when their neighbours come in
//!    the other order).
//! 4. An edge used once each way joins the corners at either end into one fan. At a position `a`
//!    the uses of edge `ab` are exactly the corners there whose next corner is at `b` (it runs
//!    `a → b`) or whose previous corner is (it runs `b → a`), so the fans around `a` are found
//!    among `a`'s own corners. Each fan becomes a vertex, numbered by its first corner; a
//!    position whose triangles were all dropped keeps its first corner as an unused vertex.
//!
//! No triangle can pass through one vertex twice: a fan only ever holds corners at one position,
//! and a kept triangle's three corners are at three. Deterministic on any number of threads: each
//! bucket is worked on alone and everything is collected in the file's order.

use super::weld::{ImportReport, Listed, NONE, mix, note};
use crate::mesh::union_find::UnionFind;
use crate::{DVec3, Error, Result};
use rayon::prelude::*;

/// About how many corners share a hash bucket.
const PER_BUCKET: usize = 1 << 11;

/// One corner: its position's bits (−0.0 made 0.0) above its number (`3 × triangle + k`).
type Record = u128;

fn same_position(a: &Record, b: &Record) -> bool {
    a >> 32 == b >> 32
}

/// Welds triangles given by their corners' positions (all finite) into vertices and triangles,
/// as the module doc describes.
pub(crate) fn weld_triangle_soup(triangles: &[[[f32; 3]; 3]]) -> Result<(Vec<DVec3>, Vec<[u32; 3]>, ImportReport)> {
    let n = triangles.len().saturating_mul(3);
    if n >= NONE as usize {
        return Err(Error::Input(format!("{n} vertices is more than Taut can index")));
    }
    let corner = |c: u32| triangles[c as usize / 3][c as usize % 3];
    // Adding 0.0 turns −0.0 into 0.0 and leaves every other value alone.
    let bits = |c: u32| corner(c).map(|x| (x + 0.0).to_bits());

    // 1. Corners bucketed by their position's hash, each bucket sorted: a record is the
    //    position's 96 bits above the corner's number.
    let buckets_log2 = (n / PER_BUCKET).max(1).ilog2();
    let bucket_of = |r: Record| {
        let h = mix((r >> 64) as u64 ^ mix((r >> 32) as u32 as u64));
        if buckets_log2 == 0 { 0 } else { (h >> (64 - buckets_log2)) as usize }
    };
    let record = |c: u32| {
        let [x, y, z] = bits(c);
        u128::from(x) << 96 | u128::from(y) << 64 | u128::from(z) << 32 | u128::from(c)
    };
    let of: Vec<u32> = (0..n as u32).into_par_iter().map(|c| bucket_of(record(c)) as u32).collect();
    let (starts, mut records) =
        crate::mesh::edge_sort::bucket_sort(n, 1 << buckets_log2, |c| of[c] as usize, |c| record(c as u32), 0);
    drop(of);
    let mut buckets = split_by(&mut records, &starts);
    buckets.par_iter_mut().for_each(|b| b.sort_unstable());
    let mut tentative = vec![NONE; n];
    for bucket in &buckets {
        for run in bucket.chunk_by(same_position) {
            let first = run[0] as u32;
            for &r in run {
                tentative[r as u32 as usize] = first;
            }
        }
    }

    // 2. Triangles left with fewer than three distinct vertices.
    let welded: Vec<[u32; 3]> =
        (0..triangles.len()).into_par_iter().map(|f| [0, 1, 2].map(|k| tentative[3 * f + k])).collect();
    drop(tentative);
    let degenerate = |t: &[u32; 3]| t[0] == t[1] || t[1] == t[2] || t[2] == t[0];
    let mut dropped: Vec<bool> = welded.par_iter().map(degenerate).collect();
    let mut report = ImportReport::default();
    let mut listed = Listed::default();
    for f in dropped.iter().enumerate().filter(|(_, d)| **d).map(|(f, _)| f) {
        report.dropped_faces += 1;
        note(&mut listed.dropped, || {
            format!("dropped face {f}: fewer than 3 distinct vertices are left once repeats are removed")
        });
    }

    // 3 and 4. Each position's repeats and fans, in one pass over the corners; the fans again,
    // without the repeats' corners, only when there are repeats.
    let mut heads = vec![NONE; n];
    let mut found = positions_pass(&buckets, &starts, &mut heads, &welded, &dropped);
    let mut repeats: Vec<(u32, u32, bool)> = found.iter_mut().flat_map(|f| std::mem::take(&mut f.repeats)).collect();
    repeats.sort_unstable();
    for &(f, g, reversed) in &repeats {
        dropped[f as usize] = true;
        listed.repeat(&mut report, f, g, reversed);
    }
    if !repeats.is_empty() {
        found = positions_pass(&buckets, &starts, &mut heads, &welded, &dropped);
    }
    drop(buckets);
    let mut head_of = vec![NONE; n];
    for (&r, &h) in records.iter().zip(&heads) {
        head_of[r as u32 as usize] = h;
    }
    drop(heads);
    drop(records);

    // Vertices in the order of the corner each stands for.
    let mut kept: Vec<u32> = found.iter().flat_map(|f| f.vertices.iter().copied()).collect();
    kept.par_sort_unstable();
    let mut new_index = vec![NONE; n];
    for (i, &c) in kept.iter().enumerate() {
        new_index[c as usize] = i as u32;
    }
    let positions: Vec<DVec3> = kept.par_iter().map(|&c| DVec3::from_array(corner(c).map(f64::from))).collect();
    report.welded = n - positions.len();
    let mut apart: Vec<(u32, u32)> = found.into_iter().flat_map(|f| f.apart).collect();
    apart.sort_unstable();
    report.kept_apart = apart.iter().map(|&(_, fans)| fans as usize - 1).sum();
    listed.touching(apart.len(), apart.iter().map(|&(c, _)| corner(c).map(f64::from)));
    let out: Vec<[u32; 3]> = (0..triangles.len())
        .into_par_iter()
        .filter(|&f| !dropped[f])
        .map(|f| [0, 1, 2].map(|k| new_index[head_of[3 * f + k] as usize]))
        .collect();
    report.warnings = listed.finish(&report);
    Ok((positions, out, report))
}

/// `items` cut at `starts` (a bucket sort's starts) into one slice per bucket.
fn split_by<'a, T>(items: &'a mut [T], starts: &[u32]) -> Vec<&'a mut [T]> {
    let mut out = Vec::with_capacity(starts.len().saturating_sub(1));
    let mut rest = items;
    for w in starts.windows(2) {
        let (head, tail) = rest.split_at_mut((w[1] - w[0]) as usize);
        out.push(head);
        rest = tail;
    }
    out
}

/// What one bucket's positions hold.
#[derive(Default)]
struct Found {
    /// `(triangle, the earlier triangle it repeats, facing the other way)`.
    repeats: Vec<(u32, u32, bool)>,
    /// The corners that become vertices: each fan's first, and the first of a position whose
    /// triangles were all dropped.
    vertices: Vec<u32>,
    /// `(first corner, fans)` of each position with more than one fan.
    apart: Vec<(u32, u32)>,
}

/// Finds each position's repeated triangles (at their smallest position) and its fans among the
/// corners of triangles not `dropped`; writes each corner's fan's first corner into `heads` (in
/// the records' order, `NONE` for a dropped triangle's corner).
fn positions_pass(
    buckets: &[&mut [Record]],
    starts: &[u32],
    heads: &mut [u32],
    welded: &[[u32; 3]],
    dropped: &[bool],
) -> Vec<Found> {
    let mut out_heads = split_by(heads, starts);
    buckets
        .par_iter()
        .zip(out_heads.par_iter_mut())
        .map_init(Fans::default, |fans, (bucket, heads)| {
            let mut found = Found::default();
            let mut at = 0;
            for run in bucket.chunk_by(same_position) {
                let count = fans.find(run, welded, dropped, &mut found.repeats);
                if count == 0 {
                    found.vertices.push(run[0] as u32);
                } else if count > 1 {
                    found.apart.push((run[0] as u32, count));
                }
                heads[at..at + run.len()].copy_from_slice(&fans.head);
                found.vertices.extend(fans.heads());
                at += run.len();
            }
            found
        })
        .collect()
}

/// The fans at one position, with buffers kept from one position to the next.
#[derive(Default)]
struct Fans {
    /// Per corner of the position, its fan's first corner (`NONE` for a dropped triangle's).
    head: Vec<u32>,
    /// Live corners: (position of the next corner, of the previous, index in the run).
    live: Vec<(u32, u32, u32)>,
    /// The live corners by the position they run to (next) and come from (previous).
    out: Vec<(u32, u32)>,
    into: Vec<(u32, u32)>,
    sets: UnionFind,
    /// Triangles whose smallest position this is: (other two positions in order, triangle, next).
    smallest: Vec<(u32, u32, u32, u32)>,
}

impl Fans {
    /// Finds the fans among `run`'s corners (one position, ascending) whose triangles are not
    /// `dropped`, and adds the repeats met at their smallest position to `repeats`; returns how
    /// many fans there are.
    fn find(
        &mut self,
        run: &[Record],
        welded: &[[u32; 3]],
        dropped: &[bool],
        repeats: &mut Vec<(u32, u32, bool)>,
    ) -> u32 {
        self.live.clear();
        self.smallest.clear();
        let a = run[0] as u32;
        for (i, &r) in run.iter().enumerate() {
            let c = r as u32;
            let (f, k) = (c as usize / 3, c as usize % 3);
            if dropped[f] {
                continue;
            }
            let t = welded[f];
            let (next, prev) = (t[(k + 1) % 3], t[(k + 2) % 3]);
            self.live.push((next, prev, i as u32));
            if next > a && prev > a {
                self.smallest.push((next.min(prev), next.max(prev), f as u32, next));
            }
        }
        if self.smallest.len() > 1 {
            self.smallest.sort_unstable();
            for same in self.smallest.chunk_by(|x, y| (x.0, x.1) == (y.0, y.1)) {
                let (first, first_next) = (same[0].2, same[0].3);
                repeats.extend(same[1..].iter().map(|&(_, _, f, next)| (f, first, next != first_next)));
            }
        }
        self.sets.reset(run.len());
        // Edge a–b joins two corners here when it is used once each way: once running to b
        // (out) and once coming from b (into).
        let live = &self.live;
        if live.len() <= 8 {
            for &(next, _, i) in live {
                if live.iter().filter(|e| e.0 == next).count() == 1 {
                    let mut from = live.iter().filter(|e| e.1 == next);
                    if let (Some(e), None) = (from.next(), from.next()) {
                        self.sets.union(i, e.2);
                    }
                }
            }
        } else {
            self.out.clear();
            self.into.clear();
            self.out.extend(live.iter().map(|e| (e.0, e.2)));
            self.into.extend(live.iter().map(|e| (e.1, e.2)));
            self.out.sort_unstable();
            self.into.sort_unstable();
            let (mut i, mut j) = (0, 0);
            while i < self.out.len() {
                let b = self.out[i].0;
                let end = i + self.out[i..].iter().take_while(|e| e.0 == b).count();
                while j < self.into.len() && self.into[j].0 < b {
                    j += 1;
                }
                let from = self.into[j..].iter().take_while(|e| e.0 == b).count();
                if end - i == 1 && from == 1 {
                    self.sets.union(self.out[i].1, self.into[j].1);
                }
                i = end;
            }
        }
        self.head.clear();
        self.head.resize(run.len(), NONE);
        let mut count = 0;
        for &(_, _, i) in &self.live {
            let root = self.sets.find(i);
            if root == i {
                count += 1;
            }
            self.head[i as usize] = run[root as usize] as u32;
        }
        count
    }

    /// The first corner of each fan found last.
    fn heads(&self) -> impl Iterator<Item = u32> + '_ {
        self.live.iter().filter(|e| self.sets.is_root(e.2)).map(|e| self.head[e.2 as usize])
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::io::weld::weld_faces;

    /// The general weld of the same soup, its polygons split into fans as an import does.
    fn general(triangles: &[[[f32; 3]; 3]]) -> Result<(Vec<DVec3>, Vec<[u32; 3]>, ImportReport)> {
        let positions: Vec<DVec3> = triangles.iter().flatten().map(|p| DVec3::from_array(p.map(f64::from))).collect();
        let faces: Vec<[u32; 3]> = (0..triangles.len() as u32).map(|t| [3 * t, 3 * t + 1, 3 * t + 2]).collect();
        let welded = weld_faces(&positions, &faces.iter().collect())?;
        let out = welded.faces.iter().map(|f| <[u32; 3]>::try_from(f).expect("triangles stay triangles")).collect();
        Ok((welded.positions, out, welded.report))
    }

    fn assert_same(triangles: &[[[f32; 3]; 3]]) -> ImportReport {
        let (p, t, r) = weld_triangle_soup(triangles).unwrap();
        let (gp, gt, gr) = general(triangles).unwrap();
        // Bit for bit, so −0.0 kept where the file has it counts too.
        let bits = |p: &[DVec3]| p.iter().map(|q| q.to_array().map(f64::to_bits)).collect::<Vec<_>>();
        assert_eq!(bits(&p), bits(&gp));
        assert_eq!(t, gt);
        assert_eq!(r, gr);
        r
    }

    /// xorshift64: pseudo-random numbers for the soups.
    struct Random(u64);
    impl Random {
        fn below(&mut self, n: u64) -> u64 {
            self.0 ^= self.0 << 13;
            self.0 ^= self.0 >> 7;
            self.0 ^= self.0 << 17;
            self.0 % n
        }
    }

    /// A closed surface of `n × n` quads (a torus grid) as a soup, corners at grid points.
    fn torus_soup(n: u32) -> Vec<[[f32; 3]; 3]> {
        let at = |i: u32, j: u32| {
            let (a, b) = ((i % n) as f32, (j % n) as f32);
            [a, b, (a * 7.0 + b * 3.0) % 5.0]
        };
        let mut out = Vec::new();
        for i in 0..n {
            for j in 0..n {
                out.push([at(i, j), at(i + 1, j), at(i + 1, j + 1)]);
                out.push([at(i, j), at(i + 1, j + 1), at(i, j + 1)]);
            }
        }
        out
    }

    #[test]
    fn a_closed_grid_welds_as_the_general_weld_does() {
        let r = assert_same(&torus_soup(40));
        assert_eq!(r.welded, 3 * 3200 - 1600);
    }

    #[test]
    fn repairs_and_touching_parts_are_reported_as_the_general_weld_does() {
        let mut soup = torus_soup(12);
        // Degenerate: two corners at one position, seven of them so the list is cut.
        for k in 0..7 {
            let p = [100.0 + k as f32, 0.0, 0.0];
            soup.push([p, p, [100.0, 1.0, 0.0]]);
        }
        // Repeats of earlier triangles, the same way round and reversed, some twice.
        for f in [3usize, 40, 41, 3, 100, 7, 8] {
            let t = soup[f];
            soup.push(t);
            soup.push([t[0], t[2], t[1]]);
        }
        // Two tetrahedra touching at one point, and −0.0 beside 0.0.
        let tet = |o: [f32; 3], s: f32| {
            let [a, b, c, d] = [o, [o[0] + s, o[1], o[2]], [o[0], o[1] + s, o[2]], [o[0], o[1], o[2] + s]];
            vec![[a, c, b], [a, b, d], [a, d, c], [b, c, d]]
        };
        soup.extend(tet([-0.0, 50.0, 0.0], 1.0));
        soup.extend(tet([0.0, 50.0, 0.0], -1.0));
        let r = assert_same(&soup);
        assert_eq!(r.duplicate_faces, 14);
        assert_eq!(r.dropped_faces, 21);
        assert_eq!(r.kept_apart, 1);
        assert!(r.warnings.iter().any(|w| w.contains("facing the other way")), "{:?}", r.warnings);
        assert!(r.warnings.iter().any(|w| w.contains("and 2 more like the above")), "{:?}", r.warnings);
    }

    #[test]
    fn random_soups_weld_as_the_general_weld_does() {
        // Corners drawn from a few positions: every kind of weld, repeat, fin and touching fan.
        let mut random = Random(0x9E37_79B9_7F4A_7C15);
        for size in [1usize, 2, 5, 30, 300, 3000] {
            for positions in [4u64, 9, 40] {
                let soup: Vec<[[f32; 3]; 3]> = (0..size)
                    .map(|_| {
                        [0; 3].map(|_| {
                            let v = random.below(positions) as f32;
                            [v % 3.0, (v / 3.0).floor(), if random.below(8) == 0 { -0.0 } else { 0.0 }]
                        })
                    })
                    .collect();
                match (weld_triangle_soup(&soup), general(&soup)) {
                    (Ok(_), Ok(_)) => {
                        assert_same(&soup);
                    }
                    (Err(e), Err(g)) => assert_eq!(e.to_string(), g.to_string()),
                    (a, b) => panic!("{size} triangles: {:?} against {:?}", a.err(), b.err()),
                }
            }
        }
    }

    #[test]
    fn the_same_weld_on_any_number_of_threads() {
        let mut soup = torus_soup(60);
        soup.extend(torus_soup(7));
        let one = rayon::ThreadPoolBuilder::new().num_threads(1).build().unwrap();
        let three = rayon::ThreadPoolBuilder::new().num_threads(3).build().unwrap();
        let a = one.install(|| weld_triangle_soup(&soup).unwrap());
        let b = three.install(|| weld_triangle_soup(&soup).unwrap());
        assert_eq!(a.1, b.1);
        assert_eq!(a.2, b.2);
        assert_eq!(a.0, b.0);
    }
}
