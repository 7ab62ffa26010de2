//! How `risk --gmf` prints: each block's rate at each site, then how many
//! of the blocks fall in one event.

use rocking::ops::risk::EventsAssessment;

/// Prints the answer (JSON with `json`).
pub fn print(a: &EventsAssessment, json: bool) -> anyhow::Result<()> {
    for w in &a.warnings {
        eprintln!("warning: {w}");
    }
    if json {
        println!("{}", serde_json::to_string(a)?);
        return Ok(());
    }
    println!(
        "{} events over {} years ({}), in {} ({}); blocks at a site fall {}",
        a.events,
        a.eff_years,
        a.eff_years_from,
        a.im,
        a.unit,
        rocking::label::Label::label(a.together)
    );
    for b in &a.blocks {
        println!(
            "\nblock {}: fragility from {} ({}), median {}, β {}",
            b.block.name,
            b.fragility.source,
            b.fragility.fit,
            b.fragility
                .median
                .map_or("—".into(), |m| format!("{m:.4} {}", a.unit)),
            b.fragility.beta.map_or("—".into(), |v| format!("{v:.3}"))
        );
        if let Some(v) = &b.vector {
            println!(
                "  vector: ln PGA_c = … + {:.3} ln(PGV/PGA), β {:.3} over {} records",
                v.slope, v.beta, v.n
            );
        }
        println!(
            "  {:>5} {:>10} {:>10} {:>12} {:>12}{}",
            "site",
            "lon",
            "lat",
            "rate (1/yr)",
            "return (yr)",
            if b.vector.is_some() {
                "  rate by the vector"
            } else {
                ""
            }
        );
        for s in &b.sites {
            println!(
                "  {:>5} {:>10.4} {:>10.4} {:>12.3e} {:>12}{}",
                s.site,
                s.lon,
                s.lat,
                s.annual_rate,
                s.return_period_years.map_or("∞".into(), super::years),
                s.annual_rate_vector
                    .map_or(String::new(), |r| format!("  {r:>18.3e}"))
            );
        }
    }
    for b in a.blocks.iter().filter(|b| !b.states.is_empty()) {
        println!(
            "\nblock {}: damage states, rate at each site (1/yr)",
            b.block.name
        );
        for st in &b.states {
            let r: Vec<String> = st.annual_rates.iter().map(|r| format!("{r:.3e}")).collect();
            println!("  {:<16} {:<24} {}", st.state, st.criterion, r.join("  "));
        }
    }
    println!("\nhow many fall in one event:");
    for c in &a.counts {
        let at: Vec<String> = c
            .at_return_periods
            .iter()
            .map(|(t, n)| format!("{t:.0} yr: {n}"))
            .collect();
        println!(
            "  {:<10} {} items: expected {:.3e} per event, {:.3e} per year; at return periods {}",
            c.site.map_or("all sites".into(), |s| format!("site {s}")),
            c.items,
            c.expected_per_event,
            c.expected_per_year,
            at.join(", ")
        );
    }
    Ok(())
}
