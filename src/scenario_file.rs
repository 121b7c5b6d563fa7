//! Loading a scenario: the built-in default (the paper's validation case),
//! a TOML file merged over it section by section, then `--set` overrides,
//! then deserialisation into [`Scenario`] and [`Scenario::validate`].
//!
//! Every error here is bad input (exit 2) and says where it comes from: the
//! file and line for malformed TOML, the argument for a malformed `--set`,
//! the `section.key` and the valid keys for an unknown or mistyped key.

use anyhow::{anyhow, bail, Context, Result};
use clap::Args;
use dembound_core::bounce::Scenario;
use serde::Deserialize;
use std::path::{Path, PathBuf};
use toml::{Table, Value};

/// The scenario of a command: an optional file and `--set` overrides.
/// Subcommands take it with `#[command(flatten)]`.
#[derive(Debug, Clone, Default, Args)]
pub struct ScenarioArgs {
    /// Scenario file (TOML). Keys it leaves out keep their default, the
    /// paper's validation case (see examples/validation.toml).
    #[arg(value_name = "SCENARIO.toml")]
    pub scenario: Option<PathBuf>,

    /// Override one key after the file, e.g. `--set contact.law=linear`,
    /// `--set boundary.radius=0.02` (m), `--set boundary.youngs_modulus=2e11`
    /// (Pa), `--set boundary.radius_ratio=inf`, `--set 'contact.law={power=1.25}'`.
    /// VALUE is read as TOML; a bare word that is not TOML is a string.
    /// Setting one of integration.dt, integration.eta and
    /// integration.tolerance drops the other two; boundary.radius drops
    /// boundary.radius_ratio and boundary.youngs_modulus drops
    /// boundary.modulus_ratio, and vice versa. Repeatable. Every value is
    /// checked against its range (`dembound keys` lists every key with unit,
    /// default and range: e.g. 1e-9 ≤ particle.radius ≤ 10 m, η ≤ 0.1, a
    /// contact not dominated by gravity); out of range exits 2 naming the key.
    #[arg(long = "set", value_name = "SECTION.KEY=VALUE")]
    pub set: Vec<String>,
}

impl ScenarioArgs {
    /// The scenario these arguments describe, validated.
    pub fn load(&self) -> Result<Scenario> {
        self.load_with(&[])
    }

    /// The scenario with `extra` `--set` overrides applied after the user's.
    pub fn load_with(&self, extra: &[String]) -> Result<Scenario> {
        let file = match &self.scenario {
            Some(path) => Some((path.as_path(), read_file(path)?)),
            None => None,
        };
        let sets: Vec<String> = self.set.iter().chain(extra).cloned().collect();
        load(file.as_ref().map(|(p, t)| (*p, t.as_str())), &sets)
    }
}

fn read_file(path: &Path) -> Result<String> {
    std::fs::read_to_string(path)
        .with_context(|| format!("cannot read scenario file `{}`", path.display()))
}

/// Builds and validates a scenario from an optional `(path, text)` file and
/// `--set` arguments.
pub fn load(file: Option<(&Path, &str)>, sets: &[String]) -> Result<Scenario> {
    let defaults = default_table()?;
    let mut merged = defaults.clone();
    if let Some((path, text)) = file {
        let user: Table = toml::from_str(text)
            .map_err(|e| anyhow!("cannot parse scenario file `{}`: {e}", path.display()))?;
        merge_file(&mut merged, user)
            .with_context(|| format!("in scenario file `{}`", path.display()))?;
    }
    for arg in sets {
        apply_set(&mut merged, arg)?;
    }
    let given = si_to_ratios(&mut merged)?;
    let scenario = deserialize(&defaults, &merged)?;
    scenario.validate().map_err(|e| {
        // A range error on a ratio the user gave in SI names both forms.
        let mut msg = e.to_string();
        for (key, ratio_field, text) in &given {
            if e.field() == Some(ratio_field.as_str()) {
                msg.push_str(&format!(" (from `boundary.{key}` = {text})"));
            }
        }
        anyhow!(msg)
    })?;
    Ok(scenario)
}

