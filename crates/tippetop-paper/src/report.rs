//! The Markdown report of a reproduction, for a referee: an abstract of
//! the decisive findings, a table of every claim with one-line results
//! (each cell at most 80 characters), the claims in detail, the extra
//! sections, the figures, and the runs with their failure messages as
//! footnotes.

use crate::{Claim, Reproduction, Verdict};

/// The claims the abstract reports, each with its lead-in, in this order.
const ABSTRACT: &[(&str, &str)] = &[
    (
        "rk4_500_adequate",
        "The paper's integrator (RK4 on 500 steps)",
    ),
    ("stays_in_contact", "The contact"),
    ("nano_lies_down_50us", "Lying down"),
    ("reversal_stands_up", "The reversed force"),
    ("upright_stable_b2", "Upright stability (App. B)"),
    ("classical_flips", "The classical top"),
    ("jellett_zero", "Jellett's integral"),
];

/// The verdicts' words, each defined once, at the top of the report.
const VERDICT_LEGEND: &str = "**The verdicts' words.** Each claim is judged by the criterion given with it in detail, \
     at two levels:\n\n\
     - **reproduced**: the criterion holds, in every computation the claim is judged on (for most nano claims \
     both accurate ones, bilateral and paper contact);\n\
     - **partly**: only the criterion's weaker level holds (its \"partly if ...\"), or the computations disagree; \
     the table's line then gives each computation's own verdict, **yes** (reproduced), **in part** or **no** \
     (not reproduced), with its numbers;\n\
     - **not reproduced**: not even the weaker level holds.\n\n";

/// `s` cut to at most `n` characters at a word boundary, with "…" when cut.
pub(crate) fn clip(s: &str, n: usize) -> String {
    if s.chars().count() <= n {
        return s.to_string();
    }
    let mut out = String::new();
    for w in s.split(' ') {
        if out.chars().count() + w.chars().count() + 2 > n {
            break;
        }
        if !out.is_empty() {
            out.push(' ');
        }
        out.push_str(w);
    }
    out.push('…');
    out
}

/// A table cell: `|` escaped, newlines flattened.
fn cell(s: &str) -> String {
    s.replace('|', "\\|").replace('\n', " ")
}

/// The paper's value for the table: the statement after the equation
/// (App. B's "ε̈ = …: always stable, …") when the whole is too long, clipped.
fn paper_cell(p: &str) -> String {
    let short = if p.chars().count() > 80 {
        p.split_once(": ").map_or(p, |(_, rest)| rest)
    } else {
        p
    };
    cell(&clip(short.split("; ").next().unwrap_or(short), 80))
}

fn verdict_counts(claims: &[Claim]) -> (usize, usize, usize) {
    let count = |v: Verdict| claims.iter().filter(|c| c.verdict == v).count();
    (
        count(Verdict::Reproduced),
        count(Verdict::Partly),
        count(Verdict::NotReproduced),
    )
}

fn push_abstract(s: &mut String, rep: &Reproduction) {
    let (yes, partly, no) = verdict_counts(&rep.claims);
    s.push_str("## Abstract\n\n");
    s.push_str(&format!(
        "Of the paper's {} checkable claims, tippetop reproduces {yes}, {partly} in part and {no} not \
         (criteria with each claim below).",
        rep.claims.len()
    ));
    for (id, lead) in ABSTRACT {
        if let Some(c) = rep.claims.iter().find(|c| c.id == *id) {
            s.push_str(&format!(
                " **{lead}** ({}): {}.",
                c.verdict.as_str(),
                c.summary
            ));
        }
    }
    s.push_str("\n\n");
}

fn push_claims(s: &mut String, rep: &Reproduction) {
    s.push_str("## The claims\n\n");
    s.push_str(
        "| claim | paper | measured (bilateral unless said) | verdict |\n|---|---|---|---|\n",
    );
    for c in &rep.claims {
        s.push_str(&format!(
            "| [{}](#{}) | {} | {} | **{}** |\n",
            c.id,
            c.id.to_lowercase(),
            paper_cell(&c.paper_value),
            cell(&c.summary),
            c.verdict.as_str()
        ));
    }
    s.push_str("\n## The claims in detail\n\n");
    for c in &rep.claims {
        s.push_str(&format!(
            "### {}\n\n{}\n\n- **Paper**: {}\n- **Verdict**: **{}**. {}\n- **Measured**:\n",
            c.id,
            c.claim,
            c.paper_value,
            c.verdict.as_str(),
            c.why
        ));
        for part in c.measured.split("; ") {
            s.push_str(&format!("  - {part}\n"));
        }
        s.push_str(&format!("- **Runs**: `{}`\n\n", c.settings));
    }
}

