//! Draws a GI run (`benches/results/gi_table.py`'s CSV) as time against error: one panel per
//! scene, the frame's GPU ms at 1080p across, the relMSE of one frame up (from 0), a point per
//! mode coloured by GI mode, filled with specular GI and hollow without, a triangle where
//! ReSTIR DI ran without reuse.
//!
//! `cargo run -p solari-benches --bin plot-gi -- GI_TABLE.csv OUT.png [--font FONT.ttf]`

use plotters::coord::Shift;
use plotters::prelude::*;
use solari_benches::font::PlotInput;
use solari_benches::gi_table::{GiRow, parse_gi};
use solari_benches::scatter::{self, Point};

fn main() {
    PlotInput::exit_on_error(run);
}

fn run() -> Result<(), String> {
    let PlotInput { csv, text, out } =
        PlotInput::from_args("usage: plot-gi GI_TABLE.csv OUT.png [--font FONT.ttf]")?;
    let (csv, out) = (&csv, &out);
    let rows: Vec<GiRow> = parse_gi(&text)?
        .into_iter()
        .filter(|r| r.gpu_ms.is_finite() && r.rel_mse_1.is_finite() && r.rel_mse_1 > 0.0)
        .collect();
    let mut scenes: Vec<&str> = rows.iter().map(|r| r.scene.as_str()).collect();
    scenes.sort();
    scenes.dedup();
    if scenes.is_empty() {
        return Err(format!("{csv}: no rows with both a time and an error"));
    }
    let cols = scenes.len().min(2);
    let grid = scenes.len().div_ceil(cols);
    let root =
        BitMapBackend::new(out, (700 * cols as u32, 520 * grid as u32 + 40)).into_drawing_area();
    root.fill(&WHITE).map_err(|e| e.to_string())?;
    let root = root
        .titled(
            "GI modes: GPU frame time at 1920×1080 against one frame's relMSE",
            ("sans-serif", 24),
        )
        .map_err(|e| e.to_string())?;
    let panels = root.split_evenly((grid, cols));
    for (scene, area) in scenes.iter().zip(panels.iter()) {
        let mine: Vec<&GiRow> = rows.iter().filter(|r| r.scene == *scene).collect();
        panel(area, scene, &mine)?;
    }
    root.present().map_err(|e| e.to_string())?;
    eprintln!("wrote {out}");
    Ok(())
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

fn panel(
    area: &DrawingArea<BitMapBackend, Shift>,
    scene: &str,
    rows: &[&GiRow],
) -> Result<(), String> {
    let points: Vec<Point> = rows
        .iter()
        .map(|r| Point {
            x: r.gpu_ms,
            y: r.rel_mse_1,
            colour: colour(r.gi()),
            filled: r.specular(),
            triangle: !r.di_reuse(),
            label: r.mode.clone(),
        })
        .collect();
    scatter::panel(
        area,
        scene,
        ("GPU ms per frame", "relMSE, one frame"),
        &points,
    )
}