/// The `[boundary]` keys that have an SI alternative: (SI key, ratio key,
/// the particle key it is relative to, unit, what ∞ means).
const SI_PAIRS: [(&str, &str, &str, &str, &str); 2] = [
    (
        "radius",
        "radius_ratio",
        "radius",
        "m",
        "an elastic half-space",
    ),
    (
        "youngs_modulus",
        "modulus_ratio",
        "youngs_modulus",
        "Pa",
        "a rigid boundary",
    ),
];

/// The ratio key that an SI `[boundary]` key replaces, if `key` is one.
fn ratio_key_of(key: &str) -> Option<&'static str> {
    SI_PAIRS.iter().find(|p| p.0 == key).map(|p| p.1)
}

/// The SI key that a ratio `[boundary]` key replaces, if `key` is one.
fn si_key_of(key: &str) -> Option<&'static str> {
    SI_PAIRS.iter().find(|p| p.1 == key).map(|p| p.0)
}

/// A number or "inf" from a TOML value.
fn number_or_inf(v: &Value) -> Option<f64> {
    match v {
        Value::Float(x) => Some(*x),
        Value::Integer(i) => Some(*i as f64),
        Value::String(s) => match s.trim().to_ascii_lowercase().as_str() {
            "inf" | "+inf" | "infinity" | "+infinity" => Some(f64::INFINITY),
            other => other.parse().ok(),
        },
        _ => None,
    }
}

/// Replaces `boundary.radius` (m) and `boundary.youngs_modulus` (Pa) by
/// the ratios the core works with, r = R_b/R_m and ζ = E_b/E_m, using the
/// particle's final radius and modulus. Returns, for each key converted,
/// (SI key, ratio field, the value as given) for error messages.
fn si_to_ratios(merged: &mut Table) -> Result<Vec<(&'static str, String, String)>> {
    let particle = |key: &str| {
        merged
            .get("particle")
            .and_then(|p| p.get(key))
            .and_then(number_or_inf)
            .filter(|x| x.is_finite() && *x > 0.0)
    };
    let mut ratios = Vec::new();
    for (si, ratio, of, unit, inf) in SI_PAIRS {
        let Some(Value::Table(b)) = merged.get("boundary") else {
            continue;
        };
        let Some(v) = b.get(si) else { continue };
        let x = number_or_inf(v).filter(|x| *x > 0.0 && !x.is_nan());
        let Some(x) = x else {
            bail!(
                "invalid value for `boundary.{si}`: {v} (allowed: > 0, in {unit}, or \"inf\" for {inf})"
            );
        };
        // A bad particle value is reported by its own key later; the ratio
        // is then a placeholder.
        let r = particle(of).map_or(1.0, |p| x / p);
        ratios.push((si, ratio, r, format!("{v} {unit}")));
    }
    let mut given = Vec::new();
    if let Some(Value::Table(b)) = merged.get_mut("boundary") {
        for (si, ratio, r, text) in ratios {
            b.remove(si);
            let value = if r.is_infinite() {
                Value::String("inf".into())
            } else {
                Value::Float(r)
            };
            b.insert(ratio.to_string(), value);
            given.push((si, format!("boundary.{ratio}"), text));
        }
    }
    Ok(given)
}

/// The default scenario as a TOML table.
pub fn default_table() -> Result<Table> {
    Table::try_from(Scenario::default())
        .map_err(|e| anyhow!("internal error: the default scenario does not serialise: {e}"))
}

fn section_list(defaults: &Table) -> String {
    defaults
        .keys()
        .map(|k| format!("[{k}]"))
        .collect::<Vec<_>>()
        .join(", ")
}

