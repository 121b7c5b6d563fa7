//! Results of another code for the same contact model, where a
//! publication's curve and ours part: the benchmark then tells the model
//! (the other code agrees with us) from a bug (it agrees with the paper).

/// Chung & Ooi (2011) Test 5, steel (ν = 0.3), from LAMMPS
/// (29 Sep 2021 – Update 2, `pair_style granular`, `hertz/material`
/// with `tangential mindlin`: k_t = 8 G* a, force −k_t ξ from the stored
/// displacement cut back to μ F_n, no damping), by
/// `scripts/lammps_chung_ooi_5.py`: a sphere of R = 1e-5 m on a sphere of
/// the same material 1000 times larger and not integrated (a plane up to
/// R/R₂ = 1e-3), v_n = 5 m/s, μ = 0.3, Δt = 2.5e-12 s ≈ T_c/20,000.
/// (ψ₁ = v_t/(μ v_n), ψ₂ = v_cp'/(μ v_n'), R ω'/(μ v_n)), at the
/// digitised curve's abscissae up to ψ₁ = 6 (the sticking range; beyond,
/// the closed form is the reference), printed to 4 decimals.
pub const LAMMPS_T5_STEEL: [(f64, f64, f64); 13] = [
    (0.0664652567975832, 0.0633, -0.0023),
    (0.3323262839879155, 0.3159, -0.0117),
    (0.6706948640483383, 0.6257, -0.0321),
    (1.0090634441087611, 0.6531, -0.2539),
    (1.3353474320241694, 0.3565, -0.6984),
    (1.6616314199395772, 0.0314, -1.1631),
    (2.0, -0.2838, -1.6294),
    (2.350453172205438, -0.5741, -2.0866),
    (2.990936555891238, -1.0016, -2.8485),
    (3.3413897280966762, -1.1785, -3.2248),
    (4.006042296072506, -1.4012, -3.8581),
    (4.996978851963746, -1.4324, -4.5876),
    (6.0, -0.9666, -4.9712),
];
