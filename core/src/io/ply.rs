//! PLY import (Turk's Polygon File Format, the Stanford scans' format): ASCII, binary
//! little-endian and binary big-endian.
//!
//! The header declares elements with a count and their properties (scalars of the eight PLY
//! types, or lists with a count type and an item type). Taut reads the `vertex` element's `x`,
//! `y`, `z` (of any numeric type) and the `face` element's `vertex_indices` (or
//! `vertex_index`) list; every other element and property is read past according to its
//! declared type, so colours, normals, confidence values and extra elements do not matter.
//!
//! Hostile files: the header must end (`end_header`) within the file; each declared count is
//! checked against the bytes left before anything is allocated for it (a fixed-size element
//! needs its bytes present, a list element at least one count per item); every read is bounds
//! checked, so nothing beyond the declared sizes or the file's end is ever read; a negative list
//! length or vertex index, a non-finite coordinate, or a number that does not fit its type is an
//! error naming the element.

use super::soup::Soup;
use crate::{DVec3, Error, Result};
use std::path::Path;

/// Longest header accepted, in bytes.
const MAX_HEADER: usize = 1 << 20;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Encoding {
    Ascii,
    Little,
    Big,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Scalar {
    I8,
    U8,
    I16,
    U16,
    I32,
    U32,
    F32,
    F64,
}

impl Scalar {
    fn parse(name: &str) -> Option<Scalar> {
        Some(match name {
            "char" | "int8" => Scalar::I8,
            "uchar" | "uint8" => Scalar::U8,
            "short" | "int16" => Scalar::I16,
            "ushort" | "uint16" => Scalar::U16,
            "int" | "int32" => Scalar::I32,
            "uint" | "uint32" => Scalar::U32,
            "float" | "float32" => Scalar::F32,
            "double" | "float64" => Scalar::F64,
            _ => return None,
        })
    }

    fn size(self) -> usize {
        match self {
            Scalar::I8 | Scalar::U8 => 1,
            Scalar::I16 | Scalar::U16 => 2,
            Scalar::I32 | Scalar::U32 | Scalar::F32 => 4,
            Scalar::F64 => 8,
        }
    }
}

#[derive(Clone, Debug)]
enum Property {
    Scalar(String, Scalar),
    List(String, Scalar, Scalar),
}

#[derive(Clone, Debug)]
struct Element {
    name: String,
    count: usize,
    properties: Vec<Property>,
}

/// Reads a PLY file into a polygon soup (not yet welded).
pub(crate) fn read_ply(path: &Path) -> Result<Soup> {
    let bytes = super::file::read_regular_file(path)?;
    parse_ply(&bytes, path)
}

/// Parses PLY bytes; `origin` names the file in messages.
pub(crate) fn parse_ply(bytes: &[u8], origin: &Path) -> Result<Soup> {
    let fail = |m: String| Error::format(origin, m);
    if !bytes.starts_with(b"ply") {
        return Err(fail("not a PLY file: it does not start with the word 'ply'".into()));
    }
    let (encoding, elements, body) = parse_header(bytes).map_err(fail)?;
    let mut reader = Reader { bytes: &bytes[body..], at: 0, encoding };
    let mut soup = Soup::default();
    let mut seen_vertex = false;
    for element in &elements {
        let min_size: usize = element
            .properties
            .iter()
            .map(|p| match p {
                Property::Scalar(_, s) => s.size(),
                Property::List(_, c, _) => c.size(),
            })
            .sum::<usize>()
            .max(1);
        // In ASCII every value takes at least two bytes (a digit and a separator).
        let min_bytes = if encoding == Encoding::Ascii { 2 * element.properties.len().max(1) } else { min_size };
        if element.count > reader.left() / min_bytes {
            return Err(fail(format!(
                "truncated PLY: the header declares {} {} elements, more than the {} bytes left can hold",
                element.count,
                element.name,
                reader.left()
            )));
        }
        match element.name.as_str() {
            "vertex" if !seen_vertex => {
                seen_vertex = true;
                let slot = |axis: &str| {
                    element.properties.iter().position(|p| matches!(p, Property::Scalar(n, _) if n == axis))
                };
                let (Some(x), Some(y), Some(z)) = (slot("x"), slot("y"), slot("z")) else {
                    return Err(fail("the vertex element has no x, y and z properties".into()));
                };
                soup.positions.reserve(element.count);
                let mut values = vec![0.0; element.properties.len()];
                for v in 0..element.count {
                    for (k, p) in element.properties.iter().enumerate() {
                        values[k] = match p {
                            Property::Scalar(_, s) => reader.number(*s),
                            Property::List(_, c, i) => reader.skip_list(*c, *i).map(|_| 0.0),
                        }
                        .map_err(|m| fail(format!("vertex {v}: {m}")))?;
                    }
                    reader.end_record().map_err(|m| fail(format!("vertex {v}: {m}")))?;
                    let p = DVec3::new(values[x], values[y], values[z]);
                    if !p.is_finite() {
                        return Err(fail(format!(
                            "vertex {v} has a non-finite coordinate ({:?}); every coordinate must be a finite number",
                            p.to_array()
                        )));
                    }
                    soup.positions.push(p);
                }
            }
            "face" => {
                let list = element
                    .properties
                    .iter()
                    .position(|p| matches!(p, Property::List(n, _, _) if n == "vertex_indices" || n == "vertex_index"));
                let Some(list) = list else {
                    return Err(fail("the face element has no vertex_indices list".into()));
                };
                let mut short = 0usize;
                for f in 0..element.count {
                    for (k, p) in element.properties.iter().enumerate() {
                        let read = match p {
                            Property::Scalar(_, s) => reader.number(*s).map(|_| ()),
                            Property::List(_, c, i) if k == list => reader.index_list(*c, *i).map(|face| {
                                if face.len() >= 3 {
                                    soup.faces.push(face);
                                } else {
                                    short += 1;
                                }
                            }),
                            Property::List(_, c, i) => reader.skip_list(*c, *i),
                        };
                        read.map_err(|m| fail(format!("face {f}: {m}")))?;
                    }
                    reader.end_record().map_err(|m| fail(format!("face {f}: {m}")))?;
                }
                if short > 0 {
                    soup.warnings.push(format!("skipped {short} faces with fewer than 3 corners"));
                }
            }
            _ => {
                for e in 0..element.count {
                    for p in &element.properties {
                        match p {
                            Property::Scalar(_, s) => reader.number(*s).map(|_| ()),
                            Property::List(_, c, i) => reader.skip_list(*c, *i),
                        }
                        .map_err(|m| fail(format!("{} {e}: {m}", element.name)))?;
                    }
                    reader.end_record().map_err(|m| fail(format!("{} {e}: {m}", element.name)))?;
                }
            }
        }
    }
    if !seen_vertex {
        return Err(fail("the file declares no vertex element".into()));
    }
    Ok(soup)
}

/// The encoding, the elements and where the body starts.
fn parse_header(bytes: &[u8]) -> std::result::Result<(Encoding, Vec<Element>, usize), String> {
    let window = &bytes[..bytes.len().min(MAX_HEADER)];
    let marker = b"end_header";
    // The line that is `end_header` alone (a comment may mention the word).
    let end = window
        .windows(marker.len())
        .enumerate()
        .position(|(k, w)| {
            let after = window.get(k + marker.len());
            w == marker && k > 0 && window[k - 1] == b'\n' && matches!(after, None | Some(b'\n' | b'\r' | b' ' | b'\t'))
        })
        .ok_or("the header does not end: no 'end_header' line (or a header over 1 MiB)")?;
    // The body starts after the end of the end_header line.
    let mut body = end + marker.len();
    while body < bytes.len() && bytes[body] == b'\r' {
        body += 1;
    }
    if body < bytes.len() && bytes[body] == b'\n' {
        body += 1;
    }
    let text = std::str::from_utf8(&bytes[..end]).map_err(|_| "the header is not text")?;
    let mut encoding = None;
    let mut elements: Vec<Element> = Vec::new();
    for (k, line) in text.lines().enumerate().skip(1) {
        let line_no = k + 1;
        let words: Vec<&str> = line.split_whitespace().collect();
        match words.as_slice() {
            [] | ["comment", ..] | ["obj_info", ..] => {}
            ["format", kind, version] => {
                if !version.starts_with('1') {
                    return Err(format!("header line {line_no}: PLY version {version} is not supported (1.0 is)"));
                }
                encoding = Some(match *kind {
                    "ascii" => Encoding::Ascii,
                    "binary_little_endian" => Encoding::Little,
                    "binary_big_endian" => Encoding::Big,
                    other => return Err(format!("header line {line_no}: unknown format '{other}'")),
                });
            }
            ["element", name, count] => {
                let count = count
                    .parse::<usize>()
                    .map_err(|_| format!("header line {line_no}: element count '{count}' is not a count"))?;
                elements.push(Element { name: name.to_string(), count, properties: Vec::new() });
            }
            ["property", "list", count, item, name] => {
                let (Some(c), Some(i)) = (Scalar::parse(count), Scalar::parse(item)) else {
                    return Err(format!("header line {line_no}: unknown list types '{count} {item}'"));
                };
                if matches!(c, Scalar::F32 | Scalar::F64) {
                    return Err(format!("header line {line_no}: a list count must be an integer type, not {count}"));
                }
                let element =
                    elements.last_mut().ok_or(format!("header line {line_no}: a property before any element"))?;
                element.properties.push(Property::List(name.to_string(), c, i));
            }
            ["property", kind, name] => {
                let s = Scalar::parse(kind).ok_or(format!("header line {line_no}: unknown property type '{kind}'"))?;
                let element =
                    elements.last_mut().ok_or(format!("header line {line_no}: a property before any element"))?;
                element.properties.push(Property::Scalar(name.to_string(), s));
            }
            _ => return Err(format!("header line {line_no}: cannot read '{}'", line.trim())),
        }
    }
    let encoding = encoding.ok_or("the header has no 'format' line")?;
    Ok((encoding, elements, body))
}

/// Reads values from the body, never past its end.
struct Reader<'a> {
    bytes: &'a [u8],
    at: usize,
    encoding: Encoding,
}

