//! ROS 2's environment settings, read as a ROS 2 node reads them (rcl, Jazzy on): the
//! domain, the discovery range and static peers, and the middleware. Flags given to mapc
//! win over the environment, as `--ros-args` would. Pure: the environment is passed in.

use std::net::{IpAddr, ToSocketAddrs};

/// `ROS_AUTOMATIC_DISCOVERY_RANGE` (rmw's `rmw_automatic_discovery_range_t`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Range {
    /// Multicast on the local network (the default).
    Subnet,
    /// This machine only: loopback, unicast discovery to 127.0.0.1.
    Localhost,
    /// No automatic discovery at all.
    Off,
    /// The middleware's own default (for mapc's DDS: as `Subnet`).
    SystemDefault,
}

/// The middleware mapc speaks with `--ros2`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Rmw {
    /// DDS (RTPS over UDP), as rmw_cyclonedds_cpp and rmw_fastrtps_cpp.
    #[default]
    Dds,
    /// Zenoh, as rmw_zenoh_cpp.
    Zenoh,
}

/// What mapc takes from the environment and its flags.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct RosEnv {
    pub domain_id: u16,
    pub range: Range,
    /// Which setting chose `range` (for messages), e.g. `ROS_LOCALHOST_ONLY=1`.
    pub range_from: String,
    /// `ROS_STATIC_PEERS` as written (host names or addresses), empty when they do not
    /// apply (range `Off` or `SystemDefault`, as in rmw_cyclonedds_cpp).
    pub static_peers: Vec<String>,
    pub rmw: Rmw,
}

/// The largest domain id: DDS's port mapping (7400 + 250 × id) ends at 65535 below 233.
pub const MAX_DOMAIN_ID: u16 = 232;

fn set(get: &dyn Fn(&str) -> Option<String>, name: &str) -> Option<String> {
    get(name)
        .map(|v| v.trim().to_string())
        .filter(|v| !v.is_empty())
}

impl RosEnv {
    /// Reads the settings through `get` (an environment lookup); `domain_flag` and
    /// `rmw_flag` are mapc's `--domain-id` and `--rmw`, which win.
    pub fn read(
        get: &dyn Fn(&str) -> Option<String>,
        domain_flag: Option<u16>,
        rmw_flag: Option<Rmw>,
    ) -> Result<RosEnv, String> {
        let domain_id = match (domain_flag, set(get, "ROS_DOMAIN_ID")) {
            (Some(d), _) => d,
            (None, None) => 0,
            (None, Some(v)) => match v.parse::<u16>() {
                Ok(d) if d <= MAX_DOMAIN_ID => d,
                _ => {
                    return Err(format!(
                        "ROS_DOMAIN_ID={v} is not a domain id (0 to {MAX_DOMAIN_ID}); set it to \
                         the domain of the other nodes, or unset it for domain 0, or pass \
                         --domain-id N"
                    ))
                }
            },
        };
        let range_env = set(get, "ROS_AUTOMATIC_DISCOVERY_RANGE");
        let mut range = match range_env.as_deref() {
            None => Range::Subnet,
            Some("SUBNET") => Range::Subnet,
            Some("LOCALHOST") => Range::Localhost,
            Some("OFF") => Range::Off,
            Some("SYSTEM_DEFAULT") => Range::SystemDefault,
            Some(v) => {
                return Err(format!(
                    "ROS_AUTOMATIC_DISCOVERY_RANGE={v} is not a discovery range: use SUBNET, \
                     LOCALHOST, OFF or SYSTEM_DEFAULT (or unset it for SUBNET)"
                ))
            }
        };
        let mut range_from = match &range_env {
            Some(v) => format!("ROS_AUTOMATIC_DISCOVERY_RANGE={v}"),
            None => "the default discovery range (SUBNET)".to_string(),
        };
        // Humble's setting; Jazzy still honours it (deprecated), before the range.
        match set(get, "ROS_LOCALHOST_ONLY").as_deref() {
            Some("1") => {
                range = Range::Localhost;
                range_from = "ROS_LOCALHOST_ONLY=1".into();
            }
            None | Some("0") => {}
            Some(v) => {
                return Err(format!(
                    "ROS_LOCALHOST_ONLY={v}: use 1 (this machine only) or 0, or unset it"
                ))
            }
        }
        let static_peers = match range {
            Range::Subnet | Range::Localhost => set(get, "ROS_STATIC_PEERS")
                .map(|v| {
                    v.split(';')
                        .map(str::trim)
                        .filter(|p| !p.is_empty())
                        .map(String::from)
                        .collect()
                })
                .unwrap_or_default(),
            Range::Off | Range::SystemDefault => Vec::new(),
        };
        let rmw = match (rmw_flag, set(get, "RMW_IMPLEMENTATION").as_deref()) {
            (Some(r), _) => r,
            (None, None) => Rmw::Dds,
            (None, Some("rmw_zenoh_cpp")) => Rmw::Zenoh,
            (
                None,
                Some(
                    "rmw_cyclonedds_cpp"
                    | "rmw_fastrtps_cpp"
                    | "rmw_fastrtps_dynamic_cpp"
                    | "rmw_connextdds"
                    | "rmw_gurumdds_cpp",
                ),
            ) => Rmw::Dds,
            (None, Some(v)) => {
                return Err(format!(
                    "RMW_IMPLEMENTATION={v}: mapc speaks DDS (as rmw_cyclonedds_cpp or \
                     rmw_fastrtps_cpp) and Zenoh (as rmw_zenoh_cpp); set one of those, or pass \
                     --rmw dds or --rmw zenoh"
                ))
            }
        };
        Ok(RosEnv {
            domain_id,
            range,
            range_from,
            static_peers,
            rmw,
        })
    }

