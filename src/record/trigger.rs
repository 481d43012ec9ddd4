//! Triggered records, as railway monitoring systems keep them: of the streams sampled all
//! the time (sensors, previews, axle loads, the deflected shape, vehicle states, GNSS),
//! only what falls in a window around each passage is written; events, vehicle and WIM
//! records, axle detections and fault labels always are. Each window opens with an event
//! saying what it holds, so a reader knows the gaps between windows are by design.

use super::records::{EventLevel, Record, Recorder};
use super::RunManifest;

/// One window of a triggered run: `[start_ns, end_ns]` and what triggered it.
#[derive(Debug, Clone, PartialEq)]
pub struct TriggerWindow {
    pub start_ns: u64,
    pub end_ns: u64,
    /// "vehicle 3 (train/ice3)".
    pub label: String,
}

/// Windows sorted and merged where they overlap (labels joined).
pub fn merged_windows(mut windows: Vec<TriggerWindow>) -> Vec<TriggerWindow> {
    windows.sort_by_key(|w| w.start_ns);
    let mut out: Vec<TriggerWindow> = Vec::new();
    for w in windows {
        match out.last_mut() {
            Some(last) if w.start_ns <= last.end_ns => {
                last.end_ns = last.end_ns.max(w.end_ns);
                last.label = format!("{}, {}", last.label, w.label);
            }
            _ => out.push(w),
        }
    }
    out
}

/// A recorder that passes on only the windows' records (see the module docs).
pub struct Triggered<'a> {
    inner: &'a mut dyn Recorder,
    windows: &'a [TriggerWindow],
    /// The first window not yet closed, and whether it has been announced.
    next: usize,
    announced: bool,
}

impl<'a> Triggered<'a> {
    pub fn new(inner: &'a mut dyn Recorder, windows: &'a [TriggerWindow]) -> Self {
        Triggered {
            inner,
            windows,
            next: 0,
            announced: false,
        }
    }

    /// Whether `t_ns` falls in a window, announcing a window on its first record.
    fn inside(&mut self, t_ns: u64) -> crate::Result<bool> {
        while self.windows.get(self.next).is_some_and(|w| w.end_ns < t_ns) {
            self.next += 1;
            self.announced = false;
        }
        let Some(w) = self.windows.get(self.next) else {
            return Ok(false);
        };
        if t_ns < w.start_ns {
            return Ok(false);
        }
        if !self.announced {
            self.announced = true;
            self.inner.record(Record::Event {
                t_ns,
                level: EventLevel::Info,
                text: format!(
                    "triggered record {} of {}: {:.3} s to {:.3} s ({})",
                    self.next + 1,
                    self.windows.len(),
                    w.start_ns as f64 * 1e-9,
                    w.end_ns as f64 * 1e-9,
                    w.label
                ),
            })?;
        }
        Ok(true)
    }
}

impl Recorder for Triggered<'_> {
    fn begin(&mut self, manifest: &RunManifest) -> crate::Result<()> {
        self.inner.begin(manifest)
    }

    fn record(&mut self, record: Record) -> crate::Result<()> {
        let sampled = matches!(
            record,
            Record::Sensor { .. }
                | Record::Preview { .. }
                | Record::AxleLoads { .. }
                | Record::BridgeShape { .. }
                | Record::VehicleState { .. }
                | Record::Gnss { .. }
        );
        if sampled && !self.inside(record.t_ns())? {
            return Ok(());
        }
        self.inner.record(record)
    }

    fn finish(&mut self) -> crate::Result<()> {
        self.inner.finish()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::record::VecRecorder;

    fn window(start_ns: u64, end_ns: u64, label: &str) -> TriggerWindow {
        TriggerWindow {
            start_ns,
            end_ns,
            label: label.into(),
        }
    }

    #[test]
    fn overlapping_windows_merge() {
        let w = merged_windows(vec![
            window(50, 70, "b"),
            window(10, 20, "a"),
            window(15, 30, "c"),
        ]);
        assert_eq!(w, vec![window(10, 30, "a, c"), window(50, 70, "b")]);
    }

    #[test]
    fn only_the_windows_sampled_records_pass_and_each_window_is_announced() {
        let windows = [window(10, 20, "train 1"), window(40, 50, "train 2")];
        let mut inner = VecRecorder::default();
        let mut gate = Triggered::new(&mut inner, &windows);
        for t in (0..60).step_by(5) {
            gate.record(Record::AxleLoads {
                t_ns: t,
                axles: Vec::new(),
            })
            .unwrap();
        }
        gate.record(Record::Event {
            t_ns: 60,
            level: EventLevel::Info,
            text: "kept".into(),
        })
        .unwrap();
        let times: Vec<(u64, bool)> = inner
            .records
            .iter()
            .map(|r| (r.t_ns(), matches!(r, Record::Event { .. })))
            .collect();
        assert_eq!(
            times,
            [
                (10, true),
                (10, false),
                (15, false),
                (20, false),
                (40, true),
                (40, false),
                (45, false),
                (50, false),
                (60, true)
            ]
        );
    }
}
