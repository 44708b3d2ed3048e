//! `tippetop device` end to end (issue #16 item 6): the report is written,
//! its deterministic figures are those of `tippetop bit` on the same bit
//! (the paper's write on the nano top), its tallies and intervals are
//! consistent, the 10-year temperature solves its own equation, and bad
//! input exits 2 with one line and nothing written.

mod common;
use common::{bin, json, repo};

fn scratch(name: &str) -> std::path::PathBuf {
    common::scratch("device-cli", name)
}

#[test]
fn device_report_is_consistent() {
    let d = scratch("quick");
    let o = bin()
        .args(["device", "--quick", "--quiet", "--out"])
        .arg(d.join("dev"))
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let r = json(&d.join("dev/device.json"));
    let md = std::fs::read_to_string(d.join("dev/device.md")).unwrap();
    assert!(md.contains("## Answer"), "{md}");
    // One number format for people: no machine-precision numbers, no
    // `1e300`/`inf` stand-ins (a 4 K retention beyond f64 reads "beyond any
    // time scale"), in the report and on the console.
    let console = format!(
        "{}{}",
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    );
    for (name, text) in [("device.md", &md), ("the console", &console)] {
        let long = common::long_numbers(text, 10);
        assert!(long.is_empty(), "long numbers in {name}: {long:?}");
        let sent = common::sentinels(text);
        assert!(sent.is_empty(), "sentinels in {name}: {sent:?}");
    }
    // The answer leads with a table (each state's retention with its
    // interval and what limits it, the writes' error rates, the design),
    // then words in short paragraphs.
    let answer = md.split("## Answer\n\n").nth(1).unwrap();
    let answer = answer.split("\n## ").next().unwrap();
    let blocks: Vec<&str> = answer.split("\n\n").collect();
    assert!(blocks[0].starts_with("**"), "{answer}");
    assert!(
        blocks[1].starts_with("| | retention or error rate (95 %) | what limits it |"),
        "no table after the verdict:\n{answer}"
    );
    for row in [
        "| state 0 (standing), 300 K | ",
        "| state 1 (lying), 300 K | ",
        "| state 1 (lying), 4 K | beyond any time scale",
        "| the paper's write, 300 K, 500.0 ps phase | write error rate ",
        "| the design at 300 K: a ",
        "| the design's write, 300 K | ",
    ] {
        assert!(blocks[1].contains(row), "no row {row:?}:\n{}", blocks[1]);
    }
    for words in &blocks[2..] {
        let n = words.split_whitespace().count();
        assert!(n <= 150, "a paragraph of {n} words: {words}");
    }
    assert!(!md.contains("(the paper's model), over the phase"), "{md}");
    // The paper's write on the paper's model: the same bit as
    // scenarios/bit/nano.toml, so the same switching time, bit for bit.
    let o = bin()
        .arg("bit")
        .arg(repo("scenarios/bit/nano.toml"))
        .args(["--quiet", "--out"])
        .arg(d.join("bit"))
        .output()
        .unwrap();
    assert!(o.status.success());
    let b = json(&d.join("bit/bit.json"));
    let nano = &r["deterministic"][0];
    assert_eq!(nano["preset"], "nano");
    assert_eq!(nano["write"]["successes"], b["write"]["successes"]);
    assert_eq!(nano["write"]["time_median"], b["write"]["time_median"]);
    assert_eq!(nano["erase"]["successes"], b["erase"]["successes"]);
    // The tip searches run for the paper's model only.
    for k in ["tip_write", "tip_erase"] {
        assert!(nano[k].is_object(), "{k}: {}", nano[k]);
        let rb = &nano[k]["robustness"];
        assert!(rb[0].as_u64().unwrap() <= rb[1].as_u64().unwrap());
        assert!(r["deterministic"][1][k].is_null(), "{k}");
    }
    // The user guide's claim (docs/guide.md): where the reversed contact force fails, a tip
    // push at the top erases (found within the --quick budget of 180 runs).
    assert_eq!(nano["erase"]["successes"], 0);
    assert_eq!(nano["tip_erase"]["found"], true, "{}", nano["tip_erase"]);
    // Tallies: successes <= runs, the interval holds the estimate.
    let check = |t: &serde_json::Value| {
        let (s, n) = (
            t["successes"].as_u64().unwrap(),
            t["runs"].as_u64().unwrap(),
        );
        assert!(s <= n && n > 0, "{t}");
        let p = s as f64 / n as f64;
        let (lo, hi) = (
            t["ci95"][0].as_f64().unwrap(),
            t["ci95"][1].as_f64().unwrap(),
        );
        assert!(lo <= p + 1e-15 && p <= hi + 1e-15, "{t}");
    };
    let temps: Vec<f64> = r["thermal"]
        .as_array()
        .unwrap()
        .iter()
        .map(|t| t["temperature"].as_f64().unwrap())
        .collect();
    assert_eq!(temps, [4.0, 77.0, 300.0]);
    for t in r["thermal"].as_array().unwrap() {
        for k in ["write", "erase", "write_without_force"] {
            check(&t[k]);
        }
        assert_eq!(t["write"]["runs"], 8);
    }
    // The 10-year temperature solves ln ν − E/(k_B T) = −ln(10 yr).
    let rt = &r["retention"];
    if let (Some(fit), Some(tt)) = (rt["fit"].as_object(), rt["t_ten_years"].as_array()) {
        let t = tt[0].as_f64().unwrap();
        let ln_nu = fit["ln_prefactor"].as_f64().unwrap();
        let e = fit["barrier"].as_f64().unwrap();
        let k = (ln_nu - e / (1.380649e-23 * t)).exp();
        let ten_years = 10.0 * 365.25 * 86400.0;
        assert!(
            (1.0 / k / ten_years - 1.0).abs() < 1e-9,
            "T {t}: 1/k = {}",
            1.0 / k
        );
        let ends = tt[1].as_array().unwrap();
        let (lo, hi) = (ends[0].as_f64().unwrap(), ends[1].as_f64().unwrap());
        assert!(lo < t && t < hi, "{tt:?}");
    }
    // The potential's barrier: 1.1 eV × (1 − exp(−(0.35/0.3)²/2)).
    let depth = 1.7623942974e-19;
    let want = depth * (1.0 - (-(0.35f64 / 0.3).powi(2) / 2.0).exp());
    let got = rt["barrier_potential"].as_f64().unwrap();
    assert!((got / want - 1.0).abs() < 1e-9, "{got} vs {want}");
    // The rare events (issue 27). The lying state at 4, 77, 300 K: the
    // same closed-form barrier; at 4 K beyond reach (1 575 kT), said so;
    // at 300 K measured; TST's bound and the overdamped twin's value fall
    // with T (and the twin is the faster: no inertia).
    let rare = &r["rare"];
    let lying = rare["lying"].as_array().unwrap();
    assert_eq!(lying.len(), 3);
    let mut last = f64::INFINITY;
    for l in lying {
        let t = l["temperature"].as_f64().unwrap();
        let b = l["barrier"].as_f64().unwrap();
        assert!((b / want - 1.0).abs() < 1e-9, "{b}");
        let kt = l["barrier_kt"].as_f64().unwrap();
        assert!((kt / (want / (1.380649e-23 * t)) - 1.0).abs() < 1e-9);
        let tst = l["tst"]["log10_seconds"].as_f64().unwrap();
        let od = l["overdamped_exact"]["log10_seconds"].as_f64().unwrap();
        assert!(tst < last && od < tst, "{l}");
        last = tst;
        match t as u32 {
            4 => {
                assert!(l["ams"].is_null());
                assert_eq!(l["not_measured"], "beyond_reach");
                assert!(l["tst"]["seconds"].is_null());
            }
            77 => assert_eq!(l["not_measured"], "not_asked", "--quick: {l}"),
            _ => {
                let m = &l["ams"];
                let (e, lo, hi) = (
                    m["estimate"].as_f64().unwrap(),
                    m["ci95"][0].as_f64().unwrap(),
                    m["ci95"][1].as_f64().unwrap(),
                );
                assert!(lo <= e && e <= hi, "{m}");
                // TST bounds the residence from below: the interval reaches it.
                assert!(hi >= 10f64.powf(tst), "{m} vs TST 1e{tst}");
            }
        }
    }
    assert!(md.contains("beyond any sampler's reach"), "{md}");
    assert!(!md.contains("inf yr") && !md.contains("NaN"), "{md}");
    // Writes: the error rate is P_late + P_hold, P_hold = 1 − exp(−h/τ).
    let tau = lying[2]["ams"]["estimate"].as_f64().unwrap();
    for w in rare["writes"].as_array().unwrap() {
        let (late, hold, rate) = (
            w["late"]["estimate"].as_f64().unwrap(),
            w["hold_escape"].as_f64().unwrap(),
            w["rate"].as_f64().unwrap(),
        );
        assert!((hold / -(-1e-10 / tau).exp_m1() - 1.0).abs() < 1e-12, "{w}");
        assert_eq!(rate, late + hold);
    }
    // The design: deeper for 300 K than for 77 K (about T's ratio).
    let d = rare["designs"].as_array().unwrap();
    let (d300, d77) = (
        d[0]["depth"].as_f64().unwrap(),
        d[1]["depth"].as_f64().unwrap(),
    );
    assert!(d300 / d77 > 3.5 && d300 / d77 < 4.3, "{d300} / {d77}");
    let dw = &rare["design_write"];
    assert_eq!(dw["force"], 0.0);
    // Every way the bit is lost: desorption at 77 K and 300 K, its rate
    // within its interval and below TST (an upper bound), the lifetime
    // 1/(k_escape + k_desorption), below both residences.
    let losses = rare["losses"].as_array().unwrap();
    assert_eq!(losses.len(), 2);
    for (l, t) in losses.iter().zip([77.0, 300.0]) {
        assert_eq!(l["temperature"], t);
        let k = l["desorption_rate"].as_f64().unwrap();
        let ci = &l["desorption_ci95"];
        let (lo, hi) = (ci[0].as_f64().unwrap(), ci[1].as_f64().unwrap());
        assert!(0.0 < lo && lo <= k && k <= hi, "{l}");
        let d = &l["desorption"];
        let tst = d["tst_rate"].as_f64().unwrap();
        assert!(hi <= tst, "{l}");
        assert_eq!(d["dt_converged"], true, "{l}");
        let ln_life = l["lifetime"]["log10_seconds"].as_f64().unwrap() * std::f64::consts::LN_10;
        let (a, b) = (
            l["ln_escape_rate"].as_f64().unwrap(),
            d["ln_rate"].as_f64().unwrap(),
        );
        let sum = a.max(b) + (-(a - b).abs()).exp().ln_1p();
        assert!((ln_life + sum).abs() < 1e-9, "{l}");
        assert!(-ln_life < a.max(b) + std::f64::consts::LN_2);
        assert_eq!(
            l["limited_by"],
            if a >= b { "orientation" } else { "desorption" }
        );
    }
    // The 300 K desorption's residence (seconds: a 0.73 eV binding) is far
    // longer than the lying state's (milliseconds): the orientation limits.
    assert_eq!(losses[1]["limited_by"], "orientation");
    assert!(md.contains("## Every way the bit is lost"), "{md}");
    // The design's binding for the molecule: above today's 0.73 eV at 300 K
    // (a 10-year stay needs ~kT ln(ν τ) ≈ 1.2 eV), below it at 77 K.
    let ev = 1.602176634e-19;
    let (b300, b77) = (
        d[0]["binding"].as_f64().unwrap() / ev,
        d[1]["binding"].as_f64().unwrap() / ev,
    );
    assert!(b300 > 1.1 && b300 < 1.4 && b77 < 0.73, "{b300} {b77}");
}

#[test]
fn device_bad_input_names_the_key() {
    let d = scratch("bad");
    for (args, key) in [
        (&["--runs", "1"][..], "--runs"),
        (&["--budget", "0"][..], "--budget"),
        (&["--retention-runs", "100000"][..], "--retention-runs"),
        (&["--threads", "0"][..], "--threads"),
    ] {
        let out = d.join("out");
        let o = bin()
            .arg("device")
            .args(args)
            .arg("--out")
            .arg(&out)
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{key}: {err}");
        assert_eq!(err.lines().count(), 1, "{err}");
        assert!(err.starts_with(&format!("error: {key}")), "{key}: {err}");
        assert!(!out.exists());
    }
}
