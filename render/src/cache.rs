//! [`SurfaceCache`]: a mesh kept on the GPU and uploaded again only when what it shows changed.
//!
//! The editor draws several meshes this way (the surface, the compare view's ghost, the mesh a
//! cage was fitted to, the Curves workspace's patches); each names what it shows with a key of
//! its own (the mesh's generations, the display frame, the colour values' identity, a document
//! revision) and the cache uploads when the key differs from the one last shown. Below the key,
//! [`SurfaceBuffers`] and [`GpuSurface`] keep the upload to what changed (positions alone during
//! a drag).

use crate::buffers::{GpuSurface, SurfaceBuffers};
use crate::display::DisplayFrame;
use crate::gpu::Gpu;
use taut_core::{DVec3, PolyMesh};

/// A mesh on the GPU with the key of what it shows.
#[derive(Debug)]
pub struct SurfaceCache<K> {
    buffers: SurfaceBuffers,
    gpu: Option<GpuSurface>,
    shown: Option<K>,
}

impl<K> Default for SurfaceCache<K> {
    fn default() -> Self {
        SurfaceCache { buffers: SurfaceBuffers::default(), gpu: None, shown: None }
    }
}

/// A mesh to show: its normals where it has them, and per-vertex values for the colour view.
#[derive(Clone, Copy, Debug)]
pub struct ShownMesh<'a> {
    pub mesh: &'a PolyMesh,
    pub normals: Option<&'a [DVec3]>,
    pub values: Option<&'a [f32]>,
}

impl<'a> ShownMesh<'a> {
    /// A mesh without normals of its own or values.
    pub fn plain(mesh: &'a PolyMesh) -> Self {
        ShownMesh { mesh, normals: None, values: None }
    }
}

impl<K: PartialEq> SurfaceCache<K> {
    /// Shows `mesh` under `key`: uploads it when `key` is not the one last shown (or nothing is
    /// on the GPU), else does nothing.
    pub fn show(&mut self, gpu: &Gpu, key: K, mesh: ShownMesh<'_>, frame: &DisplayFrame) {
        self.show_with(gpu, key, || Some(mesh), frame);
    }

    /// [`show`](Self::show) for a mesh that is made only when the key changed; `None` from
    /// `make` shows nothing until the key changes again.
    pub fn show_with<'m>(
        &mut self,
        gpu: &Gpu,
        key: K,
        make: impl FnOnce() -> Option<ShownMesh<'m>>,
        frame: &DisplayFrame,
    ) {
        if self.shown.as_ref() == Some(&key) {
            return;
        }
        self.shown = Some(key);
        let Some(shown) = make() else {
            self.gpu = None;
            return;
        };
        let first = self.buffers.update_with(shown.mesh, shown.normals, frame);
        let mut changes = first;
        if let Some(values) = shown.values.filter(|v| v.len() == shown.mesh.vertex_count()) {
            self.buffers.set_values(values);
            changes = self.buffers.update_with(shown.mesh, shown.normals, frame);
            changes.vertices = true;
            // The second update sees the new topology as known already: keep the first's word,
            // or a new mesh drawn in colour keeps the old mesh's triangles.
            changes.indices |= first.indices;
        }
        match &mut self.gpu {
            Some(surface) => surface.upload(&gpu.device, &gpu.queue, &self.buffers, changes),
            None => self.gpu = Some(GpuSurface::new(&gpu.device, &self.buffers)),
        }
    }

    /// Shows nothing (and forgets the key, so the next [`show`](Self::show) uploads).
    pub fn clear(&mut self) {
        self.gpu = None;
        self.shown = None;
    }

    /// The mesh on the GPU, if one is shown.
    pub fn surface(&self) -> Option<&GpuSurface> {
        self.gpu.as_ref()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use taut_core::VertexId;

    fn quads(n: u32) -> PolyMesh {
        let positions = (0..=n).flat_map(|i| [DVec3::new(f64::from(i), 0.0, 0.0), DVec3::new(f64::from(i), 1.0, 0.0)]);
        let faces: Vec<[u32; 4]> = (0..n).map(|i| [2 * i, 2 * i + 2, 2 * i + 3, 2 * i + 1]).collect();
        PolyMesh::from_polygons(positions.collect(), &faces).unwrap()
    }

    #[test]
    fn a_mesh_is_uploaded_again_only_when_its_key_changes() {
        let gpu = Gpu::headless(crate::AdapterPreference::Software).unwrap_or_else(|e| panic!("{e}"));
        let frame = DisplayFrame::default();
        let mut cache = SurfaceCache::<u32>::default();
        let mut mesh = quads(2);
        let made = std::cell::Cell::new(0);
        let show = |cache: &mut SurfaceCache<u32>, key: u32, mesh: &PolyMesh| {
            cache.show_with(
                &gpu,
                key,
                || {
                    made.set(made.get() + 1);
                    Some(ShownMesh::plain(mesh))
                },
                &frame,
            )
        };
        show(&mut cache, 1, &mesh);
        show(&mut cache, 1, &mesh);
        assert_eq!(made.get(), 1, "the same key shows what is there");
        assert_eq!(cache.surface().unwrap().index_uploads(), 1);
        // A drag: a new key, the same connectivity: the vertices go up, the indices stay.
        mesh.set_position(VertexId(0), DVec3::new(0.0, 0.0, 0.5));
        show(&mut cache, 2, &mesh);
        assert_eq!((made.get(), cache.surface().unwrap().index_uploads()), (2, 1));
        // A new mesh in colour: its triangles go up too.
        let other = quads(3);
        let values = vec![0.5f32; other.vertex_count()];
        cache.show(&gpu, 3, ShownMesh { mesh: &other, normals: None, values: Some(&values) }, &frame);
        assert_eq!(cache.surface().unwrap().index_uploads(), 2);
        assert_eq!(cache.surface().unwrap().index_count, 3 * 6);
        // Cleared, the same key uploads again; nothing to show shows nothing.
        cache.clear();
        assert!(cache.surface().is_none());
        show(&mut cache, 3, &other);
        assert_eq!(made.get(), 3);
        cache.show_with(&gpu, 4, || None, &frame);
        assert!(cache.surface().is_none());
    }
}
