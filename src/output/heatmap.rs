//! Heat maps of a study: a claimed quantity over two varied values, one panel per model (and
//! per combination of any further varied values), the samples where the claim holds outlined,
//! those whose value rests on a point that did not settle hatched one way and those where it
//! cannot be evaluated the other. A full grid draws cells; a quasi-random design draws dots.

use std::path::Path;

use plotters::prelude::*;

use crate::analysis::study::{ClaimRow, Verdict};
use crate::error::{Error, Result};
use crate::number::fmt_num;

use super::manifest::Manifest;

/// How a sample is marked on a map.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Mark {
    /// The claim holds on settled points: outlined.
    Holds,
    /// It does not: plain.
    Fails,
    /// Its value rests on a point that did not settle: hatched (falling strokes, purple).
    Unsettled,
    /// It cannot be evaluated: hatched (rising strokes, white) or crossed.
    NotEvaluable,
}

impl Mark {
    /// The mark of a study row.
    pub fn of(r: &ClaimRow) -> Mark {
        if r.outcome == Verdict::NotEvaluable {
            Mark::NotEvaluable
        } else if !r.settled {
            Mark::Unsettled
        } else if r.outcome == Verdict::Holds {
            Mark::Holds
        } else {
            Mark::Fails
        }
    }
}

/// One panel: its title, its samples as (x, y, value, mark), and where the experiment itself
/// sits (its own values of the two axes; none when unknown or when another varied value of the
/// panel is not the experiment's own).
#[derive(Debug, Clone)]
pub struct MapPanel {
    /// Panel title.
    pub title: String,
    /// Samples as (x, y, value, mark).
    pub points: Vec<(f64, f64, f64, Mark)>,
    /// Where the experiment itself sits (x, y), when known.
    pub assumed: Option<(f64, f64)>,
}

/// A heat map of one claim.
#[derive(Debug, Clone)]
pub struct HeatMap {
    /// File stem.
    pub id: String,
    /// Title above the panels.
    pub title: String,
    /// Horizontal axis label.
    pub x_label: String,
    /// Vertical axis label.
    pub y_label: String,
    /// Logarithmic horizontal axis.
    pub x_log: bool,
    /// Logarithmic vertical axis.
    pub y_log: bool,
    /// The samples lie on a grid (cells drawn) rather than scattered (dots).
    pub grid: bool,
    /// One panel per claim.
    pub panels: Vec<MapPanel>,
}

/// Most panels drawn per map (further combinations of other varied values are left out, and
/// the title says so).
const MAX_PANELS: usize = 12;
/// The colour of a value that rests on a point that did not settle (the pages' `.unsettled`).
const UNSETTLED: RGBColor = RGBColor(130, 80, 223);
const PANEL_W: u32 = 420;
const PANEL_H: u32 = 400;
const BAR_W: u32 = 130;

