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

/// `--substrate nanotube`: the JSON has the graphene case's fields plus
/// `offset` and `on_axis`, equal to the library's (which tests/nanotube.rs
/// checks against quadrature), for a radius and for a chirality; the
/// (10,10) tube holds the cage on its axis (offset 0, gap b − R, no
/// pull-off), a wide tube against its wall.
#[test]
fn nanotube_on_and_off_the_axis() {
    use tippetop::physics::nanotube::{Nanotube, chirality_radius};
    let graphene = json(&[]);
    let v = json(&["--substrate", "nanotube", "--tube-radius", "6.78e-10"]);
    for key in graphene.as_object().unwrap().keys() {
        assert!(v.get(key).is_some(), "missing {key}");
    }
    let lib = Nanotube::c60_in(6.78e-10).binding().unwrap();
    assert_eq!(v["substrate"], "nanotube");
    assert_eq!(v["on_axis"], true);
    assert_eq!(v["offset"].as_f64(), Some(0.0));
    assert_eq!(v["binding_energy"].as_f64().unwrap(), lib.energy);
    assert_eq!(v["gap"].as_f64().unwrap(), 6.78e-10 - 3.55e-10);
    assert!(v["pull_off_force"].is_null());
    let c = json(&["--substrate", "nanotube", "--chirality", "10,10"]);
    assert_eq!(c["tube_radius"].as_f64().unwrap(), chirality_radius(10, 10));
    assert_eq!(c["chirality"], serde_json::json!([10, 10]));
    // (20,20), b = 13.56 Å: against the wall, at about the sheet's gap.
    let w = json(&["--substrate", "nanotube", "--chirality", "20,20"]);
    let lib = Nanotube::c60_in(chirality_radius(20, 20))
        .binding()
        .unwrap();
    assert_eq!(w["on_axis"], false);
    assert_eq!(w["offset"].as_f64().unwrap(), lib.offset);
    let gap = w["gap"].as_f64().unwrap();
    assert!((2.5e-10..3.5e-10).contains(&gap), "{gap}");
    assert!(
        (w["offset"].as_f64().unwrap() + gap + 3.55e-10 - chirality_radius(20, 20)).abs() < 1e-22
    );
    assert!(w["pull_off_force"].as_f64().unwrap() > 0.0);
    let text = tippetop()
        .args([
            "adhesion",
            "--substrate",
            "nanotube",
            "--chirality",
            "10,10",
        ])
        .output()
        .unwrap();
    let text = String::from_utf8(text.stdout).unwrap();
    assert!(text.contains("on the axis"), "{text}");
    assert!(text.contains("touches nothing"), "{text}");
    assert!(text.contains("3.247 eV"), "{text}");
}

/// Bad tube input: one line naming the option and its range, exit 2,
/// nothing on stdout.
#[test]
fn nanotube_bad_input_names_the_option() {
    let cases: &[(&[&str], &str)] = &[
        // (9,9): b = 6.10 Å < R + gap = 6.51 Å.
        (
            &["--substrate", "nanotube", "--chirality", "9,9"],
            "--chirality",
        ),
        (
            &["--substrate", "nanotube", "--tube-radius", "6.5e-10"],
            "--tube-radius",
        ),
        (
            &["--substrate", "nanotube", "--tube-radius", "2e-6"],
            "--tube-radius",
        ),
        (
            &["--substrate", "nanotube", "--tube-radius", "nan"],
            "--tube-radius",
        ),
        (
            &["--substrate", "nanotube", "--tube-radius=-1"],
            "--tube-radius",
        ),
        (
            &[
                "--substrate",
                "nanotube",
                "--tube-radius",
                "7e-10",
                "--chirality",
                "10,10",
            ],
            "--chirality",
        ),
        (
            &["--substrate", "nanotube", "--chirality", "5,6"],
            "--chirality",
        ),
        (
            &["--substrate", "nanotube", "--chirality", "0,0"],
            "--chirality",
        ),
        (
            &["--substrate", "nanotube", "--chirality", "5001,0"],
            "--chirality",
        ),
        (
            &["--substrate", "nanotube", "--chirality", "ten"],
            "--chirality",
        ),
        (&["--substrate", "nanotube"], "--tube-radius"),
        (&["--tube-radius", "7e-10"], "--tube-radius"),
        (
            &["--substrate", "graphite", "--chirality", "10,10"],
            "--chirality",
        ),
        (
            &[
                "--substrate",
                "nanotube",
                "--chirality",
                "10,10",
                "--lj-a",
                "0",
            ],
            "--lj-a",
        ),
    ];
    for (args, opt) in cases {
        let out = tippetop().arg("adhesion").args(*args).output().unwrap();
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {stderr}");
        assert_eq!(stderr.lines().count(), 1, "{args:?}: {stderr}");
        assert!(
            stderr.starts_with(&format!("error: {opt}: ")),
            "{args:?}: {stderr}"
        );
        assert!(out.stdout.is_empty(), "{args:?}");
    }
}
