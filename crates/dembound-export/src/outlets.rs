//! Outlets (`[[outlet]]`, issue 28) in the LAMMPS and LIGGGHTS scene
//! decks: at every multiple of [`EVERY`] steps (`run N every K "…"`, the
//! runs cut so that the checks fall on the multiples after a gate's
//! switch too), each outlet's region (`region outletK block …` or
//! `cylinder …`, `units box`) takes the free spheres whose centres are
//! inside it (surface included, as dembound's `Region::holds`) into a
//! group, adds their count and mass to `outK_done_n` and `outK_done_m`,
//! and `delete_atoms` them (`compress no`: the others keep their ids).
//! Outlets act in file order, so a sphere in two regions counts for the
//! first, as in dembound. Neither LIGGGHTS 3.8 (no `fix evaporate`; `fix
//! massflow/mesh … delete_atoms yes` removes spheres that *cross* a mesh
//! face, another rule) nor LAMMPS's `fix evaporate` (which reports no
//! mass) gives the rule and the mass directly, hence the commands.
//!
//! **The rows are the state after the deletion.** The dump and the
//! thermo row of a step are written inside the run's last step
//! (`Verlet::run` calls `Output::write` at the end of each step), before
//! `run … every` executes its commands (`Run::command`, LIGGGHTS-PUBLIC
//! `src/run.cpp`, and LAMMPS's alike), and the next run's setup does not
//! write the dump again at that step (`Output::setup`, `src/output.cpp`:
//! only when `last_dump != ntimestep`). So the rows do not wait for the
//! deletion: they leave out what it is about to delete. The dump skips
//! the free spheres whose centres are in an outlet (`dump_modify … thresh
//! v_outlet_pending == 0`, an atom-style `grmask(free,outlets)`), and the
//! thermo columns `v_outK_n v_outK_m` count them as removed (the running
//! totals plus `count(free,…)`, `mass(free,…)` of those in the region
//! now, each in its first outlet only). At a multiple of [`EVERY`] that
//! is exactly the state after the deletion; at a row between checks it
//! is the state a deletion at that row would leave (the spheres are
//! deleted at the next check, unless one leaves the region first, which
//! a later row then shows again). Before, the rows were written before
//! the deletion and held every sphere that entered an outlet in the last
//! [`EVERY`] steps (docs/export-liggghts.md, "The fed hopper over inlet
//! seeds").
//!
//! **How it differs from dembound's rule** (`dembound_scene::removal`):
//! dembound checks at its neighbour-list rebuilds and removes a sphere
//! only once it touches nothing (no sphere, no wall), so that no
//! contact's elastic energy leaves with it; the deck checks every
//! [`EVERY`] steps and removes every sphere inside, touching or not. For
//! spheres falling freely through an outlet below an orifice both remove
//! the same spheres, each code up to its cadence later than the step
//! the centre entered (`tests/export_outlets.rs`). It matters when an
//! outlet holds spheres in contact: a sphere resting on a floor inside an
//! outlet, or a packed bed reaching into it, stays in dembound until it
//! separates (for ever, resting), and leaves the deck at the next check.
//! A sphere that crosses a region in fewer than [`EVERY`] steps escapes
//! the deck's check (give the region a depth above v · [`EVERY`] Δt).

use std::fmt::Write as _;

use dembound_scene::region::Region;
use dembound_scene::SceneSetup;

use crate::{num, Error, Result};

/// Steps between the deck's removals.
pub const EVERY: u64 = 100;

/// The outlet commands of a deck.
pub(crate) struct Outlets {
    /// `region` and `variable` lines, written once before the runs.
    pub setup: String,
    /// The quoted commands `run … every` executes.
    pub commands: String,
    /// The thermo columns (with a leading space).
    pub columns: String,
}

/// The region line of `region` as `outlet{k}` (`code` the deck's code).
fn region_line(k: usize, region: &Region, code: &str) -> Result<String> {
    region_command(&format!("outlet{k}"), &format!("outlet[{k}]"), region, code)
}

