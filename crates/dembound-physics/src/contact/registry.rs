//! The one registry of contact sub-models (after LAMMPS GRANULAR's
//! `gran_sub_mod_register`): one row per normal law and per damping model,
//! with its name (the names the CLI uses), parameters with units and
//! allowed ranges, capability flags and type (the constructor), plus the
//! one table of which damping combines with which normal laws
//! ([`DampingRow::combines_with`], by [`Family`]).
//!
//! Adding a normal law is one file under `normal/` and one row here (the
//! row names the file's module, which `normal/mod.rs` declares from the
//! rows: `normal_modules`); a damping is one file under `damping/`, one
//! row and its `pub mod` line: the macros below generate the configuration enum
//! ([`NormalLaw`], [`DampingKind`]), the per-pair enum dispatched on the
//! hot path ([`NormalPair`], [`DampingPair`]: `Copy`, no `dyn`), the row
//! lookup and the parsing by name from the rows.

use super::damping::{self, DampingSetup, DampingSubModel, Dissipation};
use super::normal::{self, NormalSubModel};
use super::{Calibration, ContactHistory};
use crate::error::PhysicsError;
use crate::material::PairProperties;
use std::fmt;

/// An allowed interval of a parameter.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Range {
    /// Lower bound.
    pub min: f64,
    /// Whether `min` itself is allowed.
    pub min_inclusive: bool,
    /// Upper bound (`f64::INFINITY`: none; infinite values are never allowed).
    pub max: f64,
    /// Whether `max` itself is allowed.
    pub max_inclusive: bool,
}

impl Range {
    /// min ≤ x ≤ max.
    pub const fn closed(min: f64, max: f64) -> Self {
        Self {
            min,
            min_inclusive: true,
            max,
            max_inclusive: true,
        }
    }

    /// x > 0, finite.
    pub const POSITIVE: Range = Range {
        min: 0.0,
        min_inclusive: false,
        max: f64::INFINITY,
        max_inclusive: false,
    };

    /// x ≥ 0, finite.
    pub const NON_NEGATIVE: Range = Range {
        min: 0.0,
        min_inclusive: true,
        max: f64::INFINITY,
        max_inclusive: false,
    };

    /// 0 < e ≤ 1.
    pub const RESTITUTION: Range = Range {
        min: 0.0,
        min_inclusive: false,
        max: 1.0,
        max_inclusive: true,
    };

    /// Whether `x` is allowed (NaN and ±∞ never are).
    pub fn contains(&self, x: f64) -> bool {
        x.is_finite()
            && (x > self.min || (self.min_inclusive && x == self.min))
            && (x < self.max || (self.max_inclusive && x == self.max))
    }
}

impl fmt::Display for Range {
    /// `1 ≤ x ≤ 3`, `x > 0` (finite), `0 < x ≤ 1`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let lo = if self.min_inclusive { "≤" } else { "<" };
        let hi = if self.max_inclusive { "≤" } else { "<" };
        if self.max == f64::INFINITY {
            let op = if self.min_inclusive { "≥" } else { ">" };
            write!(f, "finite and {op} {}", self.min)
        } else {
            write!(f, "{} {lo} x {hi} {}", self.min, self.max)
        }
    }
}

/// One parameter of a sub-model.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ParamSpec {
    /// Configuration key under `contact.` (`exponent`, `restitution`, …).
    pub key: &'static str,
    /// Symbol in the formulas (α, e, k_n, …).
    pub symbol: &'static str,
    /// SI unit (`1` for dimensionless).
    pub unit: &'static str,
    /// Allowed values.
    pub range: Range,
}

impl ParamSpec {
    /// Checks `value`: an error naming the key, the value and the range.
    pub fn check(&self, value: f64) -> Result<f64, PhysicsError> {
        if self.range.contains(value) {
            Ok(value)
        } else {
            Err(PhysicsError::new(
                format!("contact.{}", self.key),
                value,
                format!("{} ({}, {})", self.range, self.symbol, self.unit),
            ))
        }
    }
}

