//! The dissipated energy summed contact by contact (`output.dissipation =
//! true`, issue 27's energy balance).
//!
//! Without it the dissipated energy D is the balance's residual,
//! E₀ + W − C − G + I − (K + E + P), which holds by construction. With it
//! D is also built from the contacts, D_c = D_n + D_t, and the balance
//! error D − D_c is reported and judged by the energy guard:
//!
//! - **D_n, the normal dashpots**: Σ over touching pairs and wall contacts
//!   of the dashpot's share of the normal force
//!   (`PairLaw::damping_share`, after the same clamp the force pass
//!   applies) times the overlap rate, integrated over each step. An
//!   undamped contact adds exactly 0.
//! - **D_t, the tangential and rolling resistance** (friction only): the
//!   work the tangential forces and rolling torques took from the
//!   contacts less what their springs hold now, D_t = −∫ Σ (F_t·v_t +
//!   M_r·(ω₁ − ω₂)) dt − U_s. This holds the tangential and rolling
//!   dashpots, the sliding (the spring cut back to μ |F_n|) and the spring
//!   energy of a contact that ended; a sticking undamped spring adds only
//!   its integration error. The forces are the ones the step applied,
//!   read back from the springs it stored (`ContactLaw::observe_applied`):
//!   a spring the step cut to its Coulomb or rolling limit is sliding.
//!   (Re-evaluated, a cut spring sits at or a rounding below its limit and
//!   half the time gains its dashpot: on a bed with rolling resistance
//!   that made D_c 20 % too large.)
//!
//! **Consistent with the integrator.** Velocity Verlet evaluates the forces
//! of step n + 1 at x_{n+1} with the half-step velocities v_{n+1/2}, and
//! that force kicks the velocity from v_{n+1/2} to v_{n+3/2}, whose mean is
//! v_{n+1} (the full-step velocity); the energy it takes out of the
//! half-step kinetic energy is exactly Δt F_{n+1}·v_{n+1}. So after each
//! step the pass takes, per contact, the force from the half-step
//! velocities v_{n+1/2} = v_{n+1} − Δt/2 F_{n+1}/m (and the spins alike)
//! and the motion from the full-step ones, and adds Δt times their product
//! (the leapfrog's exact bookkeeping for a velocity-dependent force: a
//! damped linear contact loses, in D_n, what the integrated trajectory
//! lost to the dashpot to rounding). Gear5 corrects to a full-step state:
//! the power there, integrated by the trapezoidal rule.
//!
//! **Cost.** One more pass over the listed pairs and wall entries per
//! step, serial, and Verlet unfused (the same bits: the fused form does
//! the same operations): opt-in. Sums per body in body order (the same on
//! any thread count), each body's contacts in list order.
//!
//! **Not covered**: the hysteresis of a normal law with history (its
//! energy loss stays in the balance error), and runs under `mpirun`
//! (refused).

use dembound_physics::contact::model::{overlap_rate, slip_velocity};
use dembound_physics::contact::{ContactForces, ContactHistory, ContactLaw, Geometry, Side};
use serde::{Deserialize, Serialize};

use super::World;
use crate::dynamics::contacts::NO_HISTORY;
use crate::setup::Scheme;

/// The dissipation summed contact by contact since t = 0.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct Dissipation {
    /// D_n: energy the normal dashpots took out, J.
    pub normal: f64,
    /// Work done on the contacts by the tangential forces and rolling
    /// torques, J (negative: taken out).
    pub tangential_work: f64,
    /// Gear5: the powers [normal dashpots, tangential work] at the last
    /// step, W (the trapezoidal rule's left end); `None` before the first.
    pub last_power: Option<[f64; 2]>,
    /// Verlet: what of the last step's force kicks the velocity beyond
    /// t_n, [normal dashpots, tangential work], J (taken off at
    /// observation).
    pub tail: [f64; 2],
    /// D − D_c at the start, J: 0 from t = 0; a restart starts from the
    /// checkpoint's residual D (the balance error before it is not kept).
    pub offset: f64,
}

impl Dissipation {
    /// D_c given the energy the springs hold now, `springs` (J).
    pub fn total(&self, springs: f64) -> f64 {
        (self.offset + self.normal - self.tail[0]) - (self.tangential_work - self.tail[1]) - springs
    }
}

