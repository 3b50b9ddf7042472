//! OUT/capacity.svg: throughput against fleet size, the mean over seeds as a line and the
//! spread (min to max) as a band, one line per value of the other axes; the knee of each
//! line marked and the resource that saturates there named from the reports' `bottleneck`.
//!
//! x is the number of robots of the run (from the report) when an axis sets a fleet's
//! `count` (of several, the one with most values; the others make lines), else the first
//! numeric axis other than `seed`. The knee is found with Kneedle
//! (Satopää et al., 2011): on the curve scaled to the unit square, the point farthest above
//! the chord from the first to the last point; a curve that stays within 0.1 of its chord
//! has no knee (throughput still grows in proportion). A dashed line in the same colour is
//! the reports' throughput bound (the mean over seeds of `bound_per_hour`): what no planning
//! could beat with that building, fleet and task mix (sim.md, Throughput bound).

use super::collect::{PlanFile, Row};
use mapc_backends::svg::Svg;
use std::collections::BTreeMap;
use std::fmt::Write;

pub(crate) struct Chart {
    pub svg: String,
    pub summary: String,
}

/// One point of a line: x and the throughputs of the runs there.
struct Point {
    x: f64,
    ys: Vec<f64>,
    mean: f64,
    min: f64,
    max: f64,
    /// The mean throughput bound of the runs there, when they have one.
    bound: Option<f64>,
}

struct Series {
    label: String,
    points: Vec<Point>,
    knee: Option<usize>,
    /// (place, share of the waiting of the runs at and beyond the knee).
    saturates: Option<(String, f64)>,
    /// All task waiting there by cause, largest first (shares).
    causes: Vec<(String, f64)>,
    /// What sets the throughput bound of the runs at the largest x (most of them).
    bound_by: Option<String>,
}

/// The report's waits by cause: (results.csv column, name).
const CAUSES: &[(&str, &str)] = &[
    ("wait_traffic_s", "traffic"),
    ("wait_lift_s", "lifts"),
    ("wait_door_s", "doors"),
    ("wait_workcell_s", "workcells"),
    ("wait_charging_s", "charging"),
];

fn is_count(path: &str) -> bool {
    let s: Vec<&str> = path.split('.').collect();
    s.len() == 3 && s[0] == "fleets" && s[2] == "count"
}

/// Kneedle on points sorted by x (at least 3).
pub(crate) fn knee(xs: &[f64], ys: &[f64]) -> Option<usize> {
    let n = xs.len();
    if n < 3 {
        return None;
    }
    let (x0, x1) = (xs[0], xs[n - 1]);
    let (lo, hi) = ys
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &y| {
            (a.min(y), b.max(y))
        });
    if x1 <= x0 || hi <= lo {
        return None;
    }
    let diff = |i: usize| (ys[i] - lo) / (hi - lo) - (xs[i] - x0) / (x1 - x0);
    let best = (1..n - 1).max_by(|&a, &b| diff(a).total_cmp(&diff(b)).then(b.cmp(&a)))?;
    (diff(best) >= 0.1).then_some(best)
}

