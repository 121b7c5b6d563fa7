//! Cross-check of the lattice source against the benchmark's own
//! generator: `tests/data/lattice_3x3x2.data` was written by
//! `peers/lattice-drop/make_lattice.py 3 2` (Python), read here by the
//! LAMMPS reader.

use dembound_scene::sources::lammps_data::LammpsData;
use dembound_scene::sources::lattice::Lattice;
use std::path::Path;

#[test]
fn lattice_source_reproduces_make_lattice_py() {
    let data = LammpsData::read(Path::new(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/tests/data/lattice_3x3x2.data"
    )))
    .unwrap();
    let lattice = Lattice {
        counts: [3, 3, 2],
        spacing: [1.2e-3, 1.2e-3, 0.54e-3],
        origin: [0.6e-3, 0.6e-3, 0.505e-3],
        radius: 0.5e-3,
        stagger: true,
    };
    let ours = lattice.spheres();
    assert_eq!(ours.len(), data.atoms.len());
    // The script's box: L = n·a + a/2 = 4.2 mm, 30 mm high.
    assert!((data.bounds[0][1] - 4.2e-3).abs() < 1e-15);
    assert_eq!(data.bounds[2], [0.0, 0.03]);
    for (q, (a, b)) in ours.iter().zip(&data.atoms).enumerate() {
        assert_eq!(b.id, q as u64 + 1);
        assert_eq!(a.radius, b.sphere.radius);
        for k in 0..3 {
            // The script prints 9 significant digits: half a unit of the
            // 9th digit, 5e-9 relative.
            let (x, y) = (a.position[k], b.sphere.position[k]);
            assert!((x - y).abs() <= 5e-9 * y.abs(), "atom {}: {x} vs {y}", b.id);
        }
    }
}

/// A scene file over `data` (a LAMMPS data text) with two materials; the
/// `[[particles]]` group gets `extra` lines.
fn resolve_data(
    data: &str,
    extra: &str,
) -> Result<dembound_scene::io::resolve::ResolvedScene, String> {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("atoms.data"), data).unwrap();
    let text = format!(
        "[domain]\nlower = [0.0, 0.0, 0.0]\nupper = [0.0042, 0.0042, 0.03]\n\
         [[material]]\nname = \"grain\"\ndensity = 1000.0\nyoungs_modulus = 1e7\npoisson_ratio = 0.3\n\
         [[material]]\nname = \"glass\"\ndensity = 2500.0\nyoungs_modulus = 6.3e10\npoisson_ratio = 0.22\n\
         [contact]\nlaw = \"hertz\"\n\
         [[particles]]\nlammps_data = \"atoms.data\"\nmaterial = \"grain\"\n{extra}\n\
         [integration]\ndt = 1e-6\nsteps = 1\n"
    );
    let file =
        dembound_scene::io::config::load(&text, "scene.toml", &[]).map_err(|e| e.to_string())?;
    dembound_scene::io::resolve::resolve(&file, dir.path()).map_err(|e| e.to_string())
}

/// Atom types map to materials (`types`), and a density that is not the
/// material's is refused naming the atom (the engine's mass comes from the
/// material: a silent mismatch would not be the state LAMMPS runs).
#[test]
fn lammps_atom_types_choose_the_material_and_densities_must_agree() {
    let data = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/tests/data/lattice_3x3x2.data"
    ))
    .unwrap();
    // Atom 2 becomes type 2 of glass density.
    let two = data
        .replace(
            "2 1 0.001 1000.0 0.0018 0.0006",
            "2 2 0.001 2500.0 0.0018 0.0006",
        )
        .replace("1 atom types", "2 atom types");
    assert_ne!(two, data);
    let scene = resolve_data(&two, "types = { \"2\" = \"glass\" }").unwrap();
    let names: Vec<&str> = scene
        .setup
        .spheres
        .iter()
        .map(|s| scene.setup.materials[s.material].name.as_str())
        .collect();
    assert_eq!(names[0], "grain");
    assert_eq!(names[1], "glass");
    assert!(names[2..].iter().all(|n| *n == "grain"));
    // Without the mapping, atom 2's 2500 kg/m³ is not grain's 1000.
    let e = resolve_data(&two, "").unwrap_err();
    assert!(
        e.contains("atom 2 (type 2)") && e.contains("2500") && e.contains("particles[0].types"),
        "{e}"
    );
    // A mapping to an unknown material names the key.
    let e = resolve_data(&two, "types = { \"2\" = \"steel\" }").unwrap_err();
    assert!(e.contains("particles[0].types.2"), "{e}");
}
