//! The 300 K part of "Inside a nanotube" (issue #30 item 3, "and at 300 K,
//! with the Langevin engine"): a small ensemble of the paper's C60 on the
//! wall of a (15,15) tube, rigid model, `method = "langevin"`
//! (docs/physics.md#tube-langevin), with the paper's force and without it
//! (the same seeds).
//!
//! Per run and sample: the contact's angle `φ` around the tube's axis
//! (unwrapped), the tilt `θ_n` of the axis against the contact normal (the
//! surface's "up"), and the kinetic energy `E − m g z`. Reported with
//! error bars from the spread over the runs: how far the contact wanders
//! around the circumference, θ_n's mean and spread, and the paper's force's
//! effect on ⟨θ_n⟩ (paired by seed).

use tippetop::human::s4;
use tippetop::input::surface::Shape;
use tippetop::input::thermal::BOLTZMANN;
use tippetop::{Error, Method, Scenario, Thermal, Trajectory, simulate};

use super::TubeRow;
use crate::{Curve, Figure};

/// The tube of the study, `(n, n)`: the wider tubes rest the cage on the
/// wall; (15,15) is the middle one of the study.
pub const HOT_TUBE: u32 = 15;

/// Runs per setting (force on, force off): seeds `run = 0 … HOT_RUNS − 1`.
pub const HOT_RUNS: u64 = 16;

/// Runs per setting with `reproduce --quick` (`time_factor < 1`): the
/// smoke test's, four, the number the φ figure draws.
pub const QUICK_HOT_RUNS: u64 = 4;

/// The window of each run \[s\] (before reproduce's time factor).
pub const HOT_T_END: f64 = 1e-9;

/// The Langevin step \[s\] (`dt · rate` = 0.011 for the fastest rate, γ).
pub const HOT_DT: f64 = 5e-15;

/// Samples per run.
pub const HOT_SAMPLES: usize = 1001;

/// The fraction of each run left out of the averages (the start is the
/// paper's cold state; the bath thermalises it within a few ps).
pub const BURN_IN: f64 = 0.05;

/// The bath: the `nano-physical` preset's (C60's reorientation in the
/// solid, γ_t = γ_r = 2.2e12 s⁻¹, no contact damping).
fn bath(run: u64) -> Thermal {
    Thermal {
        run,
        ..Scenario::nano_physical().thermal
    }
}

/// One run's series, at its samples.
#[derive(Debug, Clone, PartialEq)]
pub struct HotSeries {
    /// `run` of `[thermal]` (the seed is the preset's).
    pub run: u64,
    /// Times \[s\].
    pub t: Vec<f64>,
    /// The contact's angle around the tube's axis, unwrapped \[rad\]
    /// (0 at the lowest line, > 0 towards `+y`).
    pub phi: Vec<f64>,
    /// The axis' tilt against the contact normal `n` (towards the axis),
    /// `acos(k·n)` \[rad\].
    pub theta_n: Vec<f64>,
    /// The kinetic energy `E − m g z` \[J\] (in contact the adhesion adds
    /// no potential: docs/physics.md#tube-dynamics).
    pub kinetic: Vec<f64>,
}

impl HotSeries {
    /// The series of a tube run: `b` the contact cylinder's radius, `a` the
    /// top's offset \[m\], `mg` its weight \[N\].
    pub fn of(run: u64, tr: &Trajectory, b: f64, a: f64, mg: f64) -> HotSeries {
        let (mut t, mut phi, mut theta_n, mut kinetic) =
            (Vec::new(), Vec::new(), Vec::new(), Vec::new());
        let mut last: Option<f64> = None;
        for s in &tr.samples {
            // k = q e3 q*.
            let (w, x, y, z) = (s.qw, s.qx, s.qy, s.qz);
            let k = [
                2.0 * (x * z + w * y),
                2.0 * (y * z - w * x),
                1.0 - 2.0 * (x * x + y * y),
            ];
            // The sphere's centre across the axis (lab: axis along X
            // through (y, z) = (0, b)), and the normal towards the axis.
            let (cy, cz) = (s.y + a * k[1], s.z + a * k[2] - b);
            let d = cy.hypot(cz);
            let n = [0.0, -cy / d, -cz / d];
            let raw = cy.atan2(-cz);
            let p = match last {
                None => raw,
                Some(prev) => {
                    let tau = std::f64::consts::TAU;
                    prev + (raw - prev + 0.5 * tau).rem_euclid(tau) - 0.5 * tau
                }
            };
            last = Some(p);
            t.push(s.t);
            phi.push(p);
            theta_n.push((k[1] * n[1] + k[2] * n[2]).clamp(-1.0, 1.0).acos());
            kinetic.push(s.energy - mg * s.z);
        }
        HotSeries {
            run,
            t,
            phi,
            theta_n,
            kinetic,
        }
    }

