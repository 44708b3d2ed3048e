//! Parameter sweeps: axes, grid order, shards, determinism across thread
//! counts and shard layouts, merge checks, failing cases.

use tippetop::analysis::sweep::{
    Axis, FIELDS, Shard, ShardInfo, Sweep, Table, csv, csv_header, csv_row, merge, shard_range,
};
use tippetop::{Error, Scenario};

/// Cheap classical runs (~50 ms of simulated time, 11 samples).
fn cheap(axes: &[&str]) -> Sweep {
    Sweep {
        preset: Some("classical".into()),
        toml_text: None,
        sets: vec!["solver.t_end=0.05".into(), "solver.samples=11".into()],
        axes: axes.iter().map(|s| Axis::parse(s).unwrap()).collect(),
    }
}

fn key_of(e: Error) -> String {
    match e {
        Error::Invalid { key, .. } => key,
        other => panic!("expected Invalid, got {other:?}"),
    }
}

fn run_csv(s: &Sweep, threads: usize) -> String {
    let rows = s.run(0..s.total(), Some(threads), &|| {}).unwrap();
    csv(&s.axes, &rows)
}

/// Each shard's (info, csv) as a run with `--shard K/N` writes them.
fn shards(s: &Sweep, n: usize) -> Vec<(ShardInfo, String)> {
    (1..=n)
        .map(|k| {
            let sh = Shard { k, n };
            let info = s.shard_info(sh).unwrap();
            let rows = s.run(s.shard_range(sh).unwrap(), Some(1), &|| {}).unwrap();
            (info, csv(&s.axes, &rows))
        })
        .collect()
}

#[test]
fn axis_parse_and_values() {
    let a = Axis::parse("top.offset=0:1:11").unwrap();
    assert_eq!(
        (a.key.as_str(), a.from, a.to, a.n, a.log),
        ("top.offset", 0.0, 1.0, 11, false)
    );
    let v = a.values();
    assert_eq!(v.len(), 11);
    assert_eq!(v[0], 0.0);
    assert_eq!(v[3], 0.3); // (to - from) * i / (n - 1): no 0.30000000000000004
    assert_eq!(v[10], 1.0);
    for (i, x) in v.iter().enumerate() {
        assert!((x - i as f64 / 10.0).abs() < 1e-15);
    }

    let l = Axis::parse(" top.inertia_axial = 1e-44:1e-40:5:log").unwrap();
    assert!(l.log);
    assert_eq!(l.key, "top.inertia_axial");
    let v = l.values();
    assert_eq!((v[0], v[4]), (1e-44, 1e-40)); // ends exact
    for (i, x) in v.iter().enumerate() {
        let want = 1e-44 * 10f64.powi(i as i32);
        assert!((x / want - 1.0).abs() < 1e-14, "{i}: {x} vs {want}");
    }

    // N = 1: FROM only (also with log); decreasing axes are fine.
    assert_eq!(
        Axis::parse("surface.gravity=9.8:100:1").unwrap().values(),
        vec![9.8]
    );
    assert_eq!(Axis::parse("a.b=2:8:1:log").unwrap().values(), vec![2.0]);
    assert_eq!(
        Axis::parse("a.b=1:0:3").unwrap().values(),
        vec![1.0, 0.5, 0.0]
    );

    // spec() round-trips.
    for s in [
        "top.offset=0.001:0.004:4",
        "top.inertia_axial=1e-44:5e-44:5:log",
    ] {
        let a = Axis::parse(s).unwrap();
        assert_eq!(a.spec(), s);
        assert_eq!(Axis::parse(&a.spec()).unwrap(), a);
    }
}

