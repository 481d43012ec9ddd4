//! DAQ node clocks and labelled faults, checked against closed forms and long-run
//! statistics. Every tolerance states the standard error (SE) it is a multiple of.

use bridgetwin::base::random::child_rng;
use bridgetwin::measurement::daq::{
    ClockSpec, DeadSpec, FaultInjector, FaultKind, FaultLabel, FaultSpec, LossSpec, NodeClock,
    OffsetStepSpec, OutageWindow, SpikeSpec, StuckSpec, OPEN_END_NS,
};
use rand_chacha::ChaCha8Rng;

const SEED: u64 = 20_260_101;

fn node_rng(seed: u64) -> ChaCha8Rng {
    child_rng(seed, "daq/node1/clock")
}

// ---------------------------------------------------------------------------------------
// Clocks
// ---------------------------------------------------------------------------------------

/// Least-squares slope of `y` against `x`, centred for conditioning.
fn slope(x: &[f64], y: &[f64]) -> f64 {
    let n = x.len() as f64;
    let (mx, my) = (x.iter().sum::<f64>() / n, y.iter().sum::<f64>() / n);
    let (mut sxy, mut sxx) = (0.0, 0.0);
    for (a, b) in x.iter().zip(y) {
        sxy += (a - mx) * (b - my);
        sxx += (a - mx) * (a - mx);
    }
    sxy / sxx
}

#[test]
fn free_running_stamps_stay_on_the_nominal_grid_while_true_instants_drift() {
    let (fs_hz, drift_ppm, offset_s, jitter_rms_s) = (100.0, 37.5, 0.25, 2e-5);
    let spec = ClockSpec {
        offset_s,
        drift_ppm,
        jitter_rms_s,
        ..ClockSpec::default()
    };
    let mut clock = NodeClock::new(&spec, fs_hz, node_rng(SEED), "daq_nodes.0.clock").unwrap();
    let true_rate_hz = fs_hz * (1.0 + drift_ppm * 1e-6);
    assert!((clock.true_rate_hz() - true_rate_hz).abs() < 1e-12 * true_rate_hz);
    assert_eq!(clock.nominal_rate_hz(), fs_hz);

    let n = 1_000_000;
    let (mut true_s, mut stamp_s) = (Vec::with_capacity(n), Vec::with_capacity(n));
    let mut sum_sq_jitter_s2 = 0.0;
    let mut max_jitter_s: f64 = 0.0;
    let mut previous_true_ns = f64::NEG_INFINITY;
    for k in 0..n as u64 {
        let s = clock.next_sample();
        assert_eq!(s.index, k);
        // Closed form of the contract: stamps are k / fs + offset exactly (10 ms grid).
        assert_eq!(s.stamp_ns, k as i64 * 10_000_000 + 250_000_000, "k = {k}");
        assert!(s.true_ns > previous_true_ns, "true instants must increase");
        previous_true_ns = s.true_ns;
        let jitter_s = (s.true_ns - k as f64 * 1e9 / true_rate_hz) * 1e-9;
        sum_sq_jitter_s2 += jitter_s * jitter_s;
        max_jitter_s = max_jitter_s.max(jitter_s.abs());
        true_s.push(s.true_ns * 1e-9);
        stamp_s.push(s.stamp_ns as f64 * 1e-9);
    }
    // Stamps against true instants: slope 1 / (1 + d)^-1 = 1 + d. With 20 us of jitter on
    // a 1e4 s record the slope's SE is 2e-5 / sqrt(n * T^2 / 12) = 7e-12 = 7e-6 ppm, so
    // 1e-3 ppm is 100+ SE and still 37 500 times smaller than the drift.
    let fitted_ppm = (slope(&true_s, &stamp_s) - 1.0) * 1e6;
    assert!(
        (fitted_ppm - drift_ppm).abs() < 1e-3,
        "fitted {fitted_ppm} ppm"
    );

    // Jitter RMS: relative SE of an RMS estimate from 1e6 draws is ~sqrt(2)/2/1000 = 0.07 %;
    // 0.5 % is 7 SE, and still smaller than the 1.3 % an uncorrected 3-sigma truncation
    // would leave.
    let rms_s = (sum_sq_jitter_s2 / n as f64).sqrt();
    eprintln!("drift fit {fitted_ppm:.7} ppm (set {drift_ppm}), jitter rms {rms_s:e} s (set {jitter_rms_s:e}), max {max_jitter_s:e} s");
    assert!(
        (rms_s / jitter_rms_s - 1.0).abs() < 5e-3,
        "jitter rms {rms_s}"
    );
    // Truncation at 3 sigma of the underlying normal, sigma = rms / 0.9865784.
    assert!(
        max_jitter_s <= 3.0 * jitter_rms_s / 0.986_578_4 + 1e-12,
        "{max_jitter_s}"
    );
    assert!(
        max_jitter_s > 2.9 * jitter_rms_s,
        "tails reach the truncation"
    );
}

