//! `mapc sweep --executor slurm` against a real one-node Slurm cluster (Debian's slurmctld,
//! slurmd, slurm-client and munge), started in a temporary directory without systemd and
//! stopped by pid: the results are byte-identical to the local executor's, `--no-wait`
//! then `mapc sweep collect` gives the same, and a run that fails is resubmitted once.
//! Prints `skipped: slurm not found` when the daemons are not installed (.ci/run installs
//! them).

mod support;

use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

const SWEEP: &str = "fixtures/sweep/clinic.sweep.yaml";

fn which(name: &str) -> Option<PathBuf> {
    let mut dirs: Vec<PathBuf> = std::env::split_paths(&std::env::var_os("PATH")?).collect();
    // The daemons are in sbin, which a non-login PATH may lack.
    dirs.extend(["/usr/sbin", "/sbin"].map(PathBuf::from));
    dirs.into_iter().map(|d| d.join(name)).find(|f| f.is_file())
}

/// A one-node cluster: munged, slurmctld and slurmd, children of the test.
struct Cluster {
    dir: tempfile::TempDir,
    children: Vec<Child>,
}

impl Drop for Cluster {
    fn drop(&mut self) {
        for c in self.children.iter_mut().rev() {
            let _ = c.kill();
            let _ = c.wait();
        }
    }
}

impl Cluster {
    fn conf(&self) -> PathBuf {
        self.dir.path().join("slurm.conf")
    }

    fn start() -> Option<Cluster> {
        let munged = which("munged")?;
        let slurmctld = which("slurmctld")?;
        let slurmd = which("slurmd")?;
        which("sbatch")?;
        which("squeue")?;
        which("sinfo")?;
        let dir = tempfile::tempdir().unwrap();
        let d = &dir.path().to_path_buf();
        for sub in ["munge", "state", "spool", "log"] {
            std::fs::create_dir(d.join(sub)).unwrap();
        }
        // The daemons and clients reach munge's socket through these directories.
        use std::os::unix::fs::PermissionsExt;
        for p in [d, &d.join("munge")] {
            std::fs::set_permissions(p, std::fs::Permissions::from_mode(0o755)).unwrap();
        }
        let key: Vec<u8> = (0..1024u32)
            .map(|i| (i.wrapping_mul(2_654_435_761) >> 13) as u8 ^ std::process::id() as u8)
            .collect();
        let key_file = d.join("munge/munge.key");
        std::fs::write(&key_file, key).unwrap();
        std::fs::set_permissions(&key_file, std::fs::Permissions::from_mode(0o600)).unwrap();
        let socket = d.join("munge/munge.socket");
        let mut cluster = Cluster {
            dir,
            children: Vec::new(),
        };
        let log = |name: &str| {
            std::fs::File::create(cluster_log(&socket, name)).map_or(Stdio::null(), Stdio::from)
        };
        let child = Command::new(munged)
            .arg(format!("--socket={}", socket.display()))
            .arg(format!("--key-file={}", key_file.display()))
            .arg(format!(
                "--pid-file={}",
                d.join("munge/munged.pid").display()
            ))
            .arg(format!("--seed-file={}", d.join("munge/seed").display()))
            .args(["--foreground", "--force"])
            .stdout(Stdio::null())
            .stderr(log("munged.log"))
            .spawn()
            .unwrap();
        cluster.children.push(child);
        wait_for("munge's socket", Duration::from_secs(10), || {
            socket.exists()
        });

        let host = std::fs::read_to_string("/proc/sys/kernel/hostname")
            .unwrap()
            .trim()
            .split('.')
            .next()
            .unwrap()
            .to_string();
        let user = String::from_utf8(Command::new("id").arg("-un").output().unwrap().stdout)
            .unwrap()
            .trim()
            .to_string();
        let free_port = || {
            std::net::TcpListener::bind("127.0.0.1:0")
                .unwrap()
                .local_addr()
                .unwrap()
                .port()
        };
        let (p1, p2) = (free_port(), free_port());
        let cpus = std::thread::available_parallelism().map_or(1, |n| n.get());
        let conf = format!(
            "ClusterName=mapctest\n\
             SlurmctldHost={host}(127.0.0.1)\n\
             SlurmUser={user}\n\
             SlurmdUser={user}\n\
             SlurmctldPort={p1}\n\
             SlurmdPort={p2}\n\
             AuthType=auth/munge\n\
             CredType=cred/munge\n\
             AuthInfo=socket={sock}\n\
             StateSaveLocation={d}/state\n\
             SlurmdSpoolDir={d}/spool\n\
             SlurmctldPidFile={d}/slurmctld.pid\n\
             SlurmdPidFile={d}/slurmd.pid\n\
             SlurmctldLogFile={d}/log/slurmctld.log\n\
             SlurmdLogFile={d}/log/slurmd.log\n\
             ProctrackType=proctrack/linuxproc\n\
             TaskPlugin=task/none\n\
             JobAcctGatherType=jobacct_gather/none\n\
             AccountingStorageType=accounting_storage/none\n\
             JobCompType=jobcomp/none\n\
             SchedulerType=sched/builtin\n\
             SelectType=select/cons_tres\n\
             SelectTypeParameters=CR_Core\n\
             ReturnToService=2\n\
             MpiDefault=none\n\
             NodeName={host} NodeAddr=127.0.0.1 CPUs={cpus} State=UNKNOWN\n\
             PartitionName=debug Nodes={host} Default=YES MaxTime=INFINITE State=UP\n",
            sock = socket.display(),
            d = d.display(),
        );
        std::fs::write(d.join("slurm.conf"), conf).unwrap();
        for (exe, name) in [(slurmctld, "slurmctld.out"), (slurmd, "slurmd.out")] {
            let child = Command::new(exe)
                .arg("-D")
                .arg("-f")
                .arg(d.join("slurm.conf"))
                .env("SLURM_CONF", d.join("slurm.conf"))
                .stdout(Stdio::null())
                .stderr(log(name))
                .spawn()
                .unwrap();
            cluster.children.push(child);
        }
        let conf = cluster.conf();
        wait_for("the node to be idle", Duration::from_secs(60), || {
            Command::new("sinfo")
                .args(["-h", "-o", "%t"])
                .env("SLURM_CONF", &conf)
                .output()
                .is_ok_and(|o| String::from_utf8_lossy(&o.stdout).trim() == "idle")
        });
        Some(cluster)
    }

