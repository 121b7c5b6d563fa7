//! The step tables: graded step sizes per region size ([`Tables`]) and
//! where a lane's next steps come from ([`Mesh`]), the same bits as
//! [`crate::bounce::schedule`].

use crate::bounce::schedule::{graded_step, GradedSteps};

/// Graded regions of up to this many steps take their sizes from a table.
pub(super) const MAX_TABLE: u64 = 1 << 14;

/// Graded step sizes of a region of n steps, per unit length:
/// `graded_step(1.0, n, j)`, so that `length * w[j]` is
/// `graded_step(length, n, j)` to the bit.
#[derive(Default)]
pub(super) struct Tables(pub(super) Vec<(u64, Vec<f64>)>);

impl Tables {
    /// Most tables a kernel keeps, and most sizes in all (a batch with
    /// many different Δt/T_c gets tables for the first ones only).
    pub(super) const MAX_TABLES: usize = 256;
    pub(super) const MAX_SIZES: usize = 1 << 20;

    /// The table of a region of `n` steps (None above [`MAX_TABLE`] steps
    /// or when the tables are full: the sizes are then computed).
    pub(super) fn id(&mut self, n: u64) -> Option<usize> {
        if n > MAX_TABLE {
            return None;
        }
        if let Some(i) = self.0.iter().rposition(|(m, _)| *m == n) {
            return Some(i);
        }
        let held: usize = self.0.iter().map(|(_, w)| w.len()).sum();
        if self.0.len() >= Self::MAX_TABLES || held + n as usize > Self::MAX_SIZES {
            return None;
        }
        self.0
            .push((n, (0..n).map(|j| graded_step(1.0, n, j)).collect()));
        Some(self.0.len() - 1)
    }

    /// `graded_step(length, n, j)`.
    #[inline(always)]
    pub(super) fn step(&self, id: Option<usize>, length: f64, n: u64, j: u64) -> f64 {
        match id {
            Some(i) => length * self.0[i].1[j as usize],
            None => graded_step(length, n, j),
        }
    }
}

/// Where a lane's steps come from: its [`GradedSteps`] and the number of
/// the next step (`GradedSteps::next` for the Power and Uniform gradings,
/// the graded sizes from [`Tables`]).
#[derive(Clone, Copy)]
pub(super) struct Mesh {
    /// The unplanned mesh of the contact (to re-plan from).
    pub(super) start: GradedSteps,
    pub(super) steps: GradedSteps,
    pub(super) j: u64,
    pub(super) onset_table: Option<usize>,
    pub(super) end_table: Option<usize>,
}

impl Mesh {
    pub(super) fn new(start: GradedSteps, tables: &mut Tables) -> Self {
        Mesh {
            start,
            steps: start,
            j: 0,
            onset_table: if start.graded {
                tables.id(start.onset_steps)
            } else {
                None
            },
            end_table: None,
        }
    }

    /// `GradedSteps::next(self.j)` with the graded sizes from the tables,
    /// then j += 1.
    #[inline(always)]
    pub(super) fn next(&mut self, tables: &Tables) -> f64 {
        let (onset_table, end_table) = (self.onset_table, self.end_table);
        let h = self.steps.next_with(self.j, |region, is_end, n, k| {
            let table = if is_end { end_table } else { onset_table };
            tables.step(table, region, n, k)
        });
        self.j += 1;
        h
    }

    /// `GradedSteps::plan_end(tau, tau_max)` found in step number `j`:
    /// the mesh from step j + 1 on.
    pub(super) fn plan_end(&mut self, j: u64, tau: f64, tau_max: f64, tables: &mut Tables) {
        // The unplanned mesh depends on j alone but for the size of the
        // last step, which the plan may grow from.
        self.steps = self.start;
        self.j = j;
        self.next(tables);
        self.steps.plan_end(tau, tau_max);
        if self.steps.planned && self.steps.end_steps > 0 {
            self.end_table = tables.id(self.steps.end_steps);
        }
    }

    /// Whether every step from here on is Δt (until a re-plan).
    #[inline(always)]
    pub(super) fn uniform_from_here(&self) -> bool {
        let g = &self.steps;
        !g.graded
            || (!g.planned && self.j >= g.onset_steps)
            || (g.planned && g.uniform_left == 0 && g.end_left == 0 && g.last == g.dt)
    }

