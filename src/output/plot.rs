//! Draws [`Figure`]s to PNG and SVG with plotters, using an embedded font so that text
//! renders on a machine with no system fonts.

use std::ops::Range;
use std::sync::Once;

use plotters::coord::ranged1d::{Ranged, ValueFormatter};
use plotters::prelude::*;

use super::axis::{axis_range, tick_format, y_extent, LogOnce};
use crate::error::{Error, Result};
use crate::figure::{Corner, Dash, Figure, Marker, Panel, Series};

/// Width of a figure, pixels.
pub const WIDTH: u32 = 1100;
/// Height of a figure's one panel, pixels; a figure of several panels gives each less
/// ([`panel_height`]).
pub const PANEL_HEIGHT: u32 = 560;

/// Height of each panel of a figure of `panels` panels, pixels: 560 alone, 480 in two, 400
/// in three or more (a figure of four panels is 1600 px tall, not 2240: a page
/// shows two of its panels at once and the file is a quarter lighter).
pub fn panel_height(panels: usize) -> u32 {
    match panels {
        0 | 1 => PANEL_HEIGHT,
        2 => 480,
        _ => 400,
    }
}

/// The palette (Tableau 10, colour-blind friendly order).
const PALETTE: [RGBColor; 8] = [
    RGBColor(31, 119, 180),
    RGBColor(214, 39, 40),
    RGBColor(44, 160, 44),
    RGBColor(148, 103, 189),
    RGBColor(255, 127, 14),
    RGBColor(23, 190, 207),
    RGBColor(140, 86, 75),
    RGBColor(127, 127, 127),
];

static FONT: Once = Once::new();

