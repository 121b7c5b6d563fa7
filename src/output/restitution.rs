//! Reports of the restitution study ([`dembound_core::study::restitution`]):
//! Markdown tables, figures and `restitution.csv`. `restitution_markdown`
//! and `restitution_figures` are also what the `paper` report calls for
//! its "beyond the paper" section.

use crate::output::format::{exact, sig};
use crate::output::table::{markdown_escape, Cell, Column, Table};
use crate::plot::{Figure, Mark, Series, BLACK};
use anyhow::Result;
use dembound_core::bounce::StepRule;
use dembound_core::contact::Calibration;
use dembound_core::study::restitution::{
    CalibrationSite, DissipativeLaw, RestitutionPoint, RestitutionStudy,
};
use std::fmt::Write as _;
use std::io::Write;
use std::path::{Path, PathBuf};

/// A ratio for text: `∞` or the number.
pub fn ratio_text(x: f64) -> String {
    if x.is_infinite() {
        "∞".into()
    } else {
        let t = sig(x, 4);
        if t.contains('.') && !t.contains('e') {
            t.trim_end_matches('0').trim_end_matches('.').to_string()
        } else {
            t
        }
    }
}

/// The values present in both r and ζ lists (the diagonal r = ζ of the grid).
fn diagonal(study: &RestitutionStudy) -> Vec<f64> {
    study
        .spec
        .radius_ratios
        .iter()
        .copied()
        .filter(|r| study.spec.modulus_ratios.contains(r))
        .collect()
}

fn drop_text(study: &RestitutionStudy) -> String {
    let s = &study.scenario;
    format!(
        "particle R_m = {} mm, ρ = {} kg/m³, E_m = {} Pa, ν = {}; dropped from a gap of {} mm at \
         {} m/s under g = {} m/s² (impact speed {} m/s); one contact, {} {} stepping, {}; \
         attraction {}",
        sig(s.particle.radius * 1e3, 6),
        sig(s.particle.density, 6),
        sig(s.particle.youngs_modulus, 6),
        sig(s.particle.poisson_ratio, 6),
        sig(s.motion.gap * 1e3, 6),
        sig(s.motion.velocity, 6),
        sig(s.relative_gravity(), 6),
        sig(s.impact_speed(), 6),
        s.integration.scheme.name(),
        super::report::stepping_name(s),
        match s.step_rule() {
            StepRule::Fraction(eta) => format!("η = {}", sig(eta, 4)),
            StepRule::Fixed(dt) => format!("Δt = {} s", sig(dt, 6)),
            StepRule::Tolerance(tol) => format!("Δt for a tolerance of {}", sig(tol, 3)),
        },
        if s.contact.attractive {
            "allowed"
        } else {
            "forbidden (F = max(F, 0))"
        },
    )
}

