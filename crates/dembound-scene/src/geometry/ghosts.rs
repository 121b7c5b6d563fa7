//! The ghost layer: images of bodies across periodic faces. The only place
//! that knows about space beyond the box; a domain decomposition would
//! fill it from the neighbouring ranks instead.

use super::domain::Domain;

/// Ghost images of real bodies. A ghost's extended index is `n + k`, n
/// the number of real bodies.
#[derive(Debug, Clone, Default)]
pub struct Ghosts {
    /// The real body each ghost is an image of.
    pub owner: Vec<u32>,
    /// Image shift, m (a multiple of the box lengths).
    pub shift: Vec<[f64; 3]>,
    pub position: Vec<[f64; 3]>,
    pub velocity: Vec<[f64; 3]>,
}

impl Ghosts {
    /// Images of every body within `width` of a periodic face (corner and
    /// edge images included), skipping bodies for which `skip` is true.
    pub fn build(
        domain: &Domain,
        position: &[[f64; 3]],
        width: f64,
        skip: impl Fn(usize) -> bool,
    ) -> Self {
        let mut g = Ghosts::default();
        if !domain.periodic.iter().any(|&p| p) {
            return g;
        }
        let len = domain.length();
        for (k, x) in position.iter().enumerate() {
            if skip(k) {
                continue;
            }
            let mut options: [[f64; 3]; 3] = [[0.0; 3]; 3];
            let mut counts = [1usize; 3];
            for a in 0..3 {
                if !domain.periodic[a] {
                    continue;
                }
                if x[a] - domain.lower[a] < width {
                    options[a][counts[a]] = len[a];
                    counts[a] += 1;
                }
                if domain.upper[a] - x[a] < width {
                    options[a][counts[a]] = -len[a];
                    counts[a] += 1;
                }
            }
            for i in 0..counts[0] {
                for j in 0..counts[1] {
                    for l in 0..counts[2] {
                        if i == 0 && j == 0 && l == 0 {
                            continue;
                        }
                        let s = [options[0][i], options[1][j], options[2][l]];
                        g.owner.push(k as u32);
                        g.shift.push(s);
                        g.position.push([x[0] + s[0], x[1] + s[1], x[2] + s[2]]);
                        g.velocity.push([0.0; 3]);
                    }
                }
            }
        }
        g
    }

    pub fn len(&self) -> usize {
        self.owner.len()
    }

    pub fn is_empty(&self) -> bool {
        self.owner.is_empty()
    }

    /// Positions and velocities from the owners.
    pub fn update(&mut self, position: &[[f64; 3]], velocity: &[[f64; 3]]) {
        for k in 0..self.owner.len() {
            let o = self.owner[k] as usize;
            let s = self.shift[k];
            let x = position[o];
            self.position[k] = [x[0] + s[0], x[1] + s[1], x[2] + s[2]];
            self.velocity[k] = velocity[o];
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn corner_body_has_three_images() {
        let d = Domain {
            lower: [0.0; 3],
            upper: [1.0; 3],
            periodic: [true, true, false],
        };
        let g = Ghosts::build(&d, &[[0.05, 0.05, 0.5], [0.5, 0.5, 0.5]], 0.1, |_| false);
        assert_eq!(g.len(), 3);
        assert!(g.owner.iter().all(|&o| o == 0));
        assert!(g.position.contains(&[1.05, 1.05, 0.5]));
    }
}
