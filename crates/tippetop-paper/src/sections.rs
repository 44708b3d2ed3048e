//! The report's sections beyond the claims table: exact Coulomb friction
//! (stick/slip), App. C against the numerics, and in extended mode the
//! classical inversion maps, the ε study of the friction law, the
//! adhesion study ([`crate::adhesion`]) and the C60 inside nanotubes
//! ([`crate::tube`]).

use tippetop::analysis::asymptotics::ErrorStat;
use tippetop::analysis::friction::{self, EpsRow};
use tippetop::analysis::sweep::{self, Axis, Sweep};
use tippetop::{Error, FrictionLaw, Top, simulate};

use crate::claims::classical_stick_time;
use crate::figures::{AppC, curve, theta_lines};
use crate::runs::{
    CLASSICAL_EXACT, NANO_BILATERAL, REVERSAL_BILATERAL, Runs, STEP1, STEP8, max_diff,
};
use crate::{Figure, MapData, Options};

/// (title, Markdown body) of the report's sections that every reproduction
/// has.
pub fn core(runs: &Runs, app_c: &AppC) -> Vec<(String, String)> {
    vec![stick_slip(runs), app_c_table(app_c)]
}

/// Exact Coulomb friction: the classical top sticks and rolls; how long the
/// nano runs roll; whether the sliding-only law changes the nano result.
pub fn stick_slip(runs: &Runs) -> (String, String) {
    let ce = &runs.tr(CLASSICAL_EXACT).summary;
    let nano_rolling: Vec<String> = [NANO_BILATERAL, REVERSAL_BILATERAL, STEP8[0], STEP1[0]]
        .iter()
        .map(|n| format!("{n} {:.1}%", 100.0 * runs.tr(n).summary.rolling_fraction))
        .collect();
    (
        "Exact Coulomb friction (stick/slip)".to_string(),
        format!(
            "Under exact Coulomb friction (`friction_law = \"coulomb\"`) the classical benchmark reaches zero slip at t = {} s, \
             sticks, and rolls for {:.1}% of the 10 s window without slipping again; it **does not invert** (θ(10 s) = {:.3} rad). \
             A rolling eccentric sphere conserves energy and cannot raise its centre of mass, so the paper's inversion needs sliding \
             friction: with the regularised law it inverts at a time that grows like 1/ε (see `reproduce --extended`).\n\n\
             Nano runs, time spent rolling under the exact law (bilateral): {}. {}\n",
            classical_stick_time(runs)
                .map(|t| format!("{t:.4}"))
                .unwrap_or("never".into()),
            100.0 * ce.rolling_fraction,
            ce.theta_final,
            nano_rolling.join(", "),
            sliding_only_difference(runs)
        ),
    )
}

/// For the constant-force nano run: does the exact law change anything
/// compared with the sliding-only law? (Same scenario, `coulomb_sliding`.)
fn sliding_only_difference(runs: &Runs) -> String {
    let run = runs.get(NANO_BILATERAL);
    let mut sc = run.scenario.clone();
    sc.surface.law = FrictionLaw::CoulombSliding;
    match simulate(&sc) {
        Ok(t) => {
            let d = max_diff(&t, &run.trajectory, |s| s.theta);
            format!(
                "For the constant-force nano run the sliding-only law gives the same θ(t) to {d:.1e} rad (max difference), so the paper's nano results do not depend on the treatment of zero slip; after the force is switched off or reversed the top can roll, and there the exact law matters."
            )
        }
        Err(e) => format!("(sliding-only comparison failed: {e})"),
    }
}

/// App. C's laws against the numerics: a table of the fits and errors, and
/// where and why the laws fail.
pub fn app_c_table(c: &AppC) -> (String, String) {
    let (p, b) = (&c.paper, &c.bilateral);
    let stat = |e: &ErrorStat| format!("{:.3}", e.rel);
    let pair = |x: &ErrorStat, y: &ErrorStat| format!("{} / {}", stat(x), stat(y));
    let mut body = String::from(
        "Fitted over the second half of the window; errors are max |closed form − numerics| / max |numerics| over that window.\n\n| quantity | paper contact | bilateral |\n|---|---|---|\n",
    );
    for (name, a, bb) in [
        (
            "fitted c1 [rad/s] (paper: 3e6)",
            format!("{:.4e}", p.fit.c1),
            format!("{:.4e}", b.fit.c1),
        ),
        (
            "free-fit slope / (−R H/C)",
            format!("{:.4}", p.slope_ratio),
            format!("{:.4}", b.slope_ratio),
        ),
        (
            "mean θ − π/2 [rad]",
            format!("{:.4}", p.theta_offset),
            format!("{:.4}", b.theta_offset),
        ),
        (
            "half-range of θ [rad]",
            format!("{:.4}", p.theta_amplitude),
            format!("{:.4}", b.theta_amplitude),
        ),
        (
            "error of (C2), fitted c1 / paper's c1",
            pair(&p.c2_fitted, &p.c2_paper),
            pair(&b.c2_fitted, &b.c2_paper),
        ),
        (
            "error of (C3), fitted c1 / paper's c1",
            pair(&p.c3_fitted, &p.c3_paper),
            pair(&b.c3_fitted, &b.c3_paper),
        ),
        (
            "error of u_x, constants from numerics / paper's",
            pair(&p.ux_numerics, &p.ux_paper),
            pair(&b.ux_numerics, &b.ux_paper),
        ),
        (
            "error of u_y, constants from numerics / paper's",
            pair(&p.uy_numerics, &p.uy_paper),
            pair(&b.uy_numerics, &b.uy_paper),
        ),
    ] {
        body.push_str(&format!("| {name} | {a} | {bb} |\n"));
    }
    body.push_str("\nWhere and why the laws fail (paper contact):\n\n");
    for line in &p.text {
        body.push_str(&format!("- {line}\n"));
    }
    (
        "App. C asymptotic laws against the numerics".to_string(),
        body,
    )
}

