use std::{
  io,
  net::{IpAddr, SocketAddr},
};

use log::error;
use pnet::datalink::NetworkInterface;

use crate::structure::locator::Locator;

pub fn get_local_multicast_locators(port: u16) -> Vec<Locator> {
  let saddr = SocketAddr::new("239.255.0.1".parse().unwrap(), port);
  vec![Locator::from(saddr)]
}

#[cfg(test)]
pub fn get_local_unicast_locators(port: u16) -> Vec<Locator> {
  get_local_unicast_locators_on(port, false)
}

/// The unicast locators of this host at `port`: the addresses of its
/// non-loopback interfaces, or with `loopback_only` those of its loopback
/// interfaces (127.0.0.1), as Cyclone DDS and Fast DDS announce when
/// restricted to localhost.
pub fn get_local_unicast_locators_on(port: u16, loopback_only: bool) -> Vec<Locator> {
  match if_addrs::get_if_addrs() {
    Ok(ifaces) => ifaces
      .iter()
      .filter(|ip| ip.is_loopback() == loopback_only)
      .filter(|ip| !loopback_only || ip.ip().is_ipv4())
      .map(|ip| Locator::from(SocketAddr::new(ip.ip(), port)))
      .collect(),
    Err(e) => {
      error!("Cannot get local network interfaces: get_if_addrs() : {e:?}");
      vec![]
    }
  }
}

/// Enumerates local interfaces that we may use for multicasting.
///
/// The result of this function is used to set up senders and listeners.
#[cfg(test)]
pub fn get_local_multicast_ip_addrs() -> io::Result<Vec<IpAddr>> {
  get_local_multicast_ip_addrs_on(false)
}

/// [`get_local_multicast_ip_addrs`], or with `loopback_only` the IPv4
/// addresses of the loopback interfaces that are up and multicast-capable
/// (Linux's `lo` is after `ip link set lo multicast on`).
pub fn get_local_multicast_ip_addrs_on(loopback_only: bool) -> io::Result<Vec<IpAddr>> {
  // grab a list of system intefaces.
  //
  // note: `pnet` works on mac, windows, and linux, potentially alongside
  // other systems.
  let interfaces = pnet::datalink::interfaces();

  if loopback_only {
    return Ok(
      interfaces
        .into_iter()
        .filter(|i| i.is_loopback() && i.is_up() && i.is_multicast())
        .flat_map(|i| i.ips)
        .map(|ip_net| ip_net.ip())
        .filter(|ip| ip.is_ipv4())
        .collect(),
    );
  }

  // grab all the ips from each interface
  Ok(get_local_multicast_ip_addrs_inner(interfaces))
}

/// Inner implementation of [`get_local_multicast_ip_addrs`], for testing
/// purposes.
fn get_local_multicast_ip_addrs_inner(interfaces: Vec<NetworkInterface>) -> Vec<IpAddr> {
  interfaces
    .into_iter()
    .filter(|ifaddr| !ifaddr.is_loopback()) // don't use lo interface
    .filter(|ifaddr| ifaddr.is_multicast()) // require support for multicast
    .flat_map(|ifaddr| ifaddr.ips)
    .map(|ip_net| ip_net.ip()) // get the ip from each ip network
    .filter(|ip| ip.is_ipv4()) // use ipv4 only :(
    .collect::<Vec<_>>()
}

/// A network interface of this host as RustDDS sees it when choosing where
/// to talk (see [`crate::DomainParticipantBuilder::loopback_only`]).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct LocalInterface {
  pub name: String,
  pub ipv4: Vec<std::net::Ipv4Addr>,
  pub up: bool,
  pub loopback: bool,
  pub multicast: bool,
}

