//! Reading what a scene deck's run wrote: `particles.dump` (LAMMPS or
//! LIGGGHTS `dump custom`, columns named by its `ITEM: ATOMS` line; each
//! row holds the spheres there at its step, so rows vary in size when an
//! inlet inserts or an outlet deletes), `walls.txt` (LAMMPS `fix
//! ave/time`: step, then Fx Fy Fz of each wall) and the log's thermo rows
//! (the inlets' and outlets' running counts).

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
    /// Radius (m), when the dump has `radius` (LIGGGHTS decks: what an
    /// inserted sphere's size is known by).
    pub radius: Option<f64>,
    /// Atom type (1-based), when the dump has `type`.
    pub kind: Option<u32>,
    /// Mass (kg), when the dump has `mass` (LAMMPS decks with inlets:
    /// their atom types are not material + 1).
    pub mass: Option<f64>,
}

/// One dump row: the step and every sphere there, sorted by id.
#[derive(Debug, Clone, PartialEq)]
pub struct DumpRow {
    pub step: u64,
    pub spheres: Vec<DumpedSphere>,
}

fn bad(what: &str, line: usize, detail: &str) -> Error {
    Error::Trace(format!("{what} line {line}: {detail}"))
}

/// Every row of a `dump custom` file with at least `id x y z vx vy vz`;
/// each row as long as its `ITEM: NUMBER OF ATOMS` says. Two spheres of
/// one id in a row are refused (a dump of two runs, or of several
/// processes' files mixed).
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
        let (radius, kind, mass) = (col("radius"), col("type"), col("mass"));
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
                radius: radius.map(|c| number(j, words[c])).transpose()?,
                kind: kind
                    .map(|c| number(j, words[c]).map(|t| t as u32))
                    .transpose()?,
                mass: mass.map(|c| number(j, words[c])).transpose()?,
            });
        }
        spheres.sort_by_key(|s| s.id);
        if let Some(p) = spheres.windows(2).find(|p| p[0].id == p[1].id) {
            return Err(bad(
                "particles.dump",
                header_at + 1,
                &format!("step {step} lists sphere id {} twice", p[0].id),
            ));
        }
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
    loop_line(line)
}

/// One `Loop time of T on P procs for N steps with M atoms` line.
fn loop_line(line: &str) -> Option<(f64, u64, u64, u64)> {
    let w: Vec<&str> = line.split_whitespace().collect();
    Some((
        w.get(3)?.parse().ok()?,
        w.get(5)?.parse().ok()?,
        w.get(8)?.parse().ok()?,
        w.get(11)?.trim_end_matches(',').parse().ok()?,
    ))
}

/// From a LAMMPS or LIGGGHTS log: (seconds, processes, steps) summed over
/// every `Loop time` line. A deck with outlets runs `run N every 100 …`,
/// one loop (and one line) per 100 steps, and a gate splits the run in
/// two: the last line alone is a small part of the run.
pub fn total_loop_time(log: &str) -> Option<(f64, u64, u64)> {
    let lines: Vec<_> = log
        .lines()
        .filter(|l| l.starts_with("Loop time of"))
        .filter_map(loop_line)
        .collect();
    let procs = lines.iter().map(|l| l.1).max()?;
    Some((
        lines.iter().map(|l| l.0).sum(),
        procs,
        lines.iter().map(|l| l.2).sum(),
    ))
}

/// One thermo row: column name → value.
pub type ThermoRow = BTreeMap<String, f64>;

