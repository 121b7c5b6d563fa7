//! What a scene deck writes besides the thermo line: every sphere's state
//! and every wall's force at the scene's series cadence, in plain text a
//! test (or `dembound compare`) reads (docs/export-lammps.md, "Output").
//!
//! - `particles.dump`: LAMMPS `dump custom`, one block per row step:
//!   `id x y z vx vy vz omegax omegay omegaz` (SI), sorted by id (dembound's
//!   input order + 1), 17 significant digits (every f64 reads back).
//! - `walls.txt`: `fix ave/time` rows `step F0x F0y F0z F1x …`, the force
//!   on each wall in file order (N, as `dembound scene`'s series.csv:
//!   the force the spheres exert on the wall). A plane's is minus the sum
//!   of its `fix wall/gran … contacts` per-atom forces; a boundary-particle
//!   wall's is the sum of the forces on its spheres, stored by `fix
//!   store/force` before `fix freeze` zeroes them. The force at the row's
//!   step only (`fix ave/time N 1 N`: one step sampled in N).
//! - `walls_mean.txt`: the same columns averaged over every step since the
//!   previous row (`fix ave/time 1 N N`: steps kN−N+1 … kN, the mean of
//!   each component; no row at step 0), what `dembound compare` reads
//!   beside dembound's own per-step mean when the file is there
//!   (docs/export-lammps.md, "Wall forces: one step or every step").
//!
//! Rows at steps 0, N, 2N, … (N = output.series_every, default the run's
//! steps / 1000 as `dembound scene`); the last step only if a multiple of N.

use crate::num;
use dembound_scene::setup::{SceneSetup, WallSetup};
use std::fmt::Write;

/// The dump file of a scene deck.
pub const DUMP_FILE: &str = "particles.dump";
/// The wall-force file of a scene deck.
pub const WALLS_FILE: &str = "walls.txt";
/// The wall-force file averaged over every step of each row interval.
pub const WALLS_MEAN_FILE: &str = "walls_mean.txt";

/// Steps between rows: `output.series_every`, else steps/1000 (≥ 1).
pub fn series_every(series_every: Option<u64>, steps: u64) -> u64 {
    series_every.unwrap_or((steps / 1000).max(1))
}

/// `id` ranges `a:b` of the spheres (0-based indices, ascending) as a
/// LAMMPS group's id list.
pub(crate) fn id_ranges(ids: &[usize]) -> String {
    let mut out: Vec<String> = Vec::new();
    let mut k = 0;
    while k < ids.len() {
        let start = ids[k];
        let mut end = start;
        while k + 1 < ids.len() && ids[k + 1] == end + 1 {
            k += 1;
            end = ids[k];
        }
        out.push(format!("{}:{}", start + 1, end + 1));
        k += 1;
    }
    out.join(" ")
}

/// Lines that must come before `fix freeze`: one group per
/// boundary-particle wall and `fix store/force` on the frozen spheres.
pub fn before_freeze(setup: &SceneSetup) -> String {
    let mut x = String::new();
    let mut any = false;
    for (w, wall) in setup.walls.iter().enumerate() {
        if !wall.is_particles() {
            continue;
        }
        let ids: Vec<usize> = setup
            .spheres
            .iter()
            .enumerate()
            .filter(|(_, s)| s.group == Some(w))
            .map(|(i, _)| i)
            .collect();
        if ids.is_empty() {
            continue;
        }
        any = true;
        writeln!(
            x,
            "group        bpw{w} id {}   # the spheres of wall[{w}]",
            id_ranges(&ids)
        )
        .ok();
    }
    if any {
        writeln!(
            x,
            "fix          wallforce frozen store/force   # before fix freeze: the forces on the wall spheres"
        )
        .ok();
    }
    x
}

