//! Dark blobs on a bright plate, in one pass over a mono8 frame, into
//! buffers sized at start-up.
//!
//! 1. **Background model.** The plate's brightness under uneven light:
//!    per 64 × 64 tile, a high percentile of the plate's pixels (parts
//!    cover a small share of a tile, so the percentile is the plate), then
//!    bilinear between tile centres.
//! 2. **Threshold** relative to that background (`threshold` × local
//!    plate brightness), only inside the plate's outline as the
//!    calibration sees it (the region of interest, one span per row).
//! 3. **Labelling** of dark runs with union-find (8-connected), and the
//!    **moments** of each blob up to order 4 (area, centroid, second
//!    central moments, the complex moments whose phase gives a triangle's
//!    and a square's orientation, mean brightness relative to the plate)
//!    summed per run in closed form, about the blob's first pixel so that
//!    nothing cancels.
//! 4. **Touching pairs**: a blob the size of two parts is cut across its
//!    long axis at its centroid (two touching discs part exactly at their
//!    contact), each half measured again from the pixels.
//!
//! Written by hand because the crates at hand (imageproc's
//! `connected_components`) return a freshly allocated label image per
//! call and no moments; here a frame allocates nothing.

use crate::lens::CameraModel;

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SegmentParams {
    /// A pixel is dark when below `threshold` × the local plate brightness.
    pub threshold: f64,
    /// Background tile side, px.
    pub tile: usize,
    /// Percentile of a tile's plate pixels taken as its background.
    pub percentile: f64,
    /// Runs a frame may hold; more (a frame of noise) skips the frame.
    pub max_runs: usize,
    /// A blob of area between 1 × and 2.6 / 1.5 × this (px²) is taken for
    /// two touching parts and split in two along its long axis; 0 never
    /// splits. Callers set it to 1.5 × a part's area.
    pub split_above_px: f64,
    /// Measure the centroid and orientation moments (`mu3`, `mu4`) of each
    /// whole blob again with every pixel of its box weighted by how dark
    /// it is, so that edge pixels count by their coverage: a polygon's
    /// angle to a fraction of a degree, a centroid to a tenth of a pixel.
    /// Costs one pass over each blob's box. On by default.
    pub coverage_moments: bool,
}

impl Default for SegmentParams {
    fn default() -> Self {
        Self {
            threshold: 0.7,
            tile: 64,
            percentile: 0.9,
            max_runs: 1 << 17,
            split_above_px: 0.0,
            coverage_moments: true,
        }
    }
}

/// One dark blob: pixel moments and how it sits.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Blob {
    pub area: f64,
    /// Centroid, px.
    pub u: f64,
    pub v: f64,
    /// Second central moments, px².
    pub mu20: f64,
    pub mu02: f64,
    pub mu11: f64,
    /// Central moments of order 3 and 4, `mu3[q]` = Σ Δu^(3-q) Δv^q (px³,
    /// px⁴, summed not averaged): a triangle's and a square's orientation.
    pub mu3: [f64; 4],
    pub mu4: [f64; 5],
    /// Bounding box, px: first and last column, first and last row.
    pub bbox: [u32; 4],
    /// Mean brightness of its pixels relative to the local plate.
    pub ratio: f64,
    /// Touches the region of interest's edge (cut by it, not whole).
    pub cut: bool,
    /// One half of a blob of two touching parts.
    pub split: bool,
}

/// Why a frame gave no blobs at all.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum BadFrame {
    /// The plate reads almost black (no light, lens cap, a black frame).
    TooDark,
    /// Most of the plate is saturated (a white frame, overexposure).
    TooBright,
    /// More dark runs than [`SegmentParams::max_runs`] (noise, not parts).
    TooManyRuns,
    /// The frame's size is not the calibration's.
    WrongSize,
}

impl core::fmt::Display for BadFrame {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(match self {
            Self::TooDark => "too dark",
            Self::TooBright => "saturated",
            Self::TooManyRuns => "too many dark runs",
            Self::WrongSize => "size differs from the calibration",
        })
    }
}