/// What extended mode adds.
#[derive(Debug, Clone, Default)]
pub struct Extended {
    /// Report sections (title, Markdown body).
    pub sections: Vec<(String, String)>,
    /// The ε-study figures.
    pub figures: Vec<Figure>,
    /// The inversion maps.
    pub maps: Vec<MapData>,
}

/// The classical inversion maps (regularised and exact friction), the ε
/// study of the friction law over 10 s and 150 s, and the adhesion study.
pub fn extended(
    runs: &Runs,
    opts: Options,
    progress: &mut dyn FnMut(&str),
) -> Result<Extended, Error> {
    let q = opts.time_factor();
    let mut out = Extended::default();
    for (law, sets) in [
        (
            "regularized",
            vec![
                "surface.friction_law=\"regularized\"".to_string(),
                "surface.friction_eps=1e-2".to_string(),
            ],
        ),
        ("exact Coulomb", vec![]),
    ] {
        progress(&format!("inversion map, {law}"));
        let (map, body) = inversion_map(law, &sets, q)?;
        out.sections
            .push((format!("Classical inversion map, {law} friction"), body));
        out.maps.push(map);
    }
    let mut base = runs.get(CLASSICAL_EXACT).scenario.clone();
    for (label, t_end) in [("10 s", base.solver.t_end), ("150 s", 150.0 * q)] {
        base.solver.t_end = t_end;
        base.solver.samples = 1501;
        progress(&format!("eps study {label}"));
        let study = friction::eps_study(&base, &[1e-2, 1e-3, 1e-4])?;
        let rows: Vec<_> = study.iter().map(|(r, _)| r.clone()).collect();
        let mut body = friction::eps_table(&rows);
        body.push_str(&eps_conclusion(&rows));
        out.sections.push((
            format!("ε study of the friction law, classical top, {label}"),
            body,
        ));
        out.figures.push(Figure {
            id: format!("eps_{}", label.replace(' ', "")),
            title: format!(
                "ε study: θ of the classical top, regularised vs exact Coulomb, {label}"
            ),
            x_label: "t [s]".into(),
            x_scale: 1.0,
            y_label: "θ [rad]".into(),
            curves: study
                .iter()
                .map(|(r, t)| {
                    let name = r
                        .eps
                        .map(|e| format!("regularised eps={e:e}"))
                        .unwrap_or("exact Coulomb".into());
                    curve(&name, t, |s| s.theta, false)
                })
                .collect(),
            hlines: theta_lines(),
            note: "Regularised Coulomb μ N v/√(|v|² + ε²) for ε = 1e-2, 1e-3, 1e-4 m/s against the exact stick/slip law.".into(),
            ..Default::default()
        });
    }
    let study = crate::adhesion::study(runs, opts, progress)?;
    out.sections.push(study.section());
    out.figures.extend(study.figures(runs));
    progress("inside a nanotube");
    let tube = crate::tube::study(q)?;
    out.sections.push(tube.section());
    out.figures.push(tube.figure());
    out.figures.extend(tube.hot.figures());
    Ok(out)
}

/// What the ε study shows, computed from its rows (exact law first).
pub fn eps_conclusion(rows: &[EpsRow]) -> String {
    let exact = &rows[0];
    let reg = &rows[1..];
    let mut s = String::from("\n");
    let inv: Vec<(f64, f64)> = reg
        .iter()
        .filter_map(|r| Some((r.eps?, r.inversion_time?)))
        .collect();
    if inv.len() >= 2 {
        let ratios: Vec<String> = inv
            .windows(2)
            .map(|w| format!("{:.1}", w[1].1 / w[0].1))
            .collect();
        s.push_str(&format!(
            "Inversion time against ε: {}; each tenfold decrease of ε multiplies it by {} (1/ε scaling would be 10). ",
            inv.iter()
                .map(|(e, t)| format!("{t:.2} s at ε = {e:e}"))
                .collect::<Vec<_>>()
                .join(", "),
            ratios.join(", ")
        ));
    }
    match reg.last() {
        Some(last) if last.inversion_time.is_none() => s.push_str(&format!(
            "In this window the smallest ε does not invert, and its end state θ = {:.4} rad is within {:.1e} rad of the exact law's ({:.4} rad): for a fixed window the regularised results converge to the exact law's as ε → 0. ",
            last.theta_final,
            (last.theta_final - exact.theta_final).abs(),
            exact.theta_final
        )),
        Some(_) => s.push_str("Every regularised run inverts in this window and heads for the same inverted state (θ near π, ω near the Jellett value), independent of ε; the exact law never inverts: the limit ε → 0 and the time t → ∞ do not commute. "),
        None => {}
    }
    s.push_str(&format!(
        "The exact law {} in this window.\n",
        match exact.inversion_time {
            Some(t) => format!("inverts at {t:.3} s"),
            None => "does not invert".to_string(),
        }
    ));
    s
}

