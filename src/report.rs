//! The study's report as Markdown (pure): settings, run times, counts,
//! capacity fractiles against the paper's Eq. 10, lognormality, the fitted
//! against the published coefficients, the capacity-convergence finding and
//! the figures. The report stage loads the data, draws the figures, calls
//! [`render`] and writes the text; the tests snapshot [`render`]'s output.
//! [`render_html`] turns that Markdown into one self-contained page, the
//! figures inline.

use std::fmt::Write as _;

use crate::figures::{convergence_levels, Figure};
use crate::fragility;
use crate::ida::CertificationKind;
use crate::study::StudyData;

/// A report's title, the pipeline's description and where the tables are
/// (`tables`: the names to list after "Tables beside this report", if any).
fn heading(
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
         documented in the rocking README.\n"
    );
}

/// The whole report. `figures` are listed with their captions, as files
/// under `figures/`.
pub fn render(d: &StudyData, figures: &[Figure]) -> String {
    let mut md = String::new();
    let plan = &d.plan;
    heading(&mut md, "Study", plan, &d.pipeline, &d.version, "");
    settings(&mut md, d);
    runtime(&mut md, d);
    capacity_fractiles(&mut md, d);
    bands(&mut md, d);
    lognormality(&mut md, d);
    regression(&mut md, d);
    fit_bands(&mut md, d);
    convergence(&mut md, d);
    figures_section(&mut md, figures);
    md
}

/// The report's last section: every figure with its caption.
fn figures_section(w: &mut String, figures: &[Figure]) {
    let _ = writeln!(w, "## Figures\n");
    for f in figures {
        let _ = writeln!(
            w,
            "![{}](figures/{})\n\n*{}*\n",
            f.chart.title, f.file, f.caption
        );
    }
}

fn list(v: &[f64]) -> String {
    v.iter()
        .map(|x| format!("{x:.3}"))
        .collect::<Vec<_>>()
        .join(", ")
}

fn settings(w: &mut String, d: &StudyData) {
    let plan = &d.plan;
    let (ps, es) = d.ps_and_eps();
    let _ = writeln!(w, "## Settings\n");
    let _ = writeln!(w, "| setting | value |\n|---|---|");
    let sets = if plan.sets.is_empty() {
        String::new()
    } else {
        format!(" ({})", plan.sets.join(", "))
    };
    let _ = writeln!(w, "| records | {}{sets} |", d.n_records());
    let _ = writeln!(
        w,
        "| model | {:?}, overturning {} |",
        plan.model, plan.overturn
    );
    let _ = writeln!(
        w,
        "| blocks | {}: p = {} 1/s; ε = {} |",
        plan.blocks.len(),
        list(&ps),
        list(&es)
    );
    let _ = writeln!(
        w,
        "| IM grid | {} {:?}-spaced levels of η from {} down to {}, capacity refined to Δη = {} |",
        plan.grid.count, plan.grid.spacing, plan.grid.eta_max, plan.grid.eta_min, plan.tol
    );
    let _ = writeln!(w, "| fractiles | Hyndman–Fan {:?} |\n", plan.fractile);
}

fn runtime(w: &mut String, d: &StudyData) {
    let _ = writeln!(w, "## Runtime and counts\n");
    let _ = writeln!(w, "| stage | time (s) |\n|---|---:|");
    for (s, t) in &d.stage_seconds {
        if let Some(t) = t {
            let _ = writeln!(w, "| {s} | {t:.2} |");
        }
    }
    let overturned = d.ida.iter().filter(|r| r.overturned).count();
    let _ = writeln!(
        w,
        "\n{} capacities from {} simulations ({} of them overturned); {} of the record × block cases never overturned down to η = {}.\n",
        d.caps.len(),
        d.ida.len(),
        overturned,
        d.caps.iter().filter(|c| c.eta_c.is_none()).count(),
        d.plan.grid.eta_min
    );
    let count = |k: CertificationKind| d.caps.iter().filter(|c| c.certification == k).count();
    let certified = d.caps.iter().filter(|c| c.certified).count();
    let (exact, tolerance) = (
        count(CertificationKind::Exact),
        count(CertificationKind::Tolerance),
    );
    let _ = write!(
        w,
        "Certification: {certified} of {} capacities certified ({exact} by the exact stepper, {tolerance} at DP5's tolerance with their decisive runs agreeing at a 100× tighter one; in both, no decisive verdict changes when η moves by 1e-9)",
        d.caps.len()
    );
    let (chaotic, flips) = (
        count(CertificationKind::Chaotic),
        count(CertificationKind::Flips),
    );
    if chaotic + flips > 0 {
        let _ = write!(
            w,
            "; not certified: {chaotic} chaotic (a decisive verdict changes when η moves by 1e-9) and {flips} whose verdict still flips at the tightest tolerance. Their η_c is one edge of a chaotic band, not a converged value (column `certification` of capacities.parquet)"
        );
    }
    let _ = writeln!(
        w,
        ". See docs/BENCHMARKS.md for how the tolerance was chosen.\n"
    );
}

