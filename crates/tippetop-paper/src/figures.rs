//! One function per figure of the paper (Figs. 2–15; Fig. 5 is a drawing
//! the CLI makes from [`fig05_snapshots`]). The closed forms of Figs. 8–11
//! are the library's (`tippetop::analysis::asymptotics`).

use std::f64::consts::{FRAC_PI_2, PI};

use tippetop::analysis::asymptotics::{self as asy, AsymptoticsReport, LyingParams, UxyConstants};
use tippetop::{Sample, Trajectory};

use crate::runs::{
    self, CLASSICAL_EXACT, CLASSICAL_REGULARIZED, CLASSICAL_RK4, NANO_BILATERAL, NANO_BILATERAL_G0,
    NANO_BILATERAL_G100, NANO_PAPER, NANO_PAPER_RK4, REVERSAL_BILATERAL, REVERSAL_PAPER,
    REVERSAL_PAPER_RK4, Runs, STEP1, STEP8,
};
use crate::{Curve, Figure, Options, PAPER_C1, PAPER_T_STAR};

const US: f64 = 1e6;

/// A curve of `f` over the samples of `tr`.
pub fn curve(name: &str, tr: &Trajectory, f: impl Fn(&Sample) -> f64, dashed: bool) -> Curve {
    Curve {
        name: name.to_string(),
        t: tr.samples.iter().map(|s| s.t).collect(),
        y: tr.samples.iter().map(f).collect(),
        dashed,
    }
}

/// Reference lines at π/2 and π.
pub fn theta_lines() -> Vec<(f64, String)> {
    vec![(FRAC_PI_2, "π/2".to_string()), (PI, "π".to_string())]
}

fn zero_line() -> Vec<(f64, String)> {
    vec![(0.0, String::new())]
}

/// A nano figure in µs with the three computations: bilateral, paper
/// contact, and the paper's RK4/500 (dashed); `runs3` names them in that
/// order.
#[allow(clippy::too_many_arguments)]
fn three(
    runs: &Runs,
    id: &str,
    title: &str,
    y_label: &str,
    f: fn(&Sample) -> f64,
    runs3: [&str; 3],
    note: &str,
    hlines: Vec<(f64, String)>,
) -> Figure {
    Figure {
        id: id.into(),
        title: title.into(),
        x_label: "t [µs]".into(),
        x_scale: US,
        y_label: y_label.into(),
        curves: vec![
            curve("bilateral (accurate)", runs.tr(runs3[0]), f, false),
            curve("paper contact (accurate)", runs.tr(runs3[1]), f, false),
            curve(
                "paper contact RK4/500 (paper's method)",
                runs.tr(runs3[2]),
                f,
                true,
            ),
        ],
        hlines,
        vlines: switch_marks(runs, runs3[0]),
        note: with_failures(
            note,
            &[
                ("bilateral (accurate)", runs.tr(runs3[0])),
                ("paper contact (accurate)", runs.tr(runs3[1])),
                ("paper contact RK4/500 (paper's method)", runs.tr(runs3[2])),
            ],
        ),
        ..Default::default()
    }
}

/// The force switches of `run`'s scenario inside its window, as vertical
/// marks (time \[s\], label): "force reversed" where H changes sign,
/// "force off" where it drops to zero, "force on", or "force switches".
pub fn switch_marks(runs: &Runs, run: &str) -> Vec<(f64, String)> {
    let sc = &runs.get(run).scenario;
    let t_end = sc.solver.t_end;
    sc.switch_times()
        .into_iter()
        .filter(|&t| t > 0.0 && t < t_end)
        .map(|t| {
            let dt = 1e-9 * t_end;
            let (a, b) = (sc.forcing.at(t - dt), sc.forcing.at(t + dt));
            let label = if b == (0.0, 0.0) {
                "force off"
            } else if a == (0.0, 0.0) {
                "force on"
            } else if b == (-a.0, -a.1) {
                "force reversed"
            } else {
                "force switches"
            };
            (t, label.to_string())
        })
        .collect()
}

