//! DAQ nodes: clocks (offset, drift, jitter, resynchronisation) and labelled faults.
//!
//! # Clock model (the contract)
//!
//! A node samples on its own oscillator, whose frequency is off by `drift_ppm`
//! (`d = drift_ppm * 1e-6`). Time `t` is true time in s from the run start.
//!
//! - True instant of sample `k` of a channel of nominal rate `fs`:
//!   `t_k = k / (fs (1 + d)) + jitter_k`; the true rate is `fs (1 + d)`. The jitter is white
//!   Gaussian, truncated at 3 sigma and scaled so its RMS is `jitter_rms_s`.
//! - The node stamps each sample with its clock `node_time(t) = t + e(t)`, with the clock
//!   error `e(t) = offset_s + d t` until the first resync. At each resync instant
//!   `j * resync_interval_s` (`j = 1, 2, ...`, true time) `e` jumps to a fresh draw
//!   `r_j ~ N(0, resync_residual_rms_s)` and grows again at the drift rate:
//!   `e(t) = r_j + d (t - j I)`.
//! - The stamp is `t_k^0 + e(t_k^0)` with `t_k^0` the instant without jitter (the node stamps
//!   the instant it meant to sample at). Substituting, the stamp is the nominal instant plus
//!   a per-segment constant: `k / fs + offset_s` before the first resync (exactly the nominal
//!   grid, however large the drift) and `k / fs + r_j - d j I` after resync `j`. Stamps are
//!   `i64` ns from the run start, `round(k * 1e9 / fs) + round(c_j * 1e9)`, computed from
//!   `k` (no accumulated sum), negative if the offset is. At a resync the stamps step by
//!   `r_j - e(j I^-)`, backwards if that is negative, as a stepped (not slewed) node clock
//!   does.
//! - `e(t)` is a function of the node's random stream and `t` only: `r_j` is read from the
//!   ChaCha block `j` of the node stream, so channels of one node at different rates, each
//!   holding a copy of the stream, see the same error function and the same resyncs
//!   without seeing each other ([`ClockError`]).
//!
//! # Faults
//!
//! [`FaultInjector`] applies a channel's [`FaultSpec`] at its output rate: packet loss
//! (random, or bursty Gilbert-Elliott, see `gilbert`), scheduled and random outages,
//! spikes, stuck values, offset steps and a dead channel. Every fault interval gets a
//! [`FaultLabel`] when its first sample is processed, so labels come out in time order
//! alongside the data.

mod clock;
mod draws;
mod fault_spec;
mod faults;
mod gilbert;

pub use clock::{
    ClockError, ClockSpec, ClockedSample, DaqNodeSpec, NodeClock, ResyncEvent,
    JITTER_TRUNCATION_SIGMAS, MAX_DRIFT_PPM,
};
pub use fault_spec::{
    DeadSpec, FaultSpec, LossSpec, OffsetStepSpec, OutageWindow, SpikeSpec, StuckSpec,
};
pub use faults::{FaultInjector, FaultKind, FaultLabel, FAULT_STREAMS, OPEN_END_NS};
pub use gilbert::gilbert_elliott_transitions;
