//! Grouped bar charts with interval whiskers: one group per input, one bar per quantity
//! (first-order and total Sobol' indices), each with its confidence interval.

use std::path::Path;

use plotters::coord::Shift;
use plotters::prelude::*;

use super::{draw_error, picture_format, save_scene, tick_label, PlotError, LINE_COLOURS};

/// One quantity drawn as a bar in every group, with its interval.
#[derive(Debug, Clone)]
pub struct Bars {
    /// Legend text.
    pub name: String,
    /// One value per group.
    pub values: Vec<f64>,
    /// The half-width of each value's interval (a whisker from value − h to value + h).
    pub half_widths: Vec<f64>,
}

/// A bar chart: groups along x, one bar of each [`Bars`] per group.
#[derive(Debug, Clone)]
pub struct BarChart {
    /// Text above the chart.
    pub title: String,
    /// Label of the y axis.
    pub y_label: String,
    /// The groups' names, along x.
    pub groups: Vec<String>,
    /// The quantities.
    pub bars: Vec<Bars>,
}

/// Saves a bar chart (`.png` or `.svg` by extension), written atomically; 160 pixels per
/// group, at least 700 wide.
pub fn save_bar_chart(path: &Path, chart: &BarChart) -> Result<(), PlotError> {
    let picture = picture_format(path)?;
    if chart.groups.is_empty() || chart.bars.is_empty() {
        return Err(PlotError::NoPanels);
    }
    let width = (160 * chart.groups.len() as u64 + 160).max(700);
    save_scene(
        path,
        picture,
        (width, 520),
        |root| draw_bars(root, chart),
        |root| draw_bars(root, chart),
    )
}

fn draw_bars<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    chart: &BarChart,
) -> Result<(), PlotError> {
    root.fill(&WHITE).map_err(draw_error)?;
    let groups = chart.groups.len();
    let finite = |v: f64| v.is_finite();
    let (mut lo, mut hi) = (0.0f64, 1.0f64);
    for b in &chart.bars {
        for (v, h) in b.values.iter().zip(&b.half_widths) {
            if finite(*v) && finite(*h) {
                lo = lo.min(v - h);
                hi = hi.max(v + h);
            }
        }
    }
    let pad = 0.05 * (hi - lo);
    let mut ctx = ChartBuilder::on(root)
        .caption(&chart.title, ("sans-serif", 20))
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(70)
        .build_cartesian_2d(0.0..groups as f64, (lo - pad)..(hi + pad))
        .map_err(draw_error)?;
    let names = chart.groups.clone();
    let label = move |x: &f64| {
        let i = x.floor() as usize;
        if (x - i as f64 - 0.5).abs() < 1e-9 && i < names.len() {
            names[i].clone()
        } else {
            String::new()
        }
    };
    ctx.configure_mesh()
        .disable_x_mesh()
        .x_labels(2 * groups + 1)
        .x_label_formatter(&label)
        .y_desc(chart.y_label.as_str())
        .y_label_formatter(&tick_label)
        .label_style(("sans-serif", 14))
        .draw()
        .map_err(draw_error)?;
    let per = chart.bars.len() as f64;
    let slot = 0.8 / per;
    for (k, b) in chart.bars.iter().enumerate() {
        let colour = LINE_COLOURS[k % LINE_COLOURS.len()];
        let left = |g: usize| g as f64 + 0.1 + k as f64 * slot;
        let rects = b
            .values
            .iter()
            .enumerate()
            .filter(|(_, v)| finite(**v))
            .map(|(g, v)| {
                Rectangle::new(
                    [(left(g), 0.0), (left(g) + 0.9 * slot, *v)],
                    colour.mix(0.8).filled(),
                )
            });
        ctx.draw_series(rects)
            .map_err(draw_error)?
            .label(b.name.as_str())
            .legend(move |(x, y)| Rectangle::new([(x, y - 5), (x + 14, y + 5)], colour.filled()));
        let whiskers = b
            .values
            .iter()
            .zip(&b.half_widths)
            .enumerate()
            .filter(|(_, (v, h))| finite(**v) && finite(**h))
            .flat_map(|(g, (v, h))| {
                // A vertical line from v − h to v + h with a cap at each end.
                let x = left(g) + 0.45 * slot;
                let cap = 0.2 * slot;
                [
                    vec![(x, v - h), (x, v + h)],
                    vec![(x - cap, v - h), (x + cap, v - h)],
                    vec![(x - cap, v + h), (x + cap, v + h)],
                ]
                .map(|line| PathElement::new(line, BLACK.stroke_width(2)))
            });
        ctx.draw_series(whiskers).map_err(draw_error)?;
    }
    ctx.configure_series_labels()
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .label_font(("sans-serif", 14))
        .draw()
        .map_err(draw_error)?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_bar_chart_is_written_in_both_formats_and_refused_when_empty() {
        let dir = std::env::temp_dir().join(format!("sp-bars-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let chart = BarChart {
            title: "Sobol' indices".into(),
            y_label: "index".into(),
            groups: vec!["x1".into(), "x2".into(), "x3".into()],
            bars: vec![
                Bars {
                    name: "first".into(),
                    values: vec![0.31, 0.44, 0.0],
                    half_widths: vec![0.01, 0.01, 0.005],
                },
                Bars {
                    name: "total".into(),
                    values: vec![0.56, 0.44, 0.24],
                    half_widths: vec![0.01, 0.01, 0.01],
                },
            ],
        };
        let png = dir.join("bars.png");
        save_bar_chart(&png, &chart).unwrap();
        let bytes = std::fs::read(&png).unwrap();
        assert_eq!(&bytes[1..4], b"PNG");
        let svg = dir.join("bars.svg");
        save_bar_chart(&svg, &chart).unwrap();
        let text = std::fs::read_to_string(&svg).unwrap();
        assert!(
            text.contains("x2") && text.contains("total"),
            "{}",
            &text[..200]
        );
        let empty = BarChart {
            groups: vec![],
            ..chart.clone()
        };
        assert!(save_bar_chart(&png, &empty).is_err());
        assert!(save_bar_chart(&dir.join("bars.gif"), &chart).is_err());
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
