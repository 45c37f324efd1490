//! The paper's figure under ours: a "scan" made here (a curve drawn by plotters in another style
//! and size than the report's, its axis calibration known), described as a reviewer would
//! describe a scan, and the overlay: every point of our curve lands within one pixel of where
//! the scan draws it, on linear and log axes. A calibration three pixels off does not.

use crate::common;

use std::path::Path;

use plotters::prelude::*;
use shotdamp::figure::{Figure, Panel, Series};
use shotdamp::output::scan;

/// A resonance curve: (f, compliance).
fn curve() -> (Vec<f64>, Vec<f64>) {
    let f: Vec<f64> = (0..=240).map(|i| 44.0 + 12.0 * i as f64 / 240.0).collect();
    let c = f.iter().map(|&f| 1e-4 / (((f / 49.0) * (f / 49.0) - 1.0).powi(2) + 0.03f64.powi(2)).sqrt()).collect();
    (f, c)
}

/// Draws the curve in red on a 900 x 620 image with wide margins and a grey frame, x from
/// `x` and y from `y` (log when `y_log`); writes the PNG and returns its calibration: the
/// pixels of the axis ends.
fn make_scan(path: &Path, x: (f64, f64), y: (f64, f64), y_log: bool) -> ([f64; 2], [f64; 2]) {
    let (w, h) = (900u32, 620u32);
    let mut rgb = vec![255u8; (3 * w * h) as usize];
    let (f, c) = curve();
    let ends;
    {
        let root = BitMapBackend::with_buffer(&mut rgb, (w, h)).into_drawing_area();
        root.fill(&WHITE).unwrap();
        let mut b = ChartBuilder::on(&root);
        b.margin_left(83).margin_right(41).margin_top(57).margin_bottom(69);
        let frame = ShapeStyle::from(&RGBColor(120, 120, 120)).stroke_width(2);
        let red = ShapeStyle::from(&RGBColor(255, 0, 0)).stroke_width(1);
        let points = f.iter().copied().zip(c.iter().copied());
        if y_log {
            let mut chart = b.build_cartesian_2d(x.0..x.1, (y.0..y.1).log_scale()).unwrap();
            let (a, z) = (chart.backend_coord(&(x.0, y.0)), chart.backend_coord(&(x.1, y.1)));
            chart.plotting_area().draw(&Rectangle::new([(x.0, y.0), (x.1, y.1)], frame)).unwrap();
            chart.draw_series(LineSeries::new(points, red)).unwrap();
            ends = (a, z);
        } else {
            let mut chart = b.build_cartesian_2d(x.0..x.1, y.0..y.1).unwrap();
            let (a, z) = (chart.backend_coord(&(x.0, y.0)), chart.backend_coord(&(x.1, y.1)));
            chart.plotting_area().draw(&Rectangle::new([(x.0, y.0), (x.1, y.1)], frame)).unwrap();
            chart.draw_series(LineSeries::new(points, red)).unwrap();
            ends = (a, z);
        }
        root.present().unwrap();
    }
    let file = std::fs::File::create(path).unwrap();
    let mut enc = png::Encoder::new(std::io::BufWriter::new(file), w, h);
    enc.set_color(png::ColorType::Rgb);
    enc.set_depth(png::BitDepth::Eight);
    enc.write_header().unwrap().write_image_data(&rgb).unwrap();
    let ((x0, y0), (x1, y1)) = ends;
    ([x0 as f64, x1 as f64], [y0 as f64, y1 as f64])
}

/// The red pixels of the scan.
fn red_pixels(path: &Path) -> (u32, Vec<bool>) {
    let decoder = png::Decoder::new(std::io::BufReader::new(std::fs::File::open(path).unwrap()));
    let mut reader = decoder.read_info().unwrap();
    let mut buf = vec![0; reader.output_buffer_size()];
    let info = reader.next_frame(&mut buf).unwrap();
    let red = buf.chunks(3).map(|p| p[0] > 200 && p[1] < 90 && p[2] < 90).collect();
    (info.width, red)
}

/// The largest distance, in pixels, from a point of the overlay to the nearest red pixel.
fn worst_distance(png: &Path, traces: &[scan::Trace]) -> f64 {
    let (w, red) = red_pixels(png);
    let h = red.len() as u32 / w;
    let mut worst: f64 = 0.0;
    let mut n = 0;
    for t in traces {
        for &(px, py) in t.runs.iter().flatten() {
            let mut best = f64::INFINITY;
            for j in (py.floor() as i64 - 3).max(0)..=(py.ceil() as i64 + 3).min(h as i64 - 1) {
                for i in (px.floor() as i64 - 3).max(0)..=(px.ceil() as i64 + 3).min(w as i64 - 1) {
                    if red[(j as u32 * w + i as u32) as usize] {
                        best = best.min((i as f64 - px).abs().max((j as f64 - py).abs()));
                    }
                }
            }
            worst = worst.max(best);
            n += 1;
        }
    }
    assert!(n > 200, "{n} points");
    worst
}

