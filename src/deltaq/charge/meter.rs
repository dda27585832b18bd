//! The cycle's Ah and time, counted in 32-bit steps.

/// mA x ms in one Q3 Ah (1/8 Ah = 450 C).
const Q3_MILLIAMP_MILLIS: u32 = 450_000_000;

/// A cycle's Ah (Q3, as 6052h) and seconds, counted in 32-bit steps (a
/// charger's controller divides 32-bit numbers in hardware, 64-bit ones
/// in a library routine).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub(super) struct CycleMeter {
    pub(super) q3: u32,
    /// Charge below one Q3 step, mA x ms.
    rest_mams: u32,
    /// Time below one millisecond (for the charge), us.
    rest_ms_us: u32,
    pub(super) seconds: u32,
    /// Time below one second, us.
    rest_s_us: u32,
    /// The battery's voltage when the cycle started (the output still
    /// off: its rest voltage), mV; where the state-of-charge estimate
    /// starts.
    pub(super) start_mv: u32,
}

impl CycleMeter {
    /// Nothing counted.
    pub(super) const ZERO: CycleMeter = CycleMeter {
        q3: 0,
        rest_mams: 0,
        rest_ms_us: 0,
        seconds: 0,
        rest_s_us: 0,
        start_mv: 0,
    };

    /// A new cycle's count, from a battery at rest at `start_mv`.
    pub(super) const fn from_rest(start_mv: u32) -> Self {
        CycleMeter {
            start_mv,
            ..Self::ZERO
        }
    }

    /// `current_ma` flowed for `dt_us`. A gap over an hour between two
    /// inputs counts as an hour, a current over 1 048 A as that much (a
    /// clock jump or a wild reading cannot stall the count).
    pub(super) fn add(&mut self, current_ma: u32, dt_us: u64) {
        let dt = dt_us.min(3_600_000_000) as u32;
        let us = self.rest_s_us + dt;
        self.seconds = self.seconds.saturating_add(us / 1_000_000);
        self.rest_s_us = us % 1_000_000;
        let us = self.rest_ms_us + dt;
        let mut ms = us / 1000;
        self.rest_ms_us = us % 1000;
        let i = current_ma.min(1 << 20);
        while ms > 0 {
            // 2047 ms x 2^20 mA plus the rest stays below 2^32.
            let chunk = ms.min(2047);
            ms -= chunk;
            let sum = self.rest_mams + i * chunk;
            self.q3 = self.q3.saturating_add(sum / Q3_MILLIAMP_MILLIS);
            self.rest_mams = sum % Q3_MILLIAMP_MILLIS;
        }
    }
}