/// The heat maps of a study's rows: one per claim check. `assumed`: per model of the manifest,
/// the experiment's own value of each varied key (may be empty), marked on the panels.
pub fn maps(manifest: &Manifest, rows: &[ClaimRow], assumed: &[Vec<Option<f64>>]) -> Vec<HeatMap> {
    let Some((xi, yi)) = manifest.map else { return Vec::new() };
    let n_checks = rows.iter().map(|r| r.check + 1).max().unwrap_or(0);
    let others: Vec<usize> = (0..manifest.vary.len()).filter(|&k| k != xi && k != yi).collect();
    let mut out = Vec::new();
    for check in 0..n_checks {
        let of: Vec<&ClaimRow> = rows.iter().filter(|r| r.check == check).collect();
        let Some(first) = of.iter().find(|r| r.outcome != Verdict::NotEvaluable).or(of.first()) else { continue };
        let mut panels: Vec<(String, MapPanel)> = Vec::new();
        for r in &of {
            let label = manifest.models.iter().find(|m| m.0 == r.model).map(|m| m.1.clone()).unwrap_or_default();
            let rest: Vec<String> =
                others.iter().map(|&k| format!("{} {}", manifest.vary[k].name, fmt_num(r.values[k]))).collect();
            let key = [label.clone()].into_iter().chain(rest).filter(|s| !s.is_empty()).collect::<Vec<_>>().join(", ");
            let point = (r.values[xi], r.values[yi], r.value, Mark::of(r));
            match panels.iter_mut().find(|(k, _)| *k == key) {
                Some((_, p)) => p.points.push(point),
                None => {
                    let own = manifest.models.iter().position(|m| m.0 == r.model).and_then(|m| assumed.get(m));
                    let at = own.and_then(|own| {
                        let same = others.iter().all(|&k| own.get(k).copied().flatten() == Some(r.values[k]));
                        match (own.get(xi).copied().flatten(), own.get(yi).copied().flatten()) {
                            (Some(x), Some(y)) if same => Some((x, y)),
                            _ => None,
                        }
                    });
                    panels.push((key.clone(), MapPanel { title: key, points: vec![point], assumed: at }))
                }
            }
        }
        let total = panels.len();
        let shown: Vec<MapPanel> = panels.into_iter().take(MAX_PANELS).map(|(_, p)| p).collect();
        let more =
            if total > shown.len() { format!(" (first {} of {total} panels)", shown.len()) } else { String::new() };
        let mut marked =
            if shown.iter().any(|p| p.assumed.is_some()) { "; red cross: the experiment's own values" } else { "" }
                .to_string();
        if of.iter().any(|r| r.unsettled()) {
            marked.push_str(if manifest.grid {
                "; purple strokes: the value rests on a point that did not settle"
            } else {
                "; purple dot: the value rests on a point that did not settle"
            });
        }
        if of.iter().any(|r| r.outcome == Verdict::NotEvaluable) {
            marked.push_str(if manifest.grid {
                "; white strokes: not evaluable"
            } else {
                "; white cross: not evaluable"
            });
        }
        out.push(HeatMap {
            id: format!("{}_check-{check}", manifest.study),
            title: format!(
                "{}: {} ({}); outlined: the claim holds{marked}{more}",
                manifest.figure, first.claim, first.bound
            ),
            x_label: manifest.vary[xi].label.clone(),
            y_label: manifest.vary[yi].label.clone(),
            x_log: manifest.vary[xi].log,
            y_log: manifest.vary[yi].log,
            grid: manifest.grid,
            panels: shown,
        });
    }
    out
}

fn size(map: &HeatMap) -> (u32, u32) {
    let cols = map.panels.len().clamp(1, 3) as u32;
    let rows = map.panels.len().div_ceil(3).max(1) as u32;
    (cols * PANEL_W + BAR_W, rows * PANEL_H + 50)
}

/// Writes the map as PNG and SVG into `dir`.
pub fn write(map: &HeatMap, dir: &Path) -> Result<()> {
    super::plot::register_font()?;
    let (w, h) = size(map);
    let mut rgb = vec![0u8; 3 * w as usize * h as usize];
    draw(map, BitMapBackend::with_buffer(&mut rgb, (w, h)).into_drawing_area())?;
    let png = super::plot::encode_png(&rgb, w, h, png::Compression::Default).map_err(|e| err(map, e))?;
    super::study::write_atomic(&dir.join(format!("{}.png", map.id)), &png)?;
    let mut svg = String::new();
    draw(map, SVGBackend::with_string(&mut svg, (w, h)).into_drawing_area())?;
    super::study::write_atomic(&dir.join(format!("{}.svg", map.id)), super::svg::compact(&svg).as_bytes())
}

fn err(map: &HeatMap, e: impl std::fmt::Display) -> Error {
    Error::Render { what: format!("heat map {}", map.id), message: e.to_string() }
}

/// Viridis, by five control points.
fn viridis(t: f64) -> RGBColor {
    const C: [(f64, f64, f64); 5] =
        [(68.0, 1.0, 84.0), (59.0, 82.0, 139.0), (33.0, 145.0, 140.0), (94.0, 201.0, 98.0), (253.0, 231.0, 37.0)];
    let t = if t.is_finite() { t.clamp(0.0, 1.0) } else { 0.0 };
    let s = t * 4.0;
    let i = (s.floor() as usize).min(3);
    let f = s - i as f64;
    let mix = |a: f64, b: f64| (a + (b - a) * f).round() as u8;
    RGBColor(mix(C[i].0, C[i + 1].0), mix(C[i].1, C[i + 1].1), mix(C[i].2, C[i + 1].2))
}

