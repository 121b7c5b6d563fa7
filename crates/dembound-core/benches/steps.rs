//! Cost of one integration step inside a contact, and of the validation case
//! end to end.
//!
//! `cargo bench -p dembound-core --bench steps`
//!
//! Instruction counts of the same loops under callgrind: `examples/step_count.rs`.
//!
//! The step benchmarks run 1000 consecutive steps of the in-contact equation
//! (the law's force continued past h = 0, so the particle oscillates in
//! contact forever and every step costs what a contact step costs), and
//! report time per step via `Throughput::Elements`.

use criterion::{black_box, criterion_group, criterion_main, Criterion, Throughput};
use dembound_core::bounce::{simulate, Scenario, Stepping};
use dembound_core::contact::{ContactLawKind, Hertz, LinearSpring, NormalContactLaw};
use dembound_core::integrate::{Gear5, Integrator, Scheme, Verlet};
use dembound_core::material::{Boundary, ContactPair, Particle};

const STEPS: u64 = 1000;

fn run_steps<I: Integrator, L: NormalContactLaw<History = ()>>(
    it: I,
    law: &L,
    mass: f64,
    dt: f64,
) -> f64 {
    // As the contact loop does: the law per unit mass, scaled once per step
    // size by the scheme's force gain (`Integrator::step_scaled`).
    let g = 9.81;
    let mut s = it.start([0.0, -0.3132, -g, 0.0, 0.0, 0.0], dt);
    let law = law.scaled(1.0 / mass).scaled(it.force_gain(&s));
    for _ in 0..STEPS {
        it.step_scaled(&mut s, -g, |x, v| law.force(-x, -v, &()));
    }
    it.kinematics(&s).position
}

fn steps(c: &mut Criterion) {
    let pair = ContactPair::new(Particle::PAPER, Boundary::PAPER);
    let mass = Particle::PAPER.mass();
    let hertz = pair.law::<Hertz>(&[]);
    let linear = pair.law::<LinearSpring>(&[]);
    let dt_h = hertz.contact_time_estimate(mass, 0.3132) / 50.0;
    let dt_l = linear.contact_time_estimate(mass, 0.3132) / 50.0;
    let mut group = c.benchmark_group("step");
    group.throughput(Throughput::Elements(STEPS));
    group.bench_function("gear5_hertz", |b| {
        b.iter(|| run_steps(Gear5::POSITION_DEPENDENT, black_box(&hertz), mass, dt_h))
    });
    group.bench_function("verlet_hertz", |b| {
        b.iter(|| run_steps(Verlet, black_box(&hertz), mass, dt_h))
    });
    group.bench_function("gear5_linear", |b| {
        b.iter(|| run_steps(Gear5::POSITION_DEPENDENT, black_box(&linear), mass, dt_l))
    });
    group.bench_function("verlet_linear", |b| {
        b.iter(|| run_steps(Verlet, black_box(&linear), mass, dt_l))
    });
    group.finish();
}

fn validation_case(c: &mut Criterion) {
    let mut group = c.benchmark_group("validation_case");
    for (name, law, scheme, stepping) in [
        (
            "hertz_gear5_event",
            ContactLawKind::Hertz,
            Scheme::Gear5,
            Stepping::Event,
        ),
        (
            "linear_gear5_event",
            ContactLawKind::Linear,
            Scheme::Gear5,
            Stepping::Event,
        ),
        (
            "hertz_verlet_event",
            ContactLawKind::Hertz,
            Scheme::Verlet,
            Stepping::Event,
        ),
        (
            "hertz_gear5_fixed",
            ContactLawKind::Hertz,
            Scheme::Gear5,
            Stepping::Fixed,
        ),
        (
            "linear_gear5_fixed",
            ContactLawKind::Linear,
            Scheme::Gear5,
            Stepping::Fixed,
        ),
    ] {
        let mut s = Scenario::default();
        s.contact.law = law;
        s.integration.scheme = scheme;
        s.integration.stepping = stepping;
        if stepping == Stepping::Fixed {
            group.sample_size(10);
        }
        group.bench_function(name, |b| b.iter(|| simulate(black_box(&s), &mut ())));
    }
    group.finish();
}

criterion_group!(benches, steps, validation_case);
criterion_main!(benches);
