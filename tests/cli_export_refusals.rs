//! Every refusal of `dembound export lammps|liggghts|yade SCENE.toml`
//! (issue 32: "every refusal tested: the message names the key and the
//! code"), one case per refusal site of crates/dembound-export: a small
//! scene (two glass spheres over a steel plane floor) plus the section or
//! the `--set` that hits the site; each run must exit 2, print one
//! `error:` naming the exact key and the code (LAMMPS, LIGGGHTS, Yade) on
//! stderr, and leave no `--out` directory behind. The table of sites,
//! with the ones no scene can reach, is docs/export-refusals.md.
//!
//! Also: `--set contact.friction=0` on a frictional file exports, and to
//! the same deck as the file without its friction keys (issue 32 item 1).

mod common;

use common::dembound;
use std::path::Path;

/// The scene every case starts from: two free glass spheres 2 mm above a
/// steel plane floor, Hertz, undamped, frictionless, 100 steps.
const BASE: &str = r#"[domain]
lower = [0.0, 0.0, 0.0]
upper = [0.01, 0.01, 0.02]
[[material]]
name = "glass"
density = 2500.0
youngs_modulus = 1.0e7
poisson_ratio = 0.3
[[material]]
name = "steel"
density = 7800.0
youngs_modulus = 5.0e7
poisson_ratio = 0.3
[contact]
law = "hertz"
[[particles]]
material = "glass"
spheres = [ { position = [0.003, 0.005, 0.005], radius = 1.0e-3 }, { position = [0.007, 0.005, 0.005], radius = 1.0e-3 } ]
[[wall]]
plane = { point = [0.0, 0.0, 0.0], normal = [0.0, 0.0, 1.0] }
material = "steel"
[motion]
gravity = [0.0, 0.0, -9.81]
[integration]
scheme = "verlet"
dt = 1.0e-5
steps = 100
"#;

/// A 10 mm square of two triangles at z = 0 (moved up 1 mm by the cases).
const FLOOR_STL: &str = r#"solid f
facet normal 0 0 1
outer loop
vertex 0 0 0
vertex 0.01 0 0
vertex 0.01 0.01 0
endloop
endfacet
facet normal 0 0 1
outer loop
vertex 0 0 0
vertex 0.01 0.01 0
vertex 0 0.01 0
endloop
endfacet
endsolid f
"#;

/// One refusal site: where it is (for the failure message and the docs'
/// table), the code, TOML appended to [`BASE`], `--set` overrides, the
/// key the message must name.
struct Case {
    site: &'static str,
    code: &'static str,
    extra: &'static str,
    sets: &'static [&'static str],
    key: &'static str,
}

fn code_name(code: &str) -> &'static str {
    match code {
        "lammps" => "LAMMPS",
        "liggghts" => "LIGGGHTS",
        _ => "Yade",
    }
}

