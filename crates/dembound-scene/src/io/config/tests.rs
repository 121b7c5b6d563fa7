use super::*;

/// Issue 12's example, verbatim (the keys users and checks rely on).
pub(crate) const ISSUE_EXAMPLE: &str = r#"
[domain]
lower = [0.0, 0.0, 0.0]                 # m
upper = [0.0246, 0.0246, 0.03]          # m
periodic = [false, false, false]
[[material]]
name = "grain"
density = 1000.0                        # kg/m³
youngs_modulus = 1.0e7                  # Pa
poisson_ratio = 0.3
[contact]                               # the same keys as run's [contact]: law, damping, restitution, …
law = "hertz"
[[particles]]
lammps_data = "lattice_10k.data"        # or lattice = {…}, random = {…}, csv = "…"; path relative to the scene file
material = "grain"
[[particles]]                           # a few spheres given inline
spheres = [{ position = [0.0, 0.0, 0.0555], radius = 0.5e-3, velocity = [0.0, 0.0, 0.0] }]
material = "grain"
[[particles]]
spheres = [{ position = [0.0, 0.0, 0.0], radius = 0.05 }]
material = "grain"
fixed = true                            # boundary particles: infinite mass, never move
[[wall]]
plane = { point = [0.0, 0.0, 0.0], normal = [0.0, 0.0, 1.0] }
material = "grain"                      # or "rigid"
[[wall]]
boundary_particles = { point = [0.0, 0.0, 0.0], normal = [0.0, 0.0, 1.0], radius_ratio = 100.0, modulus_ratio = 100.0, tiling = "square" }
material = "grain"                      # the particle material r and ζ refer to
[motion]
gravity = [0.0, 0.0, -9.81]             # m/s²
[integration]
scheme = "verlet"                       # or "gear5"
dt = 2.0e-6                             # s, or eta = 0.02
steps = 10000                           # or duration = … (s)
[output]
collisions = false
"#;

fn sets(args: &[&str]) -> Vec<String> {
    args.iter().map(|s| s.to_string()).collect()
}

#[test]
fn the_issue_example_parses_with_its_values() {
    let s = load(ISSUE_EXAMPLE, "issue.toml", &[]).unwrap();
    assert_eq!(s.domain.upper, [0.0246, 0.0246, 0.03]);
    assert_eq!(s.materials[0].youngs_modulus, 1.0e7);
    assert_eq!(s.contact.law, Law::Name("hertz".into()));
    assert_eq!(s.particles.len(), 3);
    assert_eq!(
        s.particles[0].lammps_data.as_deref(),
        Some("lattice_10k.data")
    );
    assert!(s.particles[2].fixed);
    assert_eq!(
        s.particles[1].spheres.as_ref().unwrap()[0].position[2],
        0.0555
    );
    let b = s.walls[1].boundary_particles.as_ref().unwrap();
    assert_eq!(
        (b.radius_ratio, b.modulus_ratio, b.tiling),
        (100.0, 100.0, TilingName::Square)
    );
    assert_eq!(s.integration.scheme, Scheme::Verlet);
    assert_eq!(
        (s.integration.dt, s.integration.steps),
        (Some(2.0e-6), Some(10000))
    );
    assert!(!s.output.collisions);
}

#[test]
fn set_overrides_index_lists_and_swap_exclusive_keys() {
    let s = load(
        ISSUE_EXAMPLE,
        "issue.toml",
        &sets(&[
            "integration.eta=0.02",
            "integration.duration=0.01",
            "wall.0.material=rigid",
            "wall[1].boundary_particles.tiling=hexagonal",
            "contact.law={power=1.25}",
            "output.collisions=true",
            "particles.2.fixed=false",
        ]),
    )
    .unwrap();
    assert_eq!((s.integration.dt, s.integration.eta), (None, Some(0.02)));
    assert_eq!(
        (s.integration.steps, s.integration.duration),
        (None, Some(0.01))
    );
    assert_eq!(s.walls[0].material, "rigid");
    assert_eq!(
        s.walls[1].boundary_particles.as_ref().unwrap().tiling,
        TilingName::Hexagonal
    );
    assert_eq!(
        s.contact.law,
        Law::WithValue([("power".to_string(), 1.25)].into_iter().collect())
    );
    assert!(s.output.collisions && !s.particles[2].fixed);
}

