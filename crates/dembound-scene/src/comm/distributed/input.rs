//! Each rank makes or reads only its part of the scene's spheres (issue 31
//! item 5): no rank ever holds the list of all spheres.
//!
//! 1. Every group's input indices are cut into equal consecutive slices,
//!    one a rank. A lattice's rank makes the sites of its slice from their
//!    indices ([`Lattice::sites`]); a data file's rank parses the lines
//!    beginning in its byte range of the `Atoms` section
//!    ([`crate::sources::lammps_part`]) and sends each atom to the rank of
//!    its id's slice (ids 1..N as LAMMPS writes them: atom id k is input
//!    index k − 1, the place the whole file's id order gives it). Line
//!    numbers, the atom count, repeated ids and densities are checked as
//!    the whole file's reader does, with its messages.
//! 2. Whatever the whole scene decides from all its spheres (the time
//!    step, the cell size, the law table's classes, the largest radius)
//!    comes from a few *representatives*, shared by every rank: the first
//!    two spheres (by input index) of each class (radius, material, fixed)
//!    and the fastest free sphere. Every rule of those decisions depends on
//!    the classes, whether a class has two members, and the fastest speed
//!    only, so the representatives decide as all spheres would.
//! 3. The decomposition is cut over the spheres' extent (a reduction), and
//!    each rank sends every sphere of its slice to its owner; a rank's
//!    bodies are then its own spheres in input order, as the scatter of
//!    the whole list left them: the same bits from the first step.
//!
//! Not covered (read whole instead, [`crate::io::resolve::resolve_parts`]):
//! random, CSV and inline spheres, walls other than planes, inlets, moving
//! groups, removal, a data file whose ids are not 1..N or that has a
//! section after `Atoms`, and more than 256 classes.

use std::collections::BTreeMap;

use super::super::pack::{Reader, Writer};
use super::super::Transport;
use super::{
    largest_radius, refuse_unsupported, refuse_unsupported_world, Decomposition,
    DistributedSimulation, Simulation, PEER_REFUSED,
};
use crate::io::resolve::{atom_material, PartGroup, PartSource};
use crate::setup::{SceneSetup, SphereInit};
use crate::setup_checks::{Label, OverlapTally, Overlaps, Worst};
use crate::sources::lammps_part;
use crate::SceneError;

/// At most this many classes (radius, material, fixed) of spheres are
/// represented; beyond, the time-step rule takes each material's extreme
/// radii, which a few representatives cannot stand for.
const MAX_CLASSES: usize = 256;

/// One rank's slice of the input indices, or its spheres.
#[derive(Debug, Clone, Default)]
pub struct Part {
    /// The spheres, by increasing input index.
    pub spheres: Vec<SphereInit>,
    /// Their input indices.
    pub ids: Vec<u32>,
}

/// The first index of slice `s` of `n` indices cut into `parts` slices.
pub(crate) fn slice_start(n: usize, s: usize, parts: usize) -> usize {
    (n as u128 * s as u128 / parts as u128) as usize
}

/// The slice holding index `q` of `n`.
pub(crate) fn slice_of(q: usize, n: usize, parts: usize) -> usize {
    let mut s = ((q as u128 * parts as u128) / n.max(1) as u128) as usize;
    s = s.min(parts - 1);
    while s > 0 && slice_start(n, s, parts) > q {
        s -= 1;
    }
    while s + 1 < parts && slice_start(n, s + 1, parts) <= q {
        s += 1;
    }
    s
}

/// Every rank learns whether any failed: Ok everywhere, or every rank an
/// error (its own, or [`PEER_REFUSED`]).
pub(crate) fn agree<T: Transport, R>(t: &T, r: Result<R, SceneError>) -> Result<R, SceneError> {
    let failed = t.max(if r.is_err() { 1.0 } else { 0.0 });
    match r {
        Ok(_) if failed > 0.0 => Err(SceneError::input(PEER_REFUSED)),
        r => r,
    }
}

/// Whether any rank found the part-wise input not to cover the scene.
fn any<T: Transport>(t: &T, whole: bool) -> bool {
    t.max(if whole { 1.0 } else { 0.0 }) > 0.0
}

