//! The wall types, one registry row each (after LAMMPS GRANULAR's
//! sub-model registry: one row per model, each model a small type with
//! the same few methods).
//!
//! A row names the type's file under `walls/` (its module, also the
//! `[[wall]]` key), the type that holds its setup (SI, [`WallType`]) and,
//! for a wall the force loops meet as a surface, its engine record (the
//! [`Surface`] variant). Everything the scene crate does with walls goes
//! through what the rows generate: [`WallSetup`] (the engine's input),
//! [`WallSection`] (the `[[wall]]` entry of the scene file), the
//! dispatch of every [`WallType`] method, [`Surface`] and its inlined
//! dispatch for the force loops, the placement checks in registry order
//! ([`check_placements`]) and the key table ([`keys`]). No other place
//! matches on a wall type.
//!
//! Order. The rows are in the order the types were added (the scene
//! file's unknown-key message lists the keys in it); listings meant for
//! people (the "exactly one of" message, the key table) put the surfaces
//! first, then the walls of boundary particles ([`listing`]).

use std::fmt::Debug;
use std::ops::Range;

use serde::de::DeserializeOwned;
use serde::{Deserialize, Serialize};

use super::{Curvature, Wall, WallPoint};
use crate::error::SceneError;
use crate::io::config::SceneFile;
use crate::io::resolve::WallResolve;
use crate::setup::SceneSetup;
use crate::setup_checks::Label;
use dembound_physics::contact::Side;

/// What each wall type implements: its `[[wall]]` entry, resolved to SI,
/// checked against the scene, built into the engine, and described.
pub trait WallType: Sized + Clone + PartialEq + Debug {
    /// The `[[wall]]` key that selects the type (also its module's name).
    const KEY: &'static str;
    /// A wall of boundary particles: spheres in the body store, no
    /// [`Surface`] (listed after the surfaces).
    const PARTICLES: bool = false;
    /// `[[wall]] KEY = { … }` as the scene file gives it.
    type Config: Clone + PartialEq + Debug + Serialize + DeserializeOwned;

    /// Checks the entry `key` (`wall[K]`) of `file`, whose `material` key
    /// is `material`: the first error names the key, value and range.
    fn validate(
        config: &Self::Config,
        file: &SceneFile,
        key: &str,
        material: &str,
    ) -> Result<(), SceneError>;

    /// The setup of the validated entry of wall `w` (file order) of
    /// `material`; a wall of boundary particles adds its spheres and
    /// material to `cx`. The entry may be rewritten as resolved (a file
    /// path made absolute, from `cx.base_dir`: the resolved scene file
    /// runs from anywhere).
    fn resolve(
        config: &mut Self::Config,
        w: usize,
        material: &str,
        cx: &mut WallResolve<'_>,
    ) -> Result<Self, SceneError>;

    /// The refusals and warnings of the walls of this type, `(file index,
    /// wall)` in file order, against the domain and the spheres (see
    /// `setup_checks`); the type's warnings are one line for all its
    /// walls.
    fn check_placements(
        _walls: &[(usize, &Self)],
        _setup: &SceneSetup,
        _label: Label<'_>,
        _warnings: &mut crate::setup_checks::Overlaps<'_>,
    ) -> Result<(), SceneError> {
        Ok(())
    }

    /// The wall's own material (index into `SceneSetup::materials`);
    /// `None` for boundary particles (their spheres carry theirs).
    fn material(&self) -> Option<usize>;

    /// The rows of the wall law tables, (material, curvature), in the
    /// order of its elements' `Wall::law_slot` (empty for boundary
    /// particles). The time-step rule estimates a contact time per row.
    fn law_rows(&self) -> Vec<(usize, Curvature)>;

    /// Checks the setup of wall `w` (each bad value named) and builds its
    /// engine record, its law rows starting at row `slot`; `None` for a
    /// wall of boundary particles (checked against `setup`'s spheres).
    fn build(
        &self,
        w: usize,
        setup: &SceneSetup,
        slot: usize,
    ) -> Result<Option<Surface>, SceneError>;

    /// The spheres of a wall of boundary particles (input indices).
    fn bodies(&self) -> Option<Range<usize>> {
        None
    }