const CASES: &[Case] = &[
    Case {
        site: "lib.rs refuse_lost_removal",
        code: "lammps",
        extra: "",
        sets: &["domain.outside=delete"],
        key: "domain.outside",
    },
    Case {
        site: "lib.rs refuse_servo_walls",
        code: "lammps",
        extra: r#"[[wall]]
plane = { point = [0.0, 0.0, 0.02], normal = [0.0, 0.0, -1.0] }
material = "steel"
servo = { force = 1.0, axis = [0.0, 0.0, -1.0], max_velocity = 0.1 }
"#,
        sets: &[],
        key: "wall[1].servo",
    },
    Case {
        site: "lib.rs no_free_sphere",
        code: "lammps",
        extra: "",
        sets: &["particles.0.fixed=true"],
        key: "particles[K].fixed",
    },
    Case {
        site: "lib.rs refuse_lost_removal",
        code: "liggghts",
        extra: "",
        sets: &["domain.outside=delete"],
        key: "domain.outside",
    },
    Case {
        site: "lib.rs refuse_servo_walls",
        code: "liggghts",
        extra: r#"[[wall]]
plane = { point = [0.0, 0.0, 0.02], normal = [0.0, 0.0, -1.0] }
material = "steel"
servo = { force = 1.0, axis = [0.0, 0.0, -1.0], max_velocity = 0.1 }
"#,
        sets: &[],
        key: "wall[1].servo",
    },
    Case {
        site: "lib.rs no_free_sphere",
        code: "liggghts",
        extra: "",
        sets: &["particles.0.fixed=true"],
        key: "particles[K].fixed",
    },
    Case {
        site: "lib.rs refuse_lost_removal",
        code: "yade",
        extra: "",
        sets: &["domain.outside=delete", "wall.0.material=glass"],
        key: "domain.outside",
    },
    Case {
        site: "lib.rs refuse_servo_walls",
        code: "yade",
        extra: r#"[[wall]]
plane = { point = [0.0, 0.0, 0.02], normal = [0.0, 0.0, -1.0] }
material = "steel"
servo = { force = 1.0, axis = [0.0, 0.0, -1.0], max_velocity = 0.1 }
"#,
        sets: &["wall.0.material=glass"],
        key: "wall[1].servo",
    },
    Case {
        site: "lib.rs no_free_sphere",
        code: "yade",
        extra: "",
        sets: &["particles.0.fixed=true", "wall.0.material=glass"],
        key: "particles[K].fixed",
    },
    Case {
        site: "lammps_scene.rs no_free_sphere (Tsuji branch)",
        code: "lammps",
        extra: "",
        sets: &[
            "particles.0.fixed=true",
            "contact.damping=tsuji",
            "contact.restitution=0.5",
        ],
        key: "particles[K].fixed",
    },
    Case {
        site: "lib.rs refuse_moving_groups",
        code: "liggghts",
        extra: r#"[[particles]]
material = "steel"
fixed = true
spheres = [ { position = [0.005, 0.005, 0.015], radius = 1.0e-3 } ]
motion = { velocity = [0.0, 0.0, 0.01] }
"#,
        sets: &[],
        key: "particles[1].motion",
    },
    Case {
        site: "lib.rs refuse_moving_groups",
        code: "yade",
        extra: r#"[[particles]]
material = "steel"
fixed = true
spheres = [ { position = [0.005, 0.005, 0.015], radius = 1.0e-3 } ]
motion = { velocity = [0.0, 0.0, 0.01] }
"#,
        sets: &["wall.0.material=glass"],
        key: "particles[1].motion",
    },
    Case {
        site: "lib.rs refuse_moving_walls",
        code: "yade",
        extra: "",
        sets: &[
            "wall.0.material=glass",
            "wall.0.motion={velocity=[0.01,0.0,0.0]}",
        ],
        key: "wall[0].motion",
    },
    Case {
        site: "lib.rs refuse_moving_walls (oscillation)",
        code: "yade",
        extra: "",
        sets: &[
            "wall.0.material=glass",
            "wall.0.oscillation={amplitude=[0.0,0.0,1e-4],frequency=10.0}",
        ],
        key: "wall[0].oscillation",
    },
    Case {
        site: "lib.rs refuse_removal",
        code: "yade",
        extra: r#"[[outlet]]
region = { box = { lower = [0.0, 0.0, 0.0], upper = [0.01, 0.01, 0.002] } }
"#,
        sets: &["wall.0.material=glass"],
        key: "outlet[0]",
    },
    Case {
        site: "lib.rs refuse_inlets",
        code: "yade",
        extra: r#"[[inlet]]
region = { box = { lower = [0.001, 0.001, 0.016], upper = [0.009, 0.009, 0.019] } }
rate = { number = 100.0 }
size = { fixed = 1.0e-3 }
material = "glass"
"#,
        sets: &["wall.0.material=glass"],
        key: "inlet[0]",
    },
    Case {
        site: "lib.rs refuse_gates",
        code: "yade",
        extra: r#"[[wall]]
plane = { point = [0.0, 0.0, 0.02], normal = [0.0, 0.0, -1.0] }
material = "steel"
active = { to = 5e-4 }
"#,
        sets: &["wall.0.material=glass"],
        key: "wall[1].active",
    },
    Case {
        site: "lammps_scene.rs deck: scheme",
        code: "lammps",
        extra: "",
        sets: &["integration.scheme=gear5"],
        key: "integration.scheme",
    },
    Case {
        site: "liggghts_scene.rs deck: scheme",
        code: "liggghts",
        extra: "",
        sets: &["integration.scheme=gear5"],
        key: "integration.scheme",
    },
    Case {
        site: "yade_scene.rs deck: scheme",
        code: "yade",
        extra: "",
        sets: &["integration.scheme=gear5", "wall.0.material=glass"],
        key: "integration.scheme",
    },
    Case {
        site: "lammps_scene.rs deck: wall type (cylinder)",
        code: "lammps",
        extra: r#"[[wall]]
cylinder = { point = [0.005, 0.005, 0.0], axis = [0.0, 0.0, 1.0], radius = 0.0045 }
material = "steel"
"#,
        sets: &[],
        key: "wall[1].cylinder",
    },
    Case {
        site: "lammps_scene.rs deck: wall type (mesh)",
        code: "lammps",
        extra: r#"[[wall]]
mesh = { file = "floor.stl", translate = [0.0, 0.0, 0.001] }
material = "steel"
"#,
        sets: &[],
        key: "wall[1].mesh",
    },
    Case {
        site: "lammps_scene.rs deck: contact.law",
        code: "lammps",
        extra: "",
        sets: &[
            "contact.law=linear",
            "contact.damping=viscous",
            "contact.restitution=0.5",
        ],
        key: "contact.law",
    },
    Case {
        site: "lammps_scene.rs deck: damping_coefficient",
        code: "lammps",
        extra: "",
        sets: &["contact.damping=tsuji", "contact.damping_coefficient=1e-3"],
        key: "contact.damping_coefficient",
    },
    Case {
        site: "lammps_scene.rs deck: damping kind",
        code: "lammps",
        extra: "",
        sets: &[
            "contact.damping=viscoelastic",
            "contact.restitution=0.9",
            "contact.calibration=formula",
        ],
        key: "contact.damping",
    },
    Case {
        site: "lammps_friction.rs plan: tangential dashpot",
        code: "lammps",
        extra: "",
        sets: &[
            "contact.friction=0.5",
            "contact.damping=tsuji",
            "contact.restitution=0.5",
        ],
        key: "contact.tangential_damping",
    },
    Case {
        site: "lammps_friction.rs plan: projected spring",
        code: "lammps",
        extra: "",
        sets: &["contact.friction=0.5", "contact.spring_rotation=project"],
        key: "contact.spring_rotation",
    },
    Case {
        site: "lammps_friction.rs plan: rolling with damping",
        code: "lammps",
        extra: "",
        sets: &[
            "contact.friction=0.5",
            "contact.rolling_friction=0.1",
            "contact.tangential_damping=false",
            "contact.damping=tsuji",
            "contact.restitution=0.5",
        ],
        key: "contact.rolling_friction",
    },
    Case {
        site: "lammps_friction.rs plan: rolling under Hertz",
        code: "lammps",
        extra: "",
        sets: &["contact.friction=0.5", "contact.rolling_friction=0.1"],
        key: "contact.rolling_friction",
    },
    Case {
        site: "lammps_friction.rs: linear tangential, several radii",
        code: "lammps",
        extra: r#"[[particles]]
material = "glass"
spheres = [ { position = [0.005, 0.005, 0.012], radius = 0.8e-3 } ]
"#,
        sets: &["contact.friction=0.5", "contact.tangential=linear"],
        key: "contact.tangential",
    },
    Case {
        site: "lammps_motion.rs group_moves: start/end",
        code: "lammps",
        extra: r#"[[particles]]
material = "steel"
fixed = true
spheres = [ { position = [0.005, 0.005, 0.015], radius = 1.0e-3 } ]
motion = { velocity = [0.0, 0.0, 0.01], start = 0.0005 }
"#,
        sets: &[],
        key: "particles[1].motion",
    },
    Case {
        site: "lammps_motion.rs group_moves: moves nothing",
        code: "lammps",
        extra: r#"[[particles]]
material = "steel"
fixed = true
spheres = [ { position = [0.005, 0.005, 0.015], radius = 1.0e-3 } ]
motion = { velocity = [0.0, 0.0, 0.0] }
"#,
        sets: &[],
        key: "particles[1].motion",
    },
    Case {
        site: "lammps_motion.rs group_moves: several motions",
        code: "lammps",
        extra: r#"[[particles]]
material = "steel"
fixed = true
spheres = [ { position = [0.005, 0.005, 0.015], radius = 1.0e-3 } ]
motion = { velocity = [0.0, 0.0, 0.01], angular_velocity = [0.0, 0.0, 1.0] }
"#,
        sets: &[],
        key: "particles[1].motion",
    },
    Case {
        site: "lammps_motion.rs plane_shear: oscillation",
        code: "lammps",
        extra: "",
        sets: &["wall.0.oscillation={amplitude=[0.0,0.0,1e-4],frequency=10.0}"],
        key: "wall[0].oscillation",
    },
    Case {
        site: "lammps_motion.rs plane_shear: angular_velocity",
        code: "lammps",
        extra: "",
        sets: &["wall.0.motion={angular_velocity=[0.0,0.0,1.0]}"],
        key: "wall[0].motion.angular_velocity",
    },
    Case {
        site: "lammps_motion.rs plane_shear: start/end",
        code: "lammps",
        extra: "",
        sets: &["wall.0.motion={velocity=[0.01,0.0,0.0],start=0.0005}"],
        key: "wall[0].motion",
    },
    Case {
        site: "lammps_motion.rs plane_shear: tilted plane",
        code: "lammps",
        extra: "",
        sets: &[
            "wall.0.plane.normal=[0.0,0.6,0.8]",
            "wall.0.motion={velocity=[0.0,0.8,-0.6]}",
        ],
        key: "wall[0].motion",
    },
    Case {
        site: "lammps_motion.rs plane_shear: along the normal",
        code: "lammps",
        extra: "",
        sets: &["wall.0.motion={velocity=[0.0,0.0,0.01]}"],
        key: "wall[0].motion.velocity",
    },
    Case {
        site: "lammps_motion.rs refuse_other_moving_walls",
        code: "lammps",
        extra: r#"[[wall]]
cylinder = { point = [0.005, 0.005, 0.0], axis = [0.0, 0.0, 1.0], radius = 0.0045 }
material = "steel"
motion = { velocity = [0.0, 0.0, 0.01] }
"#,
        sets: &[],
        key: "wall[1].motion",
    },
    Case {
        site: "lammps_inlets.rs refuse: beside a moving group",
        code: "lammps",
        extra: r#"[[inlet]]
region = { box = { lower = [0.001, 0.001, 0.016], upper = [0.009, 0.009, 0.019] } }
rate = { number = 100.0 }
size = { fixed = 1.0e-3 }
material = "glass"
[[particles]]
material = "steel"
fixed = true
spheres = [ { position = [0.005, 0.005, 0.015], radius = 1.0e-3 } ]
motion = { velocity = [0.0, 0.0, 0.01] }
"#,
        sets: &[],
        key: "inlet[0]",
    },
    Case {
        site: "outlets.rs region_command: tilted cylinder",
        code: "lammps",
        extra: r#"[[outlet]]
region = { cylinder = { center = [0.005, 0.005, 0.002], axis = [0.0, 0.6, 0.8], radius = 0.002, length = 0.002 } }
"#,
        sets: &[],
        key: "outlet[0].region.cylinder.axis",
    },
    Case {
        site: "outlets.rs region_command: tilted cylinder",
        code: "liggghts",
        extra: r#"[[outlet]]
region = { cylinder = { center = [0.005, 0.005, 0.002], axis = [0.0, 0.6, 0.8], radius = 0.002, length = 0.002 } }
"#,
        sets: &[],
        key: "outlet[0].region.cylinder.axis",
    },
    Case {
        site: "liggghts_scene.rs deck: tilted plane",
        code: "liggghts",
        extra: "",
        sets: &["wall.0.plane.normal=[0.0,0.6,0.8]"],
        key: "wall[0].plane",
    },
    Case {
        site: "liggghts_scene.rs deck: active with motion",
        code: "liggghts",
        extra: r#"[[wall]]
mesh = { file = "floor.stl", translate = [0.0, 0.0, 0.001] }
material = "steel"
active = { from = 5e-4 }
motion = { angular_velocity = [0.0, 0.0, 1.0], center = [0.005, 0.005, 0.0] }
"#,
        sets: &[],
        key: "wall[1].active",
    },
    Case {
        site: "liggghts_scene.rs deck: wall type (cylinder)",
        code: "liggghts",
        extra: r#"[[wall]]
cylinder = { point = [0.005, 0.005, 0.0], axis = [0.0, 0.0, 1.0], radius = 0.0045 }
material = "steel"
"#,
        sets: &[],
        key: "wall[1].cylinder",
    },
    Case {
        site: "liggghts_scene.rs deck: rigid material",
        code: "liggghts",
        extra: "",
        sets: &["material.1.youngs_modulus=inf"],
        key: "material[1].youngs_modulus",
    },
    Case {
        site: "liggghts_contact.rs: contact.law",
        code: "liggghts",
        extra: "",
        sets: &[
            "contact.law=linear",
            "contact.damping=viscous",
            "contact.restitution=0.5",
        ],
        key: "contact.law",
    },
    Case {
        site: "liggghts_contact.rs: Hooke damped",
        code: "liggghts",
        extra: "",
        sets: &[
            "contact.law={hooke=100.0}",
            "contact.damping=viscous",
            "contact.restitution=0.5",
        ],
        key: "contact.damping",
    },
    Case {
        site: "liggghts_contact.rs: exact calibration",
        code: "liggghts",
        extra: "",
        sets: &[
            "contact.restitution=0.05",
            "contact.damping=tsuji",
            "contact.calibration=exact",
        ],
        key: "contact.restitution",
    },
    Case {
        site: "liggghts_contact.rs: damping_coefficient",
        code: "liggghts",
        extra: "",
        sets: &["contact.damping=tsuji", "contact.damping_coefficient=1e-3"],
        key: "contact.damping_coefficient",
    },
    Case {
        site: "liggghts_contact.rs: damping kind",
        code: "liggghts",
        extra: "",
        sets: &[
            "contact.damping=viscoelastic",
            "contact.restitution=0.9",
            "contact.calibration=formula",
        ],
        key: "contact.damping",
    },
    Case {
        site: "liggghts_contact.rs: rolling under Hertz",
        code: "liggghts",
        extra: "",
        sets: &["contact.friction=0.5", "contact.rolling_friction=0.1"],
        key: "contact.rolling_friction",
    },
    Case {
        site: "liggghts_contact.rs: Mindlin under Hooke",
        code: "liggghts",
        extra: "",
        sets: &[
            "contact.law={hooke=100.0}",
            "contact.friction=0.5",
            "contact.tangential=mindlin",
        ],
        key: "contact.tangential",
    },
    Case {
        site: "liggghts_contact.rs: linear under Hertz",
        code: "liggghts",
        extra: "",
        sets: &["contact.friction=0.5", "contact.tangential=linear"],
        key: "contact.tangential",
    },
    Case {
        site: "liggghts_contact.rs: tangential dashpot",
        code: "liggghts",
        extra: "",
        sets: &[
            "contact.friction=0.5",
            "contact.damping=tsuji",
            "contact.restitution=0.5",
        ],
        key: "contact.damping",
    },
    Case {
        site: "liggghts_contact.rs: linear, several radii",
        code: "liggghts",
        extra: r#"[[particles]]
material = "glass"
spheres = [ { position = [0.005, 0.005, 0.012], radius = 0.8e-3 } ]
"#,
        sets: &[
            "contact.law={hooke=100.0}",
            "contact.friction=0.5",
            "contact.tangential=linear",
        ],
        key: "contact.tangential",
    },
    Case {
        site: "liggghts_contact.rs: epsd2 rolling stiffness",
        code: "liggghts",
        extra: "",
        sets: &[
            "contact.law={hooke=100.0}",
            "contact.friction=0.5",
            "contact.tangential=linear",
            "contact.rolling_friction=0.1",
        ],
        key: "contact.rolling_friction",
    },
    Case {
        site: "liggghts_motion.rs move_mesh_line: not a mesh (cylinder)",
        code: "liggghts",
        extra: r#"[[wall]]
cylinder = { point = [0.005, 0.005, 0.0], axis = [0.0, 0.0, 1.0], radius = 0.0045 }
material = "steel"
motion = { velocity = [0.0, 0.0, 0.01] }
"#,
        sets: &[],
        key: "wall[1].motion",
    },
    Case {
        site: "liggghts_motion.rs move_mesh_line: not a mesh (plane)",
        code: "liggghts",
        extra: "",
        sets: &["wall.0.motion={velocity=[0.01,0.0,0.0]}"],
        key: "wall[0].motion",
    },
    Case {
        site: "liggghts_motion.rs move_mesh_line: plane oscillation",
        code: "liggghts",
        extra: "",
        sets: &["wall.0.oscillation={amplitude=[0.0,0.0,1e-4],frequency=10.0}"],
        key: "wall[0].oscillation",
    },
    Case {
        site: "liggghts_motion.rs linear_line: start/end",
        code: "liggghts",
        extra: r#"[[wall]]
mesh = { file = "floor.stl", translate = [0.0, 0.0, 0.001] }
material = "steel"
motion = { velocity = [0.01, 0.0, 0.0], start = 0.0005 }
"#,
        sets: &[],
        key: "wall[1].motion",
    },
    Case {
        site: "liggghts_motion.rs rotate_line: oscillation",
        code: "liggghts",
        extra: r#"[[wall]]
mesh = { file = "floor.stl", translate = [0.0, 0.0, 0.001] }
material = "steel"
oscillation = { amplitude = [0.0, 0.0, 1e-4], frequency = 10.0 }
"#,
        sets: &[],
        key: "wall[1].oscillation",
    },
    Case {
        site: "liggghts_motion.rs rotate_line: velocity with turning",
        code: "liggghts",
        extra: r#"[[wall]]
mesh = { file = "floor.stl", translate = [0.0, 0.0, 0.001] }
material = "steel"
motion = { velocity = [0.01, 0.0, 0.0], angular_velocity = [0.0, 0.0, 1.0], center = [0.005, 0.005, 0.0] }
"#,
        sets: &[],
        key: "wall[1].motion.velocity",
    },
    Case {
        site: "liggghts_motion.rs rotate_line: start/end",
        code: "liggghts",
        extra: r#"[[wall]]
mesh = { file = "floor.stl", translate = [0.0, 0.0, 0.001] }
material = "steel"
motion = { angular_velocity = [0.0, 0.0, 1.0], center = [0.005, 0.005, 0.0], start = 0.0005 }
"#,
        sets: &[],
        key: "wall[1].motion",
    },
    Case {
        site: "liggghts_motion.rs rotate_line: moves nothing",
        code: "liggghts",
        extra: r#"[[wall]]
mesh = { file = "floor.stl", translate = [0.0, 0.0, 0.001] }
material = "steel"
motion = { velocity = [0.0, 0.0, 0.0] }
"#,
        sets: &[],
        key: "wall[1].motion",
    },
    Case {
        site: "yade_scene.rs deck: periodic lower corner",
        code: "yade",
        extra: "",
        sets: &[
            "wall.0.material=glass",
            "domain.periodic=[true,false,false]",
            "domain.lower=[-0.01,0.0,0.0]",
        ],
        key: "domain.lower",
    },
    Case {
        site: "yade_scene.rs deck: tilted plane",
        code: "yade",
        extra: "",
        sets: &["wall.0.material=glass", "wall.0.plane.normal=[0.0,0.6,0.8]"],
        key: "wall[0].plane",
    },
    Case {
        site: "yade_scene.rs deck: wall type (cylinder)",
        code: "yade",
        extra: r#"[[wall]]
cylinder = { point = [0.005, 0.005, 0.0], axis = [0.0, 0.0, 1.0], radius = 0.0045 }
material = "steel"
"#,
        sets: &["wall.0.material=glass"],
        key: "wall[1].cylinder",
    },
    Case {
        site: "yade_scene.rs deck: wall type (mesh)",
        code: "yade",
        extra: r#"[[wall]]
mesh = { file = "floor.stl", translate = [0.0, 0.0, 0.001] }
material = "steel"
"#,
        sets: &["wall.0.material=glass"],
        key: "wall[1].mesh",
    },
    Case {
        site: "yade_scene.rs deck: two free materials",
        code: "yade",
        extra: r#"[[particles]]
material = "steel"
spheres = [ { position = [0.005, 0.005, 0.012], radius = 1.0e-3 } ]
"#,
        sets: &["wall.0.material=glass"],
        key: "material",
    },
    Case {
        site: "yade_scene.rs deck: rigid free material",
        code: "yade",
        extra: "",
        sets: &[
            "material.0.youngs_modulus=inf",
            "integration.dt=1e-6",
            "wall.0.material=glass",
        ],
        key: "material[0].youngs_modulus",
    },
    Case {
        site: "yade_scene.rs deck: rolling under Hertz",
        code: "yade",
        extra: "",
        sets: &[
            "wall.0.material=glass",
            "contact.friction=0.5",
            "contact.rolling_friction=0.1",
        ],
        key: "contact.rolling_friction",
    },
    Case {
        site: "yade_scene.rs deck: tangential vs law",
        code: "yade",
        extra: "",
        sets: &[
            "wall.0.material=glass",
            "contact.friction=0.5",
            "contact.tangential=linear",
        ],
        key: "contact.tangential",
    },
    Case {
        site: "yade_scene.rs deck: tangential dashpot",
        code: "yade",
        extra: "",
        sets: &[
            "wall.0.material=glass",
            "contact.friction=0.5",
            "contact.damping=tsuji",
            "contact.restitution=0.5",
        ],
        key: "contact.tangential_damping",
    },
    Case {
        site: "yade_scene.rs deck: projected spring",
        code: "yade",
        extra: "",
        sets: &[
            "wall.0.material=glass",
            "contact.friction=0.5",
            "contact.spring_rotation=project",
        ],
        key: "contact.spring_rotation",
    },
    Case {
        site: "yade_scene.rs deck: no stand-in material",
        code: "yade",
        extra: "",
        sets: &[],
        key: "wall[0]",
    },
    Case {
        site: "yade_scene.rs deck: attractive Tsuji",
        code: "yade",
        extra: "",
        sets: &[
            "wall.0.material=glass",
            "contact.attractive=true",
            "contact.damping=tsuji",
            "contact.restitution=0.5",
        ],
        key: "contact.attractive",
    },
    Case {
        site: "yade_scene.rs deck: damping_coefficient",
        code: "yade",
        extra: "",
        sets: &[
            "wall.0.material=glass",
            "contact.damping=tsuji",
            "contact.damping_coefficient=1e-3",
        ],
        key: "contact.damping_coefficient",
    },
    Case {
        site: "yade_scene.rs deck: damping kind",
        code: "yade",
        extra: "",
        sets: &[
            "wall.0.material=glass",
            "contact.damping=viscoelastic",
            "contact.restitution=0.9",
            "contact.calibration=formula",
        ],
        key: "contact.damping",
    },
    Case {
        site: "yade_scene.rs deck: Hooke damped",
        code: "yade",
        extra: "",
        sets: &[
            "wall.0.material=glass",
            "contact.law={hooke=100.0}",
            "contact.damping=viscous",
            "contact.restitution=0.5",
        ],
        key: "contact.damping",
    },
    Case {
        site: "yade_scene.rs deck: Hooke, several radii",
        code: "yade",
        extra: r#"[[particles]]
material = "glass"
spheres = [ { position = [0.005, 0.005, 0.012], radius = 0.8e-3 } ]
"#,
        sets: &["wall.0.material=glass", "contact.law={hooke=100.0}"],
        key: "contact.law",
    },
    Case {
        site: "yade_scene.rs deck: rolling stand-in",
        code: "yade",
        extra: "",
        sets: &[
            "wall.0.material=glass",
            "contact.law={hooke=100.0}",
            "contact.friction=0.5",
            "contact.tangential=linear",
            "contact.rolling_friction=0.1",
            "wall.0.rolling_friction=0.5",
        ],
        key: "wall[0].rolling_friction",
    },
    Case {
        site: "yade_scene.rs deck: contact.law",
        code: "yade",
        extra: "",
        sets: &[
            "wall.0.material=glass",
            "contact.law=linear",
            "contact.damping=viscous",
            "contact.restitution=0.5",
        ],
        key: "contact.law",
    },
    Case {
        site: "yade_scene.rs deck: wall friction above the spheres'",
        code: "yade",
        extra: "",
        sets: &[
            "wall.0.material=glass",
            "wall.0.friction=0.9",
            "contact.friction=0.3",
            "contact.tangential_damping=false",
        ],
        key: "wall[0]",
    },
    Case {
        site: "yade_scene.rs deck: lower corner below 0",
        code: "yade",
        extra: "",
        sets: &[
            "wall.0.material=glass",
            "domain.periodic=[true,false,false]",
            "domain.lower=[0.0,-0.01,0.0]",
        ],
        key: "domain.lower",
    },
    Case {
        site: "yade_scene.rs deck: Hooke, a wall's k_t above twice the spheres'",
        code: "yade",
        extra: "",
        sets: &[
            "contact.law={hooke=100.0}",
            "contact.friction=0.5",
            "contact.tangential=linear",
        ],
        key: "wall[0]",
    },
];

