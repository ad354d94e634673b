//! glTF 2.0 import: reading every triangle of a scene (`.gltf` with external or embedded
//! buffers, and `.glb`). Writing is in [`glb`](super::glb).
//!
//! The `gltf` crate parses the container and the JSON into its typed `json::Root`; everything
//! after that is read here with every index and byte range checked, because the crate's own
//! validation and accessor readers index arrays directly and panic on hostile files (an
//! attribute naming a missing accessor, an accessor with count 0, a GLB header shorter than
//! itself, a percent-encoded URI that is not UTF-8). Meshes are placed by their nodes'
//! transforms, accumulated down the hierarchy (glTF 2.0 spec §3.5); a node whose transform
//! mirrors (negative determinant) has its triangles' winding reversed so the orientation stays
//! consistent. Triangle strips and fans are converted to triangles (spec §3.7.2.1).
//!
//! glTF is Y up (spec §3.4); positions are turned into Taut's Z-up axes as they are read.
//! External buffers are read only from relative URIs that stay inside the `.gltf` file's own
//! folder once links are followed, only from regular files, and never beyond the declared
//! `byteLength` (a shorter file is an error). Images are never read. A file that requires any
//! extension (`extensionsRequired`) is refused, naming it: the spec says such a file cannot be
//! loaded correctly without it.
//!
//! Weak spots: sparse, quantized and compressed (Draco, meshopt) geometry is refused; morph
//! targets and skins are ignored (the rest pose is read); f32 storage rounds positions.

use super::UpAxis;
use super::soup::Soup;
use crate::{DVec3, Error, Result};
use ::gltf::json::accessor::{ComponentType, GenericComponentType, Type};
use ::gltf::json::mesh::{Mode, Semantic};
use ::gltf::json::validation::Checked;
use ::gltf::json::{self, Index};
use glam::{DMat3, DMat4, DQuat};
use std::borrow::Cow;
use std::cell::OnceCell;
use std::path::Path;

/// Extensions that change how geometry is stored, named in the refusal so the designer knows what
/// to turn off when exporting again.
const GEOMETRY_EXTENSIONS: [&str; 3] =
    ["KHR_draco_mesh_compression", "EXT_meshopt_compression", "KHR_mesh_quantization"];

/// Reads a `.gltf` or `.glb` file into a polygon soup (not yet welded).
pub(crate) fn read_gltf(path: &Path) -> Result<Soup> {
    let bytes = super::file::read_regular_file(path)?;
    let binary = path.extension().is_some_and(|e| e.eq_ignore_ascii_case("glb"));
    parse_gltf(&bytes, path, binary)
}

/// Parses glTF bytes; `origin` names the file in messages and locates external buffers.
/// `binary` demands the GLB container (a `.glb` file); otherwise either form is accepted.
pub(crate) fn parse_gltf(bytes: &[u8], origin: &Path, binary: bool) -> Result<Soup> {
    let fail = |m: String| Error::format(origin, m);
    if bytes.is_empty() {
        return Err(fail("the file is empty".into()));
    }
    let (json_bytes, blob) = if bytes.starts_with(b"glTF") {
        split_glb(bytes).map_err(fail)?
    } else if binary {
        return Err(fail("not a binary glTF file: it does not start with the bytes 'glTF'".into()));
    } else {
        (Cow::Borrowed(bytes.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(bytes)), None)
    };
    let root = json::Root::from_slice(&json_bytes).map_err(|e| fail(format!("not a glTF 2.0 file: {e}")))?;
    if root.asset.version.split('.').next() != Some("2") {
        return Err(fail(format!("glTF version {} is not supported; Taut reads glTF 2.0", root.asset.version)));
    }
    let mut soup = Soup::default();
    if let Some(ext) = root.extensions_required.first() {
        let advice = if GEOMETRY_EXTENSIONS.contains(&ext.as_str()) {
            "export it again without mesh compression or quantization"
        } else {
            "export it again without that extension"
        };
        return Err(fail(format!("the file requires the glTF extension {ext}, which Taut does not support; {advice}")));
    }
    let buffers = (0..root.buffers.len()).map(|_| OnceCell::new()).collect();
    let reader = Reader { origin, document: ::gltf::Document::from_json_without_validation(root), blob, buffers };
    reader.read(&mut soup)?;
    Ok(soup)
}

/// The JSON chunk and the optional binary chunk of a GLB file.
type GlbChunks<'a> = (Cow<'a, [u8]>, Option<Vec<u8>>);

