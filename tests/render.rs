//! `mapc render`: every level of every fixture and demo map (`../shared`, when present)
//! gives an SVG that parses and a PNG whose pixels show the walls and lanes where the map
//! has them; snapshots of two small fixtures' SVG; the command line; and Chromium (when
//! installed) loads every picture.
//!
//! After an intended change of the drawing: `INSTA_UPDATE=always cargo test --test render`.

use mapc_backends::render::{self, colours, RenderOptions};
use mapc_ir::{Building, Handle, Level};
use std::path::{Path, PathBuf};
use std::process::Command;

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

const FIXTURES: &[&str] = &[
    "two_level_clinic",
    "cartesian_warehouse",
    "wgs84_campus",
    "web_mercator_legacy",
    "legacy_2019",
    "lift_doors",
];

/// Fixture maps, then the demo maps when `../shared` exists.
fn maps() -> Vec<PathBuf> {
    let mut v: Vec<PathBuf> = FIXTURES
        .iter()
        .map(|n| root().join("fixtures").join(format!("{n}.building.yaml")))
        .collect();
    let shared = root().join("../shared/maps");
    if shared.is_dir() {
        let mut demo: Vec<PathBuf> = std::fs::read_dir(&shared)
            .unwrap()
            .map(|e| e.unwrap().path())
            .map(|d| {
                let n = d.file_name().unwrap().to_str().unwrap().to_string();
                d.join(format!("{n}.building.yaml"))
            })
            .collect();
        demo.sort();
        assert_eq!(demo.len(), 7, "the 7 demo maps");
        v.extend(demo);
    } else {
        println!("skipped: ../shared not found (demo maps)");
    }
    v
}

fn load(path: &Path) -> (Building, Vec<mapc_ir::Diagnostic>) {
    let parsed = mapc_frontend::load(path).unwrap();
    let b = parsed.building.expect("a building");
    let mut d = parsed.diagnostics;
    d.extend(mapc_ir::validate(&b));
    (b, d)
}

/// Checks that `svg` is well-formed XML with an `<svg>` root and returns its text nodes.
fn parse_svg(svg: &str) -> Vec<String> {
    use quick_xml::events::Event;
    let mut r = quick_xml::Reader::from_str(svg);
    let mut texts = Vec::new();
    let mut depth = 0i32;
    let mut root = None;
    let mut in_text = false;
    loop {
        match r
            .read_event()
            .unwrap_or_else(|e| panic!("SVG does not parse: {e}"))
        {
            Event::Start(e) => {
                if root.is_none() {
                    root = Some(String::from_utf8_lossy(e.name().as_ref()).into_owned());
                }
                in_text = e.name().as_ref() == b"text";
                depth += 1;
            }
            Event::End(_) => {
                in_text = false;
                depth -= 1;
            }
            Event::Text(t) if in_text => {
                texts.push(t.decode().unwrap().into_owned());
            }
            Event::Eof => break,
            _ => {}
        }
    }
    assert_eq!(depth, 0, "unbalanced SVG");
    assert_eq!(root.as_deref(), Some("svg"));
    texts
}

struct Picture {
    w: usize,
    h: usize,
    rgba: Vec<u8>,
}

impl Picture {
    fn decode(png_bytes: &[u8]) -> Picture {
        let mut d = png::Decoder::new(std::io::Cursor::new(png_bytes))
            .read_info()
            .unwrap();
        let mut buf = vec![0; d.output_buffer_size().unwrap()];
        let info = d.next_frame(&mut buf).unwrap();
        buf.truncate(info.buffer_size());
        let rgba = match info.color_type {
            png::ColorType::Rgba => buf,
            png::ColorType::Rgb => buf
                .chunks(3)
                .flat_map(|p| [p[0], p[1], p[2], 255])
                .collect(),
            other => panic!("unexpected PNG colour type {other:?}"),
        };
        Picture {
            w: info.width as usize,
            h: info.height as usize,
            rgba,
        }
    }
    fn at(&self, x: usize, y: usize) -> [u8; 3] {
        let i = (y * self.w + x) * 4;
        [self.rgba[i], self.rgba[i + 1], self.rgba[i + 2]]
    }
    /// Is a pixel within `tol` of `colour` in the (2r+1)² window around (x, y)?
    fn near(&self, p: (f64, f64), r: i64, colour: [u8; 3], tol: i32) -> bool {
        let (cx, cy) = (p.0.round() as i64, p.1.round() as i64);
        for y in cy - r..=cy + r {
            for x in cx - r..=cx + r {
                if x < 0 || y < 0 || x >= self.w as i64 || y >= self.h as i64 {
                    continue;
                }
                let c = self.at(x as usize, y as usize);
                if (0..3).all(|i| (c[i] as i32 - colour[i] as i32).abs() <= tol) {
                    return true;
                }
            }
        }
        false
    }
}

