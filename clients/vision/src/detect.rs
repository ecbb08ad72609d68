//! From blobs to parts: each whole blob of a part's size (a touching pair
//! comes split in two, see `blobs`) becomes a detection on the plate (its
//! centroid through the calibration), with the class whose brightness is
//! nearest. A blob cut by the plate's edge, a blob of three or more
//! touching parts, and a speck are counted, never reported as a wrong part.
//!
//! A polygon's angle comes from the phase of the blob's complex moment of
//! its symmetry order (3 for a triangle, 4 for a square: the lower ones
//! vanish by symmetry), turned into a direction on the plate through the
//! calibration; a disc's angle is 0. A detection carries its class's
//! outline.

use crate::blobs::{Blob, binomial};
use crate::class_outline::{BodyOutline, ClassOutline};
use crate::lens::CameraModel;
use crate::part_look::PartLook;
use crate::tracker::Detection;

/// Counts of blobs that did not become a detection.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct BlobCounts {
    pub detected: u64,
    /// Cut by the edge of the region of interest.
    pub cut: u64,
    /// Larger than any one part: touching parts.
    pub merged: u64,
    /// Smaller than any part.
    pub small: u64,
    /// Detections that were one half of two touching parts.
    pub split: u64,
}

/// The blob area (px²) above which the segmenter tries a blob as two
/// touching parts: 1.5 × the largest part's area at the plate's centre.
pub fn split_area_px(model: &CameraModel, looks: &[PartLook]) -> f64 {
    let mpp = model.metres_per_pixel(0.0, 0.0).unwrap_or(f64::NAN);
    let largest = looks.iter().map(PartLook::area).fold(0.0, f64::max);
    let area = 1.5 * largest / (mpp * mpp);
    if area.is_finite() { area } else { 0.0 }
}

/// Blobs of one frame → detections (appended to `out`, never beyond its
/// capacity: a blob that does not fit counts as merged).
pub fn detect(
    blobs: &[Blob],
    model: &CameraModel,
    looks: &[PartLook],
    out: &mut Vec<Detection>,
    counts: &mut BlobCounts,
) {
    for b in blobs {
        if b.cut {
            counts.cut += 1;
            continue;
        }
        let Some([x, y]) = model.unproject(b.u, b.v) else {
            counts.cut += 1;
            continue;
        };
        let Some(mpp) = model.metres_per_pixel(x, y) else {
            counts.cut += 1;
            continue;
        };
        let area = b.area * mpp * mpp;
        let expected = PartLook::area;
        let smallest = looks.iter().map(expected).fold(f64::INFINITY, f64::min);
        let largest = looks.iter().map(expected).fold(0.0, f64::max);
        if area < 0.5 * smallest {
            counts.small += 1;
            continue;
        }
        if area > 1.5 * largest {
            counts.merged += 1;
            continue;
        }
        let class = looks
            .iter()
            .enumerate()
            .min_by(|(_, a), (_, c)| {
                let score =
                    |l: &PartLook| (b.ratio - l.ratio).abs() + (area / expected(l) - 1.0).abs() * 0.25;
                score(a).total_cmp(&score(c))
            })
            .map_or(0, |(i, _)| i as u32);
        if out.len() == out.capacity() {
            // More than the caller made room for: counted, not grown.
            counts.merged += 1;
            continue;
        }
        counts.detected += 1;
        counts.split += u64::from(b.split);
        let look = looks.get(class as usize);
        let shape = look.map_or(ClassOutline::Disc, |l| l.shape);
        let theta = plate_angle(b, shape, model);
        let outline = look.map_or(BodyOutline::POINT, PartLook::outline);
        out.push(Detection { x, y, theta, class, period: shape.period(), outline });
    }
}