/// Clock error of every sample, `(true_s, e_s)`, for a jitter-free clock.
fn clock_errors(spec: &ClockSpec, rate_hz: f64, duration_s: f64) -> Vec<(f64, f64)> {
    let mut clock = NodeClock::new(spec, rate_hz, node_rng(SEED), "c").unwrap();
    let n = (duration_s * rate_hz) as usize;
    (0..n)
        .map(|_| {
            let s = clock.next_sample();
            (s.true_ns * 1e-9, (s.stamp_ns as f64 - s.true_ns) * 1e-9)
        })
        .collect()
}

#[test]
fn resyncs_bound_the_error_and_channels_at_different_rates_share_it() {
    let (drift, interval_s, residual_rms_s) = (40e-6, 1.0, 50e-6);
    let spec = ClockSpec {
        offset_s: 0.01,
        drift_ppm: 40.0,
        resync_interval_s: Some(interval_s),
        resync_residual_rms_s: residual_rms_s,
        ..ClockSpec::default()
    };
    let segments = 2000;
    // Per channel: the residual of segment j, e - d (t - j I), which the model says is
    // constant within a segment. 1 ns stamp rounding plus float noise: 2e-9 s.
    let residuals = |rate_hz: f64| {
        let mut r = vec![f64::NAN; segments];
        for (t_s, e_s) in clock_errors(&spec, rate_hz, segments as f64 * interval_s) {
            let j = (t_s / interval_s).floor() as usize;
            let start_error_s = e_s - drift * (t_s - j as f64 * interval_s);
            if r[j].is_nan() {
                r[j] = start_error_s;
            }
            assert!(
                (start_error_s - r[j]).abs() < 2e-9,
                "t = {t_s}: {start_error_s} vs {}",
                r[j]
            );
        }
        r
    };
    let a = residuals(100.0);
    let b = residuals(256.0);
    assert!((a[0] - 0.01).abs() < 2e-9, "offset before the first resync");
    for j in 0..segments {
        assert!(
            (a[j] - b[j]).abs() < 2e-9,
            "segment {j}: {} vs {}",
            a[j],
            b[j]
        );
    }
    // Residuals ~ N(0, 50 us) over 1999 resyncs: SE of the RMS = rms / sqrt(2 n) = 1.6 %,
    // tolerance 4 SE; SE of the mean = rms / sqrt(n) = 1.1 us, tolerance 4 SE.
    let draws = &a[1..];
    let n = draws.len() as f64;
    let rms_s = (draws.iter().map(|r| r * r).sum::<f64>() / n).sqrt();
    let mean_s = draws.iter().sum::<f64>() / n;
    eprintln!("resync residual rms {rms_s:e} s (set {residual_rms_s:e}), mean {mean_s:e} s");
    assert!(
        (rms_s / residual_rms_s - 1.0).abs() < 4.0 * (0.5 / n).sqrt(),
        "{rms_s}"
    );
    assert!(mean_s.abs() < 4.0 * residual_rms_s / n.sqrt(), "{mean_s}");
    // The bound: |e| <= max |r_j| + |d| I everywhere after the first resync.
    let max_residual_s = draws.iter().fold(0.0_f64, |m, r| m.max(r.abs()));
    for (t_s, e_s) in clock_errors(&spec, 100.0, 100.0) {
        if t_s >= interval_s {
            assert!(
                e_s.abs() <= max_residual_s + drift * interval_s + 2e-9,
                "t = {t_s}"
            );
        }
    }
    // The events agree with what the samples saw.
    let clock = NodeClock::new(&spec, 100.0, node_rng(SEED), "c").unwrap();
    for event in clock.clock_error().resync_events().take(segments - 1) {
        let j = event.index as usize;
        assert_eq!(event.true_ns, j as u64 * 1_000_000_000);
        assert!((event.error_after_s - a[j]).abs() < 2e-9);
        assert!((event.error_before_s - (a[j - 1] + drift * interval_s)).abs() < 2e-9);
    }
}

