//! Presets are written with the digits the paper gives (issue #29, 5):
//! `1.35e-6`, not `1.3499999999999998e-6`. Each literal is the paper's
//! formula to within one ulp, and no resolved preset shows a machine-
//! precision number except where the value is itself computed (an inertia
//! of (2/3) m R², the adhesion constants, π/2, a well's depth).

use tippetop::input::scenario::PRESETS;
use tippetop::{Scenario, Top};

/// `x` and `y` differ by at most one unit in the last place.
fn within_one_ulp(x: f64, y: f64) -> bool {
    (x.to_bits() as i64 - y.to_bits() as i64).abs() <= 1
}

#[test]
fn preset_literals_are_the_papers_formulas() {
    let c = Top::classical();
    assert_eq!(c.inertia_axial, 1.35e-6);
    assert_eq!(c.inertia_transverse, 1.35e-6);
    // A = C = (2/5) M R² (paper, App. A).
    assert!(within_one_ulp(
        c.inertia_axial,
        0.4 * c.mass * c.radius * c.radius
    ));
    assert!(within_one_ulp(c.offset, 0.1 * c.radius));
    let n = Top::nano();
    assert_eq!(n.offset, 3.55e-11);
    // a = 0.1 R (paper, §III).
    assert!(within_one_ulp(n.offset, 0.1 * n.radius));
}

/// Numbers in `text` with 16 or more significant digits.
fn machine_numbers(text: &str) -> Vec<(String, String)> {
    text.lines()
        .filter_map(|l| l.split_once(" = "))
        .filter(|(_, v)| {
            let mantissa = v.split(['e', 'E']).next().unwrap_or("");
            mantissa
                .trim_start_matches('-')
                .trim_start_matches(['0', '.'])
                .chars()
                .filter(char::is_ascii_digit)
                .count()
                >= 16
        })
        .map(|(k, v)| (k.trim().to_string(), v.to_string()))
        .collect()
}

#[test]
fn resolved_presets_show_their_given_digits() {
    // Computed values, written with full digits on purpose.
    let computed = [
        "inertia_transverse",
        "inertia_axial",
        "force",
        "energy",
        "theta",
        "depth",
    ];
    for name in PRESETS.iter().map(|p| p.name) {
        let text = Scenario::preset(name).unwrap().to_toml_string();
        let bad: Vec<_> = machine_numbers(&text)
            .into_iter()
            .filter(|(k, _)| !computed.contains(&k.as_str()))
            .collect();
        assert!(bad.is_empty(), "{name}: {bad:?}");
    }
    let classical = Scenario::preset("classical").unwrap().to_toml_string();
    assert!(classical.contains("inertia_axial = 1.35e-6"), "{classical}");
    assert!(machine_numbers(&classical).is_empty(), "{classical}");
}
