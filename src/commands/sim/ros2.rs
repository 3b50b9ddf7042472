//! `mapc sim --ros2` and `--mcap`: the run as a ROS 2 peer (the DDS bridge of mapc-ros2,
//! paced at `--rate`, with `/clock`) and as a rosbag2 MCAP file. Both only observe the run
//! (and, with `--plugins-only`, add the requests other nodes send), so without these flags
//! `mapc sim` is unchanged.

use crate::driver::output;
use mapc_sim::msgs::{Msg, Published, Topic};
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};
#[cfg(any(feature = "dds", feature = "zenoh"))]
use std::time::{Duration, Instant};

#[derive(clap::Args, Default)]
pub(crate) struct Ros2Args {
    /// Join ROS 2 (DDS): publish the run's messages on RMF's topics with RMF's types, plus
    /// `/clock` and `/map`, paced at --rate (docs/ros2.md).
    #[arg(long)]
    pub ros2: bool,
    /// The ROS 2 domain to join (default: ROS_DOMAIN_ID, else 0).
    #[arg(long, value_name = "N", requires = "ros2",
          value_parser = clap::value_parser!(u16).range(0..=232))]
    pub domain_id: Option<u16>,
    /// The middleware: `dds` (as rmw_cyclonedds_cpp, rmw_fastrtps_cpp) or `zenoh` (as
    /// rmw_zenoh_cpp) (default: from RMW_IMPLEMENTATION, else dds).
    #[arg(long, value_name = "RMW", requires = "ros2")]
    pub rmw: Option<RmwArg>,
    /// Simulated seconds per wall-clock second with --ros2 (1 = real time, as Gazebo).
    #[arg(long, value_name = "X", requires = "ros2", value_parser = parse_rate)]
    pub rate: Option<f64>,
    /// Play only the Gazebo side (slotcars, doors, lifts, dispensers, ingestors) and answer
    /// the requests of RMF's own fleet adapters and supervisors.
    #[arg(long, requires = "ros2")]
    pub plugins_only: bool,
    /// Write every message of the run as a rosbag2-compatible MCAP file (ROS 2 schemas, CDR).
    #[arg(long, value_name = "FILE")]
    pub mcap: Option<PathBuf>,
}

#[derive(clap::ValueEnum, Clone, Copy, Debug)]
pub(crate) enum RmwArg {
    Dds,
    Zenoh,
}

/// ROS 2's settings from the environment, the flags winning.
#[cfg(any(feature = "dds", feature = "zenoh"))]
fn ros_env(args: &Ros2Args) -> Result<mapc_ros2::ros_env::RosEnv, String> {
    use mapc_ros2::ros_env::{Rmw, RosEnv};
    let rmw = args.rmw.map(|r| match r {
        RmwArg::Dds => Rmw::Dds,
        RmwArg::Zenoh => Rmw::Zenoh,
    });
    RosEnv::read(&|k| std::env::var(k).ok(), args.domain_id, rmw)
}

fn parse_rate(s: &str) -> Result<f64, String> {
    match s.parse::<f64>() {
        Ok(x) if x.is_finite() && x > 0.0 => Ok(x),
        _ => Err("must be a positive number (simulated seconds per second)".into()),
    }
}

/// An MCAP file being written: a temporary renamed when the run ends (as the trace is).
struct McapFile {
    recorder: Option<mapc_ros2::mcap::Recorder<BufWriter<std::fs::File>>>,
    /// Removes the temporary when dropped unfinished.
    pending: Option<output::Pending>,
    path: PathBuf,
    /// The first write error; the run goes on and the error is reported at the end.
    error: Option<String>,
}

impl McapFile {
    fn create(path: &Path, building: &mapc_ir::Building) -> Result<McapFile, String> {
        let err = |e: String| format!("{}: {e}", crate::ui::shown(path));
        let dir = path
            .parent()
            .filter(|p| !p.as_os_str().is_empty())
            .unwrap_or(Path::new("."));
        std::fs::create_dir_all(dir).map_err(|e| err(e.to_string()))?;
        output::sweep_temporaries(dir);
        let (pending, f) = output::Pending::create(path).map_err(|e| err(e.to_string()))?;
        let mut file = McapFile {
            recorder: None,
            pending: Some(pending),
            path: path.to_path_buf(),
            error: None,
        };
        let mut r =
            mapc_ros2::mcap::Recorder::new(BufWriter::with_capacity(1 << 20, f)).map_err(err)?;
        r.building(building).map_err(err)?;
        file.recorder = Some(r);
        Ok(file)
    }

    fn record(&mut self, p: &Published) {
        if self.error.is_some() {
            return;
        }
        if let Some(r) = self.recorder.as_mut() {
            if let Err(e) = r.record(p) {
                self.error = Some(e);
            }
        }
    }

    fn clock(&mut self, t: f64) {
        if self.error.is_some() {
            return;
        }
        if let Some(r) = self.recorder.as_mut() {
            if let Err(e) = r.clock(t) {
                self.error = Some(e);
            }
        }
    }

