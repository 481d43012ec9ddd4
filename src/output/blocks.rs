//! The block layout: consecutive samples of one sensor packed into one message, as a DAQ
//! node sends packets (`SampleBlock`, `SensorTruthBlock`).
//!
//! A block is stamped with its first sample's time but can only be written once its last
//! sample is known, while other records (axle loads, events, other sensors) keep coming in
//! time order. MCAP files must stay in log-time order, so finished blocks and every other
//! record wait in a small reorder buffer: an item is released once no open block starts
//! before it. The buffer holds at most one block duration of records.

use std::collections::BTreeMap;

use crate::base::rate::ExactRate;
use crate::record::{Quantities, Record};

/// Which stream of a sensor a block belongs to.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Stream {
    /// The measured values (one column), on the node's clock; lost samples are gaps.
    Measured,
    /// The truth quantities (five columns, `Quantities` order), on true time, complete.
    Truth,
}

/// Samples of one stream of one sensor waiting to fill a block.
#[derive(Debug)]
pub(super) struct OpenBlock {
    stream: Stream,
    /// Nominal sample rate, exact (sample spacings need not be whole ns).
    rate: ExactRate,
    capacity: usize,
    /// Run-relative true time of the first sample (ns): the block's log time.
    start_ns: u64,
    /// The first sample's stamp (ns): the node clock's for measured blocks, else = start.
    start_stamp_ns: i64,
    pub columns: Vec<Vec<f64>>,
}

/// A block ready to be written.
#[derive(Debug)]
pub(super) struct ClosedBlock {
    pub sensor: usize,
    pub stream: Stream,
    /// Run-relative true time of the first sample (ns).
    pub start_ns: u64,
    /// Stamp of the first sample (ns since the run start, node clock for measured).
    pub start_stamp_ns: i64,
    pub columns: Vec<Vec<f64>>,
}

impl OpenBlock {
    pub fn new(stream: Stream, rate: ExactRate, capacity: usize) -> Self {
        let width = match stream {
            Stream::Measured => 1,
            Stream::Truth => Quantities::COUNT,
        };
        OpenBlock {
            stream,
            rate,
            capacity,
            start_ns: 0,
            start_stamp_ns: 0,
            columns: (0..width).map(|_| Vec::with_capacity(capacity)).collect(),
        }
    }

    fn len(&self) -> usize {
        self.columns[0].len()
    }

    /// True time of the first sample, if the block holds any.
    pub fn start_ns(&self) -> Option<u64> {
        (self.len() > 0).then_some(self.start_ns)
    }

    /// Whether a sample stamped `stamp_ns` continues this block without a gap (a sample
    /// the DAQ lost, or a clock resynchronisation, starts a new block, so that
    /// `timestamp + i * period` stays true inside a block).
    fn continues(&self, stamp_ns: i64) -> bool {
        let expected_ns =
            self.start_stamp_ns as i128 + self.rate.span_ns(self.len() as u64) as i128;
        // A quarter period either side: node clock jitter stays far inside, a lost sample
        // or a resync step far outside.
        let tolerance_ns = self.rate.span_ns(1) as i128 / 4;
        (stamp_ns as i128 - expected_ns).abs() < tolerance_ns
    }

    /// Adds a sample (`values` has one entry per column); blocks that close (interrupted
    /// by a gap before this sample, or full with it) go to `closed`.
    pub fn push(
        &mut self,
        sensor: usize,
        (t_ns, stamp_ns): (u64, i64),
        values: &[f64],
        closed: &mut Vec<ClosedBlock>,
    ) {
        if self.len() > 0 && !self.continues(stamp_ns) {
            closed.extend(self.take(sensor));
        }
        if self.len() == 0 {
            self.start_ns = t_ns;
            self.start_stamp_ns = stamp_ns;
        }
        for (column, &value) in self.columns.iter_mut().zip(values) {
            column.push(value);
        }
        if self.len() >= self.capacity {
            closed.extend(self.take(sensor));
        }
    }

    /// Empties the block into a `ClosedBlock` (None when empty).
    pub fn take(&mut self, sensor: usize) -> Option<ClosedBlock> {
        if self.len() == 0 {
            return None;
        }
        let capacity = self.capacity;
        Some(ClosedBlock {
            sensor,
            stream: self.stream,
            start_ns: self.start_ns,
            start_stamp_ns: self.start_stamp_ns,
            columns: self
                .columns
                .iter_mut()
                .map(|c| std::mem::replace(c, Vec::with_capacity(capacity)))
                .collect(),
        })
    }

    /// Nominal spacing of the samples rounded to whole ns (what the message carries).
    pub fn period_ns_rounded(&self) -> u64 {
        self.rate.period_ns_rounded()
    }
}

