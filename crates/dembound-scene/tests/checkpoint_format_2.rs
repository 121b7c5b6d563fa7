//! Checkpoint files of format 2 (the completed collisions a CBOR map a
//! row, serde's derive of `Collision`; the log's tracks a list of
//! `(a, b, Track)` triples) and format 3 (the collisions in columns, the
//! tracks still triples) still restart, to the same collision log as the
//! run never stopped; format 4 (collisions and tracks in columns) is what
//! is written now, and a file whose columns are damaged behind a valid
//! checksum is refused naming what is wrong.
//!
//! The older files are built here the way those formats were written: the
//! file's CBOR with the collisions and tracks serialised by their derives,
//! the version in the header and the content, the length and SHA-256
//! after.

mod common;

use ciborium::Value;
use dembound_scene::dynamics::collisions::Partner;
use dembound_scene::io::checkpoint::{self, CheckpointFile, MAGIC};
use dembound_scene::io::config;
use dembound_scene::Simulation;
use sha2::{Digest, Sha256};

/// The example scene's file, for the checkpoint's record of the scene (a
/// restart takes the setup it is given).
fn scene() -> config::SceneFile {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../examples/scenes/lattice_drop.toml");
    config::read(&path, &[]).expect("the example scene reads")
}

/// Header, `payload`, length and SHA-256, as `io::checkpoint` frames a
/// file.
fn framed(version: u32, payload: &[u8]) -> Vec<u8> {
    let mut bytes = MAGIC.to_vec();
    bytes.extend(version.to_le_bytes());
    bytes.extend(payload);
    bytes.extend((payload.len() as u64).to_le_bytes());
    bytes.extend(Sha256::digest(payload));
    bytes
}

/// `file`'s CBOR as a value, `edit` applied to each entry of its `state`
/// by name (and `version` set), framed.
fn rewritten(file: &CheckpointFile, version: u32, edit: impl Fn(&str, &mut Value)) -> Vec<u8> {
    let mut v = Value::serialized(file).expect("a CBOR value");
    let Value::Map(top) = &mut v else {
        panic!("the file is a map")
    };
    let mut found = false;
    for (key, value) in top.iter_mut() {
        match key.as_text() {
            Some("version") => *value = Value::Integer(version.into()),
            Some("state") => {
                let Value::Map(state) = value else {
                    panic!("the state is a map")
                };
                for (k, c) in state.iter_mut() {
                    if let Some(name) = k.as_text() {
                        found |= name == "collisions";
                        edit(name, c);
                    }
                }
            }
            _ => {}
        }
    }
    assert!(found, "the state holds the collisions");
    let mut payload = Vec::new();
    ciborium::into_writer(&v, &mut payload).expect("encoded");
    framed(version, &payload)
}

#[test]
fn a_format_2_checkpoint_restarts_to_the_same_log() {
    // Mindlin μ = 0.5 with rolling friction (spins in the rows), Verlet,
    // the collision log on; the lattice lands from step ~50.
    let setup = common::frictional_lattice(6, 6, 2.0e-5);
    let (first, second) = (600, 400);
    let mut straight = Simulation::new(setup.clone(), 1).expect("a valid scene");
    straight.step(first + second);
    let mut a = Simulation::new(setup.clone(), 1).expect("a valid scene");
    a.step(first);
    let cp = a.checkpoint();
    // Not vacuous: completed contacts of both partner kinds, with spins,
    // and more of them after the checkpoint.
    let c = &cp.collisions;
    assert!(c.iter().any(|r| matches!(r.j, Partner::Body(_))), "{c:?}");
    assert!(c.iter().any(|r| matches!(r.j, Partner::Wall(_))), "{c:?}");
    assert!(c.iter().any(|r| r.rebound_spin_i != [0.0; 3]), "{c:?}");
    assert!(straight.collisions().len() > c.len());
    let file = CheckpointFile::new(scene(), cp.clone());
    // Format 2's rows: `Collision`'s derive (a list of maps).
    let rows = Value::serialized(&cp.collisions).expect("the rows");
    assert!(matches!(&rows, Value::Array(r) if r.len() == c.len()));
    // Formats 2 and 3's tracks: the derive of the triples (lists of maps).
    assert!(!cp.pair_tracks.is_empty() && !cp.plane_tracks.is_empty());
    let pair_tracks = Value::serialized(&cp.pair_tracks).expect("the triples");
    let plane_tracks = Value::serialized(&cp.plane_tracks).expect("the triples");
    assert!(matches!(&pair_tracks, Value::Array(t) if t.len() == cp.pair_tracks.len()));
    let triples = |name: &str, v: &mut Value| match name {
        "pair_tracks" => *v = pair_tracks.clone(),
        "plane_tracks" => *v = plane_tracks.clone(),
        _ => {}
    };
    // Format 3: the collisions as written now, the tracks as triples.
    let third = rewritten(&file, 3, triples);
    let read = checkpoint::read_from(&third[..], "format-3.cbor").expect("format 3 is read");
    assert_eq!(read.version, 3);
    assert_eq!(read.state, cp);
    let old = rewritten(&file, 2, |name, v| match name {
        "collisions" => *v = rows.clone(),
        _ => triples(name, v),
    });
    let read = checkpoint::read_from(&old[..], "format-2.cbor").expect("format 2 is read");
    assert_eq!(read.version, 2);
    assert_eq!(read.state, cp);
    let mut b = Simulation::restore(setup, &read.state, 1).expect("restored");
    b.step(second);
    // Positions, velocities, spins, forces, observables and the whole
    // collision log, every f64 printed exactly.
    assert_eq!(common::state(&straight), common::state(&b));
    // Written now: format 4, the columns, fewer bytes than either.
    let mut new = Vec::new();
    checkpoint::write(&mut new, &file).expect("written");
    assert_eq!(new[MAGIC.len()..MAGIC.len() + 4], 4u32.to_le_bytes());
    assert!(new.len() < third.len(), "{} vs {}", new.len(), third.len());
    assert!(third.len() < old.len(), "{} vs {}", third.len(), old.len());
    let read = checkpoint::read_from(&new[..], "format-4.cbor").expect("format 4 is read");
    assert_eq!(read.state, cp);
}

