//! The vector model's sliding right-hand side at [`LANES`] states at once,
//! in structure-of-arrays form (one `[f64; LANES]` per quantity), for
//! several runs of an ensemble per SIMD register (docs/performance.md,
//! "Langevin lanes (session 8)"). Each lane performs the scalar
//! evaluation's operations in the scalar evaluation's order (IEEE
//! addition, multiplication, division and square root round the same in
//! a vector register as in a scalar one, and Rust never fuses them), and
//! the data-dependent branches (the friction coefficient, the closure's
//! branch, the wells' `atan2` and `exp`, the precessing frame at the pole)
//! call the scalar code lane by lane: each lane's result is the scalar
//! [`crate::integrate::OdeSystem::rhs`]'s, bit for bit (test
//! `lanes_equal_the_scalar_right_hand_side`).
//!
//! Not used by runs yet: it measures what the lane layout buys on the
//! evaluation (criterion `langevin_parts/rhs_4_lanes_*`). The build has no
//! `target-cpu`, so the compiler uses SSE2 (2 lanes of `f64` per register);
//! [`Vector::rhs_lanes`] also has an AVX2 path (4 lanes) chosen at run
//! time.

// Lane loops index several arrays at once; iterators would obscure them.
#![allow(clippy::needless_range_loop)]

use super::{DIM, K, OMEGA, QUAT, VEL, Vector};
use crate::model::reduced::Mode;

/// Number of states per call of [`Vector::rhs_lanes`].
pub const LANES: usize = 4;

/// One quantity of [`LANES`] states.
type L = [f64; LANES];
/// A vector of [`LANES`] states.
type L3 = [L; 3];

#[inline(always)]
fn splat(x: f64) -> L {
    [x; LANES]
}
#[inline(always)]
fn ladd(a: L, b: L) -> L {
    std::array::from_fn(|i| a[i] + b[i])
}
#[inline(always)]
fn lsub(a: L, b: L) -> L {
    std::array::from_fn(|i| a[i] - b[i])
}
#[inline(always)]
fn lmul(a: L, b: L) -> L {
    std::array::from_fn(|i| a[i] * b[i])
}
#[inline(always)]
fn lneg(a: L) -> L {
    std::array::from_fn(|i| -a[i])
}
#[inline(always)]
fn add3(a: L3, b: L3) -> L3 {
    [ladd(a[0], b[0]), ladd(a[1], b[1]), ladd(a[2], b[2])]
}
#[inline(always)]
fn scale3(s: L, a: L3) -> L3 {
    [lmul(s, a[0]), lmul(s, a[1]), lmul(s, a[2])]
}
#[inline(always)]
fn dot3(a: L3, b: L3) -> L {
    ladd(ladd(lmul(a[0], b[0]), lmul(a[1], b[1])), lmul(a[2], b[2]))
}
#[inline(always)]
fn cross3(a: L3, b: L3) -> L3 {
    [
        lsub(lmul(a[1], b[2]), lmul(a[2], b[1])),
        lsub(lmul(a[2], b[0]), lmul(a[0], b[2])),
        lsub(lmul(a[0], b[1]), lmul(a[1], b[0])),
    ]
}
/// Lane `i` of a vector.
#[inline(always)]
fn lane(v: L3, i: usize) -> [f64; 3] {
    [v[0][i], v[1][i], v[2][i]]
}

impl Vector {
    /// Whether [`Vector::rhs_lanes`] covers the model's current state: the
    /// sliding mode without body actuators or Coulomb–Contensou friction
    /// (the Langevin runs' configuration).
    pub fn lanes_cover(&self) -> bool {
        self.plane.mode == Mode::Sliding
            && self.plane.forces().body_is_zero()
            && !self.plane.is_contensou()
    }

    /// The right-hand side ([`crate::integrate::OdeSystem::rhs`]) at [`LANES`] states, lane by
    /// lane the same bits. `false` (and `dy` unspecified) where the lanes
    /// do not cover the model's state ([`Vector::lanes_cover`]) or some
    /// lane's evaluation fails (a Painlevé case, chattering): evaluate
    /// those states with [`crate::integrate::OdeSystem::rhs`] instead. Counts [`LANES`]
    /// evaluations.
    pub fn rhs_lanes(&mut self, y: &[[f64; DIM]; LANES], dy: &mut [[f64; DIM]; LANES]) -> bool {
        if !self.lanes_cover() {
            return false;
        }
        for _ in 0..LANES {
            if self.plane.start_evaluation().is_err() {
                return false;
            }
        }
        #[cfg(target_arch = "x86_64")]
        if std::arch::is_x86_feature_detected!("avx2") {
            // SAFETY: the CPU has AVX2 (checked just above).
            return unsafe { self.sliding_lanes_avx2(y, dy) };
        }
        self.sliding_lanes(y, dy)
    }

