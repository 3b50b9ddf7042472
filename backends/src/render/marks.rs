//! Diagnostics on the picture: a mark at each one's place and the list beside the map.

use super::*;

pub(super) fn severity_colour(s: Severity) -> &'static str {
    match s {
        Severity::Error => colours::ERROR,
        Severity::Warning => colours::WARNING,
    }
}

pub(super) fn draw_diagnostic_marks(s: &mut Svg, diags: &[(&Diagnostic, Located)], view: &View) {
    s.open(r#"g class="diagnostics""#);
    for (i, (d, at)) in diags.iter().enumerate() {
        let Some(p) = at.at else { continue };
        let colour = severity_colour(d.severity);
        let c = view.px(p);
        for &q in &at.labels {
            let lq = view.px(q);
            s.line(
                c,
                lq,
                &format!(r#"stroke="{colour}" stroke-width="1.5" stroke-dasharray="4 3""#),
            );
            s.circle(
                lq,
                6.0,
                &format!(r#"fill="none" stroke="{colour}" stroke-width="2""#),
            );
        }
        s.circle(
            c,
            9.0,
            &format!(r#"fill="{colour}" fill-opacity="0.25" stroke="{colour}" stroke-width="2.5""#),
        );
        s.text(
            (c.0 + 11.0, c.1 + 14.0),
            11.0,
            &format!(
                r##"fill="{colour}" font-weight="bold" stroke="#ffffff" stroke-width="3" paint-order="stroke""##
            ),
            &format!("{} {}", i + 1, d.code),
        );
    }
    s.close("g");
}

pub(super) fn draw_diagnostic_list(
    s: &mut Svg,
    diags: &[(&Diagnostic, Located)],
    top: f64,
    width: f64,
) {
    s.open(r#"g class="diagnostic-list""#);
    s.text(
        (MARGIN, top + LINE_H - 2.0),
        13.0,
        r##"font-weight="bold" fill="#222222""##,
        &format!("Diagnostics ({})", diags.len()),
    );
    let max_chars = ((width - 2.0 * MARGIN) / 6.2).max(20.0) as usize;
    for (i, (d, at)) in diags.iter().enumerate() {
        let sev = match d.severity {
            Severity::Error => "error",
            Severity::Warning => "warning",
        };
        let place = if at.at.is_some() {
            ""
        } else {
            " (no place on the map)"
        };
        let mut line = format!(
            "{}. {} {sev} [{}:{}] {}{place}",
            i + 1,
            d.code,
            d.span.line,
            d.span.col,
            d.message
        );
        if line.chars().count() > max_chars {
            line = line.chars().take(max_chars - 1).collect::<String>() + "…";
        }
        s.text(
            (MARGIN, top + LINE_H * (i as f64 + 2.0) - 2.0),
            11.0,
            &format!(r#"fill="{}""#, severity_colour(d.severity)),
            &line,
        );
    }
    s.close("g");
}