#[test]
fn axis_parse_errors() {
    let cases: &[(&str, &str, &str)] = &[
        ("top.offset", "--vary", "no '='"),
        ("=1:2:3", "--vary", "no key"),
        ("top.offset=1:2", "top.offset", "FROM:TO:N"),
        ("top.offset=1:2:3:4:5", "top.offset", "FROM:TO:N"),
        ("top.offset=1:2:3:lin", "top.offset", "unknown spacing"),
        ("top.offset=x:2:3", "top.offset", "FROM \"x\""),
        ("top.offset=1:inf:3", "top.offset", "TO = inf"),
        ("top.offset=1:NaN:3", "top.offset", "TO = NaN"),
        ("top.offset=1:2:2.5", "top.offset", "not a whole number"),
        ("top.offset=1:2:-1", "top.offset", "not a whole number"),
        ("top.offset=1:2:0", "top.offset", "N = 0"),
        ("top.offset=0:2:3:log", "top.offset", "log spacing"),
        ("top.offset=-1:-2:3:log", "top.offset", "log spacing"),
    ];
    for (spec, key, what) in cases {
        let e = Axis::parse(spec).unwrap_err();
        let msg = e.to_string();
        assert_eq!(key_of(e), *key, "{spec}: {msg}");
        assert!(msg.contains(what), "{spec}: {msg}");
        assert!(!msg.contains('\n') && msg.ends_with(')'), "{msg}");
    }
}

#[test]
fn grid_order_first_axis_slowest() {
    let s = cheap(&["top.offset=1e-3:3e-3:3", "surface.friction=0.1:0.2:2"]);
    assert_eq!(s.total(), 6);
    let got: Vec<(usize, Vec<f64>)> = s.cases().into_iter().map(|c| (c.index, c.values)).collect();
    let want = vec![
        (0, vec![1e-3, 0.1]),
        (1, vec![1e-3, 0.2]),
        (2, vec![2e-3, 0.1]),
        (3, vec![2e-3, 0.2]),
        (4, vec![3e-3, 0.1]),
        (5, vec![3e-3, 0.2]),
    ];
    assert_eq!(got, want);
    // Three axes: the last varies fastest.
    let t = cheap(&[
        "top.offset=1:2:2",
        "top.mass=1:3:3",
        "surface.friction=1:4:4",
    ]);
    assert_eq!(t.total(), 24);
    assert_eq!(t.case(0).values, vec![1.0, 1.0, 1.0]);
    assert_eq!(t.case(1).values, vec![1.0, 1.0, 2.0]);
    assert_eq!(t.case(4).values, vec![1.0, 2.0, 1.0]);
    assert_eq!(t.case(12).values, vec![2.0, 1.0, 1.0]);
    assert_eq!(t.case(23).values, vec![2.0, 3.0, 4.0]);
}

#[test]
fn swept_values_reach_the_scenario_exactly() {
    let s = cheap(&[
        "top.inertia_axial=1e-7:1.3e-6:7:log",
        "initial.spin=3:179.3:5",
        "surface.friction=0.0:0.1:4",
    ]);
    for case in s.cases() {
        let sc: Scenario = s.load_case(&case).unwrap();
        assert_eq!(sc.top.inertia_axial, case.values[0]);
        assert_eq!(sc.initial.spin, case.values[1]);
        assert_eq!(sc.surface.friction, case.values[2]);
        assert_eq!(sc.solver.t_end, 0.05);
    }
}

