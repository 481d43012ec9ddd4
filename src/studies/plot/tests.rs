use super::*;

/// Checks that `svg` is a well-formed XML element tree: every start tag is closed by the
/// matching end tag, quotes are balanced, no stray `<` or `&` appears in text, and there is
/// exactly one root element, `svg`. Returns the number of elements.
fn check_xml(svg: &str) -> Result<usize, String> {
    let bytes = svg.as_bytes();
    let mut stack: Vec<String> = Vec::new();
    let mut roots = 0;
    let mut elements = 0;
    let mut i = 0;
    while i < bytes.len() {
        match bytes[i] {
            b'<' => {
                let end = svg[i..]
                    .find('>')
                    .map(|e| i + e)
                    .ok_or_else(|| format!("unterminated tag at byte {i}"))?;
                let tag = &svg[i + 1..end];
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

fn demo_chart() -> Chart {
    let speeds: Vec<f64> = (0..13).map(|i| 20.0 + 10.0 * f64::from(i)).collect();
    let median: Vec<(f64, f64)> = speeds
        .iter()
        .map(|&v| (v, 1.05 + 0.2 * (v / 140.0).powi(2) + 0.03 * (v / 9.0).sin()))
        .collect();
    let band: Vec<(f64, f64, f64)> = median
        .iter()
        .map(|&(v, m)| (v, m - 0.04 - 0.0006 * v, m + 0.05 + 0.0008 * v))
        .collect();
    let smooth: Vec<(f64, f64)> = speeds
        .iter()
        .map(|&v| (v, 1.0 + 0.05 * (v / 140.0)))
        .collect();
    Chart::new(
        "Dynamic load coefficient vs speed",
        "speed [km/h]",
        "DLC [-]",
    )
    .with_series(Series::line_markers("class A (median, 5-95 %)", median).with_band(band))
    .with_series(Series::line("smooth road", smooth).with_dashed(true))
    .with_series(Series::markers(
        "measured <&> \"quoted\"",
        vec![(45.0, 1.1), (80.0, 1.16), (f64::NAN, 1.0), (120.0, 1.25)],
    ))
    .with_hline(1.4, "code limit 1.4")
}

#[test]
fn chart_svg_is_well_formed() {
    let svg = demo_chart().to_svg();
    assert!(svg.starts_with("<svg"), "{}", &svg[..40]);
    assert!(svg.ends_with("</svg>"));
    let n = check_xml(&svg).unwrap();
    assert!(n > 50, "only {n} elements");
    assert!(svg.contains("&lt;&amp;&gt; &quot;quoted&quot;"));
    assert!(!svg.contains("NaN") && !svg.contains("inf"));
}

#[test]
fn the_checker_rejects_broken_xml() {
    assert!(check_xml("<svg><g></svg>").is_err());
    assert!(check_xml("<svg><g/></svg><svg></svg>").is_err());
    assert!(check_xml("<svg>a & b</svg>").is_err());
    assert!(check_xml("<svg><text>1 < 2</text></svg>").is_err());
    assert!(check_xml("<svg><g/></svg>").is_ok());
}

#[test]
fn same_input_same_bytes() {
    let a = demo_chart().to_svg();
    let b = demo_chart().to_svg();
    assert_eq!(a, b);
    let grid = |c: &Chart| Figure::grid(1, 2, &[c.clone(), c.clone()]);
    assert_eq!(grid(&demo_chart()), grid(&demo_chart()));
}

#[test]
fn linear_ticks_are_sensible() {
    for (lo, hi) in [
        (0.013, 0.87),
        (0.0, 1.0),
        (-3.7, 12.2),
        (1e-5, 3e-1),
        (990.0, 1010.0),
        (-1e7, 2e7),
        (2.5e-6, 7.1e-6),
    ] {
        let t = linear_ticks(lo, hi, 8);
        let n = t.major.len();
        assert!(
            (3..=10).contains(&n),
            "[{lo}, {hi}]: {n} ticks {:?}",
            t.major
        );
        assert_eq!(t.labels.len(), n);
        for &v in &t.major {
            assert!(v >= lo && v <= hi, "[{lo}, {hi}]: tick {v} outside");
        }
        // Evenly spaced by a 1-2-5 step.
        let step = t.major[1] - t.major[0];
        let mantissa = step / 10f64.powf(step.log10().floor());
        assert!(
            [1.0, 2.0, 5.0].iter().any(|m| (mantissa - m).abs() < 1e-6),
            "step {step}"
        );
        for w in t.major.windows(2) {
            assert!(((w[1] - w[0]) - step).abs() < 1e-9 * step.abs().max(1.0));
        }
        // Distinct labels.
        let mut labels = t.labels.clone();
        labels.dedup();
        assert_eq!(labels.len(), n, "{:?}", t.labels);
    }
    let t = linear_ticks(0.013, 0.87, 8);
    assert_eq!(t.major, vec![0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8]);
    assert_eq!(
        t.labels,
        ["0.1", "0.2", "0.3", "0.4", "0.5", "0.6", "0.7", "0.8"]
    );
    let t = linear_ticks(0.013, 0.87, 5);
    assert_eq!(t.labels, ["0.2", "0.4", "0.6", "0.8"]);
    let t = linear_ticks(-1.0, 1.0, 5);
    assert_eq!(t.labels, ["-1.0", "-0.5", "0.0", "0.5", "1.0"]);
    let t = linear_ticks(2.5e-6, 7.1e-6, 6);
    assert_eq!(t.labels, ["3e-6", "4e-6", "5e-6", "6e-6", "7e-6"]);
    let t = linear_ticks(0.0, 120.0, 7);
    assert_eq!(t.labels, ["0", "20", "40", "60", "80", "100", "120"]);
}

#[test]
fn degenerate_tick_ranges_do_not_panic() {
    assert_eq!(linear_ticks(2.0, 2.0, 5).major, vec![2.0]);
    assert!(linear_ticks(f64::NAN, 1.0, 5).major.is_empty());
    assert!(log10_ticks(0.0, 1.0, 5).major.is_empty());
    assert!(log10_ticks(-1.0, 1.0, 5).major.is_empty());
    let t = linear_ticks(1.0, 0.0, 6);
    assert!(t.major.len() >= 3);
    let t = log10_ticks(2.0, 2.5, 6);
    assert!(t.major.len() >= 2 && t.major.iter().all(|&v| (2.0..=2.5).contains(&v)));
}

#[test]
fn log_ticks_are_sensible() {
    let (lo, hi) = (1e-5, 3e-1);
    let t = log10_ticks(lo, hi, 8);
    assert_eq!(t.major.len(), 5);
    assert_eq!(t.labels, ["1e-5", "1e-4", "0.001", "0.01", "0.1"]);
    for (v, e) in t.major.iter().zip(-5..) {
        assert!((v.log10() - f64::from(e)).abs() < 1e-12);
    }
    // Minor ticks at 2..9 per decade, inside the range.
    assert!(t.minor.iter().all(|&v| v >= lo && v <= hi));
    assert!(t.minor.iter().any(|&v| (v - 2e-5).abs() < 1e-18));
    assert!(t.minor.iter().any(|&v| (v - 0.3).abs() < 1e-12));
    assert_eq!(t.minor.len(), 4 * 8 + 2);

    for (lo, hi) in [
        (1e-5, 3e-1),
        (0.5, 20.0),
        (2.0, 8.0),
        (1e-12, 1e12),
        (3.0, 3000.0),
    ] {
        let t = log10_ticks(lo, hi, 8);
        let n = t.major.len();
        assert!((3..=10).contains(&n), "[{lo}, {hi}]: {:?}", t.major);
        assert!(t
            .major
            .iter()
            .all(|&v| v >= lo * (1.0 - 1e-12) && v <= hi * (1.0 + 1e-12)));
        assert!(t.major.windows(2).all(|w| w[0] < w[1]));
    }
    // Many decades: every other (or third ...) decade labelled, the rest minor.
    let t = log10_ticks(1e-12, 1e12, 8);
    assert!(t.major.len() <= 8);
    assert_eq!(t.labels[0], "1e-12");
    assert_eq!(
        log10_ticks(0.5, 20.0, 8).labels,
        ["0.5", "1", "2", "5", "10", "20"]
    );
}

#[test]
fn compact_formatting() {
    assert_eq!(format_compact(0.001), "0.001");
    assert_eq!(format_compact(1e-4), "1e-4");
    assert_eq!(format_compact(2.5e-4), "2.5e-4");
    assert_eq!(format_compact(12.5), "12.5");
    assert_eq!(format_compact(10000.0), "10000");
    assert_eq!(format_compact(1e5), "1e5");
    assert_eq!(format_compact(-0.0), "0");
    assert_eq!(format_compact(-3e6), "-3e6");
}

#[test]
fn log_axis_skips_non_positive_and_non_finite_points() {
    let chart = Chart::new("log", "f [Hz]", "PSD")
        .with_scales(Scale::Log10, Scale::Log10)
        .with_series(Series::line_markers(
            "",
            vec![
                (0.0, 1.0),
                (1.0, 1e-3),
                (2.0, -1.0),
                (3.0, 1e-4),
                (f64::INFINITY, 1.0),
                (10.0, 1e-5),
                (-5.0, 1.0),
                (20.0, f64::NAN),
            ],
        ));
    let svg = chart.to_svg();
    check_xml(&svg).unwrap();
    assert!(!svg.contains("NaN") && !svg.contains("inf"));
    // Three drawable points, each isolated between undrawable ones: three markers (circles,
    // the first shape) and no line segment through the skipped points.
    assert_eq!(svg.matches("<circle").count(), 3, "{svg}");
    assert!(!svg.contains("stroke-linejoin"));
    // The range came from the positive data only.
    assert!(
        svg.contains(">1e\u{2212}5<") || svg.contains(">0.0001<"),
        "{svg}"
    );
}

#[test]
fn empty_series_and_empty_charts_render() {
    let empty = Chart::new("nothing", "x", "y").with_series(Series::line("empty", vec![]));
    let svg = empty.to_svg();
    check_xml(&svg).unwrap();
    assert!(svg.contains("no data"));
    let bare = Chart::default();
    check_xml(&bare.to_svg()).unwrap();
    let log = Chart::default()
        .with_scales(Scale::Log10, Scale::Log10)
        .with_series(Series::markers(
            "only bad",
            vec![(-1.0, 0.0), (f64::NAN, 2.0)],
        ));
    check_xml(&log.to_svg()).unwrap();
    let single = Chart::default().with_series(Series::line("one", vec![(3.0, 3.0)]));
    let svg = single.to_svg();
    check_xml(&svg).unwrap();
    assert_eq!(svg.matches("<circle").count(), 1);
    let tiny = Chart::default().with_size(10, 10).with_series(Series::line(
        "a very long legend entry that cannot fit anywhere",
        vec![(0.0, 0.0), (1.0, 1.0)],
    ));
    check_xml(&tiny.to_svg()).unwrap();
}

#[test]
fn fixed_ranges_and_hlines() {
    let chart = Chart::new("zoom", "x", "y")
        .with_x_range(0.0, 10.0)
        .with_y_range(-1.0, 1.0)
        .with_series(Series::line(
            "sine",
            (0..1000)
                .map(|i| (f64::from(i) * 0.05, (f64::from(i) * 0.05).sin()))
                .collect(),
        ))
        .with_hline(0.5, "limit")
        .with_hline(0.55, "other limit")
        .with_hline(7.0, "off-range");
    let svg = chart.to_svg();
    check_xml(&svg).unwrap();
    assert!(svg.contains(">limit<") && svg.contains(">other limit<"));
    assert!(!svg.contains(">off-range<"));
    assert!(svg.contains(">\u{2212}1.0<") && svg.contains(">1.0<"));
}

#[test]
fn dense_lines_are_thinned_without_losing_extremes() {
    let n = 200_000;
    let points: Vec<(f64, f64)> = (0..n)
        .map(|i| {
            let x = f64::from(i) / f64::from(n);
            (x, (x * 3000.0).sin() + if i == 123_457 { 5.0 } else { 0.0 })
        })
        .collect();
    let chart = Chart::new("dense", "t", "y").with_series(Series::line("signal", points));
    let svg = chart.to_svg();
    check_xml(&svg).unwrap();
    assert!(svg.len() < 200_000, "{} bytes", svg.len());
    // The spike sets the range and is still drawn: the line reaches the top of the data,
    // 4 % of the plot height below the top of the plot box.
    let attr = |tag: &str, name: &str| -> f64 {
        let i = svg.find(tag).unwrap();
        let j = i + svg[i..].find(&format!(" {name}=\"")).unwrap() + name.len() + 3;
        svg[j..j + svg[j..].find('"').unwrap()].parse().unwrap()
    };
    let (top, height) = (attr("<clipPath", "y"), attr("<clipPath", "height"));
    let i = svg.find("<path d=\"M").unwrap() + 10;
    let d = &svg[i..i + svg[i..].find('"').unwrap()];
    let min_y = d
        .split(['M', 'L'])
        .filter(|p| !p.is_empty())
        .map(|p| p.split(',').nth(1).unwrap().parse::<f64>().unwrap())
        .fold(f64::INFINITY, f64::min);
    let expected = top + height * 0.04 / 1.08;
    assert!(
        (min_y - expected).abs() < 1.0,
        "top of line at {min_y}, expected {expected}"
    );
}

#[test]
fn figure_grid_places_sub_figures() {
    let charts: Vec<Chart> = ["smooth", "A", "B", "C"]
        .iter()
        .enumerate()
        .map(|(k, class)| {
            Chart::new(format!("class {class}"), "speed [km/h]", "DLC [-]")
                .with_size(480, 320)
                .with_series(Series::line_markers(
                    "DLC",
                    (0..8)
                        .map(|i| {
                            (
                                20.0 + 15.0 * f64::from(i),
                                1.0 + 0.02 * k as f64 * f64::from(i),
                            )
                        })
                        .collect(),
                ))
        })
        .collect();
    let svg = Figure::grid(2, 2, &charts);
    assert!(svg.starts_with("<svg") && svg.ends_with("</svg>"));
    check_xml(&svg).unwrap();
    assert!(svg.contains(r#"width="960" height="640""#));
    assert_eq!(svg.matches("<clipPath").count(), 4);
    // Clip ids are unique.
    let mut ids: Vec<&str> = svg
        .match_indices("<clipPath id=\"")
        .map(|(i, _)| &svg[i + 15..i + 15 + svg[i + 15..].find('"').unwrap_or(0)])
        .collect();
    ids.sort_unstable();
    ids.dedup();
    assert_eq!(ids.len(), 4);
    // Too many charts for the cells: rows are added.
    let svg = Figure::grid_titled("All classes", 1, 2, &charts);
    check_xml(&svg).unwrap();
    assert!(svg.contains(r#"height="680""#));
    check_xml(&Figure::grid(0, 0, &[])).unwrap();
}

#[test]
fn write_svg_creates_directories() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("figs/demo.svg");
    demo_chart().write_svg(&path).unwrap();
    let text = std::fs::read_to_string(&path).unwrap();
    assert_eq!(text, demo_chart().to_svg() + "\n");
}

/// Writes demo figures to $BRIDGETWIN_PLOT_DEMO_DIR (for looking at them); a no-op otherwise.
#[test]
fn demo_figures() {
    let Ok(dir) = std::env::var("BRIDGETWIN_PLOT_DEMO_DIR") else {
        return;
    };
    let dir = std::path::PathBuf::from(dir);
    write_svg(dir.join("plot_demo.svg"), &demo_chart().to_svg()).unwrap();

    let freq: Vec<f64> = (0..400)
        .map(|i| 10f64.powf(-1.0 + f64::from(i) * 0.01))
        .collect();
    let psd = |c: f64| -> Vec<(f64, f64)> {
        freq.iter()
            .map(|&n| (n, c * 1e-6 * (n / 0.1).powf(-2.0)))
            .collect()
    };
    let log = Chart::new(
        "Road profile PSD (ISO 8608)",
        "spatial frequency n [cycles/m]",
        "G_d(n) [m³]",
    )
    .with_scales(Scale::Log10, Scale::Log10)
    .with_series(Series::line("class A", psd(16.0)))
    .with_series(Series::line("class B", psd(64.0)))
    .with_series(Series::line("class C", psd(256.0)).with_dashed(true))
    .with_series(Series::markers(
        "measured",
        (0..25)
            .map(|i| {
                let n = 10f64.powf(-0.9 + f64::from(i) * 0.15);
                (
                    n,
                    64e-6 * (n / 0.1).powf(-2.0) * (1.0 + 0.4 * (f64::from(i) * 1.7).sin()),
                )
            })
            .collect(),
    ));
    write_svg(dir.join("plot_log.svg"), &log.to_svg()).unwrap();

    let classes = ["smooth", "A", "B", "C"];
    let charts: Vec<Chart> = classes
        .iter()
        .enumerate()
        .map(|(k, class)| {
            let amp = 0.02 * (k as f64 + 0.3);
            let mut chart = Chart::new(format!("class {class}"), "speed [km/h]", "DLC [-]")
                .with_size(520, 340)
                .with_y_range(0.9, 1.6)
                .with_hline(1.4, "EN 1991-2 limit");
            for (j, axles) in [2, 3, 5].iter().enumerate() {
                let pts: Vec<(f64, f64)> = (0..15)
                    .map(|i| {
                        let v = 20.0 + 10.0 * f64::from(i);
                        (
                            v,
                            1.0 + amp * (1.0 + j as f64 * 0.5) * (v / 40.0)
                                + 0.02 * (v / 13.0).sin(),
                        )
                    })
                    .collect();
                let band = pts
                    .iter()
                    .map(|&(v, m)| (v, m - amp, m + 1.5 * amp))
                    .collect();
                let mut s = Series::line_markers(format!("{axles}-axle truck"), pts);
                if j == 0 {
                    s = s.with_band(band);
                }
                chart = chart.with_series(s);
            }
            chart
        })
        .collect();
    // Stress: many series, negative values, scientific labels, a dense time history.
    let mut many = Chart::new("Ten series", "time [s]", "deflection [m]").with_size(640, 400);
    for k in 0..10 {
        let pts = (0..60)
            .map(|i| {
                let t = f64::from(i) * 0.05;
                (
                    t,
                    1e-6 * (k as f64 - 4.5) * (1.0 + (t * 2.0 + k as f64).sin()),
                )
            })
            .collect();
        let style = [Style::Line, Style::LineMarkers, Style::Markers][k % 3];
        many = many.with_series(Series::new(format!("series {k}"), pts, style).with_dashed(k >= 7));
    }
    write_svg(dir.join("plot_many.svg"), &many.to_svg()).unwrap();
    let n = 50_000;
    let history: Vec<(f64, f64)> = (0..n)
        .map(|i| {
            let t = f64::from(i) * 2e-4;
            let y = -12.0 * (-(t - 4.0).powi(2) / 2.0).exp() * (1.0 + 0.2 * (t * 40.0).sin())
                + 0.5 * (t * 97.0).sin();
            (t, if i % 9973 == 0 { f64::NAN } else { y })
        })
        .collect();
    let history = Chart::new(
        "Midspan deflection, truck at 80 km/h",
        "time [s]",
        "deflection [mm]",
    )
    .with_size(800, 320)
    .with_series(Series::line("simulated", history))
    .with_hline(-10.0, "SLS limit L/600")
    .with_hline(-12.5, "design");
    write_svg(dir.join("plot_history.svg"), &history.to_svg()).unwrap();

    write_svg(
        dir.join("plot_grid.svg"),
        &Figure::grid_titled("Dynamic load coefficient vs speed", 2, 2, &charts),
    )
    .unwrap();
}
