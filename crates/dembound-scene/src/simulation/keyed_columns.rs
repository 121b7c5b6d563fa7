//! The checkpoint's records keyed by two input ids — `(a, b, record)`
//! triples: the collision log's pair and wall tracks — in columns: a CBOR
//! map of byte strings, each value little-endian and fixed-width, so
//! 10⁵ tracks are written as a few large byte strings rather than a map
//! with every field name a record (checkpoint format 4; the same scheme
//! as `collision_columns`).
//!
//! The map's entries:
//! - `rows`: the number of records, n;
//! - `a`, `b`: u32 a record;
//! - `flags`: a byte a record ([`Keyed::FLAGS`] says which bits mean
//!   something), absent when every record's is 0;
//! - one entry a value of [`Keyed::VALUE_NAMES`] (f64 a record, by bits:
//!   NaN, ±∞ and −0.0 kept), absent when every record's is +0.0.
//!
//! [`deserialize`] reads this map or the list of triples of formats 2
//! and 3 (serde's derive of the record), so older checkpoints restart.

use std::fmt;
use std::marker::PhantomData;

use serde::de::{self, DeserializeOwned, MapAccess, SeqAccess, Visitor};
use serde::ser::SerializeStruct;
use serde::{Deserializer, Serializer};

use super::collision_columns::{f64_at, u32_at, ByteColumn, Bytes};
use crate::dynamics::collisions::Track;

/// A record stored as flag bits and a fixed number of f64 values.
pub trait Keyed: Sized + DeserializeOwned {
    /// Its values' column names, in order.
    const VALUE_NAMES: &'static [&'static str];
    /// The flag bits a record may have.
    const FLAGS: u8;
    fn flags(&self) -> u8;
    /// Value `k` of [`Self::VALUE_NAMES`].
    fn value(&self, k: usize) -> f64;
    /// The record of `flags` and `values` (one a name, in order).
    fn from_parts(flags: u8, values: &[f64]) -> Self;
}

impl Keyed for Track {
    const VALUE_NAMES: &'static [&'static str] = &Track::VALUE_NAMES;
    const FLAGS: u8 = Track::KNOWN | Track::IN_CONTACT;
    fn flags(&self) -> u8 {
        Track::flags(self)
    }
    fn value(&self, k: usize) -> f64 {
        Track::value(self, k)
    }
    fn from_parts(flags: u8, values: &[f64]) -> Self {
        let mut v = [0.0; 24];
        v.copy_from_slice(values);
        Track::from_parts(flags, &v)
    }
}

/// Writes `records` as the columns (`#[serde(with)]`).
pub fn serialize<S: Serializer, T: Keyed>(
    records: &[(u32, u32, T)],
    s: S,
) -> Result<S::Ok, S::Error> {
    let n = records.len();
    let mut a = Vec::with_capacity(4 * n);
    let mut b = Vec::with_capacity(4 * n);
    let mut flags = Vec::with_capacity(n);
    for (x, y, r) in records {
        a.extend(x.to_le_bytes());
        b.extend(y.to_le_bytes());
        flags.push(r.flags());
    }
    let any_flag = flags.iter().any(|&f| f != 0);
    let stored: Vec<usize> = (0..T::VALUE_NAMES.len())
        .filter(|&k| records.iter().any(|r| r.2.value(k).to_bits() != 0))
        .collect();
    let fields = 3 + usize::from(any_flag) + stored.len();
    let mut m = s.serialize_struct("KeyedColumns", fields)?;
    m.serialize_field("rows", &(n as u64))?;
    m.serialize_field("a", &Bytes(a))?;
    m.serialize_field("b", &Bytes(b))?;
    if any_flag {
        m.serialize_field("flags", &Bytes(flags))?;
    }
    // One column at a time: the largest buffer is 8 n bytes.
    for k in stored {
        let mut column = Vec::with_capacity(8 * n);
        for r in records {
            column.extend(r.2.value(k).to_le_bytes());
        }
        m.serialize_field(T::VALUE_NAMES[k], &Bytes(column))?;
    }
    m.end()
}

/// Reads the columns (format 4) or the list of triples (formats 2, 3).
pub fn deserialize<'de, D: Deserializer<'de>, T: Keyed>(
    d: D,
) -> Result<Vec<(u32, u32, T)>, D::Error> {
    d.deserialize_any(TriplesOrColumns(PhantomData))
}

struct TriplesOrColumns<T>(PhantomData<T>);

