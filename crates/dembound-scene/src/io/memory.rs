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
//! The estimate rounds these up by ~10 % (looser packings list more
//! neighbours) and is compared with the memory the system reports
//! available (`MemAvailable` of `/proc/meminfo`); where that is not
//! known, nothing is refused.

use crate::SceneError;

/// Bytes a sphere needs, Verlet without friction (measured 504 B).
pub const BYTES_PER_SPHERE: u64 = 560;
/// Bytes a sphere needs with Gear5 or friction (measured 938 B for both).
pub const BYTES_PER_SPHERE_GEAR5_OR_FRICTION: u64 = 1040;

/// The memory `count` spheres need, bytes.
pub fn estimate(count: u64, gear5_or_friction: bool) -> u64 {
    let per = if gear5_or_friction {
        BYTES_PER_SPHERE_GEAR5_OR_FRICTION
    } else {
        BYTES_PER_SPHERE
    };
    count.saturating_mul(per)
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
    count: u64,
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
    Err(SceneError::input(format!(
        "{what}: {count} spheres need about {:.3} GB of memory ({} bytes a sphere{}), more than \
         the {:.3} GB this machine has available (MemAvailable); allowed: a scene that fits, \
         at most about {} spheres here",
        gb(need),
        if gear5_or_friction {
            BYTES_PER_SPHERE_GEAR5_OR_FRICTION
        } else {
            BYTES_PER_SPHERE
        },
        if gear5_or_friction {
            " with Gear5 or friction"
        } else {
            ""
        },
        gb(available),
        available
            / if gear5_or_friction {
                BYTES_PER_SPHERE_GEAR5_OR_FRICTION
            } else {
                BYTES_PER_SPHERE
            }
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
        // 10⁸ spheres at 560 B: 56 GB, over 24 GB.
        let e = check(
            100_000_000,
            false,
            "particles[0].lattice",
            Some(24_000_000_000),
        )
        .unwrap_err()
        .to_string();
        assert!(
            e.contains("100000000 spheres") && e.contains("56.000 GB"),
            "{e}"
        );
        assert!(
            e.contains("particles[0].lattice") && e.contains("24.000 GB"),
            "{e}"
        );
        assert!(check(1_000_000, true, "x", Some(2_000_000_000)).is_ok());
        assert!(check(u64::MAX, true, "x", None).is_ok());
    }
}
