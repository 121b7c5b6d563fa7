//! The friction keys of the scene file (issue 13): validated (exit 2 in
//! the CLI: input errors naming the key, the value and the range) and
//! resolved into the engine's setup with the stated mixing.

use dembound_physics::contact::tangential::TangentialKind;
use dembound_scene::io::config;
use dembound_scene::io::resolve::resolve;
use std::path::Path;

const SCENE: &str = r#"
[domain]
lower = [0.0, 0.0, 0.0]
upper = [0.01, 0.01, 0.01]
[[material]]
name = "grain"
density = 1000.0
youngs_modulus = 1.0e7
poisson_ratio = 0.3
[contact]
law = "hertz"
damping = "tsuji"
restitution = 0.5
[[particles]]
spheres = [{ position = [0.005, 0.005, 0.002], radius = 0.5e-3 }]
material = "grain"
[[wall]]
plane = { point = [0.0, 0.0, 0.0], normal = [0.0, 0.0, 1.0] }
material = "rigid"
[integration]
dt = 1.0e-6
steps = 10
"#;

fn load(
    sets: &[&str],
) -> Result<dembound_scene::io::resolve::ResolvedScene, dembound_scene::SceneError> {
    let sets: Vec<String> = sets.iter().map(|s| s.to_string()).collect();
    let file = config::load(SCENE, "test.toml", &sets)?;
    resolve(&file, Path::new("."))
}

#[test]
fn no_friction_key_no_friction() {
    assert!(load(&[]).unwrap().setup.friction.is_none());
}

#[test]
fn bad_values_name_their_key() {
    for (set, key) in [
        ("contact.friction=-0.1", "contact.friction"),
        ("contact.friction=nan", "contact.friction"),
        ("contact.rolling_friction=-1", "contact.rolling_friction"),
        ("contact.tangential=\"hooke\"", "contact.tangential"),
        ("material.0.friction=-2", "material[0].friction"),
        ("wall.0.friction=-2", "wall[0].friction"),
    ] {
        let err = load(&[set])
            .err()
            .unwrap_or_else(|| panic!("{set} accepted"));
        assert!(err.is_input(), "{set}: {err}");
        assert!(err.to_string().contains(key), "{set}: {err}");
    }
}

/// Friction with the paper's Gear5 (the spins integrated by Gear's
/// first-order corrector, `dynamics::gear5_rotation`) loads and runs.
#[test]
fn friction_with_gear5_is_accepted_and_runs() {
    let r = load(&["contact.friction=0.3", "integration.scheme=\"gear5\""]).unwrap();
    assert_eq!(
        r.setup.integration.scheme,
        dembound_scene::setup::Scheme::Gear5
    );
    assert!(r.setup.friction.is_some());
    let mut sim = dembound_scene::Simulation::new(r.setup, 1).unwrap();
    sim.run_to_end();
    assert_eq!(sim.steps_done(), 10);
}

#[test]
fn coefficients_resolve_per_surface() {
    let r = load(&[
        "contact.friction=0.4",
        "contact.tangential=\"linear\"",
        "material.0.rolling_friction=0.02",
        "wall.0.friction=0.1",
    ])
    .unwrap();
    let f = r.setup.friction.unwrap();
    assert_eq!(f.model.tangential, TangentialKind::Linear);
    assert_eq!(f.model.friction, 0.4);
    // The grain: μ from contact, μ_r its own.
    assert_eq!(f.of_material(0), (0.4, 0.02));
    // The rigid plane: its own μ, μ_r from contact (0).
    assert_eq!(f.of_wall(0, 1), (0.1, 0.0));
}
