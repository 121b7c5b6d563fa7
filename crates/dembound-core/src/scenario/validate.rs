//! The checks of a [`Scenario`]: each bad input becomes an [`Error::Input`]
//! naming the key, the value and the allowed range ([`super::limits`]).

use super::limits;
use super::{GravityOn, Scenario, MAX_TOLERANCE, MIN_TOLERANCE};
use crate::contact::{ContactLawKind, DampingKind};
use crate::{Error, Result};
use std::fmt;

/// `value` and `allowed` are formatted only when the check fails: the
/// batched sweep validates every case, and formatting the ranges of every
/// key each time cost ~50k instructions a case (76 % of the batched path).
fn check(
    ok: bool,
    field: &str,
    value: impl fmt::Display,
    allowed: impl fmt::Display,
) -> Result<()> {
    if ok {
        Ok(())
    } else {
        Err(Error::Input {
            field: field.into(),
            value: value.to_string(),
            allowed: allowed.to_string(),
        })
    }
}

fn positive(field: &str, x: f64, unit: &str) -> Result<()> {
    if x.is_finite() && x > 0.0 {
        return Ok(());
    }
    check(
        false,
        field,
        limits::Shown(x),
        format_args!("finite and > 0, in {unit}"),
    )
}

/// `range.0 ≤ x ≤ range.1` ([`limits`]).
fn within(field: &str, x: f64, range: (f64, f64), unit: &str) -> Result<()> {
    check(
        x >= range.0 && x <= range.1,
        field,
        limits::Shown(x),
        limits::Described(range, unit),
    )
}

fn ratio(field: &str, x: f64) -> Result<()> {
    check(
        x == f64::INFINITY || (x >= limits::RATIO.0 && x <= limits::RATIO.1),
        field,
        limits::Shown(x),
        format_args!("{}, or \"inf\"", limits::Described(limits::RATIO, "")),
    )
}

fn poisson(field: &str, x: f64) -> Result<()> {
    check(x > -1.0 && x < 0.5, field, x, "-1 < ν < 0.5")
}

impl Scenario {
    /// Checks every field; the first error names the field, value and range.
    pub fn validate(&self) -> Result<()> {
        let p = &self.particle;
        within("particle.radius", p.radius, limits::RADIUS, "m")?;
        within("particle.density", p.density, limits::DENSITY, "kg/m³")?;
        within(
            "particle.youngs_modulus",
            p.youngs_modulus,
            limits::YOUNGS_MODULUS,
            "Pa",
        )?;
        poisson("particle.poisson_ratio", p.poisson_ratio)?;
        let b = &self.boundary;
        ratio("boundary.radius_ratio", b.radius_ratio)?;
        ratio("boundary.modulus_ratio", b.modulus_ratio)?;
        if let Some(nu) = b.poisson_ratio {
            poisson("boundary.poisson_ratio", nu)?;
        }
        self.validate_free_boundary()?;
        if let ContactLawKind::Power(alpha) = self.contact.law {
            check(
                (1.0..=3.0).contains(&alpha),
                "contact.law.power",
                alpha,
                "1 ≤ α ≤ 3",
            )?;
        }
        self.validate_contact()?;
        let m = &self.motion;
        within("motion.gap", m.gap, limits::GAP, "m")?;
        check(
            m.velocity.abs() <= limits::MAX_SPEED,
            "motion.velocity",
            limits::Shown(m.velocity),
            format_args!("-{0:e} to {0:e} m/s", limits::MAX_SPEED),
        )?;
        check(
            m.gravity == 0.0 || (m.gravity >= limits::GRAVITY.0 && m.gravity <= limits::GRAVITY.1),
            "motion.gravity",
            limits::Shown(m.gravity),
            format_args!("0, or {}", limits::Described(limits::GRAVITY, "m/s²")),
        )?;
        check(
            (1..=1_000_000).contains(&m.contacts),
            "motion.contacts",
            m.contacts,
            "1 to 1000000",
        )?;
        if self.relative_gravity() == 0.0 {
            let why = match m.gravity_on {
                GravityOn::Particle => "when motion.gravity = 0",
                GravityOn::Both => {
                    "when motion.gravity_on = \"both\" (no gravity in the relative motion)"
                }
                GravityOn::None => "when motion.gravity_on = \"none\"",
            };
            if b.fixed {
                check(
                    m.velocity < 0.0,
                    "motion.velocity",
                    m.velocity,
                    format_args!("< 0 (moving towards the boundary) {why}"),
                )?;
            } else {
                check(
                    self.relative_velocity() < 0.0,
                    "motion.velocity",
                    m.velocity,
                    format_args!(
                        "< boundary.velocity = {} (the spheres approaching) {why}",
                        b.velocity.unwrap_or(0.0)
                    ),
                )?;
            }
            check(
                m.contacts == 1,
                "motion.contacts",
                m.contacts,
                format_args!("1 {why} (the spheres never meet again)"),
            )?;
        }
        let i = &self.integration;
        if let Some(eta) = i.eta {
            check(
                eta >= limits::ETA.0 && eta <= limits::ETA.1,
                "integration.eta",
                limits::Shown(eta),
                format_args!(
                    "{} (Δt = η T_c; above 0.1 the first contact's e, h_max, T_c are off by more \
                     than ~1 % and from 0.125 the integrator diverges)",
                    limits::Described(limits::ETA, "")
                ),
            )?;
        }
        if let Some(dt) = i.dt {
            positive("integration.dt", dt, "s")?;
            check(
                i.eta.is_none(),
                "integration.eta",
                i.eta.unwrap_or(0.0),
                "absent when integration.dt is given (give one of them)",
            )?;
        }
        if let Some(tol) = i.tolerance {
            check(
                (MIN_TOLERANCE..=MAX_TOLERANCE).contains(&tol),
                "integration.tolerance",
                tol,
                "1e-13 ≤ tolerance ≤ 0.01 (a relative error as a plain fraction: 0.01 = 1 %)",
            )?;
            check(
                i.eta.is_none() && i.dt.is_none(),
                "integration.tolerance",
                tol,
                "absent when integration.eta or integration.dt is given (give one of them)",
            )?;
        }
        Ok(())
    }

