//! Rounds 2 and later: a two-sided, distance-weighted least-squares fit of the limit surface to
//! the original (beyond the paper, which stops at its one solve).
//!
//! The paper's solve puts the cage's own limit points on the original. Between them the limit
//! surface may still stand off the original, and a thin or sharp part of the original (an ear,
//! a rim) may have no limit point near it at all: the surface then misses it, which is what
//! decides the Hausdorff distance. Each round here:
//! 1. samples the limit surface as the limit points of the cage refined [`LEVELS`] times, each a
//!    fixed linear combination of the cage's vertices (the rows of [`Sampling`]);
//! 2. pulls every sample to its closest point on the original (the forward side), and pulls the
//!    closest point of the sampled surface to every sampled point of the original to that point
//!    (the backward side: a barycentric combination of three samples, so again linear in the
//!    cage);
//! 3. weighs each pull by `1 + (d / d̄)²`, `d` its present distance and `d̄` the mean of its side,
//!    so the farthest points count most (one step of iteratively reweighted least squares toward
//!    the largest distance, which the Hausdorff distance measures), each side normalised by its
//!    count so both sides count alike;
//! 4. solves the weighted least squares for the cage by conjugate gradients on the normal
//!    equations (CGLS), started from the present cage.
//!
//! Fitting closest points both ways is the surface fitting of Hoppe et al. (1994) and Marinov
//! and Kobbelt (2005), here with Loop's limit surface; the weighting is ours.
//!
//! Weak spots: closest points let samples slide along the original, so a round moves the cage
//! tangentially only slowly; a sharp edge of the original is rounded (Loop has no creases here).

use super::Monitor;
use super::evaluate::Original;
use super::solve::least_squares;
use super::surface_index::SurfaceIndex;
use crate::mesh::PolyMesh;
use crate::subdiv::{Refinement, Scheme, SparseRows, loop_limit_matrix};
use crate::{DVec3, Result};

/// Refinement levels at which the rounds sample the limit surface: 16 samples a cage triangle.
/// Three levels (64) fitted the real scans of the MeshLab comparison no closer (Hausdorff and
/// mean within 1 % on 11 of 12, 7 % on the twelfth) at three times the cost.
pub const LEVELS: u32 = 2;

/// Most points of the original pulled by the backward side of a round (taken at an even stride
/// from the evaluation's samples): far more than the unknowns of any cage fitted whole, and
/// every vertex of a scan of up to 64 k triangles.
pub const POINTS: usize = 1 << 15;

/// The limit surface of a cage refined `levels` times, as rows over the cage's vertices.
#[derive(Clone, Debug)]
pub struct Sampling {
    /// Row `j`: the limit point of refined vertex `j` as a combination of the cage's vertices.
    pub rows: SparseRows,
    /// The refined triangles joining the samples.
    pub triangles: Vec<[u32; 3]>,
}

impl Sampling {
    /// Samples a triangle cage's limit surface `levels ≥ 1` times refined.
    pub fn new(cage: &PolyMesh, levels: u32) -> Result<Self> {
        let levels = levels.max(1);
        let refinement = Refinement::new(cage, Scheme::Loop, &[], levels)?;
        let mut stencils = refinement.stencils(1).clone();
        for level in 2..=levels {
            stencils = refinement.stencils(level).compose(&stencils);
        }
        let finest = refinement.mesh(levels);
        let rows = loop_limit_matrix(finest)?.compose(&stencils);
        Ok(Sampling { rows, triangles: finest.triangles() })
    }
}

/// What one round measured before it moved the cage: the distances of the sampled limit surface
/// to the original (forward) and of the original's samples to it (backward), in the original's
/// units.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Distances {
    pub forward_max: f64,
    pub forward_mean: f64,
    pub backward_max: f64,
    pub backward_mean: f64,
}

impl Distances {
    /// The sampled symmetric Hausdorff distance.
    pub fn hausdorff(&self) -> f64 {
        self.forward_max.max(self.backward_max)
    }

    /// The mean of the two one-sided means.
    pub fn mean(&self) -> f64 {
        0.5 * (self.forward_mean + self.backward_mean)
    }
}

/// Pulls for the weighted least squares: each a combination of samples and its goal.
struct Pulls {
    /// Forward: sample `j` to its closest point; backward: three samples with barycentric weights.
    rows: Vec<([u32; 3], [f64; 3])>,
    goals: Vec<DVec3>,
    distances: Vec<f64>,
}

