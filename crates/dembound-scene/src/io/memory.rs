//! The memory a scene will need, checked before its spheres are made: a
//! scene that cannot fit is refused with the estimate and the count (bad
//! input: the CLI exits 2) instead of aborting the process on a failed
//! allocation (a 10⁸-sphere lattice, within the lattice's own maximum,
//! asked for 8.8 GB at once and ended in SIGABRT).
//!
//! The bytes per sphere are measured: the peak resident memory of
//! `dembound scene --out` (one thread, two steps, a dense lattice of
//! spheres 1 % apart, so that each has its 6 lattice neighbours in its
//! list; the snapshots and the checkpoint written) at 5·10⁵ and 10⁶
//! spheres, the difference divided by 5·10⁵:
//! - Verlet without friction: 271,968 kB and 518,080 kB → 504 B a sphere
//!   (380 B without `--out`);
//! - Gear5 with Mindlin and rolling friction: 490,364 kB and 948,388 kB
//!   → 938 B a sphere.
//!
//! These runs listed every sphere (88 B each, [`LISTED_BYTES_PER_SPHERE`])
//! while the engine's arrays were made. A lattice group is now kept as its
//! formula and never listed (`crate::spheres`), so a lattice sphere is
//! charged the engine's bytes only (the measurement less the list's 88 B);
//! every other source (random, CSV, data files, inline lists, walls) is
//! still listed and charged the list too. For comparison, the 10⁷-sphere
//! lattice drop (one thread, 100 steps, no `--out`, BENCHMARKS.md) peaks at
//! 262 B a sphere frictionless and 390 B with Hertz–Mindlin friction.
//!
//! The estimate rounds these up by ~10 % (looser packings list more
//! neighbours) and is compared with the memory the system reports
//! available (`MemAvailable` of `/proc/meminfo`); where that is not
//! known, nothing is refused.

use crate::setup::SphereInit;
use crate::SceneError;

/// Bytes of one listed sphere ([`SphereInit`]: 3 + 3 + 1 doubles, a
/// material index, the fixed flag and an optional wall index: 88 B).
pub const LISTED_BYTES_PER_SPHERE: u64 = std::mem::size_of::<SphereInit>() as u64;
/// Bytes a listed sphere needs, Verlet without friction (measured 504 B).
pub const BYTES_PER_SPHERE: u64 = 560;
/// Bytes a listed sphere needs with Gear5 or friction (measured 938 B for
/// both).
pub const BYTES_PER_SPHERE_GEAR5_OR_FRICTION: u64 = 1040;

/// Spheres to charge: those listed one by one and those of lattice groups
/// (made when read, never listed).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct SphereCount {
    /// Spheres held in a list (random, CSV, data files, inline, walls).
    pub listed: u64,
    /// Spheres of lattice groups.
    pub lattice: u64,
}

impl SphereCount {
    /// All of them.
    pub fn total(&self) -> u64 {
        self.listed.saturating_add(self.lattice)
    }

    /// Each part divided among `ranks` (rounded up): one rank's share.
    pub fn share(&self, ranks: u64) -> Self {
        let ranks = ranks.max(1);
        Self {
            listed: self.listed.div_ceil(ranks),
            lattice: self.lattice.div_ceil(ranks),
        }
    }
}

/// Bytes a listed sphere needs.
fn listed_bytes(gear5_or_friction: bool) -> u64 {
    if gear5_or_friction {
        BYTES_PER_SPHERE_GEAR5_OR_FRICTION
    } else {
        BYTES_PER_SPHERE
    }
}

/// Bytes a lattice sphere needs: a listed one's without the list.
fn lattice_bytes(gear5_or_friction: bool) -> u64 {
    listed_bytes(gear5_or_friction) - LISTED_BYTES_PER_SPHERE
}

/// The memory `count` spheres need, bytes.
pub fn estimate(count: SphereCount, gear5_or_friction: bool) -> u64 {
    count
        .listed
        .saturating_mul(listed_bytes(gear5_or_friction))
        .saturating_add(
            count
                .lattice
                .saturating_mul(lattice_bytes(gear5_or_friction)),
        )
}

/// The memory available to a new allocation, bytes (`MemAvailable` of
/// `/proc/meminfo`; `None` where unknown).
pub fn available() -> Option<u64> {
    let text = std::fs::read_to_string("/proc/meminfo").ok()?;
    parse_meminfo(&text)
}

fn parse_meminfo(text: &str) -> Option<u64> {
    let line = text.lines().find(|l| l.starts_with("MemAvailable:"))?;
    let mut words = line.split_whitespace().skip(1);
    let value: u64 = words.next()?.parse().ok()?;
    match words.next() {
        Some("kB") => value.checked_mul(1024),
        None => Some(value),
        Some(_) => None,
    }
}

