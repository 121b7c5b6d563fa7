//! `dembound run`: one scenario, every contact reported.

use super::{warnings, CliError, CliResult};
use crate::output::files::AtomicDir;
use crate::output::format::{duration, sig};
use crate::output::history::HistoryRecorder;
use crate::output::observer::Tee;
use crate::output::progress::{self, Progress};
use crate::output::report::{self, RelativeErrors, RunReport};
use crate::output::run_plots::{write_run_figures, RunTrace};
use crate::scenario_file::ScenarioArgs;
use anyhow::anyhow;
use clap::Args;
use dembound_core::bounce::{
    resolve, simulate_resolved, ContactRecord, Problem, RunOutcome, Scenario, Stepping,
};
use dembound_core::Error;
use std::io::Write;
use std::path::PathBuf;

/// Runs expected to take more steps than this need `--force`.
pub const MAX_STEPS_WITHOUT_FORCE: f64 = 1e9;

/// The cost per step assumed when estimating run times, s.
pub const ASSUMED_SECONDS_PER_STEP: f64 = 10e-9;

#[derive(Debug, Args)]
pub struct RunArgs {
    #[command(flatten)]
    pub scenario: ScenarioArgs,

    /// Write scenario.toml (resolved, re-runnable), contacts.csv and
    /// history.csv into DIR (created if missing; checked before the run;
    /// all three files or none)
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,

    /// Print one JSON object (scenario, contacts, steps, dt,
    /// contact_time_estimate; SI) to stdout instead of the table
    #[arg(long)]
    pub json: bool,

    /// Also write figures into DIR (needs --out): overlap_vs_time (h
    /// against the time since each contact's onset), force_vs_overlap
    /// (F against h) and velocity_vs_time (v over the run), SVG and PNG
    #[arg(long)]
    pub plot: bool,

    /// At most N rows in history.csv (the trajectory is evenly decimated)
    #[arg(long, value_name = "N", default_value_t = 10_000,
          value_parser = clap::value_parser!(u64).range(1..))]
    pub history_points: u64,

    /// Also report every quantity's relative error against the exact
    /// reference (value/exact − 1): a second table, or `relative_errors` in
    /// the JSON
    #[arg(long)]
    pub compare_exact: bool,

    /// No progress bar
    #[arg(long, short)]
    pub quiet: bool,

    /// Run even when more than 1e9 integration steps are expected
    #[arg(long)]
    pub force: bool,
}