/// Measures the cage `x` against the original (`points` its sampled points for the backward
/// side) and, unless `solve` is false, moves it by one weighted least-squares round of at most `iterations` CGLS steps. Returns the distances
/// measured before the move, the CGLS steps taken, and `None` when cancelled.
pub fn round(
    sampling: &Sampling,
    original: &Original<'_>,
    points: &[DVec3],
    x: &mut [DVec3],
    iterations: usize,
    solve: bool,
    monitor: &mut Monitor<'_>,
) -> Result<Option<(Distances, usize)>> {
    let samples = sampling.rows.apply(x);
    let Some(forward) = monitor.map(samples.len(), |j| original.index.closest_point(samples[j])) else {
        return Ok(None);
    };
    let surface = SurfaceIndex::new(&samples, &sampling.triangles)?;
    let Some(backward) = monitor.map(points.len(), |i| surface.closest_on_triangle(points[i])) else {
        return Ok(None);
    };

    let mut pulls = Pulls { rows: Vec::new(), goals: Vec::new(), distances: Vec::new() };
    for (j, goal) in forward.iter().enumerate() {
        pulls.rows.push(([j as u32, 0, 0], [1.0, 0.0, 0.0]));
        pulls.goals.push(*goal);
        pulls.distances.push((*goal - samples[j]).length());
    }
    let split = pulls.rows.len();
    for (i, (point, triangle, weights)) in backward.iter().enumerate() {
        pulls.rows.push((sampling.triangles[*triangle], *weights));
        pulls.goals.push(points[i]);
        pulls.distances.push((*point - points[i]).length());
    }
    let (fd, bd) = pulls.distances.split_at(split);
    let max = |d: &[f64]| d.iter().copied().fold(0.0, f64::max);
    let mean = |d: &[f64]| if d.is_empty() { 0.0 } else { d.iter().sum::<f64>() / d.len() as f64 };
    let distances =
        Distances { forward_max: max(fd), forward_mean: mean(fd), backward_max: max(bd), backward_mean: mean(bd) };
    if !solve {
        return Ok(Some((distances, 0)));
    }

    // Each side's weights sum to about one, growing with the square of the distance.
    let scale: Vec<f64> = pulls
        .distances
        .iter()
        .enumerate()
        .map(|(k, &d)| {
            let (count, side_mean) =
                if k < split { (fd.len(), distances.forward_mean) } else { (bd.len(), distances.backward_mean) };
            let relative = if side_mean > 0.0 { d / side_mean } else { 0.0 };
            ((1.0 + relative * relative) / count as f64).sqrt()
        })
        .collect();
    let system = SparseRows::build_parallel(x.len(), pulls.rows.len(), |k, builder| {
        let (corners, weights) = pulls.rows[k];
        for (&corner, &w) in corners.iter().zip(&weights) {
            if w != 0.0 {
                for (c, v) in sampling.rows.row(corner as usize) {
                    builder.add(c, scale[k] * w * v);
                }
            }
        }
    });
    let goals: Vec<DVec3> = pulls.goals.iter().zip(&scale).map(|(g, s)| *g * *s).collect();
    let mut moved = x.to_vec();
    let steps = least_squares(&system, &goals, &mut moved, 1e-4, iterations);
    if let Some(volume) = original.volume {
        keep_volume(sampling, volume, &mut moved);
    }
    if moved.iter().all(|p| p.is_finite()) {
        x.copy_from_slice(&moved);
    }
    Ok(Some((distances, steps)))
}

/// Moves the cage by the least change that gives its sampled limit surface the original's
/// `volume` (Newton steps on the volume, each along its gradient with respect to the cage).
fn keep_volume(sampling: &Sampling, volume: f64, x: &mut [DVec3]) {
    for _ in 0..VOLUME_STEPS {
        let samples = sampling.rows.apply(x);
        let mut enclosed = 0.0;
        let mut by_sample = vec![DVec3::ZERO; samples.len()];
        for t in &sampling.triangles {
            let [a, b, c] = t.map(|i| samples[i as usize]);
            enclosed += a.dot(b.cross(c)) / 6.0;
            by_sample[t[0] as usize] += b.cross(c) / 6.0;
            by_sample[t[1] as usize] += c.cross(a) / 6.0;
            by_sample[t[2] as usize] += a.cross(b) / 6.0;
        }
        let mut gradient = vec![DVec3::ZERO; x.len()];
        for (j, g) in by_sample.iter().enumerate() {
            for (c, w) in sampling.rows.row(j) {
                gradient[c as usize] += w * *g;
            }
        }
        let norm: f64 = gradient.iter().map(|g| g.length_squared()).sum();
        let gap = volume - enclosed;
        if norm <= 0.0 || !norm.is_finite() || gap.abs() <= VOLUME_TOLERANCE * volume.abs() {
            return;
        }
        let step = gap / norm;
        for (p, g) in x.iter_mut().zip(&gradient) {
            *p += step * *g;
        }
    }
}

/// Newton steps toward the original's volume per round, and the relative gap they stop at.
const VOLUME_STEPS: usize = 8;
const VOLUME_TOLERANCE: f64 = 1e-6;

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cage_fit::input::signed_volume;
    use crate::mesh::primitives::icosphere;

    #[test]
    fn keeping_the_volume_gives_the_sampled_limit_surface_the_asked_volume() {
        // The icosahedron: every vertex alike.
        let cage = icosphere(0, 1.0).unwrap();
        let sampling = Sampling::new(&cage, 2).unwrap();
        let volume = |x: &[DVec3]| signed_volume(&sampling.rows.apply(x), &sampling.triangles);
        let mut x = cage.positions().to_vec();
        // The limit surface of a cage on the unit sphere lies inside it; ask for the ball's volume.
        let ball = 4.0 / 3.0 * std::f64::consts::PI;
        assert!(volume(&x) < 0.9 * ball);
        keep_volume(&sampling, ball, &mut x);
        assert!((volume(&x) - ball).abs() < VOLUME_TOLERANCE * ball, "{} vs {ball}", volume(&x));
        // By symmetry every vertex moves out alike: the cage stays a scaled icosahedron.
        let radii: Vec<f64> = x.iter().map(|p| p.length()).collect();
        let (lo, hi) = radii.iter().fold((f64::MAX, 0.0f64), |(a, b), &r| (a.min(r), b.max(r)));
        assert!(hi - lo < 1e-9 * hi && hi > 1.0, "{lo} … {hi}");
    }

    #[test]
    fn the_sampling_reproduces_the_limit_points_of_the_refined_cage() {
        let cage = icosphere(1, 1.0).unwrap();
        let sampling = Sampling::new(&cage, 2).unwrap();
        let expected = crate::cage_fit::evaluate::limit_mesh(&cage, 2).unwrap();
        let samples = sampling.rows.apply(cage.positions());
        assert_eq!(samples.len(), expected.vertex_count());
        assert_eq!(sampling.triangles, expected.triangles());
        for (a, b) in samples.iter().zip(expected.positions()) {
            assert!((*a - *b).length() < 1e-13, "{a} {b}");
        }
    }
}
