//! Van der Waals adhesion, the `[adhesion]` table (docs/physics.md#adhesion):
//! pull-off force `F_a` \[N\] and binding energy `E_b` \[J\], a force along
//! the vertical through the sphere's centre, pulling the top onto the plane.
//!
//! - In contact: a load `F_a`. Its line is the vertical through the
//!   sphere's centre, which passes through the contact point `P`, so it
//!   enters exactly as a vertical load at `P` (§vertical-load): the closure is
//!   `N_c D(σ) = Q + F_a D₀`, the plane's reaction `N_c` (the `N` column)
//!   is `F_a` plus what the contact must supply besides, the friction sees
//!   `N_c`; without friction the motion is that without adhesion and
//!   `N_c = F_a + N`. Rolling: `N_c = F_Z + F_a`. Under unilateral contact
//!   the top leaves the plane when `N_c` falls below zero, i.e. when a pull
//!   exceeds `F_a` plus what holds it down otherwise.
//! - In flight (rigid model): the force `−U′(z) Z` with
//!   `U(z) = −E_b exp(−F_a z/E_b)`, `z` the gap: `U(0) = −E_b`,
//!   `−U′(0) = F_a` (continuous at lift-off), monotone, separation work `E_b`.
//! - Jellett's J: conserved (a force whose line passes through `P`, §invariants).
//! - Energy: a potential. In contact it is the constant `U(0)`, and the
//!   force does no work (`v_Pz = 0`); the energy the models report counts it
//!   from contact, `U(z) − U(0) = E_b (1 − exp(−F_a z/E_b))`, zero in contact,
//!   so the energy in contact is the one without adhesion.

use super::{Applied, CentreVertical, Energy, ForceTerm, Kind, Properties};

/// The adhesion term of a scenario.
#[derive(Debug, Clone)]
pub struct Adhesion {
    value: CentreVertical,
}

impl Adhesion {
    /// The term of the scenario's `[adhesion]` table.
    pub fn of(a: &crate::Adhesion) -> Self {
        Adhesion {
            value: CentreVertical {
                force: a.force,
                energy: a.energy,
            },
        }
    }
}

impl ForceTerm for Adhesion {
    fn name(&self) -> &'static str {
        "van der Waals adhesion (adhesion.force, adhesion.energy)"
    }
    fn kind(&self) -> Kind {
        Kind::CentreVertical
    }
    fn properties(&self) -> Properties {
        Properties {
            closure: "in contact Q += F_a D0 (N_c = F_a + N); in flight the gap potential U(z) = -E_b exp(-F_a z/E_b) (docs/physics.md#adhesion)",
            conserves_jellett: true,
            energy: Energy::Potential,
        }
    }
    fn add_to(&self, _t: f64, acc: &mut Applied) {
        acc.centre_vertical.force += self.value.force;
        acc.centre_vertical.energy += self.value.energy;
    }
}