/// This rank's slice of every group (collective). `Ok(None)`: the scene
/// is to be read whole (every rank agrees).
pub fn read_slices<T: Transport>(
    setup: &SceneSetup,
    groups: &[PartGroup],
    t: &T,
) -> Result<Option<Part>, SceneError> {
    let (rank, size) = (t.rank(), t.size());
    let total = groups.last().map_or(0, |g| g.ids.end);
    if any(t, total >= u32::MAX as usize) {
        return Ok(None);
    }
    let mut part = Part::default();
    for g in groups {
        let n = g.ids.len();
        let slice = slice_start(n, rank, size)..slice_start(n, rank + 1, size);
        let sphere = |position, velocity, radius, material| SphereInit {
            position,
            velocity,
            radius,
            material,
            fixed: g.fixed,
            group: None,
        };
        match &g.source {
            PartSource::Lattice { lattice, velocity } => {
                for (q, s) in slice.clone().zip(lattice.sites(slice.clone())) {
                    part.spheres
                        .push(sphere(s.position, *velocity, s.radius, g.material));
                    part.ids.push((g.ids.start + q) as u32);
                }
            }
            PartSource::Data {
                path,
                key,
                by_type,
                header,
            } => {
                let Some(atoms) = read_atoms(path, header, n, t)? else {
                    return Ok(None);
                };
                let made: Result<Vec<_>, SceneError> = slice
                    .clone()
                    .zip(&atoms)
                    .map(|(q, a)| {
                        atom_material(a, by_type, g.material, g.fixed, &setup.materials, key, path)
                            .map(|m| (q, sphere(a.sphere.position, [0.0; 3], a.sphere.radius, m)))
                    })
                    .collect();
                drop(atoms);
                let made = agree(t, made)?;
                for (q, s) in made {
                    part.spheres.push(s);
                    part.ids.push((g.ids.start + q) as u32);
                }
            }
        }
    }
    Ok(Some(part))
}

/// The atoms of this rank's id slice of a data file of `n` atoms, by id
/// (collective); `Ok(None)`: read the file whole.
fn read_atoms<T: Transport>(
    path: &std::path::Path,
    header: &lammps_part::DataHeader,
    n: usize,
    t: &T,
) -> Result<Option<Vec<crate::sources::lammps_data::DataAtom>>, SceneError> {
    let (rank, size) = (t.rank(), t.size());
    let name = path.display().to_string();
    let range = agree(t, lammps_part::read_range(path, header, rank, size))?;
    let ends = t.all_gather(range.line_ends() as f64);
    let before: usize = ends[..rank].iter().map(|&e| e as usize).sum();
    let all_lines: usize = ends.iter().map(|&e| e as usize).sum();
    let parsed = agree(
        t,
        lammps_part::parse_range(&range, header.header_lines + 1 + before, &name),
    )?;
    drop(range);
    let whole = parsed
        .as_ref()
        .is_none_or(|atoms| atoms.iter().any(|(_, a)| a.id == 0 || a.id > n as u64));
    if any(t, whole) {
        return Ok(None);
    }
    let atoms = parsed.unwrap_or_default();
    let found = t.sum(&[atoms.len() as f64])[0] as usize;
    if found != n {
        let last_line = (header.header_lines + all_lines).max(1);
        return Err(SceneError::input(format!(
            "LAMMPS data file `{name}`, line {last_line}: the header announces {n} atoms, the \
             Atoms section has {found}"
        )));
    }
    // Each atom to the rank of its id's slice.
    let mut out: BTreeMap<usize, Writer> = BTreeMap::new();
    let mut mine = Vec::new();
    for (line, a) in atoms {
        let to = slice_of((a.id - 1) as usize, n, size);
        if to == rank {
            mine.push((line, a));
            continue;
        }
        let w = out.entry(to).or_insert_with(|| Writer(Vec::new()));
        w.u64(a.id);
        w.u64(line as u64);
        w.u32(a.atom_type);
        w.f64(a.density);
        w.vec3(a.sphere.position);
        w.f64(a.sphere.radius);
    }
    for bytes in send_all(t, out) {
        let mut r = Reader::new(&bytes);
        while !r.done() {
            let id = r.u64();
            let line = r.u64() as usize;
            let atom_type = r.u32();
            let density = r.f64();
            let position = r.vec3();
            let radius = r.f64();
            mine.push((
                line,
                crate::sources::lammps_data::DataAtom {
                    id,
                    atom_type,
                    density,
                    sphere: crate::sources::SourceSphere::at_rest(position, radius),
                },
            ));
        }
    }
    // A repeated id: the file's reader names the later line of the first
    // repetition in file order, the smallest such line over the ranks.
    mine.sort_by_key(|(line, a)| (a.id, *line));
    let repeated = mine
        .windows(2)
        .filter(|w| w[0].1.id == w[1].1.id)
        .map(|w| (w[1].0, w[1].1.id))
        .min();
    let first = -t.max(-repeated.map_or(f64::INFINITY, |(l, _)| l as f64));
    if first.is_finite() {
        return Err(match repeated {
            Some((line, id)) if line as f64 == first => SceneError::input(format!(
                "LAMMPS data file `{name}`, line {line}: atom id {id} appears twice"
            )),
            _ => SceneError::input(PEER_REFUSED),
        });
    }
    Ok(Some(mine.into_iter().map(|(_, a)| a).collect()))
}

