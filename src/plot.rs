//! Figures: line and point series on linear or logarithmic axes, written as
//! SVG and PNG side by side (atomically: temporary file, then rename). A
//! series with an empty label stays out of the legend; a series with no
//! points only adds a legend entry (e.g. to explain line styles).
//!
//! PNG text needs a font: DejaVu Sans (permissive licence,
//! `assets/DejaVuSans-LICENSE.txt`) is compiled in and registered with
//! plotters' `ab_glyph` renderer, so no system font is needed.

// Used by `validate`, `sweep` and `paper` (on their way); until they land
// the module is exercised only by its own tests.
#![allow(dead_code)]

use anyhow::{anyhow, Context, Result};
use plotters::coord::Shift;
use plotters::prelude::*;
use std::path::{Path, PathBuf};
use std::sync::Once;

static FONT: &[u8] = include_bytes!("../assets/DejaVuSans.ttf");
static REGISTER: Once = Once::new();

fn register_font() {
    REGISTER.call_once(|| {
        // The bundled font is a valid TTF; if registration ever failed, PNG
        // text would be missing, never a panic.
        let _ = plotters::style::register_font("sans-serif", FontStyle::Normal, FONT);
    });
}

/// How a series is drawn.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Mark {
    /// A solid line (exact curves).
    Line,
    /// A dashed line (theory, estimates).
    Dashed,
    /// Markers only (numerical points).
    Points,
    /// Line with markers.
    LinePoints,
}

/// One curve of a figure.
#[derive(Debug, Clone)]
pub struct Series {
    pub label: String,
    pub points: Vec<(f64, f64)>,
    pub mark: Mark,
    /// Index into the palette; series sharing a colour share a parameter.
    pub color: usize,
}

impl Series {
    pub fn new(
        label: impl Into<String>,
        points: Vec<(f64, f64)>,
        mark: Mark,
        color: usize,
    ) -> Self {
        Self {
            label: label.into(),
            points,
            mark,
            color,
        }
    }
}

/// A figure: title, axis labels with units, series.
#[derive(Debug, Clone, Default)]
pub struct Figure {
    pub title: String,
    pub x_label: String,
    pub y_label: String,
    pub x_log: bool,
    pub y_log: bool,
    pub series: Vec<Series>,
}

/// Colour-blind-friendly palette (Okabe–Ito), then black, then two more
/// for figures with many curves.
const PALETTE: [RGBColor; 10] = [
    RGBColor(0, 114, 178),
    RGBColor(213, 94, 0),
    RGBColor(0, 158, 115),
    RGBColor(204, 121, 167),
    RGBColor(230, 159, 0),
    RGBColor(86, 180, 233),
    RGBColor(120, 120, 120),
    RGBColor(0, 0, 0),
    RGBColor(128, 0, 64),
    RGBColor(90, 60, 150),
];

/// Palette index of black (for legend entries that explain line styles).
pub const BLACK: usize = 7;

fn color(i: usize) -> RGBColor {
    PALETTE[i % PALETTE.len()]
}

fn range(values: impl Iterator<Item = f64>, log: bool) -> Option<(f64, f64)> {
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for v in values.filter(|v| v.is_finite() && (!log || *v > 0.0)) {
        lo = lo.min(v);
        hi = hi.max(v);
    }
    if !lo.is_finite() {
        return None;
    }
    if log {
        let (l, h) = (lo.log10(), hi.log10());
        let pad = ((h - l) * 0.05).max(0.05);
        Some((10f64.powf(l - pad), 10f64.powf(h + pad)))
    } else {
        let pad = ((hi - lo) * 0.05).max(hi.abs().max(1e-300) * 1e-3);
        Some((lo - pad, hi + pad))
    }
}

impl Figure {
    fn ranges(&self) -> Result<((f64, f64), (f64, f64))> {
        let pts = || self.series.iter().flat_map(|s| s.points.iter());
        let x = range(pts().map(|p| p.0), self.x_log);
        let y = range(pts().map(|p| p.1), self.y_log);
        match (x, y) {
            (Some(x), Some(y)) => Ok((x, y)),
            _ => Err(anyhow!(
                "figure \"{}\" has no finite points to draw",
                self.title
            )),
        }
    }

