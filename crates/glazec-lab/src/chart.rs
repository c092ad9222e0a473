//! The speed-against-accuracy chart of `glazec bench --chart DIR` (plotters; SVG and PNG).
//!
//! **Input:** the methods' rows of a [`Report`]: kernel time as a ratio to the Lambert kernel
//! timed in the same rounds (x) against the error on the accuracy set (y, log scale), in two
//! panels: the under-coat lobe relRMSE (median as a dot, the worst case as a ring above it) and
//! the largest directional-albedo error (which sees what the lobe measure cannot: the lobe is
//! measured with the coat's own reflection subtracted, so a change to that reflection, such as
//! leaving out its multiple-scattering lobe, shows only in the albedo).
//! **Output:** `speed-accuracy.svg` and `speed-accuracy.png`, each panel with its Pareto front
//! (the methods that no other method beats on both cost and that error) joined by a line.
//!
//! Text is set in DejaVu Sans, compiled in (the `dejavu` crate), so the chart needs no system
//! fonts and comes out the same on every machine for the same numbers.

use std::path::{Path, PathBuf};
use std::sync::OnceLock;

use plotters::coord::Shift;
use plotters::prelude::*;

use crate::bench::{MethodRow, Report};

/// The chart's size in pixels (PNG) and user units (SVG).
const SIZE: (u32, u32) = (1200, 560);
const FONT: &str = "sans-serif";

/// The indices of the Pareto-optimal rows for (cost, error), in order of increasing cost: a row
/// is on the front when no other row is at most as costly and at most as wrong while being
/// strictly better in one of the two.
pub fn pareto_front(points: &[(f64, f64)]) -> Vec<usize> {
    let dominated = |i: usize| {
        let (c, e) = points[i];
        points.iter().any(|&(c2, e2)| c2 <= c && e2 <= e && (c2 < c || e2 < e))
    };
    let mut front: Vec<usize> =
        (0..points.len()).filter(|&i| points[i].0.is_finite() && points[i].1.is_finite() && !dominated(i)).collect();
    front.sort_by(|&a, &b| points[a].0.total_cmp(&points[b].0));
    front
}

fn register_font() -> Result<(), String> {
    static REGISTERED: OnceLock<Result<(), String>> = OnceLock::new();
    REGISTERED
        .get_or_init(|| {
            plotters::style::register_font(FONT, FontStyle::Normal, dejavu::sans::regular())
                .map_err(|_| "the compiled-in DejaVu Sans font did not load".to_string())
        })
        .clone()
}

/// Writes `speed-accuracy.svg` and `speed-accuracy.png` into `dir` (created if missing);
/// returns their paths.
///
/// # Errors
/// A directory or file that cannot be written, or a drawing error.
pub fn write(report: &Report, dir: &Path) -> Result<Vec<PathBuf>, String> {
    register_font()?;
    std::fs::create_dir_all(dir).map_err(|e| format!("cannot create {}: {e}", dir.display()))?;
    let svg = dir.join("speed-accuracy.svg");
    let png = dir.join("speed-accuracy.png");
    draw(SVGBackend::new(&svg, SIZE).into_drawing_area(), report).map_err(|e| format!("{}: {e}", svg.display()))?;
    draw(BitMapBackend::new(&png, SIZE).into_drawing_area(), report).map_err(|e| format!("{}: {e}", png.display()))?;
    Ok(vec![svg, png])
}

/// Label text height in pixels, and the width of one character (an estimate for DejaVu Sans).
const LABEL_SIZE: u32 = 11;
const CHAR_WIDTH: i32 = 6;

/// A label's box in pixels: (left, top, right, bottom).
type Rect = (i32, i32, i32, i32);

