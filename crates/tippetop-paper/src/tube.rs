//! The "Inside a nanotube" study of `reproduce --extended` (issue #30 item
//! 3): where the paper's C60 sits inside a single-walled carbon nanotube,
//! whether it touches anything, what the paper's force can do there, and
//! what remains of the tippe-top story.
//!
//! The statics are `physics::nanotube`'s (continuum Lennard-Jones, the
//! constants of the graphene case, docs/physics.md#nanotube) for C60 in
//! the armchair tubes (10,10), (12,12), (15,15) and (20,20), with the
//! graphene sheet (`physics::adhesion`) as the reference; the dynamics are
//! the paper's nano scenario on the wall of each tube where the cage rests
//! (rigid model, `[adhesion]` the tube's pull-off force as the load,
//! docs/physics.md#tube-dynamics). The verdicts are computed from the
//! numbers with the criterion beside each, never written in.

use tippetop::human::s4;
use tippetop::input::solver::ModelKind;
use tippetop::input::surface::Shape;
use tippetop::input::thermal::BOLTZMANN;
use tippetop::physics::adhesion::{ANGSTROM, Binding, EV};
use tippetop::physics::nanotube::{Nanotube, TubeBinding, chirality_radius, off_axis_radius};
use tippetop::{Adhesion, Error, FrictionLaw, Scenario, Trajectory, simulate};

use crate::{Curve, Figure};

pub mod langevin;
pub use langevin::{HOT_TUBE, HotStudy, boltzmann_cos2, hot_study};

/// The tubes of the study, `(n, n)`.
pub const TUBES: [u32; 4] = [10, 12, 15, 20];

/// The temperature of the thermal estimates \[K\].
pub const TEMPERATURE: f64 = 300.0;

/// Offset step of the figure's curves \[m\] (0.025 Å).
pub const FIGURE_STEP: f64 = 0.025 * ANGSTROM;

/// A thermal excursion counts as frequent when the Boltzmann factor of
/// the energy it costs is above this (an energy below ~4.6 k_B T), as
/// rare below.
pub const THERMAL_REACH: f64 = 1e-2;

/// One tube of the study.
#[derive(Debug, Clone, PartialEq)]
pub struct TubeRow {
    /// `n` of the `(n, n)` tube.
    pub n: u32,
    /// The tube (C60, graphene's density and constants).
    pub tube: Nanotube,
    /// Equilibrium, binding, stiffness, pull-off, suction.
    pub binding: TubeBinding,
    /// Thermal rms excursion at [`TEMPERATURE`] along one radial
    /// direction, `√(k_B T / U″(p₀))` \[m\].
    pub rms: f64,
    /// Offset at which the cage is as near the wall as it sits on the
    /// flat sheet (its gap there equals the sheet's equilibrium gap):
    /// `b − R − gap_sheet` \[m\]; at or below the equilibrium offset for
    /// the tubes where the cage rests on the wall.
    pub touch_offset: f64,
    /// On the axis: the largest restoring force `max U′` on the way from
    /// the axis to [`Self::touch_offset`] (what a force must exceed to
    /// push the cage to the wall) \[N\]. Off the axis: the pull-off force
    /// (what holds the cage on the wall) \[N\].
    pub holding_force: f64,
    /// On the axis: `U(touch_offset) − U(0)`, the energy to bring the cage
    /// to the wall \[J\]. Off the axis: `U(0) − U(p₀)`, the barrier across
    /// the axis to the opposite wall \[J\].
    pub barrier: f64,
}

impl TubeRow {
    /// Whether the cage rests against the wall (a contact point exists).
    pub fn touches(&self) -> bool {
        !self.binding.on_axis
    }

    /// Boltzmann factor `exp(−barrier/(k_B T))` at [`TEMPERATURE`].
    pub fn thermal_factor(&self) -> f64 {
        (-self.barrier / (BOLTZMANN * TEMPERATURE)).exp()
    }
}

