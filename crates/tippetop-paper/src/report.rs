//! The Markdown report of a reproduction: every claim beside what we
//! measured, the extra sections, the figures and the table of runs.

use crate::{Reproduction, Verdict};

/// The Markdown report: every claim beside what we measured.
pub fn report_markdown(rep: &Reproduction) -> String {
    let mut s = String::new();
    s.push_str(
        "# tippetop reproduction of *Dynamics of nano tippe top* (Chan, Thamwattana & Hill)\n\n",
    );
    if rep.quick {
        s.push_str("**Quick mode: every window shortened 10x. The verdicts below are NOT meaningful.**\n\n");
    }
    s.push_str("Each claim of the paper beside what tippetop measured. Three computations of each nano result:\n\n");
    s.push_str("- **bilateral (accurate)**: exact Coulomb friction (`coulomb`), contact held with friction μ|N|, adaptive DOP853 at rtol 1e-10. The physically consistent reading of the paper's model.\n");
    s.push_str("- **paper contact (accurate)**: the paper's literal law `−μ N v/|v|` with N's sign (`contact = \"paper\"`, `friction_law = \"coulomb_sliding\"`), solved accurately: what the paper's equations give.\n");
    s.push_str("- **RK4/500 (paper's method)**: the same equations with classical RK4 on 500 steps over the window.\n\n");
    s.push_str("Derivations and every modelling choice: `docs/physics.md`. Verdict criteria are stated in each row.\n\n");
    let count = |v: Verdict| rep.claims.iter().filter(|c| c.verdict == v).count();
    s.push_str(&format!(
        "**Summary**: {} reproduced, {} partly, {} not reproduced.\n\n",
        count(Verdict::Reproduced),
        count(Verdict::Partly),
        count(Verdict::NotReproduced)
    ));
    s.push_str("| claim | paper | measured | verdict | why |\n|---|---|---|---|---|\n");
    for c in &rep.claims {
        s.push_str(&format!(
            "| **{}**: {} | {} | {} | **{}** | {} |\n",
            c.id,
            c.claim.replace('|', "\\|"),
            c.paper_value.replace('|', "\\|"),
            c.measured.replace('|', "\\|"),
            c.verdict.as_str(),
            c.why.replace('|', "\\|")
        ));
    }
    for (title, body) in &rep.sections {
        s.push_str(&format!("\n## {title}\n\n{body}\n"));
    }
    s.push_str("\n## Figures\n\n");
    for f in &rep.figures {
        s.push_str(&format!(
            "### fig{}: {}\n\n![fig{}](fig{}.png)\n\n{}\n\n",
            f.id, f.title, f.id, f.id, f.note
        ));
        if f.id == "02" {
            s.push_str("The five curves overlap, so `fig02.png` draws each one's envelope (its smallest and largest θ over 150 windows of the run; the curves themselves are in `fig02.csv`), and `fig02_zoom.png` the curves over the first 10 µs:\n\n![fig02_zoom](fig02_zoom.png)\n\n");
        }
        if f.id == "04" {
            s.push_str("### fig05: Fig. 5: precession of the nano tippe top\n\n![fig05](fig05.png)\n\nThe top drawn at several instants of the accurate (bilateral) run.\n\n");
        }
    }
    s.push_str("## Runs\n\n| run | settings | status | steps | RHS evaluations | J drift | first N < 0 [s] |\n|---|---|---|---|---|---|---|\n");
    for r in &rep.runs {
        let su = &r.trajectory.summary;
        s.push_str(&format!(
            "| {} | `{}` | {} | {} | {} | {:.1e} | {} |\n",
            r.name,
            r.settings,
            su.status.replace('|', "/"),
            su.steps,
            su.rhs_evaluations,
            su.jellett_max_rel_drift,
            su.contact_lost_at
                .map(|t| format!("{t:.4e}"))
                .unwrap_or("never".into())
        ));
    }
    s
}
