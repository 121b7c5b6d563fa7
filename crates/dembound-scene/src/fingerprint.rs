//! The scene a checkpoint belongs to, as far as it shapes the trajectory:
//! each body's radius, material and fixedness, every material, the contact
//! and friction models, the walls, gravity, the domain, the scheme and the
//! neighbour skin. A checkpoint carries the [`Fingerprint`] of the scene
//! that wrote it; a restart refuses a scene whose fingerprint differs and
//! names the first key that does (a restart with another density or radius
//! would otherwise run on, with the stored contact histories and energies
//! of another scene: a negative dissipated energy).
//!
//! Not part of it: the initial positions and velocities (the checkpoint's
//! replace them), the run length and the outputs (a restart may change
//! them), the time step (checked exactly, from the resolved Δt).

use crate::setup::SceneSetup;
use crate::SceneError;
use serde::{Deserialize, Serialize};

/// The setting of the number of walls.
const WALL_COUNT: &str = "walls (count)";
/// The setting of the friction model (with its per-wall list).
const FRICTION: &str = "friction";

/// The friction setting's text without its per-wall list `walls: [..]`,
/// and the list's entries (`None`, `Some((μ, μ_r))`), as
/// `FrictionSetup`'s `Debug` prints them.
fn split_friction(text: &str) -> (String, Vec<String>) {
    const OPEN: &str = "walls: [";
    let Some(start) = text.find(OPEN) else {
        return (text.to_string(), Vec::new());
    };
    let inner_start = start + OPEN.len();
    let Some(len) = text[inner_start..].find(']') else {
        return (text.to_string(), Vec::new());
    };
    let inner = &text[inner_start..inner_start + len];
    let rest = format!("{}{}", &text[..start], &text[inner_start + len + 1..]);
    // Top-level commas only: an entry is `Some((0.5, 0.05))`.
    let mut entries = Vec::new();
    let (mut depth, mut from) = (0i32, 0usize);
    for (k, ch) in inner.char_indices() {
        match ch {
            '(' => depth += 1,
            ')' => depth -= 1,
            ',' if depth == 0 => {
                entries.push(inner[from..k].trim().to_string());
                from = k + 1;
            }
            _ => {}
        }
    }
    if !inner[from..].trim().is_empty() {
        entries.push(inner[from..].trim().to_string());
    }
    (rest, entries)
}

/// One wall as a fingerprint records it: its setup's text (type,
/// geometry, material), and what else makes it the same wall.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct WallPrint {
    /// The setup's `Debug` ("Plane { point: …, normal: …, material: 0 }").
    pub text: String,
    /// The text, the motion, the servo and the wall's own friction: equal
    /// identities are the same wall (`crate::restart_walls`).
    pub identity: String,
    /// A wall of boundary particles (no surface).
    pub particles: bool,
}

/// What a checkpoint must match in the scene that continues it.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct Fingerprint {
    /// (key, value) of each setting, in a fixed order; the values printed
    /// exactly (f64 in Rust's shortest round-trip form).
    pub settings: Vec<(String, String)>,
    /// Each body's radius in input order, m.
    pub radius: Vec<f64>,
    /// Each body's material index in input order.
    pub material: Vec<u32>,
    /// Each body fixed (boundary particles, `fixed = true`) or free.
    pub fixed: Vec<bool>,
}

