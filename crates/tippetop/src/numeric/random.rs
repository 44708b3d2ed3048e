//! Counter-based random numbers for stochastic runs: every draw is a pure
//! function of (seed, run, step, index), so any step of any run can be
//! regenerated alone, in any order, on any thread, and results cannot depend
//! on threads, shards or the order runs are done in.
//!
//! # Generator
//!
//! Philox4x32-10 (Salmon, Moraes, Dror & Shaw, "Parallel random numbers: as
//! easy as 1, 2, 3", SC'11), the block function of the
//! [`rand_philox`](https://crates.io/crates/rand_philox) crate, used with its
//! default features off (no dependencies, `no_std`, no `unsafe`). Crates
//! checked (crates.io, 2026-11): `rand_philox` 0.2 (taken: the block function
//! is public and pure, pinned by the crate's tests to the three Random123
//! known-answer vectors; a step's few blocks are evaluated one by one with
//! it, see [`Stream::normals`]); `philox` 0.0.0 (one unstable 2019 release
//! on `generic-array` 0.12, no tests); the Philox inside `urng`, `rng-pack`
//! and `ferray-random` (parts of larger general-purpose RNG collections, with
//! seeding by SplitMix or internal state rather than an exposed
//! (counter, key) function); no crate named `random123`, `cbrng` or
//! `threefry` exists. Our tests check the block function again against the
//! Random123 distribution's own `kat_vectors` file, through the key layout
//! below.
//!
//! # Key layout
//!
//! One Philox block maps a 128-bit counter `c0 c1 c2 c3` and a 64-bit key
//! `k0 k1` (32-bit words) to four 32-bit words. A [`Stream`] puts
//!
//! | word | carries |
//! |---|---|
//! | `k0`, `k1` | `seed`, low and high 32 bits (unmixed: Philox's keys need no conditioning) |
//! | `c0` | block index within the step (0 … 2³² − 1) |
//! | `c1`, `c2` | `step`, low and high 32 bits (any `u64`) |
//! | `c3` | `run` (0 … 2³² − 1, [`MAX_RUN`]) |
//!
//! The map from (seed, run, step, block) to (key, counter) is a bijection, so
//! no two draws of any seed, run or step share a block. Limits: runs
//! `< 2³²`; at most 2³² blocks, i.e. 2³³ uniforms or normals, per step; steps
//! are unlimited (`u64`). The whole key is the Philox input, so the first
//! block of seed 0, run 0, step 0 is Random123's first `philox4x32_10`
//! known-answer vector.
//!
//! # Uniforms and normals
//!
//! Block `j` of a step gives two 64-bit words `w0 | w1 << 32` and
//! `w2 | w3 << 32` of its output words, hence uniforms `2j` and `2j + 1`
//! ([`unit_open`]: the top 52 bits as an odd multiple of 2⁻⁵³, exactly
//! representable, in [2⁻⁵³, 1 − 2⁻⁵³]: never 0 or 1, mean exactly 1/2, and
//! `1 − u` has the same distribution).
//!
//! Normals `2j` and `2j + 1` are the Box–Muller pair of those two uniforms
//! ([`box_muller`]): `r = √(−2 ln u₁)`, `z = (r cos 2πu₂, r sin 2πu₂)`. Chosen
//! because it is exact in distribution (for exact uniforms; here the only
//! approximation is the 2⁻⁵³ grid, which truncates the tail at
//! `|z| ≤ √(106 ln 2) = 8.57`, a probability of 10⁻¹⁷) and because it uses a
//! fixed number of words per normal: a rejection method (Ziggurat, polar)
//! would be faster per normal but would draw a variable number of blocks,
//! breaking the "k-th normal of the step is block k/2" rule that makes each
//! normal addressable on its own. Its cost is one `ln`, one `sqrt` and one
//! `sin_cos` per pair, our own ([`crate::detmath`], fdlibm's polynomials:
//! below 2 ulps, branch-free, vectorised over the pairs of a call;
//! docs/performance.md#random-streams and #langevin-step).
//!
//! Uniform `k` and normal `k` of one step come from the same block: a caller
//! that needs both kinds in one step takes them at disjoint indices.
//!
//! Reproducibility: the words and the uniforms are integer or exact
//! arithmetic, and the normals plain IEEE double arithmetic (our own `ln`
//! and `sin_cos`, no fused multiply–add): bit-identical on every platform.
//! (Before commit 65ed400 the normals used the platform's libm; today's
//! normals differ from those in the last bits, so stochastic outputs of
//! older versions are not reproduced bit for bit.)

