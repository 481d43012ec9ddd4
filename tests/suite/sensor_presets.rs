//! Sensor presets and measurement-chain stages against closed forms and statistics:
//! noise densities (Welch PSD), 1/f slope and level, ADC steps and clipping, the AC
//! high-pass, DC bias drift, gain-error spread, per-stage random streams, parameter errors
//! and TOML overrides. Run with `--nocapture` to see the measured figures.

use std::f64::consts::PI;
use std::sync::Arc;

use bridgetwin::base::random::child_rng;
use bridgetwin::measurement::sensor::chain::{
    resolve, ChainSpec, ChainStages, Coupling, Draw, ResolvedChain, SensorPreset, TemperatureFn,
    TransducerKind, STANDARD_GRAVITY_M_S2,
};
use rand_chacha::ChaCha8Rng;
use serde::Deserialize;

const PREFIX: &str = "sensors.3";

fn spec(toml_text: &str) -> ChainSpec {
    toml::from_str(toml_text).expect("chain spec parses")
}

fn chain(preset: SensorPreset, kind: TransducerKind, toml_text: &str) -> ResolvedChain {
    resolve(preset, kind, &spec(toml_text), PREFIX).expect("chain resolves")
}

fn room_temperature() -> TemperatureFn {
    Arc::new(|_| 20.0)
}

/// Stages for sensor `seed` at `fs_hz`, streams `sensor/<seed>/<stage>`, flat anti-alias.
fn build(c: &ResolvedChain, fs_hz: f64, seed: u64, temperature: TemperatureFn) -> ChainStages {
    let mut rng_for = |name: &str| -> ChaCha8Rng { child_rng(seed, &format!("sensor/{name}")) };
    c.stages(fs_hz, &mut rng_for, temperature, &|_| 1.0)
        .expect("stages build")
}

/// Output instants `round(k * 1e9 / fs)` ns, as the channel's.
fn instant_ns(k: usize, fs_hz: f64) -> u64 {
    (k as f64 * 1e9 / fs_hz).round() as u64
}

/// Runs `n` samples of `input(t_s)` through the stages.
fn run(stages: &mut ChainStages, n: usize, fs_hz: f64, input: impl Fn(f64) -> f64) -> Vec<f64> {
    (0..n)
        .map(|k| {
            let t_ns = instant_ns(k, fs_hz);
            let mut v = input(t_ns as f64 * 1e-9);
            for s in stages.stages.iter_mut() {
                v = s.apply(t_ns, v);
            }
            v
        })
        .collect()
}

/// One-sided Welch PSD (the library's: Hann window, 50 % overlap, each segment's mean
/// removed, a white sequence of variance s^2 giving `2 s^2 / fs`): (frequency Hz,
/// PSD unit^2/Hz) for bins 1 .. segment/2 - 1.
fn welch(x: &[f64], fs_hz: f64, segment: usize) -> Vec<(f64, f64)> {
    let psd = bridgetwin::base::signal::welch_psd(x, 1.0 / fs_hz, segment).expect("welch");
    psd.frequencies.into_iter().zip(psd.density).collect()
}

/// Mean of `measured / expected(f)` over the bins in `[low, high]`.
fn band_ratio(psd: &[(f64, f64)], low: f64, high: f64, expected: impl Fn(f64) -> f64) -> f64 {
    let in_band: Vec<f64> = psd
        .iter()
        .filter(|(f, _)| *f >= low && *f <= high)
        .map(|&(f, p)| p / expected(f))
        .collect();
    in_band.iter().sum::<f64>() / in_band.len() as f64
}

/// Segments of a Welch estimate over `n` samples: `segment` long, overlapping by half.
pub(crate) fn welch_segments(n: usize, segment: usize) -> usize {
    (n - segment) / (segment / 2) + 1
}

