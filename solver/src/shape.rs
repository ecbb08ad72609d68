//! Extended parts: what one rotation does to a part's whole contact patch.
//!
//! A slot about c drags every point q of a part at rest along the unit
//! tangent t(q) = R90(q − c)/|q − c| (the plate slips under it everywhere,
//! the paper's assumption), so with uniform pressure the part feels μmg
//! times the patch average of t(q) — not t at its centre, the paper's point
//! model — and about its centroid g the torque μmg·m times the average of
//! (q − g) × t(q). A shaped part's rows are that average force and the
//! curl a uniform field would need to give that torque, 2τ̄/ρ² (ρ² = I/m):
//! for a point far from c both reduce to the paper's t(p) and 1/r, so a
//! curl request means the same for every shape.
//!
//! **Discs** (radius R, d = |p − c|/R): by symmetry the average is
//! g(d)·t(p) and the torque R·h(d). In polar coordinates about c only the
//! arc of each circle inside the disc matters, so g and h are 1-D
//! integrals; they are tabulated once per process (`TABLE_NODES` nodes,
//! uniform in d/(1 + d), linear between), and beyond d = `FAR` the far
//! field g = 1 − 1/(8d²), h = 1/(4d) is used. **Convex polygons** (up to
//! [`MAX_SHAPE_VERTICES`]): the pressure model of the simulator, a fan of
//! triangles from the centroid, each pressed at its three edge midpoints
//! with a third of its area (exact for quadratics, so a far center's
//! torque is exact; 3 points per vertex).
//!
//! **Limits:** the part is taken at rest; a sliding part's own velocity
//! (which makes the drag anisotropic) is not in these rows — the solve
//! stage's part-dynamics correction (`upm_motion::PartDynamics`) adds it
//! around the solve, linearized about the reported state. A disc is
//! pressed uniformly; a polygon at its fan's edge midpoints.

use std::sync::OnceLock;

pub use ipc_types::part_shape::{MAX_SHAPE_VERTICES, ShapeError};

/// The contact patch of a part, relative to its position.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub enum PartShape {
    /// The paper's model: the field at the part's position.
    #[default]
    Point,
    Disc {
        radius: f64,
    },
    /// A convex polygon, vertices relative to the part's position, in
    /// order (either winding); `count` of them are used.
    Polygon {
        vertices: [[f64; 2]; MAX_SHAPE_VERTICES],
        count: usize,
    },
}

impl PartShape {
    /// A part's outline as the wire carries it, turned by its `theta` into
    /// plate axes (a validated `PartState`; an unknown code is a point).
    pub fn from_wire(p: &ipc_types::PartState) -> Self {
        match p.shape {
            ipc_types::SHAPE_DISC => Self::Disc { radius: p.radius },
            ipc_types::SHAPE_POLYGON => {
                let (sin, cos) = p.theta.sin_cos();
                let mut vertices = [[0.0; 2]; MAX_SHAPE_VERTICES];
                for (out, v) in vertices.iter_mut().zip(p.polygon()) {
                    *out = [cos * v[0] - sin * v[1], sin * v[0] + cos * v[1]];
                }
                Self::Polygon { vertices, count: p.polygon().len() }
            }
            _ => Self::Point,
        }
    }

    /// A polygon from its vertices (relative to the part's position).
    pub fn polygon(vertices: &[[f64; 2]]) -> Result<Self, ShapeError> {
        if !(3..=MAX_SHAPE_VERTICES).contains(&vertices.len()) {
            return Err(ShapeError::VertexCount);
        }
        let mut v = [[0.0; 2]; MAX_SHAPE_VERTICES];
        v[..vertices.len()].copy_from_slice(vertices);
        let s = Self::Polygon { vertices: v, count: vertices.len() };
        s.check()?;
        Ok(s)
    }

    /// Whether the shape is one the model can integrate (the wire's
    /// check, without its size bound).
    pub fn check(&self) -> Result<(), ShapeError> {
        match *self {
            Self::Point => Ok(()),
            Self::Disc { radius } => ipc_types::part_shape::check_disc(radius, f64::INFINITY),
            Self::Polygon { vertices, count } => {
                let v = vertices.get(..count).ok_or(ShapeError::VertexCount)?;
                ipc_types::part_shape::check_polygon(v, f64::INFINITY)
            }
        }
    }
}

