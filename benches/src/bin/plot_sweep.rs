//! Draws a `solari bench-di` sweep as run time against error: one line per light-tile and
//! light-grid setting through its candidate counts, each point labelled with its count.
//!
//! `cargo run -p solari-benches --bin plot-sweep -- SWEEP.csv OUT.png [--font FONT.ttf]`
//!
//! Text needs a TrueType font (see `solari_benches::font`).

use plotters::prelude::*;
use solari_benches::font::PlotInput;
use solari_benches::sweep::{SweepRow, parse_sweep};

fn main() {
    PlotInput::exit_on_error(run);
}

fn run() -> Result<(), String> {
    let PlotInput { csv, text, out } =
        PlotInput::from_args("usage: plot-sweep SWEEP.csv OUT.png [--font FONT.ttf]")?;
    let (csv, out) = (&csv, &out);
    let rows: Vec<SweepRow> = parse_sweep(&text)?
        .into_iter()
        .filter(|r| r.rmse.is_finite() && r.lighting_ms.is_finite())
        .collect();
    if rows.is_empty() {
        return Err(format!("{csv}: no rows with both a time and an error"));
    }
    let max_ms = rows.iter().map(|r| r.lighting_ms).fold(0.0, f64::max) * 1.15;
    let max_err = rows.iter().map(|r| r.rmse).fold(0.0, f64::max) * 1.15;
    let root = BitMapBackend::new(out, (900, 600)).into_drawing_area();
    root.fill(&WHITE).map_err(|e| e.to_string())?;
    let mut chart = ChartBuilder::on(&root)
        .caption(
            format!("{}: ReSTIR DI time against error", rows[0].scene),
            ("sans-serif", 24),
        )
        .margin(16)
        .x_label_area_size(48)
        .y_label_area_size(72)
        .build_cartesian_2d(0.0..max_ms, 0.0..max_err)
        .map_err(|e| e.to_string())?;
    chart
        .configure_mesh()
        .x_desc("GPU ms per frame (light tiles + ReSTIR DI)")
        .y_desc("RMSE of one frame vs the direct-only reference")
        .label_style(("sans-serif", 14))
        .draw()
        .map_err(|e| e.to_string())?;
    let mut settings: Vec<(u32, u32, &str)> = rows
        .iter()
        .map(|r| (r.tiles, r.samples_per_tile, r.light_grid.as_str()))
        .collect();
    settings.sort();
    settings.dedup();
    for (i, (tiles, spt, grid)) in settings.iter().enumerate() {
        let colour = Palette99::pick(i).to_rgba();
        let mut series: Vec<&SweepRow> = rows
            .iter()
            .filter(|r| {
                (r.tiles, r.samples_per_tile, r.light_grid.as_str()) == (*tiles, *spt, *grid)
            })
            .collect();
        series.sort_by_key(|r| r.candidates);
        chart
            .draw_series(LineSeries::new(
                series.iter().map(|r| (r.lighting_ms, r.rmse)),
                colour.stroke_width(2),
            ))
            .map_err(|e| e.to_string())?
            .label(if *grid == "off" {
                format!("{tiles} tiles × {spt}")
            } else {
                format!("{tiles} tiles × {spt}, light grid share {grid}")
            })
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], colour));
        chart
            .draw_series(series.iter().map(|r| {
                EmptyElement::at((r.lighting_ms, r.rmse))
                    + Circle::new((0, 0), 4, colour.filled())
                    + Text::new(
                        format!("{}", r.candidates),
                        (6, -14),
                        ("sans-serif", 13).into_font(),
                    )
            }))
            .map_err(|e| e.to_string())?;
    }
    chart
        .configure_series_labels()
        .background_style(WHITE.mix(0.8))
        .border_style(BLACK)
        .label_font(("sans-serif", 14))
        .draw()
        .map_err(|e| e.to_string())?;
    root.present().map_err(|e| e.to_string())?;
    eprintln!("wrote {out}");
    Ok(())
}
