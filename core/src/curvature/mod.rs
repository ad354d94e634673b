//! Curvature of meshes and polylines, for the curvature colouring and the curvature combs
//! (`docs/rendering.md`, "Curvature colouring").
//!
//! [`vertex_curvature`] estimates a curvature tensor per vertex after Rusinkiewicz, "Estimating
//! curvatures and their derivatives on triangle meshes" (3DPVT 2004): every face gets the shape
//! operator that best maps its vertices' position differences to their normal differences (least
//! squares, eq. 3), each vertex rotates the tensors of its faces into its tangent plane and
//! averages them weighted by its Voronoi share of each face (mixed areas, Meyer et al. 2002), and
//! the averaged 2×2 tensor is diagonalised in closed form. Polygons are fitted directly, on all
//! pairs of their corners, not fan-triangulated: a fan would make a quad's estimate depend on
//! which corner it starts from. The method differentiates normals, so it is only as good as they
//! are: by default they come from a quadric fitted around each vertex (second-order accurate, see
//! [`VertexNormals`]); the mesh's area-weighted normals are available but leave an error that does
//! not shrink with refinement on irregular meshes (about 6 % of `1/r` on an icosphere, 25 % next
//! to the poles of a UV sphere).
//!
//! Sign convention: curvature is positive where the surface bends away from its normal, so a
//! sphere with outward normals (faces counter-clockwise seen from outside) has `H = κ = +1/r`;
//! `H = (κ_min + κ_max) / 2` is the average, not the sum, and `K = κ_min·κ_max`.
//!
//! Where it is weak: the error is first-order in the edge length on irregular meshes (second on
//! regular ones), so coarse cages get rough values; boundary vertices see faces on one side only,
//! so their estimate is one-sided and markedly less accurate (it is still made, from the faces
//! they have); strongly warped polygons are projected onto their average plane; creases are
//! smoothed over. Faces of zero area are skipped; a vertex left with no usable face gets zeros and
//! `estimated[v] == false`, never NaN.
//!
//! [`polyline_curvature`] (from [`crate::curve::menger`]) gives the discrete curvature of a
//! polyline from the circle through each point and its two neighbours.

mod normals;
mod tensor;

pub use crate::curve::menger::{PolylineCurvature, polyline_curvature};
pub use normals::VertexNormals;

use crate::mesh::{FaceId, PolyMesh, VertexId};
use crate::{DVec3, Error, Result};
use rayon::prelude::*;
use std::fmt;
use std::str::FromStr;
use tensor::{FaceFit, Frame, Tensor2};

/// Fewest faces or vertices one parallel task takes (below that, threads cost more than they save).
const MIN_PARALLEL_LEN: usize = 1024;

/// Per-vertex curvature of a mesh, indexed by vertex like [`PolyMesh::positions`].
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Curvature {
    /// Mean curvature `H = (κ_min + κ_max) / 2`; `+1/r` on a sphere with outward normals.
    pub mean: Vec<f64>,
    /// Gaussian curvature `K = κ_min·κ_max`.
    pub gaussian: Vec<f64>,
    /// Smaller principal curvature `κ_min`.
    pub min_principal: Vec<f64>,
    /// Larger principal curvature `κ_max ≥ κ_min`.
    pub max_principal: Vec<f64>,
    /// `max(|κ_min|, |κ_max|)`.
    pub max_absolute: Vec<f64>,
    /// Unit tangent along which the surface bends by `κ_min` (zero where not estimated).
    pub min_direction: Vec<DVec3>,
    /// Unit tangent along which the surface bends by `κ_max` (zero where not estimated).
    pub max_direction: Vec<DVec3>,
    /// The unit normal the estimate was made against ([`CurvatureSettings::normals`]; zero for
    /// isolated vertices).
    pub normal: Vec<DVec3>,
    /// The area the vertex's estimate averages over: its Voronoi share of its usable faces.
    /// Over the whole mesh they add up to the surface area, so `Σ area·K` approximates the total
    /// curvature `∫K dA`.
    pub area: Vec<f64>,
    /// False where the vertex had no usable face (isolated, or all its faces degenerate); its
    /// values are then all zero.
    pub estimated: Vec<bool>,
}

impl Curvature {
    /// Number of vertices.
    pub fn len(&self) -> usize {
        self.mean.len()
    }

    /// True for a mesh without vertices.
    pub fn is_empty(&self) -> bool {
        self.mean.is_empty()
    }

