//! The preview of one sensor: its measured and true stream decimated by a whole factor
//! with the anti-alias filter, one sample per record, so that a viewer plots every run as
//! time series whatever its layout (a block message holds many samples, which a plot
//! panel cannot draw against time). The filter is the channel's anti-alias design (pass
//! band to 0.4 of the preview rate, stop band from 0.5) at 60 dB.
//!
//! Both streams are decimated by index, as the DAQ would: preview sample `j` is centred
//! on the sensor's sample `j M` and carries its true instant and node stamp. A sample the
//! DAQ lost enters the measured filter as the last value received (hold); a preview
//! sample whose centre was lost has no measured value. The truth preview is the measured
//! quantity's truth through the same filter, so the two compare like with like.

use std::collections::VecDeque;

use crate::error::Result;
use crate::measurement::sensor::{AntiAliasOptions, Decimator};
use crate::record::Record;

/// Stop-band attenuation of the preview's filter (dB): aliases 1000x below the signal
/// are invisible on a plot; the 80 dB of the DAQ channel would cost 1.6x the taps and
/// the latency (held in the run's merge buffer) for nothing a viewer shows.
pub const PREVIEW_ATTENUATION_DB: f64 = 60.0;

/// A centre sample waiting for its preview: (index, true instant, node stamp, lost).
type Centre = (u64, u64, i64, bool);

/// The two decimated streams of one sensor.
pub(super) struct Preview {
    sensor: usize,
    factor: u64,
    /// `None` for factor 1: the preview is the stream itself.
    filters: Option<(Decimator, Decimator)>,
    /// The last measured value received (the stand-in for a lost sample).
    last_measured: Option<f64>,
    centres: VecDeque<Centre>,
    samples: u64,
    /// Preview records in time order.
    out: VecDeque<Record>,
}

impl Preview {
    /// The preview of sensor `sensor` decimated by `factor` (>= 1).
    pub fn new(sensor: usize, factor: u64) -> Result<Self> {
        let filters = match factor {
            0 | 1 => None,
            _ => {
                let options = AntiAliasOptions {
                    stopband_attenuation_db: PREVIEW_ATTENUATION_DB,
                    ..AntiAliasOptions::default()
                };
                let measured = Decimator::new(factor, &options, "preview decimation factor")?;
                Some((measured.clone(), measured))
            }
        };
        Ok(Preview {
            sensor,
            factor: factor.max(1),
            filters,
            last_measured: None,
            centres: VecDeque::with_capacity(4),
            samples: 0,
            out: VecDeque::with_capacity(4),
        })
    }

    /// Sensor samples between a preview sample's centre and its hand-over.
    pub fn latency_samples(&self) -> u64 {
        self.filters
            .as_ref()
            .map_or(0, |(m, _)| m.latency_samples())
    }

    /// Feeds the sensor's next sample (measured `None`: lost).
    pub fn push(&mut self, t_ns: u64, stamp_ns: i64, measured: Option<f64>, truth: f64) {
        let k = self.samples;
        self.samples += 1;
        if k.is_multiple_of(self.factor) {
            self.centres
                .push_back((k, t_ns, stamp_ns, measured.is_none()));
        }
        if measured.is_some() {
            self.last_measured = measured;
        }
        let held = self.last_measured.unwrap_or(truth);
        let Some((m, t)) = self.filters.as_mut() else {
            self.emit(measured, truth);
            return;
        };
        let mut value = None;
        m.push(held, |_, y| value = Some(y));
        let mut truth_value = None;
        t.push(truth, |_, y| truth_value = Some(y));
        if let (Some(y), Some(yt)) = (value, truth_value) {
            self.emit(Some(y), yt);
        }
    }

    /// Queues the preview sample of the oldest waiting centre.
    fn emit(&mut self, measured: Option<f64>, truth: f64) {
        let Some((_, t_ns, stamp_ns, lost)) = self.centres.pop_front() else {
            return;
        };
        self.out.push_back(Record::Preview {
            sensor: self.sensor,
            t_ns,
            stamp_ns,
            measured: measured.filter(|_| !lost),
            truth,
        });
    }

    /// Completes the previews up to the last sample (end of the run).
    pub fn flush(&mut self) {
        let Some((m, t)) = self.filters.as_mut() else {
            return;
        };
        let mut measured = Vec::new();
        m.flush(|_, y| measured.push(y));
        let mut truth = Vec::new();
        t.flush(|_, y| truth.push(y));
        for (y, yt) in measured.into_iter().zip(truth) {
            self.emit(Some(y), yt);
        }
    }

    /// The time of the next preview record, if any.
    pub fn next_time_ns(&self) -> Option<u64> {
        self.out.front().map(Record::t_ns)
    }

    /// Removes the next preview record.
    pub fn pop(&mut self) -> Option<Record> {
        self.out.pop_front()
    }
}
