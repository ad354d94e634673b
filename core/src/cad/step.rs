//! ISO 10303-21 (STEP Part 21) text for a [`BrepModel`]: every vertex, edge and face as
//! B-spline geometry (`B_SPLINE_CURVE_WITH_KNOTS`, `B_SPLINE_SURFACE_WITH_KNOTS`) with its
//! topology (`VERTEX_POINT`, `EDGE_CURVE`, `ADVANCED_FACE`), the shells as solids or as a
//! surface model, and the product structure, units and tolerance a CAD system needs to import
//! the file as a part.
//!
//! The schema is AP214 (`AUTOMOTIVE_DESIGN`): it has the widest reader support for B-spline
//! B-reps of any application protocol, and AP242 readers read AP214 too. Entity numbers run from
//! `#1` in the order written, and every entity refers only to entities written before it, so the
//! same model always gives the same text.

use std::fmt::{self, Display, Write as _};

use super::brep::{BSplineCurve, BSplineSurface, BrepModel, LengthUnit};
use crate::{DVec3, Error, Result};

/// What the file's header says.
#[derive(Clone, Copy, Debug)]
pub struct StepHeader<'a> {
    /// The file's name, also written as the product's id and name.
    pub name: &'a str,
    /// When the file was written, ISO 8601 (e.g. `"2026-12-03T10:00:00"`).
    pub timestamp: &'a str,
    /// Who wrote it.
    pub author: &'a str,
}

/// The AP214 schema name readers look for in `FILE_SCHEMA`.
const SCHEMA: &str = "AUTOMOTIVE_DESIGN { 1 0 10303 214 1 1 1 1 }";

