//! The generic integrators on scalar, 3-vector and many-body states.
//! Expected values: the harmonic oscillator's exact solution
//! x = cos t (ẍ = −x), and bit-equality between a vector state and the
//! scalar runs of its components (the arithmetic is element-wise, so a
//! state type must not change a single bit).

use super::gear5::Gear5;
use super::verlet::Verlet;
use super::{Bodies, Integrator, State, Vec3};
use std::f64::consts::PI;

/// Runs `n` steps of ẍ = −x from `start` and returns x at the end.
fn run<S: State, I: Integrator<S>>(it: I, start: [S; 6], dt: f64, n: usize) -> S {
    let mut s = it.start(start, dt);
    for _ in 0..n {
        it.step(&mut s, |x, _| x * -1.0);
    }
    it.kinematics(&s).position
}

/// x = cos t: derivatives at t = 0 are 1, 0, −1, 0, 1, 0.
const COS: [f64; 6] = [1.0, 0.0, -1.0, 0.0, 1.0, 0.0];

#[test]
fn scalar_oscillator_errors_have_the_schemes_orders() {
    // A quarter period in n steps; x(π/2) = 0 exactly, where the error is
    // the phase error (at a turning point it would be its square).
    let err = |it: &dyn Fn(usize) -> f64, n: usize| it(n).abs();
    let gear = |n: usize| run(Gear5::POSITION_DEPENDENT, COS, 0.5 * PI / n as f64, n);
    let verlet = |n: usize| run(Verlet, COS, 0.5 * PI / n as f64, n);
    // Verlet: second order, the error ratio per halving of Δt → 4 (3.9–4.1
    // allows the O(Δt⁴) term at 100 steps per quarter period).
    let ratio = err(&verlet, 100) / err(&verlet, 200);
    assert!((3.9..4.1).contains(&ratio), "verlet ratio {ratio}");
    // Gear5 with the position corrector: far more accurate (< 1e-7 at 25
    // steps per quarter period, as the bounce's scalar Gear5 test has it
    // for 50 per half period).
    assert!(err(&gear, 25) < 1e-7, "gear5 {}", err(&gear, 25));
}

#[test]
fn a_vector_state_gives_the_bits_of_its_scalar_components() {
    let dt = PI / 37.0;
    for n in [1, 10, 100] {
        // Three independent oscillators of different amplitude, one per axis.
        let amp = [1.0, -0.3, 2.5];
        let vec_start: [Vec3; 6] = std::array::from_fn(|k| Vec3(amp.map(|a| a * COS[k])));
        let g = run(Gear5::POSITION_DEPENDENT, vec_start, dt, n);
        let v = run(Verlet, vec_start, dt, n);
        for (i, a) in amp.iter().enumerate() {
            let scalar_start = COS.map(|c| a * c);
            assert_eq!(
                g.0[i],
                run(Gear5::POSITION_DEPENDENT, scalar_start, dt, n),
                "gear5 axis {i}"
            );
            assert_eq!(v.0[i], run(Verlet, scalar_start, dt, n), "verlet axis {i}");
        }
    }
}

#[test]
fn many_bodies_step_as_each_alone() {
    let dt = 0.01;
    let n = 500;
    // Two bodies, 3-vectors each, different starts.
    let a: [Vec3; 6] = std::array::from_fn(|k| Vec3([COS[k], 0.0, -COS[k]]));
    let b: [Vec3; 6] = std::array::from_fn(|k| Vec3([0.5 * COS[k], 2.0 * COS[k], 0.0]));
    let both: [Bodies<Vec3, 2>; 6] = std::array::from_fn(|k| Bodies([a[k], b[k]]));
    for scheme in 0..2 {
        let (together, alone_a, alone_b) = if scheme == 0 {
            let it = Gear5::VELOCITY_DEPENDENT;
            (run(it, both, dt, n), run(it, a, dt, n), run(it, b, dt, n))
        } else {
            (
                run(Verlet, both, dt, n),
                run(Verlet, a, dt, n),
                run(Verlet, b, dt, n),
            )
        };
        assert_eq!(together.0[0], alone_a, "scheme {scheme}");
        assert_eq!(together.0[1], alone_b, "scheme {scheme}");
        // And they are right: x(5) = cos 5 to the schemes' accuracy
        // (Verlet at Δt = 0.01: ~1e-5; Gear5: far below).
        let exact = 5.0_f64.cos();
        assert!((alone_a.0[0] - exact).abs() < 2e-5, "{alone_a:?}");
    }
}

#[test]
fn changing_the_step_keeps_the_trajectory() {
    // Halving Δt midway: still on x = cos t at the end (Gear5 rescales its
    // Nordsieck vector, Verlet needs nothing).
    for gear in [true, false] {
        let end = if gear {
            let it = Gear5::POSITION_DEPENDENT;
            let mut s = it.start(COS, 0.02);
            (0..100).for_each(|_| it.step(&mut s, |x, _| -x));
            it.set_step(&mut s, 0.01);
            (0..200).for_each(|_| it.step(&mut s, |x, _| -x));
            it.kinematics(&s)
        } else {
            let mut s = Verlet.start(COS, 0.02);
            (0..100).for_each(|_| Verlet.step(&mut s, |x: f64, _| -x));
            Integrator::<f64>::set_step(&Verlet, &mut s, 0.01);
            (0..200).for_each(|_| Verlet.step(&mut s, |x: f64, _| -x));
            Verlet.kinematics(&s)
        };
        // t = 4: cos 4, −sin 4; Verlet's error ≈ Δt² t/24-ish ≲ 1e-4.
        assert!(
            (end.position - 4.0_f64.cos()).abs() < 1e-4,
            "{gear} {end:?}"
        );
        assert!(
            (end.velocity + 4.0_f64.sin()).abs() < 1e-4,
            "{gear} {end:?}"
        );
    }
}