pub fn run(args: &RunArgs) -> CliResult {
    if args.plot && args.out.is_none() {
        return Err(CliError::input(anyhow!(
            "--plot writes figures into the output directory: give --out DIR"
        )));
    }
    let scenario = args.scenario.load().map_err(CliError::input)?.resolved();
    // Resolved once: validated, calibrated, Δt chosen (pilot runs with a
    // tolerance); the run and the reference reuse it.
    let resolved = resolve(&scenario).map_err(simulation_error)?;
    let problem = resolved.problem;
    let coefficient = resolved.damping_coefficient;
    // The reference, computed once when the rebound check or
    // --compare-exact needs it.
    let reference = (args.compare_exact || rebounds_checked(&scenario))
        .then(|| dembound_core::exact::scenario_contacts_with(&scenario, coefficient));
    check_rebounds(&scenario, reference.as_ref())?;
    warnings::print(&warnings::inputs(&scenario));
    guard_step_count(&scenario, &problem, args.force)?;
    let out = match &args.out {
        Some(dir) => Some(super::output_dir(dir, "run")?),
        None => None,
    };
    // Before the run, so that a scenario without a reference fails at once.
    let exact = match reference.filter(|_| args.compare_exact) {
        Some(reference) => Some(reference.map_err(super::exact::exact_error)?),
        None => None,
    };

    let mut history = out.as_ref().map(|_| {
        let rows = usize::try_from(args.history_points).unwrap_or(usize::MAX);
        RunTrace::new(
            HistoryRecorder::new(
                rows,
                HistoryRecorder::flight_samples_for(rows, scenario.motion.contacts),
            ),
            args.plot,
            scenario.motion.contacts,
        )
    });
    let mut bar = progress::wanted(problem.expected_steps(), args.quiet).then(Progress::new);
    let outcome = match (&mut history, &mut bar) {
        (None, None) => simulate_resolved(&scenario, &resolved, &mut ()),
        (Some(h), None) => simulate_resolved(&scenario, &resolved, h),
        (None, Some(p)) => simulate_resolved(&scenario, &resolved, p),
        (Some(h), Some(p)) => simulate_resolved(&scenario, &resolved, &mut Tee(h, p)),
    };
    if let Some(bar) = bar {
        bar.finish();
    }
    let outcome = outcome.map_err(|e| run_error(&scenario, e))?;
    // The header after the run: a run refused for a contact that did not
    // end (`run_error`) prints nothing on stdout.
    let mut stdout = std::io::stdout().lock();
    if !args.json {
        write!(stdout, "{}", report::header(&scenario, &problem)).map_err(CliError::failed)?;
    }
    warnings::print(&warnings::contacts(&scenario, &outcome.contacts));

    let written = match (out, &history) {
        (Some(out), Some(history)) => Some(write_outputs(out, &scenario, &outcome, history)?),
        _ => None,
    };

    let errors = exact
        .as_ref()
        .map(|exact| RelativeErrors::all(&outcome.contacts, exact));
    if args.json {
        let mut report = RunReport::new(&scenario, &outcome);
        report.relative_errors = errors;
        write!(stdout, "{}", super::json_text(&report)?).map_err(CliError::failed)?;
    } else {
        let pilots = match outcome.pilot_steps {
            Some(pilot) => format!(
                ", and {pilot} in the pilot runs that chose Δt ({} in all)",
                outcome.total_steps()
            ),
            None => String::new(),
        };
        writeln!(
            stdout,
            "{}\n{} steps taken{pilots}",
            report::contacts_table(&outcome.contacts),
            outcome.steps
        )
        .map_err(CliError::failed)?;
        if let Some(errors) = &errors {
            writeln!(
                stdout,
                "\nrelative errors against the exact reference (value/exact − 1; \
                 times are absolute, from t = 0):\n{}",
                report::relative_errors_table(errors)
            )
            .map_err(CliError::failed)?;
        }
        if let Some(written) = written {
            for path in written {
                writeln!(stdout, "wrote {}", path.display()).map_err(CliError::failed)?;
            }
        }
    }
    stdout.flush().map_err(CliError::failed)?;
    Ok(())
}

/// Input errors exit 2; a run that fails exits 1.
fn simulation_error(e: Error) -> CliError {
    match e {
        e @ Error::Input { .. } => CliError::input(e),
        e => CliError::failed(anyhow!("the run failed: {e}")),
    }
}

/// [`simulation_error`], with a contact of a dissipative run that did not
/// end refused (exit 2) as [`check_rebounds`] refuses it before the run:
/// a later contact naming `motion.contacts`, the first naming the key that
/// sets the dissipation: gravity
/// holds the particle once the damping has slowed it, or an overdamped
/// contact's slow release (time ~ c/k, steps ~ c²) outlasts the step
/// budget. The law's reference cannot say so before the run when the
/// contact is overdamped ([`check_rebounds`]: it has no closed form for ξ ≥ 1);
/// nothing has been written then (`--out` is written after the run).
/// Session 34 saw exit 1 at `contact.damping_coefficient = 100` (ξ = 26).
fn run_error(s: &Scenario, e: Error) -> CliError {
    use dembound_core::contact::DampingKind;
    let Error::NoRebound { contact, steps } = e else {
        return simulation_error(e);
    };
    if !dembound_core::exact::dissipative::is_dissipative(s) {
        return simulation_error(e);
    }
    if contact > 1 {
        return CliError::input(anyhow!(
            "invalid value for `motion.contacts`: {} (allowed: 1 to {} for this scenario: \
             contact {contact} did not end after {steps} steps, gravity holds the particle on \
             the boundary once the damping has slowed it)",
            s.motion.contacts,
            contact - 1
        ));
    }
    let show = dembound_core::scenario::limits::show;
    let (field, value, less) = match (s.contact.restitution, s.contact.damping_coefficient) {
        (None, Some(c)) => {
            let unit = match s.contact.damping {
                DampingKind::Tsuji => "N s/m^(5/4)",
                DampingKind::Viscoelastic => "s",
                _ => "N s/m",
            };
            (
                "contact.damping_coefficient",
                format!("{} {unit}", show(c)),
                "a smaller contact.damping_coefficient",
            )
        }
        (e, _) => (
            "contact.restitution",
            e.map_or_else(|| "missing".to_string(), show),
            "a larger contact.restitution",
        ),
    };
    CliError::input(anyhow!(
        "invalid value for `{field}`: {value} (allowed: a dissipation that lets the particle \
         leave the boundary; with this one contact {contact} did not end after {steps} steps: \
         gravity holds the particle on the boundary once the damping has slowed it, or an \
         overdamped contact releases it (in a time ~ c/k) more slowly than the step budget \
         allows; {less}, a larger motion.gap or a faster motion.velocity lets it rebound)"
    ))
}