/// The paper's nano scenario run on the wall of one tube (rigid model).
#[derive(Debug, Clone)]
pub struct TubeRun {
    /// `n` of the `(n, n)` tube.
    pub n: u32,
    /// The scenario run: the nano preset (the paper's constant H, exact
    /// Coulomb friction μ = 0.13, bilateral contact) with `model =
    /// "rigid"`, `shape = "tube"`, the contact cylinder's radius
    /// `p₀ + R` (the cage's centre on its circle of equilibria when it
    /// touches) and `[adhesion]` the tube's pull-off force and binding.
    pub scenario: Scenario,
    /// The result.
    pub trajectory: Trajectory,
    /// The same without the force (every window's H set to 0).
    pub no_force: Trajectory,
}

impl TubeRun {
    /// Largest `|W_a|` over the samples \[J\].
    pub fn work_applied_max(&self) -> f64 {
        self.trajectory
            .samples
            .iter()
            .map(|s| s.work_applied.abs())
            .fold(0.0, f64::max)
    }

    /// Largest `|θ − θ without H|` over the samples \[rad\].
    pub fn force_effect(&self) -> f64 {
        self.trajectory
            .samples
            .iter()
            .zip(&self.no_force.samples)
            .map(|(a, b)| (a.theta - b.theta).abs())
            .fold(0.0, f64::max)
    }

    /// Smallest reaction over the samples \[N\].
    pub fn normal_min(&self) -> f64 {
        self.trajectory
            .samples
            .iter()
            .map(|s| s.normal)
            .fold(f64::INFINITY, f64::min)
    }
}

/// The nano preset on the wall of `row`'s tube: rigid model, the contact
/// cylinder's radius `p₀ + R` (the cage touches it on its circle of
/// equilibria), `[adhesion]` the tube's pull-off force as the load.
pub fn on_the_wall(row: &TubeRow) -> Scenario {
    let b = &row.binding;
    let mut sc = Scenario::nano();
    sc.solver.model = ModelKind::Rigid;
    sc.surface.shape = Shape::Tube {
        radius: b.offset + sc.top.radius,
        angle: 0.0,
    };
    sc.set_adhesion(Adhesion {
        force: row.holding_force,
        energy: b.energy,
    });
    sc
}

/// Every window's H set to 0.
pub fn without_force(sc: &mut Scenario) {
    for w in &mut sc.forcing.windows {
        w.hx = 0.0;
        w.hy = 0.0;
    }
}

/// The nano scenario on the wall of `row`'s tube, its window scaled by
/// `time_factor`, and the same with no force.
pub fn wall_run(row: &TubeRow, time_factor: f64) -> Result<TubeRun, Error> {
    let mut sc = on_the_wall(row);
    sc.solver.t_end *= time_factor;
    sc.surface.law = FrictionLaw::Coulomb;
    sc.surface.friction = crate::adhesion::PAPER_MU;
    sc.validate()?;
    let trajectory = simulate(&sc)?;
    let mut free = sc.clone();
    without_force(&mut free);
    let no_force = simulate(&free)?;
    Ok(TubeRun {
        n: row.n,
        scenario: sc,
        trajectory,
        no_force,
    })
}

