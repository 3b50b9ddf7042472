//! `mapc sim --html`: for every fixture scenario the replay page is one file with no
//! http(s) reference, its data decode, and (when Chromium is installed) it loads without
//! console errors and two moments of the run look different where a robot moved.

use serde_json::Value;
use std::path::{Path, PathBuf};
use std::process::Command;

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

fn scenarios() -> Vec<PathBuf> {
    let mut v: Vec<PathBuf> = std::fs::read_dir(root().join("fixtures"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.to_str().unwrap().ends_with(".scenario.yaml"))
        .collect();
    v.sort();
    assert!(v.len() >= 4);
    v
}

fn chromium() -> Option<PathBuf> {
    ["chromium", "chromium-browser", "google-chrome"]
        .iter()
        .find_map(|n| {
            std::env::var_os("PATH").and_then(|p| {
                std::env::split_paths(&p)
                    .map(|d| d.join(n))
                    .find(|f| f.is_file())
            })
        })
}

const HEADLESS: [&str; 5] = [
    "--headless",
    "--no-sandbox",
    "--disable-gpu",
    "--hide-scrollbars",
    "--no-first-run",
];

/// The page's data (the JSON in `<script id="data">`).
fn data(html: &str) -> Value {
    let start = html
        .find("<script id=\"data\" type=\"application/json\">")
        .unwrap();
    let rest = &html[start..];
    let open = rest.find('>').unwrap() + 1;
    let close = rest.find("</script>").unwrap();
    serde_json::from_str(&rest[open..close]).expect("data is JSON")
}

/// A robot's kept samples: (seconds, x, y) decoded like replay.js does.
fn track(r: &Value, tick: f64) -> Vec<(f64, f64, f64)> {
    let first: Vec<i64> = serde_json::from_value(r["first"].clone()).unwrap();
    let d: Vec<i64> = serde_json::from_value(r["track"].clone()).unwrap();
    let (mut t, mut x, mut y) = (first[0], first[1], first[2]);
    let mut out = vec![(t as f64 * tick, x as f64 / 100.0, y as f64 / 100.0)];
    for c in d.chunks(4) {
        t += c[0];
        x += c[1];
        y += c[2];
        out.push((t as f64 * tick, x as f64 / 100.0, y as f64 / 100.0));
    }
    out
}

/// Value of a `[tick, v, ...]` change list at time `t`.
fn at(list: &Value, t: f64, tick: f64) -> i64 {
    let v: Vec<i64> = serde_json::from_value(list.clone()).unwrap();
    let mut out = -1;
    for c in v.chunks(2) {
        if c[0] as f64 * tick <= t {
            out = c[1];
        }
    }
    out
}

fn shot(chromium: &Path, url: &str, file: &Path) -> Vec<u8> {
    let o = Command::new(chromium)
        .args(HEADLESS)
        .arg("--window-size=1400,900")
        .arg("--virtual-time-budget=3000")
        .arg(format!("--screenshot={}", file.display()))
        .arg(url)
        .output()
        .unwrap();
    let bytes = std::fs::read(file)
        .unwrap_or_else(|_| panic!("no screenshot: {}", String::from_utf8_lossy(&o.stderr)));
    let mut d = png::Decoder::new(std::io::Cursor::new(bytes))
        .read_info()
        .unwrap();
    let mut buf = vec![0; d.output_buffer_size().unwrap()];
    let info = d.next_frame(&mut buf).unwrap();
    buf.truncate(info.buffer_size());
    assert_eq!(info.width, 1400);
    buf
}

#[test]
fn replay_pages_of_every_fixture_scenario() {
    let dir = tempfile::tempdir().unwrap();
    let browser = chromium();
    if browser.is_none() {
        println!("skipped: chromium not found (page checks in a browser)");
    }
    for scenario in scenarios() {
        let name = scenario.file_name().unwrap().to_str().unwrap().to_string();
        let html_path = dir.path().join(format!("{name}.html"));
        let o = Command::new(env!("CARGO_BIN_EXE_mapc"))
            .arg("sim")
            .arg(&scenario)
            .arg("--html")
            .arg(&html_path)
            .output()
            .unwrap();
        assert!(
            o.status.success(),
            "{name}: {}",
            String::from_utf8_lossy(&o.stderr)
        );
        let html = std::fs::read_to_string(&html_path).unwrap();
        let lower = html.to_ascii_lowercase();
        assert!(
            !lower.contains("http:") && !lower.contains("https:"),
            "{name}: the page references a URL"
        );
        assert!(!lower.contains("<script src") && !lower.contains("<link"));
        let d = data(&html);
        let tick = d["tick"].as_f64().unwrap();
        let robots = d["robots"].as_array().unwrap();
        assert!(!robots.is_empty(), "{name}: no robot");
        assert!(!d["levels"].as_array().unwrap().is_empty());

        // A moment when a robot moves at least 2 m within 20 s, on one level.
        let mut moment = None;
        'find: for r in robots {
            let tr = track(r, tick);
            for (i, &(t1, x1, y1)) in tr.iter().enumerate() {
                let t2 = t1 + 20.0;
                let Some(&(_, x2, y2)) = tr[i..].iter().take_while(|s| s.0 <= t2).last() else {
                    continue;
                };
                let (l1, l2) = (at(&r["level"], t1, tick), at(&r["level"], t2, tick));
                if (x2 - x1).hypot(y2 - y1) > 2.0 && l1 == l2 && l1 >= 0 {
                    moment = Some((t1, t2, l1 as usize));
                    break 'find;
                }
            }
        }
        let (t1, t2, level) = moment.unwrap_or_else(|| panic!("{name}: no robot moves"));
        let level_name = d["levels"][level]["name"].as_str().unwrap().to_string();

        let Some(browser) = &browser else { continue };
        let url = |t: f64| format!("file://{}#t={t}&level={level_name}", html_path.display());
        // Loads without console messages or errors, and says it is ready.
        let o = Command::new(browser)
            .args(HEADLESS)
            .args([
                "--enable-logging=stderr",
                "--v=0",
                "--virtual-time-budget=3000",
            ])
            .arg("--dump-dom")
            .arg(url(t1))
            .output()
            .unwrap();
        let dom = String::from_utf8_lossy(&o.stdout);
        let log = String::from_utf8_lossy(&o.stderr);
        let console: Vec<&str> = log.lines().filter(|l| l.contains("CONSOLE")).collect();
        assert!(console.is_empty(), "{name}: console output {console:#?}");
        assert!(dom.contains("data-ready=\"1\""), "{name}: page not ready");
        // People (the warehouse's crowd): one circle each, on the map.
        assert_eq!(
            d.get("people").is_some(),
            name.contains("warehouse"),
            "{name}: people in the page"
        );
        if let Some(p) = d.get("people") {
            let n = p["first"].as_array().unwrap().len();
            assert!(n > 0, "{name}: an empty crowd");
            assert_eq!(dom.matches("<circle class=\"person\"").count(), n, "{name}");
        }
        assert!(
            dom.contains("<pre id=\"errors\"></pre>"),
            "{name}: errors in the page: {}",
            dom.lines()
                .find(|l| l.contains("id=\"errors\""))
                .unwrap_or("")
        );
        // Two moments differ in the map area (left of the panels).
        let a = shot(browser, &url(t1), &dir.path().join("a.png"));
        let b = shot(browser, &url(t2), &dir.path().join("b.png"));
        let bpp = a.len() / (1400 * 900);
        let map_diff = (0..900)
            .flat_map(|y| (0..900).map(move |x| (y * 1400 + x) * bpp))
            .filter(|&i| a[i..i + 3] != b[i..i + 3])
            .count();
        assert!(
            map_diff > 30,
            "{name}: the map looks the same at {t1} s and {t2} s ({map_diff} pixels differ)"
        );
    }
}

