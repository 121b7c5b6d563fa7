//! The inflow and outflow of a scene with inlets or outlets, for `dembound
//! compare DECK`: spheres and mass inserted and discharged so far at each
//! row, and the discharge rate between rows.
//!
//! - The peer's counts are its thermo columns (liggghts_inlets.rs:
//!   `f_insK[1]` spheres and `f_insK[2]` kg inserted by inlet K,
//!   `FixInsert::compute_vector`; lammps_inlets.rs: `v_insK_n`,
//!   `v_insK_m`; outlets.rs: `v_outK_n`, `v_outK_m`
//!   removed by outlet K), printed as `insK[1]` … or `out0_n` … by
//!   LIGGGHTS 3.8 and with their prefixes by LAMMPS. The row of a dump
//!   step: the first printed at that step (written with the dump, before
//!   the outlets' `run … every` commands delete), else the last printed
//!   before it (after them); so the peer's spheres in a dump row are its
//!   scene's plus those inserted less those discharged, as dembound's are.
//! - dembound's are its observation's (`Observation::inlets`,
//!   `Observation::outlets`), summed over inlets and over outlets.
//! - The discharge rate of row k is (M_k − M_{k−1}) / (t_k − t_{k−1}),
//!   M the mass discharged (kg/s): its mean over a window is the mass
//!   discharged in it over its length (the sum telescopes), its standard
//!   error from the batch means of the series (`agreement::window_mean`).

use dembound_export::scene_dump::ThermoRow;
use dembound_scene::Observation;
use std::collections::BTreeMap;

/// What has come in and gone out so far.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Flow {
    pub inserted: f64,
    /// kg.
    pub inserted_mass: f64,
    pub discharged: f64,
    /// kg.
    pub discharged_mass: f64,
}

/// The thermo column `name`, by LIGGGHTS's name (without `v_` or `f_`)
/// or LAMMPS's (with it).
fn column(row: &ThermoRow, prefix: &str, name: &str) -> Option<f64> {
    row.get(name)
        .or_else(|| row.get(&format!("{prefix}{name}")))
        .copied()
}

/// The peer's flow at `step` from its thermo rows, for `inlets` inlets and
/// `outlets` outlets (module doc); None when no row is at or before the
/// step or one of the columns is missing.
pub fn peer_flow(
    thermo: &BTreeMap<u64, Vec<ThermoRow>>,
    step: u64,
    inlets: usize,
    outlets: usize,
) -> Option<Flow> {
    let row = match thermo.get(&step) {
        Some(rows) => rows.first()?,
        None => thermo.range(..step).next_back()?.1.last()?,
    };
    let mut flow = Flow::default();
    for k in 0..inlets {
        // LIGGGHTS's fix vector, else the LAMMPS deck's variables.
        let (n, m) = match column(row, "f_", &format!("ins{k}[1]")) {
            Some(n) => (n, column(row, "f_", &format!("ins{k}[2]"))?),
            None => (
                row.get(&format!("v_ins{k}_n")).copied()?,
                row.get(&format!("v_ins{k}_m")).copied()?,
            ),
        };
        flow.inserted += n;
        flow.inserted_mass += m;
    }
    for k in 0..outlets {
        flow.discharged += column(row, "v_", &format!("out{k}_n"))?;
        flow.discharged_mass += column(row, "v_", &format!("out{k}_m"))?;
    }
    Some(flow)
}

/// dembound's flow in an observation.
pub fn dembound_flow(o: &Observation) -> Flow {
    Flow {
        inserted: o.inlets.iter().map(|i| i.count as f64).sum(),
        inserted_mass: o.inlets.iter().map(|i| i.mass).sum(),
        discharged: o.outlets.iter().map(|o| o.count as f64).sum(),
        discharged_mass: o.outlets.iter().map(|o| o.mass).sum(),
    }
}