    /// [`Vector::sliding_lanes`] compiled for AVX2 (4 lanes per register).
    ///
    /// # Safety
    /// The CPU must support AVX2.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    unsafe fn sliding_lanes_avx2(
        &self,
        y: &[[f64; DIM]; LANES],
        dy: &mut [[f64; DIM]; LANES],
    ) -> bool {
        self.sliding_lanes(y, dy)
    }

    /// `eval_sliding` over the lanes (see the module docs).
    #[inline(always)]
    fn sliding_lanes(&self, y: &[[f64; DIM]; LANES], dy: &mut [[f64; DIM]; LANES]) -> bool {
        let col = |j: usize| -> L { std::array::from_fn(|i| y[i][j]) };
        let a = splat(self.a);
        let k: L3 = [col(K), col(K + 1), col(K + 2)];
        let w: L3 = [col(OMEGA), col(OMEGA + 1), col(OMEGA + 2)];
        let kd = cross3(w, k);
        let wk = dot3(w, k);
        let r: L3 = [
            lmul(a, k[0]),
            lmul(a, k[1]),
            lsub(lmul(a, k[2]), splat(1.0)),
        ];
        let wr = cross3(w, r);
        let v = [col(VEL), col(VEL + 1)];
        let vp = [ladd(v[0], wr[0]), ladd(v[1], wr[1])];
        let reg_d = self.plane.regularized_eps().map(|eps| -> L {
            std::array::from_fn(|i| (vp[0][i] * vp[0][i] + vp[1][i] * vp[1][i] + eps * eps).sqrt())
        });
        // The friction coefficient: the Coulomb laws' common branch over the
        // lanes, else lane by lane (the branches of the law).
        let common = match reg_d {
            Some(_) => None,
            None => self.plane.coefficient_lanes(vp),
        };
        let mut f: [L; 2] = common.unwrap_or([splat(0.0); 2]);
        for i in (0..LANES).filter(|_| common.is_none()) {
            let fi = match reg_d {
                Some(d) => {
                    let kf = self.plane.mu() / d[i];
                    [kf * vp[0][i], kf * vp[1][i]]
                }
                None => self.plane.coefficient([vp[0][i], vp[1][i]]),
            };
            f[0][i] = fi[0];
            f[1][i] = fi[1];
        }
        // The applied force in the precessing frame.
        let hw: L3 = {
            let [hx, hy] = self.plane.applied();
            if hx == 0.0 && hy == 0.0 {
                [splat(0.0); 3]
            } else {
                // `Vector::frame`: x̂ = k_h/|k_h| (X at the pole), ŷ = Z × x̂;
                // H = h_x x̂ + h_y ŷ.
                let kh2 = ladd(lmul(k[0], k[0]), lmul(k[1], k[1]));
                if kh2.iter().all(|&x| x > 0.0) {
                    let inv: L = std::array::from_fn(|i| 1.0 / kh2[i].sqrt());
                    let xh = [lmul(k[0], inv), lmul(k[1], inv)];
                    let (hx, hy) = (splat(hx), splat(hy));
                    [
                        ladd(lmul(hx, xh[0]), lmul(hy, lneg(xh[1]))),
                        ladd(lmul(hx, xh[1]), lmul(hy, xh[0])),
                        ladd(lmul(hx, splat(0.0)), lmul(hy, splat(0.0))),
                    ]
                } else {
                    let mut out = [splat(0.0); 3];
                    for i in 0..LANES {
                        let hwi = self.applied_world(lane(k, i));
                        for c in 0..3 {
                            out[c][i] = hwi[c];
                        }
                    }
                    out
                }
            }
        };
        // ẇ₀ with the wells' torque, lane by lane (atan2, exp).
        let w0: L3 = {
            let base = scale3(lmul(splat(-self.gyro), wk), kd);
            let wells = self.plane.wells();
            if wells.is_empty() {
                base
            } else {
                let mut tau = [splat(0.0); 3];
                for i in 0..LANES {
                    let t = crate::physics::forces::wells::torque_world(wells, lane(k, i));
                    for c in 0..3 {
                        tau[c][i] = t[c];
                    }
                }
                add3(base, scale3(splat(self.inv_ia), tau))
            }
        };
        let g_z = splat(self.g);
        let e: L3 = [k[1], lneg(k[0]), splat(0.0)];
        let u = scale3(splat(self.inv_ia), cross3(e, r));
        let wkd_z = lsub(lmul(w[0], kd[1]), lmul(w[1], kd[0]));
        let q = ladd(
            g_z,
            lmul(
                a,
                lsub(
                    lsub(ladd(lmul(hw[0], u[0]), lmul(hw[1], u[1])), dot3(w0, e)),
                    wkd_z,
                ),
            ),
        );
        let cp = self.plane.contact_point();
        let one = splat(1.0);
        let q: L = std::array::from_fn(|i| cp.closure_q(q[i], 1.0 + self.a * u[2][i]));
        let (q, dp, dm) = match reg_d {
            Some(d) => {
                let base = lmul(d, ladd(one, lmul(a, u[2])));
                let t = lmul(
                    lmul(a, splat(self.plane.mu())),
                    ladd(lmul(vp[0], u[0]), lmul(vp[1], u[1])),
                );
                (lmul(d, q), lsub(base, t), ladd(base, t))
            }
            None => {
                let fu = ladd(lmul(f[0], u[0]), lmul(f[1], u[1]));
                (
                    q,
                    ladd(one, lmul(a, lsub(u[2], fu))),
                    ladd(one, lmul(a, ladd(u[2], fu))),
                )
            }
        };
        // The closure: the one-division branch over the lanes, else lane by
        // lane.
        let common = self.plane.closure_lanes(q, dp, dm);
        let (mut normal, mut nf) = common.unwrap_or((splat(0.0), splat(0.0)));
        for i in (0..LANES).filter(|_| common.is_none()) {
            match self.plane.closure(q[i], dp[i], dm[i]) {
                Ok(n) => {
                    normal[i] = n;
                    nf[i] = self.plane.friction_normal(n);
                }
                Err(_) => return false,
            }
        }
        let ff = [lmul(lneg(nf), f[0]), lmul(lneg(nf), f[1])];
        let force: L3 = [
            lsub(ff[0], hw[0]),
            lsub(ff[1], hw[1]),
            std::array::from_fn(|i| cp.vertical_total(normal[i])),
        ];
        // I⁻¹ x = x/A + (1/C − 1/A)(x·k) k.
        let x = cross3(r, force);
        let wd = add3(
            w0,
            add3(
                scale3(splat(self.inv_ia), x),
                scale3(lmul(splat(self.dinv), dot3(x, k)), k),
            ),
        );
        let wf = ladd(lmul(ff[0], vp[0]), lmul(ff[1], vp[1]));
        let half = splat(0.5);
        // The attitude's untwisted frame turns with w_⊥ = w − (w·k) k; the
        // spin enters χ̇ = w·k − ω₀ (`attitude_rate`).
        let w: L3 = [
            lsub(w[0], lmul(wk, k[0])),
            lsub(w[1], lmul(wk, k[1])),
            lsub(w[2], lmul(wk, k[2])),
        ];
        let chi = lsub(wk, splat(self.spin_ref));
        let qv: [L; 4] = [col(QUAT), col(QUAT + 1), col(QUAT + 2), col(QUAT + 3)];
        let qd: [L; 4] = [
            lmul(
                half,
                lsub(
                    lsub(lmul(lneg(w[0]), qv[1]), lmul(w[1], qv[2])),
                    lmul(w[2], qv[3]),
                ),
            ),
            lmul(
                half,
                lsub(
                    ladd(lmul(w[0], qv[0]), lmul(w[1], qv[3])),
                    lmul(w[2], qv[2]),
                ),
            ),
            lmul(
                half,
                lsub(
                    ladd(lmul(w[1], qv[0]), lmul(w[2], qv[1])),
                    lmul(w[0], qv[3]),
                ),
            ),
            lmul(
                half,
                lsub(
                    ladd(lmul(w[2], qv[0]), lmul(w[0], qv[2])),
                    lmul(w[1], qv[1]),
                ),
            ),
        ];
        let wa = lsub(lmul(lneg(hw[0]), vp[0]), lmul(hw[1], vp[1]));
        let cols: [L; DIM] = [
            kd[0], kd[1], kd[2], wd[0], wd[1], wd[2], force[0], force[1], wf, wa, qd[0], qd[1],
            qd[2], qd[3], chi, v[0], v[1],
        ];
        for (i, d) in dy.iter_mut().enumerate() {
            for j in 0..DIM {
                d[j] = cols[j][i];
            }
        }
        true
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Scenario;
    use crate::integrate::OdeSystem;

    /// Each lane of [`Vector::rhs_lanes`] is the scalar right-hand side,
    /// bit for bit, at 4 000 states each of the `nano-physical` preset (adhesion,
    /// the lying well, the applied force), of the preset without well
    /// and adhesion, and with the exact and regularised Coulomb laws at
    /// μ = 0.3, each lane a different random state (axis over the
    /// sphere including the poles, velocities over ±10 thermal widths).
    #[test]
    fn lanes_equal_the_scalar_right_hand_side() {
        let mut seed = 0x9e37_79b9_7f4a_7c15u64;
        let mut uniform = move || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            (seed >> 11) as f64 / (1u64 << 53) as f64
        };
        let plain = {
            let mut sc = Scenario::nano_physical();
            sc.wells.clear();
            sc.adhesion = Default::default();
            sc
        };
        // Friction on (no thermal partner, but the lanes cover it): the
        // exact and the regularised Coulomb laws.
        let rough = |law| {
            let mut sc = Scenario::nano_physical();
            sc.surface.friction = 0.3;
            sc.surface.law = law;
            sc
        };
        let scenarios = [
            Scenario::nano_physical(),
            plain,
            rough(crate::FrictionLaw::Coulomb),
            rough(crate::FrictionLaw::Regularized { eps: 1e-3 }),
        ];
        for sc in scenarios {
            let mut m = Vector::new(&sc);
            m.latch_force(0.0);
            let mut y0 = m.scale_state(&sc.initial);
            let (mut checked, mut refused) = (0, 0);
            for n in 0..1000 {
                let mut ys = [[0.0; DIM]; LANES];
                for (i, y) in ys.iter_mut().enumerate() {
                    *y = y0;
                    let (th, ph) = if (n + i) % 97 == 0 {
                        (0.0, 0.0)
                    } else {
                        (std::f64::consts::PI * uniform(), 6.0 * uniform())
                    };
                    y[K] = th.sin() * ph.cos();
                    y[K + 1] = th.sin() * ph.sin();
                    y[K + 2] = th.cos();
                    for j in OMEGA..VEL + 2 {
                        y[j] = 20.0 * (uniform() - 0.5);
                    }
                }
                let mut dy = [[f64::NAN; DIM]; LANES];
                if m.rhs_lanes(&ys, &mut dy) {
                    // The baseline (SSE2) build of the kernel too, where
                    // `rhs_lanes` took the AVX2 one.
                    let mut dy2 = [[f64::NAN; DIM]; LANES];
                    assert!(m.sliding_lanes(&ys, &mut dy2));
                    assert_eq!(
                        dy.map(|d| d.map(f64::to_bits)),
                        dy2.map(|d| d.map(f64::to_bits))
                    );
                    for i in 0..LANES {
                        let mut d = [0.0; DIM];
                        m.rhs(0.0, &ys[i], &mut d).unwrap();
                        let (a, b) = (d.map(f64::to_bits), dy[i].map(f64::to_bits));
                        assert_eq!(a, b, "state {n} lane {i}");
                        checked += 1;
                    }
                } else {
                    // Only where some lane's scalar evaluation fails (a
                    // Painlevé case of the rough laws).
                    let mut d = [0.0; DIM];
                    assert!(ys.iter().any(|y| m.rhs(0.0, y, &mut d).is_err()));
                    refused += 1;
                }
                y0 = ys[n % LANES];
            }
            assert!(
                checked >= 3000,
                "{checked} lanes checked, {refused} calls refused"
            );
            if sc.surface.friction == 0.0 {
                assert_eq!(checked, 4000);
            }
        }
    }
}
