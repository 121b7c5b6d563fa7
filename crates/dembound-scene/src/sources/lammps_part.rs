//! One rank's part of a LAMMPS data file ([`super::lammps_data`]'s
//! format): the header read by every rank (it is short), then the `Atoms`
//! section split into equal byte ranges, each rank parsing the lines that
//! begin in its own range. A line belongs to the range holding its first
//! byte, so every line is read by exactly one rank.
//!
//! Line numbers for messages: each rank counts the line ends in its range,
//! the counts are shared ([`RangeText::line_ends`]) and each rank numbers
//! its lines from the sum of those before it.

use std::io::{BufRead, BufReader, Read, Seek, SeekFrom};
use std::path::Path;

use super::lammps_data::{header_line, parse_atom, DataAtom, Section};
use crate::SceneError;

/// What the header of a data file says, and where its `Atoms` lines start.
#[derive(Debug, Clone, PartialEq)]
pub struct DataHeader {
    /// `N atoms`.
    pub atoms: usize,
    /// `[lo, hi]` along x, y, z, m.
    pub bounds: [[f64; 2]; 3],
    /// The byte after the `Atoms` line.
    pub atoms_start: u64,
    /// The file's length, bytes.
    pub len: u64,
    /// Lines up to and including the `Atoms` line.
    pub header_lines: usize,
    /// A `Velocities` section came before `Atoms` (read whole instead).
    pub velocities_first: bool,
}

fn err(name: &str, line: usize, msg: impl std::fmt::Display) -> SceneError {
    SceneError::input(format!("LAMMPS data file `{name}`, line {line}: {msg}"))
}

/// Reads the header of `path` (the scene key `key`) up to its `Atoms` line.
pub fn read_header(path: &Path, key: &str) -> Result<DataHeader, SceneError> {
    let name = path.display().to_string();
    let shown = || format!("`{key}` = `{name}`");
    let meta = std::fs::metadata(path)
        .map_err(|e| SceneError::input(format!("{}: cannot read the file: {e}", shown())))?;
    if !meta.is_file() {
        return Err(SceneError::input(format!(
            "{}: not a regular file (a data file read in parts under MPI)",
            shown()
        )));
    }
    let len = meta.len();
    if len > super::MAX_DATA_FILE_BYTES {
        return Err(SceneError::input(format!(
            "{}: the file has {len} bytes; at most {} bytes ({} GiB) are read",
            shown(),
            super::MAX_DATA_FILE_BYTES,
            super::MAX_DATA_FILE_BYTES >> 30
        )));
    }
    let file = std::fs::File::open(path)
        .map_err(|e| SceneError::input(format!("{}: cannot read the file: {e}", shown())))?;
    let mut reader = BufReader::new(file);
    let mut n_atoms = None;
    let mut bounds: [Option<[f64; 2]>; 3] = [None; 3];
    let mut section = Section::Header;
    let mut velocities_first = false;
    let mut offset = 0u64;
    let mut raw = Vec::new();
    let mut line_no = 0usize;
    loop {
        raw.clear();
        let got = reader
            .read_until(b'\n', &mut raw)
            .map_err(|e| SceneError::input(format!("{}: cannot read the file: {e}", shown())))?;
        if got == 0 {
            return Err(err(&name, line_no.max(1), "no `Atoms` section"));
        }
        offset += got as u64;
        line_no += 1;
        let text = std::str::from_utf8(&raw).map_err(|e| {
            SceneError::input(format!(
                "LAMMPS data file `{name}`: not UTF-8 text (byte {})",
                offset - got as u64 + e.valid_up_to() as u64
            ))
        })?;
        if line_no == 1 {
            continue; // the title
        }
        let line = text.split('#').next().unwrap_or("").trim();
        if line.is_empty() {
            continue;
        }
        let words: Vec<&str> = line.split_whitespace().collect();
        if let Some(next) = Section::named(words[0]) {
            if words.len() > 1 {
                return Err(err(
                    &name,
                    line_no,
                    format!("unexpected text after `{}`", words[0]),
                ));
            }
            if next == Section::Atoms {
                let style = text.split_once('#').map(|(_, c)| c.trim());
                if let Some(style) = style.filter(|s| !s.is_empty()) {
                    if style != "sphere" {
                        return Err(err(
                            &name,
                            line_no,
                            format!("`Atoms # {style}`: only atom_style sphere is read"),
                        ));
                    }
                }
                break;
            }
            velocities_first |= next == Section::Velocities;
            section = next;
            continue;
        }
        if section == Section::Header {
            header_line(&words, &mut n_atoms, &mut bounds).map_err(|m| err(&name, line_no, m))?;
        }
    }
    let Some(atoms) = n_atoms else {
        return Err(err(&name, 1, "no `N atoms` line in the header"));
    };
    let mut resolved = [[0.0; 2]; 3];
    for (k, b) in bounds.iter().enumerate() {
        resolved[k] = b.ok_or_else(|| {
            err(
                &name,
                1,
                format!("no `{0}lo {0}hi` line in the header", ["x", "y", "z"][k]),
            )
        })?;
    }
    Ok(DataHeader {
        atoms,
        bounds: resolved,
        atoms_start: offset,
        len,
        header_lines: line_no,
        velocities_first,
    })
}

/// The text of the lines that begin in one rank's byte range of the
/// `Atoms` section (and of what follows it).
#[derive(Debug, Clone, PartialEq)]
pub struct RangeText {
    pub text: String,
    /// The range is the file's last.
    pub last: bool,
}