/// Relative standard error of the density (the square root of the PSD) averaged over
/// `bins` bins of a Welch estimate from `segments` Hann-windowed segments overlapping by
/// half, for white noise.
///
/// Each bin's PSD is a mean of `segments` periodograms, each chi-square with 2 degrees of
/// freedom (relative variance 1); half-overlapping Hann segments are correlated by
/// rho^2 = (1/6)^2, so the variance of their mean is (1 + 2 rho^2) / segments. Over the
/// band, neighbouring Hann bins are correlated by (2/3)^2 and bins two apart by (1/6)^2:
/// the mean of `bins` bins has (1 + 2 (4/9) + 2 (1/36)) / bins of that. The density's
/// relative error is half the PSD's.
pub(crate) fn density_standard_error(bins: usize, segments: usize) -> f64 {
    let segment_factor = 1.0 + 2.0 / 36.0;
    let bin_factor = 1.0 + 2.0 * 4.0 / 9.0 + 2.0 / 36.0;
    0.5 * (segment_factor * bin_factor / (segments as f64 * bins as f64)).sqrt()
}

fn kind_of(preset: SensorPreset) -> TransducerKind {
    preset.kind().unwrap_or(TransducerKind::Displacement)
}

#[test]
fn every_preset_with_noise_has_its_white_density() {
    // 2^17 samples in segments of 1024: ~255 averaged segments and >= 300 bins in the
    // band. The tolerance is 5 standard errors of the band-mean density, computed per
    // preset (`density_standard_error`: ~0.24 %, so ~1.2 %); the measured errors are
    // 0.07-0.26 %. The whole preset chain runs on a zero input, its ADC included, whose
    // quantisation noise (LSB^2 / 12 spread over fs / 2) is part of the expected PSD; the
    // band starts 10 corner frequencies up and the expected PSD includes the 1/f term.
    for preset in SensorPreset::ALL {
        let c = chain(preset, kind_of(preset), "");
        let p = *c.chain_parameters();
        if p.noise_density == 0.0 {
            continue;
        }
        let fs_hz = p.max_rate_hz.unwrap_or(1000.0).min(4000.0);
        let mut stages = build(&c, fs_hz, 11, room_temperature());
        let x = run(&mut stages, 1 << 17, fs_hz, |_| 0.0);
        let psd = welch(&x, fs_hz, 1024);
        let low = (10.0 * p.flicker_corner_hz).max(0.05 * fs_hz);
        let nd2 = p.noise_density.powi(2);
        let quantisation = p.adc.map_or(0.0, |a| a.lsb().powi(2) / 12.0 * 2.0 / fs_hz);
        let ratio = band_ratio(&psd, low, 0.4 * fs_hz, |f| {
            nd2 * (1.0 + p.flicker_corner_hz / f) + quantisation
        });
        let measured = p.noise_density * ratio.sqrt();
        let bins = psd
            .iter()
            .filter(|(f, _)| *f >= low && *f <= 0.4 * fs_hz)
            .count();
        let sigma = density_standard_error(bins, welch_segments(1 << 17, 1024));
        println!(
            "{preset}: density {:.4e} measured {:.4e} ({:+.2} %, standard error {:.2} %) at \
             {fs_hz} Hz",
            p.noise_density,
            measured,
            100.0 * (ratio.sqrt() - 1.0),
            100.0 * sigma
        );
        assert!(
            (ratio.sqrt() - 1.0).abs() < 5.0 * sigma,
            "{preset}: {measured} ({:+.3} %, 5 standard errors {:.3} %)",
            100.0 * (ratio.sqrt() - 1.0),
            500.0 * sigma
        );
    }
}

