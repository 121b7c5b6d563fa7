//! The trajectory of a run, evenly decimated to at most N rows.

use anyhow::Result;
use dembound_core::bounce::{Observer, Sample};
use std::io::Write;

use super::format::exact;

/// Keeps every k-th sample; when more than `max_rows` are kept, drops every
/// other row and doubles k, so the rows stay evenly spaced in sample count.
#[derive(Debug, Clone)]
pub struct HistoryRecorder {
    max_rows: usize,
    stride: u64,
    seen: u64,
    flight_samples: usize,
    rows: Vec<Sample>,
}

impl HistoryRecorder {
    /// At most `max_rows` rows (≥ 1); `flight_samples` points per free-flight
    /// arc in event stepping.
    pub fn new(max_rows: usize, flight_samples: usize) -> Self {
        HistoryRecorder {
            max_rows: max_rows.max(1),
            stride: 1,
            seen: 0,
            flight_samples,
            rows: Vec::new(),
        }
    }

    /// Points per flight arc for a run of `contacts` contacts: about half the
    /// rows go to the flights (event stepping integrates only the contacts).
    pub fn flight_samples_for(max_rows: usize, contacts: u32) -> usize {
        (max_rows / (2 * (contacts as usize + 1))).clamp(2, 1000)
    }

    pub fn rows(&self) -> &[Sample] {
        &self.rows
    }

    /// Writes `history.csv`.
    pub fn write_csv(&self, w: &mut dyn Write) -> Result<()> {
        let mut csv = csv::Writer::from_writer(w);
        csv.write_record([
            "t_s",
            "x_m",
            "v_m_s",
            "a_m_s2",
            "overlap_m",
            "force_N",
            "in_contact",
        ])?;
        for s in self.rows() {
            csv.write_record([
                exact(s.t),
                exact(s.x),
                exact(s.v),
                exact(s.a),
                exact(s.overlap),
                exact(s.force),
                u8::from(s.in_contact).to_string(),
            ])?;
        }
        csv.flush()?;
        Ok(())
    }
}

impl Observer for HistoryRecorder {
    fn sample(&mut self, sample: &Sample) {
        if self.seen.is_multiple_of(self.stride) {
            self.rows.push(*sample);
            if self.rows.len() > self.max_rows {
                let mut i = 0;
                self.rows.retain(|_| {
                    i += 1;
                    i % 2 == 1
                });
                self.stride *= 2;
            }
        }
        self.seen += 1;
    }

    fn flight_samples(&self) -> usize {
        self.flight_samples
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn at(t: f64) -> Sample {
        Sample {
            t,
            x: 0.0,
            v: 0.0,
            a: 0.0,
            overlap: 0.0,
            force: 0.0,
            in_contact: false,
        }
    }

    #[test]
    fn decimation_is_even_and_bounded() {
        for (n, max) in [(10, 100), (1000, 100), (100_000, 37), (5, 1)] {
            let mut h = HistoryRecorder::new(max, 0);
            for i in 0..n {
                h.sample(&at(i as f64));
            }
            let rows = h.rows();
            assert!(rows.len() <= max && !rows.is_empty(), "{n} {max}");
            assert!(rows.len() > max / 2 || rows.len() == n, "{n} {max}");
            assert_eq!(rows[0].t, 0.0);
            let step = if rows.len() > 1 { rows[1].t } else { 1.0 };
            for (k, r) in rows.iter().enumerate() {
                assert_eq!(r.t, k as f64 * step);
            }
        }
    }
}
