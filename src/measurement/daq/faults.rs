//! Fault injection at a channel's output rate, with a label for every fault interval.

use rand::RngExt;
use rand_chacha::ChaCha8Rng;
use rand_distr::StandardNormal;

use super::draws::{exponential, field, seconds_to_ns, PoissonOnsets, NS_PER_S};
use super::fault_spec::FaultSpec;
use super::gilbert::{LossProcess, LossStep};
use crate::error::{require_positive, Result};

/// `end_ns` of a label whose effect lasts until the end of the run (offset steps, dead).
pub const OPEN_END_NS: u64 = u64::MAX;

/// Names passed to `rng_for` by [`FaultInjector::new`], one random stream per kind.
pub const FAULT_STREAMS: [&str; 5] = ["loss", "outage", "spike", "stuck", "offset_step"];

/// What a label marks.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum FaultKind {
    /// One sample lost by independent random loss.
    LossRandom,
    /// A burst of the Gilbert-Elliott loss process.
    LossBurst,
    /// Scheduled or random outage: every sample inside is lost.
    Outage,
    /// One sample offset by +/- the spike amplitude.
    Spike,
    /// The value is frozen at the last good one.
    Stuck,
    /// A persistent jump of the offset.
    OffsetStep,
    /// The channel reports a constant.
    Dead,
}

impl FaultKind {
    /// Stable name for output (`/events`, label topics).
    pub fn name(self) -> &'static str {
        match self {
            FaultKind::LossRandom => "loss_random",
            FaultKind::LossBurst => "loss_burst",
            FaultKind::Outage => "outage",
            FaultKind::Spike => "spike",
            FaultKind::Stuck => "stuck",
            FaultKind::OffsetStep => "offset_step",
            FaultKind::Dead => "dead",
        }
    }
}

/// One fault interval: the samples whose instants `t` (as passed to
/// [`FaultInjector::apply`]) satisfy `start_ns <= t < end_ns` are affected by it, all
/// others are not. `magnitude` is, by kind: lost samples (`loss_*`), duration in s
/// (`outage`), the signed amplitude (`spike`), the held value (`stuck`), the jump
/// (`offset_step`), the constant (`dead`). Sample-counted faults (loss, spike) end
/// `round(n * 1e9 / rate_hz)` ns after their first sample, so on the channel's regular
/// grid the interval holds exactly their `n` samples.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FaultLabel {
    /// What happened.
    pub kind: FaultKind,
    /// First affected instant, ns, in the time base of the `t_ns` given to `apply`.
    pub start_ns: u64,
    /// Exclusive; [`OPEN_END_NS`] for effects lasting to the end of the run.
    pub end_ns: u64,
    /// Size, by kind (see the type's doc).
    pub magnitude: f64,
}

/// Intervals with Poisson onsets snapped to the first sample at or after them and
/// exponential durations; overlapping ones merge their effect (each keeps its label).
#[derive(Debug, Clone)]
struct RandomIntervals {
    onsets: PoissonOnsets,
    mean_duration_s: f64,
    rng: ChaCha8Rng,
}

impl RandomIntervals {
    fn new(rate_per_hour: f64, mean_duration_s: f64, mut rng: ChaCha8Rng) -> Self {
        Self {
            onsets: PoissonOnsets::new(rate_per_hour, &mut rng),
            mean_duration_s,
            rng,
        }
    }

    /// Duration in ns of the next interval starting at the sample `t_ns`, if one is due.
    fn next_due(&mut self, t_ns: u64) -> Option<u64> {
        if !self.onsets.take_due(t_ns, &mut self.rng) {
            return None;
        }
        let duration_s = exponential(&mut self.rng, self.mean_duration_s);
        // At least 1 ns so that the onset sample is always inside its own label.
        Some(((duration_s * NS_PER_S).round() as u64).max(1))
    }
}

/// Point events (spikes, offset steps) with Poisson onsets and a normal draw each.
#[derive(Debug, Clone)]
struct RandomEvents {
    onsets: PoissonOnsets,
    rng: ChaCha8Rng,
}