    /// The step sizes that follow, through `put`, up to the first of a run
    /// of Δt to the end (the sizes [`Self::next`] gives) but at most
    /// `max`; returns how many, and whether that run of Δt was reached.
    #[inline(always)]
    pub(super) fn explicit(
        &mut self,
        tables: &Tables,
        max: u64,
        mut put: impl FnMut(f64),
    ) -> (u64, bool) {
        let mut done = 0;
        loop {
            if self.uniform_from_here() {
                return (done, true);
            }
            if done == max {
                return (done, false);
            }
            let g = &mut self.steps;
            let count = max - done;
            let k;
            if !g.planned {
                k = count.min(g.onset_steps - self.j);
                let (region, n) = (g.onset_region, g.onset_steps);
                match self.onset_table {
                    Some(t) => {
                        let w = &tables.0[t].1[self.j as usize..(self.j + k) as usize];
                        for &w in w {
                            put(region * w);
                        }
                    }
                    None => {
                        for j in self.j..self.j + k {
                            put(graded_step(region, n, j));
                        }
                    }
                }
                g.last = tables.step(self.onset_table, region, n, self.j + k - 1);
            } else if g.uniform_left > 0 {
                k = count.min(g.uniform_left);
                for _ in 0..k {
                    put(g.uniform_size);
                }
                g.uniform_left -= k;
                g.last = g.uniform_size;
            } else if g.end_left > 0 {
                k = count.min(g.end_left);
                let (region, n, left) = (g.end_region, g.end_steps, g.end_left);
                match self.end_table {
                    Some(t) => {
                        let w = &tables.0[t].1[(left - k) as usize..left as usize];
                        for &w in w.iter().rev() {
                            put(region * w);
                        }
                    }
                    None => {
                        for i in (left - k..left).rev() {
                            put(graded_step(region, n, i));
                        }
                    }
                }
                g.end_left -= k;
                g.last = tables.step(self.end_table, region, n, g.end_left);
            } else {
                // Past the planned rebound: grow until it is crossed, up to
                // Δt: min(2 last, Δt) again and again, that is min(2ⁱ h, Δt)
                // (doubling is exact), computed without the chain through
                // `last`; f64::min is the plain comparison for these
                // (positive, not NaN) values.
                let (h, dt) = (g.last, g.dt);
                let mut n = 0;
                let mut scale = 2.0;
                while n < count {
                    let grown = h * scale;
                    g.last = if grown < dt { grown } else { dt };
                    put(g.last);
                    n += 1;
                    if g.last == dt {
                        break;
                    }
                    scale *= 2.0;
                }
                k = n;
            }
            done += k;
            self.j += k;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bounce::schedule::Grading;

    #[test]
    fn tabled_graded_steps_equal_the_schedules() {
        let mut tables = Tables::default();
        for (dt, t) in [(1.0, 50.0), (0.02, 1.0), (3e-9, 1.1e-7), (1.0, 1e5)] {
            let g = GradedSteps::new(dt, t, Grading::Power);
            let mut reference = g;
            let mut mesh = Mesh::new(g, &mut tables);
            let mut tau = 0.0;
            for j in 0..(g.onset_steps + 10) {
                let (a, b) = (reference.next(j), mesh.next(&tables));
                assert_eq!(a.to_bits(), b.to_bits(), "onset step {j}");
                tau += a;
            }
            // Re-plan after the step j = onset + 9 and compare the rest.
            let j = g.onset_steps + 9;
            reference.plan_end(tau, 0.55 * tau);
            mesh.plan_end(j, tau, 0.55 * tau, &mut tables);
            for k in 0..(reference.uniform_left + reference.end_steps + 5) {
                let (a, b) = (reference.next(j + 1 + k), mesh.next(&tables));
                assert_eq!(a.to_bits(), b.to_bits(), "planned step {k}");
            }
        }
    }

    #[test]
    fn filled_runs_equal_the_schedules() {
        let mut tables = Tables::default();
        for (dt, t, grading) in [
            (1.0, 50.0, Grading::Power),
            (3e-9, 1.1e-7, Grading::Power),
            (1.0, 1e5, Grading::Power),
            (0.5, 50.0, Grading::Uniform),
        ] {
            for plan_at in [3, 40, 80] {
                let g = GradedSteps::new(dt, t, grading);
                let mut reference = g;
                let mut expected = Vec::new();
                let mut tau = 0.0;
                for j in 0..plan_at {
                    expected.push(reference.next(j));
                    tau += expected[j as usize];
                }
                reference.plan_end(tau, 0.52 * tau);
                for j in plan_at..plan_at + 200 {
                    expected.push(reference.next(j));
                }
                // The same in runs of 1 to 13 steps, re-planned alike, Δt
                // after the explicit sizes.
                let mut mesh = Mesh::new(g, &mut tables);
                let mut got = Vec::new();
                let mut run = 1;
                let mut ended = false;
                while (got.len() as u64) < plan_at {
                    let count = run.min(plan_at - got.len() as u64);
                    if ended {
                        got.extend((0..count).map(|_| dt));
                    } else {
                        ended = mesh.explicit(&tables, count, |h| got.push(h)).1;
                    }
                    run = run % 13 + 4;
                }
                mesh.plan_end(plan_at - 1, tau, 0.52 * tau, &mut tables);
                ended = false;
                while got.len() < expected.len() {
                    if ended {
                        got.push(dt);
                    } else {
                        ended = mesh.explicit(&tables, run, |h| got.push(h)).1;
                    }
                    run = run % 13 + 4;
                }
                got.truncate(expected.len());
                let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
                assert_eq!(
                    bits(&got),
                    bits(&expected),
                    "{dt} {t} {grading:?} {plan_at}"
                );
            }
        }
    }
}