/// The model as Part 21 text, lengths in `unit`, `tolerance` (in `unit`) written as the
/// context's distance accuracy (the gap a reader may treat as closed).
///
/// When every shell is closed, each becomes a `MANIFOLD_SOLID_BREP` in one
/// `ADVANCED_BREP_SHAPE_REPRESENTATION`, so CAD systems import solids. When any shell is open,
/// all shells (`OPEN_SHELL` or `CLOSED_SHELL`) go into one `SHELL_BASED_SURFACE_MODEL` in a
/// `MANIFOLD_SURFACE_SHAPE_REPRESENTATION`, so they import as surfaces.
///
/// Fails with [`Error::Input`] on an empty model, a non-finite coordinate, knot or tolerance, an
/// index to a missing vertex, edge or face, a face loop whose edges do not join, or knots and
/// multiplicities that do not fit the control points.
pub fn step_text(model: &BrepModel, unit: LengthUnit, tolerance: f64, header: &StepHeader<'_>) -> Result<String> {
    if !(tolerance.is_finite() && tolerance > 0.0) {
        return Err(Error::Input(format!("STEP tolerance must be a positive number, got {tolerance}")));
    }
    check_model(model, tolerance)?;
    let mut file = Part21::default();
    file.header(header);
    let context = file.context(unit, tolerance);

    let vertices: Vec<usize> = model
        .vertices
        .iter()
        .map(|&p| {
            let point = file.point(p);
            file.entity(format_args!("VERTEX_POINT('',{})", Ref(point)))
        })
        .collect();
    // Surfaces first: an edge names the faces' surfaces its parameter-plane curves lie on.
    let surfaces: Vec<usize> = model.faces.iter().map(|face| file.surface(&face.surface)).collect();
    let mut on_faces: Vec<Vec<(usize, [[f64; 2]; 2])>> = vec![Vec::new(); model.edges.len()];
    for (f, face) in model.faces.iter().enumerate() {
        for (&(e, _), &uv) in face.outer.iter().zip(&face.outer_uv) {
            on_faces[e].push((f, uv));
        }
    }
    let parametric = on_faces.iter().any(|uses| !uses.is_empty()).then(|| {
        file.entity(format_args!(
            "( GEOMETRIC_REPRESENTATION_CONTEXT(2) PARAMETRIC_REPRESENTATION_CONTEXT() \
             REPRESENTATION_CONTEXT('2D SPACE','') )"
        ))
    });
    let edges: Vec<usize> = model
        .edges
        .iter()
        .zip(&on_faces)
        .map(|(edge, uses)| {
            let mut geometry = file.curve(&edge.curve);
            if let (Some(context), 1..=2) = (parametric, uses.len()) {
                // The edge as a line in each face's parameter plane, with the curve's parameter.
                let (first, last) = (edge.curve.knots[0], edge.curve.knots[edge.curve.knots.len() - 1]);
                let pcurves: Vec<usize> = uses
                    .iter()
                    .map(|&(f, [a, b])| {
                        let (a, b) = (file.point_2d(a), file.point_2d(b));
                        let line = file.entity(format_args!(
                            "B_SPLINE_CURVE_WITH_KNOTS('',1,({},{}),.POLYLINE_FORM.,.F.,.F.,(2,2),({},{}),\
                             .UNSPECIFIED.)",
                            Ref(a),
                            Ref(b),
                            Real(first),
                            Real(last)
                        ));
                        let representation = file.entity(format_args!(
                            "DEFINITIONAL_REPRESENTATION('',({}),{})",
                            Ref(line),
                            Ref(context)
                        ));
                        file.entity(format_args!("PCURVE('',{},{})", Ref(surfaces[f]), Ref(representation)))
                    })
                    .collect();
                let curve = Ref(geometry);
                geometry = file.entity(format_args!("SURFACE_CURVE('',{curve},{},.CURVE_3D.)", Refs(&pcurves)));
            }
            let (start, end) = (Ref(vertices[edge.start]), Ref(vertices[edge.end]));
            file.entity(format_args!("EDGE_CURVE('',{start},{end},{},.T.)", Ref(geometry)))
        })
        .collect();
    let faces: Vec<usize> = model
        .faces
        .iter()
        .zip(&surfaces)
        .map(|(face, &surface)| {
            let oriented: Vec<usize> = face
                .outer
                .iter()
                .map(|&(edge, same_sense)| {
                    let (edge, sense) = (Ref(edges[edge]), Bool(same_sense));
                    file.entity(format_args!("ORIENTED_EDGE('',*,*,{edge},{sense})"))
                })
                .collect();
            let edge_loop = file.entity(format_args!("EDGE_LOOP('',{})", Refs(&oriented)));
            let bound = file.entity(format_args!("FACE_OUTER_BOUND('',{},.T.)", Ref(edge_loop)));
            let (surface, sense) = (Ref(surface), Bool(face.same_sense));
            file.entity(format_args!("ADVANCED_FACE('',({}),{surface},{sense})", Ref(bound)))
        })
        .collect();
    let shells: Vec<usize> = model
        .shells
        .iter()
        .map(|shell| {
            let kind = if shell.closed { "CLOSED_SHELL" } else { "OPEN_SHELL" };
            let members: Vec<usize> = shell.faces.iter().map(|&f| faces[f]).collect();
            file.entity(format_args!("{kind}('',{})", Refs(&members)))
        })
        .collect();

    let origin = file.point(DVec3::ZERO);
    let z = file.entity(format_args!("DIRECTION('',(0.,0.,1.))"));
    let x = file.entity(format_args!("DIRECTION('',(1.,0.,0.))"));
    let placement = file.entity(format_args!("AXIS2_PLACEMENT_3D('',{},{},{})", Ref(origin), Ref(z), Ref(x)));
    let mut items = vec![placement];
    let representation = if model.shells.iter().all(|shell| shell.closed) {
        for &shell in &shells {
            items.push(file.entity(format_args!("MANIFOLD_SOLID_BREP('',{})", Ref(shell))));
        }
        let items = Refs(&items);
        file.entity(format_args!("ADVANCED_BREP_SHAPE_REPRESENTATION('',{items},{})", Ref(context)))
    } else {
        items.push(file.entity(format_args!("SHELL_BASED_SURFACE_MODEL('',{})", Refs(&shells))));
        let items = Refs(&items);
        file.entity(format_args!("MANIFOLD_SURFACE_SHAPE_REPRESENTATION('',{items},{})", Ref(context)))
    };
    file.product(header, representation);
    file.text.push_str("ENDSEC;\nEND-ISO-10303-21;\n");
    Ok(file.text)
}

