//! `taut lcg`: plot a curve's curvature against arc length and its logarithmic curvature graph
//! with the fitted line and α, into a PNG (see `taut_core::aesthetic::lcg`).
//!
//! The plots are drawn with `plotters` on its bitmap backend, text in the Ubuntu Light face that
//! egui ships (`epaint_default_fonts`), and saved with `image`. Planar curves show their signed
//! curvature (counter-clockwise positive, seen from the plane normal); space curves |κ|.

use clap::Args;
use plotters::prelude::*;
use plotters::style::FontStyle;
use std::path::PathBuf;
use taut_core::aesthetic::curvature_graph;
use taut_core::curve::{Plane, PointSequence};
use taut_core::io::points;

#[derive(Debug, Args)]
pub struct LcgArgs {
    /// The curve: .json ({"points": [[x, y], ...]}) or .csv (x,y or x,y,z rows).
    pub input: PathBuf,
    /// Where to write the plots (.png).
    #[arg(short, long)]
    pub output: PathBuf,
    /// Picture size WIDTHxHEIGHT.
    #[arg(long, default_value = "1200x500")]
    pub size: String,
    /// Treat the points as a closed curve.
    #[arg(long)]
    pub closed: bool,
    /// Write the output even when it is the input file.
    #[arg(long)]
    pub force: bool,
}

const FONT: &str = "sans-serif";

fn parse_size(text: &str) -> Result<(u32, u32), String> {
    let (w, h) = text.split_once('x').ok_or_else(|| format!("--size {text}: expected WIDTHxHEIGHT, e.g. 1200x500"))?;
    let (w, h) = (w.trim().parse::<u32>(), h.trim().parse::<u32>());
    match (w, h) {
        (Ok(w), Ok(h)) if (300..=8192).contains(&w) && (200..=8192).contains(&h) => Ok((w, h)),
        _ => Err(format!("--size {text}: width 300–8192 and height 200–8192 pixels")),
    }
}

/// A range around the values, padded by 5 % (and widened if they are all equal).
fn span(values: impl Iterator<Item = f64>) -> (f64, f64) {
    let (lo, hi) = values.fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| (lo.min(v), hi.max(v)));
    if !lo.is_finite() {
        return (-1.0, 1.0);
    }
    let pad = ((hi - lo) * 0.05).max(1e-9 * lo.abs().max(1.0));
    (lo - pad, hi + pad)
}

pub fn run(args: &LcgArgs) -> Result<(), String> {
    crate::cli::check_output(args.force, &[&args.input], &args.output)?;
    let input = args.input.display();
    if crate::surface_cmd::extension(&args.output) != "png" {
        return Err(format!("{}: the plots are written as PNG; use a .png file name", args.output.display()));
    }
    let (width, height) = parse_size(&args.size)?;
    let file = points::read_points(&args.input).map_err(|e| e.to_string())?;
    let curve = PointSequence::new(file.points, file.closed || args.closed);
    curve.validate(3).map_err(|e| format!("{input}: {e}"))?;
    let tolerance = 1e-9 * curve.diagonal();
    let planar = Plane::fit(&curve.points).filter(|p| curve.points.iter().all(|q| p.distance(*q).abs() <= tolerance));
    let graph = curvature_graph(&curve, planar.map(|p| p.normal));
    let curvature: Vec<(f64, f64)> =
        graph.arc_length.iter().zip(&graph.curvature).filter_map(|(s, k)| k.map(|k| (*s, k))).collect();
    let lcg: Vec<(f64, f64)> = graph.lcg.iter().map(|p| (p.x, p.y)).collect();

    plotters::style::register_font(FONT, FontStyle::Normal, epaint_default_fonts::UBUNTU_LIGHT)
        .map_err(|_| "the bundled font could not be loaded".to_string())?;
    let mut pixels = vec![255u8; width as usize * height as usize * 3];
    draw(&mut pixels, (width, height), &curvature, &lcg, &graph, planar.is_some())
        .map_err(|e| format!("cannot draw the plots: {e}"))?;
    let image = image::RgbImage::from_raw(width, height, pixels).ok_or("the picture buffer has the wrong size")?;
    let mut bytes = Vec::new();
    image
        .write_to(&mut std::io::Cursor::new(&mut bytes), image::ImageFormat::Png)
        .map_err(|e| format!("cannot encode the PNG: {e}"))?;
    taut_core::io::write_atomic(&args.output, &bytes).map_err(|e| e.to_string())?;
    match graph.fit {
        Some(fit) => println!(
            "LCG: {} points, fitted line slope α = {:.4}, intercept {:.4}, residual {:.3e}; wrote {}",
            fit.count,
            fit.slope,
            fit.intercept,
            fit.residual,
            args.output.display()
        ),
        None => {
            println!("LCG: too few points with a changing curvature to fit a line; wrote {}", args.output.display())
        }
    }
    Ok(())
}

fn draw(
    pixels: &mut [u8],
    size: (u32, u32),
    curvature: &[(f64, f64)],
    lcg: &[(f64, f64)],
    graph: &taut_core::aesthetic::CurvatureGraph,
    planar: bool,
) -> Result<(), Box<dyn std::error::Error>> {
    let root = BitMapBackend::with_buffer(pixels, size).into_drawing_area();
    root.fill(&WHITE)?;
    let (left, right) = root.split_horizontally(size.0 / 2);
    let font = |px: u32| (FONT, px).into_font();

    let (s0, s1) = span(curvature.iter().map(|p| p.0));
    let (k0, k1) = span(curvature.iter().map(|p| p.1).chain([0.0]));
    let mut chart = ChartBuilder::on(&left)
        .caption(
            if planar { "curvature κ (signed) against arc length s" } else { "curvature |κ| against arc length s" },
            font(20),
        )
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(70)
        .build_cartesian_2d(s0..s1, k0..k1)?;
    chart.configure_mesh().x_desc("s").y_desc("κ").label_style(font(14)).axis_desc_style(font(16)).draw()?;
    chart.draw_series(LineSeries::new(curvature.iter().copied(), BLUE.stroke_width(2)))?;
    chart.draw_series(curvature.iter().map(|p| Circle::new(*p, 2, BLUE.filled())))?;

    let (x0, x1) = span(lcg.iter().map(|p| p.0));
    let (y0, y1) = span(lcg.iter().map(|p| p.1));
    let title = match graph.fit {
        Some(fit) => format!("LCG: fitted slope α = {:.3}, residual {:.2e}", fit.slope, fit.residual),
        None => "LCG (no line: too few points)".to_string(),
    };
    let mut chart = ChartBuilder::on(&right)
        .caption(title, font(20))
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(70)
        .build_cartesian_2d(x0..x1, y0..y1)?;
    chart
        .configure_mesh()
        .x_desc("log ρ")
        .y_desc("log(ρ ds/dρ)")
        .label_style(font(14))
        .axis_desc_style(font(16))
        .draw()?;
    chart.draw_series(lcg.iter().map(|p| Circle::new(*p, 3, RED.filled())))?;
    if let Some(fit) = graph.fit {
        chart.draw_series(LineSeries::new([(x0, fit.at(x0)), (x1, fit.at(x1))], BLACK.stroke_width(2)))?;
    }
    root.present()?;
    Ok(())
}
