//! Figures as finished data: what to draw, not how. Analyses build these; the plot
//! renderer draws them without knowing any physics.

/// Line pattern of a series.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Dash {
    /// A solid line.
    Solid,
    /// Dashes.
    Dashed,
    /// Dots.
    Dotted,
    /// Dashes and dots.
    DashDot,
}

/// Point markers of a series.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Marker {
    /// No marker.
    None,
    /// A circle.
    Circle,
    /// A cross.
    Cross,
    /// A square.
    Square,
    /// A triangle.
    Triangle,
    /// A diamond (a square on its corner).
    Diamond,
}

/// One drawn series.
#[derive(Debug, Clone)]
pub struct Series {
    /// Legend label (empty: not in the legend).
    pub label: String,
    /// Abscissae.
    pub x: Vec<f64>,
    /// Ordinates.
    pub y: Vec<f64>,
    /// Index into the shared palette.
    pub color: usize,
    /// Line style.
    pub dash: Dash,
    /// Draw a line through the points.
    pub line: bool,
    /// Marker at each point.
    pub marker: Marker,
    /// Filled markers (hollow otherwise).
    pub filled: bool,
    /// Marker radius, pixels.
    pub marker_size: u32,
}

impl Series {
    /// Where a line through the points breaks because the abscissae skip a stretch that was
    /// not sampled: `true` at `i` when the step from point `i - 1` to `i` is more than four
    /// times the series' median step and three times both neighbouring steps (on a logarithmic
    /// axis, in the logarithm). Only for strictly increasing abscissae of at least five points
    /// (a frequency list of two bands: drawn as two lines, not one across the gap); grids,
    /// refined grids and branches that turn back are drawn whole.
    pub fn gaps(&self, x_log: bool) -> Vec<bool> {
        let mut gap = vec![false; self.x.len()];
        let at = |x: f64| if x_log { x.ln() } else { x };
        let steps: Vec<f64> = self.x.windows(2).map(|w| at(w[1]) - at(w[0])).collect();
        if self.x.len() < 5 || !steps.iter().all(|s| s.is_finite() && *s > 0.0) {
            return gap;
        }
        let mut sorted = steps.clone();
        sorted.sort_by(f64::total_cmp);
        let median = sorted[sorted.len() / 2];
        for (i, &s) in steps.iter().enumerate() {
            let before = if i > 0 { steps[i - 1] } else { 0.0 };
            let after = steps.get(i + 1).copied().unwrap_or(0.0);
            gap[i + 1] = s > 4.0 * median && s > 3.0 * before.max(after);
        }
        gap
    }

    /// A solid line.
    pub fn line(label: impl Into<String>, x: Vec<f64>, y: Vec<f64>, color: usize) -> Series {
        Series {
            label: label.into(),
            x,
            y,
            color,
            dash: Dash::Solid,
            line: true,
            marker: Marker::None,
            filled: false,
            marker_size: 4,
        }
    }

    /// The same series with another dash.
    pub fn dashed(mut self, dash: Dash) -> Series {
        self.dash = dash;
        self
    }

    /// A line through a dense signal, reduced to the smallest and largest value in each of
    /// `bins` equal intervals of x (in the order they occur), so that the drawing is the same
    /// at the figure's resolution while the files stay small.
    pub fn dense(label: impl Into<String>, x: &[f64], y: &[f64], color: usize, bins: usize) -> Series {
        let n = x.len().min(y.len());
        if n <= 2 * bins || bins == 0 {
            return Series::line(label, x[..n].to_vec(), y[..n].to_vec(), color);
        }
        let (x0, x1) = (x[0], x[n - 1]);
        let width = (x1 - x0) / bins as f64;
        let (mut xs, mut ys) = (Vec::with_capacity(2 * bins + 2), Vec::with_capacity(2 * bins + 2));
        let mut i = 0;
        while i < n {
            let bin = (((x[i] - x0) / width) as usize).min(bins - 1);
            let mut j = i;
            let (mut lo, mut hi) = (i, i);
            while j < n && (((x[j] - x0) / width) as usize).min(bins - 1) == bin {
                if y[j] < y[lo] {
                    lo = j;
                }
                if y[j] > y[hi] {
                    hi = j;
                }
                j += 1;
            }
            for k in if lo <= hi { [lo, hi] } else { [hi, lo] } {
                if xs.last() != Some(&x[k]) {
                    xs.push(x[k]);
                    ys.push(y[k]);
                }
            }
            i = j;
        }
        Series::line(label, xs, ys, color)
    }