    /// The vertices that got no estimate (their values are zero).
    pub fn unestimated(&self) -> impl Iterator<Item = VertexId> + '_ {
        self.estimated.iter().enumerate().filter(|(_, ok)| !**ok).map(|(v, _)| VertexId(v as u32))
    }

    /// One value per vertex of quantity `q`.
    pub fn values(&self, q: CurvatureQuantity) -> Vec<f64> {
        match q {
            CurvatureQuantity::Mean => self.mean.clone(),
            CurvatureQuantity::Gaussian => self.gaussian.clone(),
            CurvatureQuantity::MinPrincipal => self.min_principal.clone(),
            CurvatureQuantity::MaxPrincipal => self.max_principal.clone(),
            CurvatureQuantity::MaxAbsolute => self.max_absolute.clone(),
        }
    }
}

/// How [`vertex_curvature_with`] estimates.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct CurvatureSettings {
    /// The vertex normals whose differences the tensor is fitted to.
    pub normals: VertexNormals,
}

/// Estimates the curvature tensor at every vertex with the default settings (fitted normals);
/// see the module documentation.
pub fn vertex_curvature(mesh: &PolyMesh) -> Curvature {
    vertex_curvature_with(mesh, &CurvatureSettings::default())
}

/// Estimates the curvature tensor at every vertex (see the module documentation).
///
/// Runs in parallel; the result is the same bit for bit for any number of threads, since every
/// face and every vertex is computed on its own and each vertex sums its faces in a fixed order.
pub fn vertex_curvature_with(mesh: &PolyMesh, settings: &CurvatureSettings) -> Curvature {
    let positions = mesh.positions();
    let normals = normals::vertex_normals(mesh, settings.normals);
    let fits: Vec<Option<FaceFit>> = (0..mesh.face_count())
        .into_par_iter()
        .with_min_len(MIN_PARALLEL_LEN)
        .map_init(
            || (Vec::new(), Vec::new()),
            |(points, face_normals), f| {
                points.clear();
                face_normals.clear();
                for v in mesh.face_vertices(FaceId(f as u32)) {
                    points.push(positions[v.index()]);
                    face_normals.push(normals[v.index()]);
                }
                tensor::fit_face(points, face_normals)
            },
        )
        .collect();
    let estimates: Vec<Option<VertexEstimate>> = (0..mesh.vertex_count())
        .into_par_iter()
        .with_min_len(MIN_PARALLEL_LEN)
        .map(|v| estimate_vertex(mesh, &normals, &fits, VertexId(v as u32)))
        .collect();

    let n = mesh.vertex_count();
    let mut out = Curvature {
        mean: Vec::with_capacity(n),
        gaussian: Vec::with_capacity(n),
        min_principal: Vec::with_capacity(n),
        max_principal: Vec::with_capacity(n),
        max_absolute: Vec::with_capacity(n),
        min_direction: Vec::with_capacity(n),
        max_direction: Vec::with_capacity(n),
        normal: normals,
        area: Vec::with_capacity(n),
        estimated: Vec::with_capacity(n),
    };
    for e in estimates {
        let e = e.unwrap_or_default();
        out.mean.push(0.5 * (e.k_min + e.k_max));
        out.gaussian.push(e.k_min * e.k_max);
        out.min_principal.push(e.k_min);
        out.max_principal.push(e.k_max);
        out.max_absolute.push(e.k_min.abs().max(e.k_max.abs()));
        out.min_direction.push(e.min_direction);
        out.max_direction.push(e.max_direction);
        out.area.push(e.area);
        out.estimated.push(e.area > 0.0);
    }
    out
}

#[derive(Clone, Copy, Debug, Default)]
struct VertexEstimate {
    k_min: f64,
    k_max: f64,
    min_direction: DVec3,
    max_direction: DVec3,
    area: f64,
}

/// The area-weighted average of the tensors of `v`'s faces, diagonalised; `None` when no face
/// of `v` is usable.
fn estimate_vertex(
    mesh: &PolyMesh,
    normals: &[DVec3],
    fits: &[Option<FaceFit>],
    v: VertexId,
) -> Option<VertexEstimate> {
    let first = mesh.vertex_halfedge(v);
    let normal = normals[v.index()];
    if !first.is_valid() || normal == DVec3::ZERO {
        return None;
    }
    let positions = mesh.positions();
    let p = positions[v.index()];
    let frame = Frame::new(normal, positions[mesh.to_vertex(first).index()] - p);
    let (mut sum, mut area) = (Tensor2::default(), 0.0);
    for h in mesh.outgoing(v) {
        let f = mesh.face(h);
        let Some(fit) = f.is_valid().then(|| fits[f.index()].as_ref()).flatten() else { continue };
        let prev = positions[mesh.from_vertex(mesh.prev(h)).index()];
        let next = positions[mesh.to_vertex(h).index()];
        let weight = tensor::corner_area(fit, prev, p, next);
        let Some(t) = tensor::tensor_in_frame(fit, &frame) else { continue };
        if weight > 0.0 {
            sum.a += weight * t.a;
            sum.b += weight * t.b;
            sum.c += weight * t.c;
            area += weight;
        }
    }
    if area <= 0.0 {
        return None; // `area` only sums positive weights, so it is never NaN
    }
    let (k_min, k_max, theta) = tensor::principal(Tensor2 { a: sum.a / area, b: sum.b / area, c: sum.c / area });
    let max_direction = theta.cos() * frame.u + theta.sin() * frame.v;
    Some(VertexEstimate { k_min, k_max, min_direction: normal.cross(max_direction), max_direction, area })
}

