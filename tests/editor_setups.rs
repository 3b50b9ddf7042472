//! The editor set-ups of docs/editors.md, tried in the real editors: each test loads the
//! set-up from `editors/` unchanged into the editor (Emacs with eglot, Vim with ALE, VS
//! Code with the extension packaged from editors/vscode), with `mapc` on `PATH` (VS Code:
//! in the `mapc.path` setting) as a user has it, opens a map with problems, and checks the
//! diagnostics the editor shows (line, column, code, severity), before and after an edit
//! that the editor sends to the server, and where its go-to-definition lands. The driving scripts are in `tests/<editor>/`.
//! Neovim's built-in client is tried by tests/nvim_lsp.rs.

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// What every editor shows for fixtures/lsp/lsp_test.building.yaml (1-based lines and
/// columns): the diagnostics on opening it; where going to the definition of the `4` of
/// lane `[1, 4, ...]` lands (vertex 4, the second `pantry`); the diagnostics after deleting
/// its self-loop lane `[3, 3, ...]` (line 14): the self-loop's E0201 goes, and the
/// diagnostics below it move up a line.
const WANT: &str = "\
open 13:9 W0208 warning
open 14:9 E0201 error
open 15:9 W0203 warning
open 19:9 W0207 warning
open 21:9 E0501 error
definition 21:9
edited 13:9 W0208 warning
edited 14:9 W0203 warning
edited 18:9 W0207 warning
edited 20:9 E0501 error
";

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

/// `PATH` with the directory of the mapc under test first, as the set-ups run `mapc`.
fn path_with_mapc() -> std::ffi::OsString {
    let bin = Path::new(env!("CARGO_BIN_EXE_mapc")).parent().unwrap();
    let mut dirs = vec![bin.to_path_buf()];
    dirs.extend(std::env::split_paths(
        &std::env::var_os("PATH").unwrap_or_default(),
    ));
    std::env::join_paths(dirs).unwrap()
}

/// A temporary home with a copy of the fixture map; returns (dir, map, result file).
fn workspace() -> (tempfile::TempDir, PathBuf, PathBuf) {
    let dir = tempfile::tempdir().expect("tempdir");
    let map = dir.path().join("m.building.yaml");
    std::fs::copy(root().join("fixtures/lsp/lsp_test.building.yaml"), &map).unwrap();
    let out = dir.path().join("diagnostics.txt");
    (dir, map, out)
}

/// Runs the editor (its script writes `out` and quits) within `limit`; returns the
/// script's lines: a first line saying how the editor took the file, then the diagnostics.
fn run_editor(
    mut cmd: Command,
    dir: &Path,
    out: &Path,
    editor: &str,
    limit: Duration,
) -> (String, String) {
    let mut child = cmd
        .env("PATH", path_with_mapc())
        .env("HOME", dir)
        .env("OUT", out)
        .current_dir(dir)
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap_or_else(|e| panic!("{editor} starts: {e}"));
    let start = Instant::now();
    let status = loop {
        if let Some(s) = child.try_wait().unwrap() {
            break s;
        }
        if start.elapsed() > limit {
            let _ = child.kill();
            panic!("{editor} did not finish in {limit:?}");
        }
        std::thread::sleep(Duration::from_millis(50));
    };
    let stderr = std::io::read_to_string(child.stderr.take().unwrap()).unwrap_or_default();
    assert!(status.success(), "{editor}: {status}\n{stderr}");
    let got = std::fs::read_to_string(out)
        .unwrap_or_else(|_| panic!("{editor}'s script wrote no result\n{stderr}"));
    println!("{editor}: {:.1} s", start.elapsed().as_secs_f64());
    let (first, rest) = got.split_once('\n').unwrap_or((&got, ""));
    // Open lines first, then edited lines, each group sorted.
    let mut lines: Vec<&str> = rest.lines().collect();
    lines.sort_by_key(|l| (!l.starts_with("open"), l.to_string()));
    (first.to_string(), lines.join("\n") + "\n")
}

fn found(cmd: &str, args: &[&str]) -> bool {
    Command::new(cmd)
        .args(args)
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .status()
        .is_ok_and(|s| s.success())
}

#[test]
fn emacs_eglot_shows_diagnostics() {
    if !found("emacs", &["--batch", "--eval", "(require 'eglot)"]) {
        println!("skipped: emacs with eglot not found");
        return;
    }
    let (dir, map, out) = workspace();
    let mut cmd = Command::new("emacs");
    // `--batch` reads no init file but the site files, where Debian puts elpa-eglot.
    cmd.args(["--batch", "-l"])
        .arg(root().join("editors/emacs/mapc.el"))
        .arg("-l")
        .arg(root().join("tests/emacs/check_diagnostics.el"))
        .env("MAP", &map);
    let (first, got) = run_editor(cmd, dir.path(), &out, "emacs", Duration::from_secs(30));
    assert_eq!(
        first, "mode mapc-map-mode eglot on",
        "the set-up took the file"
    );
    assert_eq!(got, WANT, "as Emacs' flymake shows them");
}

