//! The two-body mechanics of a free boundary (`boundary.fixed = false`):
//! the boundary's mass, the reduced mass and gravity of the relative
//! motion, and each sphere's velocities recovered from the centre of mass.

use super::{GravityOn, Scenario};

/// The two spheres of a free-boundary run, for recovering each sphere's
/// motion from the relative coordinate: the centre of mass moves
/// ballistically (the contact force is internal), so with the relative
/// velocity v = v_m − v_b, v_m = V + (m_b/M) v and v_b = V − (m_m/M) v.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TwoBody {
    /// m_m, kg.
    pub particle_mass: f64,
    /// m_b, kg.
    pub boundary_mass: f64,
    /// Centre-of-mass velocity at t = 0, m/s, upward positive.
    pub cm_velocity: f64,
    /// Its constant acceleration, m/s² (−g, −g m_m/M or 0).
    pub cm_acceleration: f64,
}

impl TwoBody {
    /// (v_m, v_b) at time `t` (s) for the relative velocity `relative` (m/s).
    pub fn velocities(&self, t: f64, relative: f64) -> (f64, f64) {
        let total = self.particle_mass + self.boundary_mass;
        let cm = self.cm_velocity + self.cm_acceleration * t;
        (
            cm + self.boundary_mass / total * relative,
            cm - self.particle_mass / total * relative,
        )
    }
}

impl Scenario {
    /// Mass of a free boundary, ρ_b 4/3 π (r R_m)³, kg; `None` when fixed.
    pub fn boundary_mass(&self) -> Option<f64> {
        let b = &self.boundary;
        (!b.fixed).then(|| {
            let radius = b.radius_ratio * self.particle.radius;
            let density = b.density.unwrap_or(self.particle.density);
            4.0 / 3.0 * std::f64::consts::PI * density * radius.powi(3)
        })
    }

    /// The mass of the relative motion, kg: the particle's against a fixed
    /// boundary, m* = m_m m_b/(m_m + m_b) against a free one.
    pub fn reduced_mass(&self) -> f64 {
        let m = self.particle.mass();
        match self.boundary_mass() {
            None => m,
            Some(mb) => m * mb / (m + mb),
        }
    }

    /// Gravity in the relative motion (the particle's minus the
    /// boundary's), m/s², acting to close the gap: g with gravity on the
    /// particle only, 0 with gravity on both or none.
    pub fn relative_gravity(&self) -> f64 {
        match self.motion.gravity_on {
            GravityOn::Particle => self.motion.gravity,
            GravityOn::Both | GravityOn::None => 0.0,
        }
    }

    /// Initial relative velocity v_m − v_b, m/s (the particle's velocity
    /// against a fixed boundary).
    pub fn relative_velocity(&self) -> f64 {
        if self.boundary.fixed {
            self.motion.velocity
        } else {
            self.motion.velocity - self.boundary.velocity.unwrap_or(0.0)
        }
    }

    /// The two spheres of a free-boundary run; `None` when the boundary is fixed.
    pub fn two_body(&self) -> Option<TwoBody> {
        let mb = self.boundary_mass()?;
        let mm = self.particle.mass();
        let total = mm + mb;
        let g = self.motion.gravity;
        let vb = self.boundary.velocity.unwrap_or(0.0);
        let cm_acceleration = match self.motion.gravity_on {
            GravityOn::Particle => -g * mm / total,
            GravityOn::Both => -g,
            GravityOn::None => 0.0,
        };
        Some(TwoBody {
            particle_mass: mm,
            boundary_mass: mb,
            cm_velocity: (mm * self.motion.velocity + mb * vb) / total,
            cm_acceleration,
        })
    }

    /// Relative speed at the first contact, m/s (≥ 0): √(v₀² + 2 g H₀) with
    /// v₀ and g those of the relative motion ([`Self::relative_velocity`],
    /// [`Self::relative_gravity`]), |v₀| without gravity (ERRATA item 7).
    pub fn impact_speed(&self) -> f64 {
        let v = self.relative_velocity();
        (v * v + 2.0 * self.relative_gravity() * self.motion.gap).sqrt()
    }
}
