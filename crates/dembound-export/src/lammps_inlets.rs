//! Inlets (`[[inlet]]`, issue 28) in the LAMMPS scene deck: dembound's own
//! placements replayed, each sphere created by `create_atoms … single`
//! between runs, and the counts as thermo columns `v_insK_n v_insK_m`
//! (spheres and kg inserted so far by inlet K), read by `dembound compare`
//! beside dembound's series.csv `inletK_inserted`, `inletK_mass_kg`.
//!
//! **Why not `fix deposit` or `fix pour`** (LAMMPS 29 Sep 2021,
//! src/fix_deposit.cpp, src/GRANULAR/fix_pour.cpp): `fix deposit` inserts
//! one atom (or molecule) every M steps, with LAMMPS's own generator and a
//! centre-distance `near` test, and gives it the mask `1 | groupbit` of its
//! fix only (`FixDeposit::pre_exchange`), while the deck integrates group
//! `free` and applies each plane's `fix wall/gran` to a group per atom
//! type; `fix pour` sets its rate from a volume fraction and the free-fall
//! speed into its region. Neither reports the mass inserted, and neither
//! places dembound's spheres.
//!
//! **What the deck does.** dembound's placement is seeded per inlet and
//! event (`dembound_scene::inlets`: ChaCha8 on stream (inlet · 2⁴⁰ +
//! event)), so the export replays it: for every event of the run, the
//! spheres due (cumulative rounding of rate · t, the schedule's own
//! `Inlets::due_after`), each radius and candidate centre drawn as the
//! engine draws them (`place_event`), tested against what the export
//! knows: the fixed spheres (boundary-particle walls included, with their
//! periodic images), the plane walls acting at the event's step, and the
//! spheres placed earlier at that step. The free spheres already in the
//! run are not known at export: the placements are dembound's exactly
//! when no free sphere is in the way at the event (the region has been
//! left by the earlier spheres). The deck checks that at run time: a
//! sphere is created only if no free sphere's centre lies within r +
//! R_max of its place (R_max the largest free radius of the scene and its
//! inlets; `count(free, region sphere)`), else it is skipped and counted
//! in `insK_skip` (printed at the end); dembound would then have tried
//! other centres, so counts part from there. Spheres dembound cannot
//! place even in an empty region (`not_placed`) are not written.
//!
//! **When.** dembound appends an event's spheres mid-step at its step s
//! (after the drift, before the forces), with the half-step velocity
//! v₀ − g Δt/2, so that the step's last half kick brings it to v₀ (module
//! doc of `dembound_scene::inlets`). The deck creates them after the run
//! that ends at state s − 1, one step back along that flight: at x −
//! (v₀ − g Δt/2) Δt with velocity v₀ − g Δt; the next run's setup gives
//! them the force m g, its first half kick v₀ − g Δt/2 and its drift the
//! place x, before the forces of step s: dembound's state to rounding (a
//! sphere touching nothing at x − v Δt, which the check above makes
//! sure of for free spheres). The rows of state s − 1 (thermo and dump,
//! written at the end of the run) are before the creation in both codes;
//! for s = 1 the deck writes `run 0` first so that state 0 is printed
//! before. Each sphere is created with a spare atom type (the last), set
//! to its radius, density, velocity and then to its material's free type,
//! and `group free` and the plane walls' per-type groups are rebuilt
//! after each event (a created atom belongs to `all` only).
//!
//! **Cost.** Each sphere is four lines of the deck, each event a run
//! boundary (LAMMPS's setup: a neighbour-list build); at most
//! [`MAX_SPHERES`] spheres are written.

use std::collections::{BTreeMap, BTreeSet};
use std::fmt::Write as _;

use dembound_scene::inlets::{event_rng, place_event, Inlets, Obstacles};
use dembound_scene::setup::WallSetup;
use dembound_scene::SceneSetup;

use crate::lammps_gates::{self, PlaneSwitch};
use crate::outlets::{self, Outlets};
use crate::{num, Error, Result};

/// The most inserted spheres a deck writes (each is about 500 bytes of
/// the deck).
pub const MAX_SPHERES: u64 = 200_000;

/// The inlet commands of a deck.
pub(crate) struct InletDeck {
    /// Comments and the count variables, written once before the runs.
    pub setup: String,
    /// The thermo columns (with a leading space).
    pub columns: String,
    /// What to do after the run that ends at a state: the creations of
    /// the events of the next step.
    pub at: BTreeMap<u64, String>,
    /// Written after the last run: the counts and the skipped spheres.
    pub end: String,
}

