//! Refusals before computing (issue 24): the setup checks that catch
//! inputs which would otherwise run and print impossible numbers.
//!
//! - physical ranges of what the spheres and the box carry (radius, speed,
//!   density of a moving sphere, gravity), from [`crate::limits`];
//! - each wall type's placement checks, in registry order
//!   (`walls::registry::check_placements`, each type's in its own file):
//!   a plane whose normal has a component along a periodic axis, a free
//!   sphere behind a plane or overlapping it by more than
//!   [`limits::OVERLAP_REFUSAL`] of its radius (`walls::plane`); a
//!   cylinder not along every periodic axis or capped while the domain is
//!   periodic, an inside tube no wider than the largest free sphere, a
//!   free sphere on the wrong side of it or overlapping it too much
//!   (`walls::cylinder`);
//! - two spheres (one of them free) overlapping by more than
//!   [`limits::OVERLAP_REFUSAL`] of the smaller radius, coincident centres
//!   included (they exert no force on each other: no contact normal).
//!
//! Overlaps above [`limits::OVERLAP_WARNING`] are returned as warnings.
//!
//! The pair search is a cell grid ([`CellGrid`], [`sort_by_cell`]) over the
//! spheres of radius ≤ [`LARGE_FACTOR`] × the smallest free radius, as the
//! engine's neighbour list; larger spheres (big boundary particles) query
//! that grid over their own extent. Linear in the number of spheres.
//!
//! [`check`] runs in `Simulation::prepare` (so under MPI, on every rank, and
//! from Python) and in `io::resolve`, which names each sphere by its source.

use crate::error::SceneError;
use crate::geometry::cells::{sort_by_cell, CellGrid};
use crate::geometry::domain::Domain;
use crate::limits::{self, describe, metres, norm, show, within};
use crate::setup::{SceneSetup, Scheme, TimeStep};
use crate::simulation::LARGE_FACTOR;
use crate::time_step::ClassPair;
use dembound_physics::contact::Dissipation;

/// How a sphere is named in a message, by its input index.
pub type Label<'a> = &'a dyn Fn(usize) -> String;

/// The default [`Label`]: the input index only.
pub fn by_index(k: usize) -> String {
    format!("sphere {k} (input index)")
}

/// The refusal of `key`'s `value`, naming what is `allowed`.
pub(crate) fn invalid(key: &str, value: impl std::fmt::Display, allowed: &str) -> SceneError {
    SceneError::input(format!(
        "invalid value for `{key}`: {value} (allowed: {allowed})"
    ))
}

/// The radius range of a sphere: a free or given sphere's, or a fixed
/// one's, which may be a boundary particle r = R_b/R_ref times larger.
pub fn radius_range(fixed: bool) -> (f64, f64) {
    if fixed {
        (
            limits::RADIUS.0 * limits::RADIUS_RATIO.0,
            limits::RADIUS.1 * limits::RADIUS_RATIO.1,
        )
    } else {
        limits::RADIUS
    }
}

/// Checks `setup` (already checked for finiteness and indices by
/// `Simulation::prepare`); returns the warnings (large initial overlaps)
/// or the first refusal.
pub fn check(setup: &SceneSetup, label: Label<'_>) -> Result<Vec<String>, SceneError> {
    Ok(check_overlaps(setup, label, &|_| true)?.lines(label))
}

/// [`check`], the warnings as tallies, counting only the overlaps that
/// `reports` gives to this process ([`Reports`]).
pub fn check_overlaps<'a>(
    setup: &SceneSetup,
    label: Label<'_>,
    reports: Reports<'a>,
) -> Result<Overlaps<'a>, SceneError> {
    ranges(setup, label)?;
    let mut overlaps = Overlaps::new(reports);
    crate::walls::registry::check_placements(setup, label, &mut overlaps)?;
    pair_overlaps(setup, label, &mut overlaps)?;
    Ok(overlaps)
}