#[test]
fn the_same_seed_gives_the_same_clock_and_another_seed_does_not() {
    let spec = ClockSpec {
        drift_ppm: -12.0,
        jitter_rms_s: 1e-5,
        resync_interval_s: Some(0.5),
        resync_residual_rms_s: 1e-4,
        ..ClockSpec::default()
    };
    let run = |seed| {
        let clock = NodeClock::new(&spec, 200.0, node_rng(seed), "c").unwrap();
        clock.take(2000).collect::<Vec<_>>()
    };
    assert_eq!(run(1), run(1));
    assert_ne!(run(1), run(2));
}

// ---------------------------------------------------------------------------------------
// Faults
// ---------------------------------------------------------------------------------------

fn injector(spec: &FaultSpec, rate_hz: f64, seed: u64) -> FaultInjector {
    let mut rng_for = |kind: &str| child_rng(seed, &format!("sensor/A1/faults/{kind}"));
    FaultInjector::new(spec, rate_hz, &mut rng_for, "sensors.0.faults").unwrap()
}

/// Outputs and labels of `n` samples on the exact grid `t_k = k * period_ns`; the input
/// is `k` itself, so any change of value is visible.
fn run(spec: &FaultSpec, period_ns: u64, n: u64, seed: u64) -> (Vec<Option<f64>>, Vec<FaultLabel>) {
    let mut faults = injector(spec, 1e9 / period_ns as f64, seed);
    let mut labels = Vec::new();
    let outputs = (0..n)
        .map(|k| {
            let out = faults.apply(k, k * period_ns, k as f64);
            faults.take_labels(&mut labels);
            out
        })
        .collect();
    (outputs, labels)
}

/// Lengths of the runs of lost samples.
fn loss_runs(outputs: impl Iterator<Item = bool>) -> Vec<u64> {
    let mut runs = Vec::new();
    let mut current = 0;
    for lost in outputs {
        if lost {
            current += 1;
        } else if current > 0 {
            runs.push(current);
            current = 0;
        }
    }
    runs
}

#[test]
fn random_loss_has_its_rate_and_runs_of_one_over_one_minus_p() {
    let p = 0.05;
    let spec = FaultSpec {
        loss: Some(LossSpec::Random { probability: p }),
        ..FaultSpec::default()
    };
    let n = 2_000_000;
    let (outputs, labels) = run(&spec, 10_000_000, n, SEED);
    let lost = outputs.iter().filter(|o| o.is_none()).count() as f64;
    // Binomial: SE = sqrt(p (1 - p) / n) = 1.5e-4; 4 SE.
    let se = (p * (1.0 - p) / n as f64).sqrt();
    assert!(
        (lost / n as f64 - p).abs() < 4.0 * se,
        "{}",
        lost / n as f64
    );
    // Runs are geometric on {1, 2, ...} with mean 1 / (1 - p) = 1.0526 and variance
    // p / (1 - p)^2; about n p (1 - p) = 95 000 runs give SE 7.6e-4; 4 SE. A run mean of 1
    // (no consecutive losses) would be 14 SE away.
    let runs = loss_runs(outputs.iter().map(Option::is_none));
    let mean_run = runs.iter().sum::<u64>() as f64 / runs.len() as f64;
    eprintln!(
        "random loss rate {} (set {p}), mean run {mean_run} (1/(1-p) = {})",
        lost / n as f64,
        1.0 / (1.0 - p)
    );
    let se_run = (p / (1.0 - p).powi(2) / runs.len() as f64).sqrt();
    assert!(
        (mean_run - 1.0 / (1.0 - p)).abs() < 4.0 * se_run,
        "{mean_run}"
    );
    // One single-sample label per lost sample, on it.
    assert_eq!(labels.len() as f64, lost);
    for l in &labels {
        assert_eq!(l.kind, FaultKind::LossRandom);
        assert_eq!(l.kind.name(), "loss_random");
        assert_eq!((l.end_ns - l.start_ns, l.magnitude), (10_000_000, 1.0));
        assert_eq!(outputs[(l.start_ns / 10_000_000) as usize], None);
    }
}

