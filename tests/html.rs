//! `report.html` in a real browser (`ROCKING_CHROMIUM=1`, which CI sets
//! after installing Debian's `chromium`). The paper study is run; a copy of
//! its page, with a probe script added at the end (the page itself has
//! none), is loaded in headless Chromium at 700 and 1,400 px, and the DOM
//! it dumps after layout says, for every inline figure and table, where the
//! browser laid it out, and for a figure whether it parsed it as SVG, the
//! box of what it drew and how many marks it holds. A figure left as a
//! broken `<img>` or parsed as text (escaped markup, a stray `<p>` inside
//! the SVG), cut off or squeezed, or a table running off the page, fails.

use std::fs;
use std::path::Path;
use std::process::Command;

use crate::util::{rocking, root, stderr, tempdir};

/// Measures, after layout, every `<svg>` and table, the viewport (without
/// its scroll bar), the body's content box and the page's full width into
/// `data-probe` on `<body>`.
const PROBE: &str = r#"<script>
const box = e => { const r = e.getBoundingClientRect(); return [r.left, r.right, r.width, r.height]; };
const figs = [...document.querySelectorAll('svg')].map(s => {
  const b = s.getBBox();
  const marks = s.querySelectorAll('polyline, path, circle, rect, line, polygon');
  const drawn = [...marks].filter(m => { const r = m.getBBox(); return r.width > 0 || r.height > 0; });
  return { svg: s instanceof SVGSVGElement, rect: box(s),
           view: [s.viewBox.baseVal.width, s.viewBox.baseVal.height],
           box: [b.width, b.height], marks: drawn.length,
           title: (s.querySelector('text') || {}).textContent || '' };
});
const tables = [...document.querySelectorAll('table')].map(t =>
  ({ rect: box(t), scroll: t.scrollWidth, client: t.clientWidth }));
document.body.setAttribute('data-probe', JSON.stringify({
  figures: figs, tables, images: document.querySelectorAll('img').length,
  viewport: document.documentElement.clientWidth,
  content: document.body.clientWidth, page: document.documentElement.scrollWidth }));
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

/// The probe's answer for `page` laid out `width` px wide.
fn probe(browser: &str, dir: &Path, page: &Path, width: u32) -> serde_json::Value {
    let profile = dir.join(format!("profile-{width}"));
    let dom = Command::new("timeout")
        .args([
            "120",
            browser,
            "--headless",
            "--no-sandbox",
            "--disable-gpu",
        ])
        .arg(format!("--user-data-dir={}", profile.display()))
        .arg(format!("--window-size={width},900"))
        .arg("--dump-dom")
        .arg(format!("file://{}", page.display()))
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
    serde_json::from_str(&json).unwrap()
}

/// The paper study's page at a phone-like 700 px and a desktop 1,400 px:
/// every figure the report lists drawn (an SVG, not a broken image or
/// escaped text, with dozens of marks over most of its canvas), whole
/// (inside the viewport, its aspect ratio kept, as wide as the text), and
/// every table inside the viewport with nothing cut off; the page never
/// scrolls sideways.
#[test]
fn report_html_of_the_paper_study_reads_at_700_and_1400_px_in_chromium() {
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
    let out = dir.path().join("out");
    let o = rocking(
        &root(),
        &[
            "run",
            "pipelines/paper.toml",
            "--outputs",
            out.to_str().unwrap(),
        ],
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let study = out.join("paper");
    let md = fs::read_to_string(study.join("report.md")).unwrap();
    let page = fs::read_to_string(study.join("report.html")).unwrap();
    let listed: Vec<&str> = md
        .lines()
        .filter(|l| l.starts_with("!["))
        .map(|l| l.rsplit("](figures/").next().unwrap().trim_end_matches(')'))
        .collect();
    // The bands' figures, the fit's and the convergence study's are among them.
    for f in [
        "fig08_capacity_bands_q50.svg",
        "fig10_regression_median.svg",
        "fragility_example.svg",
        "capacity_convergence.svg",
    ] {
        assert!(listed.contains(&f), "{f} not in {listed:?}");
    }
    // Self-contained: no figure file is referenced, nothing is fetched.
    assert!(!page.contains("figures/") && !page.contains("<script") && !page.contains("<link"));
    let probed = dir.path().join("probed.html");
    fs::write(&probed, page.replace("</body>", &format!("{PROBE}</body>"))).unwrap();
    for width in [700, 1400] {
        let probe = probe(browser, dir.path(), &probed, width);
        let at = |v: &serde_json::Value, i: usize| v[i].as_f64().unwrap();
        let viewport = probe["viewport"].as_f64().unwrap();
        let content = probe["content"].as_f64().unwrap();
        assert!(
            probe["page"].as_f64().unwrap() <= viewport,
            "{width} px: the page scrolls sideways: {probe}"
        );
        let figs = probe["figures"].as_array().unwrap();
        assert_eq!(
            figs.len(),
            listed.len(),
            "inline figures against the report's list: {probe}"
        );
        assert_eq!(probe["images"], 0, "a figure left as an image: {probe}");
        for (f, file) in figs.iter().zip(&listed) {
            assert!(
                f["svg"].as_bool().unwrap(),
                "{file}: not parsed as SVG: {f}"
            );
            let (left, right, w, h) = (
                at(&f["rect"], 0),
                at(&f["rect"], 1),
                at(&f["rect"], 2),
                at(&f["rect"], 3),
            );
            let (vw, vh) = (at(&f["view"], 0), at(&f["view"], 1));
            assert!(
                left >= 0.0 && right <= viewport,
                "{width} px, {file}: cut off: {f}"
            );
            assert!(
                w >= 0.95 * content.min(vw),
                "{width} px, {file}: {w} px of {content}: {f}"
            );
            assert!(
                (h / w - vh / vw).abs() < 0.01,
                "{width} px, {file}: squeezed: {f}"
            );
            // A chart is axes, ticks, grid lines and its series: dozens of
            // marks, drawn over most of its canvas.
            let (bw, bh) = (at(&f["box"], 0), at(&f["box"], 1));
            assert!(
                bw > 0.6 * vw && bh > 0.6 * vh,
                "{file}: draws a {bw} × {bh} box: {f}"
            );
            assert!(f["marks"].as_u64().unwrap() >= 20, "{file}: {f}");
        }
        let tables = probe["tables"].as_array().unwrap();
        assert!(tables.len() >= 8, "{probe}");
        for t in tables {
            let (left, right) = (at(&t["rect"], 0), at(&t["rect"], 1));
            assert!(
                left >= 0.0 && right <= viewport,
                "{width} px: a table runs off the page: {t}"
            );
            assert!(
                t["scroll"].as_f64().unwrap() <= t["client"].as_f64().unwrap() + 1.0,
                "{width} px: a table's content is cut: {t}"
            );
        }
    }
}
