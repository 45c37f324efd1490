//! The same SVG picture in fewer bytes. plotters writes one element per line, each with its
//! whole style (`<rect x=".." y=".." width="4" height="4" fill="none" stroke="#1F77B4"/>`
//! for every marker of a curve). [`compact`] rewrites only what cannot change the picture:
//!
//! - `opacity="1"` (the default) is left out;
//! - a polyline's point repeated at once (the same pixel: plotters rounds to whole pixels) is
//!   written once;
//! - a circle of radius 0 (which SVG does not render) is left out;
//! - a run of consecutive elements with the same inherited style (fill, stroke, stroke width
//!   and the like, never `opacity`, which a group would apply to the group as a whole) is put
//!   in one `<g>` that carries that style once: each element inherits exactly the values it
//!   had.

/// Presentation attributes that SVG inherits from a parent `<g>` (SVG 1.1, "Property
/// index": all inherited), and so may move to a group.
const INHERITED: [&str; 11] = [
    "fill",
    "fill-opacity",
    "stroke",
    "stroke-width",
    "stroke-opacity",
    "stroke-linecap",
    "stroke-linejoin",
    "stroke-dasharray",
    "font-family",
    "font-size",
    "font-weight",
];

/// The same picture in fewer bytes (module documentation).
pub fn compact(svg: &str) -> String {
    let svg = svg.replace(" opacity=\"1\"", "");
    group_styles(&dedup_points(&svg))
}

/// A polyline's point repeated at once written once.
fn dedup_points(svg: &str) -> String {
    let mut out = String::with_capacity(svg.len());
    let mut rest = svg;
    while let Some(at) = rest.find("points=\"") {
        let (head, tail) = rest.split_at(at + "points=\"".len());
        out.push_str(head);
        let end = tail.find('"').unwrap_or(tail.len());
        out.push_str(&dedup(&tail[..end]));
        rest = &tail[end..];
    }
    out.push_str(rest);
    out
}

/// A list of points with each point repeated at once written once.
fn dedup(points: &str) -> String {
    let mut out = String::with_capacity(points.len());
    let mut last = None;
    for p in points.split_whitespace() {
        if last != Some(p) {
            out.push_str(p);
            out.push(' ');
            last = Some(p);
        }
    }
    out
}

/// One line holding one empty element: `<tag a="v" .../>`.
struct Element<'a> {
    tag: &'a str,
    attrs: Vec<(&'a str, &'a str)>,
}

fn parse(line: &str) -> Option<Element<'_>> {
    let body = line.trim().strip_prefix('<')?.strip_suffix("/>")?;
    let (tag, mut rest) = body.split_once(' ')?;
    if tag.is_empty() || !tag.chars().all(|c| c.is_ascii_alphabetic()) {
        return None;
    }
    let mut attrs = Vec::new();
    loop {
        rest = rest.trim_start();
        if rest.is_empty() {
            break;
        }
        let (name, after) = rest.split_once("=\"")?;
        if name.is_empty() || !name.chars().all(|c| c.is_ascii_alphanumeric() || c == '-' || c == ':') {
            return None;
        }
        let (value, after) = after.split_once('"')?;
        attrs.push((name, value));
        rest = after;
    }
    Some(Element { tag, attrs })
}

/// The element's inherited style (as written) and the element without it; `None` for a
/// line that is not one empty element, or draws nothing.
fn split(line: &str) -> Option<(String, String)> {
    let e = parse(line)?;
    let mut style = String::new();
    let mut own = format!("<{}", e.tag);
    for (name, value) in &e.attrs {
        let target = if INHERITED.contains(name) { &mut style } else { &mut own };
        target.push_str(&format!(" {name}=\"{value}\""));
    }
    own.push_str("/>");
    Some((style, own))
}

/// Drawn nothing: a circle of radius 0.
fn draws_nothing(line: &str) -> bool {
    parse(line).is_some_and(|e| e.tag == "circle" && e.attrs.iter().any(|&(n, v)| n == "r" && v == "0"))
}

