//! Rendering [`Chart`]s with `plotters` and its SVG backend.
//!
//! plotters draws the frame, the ticks and their labels, the grid, the lines and the
//! legend; this file adds the house style and what plotters leaves to the caller: the axis
//! ranges (data extent with a margin), skipping undrawable points, percentile bands,
//! labelled reference lines, and the legend corner that covers the least data.

use std::ops::Range;

use plotters::coord::ranged1d::{BoldPoints, KeyPointHint, NoDefaultFormatting, ValueFormatter};
use plotters::coord::types::RangedCoordf64;
use plotters::coord::Shift;
use plotters::element::{Drawable, PointCollection};
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};
use plotters_backend::{BackendCoord, DrawingErrorKind};

use super::{Chart, Scale, Series, Style};

type Area<'a> = DrawingArea<SVGBackend<'a>, Shift>;
type Failure = DrawingAreaErrorKind<std::io::Error>;

const FONT: FontFamily<'static> = FontFamily::SansSerif;
// plotters' SVG backend writes font-size = size / 1.24: these are the sizes it is given.
const TITLE_SIZE: f64 = 20.0;
const FIGURE_TITLE_SIZE: f64 = 23.0;
const AXIS_LABEL_SIZE: f64 = 17.0;
const TICK_SIZE: f64 = 15.0;
const LEGEND_SIZE: f64 = 15.0;
const HLINE_SIZE: f64 = 14.0;

const TEXT: RGBColor = RGBColor(0x22, 0x22, 0x22);
const GRID: RGBColor = RGBColor(0xe0, 0xe0, 0xe0);
const MINOR_GRID: RGBColor = RGBColor(0xf3, 0xf3, 0xf3);
const REFERENCE: RGBColor = RGBColor(0x55, 0x55, 0x55);

/// Okabe-Ito colours, most distinct on white first (the palette's yellow is too pale for
/// thin lines and is left out).
const PALETTE: [RGBColor; 7] = [
    RGBColor(0x00, 0x72, 0xB2),
    RGBColor(0xD5, 0x5E, 0x00),
    RGBColor(0x00, 0x9E, 0x73),
    RGBColor(0xCC, 0x79, 0xA7),
    RGBColor(0xE6, 0x9F, 0x00),
    RGBColor(0x56, 0xB4, 0xE9),
    RGBColor(0x00, 0x00, 0x00),
];

/// Marker shapes, cycling with the colours: four shapes against seven colours repeat only
/// after 28 series.
const MARKERS: usize = 4;

const LINE_WIDTH: u32 = 2;
const DASH_PX: u32 = 7;
const GAP_PX: u32 = 4;
const BAND_ALPHA: f64 = 0.2;
/// Pixels around the plot and reserved for the tick labels and axis labels.
const MARGIN_PX: u32 = 12;
const X_LABEL_AREA_PX: u32 = 48;
const Y_LABEL_AREA_PX: u32 = 78;
/// Legend rows and the width of a character, for choosing its corner (plotters does not
/// measure text without font files, and neither do we: these err on the large side).
const LEGEND_ROW_PX: f64 = 20.0;
const LEGEND_CHAR_PX: f64 = 7.5;
const LEGEND_SAMPLE_PX: f64 = 45.0;

fn colour(index: usize) -> RGBColor {
    PALETTE[index % PALETTE.len()]
}

/// One axis: a linear or base-10 logarithmic map of `[lo, hi]`, with plotters' key points
/// (1-2-5 steps; decades on a log axis, linear steps inside a range narrower than that).
#[derive(Debug, Clone, Copy)]
struct Axis {
    scale: Scale,
    lo: f64,
    hi: f64,
}

impl Axis {
    /// Position of `v` in the range: 0 at `lo`, 1 at `hi`.
    fn fraction(&self, v: f64) -> f64 {
        match self.scale {
            Scale::Linear => (v - self.lo) / (self.hi - self.lo),
            Scale::Log10 => (v / self.lo).ln() / (self.hi / self.lo).ln(),
        }
    }

    fn draws(&self, v: f64) -> bool {
        // A relative slack keeps a point exactly at an end of a fixed range.
        self.scale.accepts(v) && (-1e-9..=1.0 + 1e-9).contains(&self.fraction(v))
    }
}

impl Ranged for Axis {
    type FormatOption = NoDefaultFormatting;
    type ValueType = f64;

