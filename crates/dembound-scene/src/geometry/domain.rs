//! The box and its periodic axes.

/// An axis-aligned box, some axes periodic.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Domain {
    pub lower: [f64; 3],
    pub upper: [f64; 3],
    pub periodic: [bool; 3],
}

impl Domain {
    /// Edge lengths, m.
    pub fn length(&self) -> [f64; 3] {
        [
            self.upper[0] - self.lower[0],
            self.upper[1] - self.lower[1],
            self.upper[2] - self.lower[2],
        ]
    }

    /// `x` brought into [lower, upper) along every periodic axis.
    #[inline]
    pub fn wrap(&self, x: [f64; 3]) -> [f64; 3] {
        let mut y = x;
        let l = self.length();
        for a in 0..3 {
            if self.periodic[a] {
                let shifted = (y[a] - self.lower[a]).rem_euclid(l[a]);
                // rem_euclid may round up to exactly l.
                y[a] = self.lower[a] + if shifted >= l[a] { 0.0 } else { shifted };
            }
        }
        y
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn wrap_moves_only_periodic_axes() {
        let d = Domain {
            lower: [0.0, 0.0, 0.0],
            upper: [1.0, 2.0, 3.0],
            periodic: [true, false, true],
        };
        let w = d.wrap([1.25, -1.0, -0.5]);
        assert_eq!(w, [0.25, -1.0, 2.5]);
    }
}