    /// `ROS_STATIC_PEERS` resolved to IPv4 addresses.
    pub fn static_peer_addresses(&self) -> Result<Vec<IpAddr>, String> {
        let mut out = Vec::new();
        for p in &self.static_peers {
            let found: Vec<IpAddr> = (p.as_str(), 0)
                .to_socket_addrs()
                .map_err(|e| {
                    format!("ROS_STATIC_PEERS: `{p}` does not resolve ({e}); list host names or IPv4 addresses separated by `;`")
                })?
                .map(|a| a.ip())
                .filter(IpAddr::is_ipv4)
                .collect();
            if found.is_empty() {
                return Err(format!(
                    "ROS_STATIC_PEERS: `{p}` has no IPv4 address (mapc's DDS is IPv4 only)"
                ));
            }
            for a in found {
                if !out.contains(&a) {
                    out.push(a);
                }
            }
        }
        Ok(out)
    }
}

/// A network interface: what the choice of where to talk depends on.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Interface {
    pub name: String,
    pub has_ipv4: bool,
    pub up: bool,
    pub loopback: bool,
    pub multicast: bool,
}

/// Where DDS talks.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct DdsNetwork {
    /// Loopback interfaces only: locators on 127.0.0.1, 127.0.0.1 as a static peer.
    pub loopback_only: bool,
    /// Why (for the line mapc prints).
    pub reason: String,
}

