//! `trails.svg`: the plate, rotation centers, and every part's trail from
//! start (open circle) to end (filled), coloured by class (paper Fig. 8/9).

use std::path::Path;

use anyhow::anyhow;
use plotters::prelude::*;

use super::recorder::Trails;

pub fn draw_trails(
    path: &Path,
    title: &str,
    half: [f64; 2],
    centers: &[[f64; 2]],
    trails: &Trails,
) -> anyhow::Result<()> {
    let e = |e: &dyn std::fmt::Display| anyhow!("{e}");
    let xs = centers.iter().map(|c| c[0].abs()).fold(half[0], f64::max) + 0.05;
    let ys = centers.iter().map(|c| c[1].abs()).fold(half[1], f64::max) + 0.05;
    let root = SVGBackend::new(path, (1000, (1000.0 * ys / xs) as u32 + 60)).into_drawing_area();
    root.fill(&WHITE).map_err(|x| e(&x))?;
    let mut chart = ChartBuilder::on(&root)
        .caption(title, ("sans-serif", 18))
        .margin(10)
        .x_label_area_size(30)
        .y_label_area_size(40)
        .build_cartesian_2d(-xs..xs, -ys..ys)
        .map_err(|x| e(&x))?;
    chart.configure_mesh().disable_mesh().draw().map_err(|x| e(&x))?;
    let plate = [
        (-half[0], -half[1]),
        (half[0], -half[1]),
        (half[0], half[1]),
        (-half[0], half[1]),
        (-half[0], -half[1]),
    ];
    chart.draw_series(LineSeries::new(plate, BLACK.stroke_width(2))).map_err(|x| e(&x))?;
    chart
        .draw_series(centers.iter().map(|c| Cross::new((c[0], c[1]), 6, RED.stroke_width(2))))
        .map_err(|x| e(&x))?;
    let palette = [BLACK, RGBColor(120, 120, 120), BLUE, GREEN, MAGENTA, CYAN];
    for (id, trail) in &trails.parts {
        let color = palette[trail.class as usize % palette.len()];
        let pts: Vec<(f64, f64)> = trail.points.iter().map(|p| (p[1], p[2])).collect();
        chart.draw_series(LineSeries::new(pts.iter().copied(), color.stroke_width(1))).map_err(|x| e(&x))?;
        if let (Some(a), Some(b)) = (pts.first(), pts.last()) {
            chart.draw_series([Circle::new(*a, 5, color.stroke_width(1))]).map_err(|x| e(&x))?;
            chart.draw_series([Circle::new(*b, 5, color.filled())]).map_err(|x| e(&x))?;
            chart
                .draw_series([Text::new(format!("{id}"), (b.0 + 0.01, b.1 + 0.01), ("sans-serif", 12))])
                .map_err(|x| e(&x))?;
        }
    }
    root.present().map_err(|x| e(&x))?;
    Ok(())
}