/// The text written so far and the next entity number.
#[derive(Debug)]
struct Part21 {
    text: String,
    next_id: usize,
}

impl Default for Part21 {
    fn default() -> Self {
        Part21 { text: String::new(), next_id: 1 }
    }
}

impl Part21 {
    /// Writes `#n=body;` on a line of its own and returns `n`.
    fn entity(&mut self, body: fmt::Arguments<'_>) -> usize {
        let id = self.next_id;
        self.next_id += 1;
        // Writing to a String cannot fail.
        let _ = writeln!(self.text, "#{id}={body};");
        id
    }

    fn header(&mut self, header: &StepHeader<'_>) {
        let version = env!("CARGO_PKG_VERSION");
        let _ = write!(
            self.text,
            "ISO-10303-21;\nHEADER;\nFILE_DESCRIPTION(('Taut surface'),'2;1');\n\
             FILE_NAME({},{},({}),(''),'Taut {version}','Taut','');\n\
             FILE_SCHEMA(('{SCHEMA}'));\nENDSEC;\nDATA;\n",
            Text(header.name),
            Text(header.timestamp),
            Text(header.author),
        );
    }

    /// The units and the uncertainty; returns the geometric representation context.
    fn context(&mut self, unit: LengthUnit, tolerance: f64) -> usize {
        let si_length = |file: &mut Self, prefix: &str| {
            file.entity(format_args!("( LENGTH_UNIT() NAMED_UNIT(*) SI_UNIT({prefix},.METRE.) )"))
        };
        let length = match unit {
            LengthUnit::Millimetre => si_length(self, ".MILLI."),
            LengthUnit::Centimetre => si_length(self, ".CENTI."),
            LengthUnit::Metre => si_length(self, "$"),
            LengthUnit::Inch => {
                let millimetre = si_length(self, ".MILLI.");
                let inch =
                    self.entity(format_args!("LENGTH_MEASURE_WITH_UNIT(LENGTH_MEASURE(25.4),{})", Ref(millimetre)));
                let exponents = self.entity(format_args!("DIMENSIONAL_EXPONENTS(1.,0.,0.,0.,0.,0.,0.)"));
                self.entity(format_args!(
                    "( CONVERSION_BASED_UNIT('INCH',{}) LENGTH_UNIT() NAMED_UNIT({}) )",
                    Ref(inch),
                    Ref(exponents)
                ))
            }
        };
        let angle = self.entity(format_args!("( NAMED_UNIT(*) PLANE_ANGLE_UNIT() SI_UNIT($,.RADIAN.) )"));
        let solid_angle = self.entity(format_args!("( NAMED_UNIT(*) SI_UNIT($,.STERADIAN.) SOLID_ANGLE_UNIT() )"));
        let uncertainty = self.entity(format_args!(
            "UNCERTAINTY_MEASURE_WITH_UNIT(LENGTH_MEASURE({}),{},'distance_accuracy_value',\
             'confusion accuracy')",
            Real(tolerance),
            Ref(length)
        ));
        self.entity(format_args!(
            "( GEOMETRIC_REPRESENTATION_CONTEXT(3) GLOBAL_UNCERTAINTY_ASSIGNED_CONTEXT(({})) \
             GLOBAL_UNIT_ASSIGNED_CONTEXT(({},{},{})) \
             REPRESENTATION_CONTEXT('Context #1','3D Context with UNIT and UNCERTAINTY') )",
            Ref(uncertainty),
            Ref(length),
            Ref(angle),
            Ref(solid_angle)
        ))
    }

    fn point(&mut self, p: DVec3) -> usize {
        let (x, y, z) = (Real(p.x), Real(p.y), Real(p.z));
        self.entity(format_args!("CARTESIAN_POINT('',({x},{y},{z}))"))
    }

