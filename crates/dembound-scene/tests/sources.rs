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
