//! Number formatting for tables and files.

pub use dembound_core::study::sig;

/// `x` exactly (shortest text that reads back to the same `f64`), for
/// files: fixed notation for moderate magnitudes, scientific otherwise.
pub fn exact(x: f64) -> String {
    let a = x.abs();
    if x == 0.0 || !x.is_finite() || (1e-4..1e15).contains(&a) {
        x.to_string()
    } else {
        format!("{x:e}")
    }
}

/// A duration in seconds, in a readable unit.
pub fn duration(seconds: f64) -> String {
    if seconds < 1e-3 {
        format!("{} µs", sig(seconds * 1e6, 3))
    } else if seconds < 1.0 {
        format!("{} ms", sig(seconds * 1e3, 3))
    } else if seconds < 120.0 {
        format!("{} s", sig(seconds, 3))
    } else if seconds < 7200.0 {
        format!("{} min", sig(seconds / 60.0, 3))
    } else if seconds < 2.0 * 86400.0 {
        format!("{} h", sig(seconds / 3600.0, 3))
    } else {
        format!("{} days", sig(seconds / 86400.0, 3))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn significant_digits() {
        assert_eq!(sig(31.927546912345, 9), "31.9275469");
        assert_eq!(sig(-0.3132091953, 9), "-0.313209195");
        assert_eq!(sig(1234.0, 9), "1234.00000");
        assert_eq!(sig(1.5e-7, 3), "1.50e-7");
        assert_eq!(sig(0.0, 9), "0");
    }

    #[test]
    fn exact_reads_back() {
        for x in [0.1, 1e-9, 3.132091953e-1, 1e20, -2.5e-5, 0.0, 123456.789] {
            assert_eq!(exact(x).parse::<f64>().unwrap(), x);
        }
    }

    #[test]
    fn durations() {
        assert_eq!(duration(1000.0), "16.7 min");
        assert_eq!(duration(0.5), "500 ms");
    }
}
