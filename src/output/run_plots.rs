//! `run --plot`: the overlap h(t) and force F(h) of every contact and the
//! velocity v(t) of the whole run, from the recorded history.
//!
//! The history is decimated evenly over the whole run, which in fixed
//! stepping can leave a microsecond contact between two kept rows; the
//! contacts are therefore recorded apart, every step in contact (evenly
//! thinned beyond [`MAX_CONTACT_SAMPLES`] per contact).

use super::files::AtomicDir;
use super::history::HistoryRecorder;
use super::table::si_prefix;
use crate::plot::{Figure, Mark, Series, Shape, BLACK};
use anyhow::Result;
use dembound_core::bounce::{ContactRecord, Observer, Sample};

/// About this many samples are kept per contact at most.
pub const MAX_CONTACT_SAMPLES: usize = 4000;

/// The samples in contact (and the onset and rebound events, at zero gap),
/// evenly thinned to at most [`MAX_CONTACT_SAMPLES`] per expected contact.
/// They are split into contacts afterwards by the contacts' time windows.
#[derive(Debug, Clone)]
pub struct ContactTrace {
    samples: Vec<Sample>,
    max: usize,
    stride: u64,
    seen: u64,
}

impl ContactTrace {
    pub fn new(contacts: u32) -> Self {
        ContactTrace {
            samples: Vec::new(),
            max: MAX_CONTACT_SAMPLES * (contacts.max(1) as usize),
            stride: 1,
            seen: 0,
        }
    }

    /// The samples of each contact, by the contacts' [t_contact, t_rebound],
    /// in time order (an event located inside a step is reported after the
    /// step's end).
    pub fn split(&self, contacts: &[ContactRecord]) -> Vec<Vec<Sample>> {
        contacts
            .iter()
            .map(|c| {
                let slack = 1e-12 * c.t_rebound.abs();
                let mut v: Vec<Sample> = self
                    .samples
                    .iter()
                    .filter(|s| s.t >= c.t_contact - slack && s.t <= c.t_rebound + slack)
                    .copied()
                    .collect();
                v.sort_by(|a, b| a.t.total_cmp(&b.t));
                v
            })
            .collect()
    }
}

impl Observer for ContactTrace {
    fn sample(&mut self, s: &Sample) {
        if !(s.in_contact || s.x == 0.0) {
            return;
        }
        if self.seen.is_multiple_of(self.stride) {
            self.samples.push(*s);
            if self.samples.len() > self.max {
                let mut i = 0;
                self.samples.retain(|_| {
                    i += 1;
                    i % 2 == 1
                });
                self.stride *= 2;
            }
        }
        self.seen += 1;
    }
}

/// What `run` records: the history for `history.csv` and, with `--plot`,
/// every contact for the figures.
pub struct RunTrace {
    pub history: HistoryRecorder,
    pub contacts: Option<ContactTrace>,
}

impl RunTrace {
    /// With `plot`, the contacts too (`contacts` expected).
    pub fn new(history: HistoryRecorder, plot: bool, contacts: u32) -> Self {
        RunTrace {
            history,
            contacts: plot.then(|| ContactTrace::new(contacts)),
        }
    }
}

impl Observer for RunTrace {
    fn sample(&mut self, s: &Sample) {
        self.history.sample(s);
        if let Some(c) = &mut self.contacts {
            c.sample(s);
        }
    }

    fn flight_samples(&self) -> usize {
        self.history.flight_samples()
    }
}

/// Contacts with a legend entry each; the others are drawn unlabelled.
const LABELLED_CONTACTS: usize = 8;

/// Palette index of contact `k` (black is kept for the legend's notes).
fn contact_color(k: usize) -> usize {
    let i = k % 9;
    if i >= BLACK {
        i + 1
    } else {
        i
    }
}

fn contact_label(k: usize, n: usize) -> String {
    if k < LABELLED_CONTACTS {
        format!("contact {}", k + 1)
    } else if k == LABELLED_CONTACTS {
        format!("contacts {}–{n}", k + 1)
    } else {
        String::new()
    }
}

