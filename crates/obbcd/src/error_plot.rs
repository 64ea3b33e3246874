//! `obbcd error --svg`: the false-positive rate against the frame time, one colour per broad
//! phase, the Pareto front drawn through the points nothing beats and labelled with their width.
//! A point is filled where its period is a synthesis estimate and hollow where it is the
//! configuration's `clock_ns`.

use crate::error::{PeriodFrom, Row};
use anyhow::{bail, Result};
use obb_model::fixed::BroadPhase;
use plotters::prelude::*;
use std::path::Path;

const FONT: &str = "sans-serif";

/// Writes the plot of `rows` to `path`.
pub fn svg(rows: &[Row], title: &str, path: &Path) -> Result<()> {
    let Some(fastest) = rows.iter().map(Row::frame_ms).reduce(f64::min) else {
        bail!("nothing to plot: no configuration completed a frame");
    };
    let slowest = rows.iter().map(Row::frame_ms).fold(fastest, f64::max);
    let worst = rows.iter().map(|r| r.fp_rate()).fold(0.01, f64::max);
    let root = SVGBackend::new(path, (1000, 640)).into_drawing_area();
    root.fill(&WHITE)?;
    let mut chart = ChartBuilder::on(&root)
        .caption(title, (FONT, 18))
        .margin(20)
        .x_label_area_size(50)
        .y_label_area_size(70)
        .build_cartesian_2d(
            (fastest / 1.6..slowest * 1.6).log_scale(),
            0.0..worst * 1.08,
        )?;
    chart
        .configure_mesh()
        .x_desc("frame time (ms): clocks x period (filled: synthesized period, hollow: clock_ns)")
        .y_desc("false-positive rate")
        .draw()?;
    for (k, phase) in BroadPhase::ALL.into_iter().enumerate() {
        let color = Palette99::pick(k).to_rgba();
        let points: Vec<&Row> = rows.iter().filter(|r| r.broad_phase == phase).collect();
        if points.is_empty() {
            continue;
        }
        chart
            .draw_series(points.into_iter().map(|r| {
                let style = match r.period_from {
                    PeriodFrom::Synthesis => color.filled(),
                    PeriodFrom::ClockNs => color.stroke_width(2),
                };
                Circle::new((r.frame_ms(), r.fp_rate()), 5, style)
            }))?
            .label(phase.to_string())
            .legend(move |(x, y)| Circle::new((x, y), 5, color.filled()));
    }
    let mut front: Vec<&Row> = rows.iter().filter(|r| r.pareto).collect();
    front.sort_by(|a, b| a.frame_ms().total_cmp(&b.frame_ms()));
    chart
        .draw_series(LineSeries::new(
            front.iter().map(|r| (r.frame_ms(), r.fp_rate())),
            BLACK.stroke_width(1),
        ))?
        .label("Pareto front")
        .legend(|(x, y)| PathElement::new(vec![(x - 10, y), (x + 10, y)], BLACK));
    chart.draw_series(front.iter().map(|r| {
        Text::new(
            format!(" {} bits", r.width),
            (r.frame_ms(), r.fp_rate()),
            (FONT, 12),
        )
    }))?;
    chart
        .configure_series_labels()
        // Top left, right of the fastest points: frame times between them and the sweep's are
        // rare (a grid of another cell size would land there).
        .position(SeriesLabelPosition::Coordinate(140, 20))
        .background_style(WHITE.mix(0.9))
        .border_style(BLACK)
        .draw()?;
    root.present()?;
    Ok(())
}
