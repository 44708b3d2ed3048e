//! How fast can a Langevin step of the vector model be at all? The bound
//! behind issue #15's target of 1e7 steps/s per core (docs/performance.md,
//! "The rate bound: a minimal step, scalar and in 8 lanes").
//!
//! Two throwaway kernels of the `nano-physical` preset's step (the vector
//! model on the plane, μ = 0, the adhesion's load, the stem's lying well,
//! γ_t = γ_r = 2.2e12 /s, 300 K, 4 fs), with nothing but the step:
//! the 10 normals of the run's stream, the two Ornstein–Uhlenbeck half
//! steps (the product's diagonal modes `v_x, v_y | k̂, ê, f̂`, the `ê` mode's
//! rate and mass at the axis), RK4's 4 evaluations, and one evaluation at
//! the step's end for N (its minimum and sum kept). Left out, so that the
//! kernels are a bound and not a product: the quaternion, the works
//! `W_f`, `W_a`, the samples, events, extremes, histograms, the energy
//! bookkeeping and every branch the preset does not take.
//!
//! - `minimal_scalar`: one run at a time, the platform's `atan2` and `exp`
//!   (as the product);
//! - `minimal_lanes`: [`LANES`] runs in lock-step (structure of arrays),
//!   the normals' Philox rounds and Box–Muller transform, the O steps, RK4
//!   and the step-end evaluation in loops over the lanes, with branch-free
//!   polynomial `atan2` and `exp` (accuracy checked below against the
//!   platform's) so the compiler can vectorise everything;
//! - `product`: the product's run of the same preset and length
//!   (`tippetop::simulate`, the baseline in the same run).
//!
//! Before timing, the bench checks that the kernels are the preset's
//! equations and noise: the minimal right-hand side against the product's
//! (`Vector::rhs`) at states of a run, the lanes' Philox words and
//! normals against `random::Stream` (bit for bit), the polynomials against
//! `f64::atan2`/`f64::exp`.
//!
//! The lanes need the CPU's widest vectors and FMA, which the committed
//! build does not assume (no `target-cpu`); LLVM also prefers 256-bit
//! vectors on this CPU unless told otherwise:
//!
//! `RUSTFLAGS="-C target-cpu=native -C target-feature=-prefer-256-bit" cargo bench -p tippetop --bench langevin_bound`
//!
//! (without the flags the lanes compile to SSE2, two lanes a register, and
//! the polynomials round twice; the measurements are in docs/performance.md).

// Component loops index several arrays at once; iterators would obscure them.
#![allow(clippy::needless_range_loop)]

use std::hint::black_box;
use std::time::Duration;

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use tippetop::{
    Scenario,
    integrate::OdeSystem,
    model::vector::{DIM, Vector},
    random::Stream,
    simulate,
};

/// Steps per benchmarked run.
const STEPS: u64 = 10_000;
/// Runs in lock-step (8 doubles: one AVX-512 register).
const LANES: usize = 8;
/// One quantity of every lane.
type F = [f64; LANES];
/// The minimal state: `k (3), w (3), v_x, v_y`.
const M: usize = 8;

/// The preset in scaled units (m = R = 1, the model's time unit).
#[derive(Debug, Clone, Copy)]
struct Consts {
    a: f64,
    ia: f64,
    ic: f64,
    g: f64,
    /// The adhesion's vertical load at the contact.
    hz: f64,
    depth: f64,
    theta_w: f64,
    width: f64,
    kt: f64,
    gt: f64,
    gr: f64,
    /// The step.
    h: f64,
}

/// The `nano-physical` preset cut to [`STEPS`] steps.
fn preset() -> Scenario {
    let mut sc = Scenario::nano_physical();
    sc.solver.t_end = STEPS as f64 * sc.solver.dt.expect("the preset has a step");
    sc.solver.samples = 41;
    sc
}

fn consts(sc: &Scenario) -> Consts {
    let s = Vector::new(sc).scales;
    let t = &sc.top;
    let w = sc.wells[0];
    Consts {
        a: t.offset / s.length,
        ia: t.inertia_transverse / s.inertia(),
        ic: t.inertia_axial / s.inertia(),
        g: sc.surface.gravity * s.time * s.time / s.length,
        hz: sc.adhesion.force / s.force(),
        depth: w.depth / s.energy(),
        theta_w: w.theta,
        width: w.width,
        kt: sc.thermal.kt() / s.energy(),
        gt: sc.thermal.damping_translational * s.time,
        gr: sc.thermal.damping_rotational * s.time,
        h: sc.solver.dt.expect("a step") / s.time,
    }
}

