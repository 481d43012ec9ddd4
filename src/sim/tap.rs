//! A sensor tap: the DAQ channel of one sensor (anti-alias, resampling, measurement
//! chain, node clock) plus the noise-free truth of every response quantity at the same
//! sample instants.
//!
//! The truth needs no schedule of its own: the tap keeps the last solver samples of all
//! five quantities in a ring as long as the channel's filter window, and when the channel
//! hands over a sample at position `n0 + frac` (solver samples; with a node clock, the
//! node's true sampling instant), it interpolates each quantity there (cubic Hermite,
//! [`crate::measurement::sensor::hermite`]). Work per solver step is five stores; the interpolation runs
//! at the sensor rate.

use std::collections::VecDeque;

use super::preview::Preview;
use crate::measurement::daq::{FaultInjector, FaultKind, FaultLabel, OPEN_END_NS};
use crate::measurement::sensor::chain::ClipCounter;
use crate::measurement::sensor::{hermite, SensorChannel, HERMITE_LOOKAHEAD, HERMITE_LOOKBACK};
use crate::record::{Quantities, Record, SensorKind};

/// The record of a fault label found at the sample at `sample_ns`.
fn fault_record(sensor: usize, label: &FaultLabel, sample_ns: u64) -> Record {
    Record::Fault {
        t_ns: label.start_ns.max(sample_ns),
        sensor,
        kind: label.kind.name(),
        end_ns: (label.end_ns != OPEN_END_NS).then_some(label.end_ns),
        magnitude: label.magnitude,
    }
}

/// A sample as the channel hands it over, with the truth of every quantity interpolated
/// at its instant.
fn sample_record(
    sensor: usize,
    history: &History,
    s: crate::measurement::sensor::ChannelSample,
) -> Record {
    Record::Sensor {
        sensor,
        t_ns: s.t_ns,
        stamp_ns: s.stamp_ns,
        measured: Some(s.measured),
        truth: history.interpolate(s.n0, s.frac),
    }
}

/// The last `cap` solver samples of the five quantities (in column order), addressed by
/// solver index.
struct History {
    buf: Vec<[f64; Quantities::COUNT]>,
    pushed: u64,
}

impl History {
    fn new(cap: usize) -> Self {
        History {
            buf: vec![[0.0; Quantities::COUNT]; cap.max(HERMITE_LOOKBACK + HERMITE_LOOKAHEAD + 1)],
            pushed: 0,
        }
    }

    fn push(&mut self, values: &Quantities) {
        let cap = self.buf.len() as u64;
        self.buf[(self.pushed % cap) as usize] = values.to_columns();
        self.pushed += 1;
    }

    /// Sample `n` (may be before the first or after the last: those hold the first and
    /// the last sample, as the channel's filter does).
    fn at(&self, n: i64) -> &[f64; Quantities::COUNT] {
        let newest = self.pushed.saturating_sub(1) as i64;
        let n = n.clamp(0, newest) as u64;
        &self.buf[(n % self.buf.len() as u64) as usize]
    }

    /// The five quantities interpolated at `n0 + frac`.
    fn interpolate(&self, n0: u64, frac: f64) -> Quantities {
        let start = n0 as i64 - HERMITE_LOOKBACK as i64;
        let mut window = [[0.0; HERMITE_LOOKBACK + HERMITE_LOOKAHEAD + 1]; Quantities::COUNT];
        for (j, n) in (start..=n0 as i64 + HERMITE_LOOKAHEAD as i64).enumerate() {
            for (q, v) in self.at(n).iter().enumerate() {
                window[q][j] = *v;
            }
        }
        Quantities::from_columns(std::array::from_fn(|q| {
            hermite(frac, &window[q], HERMITE_LOOKBACK)
        }))
    }
}

/// Channel + truth history + faults of one sensor.
pub struct SensorTap {
    /// Index of the sensor in the scenario.
    sensor: usize,
    channel: SensorChannel,
    history: History,
    /// What the sensor measures of the quantities.
    pub kind: SensorKind,
    faults: Option<FaultInjector>,
    labels: Vec<FaultLabel>,
    /// Sensor samples and fault labels, in time order.
    ready: VecDeque<Record>,
    emitted: u64,
    /// Single samples lost at random so far (labelled on `/truth/faults` only).
    random_losses: u64,
    /// The ADC stage's count of clipped samples, if the chain has an ADC.
    clipped: Option<ClipCounter>,
    /// The decimated preview of both streams, if the run writes one.
    preview: Option<Preview>,
    /// Nominal sample period (ns), for the preview's latency.
    period_ns: u64,
}

impl SensorTap {
    /// A tap for sensor `sensor` around `channel` (built with the sensor's rate, chain
    /// and clock), measuring what a sensor of `kind` measures, with the sensor's faults
    /// (`None`: none).
    pub fn new(
        sensor: usize,
        channel: SensorChannel,
        kind: SensorKind,
        faults: Option<FaultInjector>,
    ) -> Self {
        let (_, width) = channel.window_geometry();
        let period_ns = channel.output_instant_ns(1);
        SensorTap {
            sensor,
            channel,
            // The channel's window reaches HERMITE_LOOKBACK (or more) samples behind n0.
            history: History::new(width),
            kind,
            faults: faults.filter(FaultInjector::enabled),
            labels: Vec::with_capacity(4),
            ready: VecDeque::with_capacity(8),
            emitted: 0,
            random_losses: 0,
            clipped: None,
            preview: None,
            period_ns,
        }
    }