/// Checks a GLB header by hand (the crate subtracts before checking) and splits the chunks.
fn split_glb(bytes: &[u8]) -> std::result::Result<GlbChunks<'_>, String> {
    let word = |k: usize| u32::from_le_bytes([bytes[k], bytes[k + 1], bytes[k + 2], bytes[k + 3]]) as usize;
    if bytes.len() < 20 {
        return Err(format!("truncated binary glTF: {} bytes is too short for a header and a JSON chunk", bytes.len()));
    }
    let (version, length) = (word(4), word(8));
    if version != 2 {
        return Err(format!("binary glTF version {version} is not supported; Taut reads version 2"));
    }
    if length < 20 {
        return Err(format!("invalid binary glTF: its header gives a total length of {length} bytes"));
    }
    if length > bytes.len() {
        return Err(format!(
            "truncated binary glTF: the header announces {length} bytes but the file has {}",
            bytes.len()
        ));
    }
    match ::gltf::binary::Glb::from_slice(&bytes[..length]) {
        Ok(glb) => {
            // Some writers pad the JSON chunk with NULs instead of spaces; JSON parsers refuse them.
            let json = match glb.json {
                Cow::Borrowed(j) => Cow::Borrowed(&j[..j.iter().rposition(|&b| b != 0).map_or(0, |k| k + 1)]),
                owned => owned,
            };
            Ok((json, glb.bin.map(Cow::into_owned)))
        }
        Err(::gltf::Error::Binary(::gltf::binary::Error::ChunkLength { .. })) => {
            Err("truncated binary glTF: a chunk is longer than the data left in the file".into())
        }
        Err(e) => Err(format!("invalid binary glTF: {e}")),
    }
}

/// The parsed document, with its buffers loaded on first use.
struct Reader<'a> {
    origin: &'a Path,
    document: ::gltf::Document,
    blob: Option<Vec<u8>>,
    buffers: Vec<OnceCell<Vec<u8>>>,
}

/// A mesh placed in the scene by a node.
struct Instance {
    node: Option<usize>,
    mesh: usize,
    world_from_mesh: DMat4,
}

/// The bytes of an accessor's elements, checked to lie inside its buffer view.
struct Elements<'d> {
    data: &'d [u8],
    stride: usize,
    count: usize,
    component: ComponentType,
}

impl Elements<'_> {
    fn element(&self, k: usize) -> &[u8] {
        &self.data[k * self.stride..]
    }
}