/// Picks the first of a few positions beside the dot at `at` where the label overlaps no label
/// placed before, records its box and returns its offset from the dot. (Methods of nearly the
/// same cost and error would otherwise write over each other.)
fn place_label(at: (i32, i32), label: &str, placed: &mut Vec<Rect>) -> (i32, i32) {
    let width = CHAR_WIDTH * label.chars().count() as i32;
    let height = LABEL_SIZE as i32 + 2;
    let candidates = [(8, -16), (8, 4), (8, -30), (8, 18), (8, -44), (8, 32), (-width - 8, -16), (-width - 8, 4)];
    let boxed = |(dx, dy): (i32, i32)| (at.0 + dx, at.1 + dy, at.0 + dx + width, at.1 + dy + height);
    let overlaps = |a: Rect, b: Rect| a.0 < b.2 && b.0 < a.2 && a.1 < b.3 && b.1 < a.3;
    let offset =
        candidates.into_iter().find(|&c| placed.iter().all(|&p| !overlaps(boxed(c), p))).unwrap_or(candidates[0]);
    placed.push(boxed(offset));
    offset
}

/// One panel: an error measure of every method against its kernel cost.
struct Panel<'a> {
    title: &'a str,
    y_desc: &'a str,
    /// The error plotted (and used for the Pareto front) per row.
    error: fn(&MethodRow) -> f64,
    /// A worse error drawn as a ring above the dot (the largest case), if any.
    worst: Option<fn(&MethodRow) -> f64>,
}

const PANELS: [Panel<'static>; 2] = [
    Panel {
        title: "Under-coat lobe error (dot: median, ring: worst case)",
        y_desc: "lobe relRMSE (%)",
        error: |r| 100.0 * r.lobe_median,
        worst: Some(|r| 100.0 * r.lobe_max),
    },
    Panel {
        title: "Directional albedo error (worst case)",
        y_desc: "largest |E − E_ref|",
        error: |r| r.albedo_max,
        worst: None,
    },
];

fn draw<DB: DrawingBackend>(root: DrawingArea<DB, Shift>, report: &Report) -> Result<(), String>
where
    DB::ErrorType: 'static,
{
    let err = |e: DrawingAreaErrorKind<DB::ErrorType>| e.to_string();
    root.fill(&WHITE).map_err(err)?;
    let (body, footer) = root.split_vertically(SIZE.1 - 54);
    let (left, right) = body.split_horizontally(SIZE.0 / 2);
    for (area, panel) in [left, right].into_iter().zip(&PANELS) {
        draw_panel(&area, &report.methods, panel)?;
    }
    let lines = [
        "Kernel time on the device relative to a bare Lambert kernel (seed's clay stack) against the error on the"
            .to_string(),
        format!(
            "120-case accuracy set; blue: the Pareto front (no method is both cheaper and more accurate). {}",
            report.device.split(" [").next().unwrap_or(&report.device)
        ),
    ];
    for (k, line) in lines.iter().enumerate() {
        footer.draw(&Text::new(line.as_str(), (16, 8 + 18 * k as i32), (FONT, 13).into_font())).map_err(err)?;
    }
    root.present().map_err(err)?;
    Ok(())
}