/// The thermo rows of a LAMMPS or LIGGGHTS log: step → its rows in the
/// order printed (column name → value, the names as the header line
/// `Step …` above prints them). A step is printed twice at the end of one
/// `run … every` loop and at the start of the next, after the loop's
/// commands (an outlet's deletion) ran: the first row is written with the
/// dump at that step, the last is the state the next steps start from.
/// Today's decks count in the first row the spheres the commands are
/// about to delete (outlets.rs), so both rows agree on the outlets'
/// columns; a log of an older deck has the count before the deletion in
/// the first.
pub fn thermo_rows(log: &str) -> BTreeMap<u64, Vec<ThermoRow>> {
    let mut rows = BTreeMap::new();
    let mut header: Vec<&str> = Vec::new();
    for line in log.lines() {
        let words: Vec<&str> = line.split_whitespace().collect();
        if words.first() == Some(&"Step") {
            header = words;
            continue;
        }
        if header.is_empty() || words.len() != header.len() {
            continue;
        }
        let Ok(values) = words
            .iter()
            .map(|w| w.parse::<f64>())
            .collect::<std::result::Result<Vec<f64>, _>>()
        else {
            continue;
        };
        let Some(&step) = values.first().filter(|s| **s >= 0.0) else {
            continue;
        };
        let row = header
            .iter()
            .zip(&values)
            .map(|(h, v)| (h.to_string(), *v))
            .collect();
        rows.entry(step as u64).or_insert_with(Vec::new).push(row);
    }
    rows
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

    /// Rows of varying size, as an inlet and an outlet leave them: ids 1
    /// and 2; then 3 and 4 inserted (their radius and type read); then 1
    /// deleted. Hand-written, so every value is known.
    #[test]
    fn rows_of_varying_size_read_by_id() {
        let head = |step: u64, n: usize| {
            format!(
                "ITEM: TIMESTEP\n{step}\nITEM: NUMBER OF ATOMS\n{n}\nITEM: BOX BOUNDS mm mm mm\n0 1\n0 1\n0 1\n\
                 ITEM: ATOMS id type radius x y z vx vy vz\n"
            )
        };
        let text = format!(
            "{}1 1 0.001 0 0 0.1 0 0 0\n2 1 0.001 0 0 0.2 0 0 0\n\
             {}4 2 0.0015 0.4 0 0.5 0 0 -1\n2 1 0.001 0 0 0.19 0 0 -0.1\n3 1 0.0012 0.3 0 0.5 0 0 -1\n1 1 0.001 0 0 0.09 0 0 -0.1\n\
             {}3 1 0.0012 0.3 0 0.45 0 0 -1.1\n2 1 0.001 0 0 0.18 0 0 -0.2\n4 2 0.0015 0.4 0 0.45 0 0 -1.1\n",
            head(0, 2),
            head(500, 4),
            head(1000, 3)
        );
        let rows = parse_dump(&text).expect("reads");
        let ids = |k: usize| rows[k].spheres.iter().map(|s| s.id).collect::<Vec<_>>();
        assert_eq!(
            rows.iter().map(|r| r.step).collect::<Vec<_>>(),
            [0, 500, 1000]
        );
        assert_eq!(
            (ids(0), ids(1), ids(2)),
            (vec![1, 2], vec![1, 2, 3, 4], vec![2, 3, 4])
        );
        let s4 = rows[1].spheres[3];
        assert_eq!((s4.radius, s4.kind), (Some(0.0015), Some(2)));
        assert_eq!(
            (s4.position, s4.velocity),
            ([0.4, 0.0, 0.5], [0.0, 0.0, -1.0])
        );
        assert_eq!(rows[2].spheres[1].radius, Some(0.0012));
        // A row shorter than its count, and an id twice, are refused.
        let short = format!("{}1 1 0.001 0 0 0.1 0 0 0\n", head(0, 2));
        assert!(parse_dump(&short).is_err());
        let twice = format!(
            "{}1 1 0.001 0 0 0.1 0 0 0\n1 1 0.001 0 0 0.2 0 0 0\n",
            head(0, 2)
        );
        let e = parse_dump(&twice).expect_err("an id twice").to_string();
        assert!(e.contains("sphere id 1 twice"), "{e}");
        // Without radius and type columns (LAMMPS decks): None.
        let lammps = "ITEM: TIMESTEP\n0\nITEM: NUMBER OF ATOMS\n1\nITEM: BOX BOUNDS mm mm mm\n0 1\n0 1\n0 1\n\
                      ITEM: ATOMS id x y z vx vy vz omegax omegay omegaz\n7 1 2 3 4 5 6 7 8 9\n";
        let s = parse_dump(lammps).expect("reads").remove(0).spheres[0];
        assert_eq!(
            (s.id, s.radius, s.kind, s.spin),
            (7, None, None, Some([7.0, 8.0, 9.0]))
        );
    }

    /// A deck with an outlet prints a thermo row at the end of each `run
    /// … every 100` loop and again at the start of the next, after the
    /// deletion: both rows of the step are kept, in order; words and
    /// other lines are skipped.
    #[test]
    fn thermo_rows_keep_both_rows_of_a_step() {
        let log = "thermo_style custom step time ke v_out0_n v_out0_m\n\
                   Step Time KinEng out0_n out0_m ins0[1] \n\
                   0 0 0 0 0 0 \n100 0.0004 1e-6 0 0 5 \n\
                   Loop time of 0.05 on 1 procs for 100 steps with 5 atoms, finish time x\n\
                   Deleted 2 atoms, new total = 3\n\
                   Step Time KinEng out0_n out0_m ins0[1] \n\
                   100 0.0004 5e-7 2 2.1e-5 5 \n200 0.0008 6e-7 2 2.1e-5 10 \n\
                   Loop time of 0.07 on 1 procs for 100 steps with 8 atoms, finish time y\n";
        let rows = thermo_rows(log);
        assert_eq!(rows.keys().copied().collect::<Vec<_>>(), [0, 100, 200]);
        assert_eq!(rows[&100].len(), 2);
        assert_eq!(
            (rows[&100][0]["out0_n"], rows[&100][1]["out0_n"]),
            (0.0, 2.0)
        );
        assert_eq!(rows[&100][1]["KinEng"], 5e-7);
        assert_eq!(rows[&200][0]["ins0[1]"], 10.0);
        // Both loops: 0.12 s for 200 steps (the last line alone: 100).
        let (s, p, n) = total_loop_time(log).expect("two lines");
        assert!((s - 0.12).abs() < 1e-15);
        assert_eq!((p, n), (1, 200));
        assert_eq!(loop_time(log).map(|l| l.2), Some(100));
        assert!(total_loop_time("no loop").is_none());
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