impl Reader<'_> {
    fn root(&self) -> &json::Root {
        self.document.as_json()
    }

    fn fail(&self, message: impl Into<String>) -> Error {
        Error::format(self.origin, message)
    }

    fn read(&self, soup: &mut Soup) -> Result<()> {
        let instances = self.instances()?;
        if instances.is_empty() && !self.root().meshes.is_empty() {
            soup.warnings.push(format!("the scene shows none of the file's {} meshes", self.root().meshes.len()));
        }
        for instance in &instances {
            let mesh = self.root().meshes.get(instance.mesh).ok_or_else(|| {
                self.fail(format!(
                    "node {} refers to mesh {}, which does not exist",
                    instance.node.unwrap_or(0),
                    instance.mesh
                ))
            })?;
            for p in 0..mesh.primitives.len() {
                let name = mesh.name.as_deref().map_or(String::new(), |n| format!(" '{n}'"));
                let label = format!("mesh {}{name} primitive {p}", instance.mesh);
                self.read_primitive(&mesh.primitives[p], instance, &label, soup)?;
            }
        }
        Ok(())
    }

    /// The meshes to read with their placement: the default scene, else every scene, else
    /// (no scenes at all) every mesh as it is.
    fn instances(&self) -> Result<Vec<Instance>> {
        let root = self.root();
        let scenes: Vec<usize> = match root.scene {
            Some(s) if s.value() < root.scenes.len() => vec![s.value()],
            Some(s) => return Err(self.fail(format!("the default scene {s} does not exist"))),
            None if root.scenes.is_empty() => {
                let all =
                    (0..root.meshes.len()).map(|mesh| Instance { node: None, mesh, world_from_mesh: DMat4::IDENTITY });
                return Ok(all.collect());
            }
            None => (0..root.scenes.len()).collect(),
        };
        let mut out = Vec::new();
        for s in scenes {
            // glTF nodes form disjoint trees: a node seen twice means a cycle or two parents.
            let mut visited = vec![false; root.nodes.len()];
            let mut stack: Vec<(Index<json::Node>, DMat4)> =
                root.scenes[s].nodes.iter().rev().map(|&n| (n, DMat4::IDENTITY)).collect();
            while let Some((n, parent)) = stack.pop() {
                let node = root
                    .get(n)
                    .ok_or_else(|| self.fail(format!("scene {s} refers to node {n}, which does not exist")))?;
                if std::mem::replace(&mut visited[n.value()], true) {
                    return Err(self.fail(format!(
                        "node {n} appears twice in the hierarchy of scene {s} (a cycle, or a node with two parents), which glTF forbids"
                    )));
                }
                let local = local_transform(node).map_err(|m| self.fail(format!("node {n}: {m}")))?;
                let world = parent * local;
                if let Some(mesh) = node.mesh {
                    out.push(Instance { node: Some(n.value()), mesh: mesh.value(), world_from_mesh: world });
                }
                for &child in node.children.iter().flatten().rev() {
                    stack.push((child, world));
                }
            }
        }
        Ok(out)
    }

    fn read_primitive(
        &self,
        primitive: &json::mesh::Primitive,
        at: &Instance,
        label: &str,
        soup: &mut Soup,
    ) -> Result<()> {
        let mode = match primitive.mode {
            Checked::Valid(mode) => mode,
            Checked::Invalid => return Err(self.fail(format!("{label} has an invalid mode"))),
        };
        if matches!(mode, Mode::Points | Mode::Lines | Mode::LineLoop | Mode::LineStrip) {
            soup.warnings.push(format!("skipped {label}: its {mode:?} are not a surface"));
            return Ok(());
        }
        let Some(&position_accessor) = primitive.attributes.get(&Checked::Valid(Semantic::Positions)) else {
            return Err(self.fail(format!("{label} has no POSITION attribute")));
        };
        let positions = self.read_positions(position_accessor.value(), label)?;
        let indices = match primitive.indices {
            Some(a) => self.read_indices(a.value(), label)?,
            None => (0..positions.len() as u32).collect(),
        };
        if let Some(&bad) = indices.iter().find(|&&i| i as usize >= positions.len()) {
            return Err(
                self.fail(format!("{label}: index {bad} refers to a vertex beyond its {} positions", positions.len()))
            );
        }
        let determinant = DMat3::from_mat4(at.world_from_mesh).determinant();
        if !determinant.is_finite() {
            return Err(self.fail(format!("{label}: its accumulated node transform overflows")));
        }
        if determinant == 0.0 {
            let node = at.node.map_or(String::new(), |n| format!(" at node {n}"));
            soup.warnings.push(format!("skipped {label}{node}: its transform flattens it (zero scale)"));
            return Ok(());
        }
        let base = soup.positions.len();
        if base + positions.len() >= u32::MAX as usize / 2 {
            return Err(self.fail("the file has more vertices than Taut can index"));
        }
        for (k, p) in positions.iter().enumerate() {
            let q = UpAxis::Y.to_taut(at.world_from_mesh.transform_point3(*p));
            if !q.is_finite() {
                return Err(self.fail(format!(
                    "{label}: vertex {k} has a non-finite coordinate ({:?}) once placed",
                    q.to_array()
                )));
            }
            soup.positions.push(q);
        }
        if mode == Mode::Triangles && indices.len() % 3 != 0 {
            return Err(self.fail(format!(
                "{label} draws triangles from {} indices, which is not a multiple of 3",
                indices.len()
            )));
        }
        let triangles = triangles(mode, &indices);
        let mirrored = determinant < 0.0;
        for [a, b, c] in triangles {
            let [a, b, c] = [a, b, c].map(|i| base as u32 + i);
            soup.faces.push(if mirrored { [a, c, b] } else { [a, b, c] });
        }
        Ok(())
    }

    fn read_positions(&self, accessor: usize, label: &str) -> Result<Vec<DVec3>> {
        let what = format!("{label}: POSITION accessor {accessor}");
        let e = self.elements(accessor, Type::Vec3, &what)?;
        if e.component != ComponentType::F32 {
            return Err(self.fail(format!("{what} stores {:?} values; Taut reads float positions only", e.component)));
        }
        let f =
            |b: &[u8], k: usize| f64::from(f32::from_le_bytes([b[4 * k], b[4 * k + 1], b[4 * k + 2], b[4 * k + 3]]));
        Ok((0..e.count).map(|k| e.element(k)).map(|b| DVec3::new(f(b, 0), f(b, 1), f(b, 2))).collect())
    }

    fn read_indices(&self, accessor: usize, label: &str) -> Result<Vec<u32>> {
        let what = format!("{label}: index accessor {accessor}");
        let e = self.elements(accessor, Type::Scalar, &what)?;
        let read: fn(&[u8]) -> u32 = match e.component {
            ComponentType::U8 => |b| u32::from(b[0]),
            ComponentType::U16 => |b| u32::from(u16::from_le_bytes([b[0], b[1]])),
            ComponentType::U32 => |b| u32::from_le_bytes([b[0], b[1], b[2], b[3]]),
            other => {
                return Err(self.fail(format!("{what} stores {other:?} values; indices must be unsigned integers")));
            }
        };
        Ok((0..e.count).map(|k| read(e.element(k))).collect())
    }

    /// Locates an accessor's elements, checking its type and every byte range.
    fn elements(&self, index: usize, want: Type, what: &str) -> Result<Elements<'_>> {
        let accessor = self.root().accessors.get(index).ok_or_else(|| self.fail(format!("{what} does not exist")))?;
        if accessor.sparse.is_some() {
            return Err(self.fail(format!("{what} is sparse, which Taut does not read")));
        }
        let (Checked::Valid(ty), Checked::Valid(GenericComponentType(component))) =
            (accessor.type_, accessor.component_type)
        else {
            return Err(self.fail(format!("{what} has an invalid type or component type")));
        };
        if ty != want {
            return Err(self.fail(format!("{what} has type {ty:?}, expected {want:?}")));
        }
        let size = ty.multiplicity() * component.size();
        let count = usize::try_from(accessor.count.0).unwrap_or(usize::MAX);
        let view_index = accessor.buffer_view.ok_or_else(|| self.fail(format!("{what} has no buffer view")))?;
        let view = self
            .root()
            .get(view_index)
            .ok_or_else(|| self.fail(format!("{what} refers to buffer view {view_index}, which does not exist")))?;
        let stride = view.byte_stride.map_or(size, |s| s.0);
        if stride < size {
            return Err(self.fail(format!(
                "buffer view {view_index} has a stride of {stride} bytes, less than the {size}-byte elements of {what}"
            )));
        }
        let bytes = self.view_bytes(view_index, view)?;
        let offset = usize::try_from(accessor.byte_offset.map_or(0, |o| o.0)).unwrap_or(usize::MAX);
        let end = if count == 0 {
            Some(offset)
        } else {
            (count - 1).checked_mul(stride).and_then(|n| n.checked_add(size)).and_then(|n| n.checked_add(offset))
        };
        match end {
            Some(end) if end <= bytes.len() => Ok(Elements { data: &bytes[offset..end], stride, count, component }),
            _ => Err(self.fail(format!(
                "{what} ({count} elements from byte {offset}) runs past the end of buffer view {view_index} ({} bytes)",
                bytes.len()
            ))),
        }
    }

    fn view_bytes(&self, index: Index<json::buffer::View>, view: &json::buffer::View) -> Result<&[u8]> {
        let data = self.buffer(view.buffer.value())?;
        let offset = usize::try_from(view.byte_offset.map_or(0, |o| o.0)).unwrap_or(usize::MAX);
        let length = usize::try_from(view.byte_length.0).unwrap_or(usize::MAX);
        match offset.checked_add(length) {
            Some(end) if end <= data.len() => Ok(&data[offset..end]),
            _ => Err(self.fail(format!(
                "buffer view {index} (bytes {offset} to {offset}+{length}) runs past the end of buffer {} ({} bytes)",
                view.buffer,
                data.len()
            ))),
        }
    }

    fn buffer(&self, index: usize) -> Result<&[u8]> {
        let cell = self.buffers.get(index).ok_or_else(|| self.fail(format!("buffer {index} does not exist")))?;
        if cell.get().is_none() {
            let _ = cell.set(self.load_buffer(index)?);
        }
        Ok(cell.get().map_or(&[][..], Vec::as_slice))
    }

    fn load_buffer(&self, index: usize) -> Result<Vec<u8>> {
        let buffer = &self.root().buffers[index];
        let data = match buffer.uri.as_deref() {
            None => match (&self.blob, index) {
                (Some(blob), 0) => blob.clone(),
                _ => {
                    return Err(self.fail(format!("buffer {index} has no uri and the file has no binary chunk for it")));
                }
            },
            Some(uri) if uri.starts_with("data:") => {
                let source = self.document.buffers().nth(index).map(|b| b.source());
                let decoded = source.map(|s| ::gltf::buffer::Data::from_source(s, None));
                match decoded {
                    Some(Ok(data)) => data.0,
                    Some(Err(e)) => return Err(self.fail(format!("buffer {index}: cannot decode its data: URI ({e})"))),
                    None => return Err(self.fail(format!("buffer {index} does not exist"))),
                }
            }
            Some(uri) if uri.contains(':') => {
                return Err(self.fail(format!(
                    "buffer {index} refers to '{uri}'; Taut reads buffers from relative file paths and data: URIs only"
                )));
            }
            Some(uri) => {
                let relative = percent_decode(uri).ok_or_else(|| {
                    self.fail(format!("buffer {index} refers to '{uri}', which is not a valid percent-encoded path"))
                })?;
                let folder = self.origin.parent().unwrap_or(Path::new(""));
                let file = super::file::resolve_inside(folder, &relative).map_err(|why| {
                    self.fail(format!("buffer {index} refers to '{uri}', which Taut will not read: {why}"))
                })?;
                let declared = buffer.byte_length.0;
                return super::file::read_regular_prefix(&file, declared).map_err(|e| {
                    let why = match e {
                        Error::Format { message, .. } => message,
                        other => other.to_string(),
                    };
                    self.fail(format!("buffer {index} refers to '{uri}', which cannot be read: {why}"))
                });
            }
        };
        let declared = buffer.byte_length.0;
        if (data.len() as u64) < declared {
            return Err(self.fail(format!(
                "buffer {index} has {} bytes but the file declares {declared} (truncated?)",
                data.len()
            )));
        }
        Ok(data)
    }
}