#[derive(Debug, Clone, Copy, Default)]
struct Run {
    v: u32,
    u0: u32,
    u1: u32,
    ratio_sum: f32,
}

/// Moments Σ uᵖ vᵠ (p + q ≤ 4) of one blob's pixels about `origin`.
#[derive(Debug, Clone, Copy, Default)]
struct Sums {
    origin: [f64; 2],
    m: [f64; MOMENTS],
    bbox: [u32; 4],
    ratio: f64,
    cut: bool,
}

/// Moments up to order 4, stored by order then by power of v.
const MOMENTS: usize = 15;

const fn at(p: usize, q: usize) -> usize {
    let order = p + q;
    order * (order + 1) / 2 + q
}

/// Σ xʲ for x in 0..=n (j ≤ 4): Faulhaber's polynomials, which also hold
/// for negative n, so a run's sum is `F(b) - F(a - 1)`.
fn power_sums(n: f64) -> [f64; 5] {
    let t = n * (n + 1.0);
    [n + 1.0, t / 2.0, t * (2.0 * n + 1.0) / 6.0, t * t / 4.0, t * (2.0 * n + 1.0) * (3.0 * t - 1.0) / 30.0]
}

impl Sums {
    fn at(origin: [f64; 2]) -> Self {
        let [u, v] = origin.map(|c| c.max(0.0) as u32);
        Self { origin, bbox: [u, v, u, v], ..Self::default() }
    }

    /// Pixels `a..=b` of row `v` (absolute coordinates).
    fn add_run(&mut self, a: f64, b: f64, v: f64) {
        let (a_, b_, v_) = (a.max(0.0) as u32, b.max(0.0) as u32, v.max(0.0) as u32);
        self.bbox = [self.bbox[0].min(a_), self.bbox[1].min(v_), self.bbox[2].max(b_), self.bbox[3].max(v_)];
        let (hi, lo) = (power_sums(b - self.origin[0]), power_sums(a - 1.0 - self.origin[0]));
        self.add_row(v, &[0, 1, 2, 3, 4].map(|p| hi[p] - lo[p]));
    }

    fn add_pixel(&mut self, u: f64, v: f64) {
        self.add_run(u, u, v);
    }

    /// Row `v` given its sums Σ w·xᵖ (p ≤ 4, x about the origin).
    fn add_row(&mut self, v: f64, along: &[f64; 5]) {
        let y = v - self.origin[1];
        let mut yq = 1.0;
        for q in 0..=4 {
            for (p, sum) in along.iter().enumerate().take(5 - q) {
                self.m[at(p, q)] += sum * yq;
            }
            yq *= y;
        }
    }
}

#[derive(Debug)]
pub struct Segmenter {
    params: SegmentParams,
    width: usize,
    height: usize,
    /// Columns `[start, end)` of the region of interest on each row.
    roi: Vec<(u32, u32)>,
    roi_rows: (usize, usize),
    tiles: (usize, usize),
    tile_bg: Vec<f32>,
    tile_ok: Vec<bool>,
    row_bg: Vec<f32>,
    row_threshold: Vec<u8>,
    /// Per column: the tile column left of it and the weight of the next.
    columns: Vec<(u32, f32)>,
    runs: Vec<Run>,
    parent: Vec<u32>,
    slot: Vec<u32>,
    /// The blob (index into `sums`) of every run.
    run_blob: Vec<u32>,
    sums: Vec<Sums>,
    blobs: Vec<Blob>,
}

fn find(parent: &mut [u32], mut i: u32) -> u32 {
    while parent[i as usize] != i {
        let p = parent[i as usize];
        parent[i as usize] = parent[p as usize];
        i = p;
    }
    i
}

