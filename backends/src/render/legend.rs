//! The legend (what each mark means, only those present) and the scale bar.

use super::*;

/// The scale bar under the map: a round length about a fifth of the map's width.
pub(super) fn draw_scale_bar(s: &mut Svg, view: &View) {
    let target = view.width / 5.0 / view.k;
    let mag = 10f64.powf(target.log10().floor());
    let len = [1.0, 2.0, 5.0, 10.0]
        .iter()
        .map(|f| f * mag)
        .rfind(|&l| l <= target)
        .unwrap_or(mag);
    let x = view.left;
    let y = view.top + view.height + 22.0;
    let px = len * view.k;
    s.open(r#"g class="scale-bar""#);
    for i in 0..4 {
        let fill = if i % 2 == 0 { "#222222" } else { "#ffffff" };
        s.rect(
            x + px * i as f64 / 4.0,
            y,
            px / 4.0,
            6.0,
            &format!(r##"fill="{fill}" stroke="#222222" stroke-width="1""##),
        );
    }
    s.text((x, y + 20.0), 11.0, r##"fill="#222222""##, "0");
    s.text(
        (x + px, y + 20.0),
        11.0,
        r##"fill="#222222" text-anchor="middle""##,
        &format!("{} m", num(len)),
    );
    s.close("g");
}

/// The legend (translated to the legend column); returns its height.
pub(super) fn draw_legend(
    s: &mut Svg,
    b: &Building,
    p: &Present,
    diags: &[(&Diagnostic, Located)],
) -> f64 {
    let mut y = 16.0;
    s.text(
        (0.0, y),
        14.0,
        r##"font-weight="bold" fill="#222222""##,
        "Legend",
    );
    y += 10.0;
    let label = |s: &mut Svg, y: f64, text: &str| {
        s.text((34.0, y + 4.0), 11.0, r##"fill="#222222""##, text);
    };
    let mut item = |s: &mut Svg, draw: &dyn Fn(&mut Svg, f64), text: &str| {
        y += 18.0;
        draw(s, y);
        label(s, y, text);
    };
    if p.floors {
        item(
            s,
            &|s, y| {
                s.rect(
                    2.0,
                    y - 6.0,
                    24.0,
                    12.0,
                    &format!(
                        r#"fill="{}" stroke="{}""#,
                        colours::FLOOR,
                        colours::FLOOR_EDGE
                    ),
                )
            },
            "floor",
        );
    }
    if p.holes {
        item(
            s,
            &|s, y| {
                s.rect(
                    2.0,
                    y - 6.0,
                    24.0,
                    12.0,
                    r##"fill="#ffffff" stroke="#888888" stroke-dasharray="4 3""##,
                )
            },
            "hole",
        );
    }
    if p.walls {
        item(
            s,
            &|s, y| {
                s.line(
                    (2.0, y),
                    (26.0, y),
                    &format!(r#"stroke="{}" stroke-width="4""#, colours::WALL),
                )
            },
            "wall",
        );
    }
    if p.doors {
        item(
            s,
            &|s, y| {
                s.line(
                    (2.0, y + 5.0),
                    (26.0, y + 5.0),
                    &format!(r#"stroke="{}" stroke-width="3""#, colours::DOOR),
                );
                s.path(
                    &format!("M26 {} A24 12 0 0 0 2 {}", num(y + 5.0), num(y - 7.0)),
                    &format!(
                        r#"stroke="{}" fill="none" stroke-dasharray="3 2""#,
                        colours::DOOR
                    ),
                );
            },
            "door (swing / slide)",
        );
    }
    if p.lifts {
        item(
            s,
            &|s, y| {
                s.rect(
                    2.0,
                    y - 7.0,
                    24.0,
                    14.0,
                    &format!(r##"fill="{}" stroke="#555555""##, colours::SHAFT),
                );
                s.rect(
                    6.0,
                    y - 4.0,
                    16.0,
                    8.0,
                    &format!(r##"fill="{}" stroke="#444444""##, colours::CABIN),
                );
                s.line(
                    (26.0, y - 4.0),
                    (26.0, y + 4.0),
                    &format!(r#"stroke="{}" stroke-width="3""#, colours::LIFT_DOOR),
                );
            },
            "lift: shaft, cabin, door",
        );
    }
    if p.models {
        item(
            s,
            &|s, y| {
                s.rect(
                    8.0,
                    y - 6.0,
                    12.0,
                    12.0,
                    &format!(
                        r#"fill="{}" fill-opacity="0.35" stroke="{}""#,
                        colours::MODEL,
                        colours::MODEL
                    ),
                )
            },
            "model",
        );
    }
    for &g in &p.graphs {
        let colour = graph_colour(b, g);
        let name = b
            .graphs
            .iter()
            .find(|i| i.index == g)
            .map(|i| i.name.as_str())
            .filter(|n| !n.is_empty());
        let text = match name {
            Some(n) => format!("lanes of graph {g} ({n})"),
            None => format!("lanes of graph {g}"),
        };
        item(
            s,
            &|s, y| {
                s.line(
                    (2.0, y),
                    (26.0, y),
                    &format!(r#"stroke="{colour}" stroke-width="3""#),
                )
            },
            &text,
        );
    }
    if p.one_way {
        item(
            s,
            &|s, y| {
                s.line(
                    (2.0, y),
                    (26.0, y),
                    r##"stroke="#555555" stroke-width="2""##,
                );
                s.polygon(
                    &[(20.0, y), (10.0, y - 5.0), (10.0, y + 5.0)],
                    r##"fill="#555555""##,
                );
            },
            "one-way lane",
        );
    }
    if p.speed_limit {
        item(
            s,
            &|s, y| {
                s.line(
                    (2.0, y),
                    (26.0, y),
                    r##"stroke="#555555" stroke-width="2""##,
                );
                s.circle(
                    (14.0, y),
                    4.5,
                    r##"fill="#ffffff" stroke="#555555" stroke-width="1.5""##,
                );
            },
            "speed limit (m/s)",
        );
    }
    if p.waypoints {
        item(
            s,
            &|s, y| s.circle((14.0, y), 3.5, &format!(r#"fill="{}""#, colours::WAYPOINT)),
            "waypoint",
        );
    }
    for (i, &(text, letter, colour)) in ROLES.iter().enumerate() {
        if p.roles[i] {
            item(
                s,
                &|s, y| {
                    s.rect(
                        8.0,
                        y - 6.0,
                        12.0,
                        12.0,
                        &format!(r#"fill="{colour}" rx="2""#),
                    );
                    s.text(
                        (14.0, y + 3.5),
                        9.0,
                        r##"fill="#ffffff" text-anchor="middle" font-weight="bold""##,
                        letter,
                    );
                },
                text,
            );
        }
    }
    let severities = [
        (Severity::Error, "error", colours::ERROR),
        (Severity::Warning, "warning", colours::WARNING),
    ];
    for (sev, text, colour) in severities {
        if diags.iter().any(|(d, _)| d.severity == sev) {
            item(
                s,
                &|s, y| {
                    s.circle(
                        (14.0, y),
                        6.0,
                        &format!(r#"fill="{colour}" fill-opacity="0.25" stroke="{colour}" stroke-width="2""#),
                    )
                },
                &format!("diagnostic: {text}"),
            );
        }
    }
    y + 12.0
}
