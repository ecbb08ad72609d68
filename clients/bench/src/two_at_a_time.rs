//! Independent, deterministic lock-step runs, one per seed, on two
//! threads (this VM has two CPUs); the results in seed order.

/// `run(seed)` for every seed: the first half on this thread, the second
/// on another.
pub fn two_at_a_time<T: Send>(
    seeds: &[u64],
    run: impl Fn(u64) -> anyhow::Result<T> + Sync,
) -> anyhow::Result<Vec<T>> {
    let (first, second) = seeds.split_at(seeds.len().div_ceil(2));
    let fill = |seeds: &[u64]| seeds.iter().map(|&s| run(s)).collect::<anyhow::Result<Vec<T>>>();
    let (mut mine, other) = std::thread::scope(|s| {
        let other = s.spawn(|| fill(second));
        let mine = fill(first);
        (mine, other.join().map_err(|_| anyhow::anyhow!("a bench thread panicked")))
    });
    let other = other??;
    if let Ok(v) = &mut mine {
        v.extend(other);
    }
    mine
}