impl RandomEvents {
    fn new(rate_per_hour: f64, mut rng: ChaCha8Rng) -> Self {
        Self {
            onsets: PoissonOnsets::new(rate_per_hour, &mut rng),
            rng,
        }
    }

    fn due(&mut self, t_ns: u64) -> bool {
        self.onsets.take_due(t_ns, &mut self.rng)
    }
}

/// Scheduled windows (sorted by start) plus random outages.
#[derive(Debug, Clone, Default)]
struct Outages {
    /// `(start_ns, end_ns, duration_s)`, sorted by start.
    windows: Vec<(u64, u64, f64)>,
    next_window: usize,
    random: Option<RandomIntervals>,
    /// Every sample before this instant is lost (0: none).
    lost_until_ns: u64,
}

#[derive(Debug, Clone, Copy)]
struct Dead {
    from_ns: u64,
    value: f64,
    started: bool,
}

#[derive(Debug, Clone)]
struct Stuck {
    intervals: RandomIntervals,
    held: f64,
    until_ns: u64,
}

/// Applies a channel's faults sample by sample and labels every fault interval. Built
/// once per channel; [`FaultInjector::apply`] does not allocate (labels go to an internal
/// buffer that keeps its capacity, drained by [`FaultInjector::take_labels`]).
///
/// Order of effects on a sample: offset steps add to the value; a stuck interval replaces
/// it with the held value (the last value out of these two stages, so a spike is never
/// held); a spike adds `+/- amplitude`; a dead channel replaces everything with its
/// constant; then an outage or a packet loss drops the sample. Each kind draws only from
/// its own stream, so switching one kind off leaves the others' faults unchanged.
#[derive(Debug, Clone)]
pub struct FaultInjector {
    period_ns: f64,
    loss: Option<LossProcess>,
    outages: Outages,
    spikes: Option<(RandomEvents, f64)>,
    stuck: Option<Stuck>,
    offsets: Option<(RandomEvents, f64)>,
    offset_sum: f64,
    dead: Option<Dead>,
    last_value: Option<f64>,
    labels: Vec<FaultLabel>,
    enabled: bool,
}

impl FaultInjector {
    /// The injector for `spec` on a channel sampled at `rate_hz`. `rng_for(name)` gives
    /// the stream of each enabled kind, named from [`FAULT_STREAMS`] (e.g.
    /// `|kind| child_rng(seed, &format!("sensor/{id}/faults/{kind}"))`). Errors name
    /// `<field_prefix>.<field>` and `rate_hz`.
    pub fn new(
        spec: &FaultSpec,
        rate_hz: f64,
        rng_for: &mut dyn FnMut(&str) -> ChaCha8Rng,
        field_prefix: &str,
    ) -> Result<Self> {
        spec.validate(field_prefix)?;
        require_positive("rate_hz", rate_hz)?;
        let loss = spec
            .loss
            .filter(|l| l.probability() > 0.0)
            .map(|l| LossProcess::new(&l, rng_for("loss")));
        let spikes = spec.spikes.filter(|s| s.rate_per_hour > 0.0).map(|s| {
            (
                RandomEvents::new(s.rate_per_hour, rng_for("spike")),
                s.amplitude,
            )
        });
        let offsets = spec
            .offset_steps
            .filter(|s| s.rate_per_hour > 0.0)
            .map(|s| {
                (
                    RandomEvents::new(s.rate_per_hour, rng_for("offset_step")),
                    s.sigma,
                )
            });
        let stuck = spec.stuck.filter(|s| s.rate_per_hour > 0.0).map(|s| Stuck {
            intervals: RandomIntervals::new(s.rate_per_hour, s.mean_duration_s, rng_for("stuck")),
            held: 0.0,
            until_ns: 0,
        });
        let outages = build_outages(spec, rng_for, field_prefix)?;
        let dead = match spec.dead {
            Some(d) => Some(Dead {
                from_ns: seconds_to_ns(&field(field_prefix, "dead.from_s"), d.from_s)?,
                value: d.value,
                started: false,
            }),
            None => None,
        };
        let enabled = loss.is_some()
            || spikes.is_some()
            || offsets.is_some()
            || stuck.is_some()
            || dead.is_some()
            || !outages.windows.is_empty()
            || outages.random.is_some();
        Ok(Self {
            period_ns: NS_PER_S / rate_hz,
            loss,
            outages,
            spikes,
            stuck,
            offsets,
            offset_sum: 0.0,
            dead,
            last_value: None,
            labels: Vec::with_capacity(if enabled { 16 } else { 0 }),
            enabled,
        })
    }