    fn point_2d(&mut self, [u, v]: [f64; 2]) -> usize {
        self.entity(format_args!("CARTESIAN_POINT('',({},{}))", Real(u), Real(v)))
    }

    fn curve(&mut self, curve: &BSplineCurve) -> usize {
        let points: Vec<usize> = curve.points.iter().map(|&p| self.point(p)).collect();
        self.entity(format_args!(
            "B_SPLINE_CURVE_WITH_KNOTS('',{},{},.UNSPECIFIED.,.F.,.F.,{},{},.UNSPECIFIED.)",
            curve.degree,
            Refs(&points),
            Ints(&curve.multiplicities),
            Reals(&curve.knots)
        ))
    }

    fn surface(&mut self, surface: &BSplineSurface) -> usize {
        // STEP's control-point list is indexed [u][v], like `points[i][j]`.
        let rows: Vec<Vec<usize>> =
            surface.points.iter().map(|row| row.iter().map(|&p| self.point(p)).collect()).collect();
        self.entity(format_args!(
            "B_SPLINE_SURFACE_WITH_KNOTS('',{},{},{},.UNSPECIFIED.,.F.,.F.,.F.,{},{},{},{},\
             .UNSPECIFIED.)",
            surface.degree_u,
            surface.degree_v,
            Grid(&rows),
            Ints(&surface.multiplicities_u),
            Ints(&surface.multiplicities_v),
            Reals(&surface.knots_u),
            Reals(&surface.knots_v)
        ))
    }

    /// The AP214 product structure that makes `representation` the shape of one part.
    fn product(&mut self, header: &StepHeader<'_>, representation: usize) {
        let application =
            self.entity(format_args!("APPLICATION_CONTEXT('core data for automotive mechanical design processes')"));
        let application = Ref(application);
        self.entity(format_args!(
            "APPLICATION_PROTOCOL_DEFINITION('international standard','automotive_design',\
             2000,{application})"
        ));
        let context = self.entity(format_args!("PRODUCT_CONTEXT('',{application},'mechanical')"));
        let name = Text(header.name);
        let product = self.entity(format_args!("PRODUCT({name},{name},'',({}))", Ref(context)));
        let formation = self.entity(format_args!("PRODUCT_DEFINITION_FORMATION('','',{})", Ref(product)));
        let definition_context =
            self.entity(format_args!("PRODUCT_DEFINITION_CONTEXT('part definition',{application},'design')"));
        let definition =
            self.entity(format_args!("PRODUCT_DEFINITION('design','',{},{})", Ref(formation), Ref(definition_context)));
        let shape = self.entity(format_args!("PRODUCT_DEFINITION_SHAPE('','',{})", Ref(definition)));
        self.entity(format_args!("SHAPE_DEFINITION_REPRESENTATION({},{})", Ref(shape), Ref(representation)));
        self.entity(format_args!("PRODUCT_RELATED_PRODUCT_CATEGORY('part',$,({}))", Ref(product)));
    }
}

/// An entity reference, `#n`.
struct Ref(usize);

impl Display for Ref {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "#{}", self.0)
    }
}

/// A Part 21 boolean, `.T.` or `.F.`.
struct Bool(bool);

impl Display for Bool {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(if self.0 { ".T." } else { ".F." })
    }
}

/// A Part 21 REAL: the shortest decimal that reads back to the same f64, always with a decimal
/// point and an upper-case exponent (`1.`, `0.5`, `-2.5E-7`), as the standard's grammar requires.
struct Real(f64);

impl Display for Real {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let mut buffer = zmij::Buffer::new();
        let shortest = buffer.format(self.0);
        let (mantissa, exponent) = match shortest.split_once(['e', 'E']) {
            Some((mantissa, exponent)) => (mantissa, Some(exponent)),
            None => (shortest, None),
        };
        let mantissa = mantissa.strip_suffix(".0").unwrap_or(mantissa);
        f.write_str(mantissa)?;
        if !mantissa.contains('.') {
            f.write_char('.')?;
        }
        if let Some(exponent) = exponent {
            write!(f, "E{}", exponent.strip_prefix('+').unwrap_or(exponent))?;
        }
        Ok(())
    }
}

