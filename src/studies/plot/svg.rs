//! The SVG renderer behind [`Chart::to_svg`] and [`Figure::grid`].
//!
//! Layout in pixels, y downwards. A chart is a white canvas holding, top to bottom: the
//! title, the plot box (grid, bands, reference lines, data, frame, ticks), the x tick labels
//! and the x label; the y tick labels and the rotated y label sit left of the box. The legend
//! goes into whichever inside corner of the plot box covers the least data, or outside on the
//! right when every corner would hide data and the chart is wide enough to spare the room.

use std::fmt::Write as _;

use super::{Chart, Figure, Scale, Series, Style, Ticks};

const FONT_FAMILY: &str = "Helvetica, Arial, DejaVu Sans, Liberation Sans, sans-serif";
const TITLE_PX: f64 = 16.0;
const AXIS_LABEL_PX: f64 = 13.5;
const TICK_PX: f64 = 12.0;
const LEGEND_PX: f64 = 12.5;
const HLINE_PX: f64 = 11.5;
const FIGURE_TITLE_PX: f64 = 18.0;

const TEXT_COLOUR: &str = "#222222";
const FRAME_COLOUR: &str = "#4d4d4d";
const GRID_COLOUR: &str = "#e0e0e0";
const MINOR_GRID_COLOUR: &str = "#f0f0f0";
const HLINE_COLOUR: &str = "#555555";

/// Okabe-Ito colours, reordered so that the first few are the most distinct on white (the
/// palette's yellow is too pale for thin lines and is left out).
const PALETTE: [&str; 7] = [
    "#0072B2", "#D55E00", "#009E73", "#CC79A7", "#E69F00", "#56B4E9", "#000000",
];

/// Marker shapes; six shapes against seven colours repeat only after 42 series.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Marker {
    Circle,
    Square,
    TriangleUp,
    Diamond,
    TriangleDown,
    Cross,
}

const MARKERS: [Marker; 6] = [
    Marker::Circle,
    Marker::Square,
    Marker::TriangleUp,
    Marker::Diamond,
    Marker::TriangleDown,
    Marker::Cross,
];

const LINE_WIDTH: f64 = 2.0;
const DASH: &str = "7 4";
const BAND_OPACITY: f64 = 0.2;

const TICK_LEN: f64 = 5.0;
const MINOR_TICK_LEN: f64 = 3.0;

/// Legend box geometry.
const LEGEND_PAD: f64 = 8.0;
const LEGEND_ROW: f64 = 19.0;
const LEGEND_SAMPLE: f64 = 28.0;
const LEGEND_GAP: f64 = 7.0;
const LEGEND_INSET: f64 = 8.0;

fn colour(index: usize) -> &'static str {
    PALETTE[index % PALETTE.len()]
}

fn marker(index: usize) -> Marker {
    MARKERS[index % MARKERS.len()]
}

/// A number with at most two decimals, trailing zeros dropped, never `-0`.
fn num(v: f64) -> String {
    let v = if v.is_finite() { v } else { 0.0 };
    let mut text = format!("{v:.2}");
    if text.contains('.') {
        text = text.trim_end_matches('0').trim_end_matches('.').to_string();
    }
    if text == "-0" {
        text = "0".to_string();
    }
    text
}

/// XML-escaped text.
fn esc(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    for c in s.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&apos;"),
            c if (c as u32) < 0x20 && c != '\t' && c != '\n' && c != '\r' => {}
            c => out.push(c),
        }
    }
    out
}

/// A tick label with its hyphens shown as minus signs (`−5e−6`), as typeset numbers are.
fn typographic_minus(label: &str) -> String {
    label.replace('-', "\u{2212}")
}

/// Approximate advance of a character in em, for a DejaVu/Helvetica-like sans-serif (errs
/// on the wide side so that estimated boxes hold the real text).
fn char_em(c: char) -> f64 {
    match c {
        '0'..='9' => 0.636,
        '.' | ',' | ':' | ';' | 'i' | 'l' | 'j' | '\'' | '|' | '!' => 0.30,
        ' ' => 0.32,
        '-' => 0.361,
        '\u{2212}' => 0.84,
        'f' | 't' | 'r' => 0.42,
        '(' | ')' | '[' | ']' | '{' | '}' | '/' => 0.40,
        'm' | 'w' | 'M' | 'W' => 0.95,
        'A'..='Z' => 0.72,
        'a'..='z' => 0.62,
        _ => 0.75,
    }
}

fn text_width(s: &str, px: f64) -> f64 {
    s.chars().map(char_em).sum::<f64>() * px
}

/// Maps data values onto pixels along one axis.
#[derive(Debug, Clone, Copy)]
struct Axis {
    scale: Scale,
    lo: f64,
    hi: f64,
    /// Pixel of `lo`.
    p0: f64,
    /// Pixel of `hi`.
    p1: f64,
}

impl Axis {
    fn transform(scale: Scale, v: f64) -> f64 {
        match scale {
            Scale::Linear => v,
            Scale::Log10 => v.log10(),
        }
    }

    /// Pixel of `v`, or `None` when `v` cannot be drawn on this axis. Far-away values are
    /// pulled in to a sane coordinate (the plot is clipped anyway).
    fn map(&self, v: f64) -> Option<f64> {
        if !self.scale.accepts(v) {
            return None;
        }
        let a = Self::transform(self.scale, self.lo);
        let b = Self::transform(self.scale, self.hi);
        let t = (Self::transform(self.scale, v) - a) / (b - a);
        let p = self.p0 + t * (self.p1 - self.p0);
        if p.is_finite() {
            Some(p.clamp(-1e5, 1e5))
        } else {
            None
        }
    }
}

