//! The checkpoint's completed collisions ([`Checkpoint::collisions`](super::Checkpoint))
//! in columns: a CBOR map of byte strings, one a field, each value
//! little-endian and fixed-width, so a long log is written as a few large
//! byte strings rather than a map with every field name a row (checkpoint
//! format 3; `io::checkpoint`).
//!
//! The map's entries:
//! - `rows`: the number of collisions, n;
//! - `kind`: a byte a row: the partner (0 a sphere, 1 a plane wall, 2 a
//!   boundary particle), plus [`HAS_TRIANGLE`] when the row names a
//!   triangle;
//! - `i`, `j`: u32 a row: sphere i (input index) and the partner's index
//!   (the sphere's input index, or the wall's in file order);
//! - `boundary_body`: u32 a boundary-particle row (row order): the
//!   particle's input index;
//! - `triangle`: u32 a row with [`HAS_TRIANGLE`] (row order);
//! - one entry a value of [`VALUES`] (f64 a row, by bits: NaN, ±∞ and −0.0
//!   kept). A value column of +0.0 alone (a frictionless run's spins) and
//!   an empty `boundary_body` or `triangle` are left out.
//!
//! [`deserialize`] reads this map or the list of row maps of format 2
//! (serde's derive of [`Collision`]), so older checkpoints still restart.

use std::fmt;

use serde::de::{self, MapAccess, SeqAccess, Visitor};
use serde::ser::{self, SerializeStruct};
use serde::{Deserialize, Deserializer, Serialize, Serializer};

use crate::dynamics::collisions::{Collision, Partner};

/// Flag of `kind`: the row names a triangle (mesh walls).
pub const HAS_TRIANGLE: u8 = 4;
/// `kind`'s partner bits.
const PARTNER: u8 = 3;

/// One f64 field of a [`Collision`]: its column's name and how to read and
/// set it.
pub struct Value {
    pub name: &'static str,
    get: fn(&Collision) -> f64,
    set: fn(&mut Collision, f64),
}

impl Value {
    /// This field of `c`.
    pub fn of(&self, c: &Collision) -> f64 {
        (self.get)(c)
    }
}

/// The f64 fields of a [`Collision`], in column order (spins by component):
/// the checkpoint's columns and collisions.csv's number columns.
pub const VALUES: [Value; 21] = [
    Value {
        name: "t_start",
        get: |c| c.t_start,
        set: |c, v| c.t_start = v,
    },
    Value {
        name: "t_end",
        get: |c| c.t_end,
        set: |c, v| c.t_end = v,
    },
    Value {
        name: "duration",
        get: |c| c.duration,
        set: |c, v| c.duration = v,
    },
    Value {
        name: "max_overlap",
        get: |c| c.max_overlap,
        set: |c, v| c.max_overlap = v,
    },
    Value {
        name: "max_normal_force",
        get: |c| c.max_normal_force,
        set: |c, v| c.max_normal_force = v,
    },
    Value {
        name: "impact_normal_velocity",
        get: |c| c.impact_normal_velocity,
        set: |c, v| c.impact_normal_velocity = v,
    },
    Value {
        name: "rebound_normal_velocity",
        get: |c| c.rebound_normal_velocity,
        set: |c, v| c.rebound_normal_velocity = v,
    },
    Value {
        name: "impact_tangential_velocity",
        get: |c| c.impact_tangential_velocity,
        set: |c, v| c.impact_tangential_velocity = v,
    },
    Value {
        name: "rebound_tangential_velocity",
        get: |c| c.rebound_tangential_velocity,
        set: |c, v| c.rebound_tangential_velocity = v,
    },
    Value {
        name: "impact_spin_i_x",
        get: |c| c.impact_spin_i[0],
        set: |c, v| c.impact_spin_i[0] = v,
    },
    Value {
        name: "impact_spin_i_y",
        get: |c| c.impact_spin_i[1],
        set: |c, v| c.impact_spin_i[1] = v,
    },
    Value {
        name: "impact_spin_i_z",
        get: |c| c.impact_spin_i[2],
        set: |c, v| c.impact_spin_i[2] = v,
    },
    Value {
        name: "rebound_spin_i_x",
        get: |c| c.rebound_spin_i[0],
        set: |c, v| c.rebound_spin_i[0] = v,
    },
    Value {
        name: "rebound_spin_i_y",
        get: |c| c.rebound_spin_i[1],
        set: |c, v| c.rebound_spin_i[1] = v,
    },
    Value {
        name: "rebound_spin_i_z",
        get: |c| c.rebound_spin_i[2],
        set: |c, v| c.rebound_spin_i[2] = v,
    },
    Value {
        name: "impact_spin_j_x",
        get: |c| c.impact_spin_j[0],
        set: |c, v| c.impact_spin_j[0] = v,
    },
    Value {
        name: "impact_spin_j_y",
        get: |c| c.impact_spin_j[1],
        set: |c, v| c.impact_spin_j[1] = v,
    },
    Value {
        name: "impact_spin_j_z",
        get: |c| c.impact_spin_j[2],
        set: |c, v| c.impact_spin_j[2] = v,
    },
    Value {
        name: "rebound_spin_j_x",
        get: |c| c.rebound_spin_j[0],
        set: |c, v| c.rebound_spin_j[0] = v,
    },
    Value {
        name: "rebound_spin_j_y",
        get: |c| c.rebound_spin_j[1],
        set: |c, v| c.rebound_spin_j[1] = v,
    },
    Value {
        name: "rebound_spin_j_z",
        get: |c| c.rebound_spin_j[2],
        set: |c, v| c.rebound_spin_j[2] = v,
    },
];