#[test]
fn flicker_psd_has_slope_minus_one_and_its_level() {
    // ND = 1, fc = 5 Hz at 100 Hz: PSD 1 + 5/f. 2^20 samples in segments of 8192
    // (df = 0.0122 Hz, 255 segments). Band means over f/1.25..1.25 f hold ~7 bins at
    // 0.2 Hz (relative standard error ~3.5 %) and ~75 bins at 2 Hz (~1 %). Tolerances:
    // level 15 % at 0.2 Hz and 8 % at 2 Hz (4 standard errors plus the 0.2 dB = 4.7 %
    // design ripple of the bank); the slope of the 1/f part (white removed) within 0.06 of
    // -1 (standard error ~0.016).
    let fs_hz = 100.0;
    let c = chain(
        SensorPreset::Ideal,
        TransducerKind::Displacement,
        "noise_density = 1.0\nflicker_corner_hz = 5.0",
    );
    let mut stages = build(&c, fs_hz, 3, room_temperature());
    let x = run(&mut stages, 1 << 20, fs_hz, |_| 0.0);
    let psd = welch(&x, fs_hz, 8192);
    let band_mean = |f0: f64| {
        let bins: Vec<&(f64, f64)> = psd
            .iter()
            .filter(|(f, _)| *f >= f0 / 1.25 && *f <= f0 * 1.25)
            .collect();
        let measured = bins.iter().map(|b| b.1).sum::<f64>() / bins.len() as f64;
        let expected = bins.iter().map(|b| 1.0 + 5.0 / b.0).sum::<f64>() / bins.len() as f64;
        (measured, expected)
    };
    let (m1, e1) = band_mean(0.2);
    let (m2, e2) = band_mean(2.0);
    let slope = ((m1 - 1.0) / (m2 - 1.0)).ln() / ((e1 - 1.0) / (e2 - 1.0)).ln();
    println!(
        "flicker: 0.2 Hz {m1:.3} vs {e1:.3}, 2 Hz {m2:.4} vs {e2:.4}, slope {:.4}",
        -slope
    );
    assert!((m1 / e1 - 1.0).abs() < 0.15, "{m1} vs {e1}");
    assert!((m2 / e2 - 1.0).abs() < 0.08, "{m2} vs {e2}");
    assert!((slope - 1.0).abs() < 0.06, "slope {}", -slope);
}

#[test]
fn adc_steps_are_exact_and_clipping_is_counted() {
    // 12 bits over +/-1: lsb = 2/4096 exactly; codes -2048..=2047. A ramp from -1.5 to 1.5
    // with an irrational step never lands on a rounding tie.
    let c = chain(
        SensorPreset::Ideal,
        TransducerKind::Displacement,
        "adc = { bits = 12, range = 1.0 }",
    );
    let mut stages = build(&c, 100.0, 1, room_temperature());
    let lsb = 2.0 / 4096.0;
    let step = 3.0 / 100_000.0 * (1.0 + 1e-3 * 3f64.sqrt());
    let n = 100_000;
    let input = |k: usize| -1.5 + k as f64 * step;
    let out = run(&mut stages, n, 100.0, |t_s| {
        input((t_s * 100.0).round() as usize)
    });
    let mut expected_clips = 0;
    for (k, &y) in out.iter().enumerate() {
        let x = input(k);
        let code = y / lsb;
        assert_eq!(code, code.round(), "{y} is not a multiple of the LSB");
        if x > 1.0 - lsb / 2.0 || x < -1.0 - lsb / 2.0 {
            expected_clips += 1;
            let limit = if x > 0.0 { 1.0 - lsb } else { -1.0 };
            assert_eq!(y, limit, "clipped {x}");
        } else {
            assert!((y - x).abs() <= lsb / 2.0, "{x} -> {y}");
        }
    }
    println!("adc: {} of {n} samples clipped", stages.clipped.get());
    assert!(expected_clips > 30_000);
    assert_eq!(stages.clipped.get(), expected_clips);
    let lsb_listed = stages.parameters.iter().find(|(k, _)| k == "adc_lsb");
    assert_eq!(lsb_listed.map(|p| p.1), Some(lsb));
}

/// Least-squares amplitude of a tone of `f_hz` in `y` sampled at `fs_hz` from sample
/// `start` on (sine and cosine fit).
fn tone_amplitude(y: &[f64], fs_hz: f64, f_hz: f64, start: usize) -> f64 {
    let (mut ss, mut sc, mut cc, mut ys, mut yc) = (0.0, 0.0, 0.0, 0.0, 0.0);
    for (k, &v) in y.iter().enumerate().skip(start) {
        let (s, c) = (2.0 * PI * f_hz * instant_ns(k, fs_hz) as f64 * 1e-9).sin_cos();
        ss += s * s;
        sc += s * c;
        cc += c * c;
        ys += v * s;
        yc += v * c;
    }
    let det = ss * cc - sc * sc;
    let a = (ys * cc - yc * sc) / det;
    let b = (yc * ss - ys * sc) / det;
    a.hypot(b)
}