    fn map(&self, value: &f64, limit: (i32, i32)) -> i32 {
        // Undrawable points are filtered before drawing; clamp whatever else arrives.
        let t = self.fraction(*value);
        let t = if t.is_finite() {
            t.clamp(-1.0, 2.0)
        } else {
            0.0
        };
        limit.0 + (t * f64::from(limit.1 - limit.0)).round() as i32
    }

    fn key_points<Hint: KeyPointHint>(&self, hint: Hint) -> Vec<f64> {
        let linear = || -> RangedCoordf64 { (self.lo..self.hi).into() };
        match self.scale {
            Scale::Linear => linear().key_points(hint),
            Scale::Log10 => {
                let (n, light) = (hint.max_num_points(), hint.weight().allow_light_points());
                let points = log_key_points(self.lo, self.hi, n, light);
                if points.len() >= 2 {
                    points
                } else if light {
                    linear().key_points(n)
                } else {
                    linear().key_points(BoldPoints(n))
                }
            }
        }
    }

    fn range(&self) -> Range<f64> {
        self.lo..self.hi
    }
}

/// `m 10^k`, divided rather than multiplied for negative k so that 1e-4 is the nearest
/// double.
fn scaled(m: f64, k: i32) -> f64 {
    if k >= 0 {
        m * 10f64.powi(k)
    } else {
        m / 10f64.powi(-k)
    }
}

/// Ticks of a log axis over `[lo, hi]`: the decades when there are three or more (every
/// second, third, ... one past `max`), else the 1-2-5 multiples, else 1..9 times the
/// decades; the minor grid (`light`) gets 1..9 times the decades when they fit. Empty when
/// nothing fits (less than a decade with few round multiples): the caller falls back to
/// linear ticks.
fn log_key_points(lo: f64, hi: f64, max: usize, light: bool) -> Vec<f64> {
    let (k0, k1) = (lo.log10().floor() as i32, hi.log10().ceil() as i32);
    let multiples = |ms: &[f64]| -> Vec<f64> {
        (k0..=k1)
            .flat_map(|k| ms.iter().map(move |&m| scaled(m, k)))
            .filter(|v| (lo..=hi).contains(v))
            .collect()
    };
    let all = multiples(&[1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 9.0]);
    if light && all.len() <= max.max(2) {
        return all;
    }
    let decades = multiples(&[1.0]);
    if decades.len() >= 3 {
        let stride = decades.len().div_ceil(max.max(2));
        return decades.into_iter().step_by(stride).collect();
    }
    [multiples(&[1.0, 2.0, 5.0]), all]
        .into_iter()
        .find(|p| (3..=max.max(3)).contains(&p.len()))
        .unwrap_or_default()
}

impl ValueFormatter<f64> for Axis {
    fn format_ext(&self, value: &f64) -> String {
        tick_label(*value)
    }
}

/// A tick label: plain with up to four decimals from 0.001 to below 100 000 (`0.002`,
/// `12.5`, `20`), scientific outside (`1e-5`, `2.5e-6`, `3e5`).
pub(super) fn tick_label(v: f64) -> String {
    let trim = |s: String| {
        if s.contains('.') {
            s.trim_end_matches('0').trim_end_matches('.').to_string()
        } else {
            s
        }
    };
    // Rounding noise of a tick (0.30000000000000004) is far below the last digit shown.
    if v.abs() < 1e-12 * (1.0 + v.abs()) {
        return "0".into();
    }
    if (1e-3..1e5).contains(&v.abs()) {
        return trim(format!("{v:.4}"));
    }
    let text = format!("{v:.3e}");
    match text.split_once('e') {
        Some((mantissa, exponent)) => format!("{}e{exponent}", trim(mantissa.to_string())),
        None => text,
    }
}