#[test]
fn shard_ranges_tile() {
    for total in 1..=40 {
        for n in 1..=total {
            let mut cursor = 0;
            let mut sizes = Vec::new();
            for k in 1..=n {
                let r = shard_range(total, Shard { k, n }).unwrap();
                assert_eq!(r.start, cursor, "total {total}, {k}/{n}");
                assert!(r.end > r.start, "total {total}, {k}/{n}: empty");
                sizes.push(r.len());
                cursor = r.end;
            }
            assert_eq!(cursor, total);
            let (lo, hi) = (sizes.iter().min().unwrap(), sizes.iter().max().unwrap());
            assert!(hi - lo <= 1, "total {total}, n {n}: {sizes:?}");
        }
        // More shards than cases: an error (every shard has a case).
        let e = shard_range(total, Shard { k: 1, n: total + 1 }).unwrap_err();
        assert_eq!(key_of(e), "--shard");
    }
    assert_eq!(shard_range(10, Shard { k: 1, n: 3 }).unwrap(), 0..4);
    assert_eq!(shard_range(10, Shard { k: 2, n: 3 }).unwrap(), 4..7);
    assert_eq!(shard_range(10, Shard { k: 3, n: 3 }).unwrap(), 7..10);
    assert_eq!(
        shard_range(1_000_000_000, Shard { k: 7, n: 7 })
            .unwrap()
            .end,
        1_000_000_000
    );

    assert_eq!(Shard::parse("3/8").unwrap(), Shard { k: 3, n: 8 });
    assert_eq!(Shard::parse(" 1 / 1 ").unwrap(), Shard::ALL);
    for bad in ["0/4", "5/4", "1/0", "1", "a/b", "1/2/3", "-1/2", ""] {
        let e = Shard::parse(bad).unwrap_err();
        assert!(e.to_string().starts_with("--shard: "), "{bad}: {e}");
    }
}

#[test]
fn validate_rejects_bad_sweeps_before_running() {
    // Unknown key: named.
    let e = cheap(&["top.colour=1:2:3"]).validate().unwrap_err();
    assert_eq!(key_of(e), "top.colour");
    let e = cheap(&["rotor.speed=1:2:3"]).validate().unwrap_err();
    assert_eq!(key_of(e), "rotor.speed");
    // A key of the wrong type for a number.
    let e = cheap(&["solver.method=1:2:2"]).validate().unwrap_err();
    assert_eq!(key_of(e), "solver.method");
    // Varied twice.
    let e = cheap(&["top.offset=1e-3:2e-3:2", "top.offset=1e-3:2e-3:3"])
        .validate()
        .unwrap_err();
    assert!(e.to_string().contains("varied twice"), "{e}");
    // Too many cases.
    let e = cheap(&["top.offset=1e-3:2e-3:100000", "top.mass=1:2:100000"])
        .validate()
        .unwrap_err();
    assert_eq!(key_of(e), "--vary");
    // No valid case at all: the first case's error.
    let e = cheap(&["top.offset=0.02:0.03:3"]).validate().unwrap_err();
    assert_eq!(key_of(e), "top.offset");
    // A bad base --set.
    let mut s = cheap(&["top.offset=1e-3:2e-3:2"]);
    s.sets.push("surface.friction=-1".into());
    assert_eq!(key_of(s.validate().unwrap_err()), "surface.friction");
    // Some valid cases, even if the first is not: fine.
    cheap(&["top.offset=0.02:0.001:3"]).validate().unwrap();
    cheap(&["top.offset=1e-3:2e-3:2"]).validate().unwrap();
    // Threads = 0.
    assert_eq!(
        key_of(
            cheap(&["top.offset=1e-3:2e-3:2"])
                .run(0..2, Some(0), &|| {})
                .unwrap_err()
        ),
        "--threads"
    );
}