    /// A few words for the run's summary ("plane", "post").
    fn summary(&self) -> String;

    /// Why a LAMMPS deck cannot hold the wall (the exporter's refusal), or
    /// `None` when the exporter writes it.
    fn export_note(&self) -> Option<String>;

    /// The type's keys, each `wall[K].KEY.name`, for the key table.
    fn keys() -> Vec<WallKey>;
}

/// One row of the scene key table (`dembound keys --scene`).
#[derive(Debug, Clone, PartialEq)]
pub struct WallKey {
    /// `wall[K].KEY.name`.
    pub key: String,
    pub unit: &'static str,
    pub default: String,
    pub allowed: String,
    pub meaning: &'static str,
}

impl WallKey {
    /// The row of key `name` of wall type `kind`.
    pub fn new(
        kind: &str,
        name: &str,
        unit: &'static str,
        default: &str,
        allowed: impl Into<String>,
        meaning: &'static str,
    ) -> Self {
        Self {
            key: format!("wall[K].{kind}.{name}"),
            unit,
            default: default.to_string(),
            allowed: allowed.into(),
            meaning,
        }
    }
}

/// Generates, from the rows, everything listed in the module doc.
macro_rules! wall_registry {
    ($( $(#[$doc:meta])* $V:ident => $m:ident::$T:ident $(, $S:ident)?; )+) => {
        /// Declares one module per row under `walls/` (invoked once in
        /// `walls/mod.rs`): a type's file is named by its row.
        macro_rules! wall_modules {
            () => { $( pub mod $m; )+ };
        }
        pub(crate) use wall_modules;

        /// A wall, as the engine takes it (one variant per registry row;
        /// its `Debug` is the inner type's, which the checkpoint
        /// fingerprint prints).
        #[derive(Clone, PartialEq)]
        pub enum WallSetup {
            $( $(#[$doc])* $V(super::$m::$T), )+
        }

        impl Debug for WallSetup {
            fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
                match self {
                    $( WallSetup::$V(x) => Debug::fmt(x, f), )+
                }
            }
        }

        /// The setup types, re-exported by `crate::setup`.
        pub mod setups {
            pub use super::WallSetup;
            $( pub use crate::walls::$m::$T; )+
        }

        impl WallSetup {
            /// The `[[wall]]` key of its type.
            pub fn key(&self) -> &'static str {
                match self { $( WallSetup::$V(_) => <super::$m::$T as WallType>::KEY, )+ }
            }
            /// A wall of boundary particles.
            pub fn is_particles(&self) -> bool {
                match self { $( WallSetup::$V(_) => <super::$m::$T as WallType>::PARTICLES, )+ }
            }
            /// [`WallType::material`].
            pub fn material(&self) -> Option<usize> {
                match self { $( WallSetup::$V(x) => x.material(), )+ }
            }
            /// [`WallType::law_rows`].
            pub fn law_rows(&self) -> Vec<(usize, Curvature)> {
                match self { $( WallSetup::$V(x) => x.law_rows(), )+ }
            }
            /// [`WallType::build`].
            pub fn build(
                &self,
                w: usize,
                setup: &SceneSetup,
                slot: usize,
            ) -> Result<Option<Surface>, SceneError> {
                match self { $( WallSetup::$V(x) => x.build(w, setup, slot), )+ }
            }
            /// [`WallType::bodies`].
            pub fn bodies(&self) -> Option<Range<usize>> {
                match self { $( WallSetup::$V(x) => x.bodies(), )+ }
            }
            /// [`WallType::summary`].
            pub fn summary(&self) -> String {
                match self { $( WallSetup::$V(x) => x.summary(), )+ }
            }
            /// [`WallType::export_note`].
            pub fn export_note(&self) -> Option<String> {
                match self { $( WallSetup::$V(x) => x.export_note(), )+ }
            }
        }

        /// `[[wall]]`: exactly one type's key, the material and the
        /// wall's own friction.
        #[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
        #[serde(deny_unknown_fields)]
        pub struct WallSection {
            $(
                #[serde(default, skip_serializing_if = "Option::is_none")]
                pub $m: Option<<super::$m::$T as WallType>::Config>,
            )+
            /// A surface's material (or `"rigid"`); for boundary particles
            /// the particle material that r and ζ refer to.
            pub material: String,
            /// The wall's own μ (addition, issue 13; default its material's).
            #[serde(default, skip_serializing_if = "Option::is_none")]
            pub friction: Option<f64>,
            /// The wall's own μ_r (addition; default its material's).
            #[serde(default, skip_serializing_if = "Option::is_none")]
            pub rolling_friction: Option<f64>,
            /// Prescribed rigid motion (issue 27, `walls::motion`).
            #[serde(default, skip_serializing_if = "Option::is_none")]
            pub motion: Option<super::motion::MotionConfig>,
            /// Sinusoidal translation (issue 27, `walls::motion`).
            #[serde(default, skip_serializing_if = "Option::is_none")]
            pub oscillation: Option<super::motion::OscillationConfig>,
            /// Force control along an axis (issue 27, `walls::servo`).
            #[serde(default, skip_serializing_if = "Option::is_none")]
            pub servo: Option<super::servo::ServoConfig>,
            /// The window the wall acts in (issue 28, `walls::gate`).
            #[serde(default, skip_serializing_if = "Option::is_none")]
            pub active: Option<super::gate::ActiveWindow>,
        }

        impl WallSection {
            /// The keys of the types given, in [`listing`] order.
            pub fn given(&self) -> Vec<&'static str> {
                let mut given = Vec::new();
                $( if self.$m.is_some() {
                    given.push(<super::$m::$T as WallType>::KEY);
                } )+
                listing(given)
            }

            /// The `[[wall]]` key of its (first given) type.
            pub fn key(&self) -> Option<&'static str> {
                self.given().first().copied()
            }

            /// [`WallType::validate`] of the type given (the first, when
            /// several are: refused before).
            pub(crate) fn validate_type(&self, file: &SceneFile, key: &str) -> Result<(), SceneError> {
                $( if let Some(c) = &self.$m {
                    return <super::$m::$T as WallType>::validate(c, file, key, &self.material);
                } )+
                Ok(())
            }

            /// [`WallType::resolve`] of the type given, as a [`WallSetup`].
            pub(crate) fn resolve(
                &mut self,
                w: usize,
                cx: &mut WallResolve<'_>,
            ) -> Result<WallSetup, SceneError> {
                $( if let Some(c) = &mut self.$m {
                    return <super::$m::$T as WallType>::resolve(c, w, &self.material, cx)
                        .map(WallSetup::$V);
                } )+
                Err(SceneError::input(format!(
                    "`wall[{w}]`: none of {} (validated before)",
                    listing(KEYS.to_vec()).join(", ")
                )))
            }
        }

        /// Every type's key, in registry order.
        pub const KEYS: &[&str] = &[ $( <super::$m::$T as WallType>::KEY ),+ ];

        /// Whether type `key` is a wall of boundary particles.
        pub(crate) fn is_particles_key(key: &str) -> bool {
            $( if key == <super::$m::$T as WallType>::KEY {
                return <super::$m::$T as WallType>::PARTICLES;
            } )+
            false
        }

        /// Every type's [`WallType::check_placements`], in registry order.
        pub fn check_placements(
            setup: &SceneSetup,
            label: Label<'_>,
            warnings: &mut crate::setup_checks::Overlaps<'_>,
        ) -> Result<(), SceneError> {
            $( {
                let walls: Vec<(usize, &super::$m::$T)> = setup
                    .walls
                    .iter()
                    .enumerate()
                    .filter_map(|(w, x)| match x {
                        WallSetup::$V(x) => Some((w, x)),
                        #[allow(unreachable_patterns)]
                        _ => None,
                    })
                    .collect();
                <super::$m::$T as WallType>::check_placements(&walls, setup, label, warnings)?;
            } )+
            Ok(())
        }

        /// Every type's keys, in [`listing`] order.
        pub fn keys() -> Vec<WallKey> {
            let mut by_type: Vec<(&str, Vec<WallKey>)> = vec![
                $( (<super::$m::$T as WallType>::KEY, <super::$m::$T as WallType>::keys()), )+
            ];
            let mut out = Vec::new();
            for key in listing(KEYS.to_vec()) {
                if let Some(k) = by_type.iter().position(|t| t.0 == key) {
                    out.append(&mut by_type[k].1);
                }
            }
            out
        }

        /// Every wall the force loops meet as a surface (an enum: they
        /// dispatch by a match, inlined, not through a pointer).
        #[derive(Debug, Clone, PartialEq)]
        pub enum Surface {
            $( $( $V(super::$m::$S), )? )+
        }

        impl Surface {
            /// [`Wall::contact`], inlined into the force loops.
            #[inline(always)]
            pub fn contact(&self, element: u32, x: [f64; 3], v: [f64; 3], r: f64) -> WallPoint {
                match self { $( $( Surface::$V(w) => <super::$m::$S as Wall>::contact(w, element, x, v, r), )? )+ }
            }

            /// [`Wall::surface_velocity`], inlined into the force loops.
            #[inline(always)]
            pub fn surface_velocity(&self, element: u32, at: [f64; 3]) -> [f64; 3] {
                match self { $( $( Surface::$V(w) => <super::$m::$S as Wall>::surface_velocity(w, element, at), )? )+ }
            }

            /// [`Wall::moving`], inlined into the force loops.
            #[inline(always)]
            pub fn moving(&self) -> Option<&super::motion::WallState> {
                match self { $( $( Surface::$V(w) => <super::$m::$S as Wall>::moving(w), )? )+ }
            }

            /// [`Wall::torque_point`], inlined into the force loops.
            #[inline(always)]
            pub fn torque_point(&self) -> [f64; 3] {
                match self { $( $( Surface::$V(w) => <super::$m::$S as Wall>::torque_point(w), )? )+ }
            }

            /// [`Wall::law_slot`].
            #[inline(always)]
            pub fn law_slot(&self, element: u32) -> usize {
                match self { $( $( Surface::$V(w) => <super::$m::$S as Wall>::law_slot(w, element), )? )+ }
            }

            /// The wall's interface.
            pub fn wall(&self) -> &dyn Wall {
                match self { $( $( Surface::$V(w) => w as &super::$m::$S, )? )+ }
            }
        }
    };
}

