//! Parsing of list arguments shared by every subcommand: numbers
//! (`inf` allowed), generated ranges and contact laws. Every error names the
//! flag, the value and what is allowed.

use anyhow::{anyhow, bail, Result};
use dembound_core::contact::ContactLawKind;
use dembound_core::study::restitution::DissipativeLaw;
use dembound_physics::contact::registry::{normal_row, NORMAL_LAWS};

/// One number, `inf` (also `infinity`) allowed.
pub fn number(flag: &str, text: &str) -> Result<f64> {
    let t = text.trim();
    let x = match t.to_ascii_lowercase().as_str() {
        "inf" | "+inf" | "infinity" | "+infinity" => f64::INFINITY,
        other => other.parse::<f64>().map_err(|_| {
            anyhow!("invalid value for `{flag}`: `{t}` is not a number (allowed: a number or inf)")
        })?,
    };
    if x.is_nan() {
        bail!("invalid value for `{flag}`: `{t}` (allowed: a number or inf)");
    }
    Ok(x)
}

/// A list: comma-separated items, each a number, `inf`, `log:A:B:N` (N
/// values from A to B evenly in log, ends included) or `lin:A:B:N`.
pub fn numbers(flag: &str, text: &str) -> Result<Vec<f64>> {
    let mut out = Vec::new();
    for item in text.split(',').map(str::trim) {
        if item.is_empty() {
            bail!("invalid value for `{flag}`: `{text}` has an empty item (allowed: e.g. 1,10,100,inf or log:1:1000:13)");
        }
        let lower = item.to_ascii_lowercase();
        if let Some(spec) = lower
            .strip_prefix("log:")
            .map(|s| (s, true))
            .or_else(|| lower.strip_prefix("lin:").map(|s| (s, false)))
        {
            out.extend(range(flag, item, spec.0, spec.1)?);
        } else {
            out.push(number(flag, item)?);
        }
    }
    Ok(out)
}

fn range(flag: &str, item: &str, spec: &str, log: bool) -> Result<Vec<f64>> {
    let bad = |why: &str| {
        anyhow!(
            "invalid value for `{flag}`: `{item}`: {why} (allowed: {}:A:B:N with finite A, B{} and N ≥ 2)",
            if log { "log" } else { "lin" },
            if log { " > 0" } else { "" }
        )
    };
    let parts: Vec<&str> = spec.split(':').collect();
    if parts.len() != 3 {
        return Err(bad("expected three fields"));
    }
    let a: f64 = parts[0]
        .trim()
        .parse()
        .map_err(|_| bad("A is not a number"))?;
    let b: f64 = parts[1]
        .trim()
        .parse()
        .map_err(|_| bad("B is not a number"))?;
    let n: usize = parts[2]
        .trim()
        .parse()
        .map_err(|_| bad("N is not a whole number"))?;
    let finite = a.is_finite() && b.is_finite() && (2..=100_000).contains(&n);
    if !finite || (log && (a <= 0.0 || b <= 0.0)) {
        return Err(bad("out of range"));
    }
    Ok((0..n)
        .map(|i| {
            let t = i as f64 / (n - 1) as f64;
            if i == n - 1 {
                b
            } else if log {
                a * (b / a).powf(t)
            } else {
                a + t * (b - a)
            }
        })
        .collect())
}

/// A list of positive ratios (r or ζ).
pub fn ratios(flag: &str, text: &str) -> Result<Vec<f64>> {
    let xs = numbers(flag, text)?;
    if let Some(x) = xs.iter().find(|x| x.is_nan() || **x <= 0.0) {
        bail!("invalid value for `{flag}`: {x} (allowed: > 0, or inf)");
    }
    Ok(xs)
}

/// Every contact law by the names used everywhere (`--law` of every
/// subcommand, `contact.law`/`contact.damping` of a scenario): the elastic
/// laws and the dissipative ones of `restitution`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum AnyLaw {
    Elastic(ContactLawKind),
    Dissipative(DissipativeLaw),
}