/// `note`, followed by a sentence for each curve whose run failed: where
/// the curve ends and why (the reason up to its first colon; the run
/// table of the report has the whole message).
pub fn with_failures(note: &str, curves: &[(&str, &Trajectory)]) -> String {
    let mut s = note.to_string();
    for (name, tr) in curves {
        if let Some(tippetop::Error::Runtime { t, why, .. }) = &tr.error {
            let short = why.split([':', ';']).next().unwrap_or(why).trim();
            s.push_str(&format!(
                " {name} ends at t = {t:.4e} s, where its run failed ({short})."
            ));
        }
    }
    s
}

const NANO3: [&str; 3] = [NANO_BILATERAL, NANO_PAPER, NANO_PAPER_RK4];

/// Fig. 2: θ of the nano top for g = 0, 9.8 and 100 m/s².
pub fn fig02(runs: &Runs) -> Figure {
    Figure {
        id: "02".into(),
        title: "Fig. 2: nutation angle θ of the nano top for g = 0, 9.8 and 100 m/s²".into(),
        x_label: "t [µs]".into(),
        x_scale: US,
        y_label: "θ [rad]".into(),
        curves: vec![
            curve(
                "g=0 bilateral",
                runs.tr(NANO_BILATERAL_G0),
                |s| s.theta,
                false,
            ),
            curve(
                "g=9.8 bilateral",
                runs.tr(NANO_BILATERAL),
                |s| s.theta,
                false,
            ),
            curve(
                "g=100 bilateral",
                runs.tr(NANO_BILATERAL_G100),
                |s| s.theta,
                false,
            ),
            curve(
                "g=9.8 paper contact",
                runs.tr(NANO_PAPER),
                |s| s.theta,
                false,
            ),
            curve(
                "g=9.8 paper contact RK4/500",
                runs.tr(NANO_PAPER_RK4),
                |s| s.theta,
                true,
            ),
        ],
        hlines: theta_lines(),
        note: with_failures(
            "H_x = H_y = 0.1 zN from t = 0; window 100 µs (our choice: the paper's text speaks of ~50 µs).",
            &[("g=9.8 paper contact RK4/500", runs.tr(NANO_PAPER_RK4))],
        ),
        ..Default::default()
    }
}

/// Fig. 3: Ω of the nano top.
pub fn fig03(runs: &Runs) -> Figure {
    let f = three(
        runs,
        "03",
        "Fig. 3: precession rate Ω of the nano top",
        "Ω [rad/s]",
        |s| s.precession,
        NANO3,
        "Same runs as Fig. 2, g = 9.8. Ω nutates faster than the figure can show: each curve is drawn as its running mean with its running min–max band.",
        zero_line(),
    );
    Figure {
        envelope: true,
        ..f
    }
}

/// Fig. 4: ω of the nano top.
pub fn fig04(runs: &Runs) -> Figure {
    three(
        runs,
        "04",
        "Fig. 4: spin ω of the nano top",
        "ω [rad/s]",
        |s| s.spin,
        NANO3,
        "ω = n·k, the axial component of the angular velocity.",
        zero_line(),
    )
}

/// Fig. 5: the instants (t \[s\], θ \[rad\]) of the accurate nano run at
/// which the CLI draws the top.
pub fn fig05_snapshots(runs: &Runs, opts: Options) -> Vec<(f64, f64)> {
    let tr = runs.tr(NANO_BILATERAL);
    [0.0, 1e-6, 2e-6, 3e-6, 5e-6, 1e-5, 5e-5]
        .iter()
        .map(|&t| t * opts.time_factor())
        .map(|t| (t, runs::at(tr, t, |s| s.theta)))
        .collect()
}