/// The shape of a normal law's elastic part, which decides the damping it
/// combines with.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Family {
    /// F = k h (k in N/m): a damped oscillator with viscous damping.
    Linear,
    /// F = k h^(3/2): the Hertz dampings (Tsuji, viscoelastic).
    Hertzian,
    /// F = k h^α, general α: elastic only.
    Power,
    /// Dissipative on its own (hysteresis): no added damping.
    Hysteretic,
}

/// What a sub-model needs or can do.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Capabilities {
    /// The force depends on the overlap rate.
    pub rate_dependent: bool,
    /// The force depends on the contact's history ([`ContactHistory`]).
    pub history: bool,
    /// Without the clamp, the force can pull (F < 0 at h > 0).
    pub attraction: bool,
}

/// A registry row of a normal law.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NormalRow {
    /// Configuration name (`law = "…"`).
    pub name: &'static str,
    /// The force law, one line.
    pub formula: &'static str,
    /// Parameters, in the constructor's order.
    pub params: &'static [ParamSpec],
    /// The shape of its elastic part.
    pub family: Family,
    /// Capability flags.
    pub capabilities: Capabilities,
}

/// A registry row of a damping model.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DampingRow {
    /// Configuration name (`damping = "…"`).
    pub name: &'static str,
    /// The damping force, one line.
    pub formula: &'static str,
    /// The raw coefficient (`contact.damping_coefficient`) with its unit;
    /// `None`: the model takes no dissipation.
    pub coefficient: Option<ParamSpec>,
    /// The normal-law families it combines with: the compatibility table.
    pub combines_with: &'static [Family],
    /// Capability flags.
    pub capabilities: Capabilities,
}

impl DampingRow {
    /// Whether it combines with the normal law of `row`.
    pub fn combines(&self, row: &NormalRow) -> bool {
        self.combines_with.contains(&row.family)
    }
}

/// The target restitution, shared by Walton–Braun and the damping models.
pub const RESTITUTION: ParamSpec = ParamSpec {
    key: "restitution",
    symbol: "e",
    unit: "1",
    range: Range::RESTITUTION,
};

const ELASTIC: Capabilities = Capabilities {
    rate_dependent: false,
    history: false,
    attraction: false,
};

const DAMPED: Capabilities = Capabilities {
    rate_dependent: true,
    history: false,
    attraction: true,
};

