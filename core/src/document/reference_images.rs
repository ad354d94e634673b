//! Reference images: pictures (PNG or JPEG) a designer models over, placed on the front, side or
//! top plane or facing the camera, as Alias's canvas planes, Rhino's Picture and Blender's
//! reference images are.
//!
//! The document holds where each image is and how it is drawn, never its pixels: the file is
//! named by a path relative to the `.taut` file's folder, `/`-separated so a document moves
//! between systems with its pictures beside it. A document is a file others send, so a path is
//! also a way to make Taut read something: [`ReferenceImage::resolve`] is the one way to the file,
//! and it refuses an absolute path, a `..` that climbs out of the document's folder and a link
//! that leads out of it, each with one line saying why. A refused or missing image stays in the
//! document (the designer sees it listed and can fix or remove it); it is only not read.
//!
//! In the `.taut` file the images are the optional key `reference_images`, a list of
//! `{"path", "plane", "centre", "width", "rotation", "opacity", "in_front", "visible"}`, absent when
//! there are none (so files without images are as before, and version 2 is kept).

use crate::{DVec3, Error, Result};
use serde::{Deserialize, Serialize};
use std::path::{Component, Path, PathBuf};

/// The plane a reference image lies in (Z is up).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ReferencePlane {
    /// The XZ plane seen from −Y: the image's right is +X, its up +Z.
    Front,
    /// The YZ plane seen from +X: right is +Y, up +Z.
    Side,
    /// The XY plane seen from +Z: right is +X, up +Y.
    Top,
    /// Facing the camera wherever it looks from (a billboard about its centre).
    View,
}

impl ReferencePlane {
    pub const ALL: [ReferencePlane; 4] =
        [ReferencePlane::Front, ReferencePlane::Side, ReferencePlane::Top, ReferencePlane::View];

    /// The name a designer reads.
    pub fn display_name(self) -> &'static str {
        match self {
            ReferencePlane::Front => "front (XZ)",
            ReferencePlane::Side => "side (YZ)",
            ReferencePlane::Top => "top (XY)",
            ReferencePlane::View => "view (faces the camera)",
        }
    }

    /// The image's right and up directions before its rotation; `None` for the view plane,
    /// whose directions are the camera's.
    pub fn axes(self) -> Option<(DVec3, DVec3)> {
        match self {
            ReferencePlane::Front => Some((DVec3::X, DVec3::Z)),
            ReferencePlane::Side => Some((DVec3::Y, DVec3::Z)),
            ReferencePlane::Top => Some((DVec3::X, DVec3::Y)),
            ReferencePlane::View => None,
        }
    }
}

/// One reference image of a document.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ReferenceImage {
    /// The picture's file, relative to the document's folder, `/`-separated.
    pub path: String,
    pub plane: ReferencePlane,
    /// Where the image's centre is, in model coordinates.
    pub centre: DVec3,
    /// The image's width in model units; its height follows from the picture's aspect.
    pub width: f64,
    /// Degrees, counter-clockwise in its plane as seen from the side it faces.
    #[serde(default)]
    pub rotation: f64,
    /// 0 transparent to 1 opaque.
    #[serde(default = "one")]
    pub opacity: f64,
    /// Drawn over the model (translucent) rather than behind it.
    #[serde(default)]
    pub in_front: bool,
    #[serde(default = "yes")]
    pub visible: bool,
}

fn one() -> f64 {
    1.0
}

fn yes() -> bool {
    true
}

impl ReferenceImage {
    /// An image at `path` on `plane`, centred at the origin, `width` wide, opaque, behind the model.
    pub fn new(path: impl Into<String>, plane: ReferencePlane, width: f64) -> Self {
        ReferenceImage {
            path: path.into(),
            plane,
            centre: DVec3::ZERO,
            width,
            rotation: 0.0,
            opacity: 1.0,
            in_front: false,
            visible: true,
        }
    }

    /// The image's right and up directions (unit, rotated in its plane), or `None` on the view
    /// plane (the renderer turns the camera's directions by the same rotation).
    pub fn axes(&self) -> Option<(DVec3, DVec3)> {
        let (right, up) = self.plane.axes()?;
        let (sin, cos) = self.rotation.to_radians().sin_cos();
        Some((right * cos + up * sin, up * cos - right * sin))
    }

    /// Checks the values a file or an edit gives (not the path's safety: see [`resolve`](Self::resolve)).
    pub fn validate(&self) -> Result<()> {
        let name = &self.path;
        if self.path.is_empty() || self.path.contains('\0') {
            return Err(Error::Input("a reference image needs the path of a file".into()));
        }
        if !self.centre.is_finite() {
            return Err(Error::Input(format!("reference image {name}: its centre must be finite numbers")));
        }
        if !(self.width.is_finite() && self.width > 0.0) {
            return Err(Error::Input(format!(
                "reference image {name}: its width must be a finite number > 0, not {}",
                self.width
            )));
        }
        if !self.rotation.is_finite() {
            return Err(Error::Input(format!("reference image {name}: its rotation must be a finite number")));
        }
        if !(0.0..=1.0).contains(&self.opacity) {
            return Err(Error::Input(format!(
                "reference image {name}: its opacity must be between 0 and 1, not {}",
                self.opacity
            )));
        }
        Ok(())
    }