fn rgb(hex: &str) -> [u8; 3] {
    let v = u32::from_str_radix(&hex[1..], 16).unwrap();
    [(v >> 16) as u8, (v >> 8) as u8, v as u8]
}

/// The pixels of a level: not blank; the wall colour at most walls' middles; each graph's
/// colour near most of its lanes (40% along, clear of the arrows and speed marks).
fn check_pixels(b: &Building, level: Handle<Level>, pic: &Picture, name: &str) {
    let white = pic
        .rgba
        .chunks(4)
        .filter(|p| p[0] > 245 && p[1] > 245 && p[2] > 245)
        .count();
    let total = pic.w * pic.h;
    // Not blank: the campus (lanes only on a large site) has about 1% drawn pixels.
    assert!(
        total - white > 20_000,
        "{name}: the picture is blank ({white} of {total} pixels white)"
    );
    let view = render::level_view(b, level);
    let l = &b.levels[level];
    let wall = rgb(colours::WALL);
    let hits = l
        .walls
        .iter()
        .filter(|&&w| {
            let w = &b.walls[w];
            let m = b.vertices[w.start]
                .pos
                .plus(b.vertices[w.end].pos)
                .scale(0.5);
            pic.near(view.px(m), 1, wall, 40)
        })
        .count();
    assert!(
        hits * 10 >= l.walls.len() * 8,
        "{name}: wall colour at only {hits} of {} walls",
        l.walls.len()
    );
    for g in b.graph_indices() {
        // Lanes long enough on the picture not to hide under their waypoints' marks.
        let lanes: Vec<_> = l
            .lanes
            .iter()
            .filter(|&&h| {
                let lane = &b.lanes[h];
                let len = b.vertices[lane.start]
                    .pos
                    .minus(b.vertices[lane.end].pos)
                    .norm();
                lane.graph == g && len * view.k > 40.0
            })
            .collect();
        if lanes.is_empty() {
            continue;
        }
        let c = rgb(render::graph_colour(b, g));
        let hits = lanes
            .iter()
            .filter(|&&&h| {
                let lane = &b.lanes[h];
                let (a, z) = (b.vertices[lane.start].pos, b.vertices[lane.end].pos);
                let p = a.plus(z.minus(a).scale(0.4));
                pic.near(view.px(p), 6, c, 60)
            })
            .count();
        assert!(
            hits * 10 >= lanes.len() * 8,
            "{name}: colour of graph {g} near only {hits} of {} lanes",
            lanes.len()
        );
    }
}

#[test]
fn every_level_of_every_map_parses_and_shows_walls_and_lanes() {
    for path in maps() {
        let (b, diags) = load(&path);
        for (level, l) in b.levels.iter() {
            let name = format!("{} {}", path.display(), l.name);
            let opts = RenderOptions {
                graphs: None,
                diagnostics: Some(&diags),
            };
            let svg = render::render_level(&b, level, &opts);
            let texts = parse_svg(&svg);
            let title = format!("{}: level {}", b.name, l.name);
            assert!(texts.contains(&title), "{name}: no title text");
            assert!(texts.iter().any(|t| t == "Legend"), "{name}: no legend");
            assert!(
                texts.iter().any(|t| t.ends_with(" m")),
                "{name}: no scale bar"
            );
            for &v in &l.vertices {
                let vx = &b.vertices[v];
                if !vx.name.is_empty() && l.lanes.iter().any(|&h| b.lanes[h].start == v) {
                    assert!(texts.contains(&vx.name), "{name}: no text {}", vx.name);
                }
            }
            // Deterministic.
            assert_eq!(svg, render::render_level(&b, level, &opts), "{name}");
            // Pixels of the plain picture (diagnostic marks may cover lanes).
            let plain = render::render_level(&b, level, &RenderOptions::default());
            let png = render::svg_to_png(&plain).unwrap();
            check_pixels(&b, level, &Picture::decode(&png), &name);
        }
    }
}

