//! Pictures of point sets: square scatter plots of coordinates 1 and 2, side by side, with
//! region boundaries traced as lines; matrices of 2-D projections for s > 2; line charts
//! of trajectories; saved as PNG or SVG.
//!
//! Everything is drawn headless with the DejaVu Sans font compiled into the binary
//! (registered with plotters on first use), so pictures come out the same on a machine
//! with no system fonts and no fontconfig. Files are written with
//! [`stillpoint::io::write_atomic`], so a failed save never leaves a broken picture
//! behind.
//!
//! A crate of its own, used by the command line and the paper's reproductions, so that
//! the library and the Python extension do not link plotters, an image encoder and a font.

#![deny(missing_docs)]

use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::OnceLock;

use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};
use plotters::style::FontStyle;

use stillpoint::PointSet;

mod bars;
pub use bars::{save_bar_chart, BarChart, Bars};

/// Width in pixels of one panel of [`save_panels`].
pub const PANEL_WIDTH: u32 = 600;

/// Height in pixels of one panel of [`save_panels`]: a title strip above the plot.
pub const PANEL_HEIGHT: u32 = TITLE_HEIGHT + BODY_HEIGHT;

const TITLE_HEIGHT: u32 = 40;
const MARGIN: u32 = 15;
const X_LABEL_AREA: u32 = 50;
const Y_LABEL_AREA: u32 = 65;
/// Chosen so that the plotting area proper is square: its width is
/// PANEL_WIDTH − 2·MARGIN − Y_LABEL_AREA and its height BODY_HEIGHT − 2·MARGIN −
/// X_LABEL_AREA.
const BODY_HEIGHT: u32 = PANEL_WIDTH - Y_LABEL_AREA + X_LABEL_AREA;

/// Largest picture side in pixels; with [`MAX_PIXELS`] it keeps a mistaken panel count
/// from asking for gigabytes of pixel buffer.
const MAX_SIDE: u32 = 16_384;

/// Largest picture area in pixels (3 bytes each while drawing a PNG).
const MAX_PIXELS: u64 = 40_000_000;

/// Largest marching-squares resolution; (resolution + 1)² evaluations of g are made.
const MAX_RESOLUTION: usize = 4096;

/// One scatter plot: coordinates 1 and 2 of `points` over the box [lo, hi], with
/// `boundary` polylines (e.g. from [`boundary_polylines`]) drawn over the points.
#[derive(Clone, Debug)]
pub struct Panel<'a> {
    /// Text above the plot.
    pub title: String,
    /// The points; their first two coordinates are drawn, points outside the box are not.
    pub points: &'a PointSet,
    /// Lower corner of the plotted box (coordinates 1 and 2).
    pub lo: [f64; 2],
    /// Upper corner of the plotted box.
    pub hi: [f64; 2],
    /// Lines to draw, each a sequence of (x1, x2) vertices; may be empty.
    pub boundary: Vec<Vec<[f64; 2]>>,
    /// Points from this index on are drawn in a second colour (the new points of a set
    /// that grew); `None`: one colour.
    pub split: Option<usize>,
}

/// Why a picture could not be made or saved.
#[derive(Debug, thiserror::Error)]
pub enum PlotError {
    /// The file name does not end in `.png` or `.svg`.
    #[error(
        "{}: cannot tell the picture format from the extension {ext:?}; use .png or .svg",
        path.display()
    )]
    UnsupportedFormat {
        /// The requested file.
        path: PathBuf,
        /// Its extension as written (empty when it has none).
        ext: String,
    },
    /// No panels were given.
    #[error("nothing to plot: no panels were given")]
    NoPanels,
    /// A panel cannot be drawn as asked (bad box, too few coordinates).
    #[error("panel {index} ({title:?}): {message}")]
    Panel {
        /// 1-based panel number.
        index: usize,
        /// Its title.
        title: String,
        /// What is wrong.
        message: String,
    },
    /// The picture would be larger than this module draws.
    #[error(
        "{width} × {height} pixels is too large a picture (at most {MAX_SIDE} per side and \
         {MAX_PIXELS} in all): use fewer panels, or more or fewer columns"
    )]
    TooLarge {
        /// Width asked for.
        width: u64,
        /// Height asked for.
        height: u64,
    },
    /// The embedded font could not be loaded (a build problem, not a user one).
    #[error("cannot load the embedded DejaVu Sans font for plot text")]
    Font,
    /// plotters failed while drawing.
    #[error("drawing failed: {0}")]
    Draw(String),
    /// The PNG encoder failed.
    #[error("PNG encoding failed: {0}")]
    Encode(String),
    /// The file could not be written.
    #[error(transparent)]
    Io(#[from] stillpoint::io::IoError),
}