/// A Part 21 STRING: quotes doubled, backslashes doubled, characters outside printable ASCII as
/// `\X2\hhhh\X0\` (UTF-16 code units).
struct Text<'a>(&'a str);

impl Display for Text<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_char('\'')?;
        for c in self.0.chars() {
            match c {
                '\'' => f.write_str("''")?,
                '\\' => f.write_str("\\\\")?,
                ' '..='~' => f.write_char(c)?,
                _ => {
                    f.write_str("\\X2\\")?;
                    for unit in c.encode_utf16(&mut [0; 2]) {
                        write!(f, "{unit:04X}")?;
                    }
                    f.write_str("\\X0\\")?;
                }
            }
        }
        f.write_char('\'')
    }
}

/// Writes `(a,b,c)` from the items' own formatting.
fn list<T>(f: &mut fmt::Formatter<'_>, items: &[T], item: impl Fn(&T) -> String) -> fmt::Result {
    f.write_char('(')?;
    for (k, x) in items.iter().enumerate() {
        if k > 0 {
            f.write_char(',')?;
        }
        f.write_str(&item(x))?;
    }
    f.write_char(')')
}

/// A list of entity references.
struct Refs<'a>(&'a [usize]);

impl Display for Refs<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        list(f, self.0, |&id| Ref(id).to_string())
    }
}

/// A list of integers.
struct Ints<'a>(&'a [usize]);

impl Display for Ints<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        list(f, self.0, usize::to_string)
    }
}

/// A list of reals.
struct Reals<'a>(&'a [f64]);

impl Display for Reals<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        list(f, self.0, |&x| Real(x).to_string())
    }
}

/// A surface's control points, one row (fixed u) per line.
struct Grid<'a>(&'a [Vec<usize>]);

impl Display for Grid<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        list(f, self.0, |row| format!("\n  {}", Refs(row)))
    }
}

/// Everything [`step_text`] needs to hold before it writes: indices in range, numbers finite,
/// loops joined, knot vectors that fit.
fn check_model(model: &BrepModel, tolerance: f64) -> Result<()> {
    let fail = |message: String| Err(Error::Input(message));
    if model.faces.is_empty() || model.shells.is_empty() {
        return fail("the model is empty: there are no faces or no shells to write".into());
    }
    for (i, p) in model.vertices.iter().enumerate() {
        if !p.is_finite() {
            return fail(format!("vertex {i} has a non-finite coordinate ({p})"));
        }
    }
    let vertex_count = model.vertices.len();
    for (i, edge) in model.edges.iter().enumerate() {
        for v in [edge.start, edge.end] {
            if v >= vertex_count {
                return fail(format!("edge {i} refers to vertex {v}, but there are {vertex_count}"));
            }
        }
        let curve = &edge.curve;
        check_points(&curve.points).map_err(|m| Error::Input(format!("edge {i}: {m}")))?;
        check_knots("", curve.degree, &curve.knots, &curve.multiplicities, curve.points.len())
            .map_err(|m| Error::Input(format!("edge {i}: {m}")))?;
        let ends = [(curve.points[0], edge.start), (curve.points[curve.points.len() - 1], edge.end)];
        if let Some((p, v)) = ends.into_iter().find(|&(p, v)| p.distance(model.vertices[v]) > tolerance) {
            let gap = p.distance(model.vertices[v]);
            return fail(format!("edge {i}'s curve ends {gap:.3e} from its vertex {v}, more than the tolerance"));
        }
    }
    let edge_count = model.edges.len();
    for (i, face) in model.faces.iter().enumerate() {
        check_surface(&face.surface).map_err(|m| Error::Input(format!("face {i}: {m}")))?;
        if face.outer.is_empty() {
            return fail(format!("face {i} has no edges in its outer loop"));
        }
        if !face.outer_uv.is_empty() && face.outer_uv.len() != face.outer.len() {
            return fail(format!(
                "face {i} places {} of its {} edges on its surface",
                face.outer_uv.len(),
                face.outer.len()
            ));
        }
        if face.outer_uv.iter().flatten().flatten().any(|x| !x.is_finite()) {
            return fail(format!("face {i} places an edge at a non-finite parameter"));
        }
        if let Some(&(e, _)) = face.outer.iter().find(|&&(e, _)| e >= edge_count) {
            return fail(format!("face {i}'s loop refers to edge {e}, but there are {edge_count}"));
        }
        let ends = |(e, same_sense): (usize, bool)| {
            let edge = &model.edges[e];
            if same_sense { (edge.start, edge.end) } else { (edge.end, edge.start) }
        };
        for (k, &entry) in face.outer.iter().enumerate() {
            let next = face.outer[(k + 1) % face.outer.len()];
            if ends(entry).1 != ends(next).0 {
                return fail(format!(
                    "face {i}'s loop does not join: edge {} ends where edge {} does not start",
                    entry.0, next.0
                ));
            }
        }
    }
    let face_count = model.faces.len();
    for (i, shell) in model.shells.iter().enumerate() {
        if shell.faces.is_empty() {
            return fail(format!("shell {i} has no faces"));
        }
        if let Some(&f) = shell.faces.iter().find(|&&f| f >= face_count) {
            return fail(format!("shell {i} refers to face {f}, but there are {face_count}"));
        }
    }
    Ok(())
}