    /// Whether any fault can occur; when not, `apply` returns its input unchanged.
    pub fn enabled(&self) -> bool {
        self.enabled
    }

    /// The value recorded for sample `k` at instant `t_ns` whose fault-free value is
    /// `value`, or `None` if the sample is lost. Call once per sample, `k = 0, 1, ...`, with
    /// increasing `t_ns`. Labels of intervals starting at this sample (or since the
    /// previous one) become available to [`FaultInjector::take_labels`].
    pub fn apply(&mut self, k: u64, t_ns: u64, value: f64) -> Option<f64> {
        if !self.enabled {
            return Some(value);
        }
        let first_new_label = self.labels.len();
        // Scheduled starts (dead, outage windows) may precede t_ns, so they go first.
        let dead_value = self.poll_dead(t_ns);
        let in_outage = self.poll_outages(t_ns);
        let mut v = value + self.poll_offsets(t_ns);
        v = self.poll_stuck(t_ns, v);
        self.last_value = Some(v);
        v += self.poll_spikes(t_ns);
        let lost_packet = self.poll_loss(k, t_ns);
        if self.labels.len() > first_new_label + 1 {
            // In place and allocation-free; keeps labels in non-decreasing start order.
            self.labels[first_new_label..].sort_unstable_by_key(|l| (l.start_ns, l.kind));
        }
        if in_outage || lost_packet {
            None
        } else {
            Some(dead_value.unwrap_or(v))
        }
    }

    /// Moves the labels produced since the last call to `out`, in non-decreasing
    /// `start_ns` order. Call regularly (e.g. after every sample): the buffer grows until
    /// drained.
    pub fn take_labels(&mut self, out: &mut Vec<FaultLabel>) {
        out.append(&mut self.labels);
    }

    fn label(&mut self, kind: FaultKind, start_ns: u64, end_ns: u64, magnitude: f64) {
        self.labels.push(FaultLabel {
            kind,
            start_ns,
            end_ns,
            magnitude,
        });
    }

    /// End of a fault of `samples` samples whose first sample is at `t_ns`.
    fn end_after_samples(&self, t_ns: u64, samples: u64) -> u64 {
        let span_ns = (samples as f64 * self.period_ns).round() as u64;
        t_ns.saturating_add(span_ns)
    }

    fn poll_dead(&mut self, t_ns: u64) -> Option<f64> {
        let Self { dead, labels, .. } = self;
        let dead = dead.as_mut()?;
        if t_ns < dead.from_ns {
            return None;
        }
        if !dead.started {
            dead.started = true;
            labels.push(FaultLabel {
                kind: FaultKind::Dead,
                start_ns: dead.from_ns,
                end_ns: OPEN_END_NS,
                magnitude: dead.value,
            });
        }
        Some(dead.value)
    }

    fn poll_outages(&mut self, t_ns: u64) -> bool {
        while let Some(&(start_ns, end_ns, duration_s)) =
            self.outages.windows.get(self.outages.next_window)
        {
            if start_ns > t_ns {
                break;
            }
            self.outages.next_window += 1;
            self.outages.lost_until_ns = self.outages.lost_until_ns.max(end_ns);
            self.label(FaultKind::Outage, start_ns, end_ns, duration_s);
        }
        while let Some(duration_ns) = self.outages.random.as_mut().and_then(|r| r.next_due(t_ns)) {
            let end_ns = t_ns.saturating_add(duration_ns);
            self.outages.lost_until_ns = self.outages.lost_until_ns.max(end_ns);
            self.label(
                FaultKind::Outage,
                t_ns,
                end_ns,
                duration_ns as f64 / NS_PER_S,
            );
        }
        t_ns < self.outages.lost_until_ns
    }

