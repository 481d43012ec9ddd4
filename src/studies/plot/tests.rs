use super::render::tick_label;
use super::*;

/// Checks that `svg` is a well-formed XML element tree: every start tag is closed by the
/// matching end tag, quotes are balanced, no stray `<` or `&` appears in text, and there is
/// exactly one root element, `svg`. Returns the number of elements.
fn check_xml(svg: &str) -> std::result::Result<usize, String> {
    let bytes = svg.as_bytes();
    let mut stack: Vec<String> = Vec::new();
    let (mut roots, mut elements, mut i) = (0, 0, 0);
    while i < bytes.len() {
        match bytes[i] {
            b'<' => {
                let end = svg[i..]
                    .find('>')
                    .map(|e| i + e)
                    .ok_or_else(|| format!("unterminated tag at byte {i}"))?;
                let tag = &svg[i + 1..end];
                if tag.starts_with('?') {
                    i = end + 1;
                    continue;
                }
                if tag.contains('<') {
                    return Err(format!("'<' inside tag at byte {i}: {tag}"));
                }
                if !tag.matches('"').count().is_multiple_of(2) {
                    return Err(format!("unbalanced quotes in tag: {tag}"));
                }
                if let Some(name) = tag.strip_prefix('/') {
                    let open = stack
                        .pop()
                        .ok_or_else(|| format!("closing </{name}> without opening"))?;
                    if open != name.trim() {
                        return Err(format!("<{open}> closed by </{name}>"));
                    }
                } else {
                    let name: String = tag
                        .chars()
                        .take_while(|c| c.is_ascii_alphanumeric() || *c == '-' || *c == ':')
                        .collect();
                    if name.is_empty() {
                        return Err(format!("bad tag name: <{tag}>"));
                    }
                    if stack.is_empty() {
                        roots += 1;
                        if name != "svg" {
                            return Err(format!("root element is <{name}>"));
                        }
                    }
                    elements += 1;
                    if !tag.ends_with('/') {
                        stack.push(name);
                    }
                }
                i = end + 1;
            }
            b'&' => {
                let rest = &svg[i..];
                let ok = ["&amp;", "&lt;", "&gt;", "&quot;", "&apos;"]
                    .iter()
                    .any(|e| rest.starts_with(e));
                if !ok {
                    return Err(format!("unescaped '&' at byte {i}"));
                }
                i += 1;
            }
            b'>' => return Err(format!("stray '>' at byte {i}")),
            _ => i += 1,
        }
    }
    if !stack.is_empty() {
        return Err(format!("unclosed elements: {stack:?}"));
    }
    if roots != 1 {
        return Err(format!("{roots} root elements"));
    }
    Ok(elements)
}

/// The text of every `<text>` element, trimmed and unescaped.
fn texts(svg: &str) -> Vec<String> {
    svg.split("<text")
        .skip(1)
        .filter_map(|t| {
            let body = &t[t.find('>')? + 1..t.find("</text>")?];
            Some(
                body.trim()
                    .replace("&lt;", "<")
                    .replace("&gt;", ">")
                    .replace("&quot;", "\"")
                    .replace("&apos;", "'")
                    .replace("&amp;", "&"),
            )
        })
        .collect()
}

/// The vertices of every polyline drawn in `colour` (`#RRGGBB`, as the SVG writes it).
fn polylines(svg: &str, colour: &str) -> Vec<Vec<(i32, i32)>> {
    svg.split("<polyline")
        .skip(1)
        .filter(|t| t[..t.find('>').unwrap_or(0)].contains(&format!("stroke=\"{colour}\"")))
        .map(|t| {
            let start = t.find("points=\"").expect("points") + 8;
            let end = start + t[start..].find('"').expect("end of points");
            t[start..end]
                .split_whitespace()
                .map(|p| {
                    let (x, y) = p.split_once(',').expect("x,y");
                    (x.parse().expect("x"), y.parse().expect("y"))
                })
                .collect()
        })
        .collect()
}