/// A byte string to write.
pub(super) struct Bytes(pub(super) Vec<u8>);

impl Serialize for Bytes {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_bytes(&self.0)
    }
}

/// A byte string read (a definite or chunked CBOR byte string).
pub(super) struct ByteColumn(pub(super) Vec<u8>);

impl<'de> Deserialize<'de> for ByteColumn {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct V;
        impl Visitor<'_> for V {
            type Value = ByteColumn;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str("a byte string")
            }
            fn visit_bytes<E: de::Error>(self, v: &[u8]) -> Result<ByteColumn, E> {
                Ok(ByteColumn(v.to_vec()))
            }
            fn visit_byte_buf<E: de::Error>(self, v: Vec<u8>) -> Result<ByteColumn, E> {
                Ok(ByteColumn(v))
            }
        }
        d.deserialize_byte_buf(V)
    }
}

/// An input index as the columns hold it (u32, as the engine's ids).
fn index<E: ser::Error>(v: usize, row: usize, what: &str) -> Result<[u8; 4], E> {
    u32::try_from(v).map(u32::to_le_bytes).map_err(|_| {
        E::custom(format!(
            "collision row {row}: {what} {v} does not fit the checkpoint's u32 indices"
        ))
    })
}

/// Writes `rows` as the columns (`#[serde(with)]`).
pub fn serialize<S: Serializer>(rows: &[Collision], s: S) -> Result<S::Ok, S::Error> {
    let n = rows.len();
    let mut kind = Vec::with_capacity(n);
    let mut i = Vec::with_capacity(4 * n);
    let mut j = Vec::with_capacity(4 * n);
    let mut boundary_body = Vec::new();
    let mut triangle = Vec::new();
    for (r, c) in rows.iter().enumerate() {
        let (k, partner) = match c.j {
            Partner::Body(b) => (0, b),
            Partner::Wall(w) => (1, w),
            Partner::BoundaryParticle { wall, body } => {
                boundary_body.extend(index::<S::Error>(body, r, "boundary particle")?);
                (2, wall)
            }
        };
        let t = match c.triangle {
            Some(t) => {
                triangle.extend(t.to_le_bytes());
                HAS_TRIANGLE
            }
            None => 0,
        };
        kind.push(k | t);
        i.extend(index::<S::Error>(c.i, r, "sphere")?);
        j.extend(index::<S::Error>(partner, r, "partner")?);
    }
    let stored: Vec<&Value> = VALUES
        .iter()
        .filter(|v| rows.iter().any(|c| (v.get)(c).to_bits() != 0))
        .collect();
    let fields = 4
        + stored.len()
        + usize::from(!boundary_body.is_empty())
        + usize::from(!triangle.is_empty());
    let mut m = s.serialize_struct("CollisionColumns", fields)?;
    m.serialize_field("rows", &(n as u64))?;
    m.serialize_field("kind", &Bytes(kind))?;
    m.serialize_field("i", &Bytes(i))?;
    m.serialize_field("j", &Bytes(j))?;
    if !boundary_body.is_empty() {
        m.serialize_field("boundary_body", &Bytes(boundary_body))?;
    }
    if !triangle.is_empty() {
        m.serialize_field("triangle", &Bytes(triangle))?;
    }
    // One column at a time: the largest buffer is 8 n bytes.
    for v in stored {
        let mut column = Vec::with_capacity(8 * n);
        for c in rows {
            column.extend((v.get)(c).to_le_bytes());
        }
        m.serialize_field(v.name, &Bytes(column))?;
    }
    m.end()
}

