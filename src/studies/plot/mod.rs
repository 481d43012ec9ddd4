//! Dependency-free SVG charts for the studies' figures.
//!
//! A [`Chart`] is a plain description of one x-y plot: a list of [`Series`] (lines, markers or
//! both, optionally dashed, optionally with a shaded percentile band behind the line), linear
//! or base-10 logarithmic axes ([`Scale`]), optional fixed axis ranges and labelled horizontal
//! reference lines (code limits, say). [`Chart::to_svg`] renders it to a self-contained SVG
//! string; [`Figure::grid`] places several charts in one SVG as sub-figures; [`write_svg`]
//! writes the result to a file.
//!
//! The output is deterministic: the same chart always gives the same bytes (coordinates are
//! written with a fixed precision and nothing depends on hashing, time or the locale). Points
//! that cannot be drawn (NaN, infinities, and non-positive values on a logarithmic axis) are
//! skipped: a line is broken at them instead of failing.
//!
//! Axis ticks come from [`linear_ticks`] (1-2-5 steps) and [`log10_ticks`] (decades with minor
//! ticks at 2..9 times the decade); both are public so studies and tests can use them directly.
//! Colours follow the colour-blind-safe Okabe-Ito palette and cycle together with the marker
//! shapes, so series stay distinguishable in grey-scale print too.

mod svg;
#[cfg(test)]
mod tests;

use std::io;
use std::path::Path;

/// How values map onto an axis.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Scale {
    /// Evenly spaced values; ticks at 1-2-5 multiples of a power of ten.
    #[default]
    Linear,
    /// Base-10 logarithmic; only positive values are drawn, ticks at decades.
    Log10,
}

impl Scale {
    /// Tick marks and labels for an axis of this scale spanning `[lo, hi]`, with at most
    /// about `max_major` labelled ticks. See [`linear_ticks`] and [`log10_ticks`].
    pub fn ticks(self, lo: f64, hi: f64, max_major: usize) -> Ticks {
        match self {
            Scale::Linear => linear_ticks(lo, hi, max_major),
            Scale::Log10 => log10_ticks(lo, hi, max_major),
        }
    }

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
    /// One marker per point.
    Markers,
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
    /// Line, markers or both.
    pub style: Style,
    /// Draw the line dashed (markers are unaffected).
    pub dashed: bool,
    /// Optional shaded band `(x, low, high)` drawn behind the line in the series' colour,
    /// e.g. a 5-95 % percentile band around a median.
    pub band: Option<Vec<(f64, f64, f64)>>,
}

impl Series {
    /// A series with the given name, points and style (solid, no band).
    pub fn new(name: impl Into<String>, points: Vec<(f64, f64)>, style: Style) -> Self {
        Self {
            name: name.into(),
            points,
            style,
            dashed: false,
            band: None,
        }
    }

    /// A solid line.
    pub fn line(name: impl Into<String>, points: Vec<(f64, f64)>) -> Self {
        Self::new(name, points, Style::Line)
    }

    /// Markers only.
    pub fn markers(name: impl Into<String>, points: Vec<(f64, f64)>) -> Self {
        Self::new(name, points, Style::Markers)
    }

