//! Typed handles into a [`PolyMesh`](super::PolyMesh). Each is a `u32` index with an invalid
//! value, so a vertex can never be passed where a face is expected.

use std::fmt;

macro_rules! handle {
    ($(#[$doc:meta])* $name:ident, $short:literal) => {
        $(#[$doc])*
        #[derive(Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
        pub struct $name(pub u32);

        impl $name {
            /// The value meaning "none".
            pub const INVALID: Self = Self(u32::MAX);

            /// The index into the mesh's arrays.
            #[inline]
            pub fn index(self) -> usize {
                self.0 as usize
            }

            /// True unless this is [`Self::INVALID`].
            #[inline]
            pub fn is_valid(self) -> bool {
                self.0 != u32::MAX
            }

            #[inline]
            #[allow(dead_code)] // not every handle is made from a bare index
            pub(crate) fn from_index(i: usize) -> Self {
                debug_assert!(i < u32::MAX as usize);
                Self(i as u32)
            }
        }

        impl fmt::Debug for $name {
            fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                if self.is_valid() { write!(f, concat!($short, "{}"), self.0) } else { f.write_str(concat!($short, "-")) }
            }
        }
    };
}

handle!(
    /// A vertex of a mesh.
    VertexId, "v"
);
handle!(
    /// A directed half of an edge; halfedges `2e` and `2e + 1` are twins and form edge `e`.
    HalfedgeId, "h"
);
handle!(
    /// An undirected edge.
    EdgeId, "e"
);
handle!(
    /// A polygonal face.
    FaceId, "f"
);

impl HalfedgeId {
    /// The opposite halfedge of the same edge.
    #[inline]
    pub fn twin(self) -> HalfedgeId {
        HalfedgeId(self.0 ^ 1)
    }

    /// The edge this halfedge belongs to.
    #[inline]
    pub fn edge(self) -> EdgeId {
        EdgeId(self.0 >> 1)
    }
}

impl EdgeId {
    /// One of the two halfedges of this edge (`side` 0 or 1).
    #[inline]
    pub fn halfedge(self, side: u32) -> HalfedgeId {
        HalfedgeId(self.0 * 2 + side)
    }
}