/// Each bad input names its key and the allowed range or set.
#[test]
fn validation_table() {
    let cases: &[(&str, &str, &str)] = &[
        // (--set, key named, allowed named)
        (
            "domain.upper=[0.0246, 0.0246, -1.0]",
            "domain.upper",
            "> domain.lower",
        ),
        // Issue 16's `[parallel]` (a --set may create the section).
        ("parallel.grid=[0, 1, 2]", "parallel.grid", "each ≥ 1"),
        ("parallel.grid=[1, 2]", "parallel.grid", "3"),
        ("parallel.ranks=2", "parallel.ranks", "grid"),
        (
            "parallel.rebalance_threshold=1.0",
            "parallel.rebalance_threshold",
            "> 1",
        ),
        (
            "parallel.rebalance_threshold=nan",
            "parallel.rebalance_threshold",
            "inf: never",
        ),
        ("domain.lower=[0.0, nan, 0.0]", "domain.lower", "finite"),
        ("domain.periodic=[true]", "domain.periodic", "3"),
        (
            "material.0.density=-1",
            "material[0].density",
            "0.001 to 1e12 kg/m³",
        ),
        (
            "material.0.youngs_modulus=0",
            "material[0].youngs_modulus",
            "1000 to 1e13 Pa",
        ),
        (
            "material.0.poisson_ratio=0.5",
            "material[0].poisson_ratio",
            "-1 < ν < 0.5",
        ),
        ("material.0.name=rigid", "material[0].name", "reserved"),
        (
            "material.0.colour=red",
            "material[0].colour",
            "unknown field",
        ),
        ("contact.law=cubic", "contact.law", "linear"),
        ("contact.law.power=4", "contact.law.power", "α"),
        ("contact.damping=tsuji", "contact.restitution", "missing"),
        (
            "contact.restitution=0.5",
            "contact.restitution",
            "absent with damping",
        ),
        ("contact.damping=sticky", "contact.damping", "viscous"),
        (
            "contact.calibration=guess",
            "contact.calibration",
            "formula",
        ),
        (
            "particles.0.material=sand",
            "particles[0].material",
            "\"grain\"",
        ),
        ("particles.0.csv=a.csv", "particles[0]", "exactly one of"),
        (
            "particles.1.spheres.0.radius=0",
            "particles[1].spheres[0].radius",
            "1e-9 to 10 m",
        ),
        (
            "particles.1.spheres.0.mass=1",
            "particles[1].spheres[0].mass",
            "unknown field",
        ),
        ("wall.0.material=steel", "wall[0].material", "\"rigid\""),
        (
            "wall.0.plane.normal=[0.0, 0.0, 0.0]",
            "wall[0].plane.normal",
            "non-zero",
        ),
        (
            "wall.1.material=rigid",
            "wall[1].material",
            "r and ζ refer to",
        ),
        (
            "wall.1.boundary_particles.radius_ratio=inf",
            "wall[1].boundary_particles.radius_ratio",
            "use a plane",
        ),
        (
            "wall.1.boundary_particles.modulus_ratio=-1",
            "wall[1].boundary_particles.modulus_ratio",
            "inf",
        ),
        (
            "wall.1.boundary_particles.tiling=hex",
            "wall[1].boundary_particles.tiling",
            "hexagonal",
        ),
        (
            "wall.1.boundary_particles.spacing=0",
            "wall[1].boundary_particles.spacing",
            "> 0, in m",
        ),
        ("motion.gravity=[0.0, 0.0, inf]", "motion.gravity", "finite"),
        ("integration.scheme=euler", "integration.scheme", "gear5"),
        ("integration.dt=-1e-6", "integration.dt", "> 0, in s"),
        ("integration.eta=2", "integration.eta", "0 < η ≤ 1"),
        ("integration.steps=0", "integration.steps", "1 ≤ steps"),
        (
            "integration.duration=0",
            "integration.duration",
            "> 0, in s",
        ),
        ("integration.skin=-1", "integration.skin", "> 0, in m"),
        ("output.every=0", "output.every", "≥ 1"),
        ("output.pictures=true", "output.pictures", "unknown field"),
        ("contact.frction=0.3", "contact.frction", "unknown field"),
        ("contact.stiffness=abc", "contact.stiffness", "expected f64"),
        (
            "contact.stiffness=5",
            "contact.stiffness",
            "no parameters for law = \"hertz\"",
        ),
        ("nosuch.key=1", "nosuch", "`domain`"),
        (
            "contact.tangential_damping=false",
            "contact.tangential_damping",
            "given only with friction",
        ),
        (
            "contact.tangential_damping=0",
            "contact.tangential_damping",
            "expected a boolean",
        ),
        (
            "contact.torque_arm=\"middle\"",
            "contact.torque_arm",
            "\"radius\" (the default: the tangential torque at R), \"contact_point\"",
        ),
        (
            "contact.torque_arm=\"contact_point\"",
            "contact.torque_arm",
            "given only with friction",
        ),
        (
            "contact.spring_rotation=\"projected\"",
            "contact.spring_rotation",
            "\"rescale\" (the default: the tangential spring projected onto the new tangent",
        ),
        (
            "contact.spring_rotation=\"project\"",
            "contact.spring_rotation",
            "given only with friction",
        ),
    ];
    for (set, key, allowed) in cases {
        let e = load(ISSUE_EXAMPLE, "issue.toml", &sets(&[set]))
            .expect_err(set)
            .to_string();
        assert!(
            e.contains(&format!("`{key}`")) || e.contains(key),
            "{set}: {e}"
        );
        assert!(e.contains(allowed), "{set}: {e}");
    }
}