/// The zero level set {g = 0} of `level` over the box [lo, hi], traced by marching squares.
///
/// The box is cut into `resolution` × `resolution` cells (clamped to 1..=4096); g is
/// evaluated at the (resolution + 1)² grid nodes, each cell edge whose ends have opposite
/// signs (g ≤ 0 against g > 0) is cut where the linear interpolation of g vanishes, and
/// the cuts are joined within each cell. A saddle cell (signs alternating around it) is
/// resolved by the sign of the mean of its corners. Segments are chained into polylines;
/// a closed curve is returned with its first vertex repeated at the end, so that summing
/// consecutive distances gives its length. Cells with a NaN or infinite corner are left
/// out. An empty vector means no sign change was seen.
pub fn boundary_polylines(
    level: &dyn Fn(&[f64]) -> f64,
    lo: [f64; 2],
    hi: [f64; 2],
    resolution: usize,
) -> Vec<Vec<[f64; 2]>> {
    let r = resolution.clamp(1, MAX_RESOLUTION);
    let stride = r + 1;
    let coord = |axis: usize, k: usize| {
        // Interpolating from both ends makes the last node exactly `hi`.
        let t = k as f64 / r as f64;
        lo[axis] * (1.0 - t) + hi[axis] * t
    };
    let node = |i: usize, j: usize| [coord(0, i), coord(1, j)];
    let mut values = Vec::with_capacity(stride * stride);
    for j in 0..stride {
        for i in 0..stride {
            values.push(level(&node(i, j)));
        }
    }
    let value = |i: usize, j: usize| values[j * stride + i];

    // An edge is named by its lower-left node and its direction, so that the two cells
    // sharing it agree on the name and on the cut point computed from it.
    let horizontal = |i: usize, j: usize| 2 * (j * stride + i);
    let vertical = |i: usize, j: usize| 2 * (j * stride + i) + 1;
    let mut cuts: HashMap<usize, [f64; 2]> = HashMap::new();
    let mut cut = |edge: usize, a: (usize, usize), b: (usize, usize)| {
        cuts.entry(edge).or_insert_with(|| {
            let (va, vb) = (value(a.0, a.1), value(b.0, b.1));
            let t = (va / (va - vb)).clamp(0.0, 1.0);
            let (pa, pb) = (node(a.0, a.1), node(b.0, b.1));
            [pa[0] + t * (pb[0] - pa[0]), pa[1] + t * (pb[1] - pa[1])]
        });
        edge
    };

    let mut segments: Vec<[usize; 2]> = Vec::new();
    for j in 0..r {
        for i in 0..r {
            let corners = [(i, j), (i + 1, j), (i + 1, j + 1), (i, j + 1)];
            let v = corners.map(|(a, b)| value(a, b));
            if v.iter().any(|v| !v.is_finite()) {
                continue;
            }
            let outside = v.map(|v| v > 0.0);
            // Edge k runs from corner k to corner k + 1 (bottom, right, top, left).
            let edges = [
                horizontal(i, j),
                vertical(i + 1, j),
                horizontal(i, j + 1),
                vertical(i, j),
            ];
            let crossed: Vec<usize> = (0..4)
                .filter(|&k| outside[k] != outside[(k + 1) % 4])
                .collect();
            let mut join = |k: usize, m: usize| {
                let (a0, b0) = ends(&corners, k);
                let (a1, b1) = ends(&corners, m);
                segments.push([cut(edges[k], a0, b0), cut(edges[m], a1, b1)]);
            };
            match crossed[..] {
                [k, m] => join(k, m),
                [..] if crossed.len() == 4 => {
                    let centre_outside = v.iter().sum::<f64>() / 4.0 > 0.0;
                    // The corners on the other side from the centre are cut off alone;
                    // corner k touches edges k − 1 and k.
                    for (k, &corner_outside) in outside.iter().enumerate() {
                        if corner_outside != centre_outside {
                            join((k + 3) % 4, k);
                        }
                    }
                }
                _ => {}
            }
        }
    }
    chain(&segments, &cuts)
}