#[test]
fn failing_cases_get_their_error_and_the_sweep_goes_on() {
    // R = 0.015: offsets 0.005, 0.0125 are fine, 0.02 and 0.0275 are not.
    let s = cheap(&["top.offset=0.005:0.0275:4"]);
    s.validate().unwrap();
    let count = std::sync::atomic::AtomicUsize::new(0);
    let rows = s
        .run(0..4, Some(2), &|| {
            count.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
        })
        .unwrap();
    assert_eq!(count.into_inner(), 4);
    assert_eq!(
        rows.iter().map(|r| r.index).collect::<Vec<_>>(),
        vec![0, 1, 2, 3]
    );
    for r in &rows[..2] {
        assert_eq!(r.status, "ok");
        assert!(r.summary.is_some());
    }
    for r in &rows[2..] {
        assert!(r.summary.is_none());
        assert!(r.status.starts_with("top.offset: "), "{}", r.status);
        assert!(r.status.contains("0 <= offset < radius"), "{}", r.status);
    }
    let text = csv(&s.axes, &rows);
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(lines.len(), 5);
    let empties = ",".repeat(FIELDS.len());
    assert!(
        lines[3].starts_with(&format!("0.02{empties}")),
        "{}",
        lines[3]
    );
    let table = Table::parse_csv(&text).unwrap();
    assert_eq!(
        table.status,
        rows.iter().map(|r| r.status.clone()).collect::<Vec<_>>()
    );
    assert!(table.column("theta_final").unwrap()[3].is_nan());
    // Parsed back == built from the rows (NaN != NaN: compare Debug text).
    assert_eq!(
        format!("{table:?}"),
        format!("{:?}", Table::from_rows(&s.axes, &rows))
    );
}

#[test]
fn csv_layout() {
    let s = cheap(&["top.offset=1e-3:2e-3:2", "initial.spin=100:120:2"]);
    assert_eq!(
        csv_header(&s.axes),
        "top.offset,initial.spin,theta_final,theta_max,omega_final,Omega_final,\
         first_time_theta_above_half_pi,contact_lost_at,negative_normal_fraction,\
         rolling_fraction,J_max_rel_drift,energy_final,steps,rhs_evaluations,status\n"
    );
    let rows = s.run(0..1, Some(1), &|| {}).unwrap();
    let line = csv_row(&rows[0]);
    assert!(line.starts_with("0.001,100.0,"), "{line}");
    assert!(line.ends_with(",ok\n"), "{line}");
    let fields: Vec<&str> = line.trim_end().split(',').collect();
    assert_eq!(fields.len(), 2 + FIELDS.len() + 1);
    // Never reaches pi/2 in 50 ms, keeps contact: empty event times.
    assert_eq!((fields[6], fields[7]), ("", ""), "{line}");
    // Floats round-trip; counts are integers.
    let sm = rows[0].summary.as_ref().unwrap();
    assert_eq!(fields[2].parse::<f64>().unwrap(), sm.theta_final);
    assert_eq!(fields[12], sm.steps.to_string());

    // Status escaping, NaN, one line per case.
    let mut r = rows[0].clone();
    r.status = "at t = 1e-3 s: bad, \"very\"\nbad".into();
    r.summary.as_mut().unwrap().theta_final = f64::NAN;
    let line = csv_row(&r);
    assert!(
        line.ends_with(",\"at t = 1e-3 s: bad, \"\"very\"\" bad\"\n"),
        "{line}"
    );
    assert!(line.contains(",NaN,"), "{line}");
    assert_eq!(line.matches('\n').count(), 1);
    let t = Table::parse_csv(&(csv_header(&s.axes) + &line)).unwrap();
    assert_eq!(t.status[0], "at t = 1e-3 s: bad, \"very\" bad");
    assert!(t.column("theta_final").unwrap()[0].is_nan());
    assert_eq!(t.column("initial.spin").unwrap(), vec![100.0]);
    assert!(t.column("nonsense").is_none());
}