/// The per-vertex quantities the curvature view can show.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum CurvatureQuantity {
    /// Mean curvature `H` (signed).
    Mean,
    /// Gaussian curvature `K` (signed).
    Gaussian,
    /// Smaller principal curvature `κ_min` (signed).
    MinPrincipal,
    /// Larger principal curvature `κ_max` (signed).
    MaxPrincipal,
    /// `max(|κ_min|, |κ_max|)` (a magnitude).
    MaxAbsolute,
}

impl CurvatureQuantity {
    /// Every quantity, in menu order.
    pub const ALL: [Self; 5] = [Self::Mean, Self::Gaussian, Self::MinPrincipal, Self::MaxPrincipal, Self::MaxAbsolute];

    /// True for quantities with a sign (shown with a diverging map centred at 0).
    pub fn is_signed(self) -> bool {
        !matches!(self, Self::MaxAbsolute)
    }

    /// The name for menus and legends.
    pub fn display_name(self) -> &'static str {
        match self {
            Self::Mean => "mean curvature H",
            Self::Gaussian => "Gaussian curvature K",
            Self::MinPrincipal => "min principal curvature κmin",
            Self::MaxPrincipal => "max principal curvature κmax",
            Self::MaxAbsolute => "max |κ|",
        }
    }

    /// The command-line name, as [`FromStr`] reads it.
    pub fn cli_name(self) -> &'static str {
        match self {
            Self::Mean => "mean",
            Self::Gaussian => "gaussian",
            Self::MinPrincipal => "kmin",
            Self::MaxPrincipal => "kmax",
            Self::MaxAbsolute => "kabs",
        }
    }
}

impl fmt::Display for CurvatureQuantity {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.display_name())
    }
}

impl FromStr for CurvatureQuantity {
    type Err = Error;

    /// Reads a command-line name: `mean`, `gaussian`, `kmin`, `kmax` or `kabs`.
    fn from_str(s: &str) -> Result<Self> {
        Self::ALL.into_iter().find(|q| q.cli_name() == s).ok_or_else(|| {
            let names: Vec<&str> = Self::ALL.iter().map(|q| q.cli_name()).collect();
            Error::Input(format!("unknown curvature quantity `{s}`: expected one of {}", names.join(", ")))
        })
    }
}

/// Percentile (in %) below which values are left out of the automatic range.
pub const RANGE_LOW_PERCENTILE: f64 = 2.0;
/// Percentile (in %) above which values are left out of the automatic range.
pub const RANGE_HIGH_PERCENTILE: f64 = 98.0;
/// Half-width of the range returned when the values give none (all equal, or none finite).
/// Relative to the values' magnitude when they have one, absolute when they are all zero.
pub const MIN_RANGE_HALF_WIDTH: f64 = 1e-9;

/// A colour-map range that ignores outliers: from the [`RANGE_LOW_PERCENTILE`]th to the
/// [`RANGE_HIGH_PERCENTILE`]th percentile (linear interpolation between sorted values) of the
/// finite values. For signed quantities the range is symmetric about 0, `±max(|p2|, |p98|)`, so
/// white stays at zero. Never of zero width: when the percentiles coincide the range is
/// widened to `c ± MIN_RANGE_HALF_WIDTH·max(|c|, 1)` around their value `c` (around 0 for
/// signed quantities). NaN and infinite values are ignored; with none left the result is
/// `(-MIN_RANGE_HALF_WIDTH, MIN_RANGE_HALF_WIDTH)`.
pub fn robust_range(values: &[f64], signed: bool) -> (f64, f64) {
    let mut finite: Vec<f64> = values.iter().copied().filter(|v| v.is_finite()).collect();
    if finite.is_empty() {
        return (-MIN_RANGE_HALF_WIDTH, MIN_RANGE_HALF_WIDTH);
    }
    let low = percentile(&mut finite, RANGE_LOW_PERCENTILE);
    let high = percentile(&mut finite, RANGE_HIGH_PERCENTILE);
    let (low, high) = if signed {
        let m = low.abs().max(high.abs());
        (-m, m)
    } else {
        (low, high)
    };
    let centre = 0.5 * (low + high);
    let half = MIN_RANGE_HALF_WIDTH * centre.abs().max(1.0);
    if high - low >= 2.0 * half { (low, high) } else { (centre - half, centre + half) }
}