/// Sends `out[rank]` to each rank and returns what the others sent here,
/// in rank order (collective).
pub(crate) fn send_all<T: Transport>(t: &T, out: BTreeMap<usize, Writer>) -> Vec<Vec<u8>> {
    let mut to = vec![false; t.size()];
    for r in out.keys() {
        to[*r] = true;
    }
    let from: Vec<usize> = t
        .who_sends(&to)
        .iter()
        .enumerate()
        .filter(|&(r, &s)| s && r != t.rank())
        .map(|(r, _)| r)
        .collect();
    let sends: Vec<(usize, Vec<u8>)> = out.into_iter().map(|(r, w)| (r, w.0)).collect();
    t.exchange(&sends, &from)
}

fn write_sphere(w: &mut Writer, id: u32, s: &SphereInit) {
    w.u32(id);
    w.vec3(s.position);
    w.vec3(s.velocity);
    w.f64(s.radius);
    w.u32(s.material as u32);
    w.u8(u8::from(s.fixed));
}

fn read_sphere(r: &mut Reader) -> (u32, SphereInit) {
    let id = r.u32();
    let position = r.vec3();
    let velocity = r.vec3();
    let radius = r.f64();
    let material = r.u32() as usize;
    let fixed = r.u8() == 1;
    (
        id,
        SphereInit {
            position,
            velocity,
            radius,
            material,
            fixed,
            group: None,
        },
    )
}

/// The representatives of every rank's spheres (collective), by input
/// index; `None` over [`MAX_CLASSES`] classes.
pub fn representatives<T: Transport>(part: &Part, t: &T) -> Option<Vec<SphereInit>> {
    type Key = (u64, usize, bool);
    let key = |s: &SphereInit| (s.radius.to_bits(), s.material, s.fixed);
    let speed = |s: &SphereInit| s.velocity.iter().map(|v| v * v).sum::<f64>();
    // This rank's candidates: the first two of each class, the fastest.
    let mut firsts: BTreeMap<Key, Vec<usize>> = BTreeMap::new();
    let mut fastest: Option<usize> = None;
    for (q, s) in part.spheres.iter().enumerate() {
        let seen = firsts.entry(key(s)).or_default();
        if seen.len() < 2 {
            seen.push(q);
        }
        if !s.fixed && fastest.is_none_or(|f| speed(s) > speed(&part.spheres[f])) {
            fastest = Some(q);
        }
        if firsts.len() > MAX_CLASSES {
            break;
        }
    }
    let mut own: Vec<usize> = firsts.values().flatten().copied().chain(fastest).collect();
    own.sort_unstable();
    own.dedup();
    let mut w = Writer(Vec::new());
    w.u8(u8::from(firsts.len() > MAX_CLASSES));
    for &q in &own {
        write_sphere(&mut w, part.ids[q], &part.spheres[q]);
    }
    let mine = w.0;
    let out: BTreeMap<usize, Writer> = (0..t.size())
        .filter(|&r| r != t.rank())
        .map(|r| (r, Writer(mine.clone())))
        .collect();
    let mut all = send_all(t, out);
    all.push(mine);
    let mut candidates: Vec<(u32, SphereInit)> = Vec::new();
    let mut over = false;
    for bytes in &all {
        let mut r = Reader::new(bytes);
        over |= r.u8() == 1;
        while !r.done() {
            candidates.push(read_sphere(&mut r));
        }
    }
    // The same list on every rank: by input index.
    candidates.sort_by_key(|(id, _)| *id);
    let mut count: BTreeMap<Key, usize> = BTreeMap::new();
    let mut keep = vec![false; candidates.len()];
    let mut top: Option<usize> = None;
    for (k, (_, s)) in candidates.iter().enumerate() {
        let c = count.entry(key(s)).or_default();
        if *c < 2 {
            keep[k] = true;
        }
        *c += 1;
        if !s.fixed && top.is_none_or(|f| speed(s) > speed(&candidates[f].1)) {
            top = Some(k);
        }
    }
    if let Some(k) = top {
        keep[k] = true;
    }
    if over || count.len() > MAX_CLASSES {
        return None;
    }
    Some(
        candidates
            .into_iter()
            .zip(keep)
            .filter(|(_, k)| *k)
            .map(|((_, s), _)| s)
            .collect(),
    )
}