/// The two grid nodes at the ends of edge k of a cell with the given corners.
fn ends(corners: &[(usize, usize); 4], k: usize) -> ((usize, usize), (usize, usize)) {
    // Ordered by node so that both cells sharing an edge interpolate in the same direction.
    let (a, b) = (corners[k], corners[(k + 1) % 4]);
    if (a.1, a.0) <= (b.1, b.0) {
        (a, b)
    } else {
        (b, a)
    }
}

/// Joins segments that share an edge cut into polylines, open ones first (they start and
/// end on the box or at a skipped cell), then closed ones. Deterministic: the order follows
/// the cells, never a hash order.
fn chain(segments: &[[usize; 2]], cuts: &HashMap<usize, [f64; 2]>) -> Vec<Vec<[f64; 2]>> {
    const NONE: usize = usize::MAX;
    // Every edge lies in at most two cells and each cell uses an edge at most once.
    let mut at: HashMap<usize, [usize; 2]> = HashMap::with_capacity(segments.len() * 2);
    for (s, seg) in segments.iter().enumerate() {
        for &edge in seg {
            let slot = at.entry(edge).or_insert([NONE, NONE]);
            if slot[0] == NONE {
                slot[0] = s;
            } else if slot[1] == NONE {
                slot[1] = s;
            }
        }
    }
    let degree = |edge: usize| at[&edge].iter().filter(|&&s| s != NONE).count();
    let mut used = vec![false; segments.len()];
    let mut lines = Vec::new();
    let mut walk = |start_edge: usize, start: usize, used: &mut Vec<bool>| {
        let mut line = vec![cuts[&start_edge]];
        let (mut edge, mut s) = (start_edge, start);
        loop {
            used[s] = true;
            let seg = segments[s];
            edge = if seg[0] == edge { seg[1] } else { seg[0] };
            let p = cuts[&edge];
            if line.last() != Some(&p) {
                line.push(p);
            }
            match at[&edge].iter().find(|&&t| t != NONE && !used[t]) {
                Some(&t) => s = t,
                None => break,
            }
        }
        if line.len() >= 2 {
            lines.push(line);
        }
    };
    for s in 0..segments.len() {
        for &edge in &segments[s] {
            if !used[s] && degree(edge) == 1 {
                walk(edge, s, &mut used);
            }
        }
    }
    for s in 0..segments.len() {
        if !used[s] {
            walk(segments[s][0], s, &mut used);
        }
    }
    lines
}

/// The picture size in pixels of `panels` panels laid out in `columns` columns (clamped
/// to 1..=panels), as [`save_panels`] makes it.
pub fn canvas_size(panels: usize, columns: usize) -> (u32, u32) {
    let (w, h) = layout(panels, columns);
    (w.min(u32::MAX as u64) as u32, h.min(u32::MAX as u64) as u32)
}

fn grid(panels: usize, columns: usize) -> (usize, usize) {
    let columns = columns.clamp(1, panels.max(1));
    (panels.div_ceil(columns), columns)
}

fn layout(panels: usize, columns: usize) -> (u64, u64) {
    let (rows, columns) = grid(panels, columns);
    (
        columns as u64 * PANEL_WIDTH as u64,
        rows as u64 * PANEL_HEIGHT as u64,
    )
}

#[derive(Clone, Copy)]
enum Picture {
    Png,
    Svg,
}

/// Saves `panels` as one picture, a grid of square scatter plots `columns` wide (clamped
/// to 1..=panels.len()), each [`PANEL_WIDTH`] × [`PANEL_HEIGHT`] pixels with its title
/// above and tick-labelled axes x1 and x2. The format follows the extension of `path`,
/// `.png` or `.svg` (any case); anything else is refused before anything is drawn or
/// written. The file is replaced atomically.
pub fn save_panels(path: &Path, panels: &[Panel], columns: usize) -> Result<(), PlotError> {
    let picture = picture_format(path)?;
    if panels.is_empty() {
        return Err(PlotError::NoPanels);
    }
    for (k, panel) in panels.iter().enumerate() {
        check_panel(k + 1, panel)?;
    }
    let size = layout(panels.len(), columns);
    save_scene(
        path,
        picture,
        size,
        |root| draw(root, panels, columns),
        |root| draw(root, panels, columns),
    )
}

fn check_panel(index: usize, panel: &Panel) -> Result<(), PlotError> {
    let refuse = |message: String| PlotError::Panel {
        index,
        title: panel.title.clone(),
        message,
    };
    if panel.points.s() < 2 {
        return Err(refuse(format!(
            "the points have {} coordinate; a scatter plot needs at least 2",
            panel.points.s()
        )));
    }
    for axis in 0..2 {
        let (lo, hi) = (panel.lo[axis], panel.hi[axis]);
        if !(lo.is_finite() && hi.is_finite() && lo < hi) {
            return Err(refuse(format!(
                "the box for x{} is [{lo}, {hi}]; it needs finite lo < hi",
                axis + 1
            )));
        }
    }
    Ok(())
}