/// Merges a user's file over the defaults: each key of each section
/// replaces the default's.
fn merge_file(base: &mut Table, user: Table) -> Result<()> {
    let sections = section_list(base);
    for (section, value) in user {
        let Some(Value::Table(slot)) = base.get_mut(&section) else {
            if value.is_table() {
                bail!("unknown section `[{section}]`; the valid sections are {sections}");
            }
            bail!("`{section} = {value}` is not in a section; the valid sections are {sections}");
        };
        let Value::Table(keys) = value else {
            bail!(
                "`{section}` must be a section (`[{section}]` followed by its keys), \
                 found `{section} = {value}`"
            );
        };
        if section == "boundary" {
            // `radius` or `radius_ratio`, `youngs_modulus` or `modulus_ratio`:
            // one of each pair, and the one given replaces the default's other.
            for (si, ratio, ..) in SI_PAIRS {
                if keys.contains_key(si) && keys.contains_key(ratio) {
                    bail!(
                        "`boundary.{si}` and `boundary.{ratio}` are both given: give one of \
                         them (the boundary's {si} in SI, or relative to the particle's)"
                    );
                }
                if keys.contains_key(si) {
                    slot.remove(ratio);
                } else if keys.contains_key(ratio) {
                    slot.remove(si);
                }
            }
        }
        for (key, v) in keys {
            slot.insert(key, v);
        }
    }
    Ok(())
}

/// Reads a `--set` value: TOML if it parses, else the bare word as a string.
pub fn parse_value(raw: &str) -> Value {
    let raw = raw.trim();
    match toml::from_str::<Table>(&format!("value = {raw}")) {
        Ok(mut t) if t.len() == 1 => t.remove("value").unwrap_or(Value::String(raw.into())),
        _ => Value::String(raw.into()),
    }
}

/// Applies one `--set section.key=value` (or a deeper dotted key, e.g.
/// `contact.law.power=1.25`).
fn apply_set(base: &mut Table, arg: &str) -> Result<()> {
    let sections = section_list(base);
    let malformed = |why: &str| {
        anyhow!("malformed --set `{arg}`: {why} (expected SECTION.KEY=VALUE, e.g. --set contact.law=linear)")
    };
    let (name, raw) = arg.split_once('=').ok_or_else(|| malformed("no `=`"))?;
    let path: Vec<&str> = name.trim().split('.').map(str::trim).collect();
    if path.len() < 2 {
        return Err(malformed("the name has no `.` between section and key"));
    }
    if path.iter().any(|p| p.is_empty()) {
        return Err(malformed("empty section or key name"));
    }
    let section = path[0];
    let Some(Value::Table(table)) = base.get_mut(section) else {
        bail!("--set `{arg}`: unknown section `{section}`; the valid sections are {sections}");
    };
    let mut table: &mut Table = table;
    let (last, parents) = match path[1..].split_last() {
        Some(split) => split,
        None => return Err(malformed("no key")),
    };
    for key in parents {
        let entry = table
            .entry((*key).to_string())
            .or_insert_with(|| Value::Table(Table::new()));
        if !entry.is_table() {
            *entry = Value::Table(Table::new());
        }
        table = match entry {
            Value::Table(inner) => inner,
            _ => return Err(malformed("a key is not a table")),
        };
    }
    table.insert((*last).to_string(), parse_value(raw));
    // The boundary's radius and modulus are given in SI or as ratios.
    if section == "boundary" && parents.is_empty() {
        if let Some(other) = ratio_key_of(last).or_else(|| si_key_of(last)) {
            table.remove(other);
        }
    }
    // Δt is given either as a fraction of the contact time or in seconds.
    if section == "integration" && parents.is_empty() {
        match *last {
            "dt" => {
                table.remove("eta");
                table.remove("tolerance");
            }
            "eta" => {
                table.remove("dt");
                table.remove("tolerance");
            }
            "tolerance" => {
                table.remove("dt");
                table.remove("eta");
            }
            _ => {}
        }
    }
    Ok(())
}

