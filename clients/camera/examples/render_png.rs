//! Render one frame of the default `[camera]` with a few parts and save it
//! as a PNG: `cargo run --release -p upm-camera --example render_png -- out.png`.

use ipc_types::{PartState, PartStates};
use upm_camera::{CameraSection, Renderer};

fn main() -> anyhow::Result<()> {
    let path = std::env::args().nth(1).unwrap_or_else(|| "frame.png".into());
    let mut renderer = Renderer::new(&CameraSection::default()).map_err(anyhow::Error::msg)?;
    let model = *renderer.model();
    let mut truth = PartStates::new();
    for (i, (x, y, vx)) in
        [(-0.6, 0.2, 0.0), (-0.2, -0.1, 0.3), (0.3, 0.25, 0.0), (0.95, -0.45, 0.0)].iter().enumerate()
    {
        truth.push(PartState::new(i as u32 + 1, (i % 2) as u32, 0, [*x, *y, 0.0], [*vx, 0.0, 0.0]))?;
    }
    let pixels = renderer.render(&truth).to_vec();
    image::GrayImage::from_raw(model.width, model.height, pixels)
        .ok_or_else(|| anyhow::anyhow!("frame size"))?
        .save(&path)?;
    eprintln!("wrote {path} ({} × {})", model.width, model.height);
    Ok(())
}