/// Registers the embedded DejaVu Sans under the "sans-serif" family (once per process).
pub(crate) fn register_font() -> Result<()> {
    let mut result = Ok(());
    FONT.call_once(|| {
        let fonts: [(FontStyle, &'static [u8]); 2] =
            [(FontStyle::Normal, dejavu::sans::regular()), (FontStyle::Bold, dejavu::sans::bold())];
        for (style, bytes) in fonts {
            if plotters::style::register_font("sans-serif", style, bytes).is_err() {
                result = Err(Error::Render {
                    what: "font".into(),
                    message: "the embedded DejaVu Sans font could not be loaded".into(),
                });
            }
        }
    });
    result
}

fn color(i: usize) -> RGBColor {
    PALETTE[i % PALETTE.len()]
}

/// A palette colour as `#rrggbb` (for drawings made outside plotters, e.g. over a scan).
pub fn colour_hex(i: usize) -> String {
    let c = color(i);
    format!("#{:02x}{:02x}{:02x}", c.0, c.1, c.2)
}

fn render_err(what: &str, e: impl std::fmt::Display) -> Error {
    Error::Render { what: what.to_string(), message: e.to_string() }
}

/// Height of the whole figure, pixels.
pub fn height(fig: &Figure) -> u32 {
    let n = fig.panels.len().max(1);
    panel_height(n) * n as u32
}

/// The figure as PNG bytes: drawn into an RGB buffer, then encoded with an indexed palette when
/// it has at most 256 colours (plots drawn with the palette above and antialiased text usually
/// do: the pixels are the same, the file about a third), else as RGB. `smallest`: the
/// encoder's best compression (11 % smaller over the report's figures, about 0.1 s more a
/// figure: `shotdamp report`, whose folder has a size cap), else its default.
pub fn to_png(fig: &Figure, smallest: bool) -> Result<Vec<u8>> {
    register_font()?;
    let (w, h) = (WIDTH, height(fig));
    let mut rgb = vec![0u8; 3 * w as usize * h as usize];
    {
        let root = BitMapBackend::with_buffer(&mut rgb, (w, h)).into_drawing_area();
        draw(fig, root, Dashes::Drawn)?;
    }
    let level = if smallest { png::Compression::Best } else { png::Compression::Default };
    encode_png(&rgb, w, h, level).map_err(|e| render_err(&format!("figure {} (PNG)", fig.id), e))
}

/// PNG bytes of an RGB image (`3 w h` bytes, rows top to bottom).
pub fn encode_png(
    rgb: &[u8],
    w: u32,
    h: u32,
    level: png::Compression,
) -> std::result::Result<Vec<u8>, png::EncodingError> {
    let mut out = Vec::new();
    let mut enc = png::Encoder::new(&mut out, w, h);
    enc.set_compression(level);
    enc.set_depth(png::BitDepth::Eight);
    match palette_of(rgb) {
        Some((palette, indices)) => {
            enc.set_color(png::ColorType::Indexed);
            enc.set_palette(palette);
            enc.set_filter(png::FilterType::NoFilter);
            enc.write_header()?.write_image_data(&indices)?;
        }
        None => {
            enc.set_color(png::ColorType::Rgb);
            // Each row with the filter that suits it: 5 % smaller than Paeth on every row
            // over the report's figures, for 0.1 s.
            enc.set_filter(png::FilterType::Paeth);
            enc.set_adaptive_filter(png::AdaptiveFilterType::Adaptive);
            enc.write_header()?.write_image_data(rgb)?;
        }
    }
    Ok(out)
}

/// The image's colours (in order of first appearance, so the bytes are deterministic) and each
/// pixel's index, or `None` with more than 256 colours.
fn palette_of(rgb: &[u8]) -> Option<(Vec<u8>, Vec<u8>)> {
    let mut index: std::collections::HashMap<[u8; 3], u8> = std::collections::HashMap::new();
    let mut palette = Vec::new();
    let mut indices = Vec::with_capacity(rgb.len() / 3);
    // Most pixels repeat their left neighbour (background, axes): one lookup per run.
    let mut last: Option<([u8; 3], u8)> = None;
    for px in rgb.chunks_exact(3) {
        let key = [px[0], px[1], px[2]];
        if let Some((k, i)) = last {
            if k == key {
                indices.push(i);
                continue;
            }
        }
        let i = match index.get(&key) {
            Some(&i) => i,
            None => {
                let i = u8::try_from(index.len()).ok()?;
                index.insert(key, i);
                palette.extend_from_slice(&key);
                i
            }
        };
        last = Some((key, i));
        indices.push(i);
    }
    Some((palette, indices))
}

/// The figure as SVG text: a dashed line is one polyline with a `stroke-dasharray` (the same
/// dashes plotters draws one element each: about a 15th of a report's bytes were dashes).
pub fn to_svg(fig: &Figure) -> Result<String> {
    let mut svg = to_svg_drawn(fig, Dashes::Attribute)?;
    for (dash, alpha) in DASH_MARKS {
        let (on, off) = dash_lengths(dash);
        svg = svg.replace(&format!(" opacity=\"{alpha}\""), &format!(" stroke-dasharray=\"{on} {off}\""));
    }
    Ok(super::svg::compact(&svg))
}

/// The SVG as plotters writes it, every dash an element of its own.
#[cfg(test)]
pub(crate) fn to_svg_raw(fig: &Figure) -> Result<String> {
    to_svg_drawn(fig, Dashes::Drawn)
}

fn to_svg_drawn(fig: &Figure, dashes: Dashes) -> Result<String> {
    register_font()?;
    let mut buf = String::new();
    {
        let root = SVGBackend::with_string(&mut buf, (WIDTH, height(fig))).into_drawing_area();
        draw(fig, root, dashes)?;
    }
    Ok(buf)
}

/// How dashed lines are drawn: dash by dash (any backend), or as whole lines marked for a
/// `stroke-dasharray` ([`to_svg`]).
#[derive(Clone, Copy, PartialEq, Eq)]
enum Dashes {
    Drawn,
    Attribute,
}

/// The opacity a whole dashed line is drawn with in SVG until [`to_svg`] replaces it by its
/// dash pattern: values no other element has.
const DASH_MARKS: [(Dash, f64); 3] = [(Dash::Dashed, 0.99951), (Dash::Dotted, 0.99952), (Dash::DashDot, 0.99953)];

/// A dash pattern's lengths on and off, pixels.
fn dash_lengths(dash: Dash) -> (u32, u32) {
    match dash {
        Dash::Solid => (0, 0),
        Dash::Dashed => (10, 6),
        Dash::Dotted => (2, 5),
        Dash::DashDot => (14, 4),
    }
}

fn draw<DB: DrawingBackend>(fig: &Figure, root: DrawingArea<DB, plotters::coord::Shift>, dashes: Dashes) -> Result<()> {
    let what = format!("figure {}", fig.id);
    root.fill(&WHITE).map_err(|e| render_err(&what, e))?;
    let areas = root.split_evenly((fig.panels.len().max(1), 1));
    for (panel, area) in fig.panels.iter().zip(areas.iter()) {
        draw_panel(panel, area, &what, dashes)?;
    }
    root.present().map_err(|e| render_err(&what, e))
}

fn draw_panel<DB: DrawingBackend>(
    panel: &Panel,
    area: &DrawingArea<DB, plotters::coord::Shift>,
    what: &str,
    dashes: Dashes,
) -> Result<()> {
    let (y0, y1) = y_extent(panel);
    let (y0, y1) = axis_range(y0, y1, panel.y_log);
    let (x0, x1) = axis_range(panel.x_range.0, panel.x_range.1, panel.x_log);
    let mut builder = ChartBuilder::on(area);
    builder
        .caption(&panel.title, ("sans-serif", 22).into_font())
        .margin(14)
        .x_label_area_size(48)
        .y_label_area_size(96);
    let fx = tick_format(x0, x1, panel.x_log);
    let fy = tick_format(y0, y1, panel.y_log);
    let err = |e| render_err(what, e);
    match (panel.x_log, panel.y_log) {
        (false, false) => fill(builder.build_cartesian_2d(x0..x1, y0..y1).map_err(err)?, panel, (what, dashes), fx, fy),
        (false, true) => {
            fill(builder.build_cartesian_2d(x0..x1, LogOnce::new(y0, y1)).map_err(err)?, panel, (what, dashes), fx, fy)
        }
        (true, false) => {
            fill(builder.build_cartesian_2d(LogOnce::new(x0, x1), y0..y1).map_err(err)?, panel, (what, dashes), fx, fy)
        }
        (true, true) => fill(
            builder.build_cartesian_2d(LogOnce::new(x0, x1), LogOnce::new(y0, y1)).map_err(err)?,
            panel,
            (what, dashes),
            fx,
            fy,
        ),
    }
}

fn fill<'a, DB, X, Y>(
    mut chart: ChartContext<'a, DB, Cartesian2d<X, Y>>,
    panel: &Panel,
    (what, dashes): (&str, Dashes),
    x_fmt: impl Fn(&f64) -> String,
    y_fmt: impl Fn(&f64) -> String,
) -> Result<()>
where
    DB: DrawingBackend + 'a,
    X: Ranged<ValueType = f64> + ValueFormatter<f64>,
    Y: Ranged<ValueType = f64> + ValueFormatter<f64>,
{
    chart
        .configure_mesh()
        .x_desc(&panel.x_label)
        .y_desc(&panel.y_label)
        .x_label_formatter(&x_fmt)
        .y_label_formatter(&y_fmt)
        .label_style(("sans-serif", 15))
        .axis_desc_style(("sans-serif", 17))
        .light_line_style(RGBColor(235, 235, 235))
        .bold_line_style(RGBColor(200, 200, 200))
        // At most four light lines between two labelled ones (a logarithmic axis: one at
        // each integer multiple of its decades); the default ten drew a grey band.
        .max_light_lines(4)
        .draw()
        .map_err(|e| render_err(what, e))?;

    let y_range: Range<f64> = chart.y_range();
    // Labels of neighbouring lines are staggered downwards so that they do not overlap.
    let at = |frac: f64| {
        if panel.y_log {
            (y_range.start.ln() + (y_range.end.ln() - y_range.start.ln()) * frac).exp()
        } else {
            y_range.start + (y_range.end - y_range.start) * frac
        }
    };
    let mut order: Vec<usize> = (0..panel.vlines.len()).collect();
    order.sort_by(|&a, &b| panel.vlines[a].x.total_cmp(&panel.vlines[b].x));
    let pos = |x: f64| if panel.x_log { x.max(f64::MIN_POSITIVE).ln() } else { x };
    let span = pos(panel.x_range.1) - pos(panel.x_range.0);
    let mut level = vec![0usize; panel.vlines.len()];
    for w in 1..order.len() {
        let (prev, cur) = (order[w - 1], order[w]);
        // Closer than ~20 % of the width to the previous label: one step lower.
        if pos(panel.vlines[cur].x) - pos(panel.vlines[prev].x) < 0.2 * span {
            level[cur] = (level[prev] + 1) % 4;
        }
    }
    for (k, v) in panel.vlines.iter().enumerate() {
        let style = ShapeStyle { color: RGBColor(110, 110, 110).to_rgba(), filled: false, stroke_width: 1 };
        let pts = vec![(v.x, y_range.start), (v.x, y_range.end)];
        chart.draw_series(DashedLineSeries::new(pts, 6, 6, style)).map_err(|e| render_err(what, e))?;
        chart
            .draw_series(std::iter::once(Text::new(
                v.label.clone(),
                (v.x, at(1.0 - 0.05 * level[k] as f64)),
                ("sans-serif", 14).into_font().color(&RGBColor(80, 80, 80)),
            )))
            .map_err(|e| render_err(what, e))?;
    }

    for s in &panel.series {
        draw_series(&mut chart, s, panel, what, dashes)?;
    }
    if panel.series.iter().any(|s| !s.label.is_empty()) {
        // The vertical lines' labels: where each starts and how many characters it has.
        let marks: Vec<(f64, f64, usize)> = panel
            .vlines
            .iter()
            .enumerate()
            .map(|(k, v)| (v.x, at(1.0 - 0.05 * level[k] as f64), v.label.chars().count()))
            .collect();
        let corner = clear_corner(&chart, panel, &marks);
        chart
            .configure_series_labels()
            .position(match corner {
                Corner::UpperRight => SeriesLabelPosition::UpperRight,
                Corner::UpperLeft => SeriesLabelPosition::UpperLeft,
                Corner::LowerRight => SeriesLabelPosition::LowerRight,
                Corner::LowerLeft => SeriesLabelPosition::LowerLeft,
            })
            .background_style(WHITE.mix(0.85))
            .border_style(RGBColor(160, 160, 160))
            .label_font(("sans-serif", 14))
            .draw()
            .map_err(|e| render_err(what, e))?;
    }
    Ok(())
}

/// The legend's corner: the panel's own unless its box would hide more of the drawn data
/// than another corner's would, then the corner hiding least (ties keep the panel's own, then
/// upper right, upper left, lower right, lower left). The box is estimated from the labels'
/// lengths and count at the legend's font; the data are the series' points and the midpoints
/// of their lines, in pixels, and the vertical lines' labels (`marks`: where each starts, its
/// characters), each of whose sampled pixels counts as [`LABEL_WEIGHT`] points: a legend over
/// a label hides words.
fn clear_corner<'a, DB, X, Y>(
    chart: &ChartContext<'a, DB, Cartesian2d<X, Y>>,
    panel: &Panel,
    marks: &[(f64, f64, usize)],
) -> Corner
where
    DB: DrawingBackend + 'a,
    X: Ranged<ValueType = f64> + ValueFormatter<f64>,
    Y: Ranged<ValueType = f64> + ValueFormatter<f64>,
{
    let labels: Vec<&Series> = panel.series.iter().filter(|s| !s.label.is_empty()).collect();
    let chars = labels.iter().map(|s| s.label.chars().count()).max().unwrap_or(0) as i32;
    // At 14 px: about 7.5 px a character, 20 px a row, the swatch and margins around them.
    let (w, h) = (60 + chars * 15 / 2, 12 + 20 * labels.len() as i32);
    let (xr, yr) = chart.plotting_area().get_pixel_range();
    let boxes = |c: Corner| {
        let (left, top) = match c {
            Corner::UpperRight => (xr.end - w, yr.start),
            Corner::UpperLeft => (xr.start, yr.start),
            Corner::LowerRight => (xr.end - w, yr.end - h),
            Corner::LowerLeft => (xr.start, yr.end - h),
        };
        (left..left + w, top..top + h)
    };
    let ok = |x: f64, y: f64| x.is_finite() && y.is_finite() && (!panel.x_log || x > 0.0) && (!panel.y_log || y > 0.0);
    let mut pixels: Vec<(i32, i32)> = Vec::new();
    for s in &panel.series {
        let mut last: Option<(i32, i32)> = None;
        for ((&x, &y), gap) in s.x.iter().zip(&s.y).zip(s.gaps(panel.x_log)) {
            if gap {
                last = None;
            }
            if !ok(x, y) {
                last = None;
                continue;
            }
            let p = chart.backend_coord(&(x, y));
            if let (true, Some(q)) = (s.line, last) {
                pixels.push(((p.0 + q.0) / 2, (p.1 + q.1) / 2));
            }
            pixels.push(p);
            last = Some(p);
        }
    }
    // A label's text at 14 px: from its anchor, about 7.5 px a character, 14 px high; sampled
    // every 4 px along its middle.
    let mut words: Vec<(i32, i32)> = Vec::new();
    for &(x, y, chars) in marks.iter().filter(|m| ok(m.0, m.1)) {
        let (px, py) = chart.backend_coord(&(x, y));
        let len = chars as i32 * 15 / 2;
        words.extend((0..=len / 4).map(|k| (px + 4 * k, py + 7)));
    }
    let hidden = |c: Corner| {
        let (bx, by) = boxes(c);
        let inside = |p: &&(i32, i32)| bx.contains(&p.0) && by.contains(&p.1);
        pixels.iter().filter(inside).count() + LABEL_WEIGHT * words.iter().filter(inside).count()
    };
    let order = [panel.legend, Corner::UpperRight, Corner::UpperLeft, Corner::LowerRight, Corner::LowerLeft];
    let mut best = (panel.legend, hidden(panel.legend));
    for c in order.into_iter().skip(1) {
        let n = hidden(c);
        if n < best.1 {
            best = (c, n);
        }
    }
    best.0
}

