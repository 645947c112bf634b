//! The bridge: the types that cross between C++ and Rust, and the functions C++ calls. Each
//! function is implemented in `calls.rs` (or `timing.rs`, for the benchmark) and is one call on
//! the shared core.

// `update` takes upstream's seven arguments, the interface and the sequence.
#![allow(clippy::too_many_arguments)]

use crate::calls::*;
use crate::timing::time_rust_calls;

/// The declarations `cxx` turns into `cooperation-cpp/src/bridge.rs.h`, in C++ namespace
/// `cooperation::bridge`.
#[cxx::bridge(namespace = "cooperation::bridge")]
pub mod ffi {
    /// A scene's 16-byte identifier, as `unique_identifier_msgs/UUID` carries it.
    #[derive(Clone, Copy, PartialEq, Eq, Debug)]
    struct Uuid {
        /// The bytes, most significant first.
        bytes: [u8; 16],
    }

    /// A time, as `builtin_interfaces/Time` carries it.
    #[derive(Clone, Copy, PartialEq, Eq, Debug)]
    struct Stamp {
        /// Seconds.
        sec: i32,
        /// Nanoseconds within the second.
        nanosec: u32,
    }

    /// What a call that changes the core did: `ok`, or the reason it changed nothing.
    #[derive(Clone, PartialEq, Eq, Debug)]
    struct Outcome {
        /// The call applied.
        ok: bool,
        /// Why it did not (empty when it did): the adapter's explanation, for a warning.
        warning: String,
    }

    /// What a call made at the node's time did, and the scenes that expired by that time, before
    /// the call (the core is told the time and the call is made in one step, under one lock).
    #[derive(Clone, PartialEq, Eq, Debug)]
    struct Told {
        /// What the call did.
        outcome: Outcome,
        /// The scenes that expired, for the log.
        expired: Vec<Uuid>,
    }

    /// A yes-or-no answer that may have none, where the adapter answers `None`
    /// (`[COOP-DEV-UNKNOWN-QUERY.1]`); one byte, passed as a number rather than through memory.
    #[derive(Debug)]
    enum Flag {
        /// The adapter has no answer.
        Unknown,
        /// No.
        No,
        /// Yes.
        Yes,
    }

    /// One `tier4_rtc_msgs/CooperateStatus`, its constants as their numbers.
    #[derive(Clone, Copy, PartialEq, Debug)]
    struct Status {
        /// The owner's last report.
        stamp: Stamp,
        /// The scene.
        uuid: Uuid,
        /// `Module.type`.
        module: u8,
        /// The module decision is activate.
        safe: bool,
        /// The owner asks the operator explicitly.
        requested: bool,
        /// `command_status.type`.
        command: u8,
        /// `state.type`.
        state: u8,
        /// The scene proceeds on the module's judgment.
        auto_mode: bool,
        /// Distance to the start of its section, in metres.
        start_distance: f32,
        /// Distance to the end of its section, in metres.
        finish_distance: f32,
    }

    /// One `tier4_rtc_msgs/CooperateCommand`, its constants as their numbers.
    #[derive(Clone, Copy, PartialEq, Eq, Debug)]
    struct CommandIn {
        /// The scene.
        uuid: Uuid,
        /// `module.type`.
        module: u8,
        /// `command.type`.
        command: u8,
    }

    /// One `tier4_rtc_msgs/CooperateResponse`: the adapter's answer for one command.
    #[derive(Clone, Copy, PartialEq, Eq, Debug)]
    struct CommandOut {
        /// The scene the command named.
        uuid: Uuid,
        /// `module.type`, as the command gave it.
        module: u8,
        /// Whether the command applied.
        success: bool,
    }

    /// The `CooperateCommands` service's answer: what the call did, and the adapter's response
    /// for each command, in request order.
    #[derive(Clone, PartialEq, Eq, Debug)]
    struct Answered {
        /// What the call did.
        outcome: Outcome,
        /// The response's entries, as the adapter wrote them.
        responses: Vec<CommandOut>,
        /// The scenes that expired by the call's time, before it, for the log.
        expired: Vec<Uuid>,
    }

    /// One call's cost in the benchmark's Rust baseline.
    #[derive(Clone, PartialEq, Debug)]
    struct CallCost {
        /// The upstream method the call stands for.
        method: String,
        /// Nanoseconds per call.
        nanos: f64,
    }