macro_rules! normal_registry {
    ($( $(#[$doc:meta])* $V:ident $({ $($p:ident),+ })? => $m:ident::$T:ident = $row:expr; )+) => {
        /// Declares one module per row's file under `normal/` (invoked once
        /// in `normal/mod.rs`): a law's file is named only by its row.
        macro_rules! normal_modules {
            () => { $( pub mod $m; )+ };
        }
        pub(crate) use normal_modules;

        /// Which normal law, with its parameters (material-independent).
        #[derive(Debug, Clone, Copy, PartialEq)]
        pub enum NormalLaw {
            $( $(#[$doc])* $V $({ $(
                #[allow(missing_docs)]
                $p: f64
            ),+ })?, )+
        }

        /// A normal law resolved for one pair: the enum the hot path
        /// dispatches on.
        #[derive(Debug, Clone, Copy, PartialEq)]
        pub enum NormalPair {
            $( #[allow(missing_docs)] $V(normal::$m::$T), )+
        }

        #[allow(non_upper_case_globals)]
        mod normal_rows {
            use super::*;
            $( pub(super) const $V: NormalRow = $row; )+
        }

        /// Every normal law, one row each, in registry order.
        pub const NORMAL_LAWS: &[NormalRow] = &[ $( normal_rows::$V ),+ ];

        impl NormalLaw {
            /// Its registry row.
            pub fn row(&self) -> &'static NormalRow {
                match self { $( NormalLaw::$V { .. } => &normal_rows::$V, )+ }
            }

            /// Its parameter values, in the row's order.
            pub fn params(&self) -> Vec<f64> {
                match *self { $( NormalLaw::$V $({ $($p),+ })? => vec![$($($p),+)?], )+ }
            }

            /// The law of registry name `name` with `params` in the row's
            /// order (unchecked; `None` for an unknown name or too few values).
            pub fn from_params(name: &str, params: &[f64]) -> Option<NormalLaw> {
                $( if name == normal_rows::$V.name {
                    #[allow(unused_mut, unused_variables)]
                    let mut values = params.iter().copied();
                    return Some(NormalLaw::$V $({ $($p: values.next()?),+ })?);
                } )+
                None
            }

            /// The law for one pair.
            pub fn resolve(&self, pair: &PairProperties) -> NormalPair {
                match *self { $(
                    NormalLaw::$V $({ $($p),+ })? =>
                        NormalPair::$V(<normal::$m::$T as NormalSubModel>::new(&[$($($p),+)?], pair)),
                )+ }
            }
        }

        impl NormalPair {
            /// [`NormalSubModel::force`].
            #[inline(always)]
            pub fn force(&self, overlap: f64, overlap_rate: f64, history: &ContactHistory) -> f64 {
                match self { $( NormalPair::$V(law) => law.force(overlap, overlap_rate, history), )+ }
            }

            /// [`NormalSubModel::update`].
            #[inline(always)]
            pub fn update(&self, overlap: f64, overlap_rate: f64, history: &mut ContactHistory) {
                match self { $( NormalPair::$V(law) => law.update(overlap, overlap_rate, history), )+ }
            }

            /// [`NormalSubModel::elastic_energy`].
            #[inline]
            pub fn elastic_energy(&self, overlap: f64, history: &ContactHistory) -> f64 {
                match self { $( NormalPair::$V(law) => law.elastic_energy(overlap, history), )+ }
            }

            /// [`NormalSubModel::stiffness`].
            pub fn stiffness(&self) -> f64 {
                match self { $( NormalPair::$V(law) => law.stiffness(), )+ }
            }

            /// [`NormalSubModel::contact_time_estimate`].
            pub fn contact_time_estimate(&self, mass: f64, impact_speed: f64) -> f64 {
                match self { $( NormalPair::$V(law) => law.contact_time_estimate(mass, impact_speed), )+ }
            }

            /// Its registry row.
            pub fn row(&self) -> &'static NormalRow {
                match self { $( NormalPair::$V(_) => &normal_rows::$V, )+ }
            }
        }
    };
}