/// The explicit range when the scale can show it, otherwise the data's extent with a 4 %
/// margin (in log space on a log axis).
fn resolve(explicit: Option<(f64, f64)>, scale: Scale, data: impl Iterator<Item = f64>) -> Axis {
    let axis = |lo, hi| Axis { scale, lo, hi };
    if let Some((a, b)) = explicit {
        let (lo, hi) = (a.min(b), a.max(b));
        if scale.accepts(lo) && scale.accepts(hi) && hi > lo {
            return axis(lo, hi);
        }
    }
    let (min, max) = data
        .filter(|&v| scale.accepts(v))
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
            (a.min(v), b.max(v))
        });
    const MARGIN: f64 = 0.04;
    match scale {
        _ if min > max => match scale {
            Scale::Linear => axis(0.0, 1.0),
            Scale::Log10 => axis(1.0, 10.0),
        },
        Scale::Linear if max > min => {
            let d = MARGIN * (max - min);
            axis(min - d, max + d)
        }
        Scale::Linear => {
            let d = if min == 0.0 { 1.0 } else { 0.1 * min.abs() };
            axis(min - d, max + d)
        }
        Scale::Log10 if max > min => {
            let d = (max / min).powf(MARGIN);
            axis(min / d, max * d)
        }
        Scale::Log10 => axis(min / 2.0, max * 2.0),
    }
}

fn axes(chart: &Chart) -> (Axis, Axis) {
    let x = resolve(
        None,
        chart.x_scale,
        chart.series.iter().flat_map(|s| {
            let band = s.band.iter().flatten().map(|b| b.0);
            s.points.iter().map(|p| p.0).chain(band)
        }),
    );
    let y = resolve(
        chart.y_range,
        chart.y_scale,
        chart
            .series
            .iter()
            .flat_map(|s| {
                let band = s.band.iter().flatten().flat_map(|b| [b.1, b.2]);
                s.points.iter().map(|p| p.1).chain(band)
            })
            .chain(chart.hlines.iter().map(|h| h.0)),
    );
    (x, y)
}

/// Consecutive drawable points of `points`, broken at undrawable ones.
fn runs<T: Copy>(points: &[T], drawable: impl Fn(&T) -> bool) -> Vec<Vec<T>> {
    let mut out: Vec<Vec<T>> = vec![Vec::new()];
    for p in points {
        match (drawable(p), out.last_mut()) {
            (true, Some(run)) => run.push(*p),
            (false, Some(run)) if !run.is_empty() => out.push(Vec::new()),
            _ => {}
        }
    }
    out.retain(|r| !r.is_empty());
    out
}

/// A data marker or a legend sample, drawn with the backend's primitives at one position:
/// an element of its own so that markers of every shape go through one `draw_series`.
#[derive(Debug, Clone, Copy)]
struct Mark<C> {
    at: C,
    /// Series index: colour and marker shape.
    index: usize,
    /// A 20 px line sample starting at `at`, dashed or not (legend entries).
    line: Option<bool>,
    marker: bool,
}

impl<'a, C: 'a> PointCollection<'a, C> for &'a Mark<C> {
    type Point = &'a C;
    type IntoIter = std::iter::Once<&'a C>;
    fn point_iter(self) -> Self::IntoIter {
        std::iter::once(&self.at)
    }
}

impl<C, DB: DrawingBackend> Drawable<DB> for Mark<C> {
    fn draw<I: Iterator<Item = BackendCoord>>(
        &self,
        mut points: I,
        backend: &mut DB,
        _parent_dim: (u32, u32),
    ) -> Result<(), DrawingErrorKind<DB::ErrorType>> {
        let Some((x, y)) = points.next() else {
            return Ok(());
        };
        let stroke = colour(self.index).stroke_width(LINE_WIDTH);
        let (cx, cy) = match self.line {
            Some(dashed) => {
                // A dashed sample is two dashes; a solid one the same segments joined.
                let gap = if dashed { 2 } else { 0 };
                backend.draw_line((x, y), (x + 10 - gap, y), &stroke)?;
                backend.draw_line((x + 10 + gap, y), (x + 20, y), &stroke)?;
                (x + 10, y)
            }
            None => (x, y),
        };
        if !self.marker {
            return Ok(());
        }
        let fill = colour(self.index).filled();
        match self.index % MARKERS {
            0 => backend.draw_circle((cx, cy), 4, &fill, true),
            1 => backend.draw_rect((cx - 3, cy - 3), (cx + 4, cy + 4), &fill, true),
            2 => backend.fill_polygon([(cx, cy - 5), (cx + 5, cy + 4), (cx - 5, cy + 4)], &fill),
            _ => {
                backend.draw_line((cx - 4, cy - 4), (cx + 4, cy + 4), &stroke)?;
                backend.draw_line((cx - 4, cy + 4), (cx + 4, cy - 4), &stroke)
            }
        }
    }
}

