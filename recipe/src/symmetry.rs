//! How often an outline repeats as it turns, and an angle error modulo it.

use core::f64::consts::TAU;

use crate::outline::Outline;

impl Outline {
    /// The largest n such that turning the outline by 2π/n maps it onto
    /// itself (1 for an asymmetric polygon); 0 for a disc, whose angle
    /// never matters.
    pub fn symmetry_order(&self) -> u32 {
        match self {
            Self::Disc { .. } => 0,
            Self::Polygon(v) => polygon_order(v),
        }
    }
}

/// Vertices match when this close, over the outline's reach: recipes
/// write coordinates to a few decimals (a hexagon's √3).
const MATCH_TOLERANCE: f64 = 1e-3;

/// The largest n dividing the vertex count that maps the vertex set onto
/// itself; 1 if none does.
fn polygon_order(v: &[[f64; 2]]) -> u32 {
    let reach = v.iter().map(|p| p[0].hypot(p[1])).fold(0.0, f64::max);
    let tol = MATCH_TOLERANCE * reach;
    let count = v.len();
    (2..=count)
        .rev()
        .filter(|n| count.is_multiple_of(*n))
        .find(|&n| {
            let (s, c) = (TAU / n as f64).sin_cos();
            v.iter().all(|p| {
                let q = [c * p[0] - s * p[1], s * p[0] + c * p[1]];
                v.iter().any(|w| (w[0] - q[0]).hypot(w[1] - q[1]) <= tol)
            })
        })
        .map_or(1, |n| n as u32)
}

/// `angle − target` wrapped into [−π/n, π/n) for an outline of symmetry
/// `order` n; 0 for a disc (order 0).
pub fn angle_error(angle: f64, target: f64, order: u32) -> f64 {
    if order == 0 {
        return 0.0;
    }
    let period = TAU / f64::from(order);
    let e = (angle - target + 0.5 * period).rem_euclid(period) - 0.5 * period;
    // A huge angle leaves rem_euclid nothing finite to work with.
    if e.is_finite() { e } else { 0.0 }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn squares_repeat_four_times_triangles_three_and_a_kite_once() {
        let square = [[-1.0, -1.0], [1.0, -1.0], [1.0, 1.0], [-1.0, 1.0]];
        let triangle: Vec<[f64; 2]> =
            (0..3).map(|k| (TAU * k as f64 / 3.0).sin_cos()).map(|(s, c)| [c, s]).collect();
        let kite = [[0.0, -1.0], [1.0, 0.0], [0.0, 2.0], [-1.0, 0.0]];
        assert_eq!(Outline::Polygon(square.to_vec()).symmetry_order(), 4);
        assert_eq!(Outline::Polygon(triangle).symmetry_order(), 3);
        assert_eq!(Outline::Polygon(kite.to_vec()).symmetry_order(), 1);
        assert_eq!(Outline::Disc { radius: 0.01 }.symmetry_order(), 0);
        assert!((angle_error(1.6, 0.0, 4) - (1.6 - core::f64::consts::FRAC_PI_2)).abs() < 1e-12);
        assert!((angle_error(-0.1, 6.2, 1) - (-0.1 - 6.2 + TAU)).abs() < 1e-12);
        assert_eq!(angle_error(2.0, 0.0, 0), 0.0);
    }
}
