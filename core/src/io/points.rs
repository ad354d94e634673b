//! Point-sequence files: JSON and CSV, for the curve commands.
//!
//! - JSON: `{"points": [[x, y], ...]}` or `[[x, y, z], ...]`, optionally `"closed": true`;
//!   other keys are ignored, so the output of one curve command can be the input of another.
//! - CSV: one point per row, `x,y` or `x,y,z`; an optional first row of column names (any row
//!   whose fields are not all numbers is taken as the header if it is the first, and refused
//!   otherwise); blank lines are skipped; spaces around fields are allowed. Every row must have
//!   the same number of columns.
//!
//! 2D points get z = 0 and the file remembers it had two coordinates, so they are written back
//! with two.

use crate::{DVec3, Error, Result};
use std::path::Path;

/// Points read from a file.
#[derive(Clone, Debug, PartialEq)]
pub struct PointFile {
    /// The points (z = 0 for 2D files).
    pub points: Vec<DVec3>,
    /// 2 or 3: the coordinates per point in the file.
    pub dimension: usize,
    /// True when a JSON file said `"closed": true`.
    pub closed: bool,
}

/// Reads a point file by its extension (`.json` or `.csv`, any case).
pub fn read_points(path: &Path) -> Result<PointFile> {
    let text = super::file::read_regular_text(path)?;
    match extension(path).as_str() {
        "json" => parse_json(&text, path),
        "csv" => parse_csv(&text, path),
        other => Err(Error::format(
            path,
            format!(
                "{} is not a point file format; use .json ({{\"points\": [[x, y], ...]}}) or .csv (x,y or x,y,z rows)",
                if other.is_empty() { "a name without extension".to_string() } else { format!("'.{other}'") }
            ),
        )),
    }
}

fn extension(path: &Path) -> String {
    path.extension().and_then(|e| e.to_str()).unwrap_or("").to_ascii_lowercase()
}

/// Parses JSON point text; `origin` names the source in messages.
pub fn parse_json(text: &str, origin: &Path) -> Result<PointFile> {
    #[derive(serde::Deserialize)]
    struct File {
        points: Vec<Vec<f64>>,
        #[serde(default)]
        closed: bool,
    }
    let file: File = serde_json::from_str(text)
        .map_err(|e| Error::format(origin, format!("not a valid point file ({{\"points\": [[x, y], ...]}}): {e}")))?;
    let dimension = file.points.first().map_or(2, |p| p.len());
    let mut points = Vec::with_capacity(file.points.len());
    for (i, p) in file.points.iter().enumerate() {
        if p.len() != dimension || !(2..=3).contains(&p.len()) {
            return Err(Error::format(
                origin,
                format!("point {i} has {} coordinates; every point needs the same 2 or 3", p.len()),
            ));
        }
        points.push(DVec3::new(p[0], p[1], p.get(2).copied().unwrap_or(0.0)));
    }
    Ok(PointFile { points, dimension, closed: file.closed })
}

/// Parses CSV point text (see the module documentation); `origin` names the source.
pub fn parse_csv(text: &str, origin: &Path) -> Result<PointFile> {
    let mut reader =
        csv::ReaderBuilder::new().has_headers(false).flexible(true).trim(csv::Trim::All).from_reader(text.as_bytes());
    let mut points = Vec::new();
    let mut dimension = 0;
    for (row, record) in reader.records().enumerate() {
        let record = record.map_err(|e| Error::format(origin, format!("row {}: {e}", row + 1)))?;
        if record.iter().all(|f| f.is_empty()) {
            continue;
        }
        let values: Vec<Option<f64>> = record.iter().map(|f| f.parse::<f64>().ok()).collect();
        if values.iter().any(|v| v.is_none()) {
            if row == 0 {
                continue; // the header
            }
            let field = record.iter().zip(&values).find(|(_, v)| v.is_none()).map_or("", |(f, _)| f);
            return Err(Error::format(origin, format!("row {}: '{field}' is not a number", row + 1)));
        }
        if dimension == 0 {
            dimension = values.len();
        }
        if values.len() != dimension || !(2..=3).contains(&values.len()) {
            return Err(Error::format(
                origin,
                format!("row {} has {} columns; every row needs the same 2 (x,y) or 3 (x,y,z)", row + 1, values.len()),
            ));
        }
        let v: Vec<f64> = values.into_iter().flatten().collect();
        points.push(DVec3::new(v[0], v[1], v.get(2).copied().unwrap_or(0.0)));
    }
    Ok(PointFile { points, dimension: dimension.max(2), closed: false })
}

/// The points as CSV text with `dimension` (2 or 3) columns and a header.
pub fn to_csv(points: &[DVec3], dimension: usize) -> String {
    let mut out = String::from(if dimension == 2 { "x,y\n" } else { "x,y,z\n" });
    for p in points {
        if dimension == 2 {
            out.push_str(&format!("{},{}\n", p.x, p.y));
        } else {
            out.push_str(&format!("{},{},{}\n", p.x, p.y, p.z));
        }
    }
    out
}

/// The points as JSON arrays of `dimension` (2 or 3) coordinates.
pub fn to_json_arrays(points: &[DVec3], dimension: usize) -> Vec<Vec<f64>> {
    points.iter().map(|p| p.to_array()[..dimension.clamp(2, 3)].to_vec()).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn csv_with_and_without_header() {
        let here = Path::new("t.csv");
        let a = parse_csv("x, y\n0, 1\n\n2.5,-3\n", here).unwrap();
        assert_eq!((a.points, a.dimension), (vec![DVec3::new(0.0, 1.0, 0.0), DVec3::new(2.5, -3.0, 0.0)], 2));
        let b = parse_csv("1,2,3\n4,5,6\n", here).unwrap();
        assert_eq!((b.points.len(), b.dimension, b.points[1].z), (2, 3, 6.0));
        assert!(parse_csv("1,2\n3,oops\n", here).unwrap_err().to_string().contains("row 2: 'oops'"));
        assert!(parse_csv("1,2\n3,4,5\n", here).unwrap_err().to_string().contains("row 2 has 3 columns"));
        assert!(parse_csv("1\n2\n", here).is_err());
        let round = parse_csv(&to_csv(&b.points, 3), here).unwrap();
        assert_eq!(round.points, b.points);
    }

    #[test]
    fn json_points() {
        let here = Path::new("t.json");
        let a = parse_json(r#"{"points": [[0, 1], [2, 3]], "closed": true, "alpha": 1}"#, here).unwrap();
        assert!(a.closed && a.dimension == 2 && a.points[1] == DVec3::new(2.0, 3.0, 0.0));
        assert!(parse_json(r#"{"points": [[0, 1], [2, 3, 4]]}"#, here).unwrap_err().to_string().contains("point 1"));
        assert!(parse_json(r#"{"points": [[0, 1], [2, "x"]]}"#, here).is_err());
        assert!(parse_json("[1, 2]", here).is_err());
    }
}
