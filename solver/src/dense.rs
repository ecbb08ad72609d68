//! Small dense kernels for the d ≤ 200 vectors of a solve.
//!
//! LLVM never reassociates a floating-point sum, so a plain `.sum()` is one
//! serial chain of adds, and its auto-vectoriser gave up on these short,
//! bounds-checked loops. `wide::f64x4` lanes make the SIMD explicit. Every
//! sum has a fixed order (four lanes, then (l0 + l2) + (l1 + l3), then the
//! tail), so results are bit-identical from run to run, and no multiply-add
//! is fused, so the SSE2 and AVX2 clones agree bit for bit too.

use wide::f64x4;

/// Four lanes from a `chunks_exact(4)` chunk (the length check folds away).
#[inline(always)]
fn lanes(chunk: &[f64]) -> f64x4 {
    let array: [f64; 4] = chunk.try_into().unwrap_or([0.0; 4]);
    f64x4::from(array)
}

#[inline(always)]
fn lanes_sum(v: f64x4) -> f64 {
    let a = v.to_array();
    (a[0] + a[2]) + (a[1] + a[3])
}

/// Σ aᵢ·bᵢ over the shorter of the two slices.
#[inline(always)]
pub(crate) fn dot(a: &[f64], b: &[f64]) -> f64 {
    let len = a.len().min(b.len());
    let body = len - len % 4;
    let (a4, a_tail) = a[..len].split_at(body);
    let (b4, b_tail) = b[..len].split_at(body);
    let mut acc = f64x4::ZERO;
    for (x, y) in a4.chunks_exact(4).zip(b4.chunks_exact(4)) {
        acc += lanes(x) * lanes(y);
    }
    let mut tail = 0.0;
    for (x, y) in a_tail.iter().zip(b_tail) {
        tail += x * y;
    }
    lanes_sum(acc) + tail
}

/// Four dot products sharing `v`: [Σ vᵢ·c₀ᵢ, …, Σ vᵢ·c₃ᵢ], each bit-identical
/// to [`dot`]. Each `cols[c]` must be at least as long as `v`.
#[inline(always)]
pub(crate) fn dot4(v: &[f64], cols: [&[f64]; 4]) -> [f64; 4] {
    let len = v.len();
    let body = len - len % 4;
    let (v4, v_tail) = v.split_at(body);
    let [c0, c1, c2, c3] = cols.map(|c| &c[..body]);
    let mut acc = [f64x4::ZERO; 4];
    for (i, x) in v4.chunks_exact(4).enumerate() {
        let vv = lanes(x);
        let r = 4 * i..4 * i + 4;
        acc[0] += vv * lanes(&c0[r.clone()]);
        acc[1] += vv * lanes(&c1[r.clone()]);
        acc[2] += vv * lanes(&c2[r.clone()]);
        acc[3] += vv * lanes(&c3[r]);
    }
    let mut out = [0.0; 4];
    for ((o, a), c) in out.iter_mut().zip(acc).zip(cols) {
        let mut tail = 0.0;
        for (x, y) in v_tail.iter().zip(&c[body..len]) {
            tail += x * y;
        }
        *o = lanes_sum(a) + tail;
    }
    out
}

/// Σ aᵢ².
#[inline(always)]
pub(crate) fn sum_sq(a: &[f64]) -> f64 {
    dot(a, a)
}

/// y ← y + α·x over the shorter of the two slices.
#[inline(always)]
pub(crate) fn axpy(alpha: f64, x: &[f64], y: &mut [f64]) {
    let len = x.len().min(y.len());
    let body = len - len % 4;
    let (x4, x_tail) = x[..len].split_at(body);
    let (y4, y_tail) = y[..len].split_at_mut(body);
    let av = f64x4::splat(alpha);
    for (yc, xc) in y4.chunks_exact_mut(4).zip(x4.chunks_exact(4)) {
        let r = lanes(yc) + av * lanes(xc);
        yc.copy_from_slice(&r.to_array());
    }
    for (yi, xi) in y_tail.iter_mut().zip(x_tail) {
        *yi += alpha * xi;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dot_matches_the_serial_sum_on_every_tail_length() {
        for len in 0..13 {
            let a: Vec<f64> = (0..len).map(|i| 1.0 + i as f64).collect();
            let b: Vec<f64> = (0..len).map(|i| 2.0 - 0.5 * i as f64).collect();
            let serial: f64 = a.iter().zip(&b).map(|(x, y)| x * y).sum();
            assert_eq!(dot(&a, &b), serial, "len {len}");
        }
    }

    /// With values whose sums round, only the documented order gives these
    /// bits: four lanes, (l0 + l2) + (l1 + l3), then the tail.
    #[test]
    fn dot_sums_in_the_documented_order() {
        for len in [4usize, 7, 9, 13] {
            let a: Vec<f64> = (0..len).map(|i| 0.1 * (i as f64 + 1.0)).collect();
            let b: Vec<f64> = (0..len).map(|i| 1.0 / (i as f64 + 3.0)).collect();
            let body = len - len % 4;
            let mut lanes = [0.0f64; 4];
            for i in 0..body {
                lanes[i % 4] += a[i] * b[i];
            }
            let mut tail = 0.0;
            for i in body..len {
                tail += a[i] * b[i];
            }
            let expected = ((lanes[0] + lanes[2]) + (lanes[1] + lanes[3])) + tail;
            assert_eq!(dot(&a, &b).to_bits(), expected.to_bits(), "len {len}");
        }
    }

    #[test]
    fn dot4_matches_four_dots() {
        let v: Vec<f64> = (0..11).map(|i| 0.5 + i as f64).collect();
        let cols: Vec<Vec<f64>> =
            (0..4).map(|c| (0..13).map(|i| (c * 7 + i) as f64 - 3.0).collect()).collect();
        let four = dot4(&v, [&cols[0], &cols[1], &cols[2], &cols[3]]);
        for c in 0..4 {
            assert_eq!(four[c], dot(&v, &cols[c]));
        }
    }

    #[test]
    fn axpy_adds_a_scaled_vector() {
        let mut y = [1.0, 2.0, 3.0, 4.0, 5.0, 6.0];
        axpy(2.0, &[1.0, 0.5, -1.0, 0.0, 1.0, -2.0], &mut y);
        assert_eq!(y, [3.0, 3.0, 1.0, 4.0, 7.0, 2.0]);
    }
}
