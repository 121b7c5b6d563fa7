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
use plotters::element::DynElement;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};
use std::path::{Path, PathBuf};
use std::sync::Once;

/// Pixel size of every figure.
const SIZE: (u32, u32) = (900, 600);

/// Black for text drawn outside the chart.
const BLACK_RGB: RGBColor = RGBColor(0, 0, 0);

static FONT: &[u8] = include_bytes!("../assets/DejaVuSans.ttf");
static REGISTER: Once = Once::new();

pub fn register_font() {
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
    /// A solid line with markers of this shape (one shape per curve).
    LineShape(Shape),
    /// Markers of this shape only.
    Shape(Shape),
}

/// Marker shapes, so that curves differ by more than colour.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Shape {
    Circle,
    Square,
    Triangle,
    Diamond,
    HollowCircle,
    HollowSquare,
    Cross,
}

/// The shapes in the order curves take them.
pub const SHAPES: [Shape; 6] = [
    Shape::Circle,
    Shape::Square,
    Shape::Triangle,
    Shape::Diamond,
    Shape::HollowCircle,
    Shape::HollowSquare,
];

/// A marker of `shape` centred at `at` (data or pixel coordinates), with a
/// short line through it when `line` (legend samples of line series).
fn marker<'a, DB: DrawingBackend + 'a, C: Clone + 'a>(
    shape: Shape,
    at: C,
    c: RGBColor,
    line: bool,
) -> DynElement<'a, DB, C> {
    // Without a line the path has no length (nothing is drawn).
    let half = if line { 11 } else { 0 };
    let e = EmptyElement::at(at) + PathElement::new(vec![(-half, 0), (half, 0)], c.stroke_width(2));
    match shape {
        Shape::Circle => (e + Circle::new((0, 0), 4, c.filled())).into_dyn(),
        Shape::HollowCircle => {
            (e + Circle::new((0, 0), 4, WHITE.filled()) + Circle::new((0, 0), 4, c.stroke_width(2)))
                .into_dyn()
        }
        Shape::Square => (e + Rectangle::new([(-4, -4), (4, 4)], c.filled())).into_dyn(),
        Shape::HollowSquare => (e
            + Rectangle::new([(-4, -4), (4, 4)], WHITE.filled())
            + Rectangle::new([(-4, -4), (4, 4)], c.stroke_width(2)))
        .into_dyn(),
        Shape::Triangle => (e + TriangleMarker::new((0, 0), 5, c.filled())).into_dyn(),
        Shape::Diamond => {
            (e + Polygon::new(vec![(0, -6), (5, 0), (0, 6), (-5, 0)], c.filled())).into_dyn()
        }
        Shape::Cross => (e + Cross::new((0, 0), 4, c.stroke_width(2))).into_dyn(),
    }
}

/// The legend's sample of a series drawn as `mark`, its left end at (x, y).
fn legend_glyph<'a, DB: DrawingBackend + 'a>(
    mark: Mark,
    c: RGBColor,
    (x, y): (i32, i32),
) -> DynElement<'a, DB, (i32, i32)> {
    match mark {
        Mark::Points => Circle::new((x + 10, y), 4, c.filled()).into_dyn(),
        Mark::Triangles => TriangleMarker::new((x + 10, y), 5, c.stroke_width(2)).into_dyn(),
        Mark::Dashed => plotters::element::DashedPathElement::new(
            vec![(x, y), (x + 22, y)],
            6,
            4,
            c.stroke_width(2),
        )
        .into_dyn(),
        Mark::Line | Mark::LinePoints => {
            PathElement::new(vec![(x, y), (x + 20, y)], c.stroke_width(2)).into_dyn()
        }
        Mark::Shape(shape) => marker(shape, (x + 11, y), c, false),
        Mark::LineShape(shape) => marker(shape, (x + 11, y), c, true),
    }
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
    /// Where ∞ is drawn on the x axis (a position beyond the largest finite
    /// value, see [`infinity_position`]): labelled `∞`, marked by a dotted
    /// line, tick labels beyond the finite values left out.
    pub x_infinity: Option<f64>,
    /// The legend to the right of the plotting area, outside the data
    /// (otherwise in the corner that covers the fewest points).
    pub legend_outside: bool,
}

