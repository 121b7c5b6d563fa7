//! A number in Rust's `{:e}` form (`1.5e-3`, `-2e10`, `0e0`) from ryu's
//! shortest round-trip digits: the same text as `format!("{x:e}")` at a
//! fraction of its cost (collisions.csv writes ~20 numbers a contact and
//! hundreds of thousands of contacts). Only the digits come from ryu; the
//! layout is rewritten here.

/// Reused buffers for [`ExpFormat::format`].
#[derive(Default)]
pub struct ExpFormat {
    ryu: ryu::Buffer,
    text: String,
}

impl ExpFormat {
    /// `x` as `format!("{x:e}")` writes it.
    pub fn format(&mut self, x: f64) -> &str {
        self.text.clear();
        if !x.is_finite() {
            // NaN, inf, -inf: rare; the formatter's own text.
            use std::fmt::Write;
            let _ = write!(self.text, "{x:e}");
            return &self.text;
        }
        if x.is_sign_negative() {
            self.text.push('-');
        }
        if x == 0.0 {
            self.text.push_str("0e0");
            return &self.text;
        }
        // ryu writes `123.45`, `0.0015`, `1.0`, `1e-7` or `1.234e20`: the
        // digits of its mantissa with the decimal point's place, then
        // an exponent when there is one.
        let shortest = self.ryu.format_finite(x.abs());
        let (mantissa, exponent) = match shortest.split_once('e') {
            Some((m, e)) => (m, e.parse::<i32>().unwrap_or(0)),
            None => (shortest, 0),
        };
        let (int_part, frac_part) = mantissa.split_once('.').unwrap_or((mantissa, ""));
        // Digits without the point, and the power of ten of the first one.
        let int_digits = int_part.trim_start_matches('0');
        let (digits, first_power): (&[u8], i32) = if !int_digits.is_empty() {
            (mantissa.as_bytes(), int_digits.len() as i32 - 1 + exponent)
        } else {
            let frac_digits = frac_part.trim_start_matches('0');
            let zeros = (frac_part.len() - frac_digits.len()) as i32;
            (frac_digits.as_bytes(), -zeros - 1 + exponent)
        };
        // The significant digits (`digits` starts at the first nonzero
        // one): the point skipped, trailing zeros dropped (ryu's shortest
        // has at most 17).
        let mut sig = [0u8; 24];
        let mut len = 0;
        for &d in digits.iter().filter(|b| b.is_ascii_digit()) {
            if len < sig.len() {
                sig[len] = d;
                len += 1;
            }
        }
        while len > 1 && sig[len - 1] == b'0' {
            len -= 1;
        }
        // Two shortest candidates can both round to `x` only from 16
        // digits on (below, the decimals are farther apart than the
        // doubles); both formatters then take the one closer to `x`, but
        // break an exact tie differently (ryu up, the standard formatter to
        // even): at a tie the standard formatter's own text is taken.
        if len >= 16 && is_decimal_tie(x.abs(), &sig[..len], first_power) {
            use std::fmt::Write;
            self.text.clear();
            let _ = write!(self.text, "{x:e}");
            return &self.text;
        }
        self.text.push(sig[0] as char);
        if len > 1 {
            self.text.push('.');
            for &b in &sig[1..len] {
                self.text.push(b as char);
            }
        }
        self.text.push('e');
        self.text.push_str(itoa_i32(first_power, &mut [0u8; 12]));
        &self.text
    }
}