fn group_styles(svg: &str) -> String {
    let mut out = String::with_capacity(svg.len());
    let lines: Vec<&str> = svg.split_inclusive('\n').filter(|l| !draws_nothing(l)).collect();
    let mut i = 0;
    while i < lines.len() {
        let Some((style, _)) = split(lines[i]).filter(|(s, _)| !s.is_empty()) else {
            out.push_str(lines[i]);
            i += 1;
            continue;
        };
        let mut j = i + 1;
        while j < lines.len() && split(lines[j]).is_some_and(|(s, _)| s == style) {
            j += 1;
        }
        if j - i < 2 {
            out.push_str(lines[i]);
        } else {
            out.push_str(&format!("<g{style}>\n"));
            for line in &lines[i..j] {
                if let Some((_, own)) = split(line) {
                    out.push_str(&own);
                    out.push('\n');
                }
            }
            out.push_str("</g>\n");
        }
        i = j;
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn drops_only_what_draws_nothing() {
        let svg = r##"<svg><polyline fill="none" opacity="1" stroke="#000000" points="1,2 1,2 3,4 3,4 3,4 1,2 "/><rect opacity="0.5" x="1"/><polyline points=""/></svg>"##;
        assert_eq!(
            compact(svg),
            r##"<svg><polyline fill="none" stroke="#000000" points="1,2 3,4 1,2 "/><rect opacity="0.5" x="1"/><polyline points=""/></svg>"##
        );
    }

    #[test]
    fn a_run_of_one_style_shares_a_group_and_opacity_stays_with_each_element() {
        let svg = "<svg width=\"10\" height=\"10\">\n\
<rect x=\"1\" y=\"2\" width=\"4\" height=\"4\" fill=\"none\" stroke=\"#1F77B4\"/>\n\
<rect x=\"3\" y=\"2\" width=\"4\" height=\"4\" fill=\"none\" stroke=\"#1F77B4\" opacity=\"0.5\"/>\n\
<circle cx=\"1\" cy=\"1\" r=\"0\" fill=\"none\" stroke=\"#1F77B4\"/>\n\
<line x1=\"0\" y1=\"0\" x2=\"1\" y2=\"1\" fill=\"none\" stroke=\"#1F77B4\"/>\n\
<line x1=\"0\" y1=\"0\" x2=\"1\" y2=\"1\" stroke=\"#000000\"/>\n\
<text x=\"1\" y=\"1\" fill=\"#000000\">\nlabel\n</text>\n</svg>\n";
        let expected = "<svg width=\"10\" height=\"10\">\n\
<g fill=\"none\" stroke=\"#1F77B4\">\n\
<rect x=\"1\" y=\"2\" width=\"4\" height=\"4\"/>\n\
<rect x=\"3\" y=\"2\" width=\"4\" height=\"4\" opacity=\"0.5\"/>\n\
<line x1=\"0\" y1=\"0\" x2=\"1\" y2=\"1\"/>\n\
</g>\n\
<line x1=\"0\" y1=\"0\" x2=\"1\" y2=\"1\" stroke=\"#000000\"/>\n\
<text x=\"1\" y=\"1\" fill=\"#000000\">\nlabel\n</text>\n</svg>\n";
        assert_eq!(compact(svg), expected);
    }

    /// Each drawn element with the style it ends up with (its own attributes over its
    /// ancestors'), in document order.
    fn effective(svg: &str) -> Vec<(String, Vec<(String, String)>)> {
        let doc = roxmltree::Document::parse(svg).unwrap();
        let mut out = Vec::new();
        for n in doc.descendants().filter(|n| n.is_element() && !matches!(n.tag_name().name(), "svg" | "g")) {
            let mut attrs: std::collections::BTreeMap<String, String> = std::collections::BTreeMap::new();
            for a in n.ancestors().filter(|a| a.is_element()).collect::<Vec<_>>().into_iter().rev() {
                for at in a.attributes() {
                    let inherited = INHERITED.contains(&at.name());
                    if a == n || inherited {
                        attrs.insert(at.name().to_string(), at.value().to_string());
                    }
                }
            }
            out.push((n.tag_name().name().to_string(), attrs.into_iter().collect()));
        }
        out
    }

    #[test]
    fn every_element_keeps_its_effective_style_on_a_real_figure() {
        use crate::figure::{Figure, Marker, Panel, Series};
        let x: Vec<f64> = (0..200).map(|i| i as f64 * 0.1).collect();
        let y = |k: f64| x.iter().map(|v| (v * k).sin() + 2.0).collect::<Vec<f64>>();
        let mut panel = Panel::new("p", "f", "c", (0.0, 20.0)).log_y();
        panel.series = vec![
            Series::points("a", x.clone(), y(1.0), 0, Marker::Square),
            Series::points("b", x.clone(), y(0.7), 1, Marker::Cross),
            Series::points("c", x.clone(), y(0.5), 2, Marker::Circle).filled(),
            Series::line("d", x.clone(), y(0.3), 3),
        ];
        let fig = Figure { id: "t".into(), title: "a figure".into(), caption: String::new(), panels: vec![panel] };
        let raw = crate::output::plot::to_svg_raw(&fig).unwrap();
        let small = compact(&raw);
        assert!(small.len() * 10 < raw.len() * 8, "{} of {} bytes", small.len(), raw.len());
        let drawn = |v: Vec<(String, Vec<(String, String)>)>| -> Vec<(String, Vec<(String, String)>)> {
            v.into_iter()
                .filter(|(tag, a)| !(tag == "circle" && a.iter().any(|(n, v)| n == "r" && v == "0")))
                .map(|(tag, a)| {
                    let a = a
                        .into_iter()
                        .filter(|(n, v)| !(n == "opacity" && v == "1"))
                        .map(|(n, v)| if n == "points" { (n, dedup(&v)) } else { (n, v) })
                        .collect();
                    (tag, a)
                })
                .collect()
        };
        let (before, after) = (drawn(effective(&raw)), drawn(effective(&small)));
        assert!(before.len() > 500, "{} elements", before.len());
        assert_eq!(after, before);
    }
}
