//! The slots one solver answer plays, in play order.

use upm_solver::Solution;

use crate::ScheduleEntry;

/// The cycle `solution` plays: each center in play order, `counts[j]`
/// consecutive slots at its k. Returns the slots filled (at most
/// `entries.len()`).
pub fn fill_entries(solution: &Solution, centers: &[[f64; 2]], entries: &mut [ScheduleEntry]) -> usize {
    let mut n = 0;
    for &j in solution.order() {
        let j = usize::from(j);
        let (Some(&center), Some(&k), Some(&count)) =
            (centers.get(j), solution.k().get(j), solution.counts().get(j))
        else {
            continue;
        };
        for _ in 0..count {
            if let Some(e) = entries.get_mut(n) {
                *e = ScheduleEntry { center, k };
                n += 1;
            }
        }
    }
    n
}