/// The capacity fractile of block (p, ε) at quantile q, if tabulated.
fn fractile_at(d: &StudyData, p: f64, e: f64, q: f64) -> Option<f64> {
    d.capacity_fractiles
        .iter()
        .find(|r| r.p == p && r.eps == e && r.quantile == q)
        .map(|r| r.eta_c)
}

fn capacity_fractiles(w: &mut String, d: &StudyData) {
    let _ = writeln!(w, "## Capacity fractiles\n");
    if !d.is_grid() {
        let _ = writeln!(
            w,
            "| block | p | ε | η_c,16 | η_c,50 | η_c,84 |\n|---|---:|---:|---:|---:|---:|"
        );
        for b in &d.plan.blocks {
            let at = |q: f64| {
                d.capacity_fractiles
                    .iter()
                    .find(|r| r.block == b.name && r.quantile == q)
                    .map_or(f64::NAN, |r| r.eta_c)
            };
            let _ = writeln!(
                w,
                "| {} | {:.3} | {:.3} | {:.4} | {:.4} | {:.4} |",
                b.name,
                b.p,
                b.eps,
                at(0.16),
                at(0.5),
                at(0.84)
            );
        }
        let _ = writeln!(w);
        return;
    }
    let (ps, es) = d.ps_and_eps();
    for (q, label) in [(0.5, "median η_c,50"), (0.16, "η_c,16"), (0.84, "η_c,84")] {
        let _ = writeln!(w, "{label}, rows p (1/s), columns ε:\n");
        let header: Vec<String> = es.iter().map(|e| format!("{e:.2}")).collect();
        let _ = writeln!(w, "| p \\ ε | {} |", header.join(" | "));
        let _ = writeln!(w, "|---:|{}", "---:|".repeat(es.len()));
        for &p in &ps {
            let cells: Vec<String> = es
                .iter()
                .map(|&e| fractile_at(d, p, e, q).map_or(String::new(), |v| format!("{v:.4}")))
                .collect();
            let _ = writeln!(w, "| {p:.3} | {} |", cells.join(" | "));
        }
        let _ = writeln!(w);
    }
    // Against the paper's Eq. 10.
    let law = &fragility::paper()[1];
    let ratios: Vec<f64> = d
        .capacity_fractiles
        .iter()
        .filter(|r| r.quantile == 0.5 && r.p >= 0.5)
        .map(|r| (r.eta_c / law.eta_c(r.p, r.eps) - 1.0).abs())
        .collect();
    if !ratios.is_empty() {
        let _ = writeln!(
            w,
            "Against the paper's Eq. 10: mean |η_c,50 / Eq. 10 − 1| = {:.1} % over the {} blocks with p ≥ 0.5 1/s.\n",
            100.0 * ratios.iter().sum::<f64>() / ratios.len() as f64,
            ratios.len()
        );
    }
}

/// The bootstrap bands against the paper's Eqs. 10–12: how often the
/// paper's curve lies inside this study's band, and how wide the bands are.
fn bands(w: &mut String, d: &StudyData) {
    let Some(bands) = d.bands.as_ref().filter(|b| !b.is_empty() && d.is_grid()) else {
        return;
    };
    let first = &bands[0];
    let _ = writeln!(
        w,
        "## How sure are the capacity fractiles?
"
    );
    let _ = writeln!(
        w,
        "{:.0} % percentile bootstrap bands from {} resamples of whole {}s \
         (`capacity_bands.parquet`). Where the paper's curve lies outside a band, the \
         difference is more than the sampling error of this record set explains.\n",
        100.0 * first.level,
        first.resamples,
        crate::label::Label::label(first.unit)
    );
    let _ = writeln!(
        w,
        "| fractile | paper's curve | blocks (p ≥ 0.5 1/s) | paper inside the band | median band width / η_c |\n|---|---|---:|---:|---:|"
    );
    for (qi, q) in [0.16, 0.5, 0.84].into_iter().enumerate() {
        let rows: Vec<BandPoint> = bands
            .iter()
            .filter(|b| b.quantile == q && b.p >= 0.5)
            .map(|b| (b.p, b.eps, b.eta_c, b.lo, b.hi))
            .collect();
        paper_against_band(w, qi, &rows);
    }
    let _ = writeln!(w);
}