/// The colour scale: value range and whether it is logarithmic.
struct Scale {
    lo: f64,
    hi: f64,
    log: bool,
}

impl Scale {
    fn of(map: &HeatMap) -> Scale {
        let v: Vec<f64> =
            map.panels.iter().flat_map(|p| p.points.iter().map(|q| q.2)).filter(|x| x.is_finite()).collect();
        let lo = v.iter().copied().fold(f64::INFINITY, f64::min);
        let hi = v.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        if !lo.is_finite() {
            return Scale { lo: 0.0, hi: 1.0, log: false };
        }
        let log = lo > 0.0 && hi / lo > 3.0;
        let hi = if hi > lo { hi } else { lo + 1.0 };
        Scale { lo, hi, log }
    }

    fn t(&self, v: f64) -> f64 {
        if self.log {
            (v / self.lo).ln() / (self.hi / self.lo).ln()
        } else {
            (v - self.lo) / (self.hi - self.lo)
        }
    }

    /// The colour bar's label at `t`: three significant digits, or as many decimals as tell
    /// its ticks apart when the values span less than that resolves (1.0368-1.0377).
    fn label(&self, t: f64) -> String {
        let v = self.value(t);
        let step = (self.hi - self.lo) / 5.0;
        if self.log || step.is_nan() || step <= 0.0 || v == 0.0 || !(0.01..1000.0).contains(&v.abs()) {
            return short(v);
        }
        let needed = (-step.log10().floor()).clamp(0.0, 8.0) as usize;
        let digits = (2 - v.abs().log10().floor() as i32).clamp(0, 4) as usize;
        if needed <= digits {
            short(v)
        } else {
            format!("{v:.needed$}")
        }
    }

    fn value(&self, t: f64) -> f64 {
        if self.log {
            self.lo * (self.hi / self.lo).powf(t)
        } else {
            self.lo + (self.hi - self.lo) * t
        }
    }
}

/// Three significant digits.
fn short(v: f64) -> String {
    if v != 0.0 && !(0.01..1000.0).contains(&v.abs()) {
        format!("{v:.2e}")
    } else {
        let digits = (2 - v.abs().max(1e-300).log10().floor() as i32).clamp(0, 4) as usize;
        format!("{v:.digits$}")
    }
}

/// Distinct sorted values.
fn distinct(v: impl Iterator<Item = f64>) -> Vec<f64> {
    let mut out: Vec<f64> = v.collect();
    out.sort_by(f64::total_cmp);
    out.dedup();
    out
}

/// The title in its 50-pixel band, wrapped at words to the band's width: one or two lines at
/// 16 px, else up to three at 13 px (a longer title is cut after the third line).
fn draw_title<DB: DrawingBackend>(map: &HeatMap, area: &DrawingArea<DB, plotters::coord::Shift>) -> Result<()> {
    let width = area.dim_in_pixel().0.saturating_sub(24);
    for (size, most, step) in [(16, 2, 20), (13, 3, 15)] {
        let font = ("sans-serif", size).into_font().color(&BLACK);
        let fits = |text: &str| area.estimate_text_size(text, &font).map(|(w, _)| w <= width).unwrap_or(true);
        let mut lines: Vec<String> = Vec::new();
        for word in map.title.split(' ') {
            match lines.last_mut() {
                Some(line) if fits(&format!("{line} {word}")) => {
                    line.push(' ');
                    line.push_str(word);
                }
                _ => lines.push(word.to_string()),
            }
        }
        if lines.len() <= most || size == 13 {
            let top = if lines.len() == 1 { 16 } else { 5 };
            for (i, line) in lines.iter().take(most).enumerate() {
                area.draw_text(line, &font, (12, top + step * i as i32)).map_err(|e| err(map, e))?;
            }
            return Ok(());
        }
    }
    Ok(())
}