    fn draw<DB: DrawingBackend>(&self, root: DrawingArea<DB, Shift>) -> Result<()>
    where
        DB::ErrorType: 'static,
    {
        let ((x0, x1), (y0, y1)) = self.ranges()?;
        root.fill(&WHITE).map_err(|e| anyhow!("{e:?}"))?;
        let mut builder = ChartBuilder::on(&root);
        builder
            .caption(&self.title, ("sans-serif", 22))
            .margin(14)
            .x_label_area_size(52)
            .y_label_area_size(84);
        macro_rules! finish {
            ($chart:expr) => {{
                let mut chart = $chart;
                chart
                    .configure_mesh()
                    .x_desc(&self.x_label)
                    .y_desc(&self.y_label)
                    .axis_desc_style(("sans-serif", 17))
                    .label_style(("sans-serif", 14))
                    .light_line_style(RGBColor(235, 235, 235))
                    .draw()
                    .map_err(|e| anyhow!("{e:?}"))?;
                for s in &self.series {
                    let c = color(s.color);
                    let pts: Vec<(f64, f64)> = s
                        .points
                        .iter()
                        .copied()
                        .filter(|p| {
                            p.0.is_finite()
                                && p.1.is_finite()
                                && (!self.x_log || p.0 > 0.0)
                                && (!self.y_log || p.1 > 0.0)
                        })
                        .collect();
                    let anno = match s.mark {
                        Mark::Line => chart
                            .draw_series(LineSeries::new(pts, c.stroke_width(2)))
                            .map_err(|e| anyhow!("{e:?}"))?,
                        Mark::Dashed => chart
                            .draw_series(DashedLineSeries::new(pts, 8, 5, c.stroke_width(2)))
                            .map_err(|e| anyhow!("{e:?}"))?,
                        Mark::Points => chart
                            .draw_series(pts.into_iter().map(|p| Circle::new(p, 4, c.filled())))
                            .map_err(|e| anyhow!("{e:?}"))?,
                        Mark::LinePoints => {
                            chart
                                .draw_series(LineSeries::new(pts.clone(), c.stroke_width(1)))
                                .map_err(|e| anyhow!("{e:?}"))?;
                            chart
                                .draw_series(pts.into_iter().map(|p| Circle::new(p, 3, c.filled())))
                                .map_err(|e| anyhow!("{e:?}"))?
                        }
                    };
                    let mark = s.mark;
                    // An empty label keeps the series out of the legend.
                    if !s.label.is_empty() {
                        anno.label(s.label.clone())
                            .legend(move |(x, y)| match mark {
                                Mark::Points => Circle::new((x + 10, y), 4, c.filled()).into_dyn(),
                                Mark::Dashed => {
                                    PathElement::new(vec![(x, y), (x + 7, y)], c.stroke_width(2))
                                        .into_dyn()
                                }
                                _ => PathElement::new(vec![(x, y), (x + 20, y)], c.stroke_width(2))
                                    .into_dyn(),
                            });
                    }
                }
                if self.series.iter().any(|s| !s.label.is_empty()) {
                    chart
                        .configure_series_labels()
                        .background_style(WHITE.mix(0.85))
                        .border_style(RGBColor(160, 160, 160))
                        .label_font(("sans-serif", 14))
                        .position(SeriesLabelPosition::UpperRight)
                        .draw()
                        .map_err(|e| anyhow!("{e:?}"))?;
                }
            }};
        }
        match (self.x_log, self.y_log) {
            (false, false) => finish!(builder
                .build_cartesian_2d(x0..x1, y0..y1)
                .map_err(|e| anyhow!("{e:?}"))?),
            (true, false) => finish!(builder
                .build_cartesian_2d((x0..x1).log_scale(), y0..y1)
                .map_err(|e| anyhow!("{e:?}"))?),
            (false, true) => finish!(builder
                .build_cartesian_2d(x0..x1, (y0..y1).log_scale())
                .map_err(|e| anyhow!("{e:?}"))?),
            (true, true) => finish!(builder
                .build_cartesian_2d((x0..x1).log_scale(), (y0..y1).log_scale())
                .map_err(|e| anyhow!("{e:?}"))?),
        }
        root.present().map_err(|e| anyhow!("{e:?}"))?;
        Ok(())
    }

    /// Writes `<stem>.svg` and `<stem>.png` (900×600 px); returns both paths.
    pub fn write(&self, stem: &Path) -> Result<[PathBuf; 2]> {
        register_font();
        let svg_path = stem.with_extension("svg");
        let png_path = stem.with_extension("png");
        let dir = stem.parent().unwrap_or_else(|| Path::new("."));
        let size = (900, 600);

        let mut svg = String::new();
        self.draw(SVGBackend::with_string(&mut svg, size).into_drawing_area())?;
        let mut tmp = tempfile::Builder::new()
            .suffix(".svg")
            .tempfile_in(dir)
            .with_context(|| format!("cannot create a temporary file in {}", dir.display()))?;
        std::io::Write::write_all(&mut tmp, svg.as_bytes())
            .with_context(|| format!("cannot write {}", svg_path.display()))?;
        tmp.persist(&svg_path)
            .with_context(|| format!("cannot write {}", svg_path.display()))?;

        let tmp = tempfile::Builder::new()
            .suffix(".png")
            .tempfile_in(dir)
            .with_context(|| format!("cannot create a temporary file in {}", dir.display()))?;
        self.draw(BitMapBackend::new(tmp.path(), size).into_drawing_area())?;
        tmp.persist(&png_path)
            .with_context(|| format!("cannot write {}", png_path.display()))?;
        Ok([svg_path, png_path])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn writes_svg_and_png_with_labels() {
        let dir = tempfile::tempdir().expect("temp dir");
        let fig = Figure {
            title: "test".into(),
            x_label: "η (1)".into(),
            y_label: "relative error (1)".into(),
            x_log: true,
            y_log: true,
            series: vec![
                Series::new("a", vec![(0.1, 1e-3), (0.01, 1e-8)], Mark::LinePoints, 0),
                Series::new("b", vec![(0.1, 1e-2), (0.01, 1e-4)], Mark::Dashed, 1),
            ],
        };
        let [svg, png] = fig.write(&dir.path().join("fig")).expect("figure written");
        let text = std::fs::read_to_string(svg).expect("svg readable");
        // Axis labels with units end up in the SVG text.
        assert!(text.contains("relative error (1)"));
        // A PNG with text is well over a few kB; an empty canvas compresses to ~2 kB.
        assert!(std::fs::metadata(png).map(|m| m.len()).unwrap_or(0) > 10_000);
    }

    #[test]
    fn a_figure_without_points_is_an_error_not_a_panic() {
        let dir = tempfile::tempdir().expect("temp dir");
        let fig = Figure {
            y_log: true,
            series: vec![Series::new("zero", vec![(1.0, 0.0)], Mark::Line, 0)],
            ..Default::default()
        };
        assert!(fig.write(&dir.path().join("empty")).is_err());
    }
}