impl Fingerprint {
    /// The fingerprint of `setup`.
    pub fn of(setup: &SceneSetup) -> Self {
        let mut settings = Vec::new();
        let mut put = |key: String, value: String| settings.push((key, value));
        let d = &setup.domain;
        put("domain.lower".into(), format!("{:?} m", d.lower));
        put("domain.upper".into(), format!("{:?} m", d.upper));
        put("domain.periodic".into(), format!("{:?}", d.periodic));
        put(
            "materials (count)".into(),
            setup.materials.len().to_string(),
        );
        for (k, m) in setup.materials.iter().enumerate() {
            let mat = &m.material;
            put(format!("material.{k}.name"), format!("{:?}", m.name));
            put(
                format!("material.{k}.density"),
                format!("{:?} kg/m³", mat.density),
            );
            put(
                format!("material.{k}.youngs_modulus"),
                format!("{:?} Pa", mat.youngs_modulus),
            );
            put(
                format!("material.{k}.poisson_ratio"),
                format!("{:?}", mat.poisson_ratio),
            );
        }
        put("contact".into(), format!("{:?}", setup.contact));
        put(FRICTION.into(), format!("{:?}", setup.friction));
        put(WALL_COUNT.into(), setup.walls.len().to_string());
        for (k, w) in setup.walls.iter().enumerate() {
            put(format!("wall.{k}"), format!("{w:?}"));
            // Only a moving wall has the key: fixed walls keep the
            // fingerprints (and checkpoints) of before.
            if let Some(Some(m)) = setup.wall_motions.get(k) {
                put(format!("wall.{k}.motion"), format!("{m:?}"));
            }
            if let Some(Some(s)) = setup.wall_servos.get(k) {
                put(format!("wall.{k}.servo"), format!("{s:?}"));
            }
            if let Some(Some(a)) = setup.wall_active.get(k) {
                put(format!("wall.{k}.active"), format!("{a:?}"));
            }
        }
        // Only a moving group has the key (the fingerprints of before stay).
        for g in &setup.group_motions {
            put(
                format!("particles.{}.motion", g.group),
                format!("{:?} {:?}", g.spheres, g.motion),
            );
        }
        put("motion.gravity".into(), format!("{:?} m/s²", setup.gravity));
        put(
            "integration.scheme".into(),
            format!("{:?}", setup.integration.scheme).to_lowercase(),
        );
        put(
            "neighbour.skin".into(),
            format!("{:?} m", setup.neighbour.skin),
        );
        let s = &setup.spheres;
        Self {
            settings,
            radius: s.iter().map(|b| b.radius).collect(),
            material: s.iter().map(|b| b.material as u32).collect(),
            fixed: s.iter().map(|b| b.fixed).collect(),
        }
    }

    /// Each wall in file order (`crate::restart_walls`).
    pub(crate) fn walls(&self) -> Vec<WallPrint> {
        let get = |key: &str| {
            self.settings
                .iter()
                .find(|(k, _)| k == key)
                .map(|(_, v)| v.as_str())
        };
        let count: usize = get(WALL_COUNT).and_then(|c| c.parse().ok()).unwrap_or(0);
        let friction = get(FRICTION).map(split_friction).unwrap_or_default().1;
        (0..count)
            .map(|k| {
                let text = get(&format!("wall.{k}")).unwrap_or_default().to_string();
                let identity = format!(
                    "{text} | motion {} | servo {} | friction {}",
                    get(&format!("wall.{k}.motion")).unwrap_or("none"),
                    get(&format!("wall.{k}.servo")).unwrap_or("none"),
                    friction.get(k).map_or("None", String::as_str),
                );
                WallPrint {
                    particles: text.starts_with(crate::walls::registry::PARTICLES_DEBUG),
                    text,
                    identity,
                }
            })
            .collect()
    }

