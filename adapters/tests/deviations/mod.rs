//! One test per deviation from Autoware's `rtc_interface` (spec §9), named after its tag.
//! Each shows the upstream quirk's trigger and this library's behaviour.

mod rtc;
mod state;