    extern "Rust" {
        /// One node's core: its state, RTC interfaces and clock, behind one lock.
        type Core;
        /// One RTC interface of a core, found by name once: the calls made through it do not
        /// search the bindings by name.
        type Handle;

        /// A core built as every node builds its own (the built-in settings file's policies
        /// and limits, the standard interface bindings). `quota` is the most live scenes one
        /// interface may hold (0: no quota).
        fn new_core(quota: usize) -> Result<Box<Core>>;
        /// The scene quota per interface every node has unless told otherwise.
        fn default_scene_quota() -> usize;
        /// The interface `name` of the core, found once (a name with no binding gives a handle
        /// through which every call is refused, saying so).
        fn find(core: &Core, name: &str) -> Box<Handle>;
        /// Binds the interface and sets its modules' policy as upstream's `enable_rtc`
        /// constructor argument does.
        fn bind(core: &Core, interface: &Handle, enable_rtc: bool) -> Outcome;
        /// The module type the interface's statuses carry (0, `NONE`, if it is not bound).
        fn module_type(core: &Core, interface: &Handle) -> u8;
        /// `updateCooperateStatus` made at the node clock's `now` (the core is told it first);
        /// `sequence` is stated when `stated` is true.
        fn update(
            core: &Core,
            now: Stamp,
            interface: &Handle,
            uuid: &Uuid,
            safe: bool,
            state: u8,
            start_distance: f64,
            finish_distance: f64,
            requested: bool,
            stated: bool,
            sequence: &str,
        ) -> Told;
        /// `removeCooperateStatus`.
        fn remove(core: &Core, interface: &Handle, uuid: &Uuid) -> Outcome;
        /// `clearCooperateStatus`.
        fn clear(core: &Core, interface: &Handle) -> Outcome;
        /// Tells the core the node's clock reads `now`; answers the scenes that expired.
        fn advance(core: &Core, now: Stamp) -> Vec<Uuid>;
        /// `isRegistered`.
        fn is_registered(core: &Core, interface: &Handle, uuid: &Uuid) -> bool;
        /// `isActivated`.
        fn is_activated(core: &Core, interface: &Handle, uuid: &Uuid) -> bool;
        /// `isForceActivated`.
        fn is_force_activated(core: &Core, interface: &Handle, uuid: &Uuid) -> bool;
        /// `isForceDeactivated`.
        fn is_force_deactivated(core: &Core, interface: &Handle, uuid: &Uuid) -> bool;
        /// `isRTCEnabled`.
        fn is_rtc_enabled(core: &Core, interface: &Handle, uuid: &Uuid) -> Flag;
        /// `isTerminated`.
        fn is_terminated(core: &Core, interface: &Handle, uuid: &Uuid) -> Flag;
        /// Replaces `out`'s contents with the statuses `publishCooperateStatus` publishes,
        /// keeping its capacity.
        fn statuses_into(core: &Core, interface: &Handle, stamp: Stamp, out: &mut Vec<Status>);
        /// The interface's auto-mode status.
        fn auto_mode_status(core: &Core, interface: &Handle) -> bool;
        /// The interface's `CooperateCommands` service, called at the node clock's `now` (the
        /// core is told it first): the adapter's response, entry for entry.
        fn cooperate_commands(
            core: &Core,
            now: Stamp,
            interface: &Handle,
            commands: &[CommandIn],
        ) -> Answered;
        /// The interface's `AutoMode` service, called at the node clock's `now` (the core is
        /// told it first).
        fn auto_mode(core: &Core, now: Stamp, interface: &Handle, enable: bool) -> Told;

        /// The benchmark's Rust baseline: the same calls as the C++ class makes, through
        /// `cooperation_adapters` directly, with `scenes` live scenes, `rounds` times each.
        fn time_rust_calls(scenes: usize, rounds: usize) -> Vec<CallCost>;
    }

    unsafe extern "C++" {
        include!("cooperation/rtc/annotate.hpp");

        /// The lock of the core at `address` was just taken (for ThreadSanitizer, which cannot
        /// see Rust's lock; a no-op otherwise).
        fn lock_acquired(address: usize);
        /// The lock of the core at `address` is about to be let go.
        fn lock_releasing(address: usize);
    }
}