/// A point of a band: (p, ε, this study's value, lo, hi).
type BandPoint = (f64, f64, f64, f64, f64);

/// One row of a "paper against the band" table for fractile `qi` (16, 50,
/// 84 %): the points, how many hold the paper's law inside their band, and
/// the median band width relative to the value. Nothing without points.
fn paper_against_band(w: &mut String, qi: usize, rows: &[BandPoint]) {
    if rows.is_empty() {
        return;
    }
    let law = &fragility::paper()[qi];
    let inside = rows
        .iter()
        .filter(|&&(p, e, _, lo, hi)| (lo..=hi).contains(&law.eta_c(p, e)))
        .count();
    let mut widths: Vec<f64> = rows
        .iter()
        .filter(|r| r.2 > 0.0)
        .map(|r| (r.4 - r.3) / r.2)
        .collect();
    widths.sort_by(|a, b| a.total_cmp(b));
    let median = crate::stats::fractile(&widths, 0.5, crate::pipeline::FractileDef::Type7)
        .unwrap_or(f64::NAN);
    let _ = writeln!(
        w,
        "| η_c,{:.0} | Eq. {} | {} | {} ({:.0} %) | {:.0} % |",
        100.0 * law.quantile,
        crate::figures::PAPER_EQ[qi],
        rows.len(),
        inside,
        100.0 * inside as f64 / rows.len() as f64,
        100.0 * median
    );
}

fn lognormality(w: &mut String, d: &StudyData) {
    let tested: Vec<_> = d
        .lognormal
        .iter()
        .filter(|r| r.p_value.is_some_and(f64::is_finite))
        .collect();
    let kept = tested.iter().filter(|r| !r.rejected_5pct).count();
    let _ = writeln!(w, "## Lognormality of η_c\n");
    let _ = writeln!(
        w,
        "The Lilliefors test does not reject lognormality at 5 % in **{kept} of {}** blocks ({:.0} %; the paper found about 80 %). p-values: Dallal–Wilkinson (1986), Stephens (1974) above 0.1, as R's `nortest`.\n",
        tested.len(),
        100.0 * kept as f64 / tested.len().max(1) as f64
    );
}

fn regression(w: &mut String, d: &StudyData) {
    if d.laws.is_empty() {
        return;
    }
    let conv = d.fit_step1.iter().filter(|r| r.converged).count();
    let _ = writeln!(w, "## Regression η_c = a(1 − e^(−bp))^c\n");
    let _ = writeln!(
        w,
        "Step 1 converged in {conv} of {} (ε, fractile) fits. Step 2, against the paper:\n",
        d.fit_step1.len()
    );
    let _ = writeln!(w, "| fractile | | a = c0 + c1 ε | b = c0 + c1 ε + c2 ε² | c = c0 + c1 ε + c2 ε² |\n|---|---|---|---|---|");
    // An empty polynomial: too few converged step-1 fits to fit it.
    let fmt = |c: &[f64]| {
        if c.is_empty() {
            return "—".to_string();
        }
        c.iter()
            .map(|v| format!("{v:+.3}"))
            .collect::<Vec<_>>()
            .join(", ")
    };
    let mut incomplete = false;
    for paper in fragility::paper().iter() {
        if let Some(law) = d.laws.iter().find(|l| l.quantile == paper.quantile) {
            incomplete |= law.a.is_empty() || law.b.is_empty() || law.c.is_empty();
            let _ = writeln!(
                w,
                "| {:.0} % | fitted | {} | {} | {} |",
                100.0 * law.quantile,
                fmt(&law.a),
                fmt(&law.b),
                fmt(&law.c)
            );
        }
        let _ = writeln!(
            w,
            "| | paper | {} | {} | {} |",
            fmt(&paper.a),
            fmt(&paper.b),
            fmt(&paper.c)
        );
    }
    if incomplete {
        let _ = writeln!(
            w,
            "\n— : too few converged step-1 fits of that fractile to fit the polynomial (a line needs 2, a quadratic 3)."
        );
    }
    let _ = writeln!(w);
}