/// The classical inversion map over (A/C, a/R): the paper's classical top
/// with C fixed, A = (A/C)·C and a = (a/R)·R varied, from the paper's
/// initial state, 10 s, with the given friction-law overrides. The
/// literature's window 1 − a/R < A/C < 1 + a/R is drawn over it.
pub fn inversion_map(law: &str, sets: &[String], q: f64) -> Result<(MapData, String), Error> {
    let top = Top::classical();
    let (c, r) = (top.inertia_axial, top.radius);
    let (nx, ny) = if q < 1.0 { (5, 4) } else { (21, 20) };
    let mut all_sets = sets.to_vec();
    all_sets.push(format!("solver.t_end={:?}", 10.0 * q));
    all_sets.push("solver.samples=201".to_string());
    let sweep = Sweep {
        preset: Some("classical".into()),
        toml_text: None,
        sets: all_sets,
        axes: vec![
            Axis {
                key: "top.inertia_transverse".into(),
                from: 0.55 * c,
                to: 1.5 * c,
                n: nx,
                log: false,
                given: None,
            },
            Axis {
                key: "top.offset".into(),
                from: 0.02 * r,
                to: 0.4 * r,
                n: ny,
                log: false,
                given: None,
            },
        ],
    };
    let rows = sweep.run(0..sweep.total(), None, &|| {})?;
    let xs: Vec<f64> = (0..nx).map(|i| sweep.axes[0].value(i) / c).collect();
    let ys: Vec<f64> = (0..ny).map(|j| sweep.axes[1].value(j) / r).collect();
    let mut z = vec![vec![f64::NAN; nx]; ny];
    let (mut inside, mut inside_inv, mut outside, mut outside_inv) = (0, 0, 0, 0);
    for row in &rows {
        let (i, j) = (row.index / ny, row.index % ny);
        let th = row
            .summary
            .as_ref()
            .filter(|_| row.status == "ok")
            .map(|s| s.theta_final)
            .unwrap_or(f64::NAN);
        z[j][i] = th;
        if th.is_finite() {
            let inverted = th > std::f64::consts::FRAC_PI_2;
            let win = (1.0 - ys[j]) < xs[i] && xs[i] < (1.0 + ys[j]);
            if win {
                inside += 1;
                inside_inv += inverted as usize;
            } else {
                outside += 1;
                outside_inv += inverted as usize;
            }
        }
    }
    let failed = rows.iter().filter(|r| r.status != "ok").count();
    let edge =
        |sign: f64| -> (Vec<f64>, Vec<f64>) { ys.iter().map(|&y| (1.0 + sign * y, y)).unzip() };
    let body = format!(
        "The paper's classical top (R = 15 mm, m = 15 g, C = 2/5 m R², μ = 0.1) from the paper's initial state (θ = 0.1, ω = 100 rad/s, no slip velocity of the centre of mass), {} s, with {law} friction{}, over A/C in [0.55, 1.5] and a/R in [0.02, 0.4] ({} cases, {failed} failed). \
         Inside the literature's inversion window 1 − a/R < A/C < 1 + a/R (white lines on the map): {inside_inv} of {inside} tops are inverted (θ > π/2) at the end; outside it: {outside_inv} of {outside}. \
         {}\n",
        10.0 * q,
        if sets.is_empty() {
            " (exact stick/slip)".to_string()
        } else {
            format!(" ({})", sets.join(", "))
        },
        rows.len(),
        if inside_inv == 0 {
            "No top inverts: under this law the tops reach rolling and roll on; the window describes which states are stable, not which are reached from this initial state without sliding dissipation."
        } else {
            "The window predicts which tops can invert; within 10 s the tops near its edges may not have finished."
        }
    );
    let id = format!(
        "inversion_map_{}",
        if sets.is_empty() {
            "exact"
        } else {
            "regularized"
        }
    );
    let lines = vec![edge(-1.0), edge(1.0)];
    Ok((
        MapData {
            id: id.clone(),
            title: format!(
                "Classical tippe top: θ after {} s ({law} friction); white: 1 ∓ a/R",
                10.0 * q
            ),
            x_label: "A/C".into(),
            y_label: "a/R".into(),
            z_label: "θ final [rad]".into(),
            xs,
            ys,
            z,
            lines,
            csv: sweep::csv(&sweep.axes, &rows),
        },
        body + &format!("\n![{id}]({id}.png)\n"),
    ))
}
