//! `[algorithm]`: which of the paper's algorithms (IPPO, HE, Other-Play).

use serde::{Deserialize, Serialize};

/// Which of the paper's algorithms; they differ only in these fields.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct AlgorithmConfig {
    /// `ippo`, `he` (high-entropy IPPO) or `op` (Other-Play). A label for tables; HE's
    /// different entropy and λ are set in `[ppo]` by its config file.
    pub name: String,
    /// Other-Play symmetries drawn per seat and episode: `none` (IPPO, HE), `colour`,
    /// `rotation` or `both` (Φ_col × Φ_rot).
    pub symmetries: SymmetrySet,
}

impl Default for AlgorithmConfig {
    fn default() -> Self {
        AlgorithmConfig {
            name: "ippo".into(),
            symmetries: SymmetrySet::None,
        }
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum SymmetrySet {
    None,
    Colour,
    Rotation,
    Both,
}

impl SymmetrySet {
    pub fn colours(self) -> bool {
        matches!(self, SymmetrySet::Colour | SymmetrySet::Both)
    }
    pub fn rotations(self) -> bool {
        matches!(self, SymmetrySet::Rotation | SymmetrySet::Both)
    }
}