/// Runs the hotel benchmark scenario for `until` and returns the page's size and, when
/// Chromium is installed, the time from navigation start until the page was ready (ms).
fn hotel_page(until: &str) -> Option<(u64, Option<u64>)> {
    let scenario = root().join("fixtures/bench/hotel_20_robots.scenario.yaml");
    if !root().join("../shared/maps/hotel").is_dir() {
        println!("skipped: ../shared not found");
        return None;
    }
    let dir = tempfile::tempdir().unwrap();
    let html = dir.path().join("hotel.html");
    let o = Command::new(env!("CARGO_BIN_EXE_mapc"))
        .arg("sim")
        .arg(&scenario)
        .args(["--until", until, "--html"])
        .arg(&html)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let size = std::fs::metadata(&html).unwrap().len();
    let ready = chromium().map(|c| {
        let o = Command::new(c)
            .args(HEADLESS)
            .args(["--virtual-time-budget=3000", "--dump-dom"])
            .arg(format!("file://{}#t=1800", html.display()))
            .output()
            .unwrap();
        let dom = String::from_utf8_lossy(&o.stdout);
        let at = dom.find("ready in ").expect("page ready") + "ready in ".len();
        dom[at..].split(' ').next().unwrap().parse::<u64>().unwrap()
    });
    Some((size, ready))
}

/// The acceptance figure: the 8 h, 20-robot hotel replay is under 20 MB (8.2 MB) and opens
/// in under 3 s (0.3-0.8 s from navigation start). About a minute in a debug build.
#[test]
fn hotel_8h_replay_under_20_mb_and_3_s() {
    let Some((size, ready)) = hotel_page("8h") else {
        return;
    };
    println!("8 h hotel replay: {size} bytes, ready in {ready:?} ms");
    assert!(size < 20_000_000, "{size} bytes");
    if let Some(ms) = ready {
        assert!(ms < 3000, "opened in {ms} ms");
    }
}
