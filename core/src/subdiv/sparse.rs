//! [`SparseRows`]: a sparse matrix in compressed rows, each row a weighted sum of input points.
//!
//! Stencils and limit masks are all of this shape: output point `i` is `Σ_k w_k · p[c_k]` over the
//! entries of row `i`. Applying a matrix computes every row on its own from the input alone, so
//! the result is bit-identical for any number of threads. Matrices are built row by row with a
//! [`RowBuilder`] (which merges repeated columns in a fixed order), in parallel chunks whose
//! results are joined in row order ([`SparseRows::build_parallel`]), so the built matrix does not
//! depend on the thread count either.

use crate::DVec3;
use rayon::prelude::*;

/// Matrices of fewer entries than this are applied on one thread; larger ones in tasks of about
/// this many entries (a few long rows, as a transposed stencil has, are worth several threads
/// as much as many short ones).
const PARALLEL_ENTRIES: usize = 1 << 15;

/// A sparse matrix in compressed rows (CSR).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SparseRows {
    /// Row `i` is `columns[offsets[i]..offsets[i + 1]]` with the same range of `weights`.
    pub offsets: Vec<u32>,
    /// Column (input point) of each entry.
    pub columns: Vec<u32>,
    /// Weight of each entry.
    pub weights: Vec<f64>,
    /// Number of columns (input points).
    pub column_count: usize,
}

impl SparseRows {
    /// An empty matrix over `column_count` input points; add rows with [`push_row`](Self::push_row).
    pub fn with_columns(column_count: usize) -> Self {
        SparseRows { offsets: vec![0], columns: Vec::new(), weights: Vec::new(), column_count }
    }

    /// Appends a row from `(column, weight)` entries (repeated columns are allowed and summed when
    /// applied).
    pub fn push_row(&mut self, entries: impl IntoIterator<Item = (u32, f64)>) {
        for (c, w) in entries {
            debug_assert!((c as usize) < self.column_count, "column {c} out of range");
            self.columns.push(c);
            self.weights.push(w);
        }
        self.offsets.push(self.columns.len() as u32);
    }

    /// Number of rows (output points).
    pub fn row_count(&self) -> usize {
        self.offsets.len().saturating_sub(1)
    }

    /// Number of stored entries.
    pub fn entry_count(&self) -> usize {
        self.columns.len()
    }

    /// Bytes of the stored arrays (what applying the matrix reads besides the input points).
    pub fn memory_bytes(&self) -> usize {
        4 * self.offsets.len() + 12 * self.columns.len()
    }

