//! The streaming front shared by every rate-changing stage: a ring buffer of the latest
//! solver samples and the schedule of output instants.
//!
//! Output `k` is due at `t_k = round(k * 1e9 / rate_hz)` ns. In solver samples it sits at
//! `n0 + frac` (`n0 = t_k div dt_ns`, `frac = (t_k mod dt_ns) / dt_ns`, both exact). An
//! evaluator that reads `lookback` samples before `n0` and `lookahead` after it can run once
//! sample `n0 + lookahead` has been pushed; that is when the output is handed over.
//! Samples before the first one are taken equal to it (hold), and [`OutputSchedule::flush`]
//! holds the last one.
//!
//! With a DAQ clock ([`InstantSource`]) the instants are the node's true sampling instants
//! instead (drifting, jittered), and each output also carries the node's stamp.

use crate::base::rate::ExactRate;

/// The latest `cap` values, contiguous in memory: each value is written twice, at `head`
/// and `head + cap`, so the window ending at the newest value is one slice.
#[derive(Debug, Clone)]
struct Ring {
    buf: Vec<f64>,
    cap: usize,
    head: usize,
}

impl Ring {
    fn new(cap: usize) -> Self {
        Self {
            buf: vec![0.0; 2 * cap],
            cap,
            head: 0,
        }
    }

    fn fill(&mut self, value: f64) {
        self.buf.fill(value);
        self.head = 0;
    }

    fn push(&mut self, value: f64) {
        self.buf[self.head] = value;
        self.buf[self.head + self.cap] = value;
        self.head = (self.head + 1) % self.cap;
    }

    /// The `cap` latest values, oldest first.
    fn latest(&self) -> &[f64] {
        &self.buf[self.head..self.head + self.cap]
    }
}

/// Where the output instants come from when a DAQ node's clock sets them.
pub trait InstantSource: std::fmt::Debug + Send {
    /// The next output's true instant (ns since the run start, fractional) and the node's
    /// stamp for it (ns since the run start), for outputs 0, 1, 2, ... in turn. True
    /// instants must increase by at least one solver step between outputs.
    fn next_instant(&mut self) -> (f64, i64);
}

/// One due output: its true instant (rounded to ns), the node's stamp, its position
/// `n0 + frac` in solver samples, and the solver samples `n0 - lookback ..= n0 + lookahead`
/// (index `lookback` is sample `n0`).
#[derive(Debug, Clone, Copy)]
pub(crate) struct Due<'a> {
    pub t_ns: u64,
    pub stamp_ns: i64,
    pub n0: u64,
    pub frac: f64,
    pub window: &'a [f64],
}

/// Ring buffer plus output schedule; see the module doc.
#[derive(Debug)]
pub(crate) struct OutputSchedule {
    rate: ExactRate,
    /// The node clock, if any: then `next_*` come from it, not from `rate`.
    clock: Option<Box<dyn InstantSource>>,
    dt_ns: u64,
    lookback: usize,
    lookahead: usize,
    ring: Ring,
    /// Window for outputs completed by hold padding in `flush`.
    scratch: Vec<f64>,
    pushed: u64,
    last_value: f64,
    next_k: u64,
    /// The next output: true instant (ns, rounded), stamp, solver sample and fraction.
    next_t_ns: u64,
    next_stamp_ns: i64,
    next_n0: u64,
    next_frac: f64,
}

impl OutputSchedule {
    /// `rate` must not exceed `1e9 / dt_ns` (checked by the callers), so that successive
    /// outputs fall in distinct solver intervals.
    pub(crate) fn new(rate: ExactRate, dt_ns: u64, lookback: usize, lookahead: usize) -> Self {
        let width = lookback + lookahead + 1;
        let mut schedule = Self {
            rate,
            clock: None,
            dt_ns,
            lookback,
            lookahead,
            ring: Ring::new(width),
            scratch: vec![0.0; width],
            pushed: 0,
            last_value: 0.0,
            next_k: 0,
            next_t_ns: 0,
            next_stamp_ns: 0,
            next_n0: 0,
            next_frac: 0.0,
        };
        schedule.set_next();
        schedule
    }

    /// The same schedule with instants from a node clock (`rate` stays the nominal rate).
    pub(crate) fn with_clock(mut self, clock: Box<dyn InstantSource>) -> Self {
        self.clock = Some(clock);
        self.set_next();
        self
    }

    pub(crate) fn rate(&self) -> ExactRate {
        self.rate
    }

    pub(crate) fn dt_ns(&self) -> u64 {
        self.dt_ns
    }

    pub(crate) fn lookahead(&self) -> usize {
        self.lookahead
    }

    /// Number of outputs handed over so far.
    pub(crate) fn emitted(&self) -> u64 {
        self.next_k
    }

    /// Number of solver samples pushed so far.
    pub(crate) fn pushed(&self) -> u64 {
        self.pushed
    }