/// Reads the columns (format 3) or the list of rows (format 2).
pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<Vec<Collision>, D::Error> {
    d.deserialize_any(RowsOrColumns)
}

struct RowsOrColumns;

impl<'de> Visitor<'de> for RowsOrColumns {
    type Value = Vec<Collision>;

    fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
        f.write_str(
            "the completed collisions: a map of columns (checkpoint format 3) or a list of \
             rows (format 2)",
        )
    }

    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Self::Value, A::Error> {
        // A size hint from the file is not trusted for the allocation.
        let mut rows = Vec::with_capacity(seq.size_hint().unwrap_or(0).min(1 << 16));
        while let Some(c) = seq.next_element::<Collision>()? {
            rows.push(c);
        }
        Ok(rows)
    }

    fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<Self::Value, A::Error> {
        let mut c = Columns::default();
        while let Some(key) = map.next_key::<String>()? {
            let slot = match key.as_str() {
                "rows" => {
                    c.rows = Some(map.next_value::<u64>()?);
                    continue;
                }
                "kind" => &mut c.kind,
                "i" => &mut c.i,
                "j" => &mut c.j,
                "boundary_body" => &mut c.boundary_body,
                "triangle" => &mut c.triangle,
                name => match VALUES.iter().position(|v| v.name == name) {
                    Some(k) => &mut c.values[k],
                    None => {
                        return Err(de::Error::custom(format!(
                            "the collision columns hold an unknown column `{name}`"
                        )))
                    }
                },
            };
            if slot.is_some() {
                return Err(de::Error::custom(format!(
                    "the collision columns hold `{key}` twice"
                )));
            }
            *slot = Some(map.next_value::<ByteColumn>()?.0);
        }
        c.rows().map_err(de::Error::custom)
    }
}

/// The columns as read, before they are checked.
#[derive(Default)]
struct Columns {
    rows: Option<u64>,
    kind: Option<Vec<u8>>,
    i: Option<Vec<u8>>,
    j: Option<Vec<u8>>,
    boundary_body: Option<Vec<u8>>,
    triangle: Option<Vec<u8>>,
    values: [Option<Vec<u8>>; 21],
}

/// The u32 at `k` of a column of u32.
pub(super) fn u32_at(column: &[u8], k: usize) -> u32 {
    let mut b = [0; 4];
    b.copy_from_slice(&column[4 * k..4 * k + 4]);
    u32::from_le_bytes(b)
}

/// The f64 at `k` of a column of f64 (by bits).
pub(super) fn f64_at(column: &[u8], k: usize) -> f64 {
    let mut b = [0; 8];
    b.copy_from_slice(&column[8 * k..8 * k + 8]);
    f64::from_bits(u64::from_le_bytes(b))
}

