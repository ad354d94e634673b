//! Deterministic Gaussian noise for the fairing tests (the same draws on every machine).

/// Deterministic uniform numbers in (0, 1] (xorshift64), and standard normals from them.
pub struct Noise(pub u64);

impl Noise {
    /// A generator whose stream depends on `seed` (mixed so nearby seeds do not start alike).
    pub fn seeded(seed: u64) -> Self {
        Noise(0x9e37_79b9_7f4a_7c15 ^ seed.wrapping_mul(0x2545_f491_4f6c_dd1d))
    }

    pub fn uniform(&mut self) -> f64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        ((self.0 >> 11) as f64 + 1.0) / (1u64 << 53) as f64
    }

    /// Standard normal (Box–Muller).
    pub fn gauss(&mut self) -> f64 {
        let (u1, u2) = (self.uniform(), self.uniform());
        (-2.0 * u1.ln()).sqrt() * (std::f64::consts::TAU * u2).cos()
    }
}
