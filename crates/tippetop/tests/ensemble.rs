//! `analysis::ensemble`: Kaplan–Meier medians and confidence intervals on
//! hand-made data with known answers, quantiles from histograms, bins,
//! histogram CSV round trip and merge, run K = the scenario with
//! `thermal.run = K`, validation.

use tippetop::analysis::ensemble::{
    self, Ensemble, Histograms, MeanAcc, StatsAcc, kaplan_meier_median, quantile,
};
use tippetop::{Error, simulate};

const SCENARIO: &str = r#"preset = "nano"
[surface]
friction = 0.0
[solver]
method = "langevin"
dt = 1e-14
t_end = 1e-11
samples = 11
[thermal]
temperature = 300.0
damping_translational = 1e11
damping_rotational = 1e11
seed = 1
"#;

fn ens(runs: usize, sets: &[&str]) -> Result<Ensemble, Error> {
    Ensemble::new(
        None,
        Some(SCENARIO.into()),
        sets.iter().map(|s| s.to_string()).collect(),
        runs,
    )
}

fn key(e: Error) -> String {
    match e {
        Error::Invalid { key, .. } => key,
        other => panic!("not an input error: {other}"),
    }
}

/// Kaplan–Meier by hand. Passages at 1, 3, 5, 6, censored at 2 and 4:
/// S(1) = 5/6, S(3) = 5/6 · 3/4 = 0.625 (4 at risk), S(5) = 0.625 · 1/2 =
/// 0.3125 (2 at risk): the median is 5 (the naive median of the observed
/// passages, 4, ignores the censoring).
#[test]
fn kaplan_meier_median_by_hand() {
    let data = [
        (6.0, true),
        (2.0, false),
        (3.0, true),
        (1.0, true),
        (4.0, false),
        (5.0, true),
    ];
    assert_eq!(kaplan_meier_median(&data), Some(5.0));
    // No censoring: the survival steps 2/3, 1/3: the median is 2.
    assert_eq!(
        kaplan_meier_median(&[(3.0, true), (1.0, true), (2.0, true)]),
        Some(2.0)
    );
    // S reaching exactly 1/2 (3/4, then 1/2 at t = 2): the smallest time
    // with S <= 1/2 is 2.
    let four = [(1.0, true), (2.0, true), (3.0, true), (4.0, true)];
    assert_eq!(kaplan_meier_median(&four), Some(2.0));
    // A run censored at the time of a passage is at risk at that time:
    // censored at 1; at t = 2 one passage among 3 at risk (the run
    // censored at 2 included): S = 2/3; at t = 3 one among 1: S = 0.
    // (Removing the censored run first would give S(2) = 1/2, median 2.)
    let tied = [(2.0, true), (2.0, false), (1.0, false), (3.0, true)];
    assert_eq!(kaplan_meier_median(&tied), Some(3.0));
    // More than half censored before passing: no median.
    let mostly = [(1.0, true), (5.0, false), (5.0, false)];
    assert_eq!(kaplan_meier_median(&mostly), None);
    assert_eq!(kaplan_meier_median(&[]), None);
}

/// 1, 2, 3, 4, 5: mean 3, s² = 10/4, half-width 1.96 sqrt(2.5/5).
#[test]
fn mean_ci_exact_case() {
    let mut a = MeanAcc::default();
    for x in [1.0, 2.0, 3.0, 4.0, 5.0, f64::NAN] {
        a.push(x);
    }
    let r = a.result();
    assert_eq!(r.n, 5);
    assert_eq!(r.mean, Some(3.0));
    assert!((r.std.unwrap() - 2.5f64.sqrt()).abs() < 1e-15);
    let h = 1.96 * 0.5f64.sqrt();
    let [lo, hi] = r.ci95.unwrap();
    assert!((lo - (3.0 - h)).abs() < 1e-14 && (hi - (3.0 + h)).abs() < 1e-14);
    let one = {
        let mut a = MeanAcc::default();
        a.push(7.0);
        a.result()
    };
    assert_eq!((one.mean, one.std, one.ci95), (Some(7.0), None, None));
}

