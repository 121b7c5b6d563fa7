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

/// Chung & Ooi (2011) Test 6, aluminium alloy (ν = 0.33), from LAMMPS
/// (29 Sep 2021 – Update 2, `pair_style granular`, `hertz/material` with
/// `damping tsuji` and `limit_damping`, `tangential mindlin` with
/// x_γt = √(4 G*/E*) = 0.8958: the tangential dashpot at the normal
/// damping ratio), by `scripts/lammps_chung_ooi_6.py`: a sphere of
/// R = 0.1 m, centre at rest tangentially, spinning so that its contact
/// point moves at v_n tan θ, on a sphere of the same material 1000 times
/// larger and not integrated, v_n = 0.2 m/s, μ = 0.4, Tsuji's α = 0.5708
/// (a clamped impact rebounds with e = 0.5; LAMMPS is given the e its
/// polynomial maps to that α, 0.2964), Δt = 5e-8 s ≈ T_c/19,000.
/// (θ in degrees, β = −v_cp'/v_cp, v_cp'/v_n'), printed to 4 decimals.
pub const LAMMPS_T6_ALLOY: [(f64, f64, f64); 17] = [
    (5.0, -0.0402, 0.0070),
    (10.0, -0.0374, 0.0132),
    (15.0, -0.0342, 0.0183),
    (20.0, -0.0301, 0.0219),
    (25.0, 0.0049, -0.0046),
    (30.0, 0.1391, -0.1607),
    (35.0, 0.2381, -0.3335),
    (40.0, 0.2148, -0.3605),
    (45.0, 0.1763, -0.3527),
    (50.0, 0.1314, -0.3131),
    (55.0, 0.0188, -0.0538),
    (60.0, -0.1221, 0.4230),
    (65.0, -0.2618, 1.1231),
    (70.0, -0.4017, 2.2074),
    (75.0, -0.5433, 4.0551),
    (80.0, -0.6883, 7.8076),
    (85.0, -0.8393, 19.1857),
];
