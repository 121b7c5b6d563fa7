//! Energy of a frictionless elastic Hertz gas in a periodic box (every
//! pair across the faces goes through the ghost layer): velocity Verlet
//! conserves kinetic + elastic energy, and its error falls as Δt².

mod common;

use dembound_scene::Simulation;

/// Largest |E(t) − E(0)|/E(0) over `samples` × `every` steps, sampled every
/// `every` steps, E = kinetic + elastic.
fn energy_error(eta: f64, samples: u64, every: u64) -> (f64, u64) {
    let setup = common::periodic_gas(4, eta, 0.5, 11);
    let mut sim = Simulation::new(setup, 1).unwrap();
    let total = |sim: &Simulation| {
        let o = sim.observe();
        o.kinetic_energy + o.elastic_energy
    };
    let e0 = total(&sim);
    let mut worst = 0.0f64;
    for _ in 0..samples {
        sim.step(every);
        worst = worst.max((total(&sim) / e0 - 1.0).abs());
    }
    (worst, sim.list_builds())
}

#[test]
fn hertz_gas_conserves_energy_over_1e5_steps() {
    // η = 1/50 of the contact time at the gas's speed scale (0.5 m/s).
    // 64 spheres, 10⁵ steps, many collisions per sphere (asserted through
    // the list rebuilds); the bound is 1e-4.
    let (err, builds) = energy_error(1.0 / 50.0, 1000, 100);
    assert!(builds > 100, "{builds} list builds");
    assert!(err < 1e-4, "energy drift {err:e}");
}

#[test]
fn energy_error_is_second_order_in_dt() {
    // The same simulated time at η, η/2, η/4, sampled at the same instants
    // (short enough that the collision sequence is the same for all three).
    // Second order: the error ratio per halving is 4; allow 3–5.5 (the
    // sampled maximum falls at slightly different phases of a contact).
    let base = 1.0 / 25.0;
    let (e1, _) = energy_error(base, 50, 20);
    let (e2, _) = energy_error(base / 2.0, 50, 40);
    let (e4, _) = energy_error(base / 4.0, 50, 80);
    for (ratio, what) in [(e1 / e2, "η/(η/2)"), (e2 / e4, "(η/2)/(η/4)")] {
        assert!(
            (3.0..5.5).contains(&ratio),
            "{what}: {ratio} ({e1:e}, {e2:e}, {e4:e})"
        );
    }
}
