//! LAMMPS data files of `atom_style sphere`, so that one initial state runs
//! in LAMMPS and here (the lattice-drop benchmark's `make_lattice.py` writes
//! them).
//!
//! Read: the header counts (`N atoms`, `N atom types`), the box
//! (`xlo xhi`, `ylo yhi`, `zlo zhi`), the `Atoms` section with lines
//! `id type diameter density x y z [ix iy iz]`, and an optional
//! `Velocities` section `id vx vy vz [wx wy wz]` (the angular velocity is
//! ignored: the engine has no rotation yet). `#` starts a comment. Other
//! sections (`Masses`, …) are skipped. Spheres are returned in the order of
//! their ids. Every error names the file and line.

use super::SourceSphere;
use crate::SceneError;
use std::collections::HashMap;
use std::path::Path;

/// One atom of the data file.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DataAtom {
    pub id: u64,
    pub atom_type: u32,
    /// Density, kg/m³ (LAMMPS `units si`).
    pub density: f64,
    pub sphere: SourceSphere,
}

/// A parsed data file.
#[derive(Debug, Clone, PartialEq)]
pub struct LammpsData {
    /// `[lo, hi]` along x, y, z, m.
    pub bounds: [[f64; 2]; 3],
    /// Atoms sorted by id.
    pub atoms: Vec<DataAtom>,
}

impl LammpsData {
    /// Reads and parses `path`.
    pub fn read(path: &Path) -> Result<Self, SceneError> {
        Self::read_for(path, "lammps_data")
    }

    /// Reads and parses `path`, the value of the scene key `key` (named
    /// when the file is missing, not a file or over
    /// [`super::MAX_DATA_FILE_BYTES`]).
    pub fn read_for(path: &Path, key: &str) -> Result<Self, SceneError> {
        let bytes = super::read_data_file(path, key)?;
        let name = path.display().to_string();
        let text = String::from_utf8(bytes).map_err(|e| {
            SceneError::input(format!(
                "LAMMPS data file `{name}`: not UTF-8 text (byte {})",
                e.utf8_error().valid_up_to()
            ))
        })?;
        Self::parse(&text, &name)
    }

    /// The spheres in id order.
    pub fn spheres(&self) -> Vec<SourceSphere> {
        self.atoms.iter().map(|a| a.sphere).collect()
    }