    /// The `(column, weight)` entries of row `i`.
    pub fn row(&self, i: usize) -> impl Iterator<Item = (u32, f64)> + '_ {
        let range = self.offsets[i] as usize..self.offsets[i + 1] as usize;
        self.columns[range.clone()].iter().copied().zip(self.weights[range].iter().copied())
    }

    /// Row `i` applied to `points`.
    #[inline]
    pub fn apply_row(&self, i: usize, points: &[DVec3]) -> DVec3 {
        let range = self.offsets[i] as usize..self.offsets[i + 1] as usize;
        let mut sum = DVec3::ZERO;
        for (&c, &w) in self.columns[range.clone()].iter().zip(&self.weights[range]) {
            sum += w * points[c as usize];
        }
        sum
    }

    /// Every row applied to `points` (which must have [`column_count`](Self::column_count)
    /// entries), written to `out` (resized to the row count).
    pub fn apply_into(&self, points: &[DVec3], out: &mut Vec<DVec3>) {
        assert_eq!(
            points.len(),
            self.column_count,
            "a matrix over {} points applied to {}",
            self.column_count,
            points.len()
        );
        out.resize(self.row_count(), DVec3::ZERO);
        let entries = self.columns.len();
        if entries < PARALLEL_ENTRIES {
            for (i, o) in out.iter_mut().enumerate() {
                *o = self.apply_row(i, points);
            }
        } else {
            let rows_per_task = (PARALLEL_ENTRIES / 4 * out.len()).div_ceil(entries).max(1);
            out.par_iter_mut()
                .with_min_len(rows_per_task)
                .enumerate()
                .for_each(|(i, o)| *o = self.apply_row(i, points));
        }
    }

    /// Every row applied to `points`.
    pub fn apply(&self, points: &[DVec3]) -> Vec<DVec3> {
        let mut out = Vec::new();
        self.apply_into(points, &mut out);
        out
    }

    /// The sum of each row's weights (1 for every row of an affine stencil).
    pub fn row_sums(&self) -> Vec<f64> {
        (0..self.row_count()).map(|i| self.row(i).map(|(_, w)| w).sum()).collect()
    }

    /// For every column, the rows that use it (the transposed pattern, without weights): what a
    /// change of one input point reaches.
    pub fn users(&self) -> Users {
        // Rows hold each column once (the builder merges repeats) and come in ascending order.
        Users::from_rows(self.column_count, self.row_count(), |i, out| out.extend(self.row(i).map(|(c, _)| c)))
    }

    /// Appends the rows of `other` (over the same columns) after these.
    pub fn append(&mut self, other: &SparseRows) {
        debug_assert_eq!(self.column_count, other.column_count);
        let base = self.columns.len() as u32;
        self.columns.extend_from_slice(&other.columns);
        self.weights.extend_from_slice(&other.weights);
        self.offsets.extend(other.offsets[1..].iter().map(|&o| o + base));
    }

    /// A matrix of `row_count` rows over `column_count` columns whose row `i` is made by
    /// `fill(i, builder)`; rows are made in parallel chunks and joined in order.
    pub fn build_parallel<F>(column_count: usize, row_count: usize, fill: F) -> SparseRows
    where
        F: Fn(usize, &mut RowBuilder) + Sync,
    {
        const CHUNK: usize = 4096;
        let chunks: Vec<SparseRows> = (0..row_count.div_ceil(CHUNK))
            .into_par_iter()
            .map(|c| {
                let mut rows = SparseRows::with_columns(column_count);
                let mut builder = RowBuilder::default();
                for i in c * CHUNK..((c + 1) * CHUNK).min(row_count) {
                    fill(i, &mut builder);
                    builder.push_into(&mut rows);
                }
                rows
            })
            .collect();
        let mut out = SparseRows::with_columns(column_count);
        for chunk in &chunks {
            out.append(chunk);
        }
        out
    }

    /// The transpose: row `c` lists the rows that read column `c`, in ascending order, with
    /// their weights. Applying it in parallel adds each output's terms in the order a scatter
    /// over the rows in order would (`out[c] += w · y[i]` for `i` ascending), so the same bits.
    pub fn transpose(&self) -> SparseRows {
        let mut offsets = vec![0u32; self.column_count + 1];
        for &c in &self.columns {
            offsets[c as usize + 1] += 1;
        }
        for c in 0..self.column_count {
            offsets[c + 1] += offsets[c];
        }
        let mut fill = offsets.clone();
        let mut columns = vec![0u32; self.columns.len()];
        let mut weights = vec![0.0; self.weights.len()];
        for i in 0..self.row_count() {
            for (c, w) in self.row(i) {
                let at = fill[c as usize] as usize;
                columns[at] = i as u32;
                weights[at] = w;
                fill[c as usize] += 1;
            }
        }
        SparseRows { offsets, columns, weights, column_count: self.row_count() }
    }

    /// The product `self · inner`: row `i` maps the columns of `inner` to what row `i` of `self`
    /// gives from the rows of `inner` (so applying the product equals applying `inner`, then
    /// `self`). Used to flatten level-by-level stencils into stencils on the cage.
    pub fn compose(&self, inner: &SparseRows) -> SparseRows {
        assert_eq!(self.column_count, inner.row_count(), "composing matrices of mismatched sizes");
        SparseRows::build_parallel(inner.column_count, self.row_count(), |i, builder| {
            for (k, w) in self.row(i) {
                for (c, v) in inner.row(k as usize) {
                    builder.add(c, w * v);
                }
            }
        })
    }
}

/// For every input point, the output rows that read it ([`SparseRows::users`]).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Users {
    offsets: Vec<u32>,
    rows: Vec<u32>,
}

impl Users {
    /// From the columns each of `row_count` rows reads, over `column_count` columns: a counting
    /// sort, so each column's rows ascend (a column read twice by a row lists it twice, which
    /// only costs a repeated visit).
    /// `columns(i, out)` appends row `i`'s columns to `out`.
    pub fn from_rows(column_count: usize, row_count: usize, columns: impl Fn(usize, &mut Vec<u32>)) -> Self {
        let mut buffer = Vec::new();
        let mut offsets = vec![0u32; column_count + 1];
        for i in 0..row_count {
            buffer.clear();
            columns(i, &mut buffer);
            for &c in &buffer {
                offsets[c as usize + 1] += 1;
            }
        }
        for c in 0..column_count {
            offsets[c + 1] += offsets[c];
        }
        let mut fill = offsets.clone();
        let mut rows = vec![0u32; offsets[column_count] as usize];
        for i in 0..row_count {
            buffer.clear();
            columns(i, &mut buffer);
            for &c in &buffer {
                rows[fill[c as usize] as usize] = i as u32;
                fill[c as usize] += 1;
            }
        }
        Users { offsets, rows }
    }

