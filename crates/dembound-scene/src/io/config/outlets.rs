//! `[[outlet]]` (addition, issue 28): a region whose entering free spheres
//! are removed (`crate::removal`), `region = { box = { lower, upper } }`
//! in m.

use super::checks::{check, finite3};
use super::{SceneError, SceneFile};
use serde::{Deserialize, Serialize};

/// One `[[outlet]]`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct OutletSection {
    pub region: RegionSection,
}

/// An outlet's region: exactly one shape.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase", deny_unknown_fields)]
pub enum RegionSection {
    /// An axis-aligned box, m.
    Box { lower: [f64; 3], upper: [f64; 3] },
}

impl OutletSection {
    /// The box of the outlet, m.
    pub fn outlet_box(&self) -> crate::removal::OutletBox {
        match self.region {
            RegionSection::Box { lower, upper } => crate::removal::OutletBox { lower, upper },
        }
    }
}

impl SceneFile {
    pub(super) fn validate_outlets(&self) -> Result<(), SceneError> {
        for (i, o) in self.outlets.iter().enumerate() {
            let RegionSection::Box { lower, upper } = o.region;
            let key = format!("outlet[{i}].region.box");
            finite3(&format!("{key}.lower"), lower, "m")?;
            finite3(&format!("{key}.upper"), upper, "m")?;
            check(
                (0..3).all(|a| upper[a] > lower[a]),
                &format!("{key}.upper"),
                format!("{upper:?}"),
                &format!("each coordinate > {key}.lower's ({lower:?}), m"),
            )?;
        }
        Ok(())
    }
}