    fn poll_offsets(&mut self, t_ns: u64) -> f64 {
        let Self {
            offsets,
            offset_sum,
            labels,
            ..
        } = self;
        if let Some((events, sigma)) = offsets.as_mut() {
            while events.due(t_ns) {
                let z: f64 = events.rng.sample(StandardNormal);
                let jump = *sigma * z;
                *offset_sum += jump;
                labels.push(FaultLabel {
                    kind: FaultKind::OffsetStep,
                    start_ns: t_ns,
                    end_ns: OPEN_END_NS,
                    magnitude: jump,
                });
            }
        }
        *offset_sum
    }

    fn poll_stuck(&mut self, t_ns: u64, value: f64) -> f64 {
        let Self {
            stuck,
            labels,
            last_value,
            ..
        } = self;
        let Some(stuck) = stuck.as_mut() else {
            return value;
        };
        while let Some(duration_ns) = stuck.intervals.next_due(t_ns) {
            if t_ns >= stuck.until_ns {
                // A new freeze holds the last value out of the offset and stuck stages
                // (the current one at the very first sample); a freeze starting inside
                // another keeps its held value.
                stuck.held = last_value.unwrap_or(value);
            }
            let end_ns = t_ns.saturating_add(duration_ns);
            stuck.until_ns = stuck.until_ns.max(end_ns);
            labels.push(FaultLabel {
                kind: FaultKind::Stuck,
                start_ns: t_ns,
                end_ns,
                magnitude: stuck.held,
            });
        }
        if t_ns < stuck.until_ns {
            stuck.held
        } else {
            value
        }
    }

    fn poll_spikes(&mut self, t_ns: u64) -> f64 {
        let end_ns = self.end_after_samples(t_ns, 1);
        let Self { spikes, labels, .. } = self;
        let mut total = 0.0;
        if let Some((events, amplitude)) = spikes.as_mut() {
            while events.due(t_ns) {
                let signed = if events.rng.random::<bool>() {
                    *amplitude
                } else {
                    -*amplitude
                };
                total += signed;
                labels.push(FaultLabel {
                    kind: FaultKind::Spike,
                    start_ns: t_ns,
                    end_ns,
                    magnitude: signed,
                });
            }
        }
        total
    }

    fn poll_loss(&mut self, k: u64, t_ns: u64) -> bool {
        let Some(loss) = self.loss.as_mut() else {
            return false;
        };
        let kind = if loss.is_bursty() {
            FaultKind::LossBurst
        } else {
            FaultKind::LossRandom
        };
        match loss.step(k) {
            LossStep::Kept => false,
            LossStep::Lost => true,
            LossStep::RunStarts { samples } => {
                let end_ns = self.end_after_samples(t_ns, samples);
                self.label(kind, t_ns, end_ns, samples as f64);
                true
            }
        }
    }
}

fn build_outages(
    spec: &FaultSpec,
    rng_for: &mut dyn FnMut(&str) -> ChaCha8Rng,
    field_prefix: &str,
) -> Result<Outages> {
    let mut windows = Vec::with_capacity(spec.outages.len());
    for (i, w) in spec.outages.iter().enumerate() {
        let start_ns = seconds_to_ns(
            &field(field_prefix, &format!("outages.{i}.start_s")),
            w.start_s,
        )?;
        let length_ns = seconds_to_ns(
            &field(field_prefix, &format!("outages.{i}.duration_s")),
            w.duration_s,
        )?;
        windows.push((
            start_ns,
            start_ns.saturating_add(length_ns.max(1)),
            w.duration_s,
        ));
    }
    windows.sort_by_key(|&(start_ns, end_ns, _)| (start_ns, end_ns));
    let random = spec
        .outage_mean_duration_s
        .filter(|_| spec.outage_rate_per_hour > 0.0)
        .map(|mean_s| RandomIntervals::new(spec.outage_rate_per_hour, mean_s, rng_for("outage")));
    Ok(Outages {
        windows,
        next_window: 0,
        random,
        lost_until_ns: 0,
    })
}