use rand_philox::philox4x32_10;

/// The largest run index a [`Stream`] takes (the run is one 32-bit counter
/// word).
pub const MAX_RUN: u64 = u32::MAX as u64;

/// The number of Philox blocks one step can address (the block index is one
/// 32-bit counter word); each block gives two uniforms or two normals.
pub const BLOCKS_PER_STEP: u64 = 1 << 32;

/// 2⁻⁵³.
const TWO_M53: f64 = 1.0 / 9_007_199_254_740_992.0;

/// The random numbers of one run of one seed: a key, not a state. Every
/// method takes `&self` and is a pure function of (seed, run, step, index);
/// see the module documentation for the key layout.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Stream {
    key: [u32; 2],
    run: u32,
}

impl Stream {
    /// The stream of run `run` of `seed`.
    ///
    /// # Panics
    /// If `run > MAX_RUN` (2³² − 1): the run is one 32-bit counter word.
    #[must_use]
    pub fn new(seed: u64, run: u64) -> Self {
        let run = u32::try_from(run)
            .unwrap_or_else(|_| panic!("random stream: run {run} is above MAX_RUN = {MAX_RUN}"));
        Stream {
            key: [seed as u32, (seed >> 32) as u32],
            run,
        }
    }

    /// The seed this stream was built with.
    #[must_use]
    pub fn seed(&self) -> u64 {
        u64::from(self.key[0]) | (u64::from(self.key[1]) << 32)
    }

    /// The run index this stream was built with.
    #[must_use]
    pub fn run(&self) -> u64 {
        u64::from(self.run)
    }

    /// The Philox counter of `block` of `step` as one little-endian `u128`
    /// (words `c0 = block`, `c1 c2 = step`, `c3 = run`).
    fn counter(&self, step: u64, block: u32) -> u128 {
        u128::from(block) | (u128::from(step) << 32) | (u128::from(self.run) << 96)
    }

    /// The four raw 32-bit words of `block` of `step`.
    #[must_use]
    pub fn block(&self, step: u64, block: u32) -> [u32; 4] {
        let c = self.counter(step, block);
        philox4x32_10(
            [
                c as u32,
                (c >> 32) as u32,
                (c >> 64) as u32,
                (c >> 96) as u32,
            ],
            self.key,
        )
    }

    /// The two uniforms of `block` of `step` (uniforms `2 block`, `2 block + 1`).
    fn uniform_pair(&self, step: u64, block: u32) -> (f64, f64) {
        let w = self.block(step, block);
        (
            unit_open(words_u64(w[0], w[1])),
            unit_open(words_u64(w[2], w[3])),
        )
    }

    /// Uniform number `k` of `step`, in (0, 1) (see [`unit_open`]).
    ///
    /// # Panics
    /// If `k ≥ 2 BLOCKS_PER_STEP`.
    #[must_use]
    pub fn uniform(&self, step: u64, k: u64) -> f64 {
        let (u1, u2) = self.uniform_pair(step, block_of(k));
        if k % 2 == 0 { u1 } else { u2 }
    }

    /// Standard normal number `k` of `step` (see [`box_muller`]): the same
    /// bits as `normals(step, ..)[k]`.
    ///
    /// # Panics
    /// If `k ≥ 2 BLOCKS_PER_STEP`.
    #[must_use]
    pub fn normal(&self, step: u64, k: u64) -> f64 {
        let (u1, u2) = self.uniform_pair(step, block_of(k));
        let (z0, z1) = box_muller(u1, u2);
        if k % 2 == 0 { z0 } else { z1 }
    }

