//! Off-screen pictures: the same [`Renderer`] drawing into a texture that is read back to an
//! RGBA image (the command line's `render` and the golden-image tests).

use crate::renderer::{Attachments, Renderer, Scene};
use crate::{Gpu, RenderError};

/// Renders `scene` at `width × height` and reads it back as tightly packed RGBA8 (sRGB) rows.
pub fn render_image(
    gpu: &Gpu,
    renderer: &mut Renderer,
    scene: &Scene<'_>,
    width: u32,
    height: u32,
) -> Result<image::RgbaImage, RenderError> {
    if width == 0 || height == 0 || width > 16384 || height > 16384 {
        return Err(RenderError::Output(format!("picture size {width}x{height} is out of range (1 to 16384)")));
    }
    let device = &gpu.device;
    let texture = device.create_texture(&wgpu::TextureDescriptor {
        label: Some("off-screen colour"),
        size: wgpu::Extent3d { width, height, depth_or_array_layers: 1 },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: renderer.targets.color,
        usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
        view_formats: &[],
    });
    let view = texture.create_view(&Default::default());
    let attachments = Attachments::new(device, &renderer.targets, width, height);
    let row_bytes = width * 4;
    let padded = row_bytes.div_ceil(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT) * wgpu::COPY_BYTES_PER_ROW_ALIGNMENT;
    let readback = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("read back"),
        size: padded as u64 * height as u64,
        usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });
    let mut encoder = device.create_command_encoder(&Default::default());
    renderer.encode(device, &gpu.queue, &mut encoder, &view, &attachments, scene);
    encoder.copy_texture_to_buffer(
        wgpu::TexelCopyTextureInfo {
            texture: &texture,
            mip_level: 0,
            origin: wgpu::Origin3d::ZERO,
            aspect: wgpu::TextureAspect::All,
        },
        wgpu::TexelCopyBufferInfo {
            buffer: &readback,
            layout: wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(padded),
                rows_per_image: Some(height),
            },
        },
        wgpu::Extent3d { width, height, depth_or_array_layers: 1 },
    );
    gpu.queue.submit([encoder.finish()]);
    let slice = readback.slice(..);
    let (sender, receiver) = std::sync::mpsc::channel();
    slice.map_async(wgpu::MapMode::Read, move |r| {
        let _ = sender.send(r);
    });
    device
        .poll(wgpu::PollType::wait_indefinitely())
        .map_err(|e| RenderError::Output(format!("waiting for the GPU: {e}")))?;
    receiver
        .recv()
        .map_err(|_| RenderError::Output("the GPU never finished the picture".into()))?
        .map_err(|e| RenderError::Output(format!("reading the picture back: {e}")))?;
    let data = slice.get_mapped_range().map_err(|e| RenderError::Output(format!("reading the picture back: {e}")))?;
    let mut pixels = Vec::with_capacity((row_bytes * height) as usize);
    for row in data.chunks(padded as usize) {
        pixels.extend_from_slice(&row[..row_bytes as usize]);
    }
    drop(data);
    readback.unmap();
    if renderer.targets.color == wgpu::TextureFormat::Bgra8UnormSrgb {
        for px in pixels.chunks_mut(4) {
            px.swap(0, 2);
        }
    }
    image::RgbaImage::from_raw(width, height, pixels).ok_or_else(|| RenderError::Output("picture size mismatch".into()))
}

/// Writes a picture as PNG, atomically.
pub fn save_png(image: &image::RgbaImage, path: &std::path::Path) -> Result<(), RenderError> {
    let mut bytes = Vec::new();
    image
        .write_to(&mut std::io::Cursor::new(&mut bytes), image::ImageFormat::Png)
        .map_err(|e| RenderError::Output(format!("{}: {e}", path.display())))?;
    taut_core::io::write_atomic(path, &bytes).map_err(|e| RenderError::Output(e.to_string()))
}