fn draw_panel<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    rows: &[MethodRow],
    panel: &Panel,
) -> Result<(), String>
where
    DB::ErrorType: 'static,
{
    let err = |e: DrawingAreaErrorKind<DB::ErrorType>| e.to_string();
    let points: Vec<(f64, f64)> = rows.iter().map(|r| (r.time_ratio, (panel.error)(r))).collect();
    let front = pareto_front(&points);
    let highest = rows.iter().map(|r| panel.worst.unwrap_or(panel.error)(r)).fold(f64::MIN_POSITIVE, f64::max);
    let lowest = points.iter().map(|p| p.1).filter(|y| *y > 0.0).fold(f64::INFINITY, f64::min);
    let x_max = rows.iter().map(|r| r.time_ratio).fold(1.0, f64::max) * 1.6; // room for the labels
    let mut chart = ChartBuilder::on(area)
        .caption(panel.title, (FONT, 15))
        .margin(12)
        .x_label_area_size(42)
        .y_label_area_size(58)
        .build_cartesian_2d(0.0..x_max, (lowest / 3.0..highest * 3.0).log_scale())
        .map_err(err)?;
    chart
        .configure_mesh()
        .x_desc("kernel time vs Lambert (×)")
        .y_desc(panel.y_desc)
        .y_label_formatter(&|y| format!("{y}"))
        .label_style((FONT, 12))
        .axis_desc_style((FONT, 13))
        .light_line_style(WHITE)
        .draw()
        .map_err(err)?;
    let front_line: Vec<(f64, f64)> = front.iter().map(|&i| points[i]).collect();
    chart.draw_series(LineSeries::new(front_line, BLUE.mix(0.5).stroke_width(2))).map_err(err)?;
    if let Some(worst) = panel.worst {
        for (row, &(x, y)) in rows.iter().zip(&points) {
            let hi = worst(row);
            chart
                .draw_series(std::iter::once(PathElement::new(vec![(x, y), (x, hi)], BLACK.mix(0.35))))
                .map_err(err)?;
            chart.draw_series(std::iter::once(Circle::new((x, hi), 4, BLACK.stroke_width(1)))).map_err(err)?;
        }
    }
    let mut placed: Vec<Rect> = Vec::new();
    for (i, row) in rows.iter().enumerate() {
        let colour = if front.contains(&i) { BLUE } else { RED };
        let label = crate::accuracy::method_label(row.method);
        let at = chart.backend_coord(&points[i]);
        let offset = place_label(at, &label, &mut placed);
        chart
            .draw_series(std::iter::once(
                EmptyElement::at(points[i])
                    + Circle::new((0, 0), 5, colour.filled())
                    + Text::new(label, offset, (FONT, LABEL_SIZE).into_font()),
            ))
            .map_err(err)?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_front_keeps_only_undominated_points_in_order_of_cost() {
        // (cost, error): b is dominated by a (costlier and worse); d ties c on cost but is worse.
        let points = [(1.0, 0.5), (1.5, 0.6), (4.0, 0.01), (4.0, 0.02), (0.5, 5.0)];
        assert_eq!(pareto_front(&points), vec![4, 0, 2]);
        assert_eq!(pareto_front(&[(1.0, 1.0)]), vec![0]);
        assert!(pareto_front(&[(f64::NAN, 1.0)]).is_empty());
    }

    #[test]
    fn writes_an_svg_and_a_png_with_every_method() {
        let row = |method, time_ratio, lobe_median, lobe_max, albedo_max| MethodRow {
            method,
            evals_per_second: 1e8,
            time_ratio,
            expressions: 100,
            transcendental: 1,
            lobe_median,
            lobe_max,
            albedo_max,
        };
        let report = Report {
            device: "test device [Vulkan]".into(),
            lambert_evals_per_second: 2e8,
            methods: vec![
                row(glazec::model::Method::INTERFACED, 4.0, 0.012, 0.19, 0.05),
                row(glazec::model::Method::WeidlichWilkie, 1.4, 0.86, 8.9, 1.9),
                row(glazec::model::Method::Additive, 1.3, 4.6, 55.0, 1.0),
            ],
            hand_written: (1.0, 1.0, 0.0),
            compile_times: vec![],
            scale: vec![],
            process_ms: None,
            eval_costs: vec![],
        };
        let dir = tempfile::tempdir().expect("temporary directory");
        let written = write(&report, dir.path()).expect("chart");
        assert_eq!(written.len(), 2);
        let svg = std::fs::read_to_string(&written[0]).expect("svg");
        for label in
            ["Interfaced (default)", "WeidlichWilkie (Bowsher 2022)", "Additive (Disney clear-coat)", "test device"]
        {
            assert!(svg.contains(label), "{label} missing from the SVG");
        }
        let png = std::fs::read(&written[1]).expect("png");
        let decoder = png::Decoder::new(std::io::Cursor::new(png));
        let info = decoder.read_info().expect("a PNG").info().clone();
        assert_eq!((info.width, info.height), SIZE);
    }
}