    /// Computes the `next_*` fields for output `next_k`: exactly in integer ns from the
    /// rate, or from the clock's fractional true instant.
    fn set_next(&mut self) {
        match self.clock.as_mut() {
            None => {
                let t_ns = self.rate.instant_ns(self.next_k);
                self.next_t_ns = t_ns;
                self.next_stamp_ns = t_ns as i64;
                self.next_n0 = t_ns / self.dt_ns;
                self.next_frac = (t_ns % self.dt_ns) as f64 / self.dt_ns as f64;
            }
            Some(clock) => {
                let (true_ns, stamp_ns) = clock.next_instant();
                let true_ns = true_ns.max(0.0);
                let position = true_ns / self.dt_ns as f64;
                self.next_t_ns = true_ns.round() as u64;
                self.next_stamp_ns = stamp_ns;
                self.next_n0 = position.floor() as u64;
                self.next_frac = position - position.floor();
            }
        }
    }

    fn advance(&mut self) {
        self.next_k += 1;
        self.set_next();
    }

    fn due<'w>(&self, window: &'w [f64]) -> Due<'w> {
        Due {
            t_ns: self.next_t_ns,
            stamp_ns: self.next_stamp_ns,
            n0: self.next_n0,
            frac: self.next_frac,
            window,
        }
    }

    /// Appends solver sample `pushed()` and calls `eval` for each output that became due.
    pub(crate) fn push(&mut self, value: f64, mut eval: impl FnMut(Due<'_>)) -> usize {
        if self.pushed == 0 {
            self.ring.fill(value);
        } else {
            self.ring.push(value);
        }
        self.pushed += 1;
        self.last_value = value;
        let newest = self.pushed - 1;
        let width = self.ring.cap;
        let mut count = 0;
        loop {
            let n0 = self.next_n0;
            if n0 + self.lookahead as u64 > newest {
                break;
            }
            // Outputs are handed over as soon as they are due, so a due output always
            // ends its window exactly at the newest sample.
            debug_assert_eq!(n0 + self.lookahead as u64, newest);
            eval(self.due(&self.ring.latest()[..width]));
            count += 1;
            self.advance();
        }
        count
    }

    /// Hands over every output up to the newest solver sample, completing the windows by
    /// holding the last value. Later pushes continue the stream normally.
    pub(crate) fn flush(&mut self, mut eval: impl FnMut(Due<'_>)) -> usize {
        if self.pushed == 0 {
            return 0;
        }
        let newest = self.pushed - 1;
        let width = self.ring.cap;
        let mut count = 0;
        while self.next_n0 < newest || (self.next_n0 == newest && self.next_frac == 0.0) {
            let n0 = self.next_n0;
            // Samples of the window beyond the newest one; 1..=lookahead here.
            let missing = (n0 + self.lookahead as u64 - newest) as usize;
            let known = width - missing;
            let mut scratch = std::mem::take(&mut self.scratch);
            scratch[..known].copy_from_slice(&self.ring.latest()[width - known..]);
            scratch[known..].fill(self.last_value);
            eval(self.due(&scratch));
            self.scratch = scratch;
            count += 1;
            self.advance();
        }
        count
    }

    /// Index of sample `n0` in a [`Due::window`].
    pub(crate) fn centre(&self) -> usize {
        self.lookback
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ring_keeps_latest_in_order() {
        let mut r = Ring::new(3);
        r.fill(0.0);
        for v in 1..=5 {
            r.push(v as f64);
        }
        assert_eq!(r.latest(), &[3.0, 4.0, 5.0]);
    }

    #[test]
    fn windows_are_centred_on_the_output_instant() {
        // 250 Hz out of 1 kHz: outputs every 4 samples, frac = 0.
        let rate = ExactRate::from_hz("r", 250.0).unwrap();
        let mut s = OutputSchedule::new(rate, 1_000_000, 2, 3);
        let mut seen = Vec::new();
        for i in 0..12 {
            s.push(i as f64, |d| seen.push((d.t_ns, d.frac, d.window.to_vec())));
        }
        // Output 0 waits for sample 3; samples before 0 hold the first value.
        assert_eq!(seen[0], (0, 0.0, vec![0.0, 0.0, 0.0, 1.0, 2.0, 3.0]));
        assert_eq!(
            seen[1],
            (4_000_000, 0.0, vec![2.0, 3.0, 4.0, 5.0, 6.0, 7.0])
        );
        assert_eq!(seen.len(), 3);
        seen.clear();
        // Flush: output 3 at sample 12 > newest 11 is not due; nothing is emitted.
        assert_eq!(
            s.flush(|d| seen.push((d.t_ns, d.frac, d.window.to_vec()))),
            0
        );
        s.push(12.0, |_| ());
        assert_eq!(
            s.flush(|d| seen.push((d.t_ns, d.frac, d.window.to_vec()))),
            1
        );
        assert_eq!(seen[0].2, vec![10.0, 11.0, 12.0, 12.0, 12.0, 12.0]);
    }
}