pub(crate) fn capacity(plan: &PlanFile, rows: &[Row]) -> Option<Chart> {
    let axes = &plan.axes;
    // The fleet count axis with the most values (the first of equals) is x; the others
    // make lines.
    let distinct = |j: usize| {
        let mut v: Vec<&str> = rows.iter().map(|r| r.values[j].text.as_str()).collect();
        v.sort_unstable();
        v.dedup();
        v.len()
    };
    let count_axis = (0..axes.len())
        .filter(|&j| is_count(&axes[j].path))
        .max_by(|&a, &b| distinct(a).cmp(&distinct(b)).then(b.cmp(&a)));
    // The axes that decide x: that count axis and those zipped with it.
    let x_axes: Vec<usize> = match count_axis {
        Some(i) if axes[i].zipped => (0..axes.len()).filter(|&j| axes[j].zipped).collect(),
        Some(i) => vec![i],
        None => {
            let j = (0..axes.len()).find(|&j| {
                axes[j].path != "seed" && rows.iter().all(|r| r.values[j].value.is_number())
            })?;
            vec![j]
        }
    };
    let x_label = match count_axis {
        Some(_) => "robots".to_string(),
        None => axes[x_axes[0]].path.clone(),
    };
    let series_axes: Vec<usize> = (0..axes.len())
        .filter(|j| !x_axes.contains(j) && axes[*j].path != "seed")
        .collect();
    // series label -> x (as bits, for ordering) -> rows
    let mut groups: BTreeMap<Vec<String>, BTreeMap<u64, Vec<&Row>>> = BTreeMap::new();
    let mut order: Vec<Vec<String>> = Vec::new();
    for r in rows.iter().filter(|r| r.numbers.is_some()) {
        let x = match count_axis {
            Some(_) => r.number("robots")?,
            None => r.values[x_axes[0]].value.as_f64()?,
        };
        let key: Vec<String> = series_axes
            .iter()
            .map(|&j| format!("{}={}", axes[j].path, r.values[j].text))
            .collect();
        if !groups.contains_key(&key) {
            order.push(key.clone());
        }
        // Non-negative x: the bits of an f64 order like the number.
        groups
            .entry(key)
            .or_default()
            .entry(x.max(0.0).to_bits())
            .or_default()
            .push(r);
    }
    if groups.is_empty() {
        return None;
    }
    let mut series = Vec::new();
    for key in &order {
        let by_x = &groups[key];
        let points: Vec<Point> = by_x
            .iter()
            .map(|(&bits, rs)| {
                let ys: Vec<f64> = rs
                    .iter()
                    .filter_map(|r| r.number("throughput_per_hour"))
                    .collect();
                let mean = ys.iter().sum::<f64>() / ys.len().max(1) as f64;
                let min = ys.iter().copied().fold(f64::INFINITY, f64::min);
                let max = ys.iter().copied().fold(f64::NEG_INFINITY, f64::max);
                let bounds: Vec<f64> = rs
                    .iter()
                    .filter_map(|r| r.number("bound_per_hour"))
                    .collect();
                Point {
                    x: f64::from_bits(bits),
                    ys,
                    mean,
                    min,
                    max,
                    bound: (!bounds.is_empty())
                        .then(|| bounds.iter().sum::<f64>() / bounds.len() as f64),
                }
            })
            .collect();
        let xs: Vec<f64> = points.iter().map(|p| p.x).collect();
        let means: Vec<f64> = points.iter().map(|p| p.mean).collect();
        let k = knee(&xs, &means);
        // Where tasks waited longest in the runs at the knee (or at the largest x): the
        // reports' bottleneck places summed, and all waiting by cause.
        let at = k.map_or(xs[xs.len() - 1], |i| xs[i]);
        let mut waits: BTreeMap<String, f64> = BTreeMap::new();
        let mut total = 0.0;
        let mut causes: Vec<(&str, f64)> = CAUSES.iter().map(|&(_, c)| (c, 0.0)).collect();
        for (&bits, rs) in by_x {
            if f64::from_bits(bits) != at {
                continue;
            }
            for r in rs {
                for (i, (col, _)) in CAUSES.iter().enumerate() {
                    causes[i].1 += r.number(col).unwrap_or(0.0);
                }
                if let (Some(place), Some(w), Some(share)) = (
                    r.text("bottleneck"),
                    r.number("bottleneck_wait_s"),
                    r.number("bottleneck_share"),
                ) {
                    *waits.entry(place.to_string()).or_default() += w;
                    if share > 0.0 {
                        total += w / share;
                    }
                }
            }
        }
        let mut by: BTreeMap<&str, usize> = BTreeMap::new();
        for r in by_x.values().next_back().into_iter().flatten() {
            if let Some(b) = r.text("bound_limited_by") {
                *by.entry(b).or_default() += 1;
            }
        }
        let bound_by = by
            .into_iter()
            .max_by(|a, b| a.1.cmp(&b.1).then(b.0.cmp(a.0)))
            .map(|(b, _)| b.to_string());
        let saturates = waits
            .into_iter()
            .max_by(|a, b| a.1.total_cmp(&b.1).then(b.0.cmp(&a.0)))
            .map(|(p, w)| (p, if total > 0.0 { w / total } else { 0.0 }));
        let all: f64 = causes.iter().map(|c| c.1).sum();
        causes.retain(|c| c.1 > 0.0);
        causes.sort_by(|a, b| b.1.total_cmp(&a.1));
        for c in &mut causes {
            c.1 /= all;
        }
        series.push(Series {
            label: if key.is_empty() {
                "all runs".into()
            } else {
                key.join(", ")
            },
            points,
            knee: k,
            saturates,
            causes: causes
                .into_iter()
                .map(|(c, f)| (c.to_string(), f))
                .collect(),
            bound_by,
        });
    }
    let seeds = rows.iter().filter(|r| r.numbers.is_some()).count().max(1);
    let per_point = series
        .iter()
        .flat_map(|s| s.points.iter().map(|p| p.ys.len()))
        .max()
        .unwrap_or(1)
        .min(seeds);
    Some(Chart {
        svg: draw(&series, &x_label, per_point),
        summary: summary(&series, &x_label, per_point),
    })
}