/// The regression's bootstrap bands: how the refits went, how often the
/// paper's curves lie inside this fit's bands, and the example fragility's
/// median PGA with its band.
fn fit_bands(w: &mut String, d: &StudyData) {
    let Some(b) = d.fit_bands.as_ref().filter(|b| !b.rows.is_empty()) else {
        return;
    };
    let share = |(k, n): (usize, usize)| 100.0 * k as f64 / n.max(1) as f64;
    let _ = writeln!(
        w,
        "## How sure is the regression?
"
    );
    let _ = writeln!(
        w,
        "Every bootstrap resample of the capacity fractiles refitted through both steps \
         (`fit_bands.parquet`): step 1 converged in {} of {} refits ({:.1} %), and {} of {} \
         resamples ({:.1} %) gave all three laws; the {:.0} % bands are over those.\n",
        b.step1_converged.0,
        b.step1_converged.1,
        share(b.step1_converged),
        b.laws_complete.0,
        b.laws_complete.1,
        share(b.laws_complete),
        100.0 * b.rows[0].level
    );
    let _ = writeln!(
        w,
        "| fractile | paper's curve | points (p ≥ 0.5 1/s, every ε) | paper inside the fit's band | median band width / η_c |\n|---|---|---:|---:|---:|"
    );
    for (qi, q) in [0.16, 0.5, 0.84].into_iter().enumerate() {
        let rows: Vec<BandPoint> = b
            .rows
            .iter()
            .filter(|r| r.quantile == Some(q) && r.p >= 0.5)
            .filter_map(|r| Some((r.p, r.eps, r.value?, r.lo?, r.hi?)))
            .collect();
        paper_against_band(w, qi, &rows);
    }
    let paper = fragility::paper();
    // The example fragility's median PGA: where each curve crosses 1/2.
    let frag = b.fragility();
    let crossing = |f: &dyn Fn(&crate::tables::fit::FitBandRow) -> Option<f64>| {
        frag.windows(2).find_map(|w| {
            let (g0, g1) = (w[0].pga_g?, w[1].pga_g?);
            let (y0, y1) = (f(w[0])?, f(w[1])?);
            (y0 < 0.5 && y1 >= 0.5).then(|| g0 + (0.5 - y0) / (y1 - y0) * (g1 - g0))
        })
    };
    let block = fragility::example_block();
    let paper_median =
        fragility::median_beta(&paper, block.p(), block.eps).map(|(m, _)| block.alpha() / m);
    if let (Some(mid), Some(lo), Some(hi)) = (
        crossing(&|r| r.value),
        crossing(&|r| r.hi),
        crossing(&|r| r.lo),
    ) {
        let _ = writeln!(
            w,
            "\nThe example block (b = 0.25 m, h = 1 m, Housner's ε) overturns with probability 1/2 \
             at PGA {mid:.3} g by this study's fit (band {lo:.3}–{hi:.3} g){}.",
            paper_median.map_or(String::new(), |g| format!("; by the paper's, at {g:.3} g"))
        );
    }
    let _ = writeln!(w);
}

fn convergence(w: &mut String, d: &StudyData) {
    let Some(conv) = &d.convergence else { return };
    let _ = writeln!(w, "## Capacity against IM-grid resolution\n");
    let summary = convergence_levels(conv);
    let levels: Vec<f64> = summary.iter().map(|c| c.levels).collect();
    let finest = levels.last().copied().unwrap_or(0.0);
    let _ = writeln!(
        w,
        "The capacity search repeated with {} levels; each record's η_c compared with the {finest}-level grid's.\n",
        levels.iter().map(|l| format!("{l}")).collect::<Vec<_>>().join(", ")
    );
    let _ = writeln!(w, "| levels | capacities that differ | mean abs. change | largest change | mean η_c,50 |\n|---:|---:|---:|---:|---:|");
    for c in &summary {
        let _ = writeln!(
            w,
            "| {} | {} of {} ({:.1} %) | {:.2e} | {:.3} | {:.4} |",
            c.levels,
            c.changed,
            c.total,
            100.0 * c.changed / c.total.max(1.0),
            c.mean_abs_change,
            c.max_abs_change,
            c.mean_q50
        );
    }
    let mean_q50 = |l: f64| {
        summary
            .iter()
            .find(|c| c.levels == l)
            .map_or(f64::NAN, |c| c.mean_q50)
    };
    let coarsest = levels.first().copied().unwrap_or(finest);
    let study = levels
        .iter()
        .copied()
        .find(|&l| l == d.plan.grid.count as f64)
        .unwrap_or(coarsest);
    let _ = writeln!(
        w,
        "\nA coarser grid can step over a thin island of overturning below the first one a finer grid finds, \
         so individual capacities move by much more than the refinement tolerance. The mean η_c,50 moves by \
         {:+.1} % from {study} levels (this study's grid) to {finest}, and by {:+.1} % from {coarsest} to {finest}: \
         capacities from a coarse grid are biased low.\n",
        100.0 * (mean_q50(finest) / mean_q50(study) - 1.0),
        100.0 * (mean_q50(finest) / mean_q50(coarsest) - 1.0),
    );
}

