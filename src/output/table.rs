//! One table model for every report: columns that carry a quantity name, an
//! SI unit and how their values are written, rendered to the terminal
//! (fitted to its width), to Markdown (escaped, so that a `|` in a cell
//! stays in its cell) and to CSV (SI, exact).
//!
//! On the terminal and in Markdown a column of a prefixable unit (m, s, N,
//! J, Pa) is shown in the SI prefix that suits its values (nm, µm, mm, …,
//! chosen per column from the largest magnitude), the unit in the header;
//! CSV keeps plain SI and the shortest exact text of every value.
//!
//! Adding a column to a report is one [`Column`] and one cell per row.

use super::format::{exact, sig};
use anyhow::Result;
use comfy_table::{presets, CellAlignment, ContentArrangement};
use std::fmt;
use std::io::Write;

/// An SI unit as it appears in headers.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Unit {
    /// Terminal and Markdown symbol: `m`, `m/s²`, `1`; empty for no unit.
    pub symbol: &'static str,
    /// The suffix of a CSV header: `m`, `m_s2`; empty for none.
    pub csv: &'static str,
    /// Whether an SI prefix may scale it (m → nm). Compound units (m/s,
    /// m/s²) and the dimensionless 1 keep their symbol.
    pub prefixable: bool,
}

impl Unit {
    /// No unit at all (labels, counts, plain numbers): no `(…)` in the header.
    pub const NONE: Unit = Unit::fixed("", "");
    /// Dimensionless: `(1)` in the header.
    pub const ONE: Unit = Unit::fixed("1", "");
    pub const METRE: Unit = Unit::prefixed("m", "m");
    pub const SECOND: Unit = Unit::prefixed("s", "s");
    pub const NEWTON: Unit = Unit::prefixed("N", "N");
    pub const JOULE: Unit = Unit::prefixed("J", "J");
    #[allow(dead_code)] // for moduli (boundary_youngs_modulus)
    pub const PASCAL: Unit = Unit::prefixed("Pa", "Pa");
    pub const METRE_PER_SECOND: Unit = Unit::fixed("m/s", "m_s");
    pub const METRE_PER_SECOND2: Unit = Unit::fixed("m/s²", "m_s2");
    pub const PERCENT: Unit = Unit::fixed("%", "percent");

    const fn prefixed(symbol: &'static str, csv: &'static str) -> Unit {
        Unit {
            symbol,
            csv,
            prefixable: true,
        }
    }

    /// A unit shown as given, never prefixed.
    pub const fn fixed(symbol: &'static str, csv: &'static str) -> Unit {
        Unit {
            symbol,
            csv,
            prefixable: false,
        }
    }
}

/// An SI prefix: its symbol and the factor it stands for.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Prefix {
    pub symbol: &'static str,
    pub factor: f64,
}

/// The prefixes used, 10^(3k) for k = −5 … 3 (f … G).
const PREFIXES: [(&str, i32); 9] = [
    ("f", -15),
    ("p", -12),
    ("n", -9),
    ("µ", -6),
    ("m", -3),
    ("", 0),
    ("k", 3),
    ("M", 6),
    ("G", 9),
];

/// The prefix that puts the largest finite nonzero magnitude of `values`
/// in [1, 1000) (clamped to f … G); no prefix when there is none.
pub fn si_prefix(values: impl IntoIterator<Item = f64>) -> Prefix {
    let largest = values
        .into_iter()
        .filter(|v| v.is_finite() && *v != 0.0)
        .map(f64::abs)
        .fold(0.0, f64::max);
    let none = Prefix {
        symbol: "",
        factor: 1.0,
    };
    if largest == 0.0 {
        return none;
    }
    // log10 of an exact power of ten may land just below the integer:
    // correct the estimate against the factor itself.
    let mut k = (largest.log10() / 3.0).floor() as i32;
    if largest / 10f64.powi(3 * k) >= 1000.0 {
        k += 1;
    } else if largest / 10f64.powi(3 * k) < 1.0 {
        k -= 1;
    }
    let k = k.clamp(-5, 3);
    PREFIXES
        .iter()
        .find(|(_, e)| *e == 3 * k)
        .map_or(none, |&(symbol, e)| Prefix {
            symbol,
            factor: 10f64.powi(e),
        })
}

