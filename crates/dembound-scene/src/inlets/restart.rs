//! The inlets in a checkpoint (issue 28): what a restart needs to go on
//! as the uninterrupted run — every inserted sphere's radius, mass and
//! material (their state is the checkpoint's, by input id like every
//! body's), each inlet's spheres due and what it inserted so far.

use serde::{Deserialize, Serialize};

use super::engine::{assign_classes, push_sphere};
use super::Inserted;
use crate::error::SceneError;
use crate::pipeline::World;

/// The inlets' part of a checkpoint.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct InletsRecord {
    /// Radius (m), mass (kg) and material index of every sphere placed,
    /// input ids from the scene's sphere count on, in order (those removed
    /// since included: ids stay).
    pub spheres: Vec<(f64, f64, u32)>,
    /// Per inlet (file order).
    pub inlets: Vec<InletRecord>,
}

/// One inlet's state in a checkpoint.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct InletRecord {
    /// Spheres due so far (placed or not).
    pub due: u64,
    /// What it inserted so far.
    pub so_far: Inserted,
    /// Steps between its events: the run's, kept on restart (the default
    /// depends on the run's length, which a restart may change).
    pub every: u64,
}

/// The record of `world`'s inlets (`None` without inlets).
pub(crate) fn record(world: &World) -> Option<InletsRecord> {
    let i = world.inlets.as_ref()?;
    Some(InletsRecord {
        spheres: i.placed.clone(),
        inlets: i
            .inlets
            .iter()
            .map(|i| InletRecord {
                due: i.due,
                so_far: i.so_far,
                every: i.every,
            })
            .collect(),
    })
}

/// Before a restore: appends the spheres the checkpoint's inlets placed to
/// `world`'s bodies (input ids after the scene's, state to be set from the
/// checkpoint), their law classes as the run grew them, and sets each
/// inlet's counts. A scene with inlets needs the record (a checkpoint
/// written before inlets could restart lacks it); the scene must have the
/// checkpoint's number of inlets.
pub(crate) fn restore(world: &mut World, record: Option<&InletsRecord>) -> Result<(), SceneError> {
    let Some(r) = record else {
        return match world.inlets.as_ref() {
            Some(i) if !i.inlets.is_empty() => Err(SceneError::Checkpoint(
                "the scene has [[inlet]] sections (inlet[0]) but the checkpoint records no \
                 inlets: it was written by a run without inlets or by a version that did not \
                 record them"
                    .into(),
            )),
            _ => Ok(()),
        };
    };
    let have = world.inlets.as_ref().map_or(0, |i| i.inlets.len());
    if have != r.inlets.len() {
        return Err(SceneError::Checkpoint(format!(
            "its run had {} [[inlet]] section(s), the scene {have}: a restart keeps the inlets \
             (their counts go on)",
            r.inlets.len()
        )));
    }
    let materials = world.laws.materials.len();
    if let Some(&(radius, mass, m)) = r.spheres.iter().find(|s| {
        !(s.0.is_finite()
            && s.0 > 0.0
            && s.1.is_finite()
            && s.1 > 0.0
            && (s.2 as usize) < materials)
    }) {
        return Err(SceneError::Checkpoint(format!(
            "an inserted sphere of radius {radius:e} m, mass {mass:e} kg, material {m} is out \
             of range"
        )));
    }
    let first_new = world.bodies.len();
    let first_id = u32::try_from(first_new).unwrap_or(u32::MAX);
    for (k, &(radius, mass, material)) in r.spheres.iter().enumerate() {
        let id = first_id.saturating_add(u32::try_from(k).unwrap_or(u32::MAX));
        push_sphere(world, [0.0; 3], radius, mass, [0.0; 3], material, id);
    }
    if !r.spheres.is_empty() {
        let keys: Vec<_> = r
            .spheres
            .iter()
            .map(|&(radius, mass, material)| (radius.to_bits(), mass.to_bits(), material))
            .collect();
        assign_classes(world, first_new, &keys);
    }
    if let Some(i) = world.inlets.as_mut() {
        for (inlet, saved) in i.inlets.iter_mut().zip(&r.inlets) {
            inlet.due = saved.due;
            inlet.so_far = saved.so_far;
            inlet.every = saved.every.max(1);
        }
        i.placed.clone_from(&r.spheres);
        i.next_id = first_id.saturating_add(u32::try_from(r.spheres.len()).unwrap_or(u32::MAX));
    }
    Ok(())
}
