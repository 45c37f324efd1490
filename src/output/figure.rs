//! Figures as finished data: what to draw, not how. Analyses build these; the plot
//! renderer draws them without knowing any physics.

/// Line pattern of a series.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Dash {
    Solid,
    Dashed,
    Dotted,
    DashDot,
}

/// Point markers of a series.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Marker {
    None,
    Circle,
    Cross,
    Square,
}

/// One drawn series.
#[derive(Debug, Clone)]
pub struct Series {
    pub label: String,
    pub x: Vec<f64>,
    pub y: Vec<f64>,
    /// Index into the shared palette.
    pub color: usize,
    pub dash: Dash,
    /// Draw a line through the points.
    pub line: bool,
    pub marker: Marker,
}

impl Series {
    /// A solid line.
    pub fn line(label: impl Into<String>, x: Vec<f64>, y: Vec<f64>, color: usize) -> Series {
        Series { label: label.into(), x, y, color, dash: Dash::Solid, line: true, marker: Marker::None }
    }

    /// The same series with another dash.
    pub fn dashed(mut self, dash: Dash) -> Series {
        self.dash = dash;
        self
    }

    /// Points only.
    pub fn points(label: impl Into<String>, x: Vec<f64>, y: Vec<f64>, color: usize, marker: Marker) -> Series {
        Series { label: label.into(), x, y, color, dash: Dash::Solid, line: false, marker }
    }
}

/// A vertical marker line with a label (e.g. a natural frequency).
#[derive(Debug, Clone)]
pub struct VLine {
    pub x: f64,
    pub label: String,
}

/// One panel of a figure.
#[derive(Debug, Clone)]
pub struct Panel {
    pub title: String,
    pub x_label: String,
    pub y_label: String,
    pub x_range: (f64, f64),
    pub y_log: bool,
    pub series: Vec<Series>,
    pub vlines: Vec<VLine>,
}

/// A figure: one or more panels stacked vertically.
#[derive(Debug, Clone)]
pub struct Figure {
    /// File stem (`ID.png`, `ID.svg`).
    pub id: String,
    pub title: String,
    /// One sentence under the figure in the report.
    pub caption: String,
    pub panels: Vec<Panel>,
}
