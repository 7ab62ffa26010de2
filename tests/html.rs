//! `report.html` in a real browser (`ROCKING_CHROMIUM=1`, which
//! CI sets after installing Debian's `chromium`). A small study with bands
//! and a fit is run; a copy of its page, with a probe script added at the
//! end (the page itself has none), is loaded in headless Chromium, and the
//! DOM it dumps after layout says, for every inline figure, whether the
//! browser parsed it as SVG, how wide it laid it out, the box of what it
//! drew and how many marks it holds. Every figure the report lists must be
//! drawn: an SVG element, laid out at a visible width, with marks that
//! cover a real area. A figure left as a broken `<img>` or parsed as text
//! (escaped markup, a stray `<p>` inside the SVG) fails.

use std::fs;
use std::process::Command;

use crate::util::{rocking, stderr, tempdir, write_pipeline};

/// Measures every `<svg>` and table after layout into `data-probe` on `<body>`.
const PROBE: &str = r#"<script>
const figs = [...document.querySelectorAll('svg')].map(s => {
  const b = s.getBBox();
  const marks = s.querySelectorAll('polyline, path, circle, rect, line, polygon');
  const drawn = [...marks].filter(m => { const r = m.getBBox(); return r.width > 0 || r.height > 0; });
  return { svg: s instanceof SVGSVGElement, width: s.getBoundingClientRect().width,
           box: [b.width, b.height], marks: drawn.length,
           title: (s.querySelector('text') || {}).textContent || '' };
});
document.body.setAttribute('data-probe', JSON.stringify({
  figures: figs, tables: document.querySelectorAll('table').length,
  images: document.querySelectorAll('img').length }));
</script>"#;

fn chromium() -> Option<&'static str> {
    ["chromium", "chromium-browser", "google-chrome"]
        .into_iter()
        .find(|c| {
            Command::new(c)
                .arg("--version")
                .output()
                .is_ok_and(|o| o.status.success())
        })
}

#[test]
fn every_figure_of_report_html_is_drawn_in_chromium() {
    if std::env::var("ROCKING_CHROMIUM").is_err() {
        eprintln!("skipped: set ROCKING_CHROMIUM=1 (with Debian's chromium installed) to run");
        return;
    }
    let Some(browser) = chromium() else {
        panic!(
            "ROCKING_CHROMIUM is set but no chromium is installed: \
             apt-get install --no-install-recommends chromium"
        );
    };
    let dir = tempdir();
    let pipe = write_pipeline(
        dir.path(),
        "page",
        "sets = [\"far-field\"]\n[blocks]\np = [1.0, 2.0, 4.0]\neps = [0.6, 0.75, 0.9]\n\
         [im]\ncount = 40\n[uncertainty]\nresamples = 200\n",
    );
    let out = dir.path().join("out");
    let o = rocking(
        dir.path(),
        &[
            "run",
            pipe.to_str().unwrap(),
            "--outputs",
            out.to_str().unwrap(),
        ],
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let study = out.join("page");
    let md = fs::read_to_string(study.join("report.md")).unwrap();
    let page = fs::read_to_string(study.join("report.html")).unwrap();
    let listed: Vec<&str> = md
        .lines()
        .filter(|l| l.starts_with("!["))
        .map(|l| l.rsplit("](figures/").next().unwrap().trim_end_matches(')'))
        .collect();
    // The bands' figures and the fit's are among them.
    for f in [
        "fig08_capacity_bands_q50.svg",
        "fig10_regression_median.svg",
        "fragility_example.svg",
    ] {
        assert!(listed.contains(&f), "{f} not in {listed:?}");
    }
    // Self-contained: no figure file is referenced, nothing is fetched.
    assert!(!page.contains("figures/") && !page.contains("<script") && !page.contains("<link"));
    let probed = dir.path().join("probed.html");
    fs::write(&probed, page.replace("</body>", &format!("{PROBE}</body>"))).unwrap();
    let profile = dir.path().join("profile");
    let dom = Command::new("timeout")
        .args([
            "120",
            browser,
            "--headless",
            "--no-sandbox",
            "--disable-gpu",
        ])
        .arg(format!("--user-data-dir={}", profile.display()))
        .args(["--window-size=1200,900", "--dump-dom"])
        .arg(format!("file://{}", probed.display()))
        .output()
        .unwrap();
    assert!(
        dom.status.success(),
        "{browser}: {}",
        String::from_utf8_lossy(&dom.stderr)
    );
    let dom = String::from_utf8(dom.stdout).unwrap();
    let attr = dom
        .split("data-probe=\"")
        .nth(1)
        .and_then(|rest| rest.split('"').next())
        .unwrap_or_else(|| {
            panic!(
                "no probe in the dumped DOM: {}",
                &dom[..dom.len().min(2000)]
            )
        });
    let json = attr
        .replace("&quot;", "\"")
        .replace("&amp;", "&")
        .replace("&lt;", "<")
        .replace("&gt;", ">");
    let probe: serde_json::Value = serde_json::from_str(&json).unwrap();
    let figs = probe["figures"].as_array().unwrap();
    assert_eq!(
        figs.len(),
        listed.len(),
        "inline figures against the report's list: {probe}"
    );
    assert_eq!(probe["images"], 0, "a figure left as an image: {probe}");
    assert!(probe["tables"].as_u64().unwrap() >= 5, "{probe}");
    for (f, file) in figs.iter().zip(&listed) {
        let width = f["width"].as_f64().unwrap();
        let (bw, bh) = (f["box"][0].as_f64().unwrap(), f["box"][1].as_f64().unwrap());
        // A chart is axes, ticks, grid lines and its series: dozens of marks,
        // drawn over most of its 900 × 620 canvas.
        assert!(
            f["svg"].as_bool().unwrap(),
            "{file}: not parsed as SVG: {f}"
        );
        assert!(width > 300.0, "{file}: laid out {width} px wide: {f}");
        assert!(
            bw > 600.0 && bh > 400.0,
            "{file}: draws a {bw} × {bh} box: {f}"
        );
        assert!(f["marks"].as_u64().unwrap() >= 20, "{file}: {f}");
    }
}