/// The style sheet of `report.html`: readable widths, tables with rules,
/// figures scaled to the page.
const STYLE: &str = "body{font-family:system-ui,-apple-system,'Segoe UI',sans-serif;\
max-width:60rem;margin:2rem auto;padding:0 1rem;line-height:1.5;color:#222}\
table{border-collapse:collapse;margin:1rem 0}th,td{border:1px solid #ccc;padding:.25rem .6rem}\
th{background:#f3f3f3}td{font-variant-numeric:tabular-nums}\
p>svg{display:block;max-width:100%;height:auto;margin:1.5rem auto .25rem}\
code{background:#f3f3f3;padding:0 .2rem}h1,h2{border-bottom:1px solid #ddd}";

/// The report as one self-contained HTML page: `markdown` (as [`render`]
/// makes it, images as `figures/<file>`) with every figure's image replaced
/// by its SVG (`svgs`: file name → SVG text) inline, and a style sheet.
/// Nothing is fetched: the page reads the same offline, mailed or moved.
/// An image without its SVG stays a link, so a missing figure shows as such.
pub fn render_html(title: &str, markdown: &str, svgs: &[(String, String)]) -> String {
    use pulldown_cmark::{html, CowStr, Event, Options, Parser, Tag, TagEnd};
    let parser = Parser::new_ext(markdown, Options::ENABLE_TABLES);
    let mut events = Vec::new();
    let mut in_image = false;
    for event in parser {
        match event {
            Event::Start(Tag::Image { ref dest_url, .. }) => {
                let file = dest_url.strip_prefix("figures/").unwrap_or(dest_url);
                match svgs.iter().find(|(f, _)| f == file) {
                    Some((_, svg)) => {
                        events.push(Event::Html(CowStr::from(svg.trim().to_string())));
                        in_image = true;
                    }
                    None => events.push(event),
                }
            }
            // The alt text of an inlined figure: its SVG has the title.
            Event::End(TagEnd::Image) if in_image => in_image = false,
            _ if in_image => {}
            _ => events.push(event),
        }
    }
    let mut body = String::new();
    html::push_html(&mut body, events.into_iter());
    let mut page = String::new();
    let _ = write!(
        page,
        "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n\
         <meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n\
         <title>{}</title>\n<style>{STYLE}</style>\n</head>\n<body>\n{body}</body>\n</html>\n",
        escape_html(title)
    );
    page
}

/// `&`, `<`, `>` and `"` as HTML entities.
fn escape_html(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            c => out.push(c),
        }
    }
    out
}

