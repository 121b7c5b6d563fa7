//! A many-particle scene (`dembound scene`'s TOML) as a LIGGGHTS deck
//! (checked with Debian's LIGGGHTS 3.8.0; docs/export-liggghts.md,
//! "Scenes"): the spheres as a data file (`atom_style granular`), one atom
//! type per material, plane walls as `fix wall/gran … primitive`, triangle
//! meshes as `fix mesh/surface` on an ASCII STL of the placed, cleaned
//! triangles written next to the deck, and `fix wall/gran … mesh`.
//!
//! Why one type per material, with the material's own E and ν: LIGGGHTS's
//! `model hertz` mixes Y* = 1/((1 − ν_i²)/Y_i + (1 − ν_j²)/Y_j) and uses
//! F = 4/3 Y* √(R* δ) δ with R* = R_i R_j/(R_i + R_j) (R* = R against a
//! wall): that is dembound's F = E_eff √R_eff h^(3/2) with eq 6's
//! E_eff = 4/3 Y*, for every pair, sphere or wall. So unlike LAMMPS no
//! pre-mixed number is needed: the wall's type carries its material.
//!
//! The subset exported (everything else is refused naming the key; damping
//! and friction: `liggghts_contact.rs`):
//! free spheres, and fixed spheres (`fixed = true`, boundary-particle
//! walls) as a frozen group (`fix freeze`, not integrated, frozen pairs
//! excluded: LIGGGHTS's pair gran then takes m_eff = the free sphere's
//! mass, `pair_gran_base.h`); `contact.law = { hooke = k }` undamped as
//! `model hooke/stiffness` (with friction the linear spring, and epsd2
//! rolling friction where k_t = 2.25 k μ_r²: liggghts_contact.rs);
//! `contact.law = "hertz"` with no damping
//! (`coefficientRestitution` 1 makes LIGGGHTS's hertz damping exactly zero)
//! or Tsuji damping given by a restitution; no friction (`tangential
//! no_history`, μ = 0) or the Mindlin spring with Coulomb friction
//! (`tangential history`), no rolling friction under Hertz; gravity; velocity Verlet
//! (`nve/sphere`); axis-aligned planes; meshes. Rigid materials (E = ∞)
//! are refused: LIGGGHTS needs a finite modulus per type.

pub use crate::liggghts_contact::{spring_rotation_note, torque_arm_note};
use crate::liggghts_gates::WallLines;
use crate::liggghts_motion::Sweep;
use crate::{num, Code, Deck, DeckFile, Error, Result};
use dembound_scene::io::resolve::ResolvedScene;
use dembound_scene::setup::{SceneSetup, Scheme, WallSetup};
use dembound_scene::Simulation;
use std::fmt::Write;

/// Declares atom type 1 through a template never inserted: LIGGGHTS
/// refuses a run whose smallest atom type in use is not 1 ("Atom types
/// must start from 1").
const TYPE_FLOOR: &str = "fix          type_floor_t all particletemplate/sphere 15485863 atom_type 1 density constant 1000 radius constant 1e-3\n\
     fix          type_floor all particledistribution/discrete 32452843 1 type_floor_t 1.0   # declares type 1 (never inserted)\n";

/// The data file the deck reads.
pub const DATA_FILE: &str = "particles.data";

/// The per-step trace of the first sphere: `time (s) x y z (m) vx vy vz
/// (m/s)`, one line per step from step 1 (`fix print`).
pub const TRAJECTORY_FILE: &str = "trajectory.txt";

/// The STL file the deck writes for mesh wall `w`.
pub fn mesh_file(w: usize) -> String {
    format!("wall{w}.stl")
}

/// The placed, cleaned triangles of a mesh as ASCII STL, every coordinate
/// the shortest text that reads back to the same f64 (LIGGGHTS reads
/// them with `atof`), so that the deck needs no scale, move or rotate
/// keywords and meets exactly the triangles dembound meets.
fn ascii_stl(name: &str, vertices: &[[f64; 3]], triangles: &[[u32; 3]]) -> String {
    let mut s = format!("solid {name}\n");
    for t in triangles {
        let p = t.map(|k| vertices[k as usize]);
        let e1 = [p[1][0] - p[0][0], p[1][1] - p[0][1], p[1][2] - p[0][2]];
        let e2 = [p[2][0] - p[0][0], p[2][1] - p[0][1], p[2][2] - p[0][2]];
        let n = [
            e1[1] * e2[2] - e1[2] * e2[1],
            e1[2] * e2[0] - e1[0] * e2[2],
            e1[0] * e2[1] - e1[1] * e2[0],
        ];
        let l = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
        let n = n.map(|c| if l > 0.0 { c / l } else { 0.0 });
        writeln!(
            s,
            "facet normal {} {} {}\nouter loop",
            num(n[0]),
            num(n[1]),
            num(n[2])
        )
        .ok();
        for v in p {
            writeln!(s, "vertex {} {} {}", num(v[0]), num(v[1]), num(v[2])).ok();
        }
        writeln!(s, "endloop\nendfacet").ok();
    }
    writeln!(s, "endsolid {name}").ok();
    s
}