/// The study: the tubes, the sheet, the paper's force and weight.
#[derive(Debug, Clone)]
pub struct TubeStudy {
    /// The tubes, in the order of [`TUBES`] ([`QUICK_TUBES`] with `--quick`).
    pub rows: Vec<TubeRow>,
    /// C60 on one graphene sheet (the same constants).
    pub sheet: Binding,
    /// The tube radius at which the cage leaves the axis \[m\].
    pub off_axis_radius: f64,
    /// `|H|` of the nano preset's force \[N\] (the paper's `H_x = H_y`).
    pub force: f64,
    /// The nano top's weight `m g` \[N\].
    pub weight: f64,
    /// The nano top's mass \[kg\].
    pub mass: f64,
    /// `k_B T` at [`TEMPERATURE`] \[J\].
    pub kt: f64,
    /// The figure's curves: per tube, offsets \[m\] and `U` \[J\] from the
    /// axis to the last grid point with `U ≤ 0`.
    pub curves: Vec<(Vec<f64>, Vec<f64>)>,
    /// The curves' grid step \[m\]: [`FIGURE_STEP`], 4x that with `--quick`.
    pub figure_step: f64,
    /// The paper's nano scenario on the wall of each tube where the cage
    /// rests on it ([`wall_run`]).
    pub runs: Vec<TubeRun>,
    /// The 300 K Langevin ensemble on the wall of the ([`HOT_TUBE`],
    /// [`HOT_TUBE`]) tube ([`hot_study`]).
    pub hot: HotStudy,
}

/// The largest of `f` over `n + 1` evenly spaced points of `[lo, hi]`.
fn scan_max(f: impl Fn(f64) -> f64, lo: f64, hi: f64, n: usize) -> f64 {
    (0..=n)
        .map(|i| f(lo + (hi - lo) * i as f64 / n as f64))
        .fold(f64::NEG_INFINITY, f64::max)
}

/// `U(p)` on the grid `0, FIGURE_STEP, …` while `U ≤ 0` and the cage stays
/// clear of the wall.
pub fn energy_curve(tube: &Nanotube) -> (Vec<f64>, Vec<f64>) {
    energy_curve_on(tube, FIGURE_STEP)
}

/// [`energy_curve`] on the grid `0, step, …` \[m\].
fn energy_curve_on(tube: &Nanotube, step: f64) -> (Vec<f64>, Vec<f64>) {
    let (mut ps, mut us) = (Vec::new(), Vec::new());
    let limit = tube.radius - tube.shell.radius;
    for i in 0.. {
        let p = i as f64 * step;
        if p >= limit {
            break;
        }
        let u = tube.energy(p);
        if u > 0.0 {
            break;
        }
        ps.push(p);
        us.push(u);
    }
    (ps, us)
}

/// The tubes of a `--quick` run ([`study`] with `time_factor < 1`): the
/// narrowest and the hot study's, so that the smoke test of the pipeline
/// stays cheap (the quadratures of the statics cost what they cost
/// whatever the windows' length).
pub const QUICK_TUBES: [u32; 2] = [TUBES[0], HOT_TUBE];

/// Run the study: the statics, and the nano scenario on the wall of each
/// tube where the cage rests (windows scaled by `time_factor`; a few
/// seconds in release). With `time_factor < 1` (`reproduce --quick`) the
/// statics cover [`QUICK_TUBES`] only, on a 4x coarser figure grid.
pub fn study(time_factor: f64) -> Result<TubeStudy, Error> {
    let quick = time_factor < 1.0;
    let (tubes, figure_step): (&[u32], f64) = if quick {
        (&QUICK_TUBES, 4.0 * FIGURE_STEP)
    } else {
        (&TUBES, FIGURE_STEP)
    };
    let nano = Scenario::nano();
    let (hx, hy) = nano.forcing.at(0.0);
    let kt = BOLTZMANN * TEMPERATURE;
    let first = Nanotube::c60_in(chirality_radius(TUBES[0], TUBES[0]));
    let sheet = first.sheet().binding()?;
    let mut rows = Vec::new();
    let mut curves = Vec::new();
    for &n in tubes {
        let tube = Nanotube::c60_in(chirality_radius(n, n));
        let binding = tube.binding()?;
        let touch_offset = tube.radius - tube.shell.radius - sheet.gap;
        let u = |p: f64| tube.energy(p);
        let (holding_force, barrier) = if binding.on_axis {
            (
                scan_max(|p| tube.energy_derivatives(p)[1], 0.0, touch_offset, 64),
                u(touch_offset) - u(0.0),
            )
        } else {
            (
                binding.pull_off_force.unwrap_or(f64::NAN),
                u(0.0) - u(binding.offset),
            )
        };
        rows.push(TubeRow {
            n,
            tube,
            rms: (kt / binding.stiffness).sqrt(),
            binding,
            touch_offset,
            holding_force,
            barrier,
        });
        curves.push(energy_curve_on(&tube, figure_step));
    }
    let runs = rows
        .iter()
        .filter(|r| !r.binding.on_axis)
        .map(|r| wall_run(r, time_factor))
        .collect::<Result<Vec<_>, Error>>()?;
    let hot_row = rows
        .iter()
        .find(|r| r.n == HOT_TUBE)
        .expect("the hot tube is in the study");
    let hot = hot_study(hot_row, time_factor)?;
    Ok(TubeStudy {
        rows,
        sheet,
        off_axis_radius: off_axis_radius(&first)?,
        force: hx.hypot(hy),
        weight: nano.top.mass * nano.surface.gravity,
        mass: nano.top.mass,
        kt,
        curves,
        figure_step,
        runs,
        hot,
    })
}