    /// Parses the text of a data file; `name` is the file named in errors.
    pub fn parse(text: &str, name: &str) -> Result<Self, SceneError> {
        let err = |line: usize, msg: String| {
            SceneError::input(format!("LAMMPS data file `{name}`, line {line}: {msg}"))
        };
        if let Some(line) = super::unterminated_last_line(text) {
            return Err(err(
                line,
                "the file ends inside this line (no line end after it): it looks cut, and a \
                 number cut short still reads as another number; end the file with a newline if \
                 the line is whole"
                    .into(),
            ));
        }
        let mut n_atoms: Option<usize> = None;
        let mut bounds: [Option<[f64; 2]>; 3] = [None; 3];
        let mut section = Section::Header;
        let mut atoms: Vec<(usize, DataAtom)> = Vec::new();
        let mut velocities: Vec<(usize, u64, [f64; 3])> = Vec::new();
        // The first line is a title, always skipped.
        for (index, raw) in text.lines().enumerate().skip(1) {
            let line_no = index + 1;
            let line = raw.split('#').next().unwrap_or("").trim();
            if line.is_empty() {
                continue;
            }
            let words: Vec<&str> = line.split_whitespace().collect();
            if let Some(next) = Section::named(words[0]) {
                if words.len() > 1 {
                    return Err(err(
                        line_no,
                        format!("unexpected text after `{}`", words[0]),
                    ));
                }
                if next == Section::Atoms {
                    let style = raw.split_once('#').map(|(_, c)| c.trim());
                    if let Some(style) = style.filter(|s| !s.is_empty()) {
                        if style != "sphere" {
                            return Err(err(
                                line_no,
                                format!("`Atoms # {style}`: only atom_style sphere is read"),
                            ));
                        }
                    }
                }
                section = next;
                continue;
            }
            match section {
                Section::Header => {
                    header_line(&words, &mut n_atoms, &mut bounds).map_err(|m| err(line_no, m))?
                }
                Section::Atoms => {
                    atoms.push((line_no, parse_atom(&words).map_err(|m| err(line_no, m))?))
                }
                Section::Velocities => {
                    if words.len() != 4 && words.len() != 7 {
                        return Err(err(
                            line_no,
                            format!(
                                "a Velocities line has 4 or 7 columns (id vx vy vz [wx wy wz]), found {}",
                                words.len()
                            ),
                        ));
                    }
                    let id = words[0].parse::<u64>().map_err(|_| {
                        err(
                            line_no,
                            format!("atom id `{}` is not a positive integer", words[0]),
                        )
                    })?;
                    let mut v = [0.0; 3];
                    for k in 0..3 {
                        v[k] =
                            parse_finite(words[1 + k], "velocity").map_err(|m| err(line_no, m))?;
                    }
                    velocities.push((line_no, id, v));
                }
                Section::Other => {}
            }
        }
        let last_line = text.lines().count().max(1);
        let Some(n_atoms) = n_atoms else {
            return Err(err(1, "no `N atoms` line in the header".into()));
        };
        if atoms.len() != n_atoms {
            return Err(err(
                last_line,
                format!(
                    "the header announces {n_atoms} atoms, the Atoms section has {}",
                    atoms.len()
                ),
            ));
        }
        let mut resolved = [[0.0; 2]; 3];
        for (k, b) in bounds.iter().enumerate() {
            resolved[k] = b.ok_or_else(|| {
                err(
                    1,
                    format!("no `{0}lo {0}hi` line in the header", ["x", "y", "z"][k]),
                )
            })?;
        }
        let mut by_id: HashMap<u64, usize> = HashMap::with_capacity(atoms.len());
        for (index, (line_no, atom)) in atoms.iter().enumerate() {
            if by_id.insert(atom.id, index).is_some() {
                return Err(err(*line_no, format!("atom id {} appears twice", atom.id)));
            }
        }
        for (line_no, id, v) in velocities {
            let Some(&index) = by_id.get(&id) else {
                return Err(err(
                    line_no,
                    format!("velocity of atom {id}, which is not in Atoms"),
                ));
            };
            atoms[index].1.sphere.velocity = v;
        }
        let mut atoms: Vec<DataAtom> = atoms.into_iter().map(|(_, a)| a).collect();
        atoms.sort_by_key(|a| a.id);
        Ok(LammpsData {
            bounds: resolved,
            atoms,
        })
    }
}

/// One header line: `N atoms` and the box bounds are kept, other lines
/// (atom types, bonds, …) say nothing a sphere needs.
pub(crate) fn header_line(
    words: &[&str],
    n_atoms: &mut Option<usize>,
    bounds: &mut [Option<[f64; 2]>; 3],
) -> Result<(), String> {
    let number = |w: &str| {
        w.parse::<f64>()
            .map_err(|_| format!("`{w}` is not a number"))
    };
    match words {
        [n, "atoms"] => {
            *n_atoms = Some(n.parse().map_err(|_| format!("`{n}` atoms: not a count"))?)
        }
        [lo, hi, axis_lo, axis_hi]
            if axis_lo.len() == 3 && axis_lo.ends_with("lo") && axis_hi.ends_with("hi") =>
        {
            let axis = match *axis_lo {
                "xlo" => 0,
                "ylo" => 1,
                "zlo" => 2,
                _ => return Err(format!("unknown bound `{axis_lo}`")),
            };
            let (lo, hi) = (number(lo)?, number(hi)?);
            if lo >= hi || lo.is_nan() || hi.is_nan() {
                return Err(format!("{axis_lo} {lo} ≥ {axis_hi} {hi}"));
            }
            bounds[axis] = Some([lo, hi]);
        }
        [_, _, _, "xy", "xz", "yz"] => return Err("triclinic boxes are not supported".into()),
        _ => {}
    }
    Ok(())
}

