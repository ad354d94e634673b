//! Taut's display side. For now: the CPU half of the surface pass, turning a [`PolyMesh`] into
//! the vertex and index arrays the wgpu passes upload.
//!
//! [`SurfaceBuffers`] follows the mesh's two counters: a position-only edit (a drag) refreshes
//! the vertex array and keeps the index array, which is rebuilt only when the connectivity
//! changes, so the upload while dragging is positions and normals alone.

use bytemuck::{Pod, Zeroable};
use taut_core::PolyMesh;

/// One vertex of the surface pass, as the shader reads it (`f32`, tightly packed).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct SurfaceVertex {
    pub position: [f32; 3],
    pub normal: [f32; 3],
}

/// Vertex and triangle-index arrays of a mesh, kept in step with its generations.
#[derive(Debug, Default)]
pub struct SurfaceBuffers {
    vertices: Vec<SurfaceVertex>,
    indices: Vec<u32>,
    generation: Option<u64>,
    topology_generation: Option<u64>,
    index_rebuilds: u64,
}

/// What [`SurfaceBuffers::update`] changed, so the caller uploads only that.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Changes {
    pub vertices: bool,
    pub indices: bool,
}

impl SurfaceBuffers {
    /// Brings the arrays up to date with `mesh` and says what changed.
    pub fn update(&mut self, mesh: &PolyMesh) -> Changes {
        let topology_changed = self.topology_generation != Some(mesh.topology_generation());
        let vertices_changed = topology_changed || self.generation != Some(mesh.generation());
        if topology_changed {
            self.indices = mesh.triangles().into_iter().flatten().collect();
            self.topology_generation = Some(mesh.topology_generation());
            self.index_rebuilds += 1;
        }
        if vertices_changed {
            let normals = mesh.vertex_normals();
            self.vertices.clear();
            self.vertices.extend(
                mesh.positions()
                    .iter()
                    .zip(&normals)
                    .map(|(p, n)| SurfaceVertex { position: p.as_vec3().to_array(), normal: n.as_vec3().to_array() }),
            );
            self.generation = Some(mesh.generation());
        }
        Changes { vertices: vertices_changed, indices: topology_changed }
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
}
