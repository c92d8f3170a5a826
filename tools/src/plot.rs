//! PNG plots: the latency histograms (count per bucket, log scale) above, the time series
//! below. Text uses egui's bundled Ubuntu font, so no system font is needed.

use std::path::Path;
use std::sync::Once;

use plotters::prelude::*;

use crate::stats::Series;

static FONT: Once = Once::new();

fn register_font() {
    FONT.call_once(|| {
        // The font is egui's own bundled TTF; it parses.
        let _ = plotters::style::register_font(
            "sans-serif",
            FontStyle::Normal,
            epaint_default_fonts::UBUNTU_LIGHT,
        );
    });
}

const COLOURS: [RGBColor; 6] = [
    RGBColor(31, 119, 180),
    RGBColor(214, 39, 40),
    RGBColor(44, 160, 44),
    RGBColor(255, 127, 14),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
];

/// A histogram to draw: name and (bucket value µs, count) pairs, ascending.
pub struct HistogramPlot {
    pub name: String,
    pub buckets: Vec<(f64, u64)>,
}

/// Bucketed counts of an hdrhistogram of ns, in µs, for plotting.
pub fn buckets_of(h: &hdrhistogram::Histogram<u64>) -> Vec<(f64, u64)> {
    if h.is_empty() {
        return Vec::new();
    }
    // About 200 log-spaced buckets from the minimum to the maximum.
    let (lo, hi) = (h.min().max(1) as f64, h.max().max(2) as f64);
    let steps = 200;
    let ratio = (hi / lo).powf(1.0 / steps as f64).max(1.0 + 1e-9);
    let mut out = Vec::new();
    let mut from = lo;
    for _ in 0..steps {
        let to = from * ratio;
        let c = h.count_between(from as u64, to as u64);
        if c > 0 {
            out.push((to / 1000.0, c));
        }
        from = to;
    }
    out
}

/// Draws `title`, the histograms and the time series into a PNG at `path`.
pub fn draw(
    path: &Path,
    title: &str,
    hists: &[HistogramPlot],
    series: &[Series],
    series_unit: &str,
) -> Result<(), String> {
    register_font();
    let e = |e: &dyn std::fmt::Display| format!("plot {}: {e}", path.display());
    let root = BitMapBackend::new(path, (1200, 900)).into_drawing_area();
    root.fill(&WHITE).map_err(|x| e(&x))?;
    let root = root.titled(title, ("sans-serif", 26)).map_err(|x| e(&x))?;
    let (top, bottom) = root.split_vertically(430);

    // Histograms: x µs (log), y count (log).
    let xs = hists.iter().flat_map(|h| h.buckets.iter().map(|b| b.0));
    let (mut xmin, mut xmax) = (f64::INFINITY, 0.0f64);
    for x in xs {
        xmin = xmin.min(x);
        xmax = xmax.max(x);
    }
    if !xmin.is_finite() {
        (xmin, xmax) = (1.0, 10.0);
    }
    let ymax = hists
        .iter()
        .flat_map(|h| h.buckets.iter().map(|b| b.1))
        .max()
        .unwrap_or(1)
        .max(1) as f64;
    let mut chart = ChartBuilder::on(&top)
        .margin(12)
        .caption("histogram", ("sans-serif", 18))
        .x_label_area_size(40)
        .y_label_area_size(60)
        .build_cartesian_2d(
            ((xmin * 0.8).max(0.01)..xmax * 1.25).log_scale(),
            (0.8..ymax * 2.0).log_scale(),
        )
        .map_err(|x| e(&x))?;
    chart
        .configure_mesh()
        .x_desc("latency, µs")
        .y_desc("count")
        .label_style(("sans-serif", 14))
        .draw()
        .map_err(|x| e(&x))?;
    for (k, h) in hists.iter().enumerate() {
        let c = COLOURS[k % COLOURS.len()];
        // One stick per non-empty bucket: sparse distributions stay readable.
        chart
            .draw_series(h.buckets.iter().map(|&(x, n)| {
                PathElement::new(vec![(x, 0.8), (x, n as f64)], c.mix(0.8).stroke_width(2))
            }))
            .map_err(|x| e(&x))?
            .label(h.name.clone())
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], c.stroke_width(2)));
    }
    if !hists.is_empty() {
        chart
            .configure_series_labels()
            .background_style(WHITE.mix(0.8))
            .border_style(BLACK)
            .label_font(("sans-serif", 14))
            .draw()
            .map_err(|x| e(&x))?;
    }

    // Time series.
    let tmax = series
        .iter()
        .flat_map(|s| s.points.iter().map(|p| p.0))
        .fold(1e-3, f64::max);
    let vmax = series
        .iter()
        .flat_map(|s| s.points.iter().map(|p| p.1))
        .fold(1e-3, f64::max);
    let mut chart = ChartBuilder::on(&bottom)
        .margin(12)
        .caption("over time", ("sans-serif", 18))
        .x_label_area_size(40)
        .y_label_area_size(60)
        .build_cartesian_2d(0.0..tmax, 0.0..vmax * 1.1)
        .map_err(|x| e(&x))?;
    chart
        .configure_mesh()
        .x_desc("time, s")
        .y_desc(series_unit)
        .label_style(("sans-serif", 14))
        .draw()
        .map_err(|x| e(&x))?;
    for (k, s) in series.iter().enumerate() {
        let c = COLOURS[k % COLOURS.len()];
        chart
            .draw_series(LineSeries::new(s.points.iter().copied(), c.stroke_width(1)))
            .map_err(|x| e(&x))?
            .label(s.name.clone())
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], c.stroke_width(2)));
    }
    if !series.is_empty() {
        chart
            .configure_series_labels()
            .background_style(WHITE.mix(0.8))
            .border_style(BLACK)
            .label_font(("sans-serif", 14))
            .draw()
            .map_err(|x| e(&x))?;
    }
    root.present().map_err(|x| e(&x))?;
    Ok(())
}