#[test]
fn threads_and_shards_give_identical_bytes() {
    // 3 x 4 = 12 cases, one of them failing (offset >= radius).
    // Long enough (0.5 s) for stick/slip switches to matter.
    let mut s = cheap(&["top.offset=0.001:0.015:3", "initial.spin=60:150:4"]);
    s.sets[0] = "solver.t_end=0.5".into();
    s.validate().unwrap();
    let one = run_csv(&s, 1);
    let two = run_csv(&s, 2);
    assert_eq!(one, two, "1 vs 2 threads");
    assert_eq!(one.lines().count(), 13);
    assert_eq!(one.matches(",ok\n").count(), 8);

    let parts = shards(&s, 4);
    assert_eq!(merge(&parts).unwrap(), one, "4 shards merged vs one-shot");
    // Any argument order.
    let mut rev = parts.clone();
    rev.reverse();
    rev.swap(0, 2);
    assert_eq!(merge(&rev).unwrap(), one);
    // A mix of layouts: 1/2 and 3/4 + 4/4 (cases 0..6 and 6..9, 9..12).
    let halves = shards(&s, 2);
    let mix = vec![halves[0].clone(), parts[2].clone(), parts[3].clone()];
    assert_eq!(merge(&mix).unwrap(), one);
    // The one-shot output is itself a mergeable shard 1/1.
    let all = (s.shard_info(Shard::ALL).unwrap(), one.clone());
    assert_eq!(
        (all.0.first_index, all.0.end_index, all.0.total_cases),
        (0, 12, 12)
    );
    assert_eq!(merge(&[all]).unwrap(), one);

    // The nano preset too (applied force, 2 us).
    let nano = Sweep {
        preset: Some("nano".into()),
        toml_text: None,
        sets: vec!["solver.t_end=2e-6".into(), "solver.samples=11".into()],
        axes: vec![Axis::parse("force.0.hx=1e-23:1e-21:5:log").unwrap()],
    };
    let one_nano = run_csv(&nano, 1);
    assert_eq!(one_nano, run_csv(&nano, 2));
    assert_eq!(merge(&shards(&nano, 3)).unwrap(), one_nano);
    assert_eq!(one_nano.matches(",ok\n").count(), 5, "{one_nano}");

    // 2D columns for a heat map.
    let t = Table::parse_csv(&one).unwrap();
    let (xs, ys, z) = t.grid2("theta_final").unwrap();
    assert_eq!(xs, vec![0.001, 0.008, 0.015]);
    assert_eq!(ys, vec![60.0, 90.0, 120.0, 150.0]);
    assert_eq!(z.len(), 3);
    assert!(z[2].iter().all(|v| v.is_nan()));
    assert!(z[0].iter().all(|v| v.is_finite()));
}

#[test]
fn merge_rejects_incomplete_overlapping_and_foreign_shards() {
    let s = cheap(&["top.offset=0.001:0.004:8"]);
    let parts = shards(&s, 4);
    let msg = |r: Result<String, Error>| {
        let e = r.unwrap_err();
        let m = e.to_string();
        assert_eq!(key_of(e), "merge");
        assert!(!m.contains('\n'));
        m
    };
    // Missing shard (middle, last, first).
    let m = msg(merge(&[
        parts[0].clone(),
        parts[1].clone(),
        parts[3].clone(),
    ]));
    assert!(m.contains("cases 4..6 of 8 are missing"), "{m}");
    let m = msg(merge(&parts[..3]));
    assert!(m.contains("cases 6..8 of 8 are missing"), "{m}");
    let m = msg(merge(&parts[1..]));
    assert!(m.contains("cases 0..2 of 8 are missing"), "{m}");
    assert!(msg(merge(&[])).contains("no shards"));
    // Overlap: a shard twice, or layouts that overlap.
    let mut dup = parts.clone();
    dup.push(parts[1].clone());
    assert!(msg(merge(&dup)).contains("overlaps"));
    let thirds = shards(&s, 3); // 0..3, 3..6, 6..8
    let m = msg(merge(&[
        parts[0].clone(),
        thirds[0].clone(),
        thirds[1].clone(),
        thirds[2].clone(),
    ]));
    assert!(m.contains("overlaps"), "{m}");
    // Another sweep: different --set, same grid.
    let mut other = s.clone();
    other.sets.push("surface.friction=0.2".into());
    let foreign = shards(&other, 4);
    let m = msg(merge(&[
        parts[0].clone(),
        parts[1].clone(),
        foreign[2].clone(),
        parts[3].clone(),
    ]));
    assert!(m.contains("another sweep"), "{m}");
    // Tampered CSV: wrong row count, wrong grid values, wrong header.
    let mut short = parts.clone();
    short[1].1 = short[1]
        .1
        .lines()
        .take(2)
        .map(|l| format!("{l}\n"))
        .collect();
    assert!(msg(merge(&short)).contains("has 1 rows, not 2"));
    let mut swapped = parts.clone();
    swapped[1].1 = parts[2].1.clone();
    assert!(msg(merge(&swapped)).contains("is not case 2"));
    let mut header = parts.clone();
    header[0].1 = header[0].1.replacen("top.offset", "top.mass", 1);
    assert!(msg(merge(&header)).contains("header"));
}

