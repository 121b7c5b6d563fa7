//! `dembound keys`: every scenario key with its unit, default and allowed
//! range. The numeric ranges are the constants the validation checks
//! ([`dembound_core::bounce::limits`]), the defaults those of
//! [`Scenario::default`], so the table cannot drift from either.

use super::{CliError, CliResult};
use clap::Args;
use comfy_table::{presets, ContentArrangement, Table};
use dembound_core::bounce::limits::{self, describe, show};
use dembound_core::bounce::{Scenario, MAX_TOLERANCE, MIN_TOLERANCE};
use dembound_core::contact::ContactLawKind;
use dembound_physics::contact::law_params::given_parameters;
use dembound_physics::contact::registry::NormalRow;
use serde::Serialize;
use std::borrow::Cow;
use std::io::Write;

#[derive(Debug, Args)]
pub struct KeysArgs {
    /// Print the table as a JSON array of {key, unit, default, allowed, meaning}
    #[arg(long)]
    pub json: bool,
    /// The keys of a scene file (`dembound scene`) instead of a scenario's
    #[arg(long)]
    pub scene: bool,
}

/// One scenario key.
#[derive(Debug, Clone, Serialize)]
pub struct KeyInfo {
    /// `section.key`, as in the TOML file and `--set`.
    pub key: Cow<'static, str>,
    /// SI unit, "" when dimensionless.
    pub unit: Cow<'static, str>,
    /// The default, or what an omitted key means.
    pub default: String,
    /// The allowed values or range.
    pub allowed: String,
    pub meaning: Cow<'static, str>,
}

/// The rows of the normal laws' parameters given by key
/// (`contact.stiffness`), read from the physics registry's rows: each
/// parameter that some law `takes` as a key, with its symbol, its units by
/// law and its range.
pub fn law_parameter_rows(takes: impl Fn(&NormalRow) -> bool) -> Vec<KeyInfo> {
    use dembound_physics::contact::registry::NORMAL_LAWS;
    let mut rows = Vec::new();
    for g in given_parameters() {
        let p = g.spec;
        let laws: Vec<&NormalRow> = NORMAL_LAWS
            .iter()
            .filter(|r| takes(r) && r.params.iter().any(|q| q.key == p.key))
            .collect();
        if laws.is_empty() {
            continue;
        }
        let names: Vec<&str> = laws.iter().map(|r| r.name).collect();
        let units: Vec<&str> = laws
            .iter()
            .filter_map(|r| r.params.iter().find(|q| q.key == p.key))
            .map(|q| q.unit)
            .collect();
        let unit = if units.iter().all(|u| *u == "1") {
            String::new()
        } else if units.iter().all(|u| *u == units[0]) {
            units[0].to_string()
        } else {
            units
                .iter()
                .zip(&names)
                .map(|(u, n)| format!("{u} ({n})"))
                .collect::<Vec<_>>()
                .join(", ")
        };
        rows.push(KeyInfo {
            key: format!("contact.{}", p.key).into(),
            unit: unit.into(),
            default: "none".into(),
            allowed: format!(
                "{}; only with law = {}",
                p.range.to_string().replace('x', p.symbol),
                names.join(", ")
            ),
            meaning: format!("{} of {}", p.symbol, names.join(", ")).into(),
        });
    }
    rows
}

