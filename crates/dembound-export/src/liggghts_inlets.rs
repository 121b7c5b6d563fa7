//! Inlets (`[[inlet]]`, issue 28) in the LIGGGHTS scene deck: per inlet,
//! one `fix particletemplate/sphere` per radius, a `fix
//! particledistribution/discrete/numberbased` over them, a `region` and
//! `fix insert/rate/region … overlapcheck yes all_in yes`, the way
//! scripts/beverloo_study.py pours the silo. The thermo columns
//! `f_insK[1] f_insK[2]` report the spheres and the mass (kg) inlet K has
//! inserted so far (`FixInsert::compute_vector`: `ninserted`,
//! `massinserted`), beside dembound's series.csv `inletK_inserted`,
//! `inletK_mass_kg`.
//!
//! **What LIGGGHTS does** (LIGGGHTS-PUBLIC 3.8, src/fix_insert.cpp,
//! fix_insert_pack.cpp, fix_insert_rate_region.cpp,
//! fix_particledistribution_discrete.cpp):
//! - events at steps `start`, `start + insert_every`, … (`pre_exchange`
//!   at `next_reneighbor`, after the step's first half kick and drift: the
//!   step dembound inserts at, mid-step, too);
//! - each event inserts floor(n + U) spheres, n = particlerate ·
//!   insert_every · Δt and U uniform in [0, 1) (`calc_ninsert_this`),
//!   clipped so the total never passes `nparticles`; the last event gets
//!   what is left;
//! - `/numberbased` fractions are by number (without it, by mass, turned
//!   into numbers by each template's mass, in the constructor); with the
//!   default `random_distribute exact`, an event of n spheres takes
//!   floor(n w_i) of template i and hands the remaining few out at random
//!   in proportion to the remainders (`randomize_list`);
//! - each sphere's centre is drawn uniformly in the region shrunk by its
//!   radius (`all_in yes`: `generate_random_shrinkby_cut`), larger
//!   templates first, and kept if it overlaps no sphere
//!   (`check_near_set_x_v_omega` against the spheres near the region; the
//!   walls are not tested); an event tries at most n · `maxattempt`
//!   centres in all (`calc_maxtry`);
//! - a sphere that finds no place is not inserted ("Less insertions than
//!   requested"): `ninserted` stays short, and since insertion goes on
//!   until `ninserted` reaches `nparticles`, later events make it up.
//!
//! **When the counts agree.** dembound inserts round(ṅ t) − (those due
//! before) at each event (`dembound_scene::inlets`), so when n = ṅ ·
//! every · Δt is a whole number both insert exactly n per event, at the
//! same steps, the last event the rest of round(ṅ (end − start)): the
//! deck writes `particlerate` nudged up by a few ulps so that LIGGGHTS's
//! product is not below n (then floor(n + U) = n for every U). When n is
//! not whole, LIGGGHTS rounds each event at random: the same mean, a
//! cumulative count spread by √(E f (1 − f)) spheres after E events (f
//! the fractional part of n), noted. Counts part when a sphere finds no
//! place: dembound counts it `not_placed` and never inserts it, LIGGGHTS
//! inserts it later; and when the region reaches a wall (LIGGGHTS places
//! spheres across it, dembound does not), noted.
//!
//! **Velocity.** dembound gives an inserted sphere v₀ at the end of its
//! step (the half-step velocity v₀ − g Δt/2 is stored, the step's last
//! half kick completes it); LIGGGHTS's last half kick adds g Δt/2 to the
//! velocity it inserts, so the deck inserts v₀ − g Δt/2 (`vel constant`):
//! the same velocity at the end of the step for a sphere touching nothing.
//!
//! **Sizes.** Fixed and table radii are exact (table fractions are by
//! number in both). LIGGGHTS has only constant template radii, so a
//! uniform or truncated normal radius is written as [`BINS`] templates:
//! [`BINS`] equal-width bins of [min, max], each the cube root of its
//! mean R³ at the bin's probability, so that the mean sphere volume and
//! mass (hence ṅ and the mass rate) are dembound's to rounding; the
//! spread of radii within a bin is lost (the mean radius and its standard
//! deviation differ slightly: the note printed at export and written in
//! the deck gives both).

use std::fmt::Write as _;

