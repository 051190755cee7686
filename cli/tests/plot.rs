//! Pictures: marching squares traces known curves accurately, and saved PNG/SVG files are
//! real pictures of the right size with something drawn, written only for known formats.

use std::f64::consts::PI;
use std::fs;

use stillpoint::PointSet;
use stillpoint_plot::{
    boundary_polylines, canvas_size, save_panels, Panel, PlotError, PANEL_HEIGHT, PANEL_WIDTH,
};

mod common;
use common::TempDir;

fn length(line: &[[f64; 2]]) -> f64 {
    line.windows(2)
        .map(|w| (w[1][0] - w[0][0]).hypot(w[1][1] - w[0][1]))
        .sum()
}

fn is_closed(line: &[[f64; 2]]) -> bool {
    line.len() > 2 && line.first() == line.last()
}

#[test]
fn marching_squares_traces_the_unit_circle() {
    let g = |p: &[f64]| p[0] * p[0] + p[1] * p[1] - 1.0;
    let lines = boundary_polylines(&g, [-1.5, -1.5], [1.5, 1.5], 200);
    assert_eq!(lines.len(), 1, "one chained polyline");
    assert!(is_closed(&lines[0]), "the circle comes back to its start");
    for p in lines.iter().flatten() {
        let r = p[0].hypot(p[1]);
        assert!((r - 1.0).abs() < 1e-3, "vertex {p:?} at radius {r}");
    }
    let total: f64 = lines.iter().map(|l| length(l)).sum();
    assert!(
        (total - 2.0 * PI).abs() < 0.01 * 2.0 * PI,
        "length {total} vs 2π"
    );
}

#[test]
fn marching_squares_traces_a_diamond_with_corners() {
    let g = |p: &[f64]| p[0].abs() + p[1].abs() - 1.0;
    // An odd resolution puts the kinks of |x| inside cells rather than on grid lines.
    for resolution in [200, 201] {
        let lines = boundary_polylines(&g, [-1.5, -1.5], [1.5, 1.5], resolution);
        assert_eq!(lines.len(), 1);
        assert!(is_closed(&lines[0]));
        for p in lines.iter().flatten() {
            let distance = (p[0].abs() + p[1].abs() - 1.0).abs() / 2f64.sqrt();
            assert!(
                distance < 1e-3,
                "vertex {p:?} is {distance} from the diamond"
            );
        }
        let total: f64 = lines.iter().map(|l| length(l)).sum();
        let exact = 4.0 * 2f64.sqrt();
        assert!(
            (total - exact).abs() < 0.01 * exact,
            "length {total} vs 4√2"
        );
    }
}

#[test]
fn open_curves_end_on_the_box_and_separate_curves_stay_apart() {
    let line = |p: &[f64]| p[0] - 0.3;
    let lines = boundary_polylines(&line, [0.0, 0.0], [1.0, 1.0], 50);
    assert_eq!(lines.len(), 1);
    assert!(!is_closed(&lines[0]));
    assert!(lines[0].iter().all(|p| (p[0] - 0.3).abs() < 1e-12));
    assert!((length(&lines[0]) - 1.0).abs() < 1e-9);

    let two_discs = |p: &[f64]| {
        let a = (p[0] + 1.0).hypot(p[1]) - 0.5;
        let b = (p[0] - 1.0).hypot(p[1]) - 0.5;
        a.min(b)
    };
    let lines = boundary_polylines(&two_discs, [-2.0, -1.0], [2.0, 1.0], 120);
    assert_eq!(lines.len(), 2);
    assert!(lines.iter().all(|l| is_closed(l)));

    // x·y = 0.01 has two branches through saddle-free cells, x·y = 0 a true saddle.
    let hyperbola = |p: &[f64]| p[0] * p[1] - 0.01;
    let lines = boundary_polylines(&hyperbola, [-1.0, -1.0], [1.0, 1.0], 101);
    assert_eq!(lines.len(), 2);
    for p in lines.iter().flatten() {
        assert!((p[0] * p[1] - 0.01).abs() < 2e-3, "vertex {p:?}");
    }
    let cross = |p: &[f64]| p[0] * p[1];
    let lines = boundary_polylines(&cross, [-1.0, -1.0], [1.0, 1.0], 101);
    assert!(!lines.is_empty());
    for p in lines.iter().flatten() {
        assert!(p[0].abs() < 1e-9 || p[1].abs() < 1e-9, "vertex {p:?}");
    }
}