/// Which velocities a pass pairs: the forces from v + `force` Δt/2 a and
/// the motion from v + `motion` Δt/2 a (a = F/m, and the spins alike with
/// the torque), v the present velocity (module doc).
#[derive(Debug, Clone, Copy)]
struct Shifts {
    force: f64,
    motion: f64,
}

/// Body k's (force-time velocity, spin, motion velocity, spin).
fn velocities(world: &World, k: usize, s: Shifts) -> ([f64; 3], [f64; 3], [f64; 3], [f64; 3]) {
    let b = &world.bodies;
    let v = b.velocity[k];
    let w = b.angular_velocity.get(k).copied().unwrap_or([0.0; 3]);
    if world.scheme != Scheme::Verlet || b.fixed[k] {
        return (v, w, v, w);
    }
    let h = 0.5 * world.dt;
    let f = b.force[k];
    let shift =
        |x: [f64; 3], by: [f64; 3], c: f64| [x[0] + c * by[0], x[1] + c * by[1], x[2] + c * by[2]];
    let a = h * b.inverse_mass[k];
    let (vf, vm) = (shift(v, f, s.force * a), shift(v, f, s.motion * a));
    let (wf, wm) = match (world.friction.is_some(), b.torque.get(k)) {
        (true, Some(&t)) => {
            let c = h * b.inverse_inertia[k];
            (shift(w, t, s.force * c), shift(w, t, s.motion * c))
        }
        _ => (w, w),
    };
    (vf, wf, vm, wm)
}

/// A body's side of a contact at velocity `v` and spin `w`.
fn side(world: &World, k: usize, v: [f64; 3], w: [f64; 3]) -> Side {
    let b = &world.bodies;
    Side {
        velocity: v,
        spin: w,
        arm: b.radius[k],
        inverse_inertia: if b.fixed[k] {
            0.0
        } else {
            b.inverse_inertia.get(k).copied().unwrap_or(0.0)
        },
    }
}

/// The powers [normal dashpots, tangential and rolling work] of main
/// list entry k, pair (i, j), W.
fn pair_power(world: &World, i: usize, j: usize, k: usize, sh: Shifts) -> [f64; 2] {
    let hist = if world.laws.history {
        world.histories.main.get(k).copied()
    } else {
        None
    };
    let t = world.shear.main.get(k).copied();
    let roll = world.shear.roll_main.get(k).copied();
    pair_power_with(world, i, j, world.bodies.position[j], (hist, t, roll), sh)
}

/// F_t·v_t + M_r·(ω₁ − ω₂) of a contact's forces `c` (on body 1) for the
/// sides' motion, W, of overlap `overlap` (m) under the law `fl`. v_t is
/// the slip with the spins at the torque's arms A
/// (`ContactLaw::torque_arm`): F_t·(v₁ − v₂ + (A₁ ω₁ + A₂ ω₂) × n) is the
/// work of F_t and its torques A n × F_t, which under `"contact_point"`
/// (A = R − δ/2) is not the spring's F_t·v_t (the spring moves at the slip
/// with R, as in LAMMPS): the difference is energy that model creates or
/// takes, and it lands in D_t.
fn tangential_power(
    c: &ContactForces,
    (fl, overlap): (&ContactLaw, f64),
    a: &Side,
    b: &Side,
    n: [f64; 3],
) -> f64 {
    let (arm1, arm2) = fl.torque_arm.arms(overlap, a.arm, b.arm);
    let vt = slip_velocity(&Side { arm: arm1, ..*a }, &Side { arm: arm2, ..*b }, n);
    let ft = c.tangential;
    let mut p = ft[0] * vt[0] + ft[1] * vt[1] + ft[2] * vt[2];
    if let Some(m) = c.rolling {
        let dw = [
            a.spin[0] - b.spin[0],
            a.spin[1] - b.spin[1],
            a.spin[2] - b.spin[2],
        ];
        p += m[0] * dw[0] + m[1] * dw[1] + m[2] * dw[2];
    }
    p
}

