//! The outline of a part class as camera and vision both know it: a disc,
//! or a regular polygon (square, equilateral triangle) given by its
//! circumradius. A polygon's orientation is seen modulo its symmetry (90°
//! for a square, 120° for a triangle); a disc has none.
//!
//! Angles follow the simulator's parts: at θ = 0 a square's edges are
//! parallel to the axes (vertices at 45°), a triangle has a vertex on +x.

use core::f64::consts::{PI, TAU};

use ipc_types::{MAX_SHAPE_VERTICES, PartState, SHAPE_DISC, SHAPE_POINT, SHAPE_POLYGON};
use serde::{Deserialize, Serialize};

#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Deserialize, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum ClassOutline {
    #[default]
    Disc,
    Square,
    Triangle,
}

impl ClassOutline {
    /// Vertices of the polygon (0 for a disc).
    pub const fn corners(self) -> u32 {
        match self {
            Self::Disc => 0,
            Self::Square => 4,
            Self::Triangle => 3,
        }
    }

    /// The angle after which the outline repeats (rad); 0 for a disc.
    pub fn period(self) -> f64 {
        match self.corners() {
            0 => 0.0,
            n => TAU / n as f64,
        }
    }

    /// Direction of the first vertex at θ = 0.
    pub fn first_vertex(self) -> f64 {
        match self {
            Self::Square => PI / 4.0,
            Self::Disc | Self::Triangle => 0.0,
        }
    }

    /// Area (m², or px² for a radius in px) for circumradius `r`.
    pub fn area(self, r: f64) -> f64 {
        match self.corners() {
            0 => PI * r * r,
            n => {
                let n = n as f64;
                0.5 * n * r * r * (TAU / n).sin()
            }
        }
    }

    /// Whether the point `(dx, dy)` from the centre lies inside the
    /// outline of circumradius `r` turned by `theta`.
    pub fn contains(self, r: f64, theta: f64, dx: f64, dy: f64) -> bool {
        self.outline(r, theta).contains(dx, dy)
    }

    /// The outline of circumradius `r` turned by `theta`, ready for many
    /// [`Outline::contains`] tests.
    pub fn outline(self, r: f64, theta: f64) -> Outline {
        let n = self.corners() as usize;
        let mut normals = [[0.0; 2]; 4];
        for (k, normal) in normals.iter_mut().enumerate().take(n) {
            // Edge normals lie halfway between vertices.
            let a = theta + self.first_vertex() + (k as f64 + 0.5) * TAU / n as f64;
            *normal = [a.cos(), a.sin()];
        }
        Outline { normals, edges: n, radius: r, inradius: self.inradius(r) }
    }

    /// Radius of the largest disc inside the outline (circumradius `r`).
    pub fn inradius(self, r: f64) -> f64 {
        match self.corners() {
            0 => r,
            n => r * (PI / n as f64).cos(),
        }
    }

    /// `angle` brought into one period centred on 0 (unchanged for a disc).
    pub fn wrap(self, angle: f64) -> f64 {
        wrap_period(angle, self.period())
    }

    /// The contact outline of circumradius `r` (m) in the part's own frame,
    /// as `PartStates` carries it: a disc, or the polygon at θ = 0 (first
    /// vertex at [`Self::first_vertex`]), counter-clockwise.
    pub fn body_outline(self, r: f64) -> BodyOutline {
        let n = self.corners() as usize;
        if n == 0 {
            return BodyOutline { shape: SHAPE_DISC, radius: r, ..BodyOutline::POINT };
        }
        let mut vertices = [[0.0; 2]; MAX_SHAPE_VERTICES];
        for (k, v) in vertices.iter_mut().take(n).enumerate() {
            let a = self.first_vertex() + k as f64 * TAU / n as f64;
            *v = [r * a.cos(), r * a.sin()];
        }
        BodyOutline { shape: SHAPE_POLYGON, vertex_count: n as u32, vertices, ..BodyOutline::POINT }
    }
}

/// A part's contact outline in its own frame (m, about its position),
/// exactly the outline fields of a `PartState`: carried from a detection
/// through the tracker to the published part.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BodyOutline {
    /// `SHAPE_POINT`, `SHAPE_DISC` or `SHAPE_POLYGON`.
    pub shape: u32,
    pub radius: f64,
    pub vertex_count: u32,
    pub vertices: [[f64; 2]; MAX_SHAPE_VERTICES],
}

impl BodyOutline {
    /// No outline: the paper's point part.
    pub const POINT: Self =
        Self { shape: SHAPE_POINT, radius: 0.0, vertex_count: 0, vertices: [[0.0; 2]; MAX_SHAPE_VERTICES] };

    /// The outline `part` carries, as it is (checking is the core's).
    pub const fn of(part: &PartState) -> Self {
        Self {
            shape: part.shape,
            radius: part.radius,
            vertex_count: part.vertex_count,
            vertices: part.vertices,
        }
    }

    /// `part` with this outline.
    pub const fn put_on(&self, mut part: PartState) -> PartState {
        part.shape = self.shape;
        part.radius = self.radius;
        part.vertex_count = self.vertex_count;
        part.vertices = self.vertices;
        part
    }
}

/// A placed outline: a disc, or a convex polygon by its edge normals.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Outline {
    normals: [[f64; 2]; 4],
    edges: usize,
    radius: f64,
    inradius: f64,
}