    /// The same tap writing a preview of both streams decimated by `factor`.
    pub(super) fn with_preview(mut self, preview: Option<Preview>) -> Self {
        self.preview = preview;
        self
    }

    /// The same tap reporting the chain's clipped samples at the end of the run.
    pub fn with_clip_counter(mut self, clipped: Option<ClipCounter>) -> Self {
        self.clipped = clipped;
        self
    }

    /// What the run announces on `/events` about this sensor at its end: the samples
    /// lost at random (each has its own label on `/truth/faults`, one line here rather
    /// than one per sample) and the samples clipped at the ADC range.
    pub fn end_notes(&self, id: &str) -> Vec<String> {
        let mut notes = Vec::new();
        if self.random_losses > 0 {
            notes.push(format!(
                "sensor {id}: {} samples lost at random (each labelled on /truth/faults)",
                self.random_losses
            ));
        }
        if let Some(clipped) = self
            .clipped
            .as_ref()
            .map(ClipCounter::get)
            .filter(|&n| n > 0)
        {
            notes.push(format!(
                "sensor {id}: {clipped} samples clipped at the ADC range (off-scale)"
            ));
        }
        notes
    }

    /// Feeds one solver step of all quantities at the sensor's point.
    pub fn push(&mut self, values: &Quantities) {
        self.history.push(values);
        let measured = values.measured_by(self.kind);
        self.hand_over(|channel, emit| channel.push(measured, emit));
    }

    /// Flushes the filters at the end of the run.
    pub fn flush(&mut self) {
        self.hand_over(|channel, emit| channel.flush(emit));
        if let Some(preview) = self.preview.as_mut() {
            preview.flush();
        }
    }

    /// Queues the samples `drive` makes the channel emit, with their truth from the
    /// history, then passes them through the faults.
    fn hand_over(
        &mut self,
        drive: impl FnOnce(
            &mut SensorChannel,
            &mut dyn FnMut(crate::measurement::sensor::ChannelSample),
        ) -> usize,
    ) {
        let Self {
            sensor,
            channel,
            history,
            ready,
            ..
        } = self;
        let first = ready.len();
        let count = drive(channel, &mut |s| {
            ready.push_back(sample_record(*sensor, history, s))
        });
        self.apply_faults(count);
        if let Some(preview) = self.preview.as_mut() {
            for record in self.ready.range(first..) {
                if let Record::Sensor {
                    t_ns,
                    stamp_ns,
                    measured,
                    truth,
                    ..
                } = record
                {
                    preview.push(*t_ns, *stamp_ns, *measured, truth.measured_by(self.kind));
                }
            }
        }
    }

    /// Passes the last `count` queued samples through the faults (a lost sample keeps its
    /// truth, with `measured = None`) and queues the labels each sample starts just before
    /// it. A label is stamped with its first affected sample: a configured outage may begin
    /// between two samples, and an earlier stamp could precede records already written.
    fn apply_faults(&mut self, count: usize) {
        let Some(faults) = self.faults.as_mut() else {
            return;
        };
        let mut i = self.ready.len() - count;
        while i < self.ready.len() {
            if let Some(Record::Sensor { t_ns, measured, .. }) = self.ready.get_mut(i) {
                let t_ns = *t_ns;
                if let Some(value) = *measured {
                    *measured = faults.apply(self.emitted, t_ns, value);
                }
                self.emitted += 1;
                faults.take_labels(&mut self.labels);
                for label in self.labels.drain(..) {
                    self.random_losses += u64::from(label.kind == FaultKind::LossRandom);
                    self.ready
                        .insert(i, fault_record(self.sensor, &label, t_ns));
                    i += 1;
                }
            }
            i += 1;
        }
    }

    /// The time of the next record, if any.
    pub fn next_time_ns(&self) -> Option<u64> {
        let sample = self.ready.front().map(Record::t_ns);
        let preview = self.preview.as_ref().and_then(Preview::next_time_ns);
        match (sample, preview) {
            (Some(a), Some(b)) => Some(a.min(b)),
            (a, b) => a.or(b),
        }
    }

    /// Removes the next record (a sample, a fault label or a preview sample; the
    /// preview's first on a tie: it is centred on a sample already written).
    pub fn pop(&mut self) -> Option<Record> {
        let sample = self.ready.front().map(Record::t_ns);
        let preview = self.preview.as_ref().and_then(Preview::next_time_ns);
        match (sample, preview) {
            (Some(a), Some(b)) if b <= a => self.preview.as_mut().and_then(Preview::pop),
            (None, Some(_)) => self.preview.as_mut().and_then(Preview::pop),
            _ => self.ready.pop_front(),
        }
    }

    /// Worst-case delay between an instant and the emission of its record (ns): the
    /// channel's filter, then the preview's, over (half-width + 1) sample periods with
    /// 1 % to spare for a drifting node clock.
    pub fn latency_ns(&self) -> u64 {
        let preview_samples = self.preview.as_ref().map_or(0, |p| p.latency_samples() + 1);
        self.channel.latency_ns() + preview_samples * self.period_ns * 101 / 100
    }

    /// The channel (rate, taps, noise).
    pub fn channel(&self) -> &SensorChannel {
        &self.channel
    }
}