#[test]
fn fingerprint_is_stable_and_specific() {
    let s = cheap(&["top.offset=0.001:0.004:8"]);
    let f = s.fingerprint();
    assert_eq!(f.len(), 16);
    assert!(f.bytes().all(|b| b.is_ascii_hexdigit()));
    assert_eq!(f, s.clone().fingerprint());
    let mut t = s.clone();
    t.axes[0].n = 9;
    assert_ne!(t.fingerprint(), f);
    let mut t = s.clone();
    t.toml_text = Some(String::new());
    assert_ne!(t.fingerprint(), f);
    let mut t = s.clone();
    t.preset = Some("nano".into());
    assert_ne!(t.fingerprint(), f);
    let mut t = s.clone();
    t.sets.swap(0, 1);
    assert_ne!(t.fingerprint(), f);
}

/// Defect 9 of issue 12: the rows of a streamed sweep arrive in grid order,
/// the same bytes for any thread count (and as `run`), and a sink that stops
/// gets no further row.
#[test]
fn streamed_rows_come_in_grid_order_for_any_thread_count() {
    // Offsets past R = 0.015 are invalid cases: fast, mixed with real runs.
    let s = cheap(&["top.offset=0.001:0.03:7", "initial.spin=60:150:6"]);
    s.validate().unwrap();
    let want = run_csv(&s, 1);
    for threads in [1, 2, 3, 7] {
        let mut text = csv_header(&s.axes);
        let mut next = 0;
        let done = s
            .run_streaming(0..s.total(), Some(threads), &mut |row| {
                assert_eq!(row.index, next, "{threads} threads");
                next += 1;
                text.push_str(&csv_row(&row));
                true
            })
            .unwrap();
        assert!(done);
        assert_eq!(text, want, "{threads} threads");
    }
    // A part of the grid, and a sink that stops after 5 rows.
    let mut got = Vec::new();
    let done = s
        .run_streaming(10..30, Some(3), &mut |row| {
            got.push(row.index);
            got.len() < 5
        })
        .unwrap();
    assert!(!done);
    assert_eq!(got, [10, 11, 12, 13, 14]);
}

/// Defect 9 of issue 12: `--threads 20000` used to start 20 000 threads (for
/// minutes); the count is now bounded by MAX_THREADS = 1024.
#[test]
fn thread_count_is_bounded() {
    use tippetop::analysis::sweep::{MAX_THREADS, threads};
    assert_eq!(MAX_THREADS, 1024);
    assert_eq!(threads(Some(1)).unwrap(), 1);
    assert_eq!(threads(Some(1024)).unwrap(), 1024);
    let t = threads(None).unwrap();
    assert!((1..=MAX_THREADS).contains(&t));
    for bad in [0, 1025, 20_000, usize::MAX] {
        let e = threads(Some(bad)).unwrap_err();
        assert!(e.to_string().contains("(1 to 1024"), "{e}");
        assert_eq!(key_of(e), "--threads");
    }
    let s = cheap(&["top.offset=1e-3:2e-3:2"]);
    assert_eq!(
        key_of(s.run(0..2, Some(20_000), &|| {}).unwrap_err()),
        "--threads"
    );
}

