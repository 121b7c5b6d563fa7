//! The side view of a settled bed (`bed_side.svg/png`): the particles as
//! circles, the floor's boundary particles and contact plane under them,
//! on equal scales; the x axis spans the bed's extent (a narrow bed gets a
//! narrow chart, centred), not the picture's width.

use dembound_scene::wall_study;
use plotters::prelude::*;

/// Side view (x–z) of a settled bed: every particle a circle, the floor's
/// boundary particles and contact plane drawn under it. SVG and PNG.
pub(super) fn side_view(b: &wall_study::Bed, label: &str) -> anyhow::Result<(String, Vec<u8>)> {
    crate::plot::register_font();
    let size = (900u32, 600u32);
    let mut svg = String::new();
    draw_side(
        SVGBackend::with_string(&mut svg, size).into_drawing_area(),
        b,
        label,
        size,
    )?;
    let mut rgb = vec![0u8; (size.0 * size.1 * 3) as usize];
    draw_side(
        BitMapBackend::with_buffer(&mut rgb, size).into_drawing_area(),
        b,
        label,
        size,
    )?;
    let mut png_bytes = Vec::new();
    {
        let mut encoder = png::Encoder::new(&mut png_bytes, size.0, size.1);
        encoder.set_color(png::ColorType::Rgb);
        encoder.set_depth(png::BitDepth::Eight);
        let mut writer = encoder.write_header()?;
        writer.write_image_data(&rgb)?;
    }
    Ok((svg, png_bytes))
}

fn draw_side<DB: DrawingBackend>(
    area: DrawingArea<DB, plotters::coord::Shift>,
    b: &wall_study::Bed,
    label: &str,
    size: (u32, u32),
) -> anyhow::Result<()>
where
    DB::ErrorType: 'static,
{
    let e = |e: DrawingAreaErrorKind<DB::ErrorType>| anyhow::anyhow!("{e:?}");
    let r = b.spheres.first().map_or(1e-3, |s| s.2);
    let x0 = -r;
    let x1 = b.side + r;
    let top = b.height + 2.0 * r;
    let bottom = -0.15 * (x1 - x0) - 2.0 * r;
    area.fill(&WHITE).map_err(e)?;
    let (w, h) = size;
    // Equal scales on both axes.
    let plot_w = f64::from(w) - 120.0;
    let plot_h = f64::from(h) - 110.0;
    let scale = (plot_w / (x1 - x0)).min(plot_h / (top - bottom));
    // The chart as wide as the bed at that scale (plus the labels' 120
    // px), centred; the caption over the whole picture.
    let used_w = ((x1 - x0) * scale + 120.0).min(f64::from(w));
    let left = ((f64::from(w) - used_w) / 2.0).max(0.0);
    let (xz1, zz1) = (x0 + (used_w - 120.0) / scale, bottom + plot_h / scale);
    let titled = area
        .titled(
            &format!("Bed on the floor \"{label}\": side view"),
            ("sans-serif", 22),
        )
        .map_err(e)?;
    let chart_h = titled.dim_in_pixel().1;
    let chart_area = titled.shrink((left as i32, 0), (used_w as u32, chart_h));
    let mut chart = ChartBuilder::on(&chart_area)
        .margin(15)
        .x_label_area_size(45)
        .y_label_area_size(70)
        .build_cartesian_2d(x0 * 1e3..xz1 * 1e3, bottom * 1e3..zz1 * 1e3)
        .map_err(e)?;
    chart
        .configure_mesh()
        .x_desc("x (mm)")
        .y_desc("z (mm)")
        .disable_mesh()
        .draw()
        .map_err(e)?;
    let px = |rr: f64| ((rr * scale).round() as i32).max(1);
    // Boundary spheres can be far larger than the view: each is drawn as
    // its upper outline within the view, filled down to the view's bottom
    // (a circle element would not be clipped to the chart).
    let (vx0, vx1, vz0, vz1) = (x0, xz1, bottom, zz1);
    for &(xc, zc, rr) in &b.floor_spheres {
        let (a, c) = ((xc - rr).max(vx0), (xc + rr).min(vx1));
        if a >= c {
            continue;
        }
        let mut outline: Vec<(f64, f64)> = (0..=200)
            .map(|k| {
                let x = a + (c - a) * f64::from(k) / 200.0;
                let dz = (rr * rr - (x - xc) * (x - xc)).max(0.0).sqrt();
                (x * 1e3, (zc + dz).clamp(vz0, vz1) * 1e3)
            })
            .collect();
        outline.push((c * 1e3, vz0 * 1e3));
        outline.push((a * 1e3, vz0 * 1e3));
        chart
            .draw_series(std::iter::once(Polygon::new(
                outline,
                RGBColor(190, 190, 190).filled(),
            )))
            .map_err(e)?;
    }
    chart
        .draw_series(std::iter::once(PathElement::new(
            vec![(x0 * 1e3, 0.0), (x1 * 1e3, 0.0)],
            BLACK.stroke_width(1),
        )))
        .map_err(e)?;
    chart
        .draw_series(b.spheres.iter().map(|&(x, z, rr)| {
            Circle::new(
                (x * 1e3, z * 1e3),
                px(rr),
                RGBColor(31, 119, 180).stroke_width(1),
            )
        }))
        .map_err(e)?;
    area.present().map_err(e)?;
    Ok(())
}