/// How the scene deck names its atom types and groups.
pub(crate) struct Naming<'a> {
    /// The free atom type (1-based) of a material.
    pub free_type: &'a dyn Fn(usize) -> usize,
    /// The spare type a sphere is created with (1-based).
    pub fresh: usize,
    /// The `group` commands that take new free atoms into the deck's
    /// groups.
    pub regroup: String,
}

/// Refuses inlets the deck cannot replay, naming the key: beside a
/// moving group of fixed spheres (the placements are computed against
/// the fixed spheres where they start).
pub(crate) fn refuse(setup: &SceneSetup, moving: bool) -> Result<()> {
    if !setup.inlets.is_empty() && moving {
        return Err(Error::Export(
            "`inlet[0]` cannot be exported to LAMMPS beside a moving group of fixed spheres: \
             the deck writes dembound's placements, computed against the fixed spheres where \
             they start; remove the [[inlet]] sections or the group's motion to export the scene"
                .into(),
        ));
    }
    Ok(())
}

/// The images of `x` across the periodic axes of `setup`'s domain (shifts
/// −L, 0, +L), `x` itself first.
fn images(setup: &SceneSetup, x: [f64; 3]) -> Vec<[f64; 3]> {
    let d = &setup.domain;
    let mut out = vec![x];
    for a in 0..3 {
        if !d.periodic[a] {
            continue;
        }
        let len = d.upper[a] - d.lower[a];
        let mut more = Vec::new();
        for y in &out {
            for s in [-len, len] {
                let mut z = *y;
                z[a] += s;
                more.push(z);
            }
        }
        out.extend(more);
    }
    out
}