    fn mapc(&self, args: &[&str]) -> (i32, String, String) {
        let out = Command::new(env!("CARGO_BIN_EXE_mapc"))
            .current_dir(env!("CARGO_MANIFEST_DIR"))
            .env("SLURM_CONF", self.conf())
            .args(args)
            .output()
            .unwrap();
        (
            out.status.code().unwrap_or(-1),
            String::from_utf8_lossy(&out.stdout).into_owned(),
            String::from_utf8_lossy(&out.stderr).into_owned(),
        )
    }

    fn queue_empty(&self) -> bool {
        Command::new("squeue")
            .args(["-h", "-o", "%i"])
            .env("SLURM_CONF", self.conf())
            .output()
            .is_ok_and(|o| o.status.success() && o.stdout.iter().all(u8::is_ascii_whitespace))
    }
}

fn cluster_log(socket: &Path, name: &str) -> PathBuf {
    socket
        .parent()
        .unwrap()
        .parent()
        .unwrap()
        .join("log")
        .join(name)
}

fn wait_for(what: &str, limit: Duration, mut ok: impl FnMut() -> bool) {
    let start = Instant::now();
    while !ok() {
        assert!(start.elapsed() < limit, "timed out waiting for {what}");
        std::thread::sleep(Duration::from_millis(200));
    }
}

fn read(p: PathBuf) -> Vec<u8> {
    std::fs::read(&p).unwrap_or_else(|e| panic!("{}: {e}", p.display()))
}

#[test]
fn slurm_job_array_gives_the_local_results() {
    let Some(cluster) = Cluster::start() else {
        println!("skipped: slurm not found");
        return;
    };
    let tmp = tempfile::tempdir().unwrap();
    let local = tmp.path().join("local");
    let (code, _, err) = support::mapc(&["sweep", SWEEP, "-o", local.to_str().unwrap()]);
    assert_eq!(code, 0, "{err}");

    // Waiting for the array, two tasks at a time.
    let out = tmp.path().join("slurm");
    let o = out.to_str().unwrap();
    let (code, stdout, err) = cluster.mapc(&[
        "sweep",
        SWEEP,
        "-o",
        o,
        "--executor",
        "slurm",
        "--max-parallel",
        "2",
        "--sbatch-args",
        "--time=10 --job-name=mapc-test",
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(err.contains("submitted Slurm job"), "{err}");
    assert!(stdout.starts_with("6 of 6 runs done"), "{stdout}");
    assert_eq!(
        read(out.join("results.csv")),
        read(local.join("results.csv"))
    );
    assert_eq!(
        read(out.join("results.json")),
        read(local.join("results.json"))
    );
    for run in ["0000", "0001", "0002", "0003", "0004", "0005"] {
        let p = Path::new("runs").join(run).join("report.json");
        assert_eq!(read(out.join(&p)), read(local.join(&p)), "{}", p.display());
    }
    // Every task wrote its log where the job script says.
    let logs = std::fs::read_dir(out.join("slurm"))
        .unwrap()
        .filter(|e| {
            e.as_ref()
                .unwrap()
                .path()
                .extension()
                .is_some_and(|x| x == "log")
        })
        .count();
    assert_eq!(logs, 6);

    // --no-wait, then collect: only the two missing runs are submitted.
    std::fs::remove_dir_all(out.join("runs/0002")).unwrap();
    std::fs::remove_dir_all(out.join("runs/0004")).unwrap();
    let (code, _, err) =
        cluster.mapc(&["sweep", SWEEP, "-o", o, "--executor", "slurm", "--no-wait"]);
    assert_eq!(code, 0, "{err}");
    assert!(err.contains(": 2 run(s)"), "{err}");
    assert!(err.contains(&format!("mapc sweep collect {o}")), "{err}");
    wait_for("the array", Duration::from_secs(120), || {
        cluster.queue_empty()
    });
    let (code, _, err) = cluster.mapc(&["sweep", "collect", o]);
    assert_eq!(code, 0, "{err}");
    assert_eq!(
        read(out.join("results.csv")),
        read(local.join("results.csv"))
    );

    // A run that cannot be written fails twice: resubmitted once, then reported.
    std::fs::remove_dir_all(out.join("runs/0001")).unwrap();
    std::fs::write(out.join("runs/0001"), "in the way").unwrap();
    let (code, _, err) = cluster.mapc(&["sweep", SWEEP, "-o", o, "--executor", "slurm"]);
    assert_eq!(code, 1, "{err}");
    assert!(err.contains("1 run(s) failed"), "{err}");
    assert!(err.contains("resubmitting them once"), "{err}");
    assert!(err.contains(": 1 run(s) again"), "{err}");
    assert!(err.contains("1 run(s) not done: 0001"), "{err}");
}