    /// `boundary.fixed`, `boundary.density`, `boundary.velocity` and
    /// `motion.gravity_on`: ranges and combinations.
    fn validate_free_boundary(&self) -> Result<()> {
        let b = &self.boundary;
        if b.fixed {
            check(
                b.density.is_none(),
                "boundary.density",
                b.density.unwrap_or(0.0),
                "absent unless boundary.fixed = false (a fixed boundary has no mass in the problem)",
            )?;
            check(
                b.velocity.is_none(),
                "boundary.velocity",
                b.velocity.unwrap_or(0.0),
                "absent unless boundary.fixed = false (a fixed boundary does not move)",
            )?;
            check(
                self.motion.gravity_on != GravityOn::Both,
                "motion.gravity_on",
                "\"both\"",
                "\"particle\" or \"none\" with a fixed boundary (\"both\" needs boundary.fixed = false)",
            )?;
            return Ok(());
        }
        check(
            b.radius_ratio.is_finite(),
            "boundary.radius_ratio",
            b.radius_ratio,
            "finite when boundary.fixed = false (a free half-space would have infinite mass)",
        )?;
        if let Some(rho) = b.density {
            within("boundary.density", rho, limits::DENSITY, "kg/m³")?;
        }
        if let Some(v) = b.velocity {
            check(
                v.abs() <= limits::MAX_SPEED,
                "boundary.velocity",
                limits::Shown(v),
                format_args!("-{0:e} to {0:e} m/s", limits::MAX_SPEED),
            )?;
        }
        Ok(())
    }

    /// The `[contact]` keys: ranges, and which combinations make sense.
    /// The parameters a registry law takes (`contact.stiffness`), from
    /// its row: each given and in the row's range; and no such key for a
    /// law that does not take it. (The paper's laws keep their own checks:
    /// the power law's exponent, Walton–Braun's restitution.)
    fn validate_law_params(&self) -> Result<()> {
        use dembound_physics::contact::registry::NORMAL_LAWS;
        let c = &self.contact;
        let row = c.law.row();
        let model = c.model();
        if let ContactLawKind::Registry(_) = c.law {
            for p in row.params {
                let Some(value) = model.param(p.key) else {
                    return Err(Error::Input {
                        field: format!("contact.{}", p.key),
                        value: "missing".into(),
                        allowed: format!(
                            "{} ({}, {}), required by law = \"{}\"",
                            p.range, p.symbol, p.unit, row.name
                        ),
                    });
                };
                p.check(value).map_err(|e| Error::Input {
                    field: e.key,
                    value: e.value,
                    allowed: e.allowed,
                })?;
            }
        }
        // A parameter given by key belongs to a registry law that takes
        // it by key (the paper's laws spell theirs otherwise: the power
        // law's exponent as law = { power = α }).
        for (key, value) in c.params.iter() {
            let takes = |r: &dembound_physics::contact::registry::NormalRow| {
                r.params.iter().any(|p| p.key == key)
                    && matches!(
                        ContactLawKind::from_name(r.name, None),
                        Some(ContactLawKind::Registry(_))
                    )
            };
            let laws: Vec<String> = NORMAL_LAWS
                .iter()
                .filter(|r| takes(r))
                .map(|r| format!("\"{}\"", r.name))
                .collect();
            let allowed = if laws.is_empty() {
                "absent: no law takes it as a key of its own".to_string()
            } else {
                format!("absent unless law is {}", laws.join(" or "))
            };
            check(takes(row), &format!("contact.{key}"), value, allowed)?;
        }
        Ok(())
    }

