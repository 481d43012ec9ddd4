//! Road profiles: ISO 8608 statistics against the closed forms of docs/physics.md section 7,
//! deterministic shapes, CSV input/output and configuration errors.

use bridgetwin::base::signal::{welch_psd, WelchPsd};
use bridgetwin::physics::road::{
    iso8608_band_rms_m, iso8608_psd_m3, IsoClass, RoadFeature, RoadProfile, RoadProfileSpec,
};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

const DX_M: f64 = 0.05;
const N1: f64 = 0.01;
const N2: f64 = 4.0;

fn rng(seed: u64) -> ChaCha8Rng {
    ChaCha8Rng::seed_from_u64(seed)
}

/// Elevation at the profile's own samples, spacing `DX_M` from `x_start_m`.
fn samples(profile: &RoadProfile) -> Vec<f64> {
    profile.sample_points().map(|(_, z)| z).collect()
}

fn iso(class: IsoClass) -> RoadProfileSpec {
    RoadProfileSpec::iso8608(class)
}

fn with_features(mut spec: RoadProfileSpec, extra: Vec<RoadFeature>) -> RoadProfileSpec {
    if let RoadProfileSpec::Iso8608 { features, .. } = &mut spec {
        *features = extra;
    }
    spec
}

#[test]
fn rms_of_each_class_matches_the_band_integral() {
    // The synthesis is exact in mean square over a full FFT period (unit test in
    // `road::iso8608`); a road is a window of half a period or less, whose mean square
    // varies. For a stationary process with one-sided PSD G the relative variance of the
    // mean square over a window T is ~ (1/T) int G^2 dn / (int G dn)^2 (Gaussian
    // approximation; a random-phase sum with fixed amplitudes varies a little less). For
    // G ~ n^-2 on [n1, n2] that is (1/3)(1/n1^3 - 1/n2^3) / (T (1/n1 - 1/n2)^2), i.e.
    // sd ~ 1 / sqrt(3 T n1) = 8.2 % for T = 5 km. Each class's mean of K = 32 windows must
    // be within 4 sd / sqrt(K) = 5.8 % in mean square (2.9 % in RMS), and the pooled mean
    // of all 128 within 4 sd / sqrt(128) = 2.9 % (1.5 % in RMS): a false failure has
    // p ~ 6e-5; a missing sqrt(2) or a wrong bin width (>= 40 %) cannot pass.
    let (length_m, k) = (5000.0, 32);
    let rel_var_one =
        (1.0 / 3.0) * (N1.powi(-3) - N2.powi(-3)) / (length_m * (1.0 / N1 - 1.0 / N2).powi(2));
    let tolerance = 4.0 * (rel_var_one / k as f64).sqrt();
    let mut pooled = Vec::new();
    for (i, class) in [IsoClass::A, IsoClass::B, IsoClass::C, IsoClass::D]
        .into_iter()
        .enumerate()
    {
        let target_m = iso8608_band_rms_m(class.gd_n0_m3(), N1, N2);
        let mut ratios = Vec::new();
        for r in 0..k {
            let p = RoadProfile::build(&iso(class), 0.0, length_m, &mut rng(1000 * i as u64 + r))
                .unwrap();
            assert_eq!(p.band_rms_m(), Some(target_m));
            let z = samples(&p);
            let ms = z.iter().map(|v| v * v).sum::<f64>() / z.len() as f64;
            ratios.push(ms / (target_m * target_m));
        }
        let ratio = ratios.iter().sum::<f64>() / k as f64;
        let sd_one =
            (ratios.iter().map(|m| (m - ratio).powi(2)).sum::<f64>() / (k - 1) as f64).sqrt();
        println!(
            "class {:?}: RMS {:.3} mm vs target {:.3} mm (mean-square ratio {ratio:.4}, \
             tolerance {tolerance:.4}; per-road sd {sd_one:.3}, predicted {:.3})",
            class,
            1e3 * (ratio * target_m * target_m).sqrt(),
            1e3 * target_m,
            rel_var_one.sqrt()
        );
        assert!((ratio - 1.0).abs() < tolerance, "class {class:?}: {ratio}");
        pooled.extend(ratios);
    }
    let pooled_ratio = pooled.iter().sum::<f64>() / pooled.len() as f64;
    let pooled_tolerance = 4.0 * (rel_var_one / pooled.len() as f64).sqrt();
    println!("all classes: mean-square ratio {pooled_ratio:.4} (tolerance {pooled_tolerance:.4})");
    assert!(
        (pooled_ratio - 1.0).abs() < pooled_tolerance,
        "{pooled_ratio}"
    );
}

