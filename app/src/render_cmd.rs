//! `taut render`: a picture of a surface as the editor's viewport would draw it, off screen.
//!
//! A `.taut` cage is smoothed with its settings (the smoothing flags override them). A mesh file
//! (`.obj`, `.gltf`, `.glb`) is drawn as it is, unless a smoothing flag is given: then it is
//! taken as a cage and smoothed. The picture uses a hardware GPU when there is one, else Mesa's
//! software rasteriser.

use crate::cli::{FileFlags, note};
use crate::smooth_cmd::{SmoothingFlags, apply_flags, extension, load_document, solve_reporting};
use clap::Args;
use std::path::PathBuf;
use std::str::FromStr;
use taut_core::curvature::{CurvatureQuantity, robust_range, vertex_curvature};
use taut_core::{DVec3, Document, PolyMesh, io};
use taut_render::colormap::ColorMap;
use taut_render::overlay::{self, CageSelection, CombStyle, Legend, OverlayData};
use taut_render::passes::overlay2d::legend_margin;
use taut_render::passes::surface::SurfaceMode;
use taut_render::{
    AdapterPreference, Camera, DisplayFrame, Gpu, GpuSurface, Renderer, Scene, SurfaceBuffers, TargetFormats, offscreen,
};

#[derive(Debug, Args)]
pub struct RenderArgs {
    /// A cage (.taut, smoothed first) or a mesh (.obj, .gltf, .glb; drawn as it is unless a
    /// smoothing flag is given).
    pub input: PathBuf,
    /// The picture to write (.png).
    #[arg(short, long)]
    pub output: PathBuf,
    /// shaded, zebra, or a curvature colour: mean, gaussian, kmin, kmax, kabs, r (NUSD |R|).
    #[arg(long, default_value = "shaded")]
    pub view: String,
    /// Picture size in pixels, WIDTHxHEIGHT.
    #[arg(long, default_value = "1280x800")]
    pub size: String,
    /// Camera: azimuth and elevation in degrees, and optionally the distance from the centre of
    /// the surface's bounding box [default: 30,25 at a distance that frames the surface].
    #[arg(long, value_name = "AZIMUTH,ELEVATION[,DISTANCE]", allow_hyphen_values = true)]
    pub camera: Option<String>,
    /// Zebra: black and white stripe pairs across a half turn of reflected directions.
    #[arg(long, default_value_t = 12.0, allow_hyphen_values = true)]
    pub stripes: f32,
    /// Zebra: direction of the stripes on screen, degrees (0: horizontal).
    #[arg(long = "stripe-angle", default_value_t = 0.0, allow_hyphen_values = true)]
    pub stripe_angle: f32,
    /// Zebra: fraction of each stripe pair that is black.
    #[arg(long = "stripe-width", default_value_t = 0.5, allow_hyphen_values = true)]
    pub stripe_width: f32,
    /// Curvature: the values at the two ends of the colour map [default: automatic, the 2nd to
    /// 98th percentile, symmetric about 0 for signed quantities].
    #[arg(long, value_name = "MIN,MAX", allow_hyphen_values = true)]
    pub range: Option<String>,
    /// Overlays, comma separated: cage (cage edges and vertices, tension shown), wire (the
    /// refined wireframe), curves (the surface's curves along the cage edges, with curvature
    /// combs).
    #[arg(long, value_delimiter = ',')]
    pub overlay: Vec<String>,
    /// Curvature views: draw the colour bar with its numbers into the picture.
    #[arg(long)]
    pub legend: bool,
    /// Draw with the software rasteriser even when a GPU is present (reproducible pictures).
    #[arg(long)]
    pub software: bool,
    #[command(flatten)]
    pub smoothing: SmoothingFlags,
    #[command(flatten)]
    pub files: FileFlags,
}

enum View {
    Shaded,
    Zebra,
    Curvature(CurvatureQuantity),
}