/// Deserialises the merged table; on failure, finds the first
/// `section.key` that fails on its own over the defaults and names it.
fn deserialize(defaults: &Table, merged: &Table) -> Result<Scenario> {
    let err = match Scenario::deserialize(Value::Table(merged.clone())) {
        Ok(s) => return Ok(s),
        Err(e) => e,
    };
    for (section, value) in merged {
        let Value::Table(keys) = value else { continue };
        for (key, v) in keys {
            let mut candidate = defaults.clone();
            if let Some(Value::Table(slot)) = candidate.get_mut(section) {
                slot.insert(key.clone(), v.clone());
            }
            if let Err(e) = Scenario::deserialize(Value::Table(candidate)) {
                let e = e.to_string();
                // toml adds a last line "in `key`": the message names the key already.
                let e = match e.trim_end().rsplit_once('\n') {
                    Some((head, last)) if last.starts_with("in `") => head.trim_end(),
                    _ => e.trim_end(),
                };
                // A law parameter's value (`LawParams`) names its key,
                // which the message names already.
                let e = match e.strip_prefix("invalid value for law parameter `") {
                    Some(rest) => rest.split_once("`: ").map_or(e, |(_, m)| m),
                    None => e,
                };
                if e.starts_with("unknown field") {
                    bail!("unknown key `{section}.{key}`: {e}");
                }
                bail!("invalid value for `{section}.{key}`: {v}: {e}");
            }
        }
    }
    bail!("invalid scenario: {}", err.to_string().trim_end())
}

#[cfg(test)]
mod tests {
    use super::*;
    use dembound_core::contact::ContactLawKind;

    fn sets(args: &[&str]) -> Vec<String> {
        args.iter().map(|s| s.to_string()).collect()
    }

    #[test]
    fn nothing_given_is_the_default() {
        assert_eq!(load(None, &[]).unwrap(), Scenario::default());
    }

    #[test]
    fn a_file_may_give_only_some_keys() {
        let text = "[motion]\ngap = 0.01\n";
        let s = load(Some((Path::new("f.toml"), text)), &[]).unwrap();
        assert_eq!(s.motion.gap, 0.01);
        assert_eq!(s.motion.gravity, 9.81);
        assert_eq!(s.particle, Scenario::default().particle);
    }

    #[test]
    fn set_values_are_toml_or_bare_strings() {
        let s = load(
            None,
            &sets(&[
                "contact.law=linear",
                "boundary.radius_ratio=inf",
                "integration.dt=1e-8",
                "motion.contacts=3",
            ]),
        )
        .unwrap();
        assert_eq!(s.contact.law, ContactLawKind::Linear);
        assert!(s.boundary.radius_ratio.is_infinite());
        assert_eq!(s.integration.dt, Some(1e-8));
        assert_eq!(s.motion.contacts, 3);
        let s = load(None, &sets(&["contact.law={power=1.25}"])).unwrap();
        assert_eq!(s.contact.law, ContactLawKind::Power(1.25));
        let s = load(None, &sets(&["contact.law.power=1.25"])).unwrap();
        assert_eq!(s.contact.law, ContactLawKind::Power(1.25));
    }

    #[test]
    fn set_dt_replaces_a_files_eta() {
        let text = "[integration]\neta = 0.01\n";
        let s = load(
            Some((Path::new("f.toml"), text)),
            &sets(&["integration.dt=1e-9"]),
        )
        .unwrap();
        assert_eq!((s.integration.eta, s.integration.dt), (None, Some(1e-9)));
    }

    #[test]
    fn errors_name_the_key_or_quote_the_argument() {
        let msg = |r: Result<Scenario>| format!("{:#}", r.unwrap_err());
        let m = msg(load(None, &sets(&["particle.colour=red"])));
        assert!(
            m.contains("particle.colour") && m.contains("youngs_modulus"),
            "{m}"
        );
        let m = msg(load(None, &sets(&["particle.radius=big"])));
        assert!(m.contains("particle.radius"), "{m}");
        let m = msg(load(None, &sets(&["nosection=1"])));
        assert!(m.contains("`nosection=1`"), "{m}");
        let m = msg(load(None, &sets(&["foo.bar=1"])));
        assert!(m.contains("`foo.bar=1`") && m.contains("[particle]"), "{m}");
        let m = msg(load(None, &sets(&["particle.radius"])));
        assert!(m.contains("`particle.radius`"), "{m}");
        let m = msg(load(Some((Path::new("f.toml"), "[extra]\na = 1\n")), &[]));
        assert!(m.contains("f.toml") && m.contains("[integration]"), "{m}");
        let m = msg(load(
            Some((Path::new("f.toml"), "[motion]\ngap = = 1\n")),
            &[],
        ));
        assert!(m.contains("f.toml") && m.contains("gap = = 1"), "{m}");
        let m = msg(load(None, &sets(&["motion.gap=-1"])));
        assert!(m.contains("motion.gap"), "{m}");
    }

