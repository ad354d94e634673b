//! A second stopping estimate for the plain iteration where tension makes the first one low:
//! the contraction measured on the displacement over blocks of sweeps.
//!
//! The step monitor ([`crate::nusd::convergence`]) estimates the distance left from the largest
//! step of a sweep and the rate at which it shrinks. With strong tension the iteration has
//! modes that reverse every sweep (negative eigenvalues) and die at their own rate; while they
//! carry the largest step, the measured rate is theirs, and a slow smooth mode holds the error:
//! on the partly unfixed default scene with τ = 8 the plain fallback stopped up to 3 thresholds
//! from its fixed point. Over an even number of sweeps a reversing mode cancels out while a
//! slow mode adds up, so the largest displacement `D` of a moving vertex over a block of
//! [`BLOCK`] sweeps shrinks by the slow mode's rate per block, `Q = D_k / D_{k−1}`, and the
//! distance left is the tail `D_k Q / (1 − Q)`. Levels with tension are stopped only when that
//! estimate is under the threshold too (the larger of the two is reported).

use crate::DVec3;
use crate::nusd::surface::local::Region;
use crate::nusd::surface::operator::{Operator, Role};

/// A block displacement under this share of the threshold is taken as settled.
pub const FLOOR: f64 = 1e-3;
/// The share of the threshold the block estimate must fall under: its measured rate still rises
/// while faster modes die out, so it too ends low.
pub const MARGIN: f64 = 0.5;
/// Sweeps per block (even: a mode that reverses every sweep cancels over a block).
pub const BLOCK: usize = 16;

#[derive(Clone, Debug, Default)]
pub(super) struct BlockMonitor {
    last: Vec<DVec3>,
    displacements: Vec<f64>,
}

impl BlockMonitor {
    pub fn reset(&mut self) {
        self.last.clear();
        self.displacements.clear();
    }

    /// Records the positions at the end of sweep `iteration` (of the region, or the whole level).
    pub fn push(&mut self, iteration: usize, op: &Operator, region: Option<&Region>, p: &[DVec3]) {
        if !iteration.is_multiple_of(BLOCK) {
            return;
        }
        let now: Vec<DVec3> = match region {
            Some(region) => region.vertices.iter().map(|&v| p[v as usize]).collect(),
            None => p.to_vec(),
        };
        if self.last.len() == now.len() {
            let index = |k: usize| region.map_or(k, |r| r.vertices[k] as usize);
            let d = now
                .iter()
                .zip(&self.last)
                .enumerate()
                .filter(|(k, _)| op.role[index(*k)] == Role::Moving)
                .map(|(_, (a, b))| (*a - *b).length())
                .fold(0.0, |a: f64, b| if a.is_nan() || b.is_nan() { f64::NAN } else { a.max(b) });
            self.displacements.push(d);
        }
        self.last = now;
    }

    /// The estimated distance left (infinite until three blocks have been seen): the tail of the
    /// last block's displacement at the larger of the last two block rates. A displacement under
    /// `floor` counts as what is left (at rounding level it no longer contracts).
    pub fn remaining(&self, floor: f64) -> f64 {
        let d = &self.displacements;
        let n = d.len();
        if n == 0 {
            return f64::INFINITY;
        }
        if d[n - 1] <= floor {
            return d[n - 1];
        }
        if n < 3 || d[n - 2] <= 0.0 || d[n - 3] <= 0.0 {
            return f64::INFINITY;
        }
        let q = (d[n - 1] / d[n - 2]).max(d[n - 2] / d[n - 3]);
        if q < 1.0 { d[n - 1] * q / (1.0 - q) } else { f64::INFINITY }
    }
}