/// The restitution study as Markdown: what was computed, the two
/// calibrations, and per target e tables of the effective restitution,
/// the contact time and the maximum overlap on the diagonal r = ζ.
pub fn restitution_markdown(study: &RestitutionStudy) -> String {
    let mut md = String::new();
    let diag = diagonal(study);
    let _ = writeln!(
        md,
        "## Beyond the paper: dissipative contacts on a boundary particle\n\n\
         A target coefficient of restitution e is set for the particle–boundary pair and the \
         drop is simulated against boundary spheres of radius ratio r = R_b/R_m and modulus \
         ratio ζ = E_b/E_m. Base case: {}.\n\n\
         The target e becomes a raw damping coefficient (c in N s/m for the linear dashpot, γ in \
         N s/m^(5/4) for Tsuji, A in s for the viscoelastic law, the unloading stiffness k₂ in \
         N/m for Walton–Braun) in one of two ways:\n",
        drop_text(study)
    );
    for c in &study.spec.calibrations {
        let _ = writeln!(md, "- **{}**: {}.", c.name(), c.description());
    }
    let mapping = study.scenario.contact.calibration.unwrap_or_default();
    let _ = writeln!(
        md,
        "\nIn both, e becomes the coefficient with `contact.calibration = \"{}\"`: {}.",
        mapping.name(),
        mapping.description()
    );
    let _ = writeln!(
        md,
        "\nWith the **pair** calibration e does not depend on r and ζ for the linear, Tsuji and \
         Walton–Braun laws (the calibration holds their dimensionless damping fixed), nor for the \
         viscoelastic law at the calibration speed; what remains comes from gravity during the \
         contact (and, with `contact.calibration = \"formula\"`, from forbidding attraction). \
         With the **wall** calibration the same raw \
         coefficient meets a softer pair: the dashpot and Tsuji laws are then more damped (e \
         drops), the viscoelastic law less (δ ∝ A k^(2/5) falls, e rises) and Walton–Braun's \
         fixed k₂ gives e √(k₁/k₁(∞)).\n"
    );
    if diag.is_empty() {
        let _ = writeln!(
            md,
            "(No r value equals a ζ value: see `restitution.csv` for the full grid.)"
        );
        return md;
    }
    let head = || {
        let mut columns = vec![Column::text("law"), Column::text("calibration")];
        columns.extend(
            diag.iter()
                .map(|d| Column::text(format!("r = ζ = {}", ratio_text(*d))).right()),
        );
        Table::new(columns).with_keys(2)
    };
    type CellText = fn(&RestitutionPoint) -> String;
    let tables: [(&str, CellText); 3] = [
        ("effective restitution v_r/|v_c|", |p| {
            format!("{:.6}", p.restitution())
        }),
        ("contact time T_c (µs)", |p| {
            sig(p.contact.duration * 1e6, 6)
        }),
        ("maximum overlap h_max (nm)", |p| {
            sig(p.contact.max_overlap * 1e9, 6)
        }),
    ];
    for &target in &study.spec.targets {
        for (what, cell) in tables {
            let _ = writeln!(md, "**e = {target}: {}**\n", markdown_escape(what));
            let mut table = head();
            for &law in &study.spec.laws {
                for &cal in &study.spec.calibrations {
                    let mut row = vec![Cell::text(law.name()), Cell::text(cal.name())];
                    row.extend(diag.iter().map(|&d| {
                        Cell::Text(
                            study
                                .point(law, cal, target, d, d)
                                .map(cell)
                                .unwrap_or_default(),
                        )
                    }));
                    table.push(row);
                }
            }
            let _ = writeln!(md, "{}", table.markdown());
        }
    }
    md
}

/// The closing note: the effective restitution at r = ζ = 100 and on the
/// rigid wall, for e = 0.5 and 0.9 under each law, with the default e →
/// coefficient mapping of `exact` and with LIGGGHTS' of `formula` (the
/// points [`dembound_core::study::paper::closing_spec`] of each study).
pub fn closing_table(exact: &RestitutionStudy, formula: &RestitutionStudy) -> String {
    let mut md = String::new();
    let _ = writeln!(
        md,
        "**Closing note: effective restitution at r = ζ = 100 and on the rigid wall (r = ζ = \
         ∞)**, {}. Columns: the e → coefficient mapping (`contact.calibration`, \
         \"{}\" by default, or LIGGGHTS' \"{}\") and where the raw coefficient is calibrated \
         (on the pair itself, or on the wall and reused). Regenerate with \
         `cargo run --release -p dembound-core --example restitution_table`.\n",
        drop_text(exact),
        Calibration::Exact.name(),
        Calibration::Formula.name(),
    );
    let mut columns = vec![Column::text("law"), Column::text("e")];
    for mapping in ["exact", "formula"] {
        for place in ["wall", "r = ζ = 100 pair", "r = ζ = 100 wall"] {
            columns.push(Column::text(format!("{place}, {mapping}")).right());
        }
    }
    let mut table = Table::new(columns).with_keys(2);
    let inf = f64::INFINITY;
    for law in DissipativeLaw::ALL {
        for e in [0.5, 0.9] {
            let mut row = vec![Cell::text(law.name()), Cell::text(e.to_string())];
            for study in [exact, formula] {
                for (cal, r) in [
                    (CalibrationSite::Pair, inf),
                    (CalibrationSite::Pair, 100.0),
                    (CalibrationSite::Wall, 100.0),
                ] {
                    row.push(Cell::Text(
                        study
                            .point(law, cal, e, r, r)
                            .map(|p| format!("{:.6}", p.restitution()))
                            .unwrap_or_else(|| "—".into()),
                    ));
                }
            }
            table.push(row);
        }
    }
    md.push_str(&table.markdown());
    let _ = writeln!(
        md,
        "\nWith attraction forbidden (as here) \"formula\" leaves the clamped linear and Tsuji \
         laws rebounding faster than the target (0.550 for 0.5 on the wall, gravity-free); \
         \"exact\" removes that, and what remains on the wall is the effect of gravity during \
         the contact. Walton–Braun is exact either way (e = √(k₁/k₂)).\n"
    );
    md
}