/// What one sampled pixel of a vertical line's label counts as in [`clear_corner`], in data
/// points.
const LABEL_WEIGHT: usize = 10;

fn draw_series<'a, DB, X, Y>(
    chart: &mut ChartContext<'a, DB, Cartesian2d<X, Y>>,
    s: &Series,
    panel: &Panel,
    what: &str,
    dashes: Dashes,
) -> Result<()>
where
    DB: DrawingBackend + 'a,
    X: Ranged<ValueType = f64> + ValueFormatter<f64>,
    Y: Ranged<ValueType = f64> + ValueFormatter<f64>,
{
    let c = color(s.color);
    // Thicker strokes draw each segment as a polygon and look ragged on dense curves.
    let style = ShapeStyle { color: c.to_rgba(), filled: false, stroke_width: 1 };
    // Split at non-finite (or non-positive on log axes) values so that gaps stay gaps.
    let ok = |y: f64| y.is_finite() && (!panel.y_log || y > 0.0);
    let ok_x = |x: f64| x.is_finite() && (!panel.x_log || x > 0.0);
    // ... and where the abscissae skip a stretch that was not sampled (`Series::gaps`).
    let gaps = s.gaps(panel.x_log);
    let mut runs: Vec<Vec<(f64, f64)>> = vec![Vec::new()];
    for ((&x, &y), &gap) in s.x.iter().zip(&s.y).zip(&gaps) {
        let inside = x >= panel.x_range.0 - 1e-9 && x <= panel.x_range.1 + 1e-9;
        if gap && s.line && runs.last().is_some_and(|r| !r.is_empty()) {
            runs.push(Vec::new());
        }
        if ok(y) && ok_x(x) && inside {
            if let Some(run) = runs.last_mut() {
                run.push((x, y));
            }
        } else if runs.last().is_some_and(|r| !r.is_empty()) {
            runs.push(Vec::new());
        }
    }
    let mut labelled = false;
    for run in runs.into_iter().filter(|r| !r.is_empty()) {
        let want_label = !labelled && !s.label.is_empty();
        if s.line {
            let mark = DASH_MARKS.iter().find(|(d, _)| *d == s.dash).map(|(_, a)| *a);
            let anno = match (s.dash, mark) {
                (Dash::Solid, _) => chart.draw_series(LineSeries::new(run.clone(), style)),
                (_, Some(alpha)) if dashes == Dashes::Attribute => {
                    let marked = ShapeStyle { color: c.mix(alpha), ..style };
                    chart.draw_series(LineSeries::new(run.clone(), marked))
                }
                (dash, _) => {
                    let (on, off) = dash_lengths(dash);
                    chart.draw_series(DashedLineSeries::new(run.clone(), on, off, style))
                }
            }
            .map_err(|e| render_err(what, e))?;
            if want_label {
                labelled = true;
                let segs = dash_segments(s.dash);
                let legend_style = ShapeStyle { stroke_width: 2, ..style };
                anno.label(s.label.clone()).legend(move |(x, y)| {
                    let seg = |(a, b): (i32, i32)| PathElement::new(vec![(a, 0), (b, 0)], legend_style);
                    EmptyElement::at((x, y)) + seg(segs[0]) + seg(segs[1]) + seg(segs[2])
                });
            }
        }
        let want_label = !labelled && !s.label.is_empty();
        if s.marker != Marker::None {
            let mstyle = if s.filled { style.filled() } else { style };
            // Polygons always fill: hollow ones fill with nothing and draw their outline.
            let fill_style: ShapeStyle = if s.filled { style.filled() } else { TRANSPARENT.into() };
            let marker = s.marker;
            let pts = run.iter().copied();
            let anno = match marker {
                Marker::Circle => chart.draw_series(pts.map(|p| Circle::new(p, s.marker_size, mstyle))),
                Marker::Cross => chart.draw_series(pts.map(|p| Cross::new(p, s.marker_size, mstyle))),
                Marker::Square => {
                    let h = s.marker_size as i32;
                    chart.draw_series(pts.map(|p| EmptyElement::at(p) + Rectangle::new([(-h, -h), (h, h)], mstyle)))
                }
                Marker::Triangle | Marker::Diamond | Marker::None => chart.draw_series(pts.map(|p| {
                    let shape = if marker == Marker::Diamond { DIAMOND.to_vec() } else { TRIANGLE.to_vec() };
                    EmptyElement::at(p) + Polygon::new(shape.clone(), fill_style) + PathElement::new(shape, style)
                })),
            }
            .map_err(|e| render_err(what, e))?;
            if want_label {
                labelled = true;
                // One element type for every marker: the unused shapes have size zero.
                let size = move |m: Marker| if m == marker { 1 } else { 0 };
                anno.label(s.label.clone()).legend(move |(x, y)| {
                    let sq = 4 * size(Marker::Square);
                    EmptyElement::at((x + 12, y))
                        + Circle::new((0, 0), 4 * size(Marker::Circle), mstyle)
                        + Cross::new((0, 0), 4 * size(Marker::Cross), mstyle)
                        + Polygon::new(
                            TRIANGLE.map(|(a, b)| (a * size(Marker::Triangle), b * size(Marker::Triangle))).to_vec(),
                            fill_style,
                        )
                        + PathElement::new(
                            TRIANGLE.map(|(a, b)| (a * size(Marker::Triangle), b * size(Marker::Triangle))).to_vec(),
                            style,
                        )
                        + Rectangle::new([(-sq, -sq), (sq, sq)], if sq > 0 { mstyle } else { TRANSPARENT.into() })
                        + PathElement::new(
                            DIAMOND.map(|(a, b)| (a * size(Marker::Diamond), b * size(Marker::Diamond))).to_vec(),
                            style,
                        )
                });
            }
        }
    }
    Ok(())
}