/// How many times `needle` appears in `svg`.
fn count(svg: &str, needle: &str) -> usize {
    svg.matches(needle).count()
}

const BLUE: &str = "#0072B2";
const ORANGE: &str = "#D55E00";

fn demo_chart() -> Chart {
    let speeds: Vec<f64> = (0..11).map(|i| 5.0 + 2.5 * f64::from(i)).collect();
    let mean: Vec<(f64, f64)> = speeds
        .iter()
        .map(|&v| (v, 1.05 + 0.2 * (v / 30.0).powi(2)))
        .collect();
    let band = mean.iter().map(|&(v, m)| (v, m - 0.05, m + 0.08)).collect();
    let smooth = speeds.iter().map(|&v| (v, 1.0 + 0.002 * v)).collect();
    Chart::new("DLC = max F / F_static, road A", "speed (m/s)", "DLC")
        .with_series(Series::line_markers("front axle: mean, p5-p95", mean).with_band(band))
        .with_series(Series::line("smooth <&> \"quoted\"", smooth).with_dashed(true))
        .with_hline(1.33, "AASHTO 1.33")
}

#[test]
fn a_chart_shows_its_title_axis_labels_legend_and_reference_line() {
    let svg = demo_chart().to_svg().unwrap();
    assert!(svg.starts_with("<svg") && svg.trim_end().ends_with("</svg>"));
    let n = check_xml(&svg).unwrap();
    assert!(n > 50, "only {n} elements");
    let t = texts(&svg);
    for expected in [
        "DLC = max F / F_static, road A",
        "speed (m/s)",
        "DLC",
        "front axle: mean, p5-p95",
        "smooth <&> \"quoted\"",
        "AASHTO 1.33",
    ] {
        assert!(t.iter().any(|s| s == expected), "{expected:?} not in {t:?}");
    }
    // Escaped in the file itself.
    assert!(svg.contains("smooth &lt;&amp;&gt; &quot;quoted&quot;"));
    // Linear x ticks inside the data range, 1-2-5 steps.
    for tick in ["10", "15", "20", "25", "30"] {
        assert!(t.iter().any(|s| s == tick), "tick {tick} missing: {t:?}");
    }
    assert!(!svg.contains("NaN") && !svg.contains("inf"));
}

#[test]
fn every_point_of_a_series_is_drawn_and_a_band_is_shaded() {
    let chart = demo_chart();
    let svg = chart.to_svg().unwrap();
    // The solid first series is one polyline through its 11 points (plus the legend's two
    // sample segments), left to right, rising.
    let lines = polylines(&svg, BLUE);
    let main = lines
        .iter()
        .find(|l| l.len() == 11)
        .expect("an 11-point line");
    assert!(main.windows(2).all(|w| w[1].0 > w[0].0), "{main:?}");
    assert!(
        main.last().unwrap().1 < main[0].1,
        "pixel y falls as DLC rises"
    );
    // One circle marker per point, and one in the legend.
    assert_eq!(count(&svg, "<circle"), 11 + 1);
    // The band: one translucent polygon in the series' colour with 2 x 11 vertices.
    let polygon = svg
        .split("<polygon")
        .nth(1)
        .expect("a band polygon")
        .split('>')
        .next()
        .unwrap();
    assert!(polygon.contains(&format!("fill=\"{BLUE}\"")) && polygon.contains("opacity=\"0.2"));
    // 2 x 11 vertices, and the first again where the backend closes the outline.
    let start = polygon.find("points=\"").unwrap() + 8;
    let vertices = polygon[start..].split_whitespace().count();
    assert!((22..=23).contains(&vertices), "{vertices}");
    // The dashed series is drawn as dashes: many short pieces of line.
    assert!(polylines(&svg, ORANGE).len() > 10);
}