    #[test]
    fn the_boundary_is_given_in_si_or_as_ratios() {
        // R_b = 50 mm on the default R_m = 0.5 mm is r = 100; E_b = 200 GPa
        // on the default E_m = 10 GPa is ζ = 20.
        let text = "[boundary]\nradius = 0.05\nyoungs_modulus = 2.0e11\n";
        let s = load(Some((Path::new("f.toml"), text)), &[]).unwrap();
        assert!((s.boundary.radius_ratio / 100.0 - 1.0).abs() < 1e-15);
        assert!((s.boundary.modulus_ratio / 20.0 - 1.0).abs() < 1e-15);
        // The conversion uses the particle's final values, --set included.
        let s = load(
            Some((Path::new("f.toml"), text)),
            &sets(&["particle.radius=1e-3", "particle.youngs_modulus=1e11"]),
        )
        .unwrap();
        assert!((s.boundary.radius_ratio / 50.0 - 1.0).abs() < 1e-15);
        assert!((s.boundary.modulus_ratio / 2.0 - 1.0).abs() < 1e-15);
        // "inf" is a half-space / a rigid boundary in either form.
        let s = load(
            None,
            &sets(&["boundary.radius=inf", "boundary.youngs_modulus=inf"]),
        )
        .unwrap();
        assert!(s.boundary.radius_ratio.is_infinite() && s.boundary.modulus_ratio.is_infinite());
        // --set of one form drops the other, from the file or the defaults.
        let s = load(
            Some((Path::new("f.toml"), text)),
            &sets(&["boundary.radius_ratio=3"]),
        )
        .unwrap();
        assert_eq!(s.boundary.radius_ratio, 3.0);
        let s = load(
            Some((Path::new("f.toml"), "[boundary]\nradius_ratio = 3.0\n")),
            &sets(&["boundary.radius=0.001"]),
        )
        .unwrap();
        assert!((s.boundary.radius_ratio / 2.0 - 1.0).abs() < 1e-15);
    }

    #[test]
    fn both_forms_or_a_bad_si_value_are_refused_by_name() {
        let msg = |r: Result<Scenario>| format!("{:#}", r.unwrap_err());
        let m = msg(load(
            Some((
                Path::new("f.toml"),
                "[boundary]\nradius = 0.05\nradius_ratio = 100.0\n",
            )),
            &[],
        ));
        assert!(
            m.contains("boundary.radius`")
                && m.contains("boundary.radius_ratio")
                && m.contains("f.toml"),
            "{m}"
        );
        let m = msg(load(
            Some((
                Path::new("f.toml"),
                "[boundary]\nyoungs_modulus = 2e11\nmodulus_ratio = 20.0\n",
            )),
            &[],
        ));
        assert!(
            m.contains("boundary.youngs_modulus") && m.contains("boundary.modulus_ratio"),
            "{m}"
        );
        for bad in [
            "boundary.radius=-1",
            "boundary.radius=0",
            "boundary.radius=big",
        ] {
            let m = msg(load(None, &sets(&[bad])));
            assert!(m.contains("`boundary.radius`") && m.contains("in m"), "{m}");
        }
        let m = msg(load(None, &sets(&["boundary.youngs_modulus=-2e11"])));
        assert!(
            m.contains("`boundary.youngs_modulus`") && m.contains("Pa"),
            "{m}"
        );
        // A bad particle radius is reported as itself, not as the boundary's.
        let m = msg(load(
            None,
            &sets(&["boundary.radius=0.05", "particle.radius=-1"]),
        ));
        assert!(m.contains("particle.radius"), "{m}");
    }
}
