//! The camera model: a pinhole with Brown–Conrady distortion (radial k1,
//! k2; tangential p1, p2) looking at the plate plane z = 0. The rendered
//! camera draws through it and vision maps pixels back to the plate
//! through it; a calibration file holds one (`upm-vision` loads it).
//!
//! Conventions: plate frame as everywhere in UPM (m, z up out of the
//! plate); camera frame x right, y down the image, z along the view;
//! `X_cam = R · X_plate + t`. Pixel (0, 0) is the centre of the top-left
//! pixel.

use serde::{Deserialize, Serialize};

#[derive(Debug, Clone, Copy, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct CameraModel {
    pub width: u32,
    pub height: u32,
    /// Focal lengths and principal point, px.
    pub fx: f64,
    pub fy: f64,
    pub cx: f64,
    pub cy: f64,
    pub k1: f64,
    pub k2: f64,
    pub p1: f64,
    pub p2: f64,
    /// Plate → camera rotation, row-major.
    pub rotation: [[f64; 3]; 3],
    /// Plate → camera translation, m.
    pub translation: [f64; 3],
}

type Mat3 = [[f64; 3]; 3];

fn mul(a: &Mat3, b: &Mat3) -> Mat3 {
    let mut c = [[0.0; 3]; 3];
    for (i, row) in c.iter_mut().enumerate() {
        for (j, v) in row.iter_mut().enumerate() {
            *v = (0..3).map(|k| a[i][k] * b[k][j]).sum();
        }
    }
    c
}

fn apply(m: &Mat3, v: [f64; 3]) -> [f64; 3] {
    [0, 1, 2].map(|i| m[i][0] * v[0] + m[i][1] * v[1] + m[i][2] * v[2])
}

fn transpose(m: &Mat3) -> Mat3 {
    [0, 1, 2].map(|i| [m[0][i], m[1][i], m[2][i]])
}

impl CameraModel {
    /// A camera of `width × height` px with focal length `f` px, principal
    /// point at the image centre, the given distortion, hung where a rig
    /// builder measures it: its lens centre over plate point `(x, y)` at
    /// height `h` (`centre` = `[x, y, h]`, m), looking down, turned by
    /// `yaw` about the vertical and tilted by `tilt` about the plate's x and
    /// y axes (rad; all 0 is straight down with image rows along plate x).
    pub fn mounted(
        width: u32,
        height: u32,
        f: f64,
        distortion: [f64; 4],
        centre: [f64; 3],
        yaw: f64,
        tilt: [f64; 2],
    ) -> Self {
        // Looking straight down: camera x = plate x, camera y = −plate y,
        // camera z = −plate z.
        let down: Mat3 = [[1.0, 0.0, 0.0], [0.0, -1.0, 0.0], [0.0, 0.0, -1.0]];
        let (s, c) = yaw.sin_cos();
        let yaw: Mat3 = [[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]];
        let (s, c) = tilt[0].sin_cos();
        let tx: Mat3 = [[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]];
        let (s, c) = tilt[1].sin_cos();
        let ty: Mat3 = [[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]];
        // Camera → plate: tilt and yaw the straight-down camera.
        let cam_to_plate = mul(&mul(&mul(&ty, &tx), &yaw), &transpose(&down));
        let rotation = transpose(&cam_to_plate);
        let rc = apply(&rotation, centre);
        let [k1, k2, p1, p2] = distortion;
        Self {
            width,
            height,
            fx: f,
            fy: f,
            cx: (width as f64 - 1.0) / 2.0,
            cy: (height as f64 - 1.0) / 2.0,
            k1,
            k2,
            p1,
            p2,
            rotation,
            translation: [-rc[0], -rc[1], -rc[2]],
        }
    }

    /// Distort normalized image coordinates.
    fn distort(&self, x: f64, y: f64) -> (f64, f64) {
        let r2 = x * x + y * y;
        let radial = 1.0 + self.k1 * r2 + self.k2 * r2 * r2;
        let xd = x * radial + 2.0 * self.p1 * x * y + self.p2 * (r2 + 2.0 * x * x);
        let yd = y * radial + self.p1 * (r2 + 2.0 * y * y) + 2.0 * self.p2 * x * y;
        (xd, yd)
    }

    /// Plate point → pixel; `None` behind the camera.
    pub fn project(&self, x: f64, y: f64) -> Option<[f64; 2]> {
        let p = apply(&self.rotation, [x, y, 0.0]);
        let p = [p[0] + self.translation[0], p[1] + self.translation[1], p[2] + self.translation[2]];
        if p[2] <= 1e-9 {
            return None;
        }
        let (xd, yd) = self.distort(p[0] / p[2], p[1] / p[2]);
        Some([self.fx * xd + self.cx, self.fy * yd + self.cy])
    }