impl Outline {
    /// Whether `(dx, dy)` from the centre lies inside.
    pub fn contains(&self, dx: f64, dy: f64) -> bool {
        if self.edges == 0 {
            return dx * dx + dy * dy <= self.radius * self.radius;
        }
        self.normals[..self.edges].iter().all(|n| dx * n[0] + dy * n[1] <= self.inradius)
    }
}

/// `angle` into `(-period/2, period/2]`; a period of 0 leaves it as is.
pub fn wrap_period(angle: f64, period: f64) -> f64 {
    if period > 0.0 { angle - period * (angle / period).round() } else { angle }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn areas_match_the_polygons() {
        assert!((ClassOutline::Square.area(2f64.sqrt()) - 4.0).abs() < 1e-12);
        let side = 3f64.sqrt();
        assert!((ClassOutline::Triangle.area(1.0) - 3f64.sqrt() / 4.0 * side * side).abs() < 1e-12);
    }

    #[test]
    fn square_at_zero_has_axis_parallel_edges() {
        let s = ClassOutline::Square;
        let r = 2f64.sqrt(); // side 2
        assert!(s.contains(r, 0.0, 0.99, 0.99));
        assert!(!s.contains(r, 0.0, 1.01, 0.0));
        // Turned by 45°: a vertex on +x.
        assert!(s.contains(r, PI / 4.0, 1.4, 0.0));
    }

    #[test]
    fn triangle_at_zero_points_along_x() {
        let t = ClassOutline::Triangle;
        assert!(t.contains(1.0, 0.0, 0.99, 0.0));
        assert!(!t.contains(1.0, 0.0, -0.99, 0.0));
        assert!(t.contains(1.0, PI, -0.99, 0.0));
    }

    /// What detection relies on: with a vertex on +x, Σ (x + iy)ⁿ over a
    /// regular n-gon is real and positive.
    #[test]
    fn a_vertex_on_x_gives_a_positive_real_moment() {
        for shape in [ClassOutline::Triangle, ClassOutline::Square] {
            let n = shape.corners() as i32;
            let (mut re, mut im) = (0.0, 0.0);
            let steps = 200;
            for i in -steps..=steps {
                for j in -steps..=steps {
                    let (x, y) = (i as f64 / steps as f64, j as f64 / steps as f64);
                    if shape.contains(1.0, -shape.first_vertex(), x, y) {
                        let (rho, phi) = (x.hypot(y), y.atan2(x));
                        re += rho.powi(n) * (n as f64 * phi).cos();
                        im += rho.powi(n) * (n as f64 * phi).sin();
                    }
                }
            }
            // The grid breaks the symmetry a little at the edges.
            assert!(re > 0.0 && im.abs() < 1e-2 * re, "{shape:?}: {re} {im}");
        }
    }

    /// The outline published for a class is the one rendered and detected:
    /// its vertices, turned by θ, are the corners of [`ClassOutline::outline`].
    #[test]
    fn body_outline_is_the_class_polygon_at_zero_counter_clockwise() {
        let r = 0.02;
        let disc = ClassOutline::Disc.body_outline(r);
        let part = PartState::new(1, 0, 0, [0.0; 3], [0.0; 3]);
        assert_eq!(disc.put_on(part), part.with_disc(r));
        for (shape, first) in [(ClassOutline::Square, PI / 4.0), (ClassOutline::Triangle, 0.0)] {
            let o = shape.body_outline(r);
            let p = o.put_on(part);
            assert_eq!(p.check_shape(1.0), Ok(()), "{shape:?}");
            assert_eq!(p.polygon().len(), shape.corners() as usize);
            assert_eq!(BodyOutline::of(&p), o);
            let v = p.polygon();
            assert_eq!(Ok(p), part.with_polygon(v));
            assert!((v[0][1].atan2(v[0][0]) - first).abs() < 1e-12, "{shape:?}: {v:?}");
            let area2: f64 = (0..v.len())
                .map(|i| {
                    let (a, b) = (v[i], v[(i + 1) % v.len()]);
                    a[0] * b[1] - b[0] * a[1]
                })
                .sum();
            assert!((0.5 * area2 - shape.area(r)).abs() < 1e-15, "{shape:?}: counter-clockwise");
            for theta in [0.0, 0.3, -2.0] {
                let outline = shape.outline(r, theta);
                for q in v {
                    assert!((q[0].hypot(q[1]) - r).abs() < 1e-15);
                    let (c, s) = (theta.cos(), theta.sin());
                    let turned = [c * q[0] - s * q[1], s * q[0] + c * q[1]];
                    assert!(outline.contains(0.999 * turned[0], 0.999 * turned[1]), "{shape:?} {theta}");
                    assert!(!outline.contains(1.001 * turned[0], 1.001 * turned[1]), "{shape:?} {theta}");
                }
            }
        }
    }

    #[test]
    fn wrap_keeps_the_angle_within_half_a_period() {
        let s = ClassOutline::Square;
        for a in [-7.0, -1.0, -0.7, 0.0, 0.3, 0.78, 2.0, 9.0] {
            let w = s.wrap(a);
            assert!(w.abs() <= PI / 4.0 + 1e-12, "{a} -> {w}");
            let turns = (a - w) / s.period();
            assert!((turns - turns.round()).abs() < 1e-9);
        }
        assert_eq!(ClassOutline::Disc.wrap(5.0), 5.0);
    }
}
