//! The parts both reports share: the title block, the list of figures with
//! their captions, and a list of numbers as the tables show it.

use std::fmt::Write as _;

use crate::figures::Figure;

/// A report's title, the pipeline's description and where the tables are
/// (`tables`: the names to list after "Tables beside this report", if any).
pub(super) fn heading(
    md: &mut String,
    kind: &str,
    plan: &crate::pipeline::Plan,
    pipeline: &str,
    version: &str,
    tables: &str,
) {
    let _ = writeln!(md, "# {kind} `{}`\n", plan.name);
    if !plan.description.is_empty() {
        let _ = writeln!(md, "{}\n", plan.description);
    }
    let _ = writeln!(
        md,
        "Pipeline `{pipeline}`, rocking {version}. Tables beside this report{tables}; columns are \
         documented in rocking's docs/tables.md.\n"
    );
}

/// The report's last section: every figure with its caption.
pub(super) fn figures_section(w: &mut String, figures: &[Figure]) {
    let _ = writeln!(w, "## Figures\n");
    for f in figures {
        let _ = writeln!(
            w,
            "![{}](figures/{})\n\n*{}*\n",
            f.chart.title, f.file, f.caption
        );
    }
}

pub(super) fn list(v: &[f64]) -> String {
    v.iter()
        .map(|x| format!("{x:.3}"))
        .collect::<Vec<_>>()
        .join(", ")
}
