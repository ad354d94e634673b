//! The CPU half of the surface pass: a [`PolyMesh`] as vertex and index arrays, and their GPU
//! copies.
//!
//! [`SurfaceBuffers`] follows the mesh's two counters: a position-only edit (a drag) refreshes
//! the vertex array and keeps the index array, which is rebuilt only when the connectivity
//! changes, so the upload while dragging is positions and normals alone. Positions are written in
//! the display coordinates of a [`DisplayFrame`], so any finite model fits f32. The normals drawn
//! are the ones the surface gives (a subdivision scheme's exact limit normals, analytic patch
//! normals); only a surface without normals of its own gets area-weighted ones. [`GpuSurface`] mirrors
//! that on the GPU: it rewrites the vertex buffer in place and recreates the index buffer only
//! when the indices changed.

use crate::display::DisplayFrame;
use bytemuck::{Pod, Zeroable};
use taut_core::{DVec3, PolyMesh};

/// One vertex of the surface pass, as the shader reads it (`f32`, tightly packed).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct SurfaceVertex {
    pub position: [f32; 3],
    pub normal: [f32; 3],
    /// The scalar shown by the curvature view (0 otherwise).
    pub value: f32,
}

/// Vertex and triangle-index arrays of a mesh, kept in step with its generations.
#[derive(Debug, Default)]
pub struct SurfaceBuffers {
    vertices: Vec<SurfaceVertex>,
    indices: Vec<u32>,
    generation: Option<u64>,
    topology_generation: Option<u64>,
    frame: Option<DisplayFrame>,
    index_rebuilds: u64,
    values_changed: bool,
}

/// What [`SurfaceBuffers::update`] changed, so the caller uploads only that.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Changes {
    pub vertices: bool,
    pub indices: bool,
}

impl SurfaceBuffers {
    /// Brings the arrays up to date with `mesh` drawn as it is, with area-weighted normals.
    pub fn update(&mut self, mesh: &PolyMesh) -> Changes {
        self.update_with(mesh, None, &DisplayFrame::IDENTITY)
    }

    /// Brings the arrays up to date with `mesh` in the display coordinates of `frame`, with the
    /// given unit normals (one per vertex; area-weighted ones when `None`), and says what changed.
    /// Normals given belong to the mesh's current generation.
    pub fn update_with(&mut self, mesh: &PolyMesh, normals: Option<&[DVec3]>, frame: &DisplayFrame) -> Changes {
        let topology_changed = self.topology_generation != Some(mesh.topology_generation());
        let geometry_changed =
            topology_changed || self.generation != Some(mesh.generation()) || self.frame != Some(*frame);
        let vertices_changed = geometry_changed || std::mem::take(&mut self.values_changed);
        if topology_changed {
            self.indices = mesh.triangles().into_iter().flatten().collect();
            self.topology_generation = Some(mesh.topology_generation());
            self.index_rebuilds += 1;
        }
        if geometry_changed {
            let computed;
            let normals = match normals {
                Some(n) if n.len() == mesh.vertex_count() => n,
                _ => {
                    computed = mesh.vertex_normals();
                    &computed
                }
            };
            let values: Vec<f32> = self.vertices.iter().map(|v| v.value).collect();
            self.vertices.clear();
            self.vertices.extend(mesh.positions().iter().zip(normals).enumerate().map(|(k, (&p, n))| SurfaceVertex {
                position: frame.point(p).to_array(),
                normal: n.as_vec3().to_array(),
                value: if topology_changed { 0.0 } else { values.get(k).copied().unwrap_or(0.0) },
            }));
            self.generation = Some(mesh.generation());
            self.frame = Some(*frame);
        }
        Changes { vertices: vertices_changed, indices: topology_changed }
    }

    /// Sets the per-vertex scalar of the curvature view (one value per vertex, in order; the
    /// callers pass values already mapped to the colour range, `[0, 1]`, see
    /// [`crate::colormap::normalize`]).
    pub fn set_values(&mut self, values: &[f32]) {
        for (v, &x) in self.vertices.iter_mut().zip(values) {
            v.value = if x.is_finite() { x } else { 0.0 };
        }
        self.values_changed = true;
    }

    /// The vertex array.
    pub fn vertices(&self) -> &[SurfaceVertex] {
        &self.vertices
    }

    /// The triangle list, three indices a triangle.
    pub fn indices(&self) -> &[u32] {
        &self.indices
    }

    /// How many times the index array was rebuilt (for tests and statistics).
    pub fn index_rebuilds(&self) -> u64 {
        self.index_rebuilds
    }
}

/// A surface's buffers on the GPU.
#[derive(Debug)]
pub struct GpuSurface {
    pub vertices: wgpu::Buffer,
    pub indices: wgpu::Buffer,
    pub index_count: u32,
    vertex_capacity: u64,
    index_uploads: u64,
}

