//! A structure-aware generator of building maps for fuzzing: it reads choices from
//! `arbitrary::Unstructured` (random bytes in `tests/fuzz_maps.rs`) and writes well-formed `.building.yaml` text with levels,
//! vertices in adversarial layouts (scattered, on a line, on one spot, on a grid), lanes,
//! walls, doors, floors, models and lifts, names from a pool of hostile names (control and
//! bidi characters, path separators, `..`, very long), and an occasional bad index or
//! value, small maps and large ones.
#![allow(dead_code)] // users take the parts they need

use arbitrary::{Result, Unstructured};
use std::fmt::Write;

/// Names that have broken tools: path and shell specials, control and bidi characters.
const NAMES: &[&str] = &[
    "L1",
    "L2",
    "lift_1",
    "main door",
    "a b",
    "L0_tab\there",
    "new\nline",
    "x\u{202e}y",
    "\u{2066}iso",
    "../up",
    "/abs",
    "a/b",
    "a\\b",
    ".",
    "..",
    "",
    " lead",
    "trail ",
    "$x#y",
    "a:b",
    "*?[",
    "日本語",
    "OpenRobotics/Chair",
    "bell\u{7}",
    "cr\rhere",
    "nul\u{0}x",
];

/// A YAML double-quoted scalar of `s`.
fn quoted(s: &str) -> String {
    let mut out = String::from("\"");
    for c in s.chars() {
        match c {
            '"' => out.push_str("\\\""),
            '\\' => out.push_str("\\\\"),
            '\n' => out.push_str("\\n"),
            '\t' => out.push_str("\\t"),
            c if (c as u32) < 0x20 || c == '\u{7f}' => {
                let _ = write!(out, "\\x{:02x}", c as u32);
            }
            c => out.push(c),
        }
    }
    out.push('"');
    out
}

fn name(u: &mut Unstructured, fallback: &str) -> Result<String> {
    Ok(match u.int_in_range(0..=9u8)? {
        0..=5 => fallback.to_string(),
        6 => "n".repeat(u.int_in_range(1..=300)?),
        _ => u.choose(NAMES)?.to_string(),
    })
}

/// Vertex layouts: the shapes of issue 18 and ordinary ones.
fn positions(u: &mut Unstructured, n: usize) -> Result<Vec<(f64, f64)>> {
    let layout = u.int_in_range(0..=4u8)?;
    let mut v = Vec::with_capacity(n);
    for i in 0..n {
        let r = f64::from(u.arbitrary::<u16>()?) / 65535.0;
        let s = f64::from(u.arbitrary::<u16>()?) / 65535.0;
        v.push(match layout {
            0 => (10.0 * r, 10.0 * s),  // scattered in a room
            1 => (0.0, 0.5 * i as f64), // one vertical line
            2 => (0.001 * (i % 10) as f64, 0.001 * (i % 7) as f64), // one spot
            3 => ((i % 50) as f64, (i / 50) as f64), // a grid
            _ => (1000.0 * r - 500.0, 1000.0 * s - 500.0), // far apart
        });
    }
    Ok(v)
}

/// An index into `n` vertices, now and then out of range.
fn index(u: &mut Unstructured, n: usize) -> Result<usize> {
    if n == 0 || u.ratio(1u8, 50u8)? {
        return Ok(n + usize::from(u.arbitrary::<u8>()?));
    }
    u.choose_index(n)
}

