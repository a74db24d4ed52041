//! Seeded randomness without global state: a SplitMix64 stream for sequential draws and
//! stateless integer hashes for point-wise procedural noise, so that the same seed always
//! gives the same output, on any thread and in any evaluation order.

/// One SplitMix64 mixing step (a bijective avalanche of 64 bits).
pub(crate) fn mix64(mut z: u64) -> u64 {
    z = z.wrapping_add(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// Hash of a seed and integer lattice coordinates.
pub fn hash3(seed: u64, i: i32, j: i32, k: i32) -> u64 {
    let mut h = mix64(seed ^ 0x5851_F42D_4C95_7F2D);
    h = mix64(h ^ (i as u32 as u64));
    h = mix64(h ^ ((j as u32 as u64) << 21));
    mix64(h ^ ((k as u32 as u64) << 42))
}

/// Maps 64 hash bits to a float in [0, 1).
pub fn unit(h: u64) -> f32 {
    (h >> 40) as f32 / (1u64 << 24) as f32
}

/// A small deterministic generator (SplitMix64).
#[derive(Clone, Debug)]
pub struct Rng {
    state: u64,
}

impl Rng {
    pub fn new(seed: u64) -> Self {
        Self {
            state: mix64(seed ^ 0xD1B5_4A32_D192_ED03),
        }
    }

    /// A generator for a named sub-stream, so adding draws to one part of a program does not
    /// shift the numbers another part sees.
    pub fn substream(seed: u64, stream: u64) -> Self {
        Self::new(mix64(seed) ^ mix64(stream.wrapping_mul(0x9E37_79B9_7F4A_7C15)))
    }

    pub fn next_u64(&mut self) -> u64 {
        self.state = self.state.wrapping_add(0x9E37_79B9_7F4A_7C15);
        mix64(self.state)
    }

    /// Uniform in [0, 1).
    pub fn uniform(&mut self) -> f32 {
        unit(self.next_u64())
    }

    /// Uniform in [lo, hi).
    pub fn range(&mut self, lo: f32, hi: f32) -> f32 {
        lo + (hi - lo) * self.uniform()
    }

    /// Standard normal (Box-Muller).
    pub fn normal(&mut self) -> f32 {
        let u1 = (self.uniform() as f64).max(1e-12);
        let u2 = self.uniform() as f64;
        ((-2.0 * u1.ln()).sqrt() * (std::f64::consts::TAU * u2).cos()) as f32
    }

    /// Uniform integer in [0, n).
    pub fn below(&mut self, n: usize) -> usize {
        (((self.next_u64() >> 11) as u128 * n as u128) >> 53) as usize
    }
}
