//! The batched path gives the scalar path's records to the last bit.
use dembound_core::bounce::batch::{simulate_batch_with, Isa};
use dembound_core::bounce::{simulate, Scenario, Stepping};
use dembound_core::contact::{ContactLawKind, DampingKind};
use dembound_core::integrate::Scheme;

/// xorshift64*, deterministic.
struct Rng(u64);
impl Rng {
    fn next(&mut self) -> f64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        (self.0.wrapping_mul(0x2545_f491_4f6c_dd1d) >> 11) as f64 / (1u64 << 53) as f64
    }
    fn log(&mut self, lo: f64, hi: f64) -> f64 {
        lo * (hi / lo).powf(self.next())
    }
}

/// Cases of varied pairs, speeds and steps; most batchable, some not.
fn cases(n: usize, seed: u64) -> Vec<Scenario> {
    let mut rng = Rng(seed);
    (0..n)
        .map(|i| {
            let mut s = Scenario::default();
            s.contact.law = if rng.next() < 0.5 {
                ContactLawKind::Hertz
            } else {
                ContactLawKind::Linear
            };
            s.boundary.radius_ratio = rng.log(0.5, 1e4);
            s.boundary.modulus_ratio = rng.log(0.1, 1e4);
            s.particle.radius = rng.log(1e-4, 1e-2);
            s.motion.gap = rng.log(1e-5, 1e-2);
            s.motion.velocity = if rng.next() < 0.3 {
                -rng.log(0.01, 3.0)
            } else {
                0.0
            };
            s.motion.contacts = 1 + (rng.next() * 4.0) as u32;
            s.integration.eta = Some(rng.log(0.002, 0.1));
            match i % 10 {
                7 => s.integration.scheme = Scheme::Verlet,
                8 => {
                    s.integration.stepping = Stepping::Fixed;
                    s.motion.gap = 1e-5;
                    s.integration.eta = Some(0.05);
                }
                9 => {
                    s.contact.law = ContactLawKind::Hertz;
                    s.contact.damping = DampingKind::Tsuji;
                    s.contact.restitution = Some(0.7);
                }
                5 => {
                    s.integration.eta = None;
                    s.integration.tolerance = Some(1e-9);
                }
                6 if i % 20 == 6 => s.motion.gap = -1.0, // invalid: an error
                _ => {}
            }
            s
        })
        .collect()
}

#[test]
fn batched_records_equal_the_scalar_ones_bit_for_bit() {
    let scenarios = cases(300, 0x5eed);
    let scalar: Vec<_> = scenarios.iter().map(|s| simulate(s, &mut ())).collect();
    for isa in [Isa::Avx512, Isa::Avx2, Isa::Baseline] {
        if !isa.available() {
            continue;
        }
        let batched = simulate_batch_with(&scenarios, isa);
        assert_eq!(batched.len(), scalar.len());
        for (i, (b, s)) in batched.iter().zip(&scalar).enumerate() {
            // PartialEq on f64 fields: bit-identical except ±0 and NaN,
            // which no record holds; compare the bits too.
            assert_eq!(b, s, "{isa:?} case {i}");
            if let (Ok(b), Ok(s)) = (b, s) {
                for (x, y) in b.contacts.iter().zip(&s.contacts) {
                    assert_eq!(format!("{x:?}"), format!("{y:?}"), "{isa:?} case {i}");
                }
            }
        }
    }
}

#[test]
fn an_empty_batch_is_empty() {
    assert!(simulate_batch_with(&[], Isa::detect()).is_empty());
}