fn summary(series: &[Series], x_label: &str, per_point: usize) -> String {
    let mut s = String::new();
    for se in series {
        let _ = writeln!(
            s,
            "{} (throughput per hour, mean over {per_point} run(s) per point):",
            se.label
        );
        let _ = writeln!(
            s,
            "  {:>8}  {:>9}  {:>9}  {:>9}  {:>9}",
            x_label, "mean", "min", "max", "bound"
        );
        for p in &se.points {
            let _ = writeln!(
                s,
                "  {:>8}  {:>9.2}  {:>9.2}  {:>9.2}  {:>9}",
                fmt_x(p.x),
                p.mean,
                p.min,
                p.max,
                p.bound.map_or("-".to_string(), |b| format!("{b:.2}"))
            );
        }
        match se.knee {
            Some(k) => {
                let _ = write!(
                    s,
                    "  knee at {} {x_label} ({:.2} tasks/h)",
                    fmt_x(se.points[k].x),
                    se.points[k].mean
                );
            }
            None => {
                let _ = write!(s, "  no knee: throughput grows across the range");
            }
        }
        match &se.saturates {
            Some((place, share)) => {
                let _ = writeln!(
                    s,
                    "; {} {place} ({:.0} % of the task waiting there)",
                    if se.knee.is_some() {
                        "saturates on"
                    } else {
                        "most waiting at"
                    },
                    100.0 * share
                );
                let by: Vec<String> = se
                    .causes
                    .iter()
                    .map(|(c, f)| format!("{c} {:.0} %", 100.0 * f))
                    .collect();
                let _ = writeln!(s, "  task waiting there by cause: {}", by.join(", "));
                if let (Some(by), Some(b)) = (&se.bound_by, se.points.last().and_then(|p| p.bound))
                {
                    let _ = writeln!(
                        s,
                        "  throughput bound at the largest fleet: {b:.2} tasks/h, set by {by}"
                    );
                }
            }
            None => {
                let _ = writeln!(s, "; no task waited");
            }
        }
    }
    s
}

fn fmt_x(x: f64) -> String {
    if x.fract() == 0.0 && x.abs() < 1e15 {
        format!("{}", x as i64)
    } else {
        format!("{x}")
    }
}

/// A round tick step giving about `n` ticks over `span`.
fn tick_step(span: f64, n: f64) -> f64 {
    let raw = (span / n).max(1e-9);
    let mag = 10f64.powf(raw.log10().floor());
    let f = raw / mag;
    let nice = if f <= 1.0 {
        1.0
    } else if f <= 2.0 {
        2.0
    } else if f <= 5.0 {
        5.0
    } else {
        10.0
    };
    nice * mag
}