#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Section {
    Header,
    Atoms,
    Velocities,
    Other,
}

impl Section {
    pub(crate) fn named(word: &str) -> Option<Self> {
        match word {
            "Atoms" => Some(Section::Atoms),
            "Velocities" => Some(Section::Velocities),
            "Masses" | "Ellipsoids" | "Lines" | "Triangles" | "Bodies" | "Bonds" | "Angles"
            | "Dihedrals" | "Impropers" | "Pair" | "PairIJ" => Some(Section::Other),
            _ => None,
        }
    }
}

fn parse_finite(word: &str, what: &str) -> Result<f64, String> {
    match word.parse::<f64>() {
        Ok(x) if x.is_finite() => Ok(x),
        _ => Err(format!("{what} `{word}` is not a finite number")),
    }
}

/// `id type diameter density x y z [ix iy iz]`.
pub(crate) fn parse_atom(words: &[&str]) -> Result<DataAtom, String> {
    if words.len() != 7 && words.len() != 10 {
        return Err(format!(
            "an Atoms line of atom_style sphere has 7 columns (id type diameter density x y z) \
             or 10 (with image flags), found {}",
            words.len()
        ));
    }
    let id = words[0]
        .parse::<u64>()
        .map_err(|_| format!("atom id `{}` is not a positive integer", words[0]))?;
    let atom_type = words[1]
        .parse::<u32>()
        .map_err(|_| format!("atom type `{}` is not a positive integer", words[1]))?;
    let diameter = parse_finite(words[2], "diameter")?;
    if diameter <= 0.0 {
        return Err(format!(
            "diameter {diameter} m: must be > 0 (a point particle, diameter 0, is not a sphere)"
        ));
    }
    let density = parse_finite(words[3], "density")?;
    if density <= 0.0 {
        return Err(format!("density {density} kg/m³: must be > 0"));
    }
    let mut position = [0.0; 3];
    for k in 0..3 {
        position[k] = parse_finite(words[4 + k], "coordinate")?;
    }
    Ok(DataAtom {
        id,
        atom_type,
        density,
        sphere: SourceSphere::at_rest(position, 0.5 * diameter),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// make_lattice.py 2 1 (written by the script, its exact format).
    const SMALL: &str = "lattice-drop benchmark: 2x2x1 spheres R=0.0005 m

4 atoms
1 atom types

0 0.0030000000000000005 xlo xhi
0 0.0030000000000000005 ylo yhi
0 0.03 zlo zhi

Atoms # sphere

1 1 0.001 1000.0 0.0006 0.0006 0.000505
2 1 0.001 1000.0 0.0018 0.0006 0.000505
3 1 0.001 1000.0 0.0006 0.0018 0.000505
4 1 0.001 1000.0 0.0018 0.0018 0.000505
";

    #[test]
    fn the_benchmark_format_is_read() {
        let d = LammpsData::parse(SMALL, "small.data").unwrap();
        assert_eq!(
            d.bounds,
            [
                [0.0, 0.0030000000000000005],
                [0.0, 0.0030000000000000005],
                [0.0, 0.03]
            ]
        );
        assert_eq!(d.atoms.len(), 4);
        assert_eq!(d.atoms[1].sphere.position, [0.0018, 0.0006, 0.000505]);
        assert_eq!(d.atoms[1].sphere.radius, 0.0005);
        assert_eq!(d.atoms[3].density, 1000.0);
        assert_eq!(d.atoms[3].atom_type, 1);
    }

    #[test]
    fn atoms_are_sorted_by_id_and_velocities_attached() {
        let text = "title\n2 atoms\n0 1 xlo xhi\n0 1 ylo yhi\n0 1 zlo zhi\n\nAtoms # sphere\n\n\
                    7 1 0.1 2 0.5 0.5 0.5 0 0 0\n3 2 0.2 2 0.2 0.2 0.2\n\nVelocities\n\n7 1 2 3 0 0 0\n";
        let d = LammpsData::parse(text, "v.data").unwrap();
        assert_eq!(d.atoms.iter().map(|a| a.id).collect::<Vec<_>>(), vec![3, 7]);
        assert_eq!(d.atoms[1].sphere.velocity, [1.0, 2.0, 3.0]);
        assert_eq!(d.atoms[0].sphere.velocity, [0.0; 3]);
        assert_eq!(d.atoms[0].atom_type, 2);
    }

    #[test]
    fn errors_name_the_file_and_line() {
        let cases: &[(&str, usize, &str)] = &[
            // (replace line, line number, text expected)
            ("1 1 0.001 1000.0 0.0006 0.0006", 12, "7 columns"),
            ("1 1 -0.001 1000.0 0.0006 0.0006 0.000505", 12, "diameter"),
            ("1 1 0.001 1000.0 0.0006 nan 0.000505", 12, "coordinate"),
            ("x 1 0.001 1000.0 0.0006 0.0006 0.000505", 12, "atom id"),
            (
                "2 1 0.001 1000.0 0.0006 0.0006 0.000505",
                13,
                "appears twice",
            ),
        ];
        for (line, at, what) in cases {
            let text = SMALL.replacen("1 1 0.001 1000.0 0.0006 0.0006 0.000505", line, 1);
            let e = LammpsData::parse(&text, "small.data")
                .unwrap_err()
                .to_string();
            assert!(
                e.contains("`small.data`") && e.contains(&format!("line {at}")) && e.contains(what),
                "{e}"
            );
        }
        let e = LammpsData::parse(&SMALL.replace("4 atoms", "5 atoms"), "s")
            .unwrap_err()
            .to_string();
        assert!(e.contains("5 atoms") && e.contains("has 4"), "{e}");
        let e = LammpsData::parse(&SMALL.replace("Atoms # sphere", "Atoms # atomic"), "s")
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("line 10") && e.contains("atom_style sphere"),
            "{e}"
        );
        let e = LammpsData::parse(&SMALL.replace("0 0.03 zlo zhi", ""), "s")
            .unwrap_err()
            .to_string();
        assert!(e.contains("zlo zhi"), "{e}");
        let e = LammpsData::read(Path::new("/nonexistent/x.data"))
            .unwrap_err()
            .to_string();
        assert!(e.contains("/nonexistent/x.data"), "{e}");
    }

    #[test]
    fn a_file_cut_inside_its_last_line_is_refused() {
        // SMALL ends with the atom at z = 0.000505 (line 15); cut inside
        // that number the line still parses (z = 0.0005), so the missing
        // line end is what tells.
        let whole = SMALL.trim_end_matches('\n');
        assert!(whole.ends_with("0.000505"), "{whole}");
        let lines = whole.lines().count();
        for cut in [0, 2, 4, 8] {
            let text = &whole[..whole.len() - cut];
            let e = LammpsData::parse(text, "cut.data").unwrap_err().to_string();
            assert!(
                e.contains("`cut.data`")
                    && e.contains(&format!("line {lines}"))
                    && e.contains("cut"),
                "{e}"
            );
        }
        // The same line with its newline is whole; a last line that is a
        // comment or blank needs none.
        assert!(LammpsData::parse(&format!("{whole}\n"), "s").is_ok());
        assert!(LammpsData::parse(&format!("{whole}\n# end"), "s").is_ok());
        assert!(LammpsData::parse(&format!("{whole}\n  "), "s").is_ok());
    }
}
