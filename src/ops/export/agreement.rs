//! Where OpenQuake's job on the exported files and `risk` on the same
//! hazard differ, said with the export: what the job leaves beyond the
//! hazard's last IML, its midpoint sum on a coarse curve, and poes it reads
//! as 1. Each is checked for every state (a light state's gap is often the
//! largest), and said for the state where it is largest, with the others
//! where they too reach 1 %.

use super::request::{ExportedBlock, HazardSites};

/// Every check's warning for the block, if any state reaches 1 % in it.
pub(super) fn warnings(b: &ExportedBlock, h: &HazardSites, cut: Option<f64>) -> Vec<String> {
    type Check = fn(&ExportedBlock, &HazardSites, Option<f64>, usize) -> Option<(f64, String)>;
    let checks: [Check; 3] = [beyond_the_curve, coarse_sum, read_as_certain];
    let n = b.fragility.states.len();
    checks
        .iter()
        .filter_map(|check| {
            let found: Vec<(usize, f64, String)> = (0..n)
                .filter_map(|i| check(b, h, cut, i).map(|(size, text)| (i, size, text)))
                .collect();
            let (worst, _, text) = found.iter().max_by(|a, b| a.1.total_cmp(&b.1))?;
            let also: Vec<String> = found
                .iter()
                .filter(|f| f.0 != *worst)
                .map(|f| format!("`{}` {:.1} %", name(b, f.0), 100.0 * f.1))
                .collect();
            Some(match also.is_empty() {
                true => text.clone(),
                false => format!(
                    "{text}; for the other states, each at its worst site: {}",
                    also.join(", ")
                ),
            })
        })
        .collect()
}

/// State `state`'s name.
fn name(b: &ExportedBlock, state: usize) -> &str {
    b.fragility
        .states
        .get(state)
        .map_or("", |s| s.name.as_str())
}

/// OpenQuake's job counts nothing beyond the hazard's last IML, where
/// `risk` by default continues the curve (`--beyond extrapolate`): where
/// that part is 1 % or more of a block's rate of a state at a
/// site, the two answers differ by it, and the warning says so and how to
/// get OpenQuake's from `risk`. The share is `risk`'s own
/// ([`crate::risk::assess_above`]).
fn beyond_the_curve(
    b: &ExportedBlock,
    h: &HazardSites,
    cut: Option<f64>,
    state: usize,
) -> Option<(f64, String)> {
    let parts = parts(b, state)?;
    let shares: Vec<_> = h
        .curves
        .iter()
        .map(|(k, c)| {
            let r = site_risk(&parts, c, cut, crate::risk::Beyond::Extrapolate);
            (*k, r.share_beyond_last_iml, r.last_iml)
        })
        .collect();
    let &(site, share, last) = worst(&shares, |s| s.1)?;
    let text = format!(
        "OpenQuake's job counts nothing beyond the hazard's last IML ({last} {}): at site \
         {site}, {:.1} % of the rate of `{}` that `risk` gives by default comes from beyond \
         it{} (`risk --beyond stop` leaves it out, as the job does)",
        h.im.unit(),
        100.0 * share,
        name(b, state),
        others(shares.iter().map(|s| s.1), shares.len())
    );
    Some((share, text))
}

/// OpenQuake's job sums the hazard at its IMLs by a midpoint rule
/// ([`crate::export::reading::midpoint_rate`]), where `risk` integrates
/// the log-log curve between them: on a coarse curve (the 14 IMLs of a
/// typical hazard export) the job's rate of a block's state
/// differs from `risk --beyond stop`'s by several per cent. Where it
/// differs by 1 % or more at a site, the warning gives both rates and what
/// brings them together.
fn coarse_sum(
    b: &ExportedBlock,
    h: &HazardSites,
    cut: Option<f64>,
    state: usize,
) -> Option<(f64, String)> {
    let parts = parts(b, state)?;
    let gaps: Vec<_> = h
        .curves
        .iter()
        .filter_map(|(k, c)| {
            let job: f64 = parts
                .iter()
                .map(|(w, frag)| {
                    let p = |x| crate::ops::damage::probability_above(frag, x, cut);
                    w * crate::export::reading::midpoint_rate(c, p)
                })
                .sum();
            let ours = site_risk(&parts, c, cut, crate::risk::Beyond::Stop).annual_rate;
            // The job's IMLs: the file's, those of poe 1 and a closing 0 too.
            let imls = c.infinite.len() + c.iml.len() + usize::from(c.ends_at.is_some());
            (ours > 0.0).then(|| (*k, job / ours - 1.0, job, ours, imls))
        })
        .collect();
    let &(site, gap, job, ours, imls) = worst(&gaps, |g| g.1.abs())?;
    let text = format!(
        "OpenQuake's job sums the hazard at its {imls} IMLs by a midpoint rule, where `risk` \
         integrates the curve between them: at site {site} the job counts {job:.3e}/yr of \
         `{}`, {:.1} % {} the {ours:.3e}/yr of `risk --beyond stop`{} (give the hazard at \
         more IMLs: the gap falls with the square of their spacing, to 0.1 % at about 20 \
         per factor of 2)",
        name(b, state),
        100.0 * gap.abs(),
        if gap > 0.0 { "above" } else { "below" },
        others(gaps.iter().map(|g| g.1.abs()), gaps.len())
    );
    Some((gap.abs(), text))
}

