//! `[[outlet]]` (addition, issue 28): a region whose entering free spheres
//! are removed (`crate::removal`), `region = { box = { lower, upper } }`
//! or `{ cylinder = { center, axis, radius, length } }` in m: the region
//! type of the inlets (`crate::region`).

use super::{SceneError, SceneFile};
use crate::region::Region;
use serde::{Deserialize, Serialize};

/// One `[[outlet]]`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct OutletSection {
    pub region: Region,
}

impl OutletSection {
    /// The engine's region of the outlet (a unit cylinder axis), m.
    pub fn outlet_region(&self) -> Region {
        self.region.normalized()
    }
}

impl SceneFile {
    pub(super) fn validate_outlets(&self) -> Result<(), SceneError> {
        for (i, o) in self.outlets.iter().enumerate() {
            o.region.validate(&format!("outlet[{i}].region"))?;
        }
        Ok(())
    }
}
