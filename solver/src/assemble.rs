//! Build A and b of Eq. 10 and 12.
//!
//! Row order (ARCHITECTURE.md §2): x rows of every force-constrained part, then
//! their y rows, then one curl row per curl point. A is stored row-major
//! (m rows × n centers), which is Aᵀ column-major: what the QR wants.
//! A shaped part's entries are its patch averages (`shape.rs`).

use super::shape::{PartShape, for_each_wrench_row};
use super::{Problem, SolveError};

/// Fills `rows[..m*n]` and `b[..m]`; returns m. `b` is scaled by N/μmg.
/// `min_dist[j]` gets the distance from center j to its nearest constrained
/// point (∞ if none), which the play order needs: computed here so each
/// distance is taken once.
/// `cx` and `cy` are scratch of length ≥ n: the centers split into x and y
/// arrays, so that each row below is a plain loop over slices that LLVM
/// vectorises (square roots and divisions four or two at a time).
pub(crate) fn assemble(
    problem: &Problem<'_>,
    rows: &mut [f64],
    b: &mut [f64],
    min_dist: &mut [f64],
    cx: &mut [f64],
    cy: &mut [f64],
) -> Result<usize, SolveError> {
    let n = problem.centers.len();
    let min_dist = &mut min_dist[..n];
    min_dist.fill(f64::INFINITY);
    let (cx, cy) = (&mut cx[..n], &mut cy[..n]);
    for ((x, y), c) in cx.iter_mut().zip(cy.iter_mut()).zip(problem.centers) {
        *x = c[0];
        *y = c[1];
    }
    let (cx, cy) = (&*cx, &*cy);
    let scale = n as f64 / problem.mu_m_g;
    let mf = problem.force_rows();
    let mut i = 0;
    for part in problem.parts {
        let Some(f) = part.force else { continue };
        let (x_row, rest) = rows[i * n..].split_at_mut(n);
        let y_row = &mut rest[(mf - 1) * n..mf * n];
        let [px, py] = part.position;
        for j in 0..n {
            // unit_tangent, written out on the split centers.
            let (dx, dy) = (px - cx[j], py - cy[j]);
            let r = (dx * dx + dy * dy).sqrt();
            let inv = 1.0 / r;
            x_row[j] = -dy * inv;
            y_row[j] = dx * inv;
            min_dist[j] = min_dist[j].min(r);
        }
        if part.shape != PartShape::Point {
            for_each_wrench_row(&part.shape, part.position, problem.centers, |j, t, _| {
                x_row[j] = t[0];
                y_row[j] = t[1];
            });
        }
        b[i] = scale * f[0];
        b[mf + i] = scale * f[1];
        i += 1;
    }
    let mut i = 2 * mf;
    for q in problem.curls {
        let row = &mut rows[i * n..(i + 1) * n];
        let [qx, qy] = q.position;
        for j in 0..n {
            let (dx, dy) = (qx - cx[j], qy - cy[j]);
            let r = (dx * dx + dy * dy).sqrt();
            row[j] = 1.0 / r;
            min_dist[j] = min_dist[j].min(r);
        }
        if q.shape != PartShape::Point {
            for_each_wrench_row(&q.shape, q.position, problem.centers, |j, _, curl| row[j] = curl);
        }
        b[i] = scale * q.curl;
        i += 1;
    }
    let m = i;
    if rows[..m * n].iter().chain(&b[..m]).any(|v| !v.is_finite()) {
        return Err(SolveError::Overflow);
    }
    Ok(m)
}