/// The product's state at the minimal state `y` (works, quaternion and
/// position zero: the right-hand side's `k̇, ẇ, v̇` do not read them).
fn product_state(y: &[f64; M]) -> [f64; DIM] {
    let mut p = [0.0; DIM];
    p[..M].copy_from_slice(y);
    p[10] = 1.0;
    p
}

/// `1/(2j + 1)`: the Taylor coefficients of `atan t = t Σ_j (−t²)^j/(2j + 1)`.
const ATAN_C: [f64; 21] = {
    let mut c = [0.0; 21];
    let mut j = 0;
    while j < 21 {
        c[j] = 1.0 / (2 * j + 1) as f64;
        j += 1;
    }
    c
};

/// `1/j!`: the Taylor coefficients of `exp r`.
const EXP_C: [f64; 14] = {
    let mut c = [1.0; 14];
    let mut j = 1;
    while j < 14 {
        c[j] = c[j - 1] / j as f64;
        j += 1;
    }
    c
};

/// `a b + c`, fused where the build has FMA (the bound's polynomials; the
/// committed build has none, so it rounds twice there).
#[inline(always)]
fn madd(a: f64, b: f64, c: f64) -> f64 {
    if cfg!(target_feature = "fma") {
        a.mul_add(b, c)
    } else {
        a * b + c
    }
}

/// `atan2(s, c)` for `s >= 0`, without branches: `t = min/max ∈ [0, 1]`,
/// folded to `|t'| <= tan(π/8)` by `t' = (t − 1)/(t + 1)` (+ π/4), then the
/// Taylor series to `t'^41` (relative error below 1e-17 there).
#[inline(always)]
fn atan2_poly(s: f64, c: f64) -> f64 {
    use std::f64::consts::{FRAC_PI_2, FRAC_PI_4, PI};
    let ac = c.abs();
    let t = s.min(ac) / s.max(ac);
    let big = t > 0.414_213_562_373_095_1;
    let tr = if big { (t - 1.0) / (t + 1.0) } else { t };
    let mt2 = -(tr * tr);
    let mut p = ATAN_C[20];
    for j in (0..20).rev() {
        p = madd(p, mt2, ATAN_C[j]);
    }
    let a = p * tr + if big { FRAC_PI_4 } else { 0.0 };
    let a = if s > ac { FRAC_PI_2 - a } else { a };
    if c < 0.0 { PI - a } else { a }
}

/// `exp(x)` for `x` in (−700, 700), without branches: `x = n ln 2 + r`,
/// `|r| <= ln 2/2`, the Taylor polynomial of degree 13 in `r`, times `2ⁿ`
/// from its bits.
#[inline(always)]
fn exp_poly(x: f64) -> f64 {
    const LN2_HI: f64 = 0.693_147_180_369_123_8;
    const LN2_LO: f64 = 1.908_214_929_270_587_7e-10;
    let n = (x * std::f64::consts::LOG2_E).round();
    let r = (x - n * LN2_HI) - n * LN2_LO;
    let mut p = EXP_C[13];
    for j in (0..13).rev() {
        p = madd(p, r, EXP_C[j]);
    }
    p * f64::from_bits(((n as i64 + 1023) as u64) << 52)
}