impl Columns {
    /// The rows, after every column's length is checked against `rows`
    /// and every `kind` byte against the partners there are.
    fn rows(self) -> Result<Vec<Collision>, String> {
        let damaged =
            |why: String| format!("the checkpoint's collision columns are damaged: {why}");
        let rows = self
            .rows
            .ok_or_else(|| damaged("they do not say how many rows they hold".into()))?;
        let kind = self.kind.unwrap_or_default();
        let n = kind.len();
        if rows != n as u64 {
            return Err(damaged(format!(
                "`rows` is {rows}, `kind` holds {n} bytes (one a row)"
            )));
        }
        let mut boundary_rows = 0;
        let mut triangle_rows = 0;
        for (r, &k) in kind.iter().enumerate() {
            if k & PARTNER > 2 || k & !(PARTNER | HAS_TRIANGLE) != 0 {
                return Err(damaged(format!(
                    "row {r} has partner kind {k} (allowed 0 sphere, 1 wall, 2 boundary \
                     particle, each plus {HAS_TRIANGLE} with a triangle)"
                )));
            }
            boundary_rows += usize::from(k & PARTNER == 2);
            triangle_rows += usize::from(k & HAS_TRIANGLE != 0);
        }
        let sized = |name: &str, column: Option<Vec<u8>>, width: usize, count: usize| {
            let column = column.unwrap_or_default();
            // An absent or empty column of f64 values is +0.0 throughout.
            if column.is_empty() && width == 8 {
                return Ok(column);
            }
            if column.len() as u64 == width as u64 * count as u64 {
                Ok(column)
            } else {
                Err(damaged(format!(
                    "`{name}` holds {} bytes, {count} entries of {width} bytes need {}",
                    column.len(),
                    width as u64 * count as u64
                )))
            }
        };
        let i = sized("i", self.i, 4, n)?;
        let j = sized("j", self.j, 4, n)?;
        let boundary_body = sized("boundary_body", self.boundary_body, 4, boundary_rows)?;
        let triangle = sized("triangle", self.triangle, 4, triangle_rows)?;
        let mut values = Vec::with_capacity(VALUES.len());
        for (v, column) in VALUES.iter().zip(self.values) {
            values.push(sized(v.name, column, 8, n)?);
        }
        let (mut next_body, mut next_triangle) = (0, 0);
        let mut out = Vec::with_capacity(n);
        for (r, &k) in kind.iter().enumerate() {
            let partner = u32_at(&j, r) as usize;
            let j = match k & PARTNER {
                0 => Partner::Body(partner),
                1 => Partner::Wall(partner),
                _ => {
                    next_body += 1;
                    Partner::BoundaryParticle {
                        wall: partner,
                        body: u32_at(&boundary_body, next_body - 1) as usize,
                    }
                }
            };
            let triangle = (k & HAS_TRIANGLE != 0).then(|| {
                next_triangle += 1;
                u32_at(&triangle, next_triangle - 1)
            });
            let mut c = Collision {
                i: u32_at(&i, r) as usize,
                j,
                t_start: 0.0,
                t_end: 0.0,
                duration: 0.0,
                max_overlap: 0.0,
                max_normal_force: 0.0,
                impact_normal_velocity: 0.0,
                rebound_normal_velocity: 0.0,
                impact_tangential_velocity: 0.0,
                rebound_tangential_velocity: 0.0,
                impact_spin_i: [0.0; 3],
                rebound_spin_i: [0.0; 3],
                impact_spin_j: [0.0; 3],
                rebound_spin_j: [0.0; 3],
                triangle,
            };
            for (v, column) in VALUES.iter().zip(&values) {
                if !column.is_empty() {
                    (v.set)(&mut c, f64_at(column, r));
                }
            }
            out.push(c);
        }
        Ok(out)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A checkpoint's field as the file holds it.
    #[derive(Serialize, Deserialize)]
    struct Holder {
        #[serde(with = "super")]
        rows: Vec<Collision>,
    }

    fn encode(rows: &[Collision]) -> Vec<u8> {
        let mut bytes = Vec::new();
        ciborium::into_writer(
            &Holder {
                rows: rows.to_vec(),
            },
            &mut bytes,
        )
        .expect("encoded");
        bytes
    }

    fn decode(bytes: &[u8]) -> Result<Vec<Collision>, String> {
        ciborium::from_reader::<Holder, _>(bytes)
            .map(|h| h.rows)
            .map_err(|e| e.to_string())
    }

    /// Every field of a row by its bits, named field by field (not through
    /// [`VALUES`], so a column read into the wrong field shows).
    fn bits(c: &Collision) -> Vec<u64> {
        let partner = match c.j {
            Partner::Body(b) => [0, b as u64, 0],
            Partner::Wall(w) => [1, w as u64, 0],
            Partner::BoundaryParticle { wall, body } => [2, wall as u64, body as u64],
        };
        let mut v = vec![c.i as u64];
        v.extend(partner);
        v.push(c.triangle.map_or(u64::MAX, u64::from));
        v.extend(
            [
                c.t_start,
                c.t_end,
                c.duration,
                c.max_overlap,
                c.max_normal_force,
                c.impact_normal_velocity,
                c.rebound_normal_velocity,
                c.impact_tangential_velocity,
                c.rebound_tangential_velocity,
            ]
            .iter()
            .chain(&c.impact_spin_i)
            .chain(&c.rebound_spin_i)
            .chain(&c.impact_spin_j)
            .chain(&c.rebound_spin_j)
            .map(|x| x.to_bits()),
        );
        v
    }

    fn row(i: usize, j: Partner, triangle: Option<u32>, first: f64) -> Collision {
        // Distinct values field by field (first + k / 64, exact in binary).
        let x = |k: u32| first + f64::from(k) / 64.0;
        Collision {
            i,
            j,
            t_start: x(0),
            t_end: x(1),
            duration: x(2),
            max_overlap: x(3),
            max_normal_force: x(4),
            impact_normal_velocity: x(5),
            rebound_normal_velocity: x(6),
            impact_tangential_velocity: x(7),
            rebound_tangential_velocity: x(8),
            impact_spin_i: [x(9), x(10), x(11)],
            rebound_spin_i: [x(12), x(13), x(14)],
            impact_spin_j: [x(15), x(16), x(17)],
            rebound_spin_j: [x(18), x(19), x(20)],
            triangle,
        }
    }

    /// Every partner kind, with and without a triangle, the largest
    /// indices the columns hold, and special values in every column: NaN
    /// (two payloads, both signs), ±∞, −0.0, the smallest subnormal, a
    /// column whose only non-+0.0 value is −0.0, and one of +0.0 alone.
    fn every_kind() -> Vec<Collision> {
        let max = u32::MAX as usize;
        let mut rows = vec![
            row(0, Partner::Body(1), None, 1.0),
            row(7, Partner::Wall(3), None, 2.0),
            row(
                9,
                Partner::BoundaryParticle { wall: 2, body: 11 },
                None,
                3.0,
            ),
            row(4, Partner::Wall(0), Some(17), 4.0),
            row(
                max,
                Partner::BoundaryParticle {
                    wall: max,
                    body: max,
                },
                Some(u32::MAX),
                5.0,
            ),
            row(5, Partner::Body(max), None, 6.0),
        ];
        let special = [
            f64::NAN,
            -f64::NAN,
            f64::from_bits(0x7ff0_0000_0000_0001),
            f64::INFINITY,
            f64::NEG_INFINITY,
            -0.0,
            f64::from_bits(1),
        ];
        for (k, v) in VALUES.iter().enumerate() {
            for (r, c) in rows.iter_mut().enumerate() {
                (v.set)(c, special[(k + r) % special.len()]);
            }
        }
        for c in &mut rows {
            c.rebound_spin_j = [0.0; 3];
            c.impact_spin_j[2] = 0.0;
        }
        rows[3].impact_spin_j[2] = -0.0;
        rows
    }

    #[test]
    fn every_partner_and_special_value_comes_back_bit_for_bit() {
        for rows in [
            every_kind(),
            vec![row(3, Partner::Body(8), None, 0.5)],
            Vec::new(),
        ] {
            let back = decode(&encode(&rows)).expect("decoded");
            let expected: Vec<_> = rows.iter().map(bits).collect();
            let got: Vec<_> = back.iter().map(bits).collect();
            assert_eq!(got, expected);
        }
    }

    #[test]
    fn the_columns_are_fixed_width() {
        // 1,000 rows of a frictionless run (spins +0.0): one kind byte, i
        // and j (u32) and nine f64 a row = 81 bytes, plus the map's keys
        // and byte-string heads (≤ 30 bytes a column with its name).
        let rows: Vec<_> = (0..1000)
            .map(|k| {
                let mut c = row(k, Partner::Body(k + 1), None, 1.0);
                for s in [
                    &mut c.impact_spin_i,
                    &mut c.rebound_spin_i,
                    &mut c.impact_spin_j,
                    &mut c.rebound_spin_j,
                ] {
                    *s = [0.0; 3];
                }
                c
            })
            .collect();
        let n = encode(&rows).len();
        assert!((81 * 1000..=81 * 1000 + 13 * 30).contains(&n), "{n} bytes");
    }

    #[test]
    fn format_2_rows_are_read() {
        // Format 2 stored the rows with serde's derive of `Collision`.
        #[derive(Serialize)]
        struct Old {
            rows: Vec<Collision>,
        }
        let rows = every_kind();
        let mut bytes = Vec::new();
        ciborium::into_writer(&Old { rows: rows.clone() }, &mut bytes).expect("encoded");
        let back = decode(&bytes).expect("decoded");
        let expected: Vec<_> = rows.iter().map(bits).collect();
        let got: Vec<_> = back.iter().map(bits).collect();
        assert_eq!(got, expected);
    }

    #[test]
    fn a_cut_encoding_is_an_error_not_a_panic() {
        let bytes = encode(&every_kind());
        for cut in 0..bytes.len() {
            assert!(decode(&bytes[..cut]).is_err(), "cut at {cut}");
        }
    }

    /// The columns of `every_kind` as a CBOR value, changed by `edit`,
    /// then decoded.
    fn edited(edit: impl Fn(&mut Vec<(ciborium::Value, ciborium::Value)>)) -> String {
        use ciborium::Value;
        let bytes = encode(&every_kind());
        let mut v: Value = ciborium::from_reader(&bytes[..]).expect("a CBOR value");
        let Value::Map(holder) = &mut v else {
            panic!("a map")
        };
        let Value::Map(columns) = &mut holder[0].1 else {
            panic!("the columns' map")
        };
        edit(columns);
        let mut out = Vec::new();
        ciborium::into_writer(&v, &mut out).expect("encoded");
        decode(&out).expect_err("refused")
    }

    fn column<'a>(
        columns: &'a mut [(ciborium::Value, ciborium::Value)],
        name: &str,
    ) -> &'a mut Vec<u8> {
        let (_, v) = columns
            .iter_mut()
            .find(|(k, _)| k.as_text() == Some(name))
            .expect("the column");
        match v {
            ciborium::Value::Bytes(b) => b,
            _ => panic!("bytes"),
        }
    }

    #[test]
    fn a_damaged_column_is_named() {
        let e = edited(|c| column(c, "kind")[2] = 3);
        assert!(e.contains("row 2 has partner kind 3"), "{e}");
        let e = edited(|c| column(c, "kind")[1] = 8);
        assert!(e.contains("row 1 has partner kind 8"), "{e}");
        let e = edited(|c| {
            column(c, "j").pop();
        });
        assert!(
            e.contains("`j` holds 23 bytes, 6 entries of 4 bytes need 24"),
            "{e}"
        );
        let e = edited(|c| column(c, "boundary_body").truncate(4));
        assert!(e.contains("`boundary_body` holds 4 bytes"), "{e}");
        let e = edited(|c| column(c, "triangle").clear());
        assert!(e.contains("`triangle` holds 0 bytes"), "{e}");
        let e = edited(|c| column(c, "t_end").truncate(40));
        assert!(
            e.contains("`t_end` holds 40 bytes, 6 entries of 8 bytes need 48"),
            "{e}"
        );
        let e = edited(|c| column(c, "kind").push(0));
        assert!(e.contains("`rows` is 6, `kind` holds 7 bytes"), "{e}");
        let e = edited(|c| c.retain(|(k, _)| k.as_text() != Some("rows")));
        assert!(e.contains("how many rows"), "{e}");
        let e = edited(|c| c[1].0 = ciborium::Value::Text("spin".into()));
        assert!(e.contains("unknown column `spin`"), "{e}");
        let e = edited(|c| c[2].0 = ciborium::Value::Text("j".into()));
        assert!(e.contains("`j` twice"), "{e}");
    }
}
