//! A curve mesh's edit state ([`CurveMeshEdits`]): read off the curve mesh ([`CurveMesh::edits`])
//! and put back onto a freshly built one ([`CurveMesh::set_edits`]), which is how a saved file and
//! undo reproduce the edited patches bit for bit.

use super::*;

impl CurveMesh {
    /// The current edit state: every edited vertex and curve with its values now.
    pub fn edits(&self) -> CurveMeshEdits {
        CurveMeshEdits {
            shape: self.shape(),
            vertices: self
                .edited_vertices
                .iter()
                .map(|&v| VertexEdit {
                    vertex: v,
                    position: self.topology.position(VertexId(v)).to_array(),
                    normal: self.normals[v as usize].to_array(),
                })
                .collect(),
            curves: self
                .edited_curves
                .iter()
                .map(|&e| CurveEdit { curve: e, inner: self.inner[e as usize].map(|p| p.to_array()) })
                .collect(),
        }
    }

    /// Vertex, curve and patch counts: the `shape` its edit states carry.
    pub fn shape(&self) -> [u32; 3] {
        [self.vertex_count() as u32, self.curve_count() as u32, self.patch_count() as u32]
    }

    /// Sets the edit state: vertices and curves listed take the listed values, every other one
    /// returns to its value as built ([`CurveMeshEdits::default`] clears every edit). Used to reopen a saved curve mesh (on a fresh build from
    /// the same cage) and for undo and redo. Checks everything first (counts, indices, finite
    /// values, unit normals, inner points in their tangent planes) and changes nothing on error.
    pub fn set_edits(&mut self, edits: &CurveMeshEdits) -> Result<Changed> {
        let none = CurveMeshEdits { shape: self.shape(), ..CurveMeshEdits::default() };
        let edits = if *edits == CurveMeshEdits::default() { &none } else { edits };
        if edits.shape != self.shape() {
            return Err(Error::Input(format!(
                "the curve-mesh edits are for {} vertices, {} curves and {} patches, this curve mesh has {}, {} and {}; rebuild from the cage they were made on",
                edits.shape[0],
                edits.shape[1],
                edits.shape[2],
                self.shape()[0],
                self.shape()[1],
                self.shape()[2]
            )));
        }
        // The target values of every vertex and curve that is or was edited.
        let mut vertex_target = std::collections::BTreeMap::new();
        for &v in &self.edited_vertices {
            vertex_target.insert(v, (self.base.positions[v as usize], self.base.normals[v as usize]));
        }
        let mut new_vertices = BTreeSet::new();
        for e in &edits.vertices {
            if e.vertex as usize >= self.vertex_count() || !new_vertices.insert(e.vertex) {
                return Err(Error::Input(format!(
                    "curve-mesh edits: vertex {} is out of range or listed twice",
                    e.vertex
                )));
            }
            let (p, n) = (DVec3::from_array(e.position), DVec3::from_array(e.normal));
            if !p.is_finite() || !n.is_finite() || (n.length() - 1.0).abs() > 1e-9 {
                return Err(Error::Input(format!(
                    "curve-mesh edits: vertex {} has a non-finite position or a normal that is not unit",
                    e.vertex
                )));
            }
            vertex_target.insert(e.vertex, (p, n));
        }
        let vertex_value = |v: VertexId| -> (DVec3, DVec3) {
            vertex_target.get(&v.0).copied().unwrap_or((self.topology.position(v), self.normals[v.index()]))
        };
        let mut curve_target = std::collections::BTreeMap::new();
        for &c in &self.edited_curves {
            curve_target.insert(c, self.base.inner[c as usize]);
        }
        let mut new_curves = BTreeSet::new();
        for e in &edits.curves {
            if e.curve as usize >= self.curve_count() || !new_curves.insert(e.curve) {
                return Err(Error::Input(format!(
                    "curve-mesh edits: curve {} is out of range or listed twice",
                    e.curve
                )));
            }
            curve_target.insert(e.curve, e.inner.map(DVec3::from_array));
        }
        // Every curve whose own points or whose end vertices change must keep its legs in the
        // tangent planes of its ends.
        let mut check: BTreeSet<u32> = curve_target.keys().copied().collect();
        for &v in vertex_target.keys() {
            check.extend(self.topology.outgoing(VertexId(v)).map(|h| h.edge().0));
        }
        for &c in &check {
            let e = EdgeId(c);
            let inner = curve_target.get(&c).copied().unwrap_or(self.inner[c as usize]);
            let (a, b) = self.topology.edge_vertices(e);
            for (k, end) in [(0, a), (1, b)] {
                let (p, n) = vertex_value(end);
                let q = inner[k];
                let leg = q - p;
                let off = leg.dot(n).abs();
                if !q.is_finite()
                    || off > 1e-9 * leg.length() + 1e-12 * (p.length() + q.length())
                    || leg.length() == 0.0
                {
                    return Err(Error::Input(format!(
                        "curve-mesh edits: curve {c}'s control point next to vertex {} is off that vertex's tangent plane; the edits do not belong to this curve mesh",
                        end.0
                    )));
                }
            }
        }
        // Apply the values that differ, then rebuild what they touch.
        let mut vertices = Vec::new();
        for (&v, &(p, n)) in &vertex_target {
            let id = VertexId(v);
            if p != self.topology.position(id) || n != self.normals[v as usize] {
                self.topology.set_position(id, p);
                self.normals[v as usize] = n;
                vertices.push(id);
            }
        }
        let mut curves = Vec::new();
        for (&c, &inner) in &curve_target {
            if inner != self.inner[c as usize] {
                self.inner[c as usize] = inner;
                curves.push(EdgeId(c));
            }
        }
        // A moved vertex moves the ends of its curves too.
        for &v in &vertices {
            curves.extend(self.topology.outgoing(v).map(|h| h.edge()));
        }
        // A vertex or curve that becomes (or stops being) edited changes whether its curves use
        // the limit surface's middle normals: their patches are rebuilt too.
        for &v in self.edited_vertices.symmetric_difference(&new_vertices) {
            vertices.push(VertexId(v));
            curves.extend(self.topology.outgoing(VertexId(v)).map(|h| h.edge()));
        }
        curves.extend(self.edited_curves.symmetric_difference(&new_curves).map(|&c| EdgeId(c)));
        vertices.sort();
        vertices.dedup();
        self.edited_vertices = new_vertices;
        self.edited_curves = new_curves;
        Ok(self.rebuild_around(&vertices, &curves))
    }
}