#[test]
fn diagnostics_are_drawn_at_their_place_and_listed() {
    // A lane through a wall (a warning with a place on the map).
    let path = root().join("fixtures/lift_doors.building.yaml");
    let (b, mut diags) = load(&path);
    let level = b.levels.iter().next().unwrap().0;
    let some_lane = b.levels[level].lanes[0];
    diags.push(mapc_ir::Diagnostic::warning(
        "E0203",
        b.lanes.span(some_lane),
        "test diagnostic on a lane",
    ));
    let svg = render::render_level(
        &b,
        level,
        &RenderOptions {
            graphs: None,
            diagnostics: Some(&diags),
        },
    );
    let texts = parse_svg(&svg);
    let n = texts
        .iter()
        .find(|t| t.contains("test diagnostic on a lane"))
        .expect("listed under the map");
    let number = n.split('.').next().unwrap();
    assert!(
        texts.contains(&format!("{number} E0203")),
        "marked on the map"
    );
    let png = render::svg_to_png(&svg).unwrap();
    let pic = Picture::decode(&png);
    let lane = &b.lanes[some_lane];
    let m = b.vertices[lane.start]
        .pos
        .plus(b.vertices[lane.end].pos)
        .scale(0.5);
    let view = render::level_view(&b, level);
    assert!(pic.near(view.px(m), 10, rgb(colours::WARNING), 30));
    // Without diagnostics: no marks and no list.
    let plain = render::render_level(&b, level, &RenderOptions::default());
    assert!(!plain.contains("E0203"));
}