pub fn run(args: &RenderArgs) -> Result<(), String> {
    let view = match args.view.as_str() {
        "shaded" => View::Shaded,
        "zebra" => View::Zebra,
        other => View::Curvature(
            CurvatureQuantity::from_str(other)
                .map_err(|_| format!("--view {other}: use shaded, zebra, mean, gaussian, kmin, kmax, kabs or r"))?,
        ),
    };
    let (width, height) = parse_size(&args.size)?;
    if extension(&args.output) != "png" {
        return Err(format!("{}: the picture must be a .png file", args.output.display()));
    }
    let overlays: Vec<&str> = args.overlay.iter().map(|s| s.trim()).filter(|s| !s.is_empty()).collect();
    if let Some(bad) = overlays.iter().find(|o| !["cage", "wire", "curves"].contains(o)) {
        return Err(format!("--overlay {bad}: use cage, wire or curves"));
    }
    if args.legend && !matches!(view, View::Curvature(_)) {
        return Err("--legend goes with a curvature view (mean, gaussian, kmin, kmax, kabs, r)".into());
    }
    if !(args.stripes > 0.0 && args.stripes.is_finite()) {
        return Err(format!("--stripes {}: must be a positive number", args.stripes));
    }
    if !args.stripe_angle.is_finite() {
        return Err(format!("--stripe-angle {}: must be a finite number of degrees", args.stripe_angle));
    }
    if !(args.stripe_width > 0.0 && args.stripe_width < 1.0) {
        return Err(format!(
            "--stripe-width {}: the black share of a stripe pair must lie strictly between 0 and 1",
            args.stripe_width
        ));
    }
    args.files.check_output(&[&args.input], &args.output)?;

    // The surface: a smoothed cage, or a mesh as it is.
    let cage_input = extension(&args.input) == "taut" || args.smoothing.any();
    let (surface, doc, solver) = if cage_input {
        let mut doc = load_document(&args.input, &args.files)?;
        apply_flags(&mut doc, &args.smoothing)?;
        doc.validate().map_err(|e| e.to_string())?;
        let solver = solve_reporting(&doc)?;
        (solver.surface(), Some(doc), Some(solver))
    } else {
        let (mesh, report) =
            io::import_mesh_with(&args.input, &args.files.import_options()).map_err(|e| e.to_string())?;
        if !report.is_clean() {
            note(format!("{}: {report}", args.input.display()));
        }
        (mesh, None, None)
    };
    if surface.face_count() == 0 {
        return Err(format!("{}: nothing to draw (no faces)", args.input.display()));
    }

    let mut data = OverlayData::default();
    let mode = match view {
        View::Shaded => SurfaceMode::Shaded,
        View::Zebra => SurfaceMode::Zebra {
            stripes: args.stripes,
            angle_degrees: args.stripe_angle,
            width_ratio: args.stripe_width,
        },
        View::Curvature(q) => {
            let r = solver.as_ref().map(|s| s.surface_second_derivatives());
            if q == CurvatureQuantity::NusdR && r.is_none() {
                return Err("--view r shows NUSD's second derivative: give a .taut cage or a smoothing flag".into());
            }
            let values = vertex_curvature(&surface).values(q, r).map_err(|e| e.to_string())?;
            let (min, max) = match &args.range {
                Some(text) => parse_range(text)?,
                None => robust_range(&values, q.is_signed()),
            };
            println!("{}: colours from {min:.4e} to {max:.4e}", q.display_name());
            let map = if q.is_signed() { ColorMap::Diverging } else { ColorMap::Sequential };
            if args.legend {
                data.legend = Some(Legend { map, min, max, title: overlay::legend_title(q).to_string() });
            }
            // The colours are chosen in f64: curvatures of a tiny model would overflow f32.
            let values = taut_render::colormap::normalize(&values, min, max);
            return draw(
                args,
                &surface,
                doc.as_ref(),
                solver.as_ref(),
                &overlays,
                data,
                SurfaceMode::Curvature { map, min: 0.0, max: 1.0 },
                Some(&values),
                (width, height),
            );
        }
    };
    draw(args, &surface, doc.as_ref(), solver.as_ref(), &overlays, data, mode, None, (width, height))
}

