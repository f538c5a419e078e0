//! A tiny deterministic generator for the suite's random scenes and probes (no dependency: the
//! suite's rows must be the same on every machine and every run, and xorshift64* is a few
//! lines).

use glam::{DMat3, DQuat};

/// xorshift64*.
pub struct Rng(pub u64);

impl Rng {
    /// Uniform in [0, 1).
    pub fn uniform(&mut self) -> f64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        (self.0.wrapping_mul(0x2545_F491_4F6C_DD1D) >> 11) as f64 / (1u64 << 53) as f64
    }

    /// A rotation from a normalised random quaternion.
    pub fn quat(&mut self) -> DQuat {
        DQuat::from_xyzw(
            self.uniform() - 0.5,
            self.uniform() - 0.5,
            self.uniform() - 0.5,
            self.uniform() - 0.5,
        )
        .normalize()
    }

    pub fn rotation(&mut self) -> DMat3 {
        DMat3::from_quat(self.quat())
    }
}
