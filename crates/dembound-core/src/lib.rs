//! Physics core of dembound: a DEM study of an elastic sphere meeting a
//! boundary sphere (Jasevičius & Kačianauskas 2007). No I/O here: the CLI
//! crate parses, writes and plots.
//!
//! - [`material`]: the two spheres and their effective properties (eqs 2, 5–14);
//! - [`contact`]: normal contact laws behind one trait (eq 4);
//! - [`integrate`]: Gear5 and velocity Verlet behind one trait (eqs 18–19);
//! - [`bounce`]: the bouncing scenario, both stepping modes and event location;
//! - [`exact`]: exact references (closed forms, quadrature), kept apart from
//!   the numerics they check;
//! - [`reference`](mod@reference): independent references for the dissipative laws;
//! - [`study`]: validation, convergence and parametric studies;
//! - [`error`]: the crate's one error type, [`Error`];
//! - [`calibration`]: from a configured model to the concrete law, a target
//!   restitution turned into its coefficient (above `contact` and `reference`).

pub mod bounce;
pub mod calibration;
pub mod contact;
pub mod error;
pub mod exact;
pub mod integrate;
pub mod material;
pub mod record;
pub mod reference;
pub mod scenario;
mod serde_inf;
pub mod study;

pub use error::{Error, Result};