/// Every law name a `--law` flag takes, for messages, from the physics
/// registry: the normal laws without parameters, the power law with its
/// exponent's range (`power=α (1 ≤ α ≤ 3)`), then the dissipative laws of
/// `restitution`. (Laws with a given stiffness, `hooke` and `hertz-kn`,
/// take `contact.stiffness` and so are used through a scenario.)
pub fn all_law_names() -> String {
    let mut names: Vec<String> = NORMAL_LAWS
        .iter()
        .filter_map(|row| match row.params {
            [] => Some(row.name.to_string()),
            [p] if p.key == POWER_KEY => Some(format!(
                "{}={} ({})",
                row.name,
                p.symbol,
                p.range.to_string().replace('x', p.symbol)
            )),
            _ => None,
        })
        .collect();
    names.extend(DissipativeLaw::ALL.iter().map(|d| d.name().to_string()));
    names.join(", ")
}

/// The parameter of the one law written `power=α`.
const POWER_KEY: &str = "exponent";

/// One contact law: a registry law without parameters (`linear`,
/// `hertz`), a power `α` (`power=1.25`, `1.25`, in the exponent's registry
/// range), or a dissipative law (`viscous`, `tsuji`, `viscoelastic`,
/// `walton-braun`).
pub fn any_law(flag: &str, text: &str) -> Result<AnyLaw> {
    let t = text.trim().to_ascii_lowercase();
    if let Some(d) = DissipativeLaw::parse(&t) {
        return Ok(AnyLaw::Dissipative(d));
    }
    if let Some(row) = normal_row(&t) {
        if row.params.is_empty() {
            if let Some(law) = ContactLawKind::from_name(row.name, None) {
                return Ok(AnyLaw::Elastic(law));
            }
        } else if row.params.iter().all(|p| p.key != POWER_KEY) {
            let keys: Vec<String> = row
                .params
                .iter()
                .map(|p| format!("contact.{}", p.key))
                .collect();
            bail!(
                "invalid value for `{flag}`: law `{}` takes {}, which a `--law` list cannot give \
                 (use it through a scenario: `dembound run --set contact.law={} --set {}=…`; \
                 allowed here: {})",
                row.name,
                keys.join(", "),
                row.name,
                keys[0],
                all_law_names()
            );
        }
    }
    let alpha = t
        .strip_prefix("power=")
        .or_else(|| t.strip_prefix("power:"))
        .unwrap_or(&t)
        .parse::<f64>()
        .ok();
    let power = normal_row("power").and_then(|r| r.params.first());
    match (alpha, power) {
        (Some(a), Some(p)) if p.range.contains(a) => Ok(AnyLaw::Elastic(ContactLawKind::Power(a))),
        _ => bail!(
            "invalid value for `{flag}`: unknown law `{}` (allowed: {})",
            text.trim(),
            all_law_names()
        ),
    }
}

/// One elastic law for a subcommand (`command`) that compares against the
/// exact elastic reference: a dissipative law is refused with the reason.
fn law_for(flag: &str, text: &str, command: &str) -> Result<ContactLawKind> {
    match any_law(flag, text)? {
        AnyLaw::Elastic(l) => Ok(l),
        AnyLaw::Dissipative(d) => bail!(
            "invalid value for `{flag}`: `{}` is a dissipative law, and {command} \
             normalises by the exact elastic reference, which it has not (allowed here: \
             linear, hertz, power=α with 1 ≤ α ≤ 3; the dissipative laws are studied by \
             `dembound restitution --law {}`)",
            text.trim(),
            d.name()
        ),
    }
}

/// A comma-separated list of elastic laws for `command` (see [`any_law`]).
pub fn laws_for(flag: &str, text: &str, command: &str) -> Result<Vec<ContactLawKind>> {
    text.split(',').map(|t| law_for(flag, t, command)).collect()
}