fn check_surface(surface: &BSplineSurface) -> Result<(), String> {
    let count_u = surface.points.len();
    let count_v = surface.points.first().map_or(0, Vec::len);
    if let Some(i) = surface.points.iter().position(|row| row.len() != count_v) {
        return Err(format!("control-point row {i} has {} points, row 0 has {count_v}", surface.points[i].len()));
    }
    for row in &surface.points {
        check_points(row)?;
    }
    let (knots_u, mults_u) = (&surface.knots_u, &surface.multiplicities_u);
    let (knots_v, mults_v) = (&surface.knots_v, &surface.multiplicities_v);
    check_knots("u ", surface.degree_u, knots_u, mults_u, count_u)?;
    check_knots("v ", surface.degree_v, knots_v, mults_v, count_v)
}

fn check_points(points: &[DVec3]) -> Result<(), String> {
    match points.iter().position(|p| !p.is_finite()) {
        Some(k) => Err(format!("control point {k} is not finite ({})", points[k])),
        None => Ok(()),
    }
}

/// A clamped knot vector: distinct increasing finite knots whose multiplicities (1 to
/// `degree + 1`) sum to `count + degree + 1`. `direction` is `""`, `"u "` or `"v "`.
fn check_knots(
    direction: &str,
    degree: usize,
    knots: &[f64],
    multiplicities: &[usize],
    count: usize,
) -> Result<(), String> {
    if degree == 0 || count <= degree {
        return Err(format!("{direction}degree {degree} with {count} control points"));
    }
    if knots.len() != multiplicities.len() || knots.len() < 2 {
        let (k, m) = (knots.len(), multiplicities.len());
        return Err(format!("{direction}{k} knots with {m} multiplicities"));
    }
    if let Some(k) = knots.iter().position(|x| !x.is_finite()) {
        return Err(format!("{direction}knot {k} is not finite ({})", knots[k]));
    }
    if let Some(k) = knots.windows(2).position(|pair| pair[0] >= pair[1]) {
        return Err(format!("{direction}knots do not increase at knot {}", k + 1));
    }
    if let Some(&m) = multiplicities.iter().find(|&&m| m == 0 || m > degree + 1) {
        return Err(format!("{direction}multiplicity {m} is outside 1..={}", degree + 1));
    }
    let sum: usize = multiplicities.iter().sum();
    if sum != count + degree + 1 {
        return Err(format!(
            "{direction}multiplicities sum to {sum}, but {count} control points of degree \
             {degree} need {}",
            count + degree + 1
        ));
    }
    Ok(())
}

#[cfg(test)]
#[path = "step_tests.rs"]
mod tests;