/// The minimal right-hand side at one state (`k̇ = w × k`, `ẇ`, `v̇ = 0`:
/// no friction, no horizontal force), the wells' torque through `atan2`
/// and `exp` (given); returns N.
#[inline(always)]
fn rhs_min(
    c: &Consts,
    y: &[f64; M],
    dy: &mut [f64; M],
    atan2: impl Fn(f64, f64) -> f64,
    exp: impl Fn(f64) -> f64,
) -> f64 {
    let (k, w) = ([y[0], y[1], y[2]], [y[3], y[4], y[5]]);
    let kd = [
        w[1] * k[2] - w[2] * k[1],
        w[2] * k[0] - w[0] * k[2],
        w[0] * k[1] - w[1] * k[0],
    ];
    let wk = w[0] * k[0] + w[1] * k[1] + w[2] * k[2];
    let gyro = (c.ic - c.ia) / c.ia;
    let mut w0 = [-gyro * wk * kd[0], -gyro * wk * kd[1], -gyro * wk * kd[2]];
    // The well: τ = −U′(θ) ŷ.
    let kh = (k[0] * k[0] + k[1] * k[1]).sqrt();
    let x = (atan2(kh, k[2]) - c.theta_w) / c.width;
    let ty = -c.depth * x / c.width * exp(-0.5 * x * x);
    let inv = if kh > 0.0 { ty / (kh * c.ia) } else { 0.0 };
    w0[0] -= k[1] * inv;
    w0[1] += k[0] * inv;
    // The closure N D = Q with the adhesion's load h_z.
    let r = [c.a * k[0], c.a * k[1], c.a * k[2] - 1.0];
    let u2 = (k[1] * r[1] + k[0] * r[0]) / c.ia; // (e × r)_Z/A, e = (k_y, −k_x, 0)
    let d0 = 1.0 + c.a * u2;
    let wkd_z = w[0] * kd[1] - w[1] * kd[0];
    let q = c.g + c.a * (-(w0[0] * k[1] - w0[1] * k[0]) - wkd_z) + c.hz * d0;
    let n = q / d0;
    let fz = n - c.hz;
    // I⁻¹ (r × F), F = fz Z.
    let t = [r[1] * fz, -r[0] * fz];
    let tk = (t[0] * k[0] + t[1] * k[1]) * (1.0 / c.ic - 1.0 / c.ia);
    dy[..3].copy_from_slice(&kd);
    dy[3] = w0[0] + t[0] / c.ia + tk * k[0];
    dy[4] = w0[1] + t[1] / c.ia + tk * k[1];
    dy[5] = w0[2] + tk * k[2];
    dy[6] = 0.0;
    dy[7] = 0.0;
    n
}

/// One mode's `(e^{−λh}, sqrt(kT (1 − e^{−2λh})/M))`.
fn factors(c: &Consts, rate: f64, mass: f64, h: f64, exp: impl Fn(f64) -> f64) -> (f64, f64) {
    let decay = exp(-rate * h);
    (decay, (c.kt / mass * (1.0 - decay * decay)).sqrt())
}

/// The O half step at one state: `v_x, v_y` at γ_t, `w` along `k̂` (mass C)
/// and `f̂` (mass A) at γ_r, along `ê` at the axis's rate and mass
/// (`ee`: its factors); `fc = [(v), (k̂), (f̂)]` factors.
#[inline(always)]
fn ou_min(y: &mut [f64; M], fc: &[(f64, f64); 3], ee: (f64, f64), z: &[f64]) {
    let k = [y[0], y[1], y[2]];
    let kh = (k[0] * k[0] + k[1] * k[1]).sqrt();
    let inv = if kh > 0.0 { 1.0 / kh } else { 0.0 };
    let e = if kh > 0.0 {
        [k[1] * inv, -k[0] * inv, 0.0]
    } else {
        [1.0, 0.0, 0.0]
    };
    let f = [
        k[1] * e[2] - k[2] * e[1],
        k[2] * e[0] - k[0] * e[2],
        k[0] * e[1] - k[1] * e[0],
    ];
    y[6] = fc[0].0 * y[6] + fc[0].1 * z[0];
    y[7] = fc[0].0 * y[7] + fc[0].1 * z[1];
    let mut w = [y[3], y[4], y[5]];
    for (j, (d, (decay, amp))) in [(k, fc[1]), (e, ee), (f, fc[2])].into_iter().enumerate() {
        let x = w[0] * d[0] + w[1] * d[1] + w[2] * d[2];
        let dx = (decay - 1.0) * x + amp * z[2 + j];
        for m in 0..3 {
            w[m] += dx * d[m];
        }
    }
    y[3..6].copy_from_slice(&w);
}