    /// A line with a marker at every point.
    pub fn line_markers(name: impl Into<String>, points: Vec<(f64, f64)>) -> Self {
        Self::new(name, points, Style::LineMarkers)
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

/// An x-y chart, rendered by [`Chart::to_svg`].
#[derive(Debug, Clone, PartialEq)]
pub struct Chart {
    /// Title above the plot; empty for none.
    pub title: String,
    /// Label under the x axis (include the unit, e.g. `"speed [km/h]"`); empty for none.
    pub x_label: String,
    /// Label left of the y axis; empty for none.
    pub y_label: String,
    /// Scale of the x axis.
    pub x_scale: Scale,
    /// Scale of the y axis.
    pub y_scale: Scale,
    /// The data, drawn in order (later series on top); colours follow the index.
    pub series: Vec<Series>,
    /// Width of the whole chart in pixels (title, labels and legend included).
    pub width_px: u32,
    /// Height of the whole chart in pixels.
    pub height_px: u32,
    /// Fixed x range; `None` fits the data with a small margin (as does a range the scale
    /// cannot show, such as a non-positive end on a log axis).
    pub x_range: Option<(f64, f64)>,
    /// Fixed y range; `None` fits the data (and the reference lines) with a small margin.
    pub y_range: Option<(f64, f64)>,
    /// Horizontal reference lines `(y, label)`, e.g. code limits.
    pub hlines: Vec<(f64, String)>,
}

impl Default for Chart {
    fn default() -> Self {
        Self {
            title: String::new(),
            x_label: String::new(),
            y_label: String::new(),
            x_scale: Scale::Linear,
            y_scale: Scale::Linear,
            series: Vec::new(),
            width_px: 720,
            height_px: 450,
            x_range: None,
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
        Self {
            title: title.into(),
            x_label: x_label.into(),
            y_label: y_label.into(),
            ..Self::default()
        }
    }

    /// Sets the scales of both axes.
    pub fn with_scales(mut self, x_scale: Scale, y_scale: Scale) -> Self {
        self.x_scale = x_scale;
        self.y_scale = y_scale;
        self
    }

    /// Sets the size of the whole chart in pixels.
    pub fn with_size(mut self, width_px: u32, height_px: u32) -> Self {
        self.width_px = width_px;
        self.height_px = height_px;
        self
    }

    /// Fixes the x range.
    pub fn with_x_range(mut self, lo: f64, hi: f64) -> Self {
        self.x_range = Some((lo, hi));
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

    /// Renders the chart and writes it to `path` (see [`write_svg`]).
    pub fn write_svg(&self, path: impl AsRef<Path>) -> io::Result<()> {
        write_svg(path, &self.to_svg())
    }
}

/// Several charts in one SVG; see [`Figure::grid`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Figure;

/// Writes an SVG string to `path`, creating missing parent directories and ending the file
/// with a newline.
pub fn write_svg(path: impl AsRef<Path>, svg: &str) -> io::Result<()> {
    let path = path.as_ref();
    if let Some(parent) = path.parent() {
        if !parent.as_os_str().is_empty() {
            std::fs::create_dir_all(parent)?;
        }
    }
    let mut text = String::with_capacity(svg.len() + 1);
    text.push_str(svg);
    if !text.ends_with('\n') {
        text.push('\n');
    }
    std::fs::write(path, text)
}

/// Tick positions and labels for one axis.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Ticks {
    /// Labelled ticks (with grid lines), ascending.
    pub major: Vec<f64>,
    /// Unlabelled minor ticks, ascending (log axes only).
    pub minor: Vec<f64>,
    /// One label per major tick.
    pub labels: Vec<String>,
}

/// Relative slack when deciding whether a tick lies in a range, so that a tick exactly at an
/// end is not lost to rounding.
const TICK_SLACK: f64 = 1e-9;

/// `m * 10^k`, computed so that decimal values such as 0.3 come out as the nearest double.
fn scaled(m: f64, k: i32) -> f64 {
    if k >= 0 {
        m * 10f64.powi(k)
    } else {
        m / 10f64.powi(-k)
    }
}

/// Ticks at multiples of a 1-2-5 step inside `[lo, hi]`: the finest such step that gives at
/// most `max_major` ticks (at least 2 are allowed for). All ticks lie inside the range.
/// Labels share one number of decimals (`0.0, 0.5, 1.0`) or switch to compact scientific
/// notation (`2.5e-4`) for very small or very large values.
pub fn linear_ticks(lo: f64, hi: f64, max_major: usize) -> Ticks {
    if !(lo.is_finite() && hi.is_finite()) {
        return Ticks::default();
    }
    let (lo, hi) = if lo <= hi { (lo, hi) } else { (hi, lo) };
    let span = hi - lo;
    if span <= 0.0 || span < f64::MIN_POSITIVE {
        let v = if lo == 0.0 { 0.0 } else { lo };
        return Ticks {
            major: vec![v],
            minor: Vec::new(),
            labels: vec![format_compact(v)],
        };
    }
    let max_major = max_major.max(2);
    let slack = span * TICK_SLACK;
    let k0 = (span / max_major as f64).log10().floor() as i32 - 1;
    for k in k0..k0 + 4 {
        for m in [1.0, 2.0, 5.0] {
            let step = scaled(m, k);
            let first = ((lo - slack) / step).ceil();
            let last = ((hi + slack) / step).floor();
            if !(first.is_finite() && last.is_finite()) || last < first {
                continue;
            }
            let count = (last - first) as usize + 1;
            if count > max_major {
                continue;
            }
            let major: Vec<f64> = (0..count)
                .map(|i| {
                    let v = scaled((first + i as f64) * m, k);
                    if v == 0.0 {
                        0.0
                    } else {
                        v
                    }
                })
                .collect();
            let labels = linear_labels(&major, k);
            return Ticks {
                major,
                minor: Vec::new(),
                labels,
            };
        }
    }
    // Unreachable for finite ranges (a step of 10^(k0+3) leaves at most two ticks), but
    // degrade gracefully rather than panic.
    Ticks {
        major: vec![lo, hi],
        minor: Vec::new(),
        labels: vec![format_compact(lo), format_compact(hi)],
    }
}

/// Labels for linear ticks whose step is `m * 10^k`.
fn linear_labels(major: &[f64], k: i32) -> Vec<String> {
    let max_abs = major.iter().fold(0.0f64, |a, v| a.max(v.abs()));
    let decimals = (-k).max(0) as usize;
    let scientific = decimals > 4 || max_abs >= 1e6;
    major
        .iter()
        .map(|&v| {
            if scientific {
                format_scientific(v, k)
            } else {
                clean_zero(format!("{v:.decimals$}"))
            }
        })
        .collect()
}

/// `-0.0` printed as `0.0`, `-0` as `0`.
fn clean_zero(s: String) -> String {
    if s.starts_with('-') && s[1..].chars().all(|c| c == '0' || c == '.') {
        s[1..].to_string()
    } else {
        s
    }
}

/// `v` as `m e E` with as many mantissa decimals as a step of `10^k` needs, trailing zeros
/// dropped: `1e-4`, `2.5e-4`, `-3e6`.
fn format_scientific(v: f64, k: i32) -> String {
    if v == 0.0 || !v.is_finite() {
        return if v.is_finite() {
            "0".to_string()
        } else {
            format!("{v}")
        };
    }
    let mut e = v.abs().log10().floor() as i32;
    let decimals = (e - k).max(0) as usize;
    let mut mantissa = v / 10f64.powi(e);
    let mut text = format!("{mantissa:.decimals$}");
    if text.trim_start_matches('-').starts_with("10") {
        e += 1;
        mantissa = v / 10f64.powi(e);
        let decimals = decimals.saturating_sub(1);
        text = format!("{mantissa:.decimals$}");
    }
    if text.contains('.') {
        text = text.trim_end_matches('0').trim_end_matches('.').to_string();
    }
    format!("{text}e{e}")
}

/// A single value in the shortest sensible form: plain for magnitudes from 0.001 to below
/// 100000 (`0.002`, `20`, `12.5`), scientific otherwise (`1e-4`, `3e5`).
pub fn format_compact(v: f64) -> String {
    if v == 0.0 {
        return "0".to_string();
    }
    if !v.is_finite() {
        return format!("{v}");
    }
    let e = v.abs().log10().floor() as i32;
    // Up to four significant digits, trailing zeros dropped.
    let k = e - 3;
    if (-3..=4).contains(&e) {
        let decimals = (-k).max(0) as usize;
        let text = format!("{v:.decimals$}");
        let text = if text.contains('.') {
            text.trim_end_matches('0').trim_end_matches('.').to_string()
        } else {
            text
        };
        clean_zero(text)
    } else {
        format_scientific(v, k)
    }
}

/// Ticks for a base-10 logarithmic axis over `[lo, hi]` (`0 < lo < hi`).
///
/// Over three or more decades the major ticks are the decades (every second, third, ... one
/// when there are more than `max_major`), with minor ticks at 2..9 times each decade (or at
/// the skipped decades). Over a narrower range the labelled ticks are the 1-2-5 (or 1..9)
/// multiples of the decades, and inside a single decade the ticks fall back to linear ones.
/// Labels are compact: `1e-5`, `0.001`, `100`, `1e5`.
pub fn log10_ticks(lo: f64, hi: f64, max_major: usize) -> Ticks {
    if !(lo.is_finite() && hi.is_finite()) {
        return Ticks::default();
    }
    let (lo, hi) = if lo <= hi { (lo, hi) } else { (hi, lo) };
    if lo <= 0.0 {
        return Ticks::default();
    }
    if hi <= lo {
        return Ticks {
            major: vec![lo],
            minor: Vec::new(),
            labels: vec![format_compact(lo)],
        };
    }
    let max_major = max_major.max(2);
    let (a, b) = (lo.log10(), hi.log10());
    let slack = (b - a) * TICK_SLACK;
    let inside = |v: f64| {
        let l = v.log10();
        l >= a - slack && l <= b + slack
    };
    let k_lo = a.floor() as i32;
    let k_hi = b.ceil() as i32;
    let decades: Vec<i32> = (k_lo..=k_hi).filter(|&k| inside(scaled(1.0, k))).collect();
    let multiples = |ms: &[u32]| -> Vec<f64> {
        let mut out = Vec::new();
        for k in k_lo..=k_hi {
            for &m in ms {
                let v = scaled(f64::from(m), k);
                if inside(v) {
                    out.push(v);
                }
            }
        }
        out
    };
    let labelled = |major: Vec<f64>, minor: Vec<f64>| -> Ticks {
        let labels = major.iter().map(|&v| format_compact(v)).collect();
        Ticks {
            major,
            minor,
            labels,
        }
    };

    if decades.len() >= 3 {
        let stride = decades.len().div_ceil(max_major).max(1) as i32;
        let mut major = Vec::new();
        let mut minor = Vec::new();
        for &k in &decades {
            if k.rem_euclid(stride) == 0 {
                major.push(scaled(1.0, k));
            } else {
                minor.push(scaled(1.0, k));
            }
        }
        if major.len() < 2 {
            // A stride that hits at most one decade (possible for few decades): label all.
            major = decades.iter().map(|&k| scaled(1.0, k)).collect();
            minor.clear();
        }
        if stride == 1 {
            minor = multiples(&[2, 3, 4, 5, 6, 7, 8, 9]);
        }
        return labelled(major, minor);
    }
    let one_two_five = multiples(&[1, 2, 5]);
    if one_two_five.len() >= 3 && one_two_five.len() <= max_major {
        return labelled(one_two_five, multiples(&[3, 4, 6, 7, 8, 9]));
    }
    let all = multiples(&[1, 2, 3, 4, 5, 6, 7, 8, 9]);
    if all.len() >= 3 && all.len() <= max_major {
        return labelled(all, Vec::new());
    }
    if decades.len() >= 2 {
        let major = decades.iter().map(|&k| scaled(1.0, k)).collect();
        return labelled(major, multiples(&[2, 3, 4, 5, 6, 7, 8, 9]));
    }
    if one_two_five.len() >= 2 && one_two_five.len() <= max_major {
        return labelled(one_two_five, multiples(&[3, 4, 6, 7, 8, 9]));
    }
    // Less than a decade with too few round multiples: linear ticks inside the range.
    let mut ticks = linear_ticks(lo, hi, max_major);
    let minor = multiples(&[1, 2, 3, 4, 5, 6, 7, 8, 9])
        .into_iter()
        .filter(|v| !ticks.major.contains(v))
        .collect();
    ticks.minor = minor;
    ticks
}
