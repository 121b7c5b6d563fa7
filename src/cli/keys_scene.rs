//! `dembound keys --scene`: every key of a scene file (`dembound scene`)
//! with its unit, default and allowed range (issue 24). The ranges are the
//! constants the scene's validation checks ([`dembound_scene::limits`],
//! `io::config`), so the table cannot drift from them; the README's scene
//! key table is this command's output (asserted by a test).

use super::keys::{law_parameter_rows, KeyInfo};
use dembound_physics::contact::tangential::rotation::SPRING_ROTATION_NAMES;
use dembound_physics::contact::tangential::tangential_names;
use dembound_physics::contact::torque_arm::TORQUE_ARM_NAMES;
use dembound_scene::io::config::MAX_STEPS;
use dembound_scene::limits::{self, describe, show};
use dembound_scene::setup_checks::radius_range;
use dembound_scene::time_step::{
    GEAR5_DAMPED_MAX_STEP_RATIO, GEAR5_MAX_STEP_RATIO, VERLET_MAX_STEP_RATIO,
};

/// The largest Δt/T_b of each scheme, as the time-step rule checks them,
/// and Gear5's closed-form bound on each damped pair
/// (`setup_checks::check_damped_gear5`).
fn step_ratios() -> String {
    let damped = dembound_physics::integrate::gear5::Gear5::for_force(true).damped_stability();
    format!(
        "{} (verlet), {} (gear5), {} (gear5 with damping; and each damped pair's \
         (ωΔt/{:.3})² + βΔt/{:.3} ≤ 1)",
        show(VERLET_MAX_STEP_RATIO),
        show(GEAR5_MAX_STEP_RATIO),
        show(GEAR5_DAMPED_MAX_STEP_RATIO),
        damped.omega_step,
        damped.rate_step
    )
}