/// A checked shape's rows for a rotation about `c`, the part at `p`: the
/// patch-average unit tangent (x, y) and the curl-equivalent of its torque
/// (module doc). For a point: t(p) and 1/|p − c|.
pub fn wrench_row(shape: &PartShape, p: [f64; 2], c: [f64; 2]) -> ([f64; 2], f64) {
    match *shape {
        PartShape::Point => {
            let (dx, dy) = (p[0] - c[0], p[1] - c[1]);
            let r = (dx * dx + dy * dy).sqrt();
            ([-dy / r, dx / r], 1.0 / r)
        }
        PartShape::Disc { radius } => {
            let (dx, dy) = (p[0] - c[0], p[1] - c[1]);
            let r = (dx * dx + dy * dy).sqrt();
            let (g, h) = disc_gh(r / radius);
            // At the centre (r = 0) no direction is preferred: g(0) = 0.
            let t = if r > 0.0 { [-dy / r, dx / r] } else { [0.0, 0.0] };
            ([g * t[0], g * t[1]], 4.0 * h / radius)
        }
        PartShape::Polygon { .. } => patch_row(&shape.patch_points(), p, c),
    }
}

/// Rings and spokes of a disc's contact points in [`PartShape::patch_points`].
const DISC_RINGS: usize = 6;
const DISC_SPOKES: usize = 16;

/// Most points [`PartShape::patch_points`] gives.
pub const MAX_PATCH_POINTS: usize = DISC_RINGS * DISC_SPOKES;

// A polygon's three points per fan triangle fit too.
const _: () = assert!(3 * MAX_SHAPE_VERTICES <= MAX_PATCH_POINTS);

/// Where a checked shape presses on the plate: points relative to the
/// part's centroid with weights summing to 1 (a disc: equal-area rings;
/// a polygon: its fan's edge midpoints, as in [`wrench_row`]), how many,
/// the centroid relative to the part's position, and ρ² = I/m.
#[derive(Debug, Clone, Copy)]
pub struct PatchPoints {
    pub points: [([f64; 2], f64); MAX_PATCH_POINTS],
    pub count: usize,
    pub centroid: [f64; 2],
    pub rho2: f64,
}

impl PartShape {
    pub fn patch_points(&self) -> PatchPoints {
        let mut out = PatchPoints {
            points: [([0.0; 2], 0.0); MAX_PATCH_POINTS],
            count: 0,
            centroid: [0.0; 2],
            rho2: 0.0,
        };
        match *self {
            Self::Point => {
                out.points[0] = ([0.0; 2], 1.0);
                out.count = 1;
            }
            Self::Disc { radius } => {
                let w = 1.0 / MAX_PATCH_POINTS as f64;
                for i in 0..DISC_RINGS {
                    let r = radius * ((i as f64 + 0.5) / DISC_RINGS as f64).sqrt();
                    for j in 0..DISC_SPOKES {
                        let a =
                            core::f64::consts::TAU * (j as f64 + 0.5 * (i % 2) as f64) / DISC_SPOKES as f64;
                        out.points[out.count] = ([r * a.cos(), r * a.sin()], w);
                        out.count += 1;
                    }
                }
                out.rho2 = 0.5 * radius * radius;
            }
            Self::Polygon { vertices, count } => {
                let v = &vertices[..count];
                let (area, g) = area_and_centroid(v);
                out.centroid = g;
                for i in 0..count {
                    let a = [v[i][0] - g[0], v[i][1] - g[1]];
                    let b = [v[(i + 1) % count][0] - g[0], v[(i + 1) % count][1] - g[1]];
                    let tri = 0.5 * (a[0] * b[1] - a[1] * b[0]).abs();
                    out.rho2 += tri
                        * (a[0] * a[0] + a[1] * a[1] + b[0] * b[0] + b[1] * b[1] + a[0] * b[0] + a[1] * b[1])
                        / 6.0;
                    for q in [
                        [a[0] / 2.0, a[1] / 2.0],
                        [(a[0] + b[0]) / 2.0, (a[1] + b[1]) / 2.0],
                        [b[0] / 2.0, b[1] / 2.0],
                    ] {
                        out.points[out.count] = (q, tri / (3.0 * area));
                        out.count += 1;
                    }
                }
                out.rho2 /= area;
            }
        }
        out
    }
}