/// Where ∞ is drawn on a log axis of `values`: a decade above the largest
/// finite value (at 1 when there is none).
fn infinity_position(values: &[f64]) -> f64 {
    values
        .iter()
        .copied()
        .filter(|v| v.is_finite())
        .fold(None, |m: Option<f64>, v| Some(m.map_or(v, |m| m.max(v))))
        .map_or(1.0, |m| 10.0 * m)
}

fn file_number(x: f64) -> String {
    let t = format!("{x}");
    t.replace('.', "p")
}

/// One quantity of the study for the figures.
struct Quantity {
    stem: &'static str,
    label: &'static str,
    value: fn(&RestitutionPoint) -> f64,
}

const QUANTITIES: [Quantity; 3] = [
    Quantity {
        stem: "restitution",
        label: "effective restitution v_r/|v_c| (1)",
        value: |p| p.restitution(),
    },
    Quantity {
        stem: "contact_time",
        label: "contact time T_c (µs)",
        value: |p| p.contact.duration * 1e6,
    },
    Quantity {
        stem: "max_overlap",
        label: "maximum overlap h_max (nm)",
        value: |p| p.contact.max_overlap * 1e9,
    },
];

/// Which ratio is on the x axis.
#[derive(Clone, Copy)]
enum Axis {
    R,
    Zeta,
}

fn figure(
    study: &RestitutionStudy,
    law: DissipativeLaw,
    target: f64,
    quantity: &Quantity,
    axis: Axis,
) -> Figure {
    let (xs, curves) = match axis {
        Axis::R => (&study.spec.radius_ratios, &study.spec.modulus_ratios),
        Axis::Zeta => (&study.spec.modulus_ratios, &study.spec.radius_ratios),
    };
    let inf_at = infinity_position(xs);
    let (x_name, curve_name) = match axis {
        Axis::R => ("r = R_b/R_m", "ζ"),
        Axis::Zeta => ("ζ = E_b/E_m", "r"),
    };
    let mut series = Vec::new();
    let calibrations = &study.spec.calibrations;
    for (i, &c) in curves.iter().enumerate() {
        for &cal in calibrations {
            let points: Vec<(f64, f64)> = xs
                .iter()
                .filter_map(|&x| {
                    let (r, z) = match axis {
                        Axis::R => (x, c),
                        Axis::Zeta => (c, x),
                    };
                    let p = study.point(law, cal, target, r, z)?;
                    let xp = if x.is_infinite() { inf_at } else { x };
                    Some((xp, (quantity.value)(p)))
                })
                .collect();
            let (mark, label) = match (cal, calibrations.len()) {
                (CalibrationSite::Wall, _) | (_, 1) => (
                    Mark::LinePoints,
                    format!("{curve_name} = {}", ratio_text(c)),
                ),
                // The wall series carries the legend entry of this colour.
                (CalibrationSite::Pair, _) => (Mark::Dashed, String::new()),
            };
            // Black is kept for the legend entries of the line styles.
            let color = if i >= BLACK { i + 1 } else { i };
            series.push(Series::new(label, points, mark, color));
        }
    }
    if calibrations.len() > 1 {
        series.push(Series::new(
            "solid: wall-calibrated",
            Vec::new(),
            Mark::LinePoints,
            BLACK,
        ));
        series.push(Series::new(
            "dashed: pair-calibrated",
            Vec::new(),
            Mark::Dashed,
            BLACK,
        ));
    }
    let calibration = if calibrations.len() == 1 {
        format!(", {}-calibrated", calibrations[0].name())
    } else {
        String::new()
    };
    Figure {
        title: format!(
            "{} ({}), target e = {target}{calibration}",
            law.description(),
            law.name()
        ),
        x_label: format!("{x_name} (1), log scale; ∞ drawn at {}", ratio_text(inf_at)),
        y_label: quantity.label.into(),
        x_log: true,
        y_log: false,
        series,
        x_infinity: xs.iter().any(|x| x.is_infinite()).then_some(inf_at),
        ..Default::default()
    }
}