/// Resolves an axis range: the explicit one when usable, otherwise the data's extent with a
/// small margin (a decade-free fallback when there is no data).
fn resolve_range(
    explicit: Option<(f64, f64)>,
    scale: Scale,
    data: impl Iterator<Item = f64>,
) -> (f64, f64) {
    if let Some((a, b)) = explicit {
        let (lo, hi) = if a <= b { (a, b) } else { (b, a) };
        if scale.accepts(lo) && scale.accepts(hi) && hi > lo {
            return (lo, hi);
        }
    }
    let mut min = f64::INFINITY;
    let mut max = f64::NEG_INFINITY;
    for v in data.filter(|&v| scale.accepts(v)) {
        min = min.min(v);
        max = max.max(v);
    }
    if min > max {
        return match scale {
            Scale::Linear => (0.0, 1.0),
            Scale::Log10 => (1.0, 10.0),
        };
    }
    const MARGIN: f64 = 0.04;
    match scale {
        Scale::Linear => {
            if max - min <= 0.0 || !(max - min).is_finite() {
                let d = if min == 0.0 { 1.0 } else { 0.1 * min.abs() };
                (min - d, max + d)
            } else {
                let d = MARGIN * (max - min);
                (min - d, max + d)
            }
        }
        Scale::Log10 => {
            let (a, b) = (min.log10(), max.log10());
            if b - a <= 0.0 {
                (min / 2.0, max * 2.0)
            } else {
                let d = MARGIN * (b - a);
                (10f64.powf(a - d), 10f64.powf(b + d))
            }
        }
    }
}

/// Everything positional about one chart.
struct Frame {
    width: f64,
    height: f64,
    left: f64,
    top: f64,
    right: f64,
    bottom: f64,
    x: Axis,
    y: Axis,
    x_ticks: Ticks,
    y_ticks: Ticks,
}

impl Frame {
    fn contains(&self, px: f64, py: f64) -> bool {
        px >= self.left && px <= self.right && py >= self.top && py <= self.bottom
    }
}

/// Chooses ticks with as many labels as fit: `fits(ticks)` says whether the labels of a
/// candidate leave enough room between them.
fn fitting_ticks(
    scale: Scale,
    lo: f64,
    hi: f64,
    most: usize,
    fits: impl Fn(&Ticks) -> bool,
) -> Ticks {
    let mut n = most.clamp(2, 10);
    loop {
        let ticks = scale.ticks(lo, hi, n);
        if n <= 2 || fits(&ticks) {
            return ticks;
        }
        n -= 1;
    }
}

fn layout(chart: &Chart, extra_right: f64) -> Frame {
    let width = f64::from(chart.width_px.max(160));
    let height = f64::from(chart.height_px.max(120));
    let (x_lo, x_hi) = x_range(chart);
    let (y_lo, y_hi) = y_range(chart, (x_lo, x_hi));

    let top = if chart.title.is_empty() {
        14.0
    } else {
        (14.0 + TITLE_PX + 14.0_f64).round()
    };
    let bottom_margin = if chart.x_label.is_empty() { 28.0 } else { 52.0 };
    let bottom = (height - bottom_margin).max(top + 20.0).round();

    // y ticks first: the plot height does not depend on anything else.
    let y_probe = Axis {
        scale: chart.y_scale,
        lo: y_lo,
        hi: y_hi,
        p0: bottom,
        p1: top,
    };
    let y_ticks = fitting_ticks(
        chart.y_scale,
        y_lo,
        y_hi,
        ((bottom - top) / 44.0) as usize,
        |t| min_gap(&y_probe, &t.major, |_, _| TICK_PX * 1.6),
    );
    let label_w = y_ticks
        .labels
        .iter()
        .map(|l| text_width(&typographic_minus(l), TICK_PX))
        .fold(0.0, f64::max);
    let y_label_room = if chart.y_label.is_empty() {
        0.0
    } else {
        AXIS_LABEL_PX + 10.0
    };
    let left = (12.0 + y_label_room + label_w + TICK_LEN + 5.0).round();

    let mut right = (width - 16.0 - extra_right).max(left + 20.0).round();
    let mut x_ticks = Ticks::default();
    let mut x_axis = Axis {
        scale: chart.x_scale,
        lo: x_lo,
        hi: x_hi,
        p0: left,
        p1: right,
    };
    for _ in 0..3 {
        x_axis.p1 = right;
        let widths = |t: &Ticks| -> Vec<f64> {
            t.labels
                .iter()
                .map(|l| text_width(&typographic_minus(l), TICK_PX))
                .collect()
        };
        x_ticks = fitting_ticks(
            chart.x_scale,
            x_lo,
            x_hi,
            ((right - left) / 50.0) as usize,
            |t| {
                let w = widths(t);
                min_gap(&x_axis, &t.major, |i, j| 0.5 * (w[i] + w[j]) + 14.0)
            },
        );
        // Keep the last label inside the canvas.
        let overhang = match (x_ticks.major.last(), x_ticks.labels.last()) {
            (Some(&v), Some(l)) => x_axis.map(v).map_or(0.0, |p| {
                p + 0.5 * text_width(&typographic_minus(l), TICK_PX) + 4.0 - (width - extra_right)
            }),
            _ => 0.0,
        };
        if overhang <= 0.0 {
            break;
        }
        right = (right - overhang).max(left + 20.0).round();
    }
    x_axis.p1 = right;
    Frame {
        width,
        height,
        left,
        top,
        right,
        bottom,
        x: x_axis,
        y: y_probe,
        x_ticks,
        y_ticks,
    }
}