#[test]
fn bursty_loss_has_its_rate_and_mean_burst() {
    let (p, burst) = (0.02, 20.0);
    let spec = FaultSpec {
        loss: Some(LossSpec::Bursty {
            probability: p,
            mean_burst_samples: burst,
        }),
        ..FaultSpec::default()
    };
    let mut faults = injector(&spec, 1000.0, SEED);
    let n: u64 = 20_000_000;
    let (mut lost, mut current) = (0_u64, 0_u64);
    let (mut labels, mut label_lengths, mut burst_lengths) = (Vec::new(), Vec::new(), Vec::new());
    for k in 0..n {
        let out = faults.apply(k, k * 1_000_000, 1.0);
        if out.is_none() {
            lost += 1;
            current += 1;
        } else if current > 0 {
            burst_lengths.push(current);
            current = 0;
        }
        faults.take_labels(&mut labels);
        for l in labels.drain(..) {
            assert_eq!(l.kind, FaultKind::LossBurst);
            assert_eq!(current, 1, "a burst is labelled at its first lost sample");
            assert_eq!(l.start_ns, k * 1_000_000);
            assert_eq!(l.end_ns - l.start_ns, l.magnitude as u64 * 1_000_000);
            label_lengths.push(l.magnitude as u64);
        }
    }
    // One label per burst, announcing its length before the burst is over.
    let complete = burst_lengths.len();
    assert!(label_lengths.len() == complete || label_lengths.len() == complete + 1);
    assert_eq!(label_lengths[..complete], burst_lengths[..]);
    // Loss fraction of a two-state chain: variance inflated by (1 + rho) / (1 - rho) with
    // rho = 1 - p_gb - p_bg = 0.949, a factor 38: SE = sqrt(p (1 - p) 38 / n) = 1.9e-4;
    // 4 SE = 7.7e-4 (3.9 % of p).
    let rho = 1.0 - p / (burst * (1.0 - p)) - 1.0 / burst;
    let se = (p * (1.0 - p) * (1.0 + rho) / (1.0 - rho) / n as f64).sqrt();
    let rate = lost as f64 / n as f64;
    assert!((rate - p).abs() < 4.0 * se, "loss rate {rate}");
    // Bursts are geometric with mean 20, sd sqrt(1 - 1/20) * 20 = 19.5; ~20 000 bursts give
    // SE 0.14; 4 SE.
    let m = burst_lengths.len() as f64;
    let mean = burst_lengths.iter().sum::<u64>() as f64 / m;
    eprintln!("bursty loss rate {rate} (set {p}), mean burst {mean} (set {burst}) over {m} bursts");
    let se_burst = ((1.0 - 1.0 / burst).sqrt() * burst) / m.sqrt();
    assert!((mean - burst).abs() < 4.0 * se_burst, "mean burst {mean}");
}

/// Marks the samples (grid `k * period_ns`) inside labels of `kind`.
fn inside(labels: &[FaultLabel], kind: FaultKind, period_ns: u64, n: usize) -> Vec<bool> {
    let mut marked = vec![false; n];
    for l in labels.iter().filter(|l| l.kind == kind) {
        let first = l.start_ns.div_ceil(period_ns) as usize;
        let end = if l.end_ns == OPEN_END_NS {
            n
        } else {
            (l.end_ns.div_ceil(period_ns) as usize).min(n)
        };
        marked[first.min(n)..end].iter_mut().for_each(|m| *m = true);
    }
    marked
}

const PERIOD_NS: u64 = 5_000_000; // 200 Hz
const TWO_HOURS: u64 = 2 * 3600 * 200;

fn assert_labels_cover_exactly_the_changed_samples(
    spec: &FaultSpec,
    kind: FaultKind,
) -> (Vec<Option<f64>>, Vec<FaultLabel>) {
    let (outputs, labels) = run(spec, PERIOD_NS, TWO_HOURS, SEED);
    assert!(labels.iter().all(|l| l.kind == kind));
    assert!(
        labels.windows(2).all(|w| w[0].start_ns <= w[1].start_ns),
        "time order"
    );
    let marked = inside(&labels, kind, PERIOD_NS, outputs.len());
    for (k, (out, &in_label)) in outputs.iter().zip(&marked).enumerate() {
        let changed = *out != Some(k as f64);
        assert_eq!(changed, in_label, "{} at sample {k}: {out:?}", kind.name());
    }
    (outputs, labels)
}