impl GpuSurface {
    /// Uploads the arrays for the first time.
    pub fn new(device: &wgpu::Device, buffers: &SurfaceBuffers) -> Self {
        let vertex_bytes: &[u8] = bytemuck::cast_slice(buffers.vertices());
        let vertices = create_buffer(device, "surface vertices", vertex_bytes, wgpu::BufferUsages::VERTEX);
        let indices = create_buffer(
            device,
            "surface indices",
            bytemuck::cast_slice(buffers.indices()),
            wgpu::BufferUsages::INDEX,
        );
        GpuSurface {
            vertices,
            indices,
            index_count: buffers.indices().len() as u32,
            vertex_capacity: vertex_bytes.len() as u64,
            index_uploads: 1,
        }
    }

    /// Uploads what [`SurfaceBuffers::update`] reported as changed: the vertex buffer is
    /// rewritten in place when it fits, the index buffer only recreated for new indices.
    pub fn upload(&mut self, device: &wgpu::Device, queue: &wgpu::Queue, buffers: &SurfaceBuffers, changes: Changes) {
        if changes.indices {
            self.indices = create_buffer(
                device,
                "surface indices",
                bytemuck::cast_slice(buffers.indices()),
                wgpu::BufferUsages::INDEX,
            );
            self.index_count = buffers.indices().len() as u32;
            self.index_uploads += 1;
        }
        if changes.vertices {
            let bytes: &[u8] = bytemuck::cast_slice(buffers.vertices());
            if bytes.len() as u64 <= self.vertex_capacity && !bytes.is_empty() {
                queue.write_buffer(&self.vertices, 0, bytes);
            } else {
                self.vertices = create_buffer(device, "surface vertices", bytes, wgpu::BufferUsages::VERTEX);
                self.vertex_capacity = bytes.len() as u64;
            }
        }
    }

    /// How many index buffers were created (for tests and statistics).
    pub fn index_uploads(&self) -> u64 {
        self.index_uploads
    }
}

fn create_buffer(device: &wgpu::Device, label: &str, bytes: &[u8], usage: wgpu::BufferUsages) -> wgpu::Buffer {
    use wgpu::util::DeviceExt;
    // wgpu refuses empty buffers: keep at least one element's worth.
    let padded;
    let contents = if bytes.is_empty() {
        padded = [0u8; 16];
        &padded[..]
    } else {
        bytes
    };
    device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some(label),
        contents,
        usage: usage | wgpu::BufferUsages::COPY_DST,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use taut_core::{DVec3, VertexId};

    fn quad_pair() -> PolyMesh {
        let p = vec![
            DVec3::ZERO,
            DVec3::X,
            DVec3::new(1.0, 1.0, 0.0),
            DVec3::Y,
            DVec3::new(2.0, 0.0, 0.0),
            DVec3::new(2.0, 1.0, 0.0),
        ];
        PolyMesh::from_polygons(p, &[[0, 1, 2, 3], [1, 4, 5, 2]]).unwrap()
    }

    #[test]
    fn dragging_refreshes_vertices_but_not_indices() {
        let mut mesh = quad_pair();
        let mut buffers = SurfaceBuffers::default();
        assert_eq!(buffers.update(&mesh), Changes { vertices: true, indices: true });
        assert_eq!(buffers.indices(), &[0, 1, 2, 0, 2, 3, 1, 4, 5, 1, 5, 2]);
        assert_eq!(buffers.vertices()[2].normal, [0.0, 0.0, 1.0]);
        assert_eq!(buffers.update(&mesh), Changes { vertices: false, indices: false });

        mesh.set_position(VertexId(2), DVec3::new(1.0, 1.0, 0.5));
        assert_eq!(buffers.update(&mesh), Changes { vertices: true, indices: false });
        assert_eq!(buffers.vertices()[2].position, [1.0, 1.0, 0.5]);
        assert_eq!(buffers.index_rebuilds(), 1);

        // A rebuilt mesh (new connectivity) rebuilds the indices.
        let rebuilt = quad_pair();
        assert_eq!(buffers.update(&rebuilt), Changes { vertices: true, indices: true });
        assert_eq!(buffers.index_rebuilds(), 2);
    }

    #[test]
    fn gpu_upload_after_a_drag_keeps_the_index_buffer() {
        let gpu = crate::Gpu::headless(crate::AdapterPreference::Software).unwrap_or_else(|e| panic!("{e}"));
        let mut mesh = quad_pair();
        let mut buffers = SurfaceBuffers::default();
        buffers.update(&mesh);
        let mut surface = GpuSurface::new(&gpu.device, &buffers);
        assert_eq!(surface.index_uploads(), 1);
        mesh.set_position(VertexId(2), DVec3::new(1.0, 1.0, 0.5));
        let changes = buffers.update(&mesh);
        surface.upload(&gpu.device, &gpu.queue, &buffers, changes);
        assert_eq!(surface.index_uploads(), 1, "a drag must not rebuild the index buffer");
        let rebuilt = quad_pair();
        let changes = buffers.update(&rebuilt);
        surface.upload(&gpu.device, &gpu.queue, &buffers, changes);
        assert_eq!(surface.index_uploads(), 2);
        assert_eq!(surface.index_count, 12);
    }
}