/// The three figures: `overlap_vs_time` (h against the time since each
/// contact's onset), `force_vs_overlap` (F against h, each contact) and
/// `velocity_vs_time` (v over the whole run, the contacts marked).
pub fn run_figures(
    history: &HistoryRecorder,
    trace: &ContactTrace,
    records: &[ContactRecord],
    law: &str,
) -> Vec<(&'static str, Figure)> {
    let contacts = &trace.split(records);
    let n = contacts.len();
    let all = || contacts.iter().flatten();
    let tau = si_prefix(records.iter().map(|c| c.t_rebound - c.t_contact));
    let h = si_prefix(all().map(|s| s.overlap));
    let f = si_prefix(all().map(|s| s.force));
    let t = si_prefix(history.rows().iter().map(|s| s.t));

    // point(sample, onset time) → (x, y)
    let per_contact = |point: &dyn Fn(&Sample, f64) -> (f64, f64)| -> Vec<Series> {
        contacts
            .iter()
            .zip(records)
            .enumerate()
            .filter_map(|(k, (c, record))| {
                let pts: Vec<(f64, f64)> = c.iter().map(|s| point(s, record.t_contact)).collect();
                if pts.is_empty() {
                    return None;
                }
                // Elastic contacts repeat each other exactly: every other
                // one dashed, so that the one below still shows.
                let mark = if k % 2 == 0 { Mark::Line } else { Mark::Dashed };
                Some(Series::new(
                    contact_label(k, n),
                    pts,
                    mark,
                    contact_color(k),
                ))
            })
            .collect()
    };

    let overlap = Figure {
        title: format!("Overlap during each contact, {law} law"),
        x_label: format!("time since contact onset t − t_c  ({}s)", tau.symbol),
        y_label: format!("overlap h  ({}m)", h.symbol),
        series: per_contact(&|s, onset| ((s.t - onset) / tau.factor, s.overlap / h.factor)),
        legend_outside: true,
        ..Default::default()
    };
    let force = Figure {
        title: format!("Contact force against overlap, {law} law"),
        x_label: format!("overlap h  ({}m)", h.symbol),
        y_label: format!("contact force F  ({}N)", f.symbol),
        series: per_contact(&|s, _| (s.overlap / h.factor, s.force / f.factor)),
        legend_outside: true,
        ..Default::default()
    };
    let mut series = vec![Series::new(
        "velocity v (upward positive)",
        history
            .rows()
            .iter()
            .map(|s| (s.t / t.factor, s.v))
            .collect(),
        Mark::Line,
        0,
    )];
    series.push(Series::new(
        "in contact",
        all().map(|s| (s.t / t.factor, s.v)).collect(),
        Mark::Shape(Shape::Circle),
        1,
    ));
    // The onset of each contact, so that a contact shorter than a pixel is seen.
    series.push(Series::new(
        "contact onset",
        contacts
            .iter()
            .zip(records)
            .filter(|(c, _)| !c.is_empty())
            .map(|(_, r)| (r.t_contact / t.factor, r.impact_velocity))
            .collect(),
        Mark::Shape(Shape::HollowSquare),
        BLACK,
    ));
    let velocity = Figure {
        title: format!("Velocity over the run, {law} law ({n} contacts)"),
        x_label: format!("time t  ({}s)", t.symbol),
        y_label: "velocity v  (m/s)".into(),
        series,
        legend_outside: true,
        ..Default::default()
    };
    vec![
        ("overlap_vs_time", overlap),
        ("force_vs_overlap", force),
        ("velocity_vs_time", velocity),
    ]
}

/// Stages the three figures (SVG and PNG) in `out`.
pub fn write_run_figures(
    out: &mut AtomicDir,
    history: &HistoryRecorder,
    contacts: &ContactTrace,
    records: &[ContactRecord],
    law: &str,
) -> Result<()> {
    for (stem, figure) in run_figures(history, contacts, records, law) {
        figure.write_into(out, stem)?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sample(t: f64, in_contact: bool) -> Sample {
        Sample {
            t,
            x: 0.0,
            v: 0.0,
            a: 0.0,
            overlap: if in_contact { 1e-9 } else { 0.0 },
            force: 0.0,
            in_contact,
        }
    }

    #[test]
    fn contacts_are_split_by_their_windows_and_bounded() {
        let mut trace = ContactTrace::new(2);
        for i in 0..10 {
            trace.sample(&sample(f64::from(i), false));
        }
        for i in 0..3 * MAX_CONTACT_SAMPLES {
            trace.sample(&sample(10.0 + i as f64, true));
        }
        trace.sample(&sample(1e6, false));
        for i in 0..5 {
            trace.sample(&sample(2e6 + f64::from(i), true));
        }
        assert!(trace.samples.len() <= 2 * MAX_CONTACT_SAMPLES);
        let record = |t_contact: f64, t_rebound: f64| ContactRecord {
            t_contact,
            t_max_overlap: t_contact,
            t_rebound,
            t_force_zero: None,
            duration: t_rebound - t_contact,
            max_overlap: 0.0,
            max_force: 0.0,
            max_acceleration: 0.0,
            impact_velocity: 0.0,
            rebound_velocity: 0.0,
            restitution: 1.0,
            energy_dissipated: 0.0,
            apex_height: None,
            steps: 0,
            bodies: None,
        };
        let c = trace.split(&[record(10.0, 1e5), record(2e6, 2e6 + 4.0)]);
        assert_eq!(c.len(), 2);
        assert!(c[0].len() > MAX_CONTACT_SAMPLES / 2, "{}", c[0].len());
        assert_eq!(c[0][0].t, 10.0);
        // Thinned evenly: the short second contact keeps every 2nd or 4th sample.
        assert!(!c[1].is_empty() && c[1].len() <= 5);
    }
}
