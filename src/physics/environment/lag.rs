//! Structure temperature as a first-order lag of the air temperature.

/// `tau dT_s/dt = T_air - T_s`, advanced exactly for air that varies linearly between
/// consecutive calls (first-order hold), whatever the step: over a step h with air going
/// from a0 to a1 (slope r = (a1 - a0) / h),
/// `T_s(h) = a1 + (T_s(0) - a0) e^(-h/tau) - r tau (1 - e^(-h/tau))`
/// (the particular solution `a(t) - r tau` plus the decaying homogeneous part). A step in
/// air between two calls is thus seen as a ramp over that step; with constant air the
/// response is the exact exponential, 63.2 % after one `tau`.
#[derive(Debug, Clone, PartialEq)]
pub struct ThermalLag {
    tau_s: f64,
    structure_c: f64,
    /// Time and air temperature of the previous call (none before the first).
    last: Option<(f64, f64)>,
}

impl ThermalLag {
    /// A lag with time constant `tau_s` (> 0; validated by the caller) and structure
    /// temperature `structure_c` at the first call's time.
    pub fn new(tau_s: f64, structure_c: f64) -> Self {
        Self {
            tau_s,
            structure_c,
            last: None,
        }
    }

    /// Advances to `t_s` where the air is `air_c`; returns the structure temperature
    /// (degC). The first call only records the air; a call at or before the previous time
    /// changes nothing.
    pub fn step(&mut self, t_s: f64, air_c: f64) -> f64 {
        match self.last {
            Some((t0_s, air0_c)) if t_s > t0_s => {
                let h_s = t_s - t0_s;
                let decay = (-h_s / self.tau_s).exp();
                // tau (1 - e^(-h/tau)) / h, in (0, 1]; expm1 keeps it exact for h << tau.
                let ramp_weight = -(-h_s / self.tau_s).exp_m1() * self.tau_s / h_s;
                self.structure_c =
                    air_c + (self.structure_c - air0_c) * decay - (air_c - air0_c) * ramp_weight;
                self.last = Some((t_s, air_c));
            }
            Some(_) => {}
            None => self.last = Some((t_s, air_c)),
        }
        self.structure_c
    }

    /// The current structure temperature (degC).
    pub fn structure_c(&self) -> f64 {
        self.structure_c
    }
}