/// The `region` line of `region` named `name`, `key` (`outlet[K]`,
/// `inlet[K]`) naming it in a refusal of a cylinder not along an axis
/// (`code` the deck's code).
pub(crate) fn region_command(name: &str, key: &str, region: &Region, code: &str) -> Result<String> {
    match *region {
        Region::Box { lower, upper } => Ok(format!(
            "region       {name} block {} {} {} {} {} {} units box",
            num(lower[0]),
            num(upper[0]),
            num(lower[1]),
            num(upper[1]),
            num(lower[2]),
            num(upper[2])
        )),
        Region::Cylinder {
            center,
            axis,
            radius,
            length,
        } => {
            let along: Vec<usize> = (0..3).filter(|&a| axis[a] != 0.0).collect();
            let [a] = along[..] else {
                return Err(Error::Export(format!(
                    "`{key}.region.cylinder.axis` = {axis:?} cannot be exported: the \
                     {code} deck's `region cylinder` has its axis along x, y or z only; give \
                     an axis-aligned cylinder or a box"
                )));
            };
            let (c1, c2) = match a {
                0 => (center[1], center[2]),
                1 => (center[0], center[2]),
                _ => (center[0], center[1]),
            };
            Ok(format!(
                "region       {name} cylinder {} {} {} {} {} {} units box",
                ["x", "y", "z"][a],
                num(c1),
                num(c2),
                num(radius),
                num(center[a] - 0.5 * length),
                num(center[a] + 0.5 * length)
            ))
        }
    }
}

/// The outlet commands of `setup` for the `code` deck, `free` the group
/// of the free spheres (`None`: every sphere is free), `dump` the id of
/// the deck's `dump custom` (written before [`Outlets::setup`]); `None`
/// without outlets. Refuses `domain.outside = "delete"` (module
/// `crate::refuse_lost_removal`) and a cylinder not along an axis.
pub(crate) fn plan(
    setup: &SceneSetup,
    code: &str,
    free: Option<&str>,
    dump: &str,
) -> Result<Option<Outlets>> {
    crate::refuse_lost_removal(setup, code)?;
    if setup.outlets.is_empty() {
        return Ok(None);
    }
    let group = free.unwrap_or("all");
    let mut o = Outlets {
        setup: format!(
            "\n# outlets: at every multiple of {EVERY} steps the free spheres whose centres are in a region\n\
             # are deleted (the commands of `run ... every {EVERY}`). The rows are the state after that\n\
             # deletion: the dump leaves out the free spheres in an outlet, and the thermo columns\n\
             # v_outK_n v_outK_m (spheres and mass (kg) removed by outlet K) count them as removed\n"
        ),
        commands: String::new(),
        columns: String::new(),
    };
    let mut regions = Vec::new();
    for (k, region) in setup.outlets.iter().enumerate() {
        writeln!(o.setup, "{}", region_line(k, region, code)?).ok();
        // The spheres outlet k takes: in its region and in no earlier one.
        let only = if k == 0 {
            format!("outlet{k}")
        } else {
            // The outside of the one before (the earlier ones' were
            // written with theirs).
            let j = k - 1;
            let outside = region_command(
                &format!("outlet{j}_out"),
                &format!("outlet[{j}]"),
                &setup.outlets[j],
                code,
            )?;
            let outs: Vec<String> = (0..k).map(|j| format!("outlet{j}_out")).collect();
            writeln!(
                o.setup,
                "{outside} side out\n\
                 region       outlet{k}_only intersect {} outlet{k} {}",
                k + 1,
                outs.join(" ")
            )
            .ok();
            format!("outlet{k}_only")
        };
        writeln!(
            o.setup,
            "variable     out{k}_done_n equal 0\nvariable     out{k}_done_m equal 0\n\
             variable     out{k}_n equal v_out{k}_done_n+count({group},{only})\n\
             variable     out{k}_m equal v_out{k}_done_m+mass({group},{only})"
        )
        .ok();
        regions.push(format!("outlet{k}"));
        let take = match free {
            None => format!(" \"group out{k} region outlet{k}\""),
            Some(f) => format!(
                " \"group out{k}_r region outlet{k}\" \"group out{k} intersect out{k}_r {f}\" \
                 \"group out{k}_r delete\""
            ),
        };
        write!(
            o.commands,
            "{take} \"variable out{k}_dn equal count(out{k})\" \
             \"variable out{k}_dm equal mass(out{k})\" \
             \"variable out{k}_done_n equal ${{out{k}_done_n}}+${{out{k}_dn}}\" \
             \"variable out{k}_done_m equal ${{out{k}_done_m}}+${{out{k}_dm}}\" \
             \"delete_atoms group out{k} compress no\" \"group out{k} delete\""
        )
        .ok();
        write!(o.columns, " v_out{k}_n v_out{k}_m").ok();
    }
    let all = if regions.len() == 1 {
        regions[0].clone()
    } else {
        writeln!(
            o.setup,
            "region       outlets union {} {}",
            regions.len(),
            regions.join(" ")
        )
        .ok();
        "outlets".into()
    };
    writeln!(
        o.setup,
        "variable     outlet_pending atom grmask({group},{all})\n\
         dump_modify  {dump} thresh v_outlet_pending == 0"
    )
    .ok();
    Ok(Some(o))
}