use dembound_scene::inlets::{InletRate, Inlets, SizeDistribution};
use dembound_scene::setup::WallSetup;
use dembound_scene::SceneSetup;

use crate::{num, Result};

/// Templates a uniform or normal radius distribution is written as.
pub const BINS: usize = 20;

/// The inlet commands of a deck.
pub(crate) struct InletLines {
    /// Templates, distributions, regions and insertion fixes.
    pub setup: String,
    /// The thermo columns (with a leading space).
    pub columns: String,
    /// What the reader should know (also written in the deck).
    pub notes: Vec<String>,
    /// The smallest radius inserted, m.
    pub min_radius: f64,
}

/// Whether `n` is prime (trial division; n < 2³¹).
fn is_prime(n: u64) -> bool {
    n >= 2
        && (2..)
            .take_while(|d| d * d <= n)
            .all(|d| !n.is_multiple_of(d))
}

/// `count` primes above a base drawn from `seed` and the inlet index `k`:
/// LIGGGHTS wants every seed a prime > 10000 below 2³¹
/// (`Random::Random`).
fn seeds(seed: u64, k: usize, count: usize) -> Vec<u64> {
    let base = 10_000 + (seed.wrapping_mul(1009).wrapping_add(k as u64) % 2_000_000) * 1000;
    (base + 1..).filter(|&n| is_prime(n)).take(count).collect()
}

/// Simpson's rule over [a, b] with `n` (even) intervals of f.
fn simpson(a: f64, b: f64, n: usize, f: &dyn Fn(f64) -> f64) -> f64 {
    let h = (b - a) / n as f64;
    (0..=n)
        .map(|i| {
            let w = if i == 0 || i == n {
                1.0
            } else if i % 2 == 1 {
                4.0
            } else {
                2.0
            };
            w * f(a + h * i as f64)
        })
        .sum::<f64>()
        * h
        / 3.0
}

/// The templates of a size distribution: (radius m, fraction by number),
/// and a note when it is binned.
pub(crate) fn templates(size: &SizeDistribution) -> (Vec<(f64, f64)>, Option<String>) {
    // (bin's probability, its E[R], E[R²], E[R³]) per bin, and the
    // distribution's E[R], E[R²].
    let binned = |bins: Vec<[f64; 4]>, what: String| {
        let total: f64 = bins.iter().map(|b| b[0]).sum();
        let moment = |j: usize| bins.iter().map(|b| b[0] * b[j]).sum::<f64>() / total;
        let (mean, mean_sq) = (moment(1), moment(2));
        let rows: Vec<(f64, f64)> = bins
            .iter()
            .filter(|b| b[0] > 0.0)
            .map(|b| (b[3].cbrt(), b[0] / total))
            .collect();
        let n: f64 = rows.iter().map(|r| r.1).sum();
        let d_mean = rows.iter().map(|r| r.1 * r.0).sum::<f64>() / n;
        let d_sq = rows.iter().map(|r| r.1 * r.0 * r.0).sum::<f64>() / n;
        let d_cube = rows.iter().map(|r| r.1 * r.0.powi(3)).sum::<f64>() / n;
        let sd = (mean_sq - mean * mean).max(0.0).sqrt();
        let d_sd = (d_sq - d_mean * d_mean).max(0.0).sqrt();
        let cube = size.mean_cube();
        let note = format!(
            "{what} written as {} LIGGGHTS templates (LIGGGHTS has constant template radii \
             only): {BINS} equal-width bins, each the cube root of its mean R^3 at its \
             probability (fractions by number); the mean sphere mass differs from dembound's \
             by {:.1e} (relative), the mean radius by {:.1e}, the radius standard deviation by \
             {:.1e}",
            rows.len(),
            ((d_cube - cube) / cube).abs(),
            ((d_mean - mean) / mean).abs(),
            if sd > 0.0 {
                ((d_sd - sd) / sd).abs()
            } else {
                0.0
            },
        );
        (rows, Some(note))
    };
    match size {
        SizeDistribution::Fixed(r) => (vec![(*r, 1.0)], None),
        SizeDistribution::Uniform(a, b) if b <= a => (vec![(*a, 1.0)], None),
        SizeDistribution::Uniform(a, b) => {
            let w = (b - a) / BINS as f64;
            let bins = (0..BINS)
                .map(|i| {
                    let (lo, hi) = (
                        a + w * i as f64,
                        if i + 1 == BINS {
                            *b
                        } else {
                            a + w * (i + 1) as f64
                        },
                    );
                    // Moments of the uniform on [lo, hi]: (hi^(j+1) −
                    // lo^(j+1)) / ((j + 1)(hi − lo)).
                    let m =
                        |j: i32| (hi.powi(j + 1) - lo.powi(j + 1)) / ((j + 1) as f64 * (hi - lo));
                    [1.0 / BINS as f64, m(1), m(2), m(3)]
                })
                .collect();
            binned(
                bins,
                format!("uniform radii in [{}, {}] m", num(*a), num(*b)),
            )
        }
        SizeDistribution::Normal {
            mean,
            std,
            min,
            max,
        } => {
            if *std == 0.0 || max <= min {
                return (vec![(mean.clamp(*min, *max), 1.0)], None);
            }
            // The truncated density (unnormalised), integrated by
            // Simpson's rule on the nodes of `SizeDistribution::mean_cube`
            // (2000 intervals over [min, max], 2000 / BINS per bin).
            let p = |r: f64| (-0.5 * ((r - mean) / std).powi(2)).exp();
            let w = (max - min) / BINS as f64;
            let per_bin = 2000 / BINS;
            let bins = (0..BINS)
                .map(|i| {
                    let (lo, hi) = (
                        min + w * i as f64,
                        if i + 1 == BINS {
                            *max
                        } else {
                            min + w * (i + 1) as f64
                        },
                    );
                    let mass = simpson(lo, hi, per_bin, &p);
                    let m = |j: i32| {
                        if mass > 0.0 {
                            simpson(lo, hi, per_bin, &|r| p(r) * r.powi(j)) / mass
                        } else {
                            0.5 * (lo + hi)
                        }
                    };
                    [mass, m(1), m(2), m(3)]
                })
                .collect();
            binned(
                bins,
                format!(
                    "normal radii (mean {} m, std {} m, truncated to [{}, {}] m)",
                    num(*mean),
                    num(*std),
                    num(*min),
                    num(*max)
                ),
            )
        }
        SizeDistribution::Table(rows) => {
            let total: f64 = rows.iter().map(|r| r.1).sum();
            (
                rows.iter()
                    .filter(|r| r.1 > 0.0)
                    .map(|r| (r.0, r.1 / total))
                    .collect(),
                None,
            )
        }
    }
}