/// How the numbers of a column are written.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Format {
    /// Cells are text (left-aligned).
    Text,
    /// Significant digits, fixed notation for moderate magnitudes.
    Sig(usize),
    /// Signed scientific with this many significant digits (`+1.23e-8`),
    /// for relative errors.
    SignedSci(usize),
    /// Scientific with this many significant digits (`1.2e-8`).
    Sci(usize),
    /// This many decimals.
    Fixed(usize),
    /// An integer (counts).
    Integer,
}

/// One column: what it is, in which unit, written how.
#[derive(Debug, Clone)]
pub struct Column {
    /// The quantity's name in terminal and Markdown headers: `h_max`.
    pub label: String,
    /// The CSV header stem (`max_overlap`, the unit suffix appended);
    /// `None` keeps the column out of CSV.
    pub key: Option<String>,
    pub unit: Unit,
    pub format: Format,
    /// Shown on the terminal and in Markdown (`false`: CSV only).
    pub shown: bool,
    /// Cells aligned right (numbers) or left (text).
    pub right: bool,
}

impl Column {
    /// A text column (names, labels, notes).
    pub fn text(label: impl Into<String>) -> Self {
        Column {
            label: label.into(),
            key: None,
            unit: Unit::NONE,
            format: Format::Text,
            shown: true,
            right: false,
        }
    }

    /// A numeric column in `unit`, written as `format`.
    pub fn number(label: impl Into<String>, unit: Unit, format: Format) -> Self {
        Column {
            label: label.into(),
            key: None,
            unit,
            format,
            shown: true,
            right: format != Format::Text,
        }
    }

    /// A quantity with `digits` significant digits.
    pub fn quantity(label: impl Into<String>, unit: Unit, digits: usize) -> Self {
        Self::number(label, unit, Format::Sig(digits))
    }

    /// The same column, in CSV under `key` (the unit's suffix appended).
    pub fn csv(mut self, key: impl Into<String>) -> Self {
        self.key = Some(key.into());
        self
    }

    /// The same column, in CSV only.
    pub fn csv_only(mut self) -> Self {
        self.shown = false;
        self
    }

    /// The same column, aligned right (text that holds numbers).
    pub fn right(mut self) -> Self {
        self.right = true;
        self
    }

    fn csv_header(&self) -> Option<String> {
        let key = self.key.as_ref()?;
        Some(if self.unit.csv.is_empty() {
            key.clone()
        } else {
            format!("{key}_{}", self.unit.csv)
        })
    }
}

/// One cell: a number (written by its column's format and unit), text, or
/// nothing.
#[derive(Debug, Clone, PartialEq)]
pub enum Cell {
    /// In the column's SI unit.
    Number(f64),
    /// Plain text; escaped in Markdown.
    Text(String),
    /// Markdown already (emphasis, code spans): only `|` escaped.
    Markdown(String),
    Empty,
}

impl Cell {
    pub fn text(s: impl Into<String>) -> Self {
        Cell::Text(s.into())
    }
}

impl From<f64> for Cell {
    fn from(x: f64) -> Self {
        Cell::Number(x)
    }
}

impl From<Option<f64>> for Cell {
    fn from(x: Option<f64>) -> Self {
        x.map_or(Cell::Empty, Cell::Number)
    }
}

impl From<u64> for Cell {
    fn from(n: u64) -> Self {
        Cell::Number(n as f64)
    }
}

impl From<usize> for Cell {
    fn from(n: usize) -> Self {
        Cell::Number(n as f64)
    }
}

impl From<String> for Cell {
    fn from(s: String) -> Self {
        Cell::Text(s)
    }
}

impl From<&str> for Cell {
    fn from(s: &str) -> Self {
        Cell::Text(s.to_string())
    }
}

/// A table: columns and rows of cells.
#[derive(Debug, Clone, Default)]
pub struct Table {
    pub columns: Vec<Column>,
    pub rows: Vec<Vec<Cell>>,
    /// Leading columns repeated in every part when a wide table is split
    /// to fit the terminal (the row's name: `#`, `law`, …).
    pub keys: usize,
}