#[test]
fn welch_psd_matches_the_target_in_band_and_is_empty_outside() {
    // K = 16 realisations of 4 km (80 000 samples), Welch segments of 4096 samples
    // (df = 4.9e-3 cycle/m), 38 segments each: 608 periodograms. With Hann and 50 %
    // overlap the variance of the average is (1 + 2 * 0.167^2) / 608 (Welch 1967), so
    // each bin is a chi-square estimate with relative sd sigma = 4.2 %.
    let (length_m, k, seg) = (4000.0, 16, 4096);
    let class = IsoClass::B;
    let gd = class.gd_n0_m3();
    let mut total: Option<WelchPsd> = None;
    for r in 0..k {
        let p =
            RoadProfile::build(&iso(class), -100.0, length_m - 100.0, &mut rng(77 + r)).unwrap();
        let psd = welch_psd(&samples(&p), DX_M, seg).unwrap();
        match &mut total {
            None => total = Some(psd),
            Some(t) => t.merge(&psd).unwrap(),
        }
    }
    let psd = total.unwrap();
    assert_eq!(psd.segments, 16 * 38);
    let sigma = ((1.0 + 2.0 * 0.167f64.powi(2)) / psd.segments as f64).sqrt();
    let df = psd.frequencies[0];

    // In band: from bin 10 (the Hann window smooths the n^-2 spectrum, a relative bias
    // of (df / n)^2 (second moment of the Hann kernel is df^2 / 3), 1 % at bin 10) to
    // 3 bins below n2 (the main lobe straddles the band edge there).
    let mut deviations = Vec::new();
    for (&n, &g) in psd.frequencies.iter().zip(&psd.density) {
        if n < 10.0 * df || n > N2 - 3.0 * df {
            continue;
        }
        let ratio = g / iso8608_psd_m3(gd, n);
        let bias = (df / n).powi(2);
        // 5 sigma per bin: ~800 bins, P(any false failure) ~ 800 * 6e-7 = 5e-4.
        assert!(
            (ratio - 1.0).abs() < 5.0 * sigma + bias,
            "n = {n}: ratio {ratio} (sigma {sigma})"
        );
        deviations.push(ratio - 1.0);
    }
    let bins = deviations.len() as f64;
    let mean_dev = deviations.iter().sum::<f64>() / bins;
    let rms_dev = (deviations.iter().map(|d| d * d).sum::<f64>() / bins).sqrt();
    let max_dev = deviations.iter().fold(0.0f64, |m, d| m.max(d.abs()));
    // Band mean: adjacent Hann bins are correlated, so count a third of the bins as
    // independent; 5 sigma of that mean plus the largest bias (1 %) averaged over the
    // bins (< 0.02 %).
    let mean_tol = 5.0 * sigma / (bins / 3.0).sqrt() + 2e-4;
    println!(
        "PSD fit over {bins} bins in [{:.3}, {:.3}] cycle/m: mean ratio - 1 = {mean_dev:.4} \
         (tolerance {mean_tol:.4}), rms {rms_dev:.4} (chi-square sigma {sigma:.4}), max \
         {max_dev:.4}",
        10.0 * df,
        N2 - 3.0 * df
    );
    assert!(mean_dev.abs() < mean_tol, "{mean_dev}");
    // The scatter is the estimator's: its rms is sigma (plus the small bias), not more.
    assert!(rms_dev < 1.2 * sigma, "{rms_dev}");

    // Out of band (above n2 + 4 df): only Hann sidelobe leakage, whose power falls as
    // d^-6 with the distance d in bins, ~ G(n2) / (5 pi^2 d^5) ~ 2e-5 G(n2) at d = 4.
    let g_edge = iso8608_psd_m3(gd, N2);
    let worst_out = psd
        .frequencies
        .iter()
        .zip(&psd.density)
        .filter(|(&n, _)| n > N2 + 4.0 * df)
        .fold(0.0f64, |m, (_, &g)| m.max(g / g_edge));
    println!("largest PSD above n2 + 4 df: {worst_out:.2e} G_d(n2)");
    assert!(worst_out < 1e-3, "{worst_out}");
}

