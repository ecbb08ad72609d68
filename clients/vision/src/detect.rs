//! From blobs to parts: each whole blob of a part's size (a touching pair
//! comes split in two, see `blobs`) becomes a detection on the plate (its
//! centroid through the calibration), with the class whose brightness is
//! nearest. A blob cut by the plate's edge, a blob of three or more
//! touching parts, and a speck are counted, never reported as a wrong part.
//!
//! Only discs are recognised so far: their orientation is not observable,
//! so a detection's angle is 0.

use crate::blobs::Blob;
use crate::lens::CameraModel;
use crate::tracker::Detection;

/// What vision knows about a part class: its brightness relative to the
/// plate and its radius (m).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PartLook {
    pub ratio: f64,
    pub radius: f64,
}

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
    let largest = looks.iter().map(|l| l.radius).fold(0.0, f64::max);
    let area = 1.5 * core::f64::consts::PI * largest * largest / (mpp * mpp);
    if area.is_finite() { area } else { 0.0 }
}

/// Blobs of one frame → detections (appended to `out`).
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
        let expected = |l: &PartLook| core::f64::consts::PI * l.radius * l.radius;
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
        counts.detected += 1;
        counts.split += u64::from(b.split);
        out.push(Detection { x, y, theta: 0.0, class });
    }
}