/// Where ∞ goes on an axis whose finite values are `values`: a decade above
/// the largest on a log axis, a quarter of the range beyond it on a linear
/// one (at 1 when there is no finite value).
pub fn infinity_position(values: &[f64], log: bool) -> f64 {
    let finite = values.iter().copied().filter(|v| v.is_finite());
    let (lo, hi) = finite.fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), v| {
        (l.min(v), h.max(v))
    });
    if !hi.is_finite() {
        1.0
    } else if log {
        10.0 * hi
    } else if hi > lo {
        hi + 0.25 * (hi - lo)
    } else {
        hi + 0.25 * hi.abs().max(1.0)
    }
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
                if let (
                    Some(q),
                    Mark::Line | Mark::Dashed | Mark::LinePoints | Mark::LineShape(_),
                ) = (pts.get(i + 1), s.mark)
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

    /// Width in pixels of the legend column of a figure `width` wide.
    fn legend_width(&self, width: u32) -> u32 {
        let longest = self
            .series
            .iter()
            .filter(|s| !s.label.is_empty())
            .map(|s| s.label.chars().count())
            .max()
            .unwrap_or(0) as u32;
        (longest * 8 + 56).clamp(120, width * 2 / 5)
    }

    fn draw<DB: DrawingBackend>(&self, root: DrawingArea<DB, Shift>) -> Result<()>
    where
        DB::ErrorType: 'static,
    {
        let ((x0, x1), (y0, y1)) = self.ranges()?;
        root.fill(&WHITE).map_err(|e| anyhow!("{e:?}"))?;
        // With the legend outside: the title over the whole width, the
        // chart on the left, the legend column on the right.
        let (area, legend_area) = if self.legend_outside {
            let titled = root
                .titled(&self.title, ("sans-serif", 22))
                .map_err(|e| anyhow!("{e:?}"))?;
            let width = titled.dim_in_pixel().0;
            let (chart, legend) = titled.split_horizontally(width - self.legend_width(width));
            (chart, Some(legend))
        } else {
            (root.clone(), None)
        };
        let mut builder = ChartBuilder::on(&area);
        if !self.legend_outside {
            builder.caption(&self.title, ("sans-serif", 22));
        }
        builder
            .margin(14)
            .x_label_area_size(52)
            .y_label_area_size(84);
        // Tick labels beyond the finite values would read as values: only ∞ is labelled there.
        let finite_max = self
            .series
            .iter()
            .flat_map(|s| s.points.iter().map(|p| p.0))
            .filter(|x| x.is_finite() && !self.x_infinity.is_some_and(|inf| *x >= inf))
            .fold(f64::NEG_INFINITY, f64::max);
        // A tick at zero computed as 1e-17 reads 0 (linear axes only reach it).
        let near_zero = |v: f64, lo: f64, hi: f64| v.abs() <= 1e-9 * (hi - lo).abs();
        let x_tick = |v: &f64| match self.x_infinity {
            Some(_) if *v > finite_max * (1.0 + 1e-9) + 1e-300 => String::new(),
            _ if near_zero(*v, x0, x1) => "0".into(),
            _ => tick(*v),
        };
        let y_tick = |v: &f64| {
            if near_zero(*v, y0, y1) {
                "0".into()
            } else {
                tick(*v)
            }
        };
        // One concrete element type per shape (no boxing in data coordinates).
        macro_rules! shapes {
            ($chart:expr, $pts:expr, $shape:expr, $c:expr) => {{
                let (pts, c) = ($pts, $c);
                let at = |p: (f64, f64)| EmptyElement::at(p);
                match $shape {
                    Shape::Circle => $chart.draw_series(
                        pts.into_iter()
                            .map(|p| at(p) + Circle::new((0, 0), 4, c.filled())),
                    ),
                    Shape::HollowCircle => $chart.draw_series(pts.into_iter().map(|p| {
                        at(p)
                            + Circle::new((0, 0), 4, WHITE.filled())
                            + Circle::new((0, 0), 4, c.stroke_width(2))
                    })),
                    Shape::Square => $chart.draw_series(
                        pts.into_iter()
                            .map(|p| at(p) + Rectangle::new([(-4, -4), (4, 4)], c.filled())),
                    ),
                    Shape::HollowSquare => $chart.draw_series(pts.into_iter().map(|p| {
                        at(p)
                            + Rectangle::new([(-4, -4), (4, 4)], WHITE.filled())
                            + Rectangle::new([(-4, -4), (4, 4)], c.stroke_width(2))
                    })),
                    Shape::Triangle => $chart.draw_series(
                        pts.into_iter()
                            .map(|p| at(p) + TriangleMarker::new((0, 0), 5, c.filled())),
                    ),
                    Shape::Diamond => $chart.draw_series(pts.into_iter().map(|p| {
                        at(p) + Polygon::new(vec![(0, -6), (5, 0), (0, 6), (-5, 0)], c.filled())
                    })),
                    Shape::Cross => $chart.draw_series(
                        pts.into_iter()
                            .map(|p| at(p) + Cross::new((0, 0), 4, c.stroke_width(2))),
                    ),
                }
                .map_err(|e| anyhow!("{e:?}"))?
            }};
        }
        macro_rules! finish {
            ($chart:expr) => {{
                let mut chart = $chart;
                chart
                    .configure_mesh()
                    .x_desc(&self.x_label)
                    .y_desc(&self.y_label)
                    .axis_desc_style(("sans-serif", 17))
                    .x_label_formatter(&x_tick)
                    .y_label_formatter(&y_tick)
                    .label_style(("sans-serif", 14))
                    .light_line_style(RGBColor(235, 235, 235))
                    .draw()
                    .map_err(|e| anyhow!("{e:?}"))?;
                if let Some(inf) = self.x_infinity {
                    chart
                        .draw_series(DashedLineSeries::new(
                            vec![(inf, y0), (inf, y1)],
                            3,
                            4,
                            RGBColor(150, 150, 150).stroke_width(1),
                        ))
                        .map_err(|e| anyhow!("{e:?}"))?;
                    let (px, py) = chart.backend_coord(&(inf, y0));
                    root.draw(&Text::new(
                        "∞",
                        (px, py + 6),
                        ("sans-serif", 20)
                            .into_font()
                            .color(&BLACK_RGB)
                            .pos(Pos::new(HPos::Center, VPos::Top)),
                    ))
                    .map_err(|e| anyhow!("{e:?}"))?;
                }
                let mut legend: Vec<(String, Mark, RGBColor)> = Vec::new();
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
                        Mark::LineShape(shape) => {
                            chart
                                .draw_series(LineSeries::new(pts.clone(), c.stroke_width(2)))
                                .map_err(|e| anyhow!("{e:?}"))?;
                            shapes!(chart, pts, shape, c)
                        }
                        Mark::Shape(shape) => shapes!(chart, pts, shape, c),
                    };
                    if s.label.is_empty() {
                        continue;
                    }
                    if self.legend_outside {
                        legend.push((s.label.clone(), s.mark, c));
                        continue;
                    }
                    let mark = s.mark;
                    // Inside the chart plotters draws the legend (concrete
                    // elements: a boxed one would need a 'static backend).
                    anno.label(s.label.clone())
                        .legend(move |(x, y)| match mark {
                            Mark::Points | Mark::Shape(_) => {
                                Circle::new((x + 10, y), 4, c.filled()).into_dyn()
                            }
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
                            Mark::Line | Mark::LinePoints | Mark::LineShape(_) => {
                                PathElement::new(vec![(x, y), (x + 20, y)], c.stroke_width(2))
                                    .into_dyn()
                            }
                        });
                }
                if let Some(area) = &legend_area {
                    // One entry per line from the top of the plotting area down.
                    let (_, top) = chart.backend_coord(&(x0, y1));
                    let (left, _) = area.get_base_pixel();
                    let (_, root_top) = root.get_base_pixel();
                    for (i, (label, mark, c)) in legend.iter().enumerate() {
                        let y = top - root_top + 10 + 22 * i as i32;
                        let x = left + 6;
                        root.draw(&legend_glyph(*mark, *c, (x, y)))
                            .map_err(|e| anyhow!("{e:?}"))?;
                        root.draw(&Text::new(
                            label.clone(),
                            (x + 30, y),
                            ("sans-serif", 14)
                                .into_font()
                                .color(&BLACK_RGB)
                                .pos(Pos::new(HPos::Left, VPos::Center)),
                        ))
                        .map_err(|e| anyhow!("{e:?}"))?;
                    }
                } else {
                    chart
                        .configure_series_labels()
                        .background_style(WHITE.mix(0.85))
                        .border_style(RGBColor(160, 160, 160))
                        .label_font(("sans-serif", 14))
                        .position(legend_position(self, (x0, x1), (y0, y1)))
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

    /// The figure as SVG text and PNG bytes (900×600 px), for writing
    /// through an [`AtomicDir`](crate::output::files::AtomicDir).
    pub fn render(&self) -> Result<(String, Vec<u8>)> {
        register_font();
        let (w, h) = SIZE;
        let mut svg = String::new();
        self.draw(SVGBackend::with_string(&mut svg, SIZE).into_drawing_area())?;
        let mut rgb = vec![0u8; (w * h * 3) as usize];
        self.draw(BitMapBackend::with_buffer(&mut rgb, SIZE).into_drawing_area())?;
        let mut png_bytes = Vec::new();
        {
            let mut encoder = png::Encoder::new(&mut png_bytes, w, h);
            encoder.set_compression(png::Compression::Best);
            encoder.set_color(png::ColorType::Rgb);
            encoder.set_depth(png::BitDepth::Eight);
            let mut writer = encoder.write_header()?;
            writer.write_image_data(&rgb)?;
        }
        Ok((svg, png_bytes))
    }

    /// Stages `<stem>.svg` and `<stem>.png` in `out`; returns their names.
    pub fn write_into(
        &self,
        out: &mut crate::output::files::AtomicDir,
        stem: &str,
    ) -> Result<[String; 2]> {
        let (svg, png_bytes) = self.render()?;
        let names = [format!("{stem}.svg"), format!("{stem}.png")];
        out.write(&names[0], |w| Ok(w.write_all(svg.as_bytes())?))?;
        out.write(&names[1], |w| Ok(w.write_all(&png_bytes)?))?;
        Ok(names)
    }

    /// Writes `<stem>.svg` and `<stem>.png` (900×600 px); returns both paths.
    pub fn write(&self, stem: &Path) -> Result<[PathBuf; 2]> {
        register_font();
        let svg_path = stem.with_extension("svg");
        let png_path = stem.with_extension("png");
        let dir = stem.parent().unwrap_or_else(|| Path::new("."));
        let size = SIZE;

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
            ..Default::default()
        };
        let [svg, png] = fig.write(&dir.path().join("fig")).expect("figure written");
        let text = std::fs::read_to_string(svg).expect("svg readable");
        // Axis labels with units end up in the SVG text.
        assert!(text.contains("relative error (1)"));
        // A PNG with text is well over a few kB; an empty canvas compresses to ~2 kB.
        assert!(std::fs::metadata(png).map(|m| m.len()).unwrap_or(0) > 10_000);
    }

    #[test]
    fn infinity_goes_beyond_the_finite_values() {
        assert_eq!(
            infinity_position(&[1.0, 10.0, 100.0, f64::INFINITY], true),
            1000.0
        );
        assert_eq!(infinity_position(&[1.0, 5.0], false), 6.0);
        assert_eq!(infinity_position(&[f64::INFINITY], true), 1.0);
    }

    #[test]
    fn legend_outside_and_infinity_render_in_memory() {
        let fig = Figure {
            title: "deviation".into(),
            x_label: "r (1)".into(),
            y_label: "deviation (1)".into(),
            x_log: true,
            y_log: true,
            series: vec![
                Series::new(
                    "ζ = 1",
                    vec![(1.0, 0.3), (10.0, 0.1), (1000.0, 0.05)],
                    Mark::LineShape(Shape::Square),
                    0,
                ),
                Series::new("", vec![(1.0, 0.31)], Mark::Shape(Shape::Cross), 0),
            ],
            x_infinity: Some(1000.0),
            legend_outside: true,
        };
        let (svg, png) = fig.render().expect("rendered");
        assert!(svg.contains("∞") && svg.contains("ζ = 1"));
        assert!(png.starts_with(b"\x89PNG") && png.len() > 10_000);
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