#[test]
fn ac_coupling_is_minus_3_db_at_the_corner_and_flat_above() {
    // The piezo preset (0.06 Hz) with every other stage off, at 100 Hz. The start
    // transient decays as exp(-2 pi fc t): after 40 s (15 time constants) it is < 1e-6, so
    // the fitted amplitudes carry no tolerance beyond that: 1e-4 at the corner (exactly
    // 1/sqrt 2 by the pre-warp); 0.5 % of 1 ten times above (analog: 10/sqrt(101) =
    // 0.99504), which must also match the analog value within 1e-4.
    let c = chain(
        SensorPreset::PiezoSeismic,
        TransducerKind::Accelerometer,
        "gain_error = 0.0\nnoise_density = 0.0\nadc = { enabled = false }",
    );
    let fs_hz = 100.0;
    let start = 4000;
    for (f_hz, expected) in [(0.06, 0.5f64.sqrt()), (0.6, 10.0 / 101f64.sqrt())] {
        let mut stages = build(&c, fs_hz, 1, room_temperature());
        let n = start + (20.0 / f_hz * fs_hz) as usize; // 20 whole cycles
        let y = run(&mut stages, n, fs_hz, |t| (2.0 * PI * f_hz * t).sin());
        let a = tone_amplitude(&y, fs_hz, f_hz, start);
        println!("high-pass 0.06 Hz: |H({f_hz} Hz)| = {a:.6} (analog {expected:.6})");
        assert!((a - expected).abs() < 1e-4, "{f_hz}: {a}");
        if f_hz > 0.1 {
            assert!((a - 1.0).abs() < 0.005, "{a}");
        }
    }
}

#[test]
fn dc_bias_follows_the_temperature_then_the_gain() {
    // mems_lownoise with a fixed bias and gain and no noise or ADC: on a zero input the
    // output is (bias + tempco (T - 20)) (1 + gain_error), tempco the preset's 0.1 mg/degC.
    let c = chain(
        SensorPreset::MemsLownoise,
        TransducerKind::Accelerometer,
        "bias = 0.01\ngain_error = 0.02\nnoise_density = 0.0\nadc = { enabled = false }",
    );
    let tempco = 1e-4 * STANDARD_GRAVITY_M_S2;
    let temperature = |t_ns: u64| 20.0 + 15.0 * (2.0 * PI * t_ns as f64 * 1e-9 / 600.0).sin();
    let mut stages = build(&c, 10.0, 1, Arc::new(temperature));
    let y = run(&mut stages, 6000, 10.0, |_| 0.0);
    for (k, &v) in y.iter().enumerate() {
        let t = temperature(instant_ns(k, 10.0));
        let expected = (0.01 + tempco * (t - 20.0)) * 1.02;
        assert!((v - expected).abs() < 1e-15, "{k}: {v} vs {expected}");
    }
    let span =
        y.iter().cloned().fold(f64::MIN, f64::max) - y.iter().cloned().fold(f64::MAX, f64::min);
    println!("bias drift over +/-15 degC: {span:.4e} m/s^2 peak to peak");
}

#[test]
fn gain_error_has_the_configured_sigma_over_many_sensors() {
    // 4000 mems_consumer sensors (sigma 3.3 %): the sample standard deviation has a
    // relative standard error 1/sqrt(2 n) = 1.1 %, so 5 % is 4.5 standard errors; the mean
    // is within 4 sigma / sqrt(n). Each realised value is read back through the stages
    // (input 1, everything else off) and must equal the listed parameter.
    let c = chain(
        SensorPreset::MemsConsumer,
        TransducerKind::Accelerometer,
        "bias = 0.0\nbias_tempco_per_degc = 0.0\nnoise_density = 0.0\nadc = { enabled = false }",
    );
    let n = 4000;
    let draws: Vec<f64> = (0..n)
        .map(|seed| {
            let mut stages = build(&c, 100.0, seed, room_temperature());
            let listed = stages.parameters.iter().find(|(k, _)| k == "gain_error");
            let g = listed.map(|p| p.1).expect("gain_error listed");
            let y = run(&mut stages, 1, 100.0, |_| 1.0)[0];
            assert!((y - (1.0 + g)).abs() < 1e-15, "{y} vs {g}");
            g
        })
        .collect();
    let mean = draws.iter().sum::<f64>() / n as f64;
    let sd = (draws.iter().map(|g| (g - mean).powi(2)).sum::<f64>() / (n - 1) as f64).sqrt();
    println!("gain error over {n} sensors: mean {mean:.5}, sigma {sd:.5} (configured 0.033)");
    assert!((sd / 0.033 - 1.0).abs() < 0.05, "{sd}");
    assert!(mean.abs() < 4.0 * 0.033 / (n as f64).sqrt(), "{mean}");
}