/// The region line of inlet `k`.
fn region_line(k: usize, region: &dembound_scene::region::Region) -> Result<String> {
    crate::outlets::region_command(
        &format!("inlet{k}"),
        &format!("inlet[{k}]"),
        region,
        "LIGGGHTS",
    )
}

/// Whether the box `lo..hi` (m) reaches wall `w` (a plane crossing or
/// touching it, a mesh whose bounding box meets it): LIGGGHTS may place
/// spheres across the wall there, dembound does not.
fn reaches(wall: &WallSetup, lo: [f64; 3], hi: [f64; 3]) -> bool {
    match wall {
        WallSetup::Plane(p) => (0..3)
            .find(|&a| p.normal[a] != 0.0)
            .is_some_and(|a| p.point[a] >= lo[a] && p.point[a] <= hi[a]),
        WallSetup::Mesh(m) => {
            (0..3).all(|a| m.geometry.lo[a] <= hi[a] && m.geometry.hi[a] >= lo[a])
        }
        _ => true,
    }
}

/// The inlet commands of `setup` for a run of `steps` steps of `dt` (s),
/// the inserting fixes on `group` (LIGGGHTS gives an inserted sphere the
/// mask `1 | groupbit` of its fix, particleToInsert.cpp: `free` puts it
/// among the integrated spheres when some are frozen); `None` without
/// inlets. Refuses, naming the key, what LIGGGHTS cannot express (a
/// cylinder not along an axis).
pub(crate) fn plan(
    setup: &SceneSetup,
    dt: f64,
    steps: u64,
    group: &str,
) -> Result<Option<InletLines>> {
    if setup.inlets.is_empty() {
        return Ok(None);
    }
    let densities: Vec<f64> = setup.materials.iter().map(|m| m.material.density).collect();
    let inlets = Inlets::new(
        &setup.inlets,
        &densities,
        setup.spheres.len(),
        dt,
        steps as f64 * dt,
    )
    .map_err(|e| crate::Error::Export(e.to_string()))?;
    let mut out = InletLines {
        setup: "\n# inlets (fix insert/rate/region; docs/export-liggghts.md, \"Inlets (scenes)\"): thermo columns\n\
                # f_insK[1] f_insK[2]: spheres and mass (kg) inserted so far by inlet K\n"
            .into(),
        columns: String::new(),
        notes: Vec::new(),
        min_radius: f64::INFINITY,
    };
    let g = setup.gravity;
    for (k, inlet) in inlets.inlets.iter().enumerate() {
        let s = &inlet.setup;
        let region = region_line(k, &s.region)?;
        let (rows, size_note) = templates(&s.size);
        if let Some(n) = size_note {
            out.notes.push(format!("inlet[{k}].size: {n}"));
        }
        out.min_radius = rows.iter().map(|r| r.0).fold(out.min_radius, f64::min);
        let seed = seeds(s.seed, k, rows.len() + 2);
        let rho = densities[s.material];
        let ty = s.material + 1;
        writeln!(
            out.setup,
            "# inlet[{k}]: material \"{}\" (type {ty}), {} radius template(s), fractions by number",
            setup.materials[s.material].name,
            rows.len()
        )
        .ok();
        for (j, (r, _)) in rows.iter().enumerate() {
            writeln!(
                out.setup,
                "fix          ins{k}_t{j} all particletemplate/sphere {} atom_type {ty} density constant {} radius constant {}",
                seed[j],
                num(rho),
                num(*r)
            )
            .ok();
        }
        let pairs: Vec<String> = rows
            .iter()
            .enumerate()
            .map(|(j, (_, w))| format!("ins{k}_t{j} {}", num(*w)))
            .collect();
        writeln!(
            out.setup,
            "fix          ins{k}_d all particledistribution/discrete/numberbased {} {} {}\n{region}",
            seed[rows.len()],
            rows.len(),
            pairs.join(" ")
        )
        .ok();
        // Spheres per event, and the rate LIGGGHTS multiplies by its
        // interval: nudged up to the whole number when n is one.
        let every = inlet.every;
        let interval = every as f64 * dt;
        let per_event = inlet.number_rate * interval;
        let whole = per_event.round();
        let mut rate = inlet.number_rate;
        if whole >= 1.0 && (per_event - whole).abs() <= 1e-9 * whole {
            while rate * interval < whole {
                rate = rate.next_up();
            }
        } else {
            let events = if inlet.window.is_finite() {
                (inlet.window / interval).ceil()
            } else {
                ((steps.saturating_sub(inlet.first_step)) / every + 1) as f64
            };
            let f = per_event.fract();
            out.notes.push(format!(
                "inlet[{k}]: rate x every x dt = {per_event:.6} spheres per event is not a whole \
                 number: LIGGGHTS inserts floor(n + U) per event (U uniform in [0, 1); \
                 fix_insert.cpp FixInsert::calc_ninsert_this), dembound round(rate t) in all; \
                 the same mean count, LIGGGHTS's spread by about {:.2} spheres after the {events} \
                 events (sqrt(E f (1 - f)), f = {f:.4}); give inlet[{k}].every (or the rate) so \
                 that the count per event is whole for equal counts",
                (events * f * (1.0 - f)).sqrt()
            ));
        }
        let total = if inlet.window.is_finite() {
            let n = (inlet.number_rate * inlet.window).round();
            format!("{}", n.clamp(0.0, 2e9) as u64)
        } else {
            "INF".into()
        };
        // LIGGGHTS tries n · maxattempt centres per event in an int.
        let max_attempt = s
            .max_attempts
            .min(i32::MAX as u64 / (per_event.ceil().max(1.0) as u64 + 1))
            .max(1);
        let v = [0, 1, 2].map(|a| s.velocity[a] - 0.5 * dt * g[a]);
        let rate_words = match s.rate {
            InletRate::Number(n) => format!("{} spheres/s", num(n)),
            InletRate::Mass(q) => {
                format!("{} kg/s, i.e. {} spheres/s", num(q), num(inlet.number_rate))
            }
        };
        writeln!(
            out.setup,
            "# {rate_words} from step {} every {every} steps ({per_event:.6} per event){}; velocity v0 - g dt/2\n\
             # (LIGGGHTS's last half kick of the step adds g dt/2: v0 at the step's end, as dembound)\n\
             fix          ins{k} {group} insert/rate/region seed {} distributiontemplate ins{k}_d nparticles {total} \
             particlerate {} insert_every {every} start {} overlapcheck yes all_in yes maxattempt {max_attempt} \
             vel constant {} {} {} region inlet{k}",
            inlet.first_step,
            if total == "INF" {
                String::new()
            } else {
                format!(", {total} spheres in all")
            },
            seed[rows.len() + 1],
            num(rate),
            inlet.first_step,
            num(v[0]),
            num(v[1]),
            num(v[2]),
        )
        .ok();
        write!(out.columns, " f_ins{k}[1] f_ins{k}[2]").ok();
        let (lo, hi) = s.region.bounds();
        for (w, wall) in setup.walls.iter().enumerate() {
            if reaches(wall, lo, hi) {
                out.notes.push(format!(
                    "inlet[{k}].region reaches wall[{w}]: LIGGGHTS's overlap check tests the \
                     spheres only (fix_insert_pack.cpp FixInsertPack::x_v_omega), so it may place \
                     spheres across the wall where dembound does not: the counts can differ"
                ));
            }
        }
    }
    for n in &out.notes {
        writeln!(out.setup, "# NOTE {n}").ok();
    }
    Ok(Some(out))
}

