//! An address prefix: what the node counts a peer's connections and guesses by, so that one
//! IPv6 host, which can choose its addresses from a /64, counts once.

use std::net::IpAddr;

/// An address prefix: an IPv4 address, or an IPv6 address's first 64 bits (an IPv4-mapped
/// IPv6 address counts as its IPv4 address).
#[derive(Clone, Copy, PartialEq, Eq, Hash, Debug)]
pub(crate) enum Prefix {
    V4([u8; 4]),
    V6([u16; 4]),
}

impl Prefix {
    pub(crate) fn of(ip: IpAddr) -> Self {
        match ip {
            IpAddr::V4(v4) => Self::V4(v4.octets()),
            IpAddr::V6(v6) => match v6.to_ipv4_mapped() {
                Some(v4) => Self::V4(v4.octets()),
                None => {
                    let [a, b, c, d, ..] = v6.segments();
                    Self::V6([a, b, c, d])
                }
            },
        }
    }
}