fn push_figures(s: &mut String, rep: &Reproduction) {
    s.push_str("\n## Figures\n\n");
    for f in &rep.figures {
        s.push_str(&format!(
            "### fig{}: {}\n\n![fig{}](fig{}.png)\n\n{}\n\n",
            f.id, f.title, f.id, f.id, f.note
        ));
        if f.id == "02" {
            s.push_str("The five curves overlap, so `fig02.png` draws each one's running mean with its running min–max band over 2.5 µs, one curve a panel on the same axes, each beside the g = 9.8 bilateral run's mean in grey (the curves themselves are in `fig02.csv`), and `fig02_zoom.png` the curves over the first 10 µs:\n\n![fig02_zoom](fig02_zoom.png)\n\n");
        }
        if f.id == "04" {
            s.push_str("### fig05: Fig. 5: precession of the nano tippe top\n\n![fig05](fig05.png)\n\nThe top drawn at several instants of the accurate (bilateral) run.\n\n");
        }
    }
}

/// A run's settings for the runs list: its command line as a code span;
/// for the C/A study, whose C is the product ratio × A (17 digits on a
/// command line), the nano file's command with C in words.
fn shown_settings(r: &crate::Run) -> String {
    use crate::runs::{C_OVER_A, c_over_a_name};
    match C_OVER_A.iter().find(|&&k| c_over_a_name(k) == r.name) {
        Some(ratio) => {
            let base: Vec<&str> = r
                .settings
                .split(" --set ")
                .filter(|p| !p.starts_with("top.inertia_axial="))
                .collect();
            let base = base.join(" --set ");
            format!(
                "`{base}` with C = {ratio} A = {} kg m² (`top.inertia_axial` set to {ratio} × \
                 `top.inertia_transverse`, in double precision)",
                tippetop::human::s4(r.scenario.top.inertia_axial)
            )
        }
        None => format!("`{}`", r.settings),
    }
}

fn push_runs(s: &mut String, rep: &Reproduction) {
    s.push_str("## Runs\n\n| run | status | steps | RHS evaluations | J drift | first N < 0 |\n|---|---|---|---|---|---|\n");
    let mut notes = Vec::new();
    for r in &rep.runs {
        let su = &r.trajectory.summary;
        let status = match crate::runs::failure(&r.trajectory) {
            None => "ok".to_string(),
            Some(msg) => {
                notes.push(msg);
                match &r.trajectory.error {
                    Some(tippetop::Error::Runtime { t, .. }) => {
                        format!("failed at {} s[^{}]", tippetop::human::s4(*t), notes.len())
                    }
                    _ => format!("failed[^{}]", notes.len()),
                }
            }
        };
        s.push_str(&format!(
            "| {} | {} | {} | {} | {} | {} |\n",
            r.name,
            status,
            su.steps,
            su.rhs_evaluations,
            tippetop::human::sig(su.jellett_max_rel_drift, 2),
            su.contact_lost_at
                .map(|t| format!("{} s", tippetop::human::s4(t)))
                .unwrap_or("never".into())
        ));
    }
    s.push_str("\nEach run's settings (the scenario and its overrides):\n\n");
    for r in &rep.runs {
        s.push_str(&format!("- {}: {}\n", r.name, shown_settings(r)));
    }
    if !notes.is_empty() {
        s.push('\n');
        for (i, n) in notes.iter().enumerate() {
            s.push_str(&format!("[^{}]: {}\n", i + 1, n.replace('\n', " ")));
        }
    }
}

/// The Markdown report: an abstract, every claim beside what we measured,
/// the sections, figures and runs.
pub fn report_markdown(rep: &Reproduction) -> String {
    let mut s = String::new();
    s.push_str(
        "# tippetop reproduction of *Dynamics of nano tippe top* (Chan, Thamwattana & Hill)\n\n",
    );
    if rep.quick {
        s.push_str("**Quick mode: every window shortened 10x. The verdicts below are NOT meaningful.**\n\n");
    }
    push_abstract(&mut s, rep);
    s.push_str(VERDICT_LEGEND);
    s.push_str("Each claim of the paper beside what tippetop measured. Three computations of each nano result:\n\n");
    s.push_str("- **bilateral (accurate)**: exact Coulomb friction (`coulomb`), contact held with friction μ|N|, adaptive DOP853 at rtol 1e-10. The physically consistent reading of the paper's model.\n");
    s.push_str("- **paper contact (accurate)**: the paper's literal law `−μ N v/|v|` with N's sign (`contact = \"paper\"`, `friction_law = \"coulomb_sliding\"`), solved accurately: what the paper's equations give.\n");
    s.push_str("- **RK4/500 (paper's method)**: the same equations with classical RK4 on 500 steps over the window.\n\n");
    s.push_str("Derivations and every modelling choice: `docs/physics.md`. The criterion of each verdict is with the claim in detail.\n\n");
    push_claims(&mut s, rep);
    for (title, body) in &rep.sections {
        s.push_str(&format!("\n## {title}\n\n{body}\n"));
    }
    push_figures(&mut s, rep);
    push_runs(&mut s, rep);
    s
}
