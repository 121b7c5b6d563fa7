//! The friction laws of a scene: the composer's [`ContactLaw`] per pair
//! of body classes and per class and wall row, or computed per contact
//! when there are too many classes.

use dembound_physics::contact::tangential::{effective_shear_modulus, mix_friction, FrictionPair};
use dembound_physics::contact::ContactLaw;
use dembound_physics::material::{Material, PairProperties};

use crate::bodies::Bodies;
use crate::dynamics::contacts::{class_info, LawTable};
use crate::setup::FrictionSetup;

/// The friction laws of a scene, tabulated over the body classes of the
/// [`LawTable`] when it has them.
#[derive(Debug, Clone)]
pub struct FrictionTable {
    pub setup: FrictionSetup,
    materials: Vec<Material>,
    /// The wall rows of the law table (material, wall, curvature).
    plane_surfaces: Vec<crate::walls::LawSlot>,
    /// Body classes of the tables (0: no tables).
    pub(crate) classes: usize,
    /// Per class pair (a · classes + b): the normal law beside its
    /// friction, so that the force loops read both by reference from one
    /// row (no per-contact copies).
    pub(crate) pairs: Vec<FrictionLaw>,
    /// Per class and plane (a · planes + p).
    pub(crate) planes: Vec<FrictionLaw>,
    /// Some surface has rolling friction (μ_r > 0): the rolling springs
    /// are stored and evaluated; else they are skipped entirely.
    pub(super) rolling: bool,
}

/// The normal law and the friction of one class pair or class–plane: the
/// physics crate's contact composer.
pub type FrictionLaw = ContactLaw;

impl FrictionTable {
    pub fn new(setup: FrictionSetup, laws: &LawTable) -> Self {
        let plane_surfaces = laws.slots.clone();
        let rolling = setup.model.rolling_friction != 0.0
            || setup.materials.iter().flatten().any(|&(_, r)| r != 0.0)
            || setup.walls.iter().flatten().any(|&(_, r)| r != 0.0);
        let mut table = FrictionTable {
            setup,
            materials: laws.materials.clone(),
            plane_surfaces,
            classes: 0,
            pairs: Vec::new(),
            planes: Vec::new(),
            rolling,
        };
        // The law table's classes (`LawTable::class_keys`).
        let Some(keys) = laws.class_keys() else {
            return table;
        };
        let classes = keys.len();
        let info = |c: usize| class_info(keys[c]);
        for a in 0..classes {
            for b in 0..classes {
                let (ra, ma, mata) = info(a);
                let (rb, mb, matb) = info(b);
                let p = table.compute_pair(laws, ra, ma, mata, rb, mb, matb);
                table.pairs.push(p);
            }
        }
        for a in 0..classes {
            for p in 0..table.plane_surfaces.len() {
                let (ra, ma, mata) = info(a);
                let f = table.compute_plane(laws, ra, ma, mata, p);
                table.planes.push(f);
            }
        }
        table.classes = classes;
        table
    }

    #[allow(clippy::too_many_arguments)]
    fn compute_pair(
        &self,
        laws: &LawTable,
        ra: f64,
        ma: f64,
        mata: usize,
        rb: f64,
        mb: f64,
        matb: usize,
    ) -> FrictionLaw {
        let (a, b) = (&self.materials[mata], &self.materials[matb]);
        let props = PairProperties::spheres(ra, ma, a, rb, mb, b);
        let law = laws.model.pair(&props);
        let (mu_a, roll_a) = self.setup.of_material(mata);
        let (mu_b, roll_b) = self.setup.of_material(matb);
        let friction = self.setup.model.pair(
            &law,
            &props,
            effective_shear_modulus(a, b),
            mix_friction(mu_a, mu_b),
            mix_friction(roll_a, roll_b),
        );
        let friction = self
            .without_dashpot_if_off(friction)
            .with_spring_rotation(self.setup.spring_rotation);
        FrictionLaw {
            law,
            friction,
            torque_arm: self.setup.torque_arm,
        }
    }

    fn compute_plane(
        &self,
        laws: &LawTable,
        r: f64,
        m: f64,
        mat: usize,
        plane: usize,
    ) -> FrictionLaw {
        let row = self.plane_surfaces[plane];
        let (wall_material, wall) = (row.material, row.wall);
        let (a, w) = (
            &self.materials[mat],
            &self.materials[wall_material as usize],
        );
        let props = row.properties(r, m, a, w);
        let law = laws.model.pair(&props);
        let (mu_a, roll_a) = self.setup.of_material(mat);
        let (mu_w, roll_w) = self.setup.of_wall(wall, wall_material as usize);
        let friction = self.setup.model.pair(
            &law,
            &props,
            effective_shear_modulus(a, w),
            mix_friction(mu_a, mu_w),
            mix_friction(roll_a, roll_w),
        );
        let friction = self
            .without_dashpot_if_off(friction)
            .with_spring_rotation(self.setup.spring_rotation);
        FrictionLaw {
            law,
            friction,
            torque_arm: self.setup.torque_arm,
        }
    }

    /// `friction` without its tangential dashpot under
    /// `contact.tangential_damping = false`.
    fn without_dashpot_if_off(&self, friction: FrictionPair) -> FrictionPair {
        if self.setup.tangential_damping {
            friction
        } else {
            friction.without_tangential_damping()
        }
    }

    /// Whether any surface has rolling friction.
    pub fn rolling(&self) -> bool {
        self.rolling
    }

    /// The law and friction of bodies i and j: a reference into the table,
    /// or computed into `scratch` when there is no table (too many
    /// classes).
    #[inline(always)]
    pub fn pair<'s>(
        &'s self,
        laws: &LawTable,
        bodies: &Bodies,
        i: usize,
        j: usize,
        scratch: &'s mut Option<FrictionLaw>,
    ) -> &'s FrictionLaw {
        if self.classes > 0 {
            let (a, b) = (bodies.class[i] as usize, bodies.class[j] as usize);
            &self.pairs[a * self.classes + b]
        } else {
            scratch.insert(self.compute_pair(
                laws,
                bodies.radius[i],
                bodies.mass[i],
                bodies.material[i] as usize,
                bodies.radius[j],
                bodies.mass[j],
                bodies.material[j] as usize,
            ))
        }
    }

    /// The law and friction of body i against plane `plane` (as
    /// [`Self::pair`]).
    #[inline(always)]
    pub fn plane<'s>(
        &'s self,
        laws: &LawTable,
        bodies: &Bodies,
        i: usize,
        plane: usize,
        scratch: &'s mut Option<FrictionLaw>,
    ) -> &'s FrictionLaw {
        if self.classes > 0 {
            &self.planes[bodies.class[i] as usize * self.plane_surfaces.len() + plane]
        } else {
            scratch.insert(self.compute_plane(
                laws,
                bodies.radius[i],
                bodies.mass[i],
                bodies.material[i] as usize,
                plane,
            ))
        }
    }
}