/// The powers of body i's wall contacts, W.
fn wall_power(world: &World, i: usize, sh: Shifts) -> [f64; 2] {
    let (b, wc) = (&world.bodies, &world.wall_contacts);
    if b.fixed[i] || world.surfaces.is_empty() || i >= wc.bodies() {
        return [0.0; 2];
    }
    let (vh, wh, v, w) = velocities(world, i, sh);
    let (x, r) = (b.position[i], b.radius[i]);
    let mut out = [0.0; 2];
    for k in wc.range(i) {
        let key = wc.key[k];
        let surface = &world.surfaces[key.wall as usize];
        let ph = surface.contact(key.element, x, vh, r);
        if ph.overlap <= 0.0 {
            continue;
        }
        let p = surface.contact(key.element, x, v, r);
        let hist = wc.history.get(k).unwrap_or(&NO_HISTORY);
        let slot = surface.law_slot(key.element);
        let Some(table) = world.friction.as_ref() else {
            let law = world.laws.wall(b, i, slot);
            out[0] += law.damping_share(ph.overlap, ph.rate, hist) * p.rate;
            continue;
        };
        let mut scratch = None;
        let fl = table.plane(&world.laws, b, i, slot, &mut scratch);
        out[0] += fl.law.damping_share(ph.overlap, ph.rate, hist) * p.rate;
        let stored = wc.shear.get(k).map_or([0.0; 6], |s| s.shear);
        let t = [stored[0], stored[1], stored[2]];
        let roll = [stored[3], stored[4], stored[5]];
        let g = ph.geometry();
        let wall = surface.side(key.element, &ph, x, r);
        let c = fl.observe_applied(
            &g,
            &side(world, i, vh, wh),
            &wall,
            hist,
            t,
            table.rolling().then_some(roll),
        );
        out[1] += tangential_power(&c, (fl, g.overlap), &side(world, i, v, w), &wall, g.normal);
    }
    out
}

impl World {
    /// The powers [normal dashpots, tangential and rolling work] of every
    /// contact at the present state, W: per body (its pairs in list order,
    /// then its walls), bodies in order; the extra pairs last.
    fn contact_powers(&self, sh: Shifts) -> [f64; 2] {
        let (b, list) = (&self.bodies, &self.list);
        let n = b.len();
        let mut total = [0.0; 2];
        if list.start.len() == n + 1 {
            for i in 0..n {
                let mut body = [0.0; 2];
                for k in list.start[i] as usize..list.start[i + 1] as usize {
                    let j = list.j[k] as usize;
                    let p = pair_power(self, i, j, k, sh);
                    body[0] += p[0];
                    body[1] += p[1];
                }
                let p = wall_power(self, i, sh);
                total[0] += body[0] + p[0];
                total[1] += body[1] + p[1];
            }
        }
        for (k, &(i, j)) in list.extra.iter().enumerate() {
            let (i, j) = (i as usize, j as usize);
            let (xj, owner) = if j < n {
                (b.position[j], j)
            } else {
                let g = j - n;
                (self.ghosts.position[g], self.ghosts.owner[g] as usize)
            };
            let p = pair_power_extra(self, i, owner, xj, k, sh);
            total[0] += p[0];
            total[1] += p[1];
        }
        total
    }

    /// After a step: adds the step's dissipation (module doc).
    pub(crate) fn account_dissipation(&mut self) {
        if self.dissipation.is_none() {
            return;
        }
        let (dt, scheme) = (self.dt, self.scheme);
        let (p, tail) = match scheme {
            // The force of step n + 1 over its whole kick, and what of it
            // falls after t_{n+1} (from v_{n+1} to v_{n+3/2}: the kinetic
            // energy is the full step's).
            Scheme::Verlet => (
                self.contact_powers(Shifts {
                    force: -1.0,
                    motion: 0.0,
                }),
                self.contact_powers(Shifts {
                    force: -1.0,
                    motion: 0.5,
                }),
            ),
            Scheme::Gear5 => (
                self.contact_powers(Shifts {
                    force: 0.0,
                    motion: 0.0,
                }),
                [0.0; 2],
            ),
        };
        if let Some(d) = self.dissipation.as_mut() {
            match scheme {
                Scheme::Verlet => {
                    d.normal += dt * p[0];
                    d.tangential_work += dt * p[1];
                    d.tail = [0.5 * dt * tail[0], 0.5 * dt * tail[1]];
                }
                Scheme::Gear5 => {
                    if let Some(last) = d.last_power {
                        d.normal += 0.5 * dt * (last[0] + p[0]);
                        d.tangential_work += 0.5 * dt * (last[1] + p[1]);
                    }
                    d.last_power = Some(p);
                }
            }
        }
    }

