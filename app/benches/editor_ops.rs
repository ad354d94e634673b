//! Every cage-modelling operation on a 20 000-face cage through the editor's own path, against
//! the one-frame budget (16 ms): `EditorState::mesh_op` (the selection read, the core edit, the
//! fixed flags, tensions and creases carried, `Edit::Replace` checked completely, the undo
//! snapshot, the selection mapped through the provenance), then its undo, all before the surface
//! re-solves (the bench never steps the solver). Also the edits of a drag (one vertex, and all of
//! them as G does), with the mirror option off and on, and Apply mirror on a half.
//!
//! Each row is reported as its fastest and median time and as a ratio to a reference measured in
//! the same run, alternately with it: one clone of the document (what every undo snapshot costs,
//! the floor of an edit through the editor). The cage is a closed torus of 200 × 100 quads (20 000
//! faces, 20 000 vertices) as in `core/benches/mesh_edit.rs`, which times the core edits alone.
//!
//! The editor is a binary crate, so the bench compiles its `editor` module from the source (and
//! `step_out`, the STEP export it shares with the command line).
//! Run with `cargo bench -p taut-app --bench editor_ops`. `TAUT_BENCH_QUICK=1` runs fewer repeats.

#[allow(dead_code, unused_imports)]
#[path = "../src/editor/mod.rs"]
mod editor;
#[allow(dead_code)]
#[path = "../src/step_out.rs"]
mod step_out;

use editor::document::EditorDocument;
use editor::files::RecentFiles;
use editor::mesh_ops::MeshOp;
use editor::select_modes::SelectMode;
use editor::state::EditorState;
use std::hint::black_box;
use std::time::{Duration, Instant};
use taut_core::Result;
use taut_core::mesh::edit::{
    self, Axis, Edited, FaceGrouping, JoinParams, MergeAt, MirrorPlane, Triangulation, delete_faces,
};
use taut_core::mesh::primitives::torus;
use taut_core::{DVec3, Document, EdgeId, Edit, FaceId, PolyMesh, VertexId};

fn ms(d: Duration) -> f64 {
    d.as_secs_f64() * 1e3
}

fn editor_on(cage: PolyMesh) -> EditorState {
    let folder = std::env::temp_dir().join(format!("taut-bench-editor-ops-{}", std::process::id()));
    let _ = std::fs::create_dir_all(&folder);
    EditorState::new(EditorDocument::new(Document::new(cage), None), RecentFiles::in_folder(&folder), None)
}

/// What the selection holds before an operation.
#[derive(Clone, Default)]
struct Pick {
    mode: Option<SelectMode>,
    vertices: Vec<VertexId>,
    edges: Vec<EdgeId>,
    faces: Vec<FaceId>,
}

impl Pick {
    fn set(&self, state: &mut EditorState) {
        let s = &mut state.view.selection;
        s.clear();
        s.mode = self.mode.unwrap_or(SelectMode::Vertex);
        s.vertices = self.vertices.clone();
        s.edges = self.edges.clone();
        s.faces = self.faces.clone();
        s.hovered_vertex = None;
        s.hovered_edge = None;
        s.hovered_face = None;
    }
}

struct Table {
    repeats: usize,
    worst: (f64, String),
}

impl Table {
    /// Times `run` (after `prepare`, untimed), then its undo, alternately with the reference;
    /// `changes`: whether `run` must make an undo step (merge by distance on a cage with nothing
    /// close changes nothing, which the editor records as no step).
    fn row(
        &mut self,
        name: &str,
        state: &mut EditorState,
        changes: bool,
        core: Option<&dyn Fn()>,
        mut prepare: impl FnMut(&mut EditorState),
        mut run: impl FnMut(&mut EditorState),
    ) {
        let (mut runs, mut undos, mut references, mut cores) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
        let mut faces = 0;
        for _ in 0..self.repeats {
            prepare(state);
            let revision = state.document.revision();
            let t = Instant::now();
            run(state);
            runs.push(t.elapsed());
            if let Some(n) = state.notice.take().filter(|n| n.is_error) {
                panic!("{name}: refused: {}", n.text);
            }
            assert_eq!(state.document.revision() != revision, changes, "{name}: changed the document?");
            faces = state.document.doc().cage.face_count();
            let t = Instant::now();
            if changes {
                state.undo();
            }
            undos.push(t.elapsed());
            let t = Instant::now();
            black_box(state.document.doc().clone());
            references.push(t.elapsed());
            if let Some(core) = core {
                let t = Instant::now();
                core();
                cores.push(t.elapsed());
            }
        }
        for v in [&mut runs, &mut undos, &mut references, &mut cores] {
            v.sort();
        }
        let median = ms(runs[runs.len() / 2]);
        let ratio = runs[0].as_secs_f64() / references[0].as_secs_f64();
        if median > self.worst.0 {
            self.worst = (median, name.to_string());
        }
        // The core edit alone, fastest run: what the editor adds on top of it.
        let core = cores.first().map_or_else(String::new, |&c| {
            format!("  core edit {:>5.2} ms, editor adds {:>5.2} ms", ms(c), ms(runs[0]) - ms(c))
        });
        println!(
            "  {name:<44} {:>6.2} ms (median {median:>6.2}) {ratio:>5.1}x clone  undo {:>4.2} ms {faces:>6} faces  {}{core}",
            ms(runs[0]),
            ms(undos[undos.len() / 2]),
            if median <= 16.0 { "within a frame" } else { "OVER 16 ms" }
        );
    }

