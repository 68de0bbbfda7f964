//! The workspace's random number generator on the CPU: the twin of `shaders/rng.wesl`, so
//! tests can reproduce exactly the numbers a shader drew (a PCG hash, Jarzynski & Olano 2020,
//! stepped as a state).

/// One PCG hash round.
pub fn pcg_hash(x: u32) -> u32 {
    let state = x.wrapping_mul(747796405).wrapping_add(2891336453);
    let word = ((state >> ((state >> 28) + 4)) ^ state).wrapping_mul(277803737);
    (word >> 22) ^ word
}

/// A generator state; WGSL keeps it in a `u32` variable.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Rng(pub u32);

impl Rng {
    /// Seeds as `rng_seed(pixel, frame, pass_salt)` does.
    pub fn seed(pixel: [u32; 2], frame: u32, pass_salt: u32) -> Self {
        Rng(pcg_hash(
            pixel[0] ^ pcg_hash(pixel[1] ^ pcg_hash(frame ^ pcg_hash(pass_salt))),
        ))
    }

    /// The next 32 random bits (`rand_u32`).
    pub fn next_u32(&mut self) -> u32 {
        self.0 = self.0.wrapping_mul(747796405).wrapping_add(2891336453);
        let s = self.0;
        let word = ((s >> ((s >> 28) + 4)) ^ s).wrapping_mul(277803737);
        (word >> 22) ^ word
    }

    /// Uniform in [0, 1) from the top 24 bits (`rand_f32`).
    pub fn next_f32(&mut self) -> f32 {
        (self.next_u32() >> 8) as f32 * (1.0 / 16777216.0)
    }
}