/// `walls.txt` (docs/export-liggghts.md, "Output"): a `fix print` row
/// every `every` steps from step `every` on, `step F0x F0y F0z F1x …`, the
/// force on each wall in file order (N; 15 significant digits, LIGGGHTS's
/// variable text): a plane's or mesh's is minus the sum of the per-sphere
/// forces its `fix wall/gran … store_force yes` keeps (`force_wallK`), a
/// boundary-particle wall's the sum of the forces on its spheres stored by
/// `fix store/force` before `fix freeze` zeroes them. Not written when a
/// wall switches (its fix is unfixed between runs).
fn wall_forces(setup: &SceneSetup, windows: &[(u64, u64)], every: u64) -> String {
    let mut x = String::new();
    if setup.walls.is_empty() || windows.iter().any(|&w| w != (0, u64::MAX)) {
        return x;
    }
    let mut columns = Vec::new();
    let mut names = Vec::new();
    writeln!(
        x,
        "\n# {}: step, then the force (N) on each wall in file order, every {every} steps",
        crate::lammps_output::WALLS_FILE
    )
    .ok();
    for (w, wall) in setup.walls.iter().enumerate() {
        for (a, c) in ["x", "y", "z"].iter().enumerate() {
            let value = if wall.is_particles() {
                if setup.spheres.iter().any(|s| s.group == Some(w)) {
                    writeln!(
                        x,
                        "compute      bpw{w}_{c} bpw{w} reduce sum f_wallforce[{}]",
                        a + 1
                    )
                    .ok();
                    format!("c_bpw{w}_{c}")
                } else {
                    "0".into()
                }
            } else {
                writeln!(
                    x,
                    "compute      fw{w}_{c} all reduce sum f_force_wall{w}[{}]",
                    a + 1
                )
                .ok();
                format!("-c_fw{w}_{c}")
            };
            writeln!(x, "variable     w{w}{c} equal {value}").ok();
            columns.push(format!("${{w{w}{c}}}"));
            names.push(format!("w{w}{c}"));
        }
    }
    writeln!(
        x,
        "variable     wstep equal step\n\
         fix          walls all print {every} \"${{wstep}} {}\" file {} title \"# step, Fx Fy Fz (N) on each wall in file order\" screen no",
        columns.join(" "),
        crate::lammps_output::WALLS_FILE
    )
    .ok();
    x.push_str(&wall_force_means(&names, every));
    x
}

/// `walls_mean.txt` (docs/export-liggghts.md, "Output"): the columns of
/// walls.txt (`names`: the variables `wWc`) averaged over every step since
/// the previous row. `fix ave/time 1 N N` (LIGGGHTS's fix_ave_time.cpp, as
/// LAMMPS's: Nevery 1, Nrepeat N, Nfreq N) averages steps kN−N+1 … kN
/// and holds the mean at kN; a `fix print` defined after it (fixes reach
/// end_of_step in the order defined) writes it with LIGGGHTS's variable
/// text (15 significant digits), as walls.txt, since LIGGGHTS's `fix
/// ave/time` has no `format` keyword (its own file would hold 6). `fix
/// print N` first prints at step N, so there is no row at step 0, as in
/// the LAMMPS deck's file.
fn wall_force_means(names: &[String], every: u64) -> String {
    let mut x = String::new();
    let values: Vec<String> = names.iter().map(|n| format!("v_{n}")).collect();
    writeln!(
        x,
        "# {}: the same columns, each averaged over every step since the previous row (the row of step k: steps k-{} ... k; no row at step 0)\n\
         fix          walls_mean_sum all ave/time 1 {every} {every} {}",
        crate::lammps_output::WALLS_MEAN_FILE,
        every - 1,
        values.join(" ")
    )
    .ok();
    let mut columns = Vec::new();
    for (k, n) in names.iter().enumerate() {
        writeln!(x, "variable     m{n} equal f_walls_mean_sum[{}]", k + 1).ok();
        columns.push(format!("${{m{n}}}"));
    }
    writeln!(
        x,
        "fix          walls_mean all print {every} \"${{wstep}} {}\" file {} title \"# step, then Fx Fy Fz (N) on each wall in file order, each the mean over every step since the previous row\" screen no",
        columns.join(" "),
        crate::lammps_output::WALLS_MEAN_FILE
    )
    .ok();
    x
}