    /// The samples after the burn-in.
    fn kept(&self) -> std::ops::Range<usize> {
        let n = self.t.len();
        ((n as f64 * BURN_IN).ceil() as usize).min(n)..n
    }

    /// Time average of `x` over the kept samples.
    pub fn mean(&self, x: &[f64]) -> f64 {
        let r = self.kept();
        x[r.clone()].iter().sum::<f64>() / r.len() as f64
    }

    /// `φ(t_end) − φ(0)` \[rad\].
    pub fn phi_travel(&self) -> f64 {
        self.phi.last().copied().unwrap_or(0.0) - self.phi[0]
    }
}

/// Mean and standard error of independent values.
pub fn mean_se(x: &[f64]) -> (f64, f64) {
    let n = x.len() as f64;
    let m = x.iter().sum::<f64>() / n;
    let var = x.iter().map(|v| (v - m) * (v - m)).sum::<f64>() / (n - 1.0);
    (m, (var / n).sqrt())
}

/// The ensemble.
#[derive(Debug, Clone)]
pub struct HotStudy {
    /// `n` of the `(n, n)` tube.
    pub n: u32,
    /// The scenario of run 0 with the paper's force (the others differ in
    /// `thermal.run`, and the force-off ones in H = 0).
    pub scenario: Scenario,
    /// With the paper's force, runs `0 … HOT_RUNS − 1` (`QUICK_HOT_RUNS`
    /// with `--quick`).
    pub on: Vec<HotSeries>,
    /// The same seeds without it.
    pub off: Vec<HotSeries>,
    /// Whether every run finished without error.
    pub all_ran: bool,
    /// `k_B T` \[J\].
    pub kt: f64,
    /// `m a²/A` of the top (the tilt's mass-matrix factor).
    pub ma2_over_a: f64,
    /// Wall-clock time of the ensemble \[s\] (not part of any figure).
    pub wall_seconds: f64,
}

/// The scenario of one run: the nano preset on the wall of `row`'s tube
/// (the contact cylinder `p₀ + R`, `[adhesion]` the pull-off force as the
/// load, as in the deterministic runs), frictionless (the bath is the
/// dissipation: `method = "langevin"` has no Coulomb friction), at 300 K.
pub fn hot_scenario(row: &TubeRow, run: u64, force: bool, time_factor: f64) -> Scenario {
    let mut sc = super::on_the_wall(row);
    sc.surface.friction = 0.0;
    sc.thermal = bath(run);
    sc.solver.method = Method::Langevin;
    sc.solver.dt = Some(HOT_DT);
    sc.solver.t_end = HOT_T_END * time_factor;
    sc.solver.samples = HOT_SAMPLES;
    if !force {
        super::without_force(&mut sc);
    }
    sc
}

/// Run the ensemble on the wall of `row`'s tube (all runs on the
/// available cores; each run's result depends on its seed only).
pub fn hot_study(row: &TubeRow, time_factor: f64) -> Result<HotStudy, Error> {
    let start = std::time::Instant::now();
    let runs = if time_factor < 1.0 {
        QUICK_HOT_RUNS
    } else {
        HOT_RUNS
    };
    let specs: Vec<(u64, bool)> = [true, false]
        .into_iter()
        .flat_map(|f| (0..runs).map(move |r| (r, f)))
        .collect();
    let scenarios = specs
        .iter()
        .map(|&(r, f)| {
            let sc = hot_scenario(row, r, f, time_factor);
            sc.validate().map(|_| sc)
        })
        .collect::<Result<Vec<_>, Error>>()?;
    let threads = std::thread::available_parallelism().map_or(1, |n| n.get());
    let mut results: Vec<Option<Result<Trajectory, Error>>> =
        (0..scenarios.len()).map(|_| None).collect();
    std::thread::scope(|s| {
        for (chunk, out) in scenarios
            .chunks(scenarios.len().div_ceil(threads))
            .zip(results.chunks_mut(scenarios.len().div_ceil(threads)))
        {
            s.spawn(move || {
                for (sc, slot) in chunk.iter().zip(out.iter_mut()) {
                    *slot = Some(simulate(sc));
                }
            });
        }
    });
    let sc0 = &scenarios[0];
    let (b, a) = match sc0.surface.shape {
        Shape::Tube { radius, .. } => (radius, sc0.top.offset),
        Shape::Plane => unreachable!("the study runs in the tube"),
    };
    let mg = sc0.top.mass * sc0.surface.gravity;
    let (mut on, mut off, mut all_ran) = (Vec::new(), Vec::new(), true);
    for (&(r, f), res) in specs.iter().zip(results) {
        let tr = res.expect("every run ran")?;
        all_ran &= tr.error.is_none();
        let series = HotSeries::of(r, &tr, b, a, mg);
        if f { on.push(series) } else { off.push(series) }
    }
    let top = &sc0.top;
    Ok(HotStudy {
        n: row.n,
        scenario: sc0.clone(),
        on,
        off,
        all_ran,
        kt: BOLTZMANN * sc0.thermal.temperature,
        ma2_over_a: top.mass * top.offset * top.offset / top.inertia_transverse,
        wall_seconds: start.elapsed().as_secs_f64(),
    })
}

