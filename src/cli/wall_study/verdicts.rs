//! wall-study's recommendation section: the tolerances, the floors within
//! each, the floors within every measured quantity, the floors that are
//! not walls, and the verdicts this run's size cannot support.

use super::sig;
use dembound_scene::sources::tiling::Pattern;
use dembound_scene::wall_study::recommend::FloorVerdict;
use dembound_scene::wall_study::{Floor, Tolerances};
use std::fmt::Write as _;

/// The recommendation: the tolerances, for each quantity the floors
/// within it, the floors within every measured one, and the floors that
/// are not walls (with the paper's r = 100).
pub(super) fn recommendation_section(s: &mut String, verdicts: &[FloorVerdict], t: &Tolerances) {
    let _ = writeln!(
        s,
        "## Recommendation: floors within tolerance of the plane\n"
    );
    let _ = writeln!(
        s,
        "Tolerances against the plane of the particles' own material: mean e_n and e_t ± {} \
         (absolute), their spread over the impact points (sd) at most the plane's + {}; median \
         contact time ± {} %; packing fraction 0–2R ± {} (absolute); floor pressure ± {} % of \
         the plane's (which is N m g/A), and no particle through the floor; floor-force \
         fluctuation (sd/mean) ± {} (absolute); the chute's slip velocity, first layer and \
         extrapolated, as a fraction of the bed's mean velocity ± {} (absolute). A floor that is \
         not a wall is never recommended. Options `--tol-restitution`, `--tol-contact-time`, \
         `--tol-packing`, `--tol-pressure`, `--tol-fluctuation`, `--tol-slip`.\n",
        t.restitution,
        t.restitution,
        100.0 * t.contact_time,
        t.packing,
        100.0 * t.pressure,
        t.fluctuation,
        t.slip
    );
    let Some(first) = verdicts.first() else {
        let _ = writeln!(s, "No floor besides the plane.\n");
        return;
    };
    let _ = writeln!(
        s,
        "| quantity | tolerance | plane | floors within (walls) |"
    );
    let _ = writeln!(s, "|---|---|---|---|");
    for (k, q) in first.verdicts.iter().enumerate() {
        let within: Vec<String> = verdicts
            .iter()
            .filter(|f| f.not_a_wall.is_none() && f.verdicts[k].within == Some(true))
            .map(|f| f.floor.label())
            .collect();
        let walls = verdicts.iter().filter(|f| f.not_a_wall.is_none()).count();
        let _ = writeln!(
            s,
            "| {} | {} | {} | {} of {walls}: {} |",
            q.quantity,
            q.tolerance,
            sig(q.plane),
            within.len(),
            if within.is_empty() {
                "none".to_string()
            } else {
                within.join(", ")
            }
        );
    }
    s.push_str(&unsupported_text(verdicts));
    let all: Vec<String> = verdicts
        .iter()
        .filter(|f| f.within_all_measured())
        .map(|f| {
            let missing = f.unmeasured();
            if missing.is_empty() {
                f.floor.label()
            } else {
                format!("{} (not measured: {})", f.floor.label(), missing.join(", "))
            }
        })
        .collect();
    let _ = writeln!(
        s,
        "\n**Within every measured quantity:** {}.\n",
        if all.is_empty() {
            "none".to_string()
        } else {
            all.join("; ")
        }
    );
    // Without the chute: a floor for beds at rest and impacts.
    let static_only: Vec<String> = verdicts
        .iter()
        .filter(|f| {
            f.not_a_wall.is_none()
                && f.verdicts
                    .iter()
                    .filter(|v| !v.quantity.starts_with("chute"))
                    .all(|v| v.within != Some(false))
        })
        .map(|f| f.floor.label())
        .collect();
    let _ = writeln!(
        s,
        "Within every quantity but the chute's slip (impacts and the bed at rest): {}.\n",
        if static_only.is_empty() {
            "none".to_string()
        } else {
            static_only.join(", ")
        }
    );
    let _ = writeln!(s, "Per floor, the quantities outside their tolerance:\n");
    for f in verdicts {
        let out: Vec<String> = f
            .verdicts
            .iter()
            .filter(|v| v.within == Some(false))
            .map(|v| format!("{} {} (plane {})", v.quantity, sig(v.value), sig(v.plane)))
            .collect();
        let _ = writeln!(
            s,
            "- {}{}: {}",
            f.floor.label(),
            if f.not_a_wall.is_some() {
                " (not a wall)"
            } else {
                ""
            },
            if out.is_empty() {
                "none".to_string()
            } else {
                out.join("; ")
            }
        );
    }
    let _ = writeln!(s, "\n### Floors that are not walls\n");
    let sq = Floor::wall_limit(Pattern::Square);
    let hex = Floor::wall_limit(Pattern::Hexagonal);
    let paper = |pattern| {
        Floor::Particles {
            radius_ratio: 100.0,
            modulus_ratio: 100.0,
            pattern,
        }
        .gap_radius()
        .unwrap_or(f64::NAN)
    };
    let _ = writeln!(
        s,
        "Touching boundary spheres of radius r R leave a hole through which a sphere of radius \
         (√2 − 1) r R passes (square tiling, between four) or (2/√3 − 1) r R (hexagonal, between \
         three). A single layer of them is a wall for the particles only for r ≤ {sq:.3} \
         (square) and r ≤ {hex:.3} (hexagonal). The paper's recommendation r = ζ = 100 leaves \
         holes of {:.1} R (square) and {:.1} R (hexagonal): a bed wider than a hole falls \
         through, so it cannot be tested as a floor of touching spheres, and the default grid stops at the largest \
         walls, r = 2.4 (square) and 6 (hexagonal). Floors above the limit are still run when \
         asked for (`--radius-ratios`): their impacts are measured, their bed counts the \
         particles that fell through, their chute is not run, and they are never recommended.\n",
        paper(Pattern::Square),
        paper(Pattern::Hexagonal)
    );
    let here: Vec<String> = verdicts
        .iter()
        .filter_map(|f| {
            f.not_a_wall
                .as_ref()
                .map(|w| format!("- {}: {w}{}", f.floor.label(), fallen_text(f)))
        })
        .collect();
    if here.is_empty() {
        let _ = writeln!(s, "Every floor of this run is a wall.\n");
    } else {
        let _ = writeln!(s, "In this run:\n\n{}\n", here.join("\n"));
    }
}

