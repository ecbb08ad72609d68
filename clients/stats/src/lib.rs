//! The one percentile of samples UPM quotes (benches, vision's frame
//! timings) and the one median (the calibration fit's robust scale, the
//! benches): a sample that was seen, never an interpolation. Latency histograms use hdrhistogram's own percentiles.

/// Nearest-rank `q`-quantile (`q` in 0..=1) of `sorted` (ascending); None
/// without samples. q = 0 is the smallest sample, q = 1 the largest.
pub fn percentile(sorted: &[f64], q: f64) -> Option<f64> {
    let i = ((q * sorted.len() as f64).ceil() as usize).clamp(1, sorted.len().max(1)) - 1;
    sorted.get(i).copied()
}

/// [`percentile`] for reports that print NaN where there were no samples.
pub fn percentile_or_nan(sorted: &[f64], q: f64) -> f64 {
    percentile(sorted, q).unwrap_or(f64::NAN)
}

/// Sorts `v` (NaN last) and takes its middle sample, the upper one of the
/// two middles of an even count; None when empty.
pub fn median(v: &mut [f64]) -> Option<f64> {
    v.sort_by(f64::total_cmp);
    v.get(v.len() / 2).copied()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nearest_rank() {
        let v = [1.0, 2.0, 3.0, 4.0];
        assert_eq!(percentile(&v, 0.0), Some(1.0));
        assert_eq!(percentile(&v, 0.5), Some(2.0));
        assert_eq!(percentile(&v, 0.75), Some(3.0));
        assert_eq!(percentile(&v, 0.99), Some(4.0));
        assert_eq!(percentile(&v, 1.0), Some(4.0));
        assert_eq!(percentile(&[], 0.5), None);
        assert_eq!(median(&mut [3.0, 1.0, 2.0]), Some(2.0));
        assert_eq!(median(&mut [4.0, 1.0, 3.0, 2.0]), Some(3.0));
        assert_eq!(median(&mut []), None);
    }
}
