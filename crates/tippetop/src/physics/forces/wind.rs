//! A constant horizontal body force at the centre of mass, the `[wind]`
//! table (`fx`, `fy` \[N\], lab frame): the example force plug-in
//! (docs/extending.md), added in two files (this one and its line in
//! [`super::PLUGINS`]).
//!
//! - Kind: [`Kind::BodyPoint`], a wrench with `F = (f_x, f_y, 0)` at the
//!   centre of mass `O` and no torque: `v̇ += F/m`. The vector and rigid
//!   models apply it (contact and flight); the reduced model refuses it.
//! - Closure: `Q −= F_Z/m = 0`, unchanged (`F` is horizontal); it changes
//!   the friction needed through the rolling constraint's `b −= F/m`.
//! - Jellett's J: conserved (no torque about `O`, `dJ/dt = −τ·r = 0`).
//! - Energy: no potential; its work `F·(x_O − x_O0)` is integrated in `W_a`.
//! - Closed form (tests/physics/wind.rs): on a frictionless plane the
//!   horizontal forces on the top are `F` alone, so `x_O(t) = x0 + v0 t +
//!   F t²/(2m)` whatever the top does.

use std::sync::Arc;

use super::{Applied, Energy, ForceTerm, Kind, Plugin, Properties};
use crate::input::{Key, TableSpec};

/// The range of `fx` and `fy`.
const FORCE_RANGE: &str = "-1000 <= f <= 1000 [N], lab frame";

const KEYS: &[Key] = &[
    Key::doc(
        "fx",
        FORCE_RANGE,
        "0",
        "wind force along the lab X axis, at the centre of mass",
    )
    .bounded(-1e3, 1e3),
    Key::doc(
        "fy",
        FORCE_RANGE,
        "0",
        "wind force along the lab Y axis, at the centre of mass",
    )
    .bounded(-1e3, 1e3),
];

/// The `[wind]` plug-in.
#[derive(Debug, Clone, Copy)]
pub struct Wind;

impl Plugin for Wind {
    fn table(&self) -> TableSpec {
        TableSpec {
            name: "wind",
            array: false,
            doc: "a constant horizontal force at the centre of mass (vector and rigid models; off by default)",
            keys: KEYS,
        }
    }
    fn kind(&self) -> Kind {
        Kind::BodyPoint
    }
    fn rate(
        &self,
        values: &[f64],
        mass: f64,
        radius: f64,
        _inertia: f64,
    ) -> Option<(f64, &'static str)> {
        Some((
            (values[0].hypot(values[1]) / (mass * radius)).sqrt(),
            "sqrt(|(fx, fy)| / (mass radius)) (wind)",
        ))
    }
    fn term(&self, values: &[f64]) -> Option<Arc<dyn ForceTerm>> {
        let force = [values[0], values[1]];
        (force != [0.0; 2]).then(|| Arc::new(WindTerm { force }) as Arc<dyn ForceTerm>)
    }
}

/// The wind's force `(f_x, f_y)` \[N\], lab frame.
#[derive(Debug, Clone, Copy)]
pub struct WindTerm {
    force: [f64; 2],
}

impl ForceTerm for WindTerm {
    fn name(&self) -> &'static str {
        "wind (wind.fx, wind.fy)"
    }
    fn kind(&self) -> Kind {
        Kind::BodyPoint
    }
    fn properties(&self) -> Properties {
        Properties {
            closure: "Q unchanged (F horizontal); rolling b -= F/m (docs/physics.md#actuators)",
            conserves_jellett: true,
            energy: Energy::Integrated,
        }
    }
    fn add_to(&self, _t: f64, acc: &mut Applied) {
        acc.body.force[0] += self.force[0];
        acc.body.force[1] += self.force[1];
    }
}

#[cfg(test)]
mod tests {
    //! The wind against its closed form, its energy balance and its input
    //! errors. Here, beside the term, so that adding it touched 2 files.

    use crate::{ModelKind, Scenario};

    /// The classical top on a frictionless plane, tilted, spinning and
    /// sliding (lab-frame initial state), with `--set`s.
    fn top(sets: &[&str]) -> Scenario {
        let mut all = vec![
            "surface.friction=0".to_string(),
            "initial.axis=[0.3, 0.1, 1.0]".into(),
            "initial.angular_velocity=[2.0, -1.0, 150.0]".into(),
            "initial.velocity=[0.05, -0.02]".into(),
            "solver.t_end=1.0".into(),
            "solver.samples=201".into(),
        ];
        all.extend(sets.iter().map(|s| s.to_string()));
        Scenario::load(Some("classical"), None, &all).expect("valid scenario")
    }

    /// The largest distance \[m\] of the centre of mass from
    /// `x0 + v0 t + F t²/(2m)` (`v0` the first sample's velocity), and the
    /// largest `|(E − E0) − F·(x − x0)|` and `|W_a − F·(x − x0)|` \[J\].
    fn errors(sc: &Scenario, f: [f64; 2]) -> (f64, f64, f64) {
        let tr = crate::simulate(sc).expect("runs");
        assert!(tr.error.is_none(), "{:?}", tr.error);
        let m = sc.top.mass;
        let s0 = &tr.samples[0];
        let v0 = [0.05, -0.02];
        let (mut dx, mut de, mut dw) = (0.0f64, 0.0f64, 0.0f64);
        for s in &tr.samples {
            let t = s.t;
            let want = [
                s0.x + v0[0] * t + f[0] * t * t / (2.0 * m),
                s0.y + v0[1] * t + f[1] * t * t / (2.0 * m),
            ];
            dx = dx.max((s.x - want[0]).hypot(s.y - want[1]));
            let work = f[0] * (s.x - s0.x) + f[1] * (s.y - s0.y);
            de = de.max(((s.energy - s0.energy) - work).abs());
            dw = dw.max((s.work_applied - work).abs());
        }
        (dx, de, dw)
    }

