//! Reference images on the CPU side: reading a document's picture safely and decoding it, and
//! the [`ReferenceQuad`] a scene draws it as ([`crate::passes::reference_images`]).
//!
//! Only PNG and JPEG are decoded (the `image` crate built with those two alone). A file is read
//! only through [`ReferenceImage::resolve`], which keeps it inside the document's folder; its
//! decoding is bounded (at most [`MAX_DECODED_BYTES`] of pixels, so a small file claiming a
//! huge size cannot exhaust memory) and a picture larger than [`MAX_SIDE`] on its long side is
//! scaled down, since a GPU texture has a size limit and a reference needs no more.

use crate::DisplayFrame;
use glam::Vec3;
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::SystemTime;
use taut_core::document::ReferenceImage;

/// The longest side a picture is kept at, in pixels.
pub const MAX_SIDE: u32 = 4096;
/// The most memory a picture may decode into (before it is scaled down).
pub const MAX_DECODED_BYTES: u64 = 1 << 30;
/// The largest file read as a picture.
pub const MAX_FILE_BYTES: u64 = 256 << 20;

/// What names a picture's pixels: the file and when it was last changed. A picture is uploaded
/// to the GPU once per key, and read again when the file changes.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct PictureKey {
    pub path: PathBuf,
    pub modified: Option<SystemTime>,
}

/// A decoded picture (sRGB RGBA, at most [`MAX_SIDE`] on its long side).
#[derive(Clone, Debug)]
pub struct Picture {
    pub key: PictureKey,
    pub pixels: Arc<image::RgbaImage>,
}

impl Picture {
    /// Height over width.
    pub fn aspect(&self) -> f64 {
        self.pixels.height() as f64 / self.pixels.width().max(1) as f64
    }
}

/// The key of the picture `image` names in `document_folder` (the file found safely and its
/// modification time), or the one line that says why it cannot be read.
pub fn picture_key(image: &ReferenceImage, document_folder: &Path) -> Result<PictureKey, String> {
    let path = image.resolve(document_folder).map_err(|e| e.to_string())?;
    let modified = std::fs::metadata(&path).ok().and_then(|m| m.modified().ok());
    Ok(PictureKey { path, modified })
}

/// Reads and decodes the picture of `key` (found by [`picture_key`]); `name` is the image's path
/// as the document gives it, for the message.
pub fn load_picture(key: PictureKey, name: &str) -> Result<Picture, String> {
    let cannot = |why: String| format!("reference image {name}: {why}");
    let size = std::fs::metadata(&key.path).map_err(|e| cannot(e.to_string()))?.len();
    if size > MAX_FILE_BYTES {
        return Err(cannot(format!("the file has {size} bytes, more than the {MAX_FILE_BYTES} a picture may have")));
    }
    let bytes = taut_core::io::file::read_regular_file(&key.path).map_err(|e| cannot(e.to_string()))?;
    let pixels = decode_picture(&bytes).map_err(cannot)?;
    Ok(Picture { key, pixels: Arc::new(pixels) })
}

/// Decodes PNG or JPEG bytes to RGBA, scaled down to at most [`MAX_SIDE`] on the long side.
pub fn decode_picture(bytes: &[u8]) -> Result<image::RgbaImage, String> {
    let mut reader = image::ImageReader::new(std::io::Cursor::new(bytes))
        .with_guessed_format()
        .map_err(|e| format!("cannot read it: {e}"))?;
    if !matches!(reader.format(), Some(image::ImageFormat::Png | image::ImageFormat::Jpeg)) {
        return Err("not a PNG or JPEG picture".into());
    }
    let mut limits = image::Limits::default();
    limits.max_alloc = Some(MAX_DECODED_BYTES);
    reader.limits(limits);
    let decoded = reader.decode().map_err(|e| format!("cannot decode it: {e}"))?;
    let (w, h) = (decoded.width(), decoded.height());
    if w == 0 || h == 0 {
        return Err("the picture is empty".into());
    }
    let decoded = if w.max(h) > MAX_SIDE {
        decoded.resize(MAX_SIDE, MAX_SIDE, image::imageops::FilterType::Triangle)
    } else {
        decoded
    };
    Ok(decoded.into_rgba8())
}

/// One reference image as the renderer draws it, in display coordinates.
#[derive(Clone, Copy, Debug)]
pub struct ReferenceQuad<'a> {
    pub picture: &'a Picture,
    pub centre: Vec3,
    /// Half the width and half the height, in display units.
    pub half_size: [f32; 2],
    /// The picture's right and up (unit); `None` faces the camera.
    pub axes: Option<(Vec3, Vec3)>,
    /// Radians, counter-clockwise (used when facing the camera; planar axes are already turned).
    pub rotation: f32,
    pub opacity: f32,
    pub in_front: bool,
}

impl<'a> ReferenceQuad<'a> {
    /// How `image` is drawn with its decoded `picture` in `frame`.
    pub fn new(image: &ReferenceImage, picture: &'a Picture, frame: &DisplayFrame) -> Self {
        let half_width = frame.length(image.width * 0.5);
        ReferenceQuad {
            picture,
            centre: frame.point(image.centre),
            half_size: [half_width as f32, (half_width * picture.aspect()) as f32],
            axes: image.axes().map(|(right, up)| (right.as_vec3(), up.as_vec3())),
            rotation: image.rotation.to_radians() as f32,
            opacity: image.opacity.clamp(0.0, 1.0) as f32,
            in_front: image.in_front,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn png(w: u32, h: u32) -> Vec<u8> {
        let mut bytes = Vec::new();
        image::RgbaImage::from_pixel(w, h, image::Rgba([200, 10, 10, 255]))
            .write_to(&mut std::io::Cursor::new(&mut bytes), image::ImageFormat::Png)
            .unwrap();
        bytes
    }

    #[test]
    fn pictures_decode_big_ones_shrink_and_broken_ones_say_so() {
        assert_eq!(decode_picture(&png(3, 2)).unwrap().dimensions(), (3, 2));
        assert_eq!(decode_picture(&png(5000, 10)).unwrap().dimensions(), (4096, 8));
        let mut jpeg = Vec::new();
        image::RgbImage::from_pixel(16, 8, image::Rgb([0, 0, 255]))
            .write_to(&mut std::io::Cursor::new(&mut jpeg), image::ImageFormat::Jpeg)
            .unwrap();
        let decoded = decode_picture(&jpeg).unwrap();
        assert_eq!(decoded.dimensions(), (16, 8));
        assert!(decoded.get_pixel(4, 4)[2] > 200, "blue stays blue");
        for (bytes, why) in [
            (b"GIF89a not wanted".to_vec(), "not a PNG or JPEG"),
            (png(4, 4)[..40].to_vec(), "cannot decode it"),
            (Vec::new(), "not a PNG or JPEG"),
        ] {
            let err = decode_picture(&bytes).unwrap_err();
            assert!(err.contains(why) && !err.contains('\n'), "{err}");
        }
    }
}

#[cfg(test)]
#[path = "reference_images_tests.rs"]
mod gpu_tests;