#[test]
fn marching_squares_survives_degenerate_input() {
    let positive = |_: &[f64]| 1.0;
    assert!(boundary_polylines(&positive, [0.0, 0.0], [1.0, 1.0], 20).is_empty());
    let nan = |_: &[f64]| f64::NAN;
    assert!(boundary_polylines(&nan, [0.0, 0.0], [1.0, 1.0], 20).is_empty());
    let circle = |p: &[f64]| p[0].hypot(p[1]) - 0.5;
    let _ = boundary_polylines(&circle, [-1.0, -1.0], [1.0, 1.0], 0);
    // Undefined (NaN) on the left half: the circle's right half survives as an open curve.
    let half = |p: &[f64]| if p[0] < 0.0 { f64::NAN } else { circle(p) };
    let lines = boundary_polylines(&half, [-1.0, -1.0], [1.0, 1.0], 100);
    assert_eq!(lines.len(), 1);
    assert!(!is_closed(&lines[0]));
    // A level set through grid nodes (exact zeros) must not break anything.
    let zeros = |p: &[f64]| p[0] - 0.5;
    let lines = boundary_polylines(&zeros, [0.0, 0.0], [1.0, 1.0], 10);
    assert!(lines.iter().flatten().all(|p| (p[0] - 0.5).abs() < 1e-12));
}

fn sample_sets() -> (PointSet, PointSet) {
    let grid: Vec<f64> = (0..100)
        .flat_map(|k| [(k % 10) as f64 / 9.0, (k / 10) as f64 / 9.0])
        .collect();
    let start = PointSet::new(100, 2, grid).unwrap();
    let mut state = 12345u64;
    let mut next = || {
        state = state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (state >> 11) as f64 / (1u64 << 53) as f64
    };
    let data: Vec<f64> = (0..300).map(|_| next()).collect();
    let result = PointSet::new(100, 3, data).unwrap();
    (start, result)
}

fn panels<'a>(start: &'a PointSet, result: &'a PointSet) -> Vec<Panel<'a>> {
    let circle = |p: &[f64]| (p[0] - 0.5).hypot(p[1] - 0.5) - 0.4;
    vec![
        Panel {
            title: "start (grid)".to_string(),
            points: start,
            lo: [0.0, 0.0],
            hi: [1.0, 1.0],
            boundary: Vec::new(),
            split: None,
        },
        Panel {
            title: "result after DEM".to_string(),
            points: result,
            lo: [0.0, 0.0],
            hi: [1.0, 1.0],
            boundary: boundary_polylines(&circle, [0.0, 0.0], [1.0, 1.0], 100),
            split: None,
        },
    ]
}

#[test]
fn png_has_the_expected_size_and_something_drawn() {
    let dir = TempDir::new("png");
    let (start, result) = sample_sets();
    let path = dir.path("pair.png");
    save_panels(&path, &panels(&start, &result), 2).unwrap();

    let bytes = fs::read(&path).unwrap();
    assert!(bytes.starts_with(b"\x89PNG\r\n\x1a\n"), "PNG signature");
    let mut reader = png::Decoder::new(std::io::Cursor::new(&bytes))
        .read_info()
        .unwrap();
    let mut pixels = vec![0u8; reader.output_buffer_size().unwrap()];
    let info = reader.next_frame(&mut pixels).unwrap();
    assert_eq!((info.width, info.height), canvas_size(2, 2));
    assert_eq!((info.width, info.height), (2 * PANEL_WIDTH, PANEL_HEIGHT));
    assert_eq!(info.color_type, png::ColorType::Rgb);

    let rgb = &pixels[..info.buffer_size()];
    let (mut light, mut dark, mut blue, mut red) = (0usize, 0usize, 0usize, 0usize);
    for p in rgb.chunks_exact(3) {
        let sum = p[0] as u32 + p[1] as u32 + p[2] as u32;
        light += usize::from(sum > 700);
        dark += usize::from(sum < 300);
        blue += usize::from(p[2] > 120 && p[0] < 80);
        red += usize::from(p[0] > 150 && p[1] < 80 && p[2] < 80);
    }
    let total = rgb.len() / 3;
    assert!(
        light > total / 2,
        "mostly white background: {light} of {total}"
    );
    assert!(
        dark > 1000,
        "text, axes and points drawn: {dark} dark pixels"
    );
    assert!(blue > 1000, "points drawn: {blue} blue pixels");
    assert!(red > 100, "boundary drawn: {red} red pixels");
    assert_eq!(
        dir.entries(),
        vec!["pair.png".to_string()],
        "no temporary files"
    );
}

