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
    // The README's claim: where the reversed contact force fails, a tip
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