impl Segmenter {
    /// The region of interest is the plate `[-hx, hx] × [-hy, hy]` as
    /// `model` sees it, shrunk by `margin` m. Allocates every buffer.
    pub fn new(model: &CameraModel, half_extent: [f64; 2], margin: f64, params: SegmentParams) -> Self {
        let (w, h) = (model.width as usize, model.height as usize);
        let inside = |u: usize, v: usize| {
            model.unproject(u as f64, v as f64).is_some_and(|[x, y]| {
                x.abs() <= half_extent[0] - margin && y.abs() <= half_extent[1] - margin
            })
        };
        // The plate's image is convex but for the lens's slight bend: one
        // span per row, from the first to the last pixel inside.
        let roi: Vec<(u32, u32)> = (0..h)
            .map(|v| match (0..w).find(|&u| inside(u, v)) {
                Some(first) => {
                    let last = (first..w).rev().find(|&u| inside(u, v)).unwrap_or(first);
                    (first as u32, last as u32 + 1)
                }
                None => (0, 0),
            })
            .collect();
        let first = roi.iter().position(|r| r.1 > r.0).unwrap_or(0);
        let last = roi.iter().rposition(|r| r.1 > r.0).map_or(0, |l| l + 1);
        let t = params.tile.max(8);
        let tiles = (w.div_ceil(t), h.div_ceil(t));
        Self {
            params: SegmentParams { tile: t, ..params },
            width: w,
            height: h,
            roi,
            roi_rows: (first, last),
            tiles,
            tile_bg: vec![0.0; tiles.0 * tiles.1],
            tile_ok: vec![false; tiles.0 * tiles.1],
            row_bg: vec![0.0; w],
            row_threshold: vec![0; w],
            columns: (0..w)
                .map(|u| {
                    let fx = ((u as f32 + 0.5) / t as f32 - 0.5).clamp(0.0, (tiles.0 - 1) as f32);
                    (fx.floor() as u32, fx - fx.floor())
                })
                .collect(),
            runs: Vec::with_capacity(params.max_runs),
            parent: Vec::with_capacity(params.max_runs),
            slot: Vec::with_capacity(params.max_runs),
            run_blob: Vec::with_capacity(params.max_runs),
            sums: Vec::with_capacity(params.max_runs),
            blobs: Vec::with_capacity(params.max_runs),
        }
    }

    /// The region of interest: columns `[start, end)` of each row.
    pub fn roi_spans(&self) -> &[(u32, u32)] {
        &self.roi
    }

    /// Pixels in the region of interest.
    pub fn roi_pixels(&self) -> usize {
        self.roi.iter().map(|r| (r.1 - r.0) as usize).sum()
    }

    /// The blobs of one frame (`stride` bytes per row).
    pub fn segment(
        &mut self,
        pixels: &[u8],
        width: u32,
        height: u32,
        stride: usize,
    ) -> Result<&[Blob], BadFrame> {
        if width as usize != self.width
            || height as usize != self.height
            || pixels.len() < stride * self.height
        {
            return Err(BadFrame::WrongSize);
        }
        self.background(pixels, stride)?;
        self.label(pixels, stride)?;
        if self.params.coverage_moments {
            self.coverage_moments(pixels, stride);
        }
        Ok(&self.blobs)
    }

