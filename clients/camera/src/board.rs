//! A calibration board lying on the plate: a Kalibr AprilGrid of tag36h11
//! tags (10 cells a side: a 2-cell black border around 6 × 6 data cells),
//! `gap` apart, with black squares in the gaps at every tag corner so the
//! corners are saddle points. `upm calibrate camera` detects it (the
//! `aprilgrid` crate) and knows where each tag's centre lies on the plate.

use serde::{Deserialize, Serialize};

/// The tag36h11 code words, as the detector reads them.
fn code(id: usize) -> Option<u64> {
    aprilgrid_codes::T36H11.get(id).copied()
}

/// The board, in plate coordinates (m): tag (0, 0) is the top-left one as
/// the camera sees the plate (x right, y up), ids run along rows.
#[derive(Debug, Clone, Copy, PartialEq, Deserialize, Serialize)]
#[serde(default, deny_unknown_fields)]
pub struct Board {
    pub cols: u32,
    pub rows: u32,
    /// Tag side and gap between tags (m).
    pub tag: f64,
    pub gap: f64,
    /// Plate point of the top-left tag's top-left corner.
    pub top_left: [f64; 2],
}

impl Default for Board {
    /// 18 × 9 tags of 80 mm over the 2 × 1 m plate.
    fn default() -> Self {
        Self { cols: 18, rows: 9, tag: 0.08, gap: 0.024, top_left: [-0.924, 0.456] }
    }
}

mod aprilgrid_codes {
    pub use aprilgrid::tag_families::T36H11;
}

impl Board {
    pub fn tags(&self) -> usize {
        (self.cols * self.rows) as usize
    }

    /// Plate point of the centre of tag `id`.
    pub fn tag_centre(&self, id: usize) -> Option<[f64; 2]> {
        (id < self.tags()).then(|| {
            let (i, j) = ((id % self.cols as usize) as f64, (id / self.cols as usize) as f64);
            let pitch = self.tag + self.gap;
            [self.top_left[0] + i * pitch + self.tag / 2.0, self.top_left[1] - j * pitch - self.tag / 2.0]
        })
    }

    /// Reflectance at plate point `(x, y)`: `None` off the board.
    pub fn level(&self, x: f64, y: f64) -> Option<f64> {
        let (bx, by) = (x - self.top_left[0], self.top_left[1] - y);
        let pitch = self.tag + self.gap;
        let (w, h) = (self.cols as f64 * pitch - self.gap, self.rows as f64 * pitch - self.gap);
        let g = self.gap;
        if bx < -g || by < -g || bx >= w + g || by >= h + g {
            return None;
        }
        let (black, white) = (Some(0.05), Some(0.95));
        // Outside the tags: the gaps, black where two gaps cross.
        let in_gap = |b: f64, len: f64| b < 0.0 || b >= len || b.rem_euclid(pitch) >= self.tag;
        let (gx, gy) = (in_gap(bx, w), in_gap(by, h));
        if gx || gy {
            return if gx && gy { black } else { white };
        }
        let (i, j) = ((bx / pitch).floor() as usize, (by / pitch).floor() as usize);
        let cell = self.tag / 10.0;
        let (cu, cv) = ((bx.rem_euclid(pitch) / cell) as usize, (by.rem_euclid(pitch) / cell) as usize);
        if !(2..8).contains(&cu) || !(2..8).contains(&cv) {
            return black;
        }
        // The detector reads the data cells row by row from the top-left
        // as the camera sees them, most significant bit first; 1 is bright.
        let k = (cv - 2) * 6 + (cu - 2);
        let bits = code(j * self.cols as usize + i).unwrap_or(0);
        if (bits >> (35 - k)) & 1 == 1 { white } else { black }
    }

    /// One line naming the first field that makes no sense.
    pub fn validate(&self) -> Result<(), String> {
        if self.cols == 0 || self.rows == 0 || self.tags() > aprilgrid_codes::T36H11.len() {
            return Err(format!(
                "camera.board: 1 to {} tags needed, got {} × {}",
                aprilgrid_codes::T36H11.len(),
                self.cols,
                self.rows
            ));
        }
        if !(self.tag.is_finite() && self.tag > 0.0 && self.gap.is_finite() && self.gap > 0.0) {
            return Err("camera.board.tag and gap must be positive".into());
        }
        Ok(())
    }
}