impl HotStudy {
    /// The independent runs: the ones with the force (the runs without it
    /// share their seeds, and the bath's common noise keeps each pair on
    /// nearly the same path: they are not independent of these).
    pub fn all(&self) -> impl Iterator<Item = &HotSeries> {
        self.on.iter()
    }

    /// `⟨θ_n⟩` over the runs of `set`: mean of the runs' time averages and
    /// its standard error \[rad\].
    pub fn theta_mean(set: &[HotSeries]) -> (f64, f64) {
        mean_se(&set.iter().map(|s| s.mean(&s.theta_n)).collect::<Vec<_>>())
    }

    /// θ_n's spread: the rms of `θ_n − ⟨θ_n⟩` over all kept samples of all
    /// runs \[rad\], with the standard error of its square from the runs.
    pub fn theta_spread(&self) -> (f64, f64) {
        let (m, _) = Self::theta_mean(&self.on);
        let per: Vec<f64> = self
            .all()
            .map(|s| {
                let d: Vec<f64> = s.theta_n.iter().map(|x| (x - m).powi(2)).collect();
                s.mean(&d)
            })
            .collect();
        let (v, se) = mean_se(&per);
        (v.sqrt(), se / (2.0 * v.sqrt()))
    }

    /// `⟨cos² θ_n⟩` over all runs, with its standard error.
    pub fn cos2_theta(&self) -> (f64, f64) {
        mean_se(
            &self
                .all()
                .map(|s| {
                    let c: Vec<f64> = s.theta_n.iter().map(|x| x.cos().powi(2)).collect();
                    s.mean(&c)
                })
                .collect::<Vec<_>>(),
        )
    }

    /// The paper's force's effect on `⟨θ_n⟩`: the mean over seeds of
    /// (force on − force off) and its standard error \[rad\].
    pub fn force_effect(&self) -> (f64, f64) {
        mean_se(
            &self
                .on
                .iter()
                .zip(&self.off)
                .map(|(a, b)| a.mean(&a.theta_n) - b.mean(&b.theta_n))
                .collect::<Vec<_>>(),
        )
    }

    /// How far the contact wanders around the circumference over the
    /// window: the rms of `φ(t_end) − φ(0)` over all runs \[rad\], with the
    /// standard error (of its square, propagated).
    pub fn phi_rms(&self) -> (f64, f64) {
        let sq: Vec<f64> = self.all().map(|s| s.phi_travel().powi(2)).collect();
        let (v, se) = mean_se(&sq);
        (v.sqrt(), se / (2.0 * v.sqrt()))
    }

    /// The mean square of `φ(t + τ) − φ(t)` at the lag of `lag` samples,
    /// averaged over the time origins `t` after the burn-in in each run,
    /// then over the runs: mean and standard error \[rad²\].
    pub fn msd(&self, lag: usize) -> (f64, f64) {
        mean_se(&self.msd_runs(lag))
    }

    /// Each run's time-averaged `⟨(φ(t + τ) − φ(t))²⟩` at the lag of `lag`
    /// samples \[rad²\].
    pub fn msd_runs(&self, lag: usize) -> Vec<f64> {
        self.all()
            .map(|s| {
                let r = s.kept();
                let starts = r.start..r.end.saturating_sub(lag);
                let n = starts.len().max(1) as f64;
                starts
                    .map(|i| (s.phi[i + lag] - s.phi[i]).powi(2))
                    .sum::<f64>()
                    / n
            })
            .collect()
    }

