//! The bounce's scalar integrators and the physics crate's generic ones
//! (`dembound_physics::integrate`) on an `f64` state are the same scheme:
//! predict/correct give the same bits, step after step, through a change
//! of step size. (The bounce additionally has a fused scalar step,
//! `step_scaled`, reassociated for latency: it differs by a few ulps and
//! is checked against exact solutions in the unit tests.)

use dembound_core::integrate::{Gear5, Integrator, Verlet};
use dembound_physics::integrate as generic;

/// A Hertz-like acceleration (stiff, nonlinear, with a constant part).
fn accel(x: f64, v: f64) -> f64 {
    -9.81 - 2.0e8 * x * x.abs().sqrt() - 3.0 * v
}

#[test]
fn gear5_predict_correct_matches_the_generic_scheme_bit_for_bit() {
    for gear in [Gear5::POSITION_DEPENDENT, Gear5::VELOCITY_DEPENDENT] {
        let start = [-1e-7, -0.3, -9.81, 40.0, -2.0, 0.5];
        let mut ours = Integrator::start(&gear, start, 1e-7);
        let mut theirs = generic::Integrator::<f64>::start(&gear, start, 1e-7);
        for i in 0..2000 {
            if i == 1000 {
                Integrator::set_step(&gear, &mut ours, 3e-8);
                generic::Integrator::<f64>::set_step(&gear, &mut theirs, 3e-8);
            }
            let (x, v) = Integrator::predict(&gear, &mut ours);
            let (gx, gv) = generic::Integrator::<f64>::predict(&gear, &mut theirs);
            assert_eq!((x, v), (gx, gv), "step {i}");
            Integrator::correct(&gear, &mut ours, accel(x, v));
            generic::Integrator::<f64>::correct(&gear, &mut theirs, accel(gx, gv));
        }
        let k = Integrator::kinematics(&gear, &ours);
        let g = generic::Integrator::<f64>::kinematics(&gear, &theirs);
        assert_eq!(
            (k.position, k.velocity, k.acceleration),
            (g.position, g.velocity, g.acceleration)
        );
    }
}

#[test]
fn verlet_predict_correct_matches_the_generic_scheme_bit_for_bit() {
    let start = [-1e-7, -0.3, -9.81, 0.0, 0.0, 0.0];
    let mut ours = Verlet.start(start, 1e-7);
    let mut theirs = generic::Integrator::<f64>::start(&generic::verlet::Verlet, start, 1e-7);
    for i in 0..2000 {
        let (x, v) = Verlet.predict(&mut ours);
        let (gx, gv) = generic::Integrator::<f64>::predict(&generic::verlet::Verlet, &mut theirs);
        assert_eq!((x, v), (gx, gv), "step {i}");
        Verlet.correct(&mut ours, accel(x, v));
        generic::Integrator::<f64>::correct(&generic::verlet::Verlet, &mut theirs, accel(gx, gv));
    }
    let k = Verlet.kinematics(&ours);
    assert_eq!((k.position, k.velocity), (theirs.x, theirs.v));
}