fn draw<DB: DrawingBackend>(map: &HeatMap, root: DrawingArea<DB, plotters::coord::Shift>) -> Result<()> {
    root.fill(&WHITE).map_err(|e| err(map, e))?;
    let (w, _) = size(map);
    let (body, bar) = root.split_horizontally(w - BAR_W);
    let (title, body) = body.split_vertically(50);
    draw_title(map, &title)?;
    let scale = Scale::of(map);
    let rows = map.panels.len().div_ceil(3).max(1);
    let cols = map.panels.len().clamp(1, 3);
    let areas = body.split_evenly((rows, cols));
    for (panel, area) in map.panels.iter().zip(areas.iter()) {
        draw_panel(map, panel, area, &scale)?;
    }
    draw_bar(map, &bar, &scale)?;
    root.present().map_err(|e| err(map, e))
}

fn draw_panel<DB: DrawingBackend>(
    map: &HeatMap,
    panel: &MapPanel,
    area: &DrawingArea<DB, plotters::coord::Shift>,
    scale: &Scale,
) -> Result<()> {
    let xs = distinct(panel.points.iter().map(|p| p.0));
    let ys = distinct(panel.points.iter().map(|p| p.1));
    // Plot coordinates: the grid index (cells), or the value (log10 on a log axis).
    let tx = |v: f64, log: bool, all: &[f64]| -> f64 {
        if map.grid {
            all.iter().position(|a| *a == v).unwrap_or(0) as f64
        } else if log {
            v.log10()
        } else {
            v
        }
    };
    let range = |all: &[f64], log: bool| -> (f64, f64) {
        if map.grid {
            (-0.5, all.len().max(1) as f64 - 0.5)
        } else if all.is_empty() {
            (0.0, 1.0)
        } else {
            let lo = tx(all[0], log, all);
            let hi = tx(all[all.len() - 1], log, all);
            let pad = ((hi - lo) * 0.05).max(1e-9);
            super::axis::axis_range(lo - pad, hi + pad, false)
        }
    };
    let (x0, x1) = range(&xs, map.x_log);
    let (y0, y1) = range(&ys, map.y_log);
    let mut chart = ChartBuilder::on(area)
        .caption(&panel.title, ("sans-serif", 15).into_font())
        .margin(8)
        .x_label_area_size(40)
        .y_label_area_size(68)
        .build_cartesian_2d(x0..x1, y0..y1)
        .map_err(|e| err(map, e))?;
    let label = |all: Vec<f64>, log: bool, grid: bool| {
        move |v: &f64| {
            if grid {
                let i = v.round();
                if (v - i).abs() < 1e-6 && i >= 0.0 && (i as usize) < all.len() {
                    fmt_num(all[i as usize])
                } else {
                    String::new()
                }
            } else if log {
                // Ticks at round steps of the logarithm: three significant digits.
                short(10f64.powf(*v))
            } else {
                fmt_num(*v)
            }
        }
    };
    let fx = label(xs.clone(), map.x_log, map.grid);
    let fy = label(ys.clone(), map.y_log, map.grid);
    let mut mesh = chart.configure_mesh();
    mesh.disable_mesh()
        .label_style(("sans-serif", 13))
        .axis_desc_style(("sans-serif", 14))
        .x_desc(map.x_label.as_str())
        .y_desc(map.y_label.as_str())
        .x_label_formatter(&fx)
        .y_label_formatter(&fy);
    if map.grid {
        mesh.x_labels(xs.len().min(12)).y_labels(ys.len().min(12));
    }
    mesh.draw().map_err(|e| err(map, e))?;
    let colour = |v: f64| if v.is_finite() { viridis(scale.t(v)) } else { RGBColor(200, 200, 200) };
    if map.grid {
        let index = |x: f64, y: f64| (tx(x, false, &xs), tx(y, false, &ys));
        draw_cells(&mut chart, map, panel, &index, &colour)?;
    } else {
        let dots = panel
            .points
            .iter()
            .map(|&(x, y, v, _)| Circle::new((tx(x, map.x_log, &xs), tx(y, map.y_log, &ys)), 5, colour(v).filled()));
        chart.draw_series(dots).map_err(|e| err(map, e))?;
        let rings = panel.points.iter().filter(|p| p.3 == Mark::Holds).map(|&(x, y, _, _)| {
            Circle::new((tx(x, map.x_log, &xs), tx(y, map.y_log, &ys)), 7, ShapeStyle::from(&BLACK).stroke_width(2))
        });
        chart.draw_series(rings).map_err(|e| err(map, e))?;
        let marked =
            panel.points.iter().filter(|p| p.3 == Mark::Unsettled).map(|&(x, y, _, _)| {
                Circle::new((tx(x, map.x_log, &xs), tx(y, map.y_log, &ys)), 2, UNSETTLED.filled())
            });
        chart.draw_series(marked).map_err(|e| err(map, e))?;
        let crossed = panel.points.iter().filter(|p| p.3 == Mark::NotEvaluable).map(|&(x, y, _, _)| {
            Cross::new((tx(x, map.x_log, &xs), tx(y, map.y_log, &ys)), 5, ShapeStyle::from(&WHITE).stroke_width(2))
        });
        chart.draw_series(crossed).map_err(|e| err(map, e))?;
    }
    let at = panel.assumed.and_then(|(x, y)| {
        if map.grid {
            Some((grid_position(x, &xs, map.x_log)?, grid_position(y, &ys, map.y_log)?))
        } else {
            let (x, y) = (tx(x, map.x_log, &xs), tx(y, map.y_log, &ys));
            (x0 <= x && x <= x1 && y0 <= y && y <= y1).then_some((x, y))
        }
    });
    if let Some(at) = at {
        // A white cross under a red one: visible on every colour of the scale.
        for (colour, width) in [(WHITE, 6), (RED, 3)] {
            chart
                .draw_series(std::iter::once(Cross::new(at, 8, ShapeStyle::from(&colour).stroke_width(width))))
                .map_err(|e| err(map, e))?;
        }
    }
    Ok(())
}