/// splitmix64: uniform numbers on [0, 1), mean 1/2, variance 1/12.
struct Rng(u64);
impl Rng {
    fn uniform(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^= z >> 31;
        (z >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// The 95 % interval covers the known mean 1/2 of uniform samples in about
/// 95 % of 400 batches of 100 (binomial: 380 ± 4.4 sd; a wrong factor,
/// e.g. 1 instead of 1.96 or s instead of s/sqrt(n), is far outside
/// 360..=395), and its half-width is on average 1.96 sqrt(1/12)/10 within
/// 2 % (the relative spread of s is sqrt((κ − 1)/(4n)) = 4.5 % per batch
/// for the uniform's kurtosis κ = 1.8, 0.22 % for the average of 400).
#[test]
fn mean_ci_covers_a_known_mean() {
    let mut rng = Rng(42);
    let mut covered = 0;
    let mut half = 0.0;
    for _ in 0..400 {
        let mut a = MeanAcc::default();
        for _ in 0..100 {
            a.push(rng.uniform());
        }
        let r = a.result();
        let [lo, hi] = r.ci95.unwrap();
        if lo <= 0.5 && 0.5 <= hi {
            covered += 1;
        }
        half += (hi - lo) / 2.0 / 400.0;
    }
    let want = 1.96 * (1.0f64 / 12.0).sqrt() / 10.0;
    assert!((half / want - 1.0).abs() < 0.02, "{half} vs {want}");
    assert!((360..=395).contains(&covered), "{covered} of 400");
}

/// Quantiles of a hand-made histogram: 4 bins of width 1 on [0, 4] with
/// counts 1, 2, 1, 0: the median (rank 2) is 1 + (2 − 1)/2 = 1.5 into bin
/// 1; the 25 % point (rank 1) is the top of bin 0, 1.0; rank 0 is the
/// bottom of the first non-empty bin. Ranks in the under/overflow: unknown.
#[test]
fn quantiles_by_hand() {
    let slots = [0, 1, 2, 1, 0, 0, 5];
    assert_eq!(quantile(&slots, 0.0, 4.0, 0.5), Some(1.5));
    assert_eq!(quantile(&slots, 0.0, 4.0, 0.25), Some(1.0));
    assert_eq!(quantile(&slots, 0.0, 4.0, 0.0), Some(0.0));
    assert_eq!(quantile(&slots, 0.0, 4.0, 1.0), Some(3.0));
    // 1 under, 2 in bin 2 ([2, 3)), 1 over: n = 4.
    let tails = [1, 0, 0, 2, 0, 1, 0];
    assert_eq!(quantile(&tails, 0.0, 4.0, 0.05), None);
    assert_eq!(quantile(&tails, 0.0, 4.0, 0.5), Some(2.5));
    assert_eq!(quantile(&tails, 0.0, 4.0, 0.95), None);
    assert_eq!(quantile(&[0, 0, 0, 0, 0, 0, 3], 0.0, 4.0, 0.5), None);
}

#[test]
fn bins_and_edges() {
    let h = Histograms::new(2, [[0.0, std::f64::consts::PI], [-1.0, 1.0], [0.0, 64.0]]);
    let b = ensemble::BINS;
    assert_eq!(h.slot(0, 0.0), 1);
    assert_eq!(h.slot(0, std::f64::consts::PI), b);
    assert_eq!(h.slot(0, -1e-300), 0);
    assert_eq!(h.slot(0, 4.0), b + 1);
    assert_eq!(h.slot(1, f64::NAN), b + 2);
    // Width 1 on [0, 64]: 10.5 is in bin 10, slot 11.
    assert_eq!(h.slot(2, 10.5), 11);
    assert_eq!(h.slot(2, 10.0), 11);
}

/// Run K is exactly `simulate` of the scenario with `thermal.run = r0 + K`;
/// histograms of two halves merge into those of the whole; the CSV of the
/// histograms parses back to the same counts; the statistics count the
/// rows.
#[test]
fn runs_rows_histograms() {
    let e = ens(4, &["thermal.run=10"]).unwrap();
    let mut whole = e.histograms();
    let mut halves = [e.histograms(), e.histograms()];
    let mut acc = StatsAcc::default();
    let mut csv = ensemble::csv_header();
    let mut rows = Vec::new();
    e.run_streaming(0..4, Some(2), &mut |row| {
        rows.push(row);
        true
    })
    .unwrap();
    for (k, row) in rows.iter().enumerate() {
        assert_eq!((row.index, row.run, row.seed), (k, 10 + k as u64, 1));
        let mut sc = e.scenario.clone();
        sc.thermal.run = 10 + k as u64;
        let traj = simulate(&sc).unwrap();
        let last = traj.samples.last().unwrap().values();
        let finals = row.finals.unwrap();
        for (a, b) in finals.iter().zip(&last) {
            assert!(a == b || (a.is_nan() && b.is_nan()));
        }
        assert_eq!(
            row.first_passage,
            traj.summary.first_time_theta_above_half_pi
        );
        assert_eq!(row.samples.len(), 11);
        whole.add(row);
        halves[k / 2].add(row);
        let line = ensemble::csv_row(row);
        acc.push_line(k + 2, line.trim_end()).unwrap();
        csv.push_str(&line);
    }
    let [mut a, b] = halves;
    a.merge(&b).unwrap();
    assert_eq!(a, whole);
    assert_eq!(Histograms::parse_csv(&whole.csv()).unwrap(), whole);
    // Every slot row sums to the 4 runs.
    for i in 0..11 {
        for q in 0..3 {
            assert_eq!(whole.slots(i, q).iter().sum::<u64>(), 4);
        }
    }
    let stats = acc.finish();
    assert_eq!((stats.runs, stats.ok, stats.failed), (4, 4, 0));
    assert_eq!(stats.theta_final.n, 4);
    let fp = &stats.first_passage;
    assert_eq!(fp.observed + fp.censored, 4);
    assert_eq!(ensemble::EnsembleStats::from_csv(&csv).unwrap(), stats);
    // The prefix of the CSV: all 4 rows, then a torn line is cut.
    let p = e.complete_prefix(0, &csv);
    assert_eq!((p.rows, p.bytes), (4, csv.len()));
    let torn = &csv[..csv.len() - 5];
    assert_eq!(e.complete_prefix(0, torn).rows, 3);
    // Another first run: nothing kept but the header.
    assert_eq!(e.complete_prefix(1, &csv).rows, 0);
    // Issue 26: the row check accepts exactly what csv_row writes for the
    // run (its run and seed), and says why not for each edit.
    let rows: Vec<&str> = csv.lines().skip(1).collect();
    for (k, r) in rows.iter().enumerate() {
        assert_eq!(ensemble::check_row(r, 10 + k as u64, 1), Ok(false), "{r}");
    }
    let r = rows[1];
    let f: Vec<&str> = r.split(',').collect();
    let with = |i: usize, v: &str| {
        let mut g = f.clone();
        g[i] = v;
        g.join(",")
    };
    let censored = 3 + tippetop::trajectory::COLUMNS.len() + 5;
    let empty_ok = {
        let mut g = vec!["11", "1", "ok"];
        g.extend(std::iter::repeat_n("", ensemble::NCOLS - 3));
        g.join(",")
    };
    for (line, why) in [
        (format!("{r},1"), "more fields than the header"),
        (f[..f.len() - 1].join(","), "too few fields"),
        (with(0, "2"), "not the run's run and seed"),
        (with(1, "2"), "not the run's run and seed"),
        (with(4, "x"), "a field that is not a number"),
        (with(censored, "2"), "a field that is not a number"),
        (with(2, ""), "a malformed status"),
        (with(2, "\"ok\""), "a malformed status"),
        (empty_ok, "status ok without results"),
    ] {
        assert_eq!(ensemble::check_row(&line, 11, 1), Err(why), "{line}");
    }
    // A failed run's status, quoted as csv_row writes it.
    assert_eq!(
        ensemble::check_row(&with(2, "\"at t = 1e-12 s: a, b\""), 11, 1),
        Ok(true)
    );
    let p = e.complete_prefix(
        0,
        &format!("{}{},1\n", &csv[..csv.len() - rows[3].len() - 1], rows[3]),
    );
    assert_eq!(
        (p.rows, p.problem),
        (3, Some("more fields than the header"))
    );
}

#[test]
fn validation() {
    assert_eq!(key(ens(0, &[]).unwrap_err()), "--runs");
    assert_eq!(
        key(ens(2, &["thermal.run=4294967295"]).unwrap_err()),
        "--runs"
    );
    assert!(ens(1, &["thermal.run=4294967295"]).is_ok());
    assert_eq!(
        key(ens(2, &["thermal.temperature=0"]).unwrap_err()),
        "thermal.temperature"
    );
    let e = Ensemble::new(Some("nano".into()), None, vec![], 3).unwrap_err();
    assert_eq!(key(e), "solver.method");
    let e = ens(3, &[]).unwrap();
    assert_eq!(
        key(e
            .shard_range(tippetop::analysis::sweep::Shard { k: 4, n: 4 })
            .unwrap_err()),
        "--shard"
    );
}

/// The escape rate's maximum-likelihood estimate with censoring on a
/// hand-made set: 3 passages at 1, 2, 3 s and 2 runs censored at 4 s:
/// `k = 3 / (1 + 2 + 3 + 4 + 4) = 3/14`, `se(ln k) = 1/sqrt 3`.
#[test]
fn escape_rate_by_hand() {
    let r = ensemble::escape_rate(&[
        (1.0, true),
        (2.0, true),
        (3.0, true),
        (4.0, false),
        (4.0, false),
    ])
    .unwrap();
    assert_eq!(r.passages, 3);
    assert_eq!(r.exposure, 14.0);
    assert_eq!(r.rate, 3.0 / 14.0);
    assert_eq!(r.ln_rate_se, 1.0 / 3f64.sqrt());
    assert!(ensemble::escape_rate(&[(4.0, false)]).is_none());
}

/// On exponential passage times (rate k = 2, inverse transform of the
/// counter-based uniforms, seed fixed) censored at 0.7 (a quarter of the
/// runs), the estimate is within 5 standard errors of k; the same data
/// without censoring give the plain `n / Σ t`.
#[test]
fn escape_rate_of_censored_exponentials() {
    let s = tippetop::random::Stream::new(42, 0);
    let k = 2.0;
    let cut = 0.7;
    let entries: Vec<(f64, bool)> = (0..4000)
        .map(|i| {
            let t = -s.uniform(i, 0).ln() / k;
            if t < cut { (t, true) } else { (cut, false) }
        })
        .collect();
    let r = ensemble::escape_rate(&entries).unwrap();
    let z = (r.rate.ln() - k.ln()) / r.ln_rate_se;
    assert!(z.abs() < 5.0, "rate {} vs {k}: {z} SE", r.rate);
    assert!(r.ln_rate_se < 0.03);
    assert!(r.ci95[0] < r.rate && r.rate < r.ci95[1]);
}

/// `--first-passage` specs: parse, hit, canonical form, errors.
#[test]
fn first_passage_specs() {
    use tippetop::trajectory::COLUMNS;
    let e = ensemble::Exit::parse("theta<1.07, theta>2.07").unwrap();
    assert_eq!(e.to_string(), "theta<1.07,theta>2.07");
    let it = COLUMNS.iter().position(|c| *c == "theta").unwrap();
    let mut v = [0.0; 26];
    for (th, hit) in [(1.0, true), (1.5, false), (2.1, true), (1.07, false)] {
        v[it] = th;
        assert_eq!(e.hit(&v), hit, "theta {th}");
    }
    for bad in ["theta", "nope>1", "theta>", "theta<nan", ""] {
        assert_eq!(
            key(ensemble::Exit::parse(bad).unwrap_err()),
            "--first-passage",
            "{bad:?}"
        );
    }
}

/// An ensemble's run skips the per-step J and energy record (session 7,
/// `simulate_for_row`) but its row is the same bits as the row of the full
/// run `simulate` gives for that run alone (what `tippetop run` with
/// `thermal.run = K` replays): status, every final value, θ max and min, N
/// min, the fraction of negative N, the first passage above π/2 and the
/// time reached; vector and rigid models, with the nano preset's adhesion.
#[test]
fn ensemble_row_equals_the_full_run_of_that_run() {
    for sets in [&[][..], &["solver.model=\"rigid\""][..]] {
        let e = ens(3, sets).unwrap();
        for k in 0..3 {
            let row = e.run(k);
            let tr = simulate(&e.scenario_of(k)).unwrap();
            let s = &tr.summary;
            assert_eq!(row.status, s.status);
            let bits = |x: Option<f64>| x.map(f64::to_bits);
            assert_eq!(
                row.finals.map(|f| f.map(f64::to_bits)),
                tr.samples.last().map(|x| x.values().map(f64::to_bits))
            );
            assert_eq!(
                bits(row.theta_max),
                Some(s.theta_max.to_bits()),
                "{sets:?} {k}"
            );
            let min = |f: fn(&tippetop::Sample) -> f64| tr.samples.iter().map(f).reduce(f64::min);
            assert_eq!(bits(row.theta_min), bits(min(|x| x.theta)));
            assert_eq!(bits(row.normal_min), bits(min(|x| x.normal)));
            assert_eq!(
                bits(row.negative_normal_fraction),
                Some(s.negative_normal_fraction.to_bits())
            );
            assert_eq!(
                bits(row.first_passage),
                bits(s.first_time_theta_above_half_pi)
            );
            assert_eq!(bits(row.t_reached), Some(s.t_end.to_bits()));
        }
    }
}

/// With `--first-passage` a run keeps the lean per-step record (θ and the
/// spin at every step, not J and the energy; `Simulation::lean`): its row is
/// the same bits as that of the full record's run to the same exit (the
/// sample-by-sample loop through the public `Simulation`, which is what
/// the ensemble ran before): status, finals, θ max and min, N min, the
/// fraction of negative N, the passage time and the time reached; vector
/// and rigid models, runs that pass and runs that do not.
#[test]
fn first_passage_row_equals_the_full_run_to_its_exit() {
    let spec = "theta>1.2";
    for sets in [&[][..], &["solver.model=\"rigid\""][..]] {
        let exit = ensemble::Exit::parse(spec).unwrap();
        let e = ens(4, sets).unwrap().with_exit(Some(exit.clone()));
        let mut passed = 0;
        for k in 0..4 {
            let row = e.run(k);
            let sc = e.scenario_of(k);
            let mut sim = tippetop::Simulation::new(&sc).unwrap();
            let (n, t_end) = (sc.solver.samples, sc.solver.t_end);
            let mut seen = 0;
            'run: for i in 0..n {
                let t = if i + 1 == n {
                    t_end
                } else {
                    t_end * i as f64 / (n - 1) as f64
                };
                sim.integrate_to(t).unwrap();
                let rows = sim.samples();
                for r in &rows[seen..] {
                    if exit.hit(&r.values()) {
                        break 'run;
                    }
                }
                seen = rows.len();
            }
            let tr = sim.into_trajectory();
            let s = &tr.summary;
            let bits = |x: Option<f64>| x.map(f64::to_bits);
            assert_eq!(row.status, s.status);
            assert_eq!(
                row.finals.map(|f| f.map(f64::to_bits)),
                tr.samples.last().map(|x| x.values().map(f64::to_bits))
            );
            assert_eq!(bits(row.theta_max), Some(s.theta_max.to_bits()));
            let min = |f: fn(&tippetop::Sample) -> f64| tr.samples.iter().map(f).reduce(f64::min);
            assert_eq!(bits(row.theta_min), bits(min(|x| x.theta)));
            assert_eq!(bits(row.normal_min), bits(min(|x| x.normal)));
            assert_eq!(
                bits(row.negative_normal_fraction),
                Some(s.negative_normal_fraction.to_bits())
            );
            let fp = tr
                .samples
                .iter()
                .find(|x| exit.hit(&x.values()))
                .map(|x| x.t);
            assert_eq!(bits(row.first_passage), bits(fp));
            assert_eq!(bits(row.t_reached), Some(s.t_end.to_bits()));
            passed += fp.is_some() as usize;
        }
        assert!(
            0 < passed && passed < 4,
            "{sets:?}: {passed} of 4 passed {spec}"
        );
    }
}