#[test]
fn vim_ale_shows_diagnostics() {
    if !found("vim", &["--version"]) {
        println!("skipped: vim not found");
        return;
    }
    // Debian's vim-ale installs ALE as an optional package.
    if !Path::new("/usr/share/vim/vimfiles/pack/dist-bundle/opt/ale").exists() {
        println!("skipped: vim-ale not found");
        return;
    }
    let (dir, map, out) = workspace();
    let vimrc = dir.path().join("vimrc");
    std::fs::write(
        &vimrc,
        format!(
            "set nocompatible\nfiletype on\nsource {}\n",
            root().join("editors/vim/mapc.vim").display()
        ),
    )
    .unwrap();
    let mut cmd = Command::new("vim");
    cmd.args(["-N", "-n", "-i", "NONE", "-u"])
        .arg(&vimrc)
        .arg("-es")
        .arg(&map)
        .arg("-S")
        .arg(root().join("tests/vim/check_diagnostics.vim"));
    let (first, got) = run_editor(cmd, dir.path(), &out, "vim", Duration::from_secs(30));
    assert_eq!(first, "filetype yaml.rmfmap", "the set-up took the file");
    assert_eq!(got, WANT, "as Vim's ALE shows them");
}

/// Where .ci/run packages editors/vscode as docs/editors.md says (`vsce package`).
const VSIX: &str = "target/vscode/mapc-0.1.0.vsix";

#[test]
fn vscode_extension_shows_diagnostics() {
    for (tool, args) in [
        ("code-server", &["--version"][..]),
        ("chromium", &["--version"][..]),
        ("unshare", &["-rn", "true"][..]),
        ("python3", &["--version"][..]),
    ] {
        if !found(tool, args) {
            println!("skipped: {tool} not found");
            return;
        }
    }
    let vsix = root().join(VSIX);
    if !vsix.exists() {
        println!("skipped: {VSIX} not found (.ci/run packages editors/vscode)");
        return;
    }
    let (dir, _map, _) = workspace();
    let (ws, ext, data) = (
        dir.path().join("ws"),
        dir.path().join("ext"),
        dir.path().join("data"),
    );
    for d in [&ws, &ext, &data.join("User")] {
        std::fs::create_dir_all(d).unwrap();
    }
    std::fs::rename(
        dir.path().join("m.building.yaml"),
        ws.join("m.building.yaml"),
    )
    .unwrap();
    // The test driver is a second extension, packed as a .vsix (a zip of `extension/`).
    let driver = dir.path().join("driver");
    std::fs::create_dir_all(driver.join("extension")).unwrap();
    for f in ["package.json", "extension.js"] {
        std::fs::copy(
            root().join("tests/vscode/check-ext").join(f),
            driver.join("extension").join(f),
        )
        .unwrap();
    }
    let zipped = Command::new("python3")
        .args(["-m", "zipfile", "-c", "driver.vsix", "extension"])
        .current_dir(&driver)
        .status()
        .unwrap();
    assert!(zipped.success());
    // The user's settings: no workspace-trust question (it would keep extensions off), no
    // telemetry, and the mapc under test as `mapc.path` (VS Code's server takes PATH from
    // a login shell, not from its parent).
    let settings = serde_json::json!({
        "security.workspace.trust.enabled": false,
        "telemetry.telemetryLevel": "off",
        "extensions.autoCheckUpdates": false,
        "extensions.autoUpdate": false,
        "mapc.path": env!("CARGO_BIN_EXE_mapc"),
    });
    std::fs::write(data.join("User/settings.json"), settings.to_string()).unwrap();
    // Installed as docs/editors.md says (`code --install-extension`), offline.
    let installed = Command::new("unshare")
        .args(["-rn", "code-server", "--user-data-dir"])
        .arg(&data)
        .arg("--extensions-dir")
        .arg(&ext)
        .arg("--install-extension")
        .arg(&vsix)
        .arg("--install-extension")
        .arg(driver.join("driver.vsix"))
        .env("HOME", dir.path())
        .output()
        .unwrap();
    let log = String::from_utf8_lossy(&installed.stdout);
    assert!(
        installed.status.success() && log.matches("was successfully installed").count() == 2,
        "code-server --install-extension: {log}{}",
        String::from_utf8_lossy(&installed.stderr)
    );
    let mut cmd = Command::new("unshare");
    // Own network and process namespaces: VS Code and Chromium reach only each other, and
    // all they start ends with the script.
    cmd.arg("-rnpf")
        .arg(root().join("tests/vscode/run.sh"))
        .args([&ws, &ext, &data]);
    let out = ws.join("diagnostics.txt");
    let (first, got) = run_editor(cmd, dir.path(), &out, "vscode", Duration::from_secs(90));
    assert_eq!(
        first, "extension found active",
        "VS Code ran the mapc extension"
    );
    assert_eq!(got, WANT, "as VS Code shows them");
}