    /// The lag \[samples\] of the diffusion estimate: a tenth of the window.
    pub fn lag(&self) -> usize {
        (self.on[0].t.len() - 1) / 10
    }

    /// The sample interval \[s\].
    pub fn sample_step(&self) -> f64 {
        let t = &self.on[0].t;
        (t[t.len() - 1] - t[0]) / (t.len() - 1) as f64
    }

    /// For a ball (`a = 0`) the contact's arc `(b − R) φ` is a free
    /// Ornstein–Uhlenbeck particle (the wall's reaction is normal to it):
    /// `⟨Δφ²⟩(τ) = 2 D [τ − (1 − e^{−γτ})/γ]/(b − R)²`, `D = k_B T/(m γ_t)`
    /// \[rad²\]; for the eccentric C60 (`a/(b − R)` ≈ 0.1) a reference.
    pub fn ball_msd(&self, tau: f64) -> f64 {
        let sc = &self.scenario;
        let g = sc.thermal.damping_translational;
        let d = self.kt / (sc.top.mass * g);
        let arm = match sc.surface.shape {
            Shape::Tube { radius, .. } => radius - sc.top.radius,
            Shape::Plane => f64::NAN,
        };
        2.0 * d * (tau - (-(-g * tau).exp_m1()) / g) / (arm * arm)
    }

    /// The largest `|φ(t_end) − φ(0)|` over all runs \[rad\].
    pub fn phi_max(&self) -> f64 {
        self.all().map(|s| s.phi_travel().abs()).fold(0.0, f64::max)
    }

    /// `⟨E_kin⟩ / k_B T` over all runs (equipartition: 5/2 for the five
    /// velocities of a top in one-point contact), with its standard error.
    pub fn kinetic_over_kt(&self) -> (f64, f64) {
        mean_se(
            &self
                .all()
                .map(|s| s.mean(&s.kinetic) / self.kt)
                .collect::<Vec<_>>(),
        )
    }

    /// The window of each run \[s\].
    pub fn window(&self) -> f64 {
        self.scenario.solver.t_end
    }
}

/// `⟨cos² θ⟩` under the orientation density of a top on a flat wall with no
/// torque, `p(θ) ∝ sin θ sqrt(1 + q sin²θ)` (`q = m a²/A`: the centre's
/// motion along the normal as the axis tilts; docs/physics.md#langevin),
/// by 64-point Gauss–Legendre over `[0, π]` (`physics::adhesion::gauss_legendre`;
/// the integrand is smooth, so the rule is exact to rounding).
pub fn boltzmann_cos2(q: f64) -> f64 {
    let half = 0.5 * std::f64::consts::PI;
    let (mut num, mut den) = (0.0, 0.0);
    for (x, w) in tippetop::physics::adhesion::gauss_legendre(64) {
        let (sn, cs) = (half * (1.0 + x)).sin_cos();
        let p = w * sn * (1.0 + q * sn * sn).sqrt();
        num += p * cs * cs;
        den += p;
    }
    num / den
}

/// A value and its standard error, 4 significant figures each.
fn pm((m, se): (f64, f64)) -> String {
    format!("{} ± {}", s4(m), s4(se))
}

impl HotStudy {
    /// Whether the paper's force moves `⟨θ_n⟩` beyond its error bar (one
    /// standard error of the ensemble's `⟨θ_n⟩`).
    pub fn force_visible(&self) -> bool {
        let (d, _) = self.force_effect();
        d.abs() > Self::theta_mean(&self.on).1
    }