    fn background(&mut self, pixels: &[u8], stride: usize) -> Result<(), BadFrame> {
        let t = self.params.tile;
        let (tx, ty) = self.tiles;
        let (mut saturated, mut total) = (0usize, 0usize);
        for j in 0..ty {
            for i in 0..tx {
                let mut hist = [0u32; 256];
                let mut n = 0u32;
                // Every 4th pixel of every 4th row: the plate is smooth.
                for v in (j * t..((j + 1) * t).min(self.height)).step_by(4) {
                    let (a, b) = self.roi[v];
                    let (a, b) = ((a as usize).max(i * t), (b as usize).min((i + 1) * t));
                    for &p in pixels[v * stride..].get(a..b).unwrap_or(&[]).iter().step_by(4) {
                        hist[p as usize] += 1;
                        n += 1;
                    }
                }
                saturated += hist[255] as usize;
                total += n as usize;
                let k = j * tx + i;
                self.tile_ok[k] = n >= (t * t / 128) as u32;
                if self.tile_ok[k] {
                    let want = (self.params.percentile * n as f64) as u32;
                    let mut seen = 0;
                    let level = hist.iter().position(|&c| {
                        seen += c;
                        seen > want
                    });
                    self.tile_bg[k] = level.unwrap_or(255) as f32;
                }
            }
        }
        if total == 0 || saturated * 2 > total {
            return Err(BadFrame::TooBright);
        }
        // Tiles with too little plate take their nearest good neighbour's.
        for _ in 0..tx.max(ty) {
            let mut missing = false;
            for k in 0..tx * ty {
                if self.tile_ok[k] {
                    continue;
                }
                let (i, j) = (k % tx, k / tx);
                let near = [(i.wrapping_sub(1), j), (i + 1, j), (i, j.wrapping_sub(1)), (i, j + 1)];
                match near
                    .iter()
                    .filter(|&&(a, b)| a < tx && b < ty)
                    .map(|&(a, b)| b * tx + a)
                    .find(|&n| self.tile_ok[n])
                {
                    Some(n) => {
                        self.tile_bg[k] = self.tile_bg[n];
                        self.tile_ok[k] = true;
                    }
                    None => missing = true,
                }
            }
            if !missing {
                break;
            }
        }
        let mut levels: [u32; 256] = [0; 256];
        for &b in &self.tile_bg {
            levels[b as usize] += 1;
        }
        let half = self.tile_bg.len() as u32 / 2;
        let mut seen = 0;
        let median = levels.iter().position(|&c| {
            seen += c;
            seen > half
        });
        if median.unwrap_or(0) < 16 {
            return Err(BadFrame::TooDark);
        }
        Ok(())
    }

    /// Background of every pixel of row `v`, bilinear between tile
    /// centres, and the darkness threshold of each (`threshold` × it).
    fn fill_row_background(&mut self, v: usize, columns: core::ops::Range<usize>) {
        let tx = self.tiles.0;
        let (j0, j1, wy) = self.tile_rows(v);
        let threshold = self.params.threshold as f32;
        let (top, bottom) = (&self.tile_bg[j0 * tx..(j0 + 1) * tx], &self.tile_bg[j1 * tx..(j1 + 1) * tx]);
        for u in columns {
            let (i0, wx) = self.columns[u];
            let i1 = (i0 as usize + 1).min(tx - 1);
            let i0 = i0 as usize;
            let a = top[i0] + (top[i1] - top[i0]) * wx;
            let b = bottom[i0] + (bottom[i1] - bottom[i0]) * wx;
            let bg = a + (b - a) * wy;
            self.row_bg[u] = bg;
            // Dark means below threshold × bg, rounded up (the cast saturates).
            self.row_threshold[u] = (threshold * bg + 0.999) as u8;
        }
    }

    fn label(&mut self, pixels: &[u8], stride: usize) -> Result<(), BadFrame> {
        self.runs.clear();
        self.parent.clear();
        self.blobs.clear();
        let mut prev = 0..0;
        let mut filled: Option<(usize, usize, usize)> = None;
        for v in self.roi_rows.0..self.roi_rows.1 {
            let (a, b) = (self.roi[v].0 as usize, self.roi[v].1 as usize);
            if a >= b {
                prev = self.runs.len()..self.runs.len();
                continue;
            }
            // The background changes over a tile (64 px): recomputing it
            // every 8th row is exact enough and 8 × cheaper.
            let band = (v / 8, a, b);
            if filled.is_none_or(|(fv, fa, fb)| fv != band.0 || fa > a || fb < b) {
                self.fill_row_background(v, a..b);
                filled = Some(band);
            }
            let row = &pixels[v * stride..v * stride + self.width];
            let here = self.runs.len();
            let thr = &self.row_threshold;
            let dark = |u: usize| row[u] < thr[u];
            let mut u = a;
            while u < b {
                // Skip 32 plate pixels at a time (most of a frame).
                if u + 32 <= b
                    && !row[u..u + 32].iter().zip(&thr[u..u + 32]).fold(false, |d, (p, t)| d | (p < t))
                {
                    u += 32;
                    continue;
                }
                if !dark(u) {
                    u += 1;
                    continue;
                }
                let start = u;
                let mut ratio_sum = 0.0;
                while u < b && dark(u) {
                    ratio_sum += row[u] as f32 / self.row_bg[u].max(1.0);
                    u += 1;
                }
                if self.runs.len() == self.params.max_runs {
                    return Err(BadFrame::TooManyRuns);
                }
                let id = self.runs.len() as u32;
                self.runs.push(Run { v: v as u32, u0: start as u32, u1: u as u32, ratio_sum });
                self.parent.push(id);
            }
            // Join with the runs of the row above that touch (8-connected).
            let mut k = prev.start;
            for r in here..self.runs.len() {
                let cur = self.runs[r];
                while k < prev.end && self.runs[k].u1 < cur.u0 {
                    k += 1;
                }
                let mut m = k;
                while m < prev.end && self.runs[m].u0 <= cur.u1 {
                    let (x, y) = (find(&mut self.parent, m as u32), find(&mut self.parent, r as u32));
                    if x != y {
                        self.parent[x.max(y) as usize] = x.min(y);
                    }
                    m += 1;
                }
            }
            prev = here..self.runs.len();
        }
        self.moments();
        self.split_pairs(pixels, stride);
        Ok(())
    }