    /// Uniforms `0 … out.len() − 1` of `step` into `out` (a prefix of a longer
    /// call gives the same values).
    ///
    /// # Panics
    /// If `out.len() > 2 BLOCKS_PER_STEP`.
    pub fn uniforms(&self, step: u64, out: &mut [f64]) {
        self.fill_pairs(step, out, |u1, u2| (u1, u2));
    }

    /// Standard normals `0 … out.len() − 1` of `step` into `out` (a prefix of
    /// a longer call gives the same values; an odd length drops the second
    /// normal of the last pair).
    ///
    /// # Panics
    /// If `out.len() > 2 BLOCKS_PER_STEP`.
    pub fn normals(&self, step: u64, out: &mut [f64]) {
        self.fill_pairs(step, out, box_muller);
    }

    /// `out[2j], out[2j + 1] = pair(uniforms of block j)`: for each group
    /// of [`LANES`] blocks, the blocks one by one (`philox4x32_10`, the same
    /// words as [`Stream::block`]), their uniforms into an array, then the
    /// pairs in a fixed-length loop the compiler vectorises (`pair` is
    /// branch-free for the normals). `rand_philox`'s
    /// `fill_u32` takes its scalar path one word at a time below 16
    /// blocks: the same words; 10 normals take 1 354 instructions here, 2 446
    /// with it (callgrind, docs/performance.md).
    fn fill_pairs(&self, step: u64, out: &mut [f64], pair: impl Fn(f64, f64) -> (f64, f64)) {
        assert!(
            out.len() as u64 <= 2 * BLOCKS_PER_STEP,
            "random stream: {} numbers in one step, above 2^33",
            out.len()
        );
        let hi = [step as u32, (step >> 32) as u32, self.run];
        for (g, chunk) in out.chunks_mut(2 * LANES).enumerate() {
            // Block index of lane l: g LANES + l (< 2³² by the assert).
            let first = (g * LANES) as u32;
            let blocks = chunk.len().div_ceil(2);
            let mut u = [0.5; 2 * LANES];
            for l in 0..blocks {
                let w = philox4x32_10(
                    [first.wrapping_add(l as u32), hi[0], hi[1], hi[2]],
                    self.key,
                );
                u[2 * l] = unit_open(words_u64(w[0], w[1]));
                u[2 * l + 1] = unit_open(words_u64(w[2], w[3]));
            }
            let z = transform(&u, &pair);
            debug_assert!(blocks <= LANES);
            chunk.copy_from_slice(&z[..chunk.len()]);
        }
    }
}

/// The pairs of a group: `pair` over the [`LANES`] uniform pairs, in the
/// AVX2 build where the CPU has it (4 lanes of `f64` per register against
/// SSE2's 2; the same operations, none fused, so the same bits: test
/// `avx2_transform_is_the_baseline_bit_for_bit`). 10 normals: 1 311 → 1 062
/// instructions, 91 → 82 ns (docs/performance.md#langevin-step).
#[inline(always)]
fn transform(u: &[f64; 2 * LANES], pair: &impl Fn(f64, f64) -> (f64, f64)) -> [f64; 2 * LANES] {
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx2") {
        // SAFETY: the CPU has AVX2 (checked just above).
        return unsafe { transform_avx2(u, pair) };
    }
    transform_baseline(u, pair)
}

/// [`transform`] in the baseline build.
#[inline(always)]
fn transform_baseline(
    u: &[f64; 2 * LANES],
    pair: &impl Fn(f64, f64) -> (f64, f64),
) -> [f64; 2 * LANES] {
    let mut z = [0.0; 2 * LANES];
    for l in 0..LANES {
        let (a, b) = pair(u[2 * l], u[2 * l + 1]);
        z[2 * l] = a;
        z[2 * l + 1] = b;
    }
    z
}