/// What `--resume` keeps of an interrupted sweep.csv: the header and the
/// complete rows of the right cases, never a torn last line.
#[test]
fn complete_prefix_of_an_interrupted_csv() {
    let s = cheap(&["top.offset=0.001:0.03:5"]);
    let full = run_csv(&s, 2);
    let header = csv_header(&s.axes);
    let ends: Vec<usize> = full.match_indices('\n').map(|(i, _)| i + 1).collect(); // ends[0]: header, ends[k]: k rows
    let failed_in = |rows: usize| {
        full[header.len()..ends[rows]]
            .lines()
            .filter(|l| !l.ends_with(",ok"))
            .count()
    };
    for cut in 0..=full.len() {
        let p = s.complete_prefix(0, &full[..cut]);
        let rows = ends.iter().filter(|&&e| e <= cut).count().saturating_sub(1);
        if cut < header.len() {
            assert_eq!((p.rows, p.bytes), (0, 0), "cut {cut}");
        } else {
            assert_eq!((p.rows, p.bytes), (rows, ends[rows]), "cut {cut}");
            assert_eq!(p.failed, failed_in(rows), "cut {cut}");
        }
    }
    assert!(s.complete_prefix(0, &full).failed > 0, "some invalid cases");
    // A shard's rows start at its first case: the same text read as cases
    // from 1 on does not match.
    assert_eq!(s.complete_prefix(1, &full).rows, 0);
    // Another sweep's header: nothing kept.
    let other = cheap(&["top.mass=0.01:0.02:5"]);
    assert_eq!(other.complete_prefix(0, &full).bytes, 0);
    // A row that is not the next case ends what is kept.
    let mut swapped = full[..ends[1]].to_string();
    swapped.push_str(&full[ends[2]..ends[3]]);
    assert_eq!(s.complete_prefix(0, &swapped).rows, 1);
}

#[test]
fn axis_of_given_values() {
    let a = Axis::of_values("top.offset", vec![2e-3, 1e-3, 0.1 + 0.2]).unwrap();
    assert_eq!(a.values(), vec![2e-3, 1e-3, 0.1 + 0.2]);
    assert_eq!((a.from, a.to, a.n, a.log), (2e-3, 0.1 + 0.2, 3, false));
    assert_eq!(a.spec(), "top.offset=[0.002, 0.001, 0.30000000000000004]");
    // A --vary axis serializes as before (no `given` key, so shard.json is
    // unchanged); a given axis round-trips.
    let p = Axis::parse("top.offset=0.001:0.004:4").unwrap();
    assert!(!toml::to_string(&p).unwrap().contains("given"));
    let text = toml::to_string(&a).unwrap();
    assert_eq!(toml::from_str::<Axis>(&text).unwrap(), a);

    // A given axis in a grid: the same rows as the --vary axis of the same values.
    let mut given = cheap(&["surface.friction=0.1:0.2:2"]);
    given.axes.insert(
        0,
        Axis::of_values(
            "top.offset",
            Axis::parse("top.offset=1e-3:3e-3:3").unwrap().values(),
        )
        .unwrap(),
    );
    let vary = cheap(&["top.offset=1e-3:3e-3:3", "surface.friction=0.1:0.2:2"]);
    given.validate().unwrap();
    assert_eq!(run_csv(&given, 2), run_csv(&vary, 1));

    for (values, what) in [
        (vec![], "no values"),
        (vec![1e-3, f64::NAN], "value 1 = NaN"),
        (vec![f64::INFINITY], "value 0 = inf"),
    ] {
        let e = Axis::of_values("top.offset", values).unwrap_err();
        let msg = e.to_string();
        assert_eq!(key_of(e), "top.offset", "{msg}");
        assert!(msg.contains(what), "{msg}");
    }
    // A hand-made axis whose bounds disagree with its values.
    let mut bad = a.clone();
    bad.n = 2;
    assert_eq!(key_of(bad.check().unwrap_err()), "top.offset");
}

