//! The lattice-drop benchmark (../shared/peers/lattice-drop/): spheres read
//! from a LAMMPS data file (`atom_style sphere`: id type diameter density x
//! y z), six plane walls of the particles' own material on the box faces,
//! Hertz, no damping, g = 9.81 m/s² along −z, Δt = 2 µs, skin 0.1 mm.
//!
//! `cargo run --release -p dembound-scene --example lattice_drop -- FILE.data [STEPS] [THREADS] [EVERY]`
//!
//! Prints the loop's wall-clock time, particle-steps/s, and the kinetic
//! energy and contact count at the last step (compare with
//! `run_lammps.sh`). The data reader here is minimal (this benchmark's
//! files only); the scene subcommand has the real one.

use std::time::Instant;

use dembound_physics::contact::{ContactModel, NormalLaw};
use dembound_physics::material::Material;
use dembound_scene::setup::{
    DomainSetup, NamedMaterial, Plane, RunLength, SphereInit, TimeStep, WallSetup,
};
use dembound_scene::{SceneSetup, Simulation};

struct Data {
    lower: [f64; 3],
    upper: [f64; 3],
    /// (diameter, density, position)
    atoms: Vec<(f64, f64, [f64; 3])>,
}

fn read_data(path: &str) -> Result<Data, String> {
    let text = std::fs::read_to_string(path).map_err(|e| format!("{path}: {e}"))?;
    let mut lower = [0.0; 3];
    let mut upper = [0.0; 3];
    let mut atoms = Vec::new();
    let mut in_atoms = false;
    for line in text.lines() {
        let line = line.split('#').next().unwrap_or("").trim();
        let words: Vec<&str> = line.split_whitespace().collect();
        if words.len() == 4 && words[2].ends_with("lo") {
            let a = match words[2] {
                "xlo" => 0,
                "ylo" => 1,
                "zlo" => 2,
                _ => continue,
            };
            lower[a] = words[0].parse().map_err(|e| format!("{line}: {e}"))?;
            upper[a] = words[1].parse().map_err(|e| format!("{line}: {e}"))?;
        } else if words.first() == Some(&"Atoms") {
            in_atoms = true;
        } else if in_atoms && words.len() >= 7 {
            let v: Result<Vec<f64>, _> = words[2..7].iter().map(|w| w.parse::<f64>()).collect();
            let v = v.map_err(|e| format!("{line}: {e}"))?;
            atoms.push((v[0], v[1], [v[2], v[3], v[4]]));
        } else if in_atoms && !words.is_empty() && words[0].parse::<f64>().is_err() {
            in_atoms = false;
        }
    }
    Ok(Data {
        lower,
        upper,
        atoms,
    })
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    if args.len() < 2 {
        eprintln!("usage: lattice_drop FILE.data [STEPS] [THREADS]");
        std::process::exit(2);
    }
    let steps: u64 = args.get(2).and_then(|s| s.parse().ok()).unwrap_or(10_000);
    let threads: usize = args.get(3).and_then(|s| s.parse().ok()).unwrap_or(1);
    let data = match read_data(&args[1]) {
        Ok(d) => d,
        Err(e) => {
            eprintln!("error: {e}");
            std::process::exit(2);
        }
    };
    let density = data.atoms.first().map_or(1000.0, |a| a.1);
    let mut setup = SceneSetup::new(
        DomainSetup {
            lower: data.lower,
            upper: data.upper,
            periodic: [false; 3],
        },
        ContactModel::elastic(NormalLaw::Hertz),
        TimeStep::Fixed(2.0e-6),
        RunLength::Steps(steps),
    );
    setup.gravity = [0.0, 0.0, -9.81];
    setup.neighbour.skin = Some(1.0e-4);
    setup.materials.push(NamedMaterial {
        name: "grain".into(),
        material: Material {
            density,
            youngs_modulus: 1.0e7,
            poisson_ratio: 0.3,
        },
    });
    for (d, _, x) in &data.atoms {
        setup.spheres.push(SphereInit {
            position: *x,
            velocity: [0.0; 3],
            radius: 0.5 * d,
            material: 0,
            fixed: false,
            group: None,
        });
    }
    // The file's copy is not needed any more (peak memory).
    drop(data);
    for a in 0..3 {
        let mut n = [0.0; 3];
        n[a] = 1.0;
        setup.walls.push(WallSetup::Plane(Plane {
            point: setup.domain.lower,
            normal: n,
            material: 0,
        }));
        n[a] = -1.0;
        setup.walls.push(WallSetup::Plane(Plane {
            point: setup.domain.upper,
            normal: n,
            material: 0,
        }));
    }
    let start = Instant::now();
    let mut sim = match Simulation::new(setup, threads) {
        Ok(s) => s,
        Err(e) => {
            eprintln!("error: {e}");
            std::process::exit(2);
        }
    };
    let setup_time = start.elapsed().as_secs_f64();
    let loop_start = Instant::now();
    // Thermo lines every `every` steps (0: none), like the LAMMPS deck's.
    let every: u64 = args.get(4).and_then(|s| s.parse().ok()).unwrap_or(0);
    if every > 0 {
        while sim.remaining_steps() > 0 {
            sim.step(every.min(sim.remaining_steps()));
            let o = sim.observe();
            println!(
                "{:>8} {:.7e} J {:>7} (2 x particle contacts)",
                sim.steps_done(),
                o.kinetic_energy,
                2 * o.particle_contacts
            );
        }
    }
    sim.run_to_end();
    let loop_time = loop_start.elapsed().as_secs_f64();
    let o = sim.observe();
    let n = sim.body_count();
    println!(
        "dembound lattice-drop N={n} steps={} threads={threads}: setup {setup_time:.3} s, loop {loop_time:.3} s, \
         {:.3e} particle-steps/s, kinetic energy {:.6e} J, particle contacts {} (x2 = {}), wall contacts {}, \
         list builds {}, listed pairs {}",
        sim.steps_done(),
        n as f64 * sim.steps_done() as f64 / loop_time,
        o.kinetic_energy,
        o.particle_contacts,
        2 * o.particle_contacts,
        o.wall_contacts,
        sim.list_builds(),
        sim.listed_pairs()
    );
}
