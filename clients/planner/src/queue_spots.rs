//! Where a part waits while every pick pose of its class is taken: spots
//! far enough apart that waiting parts never touch, off every pose's
//! clearance and out of the corridor the parts travel through (the convex
//! hull of the infeed region and the poses, widened by a part's reach and
//! the gap), so waiting parts block no way in; nearest a pose first.

/// A pick pose as the spots see it: its position and its part's reach (m).
#[derive(Debug, Clone, Copy)]
pub struct PoseZone {
    pub position: [f64; 2],
    pub reach: f64,
}

/// How far from the pick zone counts against a spot, per metre from the
/// plate's middle: spots on the far side come last.
const FAR_SIDE_WEIGHT: f64 = 0.25;
/// At most this many grid points are looked at (a one-off, at start).
const MAX_CANDIDATES: f64 = 40_000.0;

/// Up to `max` spots for parts reaching `reach` (m) on a plate of
/// `half_extent`, best first; `gap` (m) is kept between parts and beyond
/// each pose's `clearance`. `infeed` (`[x0, y0, x1, y1]`, m) is where the
/// parts arrive: spots keep out of the corridor from it to the poses
/// unless nothing else is left.
pub fn queue_spots(
    poses: &[PoseZone],
    infeed: Option<[f64; 4]>,
    reach: f64,
    clearance: f64,
    gap: f64,
    half_extent: [f64; 2],
    max: usize,
) -> Vec<[f64; 2]> {
    let [hx, hy] = half_extent;
    let mut spacing = 2.0 * reach + gap;
    // Tiny parts on a large plate: fewer, wider spots rather than a huge grid.
    spacing = spacing.max((4.0 * hx * hy / MAX_CANDIDATES).sqrt());
    let keep_out = |z: &PoseZone| z.reach + clearance + reach + gap;
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for z in poses {
        for a in 0..2 {
            lo[a] = lo[a].min(z.position[a] - keep_out(z));
            hi[a] = hi[a].max(z.position[a] + keep_out(z));
        }
    }
    if poses.is_empty() {
        (lo, hi) = ([0.0; 2], [0.0; 2]);
    }
    let centre = [0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1])];
    let to_zone = |p: [f64; 2]| {
        let d = |a: usize| (lo[a] - p[a]).max(p[a] - hi[a]).max(0.0);
        d(0).hypot(d(1))
    };
    let to_pose = |p: [f64; 2]| {
        poses.iter().map(|z| (p[0] - z.position[0]).hypot(p[1] - z.position[1])).fold(f64::INFINITY, f64::min)
    };
    let mut corners: Vec<[f64; 2]> = poses.iter().map(|z| z.position).collect();
    if let Some([x0, y0, x1, y1]) = infeed {
        corners.extend([[x0, y0], [x1, y0], [x1, y1], [x0, y1]]);
    }
    let corridor = convex_hull(corners);
    let corridor_margin = reach + gap;
    let (xmax, ymax) = (hx - reach - gap, hy - reach - gap);
    // Grid points aligned on the pick zone's centre, on the plate.
    let steps = |c: f64, limit: f64| {
        let lo = ((-limit - c) / spacing).ceil() as i64;
        let hi = ((limit - c) / spacing).floor() as i64;
        lo..=hi
    };
    let mut outside = Vec::new();
    let mut inside = Vec::new();
    for i in steps(centre[0], xmax) {
        for j in steps(centre[1], ymax) {
            let p = [centre[0] + i as f64 * spacing, centre[1] + j as f64 * spacing];
            if poses.iter().any(|z| (p[0] - z.position[0]).hypot(p[1] - z.position[1]) < keep_out(z)) {
                continue;
            }
            let key =
                if infeed.is_some() { to_pose(p) } else { to_zone(p) + FAR_SIDE_WEIGHT * p[0].hypot(p[1]) };
            let clear = if infeed.is_some() {
                distance_outside(&corridor, p) >= corridor_margin
            } else {
                to_zone(p) > 0.0
            };
            if clear { outside.push((key, p)) } else { inside.push((key, p)) }
        }
    }
    // Inside the zone or corridor only when nothing else is left.
    let by_key = |a: &(f64, [f64; 2]), b: &(f64, [f64; 2])| a.0.total_cmp(&b.0);
    outside.sort_by(by_key);
    inside.sort_by(by_key);
    outside.into_iter().chain(inside).map(|(_, p)| p).take(max).collect()
}