#[test]
fn graph_filter_keeps_only_those_lanes() {
    let path = root().join("fixtures/cartesian_warehouse.building.yaml");
    let (b, _) = load(&path);
    let level = b.levels.iter().next().unwrap().0;
    let all = render::render_level(&b, level, &RenderOptions::default());
    assert!(all.contains(r#"data-graph="0""#) && all.contains(r#"data-graph="1""#));
    let one = render::render_level(
        &b,
        level,
        &RenderOptions {
            graphs: Some(&[1]),
            diagnostics: None,
        },
    );
    assert!(one.contains(r#"data-graph="1""#));
    assert!(!one.contains(r#"data-graph="0""#));
}

#[test]
fn snapshots_of_two_small_fixtures() {
    for name in ["legacy_2019", "lift_doors"] {
        let (b, _) = load(&root().join(format!("fixtures/{name}.building.yaml")));
        for (level, l) in b.levels.iter() {
            let svg = render::render_level(&b, level, &RenderOptions::default());
            insta::assert_snapshot!(format!("render_{name}_{}", l.name), svg);
        }
    }
}

fn mapc(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_mapc"))
        .args(args)
        .output()
        .unwrap()
}

#[test]
fn command_line_writes_one_picture_per_level() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().to_str().unwrap();
    let map = root().join("fixtures/two_level_clinic.building.yaml");
    let map = map.to_str().unwrap();
    let o = mapc(&["render", map, "-o", out, "--format", "svg,png"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    // The manifest (what this run wrote, so that the next run removes stale pictures).
    let mut names: Vec<String> = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().file_name().into_string().unwrap())
        .filter(|n| !n.starts_with(".mapc-manifest"))
        .collect();
    names.sort();
    assert_eq!(
        names,
        [
            "two_level_clinic_L1.png",
            "two_level_clinic_L1.svg",
            "two_level_clinic_L2.png",
            "two_level_clinic_L2.svg"
        ]
    );
    let png = std::fs::read(dir.path().join("two_level_clinic_L2.png")).unwrap();
    assert!(png.starts_with(b"\x89PNG"));

    // One level; an unknown level is a usage error.
    let dir2 = tempfile::tempdir().unwrap();
    let out2 = dir2.path().to_str().unwrap();
    let o = mapc(&["render", map, "-o", out2, "--level", "L2"]);
    assert!(o.status.success());
    let pictures = |d: &Path| {
        std::fs::read_dir(d)
            .unwrap()
            .map(|e| e.unwrap().path())
            .filter(|p| p.extension().is_some_and(|x| x == "svg" || x == "png"))
            .collect::<Vec<_>>()
    };
    assert_eq!(pictures(dir2.path()).len(), 1);
    let o = mapc(&["render", map, "-o", out2, "--level", "L9"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("no level `L9`"));

    // A map with errors: nothing written, unless the pictures are to show the problems.
    let bad = root().join("fixtures/invalid/E0201-lane-self-loop.building.yaml");
    let bad = bad.to_str().unwrap();
    let dir3 = tempfile::tempdir().unwrap();
    let out3 = dir3.path().join("pics");
    let out3 = out3.to_str().unwrap();
    let o = mapc(&["render", bad, "-o", out3]);
    assert_eq!(o.status.code(), Some(1));
    assert!(!Path::new(out3).exists());
    let o = mapc(&["render", bad, "-o", out3, "--diagnostics"]);
    assert_eq!(o.status.code(), Some(1));
    let svg = pictures(Path::new(out3)).into_iter().next().unwrap();
    let text = std::fs::read_to_string(svg).unwrap();
    assert!(text.contains("E0201"));

    // At the user's lint levels: the error allowed, the pictures are written.
    let dir4 = tempfile::tempdir().unwrap();
    let o = mapc(&[
        "render",
        bad,
        "-o",
        dir4.path().to_str().unwrap(),
        "--allow",
        "E0201",
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(!pictures(dir4.path()).is_empty());
}

/// Headless Chromium loads every fixture's and demo map's SVG as an image (a broken SVG
/// fails to load), and a screenshot of one of them is not blank.
#[test]
fn chromium_renders_the_svgs() {
    let Some(chromium) = chromium() else {
        println!("skipped: chromium not found");
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let mut imgs = String::new();
    let mut count = 0;
    for path in maps() {
        let (b, diags) = load(&path);
        let levels: Vec<_> = b.levels.iter().map(|(h, _)| h).collect();
        let opts = RenderOptions {
            graphs: None,
            diagnostics: Some(&diags),
        };
        for f in render::render_svgs(&b, &levels, &opts) {
            let name = format!("{count}_{}", f.path.display());
            std::fs::write(dir.path().join(&name), &f.contents).unwrap();
            imgs.push_str(&format!(
                "<img src=\"{name}\" onload=\"ok(this)\" onerror=\"bad(this)\">\n"
            ));
            count += 1;
        }
    }
    let page = format!(
        "<!doctype html><html><body><div id=\"r\"></div>
<script>let n=0,b=[];function done(){{if(n+b.length=={count})document.getElementById('r').textContent='LOADED '+n+' BROKEN '+b.join(',');}}
function ok(i){{if(i.naturalWidth>0)n++;else b.push(i.src);done();}}function bad(i){{b.push(i.src);done();}}</script>
{imgs}</body></html>"
    );
    let html = dir.path().join("all.html");
    std::fs::write(&html, page).unwrap();
    let out = Command::new(&chromium)
        .args(headless_args())
        .arg("--virtual-time-budget=20000")
        .arg("--dump-dom")
        .arg(format!("file://{}", html.display()))
        .output()
        .unwrap();
    let dom = String::from_utf8_lossy(&out.stdout);
    assert!(
        dom.contains(&format!("LOADED {count} BROKEN <"))
            || dom.contains(&format!("LOADED {count} BROKEN ")),
        "chromium: {}\n{}",
        dom.lines()
            .find(|l| l.contains("LOADED"))
            .unwrap_or("no result"),
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(!dom.contains("BROKEN file"), "some SVG did not load");

    // A screenshot of one picture shows walls and floors, not a blank page.
    let svg = dir.path().join("0_two_level_clinic_L1.svg");
    let shot = dir.path().join("shot.png");
    let out = Command::new(&chromium)
        .args(headless_args())
        .arg(format!("--screenshot={}", shot.display()))
        .arg("--window-size=1200,900")
        .arg(format!("file://{}", svg.display()))
        .output()
        .unwrap();
    assert!(shot.exists(), "{}", String::from_utf8_lossy(&out.stderr));
    let pic = Picture::decode(&std::fs::read(&shot).unwrap_or_default());
    let wall = rgb(colours::WALL);
    let floor = rgb(colours::FLOOR);
    let count_of = |c: [u8; 3]| {
        pic.rgba
            .chunks(4)
            .filter(|p| (0..3).all(|i| (p[i] as i32 - c[i] as i32).abs() <= 8))
            .count()
    };
    assert!(count_of(wall) > 1000, "no walls in Chromium's picture");
    assert!(count_of(floor) > 10000, "no floor in Chromium's picture");
}

pub fn chromium() -> Option<PathBuf> {
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

pub fn headless_args() -> [&'static str; 5] {
    [
        "--headless",
        "--no-sandbox",
        "--disable-gpu",
        "--hide-scrollbars",
        "--no-first-run",
    ]
}