#[test]
fn damaged_collision_columns_behind_a_valid_checksum_are_named() {
    let setup = common::frictional_lattice(6, 6, 2.0e-5);
    let mut a = Simulation::new(setup, 1).expect("a valid scene");
    a.step(600);
    let file = CheckpointFile::new(scene(), a.checkpoint());
    let kind = |edit: fn(&mut Vec<u8>)| {
        move |name: &str, c: &mut Value| {
            if name != "collisions" {
                return;
            }
            let Value::Map(columns) = c else {
                panic!("format 4 writes a map of columns")
            };
            for (k, v) in columns.iter_mut() {
                if let (Some("kind"), Value::Bytes(b)) = (k.as_text(), v) {
                    edit(b);
                }
            }
        }
    };
    // A kind byte no partner has.
    let bad = rewritten(&file, 4, kind(|b| b[0] = 7));
    let e = checkpoint::read_from(&bad[..], "bad.cbor")
        .expect_err("refused")
        .to_string();
    assert!(
        e.contains("`bad.cbor`") && e.contains("row 0 has partner kind 7"),
        "{e}"
    );
    // A row short.
    let cut = rewritten(&file, 4, kind(|b| b.truncate(b.len() - 1)));
    let e = checkpoint::read_from(&cut[..], "cut.cbor")
        .expect_err("refused")
        .to_string();
    assert!(e.contains("`kind` holds"), "{e}");
}

/// The tracks' columns damaged behind a valid checksum: a flag bit no
/// track has, a column a byte short, a column named twice are refused
/// naming the fault (never a different run).
#[test]
fn damaged_track_columns_behind_a_valid_checksum_are_named() {
    let setup = common::frictional_lattice(6, 6, 2.0e-5);
    let mut a = Simulation::new(setup, 1).expect("a valid scene");
    a.step(600);
    let file = CheckpointFile::new(scene(), a.checkpoint());
    let column = |which: &'static str, edit: fn(&mut Vec<(Value, Value)>)| {
        move |name: &str, c: &mut Value| {
            if name == which {
                let Value::Map(columns) = c else {
                    panic!("format 4 writes the tracks as a map of columns")
                };
                edit(columns);
            }
        }
    };
    fn bytes_of(columns: &mut [(Value, Value)], name: &str, edit: fn(&mut Vec<u8>)) {
        for (k, v) in columns.iter_mut() {
            if let (Some(n), Value::Bytes(b)) = (k.as_text(), v) {
                if n == name {
                    edit(b);
                    return;
                }
            }
        }
        panic!("no column `{name}`");
    }
    let refused = |bytes: Vec<u8>, expected: &str| {
        let e = checkpoint::read_from(&bytes[..], "bad.cbor")
            .expect_err("refused")
            .to_string();
        assert!(e.contains("`bad.cbor`") && e.contains(expected), "{e}");
    };
    // Bit 2 is neither `known` (1) nor `in contact` (2).
    refused(
        rewritten(
            &file,
            4,
            column("pair_tracks", |c| bytes_of(c, "flags", |b| b[0] |= 4)),
        ),
        "row 0 has flags 0x",
    );
    refused(
        rewritten(
            &file,
            4,
            column("plane_tracks", |c| {
                bytes_of(c, "overlap", |b| {
                    b.pop();
                })
            }),
        ),
        "`overlap` holds",
    );
    refused(
        rewritten(
            &file,
            4,
            column("pair_tracks", |c| {
                let first = c[1].clone();
                c.push(first);
            }),
        ),
        "twice",
    );
}
