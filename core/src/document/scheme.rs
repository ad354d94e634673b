//! The surface scheme a document asks for ([`SchemeKind`]) and the subdivision schemes' settings
//! ([`SubdivSettings`]): properties of the document, saved with it; the schemes themselves are in
//! [`crate::surface`].

use crate::{Error, Result};
use serde::{Deserialize, Serialize};

/// The schemes a document can use.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum SchemeKind {
    /// Nonuniform spline diffusion: interpolates the fixed cage vertices, with tension.
    #[default]
    Nusd,
    /// Catmull–Clark subdivision (any polygons), with creases.
    CatmullClark,
    /// Loop subdivision (triangle cages), with creases.
    Loop,
    /// A curve mesh on the Catmull–Clark limit surface filled with G1 Gregory patches, edited
    /// vertex by vertex.
    CurveMesh,
}

impl SchemeKind {
    /// Every scheme, in the order the editor lists them.
    pub const ALL: [SchemeKind; 4] =
        [SchemeKind::Nusd, SchemeKind::CatmullClark, SchemeKind::Loop, SchemeKind::CurveMesh];

    /// The name a designer reads.
    pub fn display_name(self) -> &'static str {
        match self {
            SchemeKind::Nusd => "NUSD",
            SchemeKind::CatmullClark => "Catmull–Clark",
            SchemeKind::Loop => "Loop",
            SchemeKind::CurveMesh => "Curve mesh",
        }
    }

    /// The name on the command line and in files.
    pub fn cli_name(self) -> &'static str {
        match self {
            SchemeKind::Nusd => "nusd",
            SchemeKind::CatmullClark => "catmull-clark",
            SchemeKind::Loop => "loop",
            SchemeKind::CurveMesh => "curve-mesh",
        }
    }

    /// True for the subdivision schemes (creases apply, tension and fixed flags do not).
    pub fn is_subdivision(self) -> bool {
        matches!(self, SchemeKind::CatmullClark | SchemeKind::Loop)
    }
}

impl std::str::FromStr for SchemeKind {
    type Err = String;
    fn from_str(s: &str) -> std::result::Result<Self, String> {
        SchemeKind::ALL
            .into_iter()
            .find(|k| k.cli_name() == s)
            .ok_or_else(|| format!("unknown scheme '{s}' (use nusd, catmull-clark, loop or curve-mesh)"))
    }
}

/// Settings of the subdivision schemes, saved with the document.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct SubdivSettings {
    /// Subdivision levels of the surface drawn and exported.
    pub levels: u32,
}

impl Default for SubdivSettings {
    fn default() -> Self {
        SubdivSettings { levels: 3 }
    }
}

impl SubdivSettings {
    /// Checks every field, with a message a designer can act on.
    pub fn validate(&self) -> Result<()> {
        if self.levels == 0 || self.levels > crate::subdiv::MAX_LEVELS {
            return Err(Error::Input(format!(
                "subdivision levels must be 1 to {}, not {}",
                crate::subdiv::MAX_LEVELS,
                self.levels
            )));
        }
        Ok(())
    }
}