/// Refuses `count` spheres (`what`: where they come from) when their
/// estimate exceeds `available` bytes.
pub fn check(
    count: SphereCount,
    gear5_or_friction: bool,
    what: &str,
    available: Option<u64>,
) -> Result<(), SceneError> {
    let Some(available) = available else {
        return Ok(());
    };
    let need = estimate(count, gear5_or_friction);
    if need <= available {
        return Ok(());
    }
    let gb = |b: u64| b as f64 / 1e9;
    let total = count.total();
    // The spheres of this mix that fit: available × total / need.
    let fit = (available as u128 * total as u128 / need.max(1) as u128) as u64;
    Err(SceneError::input(format!(
        "{what}: {total} spheres need about {:.3} GB of memory ({} bytes a listed sphere, {} a \
         lattice one{}; {} listed, {} of lattices), more than the {:.3} GB this machine has \
         available (MemAvailable); allowed: a scene that fits, at most about {fit} spheres here",
        gb(need),
        listed_bytes(gear5_or_friction),
        lattice_bytes(gear5_or_friction),
        if gear5_or_friction {
            " with Gear5 or friction"
        } else {
            ""
        },
        count.listed,
        count.lattice,
        gb(available),
    )))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn meminfo_is_read_in_kilobytes() {
        let text =
            "MemTotal:       24000000 kB\nMemFree:         1000 kB\nMemAvailable:   2000000 kB\n";
        assert_eq!(parse_meminfo(text), Some(2_048_000_000));
        assert_eq!(parse_meminfo("MemTotal: 1 kB\n"), None);
    }

    #[test]
    fn the_estimate_is_refused_over_the_available_memory() {
        // 10⁸ listed spheres at 560 B: 56 GB, over 24 GB.
        let listed = SphereCount {
            listed: 100_000_000,
            lattice: 0,
        };
        let e = check(
            listed,
            false,
            "particles[0].random.count = 100000000",
            Some(24_000_000_000),
        )
        .unwrap_err()
        .to_string();
        assert!(
            e.contains("100000000 spheres") && e.contains("56.000 GB"),
            "{e}"
        );
        assert!(
            e.contains("particles[0].random.count") && e.contains("24.000 GB"),
            "{e}"
        );
        let million = SphereCount {
            listed: 1_000_000,
            lattice: 0,
        };
        assert!(check(million, true, "x", Some(2_000_000_000)).is_ok());
        let all = SphereCount {
            listed: u64::MAX,
            lattice: u64::MAX,
        };
        assert!(check(all, true, "x", None).is_ok());
    }

    #[test]
    fn a_listed_sphere_is_88_bytes() {
        // SphereInit: position and velocity 3 × 8 B each, radius 8 B,
        // material (usize) 8 B, fixed 1 B (padded to 8 with the layout's
        // alignment of 8), group Option<usize> 16 B: 24 + 24 + 8 + 8 + 8 + 16.
        assert_eq!(LISTED_BYTES_PER_SPHERE, 88);
    }

    #[test]
    fn a_lattice_sphere_is_charged_without_the_list() {
        // 10⁶ spheres, 500 MB available. Listed: 10⁶ × 560 B = 560 MB,
        // refused; a lattice's: 10⁶ × (560 − 88) B = 472 MB, accepted.
        // With friction: 10⁶ × 1040 B = 1.04 GB against 10⁶ × 952 B;
        // 1.0 GB available lies between them.
        let n = 1_000_000;
        let lattice = SphereCount {
            listed: 0,
            lattice: n,
        };
        let listed = SphereCount {
            listed: n,
            lattice: 0,
        };
        assert_eq!(estimate(lattice, false), 472_000_000);
        assert_eq!(estimate(listed, false), 560_000_000);
        assert_eq!(estimate(lattice, true), 952_000_000);
        assert_eq!(estimate(listed, true), 1_040_000_000);
        assert!(check(lattice, false, "x", Some(500_000_000)).is_ok());
        let e = check(listed, false, "x", Some(500_000_000))
            .unwrap_err()
            .to_string();
        // 500 MB / 560 B = 892,857 spheres fit.
        assert!(
            e.contains("0.560 GB") && e.contains("at most about 892857 spheres"),
            "{e}"
        );
        assert!(check(lattice, true, "x", Some(1_000_000_000)).is_ok());
        assert!(check(listed, true, "x", Some(1_000_000_000)).is_err());
        // Half and half: 5·10⁵ × 560 + 5·10⁵ × 472 = 516 MB.
        let mixed = SphereCount {
            listed: n / 2,
            lattice: n / 2,
        };
        assert_eq!(estimate(mixed, false), 516_000_000);
        // Two ranks: each holds half of each part, rounded up.
        assert_eq!(
            SphereCount {
                listed: 3,
                lattice: 5
            }
            .share(2),
            SphereCount {
                listed: 2,
                lattice: 3
            }
        );
    }
}