/// Every scene key, in file order of the sections.
pub fn keys() -> Vec<KeyInfo> {
    let row = |key: &'static str,
               unit: &'static str,
               default: &str,
               allowed: String,
               meaning: &'static str| KeyInfo {
        key: key.into(),
        unit: unit.into(),
        default: default.to_string(),
        allowed,
        meaning: meaning.into(),
    };
    let radius = describe(limits::RADIUS, "");
    let fixed_radius = describe(radius_range(true), "");
    let speed = format!("finite, \\|v\\| ≤ {}", show(limits::MAX_SPEED));
    let mu = describe(limits::FRICTION, "");
    let mu_r = describe(limits::ROLLING_FRICTION, "");
    let finite3 = || "three finite numbers".to_string();
    let ratio_inf = |r: (f64, f64)| format!("{}, or inf", describe(r, ""));
    let mut rows = vec![
        row(
            "domain.lower",
            "m",
            "—",
            finite3(),
            "the box's lower corner",
        ),
        row(
            "domain.upper",
            "m",
            "—",
            "finite, > domain.lower on each axis".into(),
            "the box's upper corner",
        ),
        row(
            "domain.periodic",
            "",
            "[false, false, false]",
            "three booleans".into(),
            "periodic axes (no wall may cross one)",
        ),
        row(
            "domain.outside",
            "",
            "\"error\"",
            "\"error\", \"keep\" or \"delete\"".into(),
            "a free sphere lost for good along a non-periodic axis (wholly outside the box grown to hold the fixed spheres, moving away, gravity not bringing it back: one thrown out through an open top that falls back is not lost) stops the run (exit 2 naming the sphere, the step and its position; no output written; checked at each series row and at the end), goes on unreported, or is removed at the next neighbour-list rebuild once it touches nothing (counted: --json deleted_particles, deleted_mass, energy_balance.carried_out_energy; series.csv deleted_particles, deleted_mass_kg, carried_out_energy_J; the same spheres at the same steps on any number of threads or MPI ranks)",
        ),
        row(
            "outlet[K].region.box.lower",
            "m",
            "—",
            finite3(),
            "an outlet's lower corner: a free sphere whose centre is inside the box (faces included) is removed at the next neighbour-list rebuild once it touches nothing, like a lost sphere under domain.outside = \"delete\" (counted per outlet: --json outlets[K].count, mass, steady_rate and steady_rate_error, the mean mass flow rate over the series intervals of the run's second half and its standard error, kg/s; series.csv outletK_removed, outletK_mass_kg, outletK_rate_kg_per_s; the energy it carries out booked as carried_out_energy)",
        ),
        row(
            "outlet[K].region.box.upper",
            "m",
            "—",
            "finite, > the lower corner on each axis".into(),
            "an outlet's upper corner",
        ),
        row(
            "outlet[K].region.cylinder",
            "m",
            "—",
            "center finite, axis finite and non-zero, radius and length finite and > 0".into(),
            "an outlet's cylinder instead of a box: { center, axis, radius, length }, center the middle of its axis segment of that length (the region type of inlet[K].region); a free sphere whose centre is inside it (surface included) is removed as by a box",
        ),
        row(
            "inlet[K].region.box.lower / .upper",
            "m",
            "—",
            "finite, inside the domain, upper > lower on each axis".into(),
            "an inlet's box (or region.cylinder = { center, axis, radius, length } in m): spheres inserted during the run lie wholly inside it, overlapping nothing (spheres, boundary particles, the walls acting at the insertion step: a wall outside its active window is no obstacle, and one that switches on later over inserted spheres books the energy of their overlaps as gate_energy); insertion events every inlet[K].every steps, each inserting the spheres due by the end of its interval (cumulative rounding: round(rate · t) in all); the same spheres on any number of threads and MPI ranks; a checkpoint restarts them (not yet under mpirun) (--json inlets[K].inserted, mass, not_placed; series.csv inletK_inserted, inletK_mass_kg, brought_in_energy_J; energy_balance.brought_in_energy)",
        ),
        row(
            "inlet[K].rate.number / .mass",
            "1/s or kg/s",
            "—",
            "finite, > 0; the sphere volume per event ≤ 0.2 × the region's volume".into(),
            "spheres per second, or kilograms per second (turned into spheres/s by the mean sphere mass of the size distribution)",
        ),
        row(
            "inlet[K].size",
            "m",
            "—",
            "fixed = R, uniform = [Rmin, Rmax], normal = { mean, std, min, max } or table = [[R, fraction], …]; radii > 0".into(),
            "the radius distribution (table fractions by number, normalised to their sum; the normal truncated to [min, max] by redrawing)",
        ),
        row(
            "inlet[K].material",
            "",
            "—",
            "a [[material]] name of finite density".into(),
            "the inserted spheres' material",
        ),
        row(
            "inlet[K].velocity",
            "m/s",
            "[0, 0, 0]",
            "finite".into(),
            "the inserted spheres' velocity",
        ),
        row(
            "inlet[K].start / .end",
            "s",
            "0 / the run's end",
            "start ≥ 0, end > start".into(),
            "when the inlet inserts",
        ),
        row(
            "inlet[K].seed",
            "",
            "0",
            "an integer ≥ 0".into(),
            "the draws: ChaCha8 of this seed on a stream keyed by the inlet's index and the event number",
        ),
        row(
            "inlet[K].every",
            "steps",
            "the time the rate brings 0.05 of the region's volume, at most 1/100 of the insertion window, at least 1 step",
            "1 to 1e9".into(),
            "steps between insertion events (each forces a neighbour-list rebuild)",
        ),
        row(
            "inlet[K].max_attempts",
            "",
            "100",
            "1 to 1e6".into(),
            "centres tried per sphere; a sphere none of them fits is not placed, counted (not_placed) and warned about",
        ),
        row(
            "material[K].name",
            "",
            "—",
            "unique, not \"rigid\"".into(),
            "a particle material",
        ),
        row(
            "material[K].density",
            "kg/m³",
            "—",
            describe(limits::DENSITY, ""),
            "ρ",
        ),
        row(
            "material[K].youngs_modulus",
            "Pa",
            "—",
            ratio_inf(limits::YOUNGS_MODULUS),
            "E (inf: rigid)",
        ),
        row(
            "material[K].poisson_ratio",
            "",
            "—",
            format!(
                "{} < ν < {}",
                limits::POISSON_RATIO.0,
                limits::POISSON_RATIO.1
            ),
            "ν",
        ),
        row(
            "material[K].friction",
            "",
            "contact.friction",
            mu.clone(),
            "the surface's μ",
        ),
        row(
            "material[K].rolling_friction",
            "",
            "contact.rolling_friction",
            mu_r.clone(),
            "the surface's μ_r",
        ),
        row(
            "contact.law",
            "",
            "\"hertz\"",
            "a registry law, or { power = α } (`dembound keys`)".into(),
            "normal contact law",
        ),
        row(
            "contact.law.power",
            "",
            "—",
            "1 ≤ α ≤ 3".into(),
            "the power law's exponent",
        ),
        row(
            "contact.damping",
            "",
            "\"none\"",
            "\"none\", \"viscous\", \"tsuji\", \"viscoelastic\"".into(),
            "dissipation",
        ),
        row(
            "contact.restitution",
            "",
            "none",
            "0 < e ≤ 1 (viscoelastic: calibration = \"formula\", 0.8 ≤ e ≤ 1)".into(),
            "target restitution",
        ),
        row(
            "contact.calibration",
            "",
            "\"exact\"",
            "\"exact\", \"formula\"".into(),
            "restitution → coefficient",
        ),
        row(
            "contact.damping_coefficient",
            "N s/m, N s/m^(5/4) or s",
            "none",
            "finite, ≥ 0; instead of restitution".into(),
            "c, γ or A",
        ),
        row(
            "contact.attractive",
            "",
            "false",
            "true, false (not with walton-braun)".into(),
            "may the damping pull",
        ),
        row(
            "contact.friction",
            "",
            "0",
            mu.clone(),
            "μ of every surface (Coulomb)",
        ),
        row(
            "contact.tangential",
            "",
            "\"mindlin\"",
            tangential_names(),
            "tangential spring",
        ),
        row(
            "contact.rolling_friction",
            "",
            "0",
            mu_r.clone(),
            "μ_r (elastic–plastic rolling spring)",
        ),
        row(
            "contact.tangential_damping",
            "",
            "true",
            "true, false (with friction)".into(),
            "tangential dashpot",
        ),
        row(
            "contact.torque_arm",
            "",
            "\"radius\"",
            format!(
                "{} (with friction)",
                TORQUE_ARM_NAMES
                    .iter()
                    .map(|name| format!("\"{name}\""))
                    .collect::<Vec<_>>()
                    .join(", ")
            ),
            "lever arm of the tangential torque",
        ),
        row(
            "contact.spring_rotation",
            "",
            "\"rescale\"",
            format!(
                "{} (with friction)",
                SPRING_ROTATION_NAMES
                    .iter()
                    .map(|name| format!("\"{name}\""))
                    .collect::<Vec<_>>()
                    .join(", ")
            ),
            "how the tangential spring follows a turning normal",
        ),
        row(
            "particles[K].material",
            "",
            "—",
            "a material name (\"rigid\" with fixed)".into(),
            "the group's material",
        ),
        row(
            "particles[K].fixed",
            "",
            "false",
            "true, false".into(),
            "boundary particles: never move (unless motion)",
        ),
        row(
            "particles[K].motion",
            "",
            "—",
            "the keys of wall[K].motion; only with fixed = true".into(),
            "the group moves as one rigid body",
        ),
        row(
            "particles[K].oscillation",
            "",
            "—",
            "the keys of wall[K].oscillation; only with fixed = true".into(),
            "the group's sinusoidal translation",
        ),
        row(
            "particles[K].spheres[J].position",
            "m",
            "—",
            finite3(),
            "inline sphere's centre",
        ),
        row(
            "particles[K].spheres[J].radius",
            "m",
            "—",
            format!("{radius} ({fixed_radius} if fixed)"),
            "inline sphere's radius",
        ),
        row(
            "particles[K].spheres[J].velocity",
            "m/s",
            "[0, 0, 0]",
            speed.clone(),
            "inline sphere's velocity",
        ),
        row(
            "particles[K].lammps_data",
            "",
            "—",
            "a LAMMPS data file (atom_style sphere)".into(),
            "spheres from LAMMPS",
        ),
        row(
            "particles[K].types",
            "",
            "—",
            "{ \"TYPE\" = material }".into(),
            "material per atom type",
        ),
        row(
            "particles[K].csv",
            "",
            "—",
            "a CSV file x,y,z,radius[,vx,vy,vz]".into(),
            "spheres from CSV",
        ),
        row(
            "particles[K].lattice.counts",
            "",
            "—",
            "three counts ≥ 1".into(),
            "nx, ny, layers",
        ),
        row(
            "particles[K].lattice.spacing",
            "m",
            "—",
            "finite, > 0, no overlap".into(),
            "ax, ay, c",
        ),
        row(
            "particles[K].lattice.origin",
            "m",
            "—",
            finite3(),
            "first centre",
        ),
        row("particles[K].lattice.radius", "m", "—", radius.clone(), "R"),
        row(
            "particles[K].lattice.stagger",
            "",
            "true",
            "true, false".into(),
            "odd layers shifted",
        ),
        row(
            "particles[K].lattice.velocity",
            "m/s",
            "[0, 0, 0]",
            speed.clone(),
            "every sphere's",
        ),
        row("particles[K].random.count", "", "—", "≥ 1".into(), "N"),
        row(
            "particles[K].random.radius",
            "m",
            "—",
            format!("R or [Rmin, Rmax], each {radius}"),
            "radii",
        ),
        row(
            "particles[K].random.lower",
            "m",
            "—",
            finite3(),
            "region corner",
        ),
        row(
            "particles[K].random.upper",
            "m",
            "—",
            finite3(),
            "region corner",
        ),
        row(
            "particles[K].random.seed",
            "",
            "0",
            "0 to 2^64 − 1".into(),
            "random seed",
        ),
        row(
            "particles[K].random.velocity",
            "m/s",
            "[0, 0, 0]",
            speed.clone(),
            "every sphere's",
        ),
        row(
            "particles[K].random.max_attempts",
            "",
            &dembound_scene::sources::random::DEFAULT_MAX_ATTEMPTS.to_string(),
            "≥ 1".into(),
            "tries per sphere",
        ),
        row(
            "wall[K].material",
            "",
            "—",
            format!(
                "a material name, or \"rigid\" ({})",
                dembound_scene::walls::registry::surfaces().join(", ")
            ),
            "the wall's material",
        ),
        row("wall[K].friction", "", "its material's", mu, "the wall's μ"),
        row(
            "wall[K].rolling_friction",
            "",
            "its material's",
            mu_r,
            "the wall's μ_r",
        ),
        row(
            "wall[K].motion.velocity",
            "m/s",
            "[0, 0, 0]",
            format!("finite, \\|V\\| ≤ {}", show(limits::MAX_SPEED)),
            "translation of a moving plane, cylinder, mesh or boundary-particle wall",
        ),
        row(
            "wall[K].motion.angular_velocity",
            "rad/s",
            "[0, 0, 0]",
            format!(
                "finite, \\|ω\\| ≤ {}",
                show(dembound_scene::walls::motion::MAX_ANGULAR_SPEED)
            ),
            "rotation about the axis through center",
        ),
        row(
            "wall[K].motion.center",
            "m",
            "[0, 0, 0]",
            "three finite numbers".into(),
            "rotation centre at t = 0 (moves with the wall)",
        ),
        row(
            "wall[K].motion.start",
            "s",
            "0",
            "finite, ≥ 0".into(),
            "the motion begins",
        ),
        row(
            "wall[K].motion.end",
            "s",
            "inf",
            "> start, or inf".into(),
            "the motion stops (the wall stays where it is)",
        ),
        row(
            "wall[K].oscillation.amplitude",
            "m",
            "—",
            format!(
                "finite, \\|a\\| ≤ {}; peak speed 2π f \\|a\\| ≤ {} m/s",
                show(dembound_scene::walls::motion::MAX_AMPLITUDE),
                show(limits::MAX_SPEED)
            ),
            "translation a sin(2π f t), from t = 0",
        ),
        row(
            "wall[K].oscillation.frequency",
            "Hz",
            "—",
            format!(
                "> 0, ≤ {}",
                show(dembound_scene::walls::motion::MAX_FREQUENCY)
            ),
            "f",
        ),
        row(
            "wall[K].servo.force",
            "N",
            "—",
            format!(
                "> 0, ≤ {}",
                show(dembound_scene::walls::servo::MAX_FORCE)
            ),
            "push F to hold (plane, cylinder or mesh; not with motion)",
        ),
        row(
            "wall[K].servo.axis",
            "—",
            "—",
            "finite, not all 0".into(),
            "direction the wall moves to press harder",
        ),
        row(
            "wall[K].servo.max_velocity",
            "m/s",
            "—",
            format!("> 0, ≤ {}", show(limits::MAX_SPEED)),
            "v_max: the speed clamp",
        ),
        row(
            "wall[K].servo.gain",
            "—",
            "0.01",
            format!(
                "> 0, ≤ {}",
                show(dembound_scene::walls::servo::MAX_GAIN)
            ),
            "k: v = k v_max (F − N)/F along axis",
        ),
        row(
            "wall[K].active.from",
            "s",
            "0",
            "finite, ≥ 0".into(),
            "t₀: the wall acts on the steps n with t₀ ≤ n Δt < t₁ (plane, cylinder or mesh; not with servo)",
        ),
        row(
            "wall[K].active.to",
            "s",
            "inf",
            "> from, or inf".into(),
            "t₁: after it the wall exerts no force, its contacts' springs dropped, their energy booked (gate_energy)",
        ),
        row(
            "motion.gravity",
            "m/s²",
            "[0, 0, -9.81]",
            format!("\\|g\\| = 0 or {}", describe(limits::GRAVITY, "")),
            "g",
        ),
        row(
            "integration.scheme",
            "",
            "\"verlet\"",
            "\"verlet\", \"gear5\"".into(),
            "integrator",
        ),
        row(
            "integration.dt",
            "s",
            "—",
            format!("finite, > 0, ≤ c T_b with c = {}; or eta", step_ratios()),
            "Δt (T_b: the smallest contact-time estimate at the fastest reachable approach)",
        ),
        row(
            "integration.eta",
            "",
            "—",
            format!("η > 0 with η T_c ≤ c T_b, c = {}; or dt", step_ratios()),
            "Δt = η T_c",
        ),
        row(
            "integration.impact_speed",
            "m/s",
            "free fall across the box, or the fastest sphere",
            "finite, > 0".into(),
            "speed of T_c",
        ),
        row(
            "integration.steps",
            "",
            "—",
            format!(
                "1 to {} (above {} with --force); or duration",
                show(MAX_STEPS as f64),
                show(super::scene_limits::MAX_SCENE_STEPS_WITHOUT_FORCE as f64)
            ),
            "run length",
        ),
        row(
            "integration.duration",
            "s",
            "—",
            format!(
                "finite, > 0, at most {} steps of Δt without --force; or steps",
                show(super::scene_limits::MAX_SCENE_STEPS_WITHOUT_FORCE as f64)
            ),
            "run length",
        ),
        row(
            "integration.skin",
            "m",
            "0.2 × smallest free radius",
            "finite, > 0".into(),
            "Verlet-list skin",
        ),
        row(
            "output.collisions",
            "",
            "false",
            "true, false".into(),
            "log every contact",
        ),
        row(
            "output.dissipation",
            "",
            "false",
            "true, false".into(),
            "dissipated energy summed per contact",
        ),
        row(
            "output.every",
            "steps",
            "run length / 20",
            "≥ 1".into(),
            "VTK interval",
        ),
        row(
            "output.series_every",
            "steps",
            "run length / 1000",
            "≥ 1".into(),
            "series interval",
        ),
        row(
            "output.wall_force_mean",
            "",
            "false",
            "true, false (not under mpirun)".into(),
            "series.csv also gives each wall's force averaged over every step since the previous row (wallK_mean_force_x_N …, after all other columns; NaN at the first row)",
        ),
        row(
            "parallel.grid",
            "",
            "least surface",
            "three counts ≥ 1, product = ranks".into(),
            "MPI sub-domains",
        ),
        row(
            "parallel.rebalance_threshold",
            "",
            &show(dembound_scene::comm::distributed::balance::DEFAULT_REBALANCE_THRESHOLD),
            "> 1, or inf".into(),
            "re-balance trigger",
        ),
        row(
            "parallel.vtk_per_rank",
            "",
            "false",
            "true, false".into(),
            "MPI snapshots as one piece per rank (.pvtp)",
        ),
        row(
            "parallel.checkpoint_per_rank",
            "",
            "false",
            "true, false".into(),
            "MPI checkpoint as one part per rank",
        ),
        row(
            "parallel.halo_overlap",
            "",
            "false",
            "true, false".into(),
            "MPI halo exchange during the interior pairs",
        ),
    ];
    // The registry laws' parameters given by key (`contact.stiffness`,
    // `contact.exponent`), before `contact.friction`.
    let at = rows
        .iter()
        .position(|k| k.key == "contact.friction")
        .unwrap_or(rows.len());
    rows.splice(at..at, law_parameter_rows(|_| true));
    // Each wall type's keys (its file under the scene crate's `walls/`),
    // after `wall[K].rolling_friction`.
    let at = rows
        .iter()
        .position(|r| r.key == "wall[K].rolling_friction")
        .map_or(rows.len(), |k| k + 1);
    rows.splice(
        at..at,
        dembound_scene::walls::registry::keys()
            .into_iter()
            .map(|k| KeyInfo {
                key: k.key.into(),
                unit: k.unit.into(),
                default: k.default,
                allowed: k.allowed,
                meaning: k.meaning.into(),
            }),
    );
    rows
}

