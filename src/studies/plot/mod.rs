//! The studies' figures: a plain description of an x-y chart ([`Chart`], [`Series`],
//! [`Scale`]), rendered to SVG by the `plotters` crate (`render.rs`).
//!
//! The studies say what to show (titles, axis labels with units, legends, log axes,
//! percentile bands, labelled reference lines); the house style (Okabe-Ito colours
//! cycling with marker shapes, so series stay distinguishable in grey-scale print, grid,
//! legend placement) is applied in one place. Text is written as SVG `<text>` in a generic
//! sans-serif family: nothing reads font files, so rendering needs no fonts on the machine.
//! The same chart always gives the same bytes.
//!
//! Points that cannot be drawn (NaN, infinities, non-positive values on a log axis, values
//! outside a fixed range) are skipped: a line is broken at them instead of failing.

mod render;
#[cfg(test)]
mod tests;

use crate::error::{Error, Result};

/// How values map onto an axis.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Scale {
    /// Evenly spaced values.
    #[default]
    Linear,
    /// Base-10 logarithmic; only positive values are drawn.
    Log10,
}

impl Scale {
    /// Whether `v` can be placed on an axis of this scale.
    pub fn accepts(self, v: f64) -> bool {
        match self {
            Scale::Linear => v.is_finite(),
            Scale::Log10 => v.is_finite() && v > 0.0,
        }
    }
}

/// How a series is drawn.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Style {
    /// A polyline through the points (broken at points that cannot be drawn).
    #[default]
    Line,
    /// A polyline with a marker at every point.
    LineMarkers,
}

/// One data series of a [`Chart`].
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Series {
    /// Legend entry; an empty name keeps the series out of the legend.
    pub name: String,
    /// The `(x, y)` points, drawn in the given order.
    pub points: Vec<(f64, f64)>,
    pub style: Style,
    /// Draw the line dashed (markers are unaffected).
    pub dashed: bool,
    /// Optional shaded band `(x, low, high)` drawn behind the line in the series' colour,
    /// e.g. a 5-95 % percentile band around a mean.
    pub band: Option<Vec<(f64, f64, f64)>>,
}

impl Series {
    /// A solid line.
    pub fn line(name: impl Into<String>, points: Vec<(f64, f64)>) -> Self {
        Series {
            name: name.into(),
            points,
            ..Series::default()
        }
    }

    /// A line with a marker at every point.
    pub fn line_markers(name: impl Into<String>, points: Vec<(f64, f64)>) -> Self {
        Series {
            style: Style::LineMarkers,
            ..Series::line(name, points)
        }
    }

    /// Sets whether the line is dashed.
    pub fn with_dashed(mut self, dashed: bool) -> Self {
        self.dashed = dashed;
        self
    }

    /// Adds a shaded band `(x, low, high)` behind the line.
    pub fn with_band(mut self, band: Vec<(f64, f64, f64)>) -> Self {
        self.band = Some(band);
        self
    }
}

/// An x-y chart, rendered by [`Chart::to_svg`] or, with others, by [`Figure::grid`].
#[derive(Debug, Clone, PartialEq)]
pub struct Chart {
    /// Title above the plot; empty for none.
    pub title: String,
    /// Label under the x axis, with the unit (`"speed (m/s)"`); empty for none.
    pub x_label: String,
    /// Label left of the y axis; empty for none.
    pub y_label: String,
    pub x_scale: Scale,
    pub y_scale: Scale,
    /// The data, drawn in order (later series on top); colours follow the index.
    pub series: Vec<Series>,
    /// Size of the chart alone in pixels (a grid cell takes the largest of its charts).
    pub width_px: u32,
    pub height_px: u32,
    /// Fixed y range; `None` fits the data and the reference lines with a small margin.
    pub y_range: Option<(f64, f64)>,
    /// Horizontal reference lines `(y, label)`, e.g. code limits.
    pub hlines: Vec<(f64, String)>,
}

impl Default for Chart {
    fn default() -> Self {
        Chart {
            title: String::new(),
            x_label: String::new(),
            y_label: String::new(),
            x_scale: Scale::Linear,
            y_scale: Scale::Linear,
            series: Vec::new(),
            width_px: 720,
            height_px: 450,
            y_range: None,
            hlines: Vec::new(),
        }
    }
}

impl Chart {
    /// An empty 720 x 450 px chart with linear axes.
    pub fn new(
        title: impl Into<String>,
        x_label: impl Into<String>,
        y_label: impl Into<String>,
    ) -> Self {
        Chart {
            title: title.into(),
            x_label: x_label.into(),
            y_label: y_label.into(),
            ..Chart::default()
        }
    }

    /// Sets the scales of both axes.
    pub fn with_scales(mut self, x_scale: Scale, y_scale: Scale) -> Self {
        self.x_scale = x_scale;
        self.y_scale = y_scale;
        self
    }

    /// Sets the size in pixels.
    pub fn with_size(mut self, width_px: u32, height_px: u32) -> Self {
        self.width_px = width_px;
        self.height_px = height_px;
        self
    }

    /// Fixes the y range.
    pub fn with_y_range(mut self, lo: f64, hi: f64) -> Self {
        self.y_range = Some((lo, hi));
        self
    }

    /// Appends a series.
    pub fn with_series(mut self, series: Series) -> Self {
        self.series.push(series);
        self
    }

    /// Appends a labelled horizontal reference line.
    pub fn with_hline(mut self, y: f64, label: impl Into<String>) -> Self {
        self.hlines.push((y, label.into()));
        self
    }

    /// The chart as a standalone SVG document.
    pub fn to_svg(&self) -> Result<String> {
        render::grid("", 1, 1, std::slice::from_ref(self)).map_err(|e| failed(&self.title, e))
    }
}

/// Several charts in one SVG document.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Figure;

impl Figure {
    /// Places `charts` in a grid of `rows` x `cols` equal cells, row by row, each as large
    /// as the largest chart. More charts than cells add rows.
    pub fn grid(rows: usize, cols: usize, charts: &[Chart]) -> Result<String> {
        Self::grid_titled("", rows, cols, charts)
    }

    /// Like [`Figure::grid`], with an overall title above the charts (empty for none).
    pub fn grid_titled(title: &str, rows: usize, cols: usize, charts: &[Chart]) -> Result<String> {
        let name = charts.first().map_or(title, |c| c.title.as_str());
        render::grid(title, rows, cols, charts).map_err(|e| failed(name, e))
    }
}

/// A rendering error, naming the figure by its (first) title.
fn failed(title: &str, reason: impl std::fmt::Display) -> Error {
    Error::Output {
        path: format!("figure \"{title}\""),
        reason: reason.to_string(),
    }
}