fn register_font() -> Result<(), PlotError> {
    static REGISTERED: OnceLock<bool> = OnceLock::new();
    let ok = *REGISTERED.get_or_init(|| {
        plotters::style::register_font("sans-serif", FontStyle::Normal, dejavu::sans::regular())
            .is_ok()
    });
    if ok {
        Ok(())
    } else {
        Err(PlotError::Font)
    }
}

fn draw_error(e: impl std::fmt::Display) -> PlotError {
    PlotError::Draw(e.to_string())
}

const POINT_COLOUR: RGBColor = RGBColor(31, 70, 160);
const BOUNDARY_COLOUR: RGBColor = RGBColor(200, 40, 40);
/// The points added to a set that grew: orange against the old points' blue.
const NEW_COLOUR: RGBColor = RGBColor(230, 120, 0);
/// Lighter than the points, so that a histogram's red reference line stands out on it.
const BAR_COLOUR: RGBColor = RGBColor(150, 175, 225);

fn draw<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    panels: &[Panel],
    columns: usize,
) -> Result<(), PlotError> {
    root.fill(&WHITE).map_err(draw_error)?;
    let cells = root.split_evenly(grid(panels.len(), columns));
    for (panel, cell) in panels.iter().zip(cells) {
        draw_panel(&cell, panel)?;
    }
    Ok(())
}

fn draw_panel<DB: DrawingBackend>(
    cell: &DrawingArea<DB, Shift>,
    panel: &Panel,
) -> Result<(), PlotError> {
    let (title_area, body) = cell.split_vertically(TITLE_HEIGHT);
    let (title_width, title_height) = title_area.dim_in_pixel();
    let title_style = TextStyle::from(("sans-serif", 22).into_font())
        .color(&BLACK)
        .pos(Pos::new(HPos::Center, VPos::Center));
    title_area
        .draw_text(
            &panel.title,
            &title_style,
            (title_width as i32 / 2, title_height as i32 / 2),
        )
        .map_err(draw_error)?;

    let (lo, hi) = to_scale(panel.lo, panel.hi, body.dim_in_pixel());
    let mut chart = ChartBuilder::on(&body)
        .margin(MARGIN)
        .x_label_area_size(X_LABEL_AREA)
        .y_label_area_size(Y_LABEL_AREA)
        .build_cartesian_2d(lo[0]..hi[0], lo[1]..hi[1])
        .map_err(draw_error)?;
    chart
        .configure_mesh()
        .x_desc("x1")
        .y_desc("x2")
        .x_labels(8)
        .y_labels(8)
        .max_light_lines(1)
        .label_style(("sans-serif", 14))
        .axis_desc_style(("sans-serif", 16))
        .draw()
        .map_err(draw_error)?;

    let inside = |p: &[f64]| (0..2).all(|k| lo[k] <= p[k] && p[k] <= hi[k]);
    let radius = match panel.points.n() {
        0..=200 => 4,
        201..=2_000 => 3,
        2_001..=20_000 => 2,
        _ => 1,
    };
    let split = panel.split.unwrap_or(usize::MAX);
    chart
        .draw_series(
            panel
                .points
                .rows()
                .enumerate()
                .filter(|(_, p)| inside(p))
                .map(|(i, p)| {
                    let colour = if i < split { POINT_COLOUR } else { NEW_COLOUR };
                    Circle::new((p[0], p[1]), radius, colour.filled())
                }),
        )
        .map_err(draw_error)?;

    // plotters pins out-of-range coordinates to the frame instead of hiding them, so lines
    // are clipped to the box here (which also drops non-finite vertices).
    for piece in panel
        .boundary
        .iter()
        .flat_map(|line| clip_polyline(line, lo, hi))
    {
        chart
            .draw_series(LineSeries::new(
                piece.into_iter().map(|p| (p[0], p[1])),
                BOUNDARY_COLOUR.stroke_width(2),
            ))
            .map_err(draw_error)?;
    }
    Ok(())
}