/// `keys` with the surfaces first, then the walls of boundary particles,
/// each group in registry order.
pub fn listing(keys: Vec<&'static str>) -> Vec<&'static str> {
    let (particles, surfaces): (Vec<_>, Vec<_>) =
        keys.into_iter().partition(|k| is_particles_key(k));
    surfaces.into_iter().chain(particles).collect()
}

/// The keys of the types that are surfaces, in registry order.
pub fn surfaces() -> Vec<&'static str> {
    KEYS.iter()
        .copied()
        .filter(|k| !is_particles_key(k))
        .collect()
}

/// The surface types' keys joined as "a, b or c" ("plane or cylinder").
pub fn surface_kinds_or() -> String {
    let surfaces = surfaces();
    match surfaces.split_last() {
        Some((last, rest)) if !rest.is_empty() => format!("{} or {last}", rest.join(", ")),
        Some((last, _)) => last.to_string(),
        None => String::new(),
    }
}

impl Surface {
    /// The wall as side 2 of its contact `point` with a sphere at `x` of
    /// radius `r` on element `element`: no lever arm or 1/I, moving at its
    /// surface velocity at the contact point (x − r n̂, n̂ the wall's
    /// normal into the sphere) and spinning with the wall (zero for a
    /// fixed wall): the rolling resistance sees the sphere's spin relative
    /// to the wall's, so a sphere carried round rigidly by a drum feels
    /// none.
    #[inline(always)]
    pub fn side(&self, element: u32, point: &WallPoint, x: [f64; 3], r: f64) -> Side {
        let n = point.normal;
        let at = [x[0] - r * n[0], x[1] - r * n[1], x[2] - r * n[2]];
        match self.moving() {
            None => Side::wall(self.surface_velocity(element, at)),
            Some(m) => Side {
                spin: m.spin,
                ..Side::wall(m.velocity_at(at))
            },
        }
    }