/// The `run` commands of the `n` steps after state `from`: with outlets,
/// the removal at every multiple of [`EVERY`] in (from, from + n] (a
/// first run up to the first multiple, `run … every {EVERY}` over the
/// whole chunks, a last run without removal to the end), so that the
/// checks fall on the same states whatever the gates cut.
pub(crate) fn run_lines(from: u64, n: u64, outlets: Option<&Outlets>) -> String {
    let Some(o) = outlets.filter(|_| n > 0) else {
        return format!("run          {n}\n");
    };
    let mut x = String::new();
    let end = from + n;
    let first = from.div_ceil(EVERY) * EVERY;
    let mut at = from;
    if first > from {
        if first <= end {
            let head = first - from;
            writeln!(x, "run          {head} post no every {head}{}", o.commands).ok();
            at = first;
        } else {
            return format!("run          {n}\n");
        }
    }
    let whole = (end - at) / EVERY * EVERY;
    if whole > 0 {
        writeln!(
            x,
            "run          {whole} post no every {EVERY}{}",
            o.commands
        )
        .ok();
        at += whole;
    }
    if end > at {
        writeln!(x, "run          {}", end - at).ok();
    }
    x
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn regions_in_the_codes_words() {
        let b = Region::Box {
            lower: [0.0, -1.0, 2.0],
            upper: [1.0, 1.0, 3.0],
        };
        assert_eq!(
            region_line(0, &b, "LAMMPS").unwrap(),
            "region       outlet0 block 0 1e0 -1e0 1e0 2e0 3e0 units box"
        );
        let c = Region::Cylinder {
            center: [1.0, 2.0, 3.0],
            axis: [0.0, 1.0, 0.0],
            radius: 0.5,
            length: 2.0,
        };
        // Along y: c1 c2 are x and z, the ends y = 2 ∓ 1.
        assert_eq!(
            region_line(1, &c, "LAMMPS").unwrap(),
            "region       outlet1 cylinder y 1e0 3e0 5e-1 1e0 3e0 units box"
        );
        let tilted = Region::Cylinder {
            center: [1.0, 2.0, 3.0],
            axis: [0.6, 0.0, 0.8],
            radius: 0.5,
            length: 2.0,
        };
        let e = region_line(2, &tilted, "LIGGGHTS").unwrap_err().to_string();
        assert!(e.contains("outlet[2].region.cylinder.axis") && e.contains("LIGGGHTS"));
    }

    #[test]
    fn a_run_removes_at_the_multiples_of_a_hundred_only_with_outlets() {
        assert_eq!(run_lines(0, 7, None), "run          7\n");
        let o = Outlets {
            setup: String::new(),
            commands: " \"x\"".into(),
            columns: String::new(),
        };
        // From state 0: whole chunks, the last 50 steps without removal.
        assert_eq!(
            run_lines(0, 250, Some(&o)),
            "run          200 post no every 100 \"x\"\nrun          50\n"
        );
        assert_eq!(
            run_lines(0, 500, Some(&o)),
            "run          500 post no every 100 \"x\"\n"
        );
        // After a switch at state 201: to 300, then on the multiples.
        assert_eq!(
            run_lines(201, 299, Some(&o)),
            "run          99 post no every 99 \"x\"\n\
             run          200 post no every 100 \"x\"\n"
        );
        // A stretch between two multiples holds no check.
        assert_eq!(run_lines(201, 50, Some(&o)), "run          50\n");
        assert_eq!(run_lines(0, 0, Some(&o)), "run          0\n");
    }

    /// Two outlets: the second counts only what the first does not take
    /// (`outlet1_only`, inside outlet1 and outside outlet0), the dump
    /// leaves out the free spheres in either, the columns add what is in
    /// the region now to what was deleted.
    #[test]
    fn the_rows_leave_out_what_the_next_check_deletes() {
        use dembound_scene::io::{config, resolve::resolve};
        let text = r#"
[domain]
lower = [0.0, 0.0, 0.0]
upper = [0.01, 0.01, 0.01]
[[material]]
name = "a"
density = 1000.0
youngs_modulus = 1.0e7
poisson_ratio = 0.3
[contact]
law = "hertz"
[[particles]]
spheres = [ { position = [0.005, 0.005, 0.008], radius = 1.0e-3 } ]
material = "a"
[[outlet]]
region = { box = { lower = [0.0, 0.0, 0.0], upper = [0.01, 0.01, 0.002] } }
[[outlet]]
region = { box = { lower = [0.0, 0.0, 0.0], upper = [0.005, 0.01, 0.004] } }
[integration]
dt = 1.0e-6
steps = 10
"#;
        let file = config::load(text, "test", &[]).expect("a valid scene");
        let scene = resolve(&file, std::path::Path::new(".")).expect("resolves");
        let o = plan(&scene.setup, "LIGGGHTS", Some("free"), "spheres")
            .expect("plans")
            .expect("outlets");
        let s = &o.setup;
        for line in [
            "region       outlet0_out block 0 1e-2 0 1e-2 0 2e-3 units box side out",
            "region       outlet1_only intersect 2 outlet1 outlet0_out",
            "variable     out0_n equal v_out0_done_n+count(free,outlet0)",
            "variable     out1_m equal v_out1_done_m+mass(free,outlet1_only)",
            "region       outlets union 2 outlet0 outlet1",
            "variable     outlet_pending atom grmask(free,outlets)",
            "dump_modify  spheres thresh v_outlet_pending == 0",
        ] {
            assert!(s.lines().any(|l| l == line), "no `{line}` in\n{s}");
        }
        // The thresh refers to the variable defined before it.
        assert!(s.find("variable     outlet_pending").unwrap() < s.find("thresh").unwrap());
        assert_eq!(o.columns, " v_out0_n v_out0_m v_out1_n v_out1_m");
        // The commands add the deleted count to the totals the columns read.
        assert!(o
            .commands
            .contains("\"variable out1_done_n equal ${out1_done_n}+${out1_dn}\""));
        assert!(o
            .commands
            .contains("\"delete_atoms group out0 compress no\""));
        // Every sphere free: the group is `all`.
        let o = plan(&scene.setup, "LAMMPS", None, "state")
            .unwrap()
            .unwrap();
        assert!(o.setup.contains("count(all,outlet0)"), "{}", o.setup);
        assert!(o
            .setup
            .contains("dump_modify  state thresh v_outlet_pending == 0"));
    }

    /// A series cadence that is not a multiple of the checks' (7 steps
    /// against [`EVERY`]): both decks print the thermo row with the outlet
    /// counts at every dump row (not only at the end), so that a row
    /// between checks reads its own step's counts, beside a dump that
    /// leaves out the spheres pending; the runs cover the 250 steps with
    /// the checks at 100 and 200 only.
    #[test]
    fn a_series_cadence_off_the_checks_prints_the_counts_at_every_row() {
        use dembound_scene::io::{config, resolve::resolve};
        let text = r#"
[domain]
lower = [0.0, 0.0, 0.0]
upper = [0.01, 0.01, 0.01]
[[material]]
name = "a"
density = 1000.0
youngs_modulus = 1.0e7
poisson_ratio = 0.3
[contact]
law = "hertz"
[[particles]]
spheres = [ { position = [0.005, 0.005, 0.008], radius = 1.0e-3 } ]
material = "a"
[[outlet]]
region = { box = { lower = [0.0, 0.0, 0.0], upper = [0.01, 0.01, 0.002] } }
[integration]
dt = 1.0e-6
steps = 250
[output]
series_every = 7
"#;
        let file = config::load(text, "test", &[]).expect("a valid scene");
        let scene = resolve(&file, std::path::Path::new(".")).expect("resolves");
        let decks = [
            (
                crate::lammps_scene::deck(&scene).expect("exports"),
                "dump         state all custom 7 ",
                "dump_modify  state thresh v_outlet_pending == 0",
            ),
            (
                crate::liggghts_scene::deck(&scene).expect("exports"),
                "dump         spheres all custom 7 ",
                "dump_modify  spheres thresh v_outlet_pending == 0",
            ),
        ];
        for (deck, dump, thresh) in decks {
            let input = &deck.files[0].text;
            let has = |p: &str| input.lines().any(|l| l.starts_with(p));
            assert!(
                has("thermo       7"),
                "no thermo at the cadence in\n{input}"
            );
            assert!(!has("thermo       250"), "{input}");
            assert!(has(dump) && has(thresh), "{input}");
            assert!(
                input.contains(" v_out0_n v_out0_m"),
                "no outlet columns in\n{input}"
            );
            // The runs: 200 steps checked every 100, then 50 unchecked.
            let runs: Vec<&str> = input.lines().filter(|l| l.starts_with("run ")).collect();
            let steps: u64 = runs
                .iter()
                .filter_map(|l| l.split_whitespace().nth(1)?.parse::<u64>().ok())
                .sum();
            assert_eq!(steps, 250, "{runs:?}");
            assert!(
                runs[0].starts_with("run          200 post no every 100 "),
                "{runs:?}"
            );
            assert_eq!(runs[runs.len() - 1], "run          50", "{runs:?}");
        }
    }
}