/// Something waiting for its turn in the file.
#[derive(Debug)]
pub(super) enum Pending {
    Record(Record),
    Block(ClosedBlock),
}

/// Items keyed by (run-relative time, arrival order): ties keep arrival order.
#[derive(Debug, Default)]
pub(super) struct Reorder {
    items: BTreeMap<(u64, u64), Pending>,
    arrivals: u64,
}

impl Reorder {
    pub fn push(&mut self, t_ns: u64, item: Pending) {
        self.items.insert((t_ns, self.arrivals), item);
        self.arrivals += 1;
    }

    /// Removes and returns the earliest item if its time is <= `watermark_ns`.
    pub fn pop_until(&mut self, watermark_ns: u64) -> Option<Pending> {
        let entry = self.items.first_entry()?;
        if entry.key().0 > watermark_ns {
            return None;
        }
        Some(entry.remove())
    }

    #[cfg(test)]
    pub fn len(&self) -> usize {
        self.items.len()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rate(hz: f64) -> ExactRate {
        ExactRate::from_hz("rate_hz", hz).unwrap()
    }

    fn push_all(block: &mut OpenBlock, times: &[u64]) -> Vec<ClosedBlock> {
        let mut closed = Vec::new();
        for (i, &t) in times.iter().enumerate() {
            block.push(0, (t, t as i64), &[i as f64; 5], &mut closed);
        }
        closed
    }

    #[test]
    fn full_blocks_close_at_capacity() {
        let mut block = OpenBlock::new(Stream::Truth, rate(200.0), 3);
        let times: Vec<u64> = (0..7).map(|k| k * 5_000_000).collect();
        let closed = push_all(&mut block, &times);
        assert_eq!(closed.len(), 2);
        assert_eq!(closed[0].columns[0], [0.0, 1.0, 2.0]);
        assert_eq!(closed[1].start_ns, 15_000_000);
        assert_eq!(closed[1].columns[4], [3.0, 4.0, 5.0]);
        let rest = block.take(0).unwrap();
        assert_eq!((rest.start_ns, rest.columns[0].len()), (30_000_000, 1));
        assert!(block.take(0).is_none());
    }

    #[test]
    fn a_gap_closes_the_block_early() {
        let mut block = OpenBlock::new(Stream::Measured, rate(200.0), 4);
        // Samples 0, 1, then 3 (2 lost), 4, 5, 6.
        let times: Vec<u64> = [0, 1, 3, 4, 5, 6].iter().map(|k| k * 5_000_000).collect();
        let closed = push_all(&mut block, &times);
        assert_eq!(closed.len(), 2);
        assert_eq!(closed[0].columns, [vec![0.0, 1.0]]);
        assert_eq!(closed[1].start_ns, 15_000_000);
        assert_eq!(closed[1].columns[0].len(), 4);
    }

    #[test]
    fn fractional_periods_do_not_accumulate_into_false_gaps() {
        // 300 Hz: 3 333 333.3 ns; sample times are rounded to whole ns by the DAQ clock.
        let mut block = OpenBlock::new(Stream::Truth, rate(300.0), 1000);
        let times: Vec<u64> = (0..1000u64)
            .map(|k| (k as f64 * 1e9 / 300.0).round() as u64)
            .collect();
        let closed = push_all(&mut block, &times);
        assert_eq!(closed.len(), 1);
        assert_eq!(closed[0].columns[0].len(), 1000);
    }

    #[test]
    fn a_clock_jump_starts_a_new_measured_block_with_the_new_stamp() {
        // True times regular; the node's stamps jump back 2 ms (resync) at sample 3.
        let mut block = OpenBlock::new(Stream::Measured, rate(200.0), 10);
        let mut closed = Vec::new();
        for k in 0..6u64 {
            let t = k * 5_000_000;
            let stamp = t as i64 + if k < 3 { 2_000_000 } else { 0 };
            block.push(0, (t, stamp), &[k as f64], &mut closed);
        }
        assert_eq!(closed.len(), 1);
        assert_eq!(closed[0].start_stamp_ns, 2_000_000);
        let rest = block.take(0).unwrap();
        assert_eq!(
            (rest.start_ns, rest.start_stamp_ns),
            (15_000_000, 15_000_000)
        );
    }

    #[test]
    fn reorder_releases_in_time_then_arrival_order() {
        let mut r = Reorder::default();
        let event = |t| {
            Pending::Record(Record::Event {
                t_ns: t,
                level: crate::record::EventLevel::Info,
                text: format!("{t}"),
            })
        };
        r.push(20, event(20));
        r.push(10, event(10));
        r.push(10, event(11));
        let mut out = Vec::new();
        while let Some(Pending::Record(Record::Event { text, .. })) = r.pop_until(15) {
            out.push(text);
        }
        assert_eq!(out, ["10", "11"]);
        assert_eq!(r.len(), 1);
    }
}