/// The inlet commands of `setup` for a run of `steps` steps of `dt` (s),
/// `windows` the states each wall acts on (`lammps_gates::windows`);
/// `None` without inlets.
pub(crate) fn plan(
    setup: &SceneSetup,
    dt: f64,
    steps: u64,
    windows: &[(u64, u64)],
    naming: &Naming,
) -> Result<Option<InletDeck>> {
    if setup.inlets.is_empty() {
        return Ok(None);
    }
    let densities: Vec<f64> = setup.materials.iter().map(|m| m.material.density).collect();
    let mut inlets = Inlets::new(
        &setup.inlets,
        &densities,
        setup.spheres.len(),
        dt,
        steps as f64 * dt,
    )
    .map_err(|e| Error::Export(e.to_string()))?;
    // Every event of the run: (step, inlet, event number).
    let mut events = Vec::new();
    for (k, i) in inlets.inlets.iter().enumerate() {
        let mut e = 0u64;
        while let Some(step) = e
            .checked_mul(i.every)
            .and_then(|d| d.checked_add(i.first_step))
        {
            if step > steps || inlets.event_at(k, step) != Some(e) {
                break;
            }
            events.push((step, k, e));
            e += 1;
        }
    }
    events.sort_unstable();
    // The guard's reach beyond a new sphere's radius: the largest free
    // radius, of the scene or an inlet.
    let r_free = setup
        .spheres
        .iter()
        .filter(|s| !s.fixed)
        .map(|s| s.radius)
        .chain(setup.inlets.iter().map(|i| i.size.max_radius()))
        .fold(0.0, f64::max);
    let fixed: Vec<([f64; 3], f64)> = setup
        .spheres
        .iter()
        .filter(|s| s.fixed)
        .flat_map(|s| {
            images(setup, s.position)
                .into_iter()
                .map(move |y| (y, s.radius))
        })
        .collect();
    // Planes: (wall index, point, unit normal into the domain).
    let planes: Vec<(usize, [f64; 3], [f64; 3])> = setup
        .walls
        .iter()
        .enumerate()
        .filter_map(|(w, wall)| match wall {
            WallSetup::Plane(p) => {
                let l = p.normal.iter().map(|c| c * c).sum::<f64>().sqrt();
                Some((w, p.point, p.normal.map(|c| c / l)))
            }
            _ => None,
        })
        .collect();
    let g = setup.gravity;
    let mut deck = InletDeck {
        setup: "\n# inlets (docs/export-lammps.md, \"Inlets\"): dembound's placements replayed, each sphere created\n\
                # by create_atoms between runs one step back along its flight; thermo columns v_insK_n v_insK_m:\n\
                # spheres and mass (kg) inserted so far by inlet K\n"
            .into(),
        columns: String::new(),
        at: BTreeMap::new(),
        end: String::new(),
    };
    for (k, i) in inlets.inlets.iter().enumerate() {
        writeln!(
            deck.setup,
            "# inlet[{k}]: {} spheres/s of material \"{}\" (type {}), events every {} steps from step {}\n\
             variable     ins{k}_n equal 0\nvariable     ins{k}_m equal 0\nvariable     ins{k}_skip equal 0",
            num(i.number_rate),
            setup.materials[i.setup.material].name,
            (naming.free_type)(i.setup.material),
            i.every,
            i.first_step
        )
        .ok();
        write!(deck.columns, " v_ins{k}_n v_ins{k}_m").ok();
        writeln!(
            deck.end,
            "print        \"inlet[{k}]: ${{ins{k}_n}} spheres inserted, ${{ins{k}_m}} kg; ${{ins{k}_skip}} skipped (a free sphere within r + R_max of dembound's place)\""
        )
        .ok();
    }
    let mut written = 0u64;
    let mut at = 0;
    while at < events.len() {
        let step = events[at].0;
        // The spheres placed at this step so far (earlier inlets'), with
        // their images: obstacles of the later inlets, as in the engine.
        let mut this_step: Vec<([f64; 3], f64)> = Vec::new();
        let mut text = String::new();
        while at < events.len() && events[at].0 == step {
            let (_, k, e) = events[at];
            at += 1;
            let due = inlets.due_after(k, e);
            let n = due.saturating_sub(inlets.inlets[k].due);
            inlets.inlets[k].due = due.max(inlets.inlets[k].due);
            if n == 0 {
                continue;
            }
            written = written.saturating_add(n);
            if written > MAX_SPHERES {
                return Err(Error::Export(format!(
                    "`inlet[{k}].rate` inserts more than {MAX_SPHERES} spheres over the run: the \
                     LAMMPS deck writes each inserted sphere's place (about 500 bytes each); \
                     shorten the run or lower the rate to export the scene"
                )));
            }
            let s = inlets.inlets[k].setup.clone();
            let r_max = s.size.max_radius();
            let (lo, hi) = s.region.bounds();
            let near = |x: &[f64; 3], r: f64| {
                (0..3).all(|a| x[a] + r >= lo[a] - r_max && x[a] - r <= hi[a] + r_max)
            };
            let list: Vec<([f64; 3], f64)> = fixed
                .iter()
                .copied()
                .chain(
                    this_step
                        .iter()
                        .flat_map(|&(x, r)| images(setup, x).into_iter().map(move |y| (y, r))),
                )
                .filter(|(x, r)| near(x, *r))
                .collect();
            let mut obstacles = Obstacles::new(list, r_max);
            // A plane acting at this state is an obstacle: clear when the
            // centre is at least r from it on the domain's side (the
            // engine's overlap r − n·(x − p) ≤ 0).
            let walls_clear = |x: [f64; 3], r: f64| {
                planes.iter().all(|&(w, p, n)| {
                    let (on, off) = windows[w];
                    let acting = on <= step && step < off;
                    !acting || r - (0..3).map(|a| n[a] * (x[a] - p[a])).sum::<f64>() <= 0.0
                })
            };
            let (placed, missed) = place_event(
                &s,
                n,
                &mut event_rng(s.seed, k, e),
                &mut obstacles,
                &walls_clear,
            );
            let material = &setup.materials[s.material].material;
            let ty = (naming.free_type)(s.material);
            writeln!(
                text,
                "# inlet[{k}] event {e} at step {step} (t = {} s): {n} due, {} placed by dembound's draws{}",
                num(step as f64 * dt),
                placed.len(),
                if missed > 0 {
                    format!(" ({missed} found no free place: dembound's not_placed)")
                } else {
                    String::new()
                }
            )
            .ok();
            let v0 = s.velocity;
            let vh = [0, 1, 2].map(|a| v0[a] - 0.5 * dt * g[a]);
            let vc = [0, 1, 2].map(|a| v0[a] - dt * g[a]);
            for &(x, r) in &placed {
                let xc = [0, 1, 2].map(|a| x[a] - vh[a] * dt);
                let m = material.sphere_mass(r);
                writeln!(
                    text,
                    "region       ins_g sphere {} {} {} {} side in units box\n\
                     if \"$(count(free,ins_g)) == 0\" then \"create_atoms {f} single {} {} {} units box remap yes\" \
                     \"set type {f} diameter {} density {} vx {} vy {} vz {} type {ty}\" \
                     \"variable ins{k}_n equal $(v_ins{k}_n+1)\" \"variable ins{k}_m equal $(v_ins{k}_m+{})\" \
                     else \"variable ins{k}_skip equal $(v_ins{k}_skip+1)\"\n\
                     region       ins_g delete",
                    num(x[0]),
                    num(x[1]),
                    num(x[2]),
                    num(r + r_free),
                    num(xc[0]),
                    num(xc[1]),
                    num(xc[2]),
                    num(2.0 * r),
                    num(material.density),
                    num(vc[0]),
                    num(vc[1]),
                    num(vc[2]),
                    num(m),
                    f = naming.fresh,
                )
                .ok();
            }
            this_step.extend(placed);
        }
        if !text.is_empty() {
            text.push_str(&naming.regroup);
            deck.at.insert(step - 1, text);
        }
    }
    Ok(Some(deck))
}