/// The rules on the scene as a whole (from the same constants).
pub fn rules() -> String {
    let pct = |x: f64| format!("{} %", show(100.0 * x));
    format!(
        "Initial overlaps: a free sphere's centre behind a plane wall or on the wrong side of a \
         cylinder (outside a tube or its caps, inside a post), or an overlap (with a plane, a \
         cylinder or a mesh's faces, or of two spheres one of them free) above {} of the smaller radius, is refused \
         (exit 2, naming both); above {} it is a warning on stderr. A sphere's \\|v\\| ≤ {} m/s; \
         a moving sphere's material density {}.",
        pct(limits::OVERLAP_REFUSAL),
        pct(limits::OVERLAP_WARNING),
        show(limits::MAX_SPEED),
        describe(limits::DENSITY, "kg/m³"),
    )
}

/// The table as Markdown: what `dembound keys --scene` prints and the
/// README holds between its scene-keys markers.
pub fn markdown() -> String {
    let mut out = String::from(
        "| key | unit | default | allowed | meaning |\n| --- | --- | --- | --- | --- |\n",
    );
    for k in keys() {
        let unit = if k.unit.is_empty() { "—" } else { &k.unit };
        out.push_str(&format!(
            "| `{}` | {} | {} | {} | {} |\n",
            k.key, unit, k.default, k.allowed, k.meaning
        ));
    }
    out.push('\n');
    out.push_str(&rules());
    out.push('\n');
    out
}

#[cfg(test)]
mod tests {
    use dembound_core::bounce::limits as bounce;
    use dembound_scene::limits as scene;

    /// The scene's ranges that the bounce study also has are the same
    /// numbers (`dembound-scene` does not depend on `dembound-core`, so
    /// the values are repeated there; this keeps them equal).
    #[test]
    fn the_shared_ranges_are_the_bounce_studys() {
        assert_eq!(scene::RADIUS, bounce::RADIUS);
        assert_eq!(scene::DENSITY, bounce::DENSITY);
        assert_eq!(scene::YOUNGS_MODULUS, bounce::YOUNGS_MODULUS);
        assert_eq!(scene::MAX_SPEED, bounce::MAX_SPEED);
        assert_eq!(scene::GRAVITY, bounce::GRAVITY);
        assert_eq!(scene::MODULUS_RATIO, bounce::RATIO);
    }

    /// Every row has a unit column that is a unit or empty, and a range.
    #[test]
    fn every_row_states_its_range() {
        for k in super::keys() {
            assert!(!k.allowed.is_empty(), "{}", k.key);
            assert!(!k.default.is_empty(), "{}", k.key);
        }
    }
}