/// Sends each sphere of `part` to the rank owning its (wrapped) centre
/// and returns this rank's own, by input index (collective).
pub(crate) fn to_owners<T: Transport>(
    part: Part,
    owner: impl Fn([f64; 3]) -> usize,
    wrap: impl Fn([f64; 3]) -> [f64; 3],
    t: &T,
) -> Part {
    let rank = t.rank();
    let mut out: BTreeMap<usize, Writer> = BTreeMap::new();
    let mut own: Vec<(u32, SphereInit)> = Vec::new();
    for (id, mut s) in part.ids.into_iter().zip(part.spheres) {
        s.position = wrap(s.position);
        let r = owner(s.position);
        if r == rank {
            own.push((id, s));
        } else {
            write_sphere(out.entry(r).or_insert_with(|| Writer(Vec::new())), id, &s);
        }
    }
    for bytes in send_all(t, out) {
        let mut r = Reader::new(&bytes);
        while !r.done() {
            own.push(read_sphere(&mut r));
        }
    }
    own.sort_by_key(|(id, _)| *id);
    let (ids, spheres) = own.into_iter().unzip();
    Part { spheres, ids }
}

/// The other ranks' spheres that come within (own radius + `largest`)
/// of this rank's sub-domain: the first halo the run builds
/// (`Decomposition::ranks_within`, as `migrate_and_rebuild`), by input
/// index (collective). Every pair of spheres that touch, one of them
/// this rank's, has both here.
fn ghosts<T: Transport>(part: &Part, d: &Decomposition, largest: f64, t: &T) -> Part {
    let mut out: BTreeMap<usize, Writer> = BTreeMap::new();
    for (&id, s) in part.ids.iter().zip(&part.spheres) {
        for r in d.ranks_within(s.position, s.radius + largest) {
            write_sphere(out.entry(r).or_insert_with(|| Writer(Vec::new())), id, s);
        }
    }
    let mut got: Vec<(u32, SphereInit)> = Vec::new();
    for bytes in send_all(t, out) {
        let mut r = Reader::new(&bytes);
        while !r.done() {
            got.push(read_sphere(&mut r));
        }
    }
    got.sort_by_key(|(id, _)| *id);
    let (ids, spheres) = got.into_iter().unzip();
    Part { spheres, ids }
}

/// `setup` with this rank's spheres and its ghosts, by input index (so a
/// pair is named in the order one process names it), their input indices
/// and whether each is this rank's own.
fn with_ghosts(setup: &SceneSetup, part: &Part, ghosts: Part) -> (SceneSetup, Vec<u32>, Vec<bool>) {
    let mut all: Vec<(u32, bool, SphereInit)> = part
        .ids
        .iter()
        .zip(part.spheres.iter())
        .map(|(&id, s)| (id, true, *s))
        .chain(
            ghosts
                .ids
                .into_iter()
                .zip(ghosts.spheres)
                .map(|(id, s)| (id, false, s)),
        )
        .collect();
    all.sort_by_key(|(id, _, _)| *id);
    let mut ids = Vec::with_capacity(all.len());
    let mut own = Vec::with_capacity(all.len());
    let mut local = setup.clone();
    local.spheres = crate::spheres::Spheres::new();
    local.spheres.reserve(all.len());
    for (id, mine, s) in all {
        ids.push(id);
        own.push(mine);
        local.spheres.push(s);
    }
    (local, ids, own)
}

