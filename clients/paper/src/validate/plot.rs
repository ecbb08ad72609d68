//! SVG of the cycle's average force field (model, from k) over the plate,
//! with centers, parts, requested and simulated forces (like the paper's
//! Fig. 7).

use anyhow::anyhow;
use plotters::prelude::*;
use upm_solver::field::cycle_force;

use super::measure::Measured;
use crate::solve_json::SolveInput;

pub fn draw(path: &std::path::Path, input: &SolveInput, k: &[f64], m: &Measured) -> anyhow::Result<()> {
    let (hx, hy) = (1.0, 0.5);
    let xs = input.centers.iter().map(|c| c[0].abs()).fold(hx, f64::max) + 0.1;
    let ys = input.centers.iter().map(|c| c[1].abs()).fold(hy, f64::max) + 0.1;
    let root = SVGBackend::new(path, (1000, (1000.0 * ys / xs) as u32 + 60)).into_drawing_area();
    root.fill(&WHITE).map_err(|e| anyhow!("{e}"))?;
    let mut chart = ChartBuilder::on(&root)
        .caption("average force field (model: grey, requested: blue, simulated: red)", ("sans-serif", 18))
        .margin(10)
        .x_label_area_size(30)
        .y_label_area_size(40)
        .build_cartesian_2d(-xs..xs, -ys..ys)
        .map_err(|e| anyhow!("{e}"))?;
    chart.configure_mesh().disable_mesh().draw().map_err(|e| anyhow!("{e}"))?;
    // Arrow length: the largest field value maps to 0.8 grid spacing.
    let step = 0.1;
    let mut grid = Vec::new();
    let (nx, ny) = ((2.0 * hx / step) as i32, (2.0 * hy / step) as i32);
    for i in 0..=nx {
        for j in 0..=ny {
            let p = [-hx + i as f64 * step, -hy + j as f64 * step];
            if input.centers.iter().all(|c| (p[0] - c[0]).hypot(p[1] - c[1]) > 1e-6) {
                grid.push((p, cycle_force(k, &input.centers, input.mu_m_g, p)));
            }
        }
    }
    let fmax = grid.iter().map(|(_, f)| f[0].hypot(f[1])).fold(1e-300, f64::max);
    let scale = 0.8 * step / fmax;
    let arrow = |p: [f64; 2], f: [f64; 2]| vec![(p[0], p[1]), (p[0] + scale * f[0], p[1] + scale * f[1])];
    let grey = RGBColor(150, 150, 150);
    for (p, f) in &grid {
        chart.draw_series(LineSeries::new(arrow(*p, *f), &grey)).map_err(|e| anyhow!("{e}"))?;
        chart
            .draw_series(std::iter::once(Circle::new((p[0], p[1]), 1, grey.filled())))
            .map_err(|e| anyhow!("{e}"))?;
    }
    // Plate outline.
    let outline = vec![(-hx, -hy), (hx, -hy), (hx, hy), (-hx, hy), (-hx, -hy)];
    chart.draw_series(LineSeries::new(outline, &BLACK)).map_err(|e| anyhow!("{e}"))?;
    for c in &input.centers {
        chart
            .draw_series(std::iter::once(Cross::new((c[0], c[1]), 6, BLACK.stroke_width(2))))
            .map_err(|e| anyhow!("{e}"))?;
    }
    for (p, s) in input.parts.iter().zip(&m.forces) {
        chart
            .draw_series(std::iter::once(Circle::new((p.position[0], p.position[1]), 5, BLACK.filled())))
            .map_err(|e| anyhow!("{e}"))?;
        if let Some(f) = p.force {
            chart
                .draw_series(LineSeries::new(arrow(p.position, f), BLUE.stroke_width(3)))
                .map_err(|e| anyhow!("{e}"))?;
        }
        chart
            .draw_series(LineSeries::new(arrow(p.position, *s), RED.stroke_width(2)))
            .map_err(|e| anyhow!("{e}"))?;
    }
    for c in &input.curls {
        let (x, y) = (c.position[0], c.position[1]);
        chart
            .draw_series(std::iter::once(Circle::new((x, y), 12, if c.curl < 0.0 { RED } else { BLUE })))
            .map_err(|e| anyhow!("{e}"))?;
    }
    root.present().map_err(|e| anyhow!("{e}"))?;
    Ok(())
}