/// The `p`th percentile of non-empty `values` (reordered), interpolating linearly between the
/// order statistics at rank `(n − 1)·p/100`.
fn percentile(values: &mut [f64], p: f64) -> f64 {
    let rank = (values.len() - 1) as f64 * p / 100.0;
    let k = rank.floor() as usize;
    let (_, &mut below, above) = values.select_nth_unstable_by(k, f64::total_cmp);
    match above.iter().copied().min_by(f64::total_cmp) {
        Some(next) => below + (rank - k as f64) * (next - below),
        None => below,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn percentiles_interpolate_between_sorted_values() {
        let mut v: Vec<f64> = (0..=100).rev().map(f64::from).collect();
        assert_eq!(percentile(&mut v, 2.0), 2.0);
        assert_eq!(percentile(&mut v, 98.0), 98.0);
        let mut v = vec![3.0, 1.0];
        assert_eq!(percentile(&mut v, 25.0), 1.5);
        let mut v = vec![7.0];
        assert_eq!(percentile(&mut v, 98.0), 7.0);
    }

    #[test]
    fn quantity_names_round_trip() {
        for q in CurvatureQuantity::ALL {
            assert_eq!(q.cli_name().parse::<CurvatureQuantity>().unwrap(), q);
        }
        let err = "curv".parse::<CurvatureQuantity>().unwrap_err().to_string();
        assert!(err.contains("curv") && err.contains("kmin"), "{err}");
    }

    #[test]
    fn vertices_share_out_each_face_by_its_corner_areas() {
        // The Voronoi weighting makes the area-weighted sum of the vertex tensors equal to the
        // area-weighted sum of the face tensors: Σ_v A_v·H_v = Σ_f A_f·H_f (the trace survives
        // the rotation into each vertex's frame). Uniform weights would break this.
        let n = 9;
        let mut p = Vec::new();
        for j in 0..=n {
            for i in 0..=n {
                let wobble = 0.3 * ((i * 7 + j * 3) % 5) as f64 / 5.0;
                let (x, y) = (i as f64 + wobble, j as f64 - wobble);
                p.push(DVec3::new(x, y, 0.5 * (0.4 * x).sin() * (0.3 * y).cos() + 0.02 * x * y));
            }
        }
        let mut faces = Vec::new();
        for j in 0..n {
            for i in 0..n {
                let v = j * (n + 1) + i;
                if (i + j) % 3 == 0 {
                    faces.push(vec![v, v + 1, v + n + 2]);
                    faces.push(vec![v, v + n + 2, v + n + 1]);
                } else {
                    faces.push(vec![v, v + 1, v + n + 1]);
                    faces.push(vec![v + 1, v + n + 2, v + n + 1]);
                }
            }
        }
        let mesh = PolyMesh::from_polygons(p, &faces).unwrap();
        let c = vertex_curvature(&mesh);
        let normals = normals::vertex_normals(&mesh, VertexNormals::default());
        let mut face_total = 0.0;
        for f in mesh.faces() {
            let corners: Vec<VertexId> = mesh.face_vertices(f).collect();
            let points: Vec<DVec3> = corners.iter().map(|v| mesh.position(*v)).collect();
            let face_normals: Vec<DVec3> = corners.iter().map(|v| normals[v.index()]).collect();
            let fit = tensor::fit_face(&points, &face_normals).unwrap();
            face_total += mesh.face_area_vector(f).length() * 0.5 * (fit.tensor.a + fit.tensor.c);
        }
        let vertex_total: f64 = c.area.iter().zip(&c.mean).map(|(a, h)| a * h).sum();
        assert!((vertex_total - face_total).abs() < 1e-12 * face_total.abs(), "{vertex_total} vs {face_total}");
        let surface: f64 = mesh.faces().map(|f| mesh.face_area_vector(f).length()).sum();
        assert!((c.area.iter().sum::<f64>() - surface).abs() < 1e-12 * surface);
    }
}