/// Whether consecutive ticks are at least `need(i, i + 1)` pixels apart.
fn min_gap(axis: &Axis, major: &[f64], need: impl Fn(usize, usize) -> f64) -> bool {
    let px: Vec<Option<f64>> = major.iter().map(|&v| axis.map(v)).collect();
    px.windows(2).enumerate().all(|(i, w)| match (w[0], w[1]) {
        (Some(a), Some(b)) => (b - a).abs() >= need(i, i + 1),
        _ => true,
    })
}

fn x_range(chart: &Chart) -> (f64, f64) {
    let data = chart.series.iter().flat_map(|s| {
        s.points
            .iter()
            .map(|p| p.0)
            .chain(s.band.iter().flat_map(|b| b.iter().map(|p| p.0)))
    });
    resolve_range(chart.x_range, chart.x_scale, data)
}

fn y_range(chart: &Chart, (x_lo, x_hi): (f64, f64)) -> (f64, f64) {
    // With a fixed x range, only what is visible decides the y range.
    let visible = |x: f64| chart.x_range.is_none() || (x >= x_lo && x <= x_hi);
    let data = chart
        .series
        .iter()
        .flat_map(|s| {
            s.points
                .iter()
                .filter(move |p| visible(p.0))
                .map(|p| p.1)
                .chain(s.band.iter().flat_map(move |b| {
                    b.iter()
                        .filter(move |p| visible(p.0))
                        .flat_map(|p| [p.1, p.2])
                }))
        })
        .chain(chart.hlines.iter().map(|h| h.0));
    resolve_range(chart.y_range, chart.y_scale, data)
}

/// Pixel runs of a series: consecutive drawable points, broken at undrawable ones.
fn pixel_runs(points: &[(f64, f64)], frame: &Frame) -> Vec<Vec<(f64, f64)>> {
    let mut runs = Vec::new();
    let mut run = Vec::new();
    for &(x, y) in points {
        match (frame.x.map(x), frame.y.map(y)) {
            (Some(px), Some(py)) => run.push((px, py)),
            _ => {
                if !run.is_empty() {
                    runs.push(std::mem::take(&mut run));
                }
            }
        }
    }
    if !run.is_empty() {
        runs.push(run);
    }
    runs
}

/// Thins a pixel run without visible change: of consecutive points in the same pixel column
/// only the first, the lowest, the highest and the last are kept.
fn decimate(run: &[(f64, f64)]) -> Vec<(f64, f64)> {
    if run.len() < 5 {
        return run.to_vec();
    }
    let mut out = Vec::with_capacity(run.len().min(4096));
    let mut start = 0;
    while start < run.len() {
        let column = run[start].0.floor();
        let mut end = start + 1;
        while end < run.len() && run[end].0.floor() == column {
            end += 1;
        }
        let group = &run[start..end];
        if group.len() <= 4 {
            out.extend_from_slice(group);
        } else {
            let (mut lo, mut hi) = (0, 0);
            for (i, p) in group.iter().enumerate() {
                if p.1 < group[lo].1 {
                    lo = i;
                }
                if p.1 > group[hi].1 {
                    hi = i;
                }
            }
            let mut keep = [0, lo, hi, group.len() - 1];
            keep.sort_unstable();
            let mut last = usize::MAX;
            for k in keep {
                if k != last {
                    out.push(group[k]);
                    last = k;
                }
            }
        }
        start = end;
    }
    out
}

fn path_data(run: &[(f64, f64)]) -> String {
    let mut d = String::with_capacity(run.len() * 14);
    for (i, &(x, y)) in run.iter().enumerate() {
        d.push(if i == 0 { 'M' } else { 'L' });
        d.push_str(&num(x));
        d.push(',');
        d.push_str(&num(y));
    }
    d
}

/// Band polygons: runs of drawable `(x, low, high)` vertices as closed pixel outlines.
fn band_polygons(band: &[(f64, f64, f64)], frame: &Frame) -> Vec<Vec<(f64, f64)>> {
    let mut polys = Vec::new();
    let mut run: Vec<(f64, f64, f64)> = Vec::new();
    let flush = |run: &mut Vec<(f64, f64, f64)>, polys: &mut Vec<Vec<(f64, f64)>>| {
        if run.len() >= 2 {
            let mut poly: Vec<(f64, f64)> = run.iter().map(|v| (v.0, v.2)).collect();
            poly.extend(run.iter().rev().map(|v| (v.0, v.1)));
            polys.push(poly);
        }
        run.clear();
    };
    for &(x, lo, hi) in band {
        match (frame.x.map(x), frame.y.map(lo), frame.y.map(hi)) {
            (Some(px), Some(plo), Some(phi)) => run.push((px, plo, phi)),
            _ => flush(&mut run, &mut polys),
        }
    }
    flush(&mut run, &mut polys);
    polys
}

