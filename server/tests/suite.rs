//! The node's integration tests, in one test binary so that they are built and linked once:
//! each module is one file of this folder, and `logged.rs`, which captures the process's log,
//! stays a binary of its own.

mod access;
mod auth;
mod cli;
mod common;
mod definitions;
mod fairness;
mod faults;
mod frames;
mod front_door;
mod guesses;
mod limits;
mod load;
mod protocol;
mod relayed;
mod revoke;
mod scenes;
mod subscriptions;
mod time;
mod whoami;