#[test]
fn explicit_gd_overrides_class_and_describe_says_which() {
    let explicit = RoadProfileSpec::Iso8608 {
        class: Some(IsoClass::A),
        gd_n0_m3: Some(256e-6),
        n1_cycles_m: N1,
        n2_cycles_m: N2,
        tyre_patch_filter_m: None,
        sample_spacing_m: DX_M,
        features: Vec::new(),
    };
    let a = RoadProfile::build(&explicit, -50.0, 80.0, &mut rng(5)).unwrap();
    let c = RoadProfile::build(&iso(IsoClass::C), -50.0, 80.0, &mut rng(5)).unwrap();
    // Same phases, same G_d(n0) = class C's: identical samples.
    assert_eq!(samples(&a), samples(&c));
    assert!(
        a.describe().contains("explicit G_d(n0) = 2.56e-4 m^3"),
        "{}",
        a.describe()
    );
    assert!(
        c.describe()
            .starts_with("ISO 8608 class C, G_d(n0) = 256e-6 m^3 (geometric mean of class)"),
        "{}",
        c.describe()
    );
    assert!(
        c.describe().contains("n in [0.01, 4] cycle/m"),
        "{}",
        c.describe()
    );
}

#[test]
fn same_seed_same_profile_different_seed_different() {
    let spec = iso(IsoClass::B);
    let a = RoadProfile::build(&spec, -100.0, 60.0, &mut rng(42)).unwrap();
    let b = RoadProfile::build(&spec, -100.0, 60.0, &mut rng(42)).unwrap();
    let c = RoadProfile::build(&spec, -100.0, 60.0, &mut rng(43)).unwrap();
    assert_eq!(a.to_csv(), b.to_csv());
    let (za, zc) = (samples(&a), samples(&c));
    assert_eq!(za.len(), zc.len());
    let differ = za.iter().zip(&zc).filter(|(x, y)| x != y).count();
    assert!(differ > za.len() / 2, "{differ} of {}", za.len());
}

#[test]
fn range_covers_the_request_and_clamps_outside() {
    let p = RoadProfile::build(&iso(IsoClass::C), -120.0, 30.01, &mut rng(1)).unwrap();
    let (lo, hi) = p.x_range_m();
    assert_eq!(lo, -120.0);
    // One sample spacing at most past the requested end.
    assert!((30.01..30.01 + DX_M).contains(&hi), "{hi}");
    // ceil(150.01 / 0.05) = 3001 intervals.
    assert_eq!(p.sample_count(), 3002);
    // Clamped, not zero: the end values hold, with zero slope.
    assert_eq!(p.elevation_m(-500.0), p.elevation_m(lo));
    assert_eq!(p.elevation_m(1e6), p.elevation_m(hi));
    assert_ne!(p.elevation_m(lo), 0.0);
    assert_eq!(p.slope(-500.0), 0.0);
    assert!(p.contains(0.0) && !p.contains(hi + 1e-9));
}

#[test]
fn step_ramp_and_bump_are_exact() {
    let step = RoadProfileSpec::Step {
        position_m: 0.013,
        height_m: 0.02,
    };
    let p = RoadProfile::build(&step, -10.0, 40.0, &mut rng(0)).unwrap();
    assert_eq!(p.elevation_m(0.0129999), 0.0);
    assert_eq!(p.elevation_m(0.013), 0.02);
    assert_eq!(p.elevation_m(39.0), 0.02);
    assert_eq!(p.slope(0.5), 0.0);
    assert!(p.describe().contains("step of 0.02 m at x = 0.013 m"));

    let ramp = RoadProfileSpec::Ramp {
        start_m: 2.0,
        length_m: 4.0,
        height_m: -0.01,
    };
    let p = RoadProfile::build(&ramp, -10.0, 40.0, &mut rng(0)).unwrap();
    assert_eq!(p.elevation_m(1.0), 0.0);
    assert_eq!(p.elevation_m(3.0), -0.0025);
    assert_eq!(p.slope(3.0), -0.0025);
    assert_eq!(p.elevation_m(7.0), -0.01);

    let bump = RoadProfileSpec::Bump {
        position_m: 1.0,
        length_m: 0.5,
        height_m: 0.03,
    };
    let p = RoadProfile::build(&bump, -10.0, 40.0, &mut rng(0)).unwrap();
    for x in [0.8, 0.9, 1.0, 1.1, 1.2] {
        let u: f64 = 2.0 * std::f64::consts::PI * (x - 1.0) / 0.5;
        let expected = 0.015 * (1.0 + u.cos());
        // Closed form, so only rounding: 1e-15 m.
        assert!((p.elevation_m(x) - expected).abs() < 1e-15, "x {x}");
    }
    assert_eq!(p.elevation_m(0.75), 0.0);
    assert_eq!(p.elevation_m(1.3), 0.0);
}