fn marker_svg(out: &mut String, shape: Marker, x: f64, y: f64, colour: &str) {
    let (xs, ys) = (num(x), num(y));
    let p = |dx: f64, dy: f64| format!("{},{}", num(x + dx), num(y + dy));
    match shape {
        Marker::Circle => {
            let _ = write!(out, r#"<circle cx="{xs}" cy="{ys}" r="3.8"/>"#);
        }
        Marker::Square => {
            let _ = write!(
                out,
                r#"<rect x="{}" y="{}" width="6.8" height="6.8"/>"#,
                num(x - 3.4),
                num(y - 3.4)
            );
        }
        Marker::TriangleUp => {
            let _ = write!(
                out,
                r#"<path d="M{}L{}L{}Z"/>"#,
                p(0.0, -4.6),
                p(4.2, 2.8),
                p(-4.2, 2.8)
            );
        }
        Marker::Diamond => {
            let _ = write!(
                out,
                r#"<path d="M{}L{}L{}L{}Z"/>"#,
                p(0.0, -4.6),
                p(4.2, 0.0),
                p(0.0, 4.6),
                p(-4.2, 0.0)
            );
        }
        Marker::TriangleDown => {
            let _ = write!(
                out,
                r#"<path d="M{}L{}L{}Z"/>"#,
                p(0.0, 4.6),
                p(4.2, -2.8),
                p(-4.2, -2.8)
            );
        }
        Marker::Cross => {
            let _ = write!(
                out,
                r#"<path d="M{}L{}M{}L{}" fill="none" stroke="{colour}" stroke-width="2"/>"#,
                p(-3.6, -3.6),
                p(3.6, 3.6),
                p(-3.6, 3.6),
                p(3.6, -3.6)
            );
        }
    }
}

fn draws_line(style: Style) -> bool {
    matches!(style, Style::Line | Style::LineMarkers)
}

fn draws_markers(style: Style) -> bool {
    matches!(style, Style::Markers | Style::LineMarkers)
}

/// Sample points of what the legend and the reference-line labels should not cover, in
/// pixels, with a weight: lines and markers count more than shaded bands.
fn data_obstacles(chart: &Chart, frame: &Frame) -> Vec<(f64, f64, f64)> {
    let mut out = Vec::new();
    for s in &chart.series {
        for run in pixel_runs(&s.points, frame) {
            let run = decimate(&run);
            if draws_line(s.style) && run.len() >= 2 {
                for w in run.windows(2) {
                    sample_segment(&mut out, w[0], w[1], 3.0);
                }
            } else {
                out.extend(run.iter().map(|&(x, y)| (x, y, 3.0)));
            }
        }
        if let Some(band) = &s.band {
            for poly in band_polygons(band, frame) {
                let n = poly.len() / 2;
                for i in 0..n.saturating_sub(1) {
                    let (x0, x1) = (poly[i].0, poly[i + 1].0);
                    let (hi0, hi1) = (poly[i].1, poly[i + 1].1);
                    let (lo0, lo1) = (poly[2 * n - 1 - i].1, poly[2 * n - 2 - i].1);
                    let cols = (((x1 - x0).abs() / 6.0).ceil() as usize).clamp(1, 500);
                    for c in 0..=cols {
                        let t = c as f64 / cols as f64;
                        let x = x0 + t * (x1 - x0);
                        let top = hi0 + t * (hi1 - hi0);
                        let bot = lo0 + t * (lo1 - lo0);
                        sample_segment(&mut out, (x, top), (x, bot), 1.0);
                    }
                }
            }
        }
    }
    out.retain(|&(x, y, _)| frame.contains(x, y));
    out
}

/// Samples every 4 px along a segment.
fn sample_segment(out: &mut Vec<(f64, f64, f64)>, a: (f64, f64), b: (f64, f64), w: f64) {
    let len = ((b.0 - a.0).powi(2) + (b.1 - a.1).powi(2)).sqrt();
    let n = ((len / 4.0).ceil() as usize).clamp(1, 2000);
    for i in 0..=n {
        let t = i as f64 / n as f64;
        out.push((a.0 + t * (b.0 - a.0), a.1 + t * (b.1 - a.1), w));
    }
}

/// Total weight of the samples inside `r = [x0, y0, x1, y1]` grown by 3 px.
fn score(obstacles: &[(f64, f64, f64)], r: [f64; 4]) -> f64 {
    obstacles
        .iter()
        .filter(|&&(x, y, _)| {
            x >= r[0] - 3.0 && x <= r[2] + 3.0 && y >= r[1] - 3.0 && y <= r[3] + 3.0
        })
        .map(|o| o.2)
        .sum()
}

fn boxes_overlap(a: &[f64; 4], b: &[f64; 4]) -> bool {
    a[0] < b[2] && a[2] > b[0] && a[1] < b[3] && a[3] > b[1]
}

/// A reference line's label: anchor point, text anchor and box.
struct HlineLabel {
    x: f64,
    y: f64,
    anchor: &'static str,
    text: String,
    bbox: [f64; 4],
}

/// Puts each reference-line label just above (or below) its line, at the right (or left)
/// end, wherever it hides the least data without overlapping another label.
fn place_hline_labels(
    chart: &Chart,
    frame: &Frame,
    obstacles: &[(f64, f64, f64)],
) -> Vec<HlineLabel> {
    let mut placed: Vec<HlineLabel> = Vec::new();
    let mut lines: Vec<(f64, &str)> = chart
        .hlines
        .iter()
        .filter(|h| !h.1.is_empty())
        .filter_map(|h| frame.y.map(h.0).map(|py| (py, h.1.as_str())))
        .filter(|&(py, _)| py >= frame.top && py <= frame.bottom)
        .collect();
    lines.sort_by(|a, b| a.0.total_cmp(&b.0));
    for (py, text) in lines {
        let w = text_width(text, HLINE_PX);
        let above = py - 5.0;
        let below = py + 5.0 + HLINE_PX * 0.8;
        let fits_above = above - HLINE_PX * 0.8 >= frame.top + 2.0;
        let fits_below = below + 3.0 <= frame.bottom;
        let mut best: Option<(f64, HlineLabel)> = None;
        for right_side in [true, false] {
            for use_above in [true, false] {
                if (use_above && !fits_above) || (!use_above && !fits_below) {
                    continue;
                }
                let base = if use_above { above } else { below };
                let (x, anchor, x0) = if right_side {
                    (frame.right - 6.0, "end", frame.right - 6.0 - w)
                } else {
                    (frame.left + 6.0, "start", frame.left + 6.0)
                };
                let bbox = [x0, base - HLINE_PX * 0.8, x0 + w, base + HLINE_PX * 0.25];
                // Another label is worse than any amount of data.
                let clash = if placed.iter().any(|p| boxes_overlap(&p.bbox, &bbox)) {
                    1e12
                } else {
                    0.0
                };
                let s = clash + score(obstacles, bbox);
                if best.as_ref().is_none_or(|(bs, _)| s < *bs) {
                    let label = HlineLabel {
                        x,
                        y: base,
                        anchor,
                        text: text.to_string(),
                        bbox,
                    };
                    best = Some((s, label));
                }
            }
        }
        if let Some((_, label)) = best {
            placed.push(label);
        }
    }
    placed
}

struct Legend {
    x: f64,
    y: f64,
    w: f64,
    h: f64,
}

fn legend_entries(chart: &Chart) -> Vec<(usize, &Series)> {
    chart
        .series
        .iter()
        .enumerate()
        .filter(|(_, s)| !s.name.is_empty())
        .collect()
}

fn legend_size(entries: &[(usize, &Series)]) -> (f64, f64) {
    let text_w = entries
        .iter()
        .map(|(_, s)| text_width(&s.name, LEGEND_PX))
        .fold(0.0, f64::max);
    let w = (LEGEND_PAD + LEGEND_SAMPLE + LEGEND_GAP + text_w + LEGEND_PAD).ceil();
    let h = (2.0 * 6.0 + entries.len() as f64 * LEGEND_ROW).ceil();
    (w, h)
}

/// The best inside position for a `w` x `h` legend: `(data covered, reference lines
/// covered, x, y)`, preferring the corners, top-right first.
fn best_inside(
    chart: &Chart,
    frame: &Frame,
    data: &[(f64, f64, f64)],
    labels: &[HlineLabel],
    (w, h): (f64, f64),
) -> Option<(f64, f64, f64, f64)> {
    if w + 2.0 * LEGEND_INSET > frame.right - frame.left
        || h + 2.0 * LEGEND_INSET > frame.bottom - frame.top
    {
        return None;
    }
    let mut lines = Vec::new();
    for &(y, _) in &chart.hlines {
        if let Some(py) = frame.y.map(y) {
            sample_segment(&mut lines, (frame.left, py), (frame.right, py), 1.0);
        }
    }
    let (l, t) = (frame.left + LEGEND_INSET, frame.top + LEGEND_INSET);
    let (r, b) = (
        frame.right - LEGEND_INSET - w,
        frame.bottom - LEGEND_INSET - h,
    );
    let (cx, cy) = (0.5 * (l + r), 0.5 * (t + b));
    let candidates = [
        (r, t),
        (l, t),
        (r, b),
        (l, b),
        (cx, t),
        (cx, b),
        (r, cy),
        (l, cy),
    ];
    // Also just below and just above each reference line, clear of its label.
    let mut beside_lines = Vec::new();
    for &(y, _) in &chart.hlines {
        if let Some(py) = frame.y.map(y) {
            for x in [r, l, cx] {
                for y in [py + 2.0 * LEGEND_INSET, py - 2.0 * LEGEND_INSET - h] {
                    if y >= t && y <= b {
                        beside_lines.push((x, y));
                    }
                }
            }
        }
    }
    let mut best: Option<(f64, f64, f64, f64)> = None;
    for (x, y) in candidates.into_iter().chain(beside_lines) {
        let rect = [x, y, x + w, y + h];
        let label_clash = labels.iter().any(|lb| boxes_overlap(&lb.bbox, &rect));
        let covered = score(data, rect) + if label_clash { 1e6 } else { 0.0 };
        let crossed = score(&lines, rect);
        let better =
            best.is_none_or(|(bc, bl, _, _)| covered < bc || (covered == bc && crossed < bl));
        if better {
            best = Some((covered, crossed, x, y));
        }
    }
    best
}

/// Frame, reference-line labels and legend box, with the legend inside where it hides no
/// data and outside on the right otherwise (if the chart is wide enough to spare the room).
fn arrange(chart: &Chart) -> (Frame, Vec<HlineLabel>, Option<Legend>) {
    let frame = layout(chart, 0.0);
    let data = data_obstacles(chart, &frame);
    let labels = place_hline_labels(chart, &frame, &data);
    let entries = legend_entries(chart);
    if entries.is_empty() {
        return (frame, labels, None);
    }
    let (w, h) = legend_size(&entries);
    let inside = best_inside(chart, &frame, &data, &labels, (w, h));
    if let Some((covered, _, x, y)) = inside {
        if covered <= 0.0 {
            return (frame, labels, Some(Legend { x, y, w, h }));
        }
    }
    let extra = w + 22.0;
    let outside_ok = frame.right - frame.left - extra >= 0.55 * frame.width;
    match inside {
        Some((_, _, x, y)) if !outside_ok => (frame, labels, Some(Legend { x, y, w, h })),
        _ => {
            let frame = layout(chart, extra);
            let data = data_obstacles(chart, &frame);
            let labels = place_hline_labels(chart, &frame, &data);
            let legend = Legend {
                x: frame.right + 14.0,
                y: frame.top,
                w,
                h,
            };
            (frame, labels, Some(legend))
        }
    }
}

/// A short, stable tag derived from the chart's text, so that element ids of different
/// charts inlined in one HTML page do not collide.
fn id_tag(chart: &Chart) -> String {
    let mut hash: u32 = 0x811c_9dc5;
    let text = chart
        .title
        .bytes()
        .chain(chart.x_label.bytes())
        .chain(chart.y_label.bytes());
    for b in text {
        hash ^= u32::from(b);
        hash = hash.wrapping_mul(0x0100_0193);
    }
    format!("{hash:08x}")
}

fn crisp(v: f64) -> f64 {
    v.round() + 0.5
}

fn render_chart(chart: &Chart, id: &str, out: &mut String) {
    let (frame, hline_labels, legend) = arrange(chart);
    let (w, h) = (frame.width, frame.height);
    let (l, t, r, b) = (frame.left, frame.top, frame.right, frame.bottom);
    let clip = format!("clip-{id}");

    let _ = write!(
        out,
        r#"<rect width="{}" height="{}" fill="white"/>"#,
        num(w),
        num(h)
    );
    out.push('\n');
    let _ = writeln!(
        out,
        r#"<defs><clipPath id="{clip}"><rect x="{}" y="{}" width="{}" height="{}"/></clipPath></defs>"#,
        num(l),
        num(t),
        num(r - l),
        num(b - t)
    );

    // Title.
    if !chart.title.is_empty() {
        let tw = text_width(&chart.title, TITLE_PX) * 1.08;
        let cx = if tw <= r - l { 0.5 * (l + r) } else { 0.5 * w };
        let _ = writeln!(
            out,
            r#"<text x="{}" y="{}" font-size="{}" font-weight="bold" text-anchor="middle" fill="{TEXT_COLOUR}">{}</text>"#,
            num(cx),
            num(14.0 + TITLE_PX * 0.8),
            num(TITLE_PX),
            esc(&chart.title)
        );
    }

    // Grid: minor lines first, then major.
    out.push_str("<g fill=\"none\" stroke-width=\"1\">\n");
    let vgrid = |out: &mut String, vals: &[f64], colour: &str| {
        for &v in vals {
            if let Some(px) = frame.x.map(v) {
                if px > l + 0.5 && px < r - 0.5 {
                    let x = num(crisp(px));
                    let _ = writeln!(
                        out,
                        r#"<line x1="{x}" y1="{}" x2="{x}" y2="{}" stroke="{colour}"/>"#,
                        num(t),
                        num(b)
                    );
                }
            }
        }
    };
    let hgrid = |out: &mut String, vals: &[f64], colour: &str| {
        for &v in vals {
            if let Some(py) = frame.y.map(v) {
                if py > t + 0.5 && py < b - 0.5 {
                    let y = num(crisp(py));
                    let _ = writeln!(
                        out,
                        r#"<line x1="{}" y1="{y}" x2="{}" y2="{y}" stroke="{colour}"/>"#,
                        num(l),
                        num(r)
                    );
                }
            }
        }
    };
    vgrid(out, &frame.x_ticks.minor, MINOR_GRID_COLOUR);
    hgrid(out, &frame.y_ticks.minor, MINOR_GRID_COLOUR);
    vgrid(out, &frame.x_ticks.major, GRID_COLOUR);
    hgrid(out, &frame.y_ticks.major, GRID_COLOUR);
    out.push_str("</g>\n");

    // Data, clipped to the plot box.
    let _ = writeln!(out, r#"<g clip-path="url(#{clip})">"#);
    for (i, s) in chart.series.iter().enumerate() {
        if let Some(band) = &s.band {
            for poly in band_polygons(band, &frame) {
                let mut d = path_data(&poly);
                d.push('Z');
                let _ = writeln!(
                    out,
                    r#"<path d="{d}" fill="{}" fill-opacity="{BAND_OPACITY}" stroke="none"/>"#,
                    colour(i)
                );
            }
        }
    }
    for &(y, _) in &chart.hlines {
        if let Some(py) = frame.y.map(y) {
            let y = num(py);
            let _ = writeln!(
                out,
                r#"<line x1="{}" y1="{y}" x2="{}" y2="{y}" stroke="{HLINE_COLOUR}" stroke-width="1.4" stroke-dasharray="9 3 2 3"/>"#,
                num(l),
                num(r)
            );
        }
    }
    let mut any_data = false;
    for (i, s) in chart.series.iter().enumerate() {
        let runs = pixel_runs(&s.points, &frame);
        any_data |= !runs.is_empty() || s.band.as_ref().is_some_and(|b| !b.is_empty());
        if !draws_line(s.style) {
            continue;
        }
        let dash = if s.dashed {
            format!(r#" stroke-dasharray="{DASH}""#)
        } else {
            String::new()
        };
        for run in &runs {
            if run.len() == 1 && s.style == Style::Line {
                // An isolated point of a line would vanish: show it as a dot.
                let _ = writeln!(
                    out,
                    r#"<circle cx="{}" cy="{}" r="{}" fill="{}"/>"#,
                    num(run[0].0),
                    num(run[0].1),
                    num(LINE_WIDTH),
                    colour(i)
                );
                continue;
            }
            if run.len() < 2 {
                continue;
            }
            let _ = writeln!(
                out,
                r#"<path d="{}" fill="none" stroke="{}" stroke-width="{}" stroke-linejoin="round" stroke-linecap="round"{dash}/>"#,
                path_data(&decimate(run)),
                colour(i),
                num(LINE_WIDTH)
            );
        }
    }
    for (i, s) in chart.series.iter().enumerate() {
        if !draws_markers(s.style) {
            continue;
        }
        let runs = pixel_runs(&s.points, &frame);
        if runs.is_empty() {
            continue;
        }
        let _ = write!(
            out,
            r#"<g fill="{}" stroke="white" stroke-width="0.8">"#,
            colour(i)
        );
        for &(x, y) in runs.iter().flatten() {
            if x >= l - 6.0 && x <= r + 6.0 && y >= t - 6.0 && y <= b + 6.0 {
                marker_svg(out, marker(i), x, y, colour(i));
            }
        }
        out.push_str("</g>\n");
    }
    out.push_str("</g>\n");

    for label in &hline_labels {
        let _ = writeln!(
            out,
            r##"<text x="{}" y="{}" font-size="{}" text-anchor="{}" fill="#333333" stroke="white" stroke-width="3" stroke-linejoin="round" paint-order="stroke">{}</text>"##,
            num(label.x),
            num(label.y),
            num(HLINE_PX),
            label.anchor,
            esc(&label.text)
        );
    }

    if !any_data {
        let _ = writeln!(
            out,
            r##"<text x="{}" y="{}" font-size="{}" text-anchor="middle" fill="#888888">no data</text>"##,
            num(0.5 * (l + r)),
            num(0.5 * (t + b) + 0.35 * AXIS_LABEL_PX),
            num(AXIS_LABEL_PX)
        );
    }

    // Frame and ticks.
    let _ = writeln!(
        out,
        r#"<rect x="{}" y="{}" width="{}" height="{}" fill="none" stroke="{FRAME_COLOUR}" stroke-width="1"/>"#,
        num(l.round() + 0.5),
        num(t.round() + 0.5),
        num((r - l).round()),
        num((b - t).round())
    );
    let _ = writeln!(out, r#"<g stroke="{FRAME_COLOUR}" stroke-width="1">"#);
    let bx = b.round() + 0.5;
    let lx = l.round() + 0.5;
    for (vals, len) in [
        (&frame.x_ticks.major, TICK_LEN),
        (&frame.x_ticks.minor, MINOR_TICK_LEN),
    ] {
        for &v in vals.iter() {
            if let Some(px) = frame.x.map(v) {
                if px >= l - 0.5 && px <= r + 0.5 {
                    let x = num(crisp(px));
                    let _ = writeln!(
                        out,
                        r#"<line x1="{x}" y1="{}" x2="{x}" y2="{}"/>"#,
                        num(bx),
                        num(bx + len)
                    );
                }
            }
        }
    }
    for (vals, len) in [
        (&frame.y_ticks.major, TICK_LEN),
        (&frame.y_ticks.minor, MINOR_TICK_LEN),
    ] {
        for &v in vals.iter() {
            if let Some(py) = frame.y.map(v) {
                if py >= t - 0.5 && py <= b + 0.5 {
                    let y = num(crisp(py));
                    let _ = writeln!(
                        out,
                        r#"<line x1="{}" y1="{y}" x2="{}" y2="{y}"/>"#,
                        num(lx - len),
                        num(lx)
                    );
                }
            }
        }
    }
    out.push_str("</g>\n");

    // Tick labels.
    let _ = writeln!(
        out,
        r#"<g font-size="{}" fill="{TEXT_COLOUR}">"#,
        num(TICK_PX)
    );
    for (v, label) in frame.x_ticks.major.iter().zip(&frame.x_ticks.labels) {
        if let Some(px) = frame.x.map(*v) {
            let _ = writeln!(
                out,
                r#"<text x="{}" y="{}" text-anchor="middle">{}</text>"#,
                num(px),
                num(b + TICK_LEN + 4.0 + TICK_PX * 0.8),
                esc(&typographic_minus(label))
            );
        }
    }
    for (v, label) in frame.y_ticks.major.iter().zip(&frame.y_ticks.labels) {
        if let Some(py) = frame.y.map(*v) {
            let _ = writeln!(
                out,
                r#"<text x="{}" y="{}" text-anchor="end">{}</text>"#,
                num(l - TICK_LEN - 4.0),
                num(py + 0.35 * TICK_PX),
                esc(&typographic_minus(label))
            );
        }
    }
    out.push_str("</g>\n");

    // Axis labels.
    if !chart.x_label.is_empty() {
        let _ = writeln!(
            out,
            r#"<text x="{}" y="{}" font-size="{}" text-anchor="middle" fill="{TEXT_COLOUR}">{}</text>"#,
            num(0.5 * (l + r)),
            num(b + TICK_LEN + 4.0 + TICK_PX + 10.0 + AXIS_LABEL_PX * 0.8),
            num(AXIS_LABEL_PX),
            esc(&chart.x_label)
        );
    }
    if !chart.y_label.is_empty() {
        let x = 12.0 + AXIS_LABEL_PX * 0.8;
        let y = 0.5 * (t + b);
        let _ = writeln!(
            out,
            r#"<text x="{x}" y="{y}" font-size="{}" text-anchor="middle" fill="{TEXT_COLOUR}" transform="rotate(-90 {x} {y})">{}</text>"#,
            num(AXIS_LABEL_PX),
            esc(&chart.y_label),
            x = num(x),
            y = num(y)
        );
    }

    if let Some(legend) = legend {
        render_legend(chart, &legend, out);
    }
}

fn render_legend(chart: &Chart, legend: &Legend, out: &mut String) {
    let _ = writeln!(
        out,
        r##"<rect x="{}" y="{}" width="{}" height="{}" rx="3" fill="white" fill-opacity="0.92" stroke="#c8c8c8" stroke-width="1"/>"##,
        num(legend.x.round() + 0.5),
        num(legend.y.round() + 0.5),
        num(legend.w),
        num(legend.h)
    );
    for (row, (i, s)) in legend_entries(chart).into_iter().enumerate() {
        let cy = legend.y + 6.0 + (row as f64 + 0.5) * LEGEND_ROW;
        let x0 = legend.x + LEGEND_PAD;
        let x1 = x0 + LEGEND_SAMPLE;
        let c = colour(i);
        if s.band.is_some() {
            let _ = writeln!(
                out,
                r#"<rect x="{}" y="{}" width="{}" height="12" fill="{c}" fill-opacity="{BAND_OPACITY}"/>"#,
                num(x0),
                num(cy - 6.0),
                num(LEGEND_SAMPLE)
            );
        }
        if draws_line(s.style) {
            let dash = if s.dashed {
                format!(r#" stroke-dasharray="{DASH}""#)
            } else {
                String::new()
            };
            let _ = writeln!(
                out,
                r#"<line x1="{}" y1="{y}" x2="{}" y2="{y}" stroke="{c}" stroke-width="{}" stroke-linecap="round"{dash}/>"#,
                num(x0 + 1.0),
                num(x1 - 1.0),
                num(LINE_WIDTH),
                y = num(cy)
            );
        }
        if draws_markers(s.style) {
            let _ = write!(out, r#"<g fill="{c}" stroke="white" stroke-width="0.8">"#);
            marker_svg(out, marker(i), 0.5 * (x0 + x1), cy, c);
            out.push_str("</g>\n");
        }
        let _ = writeln!(
            out,
            r#"<text x="{}" y="{}" font-size="{}" fill="{TEXT_COLOUR}">{}</text>"#,
            num(x1 + LEGEND_GAP),
            num(cy + 0.35 * LEGEND_PX),
            num(LEGEND_PX),
            esc(&s.name)
        );
    }
}

fn svg_open(out: &mut String, w: f64, h: f64) {
    let _ = writeln!(
        out,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{w}" height="{h}" viewBox="0 0 {w} {h}" font-family="{FONT_FAMILY}">"#,
        w = num(w),
        h = num(h)
    );
}

impl Chart {
    /// Renders the chart as a standalone SVG document (starting with `<svg`, ending with
    /// `</svg>`). Deterministic: the same chart gives the same bytes.
    pub fn to_svg(&self) -> String {
        let mut out = String::new();
        let w = f64::from(self.width_px.max(160));
        let h = f64::from(self.height_px.max(120));
        svg_open(&mut out, w, h);
        render_chart(self, &id_tag(self), &mut out);
        out.push_str("</svg>");
        out
    }
}

impl Figure {
    /// Places `charts` in a grid of `rows` x `cols` cells, row by row, as one SVG document.
    ///
    /// Every cell is as large as the largest chart; each chart keeps its own size, axes and
    /// legend. More charts than cells add rows; zero `rows` or `cols` are treated as one.
    pub fn grid(rows: usize, cols: usize, charts: &[Chart]) -> String {
        Self::grid_titled("", rows, cols, charts)
    }

    /// Like [`Figure::grid`], with an overall title above the sub-figures (empty for none).
    pub fn grid_titled(title: &str, rows: usize, cols: usize, charts: &[Chart]) -> String {
        let cols = cols.max(1);
        let rows = rows.max(charts.len().div_ceil(cols)).max(1);
        let cell_w = charts
            .iter()
            .map(|c| f64::from(c.width_px.max(160)))
            .fold(0.0, f64::max)
            .max(160.0);
        let cell_h = charts
            .iter()
            .map(|c| f64::from(c.height_px.max(120)))
            .fold(0.0, f64::max)
            .max(120.0);
        let title_h = if title.is_empty() { 0.0 } else { 40.0 };
        let w = cell_w * cols as f64;
        let h = title_h + cell_h * rows as f64;
        let mut out = String::new();
        svg_open(&mut out, w, h);
        let _ = writeln!(
            out,
            r#"<rect width="{}" height="{}" fill="white"/>"#,
            num(w),
            num(h)
        );
        if !title.is_empty() {
            let _ = writeln!(
                out,
                r#"<text x="{}" y="{}" font-size="{}" font-weight="bold" text-anchor="middle" fill="{TEXT_COLOUR}">{}</text>"#,
                num(0.5 * w),
                num(12.0 + FIGURE_TITLE_PX * 0.8),
                num(FIGURE_TITLE_PX),
                esc(title)
            );
        }
        for (k, chart) in charts.iter().enumerate() {
            let (row, col) = (k / cols, k % cols);
            let _ = writeln!(
                out,
                r#"<g transform="translate({},{})">"#,
                num(col as f64 * cell_w),
                num(title_h + row as f64 * cell_h)
            );
            render_chart(chart, &format!("{}-{k}", id_tag(chart)), &mut out);
            out.push_str("</g>\n");
        }
        out.push_str("</svg>");
        out
    }
}