/// The box widened along one axis so that a unit is as long on both axes in the plotting
/// area of a panel of `size` pixels: a circle looks round, a diamond twice as wide as
/// tall looks so.
fn to_scale(lo: [f64; 2], hi: [f64; 2], size: (u32, u32)) -> ([f64; 2], [f64; 2]) {
    let w = size.0.saturating_sub(2 * MARGIN + Y_LABEL_AREA).max(1) as f64;
    let h = size.1.saturating_sub(2 * MARGIN + X_LABEL_AREA).max(1) as f64;
    let (dx, dy) = (hi[0] - lo[0], hi[1] - lo[1]);
    if !(dx > 0.0 && dy > 0.0 && dx.is_finite() && dy.is_finite()) {
        return (lo, hi);
    }
    if dx / w > dy / h {
        let pad = (dx * h / w - dy) / 2.0;
        ([lo[0], lo[1] - pad], [hi[0], hi[1] + pad])
    } else {
        let pad = (dy * w / h - dx) / 2.0;
        ([lo[0] - pad, lo[1]], [hi[0] + pad, hi[1]])
    }
}

/// The parts of a polyline inside the box [lo, hi], each with at least two vertices.
fn clip_polyline(line: &[[f64; 2]], lo: [f64; 2], hi: [f64; 2]) -> Vec<Vec<[f64; 2]>> {
    let mut pieces = Vec::new();
    let mut piece: Vec<[f64; 2]> = Vec::new();
    let mut finish = |piece: &mut Vec<[f64; 2]>| {
        if piece.len() >= 2 {
            pieces.push(std::mem::take(piece));
        } else {
            piece.clear();
        }
    };
    for w in line.windows(2) {
        match clip_segment(w[0], w[1], lo, hi) {
            Some((c, d)) => {
                if piece.last() != Some(&c) {
                    finish(&mut piece);
                    piece.push(c);
                }
                piece.push(d);
                if d != w[1] {
                    finish(&mut piece);
                }
            }
            None => finish(&mut piece),
        }
    }
    finish(&mut piece);
    pieces
}

/// Liang–Barsky: the part of segment a–b inside the box, if any. Endpoints inside the box
/// are returned unchanged, so that consecutive clipped segments still join exactly.
fn clip_segment(
    a: [f64; 2],
    b: [f64; 2],
    lo: [f64; 2],
    hi: [f64; 2],
) -> Option<([f64; 2], [f64; 2])> {
    if !a.iter().chain(&b).all(|v| v.is_finite()) {
        return None;
    }
    let (mut t0, mut t1) = (0.0f64, 1.0f64);
    for k in 0..2 {
        let d = b[k] - a[k];
        for (p, q) in [(-d, a[k] - lo[k]), (d, hi[k] - a[k])] {
            if p == 0.0 {
                if q < 0.0 {
                    return None;
                }
            } else {
                let t = q / p;
                if p < 0.0 {
                    t0 = t0.max(t);
                } else {
                    t1 = t1.min(t);
                }
            }
        }
    }
    if t0 > t1 {
        return None;
    }
    let at = |t: f64| [a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])];
    let c = if t0 > 0.0 { at(t0) } else { a };
    let d = if t1 < 1.0 { at(t1) } else { b };
    Some((c, d))
}

fn encode_png(rgb: &[u8], (width, height): (u32, u32)) -> Result<Vec<u8>, PlotError> {
    let mut bytes = Vec::new();
    let mut encoder = png::Encoder::new(&mut bytes, width, height);
    encoder.set_color(png::ColorType::Rgb);
    encoder.set_depth(png::BitDepth::Eight);
    let encode_error = |e: png::EncodingError| PlotError::Encode(e.to_string());
    let mut writer = encoder.write_header().map_err(encode_error)?;
    writer.write_image_data(rgb).map_err(encode_error)?;
    writer.finish().map_err(encode_error)?;
    Ok(bytes)
}

/// One curve of a line chart.
#[derive(Debug, Clone)]
pub struct Series {
    /// Legend text.
    pub name: String,
    /// (x, y) points in drawing order; non-finite points are skipped.
    pub points: Vec<(f64, f64)>,
}

/// A chart of curves against a common x axis.
#[derive(Debug, Clone)]
pub struct LineChart {
    /// Text above the chart.
    pub title: String,
    /// Label of the x axis.
    pub x_label: String,
    /// Label of the y axis.
    pub y_label: String,
    /// Draw y on a log scale (for energies and discrepancies falling over decades).
    pub log_y: bool,
    /// The curves.
    pub series: Vec<Series>,
}