impl Reader<'_> {
    fn left(&self) -> usize {
        self.bytes.len() - self.at
    }

    fn take(&mut self, n: usize) -> std::result::Result<&[u8], String> {
        if self.left() < n {
            return Err("the file ends early (truncated PLY)".into());
        }
        let out = &self.bytes[self.at..self.at + n];
        self.at += n;
        Ok(out)
    }

    /// In ASCII, one element is one line: after its values only spaces may follow before the
    /// line ends (a line with extra numbers would otherwise shift every later value).
    fn end_record(&mut self) -> std::result::Result<(), String> {
        if self.encoding != Encoding::Ascii {
            return Ok(());
        }
        while self.at < self.bytes.len() && matches!(self.bytes[self.at], b' ' | b'\t') {
            self.at += 1;
        }
        match self.bytes.get(self.at) {
            None | Some(b'\n' | b'\r') => Ok(()),
            Some(_) => Err("the line has more values than the header declares for this element".into()),
        }
    }

    fn word(&mut self) -> std::result::Result<&str, String> {
        while self.at < self.bytes.len() && self.bytes[self.at].is_ascii_whitespace() {
            self.at += 1;
        }
        let start = self.at;
        while self.at < self.bytes.len() && !self.bytes[self.at].is_ascii_whitespace() {
            self.at += 1;
        }
        if start == self.at {
            return Err("the file ends early (truncated PLY)".into());
        }
        std::str::from_utf8(&self.bytes[start..self.at]).map_err(|_| "a value is not text".to_string())
    }

    fn number(&mut self, s: Scalar) -> std::result::Result<f64, String> {
        if self.encoding == Encoding::Ascii {
            let word = self.word()?;
            let value: f64 = word.parse().map_err(|_| format!("cannot read '{word}' as a number"))?;
            let integer = !matches!(s, Scalar::F32 | Scalar::F64);
            if integer && value.fract() != 0.0 {
                return Err(format!("'{word}' is not an integer"));
            }
            return Ok(value);
        }
        let big = self.encoding == Encoding::Big;
        let raw = self.take(s.size())?;
        let mut b = [0u8; 8];
        b[..raw.len()].copy_from_slice(raw);
        if big {
            b[..raw.len()].reverse();
        }
        Ok(match s {
            Scalar::I8 => f64::from(b[0] as i8),
            Scalar::U8 => f64::from(b[0]),
            Scalar::I16 => f64::from(i16::from_le_bytes([b[0], b[1]])),
            Scalar::U16 => f64::from(u16::from_le_bytes([b[0], b[1]])),
            Scalar::I32 => f64::from(i32::from_le_bytes([b[0], b[1], b[2], b[3]])),
            Scalar::U32 => f64::from(u32::from_le_bytes([b[0], b[1], b[2], b[3]])),
            Scalar::F32 => f64::from(f32::from_le_bytes([b[0], b[1], b[2], b[3]])),
            Scalar::F64 => f64::from_le_bytes(b),
        })
    }

    /// A list length, checked against the bytes left.
    fn length(&mut self, count: Scalar, item: Scalar) -> std::result::Result<usize, String> {
        let n = self.number(count)?;
        if n < 0.0 {
            return Err(format!("a list has a negative length ({n})"));
        }
        let n = n as usize;
        let item_bytes = if self.encoding == Encoding::Ascii { 2 } else { item.size() };
        if n > self.left() / item_bytes + 1 {
            return Err(format!("a list of {n} values is longer than the rest of the file (truncated PLY)"));
        }
        Ok(n)
    }

    fn skip_list(&mut self, count: Scalar, item: Scalar) -> std::result::Result<(), String> {
        let n = self.length(count, item)?;
        for _ in 0..n {
            self.number(item)?;
        }
        Ok(())
    }

    fn index_list(&mut self, count: Scalar, item: Scalar) -> std::result::Result<Vec<u32>, String> {
        let n = self.length(count, item)?;
        let mut face = Vec::with_capacity(n);
        for _ in 0..n {
            let v = self.number(item)?;
            if !(0.0..u32::MAX as f64).contains(&v) || v.fract() != 0.0 {
                return Err(format!("vertex index {v} is not a valid index"));
            }
            face.push(v as u32);
        }
        Ok(face)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(bytes: &[u8]) -> Result<Soup> {
        parse_ply(bytes, Path::new("t.ply"))
    }

    #[test]
    fn ascii_with_extra_properties_and_elements() {
        let text = "ply\r\nformat ascii 1.0\r\ncomment made by hand\r\nelement vertex 4\r\nproperty float x\r\n\
                    property uchar red\r\nproperty float y\r\nproperty double z\r\nelement face 2\r\n\
                    property list uchar int vertex_indices\r\nproperty list uchar float texcoord\r\nelement edge 1\r\n\
                    property int vertex1\r\nproperty int vertex2\r\nend_header\r\n\
                    0 255 0 0\r\n1 0 0 0\r\n1 7 1 0.5\r\n0 0 1 0\r\n3 0 1 2 2 0.5 0.5\r\n4 0 2 3 1 0\r\n0 1\r\n";
        let soup = parse(text.as_bytes()).unwrap();
        assert_eq!(soup.positions[2], DVec3::new(1.0, 1.0, 0.5));
        assert_eq!(soup.faces.to_vecs(), vec![vec![0, 1, 2], vec![0, 2, 3, 1]]);
    }

    #[test]
    fn big_endian_binary_with_short_types() {
        let mut bytes = b"ply\nformat binary_big_endian 1.0\nelement vertex 3\nproperty short x\nproperty short y\n\
                          property short z\nelement face 1\nproperty list uchar ushort vertex_index\nend_header\n"
            .to_vec();
        for v in [[0i16, 0, 0], [-2, 0, 0], [0, 3, 1]] {
            bytes.extend(v.iter().flat_map(|c| c.to_be_bytes()));
        }
        bytes.push(3);
        bytes.extend([0u16, 2, 1].iter().flat_map(|c| c.to_be_bytes()));
        let soup = parse(&bytes).unwrap();
        assert_eq!(soup.positions, vec![DVec3::ZERO, DVec3::new(-2.0, 0.0, 0.0), DVec3::new(0.0, 3.0, 1.0)]);
        assert_eq!(soup.faces.to_vecs(), vec![vec![0, 2, 1]]);
    }

    #[test]
    fn end_header_in_a_comment_does_not_end_the_header() {
        let text = "ply\nformat ascii 1.0\ncomment written by a tool; see end_header below\nelement vertex 3\n\
                    property float x\nproperty float y\nproperty float z\nelement face 1\n\
                    property list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
        let soup = parse(text.as_bytes()).unwrap();
        assert_eq!(soup.positions.len(), 3);
        assert_eq!(soup.positions[1], DVec3::new(1.0, 0.0, 0.0));
        assert_eq!(soup.faces.len(), 1);
    }

    #[test]
    fn an_ascii_line_with_extra_numbers_is_refused() {
        let text = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n\
                    element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0 7\n1 0 0\n0 1 0\n3 0 1 2\n";
        let err = parse(text.as_bytes()).unwrap_err().to_string();
        assert!(err.contains("vertex 0") && err.contains("more values than the header declares"), "{err}");
    }

    #[test]
    fn damaged_files_are_named_errors() {
        let head = |body: &str| format!("ply\nformat ascii 1.0\n{body}");
        let cases: Vec<(String, &str)> = vec![
            ("obj".into(), "does not start with the word 'ply'"),
            ("ply\nformat ascii 1.0\nelement vertex 3\n".into(), "no 'end_header'"),
            (head("element vertex 99999999999\nproperty float x\nend_header\n0\n"), "declares 99999999999 vertex"),
            (head("element vertex 1\nproperty float x\nproperty float y\nend_header\n0 0\n"), "no x, y and z"),
            (
                head("element vertex 1\nproperty float x\nproperty float y\nproperty float z\nend_header\n0 0\n"),
                "truncated",
            ),
            (
                head("element vertex 1\nproperty float x\nproperty float y\nproperty float z\nend_header\n0 nan 0\n"),
                "non-finite",
            ),
            (head("element vertex 1\nproperty weird x\nend_header\n"), "unknown property type 'weird'"),
            ("ply\nformat binary_middle_endian 1.0\nend_header\n".into(), "unknown format"),
            ("ply\nelement vertex 0\nend_header\n".into(), "no 'format' line"),
            (
                head(
                    "element vertex 1\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n3 0 -1 2\n",
                ),
                "face 0: vertex index -1",
            ),
            (
                head(
                    "element vertex 1\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list int int vertex_indices\nend_header\n0 0 0\n-3 0 1 2\n",
                ),
                "negative length",
            ),
            (
                head(
                    "element vertex 1\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uint int vertex_indices\nend_header\n0 0 0\n4000000000 0\n",
                ),
                "longer than the rest of the file",
            ),
        ];
        for (text, expected) in cases {
            let err = parse(text.as_bytes()).unwrap_err().to_string();
            assert!(err.starts_with("t.ply: ") && err.contains(expected), "expected '{expected}' in: {err}");
        }
    }
}