/// Writes the study's figures into `dir` (SVG + PNG each): per target e and
/// law, the effective restitution, contact time and maximum overlap against
/// r (one curve per ζ), and the effective restitution against ζ (one curve
/// per r); wall calibration solid, pair calibration dashed. Returns the
/// paths written.
pub fn restitution_figures(study: &RestitutionStudy, dir: &Path) -> Result<Vec<PathBuf>> {
    std::fs::create_dir_all(dir)?;
    let mut jobs = Vec::new();
    for &target in &study.spec.targets {
        for &law in &study.spec.laws {
            for quantity in &QUANTITIES {
                jobs.push((target, law, quantity, Axis::R));
            }
            jobs.push((target, law, &QUANTITIES[0], Axis::Zeta));
        }
    }
    let mut written = Vec::new();
    for (target, law, quantity, axis) in jobs {
        let fig = figure(study, law, target, quantity, axis);
        let against = match axis {
            Axis::R => "r",
            Axis::Zeta => "zeta",
        };
        let stem = format!(
            "restitution_{}_e{}_{}_vs_{against}",
            law.name().replace('-', "_"),
            file_number(target),
            quantity.stem
        );
        let paths = fig.write(&dir.join(stem))?;
        written.extend(paths);
    }
    Ok(written)
}

/// Writes `restitution.csv`: one row per point of the sweep, SI.
pub fn write_restitution_csv(study: &RestitutionStudy, w: &mut dyn Write) -> Result<()> {
    let mut csv = csv::Writer::from_writer(w);
    csv.write_record([
        "law",
        "calibration",
        "target_restitution",
        "radius_ratio",
        "modulus_ratio",
        "boundary_radius_m",
        "boundary_youngs_modulus_Pa",
        "coefficient",
        "coefficient_unit",
        "restitution",
        "duration_s",
        "max_overlap_m",
        "force_zero_after_onset_s",
        "max_force_N",
        "impact_velocity_m_s",
        "rebound_velocity_m_s",
        "steps",
    ])?;
    for p in &study.points {
        let c = &p.contact;
        csv.write_record([
            p.law.name().to_string(),
            p.calibration.name().to_string(),
            exact(p.target),
            exact(p.radius_ratio),
            exact(p.modulus_ratio),
            exact(super::boundary::radius(&study.scenario, p.radius_ratio)),
            exact(super::boundary::youngs_modulus(
                &study.scenario,
                p.modulus_ratio,
            )),
            exact(p.coefficient),
            p.law.coefficient_unit().to_string(),
            exact(c.restitution),
            exact(c.duration),
            exact(c.max_overlap),
            c.t_force_zero
                .map(|t| exact(t - c.t_contact))
                .unwrap_or_default(),
            exact(c.max_force),
            exact(c.impact_velocity),
            exact(c.rebound_velocity),
            c.steps.to_string(),
        ])?;
    }
    csv.flush()?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use dembound_core::bounce::Scenario;
    use dembound_core::study::restitution::{restitution_sweep, RestitutionSpec};

    fn small() -> RestitutionStudy {
        let spec = RestitutionSpec {
            laws: vec![DissipativeLaw::Viscous, DissipativeLaw::WaltonBraun],
            targets: vec![0.5],
            radius_ratios: vec![10.0, f64::INFINITY],
            modulus_ratios: vec![10.0, f64::INFINITY],
            ..Default::default()
        };
        restitution_sweep(&Scenario::default(), &spec).unwrap()
    }

    #[test]
    fn ratios_print_short_and_whole() {
        assert_eq!(ratio_text(1000.0), "1000");
        assert_eq!(ratio_text(100.0), "100");
        assert_eq!(ratio_text(0.5), "0.5");
        assert_eq!(ratio_text(3.0), "3");
        assert_eq!(ratio_text(f64::INFINITY), "∞");
    }

    #[test]
    fn markdown_names_both_calibrations_and_the_diagonal() {
        let md = restitution_markdown(&small());
        assert!(md.contains("**wall**") && md.contains("**pair**"), "{md}");
        assert!(
            md.contains("r = ζ = 10 |") && md.contains("r = ζ = ∞ |"),
            "{md}"
        );
        assert!(md.contains("| walton-braun | wall |"), "{md}");
    }

    #[test]
    fn figures_are_written_for_every_law_and_quantity() {
        let dir = tempfile::tempdir().unwrap();
        let written = restitution_figures(&small(), dir.path()).unwrap();
        // 2 laws × (3 against r + 1 against ζ) × (svg + png).
        assert_eq!(written.len(), 16);
        let svg = std::fs::read_to_string(
            dir.path()
                .join("restitution_viscous_e0p5_restitution_vs_r.svg"),
        )
        .unwrap();
        assert!(svg.contains("effective restitution") && svg.contains("dashed: pair-calibrated"));
    }
}