/// Every scenario key.
pub fn keys() -> Vec<KeyInfo> {
    let d = Scenario::default();
    let row = |key: &'static str,
               unit: &'static str,
               default: String,
               allowed: String,
               meaning: &'static str| KeyInfo {
        key: key.into(),
        unit: unit.into(),
        default,
        allowed,
        meaning: meaning.into(),
    };
    let ratio = format!("{}, or \"inf\"", describe(limits::RATIO, ""));
    let speed = format!(
        "{} to {}",
        show(-limits::MAX_SPEED),
        show(limits::MAX_SPEED)
    );
    let poisson = "-1 < ν < 0.5".to_string();
    let mut rows = vec![
        row(
            "particle.radius",
            "m",
            show(d.particle.radius),
            describe(limits::RADIUS, ""),
            "R_m, the mobile sphere's radius (warning above 0.1 m)",
        ),
        row(
            "particle.density",
            "kg/m³",
            show(d.particle.density),
            describe(limits::DENSITY, ""),
            "ρ",
        ),
        row(
            "particle.youngs_modulus",
            "Pa",
            show(d.particle.youngs_modulus),
            describe(limits::YOUNGS_MODULUS, ""),
            "E_m (warning below 1e5 Pa)",
        ),
        row(
            "particle.poisson_ratio",
            "",
            show(d.particle.poisson_ratio),
            poisson.clone(),
            "ν_m",
        ),
        row(
            "boundary.radius_ratio",
            "",
            show(d.boundary.radius_ratio),
            ratio.clone(),
            "r = R_b/R_m; inf: a half-space",
        ),
        row(
            "boundary.modulus_ratio",
            "",
            show(d.boundary.modulus_ratio),
            ratio,
            "ζ = E_b/E_m; inf: rigid",
        ),
        row(
            "boundary.poisson_ratio",
            "",
            "the particle's".into(),
            poisson,
            "ν_b",
        ),
        row(
            "boundary.fixed",
            "",
            "true".into(),
            "true, false".into(),
            "false: a free sphere (two-body collision)",
        ),
        row(
            "boundary.density",
            "kg/m³",
            "the particle's".into(),
            format!("{}; only with fixed = false", describe(limits::DENSITY, "")),
            "ρ_b of a free boundary",
        ),
        row(
            "boundary.velocity",
            "m/s",
            "0".into(),
            format!("{speed}; only with fixed = false"),
            "initial velocity of a free boundary, upward positive",
        ),
        row(
            "contact.law",
            "",
            format!("\"{}\"", d.contact.law.name()),
            law_names(),
            "normal contact law",
        ),
        row(
            "contact.damping",
            "",
            "\"none\"".into(),
            "\"none\"; \"viscous\" (linear); \"tsuji\", \"viscoelastic\" (hertz)".into(),
            "dissipation of the law",
        ),
        row(
            "contact.restitution",
            "",
            "none".into(),
            "0 < e ≤ 1; with damping or walton-braun (then also ω₂Δt ≤ 0.9 Gear5, 0.5 Verlet)"
                .into(),
            "target coefficient of restitution",
        ),
        row(
            "contact.damping_coefficient",
            "N s/m, N s/m^(5/4) or s",
            "none".into(),
            "finite, ≥ 0; instead of restitution".into(),
            "c (viscous), γ (tsuji), A (viscoelastic)",
        ),
        row(
            "contact.attractive",
            "",
            "false".into(),
            "true, false (not with walton-braun)".into(),
            "may the damping pull",
        ),
        row(
            "contact.calibration",
            "",
            "\"exact\"".into(),
            "\"exact\", \"formula\"".into(),
            "how restitution becomes the coefficient",
        ),
        row(
            "motion.gap",
            "m",
            show(d.motion.gap),
            format!(
                "{}, and g T_c/|v_c| ≤ {} (gravity must not dominate the contact)",
                describe(limits::GAP, ""),
                limits::MAX_GRAVITY_SHARE
            ),
            "initial distance between the surfaces",
        ),
        row(
            "motion.velocity",
            "m/s",
            show(d.motion.velocity),
            format!("{speed}; < 0 without gravity"),
            "initial velocity, upward positive",
        ),
        row(
            "motion.gravity",
            "m/s²",
            show(d.motion.gravity),
            format!("0, or {}", describe(limits::GRAVITY, "")),
            "g, acting downward",
        ),
        row(
            "motion.contacts",
            "",
            d.motion.contacts.to_string(),
            "1 to 1000000; 1 without gravity".into(),
            "rebounds to run",
        ),
        row(
            "motion.gravity_on",
            "",
            "\"particle\"".into(),
            "\"particle\", \"both\" (free boundary), \"none\"".into(),
            "which spheres gravity acts on",
        ),
        row(
            "integration.scheme",
            "",
            "\"gear5\"".into(),
            "\"gear5\", \"verlet\"".into(),
            "time integrator",
        ),
        row(
            "integration.eta",
            "",
            show(dembound_core::bounce::DEFAULT_ETA),
            describe(limits::ETA, ""),
            "Δt = η T_c (T_c the law's contact-time estimate)",
        ),
        row(
            "integration.dt",
            "s",
            "none (η is used)".into(),
            format!("> 0 and ≤ {} T_c", limits::MAX_ETA),
            "Δt, instead of eta",
        ),
        row(
            "integration.tolerance",
            "",
            "none".into(),
            format!(
                "{} (a plain fraction: 0.01 = 1 %)",
                describe((MIN_TOLERANCE, MAX_TOLERANCE), "")
            ),
            "accuracy target instead of eta or dt",
        ),
        row(
            "integration.stepping",
            "",
            "\"event\"".into(),
            "\"event\", \"fixed\"".into(),
            "exact flight, or one Δt through the whole path",
        ),
    ];
    // The registry laws' parameters given by key (`contact.stiffness`),
    // before `contact.attractive`: those of the laws a scenario names by
    // name alone (the power law's exponent is written law = { power = α }).
    let at = rows
        .iter()
        .position(|k| k.key == "contact.attractive")
        .unwrap_or(rows.len());
    let params = law_parameter_rows(|r| {
        matches!(
            ContactLawKind::from_name(r.name, None),
            Some(ContactLawKind::Registry(_))
        )
    });
    rows.splice(at..at, params);
    rows
}