/// The `ê` mode's factors at the axis of `y` (half step `h`).
#[inline(always)]
fn e_factors(c: &Consts, y: &[f64; M], h: f64, exp: impl Fn(f64) -> f64) -> (f64, f64) {
    let beta = c.a * c.a * (y[0] * y[0] + y[1] * y[1]);
    let mass = c.ia + beta;
    factors(c, (c.gr * c.ia + c.gt * beta) / mass, mass, h, exp)
}

/// The preset's initial minimal state.
fn initial(sc: &Scenario) -> [f64; M] {
    let p = Vector::new(sc).scale_state(&sc.initial);
    let mut y = [0.0; M];
    y.copy_from_slice(&p[..M]);
    y
}

/// `STEPS` minimal steps of run `run`, one at a time; the final state and
/// N's minimum and sum.
fn run_scalar(c: &Consts, y0: [f64; M], stream: &Stream) -> ([f64; M], f64, f64) {
    let h = c.h;
    let fc = [
        factors(c, c.gt, 1.0, 0.5 * h, f64::exp),
        factors(c, c.gr, c.ic, 0.5 * h, f64::exp),
        factors(c, c.gr, c.ia, 0.5 * h, f64::exp),
    ];
    let (at, ex) = (f64::atan2, f64::exp);
    let mut y = y0;
    let mut ee = e_factors(c, &y, 0.5 * h, ex);
    let (mut nmin, mut nsum) = (f64::INFINITY, 0.0);
    let mut xi = [0.0; 10];
    for step in 0..STEPS {
        stream.normals(step, &mut xi);
        ou_min(&mut y, &fc, ee, &xi[..5]);
        let (mut k1, mut k2, mut k3, mut k4, mut yt) = ([0.0; M], [0.0; M], [0.0; M], [0.0; M], y);
        rhs_min(c, &y, &mut k1, at, ex);
        for i in 0..M {
            yt[i] = y[i] + 0.5 * h * k1[i];
        }
        rhs_min(c, &yt, &mut k2, at, ex);
        for i in 0..M {
            yt[i] = y[i] + 0.5 * h * k2[i];
        }
        rhs_min(c, &yt, &mut k3, at, ex);
        for i in 0..M {
            yt[i] = y[i] + h * k3[i];
        }
        rhs_min(c, &yt, &mut k4, at, ex);
        for i in 0..M {
            y[i] += h / 6.0 * (k1[i] + 2.0 * (k2[i] + k3[i]) + k4[i]);
        }
        ee = e_factors(c, &y, 0.5 * h, ex);
        ou_min(&mut y, &fc, ee, &xi[5..]);
        let n = rhs_min(c, &y, &mut k1, at, ex);
        nmin = nmin.min(n);
        nsum += n;
    }
    (y, nmin, nsum)
}

/// Philox4x32-10 (Salmon et al. 2011), the rounds written out so a loop
/// over lanes vectorises (32×32 → 64-bit products).
#[inline(always)]
fn philox(mut c: [u32; 4], mut k: [u32; 2]) -> [u32; 4] {
    for _ in 0..10 {
        let p0 = u64::from(c[0]) * 0xD251_1F53;
        let p1 = u64::from(c[2]) * 0xCD9E_8D57;
        c = [
            ((p1 >> 32) as u32) ^ c[1] ^ k[0],
            p1 as u32,
            ((p0 >> 32) as u32) ^ c[3] ^ k[1],
            p0 as u32,
        ];
        k = [
            k[0].wrapping_add(0x9E37_79B9),
            k[1].wrapping_add(0xBB67_AE85),
        ];
    }
    c
}

/// The 10 normals of `step` of every lane's run (the stream's counter
/// layout: words `block, step lo, step hi, run`; key = seed).
#[inline(always)]
fn lane_normals(seed: u64, runs: &[u32; LANES], step: u64, xi: &mut [F; 10]) {
    let key = [seed as u32, (seed >> 32) as u32];
    for b in 0..5u32 {
        let (mut u1, mut u2) = ([0.0; LANES], [0.0; LANES]);
        for i in 0..LANES {
            let w = philox([b, step as u32, (step >> 32) as u32, runs[i]], key);
            let b1 = u64::from(w[0]) | (u64::from(w[1]) << 32);
            let b2 = u64::from(w[2]) | (u64::from(w[3]) << 32);
            u1[i] = tippetop::random::unit_open(b1);
            u2[i] = tippetop::random::unit_open(b2);
        }
        for i in 0..LANES {
            let (z0, z1) = tippetop::random::box_muller(u1[i], u2[i]);
            xi[2 * b as usize][i] = z0;
            xi[2 * b as usize + 1][i] = z1;
        }
    }
}

