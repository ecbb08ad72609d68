//! The friction field of one plate rotation (paper Eq. 8, 11).
//!
//! A rotation about `c` with intensity `k` (k > 0 = CCW) drags a sliding part
//! at `p` with φ(p) = k·μmg·R90(p − c)/|p − c|, R90(x, y) = (−y, x).

/// Unit tangential direction R90(p − c)/|p − c| and the distance |p − c|.
#[inline]
pub fn unit_tangent(p: [f64; 2], c: [f64; 2]) -> ([f64; 2], f64) {
    let dx = p[0] - c[0];
    let dy = p[1] - c[1];
    let r = (dx * dx + dy * dy).sqrt();
    // One division, not two: assembly calls this m·n times per solve.
    let inv = 1.0 / r;
    ([-dy * inv, dx * inv], r)
}

/// Average force at `p` of a rotation about `c` with intensity `k` (Eq. 8).
#[inline]
pub fn rotation_force(k: f64, mu_m_g: f64, c: [f64; 2], p: [f64; 2]) -> [f64; 2] {
    let (t, _) = unit_tangent(p, c);
    [k * mu_m_g * t[0], k * mu_m_g * t[1]]
}

/// Curl ∂fy/∂x − ∂fx/∂y of that field at `p` (Eq. 11): k·μmg/|p − c|.
#[inline]
pub fn rotation_curl(k: f64, mu_m_g: f64, c: [f64; 2], p: [f64; 2]) -> f64 {
    let (_, r) = unit_tangent(p, c);
    k * mu_m_g / r
}

/// Divergence ∂fx/∂x + ∂fy/∂y of that field at `p`, written out term by term
/// (it cancels to zero: the paper's §3.6 argument against sensorless use).
#[inline]
pub fn rotation_divergence(k: f64, mu_m_g: f64, c: [f64; 2], p: [f64; 2]) -> f64 {
    let dx = p[0] - c[0];
    let dy = p[1] - c[1];
    let r = (dx * dx + dy * dy).sqrt();
    let r3 = r * r * r;
    let dfx_dx = k * mu_m_g * dy * dx / r3;
    let dfy_dy = -k * mu_m_g * dx * dy / r3;
    dfx_dx + dfy_dy
}

/// Average force of a whole cycle of N slots (Eq. 9–10):
/// f(p) = (μmg/N) Σ_j k_j R90(p − c_j)/|p − c_j|.
pub fn cycle_force(k: &[f64], centers: &[[f64; 2]], mu_m_g: f64, p: [f64; 2]) -> [f64; 2] {
    let n = centers.len().max(1) as f64;
    let mut f = [0.0; 2];
    for (&kj, &c) in k.iter().zip(centers) {
        let fj = rotation_force(kj, mu_m_g, c, p);
        f[0] += fj[0];
        f[1] += fj[1];
    }
    [f[0] / n, f[1] / n]
}

/// Curl of the cycle's average field at `p` (Eq. 12).
pub fn cycle_curl(k: &[f64], centers: &[[f64; 2]], mu_m_g: f64, p: [f64; 2]) -> f64 {
    let n = centers.len().max(1) as f64;
    k.iter().zip(centers).map(|(&kj, &c)| rotation_curl(kj, mu_m_g, c, p)).sum::<f64>() / n
}