#[test]
fn outages_drop_exactly_the_labelled_samples() {
    let spec = FaultSpec {
        outages: vec![
            OutageWindow {
                start_s: 100.0,
                duration_s: 30.0,
            },
            OutageWindow {
                start_s: 1000.0025,
                duration_s: 0.001,
            },
        ],
        outage_rate_per_hour: 20.0,
        outage_mean_duration_s: Some(20.0),
        ..FaultSpec::default()
    };
    let (outputs, labels) =
        assert_labels_cover_exactly_the_changed_samples(&spec, FaultKind::Outage);
    let fixed = labels
        .iter()
        .find(|l| l.start_ns == 100_000_000_000)
        .unwrap();
    assert_eq!((fixed.end_ns, fixed.magnitude), (130_000_000_000, 30.0));
    // 100.000 .. 129.995 s at 200 Hz: 6000 samples.
    assert_eq!(
        outputs[20_000..26_000]
            .iter()
            .filter(|o| o.is_none())
            .count(),
        6000
    );
    // A 1 ms window between two samples (1000.0025 s) is labelled and drops nothing
    // (checked by the cover test above); the random ones are there too.
    assert!(labels.iter().any(|l| l.start_ns == 1_000_002_500_000));
    assert!(labels.len() > 30, "{}", labels.len());
}

#[test]
fn stuck_values_hold_the_last_good_value_inside_their_labels() {
    let spec = FaultSpec {
        stuck: Some(StuckSpec {
            rate_per_hour: 30.0,
            mean_duration_s: 10.0,
        }),
        ..FaultSpec::default()
    };
    let (outputs, labels) =
        assert_labels_cover_exactly_the_changed_samples(&spec, FaultKind::Stuck);
    assert!(labels.len() > 30);
    for l in &labels {
        let k = (l.start_ns / PERIOD_NS) as usize;
        // The held value is the sample before the freeze (input k - 1), or that of an
        // earlier freeze still running.
        assert!(l.magnitude <= (k as f64 - 1.0).max(0.0), "{l:?}");
        assert_eq!(outputs[k], Some(l.magnitude));
    }
}

#[test]
fn spikes_offset_steps_and_dead_channels_change_exactly_the_labelled_samples() {
    let spikes = FaultSpec {
        spikes: Some(SpikeSpec {
            rate_per_hour: 100.0,
            amplitude: 0.5,
        }),
        ..FaultSpec::default()
    };
    let (outputs, labels) =
        assert_labels_cover_exactly_the_changed_samples(&spikes, FaultKind::Spike);
    for l in &labels {
        let k = (l.start_ns / PERIOD_NS) as usize;
        assert_eq!(l.end_ns - l.start_ns, PERIOD_NS);
        assert_eq!(outputs[k], Some(k as f64 + l.magnitude));
        assert_eq!(l.magnitude.abs(), 0.5);
    }
    let positive = labels.iter().filter(|l| l.magnitude > 0.0).count() as f64;
    // Signs are fair coins: SE = sqrt(n) / 2; 4 SE.
    let n = labels.len() as f64;
    assert!(
        (positive - n / 2.0).abs() < 2.0 * n.sqrt(),
        "{positive} of {n}"
    );

    let steps = FaultSpec {
        offset_steps: Some(OffsetStepSpec {
            rate_per_hour: 3.0,
            sigma: 0.25,
        }),
        ..FaultSpec::default()
    };
    let (outputs, labels) = run(&steps, PERIOD_NS, TWO_HOURS, SEED);
    assert!(!labels.is_empty());
    let mut cumulative = 0.0;
    let mut next = labels.iter().peekable();
    for (k, out) in outputs.iter().enumerate() {
        while let Some(l) = next.next_if(|l| l.start_ns <= k as u64 * PERIOD_NS) {
            assert_eq!((l.kind, l.end_ns), (FaultKind::OffsetStep, OPEN_END_NS));
            cumulative += l.magnitude;
        }
        let offset = out.unwrap() - k as f64;
        // The input k reaches 1.44e6, so the offset is resolved to ~2.3e-10.
        assert!(
            (offset - cumulative).abs() < 1e-9,
            "sample {k}: {offset} vs {cumulative}"
        );
    }

    let dead = FaultSpec {
        dead: Some(DeadSpec {
            from_s: 500.0,
            value: -1.0,
        }),
        ..FaultSpec::default()
    };
    let (outputs, labels) = assert_labels_cover_exactly_the_changed_samples(&dead, FaultKind::Dead);
    assert_eq!(labels.len(), 1);
    assert_eq!(
        (labels[0].start_ns, labels[0].end_ns),
        (500_000_000_000, OPEN_END_NS)
    );
    assert!(outputs[100_000..].iter().all(|o| *o == Some(-1.0)));
}

