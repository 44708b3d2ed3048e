//! `tippetop adhesion`: the numbers it prints, its JSON, and bad input.

use assert_cmd::Command;

fn tippetop() -> Command {
    Command::cargo_bin("tippetop").unwrap()
}

fn json(args: &[&str]) -> serde_json::Value {
    let out = tippetop()
        .arg("adhesion")
        .args(args)
        .arg("--json")
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).unwrap()
}

/// The table and the JSON agree with the library (which the library's
/// tests check against quadrature and the published range).
#[test]
fn prints_binding_energy_and_pull_off() {
    let v = json(&[]);
    let lib = tippetop::physics::adhesion::Adhesion::c60_on_graphene()
        .binding()
        .unwrap();
    assert_eq!(v["binding_energy"].as_f64().unwrap(), lib.energy);
    assert_eq!(v["pull_off_force"].as_f64().unwrap(), lib.pull_off_force);
    assert_eq!(v["substrate"], "graphene");
    let text = tippetop().arg("adhesion").output().unwrap();
    let text = String::from_utf8(text.stdout).unwrap();
    assert!(text.contains("binding energy E_b"), "{text}");
    assert!(text.contains("F_a / (m g)"), "{text}");
    // Graphite binds more strongly than one sheet.
    let g = json(&["--substrate", "graphite"]);
    assert!(g["binding_energy"].as_f64().unwrap() > v["binding_energy"].as_f64().unwrap());
    assert_eq!(g["layers"], 30);
}

/// Every option at the edges of f64 and of its range: exit 2 with one line
/// naming the option, or exit 0 with every number finite and positive
/// (never NaN with exit 0, never a panic).
#[test]
fn extreme_options_never_give_nan_or_panic() {
    let values = [
        "0", "-1", "1e-320", "1e-300", "1e-10", "1e-6", "1", "60", "1e8", "1e300", "nan", "inf",
    ];
    for opt in [
        "--radius",
        "--atoms",
        "--lj-a",
        "--lj-b",
        "--mass",
        "--gravity",
    ] {
        for v in values {
            let out = tippetop()
                .args(["adhesion", "--substrate", "graphite", "--json"])
                .arg(format!("{opt}={v}"))
                .output()
                .unwrap();
            let stderr = String::from_utf8_lossy(&out.stderr);
            match out.status.code() {
                Some(0) => {
                    let j: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
                    for key in [
                        "binding_energy",
                        "pull_off_force",
                        "stiffness",
                        "height",
                        "gap",
                    ] {
                        let x = j[key].as_f64();
                        assert!(
                            x.is_some_and(|x| x.is_finite() && x > 0.0),
                            "{opt}={v}: {key} = {:?}",
                            j[key]
                        );
                    }
                }
                Some(2) => {
                    assert_eq!(stderr.lines().count(), 1, "{opt}={v}: {stderr}");
                    assert!(
                        stderr.starts_with(&format!("error: {opt}: ")),
                        "{opt}={v}: {stderr}"
                    );
                }
                c => panic!("{opt}={v}: exit {c:?}: {stderr}"),
            }
            if out.status.code() == Some(0) && opt != "--gravity" {
                let j: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
                let r = j["pull_off_over_weight"].as_f64();
                assert!(
                    r.is_some_and(|r| r.is_finite() && r > 0.0),
                    "{opt}={v}: {r:?}"
                );
            }
        }
    }
}

#[test]
fn layers_out_of_range_is_bad_input() {
    for layers in ["0", "100001"] {
        let out = tippetop()
            .args(["adhesion", "--substrate", "graphite", "--layers", layers])
            .output()
            .unwrap();
        assert_eq!(out.status.code(), Some(2));
        let stderr = String::from_utf8(out.stderr).unwrap();
        assert!(stderr.starts_with("error: --layers: "), "{stderr}");
        assert!(out.stdout.is_empty());
    }
}
