//! The ROS graph: `ros_discovery_info`, where each ROS 2 participant says which nodes it holds and
//! which readers and writers each node owns, so that `ros2 node list` and `ros2 node info` show
//! the node.

use serde::ser::SerializeTuple;
use serde::{Serialize, Serializer};

/// The topic (a DDS topic of the middleware's own, without `rt/`).
pub const TOPIC: &str = "ros_discovery_info";
/// Its DDS type.
pub const TYPE: &str = "rmw_dds_common::msg::dds_::ParticipantEntitiesInfo_";

/// The ROS 2 release line, which fixes the length of an entity's `Gid` on the wire.
#[derive(Clone, Copy, PartialEq, Eq, Debug, clap::ValueEnum)]
pub enum Distro {
    /// Humble and older: `uint8[24] data`.
    Humble,
    /// Iron, Jazzy and newer: `uint8[16] data`.
    Jazzy,
}

impl Distro {
    /// The length of a `Gid`.
    #[must_use]
    pub const fn gid_len(self) -> usize {
        match self {
            Self::Humble => 24,
            Self::Jazzy => 16,
        }
    }
}

/// `rmw_dds_common/Gid`: an entity's DDS GUID, zero-padded to the release's length (a fixed
/// array on the wire, with no count).
#[derive(Clone, PartialEq, Eq, Debug)]
pub struct Gid {
    /// The GUID's sixteen bytes.
    pub guid: [u8; 16],
    /// The length on the wire.
    pub len: usize,
}

impl Serialize for Gid {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        let mut array = serializer.serialize_tuple(self.len)?;
        for index in 0..self.len {
            array.serialize_element(&self.guid.get(index).copied().unwrap_or(0))?;
        }
        array.end()
    }
}

/// `rmw_dds_common/NodeEntitiesInfo`.
#[derive(Clone, PartialEq, Eq, Debug, Serialize)]
pub struct NodeEntitiesInfo {
    /// The node's namespace, e.g. `/`.
    pub node_namespace: String,
    /// The node's name.
    pub node_name: String,
    /// Its readers.
    pub reader_gid_seq: Vec<Gid>,
    /// Its writers.
    pub writer_gid_seq: Vec<Gid>,
}

/// `rmw_dds_common/ParticipantEntitiesInfo`.
#[derive(Clone, PartialEq, Eq, Debug, Serialize)]
pub struct ParticipantEntitiesInfo {
    /// The participant.
    pub gid: Gid,
    /// Its nodes.
    pub node_entities_info_seq: Vec<NodeEntitiesInfo>,
}
