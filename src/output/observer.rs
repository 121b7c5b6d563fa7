//! Combining observers.

use dembound_core::bounce::{Observer, Sample};

/// Two observers watching one run.
pub struct Tee<'a, A, B>(pub &'a mut A, pub &'a mut B);

impl<A: Observer, B: Observer> Observer for Tee<'_, A, B> {
    const ACTIVE: bool = A::ACTIVE || B::ACTIVE;

    fn sample(&mut self, sample: &Sample) {
        if A::ACTIVE {
            self.0.sample(sample);
        }
        if B::ACTIVE {
            self.1.sample(sample);
        }
    }

    fn flight_samples(&self) -> usize {
        self.0.flight_samples().max(self.1.flight_samples())
    }

    fn progress(&mut self, t: f64, t_end: f64) {
        self.0.progress(t, t_end);
        self.1.progress(t, t_end);
    }
}