/// A triangle marker around a point, pixels (closed path).
const TRIANGLE: [(i32, i32); 4] = [(0, -5), (5, 4), (-5, 4), (0, -5)];

/// A diamond marker around a point, pixels (closed path).
const DIAMOND: [(i32, i32); 5] = [(0, -6), (6, 0), (0, 6), (-6, 0), (0, -6)];

/// Segments of a legend swatch whose spacing shows the dash pattern.
fn dash_segments(dash: Dash) -> [(i32, i32); 3] {
    match dash {
        Dash::Solid => [(0, 8), (8, 16), (16, 24)],
        Dash::Dashed => [(0, 6), (9, 15), (18, 24)],
        Dash::Dotted => [(0, 2), (11, 13), (22, 24)],
        Dash::DashDot => [(0, 9), (13, 15), (19, 24)],
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::figure::{Figure, Panel, Series};
    use crate::output::axis::{AXIS_DECADES, AXIS_MAX};

    /// Data no run should produce, but a guard must survive: every plot's axes pass through
    /// `axis_range`, so every kind of panel (linear or logarithmic on either axis, ranges from
    /// the data or given) draws it in bounded time and memory.
    #[test]
    fn extreme_data_draws_on_every_kind_of_axis() {
        let sets: Vec<(&str, Vec<f64>, Vec<f64>)> = vec![
            ("tiny", vec![1e-320, 2e-320, 5e-300], vec![1e-320, 1e-310, 4e-300]),
            ("huge", vec![1.0, 1e200, 1e308], vec![1e160, 1e300, f64::MAX]),
            ("both", vec![1e-300, 1.0, 1e300], vec![1e-300, 1.0, 1e300]),
            ("flat", vec![3.0, 3.0, 3.0], vec![7.5, 7.5, 7.5]),
            ("non-finite", vec![f64::NAN, 1.0, f64::INFINITY], vec![f64::NEG_INFINITY, f64::NAN, 2.0]),
            ("negative", vec![-5.0, -1.0, 0.0], vec![-1e300, -2.0, 0.0]),
            ("empty", vec![], vec![]),
        ];
        for (name, x, y) in &sets {
            let finite = |v: &[f64]| {
                let f: Vec<f64> = v.iter().copied().filter(|a| a.is_finite()).collect();
                (f.iter().copied().fold(f64::INFINITY, f64::min), f.iter().copied().fold(f64::NEG_INFINITY, f64::max))
            };
            for (x_log, y_log) in [(false, false), (true, false), (false, true), (true, true)] {
                for y_range in [None, Some(finite(y)), Some((f64::NAN, f64::INFINITY))] {
                    let mut panel = Panel::new(*name, "x", "y", finite(x));
                    panel.x_log = x_log;
                    panel.y_log = y_log;
                    panel.y_range = y_range;
                    panel.series.push(Series::line("data", x.clone(), y.clone(), 0));
                    let fig =
                        Figure { id: "extreme".into(), title: "t".into(), caption: String::new(), panels: vec![panel] };
                    let what = format!("{name}, log x {x_log}, log y {y_log}, y range {y_range:?}");
                    assert!(to_png(&fig, false).is_ok(), "{what}");
                    assert!(to_svg(&fig).is_ok(), "{what}");
                }
            }
        }
    }

    #[test]
    fn axis_ranges_are_finite_ordered_and_bounded() {
        let cases = [
            (1e-320, 1e308, true),
            (0.0, 0.0, true),
            (-1.0, 5.0, true),
            (f64::NAN, 1.0, false),
            (5.0, 5.0, false),
            (0.0, 0.0, false),
            (-f64::MAX, f64::MAX, false),
            (f64::NEG_INFINITY, f64::INFINITY, true),
            (3.0, 1.0, false),
        ];
        for (lo, hi, log) in cases {
            let (a, b) = axis_range(lo, hi, log);
            assert!(a.is_finite() && b.is_finite() && a < b, "({lo}, {hi}, log {log}) -> ({a}, {b})");
            assert!(a.abs() <= AXIS_MAX && b.abs() <= AXIS_MAX);
            if log {
                assert!(a > 0.0 && (b / a).log10() <= AXIS_DECADES + 1e-9, "({lo}, {hi}) -> ({a}, {b})");
            }
        }
        assert_eq!(axis_range(1e-4, 1e-2, true), (1e-4, 1e-2), "sane ranges are kept");
        assert_eq!(axis_range(-2.0, 3.0, false), (-2.0, 3.0));
    }

    #[test]
    fn png_is_indexed_when_few_colours_and_decodes_to_the_same_pixels() {
        let (w, h) = (7u32, 5u32);
        let few: Vec<u8> =
            (0..w * h).flat_map(|i| if i % 3 == 0 { [255, 255, 255] } else { [31, 119, i as u8] }).collect();
        let many: Vec<u8> = (0..300u32).flat_map(|i| [(i % 256) as u8, (i / 256) as u8, 7]).collect();
        for (rgb, w, h, indexed) in [(few, w, h, true), (many, 300, 1, false)] {
            let bytes = encode_png(&rgb, w, h, png::Compression::Default).unwrap();
            let mut dec = png::Decoder::new(std::io::Cursor::new(bytes));
            dec.set_transformations(png::Transformations::EXPAND);
            let mut reader = dec.read_info().unwrap();
            assert_eq!(reader.info().color_type == png::ColorType::Indexed, indexed);
            let mut buf = vec![0; reader.output_buffer_size()];
            let frame = reader.next_frame(&mut buf).unwrap();
            assert_eq!(&buf[..frame.buffer_size()], &rgb[..], "same pixels");
        }
    }

    #[test]
    fn a_dashed_line_is_one_polyline_with_its_dash_pattern_in_svg_and_dashes_in_png() {
        use crate::figure::{Dash, Figure, Panel, Series};
        let x: Vec<f64> = (0..200).map(|i| i as f64 * 0.1).collect();
        let y: Vec<f64> = x.iter().map(|v| v.sin() + 2.0).collect();
        let mut panel = Panel::new("p", "f", "c", (0.0, 20.0));
        panel.series = vec![
            Series::line("solid", x.clone(), y.clone(), 0),
            Series::line("dashed", x.clone(), y.clone(), 1).dashed(Dash::Dashed),
            Series::line("dotted", x.clone(), y.clone(), 2).dashed(Dash::Dotted),
        ];
        let fig = Figure { id: "t".into(), title: "dashes".into(), caption: String::new(), panels: vec![panel] };
        let svg = to_svg(&fig).unwrap();
        let raw = to_svg_raw(&fig).unwrap();
        assert!(svg.contains("stroke-dasharray=\"10 6\"") && svg.contains("stroke-dasharray=\"2 5\""), "{svg}");
        assert!(!svg.contains("0.9995"), "every mark replaced");
        // The dashed curve is the solid one's polyline, point for point.
        let lines: Vec<&str> =
            svg.lines().filter(|l| l.contains("<polyline") && l.matches(',').count() > 100).collect();
        let points = |l: &str| l.split("points=\"").nth(1).map(|p| p.split('"').next().unwrap_or("").to_string());
        assert_eq!(lines.len(), 3, "{svg}");
        assert_eq!(points(lines[0]), points(lines[1]));
        assert_eq!(points(lines[0]), points(lines[2]));
        let count = |t: &str| t.matches("<polyline").count();
        assert!(count(&raw) > count(&svg) + 100, "{} dash elements before, {} after", count(&raw), count(&svg));
        assert!(svg.len() * 2 < raw.len(), "{} of {} bytes", svg.len(), raw.len());
        // A PNG draws the dashes: its pixels differ from a figure whose lines are all solid.
        let mut solid = fig.clone();
        solid.panels[0].series.iter_mut().for_each(|s| s.dash = Dash::Solid);
        assert_ne!(to_png(&fig, false).unwrap(), to_png(&solid, false).unwrap());
    }
}
