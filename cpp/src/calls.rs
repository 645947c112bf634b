//! The bridge's functions: each is one call of `cooperation_adapters` on a node's [`Core`], its
//! arguments converted in and its answer converted out.

use cooperation::{SceneId, Sequence, Transition};
use cooperation_adapters::engine::{self, Engine, Now};
use cooperation_adapters::rtc::{
    self, AutoModeRequest, CooperateCommand, CooperateCommandsRequest, CooperateCommandsResponse,
    InterfaceId, RtcError, StatusReport,
};
use cooperation_adapters::{Host, Shared, Time};

use crate::bridge::ffi::{
    self, Answered, CommandIn, CommandOut, Flag, Outcome, Stamp, Status, Told, Uuid,
};
use crate::snapshot::{Answers, Lookup, Snapshot};

/// One node's core: the service engine (the state, the RTC interfaces' routing and the clock
/// the core was last told of) behind one lock ([`Shared`]), shared by every interface of the
/// node (in C++, by every `RTCInterface` built on the same node) and by its service callbacks.
#[derive(Debug)]
pub struct Core {
    shared: Shared,
}

impl Core {
    /// A core built as every node builds its own: the built-in settings file's policies and
    /// limits (`cooperation_adapters::settings::BUILT_IN`), the standard bindings, the engine's
    /// default options, and `quota` live scenes per interface (0: no quota; the nodes' default
    /// is `default_scene_quota()`).
    ///
    /// # Errors
    /// The settings' or the core's refusal of the configuration (the built-in file is valid, so
    /// neither happens).
    pub fn new(quota: usize) -> Result<Self, String> {
        let options = engine::Options {
            scene_quota: quota,
            ..engine::Options::default()
        };
        Ok(Self {
            shared: Shared::new(Engine::from_settings(None, options).map_err(|e| e.to_string())?),
        })
    }

    /// The shared core, for a Rust caller in the same process.
    #[must_use]
    pub const fn shared(&self) -> &Shared {
        &self.shared
    }

    /// Runs `change` under the core's lock, telling ThreadSanitizer of the lock.
    fn change<R>(&self, change: impl FnOnce(&mut Engine) -> R) -> R {
        let address = std::ptr::from_ref(self) as usize;
        self.shared.update(|engine| {
            ffi::lock_acquired(address);
            let answer = change(engine);
            ffi::lock_releasing(address);
            answer
        })
    }

    /// Makes `call` at the node clock's `now` ([`Engine::call_at`]: the core is told the time
    /// first, `[COOP-ENGINE-TIME.1]`), in one step under the core's lock: the call's result, and
    /// the scenes that expired before it.
    fn call_at<T, E>(
        &self,
        now: Stamp,
        call: impl FnOnce(&mut Host) -> Result<T, E>,
    ) -> (Result<T, E>, Vec<Uuid>) {
        self.change(|engine| {
            let (result, _, ticked) = engine.call_at(Now::of_stamp(time(now)), call);
            (result, expired(ticked))
        })
    }

    /// Runs `query` under the core's lock, telling ThreadSanitizer of the lock: `query` is
    /// given the core's change count ([`Shared::changes`]) with it.
    fn query<R>(&self, query: impl FnOnce(u64, &Host) -> R) -> R {
        let address = std::ptr::from_ref(self) as usize;
        self.shared.read_counted(|changes, engine| {
            ffi::lock_acquired(address);
            let answer = query(changes, engine.host());
            ffi::lock_releasing(address);
            answer
        })
    }
}

/// One RTC interface of a node's core, found by name once (the C++ `InterfaceCore` holds it), so
/// that the calls made through it do not search the bindings by name each time.
#[derive(Debug)]
pub struct Handle {
    /// The interface, or why no binding has the name (every call through it is refused so).
    found: Result<InterfaceId, RtcError>,
    /// The answers of the interface's queries, kept for the next queries while the core does
    /// not change.
    snapshot: Snapshot,
}

