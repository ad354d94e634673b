//! [`SparseRows`]: a sparse matrix in compressed rows, each row a weighted sum of input points.
//!
//! Stencils and limit masks are all of this shape: output point `i` is `Σ_k w_k · p[c_k]` over the
//! entries of row `i`. Applying a matrix computes every row on its own from the input alone, so
//! the result is bit-identical for any number of threads.

use crate::DVec3;
use rayon::prelude::*;

/// Rows below this count are applied on one thread.
const PARALLEL_ROWS: usize = 8192;

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

    /// The `(column, weight)` entries of row `i`.
    pub fn row(&self, i: usize) -> impl Iterator<Item = (u32, f64)> + '_ {
        let range = self.offsets[i] as usize..self.offsets[i + 1] as usize;
        self.columns[range.clone()].iter().copied().zip(self.weights[range].iter().copied())
    }

    /// Row `i` applied to `points`.
    #[inline]
    pub fn apply_row(&self, i: usize, points: &[DVec3]) -> DVec3 {
        let (a, b) = (self.offsets[i] as usize, self.offsets[i + 1] as usize);
        let mut sum = DVec3::ZERO;
        for k in a..b {
            sum += self.weights[k] * points[self.columns[k] as usize];
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
        if out.len() < PARALLEL_ROWS {
            for (i, o) in out.iter_mut().enumerate() {
                *o = self.apply_row(i, points);
            }
        } else {
            out.par_iter_mut().with_min_len(4096).enumerate().for_each(|(i, o)| *o = self.apply_row(i, points));
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
}