#[test]
fn random_fault_rates_and_durations_match_per_hour() {
    // 2e6 samples at 10 Hz: 55.6 h.
    let spec = FaultSpec {
        outage_rate_per_hour: 36.0,
        outage_mean_duration_s: Some(5.0),
        spikes: Some(SpikeSpec {
            rate_per_hour: 360.0,
            amplitude: 1.0,
        }),
        stuck: Some(StuckSpec {
            rate_per_hour: 36.0,
            mean_duration_s: 8.0,
        }),
        offset_steps: Some(OffsetStepSpec {
            rate_per_hour: 36.0,
            sigma: 1.0,
        }),
        ..FaultSpec::default()
    };
    let hours = 2e6 / 10.0 / 3600.0;
    let (_, labels) = run(&spec, 100_000_000, 2_000_000, SEED);
    let of = |kind| labels.iter().filter(move |l: &&FaultLabel| l.kind == kind);
    for (kind, rate) in [
        (FaultKind::Outage, 36.0),
        (FaultKind::Spike, 360.0),
        (FaultKind::Stuck, 36.0),
        (FaultKind::OffsetStep, 36.0),
    ] {
        // Poisson counts: SE = sqrt(expected); 4 SE (3.3 % for spikes, 10 % for the rest).
        let expected = rate * hours;
        let count = of(kind).count() as f64;
        eprintln!("{}: {count} events, expected {expected:.1}", kind.name());
        assert!(
            (count - expected).abs() < 4.0 * expected.sqrt(),
            "{}: {count} vs {expected}",
            kind.name()
        );
    }
    // Exponential durations: SE of the mean = mean / sqrt(count); 4 SE.
    for (kind, mean_s) in [(FaultKind::Outage, 5.0), (FaultKind::Stuck, 8.0)] {
        let durations: Vec<f64> = of(kind)
            .map(|l| (l.end_ns - l.start_ns) as f64 * 1e-9)
            .collect();
        let m = durations.len() as f64;
        let mean = durations.iter().sum::<f64>() / m;
        eprintln!("{}: mean duration {mean} s (set {mean_s})", kind.name());
        assert!(
            (mean - mean_s).abs() < 4.0 * mean_s / m.sqrt(),
            "{}: {mean}",
            kind.name()
        );
    }
    // Offset jumps ~ N(0, 1): SE of the RMS = 1 / sqrt(2 m); 4 SE.
    let jumps: Vec<f64> = of(FaultKind::OffsetStep).map(|l| l.magnitude).collect();
    let m = jumps.len() as f64;
    let rms = (jumps.iter().map(|j| j * j).sum::<f64>() / m).sqrt();
    assert!((rms - 1.0).abs() < 4.0 / (2.0 * m).sqrt(), "{rms}");
}

fn all_faults() -> FaultSpec {
    FaultSpec {
        loss: Some(LossSpec::Bursty {
            probability: 0.01,
            mean_burst_samples: 10.0,
        }),
        outages: vec![OutageWindow {
            start_s: 60.0,
            duration_s: 5.0,
        }],
        outage_rate_per_hour: 30.0,
        outage_mean_duration_s: Some(3.0),
        spikes: Some(SpikeSpec {
            rate_per_hour: 120.0,
            amplitude: 2.0,
        }),
        stuck: Some(StuckSpec {
            rate_per_hour: 30.0,
            mean_duration_s: 4.0,
        }),
        offset_steps: Some(OffsetStepSpec {
            rate_per_hour: 30.0,
            sigma: 0.1,
        }),
        dead: Some(DeadSpec {
            from_s: 3000.0,
            value: 0.0,
        }),
    }
}