#[test]
fn features_add_exactly_on_top_of_a_random_profile() {
    let feats = vec![
        RoadFeature::Step {
            position_m: 0.0,
            height_m: 0.01,
        },
        RoadFeature::Bump {
            position_m: 30.0,
            length_m: 2.0,
            height_m: -0.005,
        },
    ];
    let plain = RoadProfile::build(&iso(IsoClass::B), -20.0, 40.0, &mut rng(9)).unwrap();
    let spec = with_features(iso(IsoClass::B), feats.clone());
    let both = RoadProfile::build(&spec, -20.0, 40.0, &mut rng(9)).unwrap();
    for i in 0..=600 {
        let x = -20.0 + 0.1 * i as f64 + 0.0371;
        let shape: f64 = feats.iter().map(|f| f.evaluate(x).0).sum();
        let shape_slope: f64 = feats.iter().map(|f| f.evaluate(x).1).sum();
        // The features do not consume randomness, so the base is the same; the sum is
        // exact up to one rounding of ~1e-2 m values: 1e-15 m.
        assert!((both.elevation_m(x) - plain.elevation_m(x) - shape).abs() < 1e-15);
        assert!((both.slope(x) - plain.slope(x) - shape_slope).abs() < 1e-15);
    }
    assert!(both.describe().contains("plus step of 0.01 m at x = 0 m"));
}

#[test]
fn slope_is_the_derivative_of_elevation() {
    // Central differences with h = 1e-6 m inside one sample interval (where the profile
    // is a cubic): truncation h^2 / 6 |r'''| < 1e-12 for |r'''| ~ (2 pi n2)^3 * 1 mm ~ 16,
    // rounding 1e-16 * 0.03 m / 1e-6 m ~ 3e-12. A slope wrong by one part in 1e4 of its
    // ~0.03 scale fails the 1e-9 bound.
    let p = RoadProfile::build(&iso(IsoClass::C), -50.0, 50.0, &mut rng(3)).unwrap();
    let h = 1e-6;
    let mut largest = 0.0f64;
    for i in 0..2000 {
        let x = -50.0 + i as f64 * DX_M + DX_M * (0.1 + 0.8 * ((i * 37 % 101) as f64 / 101.0));
        let fd = (p.elevation_m(x + h) - p.elevation_m(x - h)) / (2.0 * h);
        assert!(
            (fd - p.slope(x)).abs() < 1e-9,
            "x {x}: fd {fd} slope {}",
            p.slope(x)
        );
        largest = largest.max(p.slope(x).abs());
    }
    assert!(
        largest > 0.01,
        "slopes this small mean the test tests nothing: {largest}"
    );
    // C1 at the knots: the slope is continuous across them (1e-9: a few ulps of r''' h).
    for i in 1..100 {
        let x = -50.0 + i as f64 * DX_M;
        assert!(
            (p.slope(x - 1e-10) - p.slope(x + 1e-10)).abs() < 1e-8,
            "knot {x}"
        );
    }
}

#[test]
fn tyre_patch_filter_smooths_the_profile() {
    let filtered = RoadProfileSpec::Iso8608 {
        class: Some(IsoClass::C),
        gd_n0_m3: None,
        n1_cycles_m: N1,
        n2_cycles_m: N2,
        tyre_patch_filter_m: Some(0.24),
        sample_spacing_m: DX_M,
        features: Vec::new(),
    };
    let a = RoadProfile::build(&iso(IsoClass::C), 0.0, 2000.0, &mut rng(8)).unwrap();
    let b = RoadProfile::build(&filtered, 0.0, 2000.0, &mut rng(8)).unwrap();
    let slope_ms = |p: &RoadProfile| {
        (0..40000)
            .map(|i| p.slope(i as f64 * DX_M).powi(2))
            .sum::<f64>()
    };
    // The slope is dominated by short wavelengths, where sinc(pi n 0.24) is small (0.19
    // at 3 cycle/m), so the filtered slope energy is well under half the raw one.
    let ratio = slope_ms(&b) / slope_ms(&a);
    println!("tyre-patch filter: slope mean-square ratio {ratio:.3}");
    assert!(ratio < 0.5, "{ratio}");
    assert!(b.describe().contains("tyre-patch moving average 0.24 m"));
}

