//! The byte layout of what crosses ranks: little-endian, fixed-size
//! fields. A body record is every per-body array of the engine
//! ([`Bodies`] and its plane-wall state), so that a body continues on its
//! new rank bit for bit.

use dembound_physics::contact::ContactHistory;

use crate::bodies::Bodies;
use crate::dynamics::friction::WallShear;
use crate::walls::near::NearEntry;
use crate::walls::{WallContacts, WallElement};

/// Appends fixed-size little-endian fields.
#[derive(Debug, Default)]
pub struct Writer(pub Vec<u8>);

impl Writer {
    pub fn u8(&mut self, v: u8) {
        self.0.push(v);
    }
    pub fn u16(&mut self, v: u16) {
        self.0.extend_from_slice(&v.to_le_bytes());
    }
    pub fn u32(&mut self, v: u32) {
        self.0.extend_from_slice(&v.to_le_bytes());
    }
    pub fn u64(&mut self, v: u64) {
        self.0.extend_from_slice(&v.to_le_bytes());
    }
    pub fn f64(&mut self, v: f64) {
        self.0.extend_from_slice(&v.to_le_bytes());
    }
    pub fn vec3(&mut self, v: [f64; 3]) {
        let mut at = [0u8; 24];
        put_vec3(&mut at, v);
        self.0.extend_from_slice(&at);
    }
    pub fn history(&mut self, h: &ContactHistory) {
        self.f64(h.max_overlap);
        self.u8(u8::from(h.unloading));
    }
    /// A length-prefixed byte string.
    pub fn blob(&mut self, b: &[u8]) {
        self.u32(b.len() as u32);
        self.0.extend_from_slice(b);
    }
}

/// `v` into the first 24 bytes of `out` (three little-endian f64s): the
/// layout of every vector on the wire, written in place where a record
/// has a fixed size (the per-step halo records).
#[inline]
pub fn put_vec3(out: &mut [u8], v: [f64; 3]) {
    let out = &mut out[..24];
    out[..8].copy_from_slice(&v[0].to_le_bytes());
    out[8..16].copy_from_slice(&v[1].to_le_bytes());
    out[16..].copy_from_slice(&v[2].to_le_bytes());
}

/// The vector [`put_vec3`] wrote into the first 24 bytes of `at`.
#[inline]
pub fn get_vec3(at: &[u8]) -> [f64; 3] {
    let at = &at[..24];
    let f = |b: &[u8]| {
        let mut bytes = [0u8; 8];
        bytes.copy_from_slice(b);
        f64::from_le_bytes(bytes)
    };
    [f(&at[..8]), f(&at[8..16]), f(&at[16..])]
}

/// A value as CBOR (every f64 bit kept): for the rarer, structured
/// records (collision tracks, the collision log).
pub fn encode<T: serde::Serialize>(v: &T) -> Vec<u8> {
    let mut out = Vec::new();
    // Writing into a Vec cannot fail for these plain records.
    let _ = ciborium::into_writer(v, &mut out);
    out
}

/// What [`encode`] wrote (`None`: not such a value, a bug).
pub fn decode<T: serde::de::DeserializeOwned>(b: &[u8]) -> Option<T> {
    ciborium::from_reader(b).ok()
}

/// Reads what a [`Writer`] wrote. Messages come from ranks of the same
/// program, so a short message is a bug: reads past the end give zeros.
#[derive(Debug)]
pub struct Reader<'a> {
    bytes: &'a [u8],
    at: usize,
}

