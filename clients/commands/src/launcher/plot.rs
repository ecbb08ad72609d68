//! `trails.svg`: the plate, rotation centers, a feed cell's pick poses
//! (a square turned to the pose's θ, in its class's colour), and every
//! part's trail from start (open circle) to end (filled), coloured by class
//! (paper Fig. 8/9).

use std::path::Path;

use anyhow::anyhow;
use plotters::prelude::*;

use super::observer::Trails;

/// A pick pose to draw: class, x, y, θ.
pub type PickMark = (u32, [f64; 3]);

/// Half the side of a pick pose's mark (m).
const POSE_MARK_M: f64 = 0.02;

pub fn draw_trails(
    path: &Path,
    title: &str,
    half: [f64; 2],
    centers: &[[f64; 2]],
    poses: &[PickMark],
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
    for (class, [x, y, theta]) in poses {
        let color = palette[*class as usize % palette.len()];
        let (c, s) = (theta.cos() * POSE_MARK_M, theta.sin() * POSE_MARK_M);
        let corner = |u: f64, v: f64| (x + u * c - v * s, y + u * s + v * c);
        let square =
            [corner(1.0, 1.0), corner(-1.0, 1.0), corner(-1.0, -1.0), corner(1.0, -1.0), corner(1.0, 1.0)];
        chart.draw_series(LineSeries::new(square, color.stroke_width(2))).map_err(|x| e(&x))?;
        // The pose's x axis, so its angle shows.
        chart
            .draw_series(LineSeries::new([(*x, *y), corner(1.6, 0.0)], color.stroke_width(2)))
            .map_err(|x| e(&x))?;
    }
    for (id, trail) in &trails.parts {
        let color = palette[trail.class as usize % palette.len()];
        let pts = thinned(trail.points.iter().map(|p| (p[1], p[2])), 0.001 * xs);
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

/// The points of a trail without those closer than `step` to the last one
/// kept (about a pixel), so a long run's picture stays small; the last point
/// is always kept.
fn thinned(points: impl Iterator<Item = (f64, f64)>, step: f64) -> Vec<(f64, f64)> {
    let mut out: Vec<(f64, f64)> = Vec::new();
    let mut skipped = None;
    for p in points {
        match out.last() {
            Some(q) if (p.0 - q.0).hypot(p.1 - q.1) < step => skipped = Some(p),
            _ => {
                out.push(p);
                skipped = None;
            }
        }
    }
    out.extend(skipped);
    out
}

#[cfg(test)]
mod tests {
    use super::thinned;

    #[test]
    fn thinning_keeps_the_ends_and_drops_sub_step_points() {
        let pts = [(0.0, 0.0), (0.0001, 0.0), (0.0002, 0.0), (0.01, 0.0), (0.0101, 0.0)];
        assert_eq!(thinned(pts.into_iter(), 0.001), vec![(0.0, 0.0), (0.01, 0.0), (0.0101, 0.0)]);
        assert!(thinned(std::iter::empty(), 0.001).is_empty());
    }
}