#[test]
fn switching_a_stage_leaves_the_other_streams_alone() {
    let fs_hz = 200.0;
    let n = 2000;
    let base = "noise_density = 1e-3\nflicker_corner_hz = 0.5\nadc = { enabled = false }";
    let noise_only = |extra: &str| {
        let c = chain(
            SensorPreset::Ideal,
            TransducerKind::Displacement,
            &format!("{base}\n{extra}"),
        );
        let mut stages = build(&c, fs_hz, 7, room_temperature());
        run(&mut stages, n, fs_hz, |_| 0.0)
    };
    // Gain and bias draw from their own streams: on a zero input with bias 0 the noise is
    // the same to the bit whether or not they were drawn.
    let reference = noise_only("");
    assert_eq!(noise_only("gain_error_sigma = 0.05"), reference);
    // The hum adds exactly its sine (fixed phase here): differences are rounding only.
    let with_hum = noise_only("hum = { frequency_hz = 50, amplitude = 0.2, phase_rad = 0.3 }");
    for (k, (h, r)) in with_hum.iter().zip(&reference).enumerate() {
        let t = instant_ns(k, fs_hz) as f64 * 1e-9;
        let hum = 0.2 * (2.0 * PI * 50.0 * t + 0.3).sin();
        assert!((h - r - hum).abs() < 1e-12, "{k}");
    }
    // A random bias (from "bias") is a constant offset of the same noise.
    let with_bias = noise_only("bias_sigma = 0.1");
    let offset = with_bias[0] - reference[0];
    assert!(offset != 0.0);
    assert!(with_bias
        .iter()
        .zip(&reference)
        .all(|(b, r)| (b - r - offset).abs() < 1e-12));
    // The same seed gives the same bytes; another seed other numbers.
    assert_eq!(noise_only(""), reference);
    let c = chain(SensorPreset::Ideal, TransducerKind::Displacement, base);
    let other = run(
        &mut build(&c, fs_hz, 8, room_temperature()),
        n,
        fs_hz,
        |_| 0.0,
    );
    assert_ne!(other, reference);
}