/// A terminal table no narrower than this is split into parts.
const MIN_WIDTH: usize = 40;

/// The width of the terminal when stdout is one, `None` otherwise (then
/// tables keep their full layout, stable for files and pipes).
pub fn terminal_width() -> Option<usize> {
    comfy_table::Table::new().width().map(usize::from)
}

impl Table {
    pub fn new(columns: Vec<Column>) -> Self {
        Table {
            columns,
            rows: Vec::new(),
            keys: 1,
        }
    }

    /// The same table with `n` key columns (see [`Table::keys`]).
    pub fn with_keys(mut self, n: usize) -> Self {
        self.keys = n;
        self
    }

    /// Appends a row (missing cells are empty, extra cells dropped).
    pub fn push(&mut self, mut row: Vec<Cell>) {
        row.resize(self.columns.len(), Cell::Empty);
        self.rows.push(row);
    }

    /// The prefix of each column for display (no prefix for unprefixable units).
    fn prefixes(&self) -> Vec<Prefix> {
        self.columns
            .iter()
            .enumerate()
            .map(|(i, c)| {
                let numeric = !matches!(c.format, Format::Text | Format::Integer);
                if !(c.unit.prefixable && numeric) {
                    return si_prefix([]);
                }
                si_prefix(self.rows.iter().filter_map(|r| match r.get(i) {
                    Some(Cell::Number(x)) => Some(*x),
                    _ => None,
                }))
            })
            .collect()
    }

    /// Header text of column `i` with its (prefixed) unit.
    fn header(&self, i: usize, prefix: Prefix, unit_below: bool) -> String {
        let c = &self.columns[i];
        if c.unit.symbol.is_empty() {
            return c.label.clone();
        }
        let sep = if unit_below { "\n" } else { " " };
        format!("{}{sep}({}{})", c.label, prefix.symbol, c.unit.symbol)
    }

    fn display_cell(&self, i: usize, cell: &Cell, prefix: Prefix) -> String {
        match cell {
            Cell::Number(x) => format_number(*x / prefix.factor, self.columns[i].format),
            Cell::Text(s) | Cell::Markdown(s) => s.clone(),
            Cell::Empty => String::new(),
        }
    }

    fn shown(&self) -> Vec<usize> {
        (0..self.columns.len())
            .filter(|&i| self.columns[i].shown)
            .collect()
    }

    /// The terminal rendering for a terminal of `width` columns (`None`:
    /// the full layout). A table wider than `width` puts the units below
    /// the names, then is split by columns into parts that each fit, the
    /// key columns repeated in each.
    pub fn terminal(&self, width: Option<usize>) -> String {
        let prefixes = self.prefixes();
        let shown = self.shown();
        let full = self.comfy(&shown, &prefixes, false, None);
        let Some(width) = width.map(|w| w.max(MIN_WIDTH)) else {
            return full.to_string();
        };
        if rendered_width(&full) <= width {
            return full.to_string();
        }
        let narrow = self.comfy(&shown, &prefixes, true, None);
        if rendered_width(&narrow) <= width {
            return narrow.to_string();
        }
        // Split by columns: each column costs its content plus padding and
        // a border (3 characters), the table one more border.
        let widths: Vec<usize> = narrow
            .column_max_content_widths()
            .iter()
            .map(|&w| usize::from(w) + 3)
            .collect();
        let keys = self.keys.min(shown.len());
        let key_width: usize = 1 + widths[..keys].iter().sum::<usize>();
        let mut parts: Vec<Vec<usize>> = Vec::new();
        let mut current: Vec<usize> = Vec::new();
        let mut used = key_width;
        for (j, &w) in widths.iter().enumerate().skip(keys) {
            if !current.is_empty() && used + w > width {
                parts.push(std::mem::take(&mut current));
                used = key_width;
            }
            current.push(j);
            used += w;
        }
        if !current.is_empty() || parts.is_empty() {
            parts.push(current);
        }
        parts
            .iter()
            .map(|part| {
                let columns: Vec<usize> = shown[..keys]
                    .iter()
                    .chain(part.iter().map(|&j| &shown[j]))
                    .copied()
                    .collect();
                // A single column still too wide wraps inside its cells.
                self.comfy(&columns, &prefixes, true, Some(width))
                    .to_string()
            })
            .collect::<Vec<_>>()
            .join("\n")
    }

