//! Play order: descending priority ρ_j = |k_j| / min_i |P_i − C_j| over every
//! constrained point (paper §3.4; the formula, not its printed numbers).

/// `min_dist[j]`: distance from center j to its nearest constrained point
/// (from assembly). Fills `priority` (input order) and `order` (indices, highest ρ first;
/// ties keep input order so the result is deterministic). No allocation.
pub(crate) fn play_order(k: &[f64], min_dist: &[f64], priority: &mut Vec<f64>, order: &mut Vec<u16>) {
    priority.clear();
    order.clear();
    for (j, &d) in min_dist[..k.len()].iter().enumerate() {
        // No constrained point: every k_j is 0 anyway.
        priority.push(if d.is_finite() { k[j].abs() / d } else { 0.0 });
        order.push(j as u16);
    }
    order.sort_unstable_by(|&a, &b| priority[b as usize].total_cmp(&priority[a as usize]).then(a.cmp(&b)));
}