    /// This wall (its reference placement) moved to `state`; itself when
    /// its type does not move.
    pub fn posed(&self, state: &super::motion::WallState) -> Surface {
        self.wall().posed(state).unwrap_or_else(|| self.clone())
    }

    /// Index of the wall in file order.
    pub fn file_index(&self) -> usize {
        self.wall().file_index()
    }
}

// The registry: one row per wall type, `Variant => module::SetupType` and,
// for a surface, its engine record. A new type: its file under `walls/`
// and one row here.
wall_registry! {
    /// A fixed plane (`walls::plane`): an elastic half-space.
    Plane => plane::Plane, PlaneWall;
    /// A wall of boundary particles (`walls::boundary_particles`): fixed
    /// spheres tiling a plane.
    BoundaryParticles => boundary_particles::BoundaryParticles;
    /// A fixed cylinder (`walls::cylinder`): a tube or a post.
    Cylinder => cylinder::Cylinder, CylinderWall;
    /// A fixed triangle mesh (`walls::mesh`): a part read from STL or OBJ.
    Mesh => mesh::Mesh, MeshWall;
}

/// How the `Debug` of a wall of boundary particles begins (the checkpoint
/// fingerprint's text of a wall: `crate::fingerprint`).
pub(crate) const PARTICLES_DEBUG: &str = "BoundaryParticles {";