fn ranges(setup: &SceneSetup, label: Label<'_>) -> Result<(), SceneError> {
    let g = norm(setup.gravity);
    if !(g == 0.0 || within(g, limits::GRAVITY)) {
        return Err(invalid(
            "motion.gravity",
            format!("{:?} (|g| = {} m/s²)", setup.gravity, show(g)),
            &format!("|g| = 0 or {}", describe(limits::GRAVITY, "m/s²")),
        ));
    }
    let mut moving_material = vec![false; setup.materials.len()];
    for (k, s) in setup.spheres.iter().enumerate() {
        if !s.position.iter().all(|x| x.is_finite()) {
            return Err(SceneError::input(format!(
                "{}: invalid position {:?} (allowed: three finite numbers, m)",
                label(k),
                s.position
            )));
        }
        let range = radius_range(s.fixed);
        if !within(s.radius, range) {
            return Err(SceneError::input(format!(
                "{}: invalid radius {} m (allowed: {}{}): check the units (SI, m)",
                label(k),
                show(s.radius),
                describe(range, "m"),
                if s.fixed { " for a fixed sphere" } else { "" }
            )));
        }
        if s.fixed {
            continue;
        }
        if let Some(m) = moving_material.get_mut(s.material) {
            *m = true;
        }
        let speed = norm(s.velocity);
        if speed > limits::MAX_SPEED {
            return Err(SceneError::input(format!(
                "{}: invalid velocity {:?} m/s, |v| = {} m/s (allowed: |v| ≤ {} m/s): check \
                 the units (SI, m/s)",
                label(k),
                s.velocity,
                show(speed),
                show(limits::MAX_SPEED)
            )));
        }
    }
    for (k, m) in setup.materials.iter().enumerate() {
        // Only a moving sphere's mass enters the run.
        if moving_material[k] && !within(m.material.density, limits::DENSITY) {
            return Err(invalid(
                &format!("material[{k}].density (\"{}\")", m.name),
                format!("{} kg/m³", show(m.material.density)),
                &describe(limits::DENSITY, "kg/m³"),
            ));
        }
    }
    servos(setup)
}

