//! Mutation robustness: each demo map in `../shared/maps`, damaged in many deterministic
//! pseudo-random ways, must never make the frontend, the validation passes or the nav
//! backend panic or stall. As in `mapc check`, validation runs whenever the frontend returns
//! a building, even one with frontend errors.
//!
//! The maps are third-party data and are not in this repository; without `../shared` the
//! test prints `skipped: ../shared not found` and passes.
//!
//! A failure names the map, the mutation number and what the mutation did; set
//! `MAPC_MUTATION_DUMP=dir` to also write each failing input there.

use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

/// Mutations per map, the same for every map whatever its size, so that the 7 demo maps
/// always get 7 × 150 = 1050 mutants (at least 1000), independently of how fast the build
/// is. `MAPC_MUTATIONS=n` sets another count for every map.
const MUTATIONS_PER_MAP: usize = 150;

fn mutations_per_map() -> usize {
    std::env::var("MAPC_MUTATIONS")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(MUTATIONS_PER_MAP)
}

/// Budget for one parse + validate + nav of a mutated map.
const BUDGET: Duration = Duration::from_secs(2);

fn shared_maps() -> Option<Vec<PathBuf>> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/maps");
    let entries = std::fs::read_dir(&dir).ok()?;
    let mut maps: Vec<PathBuf> = entries
        .filter_map(|e| {
            let d = e.ok()?.path();
            let name = d.file_name()?.to_str()?.to_string();
            let f = d.join(format!("{name}.building.yaml"));
            f.is_file().then_some(f)
        })
        .collect();
    maps.sort();
    Some(maps)
}

/// xorshift64*: small, deterministic, good enough to pick mutation sites.
struct Rng(u64);

impl Rng {
    fn new(seed: u64) -> Self {
        Rng(seed.max(1))
    }
    fn next(&mut self) -> u64 {
        let mut x = self.0;
        x ^= x >> 12;
        x ^= x << 25;
        x ^= x >> 27;
        self.0 = x;
        x.wrapping_mul(0x2545_f491_4f6c_dd1d)
    }
    fn below(&mut self, n: usize) -> usize {
        if n == 0 {
            0
        } else {
            (self.next() % n as u64) as usize
        }
    }
    fn pick<'a, T>(&mut self, items: &'a [T]) -> &'a T {
        &items[self.below(items.len())]
    }
}

/// FNV-1a, to seed each map from its name.
fn fnv(s: &str) -> u64 {
    s.bytes().fold(0xcbf2_9ce4_8422_2325, |h, b| {
        (h ^ b as u64).wrapping_mul(0x0100_0000_01b3)
    })
}

/// Byte offset of a char boundary at or before `i`.
fn boundary(s: &str, mut i: usize) -> usize {
    i = i.min(s.len());
    while !s.is_char_boundary(i) {
        i -= 1;
    }
    i
}

/// Byte ranges of the numbers in `s` (an optional `-`, digits, an optional fraction).
fn numbers(s: &str) -> Vec<(usize, usize)> {
    let b = s.as_bytes();
    let mut out = Vec::new();
    let mut i = 0;
    while i < b.len() {
        if b[i].is_ascii_digit() && (i == 0 || !(b[i - 1].is_ascii_alphanumeric())) {
            let start = if i > 0 && b[i - 1] == b'-' { i - 1 } else { i };
            let mut j = i;
            while j < b.len() && (b[j].is_ascii_digit() || b[j] == b'.') {
                j += 1;
            }
            out.push((start, j));
            i = j;
        } else {
            i += 1;
        }
    }
    out
}

const NUMBER_REPLACEMENTS: &[&str] = &[
    "1e308",
    "-1e308",
    "1e999",
    "99999999999999999999999",
    "-1",
    "-12345",
    "0",
    "-0.0",
    ".nan",
    ".inf",
    "-.inf",
    "4294967296",
    "9223372036854775807",
    "-9223372036854775808",
    "0x7fffffffffffffff",
    "1.5",
    "\"7\"",
    "null",
    "[]",
    "{}",
];