    /// The image's file, if it is safely inside `document_folder`: refuses an absolute path, a
    /// `..` that climbs out and (after links are followed) a file outside the folder, and says
    /// when the file is missing, each in one line naming the image.
    pub fn resolve(&self, document_folder: &Path) -> Result<PathBuf> {
        let name = &self.path;
        let relative = checked_relative(name)?;
        let refused = |why: String| Error::Input(format!("reference image {name} {why}; it was not read"));
        let missing = || Error::Input(format!("reference image {name} not found next to the document"));
        let folder = document_folder.canonicalize().map_err(|_| missing())?;
        let file = folder.join(relative);
        let real = match file.canonicalize() {
            Ok(real) => real,
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Err(missing()),
            Err(e) => return Err(Error::Input(format!("reference image {name}: cannot read it: {e}"))),
        };
        if !real.starts_with(&folder) {
            return Err(refused("leads outside the document's folder through a link".into()));
        }
        if !real.is_file() {
            return Err(refused("is not a file".into()));
        }
        Ok(real)
    }
}

/// The `/`-separated relative path as a path under the document's folder, with `.` and inner
/// `..` folded away; refuses an absolute path and one that climbs out of the folder.
pub fn checked_relative(path: &str) -> Result<PathBuf> {
    let refused = |why: &str| Error::Input(format!("reference image {path} {why}; it was not read"));
    // A drive letter or a backslash root is absolute on Windows whatever system reads the file.
    let windows_absolute = path.starts_with('\\') || path.as_bytes().get(1) == Some(&b':');
    if Path::new(path).is_absolute() || path.starts_with('/') || windows_absolute {
        return Err(refused("is an absolute path (reference images are kept next to the document)"));
    }
    let mut parts: Vec<&str> = Vec::new();
    for part in path.split(['/', '\\']) {
        match part {
            "" | "." => {}
            ".." => {
                if parts.pop().is_none() {
                    return Err(refused("points outside the document's folder"));
                }
            }
            part => parts.push(part),
        }
    }
    if parts.is_empty() {
        return Err(Error::Input(format!("reference image {path:?} names no file")));
    }
    // Each part is a plain name now: no root, prefix or `..` can come back in.
    let out: PathBuf = parts.iter().collect();
    if out.components().any(|c| !matches!(c, Component::Normal(_))) {
        return Err(refused("is not a plain relative path"));
    }
    Ok(out)
}

/// The path a picture is saved as in a document in `document_folder`: relative and
/// `/`-separated when the picture is inside the folder (links followed), else `None` (the editor
/// then offers to copy it next to the document).
pub fn relative_to_folder(picture: &Path, document_folder: &Path) -> Option<String> {
    let folder = document_folder.canonicalize().ok()?;
    let real = picture.canonicalize().ok()?;
    let inside = real.strip_prefix(&folder).ok()?;
    let parts: Option<Vec<&str>> = inside.components().map(|c| c.as_os_str().to_str()).collect();
    let text = parts?.join("/");
    (!text.is_empty()).then_some(text)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn relative_paths_are_checked_before_any_file_is_touched() {
        assert_eq!(checked_relative("a/./b/../c.png").unwrap(), Path::new("a/c.png"));
        assert_eq!(checked_relative("pics\\front.jpg").unwrap(), Path::new("pics/front.jpg"));
        for (bad, why) in [
            ("/etc/passwd", "absolute"),
            ("C:/x.png", "absolute"),
            ("\\\\server\\x.png", "absolute"),
            ("../outside.png", "outside the document's folder"),
            ("a/../../outside.png", "outside the document's folder"),
            ("./..", "outside the document's folder"),
        ] {
            let err = checked_relative(bad).unwrap_err().to_string();
            assert!(err.contains(why) && err.contains("not read"), "{bad}: {err}");
        }
        assert!(checked_relative("a/..").is_err(), "no file named");
    }

    #[test]
    fn rotation_turns_the_axes_in_the_plane() {
        let mut image = ReferenceImage::new("x.png", ReferencePlane::Front, 2.0);
        assert_eq!(image.axes(), Some((DVec3::X, DVec3::Z)));
        image.rotation = 90.0;
        let (right, up) = image.axes().unwrap();
        assert!((right - DVec3::Z).length() < 1e-12 && (up + DVec3::X).length() < 1e-12, "{right} {up}");
        image.plane = ReferencePlane::View;
        assert_eq!(image.axes(), None);
    }

    #[test]
    fn resolve_reads_only_inside_the_folder() {
        let root = std::env::temp_dir().join(format!("taut-refimg-{}", std::process::id()));
        let doc = root.join("doc");
        std::fs::create_dir_all(doc.join("pics")).unwrap();
        std::fs::write(doc.join("pics/in.png"), b"x").unwrap();
        std::fs::write(root.join("outside.png"), b"x").unwrap();
        let at = |p: &str| ReferenceImage::new(p, ReferencePlane::Top, 1.0).resolve(&doc);
        assert_eq!(at("pics/in.png").unwrap(), doc.join("pics/in.png").canonicalize().unwrap());
        assert!(at("../outside.png").unwrap_err().to_string().contains("outside the document's folder"));
        let missing = at("pics/gone.png").unwrap_err().to_string();
        assert!(missing.contains("pics/gone.png not found next to the document"), "{missing}");
        assert!(at("pics").unwrap_err().to_string().contains("not a file"));
        #[cfg(unix)]
        {
            let _ = std::fs::remove_file(doc.join("link.png"));
            std::os::unix::fs::symlink(root.join("outside.png"), doc.join("link.png")).unwrap();
            let err = at("link.png").unwrap_err().to_string();
            assert!(err.contains("through a link") && err.contains("not read"), "{err}");
        }
        assert_eq!(relative_to_folder(&doc.join("pics/in.png"), &doc).as_deref(), Some("pics/in.png"));
        assert_eq!(relative_to_folder(&root.join("outside.png"), &doc), None);
        let _ = std::fs::remove_dir_all(&root);
    }
}