    fn finish(mut self) -> Result<(), String> {
        let err = |e: String| format!("{}: {e}", crate::ui::shown(&self.path));
        if let Some(e) = self.error.take() {
            return Err(err(e));
        }
        let Some(r) = self.recorder.take() else {
            return Ok(());
        };
        let mut w = r.finish().map_err(err)?;
        w.flush().map_err(|e| err(e.to_string()))?;
        match self.pending.take() {
            Some(p) => p.commit(w.get_ref()).map_err(|e| err(e.to_string())),
            None => Ok(()),
        }
    }
}

/// Holds the run to `rate` simulated seconds per wall-clock second.
#[cfg(any(feature = "dds", feature = "zenoh"))]
struct Pace {
    rate: f64,
    start: Option<(Instant, f64)>,
}

#[cfg(any(feature = "dds", feature = "zenoh"))]
impl Pace {
    fn wait(&mut self, t: f64) {
        let (start, t0) = *self.start.get_or_insert((Instant::now(), t));
        let due = start + Duration::from_secs_f64(((t - t0) / self.rate).max(0.0));
        let now = Instant::now();
        if due > now {
            std::thread::sleep(due - now);
        }
    }
}

/// What `--ros2` and `--mcap` add to a run.
pub(crate) struct Ros2Run {
    mcap: Option<McapFile>,
    #[cfg(any(feature = "dds", feature = "zenoh"))]
    bridge: Option<(mapc_ros2::link::Link, Pace, Option<Instant>)>,
}

/// `/clock` at most this often (wall clock): a fast run need not flood the bus.
#[cfg(any(feature = "dds", feature = "zenoh"))]
const CLOCK_PERIOD: Duration = Duration::from_millis(5);

impl Ros2Run {
    pub(crate) fn start(args: &Ros2Args, building: &mapc_ir::Building) -> Result<Ros2Run, String> {
        let mcap = args
            .mcap
            .as_deref()
            .map(|p| McapFile::create(p, building))
            .transpose()?;
        #[cfg(any(feature = "dds", feature = "zenoh"))]
        let bridge = if args.ros2 {
            let env = ros_env(args)?;
            let b = mapc_ros2::link::Link::open(
                &env,
                &|k| std::env::var(k).ok(),
                args.plugins_only,
                building,
            )?;
            eprintln!("{}", b.summary());
            b.settle();
            let pace = Pace {
                rate: args.rate.unwrap_or(1.0),
                start: None,
            };
            Some((b, pace, None))
        } else {
            None
        };
        #[cfg(not(any(feature = "dds", feature = "zenoh")))]
        if args.ros2 {
            return Err(
                "--ros2: this mapc was built without DDS and Zenoh (cargo features `dds`, `zenoh`)"
                    .into(),
            );
        }
        Ok(Ros2Run {
            mcap,
            #[cfg(any(feature = "dds", feature = "zenoh"))]
            bridge,
        })
    }

    /// Whether the run needs the observer.
    pub(crate) fn active(&self) -> bool {
        #[cfg(any(feature = "dds", feature = "zenoh"))]
        if self.bridge.is_some() {
            return true;
        }
        self.mcap.is_some()
    }

    /// Whether the run calls `inject` before each step: the bridge paces the run, publishes
    /// `/clock` and injects other nodes' requests; the recorder records `/clock` (it
    /// injects nothing).
    pub(crate) fn injects(&self) -> bool {
        self.active()
    }

    pub(crate) fn observe(&mut self, p: &Published) {
        if let Some(m) = self.mcap.as_mut() {
            m.record(p);
        }
        #[cfg(any(feature = "dds", feature = "zenoh"))]
        if let Some((b, _, _)) = self.bridge.as_mut() {
            b.publish(p);
        }
    }

    /// Before each step: record `/clock`, keep pace, publish `/clock`, take what other
    /// nodes sent.
    #[cfg_attr(
        not(any(feature = "dds", feature = "zenoh")),
        allow(unused_variables, clippy::ptr_arg)
    )]
    pub(crate) fn inject(&mut self, t: f64, out: &mut Vec<(Topic, Msg)>) {
        if let Some(m) = self.mcap.as_mut() {
            m.clock(t);
        }
        #[cfg(any(feature = "dds", feature = "zenoh"))]
        if let Some((b, pace, last_clock)) = self.bridge.as_mut() {
            pace.wait(t);
            let now = Instant::now();
            if last_clock.is_none_or(|l| now - l >= CLOCK_PERIOD) {
                b.clock(t);
                *last_clock = Some(now);
            }
            b.take_requests(out);
        }
    }

    pub(crate) fn finish(self) -> Result<(), String> {
        #[cfg(any(feature = "dds", feature = "zenoh"))]
        if let Some((b, _, _)) = self.bridge {
            b.finish();
        }
        match self.mcap {
            Some(m) => m.finish(),
            None => Ok(()),
        }
    }
}