    /// `Ok` when the scene's fingerprint `scene` is this checkpoint's;
    /// otherwise the first difference, named. The walls are not compared
    /// here: a restart may add and remove walls (`crate::restart_walls`
    /// matches them); the friction setting is compared without its
    /// per-wall list, which goes with the walls.
    pub fn check(&self, scene: &Fingerprint) -> Result<(), SceneError> {
        let differs = |what: String| Err(SceneError::Checkpoint(what));
        let (n, m) = (self.radius.len(), scene.radius.len());
        if n != m {
            return differs(format!("it holds {n} bodies, the scene {m}"));
        }
        let walls_key = |k: &str| k == WALL_COUNT || k.starts_with("wall.");
        for (key, value) in self.settings.iter().filter(|(k, _)| !walls_key(k)) {
            match scene.settings.iter().find(|(k, _)| k == key) {
                Some((_, now)) if now == value => {}
                Some((_, now))
                    if key == FRICTION && split_friction(now).0 == split_friction(value).0 => {}
                Some((_, now)) => {
                    return differs(format!(
                        "{key} differs: the checkpoint's {value}, the scene's {now}"
                    ))
                }
                None => {
                    return differs(format!("the scene has no {key} (the checkpoint: {value})"))
                }
            }
        }
        if let Some((key, value)) = scene
            .settings
            .iter()
            .filter(|(k, _)| !walls_key(k))
            .find(|(k, _)| !self.settings.iter().any(|(mine, _)| mine == k))
        {
            return differs(format!("the checkpoint has no {key} (the scene: {value})"));
        }
        let body = |k: usize| format!("sphere {k} (input order)");
        for k in 0..n {
            let (a, b) = (self.radius[k], scene.radius[k]);
            if a.to_bits() != b.to_bits() {
                return differs(format!(
                    "{}: radius differs: the checkpoint's {a:?} m, the scene's {b:?} m",
                    body(k)
                ));
            }
        }
        for (k, (a, b)) in self.material.iter().zip(&scene.material).enumerate() {
            if a != b {
                return differs(format!(
                    "{}: material differs: the checkpoint's {a}, the scene's {b}",
                    body(k)
                ));
            }
        }
        for (k, (a, b)) in self.fixed.iter().zip(&scene.fixed).enumerate() {
            if a != b {
                let kind = |f: bool| if f { "fixed" } else { "free" };
                return differs(format!(
                    "{}: the checkpoint's is {}, the scene's {}",
                    body(k),
                    kind(*a),
                    kind(*b)
                ));
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::setup::{DomainSetup, NamedMaterial, RunLength, SphereInit, TimeStep};
    use dembound_physics::contact::{ContactModel, NormalLaw};
    use dembound_physics::material::Material;

    fn setup(density: f64, radius: f64) -> SceneSetup {
        let domain = DomainSetup {
            lower: [0.0; 3],
            upper: [1.0; 3],
            periodic: [false; 3],
        };
        let mut s = SceneSetup::new(
            domain,
            ContactModel::elastic(NormalLaw::Hertz),
            TimeStep::Fixed(1e-6),
            RunLength::Steps(10),
        );
        s.materials.push(NamedMaterial {
            name: "grain".into(),
            material: Material {
                density,
                youngs_modulus: 1e7,
                poisson_ratio: 0.3,
            },
        });
        for k in 0..3 {
            s.spheres.push(SphereInit {
                position: [0.1 + 0.2 * k as f64, 0.5, 0.5],
                velocity: [0.0; 3],
                radius,
                material: 0,
                fixed: false,
                group: None,
            });
        }
        s
    }

    /// The friction text without its wall list, and the list's entries
    /// split at the top-level commas only.
    #[test]
    fn the_friction_text_splits_off_its_walls() {
        let text = "Some(FrictionSetup { model: M { a: 1 }, materials: [None], walls: [None, \
                    Some((0.5, 0.05)), None] })";
        let (rest, walls) = split_friction(text);
        assert_eq!(
            rest,
            "Some(FrictionSetup { model: M { a: 1 }, materials: [None],  })"
        );
        assert_eq!(walls, ["None", "Some((0.5, 0.05))", "None"]);
        assert_eq!(split_friction("None"), ("None".to_string(), Vec::new()));
        let (_, none) = split_friction("Some(FrictionSetup { walls: [] })");
        assert!(none.is_empty());
    }

    /// A scene with a wall more still fits (the walls are matched by
    /// `restart_walls`); its walls' identities differ by the new one.
    #[test]
    fn walls_do_not_count_in_the_check() {
        let mut a = setup(1000.0, 1e-3);
        a.walls
            .push(crate::setup::WallSetup::Plane(crate::setup::Plane {
                point: [0.0; 3],
                normal: [0.0, 0.0, 1.0],
                material: 0,
            }));
        let b = setup(1000.0, 1e-3);
        let (fa, fb) = (Fingerprint::of(&a), Fingerprint::of(&b));
        assert!(fa.check(&fb).is_ok() && fb.check(&fa).is_ok());
        let walls = fa.walls();
        assert_eq!(walls.len(), 1);
        assert!(walls[0].text.starts_with("Plane { point: [0.0, 0.0, 0.0]"));
        assert!(walls[0]
            .identity
            .ends_with("| motion none | servo none | friction None"));
        assert!(!walls[0].particles);
        assert!(fb.walls().is_empty());
    }

    #[test]
    fn the_same_scene_fits_and_another_is_named() {
        let a = Fingerprint::of(&setup(1000.0, 1e-3));
        assert!(a.check(&Fingerprint::of(&setup(1000.0, 1e-3))).is_ok());
        let e = a
            .check(&Fingerprint::of(&setup(1001.0, 1e-3)))
            .unwrap_err()
            .to_string();
        assert!(e.contains("material.0.density"), "{e}");
        assert!(e.contains("1000.0") && e.contains("1001.0"), "{e}");
        let e = a
            .check(&Fingerprint::of(&setup(1000.0, 1.1e-3)))
            .unwrap_err()
            .to_string();
        assert!(e.contains("sphere 0") && e.contains("radius"), "{e}");
    }

    #[test]
    fn initial_positions_do_not_count() {
        let a = setup(1000.0, 1e-3);
        let mut b = a.clone();
        let moved = b.spheres.get_mut(1).expect("the setup has two spheres");
        moved.position[0] += 0.01;
        moved.velocity[2] = 3.0;
        assert!(Fingerprint::of(&a).check(&Fingerprint::of(&b)).is_ok());
    }
}
