//! The mass flow through the outlets (`[[outlet]]`, issue 28): per outlet,
//! the rate between consecutive series rows (series.csv) and the steady
//! mean rate with its standard error over the second half of the run
//! (`--json`), the quantity a hopper or Beverloo study measures.

use serde::Serialize;

use crate::simulation::Observation;

/// The series.csv columns of outlet `k`: spheres removed so far, their
/// mass, the mass flow rate since the previous row.
pub fn outlet_columns(k: usize) -> [String; 3] {
    [
        format!("outlet{k}_removed"),
        format!("outlet{k}_mass_kg"),
        format!("outlet{k}_rate_kg_per_s"),
    ]
}

/// The mass flow rate of outlet `k` at row `i` of `rows` (time order),
/// kg/s: [`rate_since`] the row before.
pub fn rate_at(rows: &[Observation], i: usize, k: usize) -> f64 {
    rate_since(&rows[i], i.checked_sub(1).map(|p| &rows[p]), k)
}

/// The mass flow rate of outlet `k` at row `o`, kg/s: the mass removed
/// since the row `previous` over the time between them (no previous row:
/// since t = 0 with nothing removed; 0 when no time has passed).
pub fn rate_since(o: &Observation, previous: Option<&Observation>, k: usize) -> f64 {
    let mass = |o: &Observation| o.outlets.get(k).map_or(0.0, |r| r.mass);
    let (m0, t0) = previous.map_or((0.0, 0.0), |p| (mass(p), p.time));
    let dt = o.time - t0;
    if dt > 0.0 {
        (mass(o) - m0) / dt
    } else {
        0.0
    }
}

/// What one outlet removed over the run (`--json` `outlets`).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct OutletReport {
    /// Spheres removed.
    pub count: u64,
    /// Their mass, kg.
    pub mass: f64,
    /// The mean mass flow rate over the rows of the second half of the run
    /// (t ≥ T/2), kg/s; `None` with fewer than two such intervals.
    pub steady_rate: Option<f64>,
    /// Its standard error, kg/s: the sample standard deviation of the
    /// interval rates over √n (n intervals; the rates taken independent,
    /// which understates it when they are correlated over an interval).
    pub steady_rate_error: Option<f64>,
}

/// The report of each outlet (file order) from the series rows of a run
/// (time order; the last is the run's end).
pub fn outlet_reports(rows: &[Observation]) -> Vec<OutletReport> {
    let Some(last) = rows.last() else {
        return Vec::new();
    };
    let half = 0.5 * last.time;
    // The intervals that lie in the second half: rows i with rows[i - 1]
    // at t ≥ T/2.
    let second: Vec<usize> = (1..rows.len())
        .filter(|&i| rows[i - 1].time >= half && rows[i].time > rows[i - 1].time)
        .collect();
    last.outlets
        .iter()
        .enumerate()
        .map(|(k, r)| {
            let rates: Vec<f64> = second.iter().map(|&i| rate_at(rows, i, k)).collect();
            let (steady_rate, steady_rate_error) = mean_and_error(&rates);
            OutletReport {
                count: r.count,
                mass: r.mass,
                steady_rate,
                steady_rate_error,
            }
        })
        .collect()
}

/// The mean of `x` and its standard error s/√n, `None` below two values.
fn mean_and_error(x: &[f64]) -> (Option<f64>, Option<f64>) {
    let n = x.len();
    if n < 2 {
        return (None, None);
    }
    let mean = x.iter().sum::<f64>() / n as f64;
    let var = x.iter().map(|v| (v - mean) * (v - mean)).sum::<f64>() / (n - 1) as f64;
    (Some(mean), Some((var / n as f64).sqrt()))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::removal::OutletRemoved;

    fn row(time: f64, mass: f64) -> Observation {
        Observation {
            step: 0,
            time,
            kinetic_energy: 0.0,
            elastic_energy: 0.0,
            potential_energy: 0.0,
            dissipated_energy: 0.0,
            particle_contacts: 0,
            wall_contacts: 0,
            wall_forces: Vec::new(),
            wall_torques: Vec::new(),
            work_by_walls: None,
            removed: None,
            wall_motions: Vec::new(),
            group_motions: Vec::new(),
            outlets: vec![OutletRemoved { count: 0, mass }],
            gate_energy: None,
            inlets: Vec::new(),
            dissipated_by_contacts: None,
            wall_force_means: None,
        }
    }

    #[test]
    fn a_constant_flow_has_its_rate_and_no_error() {
        // 2 kg/s from t = 0: every interval rate is 2, the error 0.
        let rows: Vec<_> = (0..=10)
            .map(|i| row(0.1 * i as f64, 0.2 * i as f64))
            .collect();
        assert!((rate_at(&rows, 3, 0) - 2.0).abs() < 1e-12);
        let r = outlet_reports(&rows);
        assert_eq!(r.len(), 1);
        assert!((r[0].steady_rate.unwrap() - 2.0).abs() < 1e-12);
        assert!(r[0].steady_rate_error.unwrap() < 1e-12);
    }

    #[test]
    fn the_steady_rate_ignores_the_first_half_and_has_the_sample_error() {
        // Nothing for t < 0.5 s, then alternately 1 and 3 kg/s over 0.1 s
        // intervals.
        let mut rows = vec![row(0.0, 0.0)];
        let mut m = 0.0;
        for i in 1..=10 {
            let t = 0.1 * i as f64;
            if t > 0.55 {
                m += if i % 2 == 0 { 0.1 } else { 0.3 };
            }
            rows.push(row(t, m));
        }
        // Second-half intervals end at rows 6..=10: rates 1, 3, 1, 3, 1
        // (row 6 even: 0.1 kg in 0.1 s); mean 1.8, sample variance
        // (3·0.64 + 2·1.44)/4 = 1.2, error √(1.2/5).
        let r = &outlet_reports(&rows)[0];
        assert!((r.steady_rate.unwrap() - 1.8).abs() < 1e-9);
        assert!((r.steady_rate_error.unwrap() - (1.2f64 / 5.0).sqrt()).abs() < 1e-9);
    }
}