    /// The rows that read column `c`.
    pub fn of(&self, c: usize) -> &[u32] {
        &self.rows[self.offsets[c] as usize..self.offsets[c + 1] as usize]
    }

    /// Bytes of the stored arrays.
    pub fn memory_bytes(&self) -> usize {
        4 * (self.offsets.len() + self.rows.len())
    }
}

/// The entries of one row being built: repeated columns are merged when the row is pushed.
#[derive(Clone, Debug, Default)]
pub struct RowBuilder {
    entries: Vec<(u32, f64)>,
}

impl RowBuilder {
    /// Adds `weight` to `column`.
    #[inline]
    pub fn add(&mut self, column: u32, weight: f64) {
        self.entries.push((column, weight));
    }

    /// True when nothing was added since the last push.
    pub fn is_empty(&self) -> bool {
        self.entries.is_empty()
    }

    /// Pushes the row to `rows` (columns ascending, repeated ones summed in the order they were
    /// added) and clears the builder.
    pub fn push_into(&mut self, rows: &mut SparseRows) {
        // A stable sort keeps the summation order of a repeated column fixed.
        self.entries.sort_by_key(|&(c, _)| c);
        let mut k = 0;
        while k < self.entries.len() {
            let (c, mut w) = self.entries[k];
            k += 1;
            while k < self.entries.len() && self.entries[k].0 == c {
                w += self.entries[k].1;
                k += 1;
            }
            debug_assert!((c as usize) < rows.column_count, "column {c} out of range");
            rows.columns.push(c);
            rows.weights.push(w);
        }
        rows.offsets.push(rows.columns.len() as u32);
        self.entries.clear();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_transpose_gathers_what_a_scatter_over_the_rows_adds_bit_for_bit() {
        // Uneven rows over 50 columns, with weights whose sums depend on the order of addition.
        let mut a = SparseRows::with_columns(50);
        for i in 0..400u32 {
            let entries: Vec<(u32, f64)> =
                (0..1 + i % 7).map(|k| ((i * 13 + k * 29) % 50, 1.0 / (1.0 + f64::from(i * 7 + k)))).collect();
            a.push_row(entries);
        }
        let y: Vec<DVec3> = (0..400).map(|i| DVec3::new((i as f64).sin(), 1e8 + i as f64, 1e-8 * i as f64)).collect();
        let mut scatter = vec![DVec3::ZERO; 50];
        for (i, &yi) in y.iter().enumerate() {
            for (c, w) in a.row(i) {
                scatter[c as usize] += w * yi;
            }
        }
        let t = a.transpose();
        assert_eq!((t.row_count(), t.column_count, t.entry_count()), (50, 400, a.entry_count()));
        assert_eq!(t.apply(&y), scatter);
        // Every entry once, under its column, its rows ascending.
        for c in 0..50 {
            let rows: Vec<(u32, f64)> = t.row(c).collect();
            assert!(rows.windows(2).all(|w| w[0].0 < w[1].0));
            for (i, w) in rows {
                assert!(a.row(i as usize).any(|e| e == (c as u32, w)));
            }
        }
    }

    #[test]
    fn builder_merges_and_compose_equals_applying_twice() {
        let mut a = SparseRows::with_columns(3);
        let mut b = RowBuilder::default();
        b.add(2, 0.25);
        b.add(0, 0.5);
        b.add(2, 0.25);
        b.push_into(&mut a);
        a.push_row([(1, 1.0)]);
        assert_eq!(a.row(0).collect::<Vec<_>>(), vec![(0, 0.5), (2, 0.5)]);
        let outer = SparseRows::build_parallel(2, 3, |i, b| {
            b.add(0, i as f64);
            b.add(1, 1.0 - i as f64);
        });
        let p = [DVec3::X, DVec3::new(0.0, 2.0, 1.0), DVec3::new(-1.0, 0.5, 3.0)];
        let composed = outer.compose(&a);
        assert_eq!(composed.row_count(), 3);
        let twice = outer.apply(&a.apply(&p));
        for (x, y) in composed.apply(&p).iter().zip(&twice) {
            assert!((*x - *y).length() < 1e-15);
        }
    }
}