    /// The same series with markers of another radius.
    pub fn sized(mut self, radius: u32) -> Series {
        self.marker_size = radius;
        self
    }

    /// The same series with filled markers.
    pub fn filled(mut self) -> Series {
        self.filled = true;
        self
    }

    /// Points only.
    pub fn points(label: impl Into<String>, x: Vec<f64>, y: Vec<f64>, color: usize, marker: Marker) -> Series {
        Series {
            label: label.into(),
            x,
            y,
            color,
            dash: Dash::Solid,
            line: false,
            marker,
            filled: false,
            marker_size: 4,
        }
    }
}

/// A vertical marker line with a label (e.g. a natural frequency).
#[derive(Debug, Clone)]
pub struct VLine {
    /// Where, in the panel's x unit.
    pub x: f64,
    /// Its label.
    pub label: String,
}

/// A corner of a panel.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Corner {
    #[default]
    /// Upper right.
    UpperRight,
    /// Upper left.
    UpperLeft,
    /// Lower right.
    LowerRight,
    /// Lower left.
    LowerLeft,
}

/// One panel of a figure.
#[derive(Debug, Clone)]
pub struct Panel {
    /// Panel title.
    pub title: String,
    /// Horizontal axis label, with its unit.
    pub x_label: String,
    /// Vertical axis label, with its unit.
    pub y_label: String,
    /// Horizontal range.
    pub x_range: (f64, f64),
    /// Logarithmic axes (values <= 0 are left out).
    pub x_log: bool,
    /// Logarithmic vertical axis.
    pub y_log: bool,
    /// Vertical range; `None`: from the data.
    pub y_range: Option<(f64, f64)>,
    /// Where the legend goes (keep it off the data that matters).
    pub legend: Corner,
    /// The curves and points drawn.
    pub series: Vec<Series>,
    /// Vertical marker lines.
    pub vlines: Vec<VLine>,
}

impl Panel {
    /// A panel with linear axes and no series yet.
    pub fn new(
        title: impl Into<String>,
        x_label: impl Into<String>,
        y_label: impl Into<String>,
        x_range: (f64, f64),
    ) -> Panel {
        Panel {
            title: title.into(),
            x_label: x_label.into(),
            y_label: y_label.into(),
            x_range,
            x_log: false,
            y_log: false,
            y_range: None,
            legend: Corner::UpperRight,
            series: Vec::new(),
            vlines: Vec::new(),
        }
    }

    /// The same panel with a logarithmic vertical axis.
    pub fn log_y(mut self) -> Panel {
        self.y_log = true;
        self
    }

    /// The same panel with a logarithmic horizontal axis.
    pub fn log_x(mut self) -> Panel {
        self.x_log = true;
        self
    }
}

/// A figure: one or more panels stacked vertically.
#[derive(Debug, Clone)]
pub struct Figure {
    /// File stem (`ID.png`, `ID.svg`).
    pub id: String,
    /// Title above the figure.
    pub title: String,
    /// One sentence under the figure in the report.
    pub caption: String,
    /// Its panels, drawn one below the other.
    pub panels: Vec<Panel>,
}

#[cfg(test)]
mod tests {
    use super::Series;

    fn breaks(x: Vec<f64>, log: bool) -> Vec<usize> {
        let s = Series::line("", x.clone(), vec![1.0; x.len()], 0);
        s.gaps(log).iter().enumerate().filter(|(_, g)| **g).map(|(i, _)| i).collect()
    }

    /// A frequency list of two bands breaks once, between the bands; a grid, a grid refined
    /// near a peak, a branch that turns back and a short list never do.
    #[test]
    fn a_line_breaks_only_across_a_stretch_not_sampled() {
        let band = |a: f64, step: f64, n: usize| (0..n).map(move |i| a + step * i as f64);
        let two: Vec<f64> = band(1.7, 0.025, 29).chain(band(5.2, 0.05, 29)).collect();
        assert_eq!(breaks(two.clone(), false), vec![29]);
        assert_eq!(breaks(two, true), vec![29]);
        assert!(breaks(band(1.0, 0.1, 50).collect(), false).is_empty());
        let refined: Vec<f64> = band(1.0, 0.1, 10).chain(band(2.0, 0.01, 50)).chain(band(2.6, 0.1, 10)).collect();
        assert!(breaks(refined, false).is_empty());
        assert!(breaks(vec![1.0, 2.0, 3.0, 2.5, 2.0, 4.0], false).is_empty());
        assert!(breaks(vec![1.0, 1.1, 9.0, 9.1], false).is_empty());
    }
}
