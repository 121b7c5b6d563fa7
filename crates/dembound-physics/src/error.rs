//! The crate's one error type.

use std::fmt;

/// A contact model that cannot be built: the offending key, its value and
/// what is allowed there.
#[derive(Debug, Clone, PartialEq)]
pub struct PhysicsError {
    /// The configuration key, e.g. `contact.restitution`.
    pub key: String,
    /// The value given (or `missing`).
    pub value: String,
    /// What is allowed, with units, e.g. `0 < e ≤ 1`.
    pub allowed: String,
}

impl PhysicsError {
    /// An error for `key` = `value`, which must satisfy `allowed`.
    pub fn new(
        key: impl Into<String>,
        value: impl fmt::Display,
        allowed: impl Into<String>,
    ) -> Self {
        Self {
            key: key.into(),
            value: value.to_string(),
            allowed: allowed.into(),
        }
    }
}

impl fmt::Display for PhysicsError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{} = {}: allowed {}", self.key, self.value, self.allowed)
    }
}

impl std::error::Error for PhysicsError {}