fn a(x: f64) -> String {
    s4(x / ANGSTROM)
}

fn ev(x: f64) -> String {
    s4(x / EV)
}

impl TubeStudy {
    /// The rows where the cage sits on the axis.
    fn on_axis(&self) -> impl Iterator<Item = &TubeRow> {
        self.rows.iter().filter(|r| r.binding.on_axis)
    }

    /// The rows where the cage rests on the wall.
    fn on_wall(&self) -> impl Iterator<Item = &TubeRow> {
        self.rows.iter().filter(|r| !r.binding.on_axis)
    }

    /// The energy gravity gives between the lowest and the highest point
    /// of the circle of equilibria of `row` (off the axis), `2 m g p₀` \[J\].
    pub fn gravity_span(&self, row: &TubeRow) -> f64 {
        2.0 * self.weight * row.binding.offset
    }

    /// `|H| / holding force`, largest over the tubes.
    pub fn force_ratio_max(&self) -> f64 {
        self.rows
            .iter()
            .map(|r| self.force / r.holding_force)
            .fold(0.0, f64::max)
    }

    /// The Markdown section (title, body).
    pub fn section(&self) -> (String, String) {
        let mut s = String::new();
        let sh = &self.sheet;
        s.push_str(&format!(
            "The paper puts its top \"on either a graphene sheet or the interior of a single-walled carbon nanotube\" and treats \
             both as a flat plane. Here the C60 (R = {} Å, N = 60) in armchair tubes, from the continuum Lennard-Jones statics of \
             `physics::nanotube` (the graphene case's constants and wall density, docs/physics.md#nanotube; `tippetop adhesion \
             --substrate nanotube --chirality N,N`). Reference: the flat graphene sheet, binding {} eV at a gap of {} Å, stiffness \
             {} N/m, pull-off {} nN. The cage leaves the axis in tubes wider than b = {} Å. The paper's force |H| = {} N \
             (the nano preset's H_x = H_y), the weight m g = {} N, k_B T = {} J ({} meV) at {TEMPERATURE} K.\n\n",
            a(self.rows[0].tube.shell.radius),
            ev(sh.energy),
            a(sh.gap),
            s4(sh.stiffness),
            s4(sh.pull_off_force * 1e9),
            a(self.off_axis_radius),
            s4(self.force),
            s4(self.weight),
            s4(self.kt),
            s4(self.kt / EV * 1e3),
        ));
        s.push_str(
            "Columns: tube radius b; where the cage sits (offset of its centre from the axis); the gap between cage and wall; binding \
             energy −U(p₀); radial stiffness U″(p₀); thermal rms excursion along one radial direction √(k_B T/U″) at 300 K (harmonic; within 6 % of the \
             Boltzmann spread of the full potential, tests/tube_study.rs) and its ratio to the wall gap; suction energy −U(0) (gained entering along the axis from free space); the holding force \
             (on the axis: the largest restoring force U′ on the way to the wall, i.e. to the sheet's gap; on the wall: the pull-off \
             force towards the axis) and |H| over it; the barrier (on the axis: the energy to bring the cage to the wall; on the wall: \
             the energy to cross the axis to the opposite wall) in units of k_B T.\n\n",
        );
        s.push_str("| tube | b [Å] | equilibrium | wall gap [Å] | binding [eV] | stiffness [N/m] | rms at 300 K [Å] | rms / gap | suction [eV] | holding force [nN] | \\|H\\| / holding | barrier / k_B T |\n|---|---|---|---|---|---|---|---|---|---|---|---|\n");
        for r in &self.rows {
            let b = &r.binding;
            s.push_str(&format!(
                "| ({n},{n}) | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} |\n",
                a(r.tube.radius),
                if b.on_axis {
                    "on the axis".to_string()
                } else {
                    format!("off, {} Å", a(b.offset))
                },
                a(b.gap),
                ev(b.energy),
                s4(b.stiffness),
                s4(r.rms / ANGSTROM),
                s4(r.rms / b.gap),
                ev(b.suction_energy),
                s4(r.holding_force * 1e9),
                s4(self.force / r.holding_force),
                s4(r.barrier / self.kt),
                n = r.n
            ));
        }
        s.push_str(
            "\n![figtube_energy](figtube_energy.png)\n\nThe energy against the offset of the cage's centre from the axis \
             (figtube_energy.png, data in figtube_energy.csv: the offset in m, U in eV per tube), with the sheet's binding as a line.\n\n",
        );
        s.push_str(&self.verdict());
        s.push_str(
            "\n![figtube_hot_phi](figtube_hot_phi.png)\n\n![figtube_hot_theta](figtube_hot_theta.png)\n\nAt 300 K on the wall of \
             the tube (data in figtube_hot_phi.csv and figtube_hot_theta.csv): the contact's angle φ around the axis and the \
             axis' tilt θ_n against the wall's normal, for the first four (φ) and two (θ_n) runs with the paper's force.\n",
        );
        ("Inside a nanotube".into(), s)
    }