/// The deck of a resolved scene: `in.liggghts`, [`DATA_FILE`] and one
/// STL per mesh wall ([`mesh_file`]).
pub fn deck(scene: &ResolvedScene) -> Result<Deck> {
    let setup = &scene.setup;
    let refuse = |s: String| Err(Error::Export(s));
    if setup.integration.scheme != Scheme::Verlet {
        return refuse(
            "integration.scheme = \"gear5\" cannot be exported: LIGGGHTS integrates with \
             velocity Verlet (fix nve/sphere); set integration.scheme = \"verlet\""
                .into(),
        );
    }
    let any_fixed = setup.spheres.iter().any(|s| s.fixed);
    let mut outlets =
        crate::outlets::plan(setup, "LIGGGHTS", any_fixed.then_some("free"), "spheres")?;
    if let Some(o) = &mut outlets {
        // LIGGGHTS refuses a run whose smallest atom type in use is not 1
        // ("Atom types must start from 1"), as when an outlet took every
        // sphere of type 1: a template of type 1, never inserted, keeps
        // type 1 declared.
        o.setup.push_str(TYPE_FLOOR);
    }
    crate::refuse_servo_walls(setup, "LIGGGHTS")?;
    crate::refuse_moving_groups(setup, "LIGGGHTS")?;
    // Moving walls: turning meshes as `fix move/mesh rotate`, the rest
    // refused (liggghts_motion.rs).
    let mut move_lines: Vec<Option<(String, Sweep)>> = vec![None; setup.walls.len()];
    for (w, m) in setup.wall_motions.iter().enumerate() {
        if let (Some(m), Some(wall)) = (m, setup.walls.get(w)) {
            move_lines[w] = Some(crate::liggghts_motion::move_mesh_line(w, wall, m)?);
        }
    }
    // Translating meshes: (bounds at t = 0, velocity), widened once the
    // run's length is known.
    let mut shifts: Vec<([f64; 3], [f64; 3], [f64; 3])> = Vec::new();
    let contact = crate::liggghts_contact::plan(setup)?;
    let words = contact.model_words();
    let settings = contact.settings();
    if setup.spheres.iter().all(|s| s.fixed) && setup.inlets.is_empty() {
        return Err(crate::no_free_sphere("LIGGGHTS"));
    }
    // The engine validates the setup and fixes Δt and the run length.
    let sim = Simulation::new(setup.clone(), 1).map_err(|e| Error::Export(e.to_string()))?;
    let dt = sim.dt();
    let steps = sim.total_steps();
    let windows = crate::liggghts_gates::windows(setup, dt);
    // Inlets: fix insert/rate/region (liggghts_inlets.rs).
    let mut inlets =
        crate::liggghts_inlets::plan(setup, dt, steps, if any_fixed { "free" } else { "all" })?;
    if let (Some(i), None) = (&mut inlets, &outlets) {
        // Atom types must start from 1 (above) when no sphere of type 1
        // is there yet.
        i.setup.push_str(TYPE_FLOOR);
    }
    // Walls: axis-aligned planes and meshes.
    let axis_name = ["xplane", "yplane", "zplane"];
    // The group the walls, the integrator and gravity act on: `free` when
    // some spheres are frozen (fixed spheres and boundary-particle walls).
    let free = if any_fixed { "free" } else { "all" };
    let mut wall_lines = Vec::new();
    let mut files = Vec::new();
    let mut used = vec![false; setup.materials.len()];
    let mut lo = setup.domain.lower;
    let mut hi = setup.domain.upper;
    for (w, wall) in setup.walls.iter().enumerate() {
        match wall {
            WallSetup::Plane(p) => {
                let nonzero: Vec<usize> = (0..3).filter(|&k| p.normal[k] != 0.0).collect();
                let [axis] = nonzero[..] else {
                    return refuse(format!(
                        "`wall[{w}].plane`: normal {:?} is not along x, y or z; LIGGGHTS's \
                         `fix wall/gran ... primitive` takes xplane, yplane and zplane only \
                         (a tilted plane can be given as a 2-triangle `mesh`)",
                        p.normal
                    ));
                };
                used[p.material] = true;
                let t = contact.wall_types[w].unwrap_or(p.material) + 1;
                wall_lines.push(WallLines {
                    wall: w,
                    add: format!(
                        "# wall[{w}]: the plane {} = {} of material \"{}\" (type {t})\n\
                         fix          wall{w} {free} wall/gran {words} primitive type {t} {} {} store_force yes{settings}\n",
                        ["x", "y", "z"][axis],
                        num(p.point[axis]),
                        setup.materials[p.material].name,
                        axis_name[axis],
                        num(p.point[axis])
                    ),
                    remove: format!("unfix        wall{w}\n"),
                });
            }
            WallSetup::Mesh(m) => {
                let g = &m.geometry;
                used[m.material] = true;
                for k in 0..3 {
                    lo[k] = lo[k].min(g.lo[k]);
                    hi[k] = hi[k].max(g.hi[k]);
                }
                let name = mesh_file(w);
                files.push(DeckFile {
                    name: name.clone(),
                    text: ascii_stl(&format!("wall{w}"), &g.vertices, &g.triangles),
                });
                let t = contact.wall_types[w].unwrap_or(m.material) + 1;
                let mut lines = WallLines {
                    wall: w,
                    add: format!(
                        "# wall[{w}]: the mesh {} ({} triangles after cleaning), placed by dembound\n\
                         # (scale, rotate, translate applied) and written to {name}; material \"{}\" (type {t})\n\
                         fix          mesh{w} all mesh/surface file {name} type {t}\n\
                         fix          wall{w} {free} wall/gran {words} mesh n_meshes 1 meshes mesh{w} store_force yes{settings}\n",
                        m.file_name(),
                        g.triangles.len(),
                        setup.materials[m.material].name,
                    ),
                    remove: format!("unfix        wall{w}\nunfix        mesh{w}\n"),
                };
                if let Some((line, sweep)) = &move_lines[w] {
                    if windows[w].0 > 0 {
                        return refuse(format!(
                            "`wall[{w}].active` with `wall[{w}].motion` cannot be exported: a \
                             LIGGGHTS `fix move/mesh` written when the wall appears would start \
                             its motion there, not at t = 0; remove `wall[{w}].active.from` or \
                             the motion to export the scene"
                        ));
                    }
                    match *sweep {
                        Sweep::Turn(center) => {
                            let (a, b) = crate::liggghts_motion::swept_bounds(&g.vertices, center);
                            for k in 0..3 {
                                lo[k] = lo[k].min(a[k]);
                                hi[k] = hi[k].max(b[k]);
                            }
                        }
                        Sweep::Shift(v) => shifts.push((g.lo, g.hi, v)),
                    }
                    lines.add.push_str(line);
                    lines.add.push('\n');
                    lines.remove = format!("unfix        move{w}\n{}", lines.remove);
                }
                wall_lines.push(lines);
            }
            other if other.is_particles() => {
                // Its spheres are frozen spheres of the data file (below).
                if windows[w] != (0, u64::MAX) {
                    return refuse(format!(
                        "`wall[{w}].active` on a `boundary_particles` wall cannot be exported: the \
                         LIGGGHTS deck switches planes and meshes only; remove `wall[{w}].active`"
                    ));
                }
            }
            other => {
                return refuse(format!(
                    "`wall[{w}].{}` is not exported to LIGGGHTS (exported: axis-aligned planes, \
                     meshes and boundary particles); replace it by planes or a mesh",
                    other.key()
                ))
            }
        }
    }
    for s in &setup.spheres {
        used[s.material] = true;
    }
    for i in &setup.inlets {
        used[i.material] = true;
    }
    for (k, m) in setup.materials.iter().enumerate() {
        if used[k] && !(m.material.youngs_modulus.is_finite() && m.material.youngs_modulus > 0.0) {
            return refuse(format!(
                "`material[{k}].youngs_modulus` = inf (material \"{}\", rigid) cannot be exported \
                 to LIGGGHTS: it needs a finite youngsModulus per type; give it a finite modulus \
                 (E_eff then changes by E_sphere/E_wall)",
                m.name
            ));
        }
    }
    let every = crate::lammps_output::series_every(scene.file.output.series_every, steps);
    // A translating mesh's nodes over the run: its bounds shifted by V T.
    let run_time = steps as f64 * dt;
    for (a, b, v) in &shifts {
        for k in 0..3 {
            let d = v[k] * run_time;
            lo[k] = lo[k].min(a[k] + d.min(0.0));
            hi[k] = hi[k].max(b[k] + d.max(0.0));
        }
    }

    // Box: the domain, widened to every sphere and mesh (LIGGGHTS drops
    // atoms and refuses mesh nodes outside it).
    let d = &setup.domain;
    for s in &setup.spheres {
        for k in 0..3 {
            if !d.periodic[k] {
                lo[k] = lo[k].min(s.position[k] - s.radius);
                hi[k] = hi[k].max(s.position[k] + s.radius);
            }
        }
    }
    for k in 0..3 {
        if d.periodic[k] {
            lo[k] = d.lower[k];
            hi[k] = d.upper[k];
        } else {
            // A margin so that nothing sits on the box's face; the faces
            // are shrink-wrapped (`m`), so the box follows a sphere that
            // flies out of it (with `f` LIGGGHTS loses it).
            let pad = 1e-3 * (hi[k] - lo[k]);
            lo[k] -= pad;
            hi[k] += pad;
        }
    }
    let n_types = contact.n_types();
    let mut data = String::new();
    writeln!(
        data,
        "LIGGGHTS data file (atom_style granular) written by `dembound export liggghts` from a scene\n\n\
         {} atoms\n{} atom types\n\n{} {} xlo xhi\n{} {} ylo yhi\n{} {} zlo zhi\n\nAtoms\n",
        setup.spheres.len(),
        n_types,
        num(lo[0]),
        num(hi[0]),
        num(lo[1]),
        num(hi[1]),
        num(lo[2]),
        num(hi[2])
    )
    .ok();
    for (i, s) in setup.spheres.iter().enumerate() {
        let p = s.position;
        writeln!(
            data,
            "{} {} {} {} {} {} {}",
            i + 1,
            s.material + 1,
            num(2.0 * s.radius),
            num(setup.materials[s.material].material.density),
            num(p[0]),
            num(p[1]),
            num(p[2])
        )
        .ok();
    }
    if setup.spheres.is_empty() {
        // No sphere before the inlets insert: no Atoms section at all.
        data.truncate(data.len() - "\nAtoms\n\n".len());
    } else {
        writeln!(data, "\nVelocities\n").ok();
    }
    for (i, s) in setup.spheres.iter().enumerate() {
        // A fixed sphere never moves (a moving group is refused above).
        let v = if s.fixed { [0.0; 3] } else { s.velocity };
        writeln!(
            data,
            "{} {} {} {} 0 0 0",
            i + 1,
            num(v[0]),
            num(v[1]),
            num(v[2])
        )
        .ok();
    }

    let mut x = String::new();
    writeln!(
        x,
        "# Exported by `dembound export liggghts` from a dembound scene (SI units); scene.toml is the scene as resolved.\n\
         # Run: {}. Every number below comes from dembound.\n\
         # spheres: {} in {DATA_FILE}, ids in dembound's input order; atom type k = material k (dembound's order).\n\
         # Hertz: LIGGGHTS mixes Y* = 1/((1-nu_i^2)/Y_i + (1-nu_j^2)/Y_j) and uses F = 4/3 Y* sqrt(R* d) d,\n\
         # which is dembound's eq 6 E_eff = 4/3 Y*: each type keeps its material's own E and nu, walls too.\n\
         {}",
        Code::Liggghts.command(),
        setup.spheres.len(),
        if contact.notes.is_empty() {
            "# Elastic: coefficientRestitution 1 makes LIGGGHTS's hertz damping zero; friction 0: no tangential force."
                .to_string()
        } else {
            contact.notes.join("\n")
        }
    )
    .ok();
    let modulus_of = |k: usize| setup.materials[k].material.youngs_modulus;
    let boundary: Vec<&str> = d
        .periodic
        .iter()
        .map(|&p| if p { "p" } else { "m" })
        .collect();
    writeln!(
        x,
        "\natom_style   granular\natom_modify  map array\nboundary     {}\nnewton       off\n\
         communicate  single vel yes\nunits        si\n\
         hard_particles yes   # allows moduli above 1e9 Pa\n{}\
         read_data    {DATA_FILE}",
        boundary.join(" "),
        // LIGGGHTS refuses E < 5e6 Pa in SI units unless told.
        if (0..setup.materials.len()).any(|k| used[k] && modulus_of(k) < 5e6) {
            "soft_particles yes   # allows moduli below 5e6 Pa\n"
        } else {
            ""
        }
    )
    .ok();
    let per_type = |f: &dyn Fn(usize) -> f64| -> String {
        contact
            .type_materials
            .iter()
            .map(|&k| num(f(k)))
            .collect::<Vec<_>>()
            .join(" ")
    };
    let material = |k: usize| &setup.materials[k].material;
    // Unused types (a rigid built-in material, say) get a placeholder the
    // contact never reads: LIGGGHTS wants a positive number for each.
    let modulus = |k: usize| {
        let e = material(k).youngs_modulus;
        if used[k] {
            e
        } else {
            1e9
        }
    };
    let pairs = |v: f64| vec![num(v); n_types * n_types].join(" ");
    writeln!(x, "\n# materials (type: name, E, nu):").ok();
    for (k, m) in setup.materials.iter().enumerate() {
        writeln!(
            x,
            "#   {}: \"{}\", E = {} Pa, nu = {}{}",
            k + 1,
            m.name,
            num(m.material.youngs_modulus),
            num(m.material.poisson_ratio),
            if used[k] {
                ""
            } else {
                " (unused: a placeholder E)"
            }
        )
        .ok();
    }
    writeln!(
        x,
        "fix          m1 all property/global youngsModulus peratomtype {}\n\
         fix          m2 all property/global poissonsRatio peratomtype {}\n\
         fix          m3 all property/global coefficientRestitution peratomtypepair {n_types} {}\n\
         fix          m4 all property/global coefficientFriction peratomtypepair {n_types} {}",
        per_type(&modulus),
        per_type(&|k| material(k).poisson_ratio),
        pairs(contact.restitution),
        contact.friction_pairs().join(" ")
    )
    .ok();
    if let Some(k) = contact.hooke {
        let kt = contact
            .tangential_stiffness
            .clone()
            .unwrap_or_else(|| vec![0.0; n_types * n_types]);
        writeln!(
            x,
            "fix          m5 all property/global kn peratomtypepair {n_types} {}\n\
             fix          m6 all property/global kt peratomtypepair {n_types} {}\n\
             fix          m7 all property/global gamman_abs peratomtypepair {n_types} {}\n\
             fix          m8 all property/global gammat_abs peratomtypepair {n_types} {}",
            pairs(k),
            kt.iter().map(|&v| num(v)).collect::<Vec<_>>().join(" "),
            pairs(0.0),
            pairs(0.0)
        )
        .ok();
    }
    if contact.rolling.is_some() {
        writeln!(
            x,
            "fix          m9 all property/global coefficientRollingFriction peratomtypepair {n_types} {}",
            contact.rolling_pairs().join(" ")
        )
        .ok();
    }
    let fixed_ids: Vec<usize> = setup
        .spheres
        .iter()
        .enumerate()
        .filter(|(_, s)| s.fixed)
        .map(|(i, _)| i)
        .collect();
    if any_fixed {
        writeln!(
            x,
            "\n# frozen spheres (fixed spheres and boundary-particle walls): not integrated, no gravity, force zeroed\n\
             # by fix freeze (pair gran then takes m_eff = the free sphere's mass, dembound's infinite-mass limit)\n\
             group        frozen id {}\n\
             group        free subtract all frozen\n\
             neigh_modify exclude group frozen frozen   # two fixed spheres never interact, as in dembound",
            crate::lammps_output::id_ranges(&fixed_ids)
        )
        .ok();
    }
    let skin = setup.neighbour.skin.unwrap_or_else(|| {
        0.2 * setup.spheres.iter().map(|s| s.radius).fold(
            inlets.as_ref().map_or(f64::INFINITY, |i| i.min_radius),
            f64::min,
        )
    });
    writeln!(
        x,
        "\npair_style   gran {words}{settings}\npair_coeff   * *\n\
         neighbor     {} bin\nneigh_modify delay 0\ntimestep     {}\n",
        num(skin),
        num(dt)
    )
    .ok();
    for l in &wall_lines {
        let w = l.wall;
        if crate::liggghts_gates::on_at_start(windows[w]) {
            x.push_str(&l.add);
        } else if windows[w].0 < windows[w].1 {
            writeln!(x, "# wall[{w}] is written where it appears (below)").ok();
        } else {
            writeln!(x, "# wall[{w}] never acts (its active window is empty)").ok();
        }
    }
    let g = setup.gravity;
    let g_norm = (g[0] * g[0] + g[1] * g[1] + g[2] * g[2]).sqrt();
    writeln!(x, "\nfix          integrate {free} nve/sphere").ok();
    if any_fixed {
        x.push_str(&crate::lammps_output::before_freeze(setup));
        writeln!(x, "fix          freeze frozen freeze").ok();
    }
    if g_norm > 0.0 {
        writeln!(
            x,
            "fix          gravity {free} gravity {} vector {} {} {}",
            num(g_norm),
            num(g[0] / g_norm),
            num(g[1] / g_norm),
            num(g[2] / g_norm)
        )
        .ok();
    }
    // With friction the spheres spin: the dump carries ω too.
    let (spin_note, spin_columns, spin_format) = if contact.friction.is_some() {
        (
            " (omega in rad/s)",
            " omegax omegay omegaz",
            " %.17g %.17g %.17g",
        )
    } else {
        ("", "", "")
    };
    if setup.spheres.is_empty() {
        // No sphere 1 before the first insertion: `x[1]` would fail.
        writeln!(
            x,
            "\n# {TRAJECTORY_FILE} is not written: the scene has no sphere before its inlets insert"
        )
        .ok();
    } else {
        writeln!(
            x,
            "\n# {TRAJECTORY_FILE}: sphere 1 every step: time (s), x y z (m), vx vy vz (m/s)\n\
             variable     t equal step*dt\n\
             variable     x1 equal x[1]\nvariable     y1 equal y[1]\nvariable     z1 equal z[1]\n\
             variable     vx1 equal vx[1]\nvariable     vy1 equal vy[1]\nvariable     vz1 equal vz[1]\n\
             fix          trajectory all print 1 \"${{t}} ${{x1}} ${{y1}} ${{z1}} ${{vx1}} ${{vy1}} ${{vz1}}\" \
             file {TRAJECTORY_FILE} title \"# time_s x_m y_m z_m vx_m_s vy_m_s vz_m_s\" screen no"
        )
        .ok();
    }
    writeln!(
        x,
        "# particles.dump: every sphere at the series cadence{spin_note}\n\
         dump         spheres all custom {every} particles.dump id type radius x y z vx vy vz{spin_columns}\n\
         dump_modify  spheres format \"%d %d %.17g %.17g %.17g %.17g %.17g %.17g %.17g{spin_format}\"\n\
         {}{}thermo_style custom step time ke{}{}\n\
         thermo_modify norm no format float %.17g\n\
         thermo       {}",
        outlets.as_ref().map_or("", |o| o.setup.as_str()),
        inlets.as_ref().map_or("", |i| i.setup.as_str()),
        outlets.as_ref().map_or("", |o| o.columns.as_str()),
        inlets.as_ref().map_or("", |i| i.columns.as_str()),
        // With inlets or outlets, the counts over time: at the series
        // cadence (a row between the outlets' checks reads its own step's
        // counts; lammps_scene.rs alike).
        if inlets.is_some() || outlets.is_some() {
            every
        } else {
            steps.max(1)
        }
    )
    .ok();
    x.push_str(&wall_forces(setup, &windows, every));
    x.push_str(&crate::liggghts_gates::runs(
        steps,
        dt,
        &windows,
        &wall_lines,
        outlets.as_ref(),
    ));
    let mut all = vec![
        DeckFile {
            name: Code::Liggghts.input_file().into(),
            text: x,
        },
        DeckFile {
            name: DATA_FILE.into(),
            text: data,
        },
    ];
    all.extend(files);
    Ok(Deck {
        code: Code::Liggghts,
        files: all,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use dembound_scene::io::{config, resolve::resolve};

    const SCENE: &str = r#"
[domain]
lower = [0.0, 0.0, 0.0]
upper = [0.01, 0.01, 0.01]
[[material]]
name = "a"
density = 1000.0
youngs_modulus = 1.0e7
poisson_ratio = 0.3
[[material]]
name = "b"
density = 2500.0
youngs_modulus = 5.0e7
poisson_ratio = 0.2
[contact]
law = "hertz"
[[particles]]
spheres = [ { position = [0.002, 0.005, 0.005], radius = 1.0e-3, velocity = [0.1, 0.0, 0.0] } ]
material = "a"
[[wall]]
plane = { point = [0.0, 0.0, 0.001], normal = [0.0, 0.0, 1.0] }
material = "b"
[[wall]]
plane = { point = [0.01, 0.0, 0.0], normal = [-1.0, 0.0, 0.0] }
material = "a"
[integration]
dt = 1.0e-6
steps = 10
"#;

    fn exported(sets: &[&str]) -> Result<Deck> {
        exported_text(SCENE, sets)
    }

    fn exported_text(text: &str, sets: &[&str]) -> Result<Deck> {
        let sets: Vec<String> = sets.iter().map(|s| s.to_string()).collect();
        let file = config::load(text, "test", &sets).expect("a valid scene");
        let scene = resolve(&file, std::path::Path::new(".")).expect("resolves");
        deck(&scene)
    }

    #[test]
    fn each_type_keeps_its_material_and_planes_their_type() {
        let d = exported(&[]).expect("exports");
        let input = &d.files[0].text;
        // Material order: "a", "b", then whatever built-ins follow (unused:
        // the placeholder).
        let line = input
            .lines()
            .find(|l| l.contains("youngsModulus peratomtype"))
            .expect("the moduli");
        assert!(line.contains("peratomtype 1e7 5e7"), "{line}");
        assert!(input.contains("primitive type 2 zplane 1e-3"), "{input}");
        assert!(input.contains("primitive type 1 xplane 1e-2"), "{input}");
        assert!(input.contains("timestep     1e-6") && input.contains("run          10"));
        let data = &d.files[1].text;
        assert!(data.contains("\n1 1 2e-3 1e3 2e-3 5e-3 5e-3\n"), "{data}");
        assert!(data.contains("\n1 1e-1 0 0 0 0 0\n"), "{data}");
    }

    #[test]
    fn the_stl_reads_back_to_the_same_f64() {
        let vertices = [
            [0.1, 1.0 / 3.0, -2e-7],
            [std::f64::consts::PI, 0.0, 1e-300],
            [-0.3, 7.0 / 11.0, 5.5],
        ];
        let text = ascii_stl("t", &vertices, &[[0, 1, 2]]);
        let read: Vec<[f64; 3]> = text
            .lines()
            .filter_map(|l| l.strip_prefix("vertex "))
            .map(|l| {
                let v: Vec<f64> = l
                    .split_whitespace()
                    .map(|w| w.parse().expect("a number"))
                    .collect();
                [v[0], v[1], v[2]]
            })
            .collect();
        assert_eq!(read, vertices);
        assert!(text.starts_with("solid t\n") && text.ends_with("endsolid t\n"));
    }

    /// Damping alone: the exact calibration's e′ (β(e′) = −ξ of the
    /// clamped law, the same γ) and `limitForce on` on the pair style and
    /// after each wall's keywords; the formula calibration writes e itself.
    /// Friction alone: `tangential history`, μ per type pair mixed as
    /// √(μ_a μ_b), a wall with its own μ on a type of its own.
    #[test]
    fn damping_and_friction_settings() {
        use dembound_physics::contact::calibration::damping_ratio_for;
        let d = exported(&["contact.damping=tsuji", "contact.restitution=0.5"]).expect("exports");
        let input = &d.files[0].text;
        let e = crate::liggghts_contact::restitution_of_ratio(damping_ratio_for(0.5, false));
        assert!(e < 0.5 && e > 0.3, "{e}");
        assert!(
            input.contains(&format!(
                "coefficientRestitution peratomtypepair 2 {} ",
                num(e)
            )),
            "{input}"
        );
        assert!(input.contains("pair_style   gran model hertz tangential no_history limitForce on"));
        assert!(
            input.contains("primitive type 2 zplane 1e-3 store_force yes limitForce on"),
            "{input}"
        );
        let d = exported(&[
            "contact.damping=tsuji",
            "contact.restitution=0.5",
            "contact.calibration=formula",
            "contact.attractive=true",
        ])
        .expect("exports");
        let input = &d.files[0].text;
        assert!(input.contains("coefficientRestitution peratomtypepair 2 5e-1 "));
        assert!(!input.contains("limitForce"), "{input}");
        let d = exported(&["contact.friction=0.4", "wall.1.friction=0.1"]).expect("exports");
        let input = &d.files[0].text;
        assert!(input.contains("pair_style   gran model hertz tangential history\n"));
        // Types: a, b, then wall[1]'s own (material a, μ 0.1); μ 0.4 else.
        let mixed = num((0.4f64 * 0.1).sqrt());
        assert!(
            input.contains(&format!(
                "coefficientFriction peratomtypepair 3 4e-1 4e-1 {mixed} 4e-1 4e-1 {mixed} {mixed} {mixed} 1e-1"
            )),
            "{input}"
        );
        assert!(
            input.contains("youngsModulus peratomtype 1e7 5e7 1e7"),
            "{input}"
        );
        assert!(input.contains("primitive type 3 xplane 1e-2"), "{input}");
        assert!(input.contains("primitive type 2 zplane 1e-3"), "{input}");
        assert!(input.contains("omegax omegay omegaz"));
        assert!(d.files[1].text.contains("\n3 atom types\n"));
    }

    /// walls_mean.txt: `fix ave/time 1 N N` over walls.txt's variables,
    /// then a `fix print` every N steps defined after it (so the mean of
    /// the step is there when it prints), 15 digits as walls.txt.
    #[test]
    fn walls_mean_averages_every_step_of_each_row() {
        let d = exported(&["output.series_every=5"]).expect("exports");
        let input = &d.files[0].text;
        let mean = input
            .find("fix          walls_mean_sum all ave/time 1 5 5 v_w0x v_w0y v_w0z v_w1x v_w1y v_w1z\n")
            .expect(input);
        let print = input
            .find("fix          walls_mean all print 5 \"${wstep} ${mw0x} ${mw0y} ${mw0z} ${mw1x} ${mw1y} ${mw1z}\" file walls_mean.txt")
            .expect(input);
        assert!(mean < print, "{input}");
        for line in [
            "# walls_mean.txt: the same columns, each averaged over every step since the previous row (the row of step k: steps k-4 ... k; no row at step 0)\n",
            "variable     mw0x equal f_walls_mean_sum[1]\n",
            "variable     mw1z equal f_walls_mean_sum[6]\n",
        ] {
            assert!(input.contains(line), "{line}\n{input}");
        }
    }

    /// Fixed spheres: a frozen group by id, not integrated, no gravity,
    /// frozen pairs excluded, `fix freeze`; the walls act on the free
    /// spheres and store their forces for walls.txt.
    #[test]
    fn fixed_spheres_are_a_frozen_group() {
        let fixed = format!(
            "{SCENE}\n[[particles]]\nmaterial = \"b\"\nfixed = true\n\
             spheres = [ {{ position = [0.005, 0.005, 0.005], radius = 1.0e-3 }} ]\n"
        );
        let d = exported_text(&fixed, &[]).expect("exports");
        let input = &d.files[0].text;
        for line in [
            "group        frozen id 2:2\n",
            "group        free subtract all frozen\n",
            "neigh_modify exclude group frozen frozen",
            "fix          integrate free nve/sphere\n",
            "fix          freeze frozen freeze\n",
            "fix          gravity free gravity",
            "fix          wall0 free wall/gran model hertz tangential no_history primitive type 2 zplane 1e-3 store_force yes\n",
            "variable     w0z equal -c_fw0_z\n",
            "fix          walls all print 1 \"${wstep} ${w0x} ${w0y} ${w0z} ${w1x} ${w1y} ${w1z}\" file walls.txt",
        ] {
            assert!(input.contains(line), "{line}\n{input}");
        }
        // The fixed sphere: type 2 ("b"), zero velocity.
        let data = &d.files[1].text;
        assert!(data.contains("\n2 2 2e-3 2.5e3 5e-3 5e-3 5e-3\n"), "{data}");
        assert!(data.contains("\n2 0 0 0 0 0 0\n"), "{data}");
        // Without fixed spheres the deck keeps `all`.
        let d = exported(&[]).expect("exports");
        assert!(d.files[0]
            .text
            .contains("fix          integrate all nve/sphere\n"));
        assert!(!d.files[0].text.contains("freeze"));
        // An inlet beside frozen spheres inserts into `free` (LIGGGHTS
        // gives an inserted sphere its fix's group), so what it pours is
        // integrated; without frozen spheres into `all`.
        let inlet = "\n[[inlet]]\nregion = { box = { lower = [0.0, 0.0, 0.005], upper = [0.01, 0.01, 0.01] } }\n\
                     rate = { number = 1.0e5 }\nsize = { fixed = 1.0e-3 }\nmaterial = \"a\"\nevery = 10\n";
        let d = exported_text(&format!("{fixed}{inlet}"), &[]).expect("exports");
        assert!(
            d.files[0].text.contains(" free insert/rate/region "),
            "{}",
            d.files[0].text
        );
        let d = exported_text(&format!("{SCENE}{inlet}"), &[]).expect("exports");
        assert!(
            d.files[0].text.contains(" all insert/rate/region "),
            "{}",
            d.files[0].text
        );
    }

    /// Hooke: `model hooke/stiffness`, kn = k for every pair, γ = 0; with
    /// friction the linear k_t = (2/7) E_eff R_eff per type pair, each wall
    /// on a type of its own (its k_t uses the sphere's R).
    #[test]
    fn hooke_writes_hooke_stiffness() {
        use dembound_physics::material::{effective_modulus, Material};
        let d = exported(&["contact.law={hooke=50.0}"]).expect("exports");
        let input = &d.files[0].text;
        assert!(input.contains(
            "pair_style   gran model hooke/stiffness tangential no_history absolute_damping on\n"
        ));
        assert!(
            input.contains("kn peratomtypepair 2 5e1 5e1 5e1 5e1\n"),
            "{input}"
        );
        assert!(input.contains("gamman_abs peratomtypepair 2 0 0 0 0\n"));
        let d = exported(&[
            "contact.law={hooke=50.0}",
            "contact.friction=0.5",
            "contact.tangential=linear",
        ])
        .expect("exports");
        let input = &d.files[0].text;
        let a = Material {
            density: 1000.0,
            youngs_modulus: 1e7,
            poisson_ratio: 0.3,
        };
        let b = Material {
            density: 2500.0,
            youngs_modulus: 5e7,
            poisson_ratio: 0.2,
        };
        // Types: a, b, wall[0] (b), wall[1] (a); the sphere (a, R = 1 mm).
        let pp = 2.0 / 7.0 * effective_modulus(&a, &a) * 0.5e-3;
        let w0 = 2.0 / 7.0 * effective_modulus(&a, &b) * 1e-3;
        let w1 = 2.0 / 7.0 * effective_modulus(&a, &a) * 1e-3;
        let row = format!(
            "kt peratomtypepair 4 {} 0 {} {} ",
            num(pp),
            num(w0),
            num(w1)
        );
        assert!(input.contains(&row), "{row}\n{input}");
        assert!(input.contains("primitive type 3 zplane 1e-3"), "{input}");
        assert!(input.contains("primitive type 4 xplane 1e-2"), "{input}");
    }

    /// A scene with no sphere and an inlet of material "b" (type 2): no
    /// Atoms section, no trajectory of sphere 1, type 1 declared, the
    /// insertion with the inserted count and mass as thermo columns;
    /// 1e5 spheres/s every 10 steps of 1 µs is one sphere per event, and
    /// the rate written gives LIGGGHTS's product ≥ 1 (its floor(n + U)
    /// then 1 for every U).
    #[test]
    fn an_inlet_without_spheres() {
        let start = SCENE.find("[[particles]]").expect("particles");
        let end = SCENE.find("[[wall]]").expect("walls");
        let text = format!(
            "{}{}[[inlet]]\nregion = {{ box = {{ lower = [0.0, 0.0, 0.005], upper = [0.01, 0.01, 0.01] }} }}\n\
             rate = {{ number = 1.0e5 }}\nsize = {{ fixed = 1.0e-3 }}\nmaterial = \"b\"\nevery = 10\n",
            &SCENE[..start],
            &SCENE[end..]
        );
        let file = config::load(&text, "test", &[]).expect("a valid scene");
        let scene = resolve(&file, std::path::Path::new(".")).expect("resolves");
        let d = deck(&scene).expect("exports");
        let (input, data) = (&d.files[0].text, &d.files[1].text);
        assert!(
            data.contains("\n0 atoms\n") && !data.contains("Atoms"),
            "{data}"
        );
        assert!(!input.contains("trajectory all print"), "{input}");
        assert!(input.contains("type_floor all particledistribution"));
        assert!(input.contains("atom_type 2 density constant 2.5e3 radius constant 1e-3"));
        assert!(input.contains("thermo_style custom step time ke f_ins0[1] f_ins0[2]\n"));
        let line = input
            .lines()
            .find(|l| l.starts_with("fix") && l.contains("insert/rate/region"))
            .expect("the insertion");
        assert!(
            line.contains("nparticles INF") && line.contains("insert_every 10 start 1 "),
            "{line}"
        );
        let rate: f64 = line
            .split("particlerate ")
            .nth(1)
            .and_then(|w| w.split_whitespace().next())
            .and_then(|w| w.parse().ok())
            .expect("a rate");
        assert!(
            rate * (10.0 * 1e-6) >= 1.0 && (rate - 1e5).abs() <= 1e-9,
            "{rate}"
        );
    }

    #[test]
    fn refusals_name_the_key() {
        for (sets, key) in [
            (vec!["integration.scheme=gear5"], "integration.scheme"),
            (vec!["contact.law=linear"], "contact.law"),
            (
                vec!["contact.damping=tsuji", "contact.damping_coefficient=0.5"],
                "contact.damping_coefficient",
            ),
            (
                vec![
                    "contact.damping=tsuji",
                    "contact.restitution=0.5",
                    "contact.friction=0.2",
                ],
                "contact.damping",
            ),
            (
                vec!["contact.friction=0.2", "contact.rolling_friction=0.1"],
                "contact.rolling_friction",
            ),
            (
                vec!["contact.friction=0.2", "contact.tangential=linear"],
                "contact.tangential",
            ),
            (vec!["wall.1.plane.normal=[-1.0,0.0,0.1]"], "wall[1].plane"),
            (vec!["wall.0.material=rigid"], "rigid"),
            (
                vec!["wall.0.motion.angular_velocity=[0,0,1]"],
                "wall[0].motion",
            ),
            (
                vec!["wall.0.servo={force=1,axis=[1,0,0],max_velocity=0.1}"],
                "wall[0].servo",
            ),
        ] {
            let e = exported(&sets).expect_err("refused");
            assert!(e.to_string().contains(key), "{sets:?}: {e}");
        }
    }
}