    fn validate_contact(&self) -> Result<()> {
        let c = &self.contact;
        if let Some(e) = c.restitution {
            check(
                e > 0.0 && e <= 1.0,
                "contact.restitution",
                e,
                "0 < e ≤ 1 (rebound speed / impact speed)",
            )?;
        }
        if let Some(x) = c.damping_coefficient {
            check(
                x.is_finite() && x >= 0.0,
                "contact.damping_coefficient",
                x,
                "finite and ≥ 0 (N s/m viscous, N s/m^(5/4) tsuji, s viscoelastic)",
            )?;
            check(
                c.restitution.is_none(),
                "contact.damping_coefficient",
                x,
                "absent when contact.restitution is given (give one of them)",
            )?;
        }
        let quoted = |s: &str| format!("\"{s}\"");
        self.validate_law_params()?;
        let law = c.law.name();
        match (c.law, c.damping) {
            (ContactLawKind::WaltonBraun, DampingKind::None) => {
                check(
                    c.damping_coefficient.is_none(),
                    "contact.damping_coefficient",
                    c.damping_coefficient.unwrap_or(0.0),
                    "absent for law = \"walton-braun\" (set contact.restitution: k2 = k1/e²)",
                )?;
                check(
                    c.restitution.is_some(),
                    "contact.restitution",
                    "missing",
                    "0 < e ≤ 1, required by law = \"walton-braun\" (k2 = k1/e²)",
                )?;
                check(
                    !c.attractive,
                    "contact.attractive",
                    c.attractive,
                    "false for law = \"walton-braun\" (the law has no tensile branch)",
                )?;
            }
            (_, DampingKind::None) => {
                check(
                    c.restitution.is_none(),
                    "contact.restitution",
                    c.restitution.unwrap_or(0.0),
                    "absent unless contact.damping is \"viscous\", \"tsuji\" or \"viscoelastic\" or law = \"walton-braun\"",
                )?;
                check(
                    c.damping_coefficient.is_none(),
                    "contact.damping_coefficient",
                    c.damping_coefficient.unwrap_or(0.0),
                    "absent unless contact.damping is \"viscous\", \"tsuji\" or \"viscoelastic\"",
                )?;
            }
            // The physics registry's compatibility table.
            (law, damping) if damping.combines_with(law) => {
                check(
                    c.restitution.is_some() || c.damping_coefficient.is_some(),
                    "contact.restitution",
                    "missing",
                    format_args!(
                        "0 < e ≤ 1 (or contact.damping_coefficient ≥ 0), required by contact.damping = {}",
                        quoted(c.damping.name())
                    ),
                )?;
                if c.damping == DampingKind::Viscoelastic && c.restitution.is_some() {
                    let v = self.impact_speed();
                    check(
                        v > 0.0 && v.is_finite(),
                        "contact.restitution",
                        c.restitution.unwrap_or(0.0),
                        "usable with damping = \"viscoelastic\" only when the first impact speed > 0 (A is solved for at that speed); give contact.damping_coefficient instead",
                    )?;
                }
            }
            (_, damping) => check(
                false,
                "contact.damping",
                quoted(damping.name()),
                format_args!(
                    "with law = {}: {}",
                    quoted(&law),
                    dembound_physics::contact::registry::dampings_for(c.law.row())
                ),
            )?,
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn default_is_valid_and_impact_speed_is_the_papers() {
        let s = Scenario::default();
        s.validate().unwrap();
        // v_c = −0.313 m/s (section 4.2); √(2·9.81·0.005) = 0.3132091953…
        assert!((s.impact_speed() - 0.313_209_195_3).abs() < 1e-10);
    }

    #[test]
    fn each_bad_field_is_named() {
        type Spoil = fn(&mut Scenario);
        let cases: Vec<(&str, Spoil)> = vec![
            ("particle.radius", |s| s.particle.radius = -1.0),
            ("particle.density", |s| s.particle.density = 0.0),
            ("particle.youngs_modulus", |s| {
                s.particle.youngs_modulus = f64::NAN
            }),
            ("particle.poisson_ratio", |s| s.particle.poisson_ratio = 0.5),
            ("boundary.radius_ratio", |s| s.boundary.radius_ratio = 0.0),
            ("boundary.modulus_ratio", |s| {
                s.boundary.modulus_ratio = -2.0
            }),
            ("boundary.poisson_ratio", |s| {
                s.boundary.poisson_ratio = Some(-1.0)
            }),
            ("contact.law.power", |s| {
                s.contact.law = ContactLawKind::Power(0.5)
            }),
            ("contact.restitution", |s| {
                s.contact.law = ContactLawKind::Linear;
                s.contact.damping = DampingKind::Viscous;
                s.contact.restitution = Some(1.5);
            }),
            ("contact.restitution", |s| {
                s.contact.law = ContactLawKind::Linear;
                s.contact.damping = DampingKind::Viscous;
            }),
            ("contact.restitution", |s| s.contact.restitution = Some(0.5)),
            ("contact.damping_coefficient", |s| {
                s.contact.damping = DampingKind::Tsuji;
                s.contact.damping_coefficient = Some(-1.0);
            }),
            ("contact.damping_coefficient", |s| {
                s.contact.damping = DampingKind::Tsuji;
                s.contact.restitution = Some(0.5);
                s.contact.damping_coefficient = Some(1.0);
            }),
            ("contact.damping", |s| {
                s.contact.damping = DampingKind::Viscous;
                s.contact.restitution = Some(0.5);
            }),
            ("contact.damping", |s| {
                s.contact.law = ContactLawKind::Linear;
                s.contact.damping = DampingKind::Tsuji;
                s.contact.restitution = Some(0.5);
            }),
            ("contact.damping", |s| {
                s.contact.law = ContactLawKind::WaltonBraun;
                s.contact.damping = DampingKind::Viscous;
                s.contact.restitution = Some(0.5);
            }),
            ("contact.restitution", |s| {
                s.contact.law = ContactLawKind::WaltonBraun;
            }),
            ("contact.attractive", |s| {
                s.contact.law = ContactLawKind::WaltonBraun;
                s.contact.restitution = Some(0.5);
                s.contact.attractive = true;
            }),
            ("contact.restitution", |s| {
                s.contact.damping = DampingKind::Viscoelastic;
                s.contact.restitution = Some(0.5);
                s.motion.gap = 0.0;
            }),
            ("motion.gap", |s| s.motion.gap = -1e-3),
            ("motion.gravity", |s| s.motion.gravity = -9.81),
            ("motion.contacts", |s| s.motion.contacts = 0),
            ("integration.eta", |s| s.integration.eta = Some(1.5)),
            ("integration.dt", |s| s.integration.dt = Some(0.0)),
            ("boundary.density", |s| s.boundary.density = Some(2000.0)),
            ("boundary.velocity", |s| s.boundary.velocity = Some(0.1)),
            ("motion.gravity_on", |s| {
                s.motion.gravity_on = GravityOn::Both
            }),
            ("boundary.radius_ratio", |s| {
                s.boundary.fixed = false;
                s.boundary.radius_ratio = f64::INFINITY;
            }),
            ("boundary.density", |s| {
                s.boundary.fixed = false;
                s.boundary.density = Some(-1.0);
            }),
            ("boundary.velocity", |s| {
                s.boundary.fixed = false;
                s.boundary.velocity = Some(f64::NAN);
            }),
            ("motion.velocity", |s| {
                s.boundary.fixed = false;
                s.motion.gravity_on = GravityOn::Both;
                s.motion.contacts = 1;
                s.motion.velocity = -0.1;
                s.boundary.velocity = Some(-0.2);
            }),
            ("motion.contacts", |s| {
                s.boundary.fixed = false;
                s.motion.gravity_on = GravityOn::None;
                s.motion.velocity = -0.3;
            }),
            ("integration.tolerance", |s| {
                s.integration.tolerance = Some(0.5)
            }),
            ("integration.tolerance", |s| {
                s.integration.tolerance = Some(1e-8);
                s.integration.eta = Some(0.02);
            }),
            ("integration.tolerance", |s| {
                s.integration.tolerance = Some(1e-8);
                s.integration.dt = Some(1e-9);
            }),
        ];
        for (field, spoil) in cases {
            let mut s = Scenario::default();
            spoil(&mut s);
            match s.validate().unwrap_err() {
                Error::Input { field: f, .. } => assert_eq!(f, field),
                other => panic!("{other:?}"),
            }
        }
    }
}