/// Walton–Braun's unloading line k₂ = k₁/e² resolved by the step: ω₂ Δt
/// ≤ 0.9 (Gear5) or 0.5 (velocity Verlet), ω₂ = √(k₂/m) of the stiffest
/// pair of the scene (every class pair, as the step bound's, at Δt
/// `dt`): the bound `dembound run` applies (`check_unloading` of
/// dembound-core, measurements in its `scenario::limits`), with the same
/// message. Beyond it the rebound is wrong by far more than the step's
/// error elsewhere: measured on `examples/scenes/validation.toml` (Gear5,
/// η = 1/50), e = 1e-6 rebounds with 0.040 and e = 1e-3 with 0.019
/// (session 35). Refused naming `contact.restitution`, with the smallest
/// e this step resolves and the step this e needs.
pub(crate) fn check_unloading(
    setup: &SceneSetup,
    dt: f64,
    pairs: &[ClassPair],
) -> Result<(), SceneError> {
    use dembound_physics::contact::normal::walton_braun::{
        MAX_UNLOADING_STEP_GEAR5, MAX_UNLOADING_STEP_VERLET,
    };
    use dembound_physics::contact::{NormalLaw, NormalPair};
    let NormalLaw::WaltonBraun { restitution: e } = setup.contact.normal else {
        return Ok(());
    };
    // The largest ω₂ of the scene's pairs.
    let Some((omega2, pair)) = pairs
        .iter()
        .filter_map(|p| match p.law.normal() {
            NormalPair::WaltonBraun(wb) => Some(((wb.unloading / p.law.mass()).sqrt(), p)),
            _ => None,
        })
        .filter(|(w, _)| w.is_finite())
        .max_by(|a, b| a.0.total_cmp(&b.0))
    else {
        return Ok(());
    };
    let limit = match setup.integration.scheme {
        Scheme::Gear5 => MAX_UNLOADING_STEP_GEAR5,
        Scheme::Verlet => MAX_UNLOADING_STEP_VERLET,
    };
    let w = omega2 * dt;
    if w <= limit {
        return Ok(());
    }
    let dt_max = limit / omega2;
    let (e_min, step, smaller) = match setup.integration.time_step {
        // ω₂ = ω₁/e: a fixed Δt resolves e ≥ e w/limit.
        TimeStep::Fixed(dt) => (
            e * w / limit,
            format!("integration.dt = {} s", show(dt)),
            format!("; or keep e with integration.dt ≤ {dt_max:.4e} s"),
        ),
        // Δt = η T_c with T_c ∝ (1 + e) (π/2 (1/ω₁ + 1/ω₂)): ω₂Δt =
        // K (1 + e)/e, K = w e/(1 + e); ≤ limit for e ≥ K/(limit − K).
        TimeStep::Eta { eta, .. } => {
            let k = w * e / (1.0 + e);
            (
                if k < limit { k / (limit - k) } else { f64::INFINITY },
                format!("integration.eta = {}", show(eta)),
                format!(
                    "; or keep e with a smaller step, integration.eta ≤ {:.3e} (Δt ≤ {dt_max:.4e} s)",
                    eta * dt_max / dt
                ),
            )
        }
    };
    let range = if e_min <= 1.0 {
        format!("{e_min:.3e} to 1 with {step}")
    } else {
        format!("none with {step}")
    };
    Err(SceneError::invalid(
        "contact.restitution",
        show(e),
        format!(
            "{range}: Walton–Braun's unloading line k₂ = k₁/e² oscillates at ω₂ = {omega2:.4e} \
             rad/s ({}), and ω₂Δt = {w:.3e} above {limit} under {} leaves it unresolved (the \
             rebound would be wrong, with energy created){smaller}",
            pair.describe(setup),
            match setup.integration.scheme {
                Scheme::Gear5 => "gear5",
                Scheme::Verlet => "verlet",
            }
        ),
    ))
}

/// Gear5's stability on a damped contact: the closed-form bound
/// (ωΔt/W)² + βΔt/B ≤ 1 (W = 0.840, B = 0.163;
/// [`dembound_physics::integrate::gear5_stability`]) with ω and β of each
/// rate-dependent class pair linearised at its largest overlap
/// ([`PairLaw::peak_linearization`]: the undamped law's, an upper bound)
/// at the pair's bounding speed (`time_step::bounding_speed`, as the step
/// bound's T_b; two free spheres at twice it, gravity pressing only a
/// sphere on a fixed body or a wall). Past it a parasitic root of the
/// predictor–corrector leaves the unit circle through −1 and the rebound
/// is wrong by far more than the step's error, without creating energy,
/// so the energy guard does not see it: the validation drop with Tsuji
/// e = 0.01 and attraction at η = 0.05 rebounded with e = 0.081, exit 0
/// (session 36). The bound `dembound run` applies
/// (`bounce::check_damped_step` of dembound-core), for one contact: what
/// several contacts per sphere add is the energy guard's. Refused naming
/// the step key with the largest step accepted, the pair and the damping
/// key.
///
/// [`PairLaw::peak_linearization`]: dembound_physics::contact::PairLaw::peak_linearization
pub(crate) fn check_damped_gear5(
    setup: &SceneSetup,
    dt: f64,
    pairs: &[ClassPair],
) -> Result<(), SceneError> {
    use crate::time_step::Partner;
    use dembound_physics::integrate::gear5::Gear5;
    if setup.integration.scheme != Scheme::Gear5 {
        return Ok(());
    }
    let stability = Gear5::for_force(true).damped_stability();
    let g = norm(setup.gravity);
    // The rate-dependent pair with the smallest stable step.
    let Some((dt_max, peak, pair)) = pairs
        .iter()
        .filter(|p| p.law.depends_on_rate())
        .map(|p| {
            // Two free spheres fall together: no relative gravity.
            let gravity = match p.partner {
                Partner::Sphere(_, _, false) => 0.0,
                _ => g,
            };
            let peak = p.law.peak_linearization(p.speed, gravity);
            (stability.max_step(peak.omega, peak.rate), peak, p)
        })
        .filter(|(d, ..)| !d.is_nan())
        .min_by(|a, b| a.0.total_cmp(&b.0))
    else {
        return Ok(());
    };
    let Err(unstable) = stability.check(peak, dt) else {
        return Ok(());
    };
    let damping = match setup.contact.damping.dissipation() {
        Some(Dissipation::Restitution(e)) => format!("contact.restitution = {}", show(e)),
        Some(Dissipation::Coefficient(c)) => format!("contact.damping_coefficient = {}", show(c)),
        None => "the law's damping".to_string(),
    };
    let why = format!(
        "a damped contact under gear5 ({pair}, at {v:.4} m/s: the fastest approach a body can \
         reach, as the step bound's): {reason} (not caught by the energy balance: no energy is \
         created); or a weaker damping, or integration.scheme = \"verlet\"",
        pair = pair.describe(setup),
        v = pair.speed,
        reason = unstable.describe(&damping),
    );
    Err(match setup.integration.time_step {
        TimeStep::Fixed(given) => SceneError::invalid(
            "integration.dt",
            format!("{} s", show(given)),
            format!("0 < Δt ≤ {dt_max:.4e} s for {why}"),
        ),
        TimeStep::Eta { eta, .. } => SceneError::invalid(
            "integration.eta",
            show(eta),
            format!(
                "η ≤ {:.3e} (Δt ≤ {dt_max:.4e} s) for {why}",
                eta * dt_max / dt
            ),
        ),
    })
}