macro_rules! damping_registry {
    ($( $(#[$doc:meta])* $V:ident => $T:ty = $row:expr; )+) => {
        /// Which damping is added to the normal law.
        #[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
        pub enum DampingKind {
            $( $(#[$doc])* $V, )+
        }

        /// A damping model resolved for one pair.
        #[derive(Debug, Clone, Copy, PartialEq)]
        pub enum DampingPair {
            $( #[allow(missing_docs)] $V($T), )+
        }

        #[allow(non_upper_case_globals)]
        mod damping_rows {
            use super::*;
            $( pub(super) const $V: DampingRow = $row; )+
        }

        /// Every damping model, one row each, in registry order.
        pub const DAMPING_MODELS: &[DampingRow] = &[ $( damping_rows::$V ),+ ];

        impl DampingKind {
            /// Its registry row.
            pub fn row(&self) -> &'static DampingRow {
                match self { $( DampingKind::$V => &damping_rows::$V, )+ }
            }

            /// The damping of registry name `name`.
            pub fn from_name(name: &str) -> Option<DampingKind> {
                $( if name == damping_rows::$V.name { return Some(DampingKind::$V); } )+
                None
            }

            /// The model for one pair.
            pub fn resolve(&self, setup: &DampingSetup) -> DampingPair {
                match self { $( DampingKind::$V => DampingPair::$V(<$T as DampingSubModel>::new(setup)), )+ }
            }

            /// The model's own checks of a dissipation ([`DampingSubModel::check`]).
            pub fn check(
                &self,
                dissipation: Dissipation,
                calibration: Calibration,
                reference_speed: Option<f64>,
            ) -> Result<(), PhysicsError> {
                match self { $( DampingKind::$V => <$T as DampingSubModel>::check(dissipation, calibration, reference_speed), )+ }
            }
        }

        impl DampingPair {
            /// [`DampingSubModel::force`].
            #[inline(always)]
            pub fn force(&self, overlap: f64, overlap_rate: f64) -> f64 {
                match self { $( DampingPair::$V(d) => d.force(overlap, overlap_rate), )+ }
            }

            /// [`DampingSubModel::time_factor`].
            pub fn time_factor(&self, mass: f64, impact_speed: f64) -> f64 {
                match self { $( DampingPair::$V(d) => d.time_factor(mass, impact_speed), )+ }
            }

            /// Its registry row.
            pub fn row(&self) -> &'static DampingRow {
                match self { $( DampingPair::$V(_) => &damping_rows::$V, )+ }
            }
        }
    };
}

normal_registry! {
    /// α = 1: F = E_eff R_eff h (eq 4).
    Linear => linear::Linear = NormalRow {
        name: "linear",
        formula: "F = k h, k = E_eff R_eff (eq 4, α = 1)",
        params: &[],
        family: Family::Linear,
        capabilities: ELASTIC,
    };
    /// α = 3/2: F = E_eff √R_eff h^(3/2) (eq 4).
    Hertz => hertz::Hertz = NormalRow {
        name: "hertz",
        formula: "F = k h^(3/2), k = E_eff √R_eff (eq 4, α = 3/2)",
        params: &[],
        family: Family::Hertzian,
        capabilities: ELASTIC,
    };
    /// General exponent: F = E_eff R_eff^(2−α) h^α (eq 4).
    Power { exponent } => power::PowerLaw = NormalRow {
        name: "power",
        formula: "F = k h^α, k = E_eff R_eff^(2−α) (eq 4)",
        params: &[ParamSpec {
            key: "exponent",
            symbol: "α",
            unit: "1",
            range: Range::closed(1.0, 3.0),
        }],
        family: Family::Power,
        capabilities: ELASTIC,
    };
    /// Walton–Braun hysteretic linear law, k₁ = E_eff R_eff, k₂ = k₁/e².
    WaltonBraun { restitution } => walton_braun::WaltonBraun = NormalRow {
        name: "walton-braun",
        formula: "F = k₁ h loading, k₂ (h − h₀) unloading, ≥ 0; k₁ = E_eff R_eff, k₂ = k₁/e²",
        params: &[RESTITUTION],
        family: Family::Hysteretic,
        capabilities: Capabilities {
            rate_dependent: false,
            history: true,
            attraction: false,
        },
    };
    /// LAMMPS/LIGGGHTS `hooke`: F = k_n h with k_n given.
    Hooke { stiffness } => hooke::Hooke = NormalRow {
        name: "hooke",
        formula: "F = k_n h, k_n given (LAMMPS/LIGGGHTS hooke)",
        params: &[ParamSpec {
            key: "stiffness",
            symbol: "k_n",
            unit: "N/m",
            range: Range::POSITIVE,
        }],
        family: Family::Linear,
        capabilities: ELASTIC,
    };
    /// LAMMPS GRANULAR `hertz`: F = k_n √R_eff h^(3/2) with k_n given.
    HertzKn { stiffness } => hertz_kn::HertzKn = NormalRow {
        name: "hertz-kn",
        formula: "F = k_n √R_eff h^(3/2), k_n given (LAMMPS granular hertz)",
        params: &[ParamSpec {
            key: "stiffness",
            symbol: "k_n",
            unit: "Pa",
            range: Range::POSITIVE,
        }],
        family: Family::Hertzian,
        capabilities: ELASTIC,
    };
}

damping_registry! {
    /// Elastic (or the law's own hysteresis).
    #[default]
    None => damping::none::NoDamping = DampingRow {
        name: "none",
        formula: "F_d = 0",
        // `Option::None`: inside the generated row module `None` is this row.
        coefficient: Option::None,
        combines_with: &[Family::Linear, Family::Hertzian, Family::Power, Family::Hysteretic],
        capabilities: ELASTIC,
    };
    /// Linear spring–dashpot (viscous).
    Viscous => damping::viscous::Viscous = DampingRow {
        name: "viscous",
        formula: "F_d = c ḣ, c = 2ξ√(k m)",
        coefficient: Some(ParamSpec {
            key: "damping_coefficient",
            symbol: "c",
            unit: "N s/m",
            range: Range::NON_NEGATIVE,
        }),
        combines_with: &[Family::Linear],
        capabilities: DAMPED,
    };
    /// Tsuji-type Hertz damping (LIGGGHTS, EDEM).
    Tsuji => damping::tsuji::Tsuji = DampingRow {
        name: "tsuji",
        formula: "F_d = γ h^(1/4) ḣ, γ = √5 ξ √(k m)",
        coefficient: Some(ParamSpec {
            key: "damping_coefficient",
            symbol: "γ",
            unit: "N s/m^(5/4)",
            range: Range::NON_NEGATIVE,
        }),
        combines_with: &[Family::Hertzian],
        capabilities: DAMPED,
    };
    /// Kuwabara–Kono/Brilliantov viscoelastic Hertz damping.
    Viscoelastic => damping::viscoelastic::Viscoelastic = DampingRow {
        name: "viscoelastic",
        formula: "F_d = (3/2) k A h^(1/2) ḣ",
        coefficient: Some(ParamSpec {
            key: "damping_coefficient",
            symbol: "A",
            unit: "s",
            range: Range::NON_NEGATIVE,
        }),
        combines_with: &[Family::Hertzian],
        capabilities: DAMPED,
    };
}

/// The normal law's row of registry name `name`.
pub fn normal_row(name: &str) -> Option<&'static NormalRow> {
    NORMAL_LAWS.iter().find(|r| r.name == name)
}

/// Registry names of all normal laws, quoted and comma-separated (for errors and lists).
pub fn normal_names() -> String {
    quoted(NORMAL_LAWS.iter().map(|r| r.name))
}

/// Registry names of all damping models, quoted and comma-separated.
pub fn damping_names() -> String {
    quoted(DAMPING_MODELS.iter().map(|r| r.name))
}

/// The damping models that combine with `law`, quoted and comma-separated.
pub fn dampings_for(law: &NormalRow) -> String {
    quoted(
        DAMPING_MODELS
            .iter()
            .filter(|d| d.combines(law))
            .map(|d| d.name),
    )
}

fn quoted<'a>(names: impl Iterator<Item = &'a str>) -> String {
    names
        .map(|n| format!("\"{n}\""))
        .collect::<Vec<_>>()
        .join(", ")
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::contact::{ContactModel, Damping};
    use crate::material::{Material, PairProperties};

    /// A value inside each parameter's range.
    fn inside(p: &ParamSpec) -> f64 {
        if p.range.max.is_finite() {
            0.5 * (p.range.min + p.range.max)
        } else {
            p.range.min + 1.0
        }
    }

    #[test]
    fn names_are_unique_and_round_trip() {
        for (i, row) in NORMAL_LAWS.iter().enumerate() {
            assert!(NORMAL_LAWS[..i].iter().all(|r| r.name != row.name));
            let params: Vec<f64> = row.params.iter().map(inside).collect();
            let law = NormalLaw::from_params(row.name, &params).expect(row.name);
            assert_eq!(law.row(), row);
            assert_eq!(law.params(), params);
            assert_eq!(normal_row(row.name), Some(row));
            // Too few values: no law.
            if !row.params.is_empty() {
                assert!(NormalLaw::from_params(row.name, &[]).is_none());
            }
            // The per-pair law carries the same row.
            let m = Material::rigid(1000.0);
            let pair = PairProperties::sphere_plane(1e-3, 1e-6, &m, &m);
            assert_eq!(law.resolve(&pair).row(), row);
        }
        assert!(NormalLaw::from_params("hooke-ish", &[]).is_none());
        for (i, row) in DAMPING_MODELS.iter().enumerate() {
            assert!(DAMPING_MODELS[..i].iter().all(|r| r.name != row.name));
            assert_eq!(DampingKind::from_name(row.name).map(|k| k.row()), Some(row));
        }
    }

    #[test]
    fn the_names_the_cli_uses() {
        let normal: Vec<&str> = NORMAL_LAWS.iter().map(|r| r.name).collect();
        for name in ["linear", "hertz", "power", "walton-braun"] {
            assert!(normal.contains(&name), "{name}");
        }
        let damping: Vec<&str> = DAMPING_MODELS.iter().map(|r| r.name).collect();
        assert_eq!(&damping[..4], ["none", "viscous", "tsuji", "viscoelastic"]);
    }

    #[test]
    fn validation_follows_the_compatibility_table() {
        // The bounce study's table: viscous with linear, tsuji and
        // viscoelastic with hertz, walton-braun and power undamped.
        let law = |name: &str| {
            let row = normal_row(name).expect(name);
            let params: Vec<f64> = row.params.iter().map(inside).collect();
            NormalLaw::from_params(name, &params).expect(name)
        };
        let damping = |kind: DampingKind| match kind {
            DampingKind::None => Damping::NONE,
            _ => Damping::new(kind, Dissipation::Coefficient(0.1)),
        };
        for (name, kind, ok) in [
            ("linear", DampingKind::Viscous, true),
            ("linear", DampingKind::Tsuji, false),
            ("hertz", DampingKind::Tsuji, true),
            ("hertz", DampingKind::Viscoelastic, true),
            ("hertz", DampingKind::Viscous, false),
            ("power", DampingKind::Viscous, false),
            ("walton-braun", DampingKind::Viscous, false),
            ("walton-braun", DampingKind::None, true),
        ] {
            let model = ContactModel::damped(law(name), damping(kind));
            assert_eq!(model.validate().is_ok(), ok, "{name} + {kind:?}");
            if !ok {
                let err = model.validate().unwrap_err();
                assert_eq!(err.key, "contact.damping");
                assert!(err.allowed.contains(&format!("law = \"{name}\"")), "{err}");
            }
        }
        // Every row is consistent with the table it defines.
        for n in NORMAL_LAWS {
            assert!(
                DAMPING_MODELS[0].combines(n),
                "none combines with {}",
                n.name
            );
        }
    }

    #[test]
    fn ranges_name_their_bounds() {
        assert_eq!(Range::closed(1.0, 3.0).to_string(), "1 ≤ x ≤ 3");
        assert_eq!(Range::RESTITUTION.to_string(), "0 < x ≤ 1");
        assert_eq!(Range::POSITIVE.to_string(), "finite and > 0");
        assert!(!Range::POSITIVE.contains(0.0));
        assert!(!Range::NON_NEGATIVE.contains(f64::INFINITY));
        assert!(!Range::NON_NEGATIVE.contains(f64::NAN));
        assert!(Range::RESTITUTION.contains(1.0));
        let err = RESTITUTION.check(1.5).unwrap_err();
        assert_eq!(
            err.to_string(),
            "contact.restitution = 1.5: allowed 0 < x ≤ 1 (e, 1)"
        );
    }
}