    /// The verdict's item (Markdown), from the numbers.
    pub fn item(&self) -> String {
        let sc = &self.scenario;
        let b = match sc.surface.shape {
            Shape::Tube { radius, .. } => radius,
            Shape::Plane => f64::NAN,
        };
        let arm = b - sc.top.radius;
        let (phi, phi_se) = self.phi_rms();
        let (th, th_se) = Self::theta_mean(&self.on);
        let (spread, spread_se) = self.theta_spread();
        let cos2 = self.cos2_theta();
        let want = boltzmann_cos2(self.ma2_over_a);
        let (d, d_se) = self.force_effect();
        let (ke, ke_se) = self.kinetic_over_kt();
        let tau = self.lag() as f64 * self.sample_step();
        let (msd, msd_se) = self.msd(self.lag());
        let ball = self.ball_msd(tau);
        format!(
            "- **At 300 K (Langevin dynamics, rigid model, docs/physics.md#tube-langevin).** {runs} runs of {win} ns with \
             the paper's force and the same {runs} seeds without it, the C60 on the wall of the ({n},{n}) tube as above but \
             frictionless, in the `nano-physical` preset's bath (γ_t = γ_r = {gamma} s⁻¹, no contact damping), dt = {dt} fs; \
             {status}. Averages over the runs with the force after the first {burn} % of each; error bars are one standard \
             error from the spread between runs. **Around the tube:** gravity's whole span around the circle is {span} k_B T, \
             so nothing holds the contact: φ, its angle around the axis, moves by {phi} rad rms over {win} ns (up to \
             {phimax} rad; {arc} Å of arc on the circle of radius {arm_a} Å that the cage's centre runs on). It diffuses: \
             ⟨Δφ²⟩ at τ = {tau} ps is {msd} rad² (a ball's free diffusion along the arc, k_B T/(m γ_t) with no eccentricity, \
             gives {ball} rad²). **The tilt:** the angle θ_n between the axis and the wall's normal has the mean {th} rad and \
             the spread {spread} rad. ⟨cos² θ_n⟩ = {cos2}, against {want} for a top with no torque on a flat wall (density \
             sin θ √(1 + m a² sin²θ/A), m a²/A = {q}): every tilt occurs and none is preferred. ⟨E_kin⟩ = {ke} k_B T (5/2 by \
             equipartition: five velocities in one-point contact). **The paper's force:** paired by seed (the same noise), it \
             changes ⟨θ_n⟩ by {d} rad, against the error bar {th_se} rad of ⟨θ_n⟩ itself: {verdict}. **Verdict at 300 K:** \
             on the tube's wall the bath spreads the axis over all tilts and the contact diffuses around the circumference. \
             Nothing is left of a tippe top, and the paper's H has no visible effect.\n",
            runs = self.on.len(),
            win = s4(self.window() * 1e9),
            n = self.n,
            gamma = s4(sc.thermal.damping_translational),
            dt = s4(sc.solver.dt.unwrap_or(f64::NAN) * 1e15),
            status = if self.all_ran {
                "every run ran to its end"
            } else {
                "NOT every run ran to its end"
            },
            burn = s4(100.0 * BURN_IN),
            span = s4(2.0 * sc.top.mass * sc.surface.gravity * arm / self.kt),
            phi = pm((phi, phi_se)),
            arc = s4(phi * arm * 1e10),
            arm_a = s4(arm * 1e10),
            phimax = s4(self.phi_max()),
            tau = s4(tau * 1e12),
            msd = pm((msd, msd_se)),
            ball = s4(ball),
            th = pm((th, th_se)),
            th_se = s4(th_se),
            spread = pm((spread, spread_se)),
            cos2 = pm(cos2),
            want = s4(want),
            q = s4(self.ma2_over_a),
            ke = pm((ke, ke_se)),
            d = pm((d, d_se)),
            verdict = if self.force_visible() {
                "beyond it, a visible effect"
            } else {
                "far below it, no visible effect"
            },
        )
    }

    /// The figures: φ against time for the first four runs with the force,
    /// θ_n for the first two.
    pub fn figures(&self) -> Vec<Figure> {
        let curves = |count: usize, f: &dyn Fn(&HotSeries) -> &Vec<f64>| {
            self.on
                .iter()
                .take(count)
                .map(|s| Curve {
                    name: format!("run {}", s.run),
                    t: s.t.clone(),
                    y: f(s).clone(),
                    dashed: false,
                })
                .collect::<Vec<_>>()
        };
        let what = format!("C60 on a ({0},{0}) tube's wall at 300 K", self.n);
        vec![
            Figure {
                id: "tube_hot_phi".into(),
                title: format!("{what}: contact angle around the axis"),
                x_label: "t [ps]".into(),
                x_scale: 1e12,
                y_label: "φ [rad]".into(),
                curves: curves(4, &|s| &s.phi),
                note: "Langevin, rigid model, the paper's force on. φ unwrapped (0 at the lowest line); each run starts at 0. Gravity's span around the circle is ~1e-12 k_B T: φ diffuses.".into(),
                ..Default::default()
            },
            Figure {
                id: "tube_hot_theta".into(),
                title: format!("{what}: tilt against the wall's normal"),
                x_label: "t [ps]".into(),
                x_scale: 1e12,
                y_label: "θ_n [rad]".into(),
                curves: curves(2, &|s| &s.theta_n),
                note: "Langevin, rigid model, the paper's force on. θ_n = acos(k·n), n the contact normal towards the tube's axis; the runs start at the paper's θ = 0.1 rad.".into(),
                ..Default::default()
            },
        ]
    }
}