/// Lane `i` of a structure of arrays.
#[inline(always)]
fn lane(y: &[F; M], i: usize) -> [f64; M] {
    std::array::from_fn(|j| y[j][i])
}

/// Lane `i` of `x` into `y`.
#[inline(always)]
fn set_lane(y: &mut [F; M], i: usize, x: &[f64; M]) {
    for j in 0..M {
        y[j][i] = x[j];
    }
}

/// `STEPS` minimal steps of runs `runs`, in lock-step: the final states and
/// N's minima and sums.
fn run_lanes(c: &Consts, y0: [f64; M], seed: u64, runs: &[u32; LANES]) -> ([F; M], F, F) {
    let h = c.h;
    let fc = [
        factors(c, c.gt, 1.0, 0.5 * h, exp_poly),
        factors(c, c.gr, c.ic, 0.5 * h, exp_poly),
        factors(c, c.gr, c.ia, 0.5 * h, exp_poly),
    ];
    let mut y: [F; M] = std::array::from_fn(|j| [y0[j]; LANES]);
    let mut ee = [e_factors(c, &y0, 0.5 * h, exp_poly); LANES];
    let (mut nmin, mut nsum) = ([f64::INFINITY; LANES], [0.0; LANES]);
    let mut xi = [[0.0; LANES]; 10];
    let rhs = |y: &[F; M], dy: &mut [F; M]| -> F {
        let mut n = [0.0; LANES];
        for i in 0..LANES {
            let mut d = [0.0; M];
            n[i] = rhs_min(c, &lane(y, i), &mut d, atan2_poly, exp_poly);
            set_lane(dy, i, &d);
        }
        n
    };
    let ou = |y: &mut [F; M], ee: &[(f64, f64); LANES], z: &[F]| {
        for i in 0..LANES {
            let mut s = lane(y, i);
            let zi: [f64; 5] = std::array::from_fn(|j| z[j][i]);
            ou_min(&mut s, &fc, ee[i], &zi);
            set_lane(y, i, &s);
        }
    };
    let zero = [[0.0; LANES]; M];
    for step in 0..STEPS {
        lane_normals(seed, runs, step, &mut xi);
        ou(&mut y, &ee, &xi[..5]);
        let (mut k1, mut k2, mut k3, mut k4, mut yt) = (zero, zero, zero, zero, zero);
        rhs(&y, &mut k1);
        for j in 0..M {
            for i in 0..LANES {
                yt[j][i] = y[j][i] + 0.5 * h * k1[j][i];
            }
        }
        rhs(&yt, &mut k2);
        for j in 0..M {
            for i in 0..LANES {
                yt[j][i] = y[j][i] + 0.5 * h * k2[j][i];
            }
        }
        rhs(&yt, &mut k3);
        for j in 0..M {
            for i in 0..LANES {
                yt[j][i] = y[j][i] + h * k3[j][i];
            }
        }
        rhs(&yt, &mut k4);
        for j in 0..M {
            for i in 0..LANES {
                y[j][i] += h / 6.0 * (k1[j][i] + 2.0 * (k2[j][i] + k3[j][i]) + k4[j][i]);
            }
        }
        for i in 0..LANES {
            ee[i] = e_factors(c, &lane(&y, i), 0.5 * h, exp_poly);
        }
        ou(&mut y, &ee, &xi[5..]);
        let n = rhs(&y, &mut k1);
        for i in 0..LANES {
            nmin[i] = nmin[i].min(n[i]);
            nsum[i] += n[i];
        }
    }
    (y, nmin, nsum)
}

/// Units in the last place between `a` and `b` (same sign, finite).
fn ulps(a: f64, b: f64) -> u64 {
    (a.to_bits() as i64 - b.to_bits() as i64).unsigned_abs()
}