/// A node's own transform: its matrix, or translation · rotation · scale (spec §3.5.2).
fn local_transform(node: &json::Node) -> std::result::Result<DMat4, String> {
    let m = match node.matrix {
        Some(m) => DMat4::from_cols_array(&m.map(f64::from)),
        None => {
            let t = node.translation.map_or(DVec3::ZERO, |t| DVec3::from_array(t.map(f64::from)));
            let s = node.scale.map_or(DVec3::ONE, |s| DVec3::from_array(s.map(f64::from)));
            let r = node.rotation.map_or(DQuat::IDENTITY, |q| DQuat::from_array(q.0.map(f64::from)));
            let length = r.length();
            if !(length.is_finite() && length > 0.0) {
                return Err(format!("its rotation quaternion {:?} cannot be normalised", r.to_array()));
            }
            DMat4::from_scale_rotation_translation(s, r / length, t)
        }
    };
    if m.is_finite() { Ok(m) } else { Err("its transform has a non-finite entry".into()) }
}

/// The triangles a primitive draws (spec §3.7.2.1); strips and fans skip their degenerate
/// connecting triangles.
fn triangles(mode: Mode, v: &[u32]) -> Vec<[u32; 3]> {
    let distinct = |t: &[u32; 3]| t[0] != t[1] && t[1] != t[2] && t[0] != t[2];
    match mode {
        Mode::TriangleStrip => (0..v.len().saturating_sub(2))
            .map(|i| if i % 2 == 0 { [v[i], v[i + 1], v[i + 2]] } else { [v[i], v[i + 2], v[i + 1]] })
            .filter(distinct)
            .collect(),
        Mode::TriangleFan => {
            (0..v.len().saturating_sub(2)).map(|i| [v[i + 1], v[i + 2], v[0]]).filter(distinct).collect()
        }
        _ => v.chunks_exact(3).map(|t| [t[0], t[1], t[2]]).collect(),
    }
}

/// Decodes `%XX` escapes in a relative URI; `None` when malformed or not UTF-8.
fn percent_decode(uri: &str) -> Option<String> {
    let mut out = Vec::with_capacity(uri.len());
    let mut rest = uri.as_bytes();
    while let Some((&b, tail)) = rest.split_first() {
        if b == b'%' {
            let hex = std::str::from_utf8(tail.get(..2)?).ok()?;
            out.push(u8::from_str_radix(hex, 16).ok()?);
            rest = &tail[2..];
        } else {
            out.push(b);
            rest = tail;
        }
    }
    String::from_utf8(out).ok()
}

#[cfg(test)]
#[path = "gltf_tests.rs"]
mod tests;