impl Handle {
    /// The interface, to change the core through.
    fn interface<'h>(&self, host: &'h mut Host) -> Result<rtc::Interface<'h>, RtcError> {
        match &self.found {
            Ok(id) => host.interface_at(*id),
            Err(refusal) => Err(refusal.clone()),
        }
    }

    /// The interface, to query.
    fn view<'h>(&self, host: &'h Host) -> Result<rtc::View<'h>, RtcError> {
        match &self.found {
            Ok(id) => host.view_at(*id),
            Err(refusal) => Err(refusal.clone()),
        }
    }
}

/// The interface `name` of `core`, found once.
pub(crate) fn find(core: &Core, name: &str) -> Box<Handle> {
    Box::new(Handle {
        found: core.query(|_, host| host.rtc().find(name)),
        snapshot: Snapshot::default(),
    })
}

pub(crate) fn new_core(quota: usize) -> Result<Box<Core>, String> {
    Core::new(quota).map(Box::new)
}

/// The scene quota per interface a node has unless told otherwise, the same for every host.
pub(crate) fn default_scene_quota() -> usize {
    engine::Options::default().scene_quota
}

fn outcome<T>(result: Result<T, RtcError>) -> Outcome {
    match result {
        Ok(_) => Outcome {
            ok: true,
            warning: String::new(),
        },
        Err(error) => Outcome {
            ok: false,
            warning: error.to_string(),
        },
    }
}

fn id(uuid: &Uuid) -> SceneId {
    rtc::Uuid { uuid: uuid.bytes }.into()
}

fn uuid(id: SceneId) -> Uuid {
    Uuid {
        bytes: rtc::Uuid::from(id).uuid,
    }
}

const fn time(stamp: Stamp) -> Time {
    Time::new(stamp.sec, stamp.nanosec)
}

/// The scenes that aged out in `ticked`, if time passed.
fn expired(ticked: Option<Transition>) -> Vec<Uuid> {
    ticked.map_or_else(Vec::new, |transition| {
        transition.retired.into_iter().map(uuid).collect()
    })
}

/// What a call made at the node's time did, and the scenes that expired before it.
fn told<T>((result, expired): (Result<T, RtcError>, Vec<Uuid>)) -> Told {
    Told {
        outcome: outcome(result),
        expired,
    }
}

pub(crate) fn bind(core: &Core, handle: &Handle, enable_rtc: bool) -> Outcome {
    core.change(|engine| {
        outcome(
            engine
                .call(|host| {
                    handle.interface(host).and_then(|mut interface| {
                        interface
                            .auto_mode(&AutoModeRequest {
                                enable: !enable_rtc,
                            })
                            .result
                    })
                })
                .0,
        )
    })
}

pub(crate) fn module_type(core: &Core, handle: &Handle) -> u8 {
    view(core, handle, |view| {
        rtc::Module::from(view.binding().module_type).r#type
    })
    .unwrap_or(rtc::Module::NONE)
}

/// A distance as the core's reports carry it. A double beyond `f32`'s range becomes an infinity,
/// which the core takes as it takes every distance, NaN included (they order after every
/// number).
#[allow(clippy::cast_possible_truncation)]
const fn metres(distance: f64) -> f32 {
    distance as f32
}

#[allow(clippy::too_many_arguments)] // Upstream's arguments, and the sequence.
pub(crate) fn update(
    core: &Core,
    now: Stamp,
    handle: &Handle,
    uuid: &Uuid,
    safe: bool,
    state: u8,
    start_distance: f64,
    finish_distance: f64,
    requested: bool,
    stated: bool,
    sequence: &str,
) -> Told {
    let report = rtc::Lifecycle::new(state)
        .phase()
        .map_err(|e| RtcError::from(e.within("state")))
        .map(|phase| StatusReport {
            requested,
            ..StatusReport::new(
                id(uuid),
                safe,
                phase,
                metres(start_distance),
                metres(finish_distance),
            )
        });
    let report = match (report, stated) {
        (Ok(report), true) => match Sequence::named(sequence) {
            Ok(sequence) => Ok(report.in_sequence(sequence)),
            Err(problem) => {
                // Refused here, and the core is still told the time, as for any report.
                return Told {
                    outcome: Outcome {
                        ok: false,
                        warning: format!("sequence {sequence:?}: {problem}"),
                    },
                    expired: advance(core, now),
                };
            }
        },
        (report, _) => report,
    };
    told(core.call_at(now, |host| {
        report.and_then(|report| {
            handle
                .interface(host)?
                .update_cooperate_status(&report)
                .map(drop)
        })
    }))
}

