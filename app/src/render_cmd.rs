//! `taut render`: a picture of a surface as the editor's viewport would draw it, off screen.
//!
//! A `.taut` cage is smoothed with its settings (the smoothing flags override them). A mesh file
//! (`.obj`, `.gltf`, `.glb`) is drawn as it is, unless a smoothing flag is given: then it is
//! taken as a cage and smoothed. The picture uses a hardware GPU when there is one, else Mesa's
//! software rasteriser.

use crate::cli::{FileFlags, note};
use crate::editor::state::comb_style;
use crate::render_analysis::{Analysis, AnalysisFlags, draft_shares};
use crate::surface_cmd::{SurfaceFlags, extension, load_document, solve_reporting};
use clap::Args;
use std::path::PathBuf;
use taut_core::curvature::{robust_range, vertex_curvature};
use taut_core::surface::{ColourBy, SchemeKind, SurfaceScheme};
use taut_core::{DVec3, Document, PolyMesh, io};
use taut_render::colormap::ColorMap;
use taut_render::overlay::{self, CageControls, CageSelection, Legend, OverlayData};
use taut_render::passes::surface::SurfaceMode;
use taut_render::picture::{Picture, View as CameraView};
use taut_render::{AdapterPreference, Gpu, RenderError, Renderer, TargetFormats, offscreen};

#[derive(Debug, Args)]
pub struct RenderArgs {
    /// A cage (.taut, smoothed first) or a mesh (.obj, .gltf, .glb; drawn as it is unless a
    /// smoothing flag is given).
    pub input: PathBuf,
    /// The picture to write (.png).
    #[arg(short, long)]
    pub output: PathBuf,
    /// shaded, zebra, draft (draft angle against --pull), highlight (highlight lines of light
    /// tubes), or a curvature colour: mean, gaussian, kmin, kmax, kabs, r (NUSD |R|).
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
    /// Section curves: where the planes AXIS = V1, V2, … cut the surface (AXIS x, y or z, in
    /// the model's coordinates as Taut reads them), drawn with curvature combs.
    #[arg(long, value_name = "AXIS:V1,V2,...", allow_hyphen_values = true)]
    pub sections: Option<String>,
    /// Draw with the software rasteriser even when a GPU is present (reproducible pictures).
    #[arg(long)]
    pub software: bool,
    /// The surface scheme of a cage: nusd, catmull-clark, loop or curve-mesh [default: the .taut file's, or
    /// nusd]; giving it draws a mesh file as a cage.
    #[arg(long)]
    pub scheme: Option<SchemeKind>,
    #[command(flatten)]
    pub analysis: AnalysisFlags,
    #[command(flatten)]
    pub smoothing: SurfaceFlags,
    #[command(flatten)]
    pub files: FileFlags,
}

enum View {
    Shaded,
    Zebra,
    Analysis(Analysis),
    Colour(String),
}

/// What a picture shows: a document's surface made by its scheme, or a mesh as it is.
enum Drawn {
    Surface { doc: Box<Document>, surface: Box<dyn SurfaceScheme> },
    Mesh(PolyMesh),
}

impl Drawn {
    fn mesh(&self) -> &PolyMesh {
        match self {
            Drawn::Surface { surface, .. } => surface.mesh(),
            Drawn::Mesh(mesh) => mesh,
        }
    }

    fn normals(&self) -> Option<&[DVec3]> {
        match self {
            Drawn::Surface { surface, .. } => surface.normals(),
            Drawn::Mesh(_) => None,
        }
    }
}

