//! What the ROS 2 tests share: the Python venv of the transport peers and private network
//! namespaces.

use std::path::{Path, PathBuf};
use std::process::Command;

/// The venv's Python (`target/ros2-venv`, or `MAPC_ROS2_PYTHON`) when it can import
/// `modules` (comma-separated, as in a Python `import` line).
pub fn python(modules: &str) -> Option<PathBuf> {
    let p = match std::env::var_os("MAPC_ROS2_PYTHON") {
        Some(p) => PathBuf::from(p),
        None => Path::new(env!("CARGO_MANIFEST_DIR")).join("target/ros2-venv/bin/python"),
    };
    let ok = Command::new(&p)
        .args(["-c", &format!("import {modules}")])
        .output()
        .is_ok_and(|o| o.status.success());
    ok.then_some(p)
}

/// Whether this machine can make a private network namespace with `lo` up, multicast on
/// and the multicast route (unshare and ip).
pub fn namespace_works() -> bool {
    Command::new("unshare")
        .args([
            "-rn",
            "sh",
            "-c",
            "ip link set lo up multicast on && ip route add 224.0.0.0/4 dev lo",
        ])
        .output()
        .is_ok_and(|o| o.status.success())
}

/// What a test with a Python transport peer needs: the venv's Python that imports
/// `modules`, and a private network namespace. Prints why the test is skipped otherwise.
pub fn peer(modules: &str) -> Option<PathBuf> {
    let Some(py) = python(modules) else {
        println!("skipped: Python modules {modules} not found; .ci/run makes target/ros2-venv");
        return None;
    };
    namespace().then_some(py)
}

/// [`namespace_works`], printing why the test is skipped when it does not.
pub fn namespace() -> bool {
    let ok = namespace_works();
    if !ok {
        println!("skipped: no private network namespace (unshare -rn, ip) here");
    }
    ok
}