/// A servo (issue 27, `walls::servo`) on a surface wall without a
/// prescribed motion, with values in range (the scene file's checks, for
/// setups built in code).
fn servos(setup: &SceneSetup) -> Result<(), SceneError> {
    use crate::walls::servo::{validate, ServoConfig};
    for (k, servo) in setup.wall_servos.iter().enumerate() {
        let Some(s) = servo else { continue };
        let key = format!("wall[{k}]");
        let wall = setup.walls.get(k).ok_or_else(|| {
            invalid(
                &format!("{key}.servo"),
                "given for a wall the scene does not have",
                &format!("a wall index below {}", setup.walls.len()),
            )
        })?;
        if wall.is_particles() {
            return Err(invalid(
                &format!("{key}.servo"),
                format!("given for a `{}` wall", wall.key()),
                &format!(
                    "a {} (walls of boundary particles have no servo)",
                    crate::walls::registry::surface_kinds_or()
                ),
            ));
        }
        if setup.wall_motions.get(k).is_some_and(Option::is_some) {
            return Err(invalid(
                &format!("{key}.servo"),
                format!("given with a motion of `{key}`"),
                "a servo or a prescribed motion, not both: the servo sets the wall's velocity",
            ));
        }
        validate(
            &key,
            &ServoConfig {
                force: s.force,
                axis: s.axis,
                max_velocity: s.max_velocity,
                gain: s.gain,
            },
        )?;
    }
    Ok(())
}

/// The axes' names.
pub(crate) const AXES: [&str; 3] = ["x", "y", "z"];

/// A share as a percentage ("5 %", "0.125 %").
pub(crate) fn percent(x: f64) -> String {
    format!("{:.3} %", 100.0 * x).replace(".000 %", " %")
}

/// Whether this process reports the overlaps of the sphere of index `k`:
/// every sphere in one process; under MPI a rank reports its own spheres'
/// wall overlaps and the pairs whose lower index is its own, so that each
/// overlap is counted once over the ranks
/// (`comm::distributed::input`).
pub type Reports<'a> = &'a dyn Fn(usize) -> bool;