#[test]
fn bad_inputs_name_their_field_and_value() {
    use SensorPreset::*;
    use TransducerKind::*;
    let cases: &[(SensorPreset, TransducerKind, &str, &str)] = &[
        (
            Ideal,
            Strain,
            "noise_density = -1",
            "sensors.3.chain.noise_density = -1 ",
        ),
        (
            Ideal,
            Strain,
            "flicker_corner_hz = -2",
            "sensors.3.chain.flicker_corner_hz = -2 ",
        ),
        (
            Ideal,
            Strain,
            "flicker_lowest_hz = 0",
            "sensors.3.chain.flicker_lowest_hz = 0 ",
        ),
        (
            StrainFoil,
            Strain,
            "adc = { bits = 0 }",
            "sensors.3.chain.adc.bits = 0 ",
        ),
        (
            StrainFoil,
            Strain,
            "adc = { bits = 33 }",
            "sensors.3.chain.adc.bits = 33 ",
        ),
        (
            StrainFoil,
            Strain,
            "adc = { range = 0 }",
            "sensors.3.chain.adc.range = 0 ",
        ),
        (
            Ideal,
            Strain,
            "adc = { bits = 16 }",
            "sensors.3.chain.adc.range = (missing) ",
        ),
        (
            StrainFoil,
            Strain,
            "adc = { enabled = false, bits = 16 }",
            "sensors.3.chain.adc.enabled = false ",
        ),
        (
            PiezoSeismic,
            Accelerometer,
            "coupling = { kind = \"ac\", highpass_hz = -1 }",
            "sensors.3.chain.coupling.highpass_hz = -1 ",
        ),
        (
            MemsLownoise,
            Accelerometer,
            "coupling = { kind = \"ac\" }",
            "sensors.3.chain.coupling.highpass_hz = (missing) ",
        ),
        (
            PiezoSeismic,
            Accelerometer,
            "bias = 0.1",
            "sensors.3.chain.bias = 0.1 applies",
        ),
        (
            Ideal,
            Strain,
            "hum = { frequency_hz = 0, amplitude = 1 }",
            "sensors.3.chain.hum.frequency_hz = 0 ",
        ),
        (
            Ideal,
            Strain,
            "hum = { amplitude = -1 }",
            "sensors.3.chain.hum.amplitude = -1 ",
        ),
        (
            Ideal,
            Strain,
            "hum = { frequency_hz = 60 }",
            "sensors.3.chain.hum.amplitude = (missing) ",
        ),
        (
            Ideal,
            Strain,
            "gain_error = 1.5",
            "sensors.3.chain.gain_error = 1.5 ",
        ),
        (
            Ideal,
            Strain,
            "gain_error_sigma = 0.5",
            "sensors.3.chain.gain_error_sigma = 0.5 ",
        ),
        (
            Ideal,
            Strain,
            "gain_error = 0.01\ngain_error_sigma = 0.01",
            "sensors.3.chain.gain_error_sigma = 0.01 conflicts",
        ),
        (
            StrainFoil,
            Strain,
            "bias_sigma = -3",
            "sensors.3.chain.bias_sigma = -3 ",
        ),
        (
            MemsConsumer,
            Strain,
            "",
            "sensors.3.preset = mems_consumer is a preset for accelerometer",
        ),
        (
            StrainFoil,
            Displacement,
            "",
            "sensors.3.preset = strain_foil ",
        ),
    ];
    for (preset, kind, text, expected) in cases {
        let e = resolve(*preset, *kind, &spec(text), PREFIX)
            .expect_err(text)
            .to_string();
        assert!(e.starts_with(expected), "{text}: {e}");
    }
    for text in [
        "noise = 1",
        "adc = { bit = 3 }",
        "coupling = { kind = \"ac\", hp = 1 }",
    ] {
        assert!(toml::from_str::<ChainSpec>(text).is_err(), "{text}");
    }
}

#[test]
fn rates_beyond_the_preset_or_the_chain_are_rejected() {
    let c = chain(
        SensorPreset::MemsLownoise,
        TransducerKind::Accelerometer,
        "",
    );
    assert!(c.check_rate(4000.0, "sensors.3.rate_hz").is_ok());
    let e = c
        .check_rate(5000.0, "sensors.3.rate_hz")
        .unwrap_err()
        .to_string();
    let expected = "sensors.3.rate_hz = 5000 Hz: rate not supported by the preset \
                    mems_lownoise (maximum 4000 Hz)";
    assert_eq!(e, expected);
    let c = chain(
        SensorPreset::Ideal,
        TransducerKind::Accelerometer,
        "coupling = { kind = \"ac\", highpass_hz = 60 }",
    );
    let e = c
        .check_rate(100.0, "sensors.3.rate_hz")
        .unwrap_err()
        .to_string();
    assert!(
        e.starts_with("sensors.3.chain.coupling.highpass_hz = 60 must be below"),
        "{e}"
    );
    let mut rng_for = |name: &str| child_rng(1, name);
    let e = c
        .stages(100.0, &mut rng_for, room_temperature(), &|_| 1.0)
        .unwrap_err()
        .to_string();
    assert!(
        e.starts_with("sensors.3.chain.coupling.highpass_hz = 60"),
        "{e}"
    );
}

