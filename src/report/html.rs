//! The report as one self-contained HTML page: the Markdown rendered, every
//! figure's SVG inline, a style sheet; nothing fetched.

use std::fmt::Write as _;

/// The style sheet of `report.html`: readable widths, tables with rules,
/// figures scaled to the page.
const STYLE: &str = "body{font-family:system-ui,-apple-system,'Segoe UI',sans-serif;\
max-width:60rem;margin:2rem auto;padding:0 1rem;line-height:1.5;color:#222}\
table{border-collapse:collapse;margin:1rem 0;font-size:.9em}\
th,td{border:1px solid #ccc;padding:.2rem .45rem}\
th{background:#f3f3f3}td{font-variant-numeric:tabular-nums}\
p>svg{display:block;max-width:100%;height:auto;margin:1.5rem auto .25rem}\
code{background:#f3f3f3;padding:0 .2rem;overflow-wrap:anywhere}h1,h2{border-bottom:1px solid #ddd}\
@media (max-width:50rem){body{margin:1rem auto;padding:0 .5rem}table{font-size:.78em}\
th,td{padding:.15rem .25rem}}";

/// The report as one self-contained HTML page: `markdown` (as [`render`](super::render)
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