const INSERTIONS: &[&str] = &[
    "[",
    "]",
    "{",
    "}",
    ":",
    ": ",
    "- ",
    "\t",
    "&a ",
    "*a",
    "*zz",
    "!!str ",
    "!!map ",
    "---\n",
    "...\n",
    "? ",
    "|",
    ">",
    "'",
    "\"",
    "#",
    "%YAML 1.2\n",
    "\u{0}",
    "\u{feff}",
    "é",
    "&x [*x]",
    "~",
];

/// Applies one random mutation; returns the new text and a description.
fn mutate(text: &str, rng: &mut Rng) -> (String, String) {
    let lines: Vec<&str> = text.split_inclusive('\n').collect();
    let n = lines.len();
    let join = |ls: &[&str]| ls.concat();
    match rng.below(12) {
        0 => {
            let i = rng.below(n);
            let mut ls = lines.clone();
            ls.remove(i);
            (join(&ls), format!("delete line {}", i + 1))
        }
        1 => {
            let i = rng.below(n);
            let mut ls = lines.clone();
            ls.insert(i, lines[i]);
            (join(&ls), format!("duplicate line {}", i + 1))
        }
        2 => {
            let (i, j) = (rng.below(n), rng.below(n));
            let mut ls = lines.clone();
            ls.swap(i, j);
            (join(&ls), format!("swap lines {} and {}", i + 1, j + 1))
        }
        3..=5 => {
            let nums = numbers(text);
            if nums.is_empty() {
                return (text.to_string(), "no number to replace".into());
            }
            let (s, e) = *rng.pick(&nums);
            let r = *rng.pick(NUMBER_REPLACEMENTS);
            (
                format!("{}{r}{}", &text[..s], &text[e..]),
                format!("replace number `{}` at byte {s} with `{r}`", &text[s..e]),
            )
        }
        6 => {
            let at = boundary(text, rng.below(text.len() + 1));
            (text[..at].to_string(), format!("truncate at byte {at}"))
        }
        7..=8 => {
            let at = boundary(text, rng.below(text.len() + 1));
            let ins = *rng.pick(INSERTIONS);
            (
                format!("{}{ins}{}", &text[..at], &text[at..]),
                format!("insert {ins:?} at byte {at}"),
            )
        }
        9 => {
            // Re-indent a line: the structure changes but stays plausible YAML.
            let i = rng.below(n);
            let mut ls: Vec<String> = lines.iter().map(|l| l.to_string()).collect();
            let l = &ls[i];
            let new = if rng.below(2) == 0 {
                format!("  {l}")
            } else {
                l.strip_prefix("  ").unwrap_or(l).to_string()
            };
            ls[i] = new;
            (ls.concat(), format!("re-indent line {}", i + 1))
        }
        10 => {
            let at = boundary(text, rng.below(text.len()));
            let end = boundary(text, at + 1 + rng.below(200));
            (
                format!("{}{}", &text[..at], &text[end.max(at)..]),
                format!("delete bytes {at}..{end}"),
            )
        }
        _ => {
            // Splice a random line into another place (moves a key to a wrong parent).
            let (i, j) = (rng.below(n), rng.below(n));
            let mut ls = lines.clone();
            let l = ls.remove(i);
            ls.insert(j.min(ls.len()), l);
            (
                join(&ls),
                format!("move line {} before line {}", i + 1, j + 1),
            )
        }
    }
}

/// How far a mutant got through the pipeline.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
struct Reached {
    /// The frontend returned a building, so the validation passes ran on it.
    validate: bool,
    /// The frontend reported no error, so the nav backend ran too.
    nav: bool,
}

enum Outcome {
    /// Finished in time.
    Ok(Duration, Reached),
    Panicked(String),
    Slow(Duration),
}

