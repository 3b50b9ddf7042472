//! Generated maps of the adversarial shapes of issue 18 (well-formed maps whose naive
//! checking is quadratic), shared by `tests/bounded_*.rs` and `benches/bounded.rs`. They
//! are generated, never committed: the large ones are megabytes.
#![allow(dead_code)] // each user takes the shapes it needs

use std::fmt::Write;

/// A small deterministic generator (64-bit LCG, high bits), so maps are the same on
/// every run without a dependency.
pub struct Lcg(u64);

impl Lcg {
    pub fn new(seed: u64) -> Self {
        Lcg(seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407))
    }
    pub fn next_u32(&mut self) -> u32 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (self.0 >> 32) as u32
    }
    /// Uniform in [0, 1).
    pub fn unit(&mut self) -> f64 {
        f64::from(self.next_u32()) / 4_294_967_296.0
    }
    /// Uniform in 0..n (n > 0).
    pub fn below(&mut self, n: usize) -> usize {
        (self.unit() * n as f64) as usize % n
    }
}

/// A one-level cartesian map with these vertices and (bidirectional, graph 0) lanes.
pub fn map(name: &str, vertices: &[(f64, f64)], lanes: &[(usize, usize)]) -> String {
    let mut s = String::with_capacity(40 * (vertices.len() + lanes.len()) + 200);
    let _ = writeln!(
        s,
        "name: {name}\ncoordinate_system: cartesian_meters\nlevels:\n  L1:"
    );
    s.push_str("    elevation: 0\n    vertices:\n");
    for (x, y) in vertices {
        let _ = writeln!(s, "      - [{x:.3}, {y:.3}, 0, \"\"]");
    }
    s.push_str("    lanes:\n");
    for (a, b) in lanes {
        let _ = writeln!(
            s,
            "      - [{a}, {b}, {{bidirectional: [4, true], graph_idx: [2, 0]}}]"
        );
    }
    s
}

/// `n` waypoints scattered over a 10 m × 10 m room, `lanes` random lanes between them
/// (issue 18: 20,000 and 10,000).
pub fn scattered(n: usize, lanes: usize) -> String {
    scattered_in(n, lanes, 10.0)
}

/// `n` waypoints scattered over a `side` × `side` room, `lanes` random lanes between them.
pub fn scattered_in(n: usize, lanes: usize, side: f64) -> String {
    let mut r = Lcg::new(18);
    let v: Vec<(f64, f64)> = (0..n).map(|_| (side * r.unit(), side * r.unit())).collect();
    let l: Vec<(usize, usize)> = (0..lanes)
        .map(|_| {
            let a = r.below(n);
            let mut b = r.below(n);
            if b == a {
                b = (a + 1) % n;
            }
            (a, b)
        })
        .collect();
    map("scattered", &v, &l)
}

/// `n` waypoints on one vertical line 0.5 m apart, chained (issue 18: 100,000).
pub fn line(n: usize) -> String {
    let v: Vec<(f64, f64)> = (0..n).map(|i| (0.0, 0.5 * i as f64)).collect();
    let l: Vec<(usize, usize)> = (1..n).map(|i| (i - 1, i)).collect();
    map("line", &v, &l)
}

/// `n` separate two-waypoint lanes, 2 m apart on a grid (issue 18: 30,000).
pub fn pairs(n: usize) -> String {
    let mut v = Vec::with_capacity(2 * n);
    for i in 0..n {
        let (x, y) = (2.0 * (i % 200) as f64, 2.0 * (i / 200) as f64);
        v.push((x, y));
        v.push((x + 1.0, y));
    }
    let l: Vec<(usize, usize)> = (0..n).map(|i| (2 * i, 2 * i + 1)).collect();
    map("pairs", &v, &l)
}

/// `n` waypoints on one spot (within 1 cm), each with a lane to its own waypoint on a
/// circle at least 5 m away, 0.2 m apart (issue 18: 3,000).
pub fn spot(n: usize) -> String {
    let mut v = Vec::with_capacity(2 * n);
    for i in 0..n {
        v.push((0.001 * (i % 10) as f64, 0.001 * (i / 10 % 10) as f64));
    }
    let r = (0.2 * n as f64 / std::f64::consts::TAU).max(5.0);
    for i in 0..n {
        let a = std::f64::consts::TAU * i as f64 / n as f64;
        v.push((r * a.cos(), r * a.sin()));
    }
    let l: Vec<(usize, usize)> = (0..n).map(|i| (i, n + i)).collect();
    map("spot", &v, &l)
}

/// `text` with CRLF line ends (as saved on Windows): read by the general YAML reader.
pub fn crlf(text: &str) -> String {
    text.replace('\n', "\r\n")
}

/// The `line` shape with its lists in flow style over many lines (`vertices: [` then one
/// entry a line), which only the general YAML reader takes.
pub fn line_flow(n: usize) -> String {
    let mut s = String::with_capacity(100 * n + 200);
    s.push_str("name: line\ncoordinate_system: cartesian_meters\nlevels:\n  L1:\n");
    s.push_str("    elevation: 0\n    vertices: [\n");
    for i in 0..n {
        let sep = if i + 1 < n { "," } else { "]" };
        let _ = writeln!(s, "      [0.000, {:.3}, 0, \"\"]{sep}", 0.5 * i as f64);
    }
    s.push_str("    lanes: [\n");
    for i in 1..n {
        let sep = if i + 1 < n { "," } else { "]" };
        let _ = writeln!(
            s,
            "      [{}, {i}, {{bidirectional: [4, true], graph_idx: [2, 0]}}]{sep}",
            i - 1
        );
    }
    s
}

/// The four shapes at the sizes of issue 18's acceptance, by name.
pub fn acceptance() -> Vec<(&'static str, String)> {
    vec![
        ("scattered", scattered(20_000, 10_000)),
        ("line", line(100_000)),
        ("pairs", pairs(30_000)),
        ("spot", spot(3_000)),
    ]
}

/// Issue 12's huge building: `n` waypoints scattered at 20,000 per hectare and `2n` lanes,
/// the first `n` chaining them, the rest random (100,000 and 200,000 make 17 MB).
pub fn huge(n: usize) -> String {
    let side = 100.0 * (n as f64 / 20_000.0).sqrt();
    let mut r = Lcg::new(12);
    let v: Vec<(f64, f64)> = (0..n).map(|_| (side * r.unit(), side * r.unit())).collect();
    let l: Vec<(usize, usize)> = (0..2 * n)
        .map(|i| {
            if i < n {
                (i, (i + 1) % n)
            } else {
                let a = r.below(n);
                let b = r.below(n);
                (a, if a == b { (a + 1) % n } else { b })
            }
        })
        .collect();
    map("huge", &v, &l)
}