#[test]
fn csv_round_trip_keeps_every_sample() {
    let p = RoadProfile::build(&iso(IsoClass::B), -30.0, 30.0, &mut rng(21)).unwrap();
    let text = p.to_csv();
    assert!(text.starts_with("x_m,elevation_m\n"));
    let back = RoadProfile::from_csv_str(&text, "roundtrip.csv").unwrap();
    assert_eq!(back.x_range_m(), p.x_range_m());
    let (a, b): (Vec<_>, Vec<_>) = (p.sample_points().collect(), back.sample_points().collect());
    assert_eq!(a, b);
    // Between samples the measured-profile interpolation uses finite-difference slopes
    // instead of the exact ones: at n2 dx = 0.2 the central difference is 24 % low, and a
    // slope error e moves the Hermite midpoint by dx e / 8 ~ 0.05 * 0.25 * 0.02 / 8 ~ 3e-5 m.
    let worst = (0..1200)
        .map(|i| -30.0 + (i as f64 + 0.5) * DX_M)
        .map(|x| (p.elevation_m(x) - back.elevation_m(x)).abs())
        .fold(0.0f64, f64::max);
    println!("CSV round trip: largest mid-sample difference {worst:.2e} m");
    assert!(worst < 1e-4, "{worst}");

    // Deterministic shapes are written on a grid of at most 0.05 m.
    let ramp = RoadProfileSpec::Ramp {
        start_m: 0.0,
        length_m: 1.0,
        height_m: 0.01,
    };
    let r = RoadProfile::build(&ramp, -1.0, 2.0, &mut rng(0)).unwrap();
    let back = RoadProfile::from_csv_str(&r.to_csv(), "ramp.csv").unwrap();
    assert_eq!(back.sample_count(), 61);
    assert_eq!(back.x_range_m(), (-1.0, 2.0));
    assert!((back.elevation_m(0.5) - 0.005).abs() < 1e-15);
}

#[test]
fn csv_spec_reads_a_file_and_checks_its_coverage() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("measured.csv");
    std::fs::write(&path, "x_m,elevation_m\n-10,0\n0,0.001\n10,0.002\n40,0\n").unwrap();
    let path = path.to_string_lossy().into_owned();
    let spec = RoadProfileSpec::Csv { path: path.clone() };
    let p = RoadProfile::build(&spec, -10.0, 40.0, &mut rng(0)).unwrap();
    assert_eq!(p.elevation_m(10.0), 0.002);
    assert!(p.describe().contains("4 points"), "{}", p.describe());
    let err = RoadProfile::build(&spec, -20.0, 40.0, &mut rng(0)).unwrap_err();
    assert_eq!(
        err.to_string(),
        format!("{path}: the profile covers [-10, 40] m but the simulation needs [-20, 40] m")
    );
}

#[test]
fn malformed_csv_errors_name_the_file_and_line() {
    let dir = tempfile::tempdir().unwrap();
    let cases = [
        (
            "nonmonotone.csv",
            "x_m,elevation_m\n0,0\n1,0\n1,0.1\n",
            "line 4: x_m = 1 is not greater than the previous x_m = 1",
        ),
        (
            "nan.csv",
            "x_m,elevation_m\n0,0\n1,NaN\n",
            "line 3: elevation_m = NaN is not finite",
        ),
        (
            "column.csv",
            "x_m,z_m\n0,0\n1,0\n",
            "line 1: header has no column `elevation_m` (found: x_m, z_m)",
        ),
        (
            "short.csv",
            "x_m,elevation_m\n0,0\n1\n",
            "line 3: expected 2 fields as in the header, found 1",
        ),
    ];
    for (name, text, reason) in cases {
        let path = dir.path().join(name);
        std::fs::write(&path, text).unwrap();
        let path = path.to_string_lossy().into_owned();
        let err = RoadProfile::from_csv_file(&path).unwrap_err().to_string();
        assert!(err.starts_with(&format!("{path}: {reason}")), "{err}");
    }
    let missing = dir
        .path()
        .join("missing.csv")
        .to_string_lossy()
        .into_owned();
    let err = RoadProfile::build(
        &RoadProfileSpec::Csv {
            path: missing.clone(),
        },
        0.0,
        1.0,
        &mut rng(0),
    )
    .unwrap_err()
    .to_string();
    assert!(
        err.starts_with(&format!("{missing}: cannot read road profile")),
        "{err}"
    );
}

