//! What the caller asks for: centers, per-part forces, curl points.

use super::PartShape;

/// One part: where it is and, optionally, the average force it should feel.
/// A part with `force: None` is only observed (its achieved force is still
/// reported); its spin can be asked for with a [`CurlConstraint`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ForceConstraint {
    pub position: [f64; 2],
    pub force: Option<[f64; 2]>,
    /// The part's contact patch (`shape.rs`); `Point` is the paper's model.
    pub shape: PartShape,
}

/// A desired curl of the average field at a point (Eq. 12); for a shaped
/// part there, the curl whose torque on that patch the part should feel.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CurlConstraint {
    pub position: [f64; 2],
    pub curl: f64,
    pub shape: PartShape,
}

/// One force-synthesis request. Borrowed, so building it allocates nothing.
#[derive(Debug, Clone, Copy)]
pub struct Problem<'a> {
    /// Coulomb friction force μ·m·g of a part, newtons (> 0).
    pub mu_m_g: f64,
    /// Bound on |k_j|, in (0, 1]: a slot cannot push harder than μmg.
    pub k_max: f64,
    pub centers: &'a [[f64; 2]],
    /// Per-center bounds on |k_j| (what each rotation can play within the
    /// rig's limits), each in (0, 1], one per center; the bound of center j
    /// is the smaller of `k_bounds[j]` and `k_max`. Empty: `k_max` for all.
    pub k_bounds: &'a [f64],
    pub parts: &'a [ForceConstraint],
    pub curls: &'a [CurlConstraint],
}

impl Problem<'_> {
    /// Rows of A: two per force-constrained part, one per curl point.
    pub fn rows(&self) -> usize {
        2 * self.force_rows() + self.curls.len()
    }

    /// Number of parts whose force is constrained.
    pub fn force_rows(&self) -> usize {
        self.parts.iter().filter(|p| p.force.is_some()).count()
    }
}
