//! Figures: line and point series on linear or logarithmic axes, written as
//! SVG and PNG side by side (atomically: temporary file, then rename). A
//! series with an empty label stays out of the legend; a series with no
//! points only adds a legend entry (e.g. to explain line styles).
//!
//! PNG text needs a font: DejaVu Sans (permissive licence,
//! `assets/DejaVuSans-LICENSE.txt`) is compiled in and registered with
//! plotters' `ab_glyph` renderer, so no system font is needed.

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
// Part of the figure API: not every build uses every mark.
#[allow(dead_code)]
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Mark {
    /// A solid line (exact curves).
    Line,
    /// A dashed line (theory, estimates).
    Dashed,
    /// Markers only (numerical points).
    Points,
    /// Line with markers.
    #[allow(dead_code)] // part of the plotting API; no figure of this branch uses it
    LinePoints,
    /// Hollow triangles only (a second kind of numerical points).
    Triangles,
}

/// One curve of a figure. A series with an empty label is drawn but gets
/// no legend entry; a series without points gets only its legend entry
/// (to explain a marker or line style once for many series).
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

/// A tick label: the value rounded to 3 significant digits, in its shortest
/// form (`1e-5`, `2.5e-7`, `0.02`, `1000`), so that log-axis ticks such as
/// 9.999999999998e-5 read `1e-4`.
fn tick(v: f64) -> String {
    if v == 0.0 || !v.is_finite() {
        return format!("{v}");
    }
    let r: f64 = format!("{v:.2e}").parse().unwrap_or(v);
    if (1e-3..1e5).contains(&r.abs()) {
        format!("{r}")
    } else {
        format!("{r:e}")
    }
}

/// Where the legend goes: the corner that covers the fewest data points.
fn legend_position(fig: &Figure, x: (f64, f64), y: (f64, f64)) -> SeriesLabelPosition {
    let norm = |v: f64, (lo, hi): (f64, f64), log: bool| {
        if log {
            (v.log10() - lo.log10()) / (hi.log10() - lo.log10())
        } else {
            (v - lo) / (hi - lo)
        }
    };
    let entries = fig.series.iter().filter(|s| !s.label.is_empty()).count() as f64;
    let longest = fig
        .series
        .iter()
        .map(|s| s.label.chars().count())
        .max()
        .unwrap_or(0) as f64;
    // The legend box as a fraction of the plotting area (14 px font, ~780 × 480 px area).
    let (w, h) = (
        ((longest * 7.5 + 50.0) / 780.0).min(0.9),
        ((entries * 19.0 + 12.0) / 480.0).min(0.95),
    );
    let corners = [
        (SeriesLabelPosition::UpperRight, 1.0 - w, 1.0, 1.0 - h, 1.0),
        (SeriesLabelPosition::UpperLeft, 0.0, w, 1.0 - h, 1.0),
        (SeriesLabelPosition::LowerRight, 1.0 - w, 1.0, 0.0, h),
        (SeriesLabelPosition::LowerLeft, 0.0, w, 0.0, h),
    ];
    let mut best = (usize::MAX, SeriesLabelPosition::UpperRight);
    for (pos, x0, x1, y0, y1) in corners {
        let mut covered = 0;
        for s in &fig.series {
            // Lines count along their length: sample between the points.
            let pts: Vec<(f64, f64)> = s
                .points
                .iter()
                .filter(|p| p.0.is_finite() && p.1.is_finite())
                .filter(|p| (!fig.x_log || p.0 > 0.0) && (!fig.y_log || p.1 > 0.0))
                .map(|p| (norm(p.0, x, fig.x_log), norm(p.1, y, fig.y_log)))
                .collect();
            let mut probe = |u: f64, v: f64| {
                if u >= x0 - 0.02 && u <= x1 + 0.02 && v >= y0 - 0.03 && v <= y1 + 0.03 {
                    covered += 1;
                }
            };
            for (i, p) in pts.iter().enumerate() {
                probe(p.0, p.1);
                if let (Some(q), Mark::Line | Mark::Dashed | Mark::LinePoints) =
                    (pts.get(i + 1), s.mark)
                {
                    for k in 1..8 {
                        let t = k as f64 / 8.0;
                        probe(p.0 + t * (q.0 - p.0), p.1 + t * (q.1 - p.1));
                    }
                }
            }
        }
        if covered < best.0 {
            best = (covered, pos);
        }
    }
    best.1
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
                    .x_label_formatter(&|v| tick(*v))
                    .y_label_formatter(&|v| tick(*v))
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
                        Mark::Triangles => chart
                            .draw_series(
                                pts.into_iter()
                                    .map(|p| TriangleMarker::new(p, 5, c.stroke_width(2))),
                            )
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
                    if s.label.is_empty() {
                        continue;
                    }
                    let mark = s.mark;
                    anno.label(s.label.clone())
                        .legend(move |(x, y)| match mark {
                            Mark::Points => Circle::new((x + 10, y), 4, c.filled()).into_dyn(),
                            Mark::Triangles => {
                                TriangleMarker::new((x + 10, y), 5, c.stroke_width(2)).into_dyn()
                            }
                            Mark::Dashed => plotters::element::DashedPathElement::new(
                                vec![(x, y), (x + 22, y)],
                                6,
                                4,
                                c.stroke_width(2),
                            )
                            .into_dyn(),
                            Mark::Line | Mark::LinePoints => {
                                PathElement::new(vec![(x, y), (x + 20, y)], c.stroke_width(2))
                                    .into_dyn()
                            }
                        });
                }
                chart
                    .configure_series_labels()
                    .background_style(WHITE.mix(0.85))
                    .border_style(RGBColor(160, 160, 160))
                    .label_font(("sans-serif", 14))
                    .position(legend_position(self, (x0, x1), (y0, y1)))
                    .draw()
                    .map_err(|e| anyhow!("{e:?}"))?;
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
    fn tick_labels_are_short() {
        assert_eq!(tick(9.999999999998e-5), "1e-4");
        assert_eq!(tick(100.00000000001), "100");
        assert_eq!(tick(0.30000000000000004), "0.3");
        assert_eq!(tick(2.5e-7), "2.5e-7");
        assert_eq!(tick(1e6), "1e6");
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
