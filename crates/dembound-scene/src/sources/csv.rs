//! Spheres from a CSV file with a header row: `x,y,z,radius` (m) and
//! optionally `vx,vy,vz` (m/s, all three or none), in any column order. One
//! sphere per row, in file order. Errors name the file and line.

use super::SourceSphere;
use crate::SceneError;
use std::path::Path;

const REQUIRED: [&str; 4] = ["x", "y", "z", "radius"];
const VELOCITY: [&str; 3] = ["vx", "vy", "vz"];

/// Reads the spheres of the CSV file `path`.
pub fn read(path: &Path) -> Result<Vec<SourceSphere>, SceneError> {
    read_for(path, "csv")
}

/// Reads the spheres of the CSV file `path`, the value of the scene key
/// `key` (named when the file is missing, not a file or over
/// [`super::MAX_DATA_FILE_BYTES`]).
pub fn read_for(path: &Path, key: &str) -> Result<Vec<SourceSphere>, SceneError> {
    let bytes = super::read_data_file(path, key)?;
    parse(&bytes[..], &path.display().to_string())
}

/// Parses CSV text from `reader`; `name` is the file named in errors.
pub fn parse(reader: impl std::io::Read, name: &str) -> Result<Vec<SourceSphere>, SceneError> {
    let err = |line: u64, msg: String| {
        SceneError::input(format!("CSV file `{name}`, line {line}: {msg}"))
    };
    let mut reader = reader;
    let mut text = String::new();
    std::io::Read::read_to_string(&mut reader, &mut text)
        .map_err(|e| err(0, format!("cannot read the file as UTF-8 text: {e}")))?;
    if let Some(line) = super::unterminated_last_line(&text) {
        return Err(err(
            line as u64,
            "the file ends inside this line (no line end after it): it looks cut, and a number \
             cut short still reads as another number; end the file with a newline if the line \
             is whole"
                .into(),
        ));
    }
    let mut rdr = ::csv::ReaderBuilder::new()
        .trim(::csv::Trim::All)
        .comment(Some(b'#'))
        .from_reader(text.as_bytes());
    let headers = rdr
        .headers()
        .map_err(|e| err(1, format!("cannot read the header row: {e}")))?
        .clone();
    let column = |name: &str| headers.iter().position(|h| h == name);
    for h in headers.iter() {
        if !REQUIRED.contains(&h) && !VELOCITY.contains(&h) {
            return Err(err(
                1,
                format!("unknown column `{h}`; the columns are x,y,z,radius (m) and optionally vx,vy,vz (m/s)"),
            ));
        }
    }
    let mut required = [0usize; 4];
    for (slot, name) in required.iter_mut().zip(REQUIRED) {
        *slot = column(name).ok_or_else(|| {
            err(
                1,
                format!("no `{name}` column; the header must name x,y,z,radius [,vx,vy,vz]"),
            )
        })?;
    }
    let velocity: Vec<Option<usize>> = VELOCITY.iter().map(|n| column(n)).collect();
    let velocity = match velocity.as_slice() {
        [Some(a), Some(b), Some(c)] => Some([*a, *b, *c]),
        [None, None, None] => None,
        _ => return Err(err(1, "give all of vx,vy,vz or none".into())),
    };
    let mut spheres = Vec::new();
    for record in rdr.records() {
        let record = record.map_err(|e| {
            let line = e.position().map_or(0, |p| p.line());
            err(line, e.to_string())
        })?;
        let line = record.position().map_or(0, |p| p.line());
        let value = |index: usize, what: &str| -> Result<f64, SceneError> {
            let word = record.get(index).unwrap_or("");
            match word.parse::<f64>() {
                Ok(x) if x.is_finite() => Ok(x),
                _ => Err(err(line, format!("{what} `{word}` is not a finite number"))),
            }
        };
        let mut position = [0.0; 3];
        for k in 0..3 {
            position[k] = value(required[k], REQUIRED[k])?;
        }
        let radius = value(required[3], "radius")?;
        if radius <= 0.0 {
            return Err(err(line, format!("radius {radius} m: must be > 0")));
        }
        let mut v = [0.0; 3];
        if let Some(columns) = velocity {
            for k in 0..3 {
                v[k] = value(columns[k], VELOCITY[k])?;
            }
        }
        spheres.push(SourceSphere {
            position,
            velocity: v,
            radius,
        });
    }
    Ok(spheres)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn columns_in_any_order_with_or_without_velocity() {
        let s = parse(
            "radius,x,y,z\n0.5e-3,1,2,3\n0.25e-3, 4, 5, 6\n".as_bytes(),
            "a.csv",
        )
        .unwrap();
        assert_eq!(s.len(), 2);
        assert_eq!(s[1].position, [4.0, 5.0, 6.0]);
        assert_eq!(s[0].radius, 0.5e-3);
        assert_eq!(s[0].velocity, [0.0; 3]);
        let s = parse(
            "x,y,z,radius,vx,vy,vz\n# a comment\n0,0,0,1,1,2,-3\n".as_bytes(),
            "b.csv",
        )
        .unwrap();
        assert_eq!(s[0].velocity, [1.0, 2.0, -3.0]);
    }

    #[test]
    fn errors_name_file_and_line() {
        let msg = |t: &str| parse(t.as_bytes(), "s.csv").unwrap_err().to_string();
        let m = msg("x,y,z,radius\n0,0,0,1\n0,0,zz,1\n");
        assert!(m.contains("`s.csv`, line 3") && m.contains("`zz`"), "{m}");
        let m = msg("x,y,z,radius\n0,0,0,-1\n");
        assert!(m.contains("line 2") && m.contains("radius"), "{m}");
        let m = msg("x,y,z,r\n0,0,0,1\n");
        assert!(m.contains("unknown column `r`"), "{m}");
        let m = msg("x,y,z,radius,vx\n0,0,0,1,2\n");
        assert!(m.contains("vx,vy,vz"), "{m}");
        let m = msg("x,y,z,radius\n0,0,0\n");
        assert!(m.contains("line 2"), "{m}");
        // Cut inside the last number: `0.001045` → `0.00`, which parses.
        let m = msg("x,y,z,radius\n0,0,0,1e-3\n0.1,0.2,0.00");
        assert!(m.contains("line 3") && m.contains("cut"), "{m}");
        assert!(parse("x,y,z,radius\n0,0,0.001045,1e-3\n".as_bytes(), "s").is_ok());
    }
}