impl<'de, T: Keyed> Visitor<'de> for TriplesOrColumns<T> {
    type Value = Vec<(u32, u32, T)>;

    fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
        f.write_str(
            "records keyed by two ids: a map of columns (checkpoint format 4) or a list of \
             triples (formats 2 and 3)",
        )
    }

    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Self::Value, A::Error> {
        // A size hint from the file is not trusted for the allocation.
        let mut out = Vec::with_capacity(seq.size_hint().unwrap_or(0).min(1 << 16));
        while let Some(t) = seq.next_element::<(u32, u32, T)>()? {
            out.push(t);
        }
        Ok(out)
    }

    fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<Self::Value, A::Error> {
        let mut rows = None;
        let (mut a, mut b, mut flags) = (None, None, None);
        let mut values: Vec<Option<Vec<u8>>> = vec![None; T::VALUE_NAMES.len()];
        while let Some(key) = map.next_key::<String>()? {
            let slot = match key.as_str() {
                "rows" => {
                    if rows.is_some() {
                        return Err(de::Error::custom("the keyed columns hold `rows` twice"));
                    }
                    rows = Some(map.next_value::<u64>()?);
                    continue;
                }
                "a" => &mut a,
                "b" => &mut b,
                "flags" => &mut flags,
                name => match T::VALUE_NAMES.iter().position(|v| *v == name) {
                    Some(k) => &mut values[k],
                    None => {
                        return Err(de::Error::custom(format!(
                            "the keyed columns hold an unknown column `{name}`"
                        )))
                    }
                },
            };
            if slot.is_some() {
                return Err(de::Error::custom(format!(
                    "the keyed columns hold `{key}` twice"
                )));
            }
            *slot = Some(map.next_value::<ByteColumn>()?.0);
        }
        records(rows, a, b, flags, values).map_err(de::Error::custom)
    }
}