/// The blob's angle on the plate (modulo the shape's period; 0 for a
/// disc). The image of a small part is the part through the local
/// Jacobian J of the pixel → plate map (lens distortion alone stretches
/// it by a few per cent, enough to turn a square's moments by a degree),
/// so the n-th complex moment is taken of the blob mapped through J:
/// with x + iy = α Δu + β Δv (α, β the columns of J as complex numbers),
/// Σ (x + iy)ⁿ = Σ_q C(n, q) α^(n-q) β^q μ_(n-q, q).
fn plate_angle(b: &Blob, shape: ClassOutline, model: &CameraModel) -> f64 {
    let n = shape.corners() as usize;
    let mu: &[f64] = match n {
        3 => &b.mu3,
        4 => &b.mu4,
        _ => return 0.0,
    };
    let h = 2.0;
    let (Some(right), Some(left), Some(down), Some(up)) = (
        model.unproject(b.u + h, b.v),
        model.unproject(b.u - h, b.v),
        model.unproject(b.u, b.v + h),
        model.unproject(b.u, b.v - h),
    ) else {
        return 0.0;
    };
    let alpha = [(right[0] - left[0]) / (2.0 * h), (right[1] - left[1]) / (2.0 * h)];
    let beta = [(down[0] - up[0]) / (2.0 * h), (down[1] - up[1]) / (2.0 * h)];
    let mul = |a: [f64; 2], b: [f64; 2]| [a[0] * b[0] - a[1] * b[1], a[0] * b[1] + a[1] * b[0]];
    let power = |z: [f64; 2], k: usize| (0..k).fold([1.0, 0.0], |acc, _| mul(acc, z));
    let mut c = [0.0; 2];
    for (q, m) in mu.iter().enumerate() {
        let term = mul(power(alpha, n - q), power(beta, q));
        let w = binomial(n, q) * m;
        c = [c[0] + w * term[0], c[1] + w * term[1]];
    }
    // A regular n-gon with a vertex on +x has a real, positive n-th
    // moment (`shape` tests it): phase / n is a vertex direction.
    let vertex = c[1].atan2(c[0]) / n as f64;
    shape.wrap(vertex - shape.first_vertex())
}

#[cfg(test)]
mod tests {
    use super::*;
    use ipc_types::{SHAPE_DISC, SHAPE_POLYGON};

    /// Each detection carries its class's outline: a disc of the class
    /// radius, a polygon of its corners at the circumradius.
    #[test]
    fn detections_carry_their_class_outline() {
        let model = CameraModel::mounted(1001, 501, 1000.0, [0.0; 4], [0.0, 0.0, 1.5], 0.0, [0.0; 2]);
        let looks = [
            PartLook { ratio: 0.2, radius: 0.015, shape: ClassOutline::Disc },
            PartLook { ratio: 0.5, radius: 0.02, shape: ClassOutline::Square },
            PartLook { ratio: 0.8, radius: 0.025, shape: ClassOutline::Triangle },
        ];
        let mpp = model.metres_per_pixel(0.0, 0.0).expect("mpp");
        let blobs: Vec<Blob> = looks
            .iter()
            .enumerate()
            .map(|(i, l)| Blob {
                area: l.area() / (mpp * mpp),
                u: 300.0 + 200.0 * i as f64,
                v: 250.0,
                ratio: l.ratio,
                ..Blob::default()
            })
            .collect();
        let mut out = Vec::with_capacity(8);
        let mut counts = BlobCounts::default();
        detect(&blobs, &model, &looks, &mut out, &mut counts);
        assert_eq!(out.iter().map(|d| d.class).collect::<Vec<_>>(), [0, 1, 2]);
        let disc = out[0].outline;
        assert_eq!((disc.shape, disc.radius), (SHAPE_DISC, 0.015));
        for (d, look) in out[1..].iter().zip(&looks[1..]) {
            let o = d.outline;
            assert_eq!((o.shape, o.vertex_count), (SHAPE_POLYGON, look.shape.corners()), "{o:?}");
            let used = &o.vertices[..o.vertex_count as usize];
            assert!(used.iter().all(|v| (v[0].hypot(v[1]) - look.radius).abs() < 1e-12), "{o:?}");
            assert_eq!(o, look.shape.body_outline(look.radius));
        }
    }
}