/// The interfaces of this host with their IPv4 addresses and flags.
pub fn local_interfaces() -> Vec<LocalInterface> {
  pnet::datalink::interfaces()
    .into_iter()
    .map(|i| LocalInterface {
      ipv4: i
        .ips
        .iter()
        .filter_map(|n| match n.ip() {
          IpAddr::V4(a) => Some(a),
          IpAddr::V6(_) => None,
        })
        .collect(),
      up: i.is_up(),
      loopback: i.is_loopback(),
      multicast: i.is_multicast(),
      name: i.name,
    })
    .collect()
}

#[cfg(test)]
mod tests {
  use std::{
    ffi::c_int,
    net::{Ipv4Addr, Ipv6Addr},
  };

  use pnet::{
    datalink::{InterfaceType, NetworkInterface},
    ipnetwork::{IpNetwork, Ipv4Network, Ipv6Network},
  };

  /// Mocks the `get_local_multicast_ip_addrs` function.
  #[test]
  fn test_get_local_multicast_ip_addrs() {
    let eth0 = interface(
      "eth0",
      1,
      &[
        IpNetwork::V4(Ipv4Network::new(Ipv4Addr::new(192, 168, 0, 137), 24).unwrap()),
        IpNetwork::V6(
          Ipv6Network::new(Ipv6Addr::new(0xfd73, 0x40a2, 0x1c3e, 0, 0, 0, 0, 0), 64).unwrap(),
        ),
      ],
      &[pnet_sys::IFF_MULTICAST],
    );

    let interfaces = vec![loopback(), eth0];

    let ips = super::get_local_multicast_ip_addrs_inner(interfaces);

    // TODO: uncomment if IPv6 becomes supported :(
    // assert_eq!(ips.len(), 2, "should only contain the non-loopback iface");
    assert_eq!(ips.len(), 1, "should only contain the non-loopback iface");
    assert!(ips.contains(&Ipv4Addr::new(192, 168, 0, 137).into()));

    // TODO: uncomment if ipv6
    // assert!(ips.contains(&Ipv6Addr::new(0xfd73, 0x40a2, 0x1c3e, 0, 0, 0, 0,
    // 0).into()))
  }

  /// Tries a number of interfaces, none of which support multicast.
  ///
  /// This should result in an empty list of IP addresses.
  #[test]
  fn no_multicast() {
    let mut interfaces = Vec::new();

    for index in 0..10 {
      interfaces.push(interface(
        format!("eth{index}"),
        index,
        &[IpNetwork::V4(
          Ipv4Network::new(Ipv4Addr::new(192, 168, 0, rand::random()), 24).unwrap(),
        )],
        &[],
      ));
    }

    let ips = super::get_local_multicast_ip_addrs_inner(interfaces);

    assert!(
      ips.is_empty(),
      "we only want interfaces w/ multicast support"
    );
  }

  #[test]
  fn empty_interfaces() {
    let ips = super::get_local_multicast_ip_addrs_inner(Vec::new());
    assert!(
      ips.is_empty(),
      "blank iface list should result in empty list of ips"
    );
  }

  fn loopback() -> NetworkInterface {
    NetworkInterface {
      name: "lo".to_string(),
      description: "loopback".to_string(),
      index: 0,
      mac: None,
      ips: vec![
        IpNetwork::V4(Ipv4Network::new(Ipv4Addr::LOCALHOST, 24).unwrap()),
        IpNetwork::V6(Ipv6Network::new(Ipv6Addr::LOCALHOST, 64).unwrap()),
      ],
      flags: pnet_sys::IFF_MULTICAST as InterfaceType & pnet_sys::IFF_LOOPBACK as InterfaceType,
    }
  }

  fn interface(
    name: impl AsRef<str>,
    index: u32,
    ips: &[IpNetwork],
    flags: &[c_int],
  ) -> NetworkInterface {
    NetworkInterface {
      name: name.as_ref().into(),
      description: String::new(),
      index,
      mac: None,
      ips: ips.to_vec(),
      flags: flags
        .iter()
        .fold(0, |acc, &flag| acc | flag as InterfaceType),
    }
  }
}