/// The report of a pulse map (`[pulses]` pipelines): settings, the walls
/// against the paper's closed forms, the modes met, and the figures.
pub fn render_pulses(d: &crate::study::PulseData, figures: &[Figure]) -> String {
    let mut md = String::new();
    let plan = &d.plan;
    heading(
        &mut md,
        "Pulse map",
        plan,
        &d.pipeline,
        &d.version,
        " (`pulse_walls.parquet`, `pulse_map.parquet`)",
    );
    if let Some(pp) = &plan.pulses {
        let shapes: Vec<String> = pp
            .shapes
            .iter()
            .map(|s| match s.beta() {
                Some(b) => format!("exp β = {b}"),
                None => "rect".into(),
            })
            .collect();
        let _ = writeln!(md, "## Settings\n");
        let _ = writeln!(md, "| setting | value |\n|---|---|");
        let _ = writeln!(
            md,
            "| pulse | {}; {} cycle, lobes of t_d = 1 s (so p = f) |",
            shapes.join("; "),
            pp.cycle.name()
        );
        let _ = writeln!(
            md,
            "| model | {:?}, overturning {} |",
            plan.model, plan.overturn
        );
        let _ = writeln!(md, "| ε | {} |", list(&pp.eps));
        let span = |v: &[f64], what: &str| {
            let end = |x: Option<&f64>| x.copied().unwrap_or(f64::NAN);
            format!(
                "{} {what} from {} to {}",
                v.len(),
                end(v.first()),
                end(v.last())
            )
        };
        let _ = writeln!(md, "| f | {} |", span(&pp.f, "values"));
        let _ = writeln!(md, "| map | {} |", span(&pp.eta, "η levels"));
        let _ = writeln!(md, "| walls | a 500-level log grid of η from 1 to 1e-5, the first overturning bisected to 1e-10 |\n");
    }
    let _ = writeln!(md, "## Runtime\n");
    let _ = writeln!(md, "| stage | time (s) |\n|---|---:|");
    for (s, t) in &d.stage_seconds {
        if let Some(t) = t {
            let _ = writeln!(md, "| {s} | {t:.2} |");
        }
    }
    let _ = writeln!(md);
    let _ = writeln!(md, "## Walls against the paper's closed forms\n");
    let _ = writeln!(md, "| family | equation | wall | walls compared | largest relative difference |\n|---|---|---|---:|---:|");
    let mut any = false;
    for (beta, eps, label) in d.families() {
        let diffs: Vec<f64> = d
            .walls_of(beta, eps)
            .filter_map(|w| w.closed_form_gap())
            .collect();
        let first = d.walls_of(beta, eps).find(|w| w.closed_form.is_some());
        if let (Some(w), false) = (first, diffs.is_empty()) {
            any = true;
            let _ = writeln!(
                md,
                "| {label} | {} | {} | {} | {:.1e} |",
                w.closed_form_equation.as_deref().unwrap_or(""),
                match w.closed_form_kind() {
                    Some(crate::pulse::WallKind::Any) => "η_w",
                    _ => "η_w,0 (Mode 0)",
                },
                diffs.len(),
                diffs.iter().cloned().fold(0.0, f64::max)
            );
        }
    }
    if !any {
        let _ = writeln!(
            md,
            "| (none: no closed form applies to this pulse, model and criterion) | | | | |"
        );
    }
    let _ = writeln!(md);
    let _ = writeln!(md, "## Modes of overturning met on the map\n");
    let _ = writeln!(
        md,
        "| family | points | safe | Mode 0 | Mode 1 | Mode 2+ |\n|---|---:|---:|---:|---:|---:|"
    );
    for (beta, eps, label) in d.families() {
        let cells: Vec<_> = d.cells_of(beta, eps).collect();
        let n = |keep: &dyn Fn(bool, i64) -> bool| {
            cells
                .iter()
                .filter(|c| keep(c.overturned, c.impacts))
                .count()
        };
        let _ = writeln!(
            md,
            "| {label} | {} | {} | {} | {} | {} |",
            cells.len(),
            n(&|o, _| !o),
            n(&|o, i| o && i == 0),
            n(&|o, i| o && i == 1),
            n(&|o, i| o && i >= 2)
        );
    }
    let _ = writeln!(md);
    figures_section(&mut md, figures);
    md
}

#[cfg(test)]
mod html_tests {
    use super::*;

    /// Figures are inlined where their image was, tables become tables,
    /// text is escaped, and a figure without its SVG stays an image.
    #[test]
    fn figures_inline_and_tables_render() {
        let md = "# Study `a<b`\n\n| x | y |\n|---|---:|\n| 1 | 2 |\n\n\
                  ![Title](figures/one.svg)\n\n*Caption*\n\n![Gone](figures/two.svg)\n";
        let svg = "<svg width=\"10\" height=\"10\" viewBox=\"0 0 10 10\" \
                   xmlns=\"http://www.w3.org/2000/svg\"><rect width=\"5\" height=\"5\"/></svg>";
        let page = render_html("Study & co", md, &[("one.svg".into(), svg.into())]);
        assert!(page.starts_with("<!DOCTYPE html>"));
        assert!(page.contains("<title>Study &amp; co</title>"));
        assert!(
            page.contains("<h1>Study <code>a&lt;b</code></h1>"),
            "{page}"
        );
        assert!(
            page.contains("<table>") && page.contains("<td style=\"text-align: right\">2</td>")
        );
        assert!(page.contains(&format!("<p>{svg}</p>")), "{page}");
        assert!(!page.contains("one.svg") && !page.contains("alt=\"Title\""));
        assert!(
            page.contains("<img src=\"figures/two.svg\" alt=\"Gone\""),
            "{page}"
        );
        // Nothing to fetch: no scripts, style sheets or images from elsewhere.
        assert!(
            !page.contains("<script") && !page.contains("<link") && !page.contains("src=\"http")
        );
    }
}
