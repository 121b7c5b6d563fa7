//! The picture of a covered part (`particle-wall`): the boundary spheres
//! seen along a fixed oblique direction, orthographic, drawn far to near
//! (painter's order) as disks of their true radius, coloured by what made
//! them (face lattice blue, corner red, edge orange, fill green) and shaded by depth. Axes are the
//! screen's in metres.

use crate::plot::register_font;
use anyhow::{anyhow, Result};
use dembound_scene::sources::mesh_tiling::{Covering, Origin};
use plotters::prelude::*;
use std::path::Path;

/// Pixel size of the picture.
const SIZE: (u32, u32) = (1000, 900);

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn unit(a: [f64; 3]) -> [f64; 3] {
    let l = dot(a, a).sqrt();
    a.map(|x| x / l)
}

fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// The view direction (from the viewer into the scene) and the screen
/// axes: looking down at 35° from the direction (−1, −1.6) in x–y.
pub fn view() -> ([f64; 3], [f64; 3], [f64; 3]) {
    let toward = unit([0.45, 0.72, -0.53]);
    let right = unit(cross(toward, [0.0, 0.0, 1.0]));
    let up = cross(right, toward);
    (toward, right, up)
}

/// Writes the picture of `c` to `png` (PNG).
pub fn write(c: &Covering, png: &Path, title: &str) -> Result<()> {
    write_marked(c, png, title, &[])
}

/// [`write`], with `marks` (points, m) drawn on top as red crosses (seen
/// through the spheres: a mark behind the part shows too).
pub fn write_marked(c: &Covering, png: &Path, title: &str, marks: &[[f64; 3]]) -> Result<()> {
    register_font();
    let (toward, right, up) = view();
    let r = c.options.radius;
    let mut order: Vec<usize> = (0..c.spheres.len()).collect();
    let depth = |i: usize| dot(c.spheres[i].position, toward);
    // Far first: the largest depth along the view direction.
    order.sort_by(|&a, &b| depth(b).total_cmp(&depth(a)).then(a.cmp(&b)));
    let (mut x0, mut x1, mut y0, mut y1) = (
        f64::INFINITY,
        f64::NEG_INFINITY,
        f64::INFINITY,
        f64::NEG_INFINITY,
    );
    let (mut d0, mut d1) = (f64::INFINITY, f64::NEG_INFINITY);
    for s in &c.spheres {
        let (x, y, d) = (
            dot(s.position, right),
            dot(s.position, up),
            dot(s.position, toward),
        );
        x0 = x0.min(x - r);
        x1 = x1.max(x + r);
        y0 = y0.min(y - r);
        y1 = y1.max(y + r);
        d0 = d0.min(d);
        d1 = d1.max(d);
    }
    if c.spheres.is_empty() {
        (x0, x1, y0, y1) = (-1.0, 1.0, -1.0, 1.0);
    }
    // Equal scales on both axes: pad the shorter range.
    let plot_w = SIZE.0 as f64 - 110.0;
    let plot_h = SIZE.1 as f64 - 110.0;
    let scale = ((x1 - x0) / plot_w).max((y1 - y0) / plot_h);
    let (cx, cy) = (0.5 * (x0 + x1), 0.5 * (y0 + y1));
    let (hw, hh) = (0.5 * scale * plot_w, 0.5 * scale * plot_h);
    let root = BitMapBackend::new(png, SIZE).into_drawing_area();
    let err = |e: &dyn std::fmt::Display| anyhow!("cannot draw `{}`: {e}", png.display());
    root.fill(&WHITE).map_err(|e| err(&e))?;
    let mut chart = ChartBuilder::on(&root)
        .caption(title, ("sans-serif", 20))
        .margin(10)
        .x_label_area_size(50)
        .y_label_area_size(60)
        .build_cartesian_2d(cx - hw..cx + hw, cy - hh..cy + hh)
        .map_err(|e| err(&e))?;
    chart
        .configure_mesh()
        .disable_mesh()
        .x_desc("screen x (m)")
        .y_desc("screen y (m)")
        .draw()
        .map_err(|e| err(&e))?;
    let (px_w, _) = chart.plotting_area().dim_in_pixel();
    let px_per_m = px_w as f64 / (2.0 * hw);
    let radius_px = (r * px_per_m).max(1.0) as i32;
    let base = |o: Origin| match o {
        Origin::Face => (70.0, 120.0, 200.0),
        Origin::Corner => (200.0, 50.0, 50.0),
        Origin::Edge => (230.0, 150.0, 40.0),
        Origin::Fill => (60.0, 170.0, 80.0),
    };
    let span = (d1 - d0).max(1e-300);
    chart
        .draw_series(order.iter().flat_map(|&i| {
            let s = &c.spheres[i];
            let p = (dot(s.position, right), dot(s.position, up));
            // Near spheres brighter: 0.55 (far) to 1 (near).
            let light = 0.55 + 0.45 * (d1 - depth(i)) / span;
            let (r0, g0, b0) = base(c.origin[i]);
            let fill = RGBColor((r0 * light) as u8, (g0 * light) as u8, (b0 * light) as u8);
            [
                Circle::new(p, radius_px, fill.filled()),
                Circle::new(p, radius_px, RGBColor(30, 30, 30).stroke_width(1)),
            ]
        }))
        .map_err(|e| err(&e))?;
    if !marks.is_empty() {
        chart
            .draw_series(marks.iter().map(|&m| {
                let p = (dot(m, right), dot(m, up));
                Cross::new(p, 6, RGBColor(220, 0, 0).stroke_width(2))
            }))
            .map_err(|e| err(&e))?;
    }
    root.present().map_err(|e| err(&e))?;
    Ok(())
}