    /// At the start (t = 0 or a restart), after the forces: Verlet's
    /// first half kick, from v_n to v_{n+1/2} with the force of the
    /// present velocities; Gear5's power (the trapezoid's first end).
    pub(crate) fn start_dissipation(&mut self) {
        if self.dissipation.is_none() {
            return;
        }
        let (dt, scheme) = (self.dt, self.scheme);
        let p = self.contact_powers(Shifts {
            force: 0.0,
            motion: 0.5,
        });
        if let Some(d) = self.dissipation.as_mut() {
            match scheme {
                // Booked now and held back as the tail (it falls after
                // t_n): D_c is unchanged until the step.
                Scheme::Verlet => {
                    d.tail = [0.5 * dt * p[0], 0.5 * dt * p[1]];
                    d.normal += d.tail[0];
                    d.tangential_work += d.tail[1];
                }
                Scheme::Gear5 => d.last_power = Some(p),
            }
        }
    }
}

/// [`pair_power`] of extra pair k (its springs in the extra arrays).
fn pair_power_extra(
    world: &World,
    i: usize,
    j: usize,
    xj: [f64; 3],
    k: usize,
    sh: Shifts,
) -> [f64; 2] {
    let hist = if world.laws.history {
        world.histories.extra.get(k).copied()
    } else {
        None
    };
    let t = world.shear.extra.get(k).copied();
    let roll = world.shear.roll_extra.get(k).copied();
    pair_power_with(world, i, j, xj, (hist, t, roll), sh)
}

/// A pair's normal history, tangential and rolling springs, if kept.
type Springs = (Option<ContactHistory>, Option<[f64; 3]>, Option<[f64; 3]>);

/// [`pair_power`] with the contact's history and springs given.
fn pair_power_with(
    world: &World,
    i: usize,
    j: usize,
    xj: [f64; 3],
    (hist, t, roll): Springs,
    sh: Shifts,
) -> [f64; 2] {
    let b = &world.bodies;
    let xi = b.position[i];
    let d = [xj[0] - xi[0], xj[1] - xi[1], xj[2] - xi[2]];
    let r2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
    let sum = b.radius[i] + b.radius[j];
    if r2 >= sum * sum || r2 == 0.0 {
        return [0.0; 2];
    }
    let r = r2.sqrt();
    let n = [d[0] / r, d[1] / r, d[2] / r];
    let overlap = sum - r;
    let (vhi, whi, vi, wi) = velocities(world, i, sh);
    let (vhj, whj, vj, wj) = velocities(world, j, sh);
    let rate_h = overlap_rate(vhi, vhj, n);
    let rate = overlap_rate(vi, vj, n);
    let hist = hist.unwrap_or(NO_HISTORY);
    let Some(table) = world.friction.as_ref() else {
        let law = world.laws.pair(b, i, j);
        return [law.damping_share(overlap, rate_h, &hist) * rate, 0.0];
    };
    let mut scratch = None;
    let fl = table.pair(&world.laws, b, i, j, &mut scratch);
    let normal = fl.law.damping_share(overlap, rate_h, &hist) * rate;
    let g = Geometry {
        overlap,
        overlap_rate: rate_h,
        normal: n,
    };
    let roll = world.shear.rolling.then(|| roll.unwrap_or([0.0; 3]));
    let c = fl.observe_applied(
        &g,
        &side(world, i, vhi, whi),
        &side(world, j, vhj, whj),
        &hist,
        t.unwrap_or([0.0; 3]),
        roll,
    );
    [
        normal,
        tangential_power(
            &c,
            (fl, overlap),
            &side(world, i, vi, wi),
            &side(world, j, vj, wj),
            n,
        ),
    ]
}