    /// The verdict on the paper's second setting, from the numbers.
    pub fn verdict(&self) -> String {
        let mut s = String::from("**Verdict on the paper's second setting.**\n\n");
        for r in self.on_axis() {
            s.push_str(&self.floating(r));
        }
        let wall: Vec<&TubeRow> = self.on_wall().collect();
        if !wall.is_empty() {
            s.push_str(&self.resting(&wall));
        }
        if !self.runs.is_empty() {
            s.push_str(&self.dynamics());
        }
        s.push_str(&self.hot.item());
        let ratio = self.force_ratio_max();
        s.push_str(&format!(
            "- **What remains of the tippe-top story.** {} In every tube the paper's force is at most {} of the force that \
             holds the cage where it is (10^{} times smaller): it cannot bring a floating cage to the wall, nor make a resting \
             one slide. The paper's second setting is therefore not a flat plane with μ = 0.13 and the weight as the load: where \
             the cage floats there is nothing to roll on, and where it rests the wall is a concave circle without a preferred \
             side, on which the cage is held as firmly as on the sheet and more.\n",
            match (self.on_axis().count(), wall.len()) {
                (0, _) => "The cage rests on the wall in every tube of the study.".to_string(),
                (_, 0) => "The cage floats on the axis in every tube of the study.".to_string(),
                _ => format!(
                    "The cage floats on the axis in tubes narrower than b = {} Å and rests on the wall in wider ones.",
                    a(self.off_axis_radius)
                ),
            },
            s4(ratio),
            (-ratio.log10()).floor(),
        ));
        s
    }

