//! The setup checks of issue 24 ([`crate::setup_checks`]) run on a
//! resolved scene, naming each sphere by where the scene file got it:
//! `particles[1].spheres[3]`, `particles[0].lammps_data` sphere 12 (the
//! 13th atom in id order), `wall[2].boundary_particles` sphere 5, always
//! with the input index.

use super::config::SceneFile;
use crate::setup::SceneSetup;
use crate::SceneError;
use std::ops::Range;

/// Checks `setup` as [`crate::setup_checks::check`] does, with the spheres
/// named by their source ([`label`]); returns the warnings.
pub fn check(
    setup: &SceneSetup,
    file: &SceneFile,
    groups: &[Range<usize>],
    wall_bodies: &[Range<usize>],
) -> Result<Vec<String>, SceneError> {
    crate::setup_checks::check(setup, &label(file, groups, wall_bodies))
}

/// The name of the sphere of input index `k` by its source: the group's
/// (`groups`, file order) or the wall's (`wall_bodies`), else the input
/// index alone.
pub fn label<'a>(
    file: &'a SceneFile,
    groups: &'a [Range<usize>],
    wall_bodies: &'a [Range<usize>],
) -> impl Fn(usize) -> String + 'a {
    move |k: usize| -> String {
        for (i, range) in groups.iter().enumerate() {
            if range.contains(&k) {
                let j = k - range.start;
                let p = file.particles.get(i);
                let source = match p {
                    Some(p) if p.spheres.is_some() => {
                        return format!("`particles[{i}].spheres[{j}]` (input index {k})")
                    }
                    Some(p) if p.lammps_data.is_some() => "lammps_data",
                    Some(p) if p.csv.is_some() => "csv",
                    Some(p) if p.lattice.is_some() => "lattice",
                    Some(p) if p.random.is_some() => "random",
                    _ => "",
                };
                return format!("`particles[{i}].{source}` sphere {j} (input index {k})");
            }
        }
        for (w, range) in wall_bodies.iter().enumerate() {
            if range.contains(&k) {
                let j = k - range.start;
                let kind = file.walls.get(w).and_then(|x| x.key()).unwrap_or("");
                return format!("`wall[{w}].{kind}` sphere {j} (input index {k})");
            }
        }
        crate::setup_checks::by_index(k)
    }
}