/// The pipeline under test: parse, then validate any building returned (as `mapc check`
/// does, frontend errors or not), then nav graphs for a building without frontend errors.
fn pipeline(name: &str, text: &str) -> Reached {
    let parsed = mapc_frontend::parse_str(name, text);
    let Some(b) = &parsed.building else {
        return Reached::default();
    };
    std::hint::black_box(mapc_ir::validate(b));
    let nav = !parsed.has_errors();
    if nav {
        std::hint::black_box(mapc_backends::nav_graphs(b));
    }
    Reached {
        validate: true,
        nav,
    }
}

fn run_once(f: &mut impl FnMut() -> Reached) -> Result<(Duration, Reached), String> {
    let t = Instant::now();
    let r = catch_unwind(AssertUnwindSafe(&mut *f));
    let took = t.elapsed();
    match r {
        Ok(nav) => Ok((took, nav)),
        Err(e) => Err(e
            .downcast_ref::<&str>()
            .map(|s| s.to_string())
            .or_else(|| e.downcast_ref::<String>().cloned())
            .unwrap_or_else(|| "non-string panic payload".into())),
    }
}

fn check(f: impl FnMut() -> Reached) -> Outcome {
    check_within(BUDGET, f)
}

fn check_within(budget: Duration, mut f: impl FnMut() -> Reached) -> Outcome {
    match run_once(&mut f) {
        Err(p) => Outcome::Panicked(p),
        Ok((d, nav)) if d <= budget => Outcome::Ok(d, nav),
        // Re-run once: a loaded machine can stall a thread; a real blow-up stays slow.
        Ok((d, _)) => match run_once(&mut f) {
            Err(p) => Outcome::Panicked(p),
            Ok((d2, nav)) if d2 <= budget => Outcome::Ok(d2, nav),
            Ok((d2, _)) => Outcome::Slow(d.min(d2)),
        },
    }
}

struct MapResult {
    failures: Vec<String>,
    count: usize,
    /// Mutated maps that still lowered to a building, so validation ran on them.
    reached_validate: usize,
    /// Mutated maps without frontend errors, so the nav backend ran on them.
    reached_nav: usize,
    slowest: Duration,
}

/// Mutates one map and runs the pipeline on every mutant.
fn fuzz_map(path: &Path) -> MapResult {
    let text = std::fs::read_to_string(path).unwrap();
    let name = path.file_name().unwrap().to_str().unwrap().to_string();
    let mut rng = Rng::new(fnv(&name));
    let dump = std::env::var_os("MAPC_MUTATION_DUMP").map(PathBuf::from);
    let mut failures = Vec::new();
    let mut slowest = Duration::ZERO;
    let (mut reached_validate, mut reached_nav) = (0, 0);
    let count = mutations_per_map();
    for i in 0..count {
        // Mostly single mutations, sometimes two or three stacked.
        let mut mutated = text.clone();
        let mut what = Vec::new();
        for _ in 0..1 + rng.below(3) / 2 + rng.below(4) / 3 {
            let (m, w) = mutate(&mutated, &mut rng);
            mutated = m;
            what.push(w);
        }
        let problem = match check(|| pipeline(&name, &mutated)) {
            Outcome::Ok(d, reached) => {
                slowest = slowest.max(d);
                reached_validate += usize::from(reached.validate);
                reached_nav += usize::from(reached.nav);
                None
            }
            Outcome::Panicked(p) => Some(format!("panicked: {p}")),
            Outcome::Slow(d) => Some(format!("took {d:?} (budget {BUDGET:?})")),
        };
        if let Some(problem) = problem {
            if let Some(dir) = &dump {
                let _ = std::fs::create_dir_all(dir);
                let _ = std::fs::write(dir.join(format!("{name}.{i}.yaml")), &mutated);
            }
            failures.push(format!(
                "{name} mutation #{i} ({}): {problem}",
                what.join("; ")
            ));
        }
    }
    MapResult {
        failures,
        count,
        reached_validate,
        reached_nav,
        slowest,
    }
}