/// Fig. 6: θ after the retarding force reverses.
pub fn fig06(runs: &Runs) -> Figure {
    three(
        runs,
        "06",
        "Fig. 6: nutation angle θ after the retarding force reverses",
        "θ [rad]",
        |s| s.theta,
        [REVERSAL_BILATERAL, REVERSAL_PAPER, REVERSAL_PAPER_RK4],
        "H = (0.1, 0.1) zN on [0, 100 µs), then (−0.1, −0.1) zN: the reversal time is our choice (scenarios/fig06_reversal.toml).",
        theta_lines(),
    )
}

/// Fig. 7: θ of the classical tippe top.
pub fn fig07(runs: &Runs) -> Figure {
    Figure {
        id: "07".into(),
        title: "Fig. 7: nutation angle θ of the classical tippe top".into(),
        x_label: "t [s]".into(),
        x_scale: 1.0,
        y_label: "θ [rad]".into(),
        curves: vec![
            curve(
                "exact Coulomb (accurate)",
                runs.tr(CLASSICAL_EXACT),
                |s| s.theta,
                false,
            ),
            curve(
                "regularised ε = 1e-2 m/s (accurate)",
                runs.tr(CLASSICAL_REGULARIZED),
                |s| s.theta,
                false,
            ),
            curve(
                "sliding Coulomb RK4/500 (paper's method)",
                runs.tr(CLASSICAL_RK4),
                |s| s.theta,
                true,
            ),
        ],
        hlines: theta_lines(),
        note: with_failures(
            "R = 15 mm, a = 0.1 R, m = 15 g, A = C, μ = 0.1, no applied force.",
            &[(
                "sliding Coulomb RK4/500 (paper's method)",
                runs.tr(CLASSICAL_RK4),
            )],
        ),
        ..Default::default()
    }
}

/// App. C against the nano runs: the closed forms' parameters, the
/// analyses of both accurate runs, and the times the closed forms are drawn
/// at (from 5 % of the window on).
pub struct AppC {
    /// R, C, m, H of the paper-contact run.
    pub params: LyingParams,
    /// Paper contact, accurate.
    pub paper: AsymptoticsReport,
    /// Bilateral, accurate.
    pub bilateral: AsymptoticsReport,
    /// Sample times of the closed-form curves \[s\].
    pub t: Vec<f64>,
}

impl AppC {
    /// Fit and compare App. C over the second half of the nano window.
    pub fn of(runs: &Runs, opts: Options) -> AppC {
        let t_end = runs.t_end(NANO_BILATERAL);
        let params = LyingParams::of(&runs.get(NANO_PAPER).scenario, 0.0);
        let t_star = PAPER_T_STAR * opts.time_factor();
        let analyse =
            |name: &str| asy::analyse(&runs.tr(name).samples, &params, 0.5 * t_end, t_end, t_star);
        AppC {
            params,
            paper: analyse(NANO_PAPER),
            bilateral: analyse(NANO_BILATERAL),
            t: runs
                .tr(NANO_BILATERAL)
                .samples
                .iter()
                .map(|s| s.t)
                .filter(|&t| t >= 0.05 * t_end)
                .collect(),
        }
    }

    /// A dashed closed-form curve `g(t)`.
    fn curve(&self, name: &str, g: impl Fn(f64) -> f64) -> Curve {
        Curve {
            name: name.into(),
            t: self.t.clone(),
            y: self.t.iter().map(|&t| g(t)).collect(),
            dashed: true,
        }
    }
}

const PAPER_CONSTANTS_NOTE: &str =
    "Paper's constants: t* = 5e-5 s, u1 = −6e-7 m/s, u2 = −4e-3 m/s, c1 = 3e6.";

