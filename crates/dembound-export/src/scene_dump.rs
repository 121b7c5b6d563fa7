//! Reading what a scene deck's run wrote: `particles.dump` (LAMMPS or
//! LIGGGHTS `dump custom`, columns named by its `ITEM: ATOMS` line) and
//! `walls.txt` (LAMMPS `fix ave/time`: step, then Fx Fy Fz of each wall).

use crate::{Error, Result};
use std::collections::BTreeMap;

/// One sphere of one dump row, SI.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DumpedSphere {
    pub id: u64,
    pub position: [f64; 3],
    pub velocity: [f64; 3],
    /// Angular velocity, when the dump has `omegax omegay omegaz`.
    pub spin: Option<[f64; 3]>,
}

/// One dump row: the step and every sphere, sorted by id.
#[derive(Debug, Clone, PartialEq)]
pub struct DumpRow {
    pub step: u64,
    pub spheres: Vec<DumpedSphere>,
}

fn bad(what: &str, line: usize, detail: &str) -> Error {
    Error::Trace(format!("{what} line {line}: {detail}"))
}

/// Every row of a `dump custom` file with at least `id x y z vx vy vz`.
pub fn parse_dump(text: &str) -> Result<Vec<DumpRow>> {
    let lines: Vec<&str> = text.lines().collect();
    let mut rows = Vec::new();
    let mut k = 0;
    let number = |k: usize, w: &str| -> Result<f64> {
        w.parse::<f64>()
            .map_err(|_| bad("particles.dump", k + 1, &format!("`{w}` is not a number")))
    };
    while k < lines.len() {
        if !lines[k].starts_with("ITEM: TIMESTEP") {
            k += 1;
            continue;
        }
        let step_line = lines.get(k + 1).copied().unwrap_or("");
        let step: u64 = step_line
            .trim()
            .parse()
            .map_err(|_| bad("particles.dump", k + 2, "expected a step"))?;
        let count_at = (k..lines.len())
            .find(|&j| lines[j].starts_with("ITEM: NUMBER OF ATOMS"))
            .ok_or_else(|| bad("particles.dump", k + 1, "no ITEM: NUMBER OF ATOMS"))?;
        let n: usize = lines
            .get(count_at + 1)
            .and_then(|l| l.trim().parse().ok())
            .ok_or_else(|| bad("particles.dump", count_at + 2, "expected an atom count"))?;
        let header_at = (count_at..lines.len())
            .find(|&j| lines[j].starts_with("ITEM: ATOMS"))
            .ok_or_else(|| bad("particles.dump", count_at + 1, "no ITEM: ATOMS"))?;
        let columns: Vec<&str> = lines[header_at]
            .trim_start_matches("ITEM: ATOMS")
            .split_whitespace()
            .collect();
        let col = |name: &str| columns.iter().position(|c| *c == name);
        let need = |name: &str| {
            col(name).ok_or_else(|| {
                bad(
                    "particles.dump",
                    header_at + 1,
                    &format!("no column `{name}` (need id x y z vx vy vz)"),
                )
            })
        };
        let (id, x, v) = (
            need("id")?,
            [need("x")?, need("y")?, need("z")?],
            [need("vx")?, need("vy")?, need("vz")?],
        );
        let w = match (col("omegax"), col("omegay"), col("omegaz")) {
            (Some(a), Some(b), Some(c)) => Some([a, b, c]),
            _ => None,
        };
        let mut spheres = Vec::with_capacity(n);
        for j in header_at + 1..header_at + 1 + n {
            let line = lines
                .get(j)
                .ok_or_else(|| bad("particles.dump", j + 1, "the row ends early"))?;
            let words: Vec<&str> = line.split_whitespace().collect();
            if words.len() < columns.len() {
                return Err(bad("particles.dump", j + 1, "too few columns"));
            }
            let get3 = |c: [usize; 3]| -> Result<[f64; 3]> {
                Ok([
                    number(j, words[c[0]])?,
                    number(j, words[c[1]])?,
                    number(j, words[c[2]])?,
                ])
            };
            spheres.push(DumpedSphere {
                id: number(j, words[id])? as u64,
                position: get3(x)?,
                velocity: get3(v)?,
                spin: w.map(get3).transpose()?,
            });
        }
        spheres.sort_by_key(|s| s.id);
        rows.push(DumpRow { step, spheres });
        k = header_at + 1 + n;
    }
    if rows.is_empty() {
        return Err(Error::Trace("particles.dump holds no row".into()));
    }
    Ok(rows)
}