/// The most contacts whose rebound is checked before a dissipative run.
const MAX_CHECKED_CONTACTS: u32 = 1000;

/// Refuses (exit 2) a dissipative run with a contact that would not end
/// (gravity holds the particle on the boundary after its force returns to
/// zero), found by the law's reference before the run: the run would spend
/// its whole step budget on it. Skipped for more than
/// [`MAX_CHECKED_CONTACTS`] contacts (the run then reports it, exit 1).
fn check_rebounds(
    s: &Scenario,
    reference: Option<&Result<Vec<ContactRecord>, Error>>,
) -> CliResult {
    if !rebounds_checked(s) {
        return Ok(());
    }
    match reference {
        Some(Err(Error::NoExactRebound { contact })) if *contact > 1 => {
            Err(CliError::input(anyhow!(
                "invalid value for `motion.contacts`: {} (allowed: 1 to {} for this scenario: \
                 contact {contact} would not end, gravity holds the particle on the boundary \
                 once the damping has slowed it)",
                s.motion.contacts,
                contact - 1
            )))
        }
        Some(Err(Error::NoExactRebound { .. })) => Err(CliError::input(anyhow!(
            "invalid value for `motion.gap`: {} m (the first contact would not end: gravity \
             holds the particle on the boundary; a larger motion.gap, a faster motion.velocity \
             or less damping (contact.restitution) lets it rebound)",
            s.motion.gap
        ))),
        // Other failures of the reference are reported by --compare-exact
        // or not at all: the run itself does not need it.
        _ => Ok(()),
    }
}

/// Whether [`check_rebounds`] looks at the reference: a dissipative
/// scenario of at most [`MAX_CHECKED_CONTACTS`] contacts.
fn rebounds_checked(s: &Scenario) -> bool {
    dembound_core::exact::dissipative::is_dissipative(s)
        && s.motion.contacts <= MAX_CHECKED_CONTACTS
}

/// Refuses runs of more than [`MAX_STEPS_WITHOUT_FORCE`] steps without `--force`.
fn guard_step_count(s: &Scenario, problem: &Problem, force: bool) -> CliResult {
    let steps = problem.expected_steps();
    if force || steps <= MAX_STEPS_WITHOUT_FORCE {
        return Ok(());
    }
    let how = match s.integration.stepping {
        Stepping::Fixed => format!(
            "fixed stepping with Δt = {} s over about {} s of simulated time",
            sig(problem.dt, 3),
            sig(problem.expected_end_time(), 3)
        ),
        Stepping::Event => format!(
            "event stepping with Δt = {} s over {} contacts",
            sig(problem.dt, 3),
            problem.contacts
        ),
    };
    Err(CliError::input(anyhow!(
        "this run would take about {} integration steps ({how}), roughly {} \
         assuming ~10 ns per step; pass --force to run it anyway, or use a larger \
         integration.dt / integration.eta or integration.stepping = \"event\"",
        sig(steps, 3),
        duration(steps * ASSUMED_SECONDS_PER_STEP)
    )))
}

/// Writes scenario.toml, contacts.csv, history.csv (and the figures with
/// `--plot`) into `dir`, all or none.
fn write_outputs(
    mut out: AtomicDir,
    scenario: &Scenario,
    outcome: &RunOutcome,
    trace: &RunTrace,
) -> CliResult<Vec<PathBuf>> {
    let history = &trace.history;
    let toml = report::scenario_toml(scenario).map_err(CliError::failed)?;
    out.write("scenario.toml", |w| Ok(w.write_all(toml.as_bytes())?))
        .map_err(CliError::failed)?;
    out.write("contacts.csv", |w| {
        report::write_contacts_csv(&outcome.contacts, w)
    })
    .map_err(CliError::failed)?;
    out.write("history.csv", |w| history.write_csv(w))
        .map_err(CliError::failed)?;
    if let Some(contacts) = &trace.contacts {
        write_run_figures(
            &mut out,
            history,
            contacts,
            &outcome.contacts,
            &scenario.contact.law.name(),
        )
        .map_err(CliError::failed)?;
    }
    out.commit().map_err(CliError::failed)
}