#[test]
fn svg_holds_the_titles_and_the_points() {
    let dir = TempDir::new("svg");
    let (start, result) = sample_sets();
    let path = dir.path("pair.SVG");
    save_panels(&path, &panels(&start, &result), 1).unwrap();

    let svg = fs::read_to_string(&path).unwrap();
    assert!(svg.contains("<svg"));
    assert!(svg.contains("start (grid)") && svg.contains("result after DEM"));
    let (w, h) = canvas_size(2, 1);
    assert_eq!((w, h), (PANEL_WIDTH, 2 * PANEL_HEIGHT));
    assert!(svg.contains(&format!("width=\"{w}\"")) && svg.contains(&format!("height=\"{h}\"")));
    assert!(svg.matches("<circle").count() >= 200, "every point drawn");
    assert!(svg.contains("<polyline"), "boundary drawn");
    assert!(
        svg.contains("\nx1\n") && svg.contains("\nx2\n"),
        "axis labels"
    );

    // Replacing an existing picture works and leaves only the picture.
    save_panels(&path, &panels(&start, &result)[..1], 3).unwrap();
    let svg = fs::read_to_string(&path).unwrap();
    assert!(!svg.contains("result after DEM"));
    assert_eq!(dir.entries(), vec!["pair.SVG".to_string()]);
}

#[test]
fn unsupported_formats_are_refused_and_write_nothing() {
    let dir = TempDir::new("formats");
    let (start, result) = sample_sets();
    for name in ["pair.jpg", "pair", "pair.png.txt", "pair.pdf"] {
        let path = dir.path(name);
        let e = save_panels(&path, &panels(&start, &result), 2).unwrap_err();
        assert!(matches!(e, PlotError::UnsupportedFormat { .. }), "{e}");
        let message = e.to_string();
        assert!(
            message.contains(".png or .svg") && message.contains(name),
            "{message}"
        );
        assert!(!path.exists());
    }
    assert!(dir.entries().is_empty(), "{:?}", dir.entries());
}

#[test]
fn bad_panels_are_refused_clearly() {
    let dir = TempDir::new("bad");
    let (start, _) = sample_sets();
    let path = dir.path("bad.png");

    assert!(matches!(
        save_panels(&path, &[], 1),
        Err(PlotError::NoPanels)
    ));

    let line = PointSet::new(3, 1, vec![0.1, 0.5, 0.9]).unwrap();
    let one_d = Panel {
        title: "1-D".to_string(),
        points: &line,
        lo: [0.0, 0.0],
        hi: [1.0, 1.0],
        boundary: Vec::new(),
        split: None,
    };
    let m = save_panels(&path, &[one_d], 1).unwrap_err().to_string();
    assert!(m.contains("1-D") && m.contains("at least 2"), "{m}");

    for (lo, hi) in [
        ([0.0, 1.0], [1.0, 1.0]),
        ([f64::NAN, 0.0], [1.0, 1.0]),
        ([0.0, 0.0], [f64::INFINITY, 1.0]),
    ] {
        let panel = Panel {
            title: "box".to_string(),
            points: &start,
            lo,
            hi,
            boundary: Vec::new(),
            split: None,
        };
        let m = save_panels(&path, &[panel], 1).unwrap_err().to_string();
        assert!(m.contains("lo < hi"), "{m}");
    }

    let many: Vec<Panel> = (0..40)
        .map(|k| Panel {
            title: format!("{k}"),
            points: &start,
            lo: [0.0, 0.0],
            hi: [1.0, 1.0],
            boundary: Vec::new(),
            split: None,
        })
        .collect();
    let e = save_panels(&path, &many, 40).unwrap_err();
    assert!(matches!(e, PlotError::TooLarge { .. }), "{e}");
    let lots: Vec<Panel> = (0..150).map(|_| many[0].clone()).collect();
    let e = save_panels(&path, &lots, 12).unwrap_err();
    assert!(e.to_string().contains("too large"), "{e}");
    assert!(dir.entries().is_empty());
}