pub(crate) fn remove(core: &Core, handle: &Handle, uuid: &Uuid) -> Outcome {
    core.change(|engine| {
        outcome(
            engine
                .call(|host| {
                    handle
                        .interface(host)
                        .and_then(|mut interface| interface.remove_cooperate_status(id(uuid)))
                })
                .0,
        )
    })
}

pub(crate) fn clear(core: &Core, handle: &Handle) -> Outcome {
    core.change(|engine| {
        outcome(
            engine
                .call(|host| {
                    handle
                        .interface(host)
                        .and_then(|mut interface| interface.clear_cooperate_status())
                })
                .0,
        )
    })
}

pub(crate) fn advance(core: &Core, now: Stamp) -> Vec<Uuid> {
    // The engine takes the first reading as its time 0, and a reading before the last as no
    // time passing.
    let now = Now::of_stamp(time(now));
    // Most of a node's calls come in the millisecond the core was last told of (every
    // interface's `removeExpiredCooperateStatus` after the cycle's updates): no time to tell,
    // no lock to take, and the queries' copies stay current.
    if core.shared.told_in(now) {
        return Vec::new();
    }
    core.change(|engine| expired(engine.advance(now).1))
}

fn view<R>(core: &Core, handle: &Handle, query: impl FnOnce(&rtc::View<'_>) -> R) -> Option<R> {
    core.query(|_, host| handle.view(host).ok().map(|view| query(&view)))
}

/// A query about the scene `uuid`: answered from the handle's snapshot by `copied` when the
/// snapshot is current and `copied` can answer; else, under the core's lock, the snapshot is
/// made again if the core changed and answers if it can, and `asked` answers through the core
/// if not (`None`: the interface cannot be queried, as [`view`]).
fn ask<R>(
    core: &Core,
    handle: &Handle,
    uuid: &Uuid,
    copied: impl Fn(Option<Answers>) -> Option<R>,
    asked: impl FnOnce(&rtc::View<'_>) -> R,
) -> Option<R> {
    let from_copy = |changes| match handle.snapshot.lookup(changes, &uuid.bytes) {
        Lookup::Current(answers) => copied(answers),
        Lookup::Ask => None,
    };
    if let Some(answer) = from_copy(core.shared.changes()) {
        return Some(answer);
    }
    core.query(|changes, host| {
        let view = handle.view(host).ok();
        handle.snapshot.make(changes, view.as_ref());
        // The copy just made is current while the lock is held.
        from_copy(changes).or_else(|| view.map(|view| asked(&view)))
    })
}

/// A yes-or-no query that is `false` for a scene that is not a live scene of the interface.
fn ask_live(
    core: &Core,
    handle: &Handle,
    uuid: &Uuid,
    copied: impl Fn(Answers) -> bool,
    asked: impl FnOnce(&rtc::View<'_>, SceneId) -> bool,
) -> bool {
    ask(
        core,
        handle,
        uuid,
        |answers| Some(answers.is_some_and(&copied)),
        |view| asked(view, id(uuid)),
    )
    .unwrap_or(false)
}

pub(crate) fn is_registered(core: &Core, handle: &Handle, uuid: &Uuid) -> bool {
    ask_live(
        core,
        handle,
        uuid,
        |_| true,
        |view, id| view.is_registered(id),
    )
}

pub(crate) fn is_activated(core: &Core, handle: &Handle, uuid: &Uuid) -> bool {
    ask_live(core, handle, uuid, Answers::activated, |view, id| {
        view.is_activated(id)
    })
}

pub(crate) fn is_force_activated(core: &Core, handle: &Handle, uuid: &Uuid) -> bool {
    ask_live(core, handle, uuid, Answers::force_activated, |view, id| {
        view.is_force_activated(id)
    })
}

pub(crate) fn is_force_deactivated(core: &Core, handle: &Handle, uuid: &Uuid) -> bool {
    ask_live(
        core,
        handle,
        uuid,
        Answers::force_deactivated,
        |view, id| view.is_force_deactivated(id),
    )
}

fn flag(answer: Option<Option<bool>>) -> Flag {
    match answer.flatten() {
        Some(true) => Flag::Yes,
        Some(false) => Flag::No,
        None => Flag::Unknown,
    }
}

pub(crate) fn is_rtc_enabled(core: &Core, handle: &Handle, uuid: &Uuid) -> Flag {
    // A scene that is not live has no answer ([`flag`]).
    flag(ask(
        core,
        handle,
        uuid,
        |answers| Some(answers.map(Answers::rtc_enabled)),
        |view| view.is_rtc_enabled(id(uuid)),
    ))
}

pub(crate) fn is_terminated(core: &Core, handle: &Handle, uuid: &Uuid) -> Flag {
    // A live scene is not terminated; of one that is not live, the snapshot knows nothing.
    flag(ask(
        core,
        handle,
        uuid,
        |answers| answers.map(|_| Some(false)),
        |view| view.is_terminated(id(uuid)),
    ))
}

/// Replaces `out`'s contents with the interface's statuses (none if it cannot be queried); it
/// allocates only when `out` has too little capacity.
pub(crate) fn statuses_into(core: &Core, handle: &Handle, stamp: Stamp, out: &mut Vec<Status>) {
    out.clear();
    view(core, handle, |view| {
        out.extend(view.cooperate_statuses(time(stamp)).map(|status| Status {
            stamp: Stamp {
                sec: status.stamp.sec,
                nanosec: status.stamp.nanosec,
            },
            uuid: Uuid {
                bytes: status.uuid.uuid,
            },
            module: status.module.r#type,
            safe: status.safe,
            requested: status.requested,
            command: status.command_status.r#type,
            state: status.state.r#type,
            auto_mode: status.auto_mode,
            start_distance: status.start_distance,
            finish_distance: status.finish_distance,
        }));
    });
}

pub(crate) fn auto_mode_status(core: &Core, handle: &Handle) -> bool {
    view(core, handle, |view| view.auto_mode_status().is_auto_mode).unwrap_or(false)
}

pub(crate) fn cooperate_commands(
    core: &Core,
    now: Stamp,
    handle: &Handle,
    commands: &[CommandIn],
) -> Answered {
    let request = CooperateCommandsRequest {
        stamp: Time::default(),
        commands: commands
            .iter()
            .map(|command| CooperateCommand {
                uuid: rtc::Uuid {
                    uuid: command.uuid.bytes,
                },
                module: rtc::Module::new(command.module),
                command: rtc::Command::new(command.command),
            })
            .collect(),
    };
    let mut response = None;
    let (result, expired) = core.call_at(now, |host| {
        let reply = handle.interface(host)?.cooperate_commands(&request);
        response = Some(reply.response);
        reply.result
    });
    // The adapter's response; an interface that is not there refuses every command.
    let response =
        response.unwrap_or_else(|| CooperateCommandsResponse::answering(&request, false));
    // What the adapter answered, entry for entry (in the adapter's own allocation: the two
    // entries have one layout, so the collection reuses it).
    Answered {
        outcome: outcome(result),
        responses: response
            .responses
            .into_iter()
            .map(|answer| CommandOut {
                uuid: Uuid {
                    bytes: answer.uuid.uuid,
                },
                module: answer.module.r#type,
                success: answer.success,
            })
            .collect(),
        expired,
    }
}

pub(crate) fn auto_mode(core: &Core, now: Stamp, handle: &Handle, enable: bool) -> Told {
    told(core.call_at(now, |host| {
        handle
            .interface(host)
            .and_then(|mut interface| interface.auto_mode(&AutoModeRequest { enable }).result)
    }))
}

#[cfg(test)]
mod tests;
