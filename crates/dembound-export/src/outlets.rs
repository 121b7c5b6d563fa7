//! Outlets (`[[outlet]]`, issue 28) in the LAMMPS and LIGGGHTS scene
//! decks: every [`EVERY`] steps (`run N every K "…"`), each outlet's
//! region (`region outletK block …` or `cylinder …`, `units box`) takes
//! the free spheres whose centres are inside it (surface included, as
//! dembound's `Region::holds`) into a group, adds their count and mass
//! to `outK_n` and `outK_m`, and `delete_atoms` them (`compress no`: the
//! others keep their ids). The thermo columns `v_outK_n v_outK_m` report
//! the spheres and the mass (kg) removed so far. Outlets act in file
//! order, so a sphere in two regions counts for the first, as in
//! dembound. Neither LIGGGHTS 3.8 (no `fix evaporate`; `fix
//! massflow/mesh … delete_atoms yes` removes spheres that *cross* a mesh
//! face, another rule) nor LAMMPS's `fix evaporate` (which reports no
//! mass) gives the rule and the mass directly, hence the commands.
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
/// of the free spheres (`None`: every sphere is free); `None` without
/// outlets. Refuses `domain.outside = "delete"` (module
/// `crate::refuse_lost_removal`) and a cylinder not along an axis.
pub(crate) fn plan(setup: &SceneSetup, code: &str, free: Option<&str>) -> Result<Option<Outlets>> {
    crate::refuse_lost_removal(setup, code)?;
    if setup.outlets.is_empty() {
        return Ok(None);
    }
    let mut o = Outlets {
        setup: format!(
            "\n# outlets: every {EVERY} steps the free spheres whose centres are in a region are deleted;\n\
             # thermo columns v_outK_n v_outK_m: spheres and mass (kg) removed so far by outlet K\n"
        ),
        commands: String::new(),
        columns: String::new(),
    };
    for (k, region) in setup.outlets.iter().enumerate() {
        writeln!(
            o.setup,
            "{}\nvariable     out{k}_n equal 0\nvariable     out{k}_m equal 0",
            region_line(k, region, code)?
        )
        .ok();
        let group = match free {
            None => format!(" \"group out{k} region outlet{k}\""),
            Some(f) => format!(
                " \"group out{k}_r region outlet{k}\" \"group out{k} intersect out{k}_r {f}\" \
                 \"group out{k}_r delete\""
            ),
        };
        write!(
            o.commands,
            "{group} \"variable out{k}_dn equal count(out{k})\" \
             \"variable out{k}_dm equal mass(out{k})\" \
             \"variable out{k}_n equal ${{out{k}_n}}+${{out{k}_dn}}\" \
             \"variable out{k}_m equal ${{out{k}_m}}+${{out{k}_dm}}\" \
             \"delete_atoms group out{k} compress no\" \"group out{k} delete\""
        )
        .ok();
        write!(o.columns, " v_out{k}_n v_out{k}_m").ok();
    }
    Ok(Some(o))
}

/// `run n`, with the outlets' removal every [`EVERY`] steps when there
/// are outlets.
pub(crate) fn run_line(n: u64, outlets: Option<&Outlets>) -> String {
    match outlets {
        Some(o) if n > 0 => format!("run          {n} post no every {EVERY}{}\n", o.commands),
        _ => format!("run          {n}\n"),
    }
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
    fn a_run_removes_every_hundred_steps_only_with_outlets() {
        assert_eq!(run_line(7, None), "run          7\n");
        let o = Outlets {
            setup: String::new(),
            commands: " \"x\"".into(),
            columns: String::new(),
        };
        assert_eq!(
            run_line(250, Some(&o)),
            "run          250 post no every 100 \"x\"\n"
        );
        assert_eq!(run_line(0, Some(&o)), "run          0\n");
    }
}