#[allow(clippy::too_many_arguments)]
fn draw(
    args: &RenderArgs,
    surface: &PolyMesh,
    doc: Option<&Document>,
    solver: Option<&taut_core::nusd::surface::SurfaceSolver>,
    overlays: &[&str],
    mut data: OverlayData,
    mode: SurfaceMode,
    values: Option<&[f32]>,
    (width, height): (u32, u32),
) -> Result<(), String> {
    // Everything is drawn relative to the surface's own box, so any finite model fits f32.
    let (lo, hi) = surface.bounding_box().ok_or("nothing to frame")?;
    let frame = &DisplayFrame::for_bounds(lo, hi);
    let normals: Option<&[DVec3]> = None;
    for &name in overlays {
        match name {
            "cage" => {
                let doc = doc.ok_or("--overlay cage needs a cage: give a .taut file or a smoothing flag")?;
                let (lines, points) = overlay::cage_overlay(
                    &doc.cage,
                    &doc.fixed,
                    &doc.vertex_tension,
                    &doc.edge_tension,
                    &CageSelection::default(),
                    frame,
                );
                data.on_top_lines.extend(lines);
                data.points.extend(points);
            }
            "wire" => data.surface_lines.extend(overlay::wireframe(surface, [0.05, 0.05, 0.06, 0.8], 1.0, frame)),
            _ => {
                // Curves along the cage edges (or the mesh's boundary loops), with combs
                // scaled so the longest tooth is 6 % of the model's size.
                let curves = curves_of(surface, solver);
                let diagonal = surface.bounding_diagonal();
                let peak = curves
                    .iter()
                    .flat_map(|c| taut_core::curvature::polyline_curvature(c, false).magnitude())
                    .fold(0.0f64, f64::max);
                let scale = if peak > 0.0 { 0.06 * diagonal / peak } else { 1.0 };
                let style = CombStyle { scale, ..Default::default() };
                for curve in &curves {
                    data.surface_lines.extend(overlay::polyline_with_comb(curve, false, &style, frame));
                }
            }
        }
    }

    let gpu = Gpu::headless(if args.software { AdapterPreference::Software } else { AdapterPreference::Hardware })
        .map_err(|e| e.to_string())?;
    let targets = TargetFormats::for_adapter(&gpu.adapter, wgpu::TextureFormat::Rgba8UnormSrgb);
    let mut renderer = Renderer::new(&gpu, targets);
    let mut buffers = SurfaceBuffers::default();
    buffers.update_with(surface, normals, frame);
    if let Some(values) = values {
        buffers.set_values(values);
    }
    let gpu_surface = GpuSurface::new(&gpu.device, &buffers);
    let margin = data.legend.as_ref().map_or(0, |l| legend_margin(l, width, height));
    let camera = camera_for(surface, frame, args.camera.as_deref(), (width, height), margin)?;
    let mut scene = Scene::new(camera, Some(&gpu_surface), mode);
    scene.overlays = Some(&data);
    let picture = offscreen::render_image(&gpu, &mut renderer, &scene, width, height).map_err(|e| e.to_string())?;
    offscreen::save_png(&picture, &args.output).map_err(|e| e.to_string())?;
    println!(
        "wrote {} ({width}x{height}, {} triangles, on {})",
        args.output.display(),
        buffers.indices().len() / 3,
        gpu.description()
    );
    Ok(())
}