/// The notes of the LIGGGHTS deck's inlets (the binning of a uniform or
/// normal size, a count per event that is not whole, a region reaching
/// a wall), for the export to print; empty without inlets or when the
/// scene does not build.
pub fn notes(setup: &SceneSetup) -> Vec<String> {
    if setup.inlets.is_empty() {
        return Vec::new();
    }
    let Ok(sim) = dembound_scene::Simulation::new(setup.clone(), 1) else {
        return Vec::new();
    };
    plan(setup, sim.dt(), sim.total_steps(), "all")
        .ok()
        .flatten()
        .map_or(Vec::new(), |p| p.notes)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn seeds_are_primes_above_ten_thousand_below_int_max() {
        for seed in [0u64, 1, 7, u64::MAX] {
            for k in 0..3 {
                let s = seeds(seed, k, 25);
                assert_eq!(s.len(), 25);
                assert!(s
                    .iter()
                    .all(|&n| n > 10_000 && n < i32::MAX as u64 && is_prime(n)));
            }
        }
        assert!(is_prime(15485863) && !is_prime(15485861));
    }

    /// The binned uniform keeps E[R³] (each bin's cube root of its mean
    /// R³: Σ w_i r_i³ = Σ w_i E[R³ | bin i] = E[R³]), to rounding.
    #[test]
    fn binned_sizes_keep_the_mean_cube() {
        let u = SizeDistribution::Uniform(0.9e-3, 1.1e-3);
        let (rows, note) = templates(&u);
        assert_eq!(rows.len(), BINS);
        let cube: f64 = rows.iter().map(|r| r.1 * r.0.powi(3)).sum();
        // 20 terms of a few roundings each: 1e-14 relative.
        assert!((cube - u.mean_cube()).abs() <= 1e-14 * u.mean_cube());
        assert!(note.unwrap().contains("20 LIGGGHTS templates"));
        let n = SizeDistribution::Normal {
            mean: 1e-3,
            std: 0.1e-3,
            min: 0.8e-3,
            max: 1.3e-3,
        };
        let (rows, _) = templates(&n);
        let w: f64 = rows.iter().map(|r| r.1).sum();
        let cube: f64 = rows.iter().map(|r| r.1 * r.0.powi(3)).sum::<f64>() / w;
        // The same Simpson nodes as mean_cube, summed by bin: 1e-13.
        assert!(
            (cube - n.mean_cube()).abs() <= 1e-13 * n.mean_cube(),
            "{cube}"
        );
        assert!(rows.windows(2).all(|p| p[0].0 < p[1].0));
        // A table keeps its rows (zero fractions dropped), normalised.
        let t = SizeDistribution::Table(vec![(1e-3, 2.0), (2e-3, 0.0), (1.5e-3, 6.0)]);
        assert_eq!(templates(&t).0, vec![(1e-3, 0.25), (1.5e-3, 0.75)]);
    }
}