// Ten distinct colours, so a chart of every baseline and the DEM never repeats one.
const LINE_COLOURS: [RGBColor; 10] = [
    RGBColor(31, 70, 160),
    RGBColor(200, 40, 40),
    RGBColor(30, 140, 60),
    RGBColor(150, 60, 170),
    RGBColor(220, 130, 20),
    RGBColor(40, 160, 170),
    RGBColor(120, 120, 120),
    RGBColor(140, 86, 75),
    RGBColor(227, 119, 194),
    RGBColor(188, 189, 34),
];

/// Saves line charts side by side (`.png` or `.svg` by extension), written atomically.
pub fn save_line_charts(path: &Path, charts: &[LineChart]) -> Result<(), PlotError> {
    save_line_chart_grid(path, charts, charts.len())
}

/// Saves line charts in a grid `columns` wide (clamped to 1..=charts.len()), each 700 ×
/// 520 pixels, `.png` or `.svg` by extension, written atomically.
pub fn save_line_chart_grid(
    path: &Path,
    charts: &[LineChart],
    columns: usize,
) -> Result<(), PlotError> {
    let picture = picture_format(path)?;
    if charts.is_empty() {
        return Err(PlotError::NoPanels);
    }
    let (rows, columns) = grid(charts.len(), columns);
    let size = (700 * columns as u64, 520 * rows as u64);
    let shape = (rows, columns);
    save_scene(
        path,
        picture,
        size,
        |root| draw_charts(root, charts, shape),
        |root| draw_charts(root, charts, shape),
    )
}

fn draw_charts<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    charts: &[LineChart],
    shape: (usize, usize),
) -> Result<(), PlotError> {
    root.fill(&WHITE).map_err(draw_error)?;
    for (chart, cell) in charts.iter().zip(root.split_evenly(shape)) {
        // Values beyond 1e300 cannot be given an axis with room around them.
        let finite =
            |p: &&(f64, f64)| p.0.abs() < 1e300 && p.1.abs() < 1e300 && (!chart.log_y || p.1 > 0.0);
        let all: Vec<(f64, f64)> = chart
            .series
            .iter()
            .flat_map(|s| s.points.iter().filter(finite).copied())
            .collect();
        if all.is_empty() {
            continue;
        }
        let (mut x0, mut x1) = all
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), p| {
                (a.min(p.0), b.max(p.0))
            });
        let (mut y0, mut y1) = all
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), p| {
                (a.min(p.1), b.max(p.1))
            });
        if x1 <= x0 {
            x1 = x0 + 1.0;
            x0 -= 0.0;
        }
        if y1 <= y0 {
            let pad = if y0 == 0.0 { 1.0 } else { y0.abs() * 0.1 };
            y0 -= pad;
            y1 += pad;
        } else if chart.log_y {
            // Room above and below so the extreme curves are not drawn on the frame; at
            // most MAX_DECADES decades, so that the axis stays readable (and cheap).
            y0 = (y0 * 0.8).max(y1 * 1.25 / 10f64.powi(MAX_DECADES));
            y1 *= 1.25;
        } else {
            let pad = 0.05 * (y1 - y0);
            y0 -= pad;
            y1 += pad;
        }
        let mut builder = ChartBuilder::on(&cell);
        builder
            .caption(&chart.title, ("sans-serif", 20))
            .margin(12)
            .x_label_area_size(40)
            .y_label_area_size(80);
        macro_rules! body {
            ($ctx:expr) => {{
                let mut ctx = $ctx;
                ctx.configure_mesh()
                    .x_desc(chart.x_label.as_str())
                    .y_desc(chart.y_label.as_str())
                    .x_label_formatter(&tick_label)
                    .y_label_formatter(&tick_label)
                    .label_style(("sans-serif", 14))
                    .draw()
                    .map_err(draw_error)?;
                for (k, s) in chart.series.iter().enumerate() {
                    let colour = LINE_COLOURS[k % LINE_COLOURS.len()];
                    let pts: Vec<(f64, f64)> = s.points.iter().filter(finite).copied().collect();
                    ctx.draw_series(LineSeries::new(pts, colour.stroke_width(2)))
                        .map_err(draw_error)?
                        .label(s.name.as_str())
                        .legend(move |(x, y)| {
                            PathElement::new(vec![(x, y), (x + 18, y)], colour.stroke_width(2))
                        });
                }
                ctx.configure_series_labels()
                    .background_style(WHITE.mix(0.85))
                    .border_style(BLACK)
                    .label_font(("sans-serif", 14))
                    .draw()
                    .map_err(draw_error)?;
            }};
        }
        if chart.log_y {
            body!(builder
                .build_cartesian_2d(x0..x1, (y0..y1).log_scale())
                .map_err(draw_error)?);
        } else {
            body!(builder
                .build_cartesian_2d(x0..x1, y0..y1)
                .map_err(draw_error)?);
        }
    }
    Ok(())
}