/// Three finite numbers.
pub(crate) fn finite3(v: [f64; 3]) -> bool {
    v.iter().all(|x| x.is_finite())
}

/// `[x, y, z]` for a message.
pub(crate) fn show3(v: [f64; 3]) -> String {
    format!("[{}, {}, {}]", v[0], v[1], v[2])
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::setup::{BoundaryParticles, Cylinder, Plane};

    /// The checkpoint fingerprint prints each wall's `Debug`; before the
    /// registry a wall was a struct variant of `WallSetup`, whose derived
    /// `Debug` is written out here by hand (a checkpoint of an earlier
    /// version must still match its scene).
    #[test]
    fn a_walls_debug_is_the_struct_variants_of_before() {
        let plane = WallSetup::Plane(Plane {
            point: [0.0, 0.5, -1.0],
            normal: [0.0, 0.0, 2.0],
            material: 1,
        });
        assert_eq!(
            format!("{plane:?}"),
            "Plane { point: [0.0, 0.5, -1.0], normal: [0.0, 0.0, 2.0], material: 1 }"
        );
        let tube = WallSetup::Cylinder(Cylinder {
            point: [1.0, 2.0, 3.0],
            axis: [0.0, 0.0, 1.0],
            radius: 0.25,
            inside: true,
            length: Some(0.5),
            material: 0,
        });
        assert_eq!(
            format!("{tube:?}"),
            "Cylinder { point: [1.0, 2.0, 3.0], axis: [0.0, 0.0, 1.0], radius: 0.25, \
             inside: true, length: Some(0.5), material: 0 }"
        );
        let tiles = WallSetup::BoundaryParticles(BoundaryParticles {
            first_body: 7,
            count: 3,
        });
        assert_eq!(
            format!("{tiles:?}"),
            "BoundaryParticles { first_body: 7, count: 3 }"
        );
        assert!(format!("{tiles:?}").starts_with(PARTICLES_DEBUG));
        assert!(!format!("{plane:?}").starts_with(PARTICLES_DEBUG));
        assert_eq!(tiles.bodies(), Some(7..10));
        assert!(tiles.is_particles() && !tube.is_particles());
        assert_eq!(
            (plane.summary(), tube.summary(), tiles.summary()),
            (
                "plane".into(),
                "cylinder".into(),
                "3 boundary particles".into()
            )
        );
    }

    /// Registry order is the order the types were added (the scene file's
    /// unknown-key message lists them so); people's listings put the
    /// surfaces first.
    #[test]
    fn orders_of_the_keys() {
        assert_eq!(KEYS, ["plane", "boundary_particles", "cylinder", "mesh"]);
        assert_eq!(
            listing(KEYS.to_vec()),
            ["plane", "cylinder", "mesh", "boundary_particles"]
        );
        assert_eq!(surface_kinds_or(), "plane, cylinder or mesh");
        let err = toml::from_str::<WallSection>("material = \"g\"\ncone = 1").unwrap_err();
        assert!(
            err.to_string().contains(
                "expected one of `plane`, `boundary_particles`, `cylinder`, `mesh`, \
                 `material`, `friction`, `rolling_friction`, `motion`, `oscillation`, `servo`"
            ),
            "{err}"
        );
        let s: WallSection = toml::from_str(
            "material = \"g\"\ncylinder = { point = [0, 0, 0], axis = [0, 0, 1], radius = 1.0 }\n\
             plane = { point = [0, 0, 0], normal = [0, 0, 1] }",
        )
        .unwrap();
        assert_eq!(s.given(), ["plane", "cylinder"]);
    }

    /// Every registered type shows in the key table (its rows, under its
    /// own key) and once in the listing.
    #[test]
    fn every_type_has_its_keys_and_one_place_in_the_listing() {
        let table = keys();
        for key in KEYS {
            let prefix = format!("wall[K].{key}.");
            assert!(
                table.iter().any(|k| k.key.starts_with(&prefix)),
                "{key}: no key rows"
            );
            assert_eq!(
                listing(KEYS.to_vec()).iter().filter(|k| *k == key).count(),
                1
            );
        }
        assert!(table
            .iter()
            .all(|k| !k.meaning.is_empty() && !k.allowed.is_empty()));
    }

    /// The law rows a wall declares (which the time-step rule reads) are
    /// the rows its engine record indexes: element e's `law_slot` −
    /// first row is e's row, and a capped tube's rows are the tube's
    /// curvature −R_c (inside) and flat caps.
    #[test]
    fn law_rows_are_the_rows_the_built_wall_indexes() {
        let mut setup = crate::setup::SceneSetup::new(
            crate::setup::DomainSetup {
                lower: [-1.0; 3],
                upper: [1.0; 3],
                periodic: [false; 3],
            },
            dembound_physics::contact::ContactModel::elastic(
                dembound_physics::contact::NormalLaw::Hertz,
            ),
            crate::setup::TimeStep::Fixed(1e-6),
            crate::setup::RunLength::Steps(1),
        );
        setup.materials.push(crate::setup::NamedMaterial {
            name: "g".into(),
            material: dembound_physics::material::Material {
                density: 1000.0,
                youngs_modulus: 1e7,
                poisson_ratio: 0.3,
            },
        });
        let walls = [
            WallSetup::Plane(Plane {
                point: [0.0; 3],
                normal: [0.0, 0.0, 3.0],
                material: 0,
            }),
            WallSetup::Cylinder(Cylinder {
                point: [0.0; 3],
                axis: [0.0, 0.0, 2.0],
                radius: 0.5,
                inside: true,
                length: Some(1.0),
                material: 0,
            }),
            WallSetup::Cylinder(Cylinder {
                point: [0.0; 3],
                axis: [1.0, 0.0, 0.0],
                radius: 0.5,
                inside: false,
                length: None,
                material: 0,
            }),
        ];
        let expected = [
            vec![(0, Curvature::Flat)],
            vec![(0, Curvature::Radius(-0.5)), (0, Curvature::Flat)],
            vec![(0, Curvature::Radius(0.5))],
        ];
        for (w, (wall, rows)) in walls.iter().zip(&expected).enumerate() {
            assert_eq!(&wall.law_rows(), rows);
            let first = 10;
            let Ok(Some(surface)) = wall.build(w, &setup, first) else {
                panic!("wall {w} builds");
            };
            let elements = surface.wall().elements();
            let used: Vec<usize> = (0..elements).map(|e| surface.law_slot(e) - first).collect();
            // Every row used, none beyond.
            assert_eq!(
                used.iter().max().map(|m| m + 1),
                Some(rows.len()),
                "{used:?}"
            );
            assert_eq!(surface.file_index(), w);
        }
        // A bad value is named by the type's build.
        let bad = WallSetup::Cylinder(Cylinder {
            point: [0.0; 3],
            axis: [0.0; 3],
            radius: 0.5,
            inside: true,
            length: None,
            material: 0,
        });
        let err = bad.build(3, &setup, 0).unwrap_err().to_string();
        assert!(err.contains("wall[3].cylinder.axis"), "{err}");
    }
}
