//! The adhesion study of `reproduce --extended` (issue #14 item 4): its
//! verdicts follow from its numbers, and the physics it rests on (a force
//! at a rolling contact point does no work) holds in every model.

use std::f64::consts::FRAC_PI_2;

use tippetop::analysis::regime::max_applied_force;
use tippetop::{ModelKind, Scenario, Trajectory, simulate};
use tippetop_paper::adhesion::{
    self, CASES, Measures, NO_WORK_REL, PAPER_MU, Study, contact_track_length, settings, theta_diff,
};
use tippetop_paper::runs::{self, Runs};
use tippetop_paper::{Options, Verdict};

/// The study with full windows (verdicts meaningful), on the baseline runs
/// of the run table only (the four bilateral nano runs).
fn full_study() -> (Study, Runs) {
    let opts = Options::default();
    let names: Vec<&str> = CASES.iter().map(|c| c.baseline).collect();
    let specs: Vec<_> = runs::specs()
        .into_iter()
        .filter(|s| names.contains(&s.name.as_str()))
        .collect();
    assert_eq!(specs.len(), 4);
    let runs = Runs::execute(&specs, opts, &mut |_| {}).unwrap();
    (adhesion::study(&runs, opts, &mut |_| {}).unwrap(), runs)
}

fn levels(flags: &[bool]) -> Verdict {
    Verdict::from_levels(flags.iter().all(|&f| f), flags.iter().any(|&f| f))
}

fn lies(m: &Measures) -> bool {
    (m.lying_second_half.0 - FRAC_PI_2).abs() <= 0.25
}

fn lies_stably(m: &Measures) -> bool {
    (m.lying_second_half.0 - FRAC_PI_2).abs() <= 0.1 && m.lying_second_half.1 <= 0.15
}

#[test]
fn adhesion_study_verdicts_follow_from_the_numbers() {
    let t0 = std::time::Instant::now();
    let (st, runs) = full_study();
    // The adhesion is the helper's, the nano-adhesive preset's values, and
    // the superlubric μ is the preset's.
    let p = Scenario::nano_adhesive();
    assert!((st.force / p.adhesion().force - 1.0).abs() < 1e-12);
    assert!((st.energy / p.adhesion().energy - 1.0).abs() < 1e-12);
    assert_eq!(settings()[1].mu, p.surface.friction);
    assert_eq!(PAPER_MU, 0.13);
    assert_eq!(st.rows.len(), 16);

    // The physics the verdicts rest on, in every adhesion run: the contact
    // sticks at once and rolls the whole window, the reaction stays F_a to
    // within a few m g (never lifts off), θ never rises above its start,
    // the spin never reverses, and the applied force changes nothing.
    for r in &st.rows {
        let m = &r.m;
        assert_eq!(m.status, "completed", "{}", r.run.name);
        assert!(m.rolling_fraction >= 0.999, "{}", r.run.name);
        assert!(m.stick_at.unwrap() < 1e-18, "{}", r.run.name);
        assert!(
            (m.n_min - st.force).abs() <= 10.0 * st.weight,
            "{}",
            r.run.name
        );
        assert!(m.contact_lost_at.is_none(), "{}", r.run.name);
        assert!(m.theta_max <= 0.1 + 1e-9, "{}", r.run.name);
        assert!(m.first_above_half_pi.is_none() && m.spin_reversed_at.is_none());
        assert!(
            m.work_applied_max_abs <= NO_WORK_REL * m.work_scale,
            "{}",
            r.run.name
        );
        if let Some(d) = m.force_effect {
            assert!(d <= 1e-9, "{}: {d}", r.run.name);
        }
    }
    assert!(st.rolling_no_work);

    // Each verdict recomputed here from the measures with the criterion
    // the report states.
    let ms = |ci: usize| -> Vec<&Measures> { st.case_rows(ci).map(|r| &r.m).collect() };
    let c = &st.claims;
    assert_eq!(c.len(), 6);
    let lie: Vec<bool> = ms(0).iter().map(|m| lies(m)).collect();
    assert_eq!(c[0].verdict, levels(&lie));
    assert_eq!(c[0].holds_without, lies(&st.baseline[0]));
    let rev: Vec<bool> = ms(0).iter().map(|m| m.spin_reversed_at.is_some()).collect();
    assert_eq!(c[1].verdict, levels(&rev));
    let t_rev = 1e-4;
    let stands = |tr: &Trajectory| {
        let before = runs::lying(tr, 0.5 * t_rev, t_rev).0;
        let after = runs::window(tr, t_rev, f64::INFINITY, |s| s.theta).0;
        (before - FRAC_PI_2).abs() <= 0.25 && after < 0.5
    };
    let up: Vec<bool> = st.case_rows(1).map(|r| stands(&r.run.trajectory)).collect();
    assert_eq!(c[2].verdict, levels(&up));
    let ok8 = |tr: &Trajectory, m: &Measures| {
        let mx = runs::window(tr, 8e-6, 2e-5, |s| s.theta).1;
        mx > FRAC_PI_2 && (m.lying_second_half.0 - FRAC_PI_2).abs() <= 0.3
    };
    let p8: Vec<bool> = st
        .case_rows(2)
        .map(|r| ok8(&r.run.trajectory, &r.m))
        .collect();
    assert_eq!(c[3].verdict, levels(&p8));
    let p1: Vec<bool> = ms(3).iter().map(|m| !lies_stably(m)).collect();
    assert_eq!(c[4].verdict, levels(&p1));
    let on: Vec<bool> = st
        .rows
        .iter()
        .map(|r| r.m.contact_lost_at.is_none() && r.m.n_min > 0.0)
        .collect();
    assert_eq!(c[5].verdict, levels(&on));

    // What those numbers give: with adhesion the top neither lies down, nor
    // reverses its spin, nor (never having lain) stands up, nor follows the
    // 8 µs pulse; trivially it does not lie after the 1 µs pulse; it stays on
    // the surface. Without adhesion it lies down and its spin reverses.
    let v: Vec<Verdict> = c.iter().map(|c| c.verdict).collect();
    use Verdict::*;
    assert_eq!(
        v,
        [
            NotReproduced,
            NotReproduced,
            NotReproduced,
            NotReproduced,
            Reproduced,
            Reproduced
        ]
    );
    assert!(c[0].holds_without && c[1].holds_without && c[2].holds_without);
    assert!(c[3].holds_without);
    assert!(c[4].holds_without && !c[5].holds_without);

    // The report section says so.
    let (title, body) = st.section();
    assert!(title.starts_with("Adhesion"));
    assert!(body.contains("**Confirmed.**"));
    assert_eq!(body.matches("| **fails** |").count(), 4);
    assert_eq!(body.matches("| **holds** |").count(), 2);
    for case in CASES {
        assert!(body.contains(&format!("fig{}.png", case.fig)));
    }
    let figs = st.figures(&runs);
    assert_eq!(figs.len(), 5);
    assert!(figs.iter().all(|f| f.curves.len() >= 3));
    let secs = t0.elapsed().as_secs_f64();
    assert!(secs < 10.0, "the study took {secs:.1} s");
}

