//! Independent references: closed forms and an adaptive, error-controlled
//! integrator, none of which share code with the Gear/Verlet time loop.

pub mod dissipative;
pub mod ode;