fn figure(y_log: bool, x: (f64, f64)) -> Figure {
    let (f, c) = curve();
    let mut panel = Panel::new("t", "Hz", "m/N", x);
    if y_log {
        panel = panel.log_y();
    }
    panel.series.push(Series::line("computed", f, c, 0));
    Figure { id: "compliance".into(), title: "t".into(), caption: "c".into(), panels: vec![panel] }
}

fn describe(dir: &Path, name: &str, xp: [f64; 2], xv: (f64, f64), yp: [f64; 2], yv: (f64, f64), y_log: bool) {
    std::fs::write(
        dir.join(format!("{name}.toml")),
        format!(
            "experiment = \"e\"\nplot = \"compliance\"\nimage = \"{name}.png\"\nx = {{ pixels = [{}, {}], values = [{:e}, {:e}] }}\ny = {{ pixels = [{}, {}], values = [{:e}, {:e}], log = {y_log} }}\n",
            xp[0], xp[1], xv.0, xv.1, yp[0], yp[1], yv.0, yv.1
        ),
    )
    .unwrap();
}

#[test]
fn the_overlay_lands_within_a_pixel_of_the_scans_curve() {
    let dir = tempfile::tempdir().unwrap();
    for (name, y_log, y) in [("log", true, (1e-5, 1e-2)), ("linear", false, (0.0, 4e-3))] {
        let x = (44.0, 56.0);
        let png = dir.path().join(format!("{name}.png"));
        let (xp, yp) = make_scan(&png, x, y, y_log);
        describe(dir.path(), name, xp, x, yp, y, y_log);
        let s = scan::load(&dir.path().join(format!("{name}.toml"))).unwrap();
        assert_eq!((s.width, s.height), (900, 620));
        let traces = scan::overlay(&s, &figure(y_log, x)).unwrap();
        let d = worst_distance(&png, &traces);
        eprintln!("{name} axes: worst distance {d} px");
        assert!(d <= 1.0, "{name} axes: a point of the overlay is {d} px from the scan's curve");

        // The check can fail: a calibration 3 px off vertically puts points off the curve.
        describe(dir.path(), name, xp, x, [yp[0] + 3.0, yp[1] + 3.0], y, y_log);
        let off = scan::load(&dir.path().join(format!("{name}.toml"))).unwrap();
        let d = worst_distance(&png, &scan::overlay(&off, &figure(y_log, x)).unwrap());
        eprintln!("{name} axes, calibration 3 px off: worst distance {d} px");
        assert!(d > 1.0, "{name} axes, calibration 3 px off: {d} px");
    }
}

#[test]
fn a_webplotdigitizer_project_calibrates_a_scan() {
    let dir = tempfile::tempdir().unwrap();
    let (x, y) = ((44.0, 56.0), (1e-5, 1e-2));
    let png = dir.path().join("wpd.png");
    let (xp, yp) = make_scan(&png, x, y, true);
    // The project a reviewer saves after calibrating the axes in WebPlotDigitizer (version 4):
    // X1, X2 on the horizontal axis, Y1, Y2 on the vertical one.
    let project = serde_json::json!({
        "version": [4, 2],
        "axesColl": [{
            "name": "XY", "type": "XYAxes", "isLogX": false, "isLogY": true,
            "calibrationPoints": [
                { "px": xp[0], "py": yp[0], "dx": "44", "dy": "0" },
                { "px": xp[1], "py": yp[0], "dx": "56", "dy": "0" },
                { "px": xp[0], "py": yp[0], "dx": "0", "dy": "1e-5" },
                { "px": xp[0], "py": yp[1], "dx": "0", "dy": "1e-2" }
            ]
        }],
        "datasetColl": []
    });
    std::fs::write(dir.path().join("wpd.json"), project.to_string()).unwrap();
    std::fs::write(
        dir.path().join("wpd.toml"),
        "title = \"Fig. 5\"\nexperiment = \"e\"\nplot = \"compliance\"\nimage = \"wpd.png\"\nwpd = \"wpd.json\"\n",
    )
    .unwrap();
    let s = scan::load(&dir.path().join("wpd.toml")).unwrap();
    let d = worst_distance(&png, &scan::overlay(&s, &figure(true, x)).unwrap());
    assert!(d <= 1.0, "{d} px");
    assert!(s.calibrated_by.contains("WebPlotDigitizer"));
}