#[test]
fn columns_are_clamped_and_odd_input_is_drawn() {
    let dir = TempDir::new("columns");
    let (start, result) = sample_sets();
    assert_eq!(canvas_size(3, 0), (PANEL_WIDTH, 3 * PANEL_HEIGHT));
    assert_eq!(canvas_size(3, 2), (2 * PANEL_WIDTH, 2 * PANEL_HEIGHT));
    assert_eq!(canvas_size(2, 9), (2 * PANEL_WIDTH, PANEL_HEIGHT));

    // Points outside the box and non-finite boundary vertices are skipped, not fatal.
    let mut three = panels(&start, &result);
    three.push(Panel {
        title: "zoom <&> \"quotes\"".to_string(),
        points: &result,
        lo: [0.25, 0.25],
        hi: [0.5, 0.75],
        boundary: vec![vec![[0.3, 0.3], [f64::NAN, 0.4], [0.4, 0.4], [0.45, 0.6]]],
        split: None,
    });
    let path = dir.path("three.svg");
    save_panels(&path, &three, 0).unwrap();
    let svg = fs::read_to_string(&path).unwrap();
    assert!(svg.contains("zoom &lt;&amp;&gt;"), "title escaped");
}

fn red_pixels(path: &std::path::Path) -> usize {
    let bytes = fs::read(path).unwrap();
    let mut reader = png::Decoder::new(std::io::Cursor::new(&bytes))
        .read_info()
        .unwrap();
    let mut pixels = vec![0u8; reader.output_buffer_size().unwrap()];
    let info = reader.next_frame(&mut pixels).unwrap();
    pixels[..info.buffer_size()]
        .chunks_exact(3)
        .filter(|p| p[0] > 150 && p[1] < 80 && p[2] < 80)
        .count()
}

#[test]
fn boundary_lines_are_clipped_to_the_box() {
    let dir = TempDir::new("clip");
    let (start, _) = sample_sets();
    let far = |p: &[f64]| (p[0] - 5.0).hypot(p[1] - 5.0) - 0.5;
    let panel = |boundary| Panel {
        title: "clip".to_string(),
        points: &start,
        lo: [0.0, 0.0],
        hi: [1.0, 1.0],
        boundary,
        split: None,
    };
    // Entirely outside: plotters would pin it to the frame's corner; nothing may show.
    let outside = boundary_polylines(&far, [4.0, 4.0], [6.0, 6.0], 50);
    assert_eq!(outside.len(), 1);
    let path = dir.path("outside.png");
    save_panels(&path, &[panel(outside)], 1).unwrap();
    assert_eq!(red_pixels(&path), 0);

    // Crossing the box: only the part inside is drawn, about one plot width of 2-px line.
    let across = vec![vec![[-3.0, 0.5], [4.0, 0.5]]];
    let path = dir.path("across.png");
    save_panels(&path, &[panel(across)], 1).unwrap();
    let red = red_pixels(&path);
    assert!((600..=2000).contains(&red), "{red} red pixels");
}

