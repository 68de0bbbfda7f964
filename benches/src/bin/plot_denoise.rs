//! Draws a `solari bench-denoise` run: on the left the RMSE against the reference per frame
//! (raw frame, plain accumulation of the raw frames, and the denoised frame for each à-trous
//! setting); on the right the RMS change from the previous frame, which on a static view is
//! flicker. Both x axes are logarithmic in the frame number.
//!
//! `cargo run -p solari-benches --bin plot-denoise -- DENOISE.csv OUT.png [--font FONT.ttf]`

use plotters::coord::Shift;
use plotters::coord::ranged1d::ValueFormatter;
use plotters::prelude::*;
use solari_benches::denoise::{DenoiseRow, parse_denoise};
use solari_benches::font::PlotInput;

fn main() {
    PlotInput::exit_on_error(run);
}

/// One line: its legend, colour and points.
struct Line {
    label: String,
    colour: RGBAColor,
    points: Vec<(f64, f64)>,
}

fn run() -> Result<(), String> {
    let PlotInput { csv, text, out } =
        PlotInput::from_args("usage: plot-denoise DENOISE.csv OUT.png [--font FONT.ttf]")?;
    let (csv, out) = (&csv, &out);
    let rows = parse_denoise(&text)?;
    let first = rows.first().ok_or(format!("{csv}: no rows"))?;
    let mut settings: Vec<u32> = rows.iter().map(|r| r.iterations).collect();
    settings.sort();
    settings.dedup();
    // The raw columns do not depend on the denoiser's setting: take them from the first.
    let raw: Vec<&DenoiseRow> = rows
        .iter()
        .filter(|r| r.iterations == settings[0])
        .collect();
    let series = |f: &dyn Fn(&DenoiseRow) -> f64, pick: &dyn Fn(&DenoiseRow) -> bool| {
        rows.iter()
            .filter(|r| pick(r))
            .map(|r| (r.frame as f64, f(r)))
            .filter(|(_, v)| v.is_finite() && *v > 0.0)
            .collect::<Vec<_>>()
    };
    let grey = RGBAColor(120, 120, 120, 1.0);
    let black = RGBAColor(0, 0, 0, 1.0);
    let first_it = settings[0];
    let mut error = vec![
        Line {
            label: "raw frame".into(),
            colour: grey,
            points: series(&|r| r.rmse_raw, &|r| r.iterations == first_it),
        },
        Line {
            label: "raw, mean of all frames so far".into(),
            colour: black,
            points: series(&|r| r.rmse_raw_mean, &|r| r.iterations == first_it),
        },
    ];
    let mut change = vec![Line {
        label: "raw frame".into(),
        colour: grey,
        points: series(&|r| r.change_raw, &|r| r.iterations == first_it),
    }];
    for (i, it) in settings.iter().enumerate() {
        let colour = Palette99::pick(i + 1).to_rgba();
        let label = format!("denoised, {it} à-trous iterations");
        error.push(Line {
            label: label.clone(),
            colour,
            points: series(&|r| r.rmse_denoised, &|r| r.iterations == *it),
        });
        change.push(Line {
            label,
            colour,
            points: series(&|r| r.change_denoised, &|r| r.iterations == *it),
        });
    }
    let frames = raw.iter().map(|r| r.frame).max().unwrap_or(1).max(2) as f64;
    let root = BitMapBackend::new(out, (1400, 620)).into_drawing_area();
    root.fill(&WHITE).map_err(|e| e.to_string())?;
    let root = root
        .titled(
            &format!(
                "{} {}×{}: fallback denoiser against frame count (static view)",
                scene_name(&first.scene),
                first.width,
                first.height
            ),
            ("sans-serif", 24),
        )
        .map_err(|e| e.to_string())?;
    let panels = root.split_evenly((1, 2));
    panel(
        &panels[0],
        &error,
        frames,
        true,
        "RMSE against the direct-only reference (log)",
    )?;
    panel(
        &panels[1],
        &change,
        frames,
        true,
        "RMS change from the previous frame (log)",
    )?;
    root.present().map_err(|e| e.to_string())?;
    eprintln!("wrote {out}");
    Ok(())
}

/// The file stem of a scene path (the CSV holds the path as given on the command line).
fn scene_name(scene: &str) -> &str {
    std::path::Path::new(scene)
        .file_stem()
        .and_then(|s| s.to_str())
        .unwrap_or(scene)
}

/// One chart of `lines` over frames 1..`frames` (log x; log y when `log_y`).
fn panel(
    area: &DrawingArea<BitMapBackend, Shift>,
    lines: &[Line],
    frames: f64,
    log_y: bool,
    y_desc: &str,
) -> Result<(), String> {
    let values = lines.iter().flat_map(|l| l.points.iter().map(|p| p.1));
    let max = values.clone().fold(0.0, f64::max) * 1.15;
    // Room below the lowest line for the legend.
    let min = values.fold(f64::INFINITY, f64::min) * 0.25;
    if !max.is_finite() || max <= 0.0 {
        return Err("nothing to plot: every value is missing or zero".into());
    }
    let mut builder = ChartBuilder::on(area);
    builder
        .margin(16)
        .x_label_area_size(48)
        .y_label_area_size(80);
    let x = (1.0..frames).log_scale();
    if log_y {
        let mut chart = builder
            .build_cartesian_2d(x, (min.max(1e-9)..max).log_scale())
            .map_err(|e| e.to_string())?;
        draw(&mut chart, lines, y_desc)
    } else {
        let mut chart = builder
            .build_cartesian_2d(x, 0.0..max)
            .map_err(|e| e.to_string())?;
        draw(&mut chart, lines, y_desc)
    }
}

/// Axes, lines and legend on a built chart.
fn draw<'a, Y>(
    chart: &mut ChartContext<'a, BitMapBackend<'a>, Cartesian2d<LogCoord<f64>, Y>>,
    lines: &[Line],
    y_desc: &str,
) -> Result<(), String>
where
    Y: Ranged<ValueType = f64> + ValueFormatter<f64>,
{
    chart
        .configure_mesh()
        .x_desc("frame")
        .y_desc(y_desc)
        .y_labels(12)
        .x_label_formatter(&|v| format!("{v:.0}"))
        .y_label_formatter(&|v| format!("{v:.2e}"))
        .light_line_style(RGBColor(238, 238, 238))
        .label_style(("sans-serif", 14))
        .draw()
        .map_err(|e| e.to_string())?;
    for l in lines {
        let colour = l.colour;
        chart
            .draw_series(LineSeries::new(
                l.points.iter().copied(),
                colour.stroke_width(2),
            ))
            .map_err(|e| e.to_string())?
            .label(l.label.clone())
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], colour));
    }
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::LowerLeft)
        .background_style(WHITE.mix(0.8))
        .border_style(BLACK)
        .label_font(("sans-serif", 14))
        .draw()
        .map_err(|e| e.to_string())?;
    Ok(())
}