fn write_tally(w: &mut Writer, t: &OverlapTally) {
    w.u64(t.count);
    match t.worst {
        None => w.u8(0),
        Some(x) => {
            w.u8(1);
            w.f64(x.share);
            w.u64(x.first as u64);
            w.u64(x.second as u64);
            w.f64(x.overlap);
        }
    }
}

fn read_tally(r: &mut Reader) -> OverlapTally {
    let count = r.u64();
    let worst = (r.u8() == 1).then(|| Worst {
        share: r.f64(),
        first: r.u64() as usize,
        second: r.u64() as usize,
        overlap: r.f64(),
    });
    OverlapTally { count, worst }
}

/// Every rank's overlap tallies (its spheres' indices local, `ids` their
/// input indices) added up at rank 0 (collective): the warning lines one
/// process prints, at rank 0; empty elsewhere. Each overlap was counted
/// by one rank ([`crate::setup_checks::Reports`]); the largest of equal
/// shares is the one of the smallest indices, as one process picks it.
fn gather_warnings<T: Transport>(
    mut overlaps: Overlaps<'_>,
    ids: &[u32],
    label: Label<'_>,
    t: &T,
) -> Vec<String> {
    let to_input = |tally: &mut OverlapTally, pair: bool| {
        if let Some(w) = &mut tally.worst {
            if pair {
                w.first = ids[w.first] as usize;
            }
            w.second = ids[w.second] as usize;
        }
    };
    for (_, tally) in &mut overlaps.walls {
        to_input(tally, false);
    }
    to_input(&mut overlaps.pairs, true);
    let mut out: BTreeMap<usize, Writer> = BTreeMap::new();
    if t.rank() != 0 {
        let mut w = Writer(Vec::new());
        for (_, tally) in &overlaps.walls {
            write_tally(&mut w, tally);
        }
        write_tally(&mut w, &overlaps.pairs);
        out.insert(0, w);
    }
    let got = send_all(t, out);
    if t.rank() != 0 {
        return Vec::new();
    }
    // Every rank ran the same wall types' checks: the same list.
    for bytes in got {
        let mut r = Reader::new(&bytes);
        for (_, tally) in &mut overlaps.walls {
            tally.merge(&read_tally(&mut r));
        }
        overlaps.pairs.merge(&read_tally(&mut r));
    }
    overlaps.lines(label)
}