/// A map generated from `u`; `max_vertices` bounds each level.
pub fn building(u: &mut Unstructured, max_vertices: usize) -> Result<String> {
    let mut s = String::new();
    let _ = writeln!(s, "name: {}", quoted(&name(u, "fuzzed")?));
    s.push_str("coordinate_system: cartesian_meters\nlevels:\n");
    let levels = u.int_in_range(1..=3usize)?;
    let mut level_names = Vec::new();
    for l in 0..levels {
        let mut ln = name(u, &format!("L{l}"))?;
        if level_names.contains(&ln) {
            ln = format!("L{l}");
        }
        level_names.push(ln.clone());
        let _ = writeln!(s, "  {}:", quoted(&ln));
        let _ = writeln!(s, "    elevation: {}", 4 * l);
        let big = u.ratio(1u8, 8u8)?;
        let n = if big {
            u.int_in_range(0..=max_vertices)?
        } else {
            u.int_in_range(0..=40usize.min(max_vertices))?
        };
        let pos = positions(u, n)?;
        s.push_str("    vertices:\n");
        for (i, (x, y)) in pos.iter().enumerate() {
            let vn = if u.ratio(1u8, 10u8)? {
                name(u, "")?
            } else {
                format!("v{i}")
            };
            let _ = writeln!(s, "      - [{x:.3}, {y:.3}, 0, {}]", quoted(&vn));
        }
        let edges = |u: &mut Unstructured, count: usize| -> Result<Vec<(usize, usize)>> {
            (0..count)
                .map(|_| Ok((index(u, n)?, index(u, n)?)))
                .collect()
        };
        let count = if big { n } else { u.int_in_range(0..=2 * n)? };
        let lanes = edges(u, count)?;
        s.push_str("    lanes:\n");
        for (a, b) in lanes {
            let g = u.int_in_range(0..=2u8)?;
            let bi = u.arbitrary::<bool>()?;
            let _ = writeln!(
                s,
                "      - [{a}, {b}, {{bidirectional: [4, {bi}], graph_idx: [2, {g}]}}]"
            );
        }
        let count = u.int_in_range(0..=n.min(200))?;
        let walls = edges(u, count)?;
        s.push_str("    walls:\n");
        for (a, b) in walls {
            let _ = writeln!(s, "      - [{a}, {b}, {{texture_name: [1, default]}}]");
        }
        let count = u.int_in_range(0..=n.min(20))?;
        let doors = edges(u, count)?;
        s.push_str("    doors:\n");
        for (i, (a, b)) in doors.into_iter().enumerate() {
            let dn = name(u, &format!("door_{l}_{i}"))?;
            let kind = u.choose(&["hinged", "sliding", "double_hinged", "double_sliding"])?;
            let _ = writeln!(
                s,
                "      - [{a}, {b}, {{name: [1, {}], type: [1, {kind}], motion_axis: [1, start], motion_degrees: [3, 90], motion_direction: [2, 1], right_left_ratio: [3, 1]}}]",
                quoted(&dn)
            );
        }
        if n >= 3 && u.arbitrary::<bool>()? {
            let k = u.int_in_range(3..=n.min(200))?;
            let ring: Vec<String> = (0..k)
                .map(|_| index(u, n).map(|i| i.to_string()))
                .collect::<Result<_>>()?;
            let _ = writeln!(
                s,
                "    floors:\n      - parameters: {{texture_name: [1, blue_linoleum]}}\n        vertices: [{}]",
                ring.join(", ")
            );
        }
        let models = u.int_in_range(0..=3usize)?;
        if models > 0 {
            s.push_str("    models:\n");
            for i in 0..models {
                let mn = name(u, &format!("model_{l}_{i}"))?;
                let x = f64::from(u.arbitrary::<u8>()?) / 10.0;
                let _ = writeln!(
                    s,
                    "      - {{name: {}, model_name: OpenRobotics/Chair, x: {x}, y: 1, z: 0, yaw: 0, static: true}}",
                    quoted(&mn)
                );
            }
        }
    }
    if u.arbitrary::<bool>()? {
        let lift = name(u, "lift_1")?;
        let _ = writeln!(
            s,
            "lifts:\n  {}:\n    depth: 2\n    width: 2\n    x: 5\n    y: 5\n    yaw: 0\n    \
             reference_floor_name: {}\n    doors:\n      d1:\n        door_type: 2\n        \
             motion_axis_orientation: 1.5708\n        width: 1\n        x: 1\n        y: 0\n    \
             level_doors:",
            quoted(&lift),
            quoted(&level_names[0])
        );
        for ln in &level_names {
            let _ = writeln!(s, "      {}: [d1]", quoted(ln));
        }
    }
    Ok(s)
}

#[cfg(test)]
mod tests {
    use saphyr::{LoadableYamlNode, YamlOwned};

    #[test]
    fn quoting_round_trips_through_yaml() {
        for n in super::NAMES {
            let text = format!("k: {}\n", super::quoted(n));
            let docs = YamlOwned::load_from_str(&text).unwrap();
            let k = docs[0].as_mapping_get("k").and_then(|v| v.as_str());
            assert_eq!(k, Some(*n), "{text}");
        }
    }
}