    /// The verdict's item for the dynamic runs on the wall.
    fn dynamics(&self) -> String {
        let mut s = format!(
            "- **The paper's scenario on the wall (rigid model).** The nano preset (H = ({}, {}) N from t = 0, exact Coulomb \
             friction μ = {}, bilateral contact, {} µs) in a tube whose contact cylinder has the radius p₀ + R (the cage touches \
             it on its circle of equilibria), with `[adhesion]` the tube's pull-off force as the load in contact \
             (docs/physics.md#tube-dynamics), and the same with H = 0:",
            s4(self.force / 2f64.sqrt()),
            s4(self.force / 2f64.sqrt()),
            crate::adhesion::PAPER_MU,
            s4(self.runs[0].scenario.solver.t_end * 1e6),
        );
        for r in &self.runs {
            let su = &r.trajectory.summary;
            let fa = r.scenario.adhesion().force;
            s.push_str(&format!(
                " ({n},{n}) {status}: rolling {roll} % of the window, θ from {th0} to at most {thm} rad (end {thf}), \
                 max |W_a| = {wa} J, max |θ − θ(H = 0)| = {dth} rad, N ≥ {nmin} F_a;",
                n = r.n,
                status = if r.trajectory.error.is_none() {
                    "ran".to_string()
                } else {
                    format!("failed ({})", su.status)
                },
                roll = s4(100.0 * su.rolling_fraction),
                th0 = s4(r.trajectory.samples[0].theta),
                thm = s4(su.theta_max),
                thf = s4(su.theta_final),
                wa = s4(r.work_applied_max()),
                dth = s4(r.force_effect()),
                nmin = s4(r.normal_min() / fa),
            ));
        }
        let lies = self
            .runs
            .iter()
            .any(|r| r.trajectory.summary.theta_max > std::f64::consts::FRAC_PI_2);
        s.push_str(if lies {
            " in at least one tube the top lies down (θ > π/2).\n"
        } else {
            " the top never lies down (θ stays below π/2): it rolls on the wall, and the force, acting at a rolling contact \
             point, does not enter its motion.\n"
        });
        s
    }

    /// The verdict's item for a tube where the cage sits on the axis.
    fn floating(&self, r: &TubeRow) -> String {
        let b = &r.binding;
        let reach = if r.thermal_factor() > THERMAL_REACH {
            "thermal motion keeps bringing it there"
        } else {
            "at 300 K it spends about that fraction of its time that near the wall, in brief excursions, not at rest"
        };
        format!(
            "- **({n},{n}), b = {b_a} Å: no contact point.** The cage floats on the axis with a {gap} Å gap all round, held by \
             the whole wall ({e} eV, {e_rel} times the sheet's binding; stiffness {k} N/m in every radial direction). Its \
             thermal rms excursion at 300 K is {rms} Å, {rms_rel} of the gap. To come as near the wall as it sits on a sheet \
             it must move {pt} Å against a restoring force up to {f} nN, which costs {du} eV = {du_kt} k_B T (Boltzmann \
             factor {bf}: {reach}). The paper's force is {h_rel} of that restoring force; alone it displaces the cage by \
             |H|/k = {dx} m. There is no point at which friction acts, no \"down\" (the weight m g = {w} N is {w_rel} of the \
             restoring force at the wall), and no tippe top.\n",
            n = r.n,
            b_a = a(r.tube.radius),
            gap = a(b.gap),
            e = ev(b.energy),
            e_rel = s4(b.energy / self.sheet.energy),
            k = s4(b.stiffness),
            rms = s4(r.rms / ANGSTROM),
            rms_rel = s4(r.rms / b.gap),
            pt = a(r.touch_offset),
            f = s4(r.holding_force * 1e9),
            du = ev(r.barrier),
            du_kt = s4(r.barrier / self.kt),
            bf = s4(r.thermal_factor()),
            h_rel = s4(self.force / r.holding_force),
            dx = s4(self.force / b.stiffness),
            w = s4(self.weight),
            w_rel = s4(self.weight / r.holding_force),
        )
    }