/// Whether `x` lies exactly halfway between `digits` (first digit at
/// 10^`first_power`) and a neighbour with its last digit one lower or
/// higher: 2x = (2D ± 1)·10^k, D the digits as an integer and k the
/// last digit's power, tested in integers (x = m·2^e, m odd).
fn is_decimal_tie(x: f64, digits: &[u8], first_power: i32) -> bool {
    let d = digits
        .iter()
        .fold(0u128, |d, &b| d * 10 + u128::from(b - b'0'));
    let k = first_power - (digits.len() as i32 - 1);
    let bits = x.to_bits();
    let (biased, fraction) = ((bits >> 52) & 0x7ff, bits & ((1u64 << 52) - 1));
    let (mut m, mut e) = if biased == 0 {
        (fraction, -1074)
    } else {
        (fraction | (1u64 << 52), biased as i32 - 1075)
    };
    if m == 0 {
        return false;
    }
    let zeros = m.trailing_zeros();
    m >>= zeros;
    e += zeros as i32;
    // 2x = m·2^(e+1), m odd; (2D ± 1)·10^k = odd·5^k·2^k.
    let twos = e + 1;
    let power_of_five = |j: i32| (0..j).try_fold(1u128, |p, _| p.checked_mul(5));
    [2 * d - 1, 2 * d + 1].into_iter().any(|odd| {
        if k >= 0 {
            twos == k
                && power_of_five(k)
                    .and_then(|p| p.checked_mul(odd))
                    .is_some_and(|rhs| rhs == u128::from(m))
        } else {
            twos == k
                && power_of_five(-k)
                    .and_then(|p| p.checked_mul(u128::from(m)))
                    .is_some_and(|lhs| lhs == odd)
        }
    })
}

/// `n` in decimal into `buf`.
fn itoa_i32(n: i32, buf: &mut [u8; 12]) -> &str {
    let mut k = buf.len();
    let mut m = n.unsigned_abs();
    loop {
        k -= 1;
        buf[k] = b'0' + (m % 10) as u8;
        m /= 10;
        if m == 0 {
            break;
        }
    }
    if n < 0 {
        k -= 1;
        buf[k] = b'-';
    }
    std::str::from_utf8(&buf[k..]).unwrap_or("0")
}

#[cfg(test)]
mod tests {
    use super::ExpFormat;
    use rand::{Rng, SeedableRng};

    /// The reference is the standard library's `{:e}` (an independent
    /// implementation: Grisu with a Dragon fallback); exact text equality,
    /// no tolerance: the file must stay byte for byte what it was.
    fn same(f: &mut ExpFormat, x: f64) {
        assert_eq!(f.format(x), format!("{x:e}"), "bits {:#018x}", x.to_bits());
    }

    #[test]
    fn special_and_boundary_values_read_as_the_standard_formatter_writes_them() {
        let mut f = ExpFormat::default();
        let specials = [
            0.0,
            -0.0,
            1.0,
            -1.0,
            10.0,
            100.0,
            0.1,
            0.3,
            1.5e-3,
            123.45,
            1e-7,
            1e16,
            1e21,
            1e22,
            1e23,
            1.234e20,
            1e23 - 1e7,
            f64::MIN_POSITIVE,
            f64::MIN_POSITIVE / 3.0,
            5e-324,
            f64::MAX,
            f64::MIN,
            f64::EPSILON,
            f64::NAN,
            f64::INFINITY,
            f64::NEG_INFINITY,
            2.0e-5,
            1.0 / 3.0,
            // An exact tie at 16 digits (…469.25): ryu rounds it up, the
            // standard formatter to even.
            f64::from_bits(0xc30280bd21d883ea),
        ];
        for x in specials {
            same(&mut f, x);
            same(&mut f, -x);
        }
        for p in -325..=308 {
            let x = 10f64.powi(p);
            same(&mut f, x);
            same(&mut f, x * 1.5);
            same(&mut f, x * 9.99);
        }
    }

    #[test]
    fn random_bit_patterns_and_engine_like_values_read_as_the_standard_formatter_writes_them() {
        let mut f = ExpFormat::default();
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(20_261_128);
        for _ in 0..400_000 {
            // Every exponent and mantissa equally likely.
            same(&mut f, f64::from_bits(rng.gen::<u64>()));
            // The log's own range: times, overlaps, speeds.
            same(
                &mut f,
                rng.gen_range(-1.0..1.0) * 10f64.powi(rng.gen_range(-12..4)),
            );
        }
    }
}