#[test]
fn a_log_axis_has_decade_ticks_and_skips_what_it_cannot_show() {
    let chart = Chart::new("error vs n", "n (masses or elements)", "relative error")
        .with_scales(Scale::Log10, Scale::Log10)
        .with_series(Series::line_markers(
            "lumped_mass",
            vec![
                (10.0, 1e-2),
                (20.0, 2e-3),
                (50.0, 0.0),
                (100.0, 1e-4),
                (200.0, f64::NAN),
                (500.0, 1e-5),
                (-3.0, 1.0),
            ],
        ));
    let svg = chart.to_svg().unwrap();
    check_xml(&svg).unwrap();
    let t = texts(&svg);
    for tick in ["1e-5", "1e-4", "0.001", "0.01", "100"] {
        assert!(t.iter().any(|s| s == tick), "tick {tick} missing: {t:?}");
    }
    // The zero, the NaN and the negative x break the line into runs of 2, 1 and 1 points;
    // each drawn point has its marker (circles: the first series), and the legend one.
    let runs: Vec<usize> = polylines(&svg, BLUE).iter().map(Vec::len).collect();
    assert!(
        runs.contains(&2) && !runs.iter().any(|&n| n > 2),
        "{runs:?}"
    );
    assert_eq!(count(&svg, "<circle"), 4 + 1);
    // Equal ratios are equal distances on a log axis: from x = 10 the decade to 100 spans
    // log10(10) / log10(2) = 3.32 times the step to 20 (1 px rounding on ~100 px: 0.1).
    let cx: Vec<i32> = svg
        .split("<circle")
        .skip(1)
        .map(|c| {
            let s = c.find("cx=\"").unwrap() + 4;
            c[s..s + c[s..].find('"').unwrap()].parse().unwrap()
        })
        .collect();
    let ratio = f64::from(cx[2] - cx[0]) / f64::from(cx[1] - cx[0]);
    assert!(
        (ratio - 10f64.log10() / 2f64.log10()).abs() < 0.1,
        "{ratio}"
    );
}

#[test]
fn a_narrow_log_range_still_gets_labelled_ticks() {
    // FE / lumped time ratios from 1.2 to 9: less than a decade.
    let chart = Chart::new("ratio", "n", "FE / lumped")
        .with_scales(Scale::Log10, Scale::Log10)
        .with_series(Series::line_markers(
            "paper's way",
            vec![(10.0, 2.5), (50.0, 5.0), (200.0, 9.0)],
        ))
        .with_series(Series::line_markers(
            "structure exploited",
            vec![(10.0, 1.2), (50.0, 1.6), (200.0, 1.25)],
        ));
    let svg = chart.to_svg().unwrap();
    let t = texts(&svg);
    let has = |tick: &str| t.iter().any(|s| s == tick);
    assert!(has("2") && (has("3") || has("4")), "{t:?}");
    // Every point has its marker (circles, then squares), and each legend entry one.
    assert_eq!(count(&svg, "<circle"), 3 + 1);
    // 3 squares and the legend one (plus the background and the legend box).
    assert!(count(&svg, "<rect") >= 4);
}

#[test]
fn a_fixed_range_and_reference_lines_outside_it() {
    let chart = Chart::new("zoom", "x (m)", "y (mm)")
        .with_y_range(-1.0, 1.0)
        .with_series(Series::line(
            "sine",
            (0..200)
                .map(|i| (f64::from(i) * 0.05, 2.0 * (f64::from(i) * 0.05).sin()))
                .collect(),
        ))
        .with_hline(0.5, "limit")
        .with_hline(0.55, "other limit")
        .with_hline(7.0, "off-range");
    let svg = chart.to_svg().unwrap();
    let t = texts(&svg);
    assert!(t.iter().any(|s| s == "limit") && t.iter().any(|s| s == "other limit"));
    assert!(!t.iter().any(|s| s == "off-range"));
    assert!(t.iter().any(|s| s == "0"), "{t:?}");
    // Points above 1 or below -1 are not drawn: the sine is cut into pieces.
    assert!(polylines(&svg, BLUE).len() >= 4);
}

