//! Draws a quality sweep (`benches/results/quality_table.py`'s CSV) as time against error,
//! to compare internal scales: one panel per scene, the frame's GPU ms across, one frame's
//! relMSE up (from 0), a point per setting coloured by internal scale (0.5, 0.67, native,
//! native antialiased), filled where specular GI ran (path and ReSTIR GI), a triangle where
//! ReSTIR DI ran without reuse.
//!
//! `cargo run -p solari-benches --bin plot-upscale -- QUALITY_TABLE.csv OUT.png [--font FONT.ttf]`

use plotters::prelude::*;
use solari_benches::font::PlotInput;
use solari_benches::quality_table::parse_quality;
use solari_benches::scatter::{self, Point};

fn main() {
    PlotInput::exit_on_error(run);
}

/// The colour of an internal scale.
fn colour(scale: &str) -> RGBAColor {
    match scale {
        "50" => RGBAColor(148, 103, 189, 1.0),
        "67" => RGBAColor(31, 119, 180, 1.0),
        "100" => RGBAColor(214, 39, 40, 1.0),
        "aa" => RGBAColor(255, 127, 14, 1.0),
        _ => RGBAColor(120, 120, 120, 1.0),
    }
}

fn run() -> Result<(), String> {
    let PlotInput { csv, text, out } =
        PlotInput::from_args("usage: plot-upscale QUALITY_TABLE.csv OUT.png [--font FONT.ttf]")?;
    let points = parse_quality(&text)?
        .into_iter()
        .filter(|r| r.gpu_ms.is_finite() && r.rel_mse.is_finite() && r.rel_mse > 0.0)
        .map(|r| {
            let point = Point {
                x: r.gpu_ms,
                y: r.rel_mse,
                colour: colour(r.scale()),
                filled: r.gi() != "cache",
                triangle: !r.di_reuse(),
                label: r.setting.clone(),
            };
            (r.scene, point)
        })
        .collect();
    let title = "Internal scale: GPU frame time against one frame's relMSE, 1920×1080 output \
                 (purple 0.5, blue 0.67, red native, orange native AA)";
    scatter::scene_grid(&out, (title, 20), points).map_err(|e| format!("{csv}: {e}"))
}