const COLOURS: &[&str] = &[
    "#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e", "#8c564b", "#e377c2", "#17becf",
];

/// A coordinate with one decimal, as the chart writes them.
fn d1(v: f64) -> String {
    format!("{v:.1}")
}

fn draw(series: &[Series], x_label: &str, per_point: usize) -> String {
    let (w, h) = (940.0, 520.0);
    // One line above the plot per knee label, so that labels never cross a curve.
    let knees = series.iter().filter(|s| s.knee.is_some()).count() as f64;
    let (left, right, top, bottom) = (70.0, 330.0, 64.0 + 16.0 * knees, 60.0);
    let mut knee_row = 0.0;
    let (pw, ph) = (w - left - right, h - top - bottom);
    let all = series.iter().flat_map(|s| s.points.iter());
    let (mut x0, mut x1, mut y1) = (f64::INFINITY, f64::NEG_INFINITY, 0.0f64);
    for p in all {
        x0 = x0.min(p.x);
        x1 = x1.max(p.x);
        y1 = y1.max(p.max).max(p.bound.unwrap_or(0.0));
    }
    if x1 <= x0 {
        x0 -= 1.0;
        x1 += 1.0;
    }
    let ystep = tick_step(if y1 > 0.0 { y1 } else { 1.0 }, 5.0);
    let y1 = (y1 / ystep).ceil().max(1.0) * ystep;
    let xstep = tick_step(x1 - x0, 8.0).max(if x0.fract() == 0.0 { 1.0 } else { 0.0 });
    let sx = |x: f64| left + (x - x0) / (x1 - x0) * pw;
    let sy = |y: f64| top + ph - y / y1 * ph;
    let mut s = Svg::default();
    s.begin(
        "svg",
        &[
            ("xmlns", &"http://www.w3.org/2000/svg"),
            ("width", &w),
            ("height", &h),
            ("viewBox", &format_args!("0 0 {w} {h}")),
            ("font-family", &"DejaVu Sans, sans-serif"),
            ("font-size", &12),
        ],
    );
    s.empty("rect", &[("width", &w), ("height", &h), ("fill", &"white")]);
    s.leaf(
        "text",
        &[
            ("x", &left),
            ("y", &24),
            ("font-size", &16),
            ("font-weight", &"bold"),
        ],
        &format!("Capacity: throughput against {x_label}"),
    );
    s.leaf(
        "text",
        &[("x", &left), ("y", &42), ("fill", &"#555")],
        &format!(
            "line: mean over {per_point} run(s) per point (seeds); band: min to max; dashed: throughput bound"
        ),
    );
    // Grid and axes.
    s.begin("g", &[("class", &"axes"), ("stroke", &"#ccc")]);
    let mut y = 0.0;
    while y <= y1 + 1e-9 {
        s.empty(
            "line",
            &[
                ("x1", &left),
                ("y1", &d1(sy(y))),
                ("x2", &d1(left + pw)),
                ("y2", &d1(sy(y))),
            ],
        );
        y += ystep;
    }
    s.close("g");
    s.begin("g", &[("class", &"ticks"), ("fill", &"#333")]);
    let mut y = 0.0;
    while y <= y1 + 1e-9 {
        s.leaf(
            "text",
            &[
                ("x", &d1(left - 6.0)),
                ("y", &d1(sy(y) + 4.0)),
                ("text-anchor", &"end"),
            ],
            &fmt_tick(y),
        );
        y += ystep;
    }
    let mut x = (x0 / xstep).ceil() * xstep;
    while x <= x1 + 1e-9 {
        s.leaf(
            "text",
            &[
                ("x", &d1(sx(x))),
                ("y", &d1(top + ph + 18.0)),
                ("text-anchor", &"middle"),
            ],
            &fmt_tick(x),
        );
        x += xstep;
    }
    s.close("g");
    s.empty(
        "path",
        &[
            (
                "d",
                &format_args!("M{left} {top}V{:.1}H{:.1}", top + ph, left + pw),
            ),
            ("fill", &"none"),
            ("stroke", &"#333"),
        ],
    );
    // x counts every robot of the run, not only the fleet whose count varies.
    let x_title = if x_label == "robots" {
        "robots (all fleets)"
    } else {
        x_label
    };
    s.leaf(
        "text",
        &[
            ("x", &d1(left + pw / 2.0)),
            ("y", &d1(h - 16.0)),
            ("text-anchor", &"middle"),
        ],
        x_title,
    );
    s.leaf(
        "text",
        &[
            (
                "transform",
                &format_args!("translate(18 {:.1}) rotate(-90)", top + ph / 2.0),
            ),
            ("text-anchor", &"middle"),
        ],
        "tasks completed per hour",
    );
    // The lines.
    for (i, se) in series.iter().enumerate() {
        let c = COLOURS[i % COLOURS.len()];
        s.begin("g", &[("class", &"series"), ("data-series", &se.label)]);
        if se.points.iter().any(|p| p.max > p.min) {
            let mut d = String::new();
            for (k, p) in se.points.iter().enumerate() {
                let _ = write!(
                    d,
                    "{}{:.1} {:.1}",
                    if k == 0 { "M" } else { "L" },
                    sx(p.x),
                    sy(p.max)
                );
            }
            for p in se.points.iter().rev() {
                let _ = write!(d, "L{:.1} {:.1}", sx(p.x), sy(p.min));
            }
            d.push('Z');
            s.empty(
                "path",
                &[
                    ("class", &"spread"),
                    ("d", &d),
                    ("fill", &c),
                    ("fill-opacity", &0.18),
                    ("stroke", &"none"),
                ],
            );
        }
        let bound: Vec<String> = se
            .points
            .iter()
            .filter_map(|p| Some(format!("{:.1},{:.1}", sx(p.x), sy(p.bound?))))
            .collect();
        if !bound.is_empty() {
            s.empty(
                "polyline",
                &[
                    ("class", &"bound"),
                    ("points", &bound.join(" ")),
                    ("fill", &"none"),
                    ("stroke", &c),
                    ("stroke-width", &1.5),
                    ("stroke-dasharray", &"6 4"),
                ],
            );
        }
        let pts: Vec<String> = se
            .points
            .iter()
            .map(|p| format!("{:.1},{:.1}", sx(p.x), sy(p.mean)))
            .collect();
        s.empty(
            "polyline",
            &[
                ("class", &"mean"),
                ("points", &pts.join(" ")),
                ("fill", &"none"),
                ("stroke", &c),
                ("stroke-width", &2),
            ],
        );
        for p in &se.points {
            s.begin(
                "circle",
                &[
                    ("class", &"point"),
                    ("cx", &d1(sx(p.x))),
                    ("cy", &d1(sy(p.mean))),
                    ("r", &3.5),
                    ("fill", &c),
                ],
            );
            s.leaf(
                "title",
                &[],
                &format!(
                    "{} {}: {:.2} tasks/h (min {:.2}, max {:.2})",
                    fmt_x(p.x),
                    x_label,
                    p.mean,
                    p.min,
                    p.max
                ),
            );
            s.close("circle");
        }
        if let Some(k) = se.knee {
            let p = &se.points[k];
            let (kx, ky) = (sx(p.x), sy(p.mean));
            s.begin("g", &[("class", &"knee"), ("data-x", &fmt_x(p.x))]);
            s.empty(
                "line",
                &[
                    ("x1", &d1(kx)),
                    ("y1", &top),
                    ("x2", &d1(kx)),
                    ("y2", &d1(top + ph)),
                    ("stroke", &c),
                    ("stroke-dasharray", &"5 4"),
                ],
            );
            s.empty(
                "circle",
                &[
                    ("cx", &d1(kx)),
                    ("cy", &d1(ky)),
                    ("r", &7),
                    ("fill", &"none"),
                    ("stroke", &c),
                    ("stroke-width", &2),
                ],
            );
            let mut label = format!("knee: {} {}", fmt_x(p.x), x_label);
            if let Some((place, _)) = &se.saturates {
                label.push_str(&format!(", saturates on {place}"));
            }
            let anchor = if kx > left + pw * 0.6 { "end" } else { "start" };
            let dx = if anchor == "end" { -10.0 } else { 10.0 };
            knee_row += 1.0;
            s.leaf(
                "text",
                &[
                    ("x", &d1(kx + dx)),
                    ("y", &d1(top - 6.0 - 16.0 * (knee_row - 1.0))),
                    ("text-anchor", &anchor),
                    ("fill", &c),
                    ("font-weight", &"bold"),
                ],
                &label,
            );
            s.close("g");
        }
        s.close("g");
    }
    // Legend.
    let lx = left + pw + 20.0;
    s.begin("g", &[("class", &"legend")]);
    let mut ly = top + 6.0;
    for (i, se) in series.iter().enumerate() {
        let c = COLOURS[i % COLOURS.len()];
        s.empty(
            "line",
            &[
                ("x1", &lx),
                ("y1", &d1(ly)),
                ("x2", &d1(lx + 18.0)),
                ("y2", &d1(ly)),
                ("stroke", &c),
                ("stroke-width", &2),
            ],
        );
        s.leaf(
            "text",
            &[("x", &d1(lx + 24.0)), ("y", &d1(ly + 4.0))],
            &se.label,
        );
        ly += 18.0;
        let note = match (&se.knee, &se.saturates) {
            (Some(_), Some((p, share))) => {
                format!("saturates: {p} ({:.0} % of waiting)", 100.0 * share)
            }
            (None, Some((p, share))) => {
                format!("no knee; most waiting: {p} ({:.0} %)", 100.0 * share)
            }
            (Some(_), None) => "knee; no task waited".to_string(),
            (None, None) => "no knee".to_string(),
        };
        let small = |s: &mut Svg, ly: f64, text: &str| {
            s.leaf(
                "text",
                &[
                    ("x", &d1(lx + 24.0)),
                    ("y", &d1(ly + 2.0)),
                    ("fill", &"#555"),
                    ("font-size", &11),
                ],
                text,
            );
        };
        small(&mut s, ly, &note);
        ly += 16.0;
        if !se.causes.is_empty() {
            let by: Vec<String> = se
                .causes
                .iter()
                .map(|(c, f)| format!("{c} {:.0} %", 100.0 * f))
                .collect();
            small(&mut s, ly, &format!("waiting: {}", by.join(", ")));
            ly += 16.0;
        }
        if let (Some(by), Some(p)) = (&se.bound_by, se.points.last()) {
            if let Some(b) = p.bound {
                let text = format!("bound at {}: {b:.1} tasks/h, set by {by}", fmt_x(p.x));
                small(&mut s, ly, &text);
                ly += 16.0;
            }
        }
        ly += 8.0;
    }
    s.close("g");
    s.close("svg");
    s.out
}

fn fmt_tick(v: f64) -> String {
    let r = (v * 1000.0).round() / 1000.0;
    if r.fract() == 0.0 {
        format!("{}", r as i64)
    } else {
        format!("{r}")
    }
}

#[cfg(test)]
mod tests {
    use super::knee;

    #[test]
    fn kneedle_finds_the_bend_and_not_a_line() {
        // Grows by 10 per robot up to 6, then flat.
        let xs = [2.0, 4.0, 6.0, 8.0, 10.0];
        assert_eq!(knee(&xs, &[20.0, 40.0, 60.0, 61.0, 62.0]), Some(2));
        assert_eq!(knee(&xs, &[20.0, 40.0, 60.0, 80.0, 100.0]), None);
        assert_eq!(knee(&xs[..2], &[1.0, 2.0]), None);
    }
}