/// The most decades a log-scale axis spans; lower values are drawn at its bottom edge.
const MAX_DECADES: i32 = 30;

/// A short axis label: 6 significant digits with trailing zeros dropped (enough for an
/// energy that moves by 1e-4 of itself), scientific outside [1e-3, 1e5), so an axis never
/// prints binary rounding such as 0.30000000000000004.
fn tick_label(v: &f64) -> String {
    let a = v.abs();
    if *v == 0.0 {
        "0".into()
    } else if !(1e-3..1e5).contains(&a) {
        format!("{v:.1e}")
    } else {
        let digits = (5 - a.log10().floor() as i32).max(0) as usize;
        let s = format!("{v:.digits$}");
        if s.contains('.') {
            s.trim_end_matches('0').trim_end_matches('.').to_string()
        } else {
            s
        }
    }
}

/// Side in pixels of one cell of [`save_projection_matrix`].
pub const MATRIX_CELL: u32 = 300;

/// Saves a `dims` × `dims` matrix of the first `dims` coordinates of `points` (`.png` or
/// `.svg` by extension, written atomically): cell (i, j) off the diagonal is the scatter
/// plot of x_j (across) against x_i (up) over the box [lo, hi]; a diagonal cell is the
/// histogram of x_i over [lo_i, hi_i], with the count a uniform spread would put in each
/// bin drawn as a line. Each cell is [`MATRIX_CELL`] pixels square, under a title strip.
pub fn save_projection_matrix(
    path: &Path,
    title: &str,
    points: &PointSet,
    dims: usize,
    lo: &[f64],
    hi: &[f64],
) -> Result<(), PlotError> {
    let picture = picture_format(path)?;
    let refuse = |message: String| PlotError::Panel {
        index: 1,
        title: title.to_string(),
        message,
    };
    if dims == 0 || dims > points.s() {
        return Err(refuse(format!(
            "{dims} coordinates asked for, the points have {} (expected 1 ≤ dims ≤ s)",
            points.s()
        )));
    }
    if lo.len() < dims || hi.len() < dims {
        return Err(refuse(format!(
            "the box has {} dimensions, {dims} are drawn",
            lo.len().min(hi.len())
        )));
    }
    for k in 0..dims {
        if !(lo[k].is_finite() && hi[k].is_finite() && lo[k] < hi[k]) {
            return Err(refuse(format!(
                "the box for x{} is [{}, {}]; it needs finite lo < hi",
                k + 1,
                lo[k],
                hi[k]
            )));
        }
    }
    let side = dims as u64 * MATRIX_CELL as u64;
    let size = (side, side + TITLE_HEIGHT as u64);
    save_scene(
        path,
        picture,
        size,
        |root| draw_matrix(root, title, points, dims, lo, hi),
        |root| draw_matrix(root, title, points, dims, lo, hi),
    )
}

/// Checks the picture size, draws it with the backend of its format (one closure per
/// backend type, as plotters' backends are distinct types) and writes it atomically.
fn save_scene(
    path: &Path,
    picture: Picture,
    (width, height): (u64, u64),
    draw_png: impl FnOnce(&DrawingArea<BitMapBackend, Shift>) -> Result<(), PlotError>,
    draw_svg: impl FnOnce(&DrawingArea<SVGBackend, Shift>) -> Result<(), PlotError>,
) -> Result<(), PlotError> {
    if width > MAX_SIDE as u64 || height > MAX_SIDE as u64 || width * height > MAX_PIXELS {
        return Err(PlotError::TooLarge { width, height });
    }
    register_font()?;
    let size = (width as u32, height as u32);
    let bytes = match picture {
        Picture::Png => {
            let mut rgb = vec![0u8; size.0 as usize * size.1 as usize * 3];
            {
                let root = BitMapBackend::with_buffer(&mut rgb, size).into_drawing_area();
                draw_png(&root)?;
                root.present().map_err(draw_error)?;
            }
            encode_png(&rgb, size)?
        }
        Picture::Svg => {
            let mut svg = String::new();
            {
                let root = SVGBackend::with_string(&mut svg, size).into_drawing_area();
                draw_svg(&root)?;
                root.present().map_err(draw_error)?;
            }
            svg.into_bytes()
        }
    };
    stillpoint::io::write_atomic(path, &bytes)?;
    Ok(())
}