/// The records, after every column's length is checked against `rows`
/// and every flag byte against [`Keyed::FLAGS`].
fn records<T: Keyed>(
    rows: Option<u64>,
    a: Option<Vec<u8>>,
    b: Option<Vec<u8>>,
    flags: Option<Vec<u8>>,
    values: Vec<Option<Vec<u8>>>,
) -> Result<Vec<(u32, u32, T)>, String> {
    let damaged = |why: String| format!("the checkpoint's keyed columns are damaged: {why}");
    let n = rows.ok_or_else(|| damaged("they do not say how many rows they hold".into()))?;
    let n = usize::try_from(n).map_err(|_| damaged(format!("`rows` is {n}")))?;
    // An absent column is all zero (flags) or +0.0 (values); a present
    // one holds `width` bytes a row.
    let sized = |name: &str, column: Option<Vec<u8>>, width: usize, optional: bool| match column {
        None if optional => Ok(Vec::new()),
        None => Err(damaged(format!("`{name}` is missing"))),
        Some(c) if c.len() as u64 == width as u64 * n as u64 => Ok(c),
        Some(c) => Err(damaged(format!(
            "`{name}` holds {} bytes, {n} rows of {width} bytes need {}",
            c.len(),
            width as u64 * n as u64
        ))),
    };
    let a = sized("a", a, 4, false)?;
    let b = sized("b", b, 4, false)?;
    let flags = sized("flags", flags, 1, true)?;
    if let Some((r, f)) = flags.iter().enumerate().find(|(_, &f)| f & !T::FLAGS != 0) {
        return Err(damaged(format!(
            "row {r} has flags {f:#04x} (allowed bits {:#04x})",
            T::FLAGS
        )));
    }
    let values = values
        .into_iter()
        .zip(T::VALUE_NAMES)
        .map(|(c, name)| sized(name, c, 8, true))
        .collect::<Result<Vec<_>, _>>()?;
    let mut row = vec![0.0; T::VALUE_NAMES.len()];
    let mut out = Vec::with_capacity(n);
    for r in 0..n {
        for (x, c) in row.iter_mut().zip(&values) {
            *x = if c.is_empty() { 0.0 } else { f64_at(c, r) };
        }
        let f = flags.get(r).copied().unwrap_or(0);
        out.push((u32_at(&a, r), u32_at(&b, r), T::from_parts(f, &row)));
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde::{Deserialize, Serialize};

    /// A checkpoint's field as the file holds it.
    #[derive(Serialize, Deserialize)]
    struct Holder {
        #[serde(with = "super")]
        tracks: Vec<(u32, u32, Track)>,
    }

    /// Every field of a track by its bits, named by hand through the
    /// serde derive's map (not through `value`), so a value read into the
    /// wrong field shows.
    fn bits(t: &Track) -> String {
        let v = ciborium::Value::serialized(t).expect("a CBOR value");
        let mut s = String::new();
        fn walk(v: &ciborium::Value, s: &mut String) {
            match v {
                ciborium::Value::Float(x) => s.push_str(&format!("{:016x} ", x.to_bits())),
                ciborium::Value::Bool(b) => s.push_str(&format!("{b} ")),
                ciborium::Value::Map(m) => m.iter().for_each(|(k, v)| {
                    s.push_str(&format!("{}=", k.as_text().unwrap_or("?")));
                    walk(v, s)
                }),
                ciborium::Value::Array(a) => a.iter().for_each(|v| walk(v, s)),
                other => s.push_str(&format!("{other:?} ")),
            }
        }
        walk(&v, &mut s);
        s
    }

    /// Tracks whose 24 values all differ (k + 1/64 r, exact in binary),
    /// each flag combination, and in one column special values: NaN with a
    /// payload, −∞, −0.0 and the smallest subnormal. A column of +0.0 alone
    /// is left out of the file and read back as +0.0.
    fn tracks() -> Vec<(u32, u32, Track)> {
        (0..4u32)
            .map(|r| {
                let mut v = [0.0; 24];
                for (k, x) in v.iter_mut().enumerate().skip(1) {
                    *x = k as f64 + f64::from(r) / 64.0;
                }
                v[23] = 0.0; // +0.0 in every record: a column left out
                v[5] = [
                    f64::from_bits(0x7ff8_0000_0000_0abc),
                    f64::NEG_INFINITY,
                    -0.0,
                    5e-324,
                ][r as usize];
                // v[0] (overlap) is +0.0 but for one record's −0.0.
                v[0] = if r == 2 { -0.0 } else { 0.0 };
                (r, u32::MAX - r, Track::from_parts(r as u8, &v))
            })
            .collect()
    }

    #[test]
    fn tracks_round_trip_bit_for_bit_through_the_columns() {
        let t = tracks();
        // Not vacuous: the flags reached the tracks (records 1 and 3
        // known, 2 and 3 in contact, by the derive's field names).
        let with = |flag: &str| {
            t.iter()
                .map(|(_, _, x)| bits(x).contains(&format!("{flag}=true")))
                .collect::<Vec<_>>()
        };
        assert_eq!(with("known"), [false, true, false, true]);
        assert_eq!(with("in_contact"), [false, false, true, true]);
        let mut bytes = Vec::new();
        ciborium::into_writer(&Holder { tracks: t.clone() }, &mut bytes).expect("encoded");
        let read: Holder = ciborium::from_reader(&bytes[..]).expect("decoded");
        assert_eq!(read.tracks.len(), t.len());
        for ((a, b, x), (c, d, y)) in t.iter().zip(&read.tracks) {
            assert_eq!((a, b), (c, d));
            assert_eq!(bits(x), bits(y));
        }
        // Columns: rows, a, b, flags and 23 values (the +0.0 one left out;
        // the overlap column kept for its one −0.0).
        let v: ciborium::Value = ciborium::from_reader(&bytes[..]).expect("a value");
        let ciborium::Value::Map(top) = v else {
            panic!("a map")
        };
        let ciborium::Value::Map(columns) = &top[0].1 else {
            panic!("columns")
        };
        let names: Vec<_> = columns.iter().filter_map(|(k, _)| k.as_text()).collect();
        assert_eq!(names.len(), 4 + 23, "{names:?}");
        assert!(names.contains(&"overlap") && !names.contains(&"impact_spin_j_z"));
    }

    /// The list of triples of formats 2 and 3 (serde's derive) is read.
    #[test]
    fn the_triples_of_earlier_formats_are_read() {
        #[derive(Serialize)]
        struct Old {
            tracks: Vec<(u32, u32, Track)>,
        }
        let t = tracks();
        let mut bytes = Vec::new();
        ciborium::into_writer(&Old { tracks: t.clone() }, &mut bytes).expect("encoded");
        let read: Holder = ciborium::from_reader(&bytes[..]).expect("decoded");
        for ((_, _, x), (_, _, y)) in t.iter().zip(&read.tracks) {
            assert_eq!(bits(x), bits(y));
        }
        assert_eq!(read.tracks.len(), t.len());
    }
}