fn area_and_centroid(v: &[[f64; 2]]) -> (f64, [f64; 2]) {
    let (mut a2, mut cx, mut cy) = (0.0, 0.0, 0.0);
    for i in 0..v.len() {
        let (p, q) = (v[i], v[(i + 1) % v.len()]);
        let cross = p[0] * q[1] - q[0] * p[1];
        a2 += cross;
        cx += (p[0] + q[0]) * cross;
        cy += (p[1] + q[1]) * cross;
    }
    (0.5 * a2.abs(), [cx / (3.0 * a2), cy / (3.0 * a2)])
}

/// [`wrench_row`] for each of `centers` in turn, a polygon's patch built
/// once for all of them.
pub fn for_each_wrench_row(
    shape: &PartShape,
    p: [f64; 2],
    centers: &[[f64; 2]],
    mut each: impl FnMut(usize, [f64; 2], f64),
) {
    if let PartShape::Polygon { .. } = shape {
        let patch = shape.patch_points();
        for (j, &c) in centers.iter().enumerate() {
            let (t, curl) = patch_row(&patch, p, c);
            each(j, t, curl);
        }
    } else {
        for (j, &c) in centers.iter().enumerate() {
            let (t, curl) = wrench_row(shape, p, c);
            each(j, t, curl);
        }
    }
}

fn patch_row(patch: &PatchPoints, p: [f64; 2], c: [f64; 2]) -> ([f64; 2], f64) {
    let g = [p[0] + patch.centroid[0], p[1] + patch.centroid[1]];
    let (mut f, mut tau) = ([0.0; 2], 0.0);
    for &(q, w) in &patch.points[..patch.count] {
        let (dx, dy) = (g[0] + q[0] - c[0], g[1] + q[1] - c[1]);
        let r = (dx * dx + dy * dy).sqrt();
        if r > 0.0 {
            let t = [-dy / r, dx / r];
            f[0] += w * t[0];
            f[1] += w * t[1];
            tau += w * (q[0] * t[1] - q[1] * t[0]);
        }
    }
    (f, 2.0 * tau / patch.rho2)
}

/// Nodes of the disc table, uniform in x = d/(1 + d) on [0, x(FAR)].
const TABLE_NODES: usize = 4096;
/// Beyond this many radii the far-field series is used.
const FAR: f64 = 64.0;
/// Midpoint steps per segment of the 1-D integrals.
const STEPS: usize = 400;

/// g(d) and h(d) of a unit disc whose centre is d from the rotation's.
fn disc_gh(d: f64) -> (f64, f64) {
    if d >= FAR {
        return (1.0 - 1.0 / (8.0 * d * d), 1.0 / (4.0 * d));
    }
    let table = disc_table();
    let x = d / (1.0 + d) / (FAR / (1.0 + FAR)) * (TABLE_NODES - 1) as f64;
    let i = (x.floor() as usize).min(TABLE_NODES - 2);
    let t = x - i as f64;
    let (a, b) = (table[i], table[i + 1]);
    (a.0 + t * (b.0 - a.0), a.1 + t * (b.1 - a.1))
}

/// Build the per-process tables now (they allocate once, on first use).
pub(crate) fn build_tables() {
    disc_table();
}

fn disc_table() -> &'static [(f64, f64)] {
    static TABLE: OnceLock<Vec<(f64, f64)>> = OnceLock::new();
    TABLE.get_or_init(|| {
        let x_far = FAR / (1.0 + FAR);
        (0..TABLE_NODES)
            .map(|i| {
                let x = x_far * i as f64 / (TABLE_NODES - 1) as f64;
                disc_integrals(x / (1.0 - x))
            })
            .collect()
    })
}