/// A grid map's cells: each in the colour of its value, outlined where the claim holds, hatched
/// white where it cannot be evaluated and in the unsettled colour where points did not settle.
/// `index` gives a sample's cell.
fn draw_cells<DB: DrawingBackend>(
    chart: &mut ChartContext<
        '_,
        DB,
        Cartesian2d<plotters::coord::types::RangedCoordf64, plotters::coord::types::RangedCoordf64>,
    >,
    map: &HeatMap,
    panel: &MapPanel,
    index: &dyn Fn(f64, f64) -> (f64, f64),
    colour: &dyn Fn(f64) -> RGBColor,
) -> Result<()> {
    let cells = panel.points.iter().map(|&(x, y, v, _)| {
        let (i, j) = index(x, y);
        Rectangle::new([(i - 0.5, j - 0.5), (i + 0.5, j + 0.5)], colour(v).filled())
    });
    chart.draw_series(cells).map_err(|e| err(map, e))?;
    let held = panel.points.iter().filter(|p| p.3 == Mark::Holds).map(|&(x, y, _, _)| {
        let (i, j) = index(x, y);
        Rectangle::new([(i - 0.45, j - 0.45), (i + 0.45, j + 0.45)], ShapeStyle::from(&BLACK).stroke_width(3))
    });
    chart.draw_series(held).map_err(|e| err(map, e))?;
    // Not evaluable: three diagonal strokes across the cell.
    let hatch = panel.points.iter().filter(|p| p.3 == Mark::NotEvaluable).flat_map(|&(x, y, _, _)| {
        let (i, j) = index(x, y);
        [-0.5, 0.0, 0.5].map(|o: f64| {
            let (a, b) = ((-0.5f64).max(o - 0.5), 0.5f64.min(o + 0.5));
            PathElement::new(vec![(i + a, j + a - o), (i + b, j + b - o)], ShapeStyle::from(&WHITE).stroke_width(2))
        })
    });
    chart.draw_series(hatch).map_err(|e| err(map, e))?;
    // Unsettled: three strokes the other way, in the colour the pages use for it.
    let hatch = panel.points.iter().filter(|p| p.3 == Mark::Unsettled).flat_map(|&(x, y, _, _)| {
        let (i, j) = index(x, y);
        [-0.5, 0.0, 0.5].map(|o: f64| {
            let (a, b) = ((-0.5f64).max(o - 0.5), 0.5f64.min(o + 0.5));
            PathElement::new(vec![(i + a, j - a + o), (i + b, j - b + o)], ShapeStyle::from(&UNSETTLED).stroke_width(3))
        })
    });
    chart.draw_series(hatch).map_err(|e| err(map, e))?;
    Ok(())
}