    /// The verdict's item for the tubes where the cage rests on the wall.
    fn resting(&self, wall: &[&TubeRow]) -> String {
        let list = |f: &dyn Fn(&TubeRow) -> String| {
            wall.iter().map(|r| f(r)).collect::<Vec<_>>().join(", ")
        };
        let span_kt = wall
            .iter()
            .map(|r| self.gravity_span(r) / self.kt)
            .fold(0.0, f64::max);
        let crossing: Vec<String> = wall
            .iter()
            .filter(|r| r.thermal_factor() > THERMAL_REACH)
            .map(|r| format!("({0},{0})", r.n))
            .collect();
        let ratio = wall
            .iter()
            .map(|r| self.force / r.holding_force)
            .fold(0.0, f64::max);
        format!(
            "- **{names}: a contact, but on a circle with no bottom.** The cage rests against the wall at gaps of {gaps} Å \
             (the sheet's: {sheet} Å), off the axis by {offs} Å. The tube is round, so every point of the circle of radius p₀ \
             around the axis is an equilibrium: the cage can roll around the tube at no cost. Only gravity picks the lowest \
             point, and the whole circle spans 2 m g p₀ ≤ {span} k_B T at 300 K: thermally the cage is anywhere on it, with no \
             \"down\" (the paper's Z) for a tippe top to invert against. Across the axis to the opposite wall the barrier is \
             {barriers} k_B T respectively{crossing}. The surface it rolls on is concave: the centre's path around the axis has \
             a radius of only {curv} cage radii. The load that holds the cage on the wall is the pull-off force, {pull} nN \
             (the sheet's {sheet_pull} nN), so |H| is at most {ratio} of it: as on the sheet (section \"Adhesion\"), Coulomb \
             friction μ times that load stops any slip at once, and a force at a rolling contact point does no work.\n",
            names = list(&|r| format!("({0},{0})", r.n)),
            gaps = list(&|r| a(r.binding.gap)),
            sheet = a(self.sheet.gap),
            offs = list(&|r| a(r.binding.offset)),
            span = s4(span_kt),
            barriers = list(&|r| s4(r.barrier / self.kt)),
            crossing = if crossing.is_empty() {
                String::new()
            } else {
                format!(" (thermal motion crosses in {})", crossing.join(", "))
            },
            curv = list(&|r| s4((r.tube.radius - r.tube.shell.radius) / r.tube.shell.radius)),
            pull = list(&|r| s4(r.holding_force * 1e9)),
            sheet_pull = s4(self.sheet.pull_off_force * 1e9),
            ratio = s4(ratio),
        )
    }

    /// The figure: `U(p)` per tube in eV against the offset in Å, the
    /// sheet's binding as a reference line.
    pub fn figure(&self) -> Figure {
        Figure {
            id: "tube_energy".into(),
            title:
                "C60 inside armchair nanotubes: energy against the centre's offset from the axis"
                    .into(),
            x_label: "offset of the cage's centre from the axis [Å]".into(),
            x_scale: 1.0 / ANGSTROM,
            x_name: "offset_m".into(),
            y_label: "U [eV]".into(),
            curves: self
                .rows
                .iter()
                .zip(&self.curves)
                .map(|(r, (ps, us))| Curve {
                    name: format!("(n = m = {}) b = {} Å", r.n, s4(r.tube.radius / ANGSTROM)),
                    t: ps.clone(),
                    y: us.iter().map(|u| u / EV).collect(),
                    dashed: false,
                })
                .collect(),
            hlines: vec![(
                -self.sheet.energy / EV,
                format!("graphene sheet, −{} eV", s4(self.sheet.energy / EV)),
            )],
            note: format!(
                "Continuum Lennard-Jones (docs/physics.md#nanotube), C60 in (n,n) tubes; each curve from the axis to the last \
                 offset (step {} Å) where U ≤ 0. The minimum of each curve is the cage's equilibrium: on the axis for (10,10), off it \
                 for the wider tubes. Reference line: the binding on a flat graphene sheet.",
                self.figure_step / ANGSTROM
            ),
            ..Default::default()
        }
    }
}