/// The largest overlap of a [`OverlapTally`]: its share of the radius,
/// what overlaps (a wall's (wall index, sphere), a pair's (lower, higher
/// sphere index)), and the overlap, m.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Worst {
    pub share: f64,
    pub first: usize,
    pub second: usize,
    pub overlap: f64,
}

/// The overlaps of one kind above [`limits::OVERLAP_WARNING`]: how many,
/// and the largest; of equal shares the smallest (first, second), which
/// is the first the walls' scans (wall by wall, spheres in order) meet, so
/// that the ranks' tallies merge to one process's.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct OverlapTally {
    pub count: u64,
    pub worst: Option<Worst>,
}

impl OverlapTally {
    /// An overlap of `share` (above the warning level or not).
    fn note(&mut self, share: f64, first: usize, second: usize, overlap: f64) {
        if share > limits::OVERLAP_WARNING {
            self.count += 1;
            self.keep(Worst {
                share,
                first,
                second,
                overlap,
            });
        }
    }

    fn keep(&mut self, w: Worst) {
        let larger = self.worst.is_none_or(|x| {
            w.share > x.share || (w.share == x.share && (w.first, w.second) < (x.first, x.second))
        });
        if larger {
            self.worst = Some(w);
        }
    }

    /// Adds another process's tally of other overlaps.
    pub fn merge(&mut self, other: &OverlapTally) {
        self.count += other.count;
        if let Some(w) = other.worst {
            self.keep(w);
        }
    }
}

/// The free spheres that start overlapping the walls of one type by more
/// than [`limits::OVERLAP_WARNING`] of their radius, for one warning line
/// per type ([`Overlaps::walls`]).
pub(crate) struct OverlapWarnings<'a> {
    reports: Reports<'a>,
    tally: OverlapTally,
}

impl OverlapWarnings<'_> {
    /// Sphere `k` overlaps wall `w` by `overlap` (m), `share` of its radius.
    pub(crate) fn note(&mut self, share: f64, k: usize, w: usize, overlap: f64) {
        if share > limits::OVERLAP_WARNING && (self.reports)(k) {
            self.tally.note(share, w, k, overlap);
        }
    }
}

/// The overlap warnings of a check, as tallies: each wall type's (those
/// with placement checks, registry order) and the sphere pairs'.
pub struct Overlaps<'a> {
    reports: Reports<'a>,
    /// (`plane`, `cylinder`, …, its tally).
    pub walls: Vec<(&'static str, OverlapTally)>,
    pub pairs: OverlapTally,
}

impl<'a> Overlaps<'a> {
    pub fn new(reports: Reports<'a>) -> Self {
        Self {
            reports,
            walls: Vec::new(),
            pairs: OverlapTally::default(),
        }
    }

    /// An empty tally for one wall type's spheres.
    pub(crate) fn wall_tally(&self) -> OverlapWarnings<'a> {
        OverlapWarnings {
            reports: self.reports,
            tally: OverlapTally::default(),
        }
    }

    /// The tally of the `kind` walls (`plane`, `cylinder`, …).
    pub(crate) fn push_walls(&mut self, kind: &'static str, t: OverlapWarnings<'_>) {
        self.walls.push((kind, t.tally));
    }

    /// The warning lines: one a wall type with overlaps, then the pairs'.
    pub fn lines(&self, label: Label<'_>) -> Vec<String> {
        let mut out = Vec::new();
        for (kind, t) in &self.walls {
            let Some(w) = t.worst else { continue };
            out.push(format!(
                "{} free sphere(s) start overlapping a {kind} wall by more than {} of their \
                 radius; the largest: {} and `wall[{}].{kind}`, {} ({}). The contact laws are \
                 small-strain theories, and the stored energy is released in the first steps",
                t.count,
                percent(limits::OVERLAP_WARNING),
                label(w.second),
                w.first,
                metres(w.overlap),
                percent(w.share)
            ));
        }
        if let Some(w) = self.pairs.worst {
            out.push(format!(
                "{} sphere pair(s) start overlapping by more than {} of the smaller radius; the \
                 largest: {} and {}, {} ({}). The contact laws are small-strain theories, and the \
                 stored energy is released in the first steps",
                self.pairs.count,
                percent(limits::OVERLAP_WARNING),
                label(w.first),
                label(w.second),
                metres(w.overlap),
                percent(w.share)
            ));
        }
        out
    }
}