fn without(labels: &[FaultLabel], kind: FaultKind) -> Vec<FaultLabel> {
    labels.iter().copied().filter(|l| l.kind != kind).collect()
}

#[test]
fn same_seed_same_output_and_each_kind_draws_from_its_own_stream() {
    let n = 720_000; // 1 h at 200 Hz
    let full = run(&all_faults(), PERIOD_NS, n, SEED);
    assert_eq!(full, run(&all_faults(), PERIOD_NS, n, SEED));
    assert_ne!(full.1, run(&all_faults(), PERIOD_NS, n, SEED + 1).1);
    let kinds: Vec<FaultKind> = full.1.iter().map(|l| l.kind).collect();
    for kind in [
        FaultKind::LossBurst,
        FaultKind::Outage,
        FaultKind::Spike,
        FaultKind::Stuck,
        FaultKind::OffsetStep,
        FaultKind::Dead,
    ] {
        assert!(kinds.contains(&kind), "{} occurs", kind.name());
    }
    // Switching one kind off leaves every other kind's labels as they were.
    let mut spec = all_faults();
    spec.spikes = None;
    assert_eq!(
        run(&spec, PERIOD_NS, n, SEED).1,
        without(&full.1, FaultKind::Spike)
    );
    let mut spec = all_faults();
    spec.loss = None;
    assert_eq!(
        run(&spec, PERIOD_NS, n, SEED).1,
        without(&full.1, FaultKind::LossBurst)
    );
    let mut spec = all_faults();
    spec.offset_steps = None;
    let (_, labels) = run(&spec, PERIOD_NS, n, SEED);
    // Stuck labels carry held values, which include offsets: compare their intervals only.
    let interval = |l: &FaultLabel| (l.kind, l.start_ns, l.end_ns);
    let kept: Vec<_> = without(&full.1, FaultKind::OffsetStep)
        .iter()
        .map(interval)
        .collect();
    assert_eq!(labels.iter().map(interval).collect::<Vec<_>>(), kept);
}

#[test]
fn a_channel_without_faults_passes_values_through() {
    let mut faults = injector(&FaultSpec::default(), 100.0, SEED);
    assert!(!faults.enabled());
    assert!(FaultSpec::default().is_empty());
    for k in 0..1000 {
        assert_eq!(
            faults.apply(k, k * 10_000_000, k as f64 * 0.5),
            Some(k as f64 * 0.5)
        );
    }
    let mut labels = Vec::new();
    faults.take_labels(&mut labels);
    assert!(labels.is_empty());
}

#[test]
fn bad_inputs_are_rejected_with_the_field_path_and_value() {
    let spec = FaultSpec {
        loss: Some(LossSpec::Random { probability: -0.1 }),
        ..FaultSpec::default()
    };
    let mut rng_for = |kind: &str| child_rng(SEED, kind);
    let e = FaultInjector::new(&spec, 100.0, &mut rng_for, "sensors.3.faults").unwrap_err();
    assert!(
        e.to_string()
            .starts_with("sensors.3.faults.loss.probability = -0.1 "),
        "{e}"
    );
    let e = FaultInjector::new(&FaultSpec::default(), 0.0, &mut rng_for, "s").unwrap_err();
    assert!(e.to_string().starts_with("rate_hz = 0 "), "{e}");
    let clock = ClockSpec {
        drift_ppm: -2000.0,
        ..ClockSpec::default()
    };
    let e = NodeClock::new(&clock, 100.0, node_rng(SEED), "daq_nodes.0.clock").unwrap_err();
    assert!(
        e.to_string()
            .starts_with("daq_nodes.0.clock.drift_ppm = -2000 "),
        "{e}"
    );
    let clock = ClockSpec {
        jitter_rms_s: f64::NAN,
        ..ClockSpec::default()
    };
    let e = NodeClock::new(&clock, 100.0, node_rng(SEED), "daq_nodes.0.clock").unwrap_err();
    assert!(
        e.to_string()
            .starts_with("daq_nodes.0.clock.jitter_rms_s = NaN "),
        "{e}"
    );
}
