//! One picture of a surface, composed as `taut render` and the golden-image tests both draw it:
//! the surface in the display coordinates of its own bounding box ([`DisplayFrame`]), framed to
//! fill the picture left of the legend's margin (or placed by an explicit camera), with its
//! normals, colour values, overlays and the document's reference images.

use crate::display::DisplayFrame;
use crate::overlay::OverlayData;
use crate::passes::overlay2d::legend_margin;
use crate::passes::surface::SurfaceMode;
use crate::reference_images::ReferenceQuad;
use crate::{Camera, Gpu, GpuSurface, RenderError, Renderer, Scene, SurfaceBuffers, offscreen};
use taut_core::document::ReferenceImage;
use taut_core::{DVec3, PolyMesh};

/// Where the camera looks from.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct View {
    /// Degrees around the vertical axis (0 looks from the front, 90 from the right).
    pub azimuth: f32,
    /// Degrees above the horizon.
    pub elevation: f32,
    /// Distance from the centre of the surface's box in model units; `None` frames the surface.
    pub distance: Option<f64>,
}

impl Default for View {
    fn default() -> Self {
        View { azimuth: 30.0, elevation: 25.0, distance: None }
    }
}

/// What a picture shows.
#[derive(Debug)]
pub struct Picture<'a> {
    pub mesh: &'a PolyMesh,
    /// Exact unit normals per vertex, if the surface has them.
    pub normals: Option<&'a [DVec3]>,
    /// Colour values per vertex, already mapped to `[0, 1]` (see [`crate::colormap::normalize`]).
    pub values: Option<&'a [f32]>,
    pub mode: SurfaceMode,
    pub view: View,
    pub width: u32,
    pub height: u32,
}

impl Picture<'_> {
    /// The display frame the picture is drawn in (build the overlays in it).
    pub fn frame(&self) -> DisplayFrame {
        self.mesh.bounding_box().map_or(DisplayFrame::IDENTITY, |(lo, hi)| DisplayFrame::for_bounds(lo, hi))
    }

    /// The camera: the surface framed to fill the picture left of `margin` pixels at its right,
    /// centred there, from the view's direction; or at the view's distance.
    pub fn camera(&self, margin: u32) -> Result<Camera, RenderError> {
        let frame = self.frame();
        let mut camera = Camera {
            azimuth: self.view.azimuth,
            elevation: self.view.elevation.clamp(-90.0, 90.0),
            ..Camera::default()
        };
        // A regular sample sees the same silhouette as a million vertices, to within a pixel.
        let step = (self.mesh.vertex_count() / 20_000).max(1);
        let points: Vec<glam::Vec3> = self.mesh.positions().iter().step_by(step).map(|&p| frame.point(p)).collect();
        let usable = self.width.saturating_sub(margin).max(1);
        camera.frame_points(&points, usable as f32 / self.height.max(1) as f32);
        if let Some(d) = self.view.distance {
            let display = frame.length(d);
            if !(d > 0.0 && display.is_finite() && (1e-6..=1e9).contains(&(display as f32))) {
                return Err(RenderError::Output(format!(
                    "the camera distance {d} must be positive and within a billion times the model's size ({:.3e})",
                    frame.scale
                )));
            }
            camera.distance = display as f32;
        }
        camera.pan(-(margin as f32) / 2.0, 0.0, self.height as f32);
        Ok(camera)
    }

    /// Draws the picture with `overlays` (built in [`frame`](Self::frame)'s coordinates).
    pub fn render(
        &self,
        gpu: &Gpu,
        renderer: &mut Renderer,
        overlays: &OverlayData,
    ) -> Result<image::RgbaImage, RenderError> {
        self.render_with_references(gpu, renderer, overlays, &[])
    }

    /// [`render`](Self::render) with the document's reference images (each with its decoded
    /// picture) behind or over the surface.
    pub fn render_with_references(
        &self,
        gpu: &Gpu,
        renderer: &mut Renderer,
        overlays: &OverlayData,
        references: &[(ReferenceImage, crate::reference_images::Picture)],
    ) -> Result<image::RgbaImage, RenderError> {
        let frame = self.frame();
        let quads: Vec<ReferenceQuad<'_>> = references
            .iter()
            .filter(|(image, _)| image.visible)
            .map(|(image, picture)| ReferenceQuad::new(image, picture, &frame))
            .collect();
        let mut buffers = SurfaceBuffers::default();
        buffers.update_with(self.mesh, self.normals, &self.frame());
        if let Some(values) = self.values {
            buffers.set_values(values);
        }
        let gpu_surface = GpuSurface::new(&gpu.device, &buffers);
        let margin = overlays.legend.as_ref().map_or(0, |l| legend_margin(l, self.width, self.height));
        let camera = self.camera(margin)?;
        let scene = Scene {
            reference_images: &quads,
            ..Scene::new(camera, Some(&gpu_surface), self.mode).with_overlays(overlays)
        };
        offscreen::render_image(gpu, renderer, &scene, self.width, self.height)
    }
}