/// Sphere-pair overlaps: a cell grid over the spheres of ordinary size,
/// the large ones queried against it and against each other.
fn pair_overlaps(
    setup: &SceneSetup,
    label: Label<'_>,
    overlaps: &mut Overlaps<'_>,
) -> Result<(), SceneError> {
    let s = &setup.spheres;
    let free_min = s
        .iter()
        .filter(|s| !s.fixed)
        .map(|s| s.radius)
        .fold(f64::INFINITY, f64::min);
    if !free_min.is_finite() {
        return Ok(()); // fixed spheres never interact with each other
    }
    let d = &setup.domain;
    let domain = Domain {
        lower: d.lower,
        upper: d.upper,
        periodic: d.periodic,
    };
    let length = domain.length();
    // Each sphere's wrapped position, radius and fixed flag, in input
    // order (read by index below).
    let position: Vec<[f64; 3]> = s.iter().map(|s| domain.wrap(s.position)).collect();
    let radius: Vec<f64> = s.iter().map(|s| s.radius).collect();
    let fixed: Vec<bool> = s.iter().map(|s| s.fixed).collect();
    let large_limit = LARGE_FACTOR * free_min;
    let (small, large): (Vec<usize>, Vec<usize>) =
        (0..radius.len()).partition(|&k| radius[k] <= large_limit);
    let reports = overlaps.reports;
    let mut scan = OverlapTally::default();
    let pair = |i: usize, j: usize, scan: &mut OverlapTally| -> Result<(), SceneError> {
        if fixed[i] && fixed[j] {
            return Ok(());
        }
        let mut dist2 = 0.0;
        for a in 0..3 {
            let mut x = position[j][a] - position[i][a];
            if d.periodic[a] {
                x -= length[a] * (x / length[a]).round();
            }
            dist2 += x * x;
        }
        let reach = radius[i] + radius[j];
        if dist2 >= reach * reach {
            return Ok(());
        }
        let distance = dist2.sqrt();
        let overlap = reach - distance;
        let smaller = radius[i].min(radius[j]);
        let share = overlap / smaller;
        let (i, j) = (i.min(j), i.max(j));
        if share > limits::OVERLAP_REFUSAL {
            return Err(SceneError::input(format!(
                "{} and {} overlap by {}, {} of the smaller radius {} (centres {} apart{}; \
                 allowed: at most {} of the smaller radius, a warning above {}): coincident or \
                 nearly coincident spheres (a duplicated atom, a unit slip?) exert a meaningless \
                 force or none at all; move or remove one of them",
                label(i),
                label(j),
                metres(overlap),
                percent(share),
                metres(smaller),
                metres(distance),
                if distance == 0.0 { ": coincident" } else { "" },
                percent(limits::OVERLAP_REFUSAL),
                percent(limits::OVERLAP_WARNING)
            )));
        }
        if share > limits::OVERLAP_WARNING && reports(i) {
            scan.note(share, i, j, overlap);
        }
        Ok(())
    };

    // The grid over the spheres of ordinary size (periodic axes: the box).
    let max_small = small.iter().map(|&k| radius[k]).fold(0.0, f64::max);
    let mut lower = [f64::INFINITY; 3];
    let mut upper = [f64::NEG_INFINITY; 3];
    for &k in &small {
        for a in 0..3 {
            lower[a] = lower[a].min(position[k][a]);
            upper[a] = upper[a].max(position[k][a]);
        }
    }
    for a in 0..3 {
        // Far strays are clamped into the edge cells (the grid's length
        // must stay finite).
        lower[a] = lower[a].max(-1e300);
        upper[a] = upper[a].min(1e300);
        if d.periodic[a] || small.is_empty() {
            lower[a] = d.lower[a];
            upper[a] = d.upper[a];
        }
    }
    let grid = CellGrid::new(lower, upper, 2.0 * max_small, small.len().max(1));
    let cell: Vec<u32> = small
        .iter()
        .map(|&k| grid.index(grid.coords(position[k])) as u32)
        .collect();
    let (order, start) = sort_by_cell(&cell, grid.count());
    let members = |c: usize| order[start[c] as usize..start[c + 1] as usize].iter();
    // Neighbour cells per axis and coordinate, each distinct cell once.
    let neighbours: [Vec<Vec<usize>>; 3] = std::array::from_fn(|a| {
        let n = grid.dims[a];
        (0..n)
            .map(|at| {
                let mut v = Vec::with_capacity(3);
                for o in [-1i64, 0, 1] {
                    let c = at as i64 + o;
                    let c = if d.periodic[a] {
                        c.rem_euclid(n as i64)
                    } else if c < 0 || c >= n as i64 {
                        continue;
                    } else {
                        c
                    } as usize;
                    if !v.contains(&c) {
                        v.push(c);
                    }
                }
                v
            })
            .collect()
    });
    for z in 0..grid.dims[2] {
        for y in 0..grid.dims[1] {
            for x in 0..grid.dims[0] {
                let here = grid.index([x, y, z]);
                if start[here] == start[here + 1] {
                    continue;
                }
                for &cz in &neighbours[2][z] {
                    for &cy in &neighbours[1][y] {
                        for &cx in &neighbours[0][x] {
                            let there = grid.index([cx, cy, cz]);
                            for &a in members(here) {
                                for &b in members(there) {
                                    if a < b {
                                        pair(small[a as usize], small[b as usize], &mut scan)?;
                                    }
                                }
                            }
                        }
                    }
                }
            }
        }
    }

    // Large spheres: against the grid over their extent, and each other.
    for (n, &i) in large.iter().enumerate() {
        let reach = radius[i] + max_small;
        let mut axes: [Vec<usize>; 3] = Default::default();
        let mut cells = 1usize;
        for a in 0..3 {
            let inv = grid.inverse_size[a];
            let lo = ((position[i][a] - reach - grid.origin[a]) * inv).floor();
            let hi = ((position[i][a] + reach - grid.origin[a]) * inv).floor();
            let dims = grid.dims[a] as f64;
            axes[a] = if d.periodic[a] && hi - lo + 1.0 < dims {
                (lo as i64..=hi as i64)
                    .map(|c| c.rem_euclid(dims as i64) as usize)
                    .collect()
            } else if d.periodic[a] || inv == 0.0 {
                (0..grid.dims[a]).collect()
            } else {
                let lo = lo.max(0.0);
                let hi = hi.min(dims - 1.0);
                if hi < lo {
                    Vec::new()
                } else {
                    (lo as usize..=hi as usize).collect()
                }
            };
            cells = cells.saturating_mul(axes[a].len());
        }
        if cells > small.len() {
            for &j in &small {
                pair(i, j, &mut scan)?;
            }
        } else {
            for &cz in &axes[2] {
                for &cy in &axes[1] {
                    for &cx in &axes[0] {
                        for &b in members(grid.index([cx, cy, cz])) {
                            pair(i, small[b as usize], &mut scan)?;
                        }
                    }
                }
            }
        }
        if !fixed[i] {
            for &j in large.iter().take(n) {
                pair(i, j, &mut scan)?;
            }
        } else {
            for &j in large.iter().take(n).filter(|&&j| !fixed[j]) {
                pair(i, j, &mut scan)?;
            }
        }
    }

    overlaps.pairs = scan;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::setup::{DomainSetup, NamedMaterial, RunLength, SphereInit, TimeStep};
    use dembound_physics::contact::{ContactModel, NormalLaw};
    use dembound_physics::material::Material;

    /// splitmix64 in [0, 1).
    struct Rng(u64);
    impl Rng {
        fn next(&mut self) -> f64 {
            self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
            let mut z = self.0;
            z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
            z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
            ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
        }
    }

    /// Random spheres (radii 0.4–0.6 mm, a few of 2.5 mm and fixed ones
    /// of 4 mm) in a 10 mm box, x and z periodic.
    fn scene(seed: u64, n: usize) -> SceneSetup {
        let mut s = SceneSetup::new(
            DomainSetup {
                lower: [0.0; 3],
                upper: [0.01; 3],
                periodic: [true, false, true],
            },
            ContactModel::elastic(NormalLaw::Hertz),
            TimeStep::Fixed(1e-6),
            RunLength::Steps(1),
        );
        s.materials.push(NamedMaterial {
            name: "g".into(),
            material: Material {
                density: 1000.0,
                youngs_modulus: 1e7,
                poisson_ratio: 0.3,
            },
        });
        let mut rng = Rng(seed);
        for k in 0..n {
            let (radius, fixed) = match k % 50 {
                0 => (2.5e-3, false),
                1 => (4e-3, true),
                _ => (4e-4 + 2e-4 * rng.next(), false),
            };
            s.spheres.push(SphereInit {
                position: [
                    0.01 * rng.next(),
                    0.012 * rng.next() - 0.001,
                    0.01 * rng.next(),
                ],
                velocity: [0.0; 3],
                radius,
                material: 0,
                fixed,
                group: None,
            });
        }
        s
    }

    /// The O(N²) reference: every pair with one free sphere, minimum image
    /// on the periodic axes; (pairs above the warning level, the largest
    /// overlap share).
    fn brute(s: &SceneSetup) -> (usize, f64) {
        let d = &s.domain;
        let b = s.spheres.to_vec();
        let (mut count, mut worst) = (0, 0.0_f64);
        for i in 0..b.len() {
            for j in i + 1..b.len() {
                if b[i].fixed && b[j].fixed {
                    continue;
                }
                let mut dist2 = 0.0_f64;
                for a in 0..3 {
                    let l = d.upper[a] - d.lower[a];
                    let mut x = b[j].position[a] - b[i].position[a];
                    if d.periodic[a] {
                        x -= l * (x / l).round();
                    }
                    dist2 += x * x;
                }
                let share =
                    (b[i].radius + b[j].radius - dist2.sqrt()) / b[i].radius.min(b[j].radius);
                if share > limits::OVERLAP_WARNING {
                    count += 1;
                }
                worst = worst.max(share);
            }
        }
        (count, worst)
    }

    #[test]
    fn the_grid_search_finds_what_the_all_pairs_search_finds() {
        let mut refused = 0;
        let mut warned = 0;
        for seed in 0..80 {
            let s = scene(seed, 4 + seed as usize);
            let (count, worst) = brute(&s);
            let mut o = Overlaps::new(&|_| true);
            let result = pair_overlaps(&s, &by_index, &mut o);
            let w = o.lines(&by_index);
            assert_eq!(
                result.is_err(),
                worst > limits::OVERLAP_REFUSAL,
                "seed {seed}: worst share {worst}: {result:?}"
            );
            if result.is_err() {
                refused += 1;
                continue;
            }
            if count > 0 {
                warned += 1;
                assert_eq!(w.len(), 1);
                assert!(
                    w[0].starts_with(&format!("{count} sphere pair(s)")),
                    "seed {seed}: {count} pairs expected: {}",
                    w[0]
                );
                assert!(w[0].contains(&percent(worst)), "seed {seed}: {}", w[0]);
            } else {
                assert!(w.is_empty());
            }
        }
        // Both branches exercised.
        assert!(
            refused > 0 && warned > 0,
            "{refused} refused, {warned} warned"
        );
    }
}