/// Chooses loopback or the network for `env` on a host with `interfaces`, or says why no
/// interface can carry DDS and what to set.
pub fn choose_network(env: &RosEnv, interfaces: &[Interface]) -> Result<DdsNetwork, String> {
    let shown = || {
        let list: Vec<String> = interfaces
            .iter()
            .map(|i| {
                let mut flags = Vec::new();
                flags.push(if i.up { "up" } else { "down" });
                if i.loopback {
                    flags.push("loopback");
                }
                if i.multicast {
                    flags.push("multicast");
                }
                if !i.has_ipv4 {
                    flags.push("no IPv4 address");
                }
                format!("{} ({})", i.name, flags.join(", "))
            })
            .collect();
        if list.is_empty() {
            "none".to_string()
        } else {
            list.join("; ")
        }
    };
    let lo_up = interfaces.iter().any(|i| i.loopback && i.up && i.has_ipv4);
    let network = interfaces
        .iter()
        .any(|i| !i.loopback && i.up && i.has_ipv4 && i.multicast);
    let one_machine = "ROS_AUTOMATIC_DISCOVERY_RANGE=LOCALHOST (ROS_LOCALHOST_ONLY=1 on Humble)";
    match env.range {
        Range::Off => Err(format!(
            "DDS: {}: automatic discovery is off, so no other node could find mapc. For nodes \
             on this machine set {one_machine}; across machines unset it (SUBNET), with \
             ROS_STATIC_PEERS for peers multicast cannot reach",
            env.range_from
        )),
        Range::Localhost if lo_up => Ok(DdsNetwork {
            loopback_only: true,
            reason: format!("{}: loopback only (127.0.0.1)", env.range_from),
        }),
        Range::Localhost => Err(format!(
            "DDS: no network interface can carry DDS: {} asks for loopback, and no loopback \
             interface is up with an IPv4 address (interfaces: {}). Bring it up \
             (`ip link set lo up`), or unset ROS_AUTOMATIC_DISCOVERY_RANGE and \
             ROS_LOCALHOST_ONLY to use the network",
            env.range_from,
            shown()
        )),
        Range::Subnet | Range::SystemDefault if network => Ok(DdsNetwork {
            loopback_only: false,
            reason: format!("{}: multicast on the local network", env.range_from),
        }),
        Range::Subnet | Range::SystemDefault if lo_up => Ok(DdsNetwork {
            loopback_only: true,
            reason: format!(
                "no interface but loopback is up with IPv4 and multicast: loopback only \
                 (127.0.0.1), as with {one_machine}"
            ),
        }),
        Range::Subnet | Range::SystemDefault => Err(format!(
            "DDS: no network interface can carry DDS: none is up with an IPv4 address, \
             loopback included (interfaces: {}). For nodes on this machine bring up loopback \
             (`ip link set lo up`) and set {one_machine}; across machines bring up a network \
             interface with multicast, or list the peers in ROS_STATIC_PEERS",
            shown()
        )),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn env<'a>(vars: &'a [(&'a str, &'a str)]) -> impl Fn(&str) -> Option<String> + 'a {
        move |k| {
            vars.iter()
                .find(|(n, _)| *n == k)
                .map(|(_, v)| v.to_string())
        }
    }

    fn read(vars: &[(&str, &str)]) -> Result<RosEnv, String> {
        RosEnv::read(&env(vars), None, None)
    }

    #[test]
    fn domain_from_environment_and_flag_wins() {
        assert_eq!(read(&[]).unwrap().domain_id, 0);
        assert_eq!(read(&[("ROS_DOMAIN_ID", "7")]).unwrap().domain_id, 7);
        assert_eq!(read(&[("ROS_DOMAIN_ID", "")]).unwrap().domain_id, 0);
        let flag = RosEnv::read(&env(&[("ROS_DOMAIN_ID", "7")]), Some(3), None).unwrap();
        assert_eq!(flag.domain_id, 3);
        for bad in ["233", "-1", "seven"] {
            let e = read(&[("ROS_DOMAIN_ID", bad)]).unwrap_err();
            assert!(
                e.contains("ROS_DOMAIN_ID") && e.contains("--domain-id"),
                "{e}"
            );
        }
    }

    #[test]
    fn discovery_range_and_localhost_only() {
        assert_eq!(read(&[]).unwrap().range, Range::Subnet);
        let r = read(&[("ROS_AUTOMATIC_DISCOVERY_RANGE", "LOCALHOST")]).unwrap();
        assert_eq!(r.range, Range::Localhost);
        assert_eq!(r.range_from, "ROS_AUTOMATIC_DISCOVERY_RANGE=LOCALHOST");
        let r = read(&[("ROS_LOCALHOST_ONLY", "1")]).unwrap();
        assert_eq!(r.range, Range::Localhost);
        assert_eq!(r.range_from, "ROS_LOCALHOST_ONLY=1");
        assert_eq!(
            read(&[("ROS_LOCALHOST_ONLY", "0")]).unwrap().range,
            Range::Subnet
        );
        assert!(read(&[("ROS_AUTOMATIC_DISCOVERY_RANGE", "LAN")])
            .unwrap_err()
            .contains("SUBNET, LOCALHOST, OFF or SYSTEM_DEFAULT"));
        assert!(read(&[("ROS_LOCALHOST_ONLY", "yes")]).is_err());
    }

    #[test]
    fn static_peers_apply_to_subnet_and_localhost() {
        let vars = [("ROS_STATIC_PEERS", "127.0.0.1; 192.0.2.7;")];
        assert_eq!(
            read(&vars).unwrap().static_peers,
            ["127.0.0.1", "192.0.2.7"]
        );
        let off = [
            ("ROS_STATIC_PEERS", "192.0.2.7"),
            ("ROS_AUTOMATIC_DISCOVERY_RANGE", "SYSTEM_DEFAULT"),
        ];
        assert!(read(&off).unwrap().static_peers.is_empty());
        let r = read(&vars).unwrap();
        assert_eq!(
            r.static_peer_addresses().unwrap(),
            [
                "127.0.0.1".parse::<IpAddr>().unwrap(),
                "192.0.2.7".parse().unwrap()
            ]
        );
    }

    #[test]
    fn middleware_from_flag_or_environment() {
        assert_eq!(read(&[]).unwrap().rmw, Rmw::Dds);
        let z = [("RMW_IMPLEMENTATION", "rmw_zenoh_cpp")];
        assert_eq!(read(&z).unwrap().rmw, Rmw::Zenoh);
        assert_eq!(
            RosEnv::read(&env(&z), None, Some(Rmw::Dds)).unwrap().rmw,
            Rmw::Dds
        );
        let c = [("RMW_IMPLEMENTATION", "rmw_cyclonedds_cpp")];
        assert_eq!(read(&c).unwrap().rmw, Rmw::Dds);
        assert!(read(&[("RMW_IMPLEMENTATION", "rmw_opendds")])
            .unwrap_err()
            .contains("--rmw"));
    }

    fn iface(name: &str, up: bool, loopback: bool, multicast: bool) -> Interface {
        Interface {
            name: name.into(),
            has_ipv4: true,
            up,
            loopback,
            multicast,
        }
    }

    #[test]
    fn network_choice() {
        let subnet = read(&[]).unwrap();
        let local = read(&[("ROS_AUTOMATIC_DISCOVERY_RANGE", "LOCALHOST")]).unwrap();
        let lo = iface("lo", true, true, false);
        let eth = iface("eth0", true, false, true);
        // A machine on a network: multicast there, unless LOCALHOST.
        let both = [lo.clone(), eth.clone()];
        assert!(!choose_network(&subnet, &both).unwrap().loopback_only);
        assert!(choose_network(&local, &both).unwrap().loopback_only);
        // Only loopback: loopback either way.
        assert!(
            choose_network(&subnet, std::slice::from_ref(&lo))
                .unwrap()
                .loopback_only
        );
        assert!(
            choose_network(&local, std::slice::from_ref(&lo))
                .unwrap()
                .loopback_only
        );
        // Nothing up: an error naming the settings.
        let down = [
            iface("lo", false, true, false),
            iface("eth0", false, false, true),
        ];
        for e in [&subnet, &local] {
            let msg = choose_network(e, &down).unwrap_err();
            assert!(msg.contains("no network interface can carry DDS"), "{msg}");
            assert!(msg.contains("lo (down, loopback)"), "{msg}");
            assert!(msg.contains("ip link set lo up"), "{msg}");
        }
        assert!(choose_network(&subnet, &down)
            .unwrap_err()
            .contains("ROS_AUTOMATIC_DISCOVERY_RANGE=LOCALHOST"));
        let off = read(&[("ROS_AUTOMATIC_DISCOVERY_RANGE", "OFF")]).unwrap();
        assert!(choose_network(&off, &both)
            .unwrap_err()
            .contains("ROS_AUTOMATIC_DISCOVERY_RANGE=OFF"));
    }
}