/// The bed and chute quantities, which two flat floors of different
/// stiffness should give alike; the impacts' e and contact time differ
/// between them by physics (the rigid plane's stiffness).
fn size_limited(quantity: &str) -> bool {
    quantity.contains("packing")
        || quantity.contains("fluctuation")
        || quantity.starts_with("chute")
}

/// The verdicts this run's size cannot support: the bed and chute
/// quantities on which the rigid plane, itself flat, falls outside the
/// tolerance of the plane. Their spread between two flat floors is the
/// run's own noise (a small bed's few particles per slab, its side
/// walls); a boundary-particle floor judged on them is judged on noise.
fn unsupported_text(verdicts: &[FloorVerdict]) -> String {
    let Some(rigid) = verdicts.iter().find(|f| f.floor == Floor::Rigid) else {
        return String::new();
    };
    let lines: Vec<String> = rigid
        .verdicts
        .iter()
        .filter(|v| size_limited(&v.quantity) && v.within == Some(false))
        .map(|v| {
            format!(
                "- {}: plane {}, rigid plane {} (tolerance {})",
                v.quantity,
                sig(v.plane),
                sig(v.value),
                v.tolerance
            )
        })
        .collect();
    if lines.is_empty() {
        return String::new();
    }
    format!(
        "\n**Verdicts this run's size cannot support.** The rigid plane is as flat as the plane, \
         so its bed and chute should match the plane's to within noise; here they differ by more \
         than the tolerance on:\n\n{}\n\nOn these quantities the bed (or chute) is too small \
         (few particles per slab, side walls a few diameters apart: `--quick` has 150 particles) \
         to tell a floor from the plane: their verdicts above, for every floor, are not \
         supported. Run a larger bed (`--particles`, default 1000).\n",
        lines.join("\n")
    )
}

/// ", its bed: N particles fell through" from the floor's own verdict (the
/// table's number), for a floor that is not a wall.
fn fallen_text(f: &FloorVerdict) -> String {
    match f
        .verdicts
        .iter()
        .find(|v| v.quantity.starts_with("particles fallen through"))
    {
        Some(v) if v.within.is_some() && v.value > 0.0 => {
            format!("; its bed lost {:.0} particles through the floor", v.value)
        }
        Some(v) if v.within.is_some() => "; its bed lost no particle through the floor in this \
             run (a bed narrower than a hole can rest on the spheres without meeting one)"
            .to_string(),
        _ => String::new(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use dembound_scene::wall_study::recommend::Verdict;

    fn verdict(quantity: &str, value: f64, within: bool) -> Verdict {
        Verdict {
            quantity: quantity.into(),
            tolerance: "± 0.02".into(),
            plane: 0.4743,
            value,
            within: Some(within),
        }
    }

    #[test]
    fn a_rigid_plane_outside_a_bed_tolerance_marks_it_unsupported() {
        // --quick's numbers: the rigid plane packs 0.5026 against the
        // plane's 0.4743 (± 0.02): unsupported; its contact time, outside
        // by physics, is not named; a wall with 0 fallen says 0.
        let rigid = FloorVerdict {
            floor: Floor::Rigid,
            not_a_wall: None,
            verdicts: vec![
                verdict("packing fraction 0–2R (1)", 0.5026, false),
                verdict("median contact time at 0° (µs)", 66.0, false),
                verdict("particles fallen through the floor (1)", 0.0, true),
            ],
        };
        let text = unsupported_text(std::slice::from_ref(&rigid));
        assert!(
            text.contains("packing fraction 0–2R (1): plane 0.4743, rigid plane 0.5026"),
            "{text}"
        );
        assert!(!text.contains("contact time"), "{text}");
        let mut within = rigid.clone();
        within.verdicts[0].within = Some(true);
        assert!(unsupported_text(&[within]).is_empty());
        let mut sieve = rigid;
        sieve.not_a_wall = Some("holes".into());
        assert!(fallen_text(&sieve).contains("lost no particle"));
        sieve.verdicts[2].value = 12.0;
        assert!(fallen_text(&sieve).contains("lost 12 particles"));
    }
}
