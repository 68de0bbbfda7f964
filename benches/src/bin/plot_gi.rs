//! Draws a GI run (`benches/results/gi_table.py`'s CSV) as time against error: one panel per
//! scene, the frame's GPU ms at 1080p across, the relMSE of one frame up (from 0; without the
//! reference's own noise where the table records it: `GiRow::own_rel_mse_1`), a point per
//! mode coloured by GI mode, filled with specular GI and hollow without, a triangle where
//! ReSTIR DI ran without reuse.
//!
//! `cargo run -p solari-benches --bin plot-gi -- GI_TABLE.csv OUT.png [--font FONT.ttf]`

use plotters::prelude::*;
use solari_benches::font::PlotInput;
use solari_benches::gi_table::parse_gi;
use solari_benches::scatter::{self, Point};

fn main() {
    PlotInput::exit_on_error(run);
}

fn run() -> Result<(), String> {
    let PlotInput { csv, text, out } =
        PlotInput::from_args("usage: plot-gi GI_TABLE.csv OUT.png [--font FONT.ttf]")?;
    let points = parse_gi(&text)?
        .into_iter()
        .filter(|r| {
            r.gpu_ms.is_finite() && r.own_rel_mse_1().is_finite() && r.own_rel_mse_1() > 0.0
        })
        .map(|r| {
            let point = Point {
                x: r.gpu_ms,
                y: r.own_rel_mse_1(),
                colour: colour(r.gi()),
                filled: r.specular(),
                triangle: !r.di_reuse(),
                label: r.mode.clone(),
            };
            (r.scene, point)
        })
        .collect();
    let title = "GI modes: GPU frame time at 1920×1080 against one frame's relMSE";
    scatter::scene_grid(&out, (title, 24), points).map_err(|e| format!("{csv}: {e}"))
}

/// The colour of a GI mode.
fn colour(gi: &str) -> RGBAColor {
    match gi {
        "cache" => RGBAColor(31, 119, 180, 1.0),
        "path" => RGBAColor(214, 39, 40, 1.0),
        "restir" => RGBAColor(44, 160, 44, 1.0),
        _ => RGBAColor(120, 120, 120, 1.0),
    }
}
