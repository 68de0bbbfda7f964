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
    let max_ms = rows.iter().map(|r| r.gpu_ms).fold(0.0, f64::max) * 1.1;
    let min_ms = rows.iter().map(|r| r.gpu_ms).fold(f64::INFINITY, f64::min) * 0.9;
    let hi = rows.iter().map(|r| r.rel_mse_1).fold(0.0, f64::max) * 1.15;
    let mut chart = ChartBuilder::on(area)
        .caption(scene, ("sans-serif", 20))
        .margin(14)
        .x_label_area_size(44)
        .y_label_area_size(72)
        .build_cartesian_2d(min_ms..max_ms, 0.0..hi)
        .map_err(|e| e.to_string())?;
    chart
        .configure_mesh()
        .x_desc("GPU ms per frame")
        .y_desc("relMSE, one frame")
        .label_style(("sans-serif", 13))
        .draw()
        .map_err(|e| e.to_string())?;
    for r in rows {
        let c = colour(r.gi());
        let style = if r.specular() {
            c.filled()
        } else {
            c.stroke_width(2)
        };
        let at = (r.gpu_ms, r.rel_mse_1);
        let label = Text::new(r.mode.clone(), (7, -6), ("sans-serif", 11).into_font());
        if r.di_reuse() {
            chart
                .draw_series(std::iter::once(
                    EmptyElement::at(at) + Circle::new((0, 0), 5, style) + label,
                ))
                .map_err(|e| e.to_string())?;
        } else {
            chart
                .draw_series(std::iter::once(
                    EmptyElement::at(at) + TriangleMarker::new((0, 0), 6, style) + label,
                ))
                .map_err(|e| e.to_string())?;
        }
    }
    Ok(())
}