/// The dump and the wall-force file, written every `every` steps. `planes`:
/// (wall index, the `fix wall/gran` ids of that plane, one per free type).
/// `inserts` (a scene with inlets): the dump also has `radius mass`, what
/// `dembound compare` knows an inserted sphere by.
pub fn output(
    setup: &SceneSetup,
    every: u64,
    planes: &[(usize, Vec<String>)],
    inserts: bool,
) -> String {
    let mut x = String::new();
    let mut columns: Vec<String> = Vec::new();
    for (w, wall) in setup.walls.iter().enumerate() {
        if matches!(wall, WallSetup::Plane(_)) {
            let fixes = planes
                .iter()
                .find(|(p, _)| *p == w)
                .map(|(_, f)| f.as_slice())
                .unwrap_or(&[]);
            let fixes: Vec<String> = fixes.to_vec();
            x.push_str(&plane_force_lines(w, &fixes));
            for c in ["x", "y", "z"] {
                columns.push(format!("v_w{w}{c}"));
            }
        } else if setup.spheres.iter().any(|s| s.group == Some(w)) {
            for (axis, c) in ["x", "y", "z"].iter().enumerate() {
                writeln!(
                    x,
                    "compute      bpw{w}_{c} bpw{w} reduce sum f_wallforce[{}]",
                    axis + 1
                )
                .ok();
                columns.push(format!("c_bpw{w}_{c}"));
            }
        } else {
            for c in ["x", "y", "z"] {
                writeln!(x, "variable     w{w}{c} equal 0").ok();
                columns.push(format!("v_w{w}{c}"));
            }
        }
    }
    writeln!(
        x,
        "dump         state all custom {every} {DUMP_FILE} id x y z vx vy vz omegax omegay omegaz{}\n\
         dump_modify  state sort id format float %.17g",
        if inserts { " radius mass" } else { "" }
    )
    .ok();
    if !columns.is_empty() {
        writeln!(
            x,
            "fix          walls all ave/time {every} 1 {every} {} file {WALLS_FILE} format \" %.17g\"",
            columns.join(" ")
        )
        .ok();
        // LAMMPS's FixAveTime (fix_ave_time.cpp, nextvalid): Nevery 1,
        // Nrepeat N, Nfreq N samples steps kN-N+1 ... kN and writes their
        // mean at kN.
        writeln!(
            x,
            "fix          walls_mean all ave/time 1 {every} {every} {} file {WALLS_MEAN_FILE} format \" %.17g\"   # every step's force, averaged over each row interval",
            columns.join(" ")
        )
        .ok();
    }
    x
}

/// The force columns of plane wall `w` (`variable wW{x,y,z}`, the force
/// on the wall) from its `fix wall/gran` ids `fixes`: columns 2-4 of
/// each fix's contacts array are the force on the sphere.
pub fn plane_force_lines(w: usize, fixes: &[String]) -> String {
    let mut x = String::new();
    for (axis, c) in ["x", "y", "z"].iter().enumerate() {
        let terms: Vec<String> = fixes
            .iter()
            .map(|f| {
                writeln!(x, "compute      {f}_{c} all reduce sum f_{f}[{}]", axis + 2).ok();
                format!("c_{f}_{c}")
            })
            .collect();
        let sum = if terms.is_empty() {
            "0".to_string()
        } else {
            format!("-({})", terms.join("+"))
        };
        writeln!(x, "variable     w{w}{c} equal {sum}").ok();
    }
    x
}

/// A comment line for the deck's header.
pub fn about(every: u64, dt: f64) -> String {
    format!(
        "rows: {DUMP_FILE} (id x y z vx vy vz omegax omegay omegaz, SI) and {WALLS_FILE} (step, then Fx Fy Fz N on each wall in file order) every {every} steps ({} s)",
        num(every as f64 * dt)
    )
}

/// A comment line for the deck's header: what walls_mean.txt holds.
pub fn about_mean(every: u64) -> String {
    format!(
        "{WALLS_MEAN_FILE}: the same columns averaged over every step since the previous row (the row of step k: steps k-{} ... k; no row at step 0)",
        every - 1
    )
}

#[cfg(test)]
mod tests {
    use super::id_ranges;

    #[test]
    fn ranges_are_one_based_and_merged() {
        assert_eq!(id_ranges(&[0, 1, 2, 5, 7, 8]), "1:3 6:6 8:9");
        assert_eq!(id_ranges(&[]), "");
    }
}