#[test]
fn empty_and_degenerate_charts_render() {
    let empty = Chart::new("nothing", "x", "y").with_series(Series::line("empty", vec![]));
    let svg = empty.to_svg().unwrap();
    check_xml(&svg).unwrap();
    assert!(texts(&svg).iter().any(|s| s == "no data"));
    check_xml(&Chart::default().to_svg().unwrap()).unwrap();
    let single = Chart::default().with_series(Series::line("one", vec![(3.0, 3.0)]));
    let svg = single.to_svg().unwrap();
    // A lone point of a line gets a marker so that it shows (and the legend has none).
    assert_eq!(count(&svg, "<circle"), 1);
    let tiny = Chart::default().with_size(10, 10).with_series(Series::line(
        "a very long legend entry that cannot fit anywhere",
        vec![(0.0, 0.0), (1.0, 1.0)],
    ));
    check_xml(&tiny.to_svg().unwrap()).unwrap();
}

#[test]
fn a_grid_places_every_chart_under_its_title() {
    let charts: Vec<Chart> = ["smooth", "A", "B", "C"]
        .iter()
        .enumerate()
        .map(|(k, class)| {
            Chart::new(format!("road {class}"), "speed (m/s)", "DLC")
                .with_size(480, 320)
                .with_series(Series::line_markers(
                    "front axle",
                    (0..8)
                        .map(|i| {
                            (
                                5.0 + 2.5 * f64::from(i),
                                1.0 + 0.02 * k as f64 * f64::from(i),
                            )
                        })
                        .collect(),
                ))
        })
        .collect();
    let svg = Figure::grid(2, 2, &charts).unwrap();
    check_xml(&svg).unwrap();
    assert!(
        svg.contains(r#"width="960" height="640""#),
        "{}",
        &svg[..200]
    );
    let t = texts(&svg);
    for class in ["smooth", "A", "B", "C"] {
        assert!(t.iter().any(|s| s == &format!("road {class}")));
    }
    assert_eq!(t.iter().filter(|s| *s == "speed (m/s)").count(), 4);
    // Too many charts for the cells: rows are added; the overall title takes 40 px.
    let svg = Figure::grid_titled("All classes", 1, 2, &charts).unwrap();
    assert!(svg.contains(r#"height="680""#));
    assert!(texts(&svg).iter().any(|s| s == "All classes"));
    check_xml(&Figure::grid(0, 0, &[]).unwrap()).unwrap();
}

#[test]
fn same_chart_same_bytes() {
    assert_eq!(
        demo_chart().to_svg().unwrap(),
        demo_chart().to_svg().unwrap()
    );
    let grid = || Figure::grid(1, 2, &[demo_chart(), demo_chart()]).unwrap();
    assert_eq!(grid(), grid());
}

#[test]
fn tick_labels_are_compact() {
    for (v, text) in [
        (0.001, "0.001"),
        (1e-4, "1e-4"),
        (2.5e-6, "2.5e-6"),
        (12.5, "12.5"),
        (0.30000000000000004, "0.3"),
        (20.0, "20"),
        (10000.0, "10000"),
        (1e5, "1e5"),
        (-0.0, "0"),
        (-3e6, "-3e6"),
        (1e-17, "0"),
    ] {
        assert_eq!(tick_label(v), text, "{v}");
    }
}

/// Writes the demo chart to $BRIDGETWIN_PLOT_DEMO_DIR, for looking at it (what the chart
/// must show is checked by `a_chart_shows_its_title_axis_labels_legend_and_reference_line`):
/// `BRIDGETWIN_PLOT_DEMO_DIR=/tmp/plot cargo test --release --lib demo_figure -- --ignored`.
#[test]
#[ignore = "writes a file for a person to look at; needs BRIDGETWIN_PLOT_DEMO_DIR"]
fn demo_figure() {
    let dir = std::env::var("BRIDGETWIN_PLOT_DEMO_DIR")
        .expect("BRIDGETWIN_PLOT_DEMO_DIR names the folder for plot_demo.svg");
    let path = std::path::Path::new(&dir).join("plot_demo.svg");
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(path, demo_chart().to_svg().unwrap()).unwrap();
}