/// Fig. 8: (C2) for ω against the numerics.
pub fn fig08(runs: &Runs, c: &AppC) -> Figure {
    let (p, b) = (&c.paper, &c.bilateral);
    let c1 = p.fit.c1;
    Figure {
        id: "08".into(),
        title: "Fig. 8: asymptotic expansion (C2) for ω".into(),
        x_label: "t [µs]".into(),
        x_scale: US,
        y_label: "ω [rad/s]".into(),
        curves: vec![
            curve(
                "bilateral (accurate)",
                runs.tr(NANO_BILATERAL),
                |s| s.spin,
                false,
            ),
            curve(
                "paper contact (accurate)",
                runs.tr(NANO_PAPER),
                |s| s.spin,
                false,
            ),
            c.curve("(C2) paper's c1 = 3e6", |t| {
                asy::omega_c2(&c.params, PAPER_C1, t)
            }),
            c.curve("(C2) c1 fitted to paper contact", |t| {
                asy::omega_c2(&c.params, c1, t)
            }),
        ],
        hlines: vec![],
        note: format!(
            "ω = −R H t/C + c1, fitted over the second half of the window. Max relative error there (paper contact): fitted c1 {:.3}, paper's c1 {:.3}; bilateral: {:.3}, {:.3}.",
            p.c2_fitted.rel, p.c2_paper.rel, b.c2_fitted.rel, b.c2_paper.rel
        ),
        ..Default::default()
    }
}

/// Fig. 9: (C3) for Ω against the numerics.
pub fn fig09(runs: &Runs, c: &AppC) -> Figure {
    let p = &c.paper;
    let c1 = p.fit.c1;
    Figure {
        id: "09".into(),
        title: "Fig. 9: asymptotic expansion (C3) for Ω".into(),
        x_label: "t [µs]".into(),
        x_scale: US,
        y_label: "Ω [rad/s]".into(),
        curves: vec![
            curve(
                "bilateral (accurate)",
                runs.tr(NANO_BILATERAL),
                |s| s.precession,
                false,
            ),
            curve(
                "paper contact (accurate)",
                runs.tr(NANO_PAPER),
                |s| s.precession,
                false,
            ),
            c.curve("(C3) paper's c1 = 3e6", |t| {
                asy::precession_c3(&c.params, PAPER_C1, t)
            }),
            c.curve("(C3) c1 fitted to paper contact", |t| {
                asy::precession_c3(&c.params, c1, t)
            }),
        ],
        hlines: zero_line(),
        note: format!(
            "Ω = R H/(c1 C − R H t); the denominator vanishes at t = {:.3} µs with c1 = 3e6 ({:.3} µs with the fitted c1). Max relative error over the second half (paper contact): fitted {:.3}, paper's {:.3}: Ω nutates at C|ω|/A, which the quasi-static law cannot follow.",
            p.c3_pole_paper * US,
            p.c3_pole_fitted * US,
            p.c3_fitted.rel,
            p.c3_paper.rel
        ),
        envelope: true,
        ..Default::default()
    }
}

/// Figs. 10 and 11: the closed form for u_x (`component` 0) or u_y (1).
fn fig_u(runs: &Runs, c: &AppC, component: usize) -> Figure {
    let p = &c.paper;
    let pick = |u: (f64, f64)| if component == 0 { u.0 } else { u.1 };
    let (id, name, f): (&str, &str, fn(&Sample) -> f64) = if component == 0 {
        ("10", "u_x", |s| s.ux)
    } else {
        ("11", "u_y", |s| s.uy)
    };
    let (err_paper, err_numerics) = if component == 0 {
        (p.ux_paper.rel, p.ux_numerics.rel)
    } else {
        (p.uy_paper.rel, p.uy_numerics.rel)
    };
    let paper_k = UxyConstants::paper();
    Figure {
        id: id.into(),
        title: format!(
            "Fig. {}: asymptotic expansion for {name} compared with the numerics",
            id.trim_start_matches('0')
        ),
        x_label: "t [µs]".into(),
        x_scale: US,
        y_label: format!("{name} [m/s]"),
        curves: vec![
            curve("bilateral (accurate)", runs.tr(NANO_BILATERAL), f, false),
            curve("paper contact (accurate)", runs.tr(NANO_PAPER), f, false),
            c.curve("closed form with paper's constants", |t| {
                pick(asy::uxy(&c.params, &paper_k, t))
            }),
            c.curve("closed form u1 u2 c1 from paper-contact numerics", |t| {
                pick(asy::uxy(&c.params, &p.uxy_numerics, t))
            }),
        ],
        hlines: vec![],
        note: format!(
            "{PAPER_CONSTANTS_NOTE} Max relative error over the second half (paper contact): paper's constants {err_paper:.3}, constants from the numerics {err_numerics:.3}."
        ),
        envelope: true,
        ..Default::default()
    }
}