#[test]
fn bad_scan_files_are_named() {
    let dir = tempfile::tempdir().unwrap();
    let (xp, yp) = make_scan(&dir.path().join("s.png"), (44.0, 56.0), (0.0, 1.0), false);
    let cases = [
        ("image = \"missing.png\"\nx = { pixels = [1, 2], values = [1, 2] }\ny = { pixels = [1, 2], values = [1, 2] }", "image"),
        ("image = \"s.png\"", "either wpd"),
        ("image = \"s.png\"\nx = { pixels = [1, 1], values = [1, 2] }\ny = { pixels = [1, 2], values = [1, 2] }", "two different pixels"),
        ("image = \"s.png\"\npanel = 0\nx = { pixels = [1, 2], values = [1, 2] }\ny = { pixels = [1, 2], values = [1, 2] }", "panels count from 1"),
        ("image = \"s.png\"\nx = { pixels = [1, 2], values = [1, 2] }\ny = { pixels = [1, 2], values = [0, 2], log = true }", "values > 0"),
        ("image = \"s.png\"\ncolour = \"red\"\nx = { pixels = [1, 2], values = [1, 2] }\ny = { pixels = [1, 2], values = [1, 2] }", "colour"),
    ];
    for (body, says) in cases {
        let file = dir.path().join("bad.toml");
        std::fs::write(&file, format!("experiment = \"e\"\nplot = \"compliance\"\n{body}\n")).unwrap();
        let e = scan::load(&file).unwrap_err().to_string();
        assert!(e.contains("bad.toml") && e.contains(says), "{body}: {e}");
    }
    let _ = (xp, yp);
}

/// Through the binary: a scan in the reference folder's `scans/` goes on the experiment's page
/// (copied beside it, our curves over it, a slider for its opacity); a scan naming a plot the
/// experiment does not have is an input error.
#[test]
fn the_page_shows_our_curves_over_the_scan() {
    let dir = tempfile::tempdir().unwrap();
    let reference = dir.path().join("reference");
    common::copy_tree(&common::repo().join("reference"), &reference);
    let scans = reference.join("scans");
    std::fs::create_dir_all(&scans).unwrap();
    let (xp, yp) = make_scan(&scans.join("fig04b.png"), (2.0, 60.0), (1e-6, 1e-2), true);
    std::fs::write(
        scans.join("fig04b.toml"),
        format!(
            "title = \"Fig. 4(b)\"\nexperiment = \"fig04b_no_damper\"\nplot = \"compliance\"\nmodels = [\"stated\"]\nimage = \"fig04b.png\"\nx = {{ pixels = [{}, {}], values = [2, 60] }}\ny = {{ pixels = [{}, {}], values = [1e-6, 1e-2], log = true }}\n",
            xp[0], xp[1], yp[0], yp[1]
        ),
    )
    .unwrap();
    let out = dir.path().join("out");
    let run = common::shotdamp()
        .arg("--reference")
        .arg(&reference)
        .args(["run", "experiments/fig04b_no_damper.toml", "--out"])
        .arg(&out)
        .output()
        .unwrap();
    assert!(run.status.code().is_some_and(|c| c <= 1), "{}", String::from_utf8_lossy(&run.stderr));
    let page = std::fs::read_to_string(out.join("fig04b_no_damper/stated/index.html")).unwrap();
    assert!(page.contains("The paper's figure under ours"));
    assert!(page.contains("<img src=\"scans/fig04b.png\""));
    assert!(page.contains("<svg class=\"ours\" viewBox=\"0 0 900 620\""));
    assert!(page.contains("type=\"range\""));
    assert!(out.join("fig04b_no_damper/stated/scans/fig04b.png").is_file());
    let other = std::fs::read_to_string(out.join("fig04b_no_damper/coil/index.html")).unwrap();
    assert!(!other.contains("The paper's figure under ours"), "models = [\"stated\"] only");

    let toml = std::fs::read_to_string(scans.join("fig04b.toml")).unwrap().replace("\"compliance\"", "\"nope\"");
    std::fs::write(scans.join("fig04b.toml"), toml).unwrap();
    let run = common::shotdamp()
        .arg("--reference")
        .arg(&reference)
        .args(["run", "experiments/fig04b_no_damper.toml", "--out"])
        .arg(dir.path().join("out2"))
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&run.stderr);
    assert_eq!(run.status.code(), Some(2), "{err}");
    assert!(err.contains("fig04b.toml") && err.contains("plot = \"nope\"") && err.contains("compliance"), "{err}");
}