/// The kernels are the preset's equations and noise (see the module docs).
fn check(sc: &Scenario, c: &Consts) {
    // The polynomials against the platform's functions, over the ranges used.
    let mut worst = (0, 0);
    for j in 0..100_000 {
        let th = std::f64::consts::PI * (j as f64 + 0.5) / 100_000.0;
        let (s, co) = th.sin_cos();
        worst.0 = worst.0.max(ulps(atan2_poly(s, co), s.atan2(co)));
        let x = -40.0 + 40.0 * j as f64 / 100_000.0;
        worst.1 = worst.1.max(ulps(exp_poly(x), x.exp()));
    }
    // Measured: atan2 3 ulps, exp 1 ulp (glibc's: within 1 ulp of the
    // exact value); a product kernel would need atan2 tighter, at more cost.
    assert!(
        worst.0 <= 4 && worst.1 <= 2,
        "polynomials off by {worst:?} ulps"
    );
    eprintln!(
        "polynomials: atan2 within {} ulps, exp within {} ulps of the platform's",
        worst.0, worst.1
    );
    // The minimal right-hand side is the product's, at states of a run.
    let mut m = Vector::new(sc);
    let (y, _, _) = run_scalar(c, initial(sc), &Stream::new(1, 3));
    let mut states = vec![initial(sc), y];
    let mut w = y;
    w[3] *= 1e3;
    w[5] *= -1e3;
    states.push(w);
    for s in &states {
        let mut mine = [0.0; M];
        rhs_min(c, s, &mut mine, f64::atan2, f64::exp);
        let mut theirs = [0.0; DIM];
        m.rhs(0.0, &product_state(s), &mut theirs).expect("rhs");
        for j in 0..6 {
            let scale = theirs[j].abs().max(1e-300);
            assert!(
                (mine[j] - theirs[j]).abs()
                    <= 1e-10 * scale
                        + 1e-14 * theirs[3..6].iter().map(|v| v.abs()).fold(0.0, f64::max),
                "component {j}: minimal {} vs product {}",
                mine[j],
                theirs[j]
            );
        }
    }
    // The lanes' noise is the stream's, bit for bit.
    let runs: [u32; LANES] = std::array::from_fn(|i| 17 + i as u32);
    for step in [0, 1, 99_999, 1 << 40] {
        let mut xi = [[0.0; LANES]; 10];
        lane_normals(1, &runs, step, &mut xi);
        for i in 0..LANES {
            let s = Stream::new(1, u64::from(runs[i]));
            let mut want = [0.0; 10];
            s.normals(step, &mut want);
            for j in 0..10 {
                assert_eq!(
                    xi[j][i].to_bits(),
                    want[j].to_bits(),
                    "normal {j} of lane {i}"
                );
            }
        }
    }
    // Lock-step lanes and one run at a time agree to rounding (the
    // polynomials against the platform's functions).
    let (yl, _, sl) = run_lanes(c, initial(sc), 1, &runs);
    let (ys, _, ss) = run_scalar(c, initial(sc), &Stream::new(1, u64::from(runs[2])));
    for j in 0..3 {
        assert!(
            (yl[j][2] - ys[j]).abs() < 1e-9,
            "axis {j}: {} vs {}",
            yl[j][2],
            ys[j]
        );
    }
    assert!(
        (sl[2] - ss).abs() <= 1e-9 * ss.abs(),
        "N sums {} vs {}",
        sl[2],
        ss
    );
}

fn bench(cr: &mut Criterion) {
    let sc = preset();
    let c = consts(&sc);
    check(&sc, &c);
    let y0 = initial(&sc);
    let mut g = cr.benchmark_group("langevin_bound");
    g.sample_size(20);
    g.measurement_time(Duration::from_secs(4));
    g.throughput(Throughput::Elements(STEPS));
    g.bench_function("product", |b| b.iter(|| simulate(black_box(&sc))));
    let stream = Stream::new(1, 0);
    g.bench_function("minimal_scalar", |b| {
        b.iter(|| run_scalar(black_box(&c), y0, &stream))
    });
    g.throughput(Throughput::Elements(STEPS * LANES as u64));
    let runs: [u32; LANES] = std::array::from_fn(|i| i as u32);
    g.bench_function("minimal_lanes", |b| {
        b.iter(|| run_lanes(black_box(&c), y0, 1, &runs))
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