    /// Pixel → plate point (the ray through the pixel meets z = 0); `None`
    /// if the ray misses the plate plane or the distortion cannot be undone.
    pub fn unproject(&self, u: f64, v: f64) -> Option<[f64; 2]> {
        let (xd, yd) = ((u - self.cx) / self.fx, (v - self.cy) / self.fy);
        // Fixed-point undistortion: converges for the mild lenses of a
        // machine-vision camera (|k1| r² well below 1).
        let (mut x, mut y) = (xd, yd);
        for _ in 0..30 {
            let (dx, dy) = self.distort(x, y);
            let (ex, ey) = (dx - xd, dy - yd);
            x -= ex;
            y -= ey;
            if ex.abs().max(ey.abs()) < 1e-13 {
                break;
            }
        }
        let (cx, cy) = self.distort(x, y);
        if !((cx - xd).abs() < 1e-9 && (cy - yd).abs() < 1e-9) {
            return None;
        }
        let rt = transpose(&self.rotation);
        let d = apply(&rt, [x, y, 1.0]);
        let c = apply(&rt, self.translation);
        let origin = [-c[0], -c[1], -c[2]];
        if d[2].abs() < 1e-12 {
            return None;
        }
        let s = -origin[2] / d[2];
        (s > 0.0).then(|| [origin[0] + s * d[0], origin[1] + s * d[1]])
    }

    /// Plate metres per pixel near plate point `(x, y)` (the geometric mean
    /// of the two directions).
    pub fn metres_per_pixel(&self, x: f64, y: f64) -> Option<f64> {
        let h = 1e-3;
        let p = self.project(x, y)?;
        let px = self.project(x + h, y)?;
        let py = self.project(x, y + h)?;
        let area = ((px[0] - p[0]) * (py[1] - p[1]) - (px[1] - p[1]) * (py[0] - p[0])).abs();
        Some(h / area.sqrt())
    }

    /// One line naming the first field that makes no sense.
    pub fn validate(&self) -> Result<(), String> {
        if self.width == 0 || self.height == 0 {
            return Err(format!("camera: width × height {} × {} is empty", self.width, self.height));
        }
        let finite = [self.fx, self.fy, self.cx, self.cy, self.k1, self.k2, self.p1, self.p2];
        if finite
            .iter()
            .chain(self.rotation.iter().flatten())
            .chain(&self.translation)
            .any(|v| !v.is_finite())
        {
            return Err("camera: every parameter must be finite".into());
        }
        if self.fx <= 0.0 || self.fy <= 0.0 {
            return Err(format!("camera: focal lengths must be positive, got {} and {}", self.fx, self.fy));
        }
        let rrt = mul(&self.rotation, &transpose(&self.rotation));
        let off = (0..3).flat_map(|i| (0..3).map(move |j| (i, j))).map(|(i, j)| {
            let id = if i == j { 1.0 } else { 0.0 };
            (rrt[i][j] - id).abs()
        });
        if off.fold(0.0, f64::max) > 1e-6 {
            return Err("camera.rotation is not a rotation (R·Rᵀ ≠ I)".into());
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tilted() -> CameraModel {
        CameraModel::mounted(
            2048,
            1152,
            1500.0,
            [-0.08, 0.02, 0.0005, -0.0003],
            [0.02, -0.01, 1.6],
            0.01,
            [0.05, -0.03],
        )
    }

    #[test]
    fn straight_down_maps_plate_x_to_image_columns() {
        let cam = CameraModel::mounted(1001, 501, 1000.0, [0.0; 4], [0.0, 0.0, 1.5], 0.0, [0.0; 2]);
        let [u, v] = cam.project(0.0, 0.0).expect("in front");
        assert!((u - 500.0).abs() < 1e-9 && (v - 250.0).abs() < 1e-9);
        let [u, v] = cam.project(0.15, 0.3).expect("in front");
        assert!((u - 600.0).abs() < 1e-9 && (v - 50.0).abs() < 1e-9, "{u} {v}");
        assert!((cam.metres_per_pixel(0.0, 0.0).expect("mpp") - 1.5e-3).abs() < 1e-9);
    }

    #[test]
    fn unproject_inverts_project_across_the_plate() {
        let cam = tilted();
        cam.validate().expect("valid");
        for i in 0..=20 {
            for j in 0..=10 {
                let (x, y) = (-1.0 + 0.1 * i as f64, -0.5 + 0.1 * j as f64);
                let [u, v] = cam.project(x, y).expect("in front");
                let [bx, by] = cam.unproject(u, v).expect("on the plate");
                assert!((bx - x).abs() < 1e-9 && (by - y).abs() < 1e-9, "({x}, {y}) → ({bx}, {by})");
            }
        }
    }

    #[test]
    fn a_calibration_file_round_trips() {
        let cam = tilted();
        let text = toml::to_string(&cam).expect("serialize");
        let back: CameraModel = toml::from_str(&text).expect("parse");
        assert_eq!(back, cam);
        let bad = CameraModel { rotation: [[2.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]], ..cam };
        assert!(bad.validate().expect_err("not a rotation").contains("camera.rotation"));
    }
}