/// The surface's curves along the cage edges, or the boundary loops of a plain mesh.
fn curves_of(surface: &PolyMesh, solver: Option<&taut_core::nusd::surface::SurfaceSolver>) -> Vec<Vec<DVec3>> {
    match solver {
        Some(solver) => solver
            .cage_edge_curves()
            .into_iter()
            .map(|(_, chain)| chain.iter().map(|&v| surface.position(v)).collect())
            .collect(),
        None => {
            let mut seen = vec![false; surface.halfedge_count()];
            let mut loops = Vec::new();
            for h in (0..surface.halfedge_count() as u32).map(taut_core::HalfedgeId) {
                if !surface.is_boundary_halfedge(h) || seen[h.index()] {
                    continue;
                }
                let mut points = Vec::new();
                let mut g = h;
                loop {
                    seen[g.index()] = true;
                    points.push(surface.position(surface.from_vertex(g)));
                    g = surface.next(g);
                    if g == h {
                        break;
                    }
                }
                points.push(points[0]);
                loops.push(points);
            }
            loops
        }
    }
}

/// The camera in the display coordinates of `frame`: the surface framed to fill the picture left
/// of the legend's margin (`margin` pixels at the right), or placed by `--camera` (its distance in
/// model units).
fn camera_for(
    surface: &PolyMesh,
    frame: &DisplayFrame,
    spec: Option<&str>,
    (width, height): (u32, u32),
    margin: u32,
) -> Result<Camera, String> {
    let mut camera = Camera::default();
    let mut distance = None;
    if let Some(spec) = spec {
        let numbers = parse_numbers(spec, "--camera")?;
        match numbers.as_slice() {
            [az, el] | [az, el, _] => {
                camera.azimuth = *az as f32;
                camera.elevation = (*el as f32).clamp(-90.0, 90.0);
            }
            _ => return Err(format!("--camera {spec}: expected AZIMUTH,ELEVATION[,DISTANCE]")),
        }
        if let [_, _, d] = numbers.as_slice() {
            let display = frame.length(*d);
            if !(*d > 0.0 && display.is_finite() && (1e-6..=1e9).contains(&(display as f32))) {
                return Err(format!(
                    "--camera {spec}: the distance must be positive and within a billion times the model's size ({:.3e})",
                    frame.scale
                ));
            }
            distance = Some(display as f32);
        }
    }
    // Framing every vertex of a million-vertex surface is wasteful: a regular sample sees the
    // same silhouette to within a pixel.
    let step = (surface.vertex_count() / 20_000).max(1);
    let points: Vec<glam::Vec3> = surface.positions().iter().step_by(step).map(|&p| frame.point(p)).collect();
    let usable = width.saturating_sub(margin).max(1);
    camera.frame_points(&points, usable as f32 / height.max(1) as f32);
    if let Some(d) = distance {
        camera.distance = d;
    }
    // Centre the model in the part of the picture the legend leaves free.
    camera.pan(-(margin as f32) / 2.0, 0.0, height as f32);
    Ok(camera)
}

fn parse_numbers(text: &str, flag: &str) -> Result<Vec<f64>, String> {
    text.split(',')
        .map(|t| {
            t.trim()
                .parse::<f64>()
                .ok()
                .filter(|x| x.is_finite())
                .ok_or_else(|| format!("{flag} {text}: '{}' is not a number", t.trim()))
        })
        .collect()
}

fn parse_range(text: &str) -> Result<(f64, f64), String> {
    match parse_numbers(text, "--range")?.as_slice() {
        [min, max] if min < max => Ok((*min, *max)),
        [_, _] => Err(format!("--range {text}: MIN must be below MAX")),
        _ => Err(format!("--range {text}: expected MIN,MAX")),
    }
}

fn parse_size(text: &str) -> Result<(u32, u32), String> {
    let bad = || format!("--size {text}: expected WIDTHxHEIGHT, for example 1280x800, each 1 to 16384");
    let (w, h) = text.split_once(['x', 'X']).ok_or_else(bad)?;
    let (w, h): (u32, u32) = (w.trim().parse().map_err(|_| bad())?, h.trim().parse().map_err(|_| bad())?);
    if w == 0 || h == 0 || w > 16384 || h > 16384 {
        return Err(bad());
    }
    Ok((w, h))
}
