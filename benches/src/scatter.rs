//! One panel of a time-against-error scatter: a point per setting, coloured by one property,
//! filled or hollow by a second and a circle or triangle by a third, each labelled. Shared by
//! `plot-gi` and `plot-upscale`, with the grid of one panel per scene around it.

use plotters::coord::Shift;
use plotters::prelude::*;

/// A point of the scatter.
pub struct Point {
    /// Across: GPU ms per frame.
    pub x: f64,
    /// Up: the error.
    pub y: f64,
    /// Its colour.
    pub colour: RGBAColor,
    /// Filled, else drawn as an outline.
    pub filled: bool,
    /// A triangle, else a circle.
    pub triangle: bool,
    /// Text beside it.
    pub label: String,
}

/// Draws `points` into `area` with axes from the points' extent (errors from 0).
pub fn panel(
    area: &DrawingArea<BitMapBackend, Shift>,
    caption: &str,
    (x_desc, y_desc): (&str, &str),
    points: &[&Point],
) -> Result<(), String> {
    let max_x = points.iter().map(|p| p.x).fold(0.0, f64::max) * 1.1;
    let min_x = points.iter().map(|p| p.x).fold(f64::INFINITY, f64::min) * 0.9;
    let max_y = points.iter().map(|p| p.y).fold(0.0, f64::max) * 1.15;
    let mut chart = ChartBuilder::on(area)
        .caption(caption, ("sans-serif", 20))
        .margin(14)
        .x_label_area_size(44)
        .y_label_area_size(72)
        .build_cartesian_2d(min_x..max_x, 0.0..max_y)
        .map_err(|e| e.to_string())?;
    chart
        .configure_mesh()
        .x_desc(x_desc)
        .y_desc(y_desc)
        .label_style(("sans-serif", 13))
        .draw()
        .map_err(|e| e.to_string())?;
    for p in points {
        let style = if p.filled {
            p.colour.filled()
        } else {
            p.colour.stroke_width(2)
        };
        let at = (p.x, p.y);
        let label = Text::new(p.label.clone(), (7, -6), ("sans-serif", 11).into_font());
        let drawn = if p.triangle {
            chart.draw_series(std::iter::once(
                EmptyElement::at(at) + TriangleMarker::new((0, 0), 6, style) + label,
            ))
        } else {
            chart.draw_series(std::iter::once(
                EmptyElement::at(at) + Circle::new((0, 0), 5, style) + label,
            ))
        };
        drawn.map_err(|e| e.to_string())?;
    }
    Ok(())
}

/// Draws one panel per scene (two across) into a PNG at `out` under `title`: `points` holds
/// (scene, point) pairs; scenes come in name order. Fails when there are none.
pub fn scene_grid(
    out: &str,
    title: (&str, u32),
    points: Vec<(String, Point)>,
) -> Result<(), String> {
    let mut scenes: Vec<&str> = points.iter().map(|(s, _)| s.as_str()).collect();
    scenes.sort();
    scenes.dedup();
    if scenes.is_empty() {
        return Err("no rows with both a time and an error".into());
    }
    let cols = scenes.len().min(2);
    let grid = scenes.len().div_ceil(cols);
    let root =
        BitMapBackend::new(out, (700 * cols as u32, 520 * grid as u32 + 40)).into_drawing_area();
    root.fill(&WHITE).map_err(|e| e.to_string())?;
    let root = root
        .titled(title.0, ("sans-serif", title.1))
        .map_err(|e| e.to_string())?;
    for (scene, area) in scenes.iter().zip(root.split_evenly((grid, cols)).iter()) {
        let mine: Vec<&Point> = points
            .iter()
            .filter(|(s, _)| s == scene)
            .map(|(_, p)| p)
            .collect();
        panel(
            area,
            scene,
            ("GPU ms per frame", "relMSE, one frame"),
            &mine,
        )?;
    }
    root.present().map_err(|e| e.to_string())?;
    eprintln!("wrote {out}");
    Ok(())
}