pub fn run(args: &KeysArgs) -> CliResult {
    let mut stdout = std::io::stdout().lock();
    if args.scene {
        let text = if args.json {
            super::json_text(&super::keys_scene::keys())?
        } else {
            super::keys_scene::markdown()
        };
        write!(stdout, "{text}").map_err(CliError::failed)?;
        stdout.flush().map_err(CliError::failed)?;
        return Ok(());
    }
    let keys = keys();
    if args.json {
        write!(stdout, "{}", super::json_text(&keys)?).map_err(CliError::failed)?;
    } else {
        let mut table = Table::new();
        table
            .load_preset(presets::ASCII_MARKDOWN)
            .set_content_arrangement(ContentArrangement::Dynamic)
            .set_header(["key", "unit", "default", "allowed", "meaning"]);
        for k in &keys {
            table.add_row([
                k.key.as_ref(),
                k.unit.as_ref(),
                k.default.as_str(),
                k.allowed.as_str(),
                k.meaning.as_ref(),
            ]);
        }
        writeln!(
            stdout,
            "{table}\nAll values SI. Set them in a scenario file ([section] key = value) or with \
             --set section.key=value."
        )
        .map_err(CliError::failed)?;
    }
    stdout.flush().map_err(CliError::failed)?;
    Ok(())
}

/// The laws `contact.law` takes, from the physics registry: each name
/// (the power law as `{ power = α }` with its exponent's range).
fn law_names() -> String {
    use dembound_physics::contact::registry::NORMAL_LAWS;
    NORMAL_LAWS
        .iter()
        .map(|row| match row.params {
            [p] if p.key == "exponent" => format!(
                "{{ {} = {} }} with {}",
                row.name,
                p.symbol,
                p.range.to_string().replace('x', p.symbol)
            ),
            _ => format!("\"{}\"", row.name),
        })
        .collect::<Vec<_>>()
        .join(", ")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_key_of_the_resolved_default_scenario_is_listed() {
        // Independent of the table: the keys serde writes for a scenario
        // with every optional key set.
        let mut s = Scenario::default().resolved();
        s.boundary.poisson_ratio = Some(0.3);
        // Every law parameter given by key (`stiffness`): listed from the
        // registry rows.
        let hooke = dembound_physics::contact::registry::normal_row("hooke").unwrap();
        s.contact.law = ContactLawKind::Registry(hooke);
        for p in hooke.params {
            assert!(s.contact.params.set(p.key, 1.0));
        }
        let value = toml::Value::try_from(s).unwrap();
        let keys = keys();
        let listed: Vec<&str> = keys.iter().map(|k| k.key.as_ref()).collect();
        for (section, table) in value.as_table().unwrap() {
            for key in table.as_table().unwrap().keys() {
                let name = format!("{section}.{key}");
                assert!(listed.contains(&name.as_str()), "{name} missing");
            }
        }
    }
}
