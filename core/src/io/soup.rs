//! [`Soup`]: polygons as a file describes them, before welding — the common output of every
//! reader. Faces are stored flat (one index array and the offsets of each face), so a file with
//! millions of faces, or one face with millions of corners, costs a few bytes a corner.

use crate::DVec3;

/// Faces in compressed rows: face `f` is `indices[offsets[f]..offsets[f + 1]]`.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct FaceList {
    offsets: Vec<u32>,
    indices: Vec<u32>,
}

impl Default for FaceList {
    fn default() -> Self {
        FaceList { offsets: vec![0], indices: Vec::new() }
    }
}

impl FaceList {
    /// Appends one face.
    pub fn push(&mut self, face: impl AsRef<[u32]>) {
        self.indices.extend_from_slice(face.as_ref());
        self.offsets.push(self.indices.len() as u32);
    }

    /// Appends the corners of a face being built; close it with [`end_face`](Self::end_face).
    pub fn push_corner(&mut self, v: u32) {
        self.indices.push(v);
    }

    /// Ends the face whose corners were pushed since the last face ended.
    pub fn end_face(&mut self) {
        self.offsets.push(self.indices.len() as u32);
    }

    /// Drops the corners pushed since the last face ended.
    pub fn discard_open_face(&mut self) {
        let start = *self.offsets.last().expect("offsets start with 0") as usize;
        self.indices.truncate(start);
    }

    /// Number of faces.
    pub fn len(&self) -> usize {
        self.offsets.len() - 1
    }

    /// True when there is no face.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Number of corners of all faces.
    pub fn corner_count(&self) -> usize {
        self.indices.len()
    }

    /// Face `f`.
    pub fn face(&self, f: usize) -> &[u32] {
        &self.indices[self.offsets[f] as usize..self.offsets[f + 1] as usize]
    }

    /// Every face, in order.
    pub fn iter(&self) -> impl ExactSizeIterator<Item = &[u32]> + '_ {
        (0..self.len()).map(|f| self.face(f))
    }

    /// The offsets (one more than there are faces, starting at 0).
    pub fn offsets(&self) -> &[u32] {
        &self.offsets
    }

    /// All corners, face after face.
    pub fn indices(&self) -> &[u32] {
        &self.indices
    }

    /// The faces as separate lists (for tests and small meshes).
    pub fn to_vecs(&self) -> Vec<Vec<u32>> {
        self.iter().map(<[u32]>::to_vec).collect()
    }
}

impl<F: AsRef<[u32]>> FromIterator<F> for FaceList {
    fn from_iter<I: IntoIterator<Item = F>>(faces: I) -> Self {
        let mut list = FaceList::default();
        for face in faces {
            list.push(face);
        }
        list
    }
}

/// Polygons as a file describes them, before welding.
#[derive(Clone, Debug, Default)]
pub struct Soup {
    pub positions: Vec<DVec3>,
    pub faces: FaceList,
    /// What the reader skipped or guessed, one sentence each.
    pub warnings: Vec<String>,
}