#[test]
fn line_charts_render_and_refuse_unknown_formats() {
    use stillpoint_plot::{save_line_charts, LineChart, Series};
    let dir = std::env::temp_dir().join(format!("stillpoint-lines-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let chart = LineChart {
        title: "energy".into(),
        x_label: "t".into(),
        y_label: "U".into(),
        log_y: true,
        series: vec![
            Series {
                name: "a".into(),
                points: (1..50).map(|k| (k as f64, 1.0 / k as f64)).collect(),
            },
            Series {
                name: "b".into(),
                points: vec![(1.0, 0.5), (2.0, f64::NAN), (3.0, 0.0), (4.0, 0.1)],
            },
        ],
    };
    let png = dir.join("c.png");
    save_line_charts(&png, &[chart.clone(), chart.clone()]).unwrap();
    let bytes = std::fs::read(&png).unwrap();
    assert!(bytes.starts_with(b"\x89PNG"));
    let svg = dir.join("c.svg");
    save_line_charts(&svg, std::slice::from_ref(&chart)).unwrap();
    let text = std::fs::read_to_string(&svg).unwrap();
    assert!(text.contains("<svg") && text.contains("energy"));
    let bad = dir.join("c.gif");
    assert!(save_line_charts(&bad, &[chart]).is_err());
    assert!(!bad.exists());
    let _ = std::fs::remove_dir_all(&dir);
}

/// Width and height from a PNG's header.
fn png_size(path: &std::path::Path) -> (u32, u32) {
    let bytes = fs::read(path).unwrap();
    assert!(bytes.starts_with(b"\x89PNG\r\n\x1a\n"), "PNG signature");
    let be = |k: usize| u32::from_be_bytes([bytes[k], bytes[k + 1], bytes[k + 2], bytes[k + 3]]);
    (be(16), be(20))
}

fn blue_pixels(path: &std::path::Path) -> usize {
    let bytes = fs::read(path).unwrap();
    let mut reader = png::Decoder::new(std::io::Cursor::new(&bytes))
        .read_info()
        .unwrap();
    let mut pixels = vec![0u8; reader.output_buffer_size().unwrap()];
    let info = reader.next_frame(&mut pixels).unwrap();
    pixels[..info.buffer_size()]
        .chunks_exact(3)
        .filter(|p| p[2] > 120 && p[0] < 80)
        .count()
}

#[test]
fn projection_matrix_has_one_cell_per_pair_and_refuses_bad_input() {
    use stillpoint_plot::{save_projection_matrix, MATRIX_CELL};
    let dir = TempDir::new("matrix");
    let (_, result) = sample_sets();
    let path = dir.path("m.png");
    save_projection_matrix(&path, "three", &result, 3, &[0.0; 3], &[1.0; 3]).unwrap();
    let (w, h) = png_size(&path);
    assert_eq!(w, 3 * MATRIX_CELL);
    assert!(h > w, "a title strip above the cells");
    assert!(blue_pixels(&path) > 1000, "points and histograms drawn");
    let svg = dir.path("m.svg");
    save_projection_matrix(&svg, "three", &result, 2, &[0.0; 3], &[1.0; 3]).unwrap();
    let text = fs::read_to_string(&svg).unwrap();
    assert!(text.contains("x1") && text.contains("x2") && text.contains("count"));
    // One coordinate: a lone histogram.
    save_projection_matrix(&dir.path("one.png"), "one", &result, 1, &[0.0], &[1.0]).unwrap();
    let bad = [
        (0, vec![0.0; 3], vec![1.0; 3], "1 ≤ dims ≤ s"),
        (4, vec![0.0; 4], vec![1.0; 4], "1 ≤ dims ≤ s"),
        (3, vec![0.0; 2], vec![1.0; 2], "box has 2 dimensions"),
        (2, vec![0.0, 1.0], vec![1.0, 1.0], "finite lo < hi"),
    ];
    for (dims, lo, hi, needle) in bad {
        let p = dir.path("bad.png");
        let e = save_projection_matrix(&p, "bad", &result, dims, &lo, &hi).unwrap_err();
        assert!(e.to_string().contains(needle), "{e}");
        assert!(!p.exists());
    }
    let e = save_projection_matrix(&dir.path("m.jpg"), "t", &result, 2, &[0.0; 3], &[1.0; 3])
        .unwrap_err();
    assert!(matches!(e, PlotError::UnsupportedFormat { .. }), "{e}");
    assert!(!dir.entries().iter().any(|n| n.contains("tmp")));
}

#[test]
fn line_chart_grid_lays_charts_in_rows() {
    use stillpoint_plot::{save_line_chart_grid, LineChart, Series};
    let dir = TempDir::new("grid");
    let chart = |t: &str| LineChart {
        title: t.into(),
        x_label: "step".into(),
        y_label: "energy".into(),
        log_y: false,
        series: vec![Series {
            name: "U".into(),
            points: (0..50)
                .map(|k| (k as f64, 1.0 / (1.0 + k as f64)))
                .collect(),
        }],
    };
    let path = dir.path("g.png");
    save_line_chart_grid(&path, &[chart("a"), chart("b"), chart("c")], 2).unwrap();
    assert_eq!(png_size(&path), (1400, 1040));
}

fn cli(args: &[&str]) -> std::process::Output {
    std::process::Command::new(env!("CARGO_BIN_EXE_stillpoint"))
        .args(args)
        .output()
        .unwrap()
}

#[test]
fn plot_command_draws_scatter_matrix_region_and_trajectory() {
    let dir = TempDir::new("cli");
    let pts = dir.path("p.csv");
    let traj = dir.path("t.json");
    let o = cli(&[
        "generate",
        "-n",
        "60",
        "-s",
        "5",
        "--steps",
        "30",
        "-q",
        "-o",
        pts.to_str().unwrap(),
        "--trajectory",
        traj.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let f = pts.to_str().unwrap();
    // s = 5: the first min(s, 4) = 4 coordinates by default, or --dims.
    let m4 = dir.path("m4.png");
    assert!(cli(&["plot", f, "-o", m4.to_str().unwrap()])
        .status
        .success());
    assert_eq!(png_size(&m4).0, 4 * stillpoint_plot::MATRIX_CELL);
    let m2 = dir.path("m2.svg");
    assert!(cli(&["plot", f, "--dims", "2", "-o", m2.to_str().unwrap()])
        .status
        .success());
    assert!(fs::read_to_string(&m2).unwrap().starts_with("<svg"));
    // Energy and the logged discrepancies against step and time: a 2 × 2 grid.
    let t = dir.path("t.png");
    let o = cli(&[
        "plot",
        "--trajectory",
        traj.to_str().unwrap(),
        "-o",
        t.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert_eq!(png_size(&t), (1400, 1040));
    // A region's points with its boundary.
    let r = dir.path("r.json");
    let o = cli(&[
        "generate",
        "--region",
        "x^2 + y^2 - 1",
        "--box",
        "-1,1,-1,1",
        "-n",
        "30",
        "--steps",
        "40",
        "-q",
        "-o",
        r.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let with = dir.path("with.png");
    let without = dir.path("without.png");
    let o = cli(&[
        "plot",
        r.to_str().unwrap(),
        "--region",
        "x^2 + y^2 - 1",
        "--box",
        "-1,1,-1,1",
        "-o",
        with.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let o = cli(&[
        "plot",
        r.to_str().unwrap(),
        "--box",
        "-1,1,-1,1",
        "-o",
        without.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert_eq!(png_size(&with), (PANEL_WIDTH, PANEL_HEIGHT));
    assert!(
        red_pixels(&with) > 200 + red_pixels(&without),
        "boundary drawn"
    );
    // Points outside the unit cube without a box: their own bounding box.
    let o = cli(&["plot", r.to_str().unwrap(), "-o", without.to_str().unwrap()]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
}

/// `--split` colours the old and new points of the scatter plot of s = 2 only: where the
/// file is drawn as a matrix of projections (s = 1 or 3, or --dims 1) it is refused,
/// naming --split and what it takes, and nothing is drawn; at s = 2 it draws.
#[test]
fn plot_split_is_refused_where_no_scatter_plot_draws_it() {
    let dir = TempDir::new("split");
    let rows = |s: usize| -> String {
        (0..4)
            .map(|i| {
                (0..s)
                    .map(|k| format!("{}", (i * s + k) as f64 / 16.0))
                    .collect::<Vec<_>>()
                    .join(",")
                    + "\n"
            })
            .collect()
    };
    for (s, extra, drawn) in [
        (
            3,
            &[][..],
            "the file has s = 3, drawn as a matrix of projections",
        ),
        (
            1,
            &[][..],
            "the file has s = 1, drawn as a matrix of projections",
        ),
        (2, &["--dims", "1"][..], "--dims 1 draws histograms"),
    ] {
        let file = dir.path(&format!("s{s}.csv"));
        fs::write(&file, rows(s)).unwrap();
        let out = dir.path(&format!("s{s}.png"));
        let mut args = vec![
            "plot",
            file.to_str().unwrap(),
            "--split",
            "2",
            "-o",
            out.to_str().unwrap(),
        ];
        args.extend_from_slice(extra);
        let o = cli(&args);
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(1), "{args:?}: {err}");
        assert!(
            err.starts_with(
                "error: invalid --split = 2: expected points of s = 2 drawn as one scatter plot"
            ),
            "{args:?}: {err}"
        );
        assert!(err.contains(drawn), "{args:?}: {err}");
        assert!(!out.exists(), "{args:?} drew {}", out.display());
    }
    let file = dir.path("s2.csv");
    let out = dir.path("split.png");
    let o = cli(&[
        "plot",
        file.to_str().unwrap(),
        "--split",
        "2",
        "-o",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert_eq!(png_size(&out), (PANEL_WIDTH, PANEL_HEIGHT));
}
