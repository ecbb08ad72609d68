//! Input checks that run before any arithmetic, so nothing downstream sees
//! NaN, infinities or a singular field.

use super::error::{InputField, MAX_INPUT_MAGNITUDE};
use super::{PartShape, Problem, SolveError, SolverCapacity, SolverParams};

fn finite2(p: [f64; 2]) -> bool {
    p[0].is_finite() && p[1].is_finite()
}

/// Finite values beyond the range: an error naming `field[index]`.
fn in_range(values: [f64; 2], scale: f64, field: InputField, index: usize) -> Result<(), SolveError> {
    if values.iter().all(|v| v.abs() <= MAX_INPUT_MAGNITUDE * scale) {
        Ok(())
    } else {
        Err(SolveError::OutOfRange { field, index })
    }
}

pub(crate) fn validate_problem(
    problem: &Problem<'_>,
    cap: &SolverCapacity,
    params: &SolverParams,
) -> Result<(), SolveError> {
    if !(problem.mu_m_g.is_finite() && problem.mu_m_g > 0.0) {
        return Err(SolveError::InvalidMuMg);
    }
    in_range([problem.mu_m_g; 2], 1.0, InputField::MuMg, 0)?;
    if !(problem.k_max.is_finite() && problem.k_max > 0.0 && problem.k_max <= 1.0) {
        return Err(SolveError::InvalidKMax);
    }
    if problem.centers.is_empty() {
        return Err(SolveError::NoCenters);
    }
    if problem.centers.len() > cap.centers {
        return Err(SolveError::TooManyCenters { given: problem.centers.len(), capacity: cap.centers });
    }
    if problem.parts.len() > cap.parts {
        return Err(SolveError::TooManyParts { given: problem.parts.len(), capacity: cap.parts });
    }
    if problem.curls.len() > cap.curls {
        return Err(SolveError::TooManyCurls { given: problem.curls.len(), capacity: cap.curls });
    }
    if !(problem.k_bounds.is_empty() || problem.k_bounds.len() == problem.centers.len()) {
        return Err(SolveError::KBoundsLength {
            given: problem.k_bounds.len(),
            centers: problem.centers.len(),
        });
    }
    if let Some(center) = problem.k_bounds.iter().position(|&k| !(k.is_finite() && k > 0.0 && k <= 1.0)) {
        return Err(SolveError::InvalidKBound { center });
    }
    for (center, &c) in problem.centers.iter().enumerate() {
        if !finite2(c) {
            return Err(SolveError::NonFiniteCenter { center });
        }
        in_range(c, 1.0, InputField::Center, center)?;
    }
    for (part, p) in problem.parts.iter().enumerate() {
        if !finite2(p.position) {
            return Err(SolveError::NonFinitePartPosition { part });
        }
        in_range(p.position, 1.0, InputField::PartPosition, part)?;
        if let Some(f) = p.force
            && !finite2(f)
        {
            return Err(SolveError::NonFinitePartForce { part });
        }
        if let Some(f) = p.force {
            in_range(f, problem.mu_m_g, InputField::PartForce, part)?;
        }
        p.shape.check().map_err(|error| SolveError::PartShape { part, error })?;
        // Only a point is singular on a center; a patch averages over it.
        if let Some(center) = nearest_too_close(p.position, problem.centers, params)?
            && p.shape == PartShape::Point
        {
            return Err(SolveError::PartOnCenter { part, center });
        }
    }
    for (curl, q) in problem.curls.iter().enumerate() {
        if !finite2(q.position) {
            return Err(SolveError::NonFiniteCurlPosition { curl });
        }
        in_range(q.position, 1.0, InputField::CurlPosition, curl)?;
        if !q.curl.is_finite() {
            return Err(SolveError::NonFiniteCurl { curl });
        }
        in_range([q.curl; 2], problem.mu_m_g, InputField::Curl, curl)?;
        q.shape.check().map_err(|error| SolveError::CurlShape { curl, error })?;
        if let Some(center) = nearest_too_close(q.position, problem.centers, params)?
            && q.shape == PartShape::Point
        {
            return Err(SolveError::CurlOnCenter { curl, center });
        }
    }
    Ok(())
}

/// First center within `min_center_distance` of `p`; overflow if the
/// distance itself is not representable. Compares squares: no square root
/// per pair.
fn nearest_too_close(
    p: [f64; 2],
    centers: &[[f64; 2]],
    params: &SolverParams,
) -> Result<Option<usize>, SolveError> {
    let min_sq = params.min_center_distance * params.min_center_distance;
    for (j, &c) in centers.iter().enumerate() {
        let (dx, dy) = (p[0] - c[0], p[1] - c[1]);
        let r_sq = dx * dx + dy * dy;
        if !r_sq.is_finite() {
            return Err(SolveError::Overflow);
        }
        if r_sq < min_sq {
            return Ok(Some(j));
        }
    }
    Ok(None)
}
