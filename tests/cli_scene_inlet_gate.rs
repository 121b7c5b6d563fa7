//! An inlet whose region a gate (`[[wall]] active = { from, to }`, issue
//! 28) crosses: insertion sees only the walls acting at the insertion
//! step. A gate that opened before the insertion is no obstacle (spheres
//! go into its former volume, the count the rate's closed form); one
//! acting keeps every centre out of its volume (at least a radius in
//! front of it), and a region wholly behind it gets none (all counted
//! `not_placed`).

use dembound_scene::io::config;
use dembound_scene::io::resolve::resolve;
use dembound_scene::Simulation;
use std::path::Path;

/// Sphere radius, m.
const R: f64 = 1e-3;
/// The gate: the plane z = Z_GATE, normal −z (its volume is z > Z_GATE).
const Z_GATE: f64 = 0.05;
/// Inlet rate, spheres/s; start and end, s.
const RATE: f64 = 5000.0;
const START: f64 = 0.002;
const END: f64 = 0.012;

/// No gravity, spheres inserted at rest (they stay where placed, touching
/// nothing), Δt = 1e-5 s, events every 100 steps (1 ms) from START to
/// END, run for 15 ms. The gate window `window`; the inlet's box from
/// z = `z_lo` to `z_hi` (m), x and y from 0.01 to 0.09 m.
fn scene(window: &str, z_lo: f64, z_hi: f64) -> String {
    format!(
        r#"
[domain]
lower = [0.0, 0.0, 0.0]
upper = [0.1, 0.1, 0.1]
[[material]]
name = "glass"
density = 2500.0
youngs_modulus = 1e7
poisson_ratio = 0.25
[contact]
law = "hertz"
[[wall]]
plane = {{ point = [0.0, 0.0, {Z_GATE:?}], normal = [0.0, 0.0, -1.0] }}
material = "glass"
active = {window}
[motion]
gravity = [0.0, 0.0, 0.0]
[integration]
dt = 1e-5
duration = 0.015
[[inlet]]
region = {{ box = {{ lower = [0.01, 0.01, {z_lo:?}], upper = [0.09, 0.09, {z_hi:?}] }} }}
rate = {{ number = {RATE:?} }}
size = {{ fixed = {R:?} }}
material = "glass"
start = {START:?}
end = {END:?}
every = 100
seed = 7
"#
    )
}

/// The scene run to its end through the engine API (the binary's code).
fn run(text: &str) -> Simulation {
    let file = config::load(text, "inlet_gate.toml", &[]).expect("the scene reads");
    let setup = resolve(&file, Path::new(".")).expect("resolves").setup;
    let mut sim = Simulation::new(setup, 1).expect("a valid scene");
    sim.step_checked(1500).expect("runs");
    sim
}

/// The closed-form count: round(ṅ (end − start)) = round(5000 · 0.01) =
/// 50 (events k = 0..9 each bring the spheres due by the end of their
/// 1 ms interval, the last by `end`: module doc of `inlets`).
fn expected_count() -> u64 {
    (RATE * (END - START)).round() as u64
}

/// A gate acting from 0 to 1 ms, before the first event at 2 ms: all 50
/// spheres placed, and the box (z from 0.03 to 0.07 m, half of it behind
/// the gate's plane) gets spheres in the gate's former volume. Centres
/// are uniform in z ∈ [0.031, 0.069] m, so the count above Z_GATE is
/// binomial(50, ½): mean 25, σ ≈ 3.5; [10, 40] is more than 4σ either
/// way for the one seeded draw (and 0 is what the old test of every wall
/// element gave).
#[test]
fn a_gate_open_before_the_insertion_is_no_obstacle() {
    let sim = run(&scene("{ from = 0.0, to = 0.001 }", 0.03, 0.07));
    let o = sim.observe();
    assert_eq!(o.inlets[0].count, expected_count());
    assert_eq!(o.inlets[0].not_placed, 0);
    let above = sim.positions().iter().filter(|x| x[2] > Z_GATE).count();
    assert!((10..=40).contains(&above), "{above} of 50 above the plane");
}

/// A gate acting all run: the 50 spheres placed (the half-box in front
/// of it holds them easily), every centre at least R in front of the
/// plane (z ≤ Z_GATE − R; the test is exact: overlap ≤ 0), so no wall
/// contact at the end.
#[test]
fn an_acting_gate_keeps_the_spheres_out_of_its_volume() {
    let sim = run(&scene("{ from = 0.0 }", 0.03, 0.07));
    let o = sim.observe();
    assert_eq!(o.inlets[0].count, expected_count());
    assert_eq!(o.inlets[0].not_placed, 0);
    for x in sim.positions() {
        assert!(x[2] <= Z_GATE - R, "a centre at z = {} m", x[2]);
    }
    assert_eq!(o.wall_contacts, 0);
}

/// A box wholly behind the plane (z from 0.06 to 0.08 m): with the gate
/// acting no sphere is placed and all 50 are counted not placed; with the
/// gate gone before the insertion (to = 1 ms) all 50 are placed.
#[test]
fn a_region_behind_a_gate_fills_only_once_it_has_gone() {
    let sim = run(&scene("{ from = 0.0 }", 0.06, 0.08));
    let o = sim.observe();
    assert_eq!((o.inlets[0].count, o.inlets[0].not_placed), (0, 50));
    let sim = run(&scene("{ from = 0.0, to = 0.001 }", 0.06, 0.08));
    let o = sim.observe();
    assert_eq!(
        (o.inlets[0].count, o.inlets[0].not_placed),
        (expected_count(), 0)
    );
    assert!(sim.positions().iter().all(|x| x[2] > Z_GATE));
}