#[test]
fn both_or_neither_of_exclusive_keys_is_refused() {
    let text = ISSUE_EXAMPLE.replace("dt = 2.0e-6", "dt = 2.0e-6\neta = 0.02");
    let e = load(&text, "f.toml", &[]).unwrap_err().to_string();
    assert!(
        e.contains("integration.dt") && e.contains("one of dt and eta"),
        "{e}"
    );
    let text = ISSUE_EXAMPLE.replace("steps = 10000", "");
    let e = load(&text, "f.toml", &[]).unwrap_err().to_string();
    assert!(
        e.contains("integration.steps") && e.contains("duration"),
        "{e}"
    );
}

#[test]
fn malformed_files_and_sets_are_named() {
    let e = load("[domain\nlower = 1", "broken.toml", &[])
        .unwrap_err()
        .to_string();
    assert!(e.contains("broken.toml") && e.contains("line 1"), "{e}");
    for bad in [
        "integration",
        "integration.steps",
        "wall.x.material=rigid",
        "wall.7.material=rigid",
    ] {
        let e = load(ISSUE_EXAMPLE, "f.toml", &sets(&[bad]))
            .unwrap_err()
            .to_string();
        assert!(
            e.contains(bad.split('=').next().unwrap_or(bad)),
            "{bad}: {e}"
        );
    }
}

#[test]
fn a_resolved_scene_round_trips_through_toml() {
    let s = load(
        ISSUE_EXAMPLE,
        "issue.toml",
        &sets(&["contact.law.power=1.25"]),
    )
    .unwrap();
    let text = toml::to_string(&s).unwrap();
    assert_eq!(load(&text, "round.toml", &[]).unwrap(), s);
}

/// `[contact]` takes the normal laws' parameters by the keys of their
/// registry rows (`stiffness` of `hooke`, `exponent` of `power`), not by
/// keys of its own; a key given twice (by name and in the law's
/// `{ name = value }` form) is refused with its key and value.
#[test]
fn law_parameters_are_read_by_the_registry_rows_keys() {
    use dembound_physics::contact::NormalLaw;
    let scene = |args: &[&str]| load(ISSUE_EXAMPLE, "issue.toml", &sets(args));
    let hooke = scene(&["contact.law=hooke", "contact.stiffness=1e5"]).unwrap();
    let model = hooke.contact.model(None).unwrap();
    assert_eq!(model.normal, NormalLaw::Hooke { stiffness: 1.0e5 });
    // Written back as a key of `[contact]`, read back the same.
    let text = toml::to_string(&hooke).unwrap();
    assert!(text.contains("stiffness = 100000.0"), "{text}");
    assert_eq!(load(&text, "round.toml", &[]).unwrap(), hooke);
    // The power law by its parameter's key or in the law's value form.
    let by_key = scene(&["contact.law=power", "contact.exponent=1.25"]).unwrap();
    let by_value = scene(&["contact.law.power=1.25"]).unwrap();
    assert_eq!(
        by_key.contact.model(None).unwrap().normal,
        NormalLaw::Power { exponent: 1.25 }
    );
    assert_eq!(
        by_key.contact.model(None).unwrap(),
        by_value.contact.model(None).unwrap()
    );
    let e = scene(&["contact.law.hooke=1e5", "contact.stiffness=2e5"])
        .expect_err("given twice")
        .to_string();
    for part in ["contact.stiffness", "200000", "given once"] {
        assert!(e.contains(part), "{part} not in {e}");
    }
}

/// `contact.tangential_damping` with friction: read, and written back only
/// when given (a checkpoint of a scene without it keeps its bytes).
#[test]
fn tangential_damping_is_read_and_written_only_when_given() {
    let f = load(
        ISSUE_EXAMPLE,
        "issue.toml",
        &sets(&["contact.friction=0.3", "contact.tangential_damping=false"]),
    )
    .expect("valid");
    assert_eq!(f.contact.tangential_damping, Some(false));
    assert!(toml::to_string(&f.contact)
        .expect("serialises")
        .contains("tangential_damping = false"));
    let f = load(
        ISSUE_EXAMPLE,
        "issue.toml",
        &sets(&["contact.friction=0.3"]),
    )
    .expect("valid");
    assert_eq!(f.contact.tangential_damping, None);
    assert!(!toml::to_string(&f.contact)
        .expect("serialises")
        .contains("tangential_damping"));
}

/// An empty scene file is refused naming what it lacks, with the place as
/// words ("the file"), not serde's root path "`.`" (before session 36:
/// "`.`: missing field `domain`").
#[test]
fn an_empty_file_names_the_missing_domain_not_a_dot() {
    let err = from_table_with(Table::new(), "empty.toml", Particles::Required)
        .err()
        .map(|e| e.to_string())
        .unwrap_or_default();
    assert!(
        err.contains("in scene file `empty.toml`: the file: missing field `domain`"),
        "{err}"
    );
    assert!(!err.contains("`.`"), "{err}");
}