/// The inside corner whose legend box would cover the fewest data points.
fn legend_corner(
    chart: &Chart,
    x: &Axis,
    y: &Axis,
    plot_w: f64,
    plot_h: f64,
) -> SeriesLabelPosition {
    let named: Vec<&Series> = chart.series.iter().filter(|s| !s.name.is_empty()).collect();
    let chars = named
        .iter()
        .map(|s| s.name.chars().count())
        .max()
        .unwrap_or(0);
    let w = ((LEGEND_SAMPLE_PX + LEGEND_CHAR_PX * chars as f64) / plot_w).min(1.0);
    let h = ((LEGEND_ROW_PX * named.len() as f64 + 10.0) / plot_h).min(1.0);
    let mut points: Vec<(f64, f64)> = chart
        .series
        .iter()
        .flat_map(|s| s.points.iter())
        .filter(|p| x.draws(p.0) && y.draws(p.1))
        .map(|p| (x.fraction(p.0), y.fraction(p.1)))
        .collect();
    // A reference line's label, at the right end, counts as much as a dozen points.
    for (value, _) in chart.hlines.iter().filter(|h| y.draws(h.0)) {
        let f = y.fraction(*value);
        points.extend((0..12).map(|i| (1.0 - 0.02 * f64::from(i), f)));
    }
    let covered = |left: bool, top: bool| {
        points
            .iter()
            .filter(|(px, py)| {
                let in_x = if left { *px <= w } else { *px >= 1.0 - w };
                let in_y = if top { *py >= 1.0 - h } else { *py <= h };
                in_x && in_y
            })
            .count()
    };
    [
        (SeriesLabelPosition::UpperRight, false, true),
        (SeriesLabelPosition::UpperLeft, true, true),
        (SeriesLabelPosition::LowerRight, false, false),
        (SeriesLabelPosition::LowerLeft, true, false),
    ]
    .into_iter()
    .min_by_key(|(_, left, top)| covered(*left, *top))
    .map_or(SeriesLabelPosition::UpperRight, |c| c.0)
}