impl<T: Transport> DistributedSimulation<T> {
    /// [`DistributedSimulation::new`] with each rank making or reading only
    /// its part of the spheres of `groups` ([`crate::io::resolve::resolve_parts`];
    /// `setup.spheres` empty). `label` names a sphere by its input index in
    /// the setup checks' messages (`io::labels::label`, as one process
    /// names it). Returns with the simulation the overlap warnings one
    /// process prints (`setup_checks`), at rank 0 (empty elsewhere).
    /// `Ok(None)`: the scene is to be read whole (every rank agrees).
    /// Collective.
    pub fn new_parts(
        setup: &SceneSetup,
        groups: &[PartGroup],
        label: Label<'_>,
        threads: usize,
        grid: Option<[usize; 3]>,
        transport: T,
    ) -> Result<Option<(Self, Vec<String>)>, SceneError> {
        let t = &transport;
        let Some(part) = read_slices(setup, groups, t)? else {
            return Ok(None);
        };
        let Some(representatives) = representatives(&part, t) else {
            return Ok(None);
        };
        // The same scene of representatives on every rank: the same
        // decisions, or the same refusal.
        let mut proxy = setup.clone();
        proxy.spheres = representatives.into();
        let checked = refuse_unsupported(&proxy)
            .and_then(|()| Simulation::prepare(&proxy, threads))
            .and_then(|sim| refuse_unsupported_world(&sim.world).map(|()| sim));
        let mut sim = agree(t, checked)?;
        let domain = sim.world.domain;
        // The spheres' extent and the box grown to hold the fixed ones
        // (`Simulation::outside_box`): reductions.
        let mut lo = [f64::INFINITY; 3];
        let mut hi = [f64::NEG_INFINITY; 3];
        let (mut flo, mut fhi) = (setup.domain.lower, setup.domain.upper);
        for s in &part.spheres {
            let x = domain.wrap(s.position);
            for a in 0..3 {
                lo[a] = lo[a].min(x[a]);
                hi[a] = hi[a].max(x[a]);
                if s.fixed {
                    flo[a] = flo[a].min(s.position[a] - s.radius);
                    fhi[a] = fhi[a].max(s.position[a] + s.radius);
                }
            }
        }
        for a in 0..3 {
            lo[a] = -t.max(-lo[a]);
            hi[a] = t.max(hi[a]);
            flo[a] = -t.max(-flo[a]);
            fhi[a] = t.max(fhi[a]);
        }
        if setup.outside == crate::setup::Outside::Error {
            sim.outside_box = Some((flo, fhi));
        }
        let d = agree(
            t,
            Decomposition::new(domain, t.size(), grid, sim.world.cell_size, Some((lo, hi))),
        )?;
        let part = to_owners(part, |x| d.owner(x), |x| domain.wrap(x), t);
        let largest_radius = largest_radius(&sim.world, setup);
        // This rank's spheres checked as the whole scene's are, with the
        // other ranks' spheres that may touch them (an overlap across a
        // sub-domain face is found on both sides).
        // Its warnings: the overlaps of its own spheres (a pair's: of the
        // lower input index), added up at rank 0.
        let ghosts = ghosts(&part, &d, largest_radius, t);
        let ids = &part.ids;
        let (local, local_ids, own) = with_ghosts(&proxy, &part, ghosts);
        let reports = |k: usize| own[k];
        let checked =
            crate::simulation::build::check_spheres(&proxy, part.spheres.iter().copied(), |q| {
                ids[q] as usize
            })
            .and_then(|()| {
                crate::setup_checks::check_overlaps(
                    &local,
                    &|k| label(local_ids[k] as usize),
                    &reports,
                )
            });
        let overlaps = agree(t, checked)?;
        drop(local);
        let warnings = gather_warnings(overlaps, &local_ids, label, t);
        let w = &mut sim.world;
        let mut b = crate::simulation::build::bodies_of(
            &proxy,
            part.spheres.iter().copied(),
            part.spheres.len(),
            |q| ids[q],
        );
        drop(part.spheres);
        // The classes of the representatives' law table, which holds every
        // class of the scene.
        b.class = match w.laws.class_keys() {
            Some(keys) => (0..b.len())
                .map(|k| {
                    let key = crate::dynamics::contacts::class_key(&b, k);
                    keys.iter()
                        .position(|&q| q == key)
                        .map_or(crate::dynamics::contacts::NO_CLASS, |c| c as u16)
                })
                .collect(),
            None => vec![crate::dynamics::contacts::NO_CLASS; b.len()],
        };
        w.wall_contacts = crate::walls::WallContacts::new(
            b.len(),
            w.laws.history,
            w.friction.is_some(),
            setup.collisions,
        );
        w.bodies = b;
        // The checkpoint's per-body lists are gathered when written.
        sim.fingerprint.radius.clear();
        sim.fingerprint.material.clear();
        sim.fingerprint.fixed.clear();
        let total = groups.last().map_or(0, |g| g.ids.end);
        let mut fixed_by_id = vec![false; total];
        for g in groups.iter().filter(|g| g.fixed) {
            fixed_by_id[g.ids.clone()].fill(true);
        }
        Ok(Some((
            Self::start(sim, d, largest_radius, fixed_by_id, transport),
            warnings,
        )))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn slices_cover_each_index_once() {
        for n in [0usize, 1, 5, 7, 100, 1001] {
            for parts in 1..=9 {
                let mut next = 0;
                for s in 0..parts {
                    let (a, b) = (slice_start(n, s, parts), slice_start(n, s + 1, parts));
                    assert_eq!(a, next);
                    for q in a..b {
                        assert_eq!(slice_of(q, n, parts), s, "n {n}, {parts} parts, q {q}");
                    }
                    next = b;
                }
                assert_eq!(next, n);
            }
        }
    }
}
