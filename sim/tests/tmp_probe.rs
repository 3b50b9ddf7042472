use mapc_sim::{parse_scenario, simulate, RunOptions};
use std::path::Path;
#[test]
fn probe() {
    let file = std::env::var("PROBE_FILE").unwrap();
    let text = std::fs::read_to_string(&file).unwrap();
    let dir = Path::new(&file).parent().unwrap();
    let map = text.lines().find_map(|l| l.strip_prefix("map: ")).unwrap();
    let map = mapc_frontend::load(&dir.join(map.trim())).expect("map");
    let b = map.valid_building().unwrap();
    let (s, d) = parse_scenario(mapc_ir::FileId(1), &text, dir);
    let s = s.unwrap_or_else(|| panic!("{d:?}"));
    let r = simulate(b, &s, RunOptions::default()).unwrap();
    let done = r.tasks.iter().filter(|t| t.result == "completed").count();
    eprintln!("DONE {done} robots {}", r.robots.len());
    let f = &r.fleets[0];
    eprintln!(
        "UTIL {:.2} dist {:.0} waits {:?} traffic {:?}",
        f.utilisation, f.distance_m, r.waits, r.traffic
    );
    for x in &r.robots {
        eprintln!(
            "ROBOT {} {:.0} m busy {:.0}",
            x.name, x.distance_m, x.busy_s
        );
    }
}