    fn moments(&mut self) {
        self.slot.clear();
        self.slot.resize(self.runs.len(), u32::MAX);
        self.run_blob.clear();
        self.sums.clear();
        let (first_row, last_row) = (self.roi_rows.0 as u32, self.roi_rows.1 as u32 - 1);
        for r in 0..self.runs.len() {
            let root = find(&mut self.parent, r as u32) as usize;
            if self.slot[root] == u32::MAX {
                self.slot[root] = self.sums.len() as u32;
                let first = self.runs[r];
                self.sums.push(Sums::at([first.u0 as f64, first.v as f64]));
            }
            self.run_blob.push(self.slot[root]);
            let run = self.runs[r];
            let (roi_a, roi_b) = self.roi[run.v as usize];
            let cut = {
                let covers = |row: u32| {
                    let (a, b) = self.roi[row as usize];
                    a < run.u0 && b > run.u1
                };
                run.u0 == roi_a
                    || run.u1 == roi_b
                    || run.v == first_row
                    || run.v == last_row
                    || !covers(run.v - 1)
                    || !covers(run.v + 1)
            };
            let s = &mut self.sums[self.slot[root] as usize];
            s.add_run(run.u0 as f64, run.u1 as f64 - 1.0, run.v as f64);
            s.ratio += run.ratio_sum as f64;
            // Cut when a neighbour of the run, on its row or the rows
            // above and below, lies outside the region of interest.
            s.cut |= cut;
        }
        for s in &self.sums {
            self.blobs.push(blob_of(s));
        }
    }

    /// The tile rows above and below pixel row `v`'s centre, and the
    /// weight of the lower one (bilinear between tile centres).
    fn tile_rows(&self, v: usize) -> (usize, usize, f32) {
        let (t, ty) = (self.params.tile as f32, self.tiles.1);
        let fy = ((v as f32 + 0.5) / t - 0.5).clamp(0.0, (ty - 1) as f32);
        let j0 = fy.floor() as usize;
        (j0, (j0 + 1).min(ty - 1), fy - fy.floor())
    }

    /// Background at one pixel, bilinear between tile centres.
    fn background_at(&self, u: usize, v: usize) -> f32 {
        let tx = self.tiles.0;
        let (j0, j1, wy) = self.tile_rows(v);
        let (i0, wx) = self.columns[u];
        let (i0, i1) = (i0 as usize, (i0 as usize + 1).min(tx - 1));
        let at = |j: usize, i: usize| self.tile_bg[j * tx + i];
        let a = at(j0, i0) + (at(j0, i1) - at(j0, i0)) * wx;
        let b = at(j1, i0) + (at(j1, i1) - at(j1, i0)) * wx;
        a + (b - a) * wy
    }