#[test]
fn mutated_demo_maps_never_panic_or_stall() {
    let Some(mut maps) = shared_maps() else {
        println!("skipped: ../shared not found");
        return;
    };
    assert!(!maps.is_empty(), "../shared/maps holds no maps");
    // Largest first, so that the two workers finish at about the same time.
    maps.sort_by_cached_key(|m| std::cmp::Reverse(std::fs::metadata(m).map_or(0, |md| md.len())));
    let t = Instant::now();
    // Two worker threads (the CI machine has 2 cores); maps are handed out in order.
    let next = std::sync::atomic::AtomicUsize::new(0);
    let results = std::sync::Mutex::new(Vec::new());
    std::thread::scope(|s| {
        for _ in 0..2 {
            s.spawn(|| loop {
                let i = next.fetch_add(1, std::sync::atomic::Ordering::SeqCst);
                let Some(map) = maps.get(i) else { break };
                let r = fuzz_map(map);
                results.lock().unwrap().push((map.clone(), r));
            });
        }
    });
    let mut results = results.into_inner().unwrap();
    results.sort_by(|a, b| a.0.cmp(&b.0));
    let mut failures = Vec::new();
    let (mut total, mut reached_validate, mut reached_nav) = (0, 0, 0);
    for (map, r) in &results {
        eprintln!(
            "{}: {} mutations, {} validated, {} without frontend errors (nav ran), {} failure(s), slowest {:?}",
            map.file_name().unwrap().to_string_lossy(),
            r.count,
            r.reached_validate,
            r.reached_nav,
            r.failures.len(),
            r.slowest
        );
        total += r.count;
        reached_validate += r.reached_validate;
        reached_nav += r.reached_nav;
        failures.extend(r.failures.iter().cloned());
    }
    eprintln!("total {total} mutations in {:?}", t.elapsed());
    assert!(
        failures.is_empty(),
        "{} mutated input(s) broke mapc:\n{}",
        failures.len(),
        failures.join("\n")
    );
    // Some mutants must get through the frontend, or the later stages would never be
    // exercised.
    assert!(reached_validate > 0, "no mutated map reached validation");
    assert!(reached_nav > 0, "no mutated map reached the nav backend");
}

#[test]
fn mutations_are_deterministic_and_change_the_text() {
    let text = "name: x\nlevels:\n  L1:\n    vertices: [[1, 2, 0, a], [3.5, -4, 0, b]]\n";
    let run = || {
        let mut rng = Rng::new(fnv("t"));
        (0..50).map(|_| mutate(text, &mut rng)).collect::<Vec<_>>()
    };
    let a = run();
    assert_eq!(a, run());
    let changed = a.iter().filter(|(m, _)| m != text).count();
    assert!(
        changed >= 40,
        "only {changed} of 50 mutations changed the text"
    );
    assert_eq!(numbers(text).len(), 6);
}

#[test]
fn check_reports_panics_and_stalls() {
    // The harness must be able to fail: panics are caught and reported, not propagated.
    assert!(matches!(
        check(|| panic!("boom")),
        Outcome::Panicked(p) if p == "boom"
    ));
    assert!(matches!(
        check_within(Duration::from_millis(20), || {
            std::thread::sleep(Duration::from_millis(40));
            Reached::default()
        }),
        Outcome::Slow(_)
    ));
    let text = "name: x\nlevels:\n  L1:\n    vertices: [[0, 0, 0, a], [1, 0, 0, b]]\n    lanes: [[0, 1, {graph_idx: [2, 0]}]]\n";
    let all = Reached {
        validate: true,
        nav: true,
    };
    assert!(matches!(check(|| pipeline("ok", text)), Outcome::Ok(_, r) if r == all));
    assert!(matches!(
        check(|| pipeline("bad", "levels: ]")),
        Outcome::Ok(_, r) if r == Reached::default()
    ));
    // A frontend error with a building: validation runs, nav does not.
    let bad_lane = text.replace("[2, 0]", "[2, x]");
    let validate_only = Reached {
        validate: true,
        nav: false,
    };
    assert!(matches!(
        check(|| pipeline("bad lane", &bad_lane)),
        Outcome::Ok(_, r) if r == validate_only
    ));
}