/// Fig. 10: u_x.
pub fn fig10(runs: &Runs, c: &AppC) -> Figure {
    fig_u(runs, c, 0)
}

/// Fig. 11: u_y.
pub fn fig11(runs: &Runs, c: &AppC) -> Figure {
    fig_u(runs, c, 1)
}

/// Fig. 12: θ with the force on for 8 µs.
pub fn fig12(runs: &Runs) -> Figure {
    three(
        runs,
        "12",
        "Fig. 12: θ with H_y = H·H(t0 − t), t0 = 8 µs",
        "θ [rad]",
        |s| s.theta,
        STEP8,
        "H_x = 0.",
        theta_lines(),
    )
}

/// Fig. 13: ω with the force on for 8 µs.
pub fn fig13(runs: &Runs) -> Figure {
    three(
        runs,
        "13",
        "Fig. 13: ω with H_y = H·H(t0 − t), t0 = 8 µs",
        "ω [rad/s]",
        |s| s.spin,
        STEP8,
        "H_x = 0.",
        zero_line(),
    )
}

/// Fig. 14: θ with the force on for 1 µs.
pub fn fig14(runs: &Runs) -> Figure {
    three(
        runs,
        "14",
        "Fig. 14: θ with H_y = H·H(t0 − t), t0 = 1 µs",
        "θ [rad]",
        |s| s.theta,
        STEP1,
        "H_x = 0.",
        theta_lines(),
    )
}

/// Fig. 15: ω with the force on for 1 µs.
pub fn fig15(runs: &Runs) -> Figure {
    three(
        runs,
        "15",
        "Fig. 15: ω with H_y = H·H(t0 − t), t0 = 1 µs",
        "ω [rad/s]",
        |s| s.spin,
        STEP1,
        "H_x = 0.",
        zero_line(),
    )
}

/// RK4/500 curves that blow up are cut where they leave the plot's scale
/// (3x the largest |value| of the figure's first, accurate curve), and the
/// note says so.
pub fn cut_blow_ups(f: &mut Figure) {
    let ymax = f.curves[0].y.iter().map(|v| v.abs()).fold(0.0, f64::max);
    let mut cut_notes = Vec::new();
    for c in f.curves.iter_mut().filter(|c| c.name.contains("RK4")) {
        if let Some(i) =
            c.y.iter()
                .position(|v| !v.is_finite() || v.abs() > 3.0 * ymax)
        {
            cut_notes.push(format!(
                "{} leaves the scale (blows up) at t = {:.4e} s and is cut there.",
                c.name, c.t[i]
            ));
            c.t.truncate(i);
            c.y.truncate(i);
        }
    }
    for n in cut_notes {
        f.note.push(' ');
        f.note.push_str(&n);
    }
}

/// Figures 02–15 (without 05), in order, blow-ups cut.
pub fn all(runs: &Runs, c: &AppC) -> Vec<Figure> {
    let mut figures = vec![
        fig02(runs),
        fig03(runs),
        fig04(runs),
        fig06(runs),
        fig07(runs),
        fig08(runs, c),
        fig09(runs, c),
        fig10(runs, c),
        fig11(runs, c),
        fig12(runs),
        fig13(runs),
        fig14(runs),
        fig15(runs),
    ];
    for f in &mut figures {
        cut_blow_ups(f);
    }
    figures
}