/// Exports `scene` (written with [`FLOOR_STL`] beside it) to `code` with
/// `sets` into `dir/deck`: (exit code, stderr, whether `deck` exists).
fn export(dir: &Path, code: &str, scene: &str, sets: &[&str]) -> (Option<i32>, String, bool) {
    std::fs::write(dir.join("floor.stl"), FLOOR_STL).expect("written");
    let path = dir.join("s.toml");
    std::fs::write(&path, scene).expect("written");
    let out = dir.join("deck");
    let set_args: Vec<String> = sets
        .iter()
        .flat_map(|s| ["--set".to_string(), (*s).to_string()])
        .collect();
    let o = dembound()
        .args(["export", code])
        .arg(&path)
        .args(&set_args)
        .arg("--out")
        .arg(&out)
        .output()
        .expect("dembound runs");
    (
        o.status.code(),
        String::from_utf8_lossy(&o.stderr).into_owned(),
        out.exists(),
    )
}

/// Every site: exit 2, the key and the code named, nothing written. All
/// cases run; the failures are listed together.
#[test]
fn every_refusal_names_the_key_and_the_code() {
    let mut failures = Vec::new();
    for case in CASES {
        let dir = tempfile::tempdir().expect("a temporary directory");
        let scene = format!("{BASE}{}", case.extra);
        let (code, stderr, written) = export(dir.path(), case.code, &scene, case.sets);
        let name = code_name(case.code);
        let ok = code == Some(2)
            && stderr.starts_with("error: ")
            && stderr.contains(case.key)
            && stderr.contains(name)
            && !written;
        if !ok {
            failures.push(format!(
                "{} ({}): exit {code:?}, deck written: {written}, want `{}` and {name} in: {stderr}",
                case.site, case.code, case.key
            ));
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// The table covers every code: each has at least one case per shared
/// refusal (lib.rs) it calls, and the cases are distinct.
#[test]
fn the_table_has_no_duplicate_case() {
    for (i, a) in CASES.iter().enumerate() {
        for b in &CASES[i + 1..] {
            assert!(
                !(a.code == b.code && a.extra == b.extra && a.sets == b.sets),
                "{} and {} are the same case",
                a.site,
                b.site
            );
        }
    }
}

/// The refusals of a bounce scenario (`dembound export CODE` with the
/// default scenario and `--set`, or `--pitfall`): exit 2, the key (or
/// option) and the code named, nothing written. The code is matched
/// without case: `--pitfall`'s own names are lower case.
#[test]
fn every_bounce_refusal_names_the_key_and_the_code() {
    let cases: &[(&str, &[&str], &str, &str)] = &[
        (
            "lib.rs export: pitfall of another code",
            &["liggghts", "--pitfall", "auto-mix"],
            "--pitfall",
            "lammps",
        ),
        (
            "plan.rs: law and damping",
            &[
                "lammps",
                "--set",
                "contact.law=walton-braun",
                "--set",
                "contact.restitution=0.5",
            ],
            "contact.law",
            "LAMMPS",
        ),
        (
            "lammps.rs: auto-mix without a sphere",
            &[
                "lammps",
                "--set",
                "boundary.radius_ratio=inf",
                "--pitfall",
                "auto-mix",
            ],
            "boundary.radius_ratio",
            "LAMMPS",
        ),
        (
            "lammps.rs: auto-mix with a rigid sphere",
            &[
                "lammps",
                "--set",
                "boundary.modulus_ratio=inf",
                "--pitfall",
                "auto-mix",
            ],
            "boundary.modulus_ratio",
            "LAMMPS",
        ),
        (
            "liggghts.rs: rigid boundary",
            &["liggghts", "--set", "boundary.modulus_ratio=inf"],
            "boundary.modulus_ratio",
            "LIGGGHTS",
        ),
        (
            "liggghts.rs: Hertz damped",
            &[
                "liggghts",
                "--set",
                "contact.damping=tsuji",
                "--set",
                "contact.restitution=0.5",
            ],
            "contact.damping",
            "LIGGGHTS",
        ),
        (
            "yade.rs: rigid boundary",
            &["yade", "--set", "boundary.modulus_ratio=inf"],
            "boundary.modulus_ratio",
            "Yade",
        ),
        (
            "yade.rs: attractive dashpot",
            &[
                "yade",
                "--set",
                "contact.law=linear",
                "--set",
                "contact.damping=viscous",
                "--set",
                "contact.restitution=0.5",
                "--set",
                "contact.attractive=true",
            ],
            "contact.attractive",
            "Yade",
        ),
        (
            "yade.rs: Hertz damped",
            &[
                "yade",
                "--set",
                "contact.damping=tsuji",
                "--set",
                "contact.restitution=0.5",
            ],
            "contact.damping",
            "Yade",
        ),
        (
            "yade.rs: yade-wall with a sphere",
            &[
                "yade",
                "--set",
                "boundary.radius_ratio=10",
                "--pitfall",
                "yade-wall",
            ],
            "boundary.radius_ratio",
            "Yade",
        ),
    ];
    let mut failures = Vec::new();
    for (site, args, key, name) in cases {
        let dir = tempfile::tempdir().expect("a temporary directory");
        let out = dir.path().join("deck");
        let o = dembound()
            .arg("export")
            .args(*args)
            .arg("--out")
            .arg(&out)
            .output()
            .expect("dembound runs");
        let stderr = String::from_utf8_lossy(&o.stderr);
        let ok = o.status.code() == Some(2)
            && stderr.contains(key)
            && stderr.to_lowercase().contains(&name.to_lowercase())
            && !out.exists();
        if !ok {
            failures.push(format!(
                "{site}: exit {:?}, want `{key}` and {name} in: {stderr}",
                o.status.code()
            ));
        }
    }
    // A scene file with --pitfall: the option and the code named.
    let dir = tempfile::tempdir().expect("a temporary directory");
    let (code, stderr, written) = {
        let path = dir.path().join("s.toml");
        std::fs::write(&path, BASE).expect("written");
        let out = dir.path().join("deck");
        let o = dembound()
            .args(["export", "lammps"])
            .arg(&path)
            .args(["--pitfall", "auto-mix", "--out"])
            .arg(&out)
            .output()
            .expect("dembound runs");
        (
            o.status.code(),
            String::from_utf8_lossy(&o.stderr).into_owned(),
            out.exists(),
        )
    };
    if !(code == Some(2) && stderr.contains("--pitfall") && stderr.contains("LAMMPS") && !written) {
        failures.push(format!(
            "export.rs run_scene: --pitfall on a scene: exit {code:?}: {stderr}"
        ));
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// `--set contact.friction=0` on a frictional file exports to every code
/// (issue 32 item 1), and writes the deck of the same file without its
/// friction keys (byte for byte, every file but the resolved scene.toml,
/// which records the override).
#[test]
fn friction_set_to_zero_exports_the_frictionless_deck() {
    // Tsuji damping with the tangential dashpot on: refused with friction
    // by LAMMPS, LIGGGHTS and Yade (the cases above), so the override is
    // what makes these exports possible. The floor glass for Yade's
    // stand-in material.
    let frictionless = BASE
        .replace(
            "law = \"hertz\"",
            "law = \"hertz\"\ndamping = \"tsuji\"\nrestitution = 0.5",
        )
        .replace("material = \"steel\"", "material = \"glass\"");
    let frictional = frictionless.replace(
        "restitution = 0.5",
        "restitution = 0.5\nfriction = 0.5\ntangential_damping = true",
    );
    assert_ne!(frictional, frictionless);
    for code in ["lammps", "liggghts", "yade"] {
        let (a, b) = (tempfile::tempdir().unwrap(), tempfile::tempdir().unwrap());
        let (refused, stderr, _) = export(a.path(), code, &frictional, &[]);
        assert_eq!(
            refused,
            Some(2),
            "{code}: the frictional file itself: {stderr}"
        );
        std::fs::remove_dir_all(a.path().join("deck")).ok();
        let (set, stderr, written) = export(a.path(), code, &frictional, &["contact.friction=0"]);
        assert!(
            set == Some(0) && written,
            "{code} --set contact.friction=0: {stderr}"
        );
        let (plain, stderr, _) = export(b.path(), code, &frictionless, &[]);
        assert_eq!(plain, Some(0), "{code} without friction: {stderr}");
        let mut names: Vec<_> = std::fs::read_dir(b.path().join("deck"))
            .unwrap()
            .map(|e| e.unwrap().file_name())
            .collect();
        names.sort();
        for name in names.iter().filter(|n| *n != "scene.toml") {
            let x = std::fs::read(a.path().join("deck").join(name)).unwrap();
            let y = std::fs::read(b.path().join("deck").join(name)).unwrap();
            assert!(
                x == y,
                "{code}: {name:?} differs from the frictionless file's"
            );
        }
    }
}