/// Issue 26: `--resume` and `merge` kept rows with an extra field (an
/// unquoted status swallowed it: a malformed sweep.csv), a non-number, or
/// an `ok` without results. `Sweep::check_line` accepts exactly the lines
/// `csv_row` writes for the case: every row of a run (quoted statuses
/// included), and refuses each such edit, saying why; `complete_prefix`
/// stops there and `merge` names the line.
#[test]
fn row_checks_refuse_what_csv_row_never_writes() {
    let s = cheap(&["top.offset=0.001:0.03:5"]);
    let full = run_csv(&s, 2);
    let ncols = 1 + FIELDS.len() + 1;
    let rows: Vec<&str> = full.lines().skip(1).collect();
    for (i, r) in rows.iter().enumerate() {
        assert_eq!(s.check_line(i, r, ncols), Ok(!r.ends_with(",ok")), "{r}");
    }
    let ok_row = rows.iter().position(|r| r.ends_with(",ok")).unwrap();
    let bad_row = rows.iter().position(|r| !r.ends_with(",ok")).unwrap();
    // A status with a comma and a quote, as csv_row writes it.
    let (head, _) = rows[bad_row].rsplit_once(',').unwrap();
    let quoted = format!("{head},\"at t = 1 s: \"\"a\"\", b\"");
    assert_eq!(s.check_line(bad_row, &quoted, ncols), Ok(true));
    let r = rows[ok_row];
    let fields: Vec<&str> = r.split(',').collect();
    let with = |i: usize, v: &str| {
        let mut f = fields.clone();
        f[i] = v;
        f.join(",")
    };
    let empty_ok = {
        let mut f: Vec<&str> = vec![fields[0]];
        f.extend(std::iter::repeat_n("", FIELDS.len()));
        f.push("ok");
        f.join(",")
    };
    for (line, why) in [
        (format!("{r},1"), "more fields than the header"),
        (
            format!("{},x", rows[bad_row]),
            "more fields than the header",
        ),
        (fields[..fields.len() - 1].join(","), "too few fields"),
        (with(2, "1.0.0"), "a field that is not a number"),
        (with(1, "theta"), "a field that is not a number"),
        (with(0, "0.0015"), "not the case's grid values"),
        (with(fields.len() - 1, "o\"k"), "a malformed status"),
        (with(fields.len() - 1, ""), "a malformed status"),
        (with(fields.len() - 1, "\"ok"), "a malformed status"),
        (empty_ok, "status ok without results"),
    ] {
        assert_eq!(s.check_line(ok_row, &line, ncols), Err(why), "{line}");
        // As the next row of a partial file: kept up to it, and why not.
        let mut text = full
            .split_inclusive('\n')
            .take(ok_row + 1)
            .collect::<String>();
        text.push_str(&line);
        text.push('\n');
        let p = s.complete_prefix(0, &text);
        assert_eq!((p.rows, p.problem), (ok_row, Some(why)), "{line}");
    }
    // A value edited into another number (or NaN) is still a row: only
    // the checkpoints and checksums beside the file catch it.
    assert_eq!(s.check_line(ok_row, &with(2, "NaN"), ncols), Ok(false));
    assert_eq!(
        s.check_line(rows.len(), r, ncols),
        Err("past the last case")
    );

    // merge: a shard with an extra field, and one cut at its last line end.
    let mut parts = shards(&s, 2);
    let row = parts[1].1.lines().nth(1).unwrap().to_string();
    parts[1].1 = parts[1].1.replace(&row, &format!("{row},1"));
    let m = merge(&parts).unwrap_err().to_string();
    assert!(
        m.contains("line 2 of sweep.csv is not case 3 (more fields than the header)"),
        "{m}"
    );
    let mut parts = shards(&s, 2);
    parts[1].1.pop();
    let m = merge(&parts).unwrap_err().to_string();
    assert!(
        m.contains("sweep.csv ends in the middle of its last row (line 3, no line end)"),
        "{m}"
    );
    assert!(!m.contains("has 2 rows, not 2"), "{m}");
}