impl<'a> Reader<'a> {
    pub fn new(bytes: &'a [u8]) -> Self {
        Self { bytes, at: 0 }
    }
    pub fn done(&self) -> bool {
        self.at >= self.bytes.len()
    }
    fn take<const N: usize>(&mut self) -> [u8; N] {
        let mut out = [0u8; N];
        if let Some(s) = self.bytes.get(self.at..self.at + N) {
            out.copy_from_slice(s);
        }
        self.at += N;
        out
    }
    pub fn u8(&mut self) -> u8 {
        self.take::<1>()[0]
    }
    pub fn u16(&mut self) -> u16 {
        u16::from_le_bytes(self.take())
    }
    pub fn u32(&mut self) -> u32 {
        u32::from_le_bytes(self.take())
    }
    pub fn u64(&mut self) -> u64 {
        u64::from_le_bytes(self.take())
    }
    pub fn f64(&mut self) -> f64 {
        f64::from_le_bytes(self.take())
    }
    pub fn vec3(&mut self) -> [f64; 3] {
        get_vec3(&self.take::<24>())
    }
    pub fn history(&mut self) -> ContactHistory {
        ContactHistory {
            max_overlap: self.f64(),
            unloading: self.u8() != 0,
        }
    }
    /// What [`Writer::blob`] wrote.
    pub fn blob(&mut self) -> &'a [u8] {
        let n = self.u32() as usize;
        let s = self.bytes.get(self.at..self.at + n).unwrap_or(&[]);
        self.at += n;
        s
    }
}

/// Writes body k: every array of [`Bodies`] (Gear5's `higher` and
/// `angular_higher` excepted: [`write_higher`] and
/// [`write_angular_higher`] send them when they migrate) and its
/// near wall elements with their contact state (`walls`: `None` for a
/// halo copy, which touches no wall here: none are sent).
pub fn write_body(w: &mut Writer, b: &Bodies, walls: Option<&WallContacts>, k: usize) {
    // Destructured so that a new per-body array fails to compile here.
    let Bodies {
        position,
        velocity,
        force,
        radius,
        mass,
        inverse_mass,
        material,
        fixed,
        id,
        group,
        class,
        higher: _,
        angular_velocity,
        torque,
        inverse_inertia,
        angular_higher: _,
    } = b;
    w.u32(id[k]);
    w.vec3(position[k]);
    w.vec3(velocity[k]);
    w.vec3(force[k]);
    w.f64(radius[k]);
    w.f64(mass[k]);
    w.f64(inverse_mass[k]);
    w.u32(material[k]);
    w.u8(u8::from(fixed[k]));
    w.u32(group[k]);
    w.u16(class[k]);
    w.vec3(angular_velocity[k]);
    w.vec3(torque[k]);
    w.f64(inverse_inertia[k]);
    let Some(walls) = walls.filter(|c| k < c.bodies()) else {
        w.u64(0);
        return;
    };
    // A u64: a body with no entries takes the 8 bytes the old bit mask did.
    w.u64(walls.range(k).len() as u64);
    for e in walls.entries(k) {
        w.u32(e.key.wall);
        w.u32(e.key.element);
        w.u8(u8::from(e.touching));
        if walls.keep_history {
            w.history(&e.history);
        }
        if walls.keep_shear {
            write_wall_shear(w, std::slice::from_ref(&e.shear), 1, 0);
        }
        if walls.keep_track {
            w.blob(&encode(&e.track));
        }
    }
}

/// Appends a body written by [`write_body`]; returns its id.
pub fn read_body(r: &mut Reader, b: &mut Bodies, walls: &mut WallContacts) -> u32 {
    let id = r.u32();
    b.id.push(id);
    b.position.push(r.vec3());
    b.velocity.push(r.vec3());
    b.force.push(r.vec3());
    b.radius.push(r.f64());
    b.mass.push(r.f64());
    b.inverse_mass.push(r.f64());
    b.material.push(r.u32());
    b.fixed.push(r.u8() != 0);
    b.group.push(r.u32());
    b.class.push(r.u16());
    b.angular_velocity.push(r.vec3());
    b.torque.push(r.vec3());
    b.inverse_inertia.push(r.f64());
    let count = r.u64();
    let mut entries = Vec::with_capacity(count.min(1 << 16) as usize);
    for _ in 0..count {
        let mut e = NearEntry {
            key: WallElement {
                wall: r.u32(),
                element: r.u32(),
            },
            touching: r.u8() != 0,
            ..NearEntry::default()
        };
        if walls.keep_history {
            e.history = r.history();
        }
        if walls.keep_shear {
            let mut s = Vec::with_capacity(1);
            read_wall_shear(r, &mut s, 1);
            e.shear = s.first().copied().unwrap_or_default();
        }
        if walls.keep_track {
            e.track = decode(r.blob()).unwrap_or_default();
        }
        entries.push(e);
    }
    walls.push_body(&entries);
    id
}