/// The `run` commands of a deck with inlets: runs end at every state
/// after which something happens, the states before an inlet event
/// (`inlets.at`), the gates' switches and, with outlets, every multiple of
/// `outlets::EVERY` (so the outlets check at the same states as in a deck
/// without inlets); after each, the outlets' removal, the switches, then
/// the creations.
pub(crate) fn runs(
    steps: u64,
    dt: f64,
    windows: &[(u64, u64)],
    planes: &[PlaneSwitch],
    outlets: Option<&Outlets>,
    inlets: &InletDeck,
) -> String {
    let switches = lammps_gates::switch_events(steps, windows, planes, |p| p.wall);
    let mut ends: BTreeSet<u64> = inlets.at.keys().copied().filter(|&b| b < steps).collect();
    ends.extend(switches.iter().map(|s| s.0));
    if outlets.is_some() {
        ends.extend((1..=steps / outlets::EVERY).map(|j| j * outlets::EVERY));
    }
    ends.insert(steps);
    let mut x = String::new();
    let mut done = 0;
    for b in ends {
        let n = b - done;
        match outlets {
            Some(o) if n > 0 && b % outlets::EVERY == 0 => {
                writeln!(x, "run          {n} post no every {n}{}", o.commands).ok();
            }
            _ if n > 0 || inlets.at.contains_key(&b) => {
                // `run 0` at state 0: its rows come before the creations.
                writeln!(x, "run          {n} post no").ok();
            }
            _ => {}
        }
        done = b;
        for (_, arrives, p) in switches.iter().filter(|s| s.0 == b) {
            x.push_str(&lammps_gates::switch_text(b, *arrives, p, dt));
        }
        if let Some(t) = inlets.at.get(&b) {
            x.push_str(t);
        }
    }
    x.push_str(&inlets.end);
    x
}

#[cfg(test)]
mod tests {
    use dembound_scene::io::{config, resolve::resolve};
    use dembound_scene::Simulation;

    /// Two inlets pouring into one box at step 1 past a fixed sphere and a
    /// plane crossing the box, a uniform radius: every candidate test of
    /// the engine (spheres, walls, the other inlet's spheres) is met.
    const SCENE: &str = r#"
[domain]
lower = [0.0, 0.0, 0.0]
upper = [0.01, 0.01, 0.01]
[[material]]
name = "a"
density = 2500.0
youngs_modulus = 1.0e7
poisson_ratio = 0.3
[contact]
law = "hertz"
[[particles]]
spheres = [ { position = [0.005, 0.005, 0.005], radius = 2.0e-3 } ]
material = "a"
fixed = true
[[wall]]
plane = { point = [0.0, 0.0, 0.003], normal = [0.0, 0.0, 1.0] }
material = "a"
[[inlet]]
region = { box = { lower = [0.0, 0.0, 0.0], upper = [0.01, 0.01, 0.01] } }
rate = { number = 30000.0 }
size = { uniform = [0.4e-3, 0.8e-3] }
material = "a"
velocity = [0.0, 0.0, -0.5]
every = 10
seed = 5
[[inlet]]
region = { box = { lower = [0.0, 0.0, 0.0], upper = [0.01, 0.01, 0.01] } }
rate = { number = 20000.0 }
size = { fixed = 0.5e-3 }
material = "a"
every = 10
seed = 6
[motion]
gravity = [0.0, 0.0, -9.81]
[integration]
dt = 1.0e-5
steps = 30
"#;