/// A force at the contact point of a rolling top does no work (its point of
/// application does not move) and, since the rolling motion's equations do
/// not contain it, changes nothing. The nano top with C60/graphene adhesion
/// under the paper's μ = 0.13, H = (0.1, 0.1) zN, 100 µs, every model: it
/// rolls all the window, |W_a| ≤ 1e-12 max|H| L_P (L_P: the length of the
/// contact point's track, over which a sliding point would take up work
/// |H| L_P), and θ equals the run without H to 1e-9 rad. A model that books
/// the work with the centre's velocity, or lets H act on a rolling top,
/// fails: without adhesion the same force does |W_a| of the order of the
/// scale (checked, so the bar is not vacuous).
#[test]
fn applied_force_at_rolling_contact_does_no_work() {
    for model in [ModelKind::Reduced, ModelKind::Vector, ModelKind::Rigid] {
        let mut sc = Scenario::nano_adhesive();
        sc.surface.friction = PAPER_MU;
        sc.solver.model = model;
        let tr = simulate(&sc).unwrap();
        let su = &tr.summary;
        assert_eq!(su.rolling_fraction, 1.0, "{model:?}");
        let scale = max_applied_force(&sc) * contact_track_length(&tr);
        assert!(scale > 1e-33, "{model:?}: {scale}");
        let wa = tr
            .samples
            .iter()
            .map(|s| s.work_applied.abs())
            .fold(0.0, f64::max);
        assert!(
            wa <= NO_WORK_REL * scale,
            "{model:?}: W_a {wa} scale {scale}"
        );
        // Energy: what friction took in the first instant, nothing else.
        let last = tr.samples.last().unwrap();
        let e0 = tr.samples[0].energy;
        assert!((last.energy - e0 - last.work_friction).abs() <= 1e-12 * e0);
        // H changes nothing.
        let mut free = sc.clone();
        free.forcing.windows.clear();
        let tf = simulate(&free).unwrap();
        assert!(theta_diff(&tr, &tf) <= 1e-9, "{model:?}");

        // Without adhesion the same force does work of the order of the scale.
        let mut bare = sc.clone();
        bare.set_adhesion(tippetop::Adhesion::NONE);
        let tb = simulate(&bare).unwrap();
        let wb = tb.samples.last().unwrap().work_applied.abs();
        let scale_b = max_applied_force(&bare) * contact_track_length(&tb);
        assert!(wb > 1e-3 * scale_b, "{model:?}: {wb} vs {scale_b}");
    }
}