/// `walls.txt`: step → the force on each wall (Fx Fy Fz per wall, N).
pub fn parse_walls(text: &str) -> Result<BTreeMap<u64, Vec<f64>>> {
    let mut rows = BTreeMap::new();
    for (k, line) in text.lines().enumerate() {
        if line.starts_with('#') || line.trim().is_empty() {
            continue;
        }
        let words: Vec<f64> = line
            .split_whitespace()
            .map(|w| w.parse::<f64>())
            .collect::<std::result::Result<_, _>>()
            .map_err(|_| bad("walls.txt", k + 1, "expected numbers"))?;
        let Some((&step, forces)) = words.split_first() else {
            continue;
        };
        rows.insert(step as u64, forces.to_vec());
    }
    Ok(rows)
}

/// From a LAMMPS or LIGGGHTS log: (loop seconds, processes, steps, atoms)
/// of the last `Loop time of T on P procs for N steps with M atoms` line.
pub fn loop_time(log: &str) -> Option<(f64, u64, u64, u64)> {
    let line = log.lines().rev().find(|l| l.starts_with("Loop time of"))?;
    let w: Vec<&str> = line.split_whitespace().collect();
    // Loop time of T on P procs for N steps with M atoms
    Some((
        w.get(3)?.parse().ok()?,
        w.get(5)?.parse().ok()?,
        w.get(8)?.parse().ok()?,
        w.get(11)?.trim_end_matches(',').parse().ok()?,
    ))
}

/// LAMMPS's "X% CPU use with P MPI tasks x T OpenMP threads" line after the
/// last "Loop time": rank 0's CPU time over the loop's wall time, percent
/// (LIGGGHTS 3.8 prints no such line).
pub fn cpu_use_percent(log: &str) -> Option<f64> {
    let after = log.rsplit_once("Loop time of")?.1;
    let line = after.lines().find(|l| l.contains("% CPU use"))?;
    line.split('%').next()?.trim().parse().ok()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_dump_reads_by_column_name_and_sorts_by_id() {
        let text = "ITEM: TIMESTEP\n5\nITEM: NUMBER OF ATOMS\n2\nITEM: BOX BOUNDS mm mm mm\n0 1\n0 1\n0 1\n\
                    ITEM: ATOMS id type radius x y z vx vy vz\n2 1 0.5 1 2 3 4 5 6\n1 1 0.5 0.1 0.2 0.3 0 0 -1\n";
        let rows = parse_dump(text).expect("reads");
        assert_eq!(rows.len(), 1);
        assert_eq!(rows[0].step, 5);
        assert_eq!(rows[0].spheres[0].id, 1);
        assert_eq!(rows[0].spheres[0].velocity, [0.0, 0.0, -1.0]);
        assert_eq!(rows[0].spheres[1].position, [1.0, 2.0, 3.0]);
        assert!(rows[0].spheres[0].spin.is_none());
        assert!(parse_dump("ITEM: TIMESTEP\nx\n").is_err());
    }

    #[test]
    fn the_loop_time_line() {
        let log = "x\nLoop time of 2.17376 on 1 procs for 1000 steps with 414 atoms\n";
        assert_eq!(loop_time(log), Some((2.17376, 1, 1000, 414)));
        // LIGGGHTS adds ", finish time …".
        let log = "Loop time of 14.6 on 1 procs for 100000 steps with 400 atoms, finish time Thu\n";
        assert_eq!(loop_time(log), Some((14.6, 1, 100000, 400)));
    }

    #[test]
    fn the_cpu_use_line_of_the_last_loop() {
        // As LAMMPS 2023 writes it (two runs: the second's line counts).
        let log = "Loop time of 1 on 1 procs for 10 steps with 2 atoms\n\n99.1% CPU use with 1 MPI tasks x 1 OpenMP threads\n\
                   Loop time of 0.012411 on 1 procs for 3000 steps with 2 atoms\n\n35.5% CPU use with 1 MPI tasks x 1 OpenMP threads\n";
        assert_eq!(cpu_use_percent(log), Some(35.5));
        // LIGGGHTS: none.
        let log = "Loop time of 14.6 on 1 procs for 100000 steps with 400 atoms, finish time Thu\n\n\nPair  time (%) = 56.8 (46.4)\n";
        assert_eq!(cpu_use_percent(log), None);
    }
}