#[derive(Debug, serde::Deserialize)]
#[serde(deny_unknown_fields)]
struct Road {
    profile: RoadProfileSpec,
}

fn parse_road(toml_text: &str) -> Result<Road, String> {
    toml::from_str::<Road>(toml_text).map_err(|e| e.to_string())
}

#[test]
fn scenario_toml_parses_and_defaults_apply() {
    let road = parse_road(r#"profile = { kind = "iso8608", class = "A" }"#).unwrap();
    assert_eq!(road.profile, iso(IsoClass::A));
    let road = parse_road(
        r#"profile = { kind = "iso8608", gd_n0_m3 = 5e-5, features = [
            { kind = "bump", position_m = 0.0, length_m = 1.0, height_m = 0.02 } ] }"#,
    )
    .unwrap();
    road.profile.validate("road.profile").unwrap();
    assert_eq!(
        parse_road(r#"profile = { kind = "smooth" }"#)
            .unwrap()
            .profile,
        RoadProfileSpec::Smooth
    );
    // Serialized specs read back the same (the resolved scenario goes into the MCAP).
    let text = toml::to_string(&Road2 {
        profile: road.profile.clone(),
    })
    .unwrap();
    assert_eq!(parse_road(&text).unwrap().profile, road.profile);
}

#[derive(serde::Serialize)]
struct Road2 {
    profile: RoadProfileSpec,
}

#[test]
fn bad_configuration_is_rejected_with_its_field_path() {
    let err = parse_road(r#"profile = { kind = "iso8608", class = "Z" }"#).unwrap_err();
    println!("class Z: {err}");
    assert!(
        err.contains("unknown variant `Z`") && err.contains("class"),
        "{err}"
    );
    let err = parse_road(r#"profile = { kind = "iso8608", class = "A", n3_cycles_m = 1.0 }"#)
        .unwrap_err();
    assert!(err.contains("unknown field `n3_cycles_m`"), "{err}");

    let road = parse_road(
        r#"profile = { kind = "iso8608", class = "B", n1_cycles_m = 4.0, n2_cycles_m = 2.0 }"#,
    )
    .unwrap();
    let err = road
        .profile
        .validate("road.profile")
        .unwrap_err()
        .to_string();
    assert_eq!(
        err,
        "road.profile.n1_cycles_m = 4 must be less than n2_cycles_m = 2"
    );

    let cases = [
        (r#"{ kind = "iso8608" }"#, "road.profile.class = (missing)"),
        (
            r#"{ kind = "iso8608", gd_n0_m3 = -1e-6 }"#,
            "road.profile.gd_n0_m3 = -0.000001",
        ),
        (
            r#"{ kind = "iso8608", class = "A", n1_cycles_m = nan }"#,
            "road.profile.n1_cycles_m = NaN",
        ),
        (
            r#"{ kind = "iso8608", class = "A", sample_spacing_m = 0.2 }"#,
            "road.profile.n2_cycles_m = 4 exceeds the Nyquist frequency",
        ),
        (
            r#"{ kind = "iso8608", class = "A", tyre_patch_filter_m = 0.0 }"#,
            "road.profile.tyre_patch_filter_m = 0",
        ),
        (
            r#"{ kind = "iso8608", class = "A", features = [{ kind = "ramp", start_m = 0.0, length_m = 0.0, height_m = 0.1 }] }"#,
            "road.profile.features.0.length_m = 0",
        ),
        (
            r#"{ kind = "bump", position_m = 1.0, length_m = -2.0, height_m = 0.1 }"#,
            "road.profile.length_m = -2",
        ),
        (r#"{ kind = "csv", path = " " }"#, "road.profile.path"),
    ];
    for (profile, expected) in cases {
        let road = parse_road(&format!("profile = {profile}")).unwrap();
        let err = road
            .profile
            .validate("road.profile")
            .unwrap_err()
            .to_string();
        assert!(err.starts_with(expected), "{profile}: {err}");
        // build validates too, with the same path.
        let built = RoadProfile::build(&road.profile, 0.0, 10.0, &mut rng(0));
        assert_eq!(built.unwrap_err().to_string(), err);
    }
    let err = RoadProfile::build(&iso(IsoClass::A), 10.0, 10.0, &mut rng(0)).unwrap_err();
    assert_eq!(
        err.to_string(),
        "x_end_m = 10 must be greater than x_start_m = 10"
    );
}
