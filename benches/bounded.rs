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
