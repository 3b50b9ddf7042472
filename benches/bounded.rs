//! Issue 18's adversarial shapes at 10^3, 10^4 and 10^5 elements: what `mapc check`
//! computes in process (parse, lower, transform, every validation pass) on each. The time
//! per shape should grow about linearly with n (slope of log time against log n near 1);
//! figures are in BENCHMARKS.md.
//!
//! - `scattered`: n waypoints at issue 18's density (20,000 in a 10 m room), n/2 random
//!   lanes;
//! - `line`: n waypoints on one vertical line 0.5 m apart, chained;
//! - `pairs`: n/2 separate two-waypoint lanes (n waypoints);
//! - `spot`: n/2 waypoints on one spot, each with a lane to its own far waypoint.
//!
//! Issue 12's huge building (`huge`: n waypoints, 2n lanes; 100,000 make 17 MB):
//! `huge_check` as above, `huge_nav` what `mapc nav` computes (parse, lower, every rule,
//! nav graphs rendered to bytes).
//!
//! Run with `cargo bench --bench bounded`. Maps are generated before timing.

#[path = "../tests/shapes/mod.rs"]
mod shapes;

use divan::{black_box, Bencher};

fn main() {
    divan::main();
}

const SIZES: [usize; 3] = [1_000, 10_000, 100_000];

fn check(b: Bencher, text: String) {
    b.counter(divan::counter::BytesCount::new(text.len()))
        .bench(|| {
            let parsed = mapc_frontend::parse_str("shape.building.yaml", black_box(&text));
            let building = parsed.building.expect("the shapes are well-formed");
            black_box(mapc_ir::validate(&building).len())
        });
}

#[divan::bench(args = SIZES, sample_count = 5, sample_size = 1)]
fn scattered(b: Bencher, n: usize) {
    // Issue 18's density: 20,000 waypoints in 100 m².
    let side = 10.0 * (n as f64 / 20_000.0).sqrt();
    check(b, shapes::scattered_in(n, n / 2, side));
}

#[divan::bench(args = SIZES, sample_count = 5, sample_size = 1)]
fn line(b: Bencher, n: usize) {
    check(b, shapes::line(n));
}

#[divan::bench(args = SIZES, sample_count = 5, sample_size = 1)]
fn pairs(b: Bencher, n: usize) {
    check(b, shapes::pairs(n / 2));
}

#[divan::bench(args = SIZES, sample_count = 5, sample_size = 1)]
fn spot(b: Bencher, n: usize) {
    check(b, shapes::spot(n / 2));
}

const HUGE: [usize; 2] = [10_000, 100_000];

#[divan::bench(args = HUGE, sample_count = 5, sample_size = 1)]
fn huge_check(b: Bencher, n: usize) {
    let text = shapes::huge(n);
    // The node limit follows the file size: the 17 MB map is read, not refused (E0002).
    let parsed = mapc_frontend::parse_str("huge.building.yaml", &text);
    assert!(!parsed.has_errors(), "{:?}", parsed.diagnostics.first());
    check(b, text);
}

#[divan::bench(args = HUGE, sample_count = 5, sample_size = 1)]
fn huge_nav(b: Bencher, n: usize) {
    let text = shapes::huge(n);
    b.counter(divan::counter::BytesCount::new(text.len()))
        .bench(|| {
            let parsed = mapc_frontend::parse_str("huge.building.yaml", black_box(&text));
            let building = parsed.building.expect("well-formed");
            let diags = mapc_ir::validate(&building);
            let files = mapc_backends::nav_graphs(&building);
            black_box((diags.len(), files))
        });
}