/// Where `v` falls on a grid axis of the distinct values `all` (cell `i` at `i`), interpolated
/// between neighbouring values (in logarithms on a log axis); `None` outside the grid.
fn grid_position(v: f64, all: &[f64], log: bool) -> Option<f64> {
    let f = |a: f64| if log { a.ln() } else { a };
    if let Some(i) = all.iter().position(|a| *a == v) {
        return Some(i as f64);
    }
    let j = all.windows(2).position(|w| w[0] < v && v < w[1])?;
    Some(j as f64 + (f(v) - f(all[j])) / (f(all[j + 1]) - f(all[j])))
}

fn draw_bar<DB: DrawingBackend>(
    map: &HeatMap,
    area: &DrawingArea<DB, plotters::coord::Shift>,
    scale: &Scale,
) -> Result<()> {
    let mut chart = ChartBuilder::on(area)
        .margin_top(70)
        .margin_bottom(50)
        .margin_right(10)
        .y_label_area_size(70)
        .build_cartesian_2d(0.0..1.0, 0.0..1.0)
        .map_err(|e| err(map, e))?;
    let steps = 64;
    chart
        .draw_series((0..steps).map(|k| {
            let (a, b) = (k as f64 / steps as f64, (k + 1) as f64 / steps as f64);
            Rectangle::new([(0.0, a), (1.0, b)], viridis(0.5 * (a + b)).filled())
        }))
        .map_err(|e| err(map, e))?;
    let fy = |t: &f64| scale.label(*t);
    chart
        .configure_mesh()
        .disable_mesh()
        .disable_x_axis()
        .y_labels(6)
        .y_label_formatter(&fy)
        .y_label_style(("sans-serif", 13))
        .axis_desc_style(("sans-serif", 14))
        .y_desc(if scale.log { "value (log colour scale)" } else { "value" })
        .draw()
        .map_err(|e| err(map, e))?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::{grid_position, Scale};

    #[test]
    fn a_narrow_colour_scale_tells_its_ticks_apart() {
        let narrow = Scale { lo: 1.036826, hi: 1.037726, log: false };
        let labels: Vec<String> = (0..=5).map(|k| narrow.label(k as f64 / 5.0)).collect();
        let mut distinct = labels.clone();
        distinct.dedup();
        assert_eq!(distinct.len(), 6, "{labels:?}");
        assert_eq!(labels[0], "1.0368");
        // A usual spread keeps three significant digits.
        let usual = Scale { lo: 1.5, hi: 4.0, log: false };
        assert_eq!((usual.label(0.0).as_str(), usual.label(1.0).as_str()), ("1.50", "4.00"));
    }

    #[test]
    fn grid_positions_interpolate_between_cells_and_stop_at_the_edges() {
        let d = [0.2, 0.3, 0.4];
        assert_eq!(grid_position(0.3, &d, false), Some(1.0));
        assert!((grid_position(0.35, &d, false).unwrap() - 1.5).abs() < 1e-12);
        // On a log axis the geometric middle is half way.
        assert!((grid_position(0.01, &[0.005, 0.02], true).unwrap() - 0.5).abs() < 1e-12);
        assert_eq!(grid_position(0.5, &d, false), None);
        assert_eq!(grid_position(0.1, &d, false), None);
        assert_eq!(grid_position(0.7, &[0.7], false), Some(0.0));
    }
}
