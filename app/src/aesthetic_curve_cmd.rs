//! `taut aesthetic-curve`: a log-aesthetic segment from three control points and α (Yoshida and
//! Saito; see `taut_core::aesthetic::segment`), written as a point file.
//!
//! The control points are the start, the intersection of the end tangents and the end, each as
//! `X,Y` or `X,Y,Z`. The output JSON has the points evenly spaced in arc length, their curvature,
//! and the segment's length, turning and shape parameter.

use clap::Args;
use serde::Serialize;
use std::path::PathBuf;
use taut_core::aesthetic::AestheticSegment;
use taut_core::{DVec3, io};

#[derive(Debug, Args)]
pub struct AestheticCurveArgs {
    /// Start point, X,Y or X,Y,Z.
    #[arg(long, allow_hyphen_values = true)]
    pub p0: String,
    /// Where the start and end tangents meet, X,Y or X,Y,Z.
    #[arg(long, allow_hyphen_values = true)]
    pub p1: String,
    /// End point, X,Y or X,Y,Z.
    #[arg(long, allow_hyphen_values = true)]
    pub p2: String,
    /// Slope α of the curvature graph (−1 clothoid, 0, 1 logarithmic spiral, 2 involute).
    #[arg(long, allow_negative_numbers = true)]
    pub alpha: f64,
    /// Where to write the points (.json).
    #[arg(short, long)]
    pub output: PathBuf,
    /// Points on the segment, evenly spaced in arc length, both ends included.
    #[arg(long, default_value_t = 101)]
    pub samples: usize,
}

#[derive(Debug, Serialize)]
struct SegmentFile {
    points: Vec<Vec<f64>>,
    curvature: Vec<f64>,
    alpha: f64,
    length: f64,
    turning_degrees: f64,
    log_radius_ratio: f64,
    lambda: f64,
}

/// Parses `X,Y` or `X,Y,Z`; returns the point and its dimension.
pub fn parse_point(text: &str, flag: &str) -> Result<(DVec3, usize), String> {
    let values: Result<Vec<f64>, _> = text.split(',').map(|v| v.trim().parse::<f64>()).collect();
    match values {
        Ok(v) if v.len() == 2 || v.len() == 3 => {
            let p = DVec3::new(v[0], v[1], v.get(2).copied().unwrap_or(0.0));
            if p.is_finite() { Ok((p, v.len())) } else { Err(format!("{flag} {text}: the coordinates must be finite")) }
        }
        _ => Err(format!("{flag} {text}: expected X,Y or X,Y,Z, for example 0,0 or 1.5,0,2")),
    }
}

pub fn run(args: &AestheticCurveArgs) -> Result<(), String> {
    if crate::surface_cmd::extension(&args.output) != "json" {
        return Err(format!("{}: the segment is written as JSON; use a .json file name", args.output.display()));
    }
    crate::cli::check_output(false, &[], &args.output)?;
    if !(2..=1_000_000).contains(&args.samples) {
        return Err(format!("--samples {}: use between 2 and 1000000 points", args.samples));
    }
    let (p0, d0) = parse_point(&args.p0, "--p0")?;
    let (p1, d1) = parse_point(&args.p1, "--p1")?;
    let (p2, d2) = parse_point(&args.p2, "--p2")?;
    let dimension = d0.max(d1).max(d2);
    let segment = AestheticSegment::from_control_points(p0, p1, p2, args.alpha).map_err(|e| e.to_string())?;
    let Some(segment) = segment else {
        let turning = (p1 - p0).angle_between(p2 - p1);
        let start_angle = (p2 - p0).angle_between(p1 - p0);
        let (lo, hi) = AestheticSegment::feasible_start_angles(args.alpha, turning);
        return Err(format!(
            "no log-aesthetic segment with α = {} has these control points: for a turn of {:.1}° the angle at P0 \
             between the tangent P0→P1 and the chord P0→P2 must lie between {:.1}° and {:.1}°, and it is {:.1}°; \
             move P1, or choose α between 0 and 1 (every triangle has a segment then)",
            args.alpha,
            turning.to_degrees(),
            lo.to_degrees(),
            hi.to_degrees(),
            start_angle.to_degrees()
        ));
    };
    let points = segment.sample(args.samples);
    let length = segment.length();
    let curvature: Vec<f64> =
        (0..args.samples).map(|k| segment.curvature_at(length * k as f64 / (args.samples - 1) as f64)).collect();
    if !(length.is_finite() && curvature.iter().all(|k| k.is_finite()) && points.iter().all(|p| p.is_finite())) {
        return Err("the segment's points or curvature are not finite numbers; move the middle control point \
                    further off the line P0–P2"
            .into());
    }
    let out = SegmentFile {
        points: io::points::to_json_arrays(&points, dimension),
        curvature,
        alpha: segment.alpha(),
        length,
        turning_degrees: segment.turning().to_degrees(),
        log_radius_ratio: segment.log_radius_ratio(),
        lambda: segment.lambda(),
    };
    let mut bytes = serde_json::to_vec(&out).map_err(|e| format!("cannot encode the segment: {e}"))?;
    bytes.push(b'\n');
    io::write_atomic(&args.output, &bytes).map_err(|e| e.to_string())?;
    println!(
        "log-aesthetic segment α = {}: length {:.6}, turning {:.2}°, end radius / start radius {:.4}; wrote {} points to {}",
        segment.alpha(),
        length,
        segment.turning().to_degrees(),
        segment.log_radius_ratio().exp(),
        args.samples,
        args.output.display()
    );
    Ok(())
}
