use tippetop::{FrictionLaw, ModelKind, Scenario, simulate};
#[test]
fn scratch() {
    let mut sc = Scenario::nano();
    sc.surface.law = FrictionLaw::CoulombSliding;
    sc.solver.rtol = 1e-12;
    for m in [ModelKind::Reduced, ModelKind::Rigid] {
        sc.solver.model = m;
        let tr = simulate(&sc).unwrap();
        println!("{m:?} {:?}", tr.summary);
        for s in tr.samples.iter().step_by(100) { println!("{:e} {:e} {:e} {:e}", s.t, s.jellett, s.theta, s.spin); }
    }
}