impl RangeText {
    /// Line ends in the text (the lines before the next rank's).
    pub fn line_ends(&self) -> usize {
        self.text.bytes().filter(|&b| b == b'\n').count()
    }
}

/// The lines beginning in byte range `part` of `parts` of the section
/// after the header.
pub fn read_range(
    path: &Path,
    header: &DataHeader,
    part: usize,
    parts: usize,
) -> Result<RangeText, SceneError> {
    let name = path.display().to_string();
    let io = |e: std::io::Error| SceneError::input(format!("`{name}`: cannot read the file: {e}"));
    let body = header.len.saturating_sub(header.atoms_start);
    let at = |p: usize| header.atoms_start + (body as u128 * p as u128 / parts as u128) as u64;
    let (lo, hi) = (at(part), at(part + 1));
    let mut file = std::fs::File::open(path).map_err(io)?;
    // The first line beginning at or after lo.
    let mut start = lo;
    if lo > header.atoms_start {
        file.seek(SeekFrom::Start(lo - 1)).map_err(io)?;
        let mut reader = BufReader::new(&mut file);
        let mut skipped = Vec::new();
        reader.read_until(b'\n', &mut skipped).map_err(io)?;
        start = lo - 1 + skipped.len() as u64;
    }
    let mut bytes = Vec::new();
    if start < hi {
        file.seek(SeekFrom::Start(start)).map_err(io)?;
        let mut reader = BufReader::new(&mut file);
        (&mut reader)
            .take(hi - start)
            .read_to_end(&mut bytes)
            .map_err(io)?;
        // The line holding byte hi − 1 ends past hi: it is this range's.
        if bytes.last().is_some_and(|&b| b != b'\n') {
            reader.read_until(b'\n', &mut bytes).map_err(io)?;
        }
    }
    let text = String::from_utf8(bytes).map_err(|e| {
        SceneError::input(format!(
            "LAMMPS data file `{name}`: not UTF-8 text (byte {})",
            start + e.utf8_error().valid_up_to() as u64
        ))
    })?;
    Ok(RangeText {
        text,
        last: part + 1 == parts,
    })
}

/// The atoms of a range's lines, each with its line number (`first_line`:
/// the number of the range's first line); `Ok(None)` when a section
/// header follows the atoms in this range (the `Atoms` section is not the
/// file's last: such files are read whole).
pub fn parse_range(
    range: &RangeText,
    first_line: usize,
    name: &str,
) -> Result<Option<Vec<(usize, DataAtom)>>, SceneError> {
    if range.last {
        if let Some(k) = super::unterminated_last_line(&range.text) {
            return Err(err(
                name,
                first_line + k - 1,
                "the file ends inside this line (no line end after it): it looks cut, and a \
                 number cut short still reads as another number; end the file with a newline if \
                 the line is whole",
            ));
        }
    }
    let mut atoms = Vec::new();
    for (k, raw) in range.text.lines().enumerate() {
        let line_no = first_line + k;
        let line = raw.split('#').next().unwrap_or("").trim();
        if line.is_empty() {
            continue;
        }
        let words: Vec<&str> = line.split_whitespace().collect();
        if Section::named(words[0]).is_some() {
            return Ok(None);
        }
        atoms.push((
            line_no,
            parse_atom(&words).map_err(|m| err(name, line_no, m))?,
        ));
    }
    Ok(Some(atoms))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// make_lattice.py 2 1, then three more atoms (ids out of order).
    const FILE: &str = "lattice-drop benchmark: 2x2x1 spheres R=0.0005 m

7 atoms
1 atom types

0 0.0030000000000000005 xlo xhi
0 0.0030000000000000005 ylo yhi
0 0.03 zlo zhi

Atoms # sphere

1 1 0.001 1000.0 0.0006 0.0006 0.000505
2 1 0.001 1000.0 0.0018 0.0006 0.000505
5 1 0.001 1000.0 0.0006 0.0018 0.000505
4 1 0.001 1000.0 0.0018 0.0018 0.000505
3 1 0.001 1000.0 0.0006 0.0006 0.002505
7 1 0.001 1000.0 0.0018 0.0006 0.002505
6 1 0.001 1000.0 0.0006 0.0018 0.002505
";

    #[test]
    fn ranges_cover_every_atom_once_with_its_line() {
        let dir = std::env::temp_dir().join(format!("lammps_part_{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("seven.data");
        std::fs::write(&path, FILE).unwrap();
        let h = read_header(&path, "lammps_data").unwrap();
        assert_eq!(h.atoms, 7);
        assert_eq!(h.header_lines, 10);
        assert_eq!(h.bounds[2], [0.0, 0.03]);
        let whole = super::super::lammps_data::LammpsData::parse(FILE, "seven.data").unwrap();
        for parts in 1..=9 {
            let mut got = Vec::new();
            let mut first = h.header_lines + 1;
            for p in 0..parts {
                let r = read_range(&path, &h, p, parts).unwrap();
                got.extend(parse_range(&r, first, "seven.data").unwrap().unwrap());
                first += r.line_ends();
            }
            // The lines' numbers, counted in FILE: title 1, Atoms 10, atoms 12–18.
            let lines: Vec<usize> = got.iter().map(|(l, _)| *l).collect();
            assert_eq!(lines, (12..=18).collect::<Vec<_>>(), "{parts} parts");
            let mut atoms: Vec<DataAtom> = got.into_iter().map(|(_, a)| a).collect();
            atoms.sort_by_key(|a| a.id);
            assert_eq!(atoms, whole.atoms, "{parts} parts");
        }
        std::fs::remove_dir_all(&dir).ok();
    }
}