    /// A modelling operation on a selection.
    fn op(&mut self, name: &str, state: &mut EditorState, op: MeshOp, pick: &Pick, core: impl Fn() -> Result<Edited>) {
        let changes = op != MeshOp::MergeByDistance;
        let core = || {
            black_box(core().unwrap_or_else(|e| panic!("{name}: {e}")));
        };
        self.row(name, state, changes, Some(&core), |s| pick.set(s), |s| s.mesh_op(op));
    }
}

fn main() {
    // The allocator settings of the `taut` binary, so the times are the editor's.
    taut_core::memory::keep_freed_memory();
    let quick = std::env::var_os("TAUT_BENCH_QUICK").is_some();
    let repeats = if quick { 3 } else { 9 };
    let ring = torus(200, 100, 2.0, 0.6).unwrap();
    let mut state = editor_on(ring.clone());
    let clone = (0..repeats)
        .map(|_| {
            let t = Instant::now();
            black_box(state.document.doc().clone());
            t.elapsed()
        })
        .min()
        .unwrap();
    println!(
        "torus cage: {} faces, {} vertices; one document clone (the reference) {:.2} ms; budget 16 ms",
        ring.face_count(),
        ring.vertex_count(),
        ms(clone)
    );
    let mut table = Table { repeats, worst: (0.0, String::new()) };
    let patch: Vec<FaceId> = (0..50u32).flat_map(|i| (0..50u32).map(move |j| FaceId(i * 100 + j))).collect();
    let along = ring.find_halfedge(VertexId(0), VertexId(1)).unwrap().edge();
    let faces = |faces: Vec<FaceId>| Pick { mode: Some(SelectMode::Face), faces, ..Default::default() };
    let vertices = |vertices: Vec<VertexId>| Pick { mode: Some(SelectMode::Vertex), vertices, ..Default::default() };
    let edges = |edges: Vec<EdgeId>| Pick { mode: Some(SelectMode::Edge), edges, ..Default::default() };
    let r = &ring;
    let offset = 0.2 * r.edge_length(EdgeId(0));
    let one_face = faces(vec![FaceId(5)]);
    let the_patch = faces(patch.clone());
    let all: Vec<VertexId> = r.vertices().collect();
    let threshold = 1e-3 * r.bounding_diagonal();
    let t = &mut table;
    let s = &mut state;
    t.op("extrude one face", s, MeshOp::Extrude, &one_face, || {
        edit::extrude_faces(r, &[FaceId(5)], FaceGrouping::Region, offset)
    });
    t.op("extrude a 50 x 50 patch", s, MeshOp::Extrude, &the_patch, || {
        edit::extrude_faces(r, &patch, FaceGrouping::Region, offset)
    });
    t.op("inset one face", s, MeshOp::Inset, &one_face, || {
        edit::inset_faces(r, &[FaceId(5)], FaceGrouping::Region, offset)
    });
    t.op("inset a 50 x 50 patch", s, MeshOp::Inset, &the_patch, || {
        edit::inset_faces(r, &patch, FaceGrouping::Region, offset)
    });
    t.op("loop cut round the torus (200 quads)", s, MeshOp::LoopCut, &edges(vec![along]), || {
        edit::loop_cut(r, along, 0.5)
    });
    t.op("delete one face", s, MeshOp::Delete, &one_face, || edit::delete_faces(r, &[FaceId(5)]));
    t.op("delete a 50 x 50 patch", s, MeshOp::DeleteFaces, &the_patch, || edit::delete_faces(r, &patch));
    t.op("delete one vertex", s, MeshOp::DeleteVertices, &vertices(vec![VertexId(5)]), || {
        edit::delete_vertices(r, &[VertexId(5)])
    });
    t.op("delete one edge", s, MeshOp::DeleteEdges, &edges(vec![EdgeId(7)]), || edit::delete_edges(r, &[EdgeId(7)]));
    t.op("dissolve one vertex", s, MeshOp::DissolveVertices, &vertices(vec![VertexId(5)]), || {
        edit::dissolve_vertices(r, &[VertexId(5)])
    });
    t.op("dissolve one edge", s, MeshOp::DissolveEdges, &edges(vec![EdgeId(7)]), || {
        edit::dissolve_edges(r, &[EdgeId(7)])
    });
    t.op("dissolve a 50 x 50 patch into one face", s, MeshOp::DissolveFaces, &the_patch, || {
        edit::dissolve_faces(r, &patch)
    });
    t.op(
        "merge two vertices at their centre",
        s,
        MeshOp::MergeAtCentre,
        &vertices(vec![VertexId(0), VertexId(1)]),
        || edit::merge_vertices(r, &[VertexId(0), VertexId(1)], MergeAt::Centre),
    );
    t.op("merge by distance over all (nothing close)", s, MeshOp::MergeByDistance, &Pick::default(), || {
        edit::merge_by_distance(r, &all, threshold)
    });
    t.op("subdivide one edge", s, MeshOp::Subdivide, &edges(vec![EdgeId(7)]), || {
        edit::split_edges(r, &[EdgeId(7)], 0.5)
    });
    t.op("connect two corners of a face", s, MeshOp::Connect, &vertices(vec![VertexId(0), VertexId(101)]), || {
        edit::connect_vertices(r, VertexId(0), VertexId(101))
    });
    t.op("flip all normals", s, MeshOp::FlipNormals, &Pick::default(), || edit::flip_normals(r, None));
    t.op("triangulate all", s, MeshOp::Triangulate, &Pick::default(), || {
        edit::triangulate(r, None, Triangulation::ShortestDiagonal)
    });

    // Fill the hole of one deleted face; join the triangles of the triangulated torus.
    let mut holed = editor_on(delete_faces(&ring, &[FaceId(5)]).unwrap().mesh);
    let hole: Vec<EdgeId> = {
        let cage = &holed.document.doc().cage;
        cage.edges().filter(|&e| cage.is_boundary_edge(e)).collect()
    };
    let holed_cage = holed.document.doc().cage.clone();
    table.op("fill a hole (4 boundary edges)", &mut holed, MeshOp::Fill, &edges(hole.clone()), || {
        edit::fill_edges(&holed_cage, &hole)
    });
    state.view.selection.clear();
    state.mesh_op(MeshOp::Triangulate);
    let mut triangles = editor_on(state.document.doc().cage.clone());
    let tris = triangles.document.doc().cage.clone();
    table.op("join all 40 000 triangles", &mut triangles, MeshOp::JoinTriangles, &Pick::default(), || {
        edit::join_triangles(&tris, None, &JoinParams::default())
    });

    // The edits of a drag: one vertex, and every vertex (G on everything), mirror off and on.
    let mut drag = editor_on(ring.clone());
    let all: Vec<VertexId> = ring.vertices().collect();
    let one = vec![(VertexId(5), ring.position(VertexId(5)) + DVec3::new(0.01, 0.02, 0.03))];
    let every: Vec<(VertexId, DVec3)> = all.iter().map(|&v| (v, ring.position(v) + DVec3::Z * 0.01)).collect();
    for mirror in [None, Some(MirrorPlane::new(Axis::X, 0.0))] {
        drag.edit(Edit::SetMirror(mirror));
        let on = if mirror.is_some() { ", mirror on" } else { "" };
        let (a, b) = (one.clone(), every.clone());
        table.row(
            &format!("move one vertex{on}"),
            &mut drag,
            true,
            None,
            |_| {},
            |s| s.edit(Edit::MoveVertices(a.clone())),
        );
        table.row(
            &format!("move all vertices{on}"),
            &mut drag,
            true,
            None,
            |_| {},
            |s| s.edit(Edit::MoveVertices(b.clone())),
        );
    }

    // Apply mirror: the half x >= 0 of the torus made whole.
    let left: Vec<FaceId> =
        ring.faces().filter(|&f| ring.face_vertices(f).map(|v| ring.position(v).x).sum::<f64>() < 0.0).collect();
    let mut half = editor_on(delete_faces(&ring, &left).unwrap().mesh);
    half.edit(Edit::SetMirror(Some(MirrorPlane::new(Axis::X, 0.0))));
    let half_cage = half.document.doc().cage.clone();
    let plane = MirrorPlane::new(Axis::X, 0.0);
    let core = || {
        black_box(edit::apply_mirror(&half_cage, plane, edit::DEFAULT_MIRROR_TOLERANCE).unwrap());
    };
    table.row("apply mirror (10 000 faces made 20 000)", &mut half, true, Some(&core), |_| {}, |s| s.apply_mirror());

    println!("slowest (median): {} at {:.2} ms", table.worst.1, table.worst.0);
}
