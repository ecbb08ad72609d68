//! Parts: shapes, their contact patches (points with pressure weights) and
//! their dynamic state.

use super::part_capacity::{MAX_CONTACTS, MAX_POLYGON_VERTICES};
use super::polygon_limit::PolygonLimit;

#[derive(Debug, Clone, Copy, PartialEq)]
pub enum BodyShape {
    /// A point mass; `radius` only matters for the fence and collisions.
    Point { radius: f64 },
    /// A uniform disc with uniform pressure over its whole face; its
    /// friction is the exact integral over the face (`disc_friction`), so
    /// sliding gives μmg and pure spin ⅔·μmga.
    Disc { radius: f64 },
    /// A uniform convex polygon, vertices counter-clockwise about any origin
    /// (re-centered on the centroid). Pressure by the edge-midpoint rule on
    /// the fan from the centroid (exact second moment).
    Polygon { vertices: [[f64; 2]; MAX_POLYGON_VERTICES], count: usize },
}

impl BodyShape {
    /// The outline in the part's body frame, as the simulator keeps it: a
    /// polygon re-centred on its centroid (where the part's position is).
    pub fn body_frame(&self) -> BodyShape {
        match *self {
            BodyShape::Polygon { vertices, count } => {
                let n = count.min(MAX_POLYGON_VERTICES);
                let (_, cen) = area2_and_centroid(&vertices[..n]);
                let mut out = vertices;
                for v in &mut out[..n] {
                    *v = [v[0] - cen[0], v[1] - cen[1]];
                }
                BodyShape::Polygon { vertices: out, count: n }
            }
            other => other,
        }
    }
}

/// A part to put on the plate.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PartSpec {
    pub shape: BodyShape,
    pub mass: f64,
    /// World position of the center of mass and orientation.
    pub position: [f64; 2],
    pub angle: f64,
}

/// Dynamic state of a part (world frame).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct PartState {
    pub position: [f64; 2],
    pub angle: f64,
    pub velocity: [f64; 2],
    pub angular_velocity: f64,
    /// True while the part sticks to the plate.
    pub stuck: bool,
}

/// Mass properties and contact patch, in the part's body frame.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Body {
    pub mass: f64,
    /// I/m (m²); 0 for a point (no rotational dynamics).
    pub rho2: f64,
    pub contacts: [[f64; 2]; MAX_CONTACTS],
    pub weights: [f64; MAX_CONTACTS],
    pub n_contacts: usize,
    /// Σ w_c |ρ_c|: the most torque friction gives (per μ m g) about the
    /// centre, with any force (a polygon's static bound).
    pub torsion_lever: f64,
    /// A polygon's static limit data, from its contacts (its pure-torque
    /// limit `spin` is at or below `torsion_lever`).
    pub limit: PolygonLimit,
    /// Bounding radius (fence, collisions); a disc's own radius.
    pub radius: f64,
    pub extended: bool,
    /// Friction from the uniform-disc table rather than the contact points.
    pub disc: bool,
}

/// Why a part was refused (index in the list given).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PartError {
    Mass,
    Position,
    Radius,
    /// Fewer than 3 or more than MAX vertices, non-finite, not convex CCW.
    Polygon,
}

impl Body {
    /// Returns the body and the centroid offset of a polygon's input origin.
    pub fn new(spec: &PartSpec) -> Result<(Body, [f64; 2]), PartError> {
        if !(spec.mass.is_finite() && spec.mass > 0.0) {
            return Err(PartError::Mass);
        }
        if !(spec.position.iter().all(|v| v.is_finite()) && spec.angle.is_finite()) {
            return Err(PartError::Position);
        }
        let mut b = Body {
            mass: spec.mass,
            rho2: 0.0,
            contacts: [[0.0; 2]; MAX_CONTACTS],
            weights: [0.0; MAX_CONTACTS],
            n_contacts: 1,
            torsion_lever: 0.0,
            limit: PolygonLimit::default(),
            radius: 0.0,
            extended: false,
            disc: false,
        };
        b.weights[0] = 1.0;
        let ok_r = |r: f64| r.is_finite() && r >= 0.0;
        match spec.shape {
            BodyShape::Point { radius } => {
                if !ok_r(radius) {
                    return Err(PartError::Radius);
                }
                b.radius = radius;
                Ok((b, [0.0; 2]))
            }
            BodyShape::Disc { radius } => {
                if !(ok_r(radius) && radius > 0.0) {
                    return Err(PartError::Radius);
                }
                b.n_contacts = 0;
                b.rho2 = 0.5 * radius * radius;
                // ∫ |ρ| dA / A over a uniform disc.
                b.torsion_lever = 2.0 * radius / 3.0;
                b.radius = radius;
                b.extended = true;
                b.disc = true;
                Ok((b, [0.0; 2]))
            }
            BodyShape::Polygon { vertices, count } => polygon(b, &vertices, count),
        }
    }
}