/// The rate of the cumulative series `m` at times `t` (s): one value per
/// row from the second, (m_k − m_{k−1}) / (t_k − t_{k−1}), at t_k; rows
/// at the same time are skipped.
pub fn rate(t: &[f64], m: &[f64]) -> (Vec<f64>, Vec<f64>) {
    let mut times = Vec::new();
    let mut rates = Vec::new();
    for k in 1..t.len().min(m.len()) {
        let dt = t[k] - t[k - 1];
        if dt > 0.0 {
            times.push(t[k]);
            rates.push((m[k] - m[k - 1]) / dt);
        }
    }
    (times, rates)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_rows_counts_are_the_last_printed_at_or_before_the_step() {
        let row = |pairs: &[(&str, f64)]| -> ThermoRow {
            pairs.iter().map(|(k, v)| (k.to_string(), *v)).collect()
        };
        let counts = |n: f64, m: f64, i: f64, im: f64| {
            row(&[
                ("out0_n", n),
                ("out0_m", m),
                ("ins0[1]", i),
                ("ins0[2]", im),
            ])
        };
        let mut thermo = BTreeMap::new();
        thermo.insert(0, vec![counts(0.0, 0.0, 0.0, 0.0)]);
        // Step 100: the row written with the dump, then the one after the
        // outlet's deletion. Decks written before the rows counted the spheres
        // about to be deleted had 0 discharged in the first (as here); today's
        // count them in both rows, so reading the first row is right for both.
        thermo.insert(
            100,
            vec![counts(0.0, 0.0, 5.0, 1.25), counts(2.0, 0.5, 5.0, 1.25)],
        );
        let f = peer_flow(&thermo, 100, 1, 1).expect("the rows of step 100");
        assert_eq!((f.inserted, f.discharged), (5.0, 0.0));
        let f = peer_flow(&thermo, 150, 1, 1).expect("after step 100");
        assert_eq!(
            f,
            Flow {
                inserted: 5.0,
                inserted_mass: 1.25,
                discharged: 2.0,
                discharged_mass: 0.5
            }
        );
        assert_eq!(peer_flow(&thermo, 99, 1, 1).map(|f| f.inserted), Some(0.0));
        // The LAMMPS deck's variables (lammps_inlets.rs, outlets.rs).
        let mut lammps = BTreeMap::new();
        lammps.insert(
            500,
            vec![row(&[
                ("v_ins0_n", 7.0),
                ("v_ins0_m", 0.5),
                ("v_out0_n", 1.0),
                ("v_out0_m", 0.25),
            ])],
        );
        assert_eq!(
            peer_flow(&lammps, 500, 1, 1),
            Some(Flow {
                inserted: 7.0,
                inserted_mass: 0.5,
                discharged: 1.0,
                discharged_mass: 0.25
            })
        );
        // A second inlet's column is not there.
        assert!(peer_flow(&thermo, 150, 2, 1).is_none());
        // LAMMPS's names keep their prefixes.
        let mut lammps = BTreeMap::new();
        lammps.insert(7, vec![row(&[("v_out0_n", 3.0), ("v_out0_m", 0.75)])]);
        let f = peer_flow(&lammps, 7, 0, 1).expect("prefixed");
        assert_eq!((f.discharged, f.discharged_mass), (3.0, 0.75));
    }

    #[test]
    fn the_rate_telescopes_to_the_mean() {
        let t = [0.0, 0.1, 0.2, 0.2, 0.4];
        let m = [0.0, 1.0, 1.0, 1.0, 5.0];
        let (times, rates) = rate(&t, &m);
        assert_eq!(times, [0.1, 0.2, 0.4]);
        // 1/0.1, 0/0.1, 4/0.2 (the repeated time skipped).
        assert_eq!(rates.len(), 3);
        assert!((rates[0] - 10.0).abs() < 1e-12 && rates[1] == 0.0);
        assert!((rates[2] - 20.0).abs() < 1e-12);
    }
}