/// The site where `size` is largest, where it reaches 1 %: the one a
/// warning names.
fn worst<T>(at: &[T], size: impl Fn(&T) -> f64) -> Option<&T> {
    at.iter()
        .max_by(|a, b| size(a).total_cmp(&size(b)))
        .filter(|x| size(x) >= 0.01)
}

/// ", and 1 % or more at N other sites of M" where a warning that names
/// its worst site holds at others too; nothing where it does not.
fn others(shares: impl Iterator<Item = f64>, sites: usize) -> String {
    match shares.filter(|&s| s >= 0.01).count() {
        0 | 1 => String::new(),
        2 => format!(", and 1 % or more at 1 other site of {sites}"),
        n => format!(", and 1 % or more at {} other sites of {sites}", n - 1),
    }
}

/// OpenQuake's job reads poes within 6e-8 of 1 as 1 and counts them at a
/// rate of 36.74/T ([`crate::export::reading`]), where `risk` reads the
/// curve as written: where the rate those IMLs add to the job's count of a
/// block's state is 1 % or more of `risk`'s rate at a site, the
/// warning says so and by how much.
fn read_as_certain(
    b: &ExportedBlock,
    h: &HazardSites,
    cut: Option<f64>,
    state: usize,
) -> Option<(f64, String)> {
    let parts = parts(b, state)?;
    let shares: Vec<_> = h
        .curves
        .iter()
        .filter_map(|(k, c)| {
            let mut excess = 0.0;
            let mut edge = None;
            for (w, frag) in &parts {
                let p = |x| crate::ops::damage::probability_above(frag, x, cut);
                let s = crate::export::reading::saturated(c, h.investigation_time, p)?;
                excess += w * s.excess_rate;
                edge = Some(s);
            }
            let s = crate::export::reading::Saturated {
                excess_rate: excess,
                ..edge?
            };
            Some((
                *k,
                excess / site_risk(&parts, c, cut, crate::risk::Beyond::Extrapolate).annual_rate,
                s,
            ))
        })
        .collect();
    let &(site, share, s) = worst(&shares, |s| s.1)?;
    let text = format!(
        "OpenQuake's job reads the hazard's poes in single precision: at site {site} its \
         first {} IMLs (to {} {}) read as poe = 1, which it counts at a rate of {:.3}/yr: \
         that adds {:.3e}/yr to the rate of `{}` the job counts, {:.1} % of `risk`'s rate{} \
         (give the job a curve whose poes fall below 1 - 6e-8 where the fragility is still \
         near 0)",
        s.imls,
        crate::im::level_text(s.up_to),
        h.im.unit(),
        s.certain_rate,
        s.excess_rate,
        name(b, state),
        100.0 * share,
        others(shares.iter().map(|s| s.1), h.curves.len()),
    );
    Some((share, text))
}

/// State `state`'s fragility of a block with its weight 1, or of each
/// branch of its tree with the branch's weight: the rate `risk --tree`
/// gives is their weighted sum, and so are its parts.
fn parts(b: &ExportedBlock, state: usize) -> Option<Vec<(f64, crate::risk::Fragility)>> {
    let of = |f: &crate::ops::damage::DamageFragility| f.states.get(state)?.fragility(f.method);
    match &b.tree {
        None => Some(vec![(1.0, of(&b.fragility)?)]),
        Some(t) => t
            .branches
            .iter()
            .map(|br| Some((br.weight, of(&br.fragility)?)))
            .collect(),
    }
}

/// `risk`'s answer at a site for `parts` (with `beyond` as its tail, the
/// export's cut): one block's, or a tree's mixture of its branches' as `risk --tree`
/// states it ([`crate::risk::mixed`]).
fn site_risk(
    parts: &[(f64, crate::risk::Fragility)],
    c: &crate::hazard::HazardCurve,
    cut: Option<f64>,
    beyond: crate::risk::Beyond,
) -> crate::risk::SiteRisk {
    let one = |f| crate::risk::assess_above(c, f, beyond, cut.unwrap_or(0.0));
    match parts {
        [(_, f)] => one(f),
        _ => crate::risk::mixed(&parts.iter().map(|(w, f)| (*w, one(f))).collect::<Vec<_>>()),
    }
}