/// g(d) = (1/π)∫ 2 sin φ(s) s ds and h(d) = (1/π)∫ 2(s φ(s) − d sin φ(s)) s ds,
/// φ(s) the half-angle of the arc of radius s about the rotation's centre
/// inside the unit disc at distance d. Each segment is integrated in t with
/// s = a + (b − a)(1 − cos t)/2, which smooths the square-root ends.
pub(crate) fn disc_integrals(d: f64) -> (f64, f64) {
    let half_angle = |s: f64| {
        if s <= 1.0 - d {
            core::f64::consts::PI
        } else {
            ((s * s + d * d - 1.0) / (2.0 * s * d)).clamp(-1.0, 1.0).acos()
        }
    };
    let segment = |a: f64, b: f64, acc: &mut (f64, f64)| {
        let dt = core::f64::consts::PI / STEPS as f64;
        for k in 0..STEPS {
            let t = (k as f64 + 0.5) * dt;
            let s = a + (b - a) * (1.0 - t.cos()) / 2.0;
            let ds = (b - a) * t.sin() / 2.0 * dt;
            let phi = half_angle(s);
            acc.0 += 2.0 * phi.sin() * s * ds;
            acc.1 += 2.0 * (s * phi - d * phi.sin()) * s * ds;
        }
    };
    let mut acc = (0.0, 0.0);
    if d < 1.0 {
        segment(0.0, 1.0 - d, &mut acc);
        segment(1.0 - d, 1.0 + d, &mut acc);
    } else {
        segment(d - 1.0, d + 1.0, &mut acc);
    }
    let pi = core::f64::consts::PI;
    (acc.0 / pi, acc.1 / pi)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The patch average by brute force: a fine Cartesian grid over the
    /// shape's bounding box, `inside` deciding membership.
    fn brute(inside: impl Fn([f64; 2]) -> bool, half: f64, p: [f64; 2], c: [f64; 2]) -> ([f64; 2], f64) {
        let n = 1200;
        let h = 2.0 * half / n as f64;
        let (mut cnt, mut f, mut tau, mut rho2, mut g) = (0.0, [0.0; 2], 0.0, 0.0, [0.0; 2]);
        let mut pts = Vec::new();
        for i in 0..n {
            for j in 0..n {
                let u = [-half + (i as f64 + 0.5) * h, -half + (j as f64 + 0.5) * h];
                if inside(u) {
                    pts.push(u);
                    g[0] += u[0];
                    g[1] += u[1];
                    cnt += 1.0;
                }
            }
        }
        g = [g[0] / cnt, g[1] / cnt];
        for u in pts {
            let q = [p[0] + u[0], p[1] + u[1]];
            let (dx, dy) = (q[0] - c[0], q[1] - c[1]);
            let r = dx.hypot(dy);
            let t = [-dy / r, dx / r];
            let a = [u[0] - g[0], u[1] - g[1]];
            f[0] += t[0];
            f[1] += t[1];
            tau += a[0] * t[1] - a[1] * t[0];
            rho2 += a[0] * a[0] + a[1] * a[1];
        }
        ([f[0] / cnt, f[1] / cnt], 2.0 * tau / rho2)
    }

    fn close(a: ([f64; 2], f64), b: ([f64; 2], f64), tol: f64) -> bool {
        let scale = a.0[0].hypot(a.0[1]).max(1e-3);
        (a.0[0] - b.0[0]).abs() <= tol * scale
            && (a.0[1] - b.0[1]).abs() <= tol * scale
            && (a.1 - b.1).abs() <= tol * a.1.abs().max(b.1.abs())
    }

    #[test]
    fn disc_rows_match_a_brute_force_average() {
        let radius = 0.02;
        let p = [0.1, -0.05];
        for d in [0.0, 0.3, 0.9, 1.0, 1.1, 1.5, 3.0, 20.0, 70.0] {
            let c = [p[0] - 0.6 * d * radius, p[1] + 0.8 * d * radius];
            let got = wrench_row(&PartShape::Disc { radius }, p, c);
            let want = brute(|u| u[0].hypot(u[1]) <= radius, radius, p, c);
            assert!(close(got, want, 2e-3), "d {d}: {got:?} vs {want:?}");
        }
    }

    #[test]
    fn far_from_the_center_every_shape_is_a_point() {
        let p = [0.3, 0.2];
        let c = [-0.7, 0.9];
        let point = wrench_row(&PartShape::Point, p, c);
        let disc = wrench_row(&PartShape::Disc { radius: 0.01 }, p, c);
        let square = PartShape::polygon(&[[-0.01, -0.01], [0.01, -0.01], [0.01, 0.01], [-0.01, 0.01]])
            .expect("square");
        for got in [disc, wrench_row(&square, p, c)] {
            assert!(close(got, point, 1e-3), "{got:?} vs {point:?}");
        }
    }

    #[test]
    fn polygon_rows_match_a_brute_force_average() {
        let tri = [[-0.02, -0.015], [0.025, -0.01], [0.0, 0.02]];
        let shape = PartShape::polygon(&tri).expect("triangle");
        let inside = |u: [f64; 2]| {
            (0..3).all(|i| {
                let (a, b) = (tri[i], tri[(i + 1) % 3]);
                (b[0] - a[0]) * (u[1] - a[1]) - (b[1] - a[1]) * (u[0] - a[0]) >= 0.0
            })
        };
        let p = [0.2, 0.1];
        // The edge-midpoint rule is exact for quadratics: close to uniform
        // pressure once the center is a few part sizes away.
        for (c, tol) in [([0.33, 0.1], 3e-2), ([0.2, 0.26], 3e-2), ([0.5, -0.3], 3e-3), ([2.0, 1.0], 3e-3)] {
            let got = wrench_row(&shape, p, c);
            let want = brute(inside, 0.03, p, c);
            assert!(close(got, want, tol), "c {c:?}: {got:?} vs {want:?}");
        }
    }

    #[test]
    fn patch_points_weigh_one_and_carry_the_second_moment() {
        let tri = PartShape::polygon(&[[-0.02, -0.015], [0.025, -0.01], [0.0, 0.02]]).expect("triangle");
        for shape in [PartShape::Point, PartShape::Disc { radius: 0.03 }, tri] {
            let p = shape.patch_points();
            let pts = &p.points[..p.count];
            let w: f64 = pts.iter().map(|(_, w)| w).sum();
            let first = pts.iter().fold([0.0; 2], |a, (q, w)| [a[0] + w * q[0], a[1] + w * q[1]]);
            let second: f64 = pts.iter().map(|(q, w)| w * (q[0] * q[0] + q[1] * q[1])).sum();
            assert!((w - 1.0).abs() < 1e-12, "{shape:?}: weights {w}");
            assert!(
                first[0].abs() < 1e-12 && first[1].abs() < 1e-12,
                "{shape:?}: about the centroid {first:?}"
            );
            assert!((second - p.rho2).abs() <= 1e-12, "{shape:?}: {second} vs {}", p.rho2);
        }
    }

    #[test]
    fn bad_shapes_are_refused() {
        assert_eq!(PartShape::Disc { radius: 0.0 }.check(), Err(ShapeError::Radius));
        assert_eq!(PartShape::Disc { radius: f64::NAN }.check(), Err(ShapeError::Radius));
        assert_eq!(PartShape::polygon(&[[0.0, 0.0], [1.0, 0.0]]), Err(ShapeError::VertexCount));
        assert_eq!(PartShape::polygon(&[[0.0, 0.0]; 9]), Err(ShapeError::VertexCount));
        assert_eq!(
            PartShape::polygon(&[[0.0, 0.0], [1.0, f64::NAN], [0.0, 1.0]]),
            Err(ShapeError::NonFinite)
        );
        // A dent, a bow tie, collinear points, a pentagram.
        let dent = [[0.0, 0.0], [2.0, 0.0], [1.0, 0.5], [2.0, 2.0], [0.0, 2.0]];
        let bow = [[0.0, 0.0], [1.0, 1.0], [1.0, 0.0], [0.0, 1.0]];
        let flat = [[0.0, 0.0], [1.0, 0.0], [2.0, 0.0]];
        let star: Vec<[f64; 2]> = (0..5)
            .map(|i| {
                let a = core::f64::consts::TAU * (2 * i) as f64 / 5.0;
                [a.cos(), a.sin()]
            })
            .collect();
        for bad in [&dent[..], &bow, &flat, &star] {
            assert_eq!(PartShape::polygon(bad), Err(ShapeError::NotConvex), "{bad:?}");
        }
        let cw = [[0.0, 0.0], [0.0, 1.0], [1.0, 1.0], [1.0, 0.0]];
        assert!(PartShape::polygon(&cw).is_ok(), "either winding");
    }
}