fn cross(a: [f64; 2], b: [f64; 2]) -> f64 {
    a[0] * b[1] - a[1] * b[0]
}

/// Twice the signed area and the centroid (the origin for no area), by
/// the shoelace formula.
fn area2_and_centroid(v: &[[f64; 2]]) -> (f64, [f64; 2]) {
    let n = v.len();
    let (mut area2, mut cx, mut cy) = (0.0, 0.0, 0.0);
    for i in 0..n {
        let (p, q) = (v[i], v[(i + 1) % n]);
        let c = cross(p, q);
        area2 += c;
        cx += (p[0] + q[0]) * c;
        cy += (p[1] + q[1]) * c;
    }
    let cen = if area2 != 0.0 { [cx / (3.0 * area2), cy / (3.0 * area2)] } else { [0.0; 2] };
    (area2, cen)
}

fn polygon(
    mut b: Body,
    v: &[[f64; 2]; MAX_POLYGON_VERTICES],
    n: usize,
) -> Result<(Body, [f64; 2]), PartError> {
    if !(3..=MAX_POLYGON_VERTICES).contains(&n) || !v[..n].iter().flatten().all(|x| x.is_finite()) {
        return Err(PartError::Polygon);
    }
    let (area2, cen) = area2_and_centroid(&v[..n]);
    if !(area2 > 0.0) {
        return Err(PartError::Polygon);
    }
    let rel: [[f64; 2]; MAX_POLYGON_VERTICES] =
        core::array::from_fn(|i| [v[i][0] - cen[0], v[i][1] - cen[1]]);
    let total = 0.5 * area2;
    let (mut j, mut rmax) = (0.0, 0.0f64);
    for i in 0..n {
        let (p, q, r) = (rel[i], rel[(i + 1) % n], rel[(i + 2) % n]);
        if cross([q[0] - p[0], q[1] - p[1]], [r[0] - q[0], r[1] - q[1]]) <= 0.0 {
            return Err(PartError::Polygon);
        }
        let a = 0.5 * cross(p, q) / total; // fan triangle weight
        // Edge-midpoint rule on triangle (centroid, p, q).
        b.contacts[2 * i] = [0.5 * (p[0] + q[0]), 0.5 * (p[1] + q[1])];
        b.weights[2 * i] = a / 3.0;
        b.contacts[2 * i + 1] = [0.5 * q[0], 0.5 * q[1]];
        let a_next = 0.5 * cross(q, r) / total;
        b.weights[2 * i + 1] = (a + a_next) / 3.0;
        j += a * (p[0] * p[0] + p[1] * p[1] + q[0] * q[0] + q[1] * q[1] + p[0] * q[0] + p[1] * q[1]) / 6.0;
        rmax = rmax.max(p[0].hypot(p[1]));
    }
    b.n_contacts = 2 * n;
    b.rho2 = j;
    b.torsion_lever =
        (0..b.n_contacts).map(|c| b.weights[c] * b.contacts[c][0].hypot(b.contacts[c][1])).sum();
    b.limit = PolygonLimit::new(&b.contacts[..b.n_contacts], &b.weights[..b.n_contacts]);
    b.radius = rmax;
    b.extended = true;
    Ok((b, cen))
}