/// The convex hull of `points`, counter-clockwise (monotone chain).
fn convex_hull(mut points: Vec<[f64; 2]>) -> Vec<[f64; 2]> {
    points.sort_by(|a, b| a[0].total_cmp(&b[0]).then(a[1].total_cmp(&b[1])));
    points.dedup();
    if points.len() < 3 {
        return points;
    }
    let cross =
        |o: [f64; 2], a: [f64; 2], b: [f64; 2]| (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0]);
    let mut hull: Vec<[f64; 2]> = Vec::with_capacity(2 * points.len());
    for pass in 0..2 {
        let start = hull.len();
        let iter: Box<dyn Iterator<Item = &[f64; 2]>> =
            if pass == 0 { Box::new(points.iter()) } else { Box::new(points.iter().rev()) };
        for &p in iter {
            while hull.len() >= start + 2 && cross(hull[hull.len() - 2], hull[hull.len() - 1], p) <= 0.0 {
                hull.pop();
            }
            hull.push(p);
        }
        hull.pop();
    }
    hull
}

/// How far `p` lies outside the convex polygon `hull` (0 inside it).
fn distance_outside(hull: &[[f64; 2]], p: [f64; 2]) -> f64 {
    let n = hull.len();
    let segment = |a: [f64; 2], b: [f64; 2]| {
        let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
        let l2 = dx * dx + dy * dy;
        let u = if l2 > 0.0 { (((p[0] - a[0]) * dx + (p[1] - a[1]) * dy) / l2).clamp(0.0, 1.0) } else { 0.0 };
        (p[0] - a[0] - u * dx).hypot(p[1] - a[1] - u * dy)
    };
    match n {
        0 => f64::INFINITY,
        1 => segment(hull[0], hull[0]),
        2 => segment(hull[0], hull[1]),
        _ => {
            let inside = (0..n).all(|i| {
                let (a, b) = (hull[i], hull[(i + 1) % n]);
                (b[0] - a[0]) * (p[1] - a[1]) - (b[1] - a[1]) * (p[0] - a[0]) >= 0.0
            });
            if inside {
                0.0
            } else {
                (0..n).map(|i| segment(hull[i], hull[(i + 1) % n])).fold(f64::INFINITY, f64::min)
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn spots_keep_off_every_pose_and_apart_and_on_the_plate() {
        let poses = [
            PoseZone { position: [0.7, 0.25], reach: 0.015 },
            PoseZone { position: [0.85, -0.25], reach: 0.0212 },
        ];
        let (reach, clearance, gap) = (0.0212, 0.005, 0.005);
        let spots = queue_spots(&poses, None, reach, clearance, gap, [1.0, 0.5], 64);
        assert_eq!(spots.len(), 64);
        for (i, s) in spots.iter().enumerate() {
            assert!(s[0].abs() + reach <= 1.0 && s[1].abs() + reach <= 0.5, "{s:?}");
            for z in &poses {
                let d = (s[0] - z.position[0]).hypot(s[1] - z.position[1]);
                assert!(d >= z.reach + clearance + reach, "{s:?} in {z:?}'s clearance");
            }
            for t in &spots[..i] {
                assert!((s[0] - t[0]).hypot(s[1] - t[1]) >= 2.0 * reach, "{s:?} {t:?}");
            }
        }
        // The best spot is near the zone, on the plate's middle side.
        assert!(spots[0][0] < 0.7 && spots[0][0] > 0.5, "{:?}", spots[0]);
    }

    #[test]
    fn a_plate_too_small_for_any_spot_gives_none() {
        let poses = [PoseZone { position: [0.0, 0.0], reach: 0.02 }];
        assert!(queue_spots(&poses, None, 0.02, 0.005, 0.005, [0.04, 0.04], 64).is_empty());
    }

    #[test]
    fn spots_keep_out_of_the_corridor_from_the_infeed() {
        let poses = [
            PoseZone { position: [0.7, 0.25], reach: 0.015 },
            PoseZone { position: [0.7, -0.25], reach: 0.015 },
        ];
        let infeed = [-0.9, -0.4, -0.6, 0.4];
        let spots = queue_spots(&poses, Some(infeed), 0.0212, 0.005, 0.005, [1.0, 0.5], 16);
        assert_eq!(spots.len(), 16);
        let corridor = convex_hull(vec![
            [0.7, 0.25],
            [0.7, -0.25],
            [-0.9, -0.4],
            [-0.6, -0.4],
            [-0.6, 0.4],
            [-0.9, 0.4],
        ]);
        for s in &spots {
            assert!(distance_outside(&corridor, *s) >= 0.0212 + 0.005, "{s:?} in the corridor");
        }
        // Between the poses is the corridor: nothing waits there.
        assert!(spots.iter().all(|s| !(s[0] < 0.7 && s[1].abs() < 0.25)), "{spots:?}");
    }
}