    fn comfy(
        &self,
        columns: &[usize],
        prefixes: &[Prefix],
        unit_below: bool,
        width: Option<usize>,
    ) -> comfy_table::Table {
        let mut t = comfy_table::Table::new();
        t.load_preset(presets::UTF8_FULL_CONDENSED);
        t.force_no_tty();
        if let Some(w) = width {
            t.set_content_arrangement(ContentArrangement::Dynamic);
            t.set_width(u16::try_from(w).unwrap_or(u16::MAX));
        }
        t.set_header(
            columns
                .iter()
                .map(|&i| self.header(i, prefixes[i], unit_below)),
        );
        for row in &self.rows {
            t.add_row(
                columns
                    .iter()
                    .map(|&i| self.display_cell(i, &row[i], prefixes[i])),
            );
        }
        for (k, &i) in columns.iter().enumerate() {
            if self.columns[i].right {
                if let Some(c) = t.column_mut(k) {
                    c.set_cell_alignment(CellAlignment::Right);
                }
            }
        }
        t
    }

    /// The Markdown (GFM) table: every cell escaped, numbers right-aligned.
    pub fn markdown(&self) -> String {
        let prefixes = self.prefixes();
        let shown = self.shown();
        let mut out = String::new();
        let line = |cells: Vec<String>| format!("| {} |\n", cells.join(" | "));
        out.push_str(&line(
            shown
                .iter()
                .map(|&i| markdown_escape(&self.header(i, prefixes[i], false)))
                .collect(),
        ));
        out.push_str(&line(
            shown
                .iter()
                .map(|&i| {
                    if self.columns[i].right {
                        "---:".to_string()
                    } else {
                        "---".to_string()
                    }
                })
                .collect(),
        ));
        for row in &self.rows {
            out.push_str(&line(
                shown
                    .iter()
                    .map(|&i| match &row[i] {
                        Cell::Markdown(s) => escape_pipes(s),
                        cell => markdown_escape(&self.display_cell(i, cell, prefixes[i])),
                    })
                    .collect(),
            ));
        }
        out
    }

    /// CSV: the columns with a key, SI values written exactly (shortest
    /// text that reads back to the same `f64`), text as is.
    pub fn write_csv(&self, w: &mut dyn Write) -> Result<()> {
        let mut csv = csv::Writer::from_writer(w);
        let columns: Vec<(usize, String)> = self
            .columns
            .iter()
            .enumerate()
            .filter_map(|(i, c)| c.csv_header().map(|h| (i, h)))
            .collect();
        csv.write_record(columns.iter().map(|(_, h)| h))?;
        for row in &self.rows {
            csv.write_record(columns.iter().map(|&(i, _)| match &row[i] {
                Cell::Number(x) if self.columns[i].format == Format::Integer => {
                    format_number(*x, Format::Integer)
                }
                Cell::Number(x) => exact(*x),
                Cell::Text(s) | Cell::Markdown(s) => s.clone(),
                Cell::Empty => String::new(),
            }))?;
        }
        csv.flush()?;
        Ok(())
    }
}

/// The terminal rendering, fitted to the terminal when stdout is one.
impl fmt::Display for Table {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.terminal(terminal_width()))
    }
}

fn rendered_width(t: &comfy_table::Table) -> usize {
    t.lines()
        // Box drawing, µ and ² are one column wide each.
        .map(|l| l.chars().count())
        .max()
        .unwrap_or(0)
}

/// A number in a column's format (already scaled to the column's prefix).
pub fn format_number(x: f64, format: Format) -> String {
    if !x.is_finite() {
        return x.to_string();
    }
    match format {
        Format::Text | Format::Sig(_) => {
            let digits = match format {
                Format::Sig(d) => d,
                _ => 6,
            };
            sig(x, digits)
        }
        Format::SignedSci(d) if x != 0.0 => format!("{:+.*e}", d.max(1) - 1, x),
        Format::Sci(d) if x != 0.0 => format!("{:.*e}", d.max(1) - 1, x),
        Format::SignedSci(_) | Format::Sci(_) => "0".into(),
        Format::Fixed(d) => format!("{x:.d$}"),
        Format::Integer => format!("{}", x.round()),
    }
}