    /// On a frictionless plane the horizontal forces on the top are the
    /// wind alone, so its centre of mass moves as `x0 + v0 t + F t²/(2m)`
    /// whatever the top does (it nutates and spins here), in the vector
    /// and the rigid model; the energy balance is `E − E0 = W_a = F·Δx`.
    /// Without the wind the same check fails by `F t²/(2m)`.
    #[test]
    fn wind_accelerates_the_centre_of_mass_by_f_over_m() {
        for model in ["vector", "rigid"] {
            let sc = top(&[
                "wind.fx=0.03",
                "wind.fy=-0.01",
                &format!("solver.model=\"{model}\""),
            ]);
            let f: [f64; 2] = [0.03, -0.01];
            let m = sc.top.mass;
            let rtol = sc.solver.rtol;
            // Lengths are scaled by R: the integrator keeps each step's
            // error below rtol of the scaled state; the displacement's
            // scale is R + F t²/(2m) (m), the energy's the initial energy
            // plus the wind's work.
            let t = sc.solver.t_end;
            let shift = (f[0].hypot(f[1])) * t * t / (2.0 * m);
            let x_scale = sc.top.radius + shift;
            let (dx, de, dw) = errors(&sc, f);
            let e_scale = sc.top.mass * sc.surface.gravity * sc.top.radius
                + 0.5 * sc.top.inertia_axial * 150.0f64.powi(2)
                + f[0].hypot(f[1]) * shift;
            println!(
                "{model}: |x - closed form| {dx:.2e} m (tol {:.2e}), energy {de:.2e} J, W_a {dw:.2e} J (tol {:.2e})",
                rtol * x_scale,
                rtol * e_scale
            );
            assert!(dx <= rtol * x_scale, "{model}: x off by {dx:e} m");
            // The energy is a sum over the state: rtol of each part, and
            // the rounding of the integrated W_a; 10 rtol of the scale.
            assert!(
                de <= 10.0 * rtol * e_scale,
                "{model}: E - E0 - F.dx = {de:e} J"
            );
            assert!(
                dw <= 10.0 * rtol * e_scale,
                "{model}: W_a - F.dx = {dw:e} J"
            );
            // Without the wind the closed form misses by F t^2/(2m).
            let (dx0, ..) = errors(&top(&[&format!("solver.model=\"{model}\"")]), f);
            assert!(
                dx0 > 0.5 * shift,
                "{model}: the check passes without the wind ({dx0:e} m)"
            );
        }
    }

    /// The reduced model refuses the wind as it refuses body actuators; a
    /// zero wind is the run without it, bit for bit.
    #[test]
    fn reduced_model_refuses_it_and_zero_wind_is_no_wind() {
        let e = Scenario::load(
            Some("classical"),
            None,
            &["wind.fx=1e-3".into(), "solver.model=\"reduced\"".into()],
        )
        .unwrap_err()
        .to_string();
        assert!(e.contains("wind") && e.contains("reduced"), "{e}");
        let mut sc = top(&["wind.fx=0"]);
        sc.solver.t_end = 0.05;
        let with = crate::simulate(&sc).unwrap();
        sc.plugins = crate::input::PluginTables::NONE;
        let without = crate::simulate(&sc).unwrap();
        assert_eq!(with.samples, without.samples);
        assert_eq!(sc.solver.model, ModelKind::Vector);
    }

    /// Bad input names `wind.fx` (or the unknown key) and the range.
    #[test]
    fn bad_wind_names_the_key_and_its_range() {
        for (set, key, range) in [
            ("wind.fx=nan", "wind.fx", "-1000 <= f <= 1000 [N]"),
            ("wind.fx=2e3", "wind.fx", "-1000 <= f <= 1000 [N]"),
            ("wind.fy=\"x\"", "wind.fy", "-1000 <= f <= 1000 [N]"),
            ("wind.fz=1", "wind.fz", "valid keys: fx, fy"),
        ] {
            let e = Scenario::load(Some("classical"), None, &[set.into()])
                .unwrap_err()
                .to_string();
            assert!(e.starts_with(key) && e.contains(range), "{set}: {e}");
            assert!(!e.contains('\n'), "{e}");
        }
    }

    /// The table round-trips through the scenario text; a scenario without
    /// it keeps its text.
    #[test]
    fn wind_round_trips_through_toml() {
        let sc = top(&["wind.fx=0.25"]);
        let text = sc.to_toml_string();
        assert!(text.contains("\n[wind]\nfx = 0.25\nfy = 0.0\n"), "{text}");
        assert_eq!(Scenario::from_toml_str(&text).unwrap(), sc);
        assert!(!Scenario::classical().to_toml_string().contains("wind"));
    }
}