fn picture_format(path: &Path) -> Result<Picture, PlotError> {
    let ext = path
        .extension()
        .map(|e| e.to_string_lossy().into_owned())
        .unwrap_or_default();
    match ext.to_ascii_lowercase().as_str() {
        "png" => Ok(Picture::Png),
        "svg" => Ok(Picture::Svg),
        _ => Err(PlotError::UnsupportedFormat {
            path: path.to_path_buf(),
            ext,
        }),
    }
}

fn draw_matrix<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    title: &str,
    points: &PointSet,
    dims: usize,
    lo: &[f64],
    hi: &[f64],
) -> Result<(), PlotError> {
    root.fill(&WHITE).map_err(draw_error)?;
    let (title_area, body) = root.split_vertically(TITLE_HEIGHT);
    let (tw, th) = title_area.dim_in_pixel();
    let title_style = TextStyle::from(("sans-serif", 22).into_font())
        .color(&BLACK)
        .pos(Pos::new(HPos::Center, VPos::Center));
    title_area
        .draw_text(title, &title_style, (tw as i32 / 2, th as i32 / 2))
        .map_err(draw_error)?;
    let radius = if points.n() <= 200 { 2 } else { 1 };
    for (cell_index, cell) in body.split_evenly((dims, dims)).into_iter().enumerate() {
        // Row 0 is at the top; the row's coordinate is drawn upwards.
        let (row, col) = (cell_index / dims, cell_index % dims);
        let mut builder = ChartBuilder::on(&cell);
        builder
            .margin(6)
            .x_label_area_size(30)
            .y_label_area_size(42);
        if row == col {
            let k = row;
            let bins = ((points.n() as f64).sqrt().round() as usize).clamp(1, 40);
            let width = (hi[k] - lo[k]) / bins as f64;
            let mut counts = vec![0usize; bins];
            for p in points.rows() {
                if lo[k] <= p[k] && p[k] <= hi[k] {
                    let b = (((p[k] - lo[k]) / width) as usize).min(bins - 1);
                    counts[b] += 1;
                }
            }
            let expected = points.n() as f64 / bins as f64;
            let top = counts.iter().copied().max().unwrap_or(0) as f64;
            let top = top.max(expected).max(1.0) * 1.15;
            let mut chart = builder
                .build_cartesian_2d(lo[k]..hi[k], 0.0..top)
                .map_err(draw_error)?;
            chart
                .configure_mesh()
                .x_desc(format!("x{}", k + 1))
                .y_desc("count")
                .x_labels(4)
                .y_labels(4)
                .max_light_lines(0)
                .label_style(("sans-serif", 11))
                .axis_desc_style(("sans-serif", 13))
                .draw()
                .map_err(draw_error)?;
            chart
                .draw_series(counts.iter().enumerate().map(|(b, &c)| {
                    let x0 = lo[k] + b as f64 * width;
                    Rectangle::new([(x0, 0.0), (x0 + width, c as f64)], BAR_COLOUR.filled())
                }))
                .map_err(draw_error)?;
            chart
                .draw_series(LineSeries::new(
                    [(lo[k], expected), (hi[k], expected)],
                    BOUNDARY_COLOUR.stroke_width(1),
                ))
                .map_err(draw_error)?;
        } else {
            let (kx, ky) = (col, row);
            let mut chart = builder
                .build_cartesian_2d(lo[kx]..hi[kx], lo[ky]..hi[ky])
                .map_err(draw_error)?;
            chart
                .configure_mesh()
                .x_desc(format!("x{}", kx + 1))
                .y_desc(format!("x{}", ky + 1))
                .x_labels(4)
                .y_labels(4)
                .max_light_lines(0)
                .label_style(("sans-serif", 11))
                .axis_desc_style(("sans-serif", 13))
                .draw()
                .map_err(draw_error)?;
            let inside = |p: &[f64]| {
                lo[kx] <= p[kx] && p[kx] <= hi[kx] && lo[ky] <= p[ky] && p[ky] <= hi[ky]
            };
            chart
                .draw_series(
                    points
                        .rows()
                        .filter(|p| inside(p))
                        .map(|p| Circle::new((p[kx], p[ky]), radius, POINT_COLOUR.filled())),
                )
                .map_err(draw_error)?;
        }
    }
    Ok(())
}
