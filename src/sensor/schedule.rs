//! The streaming front shared by every rate-changing stage: a ring buffer of the latest
//! solver samples and the schedule of output instants.
//!
//! Output `k` is due at `t_k = round(k * 1e9 / rate_hz)` ns. In solver samples it sits at
//! `n0 + frac` (`n0 = t_k div dt_ns`, `frac = (t_k mod dt_ns) / dt_ns`, both exact). An
//! evaluator that reads `lookback` samples before `n0` and `lookahead` after it can run once
//! sample `n0 + lookahead` has been pushed; that is when the output is handed over.
//! Samples before the first one are taken equal to it (hold), and [`OutputSchedule::flush`]
//! holds the last one.

use super::rate::ExactRate;

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

/// One due output: its instant, its fractional position after solver sample `n0`, and the
/// solver samples `n0 - lookback ..= n0 + lookahead` (index `lookback` is sample `n0`).
#[derive(Debug, Clone, Copy)]
pub(crate) struct Due<'a> {
    pub t_ns: u64,
    pub frac: f64,
    pub window: &'a [f64],
}

/// Ring buffer plus output schedule; see the module doc.
#[derive(Debug, Clone)]
pub(crate) struct OutputSchedule {
    rate: ExactRate,
    dt_ns: u64,
    lookback: usize,
    lookahead: usize,
    ring: Ring,
    /// Window for outputs completed by hold padding in `flush`.
    scratch: Vec<f64>,
    pushed: u64,
    last_value: f64,
    next_k: u64,
    next_t_ns: u64,
}

impl OutputSchedule {
    /// `rate` must not exceed `1e9 / dt_ns` (checked by the callers), so that successive
    /// outputs fall in distinct solver intervals.
    pub(crate) fn new(rate: ExactRate, dt_ns: u64, lookback: usize, lookahead: usize) -> Self {
        let width = lookback + lookahead + 1;
        Self {
            rate,
            dt_ns,
            lookback,
            lookahead,
            ring: Ring::new(width),
            scratch: vec![0.0; width],
            pushed: 0,
            last_value: 0.0,
            next_k: 0,
            next_t_ns: 0,
        }
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

    fn position(&self, t_ns: u64) -> (u64, f64) {
        let n0 = t_ns / self.dt_ns;
        let frac = (t_ns % self.dt_ns) as f64 / self.dt_ns as f64;
        (n0, frac)
    }

    fn advance(&mut self) {
        self.next_k += 1;
        self.next_t_ns = self.rate.instant_ns(self.next_k);
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
            let (n0, frac) = self.position(self.next_t_ns);
            if n0 + self.lookahead as u64 > newest {
                break;
            }
            // Outputs are handed over as soon as they are due and consecutive outputs lie
            // in distinct solver intervals (rate <= solver rate), so a due output always
            // ends its window exactly at the newest sample.
            debug_assert_eq!(n0 + self.lookahead as u64, newest);
            eval(Due {
                t_ns: self.next_t_ns,
                frac,
                window: &self.ring.latest()[..width],
            });
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
        while self.next_t_ns <= newest.saturating_mul(self.dt_ns) {
            let (n0, frac) = self.position(self.next_t_ns);
            // Samples of the window beyond the newest one; 1..=lookahead here.
            let missing = (n0 + self.lookahead as u64 - newest) as usize;
            let known = width - missing;
            self.scratch[..known].copy_from_slice(&self.ring.latest()[width - known..]);
            self.scratch[known..].fill(self.last_value);
            eval(Due {
                t_ns: self.next_t_ns,
                frac,
                window: &self.scratch,
            });
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