#[test]
fn hum_is_scaled_by_the_anti_alias_gain_and_aliases_when_sampled() {
    // 60 Hz hum of amplitude 1 through an anti-alias gain of 0.25 at 60 Hz, sampled at
    // 100 Hz: the output is 0.25 sin(2 pi 60 t + 0.5) at the output instants, i.e. the
    // 40 Hz alias, to rounding (1e-12).
    let c = chain(
        SensorPreset::Ideal,
        TransducerKind::Strain,
        "hum = { frequency_hz = 60, amplitude = 1.0, phase_rad = 0.5 }",
    );
    let mut rng_for = |name: &str| child_rng(1, name);
    let aa_gain = |f_hz: f64| if f_hz == 60.0 { 0.25 } else { 1.0 };
    let mut built = c
        .stages(100.0, &mut rng_for, room_temperature(), &aa_gain)
        .expect("stages");
    let y = run(&mut built, 1000, 100.0, |_| 0.0);
    for (k, v) in y.iter().enumerate() {
        let t = instant_ns(k, 100.0) as f64 * 1e-9;
        let alias = -0.25 * (2.0 * PI * 40.0 * t - 0.5).sin();
        assert!((v - alias).abs() < 1e-12, "{k}: {v} vs {alias}");
    }
    let listed = built
        .parameters
        .iter()
        .find(|(k, _)| k == "hum_amplitude_after_anti_alias");
    assert_eq!(listed.map(|p| p.1), Some(0.25));
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct SensorTable {
    preset: SensorPreset,
    #[serde(default)]
    chain: ChainSpec,
}

#[test]
fn presets_parse_and_overrides_apply_field_by_field() {
    for preset in SensorPreset::ALL {
        let t: SensorTable = toml::from_str(&format!("preset = \"{preset}\"")).expect("parses");
        assert_eq!(t.preset, preset);
    }
    let table = |chain: &str| -> SensorTable {
        toml::from_str(&format!("preset = \"mems_lownoise\"\n[chain]\n{chain}")).expect("parses")
    };
    let base = SensorPreset::MemsLownoise.parameters();
    let resolved = |chain: &str| {
        let t = table(chain);
        *resolve(t.preset, TransducerKind::Accelerometer, &t.chain, PREFIX)
            .expect("resolves")
            .chain_parameters()
    };
    assert_eq!(resolved(""), base);
    let mut want = base;
    want.noise_density = 1e-4;
    assert_eq!(resolved("noise_density = 1e-4"), want);
    let mut want = base;
    want.flicker_corner_hz = 0.0;
    assert_eq!(resolved("flicker_corner_hz = 0"), want);
    let mut want = base;
    want.gain_error = Draw::Fixed(0.03);
    assert_eq!(resolved("gain_error = 0.03"), want);
    let mut want = base;
    want.coupling = Coupling::Ac { highpass_hz: 0.1 };
    assert_eq!(
        resolved("coupling = { kind = \"ac\", highpass_hz = 0.1 }"),
        want
    );
    let mut want = base;
    if let Coupling::Dc { bias, .. } = base.coupling {
        want.coupling = Coupling::Dc {
            bias,
            bias_tempco_per_degc: 0.0,
        };
    }
    assert_eq!(resolved("bias_tempco_per_degc = 0.0"), want);
    let mut want = base;
    if let Some(adc) = want.adc.as_mut() {
        adc.range = 4.0;
    }
    assert_eq!(resolved("adc = { range = 4.0 }"), want);
    let mut want = base;
    want.adc = None;
    assert_eq!(resolved("adc = { enabled = false }"), want);
    let hum = resolved("hum = { amplitude = 0.01 }").hum.expect("hum on");
    assert_eq!(
        (hum.frequency_hz, hum.amplitude, hum.phase_rad),
        (50.0, 0.01, None)
    );
}

#[test]
fn the_ideal_preset_builds_no_stage_and_lists_realised_values() {
    let c = chain(SensorPreset::Ideal, TransducerKind::Strain, "");
    let stages = build(&c, 100.0, 1, room_temperature());
    assert!(stages.stages.is_empty());
    let c = chain(
        SensorPreset::MemsLownoise,
        TransducerKind::Accelerometer,
        "",
    );
    let built = build(&c, 100.0, 1, room_temperature());
    assert_eq!(built.stages.len(), 4); // DC offset, gain, noise, ADC
    let names: Vec<&str> = built.parameters.iter().map(|(k, _)| k.as_str()).collect();
    for key in [
        "bias_sigma",
        "bias",
        "gain_error_sigma",
        "gain_error",
        "noise_density",
        "adc_lsb",
    ] {
        assert!(names.contains(&key), "{key} in {names:?}");
    }
}