/// Writes a friction run's per-plane springs of body k (`planes` of
/// them, `shear[k * planes..]`; relaxed if the array is not sized yet).
pub fn write_wall_shear(w: &mut Writer, shear: &[WallShear], planes: usize, k: usize) {
    for q in 0..planes {
        let s = shear.get(k * planes + q).copied().unwrap_or_default();
        for x in s.shear.iter().chain(&s.before) {
            w.f64(*x);
        }
        w.u64(s.stamp);
    }
}

/// Appends what [`write_wall_shear`] wrote.
pub fn read_wall_shear(r: &mut Reader, shear: &mut Vec<WallShear>, planes: usize) {
    for _ in 0..planes {
        let mut s = WallShear::default();
        for x in s.shear.iter_mut().chain(s.before.iter_mut()) {
            *x = r.f64();
        }
        s.stamp = r.u64();
        shear.push(s);
    }
}

/// Writes a Gear5 run's scaled derivatives r₂..r₅ of body k (zeros if
/// the array is not sized).
pub fn write_higher(w: &mut Writer, higher: &[[[f64; 3]; 4]], k: usize) {
    for r in higher.get(k).copied().unwrap_or_default() {
        w.vec3(r);
    }
}

/// Appends what [`write_higher`] wrote.
pub fn read_higher(r: &mut Reader, higher: &mut Vec<[[f64; 3]; 4]>) {
    higher.push([r.vec3(), r.vec3(), r.vec3(), r.vec3()]);
}

/// Writes a Gear5 run's spin derivatives r₁..r₄ of body k (friction;
/// zeros if the array is not sized).
pub fn write_angular_higher(w: &mut Writer, higher: &[[[f64; 3]; 4]], k: usize) {
    write_higher(w, higher, k);
}

/// Appends what [`write_angular_higher`] wrote.
pub fn read_angular_higher(r: &mut Reader, higher: &mut Vec<[[f64; 3]; 4]>) {
    read_higher(r, higher);
}

/// Bytes of one body record with `entries` near wall entries (without
/// springs or tracks).
pub fn body_bytes(entries: usize, wall_history: bool) -> usize {
    4 + 9 * 8
        + 3 * 8
        + 4
        + 1
        + 4
        + 2
        + 6 * 8
        + 8
        + 8
        + entries * (9 + if wall_history { 9 } else { 0 })
}

#[cfg(test)]
mod tests {
    use super::{get_vec3, put_vec3, Reader, Writer};

    /// A vector on the wire is its three f64s' little-endian bytes (as
    /// `f64::to_le_bytes` gives them, joined here), written the same in
    /// place and by the writer, and read back to the same bits by both
    /// readers: signed zeros, subnormals, infinities and a NaN's payload
    /// included (the halo records must not change a bit).
    #[test]
    fn vectors_are_three_little_endian_f64s_read_back_bit_for_bit() {
        let values = [
            [1.25e-3, -0.0, f64::MIN_POSITIVE / 3.0],
            [
                f64::INFINITY,
                f64::from_bits(0x7ff8_dead_beef_0001),
                -7.5e300,
            ],
        ];
        for v in values {
            let expected: Vec<u8> = v.iter().flat_map(|x| x.to_le_bytes()).collect();
            let mut at = [0u8; 24];
            put_vec3(&mut at, v);
            assert_eq!(&at[..], &expected[..]);
            let mut w = Writer(Vec::new());
            w.vec3(v);
            assert_eq!(w.0, expected);
            let bits = v.map(f64::to_bits);
            assert_eq!(get_vec3(&at).map(f64::to_bits), bits);
            assert_eq!(Reader::new(&w.0).vec3().map(f64::to_bits), bits);
        }
    }
}