pub fn run(args: &RenderArgs) -> Result<(), String> {
    let view = match (args.view.as_str(), args.analysis.check(&args.view)?) {
        (_, Some(analysis)) => View::Analysis(analysis),
        ("shaded", _) => View::Shaded,
        ("zebra", _) => View::Zebra,
        (other, _) => View::Colour(other.to_string()),
    };
    let (width, height) = parse_size(&args.size)?;
    if extension(&args.output) != "png" {
        return Err(format!("{}: the picture must be a .png file", args.output.display()));
    }
    let overlays: Vec<&str> = args.overlay.iter().map(|s| s.trim()).filter(|s| !s.is_empty()).collect();
    if let Some(bad) = overlays.iter().find(|o| !["cage", "wire", "curves"].contains(o)) {
        return Err(format!("--overlay {bad}: use cage, wire or curves"));
    }
    // Checked before any work; drawn with the other overlays.
    args.sections.as_deref().map(parse_sections).transpose()?;
    if args.legend && !matches!(view, View::Colour(_)) {
        return Err("--legend goes with a colour view (mean, gaussian, kmin, kmax, kabs, r)".into());
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
    let colour_by = match &view {
        View::Colour(name) => {
            let scheme = args.scheme.unwrap_or(SchemeKind::Nusd);
            let by = match ColourBy::parse(name, scheme) {
                Ok(by) => by,
                Err(_) if name == "r" => {
                    return Err(format!(
                        "--view r shows NUSD's second derivative, which the {} scheme does not have",
                        scheme.display_name()
                    ));
                }
                Err(_) => {
                    return Err(format!(
                        "--view {name}: use shaded, zebra, draft, highlight, mean, gaussian, kmin, kmax, kabs or r"
                    ));
                }
            };
            Some(by)
        }
        _ => None,
    };

    // The surface: a cage made smooth by its scheme, or a mesh as it is.
    let cage_input = extension(&args.input) == "taut" || args.smoothing.any() || args.scheme.is_some();
    let drawn = if cage_input {
        let mut doc = load_document(&args.input, &args.files)?;
        args.smoothing.apply(&mut doc, args.scheme)?;
        doc.validate().map_err(|e| e.to_string())?;
        let surface = solve_reporting(&doc, true)?;
        Drawn::Surface { doc: Box::new(doc), surface }
    } else {
        let (mesh, report) =
            io::import_mesh_with(&args.input, &args.files.import_options()).map_err(|e| e.to_string())?;
        if !report.is_clean() {
            note(format!("{}: {report}", args.input.display()));
        }
        Drawn::Mesh(mesh)
    };
    if drawn.mesh().face_count() == 0 {
        return Err(format!("{}: nothing to draw (no faces)", args.input.display()));
    }

    let mut data = OverlayData::default();
    let Some(by) = colour_by else {
        let mode = match view {
            View::Zebra => SurfaceMode::Zebra {
                stripes: args.stripes,
                angle_degrees: args.stripe_angle,
                width_ratio: args.stripe_width,
            },
            View::Analysis(analysis) => {
                let frame = drawn.mesh().bounding_box().map_or(taut_render::DisplayFrame::IDENTITY, |(lo, hi)| {
                    taut_render::DisplayFrame::for_bounds(lo, hi)
                });
                report_analysis(&analysis, &drawn, parse_view(args.camera.as_deref())?);
                analysis.mode(&frame)
            }
            _ => SurfaceMode::Shaded,
        };
        return draw(args, &drawn, &overlays, data, mode, None, (width, height));
    };
    let values = match (&drawn, by) {
        (Drawn::Surface { surface, .. }, by) => by.values(surface.as_ref()).map_err(|e| e.to_string())?,
        (Drawn::Mesh(mesh), ColourBy::Curvature(q)) => vertex_curvature(mesh).values(q),
        (Drawn::Mesh(_), _) => {
            return Err("--view r shows NUSD's second derivative: give a .taut cage or a smoothing flag".into());
        }
    };
    let (min, max) = match &args.range {
        Some(text) => parse_range(text)?,
        None => robust_range(&values, by.is_signed()),
    };
    println!("{}: colours from {min:.4e} to {max:.4e}", by.display_name());
    let map = if by.is_signed() { ColorMap::Diverging } else { ColorMap::Sequential };
    if args.legend {
        data.legend = Some(Legend { map, min, max, title: overlay::legend_title(by).to_string() });
    }
    // The colours are chosen in f64: curvatures of a tiny model would overflow f32.
    let values = taut_render::colormap::normalize(&values, min, max);
    draw(
        args,
        &drawn,
        &overlays,
        data,
        SurfaceMode::Curvature { map, min: 0.0, max: 1.0 },
        Some(&values),
        (width, height),
    )
}

fn draw(
    args: &RenderArgs,
    drawn: &Drawn,
    overlays: &[&str],
    mut data: OverlayData,
    mode: SurfaceMode,
    values: Option<&[f32]>,
    (width, height): (u32, u32),
) -> Result<(), String> {
    let surface = drawn.mesh();
    let picture = Picture {
        mesh: surface,
        normals: drawn.normals(),
        values,
        mode,
        view: parse_view(args.camera.as_deref())?,
        width,
        height,
    };
    // Everything is drawn relative to the surface's own box, so any finite model fits f32.
    let frame = &picture.frame();
    for &name in overlays {
        match name {
            "cage" => {
                let Drawn::Surface { doc, .. } = drawn else {
                    return Err("--overlay cage needs a cage: give a .taut file or a smoothing flag".into());
                };
                let controls = CageControls::of(doc);
                let (lines, points) = overlay::cage_overlay(&doc.cage, controls, &CageSelection::default(), frame);
                data.on_top_lines.extend(lines);
                data.points.extend(points);
            }
            "wire" => data.surface_lines.extend(overlay::wireframe(surface, [0.05, 0.05, 0.06, 0.8], 1.0, frame)),
            _ => {
                // Curves along the cage edges (or the mesh's boundary loops), with combs
                // scaled so the longest tooth is 12 % of the model's size.
                let curves = curves_of(drawn);
                let style = comb_style(&curves, surface.bounding_diagonal(), 0.12, 1);
                for curve in &curves {
                    data.surface_lines.extend(overlay::polyline_with_comb(curve, false, &style, frame));
                }
            }
        }
    }

    if let Some((normal, offsets)) = &args.sections.as_deref().map(parse_sections).transpose()? {
        // Combs scaled so the longest tooth is 12 % of the model's size, as the curves overlay.
        let curves: Vec<taut_core::mesh::sections::SectionCurve> =
            taut_core::mesh::sections::sections(surface, *normal, offsets).into_iter().flatten().collect();
        // Combs on the sections resampled evenly (`SectionCurve::evenly`).
        let step = taut_core::mesh::sections::comb_step(surface);
        let points: Vec<Vec<DVec3>> = curves.iter().map(|c| c.evenly(step)).collect();
        let style = comb_style(&points, surface.bounding_diagonal(), 0.12, 1);
        for (curve, even) in curves.iter().zip(&points) {
            data.surface_lines.extend(overlay::polyline_with_comb(even, curve.closed, &style, frame));
        }
        println!(
            "sections: {} planes, {} curves ({} closed)",
            offsets.len(),
            curves.len(),
            curves.iter().filter(|c| c.closed).count()
        );
    }

    let gpu = Gpu::headless(if args.software { AdapterPreference::Software } else { AdapterPreference::Hardware })
        .map_err(|e| e.to_string())?;
    let targets = TargetFormats::for_adapter(&gpu.adapter, wgpu::TextureFormat::Rgba8UnormSrgb);
    let mut renderer = Renderer::new(&gpu, targets);
    let references = match drawn {
        Drawn::Surface { doc, .. } => reference_pictures(doc, &args.input),
        Drawn::Mesh(_) => Vec::new(),
    };
    let image = picture.render_with_references(&gpu, &mut renderer, &data, &references).map_err(|e| match e {
        RenderError::Output(m) if m.starts_with("the camera distance") => {
            format!("--camera {}: {m}", args.camera.as_deref().unwrap_or_default())
        }
        other => other.to_string(),
    })?;
    offscreen::save_png(&image, &args.output).map_err(|e| e.to_string())?;
    println!(
        "wrote {} ({width}x{height}, {} triangles, on {})",
        args.output.display(),
        surface.triangles().len(),
        gpu.description()
    );
    Ok(())
}

/// The document's visible reference images with their pictures, read as the editor reads them
/// (only from the document's folder); one that cannot be read is told in one line and left out.
fn reference_pictures(
    doc: &Document,
    input: &std::path::Path,
) -> Vec<(taut_core::document::ReferenceImage, taut_render::reference_images::Picture)> {
    use taut_render::reference_images::{load_picture, picture_key};
    let folder = input.parent().filter(|p| !p.as_os_str().is_empty()).unwrap_or(std::path::Path::new("."));
    doc.reference_images
        .iter()
        .filter(|image| image.visible)
        .filter_map(|image| match picture_key(image, folder).and_then(|key| load_picture(key, &image.path)) {
            Ok(picture) => Some((image.clone(), picture)),
            Err(message) => {
                note(message);
                None
            }
        })
        .collect()
}

/// Prints what the analysis view shows in numbers: the draft classes' shares of the area.
fn report_analysis(analysis: &Analysis, drawn: &Drawn, view: CameraView) {
    let Analysis::Draft { pull, angle_degrees } = *analysis else { return };
    let pull = match pull {
        taut_render::analysis::Pull::Direction(p) => p.normalize(),
        taut_render::analysis::Pull::View => {
            let camera = taut_render::Camera { azimuth: view.azimuth, elevation: view.elevation, ..Default::default() };
            camera.backward().as_dvec3()
        }
    };
    let [positive, below, negative] = draft_shares(drawn.mesh(), drawn.normals(), pull, angle_degrees);
    println!(
        "draft against ({:.3}, {:.3}, {:.3}), threshold {angle_degrees}°: {:.1} % of the area positive, \
         {:.1} % below the threshold, {:.1} % undercut",
        pull.x,
        pull.y,
        pull.z,
        100.0 * positive,
        100.0 * below,
        100.0 * negative
    );
}

/// `--sections AXIS:V1,V2,…`: the planes' normal and their offsets along it.
fn parse_sections(spec: &str) -> Result<(DVec3, Vec<f64>), String> {
    let bad = |why: &str| format!("--sections {spec}: {why} (write AXIS:V1,V2,… with AXIS x, y or z)");
    let (axis, values) = spec.split_once(':').ok_or_else(|| bad("no ':' after the axis"))?;
    let normal = match axis.trim() {
        "x" | "X" => DVec3::X,
        "y" | "Y" => DVec3::Y,
        "z" | "Z" => DVec3::Z,
        other => return Err(bad(&format!("'{other}' is not an axis"))),
    };
    let offsets = values
        .split(',')
        .map(|v| match v.trim().parse::<f64>() {
            Ok(x) if x.is_finite() => Ok(x),
            _ => Err(bad(&format!("'{}' is not a finite number", v.trim()))),
        })
        .collect::<Result<Vec<f64>, String>>()?;
    if offsets.len() > 1000 {
        return Err(bad("at most 1000 planes"));
    }
    Ok((normal, offsets))
}

/// The surface's curves along the cage edges, or the boundary loops of a plain mesh.
fn curves_of(drawn: &Drawn) -> Vec<Vec<DVec3>> {
    let surface = match drawn {
        Drawn::Surface { surface, .. } => return surface.curves(),
        Drawn::Mesh(mesh) => mesh,
    };
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

/// `--camera AZIMUTH,ELEVATION[,DISTANCE]` (the distance in model units).
fn parse_view(spec: Option<&str>) -> Result<CameraView, String> {
    let Some(spec) = spec else { return Ok(CameraView::default()) };
    let numbers = parse_numbers(spec, "--camera")?;
    let (azimuth, elevation) = match numbers.as_slice() {
        [az, el] | [az, el, _] => (*az as f32, *el as f32),
        _ => return Err(format!("--camera {spec}: expected AZIMUTH,ELEVATION[,DISTANCE]")),
    };
    let distance = match numbers.as_slice() {
        [_, _, d] if *d <= 0.0 => return Err(format!("--camera {spec}: the distance must be positive")),
        [_, _, d] => Some(*d),
        _ => None,
    };
    Ok(CameraView { azimuth, elevation, distance })
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