/// Draws one chart into `area`.
fn draw_chart(chart: &Chart, area: &Area<'_>) -> Result<(), Failure> {
    let (x, y) = axes(chart);
    let mut builder = ChartBuilder::on(area);
    builder
        .margin(MARGIN_PX)
        .x_label_area_size(X_LABEL_AREA_PX)
        .y_label_area_size(Y_LABEL_AREA_PX);
    if !chart.title.is_empty() {
        builder.caption(&chart.title, (FONT, TITLE_SIZE).into_font().color(&TEXT));
    }
    let mut ctx = builder.build_cartesian_2d(x, y)?;
    ctx.configure_mesh()
        .x_desc(chart.x_label.as_str())
        .y_desc(chart.y_label.as_str())
        .x_labels(8)
        .y_labels(8)
        .bold_line_style(GRID.stroke_width(1))
        .light_line_style(MINOR_GRID.stroke_width(1))
        .axis_style(REFERENCE.stroke_width(1))
        .label_style((FONT, TICK_SIZE).into_font().color(&TEXT))
        .axis_desc_style((FONT, AXIS_LABEL_SIZE).into_font().color(&TEXT))
        .draw()?;

    for (i, s) in chart.series.iter().enumerate() {
        for run in runs(s.band.as_deref().unwrap_or(&[]), |b| {
            x.draws(b.0) && y.draws(b.1) && y.draws(b.2)
        }) {
            let outline: Vec<(f64, f64)> = run
                .iter()
                .map(|b| (b.0, b.2))
                .chain(run.iter().rev().map(|b| (b.0, b.1)))
                .collect();
            ctx.draw_series(std::iter::once(Polygon::new(
                outline,
                colour(i).mix(BAND_ALPHA).filled(),
            )))?;
        }
    }

    let (plot_w, plot_h) = ctx.plotting_area().dim_in_pixel();
    let mut last_label_px: Option<i32> = None;
    let mut hlines: Vec<&(f64, String)> = chart.hlines.iter().filter(|h| y.draws(h.0)).collect();
    hlines.sort_by(|a, b| a.0.total_cmp(&b.0));
    for (value, label) in hlines {
        ctx.draw_series(DashedLineSeries::new(
            [(x.lo, *value), (x.hi, *value)],
            DASH_PX,
            GAP_PX,
            REFERENCE.stroke_width(1),
        ))?;
        // Labels sit just above their line at the right end; one that would touch the
        // label below it moves to the left end.
        let px = y.map(value, (i32::try_from(plot_h).unwrap_or(i32::MAX), 0));
        let crowded = last_label_px.is_some_and(|p| (p - px).abs() < 14);
        // Near the top of the plot a label above its line would leave the plot: below it.
        let (v_pos, dy) = if y.fraction(*value) > 0.92 {
            (VPos::Top, 3)
        } else {
            (VPos::Bottom, -2)
        };
        let (at_x, anchor, dx) = if crowded {
            (x.lo, Pos::new(HPos::Left, v_pos), 4)
        } else {
            (x.hi, Pos::new(HPos::Right, v_pos), -4)
        };
        if !crowded {
            last_label_px = Some(px);
        }
        let style = (FONT, HLINE_SIZE).into_font().color(&REFERENCE).pos(anchor);
        ctx.draw_series(std::iter::once(
            EmptyElement::at((at_x, *value)) + Text::new(label.clone(), (dx, dy), style),
        ))?;
    }

    for (i, s) in chart.series.iter().enumerate() {
        let style = colour(i).stroke_width(LINE_WIDTH);
        for run in runs(&s.points, |p| x.draws(p.0) && y.draws(p.1)) {
            if s.dashed {
                ctx.draw_series(DashedLineSeries::new(run.clone(), DASH_PX, GAP_PX, style))?;
            } else {
                ctx.draw_series(LineSeries::new(run.clone(), style))?;
            }
            // A lone point has no line to show it: it gets a marker whatever the style.
            if s.style == Style::LineMarkers || run.len() == 1 {
                ctx.draw_series(run.iter().map(|&at| Mark {
                    at,
                    index: i,
                    line: None,
                    marker: true,
                }))?;
            }
        }
        if !s.name.is_empty() {
            let (dashed, markers) = (s.dashed, s.style == Style::LineMarkers);
            ctx.draw_series(std::iter::empty::<Circle<(f64, f64), i32>>())?
                .label(s.name.as_str())
                .legend(move |at| Mark {
                    at,
                    index: i,
                    line: Some(dashed),
                    marker: markers,
                });
        }
    }
    if chart.series.iter().any(|s| !s.name.is_empty()) {
        let corner = legend_corner(chart, &x, &y, f64::from(plot_w), f64::from(plot_h));
        ctx.configure_series_labels()
            .position(corner)
            .margin(8)
            .legend_area_size(26)
            .background_style(WHITE.mix(0.85))
            .border_style(GRID)
            .label_font((FONT, LEGEND_SIZE).into_font().color(&TEXT))
            .draw()?;
    }
    if chart
        .series
        .iter()
        .all(|s| runs(&s.points, |p| x.draws(p.0) && y.draws(p.1)).is_empty())
    {
        let centre = ((x.lo + x.hi) / 2.0, (y.lo + y.hi) / 2.0);
        let style = (FONT, AXIS_LABEL_SIZE)
            .into_font()
            .color(&REFERENCE)
            .pos(Pos::new(HPos::Center, VPos::Center));
        ctx.draw_series(std::iter::once(Text::new("no data", centre, style)))?;
    }
    Ok(())
}

/// Renders `charts` in a `rows` x `cols` grid of equal cells under an optional title.
pub(super) fn grid(
    title: &str,
    rows: usize,
    cols: usize,
    charts: &[Chart],
) -> Result<String, Failure> {
    let cols = cols.max(1);
    let rows = rows.max(charts.len().div_ceil(cols)).max(1);
    let cell_w = charts
        .iter()
        .map(|c| c.width_px)
        .max()
        .unwrap_or(720)
        .max(160);
    let cell_h = charts
        .iter()
        .map(|c| c.height_px)
        .max()
        .unwrap_or(450)
        .max(120);
    let title_h = if title.is_empty() { 0 } else { 40 };
    let size = (cell_w * cols as u32, title_h + cell_h * rows as u32);
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, size).into_drawing_area();
        root.fill(&WHITE)?;
        let body = if title.is_empty() {
            root.clone()
        } else {
            root.titled(
                title,
                (FONT, FIGURE_TITLE_SIZE)
                    .into_font()
                    .style(FontStyle::Bold)
                    .color(&TEXT),
            )?
        };
        for (chart, cell) in charts.iter().zip(body.split_evenly((rows, cols))) {
            draw_chart(chart, &cell)?;
        }
        root.present()?;
    }
    Ok(svg)
}