/// [`transform`] in the AVX2 build.
///
/// # Safety
/// The CPU must support AVX2.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn transform_avx2(
    u: &[f64; 2 * LANES],
    pair: &impl Fn(f64, f64) -> (f64, f64),
) -> [f64; 2 * LANES] {
    transform_baseline(u, pair)
}

/// Blocks per group of `Stream::fill_pairs`: the largest step (the rigid
/// model's 12 normals, 6 blocks) in one group. The transform runs over all
/// eight pairs of a group (the unused ones at u = 1/2, discarded): a
/// fixed-length loop the compiler vectorises whole, which measured faster
/// than a loop over the pairs needed (5 for the vector model).
const LANES: usize = 8;

/// Standard normals `0 … out.len() − 1` of `step` of run `run` of `seed`:
/// `Stream::new(seed, run).normals(step, out)`, a pure function of its
/// arguments.
///
/// # Panics
/// If `run > MAX_RUN` or `out.len() > 2 BLOCKS_PER_STEP`.
pub fn normals(seed: u64, run: u64, step: u64, out: &mut [f64]) {
    Stream::new(seed, run).normals(step, out);
}

/// A 64-bit word to a uniform in the open interval (0, 1): the top 52 bits
/// `m` give `(2m + 1) 2⁻⁵³`, exact in `f64`, one of 2⁵² equally likely
/// values from 2⁻⁵³ to 1 − 2⁻⁵³ (symmetric about 1/2).
#[must_use]
pub fn unit_open(bits: u64) -> f64 {
    ((bits >> 11) | 1) as f64 * TWO_M53
}

/// The Box–Muller transform: two independent uniforms in (0, 1) to two
/// independent standard normals `(r cos 2πu₂, r sin 2πu₂)`, `r = √(−2 ln u₁)`,
/// with our own `ln` and `sin_cos` ([`crate::detmath`]: fdlibm's polynomials
/// in plain `f64` arithmetic, the same bits on every platform; `sqrt` is
/// IEEE's correctly rounded one), not the platform's libm (`ln`,
/// `sin_cos(2π u₂)`), whose outputs differ in the last bits.
#[inline(always)]
#[must_use]
pub fn box_muller(u1: f64, u2: f64) -> (f64, f64) {
    let r = (-2.0 * crate::detmath::ln(u1)).sqrt();
    let (s, c) = crate::detmath::sin_cos_turns(u2);
    (r * c, r * s)
}

/// `lo | hi << 32`.
fn words_u64(lo: u32, hi: u32) -> u64 {
    u64::from(lo) | (u64::from(hi) << 32)
}

/// The block holding number `k` of a step.
fn block_of(k: u64) -> u32 {
    u32::try_from(k / 2)
        .unwrap_or_else(|_| panic!("random stream: index {k} is above 2^33 - 1 in one step"))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The AVX2 build of the Box–Muller transform gives the baseline
    /// build's bits, over 10⁶ pairs of the stream's own uniforms (the
    /// extreme ones among them: 2⁻⁵³ and 1 − 2⁻⁵³ are added).
    #[cfg(target_arch = "x86_64")]
    #[test]
    fn avx2_transform_is_the_baseline_bit_for_bit() {
        if !std::arch::is_x86_feature_detected!("avx2") {
            return;
        }
        let s = Stream::new(7, 3);
        let edge = [TWO_M53, 1.0 - TWO_M53, 0.5, TWO_M53];
        for step in 0..62_500u64 {
            let mut u = [0.5; 2 * LANES];
            for l in 0..LANES {
                let w = s.block(step, l as u32);
                u[2 * l] = unit_open(words_u64(w[0], w[1]));
                u[2 * l + 1] = unit_open(words_u64(w[2], w[3]));
            }
            if step == 0 {
                u[..4].copy_from_slice(&edge);
            }
            let base = transform_baseline(&u, &box_muller);
            // SAFETY: the CPU has AVX2 (checked above).
            let avx = unsafe { transform_avx2(&u, &box_muller) };
            assert_eq!(base.map(f64::to_bits), avx.map(f64::to_bits), "step {step}");
        }
    }
}