    /// Centroid, `mu3` and `mu4` of each whole blob from the pixels of its
    /// box (one pixel around), weighted by coverage: 0 at the plate's
    /// brightness, 1 at the blob's own mean brightness.
    fn coverage_moments(&mut self, pixels: &[u8], stride: usize) {
        // The background model reads a little above the plate's mean and
        // noise lifts some plate pixels: below this coverage a pixel is
        // plate. Without the floor the box's square frame of faint weights
        // pulls a square's angle towards the pixel grid.
        const COVER_FLOOR: f64 = 0.08;
        for b in 0..self.blobs.len() {
            let blob = self.blobs[b];
            if blob.cut || blob.split || blob.ratio >= 0.95 {
                continue;
            }
            let [u0, v0, u1, v1] = blob.bbox;
            let (u0, v0) = (u0.saturating_sub(1) as usize, v0.saturating_sub(1) as usize);
            let (u1, v1) = ((u1 as usize + 1).min(self.width - 1), (v1 as usize + 1).min(self.height - 1));
            let mut s = Sums::at([blob.u.round(), blob.v.round()]);
            // cover = ((1 − p/bg) / (1 − ratio) − floor) / (1 − floor),
            // as a − b·p/bg.
            let scale = 1.0 / ((1.0 - blob.ratio) * (1.0 - COVER_FLOOR));
            let a = (1.0 - (1.0 - blob.ratio) * COVER_FLOOR) * scale;
            for v in v0..=v1 {
                self.fill_row_background(v, u0..u1 + 1);
                let row = &pixels[v * stride + u0..v * stride + u1 + 1];
                // Σ cover · xᵖ along the row, then into the moments once.
                let mut along = [0.0f64; 5];
                for (k, (&p, &bg)) in row.iter().zip(&self.row_bg[u0..=u1]).enumerate() {
                    let cover = a - scale * f64::from(p) / f64::from(bg.max(1.0));
                    if cover > 0.0 {
                        let x = (u0 + k) as f64 - s.origin[0];
                        let mut term = cover.min(1.0);
                        for sum in &mut along {
                            *sum += term;
                            term *= x;
                        }
                    }
                }
                s.add_row(v as f64, &along);
            }
            if s.m[0] > 0.0 {
                let weighted = blob_of(&s);
                let blob = &mut self.blobs[b];
                (blob.u, blob.v, blob.mu3, blob.mu4) = (weighted.u, weighted.v, weighted.mu3, weighted.mu4);
            }
        }
    }

    /// Split each blob the size of two parts at the line through its
    /// centroid across its long axis: two touching discs are cut exactly
    /// at their contact. Each half gets its own moments and brightness.
    fn split_pairs(&mut self, pixels: &[u8], stride: usize) {
        let low = self.params.split_above_px;
        if low <= 0.0 {
            return;
        }
        let high = low * 2.6 / 1.5;
        for b in 0..self.blobs.len() {
            let blob = self.blobs[b];
            if blob.split || blob.cut || blob.area < low || blob.area > high {
                continue;
            }
            let angle = 0.5 * (2.0 * blob.mu11).atan2(blob.mu20 - blob.mu02);
            let (ex, ey) = (angle.cos(), angle.sin());
            let mut halves = [Sums::at([blob.u.round(), blob.v.round()]); 2];
            for (r, run) in self.runs.iter().enumerate() {
                if self.run_blob[r] as usize != b {
                    continue;
                }
                let v = run.v as f64;
                let (u0, u1) = (run.u0 as usize, run.u1 as usize);
                let row = &pixels[run.v as usize * stride + u0..run.v as usize * stride + u1];
                for (u, &p) in (u0..u1).zip(row) {
                    let uf = u as f64;
                    let h = &mut halves[usize::from((uf - blob.u) * ex + (v - blob.v) * ey >= 0.0)];
                    h.add_pixel(uf, v);
                    h.ratio += (p as f32 / self.background_at(u, run.v as usize).max(1.0)) as f64;
                }
            }
            if halves.iter().all(|h| h.m[0] > 0.0) && self.blobs.len() < self.blobs.capacity() {
                let [a, c] = halves.map(|h| Blob { split: true, ..blob_of(&h) });
                self.blobs[b] = a;
                self.blobs.push(c);
            }
        }
    }
}

