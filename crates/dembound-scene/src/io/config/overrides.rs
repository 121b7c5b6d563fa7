//! The `--set KEY=VALUE` overrides, applied to the scene's TOML table
//! before it is deserialised.

use crate::SceneError;
use toml::{Table, Value};

/// Reads a `--set` value: TOML if it parses, else the bare word as a string
/// (as `dembound run --set` does).
pub fn parse_value(raw: &str) -> Value {
    let raw = raw.trim();
    match toml::from_str::<Table>(&format!("value = {raw}")) {
        Ok(mut t) if t.len() == 1 => t.remove("value").unwrap_or(Value::String(raw.into())),
        _ => Value::String(raw.into()),
    }
}

/// The top-level keys of a scene file.
const SECTIONS: [&str; 9] = [
    "domain",
    "material",
    "contact",
    "particles",
    "wall",
    "motion",
    "integration",
    "output",
    "parallel",
];

/// The sections that are one table (a `--set` may create them).
const TABLE_SECTIONS: [&str; 6] = [
    "domain",
    "contact",
    "motion",
    "integration",
    "output",
    "parallel",
];

/// Keys of which only one may be given: setting one drops the other.
const EXCLUSIVE: [(&str, &str); 2] = [("dt", "eta"), ("steps", "duration")];

/// Applies one `--set KEY=VALUE` to the scene table. KEY is a dotted path;
/// an array of tables is indexed by a number: `wall.1.material=rigid` or
/// `wall[1].material=rigid`. Setting `integration.dt` drops
/// `integration.eta` (and the reverse), `steps` drops `duration`.
pub fn apply_set(table: &mut Table, arg: &str) -> Result<(), SceneError> {
    let malformed = |why: &str| {
        SceneError::input(format!(
            "malformed --set `{arg}`: {why} (expected KEY=VALUE, e.g. --set integration.steps=1000 \
             or --set wall.0.material=rigid)"
        ))
    };
    let (name, raw) = arg.split_once('=').ok_or_else(|| malformed("no `=`"))?;
    let name = name.trim().replace('[', ".").replace(']', "");
    let path: Vec<&str> = name.split('.').map(str::trim).collect();
    if path.len() < 2 || path.iter().any(|p| p.is_empty()) {
        return Err(malformed("KEY must be SECTION.KEY, with no empty part"));
    }
    let (last, parents) = path.split_last().ok_or_else(|| malformed("no key"))?;
    if !table.contains_key(parents[0]) {
        if !TABLE_SECTIONS.contains(&parents[0]) {
            return Err(SceneError::input(format!(
                "--set `{arg}`: unknown section `{}`; the sections are {}",
                parents[0],
                SECTIONS.map(|s| format!("`{s}`")).join(", ")
            )));
        }
        table.insert(parents[0].to_string(), Value::Table(Table::new()));
    }
    let mut here: &mut Value = table
        .get_mut(parents[0])
        .ok_or_else(|| malformed("unknown section"))?;
    for depth in 1..=parents.len() {
        let so_far = parents[..depth].join(".");
        // A value where a table is wanted is replaced (as `run --set`
        // does: `contact.law.power=1.25` over `law = "hertz"`).
        if !matches!(here, Value::Array(_) | Value::Table(_)) {
            *here = Value::Table(Table::new());
        }
        let Some(part) = parents.get(depth) else {
            break;
        };
        here = match here {
            Value::Array(items) => {
                let len = items.len();
                let index: usize = part.parse().map_err(|_| {
                    malformed(&format!(
                        "`{so_far}` is a list: index it by a number 0..{len}"
                    ))
                })?;
                items.get_mut(index).ok_or_else(|| {
                    SceneError::input(format!(
                        "--set `{arg}`: `{so_far}` has {len} entries, no index {index}"
                    ))
                })?
            }
            Value::Table(t) => t
                .entry(part.to_string())
                .or_insert_with(|| Value::Table(Table::new())),
            _ => return Err(malformed(&format!("`{so_far}` is a value, not a table"))),
        };
    }
    let target = match here {
        Value::Table(target) => target,
        Value::Array(items) => {
            // The last part indexes the list: replace that entry.
            let len = items.len();
            let index: usize = last.parse().map_err(|_| {
                malformed(&format!(
                    "`{}` is a list: index it by a number 0..{len}",
                    parents.join(".")
                ))
            })?;
            let entry = items.get_mut(index).ok_or_else(|| {
                SceneError::input(format!(
                    "--set `{arg}`: `{}` has {len} entries, no index {index}",
                    parents.join(".")
                ))
            })?;
            *entry = parse_value(raw);
            return Ok(());
        }
        _ => return Err(malformed(&format!("`{}` is a value", parents.join(".")))),
    };
    target.insert(last.to_string(), parse_value(raw));
    if parents.len() == 1 && parents[0] == "integration" {
        for (a, b) in EXCLUSIVE {
            if *last == a {
                target.remove(b);
            } else if *last == b {
                target.remove(a);
            }
        }
    }
    Ok(())
}