/// A comma-separated list of dissipative laws (`restitution`): an elastic
/// law is refused with the reason.
pub fn dissipative_laws(flag: &str, text: &str) -> Result<Vec<DissipativeLaw>> {
    text.split(',')
        .map(|t| match any_law(flag, t)? {
            AnyLaw::Dissipative(d) => Ok(d),
            AnyLaw::Elastic(l) => bail!(
                "invalid value for `{flag}`: `{}` ({}) is elastic: it rebounds with e = 1 \
                 whatever the boundary (allowed here: viscous, tsuji, viscoelastic, \
                 walton-braun; the elastic laws are studied by `dembound sweep --law {}`)",
                t.trim(),
                l.name(),
                l.name()
            ),
        })
        .collect()
}

/// A list of restitution coefficients, 0 < e ≤ 1 (the list syntax of [`numbers`]).
pub fn restitutions(flag: &str, text: &str) -> Result<Vec<f64>> {
    let xs = numbers(flag, text)?;
    if let Some(x) = xs.iter().find(|x| !(**x > 0.0 && **x <= 1.0)) {
        bail!("invalid value for `{flag}`: {x} (allowed: 0 < e ≤ 1)");
    }
    Ok(xs)
}

pub use dembound_core::study::show;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lists() {
        assert_eq!(
            numbers("--r", "1, 10,100,inf").unwrap(),
            vec![1.0, 10.0, 100.0, f64::INFINITY]
        );
        let l = numbers("--zeta", "log:1:1000:13").unwrap();
        assert_eq!(l.len(), 13);
        assert_eq!((l[0], l[12]), (1.0, 1000.0));
        assert!((l[4] - 10.0).abs() < 1e-12);
        assert_eq!(
            numbers("--x", "lin:0:1:3,5").unwrap(),
            vec![0.0, 0.5, 1.0, 5.0]
        );
        for bad in ["", "1,,2", "abc", "log:0:10:3", "log:1:10", "lin:1:2:1"] {
            let e = numbers("--r", bad).unwrap_err().to_string();
            assert!(e.contains("`--r`"), "{e}");
        }
        assert!(ratios("--r", "1,-2")
            .unwrap_err()
            .to_string()
            .contains("-2"));
        assert_eq!(
            laws_for("--law", "linear,HERTZ,power=1.25", "sweep")
                .unwrap()
                .len(),
            3
        );
        assert!(any_law("--law", "cubic")
            .unwrap_err()
            .to_string()
            .contains("cubic"));
        assert!(any_law("--law", "4").is_err());
    }

    #[test]
    fn laws_are_named_alike_everywhere() {
        // The same names parse in every command; a law a command cannot take
        // is refused with the reason, naming the flag, not as "unknown".
        assert_eq!(
            any_law("--law", "Tsuji").unwrap(),
            AnyLaw::Dissipative(DissipativeLaw::Tsuji)
        );
        let e = laws_for("--law", "hertz,tsuji", "sweep")
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("`--law`")
                && e.contains("tsuji")
                && e.contains("dissipative")
                && e.contains("sweep")
                && e.contains("restitution"),
            "{e}"
        );
        assert_eq!(
            dissipative_laws("--law", "viscous, walton-braun").unwrap(),
            vec![DissipativeLaw::Viscous, DissipativeLaw::WaltonBraun]
        );
        let e = dissipative_laws("--law", "hertz").unwrap_err().to_string();
        assert!(e.contains("`--law`") && e.contains("elastic"), "{e}");
        let e = any_law("--law", "cubic").unwrap_err().to_string();
        assert!(e.contains("cubic") && e.contains("walton-braun"), "{e}");
        let e = restitutions("--e", "lin:0.5:0.9:3,1").unwrap();
        assert_eq!((e.len(), e[0], e[2], e[3]), (4, 0.5, 0.9, 1.0));
        assert!(restitutions("--e", "0.5,1.5")
            .unwrap_err()
            .to_string()
            .contains("1.5"));
    }
}