/// C(n, k) for n ≤ 4.
pub fn binomial(n: usize, k: usize) -> f64 {
    const PASCAL: [[f64; 5]; 5] = [
        [1.0, 0.0, 0.0, 0.0, 0.0],
        [1.0, 1.0, 0.0, 0.0, 0.0],
        [1.0, 2.0, 1.0, 0.0, 0.0],
        [1.0, 3.0, 3.0, 1.0, 0.0],
        [1.0, 4.0, 6.0, 4.0, 1.0],
    ];
    PASCAL[n][k]
}

fn blob_of(s: &Sums) -> Blob {
    let m = &s.m;
    let n = m[0];
    // Centroid about the origin, then the central moments μ_pq.
    let (cu, cv) = (m[at(1, 0)] / n, m[at(0, 1)] / n);
    let mu = |p: usize, q: usize| {
        let mut sum = 0.0;
        for r in 0..=p {
            for t in 0..=q {
                sum += binomial(p, r)
                    * binomial(q, t)
                    * (-cu).powi((p - r) as i32)
                    * (-cv).powi((q - t) as i32)
                    * m[at(r, t)];
            }
        }
        sum
    };
    Blob {
        area: n,
        u: s.origin[0] + cu,
        v: s.origin[1] + cv,
        mu20: mu(2, 0) / n,
        mu02: mu(0, 2) / n,
        mu11: mu(1, 1) / n,
        mu3: [0, 1, 2, 3].map(|q| mu(3 - q, q)),
        mu4: [0, 1, 2, 3, 4].map(|q| mu(4 - q, q)),
        bbox: s.bbox,
        ratio: s.ratio / n,
        cut: s.cut,
        split: false,
    }
}

#[cfg(test)]
mod moment_tests {
    use super::*;

    /// Closed-form run sums equal pixel-by-pixel sums, wherever the origin.
    #[test]
    fn run_sums_match_pixel_sums() {
        let mut by_run = Sums::at([7.0, -3.0]);
        let mut by_pixel = Sums::at([7.0, -3.0]);
        for (a, b, v) in [(2.0, 11.0, 1.0), (-4.0, 3.0, 2.0), (9.0, 9.0, -5.0)] {
            by_run.add_run(a, b, v);
            let mut u = a;
            while u <= b {
                by_pixel.add_pixel(u, v);
                u += 1.0;
            }
        }
        for k in 0..MOMENTS {
            assert!((by_run.m[k] - by_pixel.m[k]).abs() <= 1e-9 * by_pixel.m[k].abs().max(1.0), "{k}");
        }
    }

    /// A square's fourth complex moment turns four times as fast as the
    /// square; the central moments do not depend on the origin.
    #[test]
    fn square_orientation_from_the_fourth_moment() {
        let blob_at = |angle: f64, origin: [f64; 2]| {
            let mut s = Sums::at(origin);
            let r = 40.0;
            for v in -60..=60 {
                for u in -60..=60 {
                    let (x, y) = (u as f64, v as f64);
                    let (c, d) = (x * angle.cos() + y * angle.sin(), -x * angle.sin() + y * angle.cos());
                    if c.abs() <= r && d.abs() <= r {
                        s.add_pixel(x + 500.0, y + 300.0);
                    }
                }
            }
            blob_of(&s)
        };
        // Σ (Δu + iΔv)⁴ = Σ_q C(4, q) i^q μ_(4-q, q).
        let phase = |b: &Blob| {
            let m = b.mu4;
            let (re, im) = (m[0] - 6.0 * m[2] + m[4], 4.0 * m[1] - 4.0 * m[3]);
            im.atan2(re)
        };
        let flat = blob_at(0.0, [480.0, 290.0]);
        assert!((flat.u - 500.0).abs() < 1e-9 && (flat.v - 300.0).abs() < 1e-9);
        for angle in [0.1f64, 0.3, -0.5] {
            let b = blob_at(angle, [0.0, 0.0]);
            let turned = phase(&b) - phase(&flat);
            let seen = crate::class_outline::wrap_period(turned / 4.0, core::f64::consts::FRAC_PI_2);
            assert!((seen - angle).abs() < 0.01, "{angle}: {seen}");
        }
    }
}