    fn exported(sets: &[&str]) -> crate::Result<crate::Deck> {
        let sets: Vec<String> = sets.iter().map(|s| s.to_string()).collect();
        let file = config::load(SCENE, "test", &sets).expect("a valid scene");
        let scene = resolve(&file, std::path::Path::new(".")).expect("resolves");
        crate::lammps_scene::deck(&scene)
    }

    /// The places the deck writes (`region ins_g sphere x y z …`), in
    /// order.
    fn places(deck: &str) -> Vec<[f64; 3]> {
        deck.lines()
            .filter(|l| l.starts_with("region       ins_g sphere "))
            .map(|l| {
                let w: Vec<f64> = l
                    .split_whitespace()
                    .skip(3)
                    .take(3)
                    .map(|x| x.parse().expect("a number"))
                    .collect();
                [w[0], w[1], w[2]]
            })
            .collect()
    }

    /// The deck's places of event 0 (step 1) are the engine's own: the
    /// scene run one step by `Simulation` (its placement against the
    /// bodies and walls it holds), compared bit for bit; the counts are
    /// the schedule's closed form round(ṅ · 10 Δt): 3 and 2 per event,
    /// three events (steps 1, 11, 21).
    #[test]
    fn the_deck_places_the_engines_spheres() {
        let d = exported(&[]).expect("exports");
        let input = &d.files[0].text;
        let all = places(input);
        assert_eq!(all.len(), 3 * (3 + 2), "{input}");
        let file = config::load(SCENE, "test", &[]).expect("a valid scene");
        let scene = resolve(&file, std::path::Path::new(".")).expect("resolves");
        let mut sim = Simulation::new(scene.setup.clone(), 1).expect("builds");
        sim.step(1);
        // Inserted ids from 1 (the scene has one sphere), in placement
        // order.
        let mut inserted: Vec<(u32, [f64; 3])> = sim
            .ids()
            .into_iter()
            .zip(sim.positions())
            .filter(|(id, _)| *id >= 1)
            .collect();
        inserted.sort_by_key(|p| p.0);
        let engine: Vec<[f64; 3]> = inserted.into_iter().map(|p| p.1).collect();
        assert_eq!(engine.len(), 5, "the engine's event-0 spheres");
        assert_eq!(&all[..5], &engine[..], "{input}");
        // The creation point is one step back along the flight: x −
        // (v₀ − g Δt/2) Δt, here v₀ = −0.5 m/s (inlet 0) along z.
        let first = input
            .lines()
            .find(|l| {
                l.starts_with("if \"$(count(free,ins_g)) == 0\" then \"create_atoms 3 single ")
            })
            .expect("a creation");
        let w: Vec<&str> = first.split_whitespace().collect();
        let zc: f64 = w[10].parse().expect("z");
        let vh = -0.5 + 0.5 * 1e-5 * 9.81;
        // The same arithmetic: within an ulp of 5 mm (9e-19 m).
        assert!((zc - (all[0][2] - vh * 1e-5)).abs() <= 1e-18, "{first}");
        // The spare type, the counts' columns, the dump's radius and mass,
        // `run 0` before the first creation, the groups taken again.
        assert!(d.files[1].text.contains("\n3 atom types\n"));
        assert!(input.contains("pair_coeff   * 3 hertz 1e0 "));
        assert!(input.contains(" v_ins0_n v_ins0_m v_ins1_n v_ins1_m\n"));
        assert!(input.contains("omegax omegay omegaz radius mass\n"));
        let run0 = input.find("run          0 post no\n").expect("run 0");
        assert!(run0 < input.find("\nif \"$(count").expect("a creation"));
        assert!(input.contains("group        free type 1\ngroup        t1 type 1\n"));
        assert!(input.contains("run          10 post no\n# inlet[0] event 1 at step 11"));
    }

    #[test]
    fn an_inlet_beside_a_moving_group_is_refused() {
        let e = exported(&["particles.0.motion={velocity=[0.0,0.0,0.1]}"]).expect_err("refused");
        let e = e.to_string();
        assert!(e.contains("inlet[0]") && e.contains("LAMMPS"), "{e}");
    }
}
