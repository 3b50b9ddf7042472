//! `mapc lsp` under a real editor: headless Neovim (Debian's `neovim`) with its built-in
//! LSP client opens a map, and the diagnostics it shows are checked, before and after an
//! edit in the buffer (which Neovim sends as an incremental change).

use std::path::Path;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

#[test]
fn neovim_shows_diagnostics() {
    if Command::new("nvim").arg("--version").output().is_err() {
        println!("skipped: nvim not found");
        return;
    }
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let dir = tempfile::tempdir().expect("tempdir");
    let map = dir.path().join("m.building.yaml");
    std::fs::copy(root.join("fixtures/lsp/lsp_test.building.yaml"), &map).unwrap();
    let out = dir.path().join("diagnostics.txt");
    let mut child = Command::new("nvim")
        .args(["--headless", "--clean", "-n"])
        .arg(&map)
        .arg("-c")
        .arg(format!(
            "luafile {}",
            root.join("tests/nvim/check_diagnostics.lua").display()
        ))
        .env("MAPC", env!("CARGO_BIN_EXE_mapc"))
        .env("OUT", &out)
        .current_dir(dir.path())
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .spawn()
        .expect("nvim starts");
    let deadline = Instant::now() + Duration::from_secs(60);
    let status = loop {
        if let Some(s) = child.try_wait().unwrap() {
            break s;
        }
        if Instant::now() > deadline {
            let _ = child.kill();
            panic!("nvim did not finish in 60 s");
        }
        std::thread::sleep(Duration::from_millis(50));
    };
    assert!(status.success(), "nvim: {status}");
    let got = std::fs::read_to_string(&out).expect("the script wrote its result");
    // Lines and columns are Neovim's (1-based); severity 1 error, 2 warning.
    let want = "\
edited 13:9 W0208 2
edited 14:9 W0203 2
edited 18:9 W0207 2
edited 20:9 E0501 1
open 13:9 W0208 2
open 14:9 E0201 1
open 15:9 W0203 2
open 19:9 W0207 2
open 21:9 E0501 1
";
    let mut lines: Vec<&str> = got.lines().collect();
    lines.sort();
    assert_eq!(lines.join("\n") + "\n", want, "as Neovim shows them");
}