/// `|` escaped (for text that is Markdown already).
pub fn escape_pipes(s: &str) -> String {
    s.replace('|', "\\|")
}

/// Text escaped for a Markdown table cell: the characters that would end
/// the cell (`|`), start emphasis, code, links or HTML, or escape, are
/// backslash-escaped; an `_` inside a word (`h_max`) cannot start
/// emphasis and stays as it is. Line breaks become spaces.
pub fn markdown_escape(s: &str) -> String {
    let chars: Vec<char> = s.chars().collect();
    let mut out = String::with_capacity(s.len());
    for (i, &c) in chars.iter().enumerate() {
        let inside_word = |j: Option<usize>| {
            j.and_then(|j| chars.get(j))
                .is_some_and(|c| c.is_alphanumeric())
        };
        match c {
            '_' if inside_word(i.checked_sub(1)) && inside_word(Some(i + 1)) => out.push(c),
            '\\' | '|' | '*' | '_' | '`' | '<' | '>' | '[' | ']' | '~' | '&' => {
                out.push('\\');
                out.push(c);
            }
            '\n' | '\r' => out.push(' '),
            _ => out.push(c),
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn prefixes_put_the_largest_magnitude_in_1_to_1000() {
        let p = |v: &[f64]| si_prefix(v.iter().copied()).symbol;
        assert_eq!(p(&[5.2419e-7]), "n"); // 524.19 nm
        assert_eq!(p(&[4.98334347e-3]), "m"); // 4.98 mm, not 4983343.47 nm
        assert_eq!(p(&[1e-6]), "µ"); // an exact power of ten: 1 µm, not 1000 nm
        assert_eq!(p(&[999.9e-9]), "n");
        assert_eq!(p(&[1e-3, 2e-9]), "m"); // the column's largest value decides
        assert_eq!(p(&[-3.2e3]), "k");
        assert_eq!(p(&[0.5]), "m");
        assert_eq!(p(&[1.0, 999.0]), "");
        assert_eq!(p(&[]), "");
        assert_eq!(p(&[0.0, f64::NAN, f64::INFINITY]), "");
        assert_eq!(p(&[1e-20]), "f"); // clamped to the smallest prefix
        assert_eq!(p(&[1e15]), "G"); // and to the largest
        assert_eq!(si_prefix([4.9e-6]).factor, 1e-6);
    }

    fn contact_like() -> Table {
        let mut t = Table::new(vec![
            Column::number("#", Unit::NONE, Format::Integer),
            Column::quantity("h_max", Unit::METRE, 9),
            Column::quantity("T_c", Unit::SECOND, 6),
            Column::quantity("v_c", Unit::METRE_PER_SECOND, 9),
            Column::quantity("e = v_r/|v_c|", Unit::ONE, 9),
        ]);
        t.push(vec![
            1usize.into(),
            4.98334347e-3.into(),
            4.92617e-6.into(),
            (-0.3132091953).into(),
            1.0.into(),
        ]);
        t.push(vec![
            2usize.into(),
            5.2419051e-7.into(),
            Cell::text("–"),
            Cell::Empty,
            0.5.into(),
        ]);
        t
    }

    #[test]
    fn values_are_scaled_to_the_column_prefix_with_the_unit_in_the_header() {
        let text = contact_like().terminal(None);
        for needle in [
            "h_max (mm)",
            "4.98334347",
            "0.000524190510", // 9 significant digits, same prefix as the column
            "T_c (µs)",
            "4.92617",
            "v_c (m/s)", // compound units are never prefixed
            "-0.313209195",
            "e = v_r/|v_c| (1)",
        ] {
            assert!(text.contains(needle), "`{needle}` missing in\n{text}");
        }
    }

    #[test]
    fn a_cell_with_a_pipe_is_one_markdown_cell() {
        let mut t = Table::new(vec![Column::text("quantity"), Column::text("note")]);
        t.push(vec![Cell::text("impact velocity |v_c|"), Cell::text("a*b")]);
        let md = t.markdown();
        assert_eq!(
            md,
            "| quantity | note |\n| --- | --- |\n| impact velocity \\|v_c\\| | a\\*b |\n"
        );
        // Rendered by the same Markdown parser as report.html: two cells.
        let html = {
            use pulldown_cmark::{html, Options, Parser};
            let mut s = String::new();
            html::push_html(&mut s, Parser::new_ext(&md, Options::ENABLE_TABLES));
            s
        };
        assert_eq!(html.matches("<td>").count(), 2, "{html}");
        assert!(html.contains("<td>impact velocity |v_c|</td>"), "{html}");
        assert!(html.contains("<td>a*b</td>"), "{html}");
    }

    #[test]
    fn markdown_escaping() {
        assert_eq!(markdown_escape("h_max"), "h_max");
        assert_eq!(markdown_escape("_x_"), "\\_x\\_");
        assert_eq!(markdown_escape("h*_max"), "h\\*\\_max");
        assert_eq!(markdown_escape("a\\b"), "a\\\\b");
        assert_eq!(markdown_escape("<b>"), "\\<b\\>");
        assert_eq!(markdown_escape("x\ny"), "x y");
        assert_eq!(escape_pipes("**no** | `a`"), "**no** \\| `a`");
    }

    #[test]
    fn markdown_keeps_units_and_alignment() {
        let md = contact_like().markdown();
        let lines: Vec<&str> = md.lines().collect();
        assert_eq!(
            lines[0],
            "| # | h_max (mm) | T_c (µs) | v_c (m/s) | e = v_r/\\|v_c\\| (1) |"
        );
        assert_eq!(lines[1], "| ---: | ---: | ---: | ---: | ---: |");
        assert_eq!(lines[3], "| 2 | 0.000524190510 | – |  | 0.500000000 |");
    }

    #[test]
    fn csv_is_si_and_exact() {
        let mut t = Table::new(vec![
            Column::number("#", Unit::NONE, Format::Integer).csv("contact"),
            Column::quantity("h_max", Unit::METRE, 3).csv("max_overlap"),
            Column::quantity("e", Unit::ONE, 3),
            Column::quantity("apex", Unit::METRE, 3)
                .csv("apex_height")
                .csv_only(),
        ]);
        t.push(vec![
            1usize.into(),
            5.2419051e-7.into(),
            1.0.into(),
            Cell::Empty,
        ]);
        let mut buf = Vec::new();
        t.write_csv(&mut buf).unwrap();
        assert_eq!(
            String::from_utf8(buf).unwrap(),
            "contact,max_overlap_m,apex_height_m\n1,5.2419051e-7,\n"
        );
        assert!(!t.terminal(None).contains("apex"));
    }

    #[test]
    fn narrow_terminals_get_parts_that_fit() {
        let mut t = Table::new(
            (0..12)
                .map(|i| Column::quantity(format!("quantity{i}"), Unit::SECOND, 9))
                .collect(),
        );
        t.columns.insert(0, Column::text("row"));
        for r in 0..3 {
            let mut row = vec![Cell::text(format!("r{r}"))];
            row.extend((0..12).map(|i| Cell::Number(1.234567891e-3 * f64::from(i + r))));
            t.push(row);
        }
        let full = t.terminal(None);
        assert!(full.lines().all(|l| !l.contains('\n')));
        assert!(full.lines().map(|l| l.chars().count()).max().unwrap() > 80);
        let narrow = t.terminal(Some(80));
        for line in narrow.lines() {
            assert!(line.chars().count() <= 80, "too wide: {line}");
        }
        // Every column is still there, and the key column in every part.
        for i in 0..12 {
            assert!(narrow.contains(&format!("quantity{i}")), "{narrow}");
        }
        assert!(narrow.matches("row").count() >= 2, "{narrow}");
        // A terminal wide enough keeps the full layout.
        assert_eq!(t.terminal(Some(1000)), full);
    }
}
