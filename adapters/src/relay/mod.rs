//! The relay: the service engine over planning modules that speak upstream's RTC endpoints.
//!
//! Beside a stock Autoware stack the planning modules keep their own RTC interfaces (upstream's
//! `rtc_interface`, or this project's C++ class): each publishes its scenes on
//! `/planning/cooperate_status/<name>` and its auto mode on `/planning/auto_mode_status/<name>`,
//! and serves `/planning/cooperate_commands/<name>` and `/planning/enable_auto_mode/<name>`. The
//! relay is the sans-IO core of a node that sits between those endpoints and the AD API, in the
//! shape the engine has ([`Engine`]):
//!
//! - [`Relay::take_statuses`] and [`Relay::take_auto_mode`]: a module's messages, each status
//!   array its report into the core through the RTC adapter (`[COOP-RELAY-REPORT.1]`).
//! - [`Relay::handle_operator`]: an AD API call. The core checks it first; what it accepts is
//!   forwarded to the owning modules, and applied to the core only as far as they take it
//!   (`[COOP-RELAY-FORWARD.1]`, `[COOP-RELAY-SUCCESS.1]`); the answer comes from
//!   [`Relay::poll_answer`] once every module answered or its deadline passed.
//! - [`Relay::poll_forward`] hands out the calls to send to modules, one at a time per module;
//!   [`Relay::take_answer`] takes a module's answer.
//! - [`Relay::handle_timeout`]: time between messages (deadlines, scenes ageing out).
//!
//! Between calls the relay compares what each module last said of its scenes with what the core
//! decides and sends what makes them agree (`[COOP-RELAY-FOLLOW.1]`): an auto-mode switch, then
//! the standing operator decisions it overwrote (`[COOP-RELAY-POLICY.1]`). Nothing here restates
//! a rule of the core: every change is an input to the core through the adapters.

mod error;
pub mod factors;
mod forward;
mod link;
mod operator;
mod pending;

pub use error::{ArrayError, ArrayTaken, RelayRefusal};
pub use link::{Correction, Link, Seen};

use std::collections::{BTreeMap, VecDeque};
use std::hash::{Hash, Hasher};

use cooperation::{Decision, OperatorDecision, Phase, SceneId, State};

use crate::engine::{Engine, Now, Publication};
use crate::rtc::{
    self, AutoModeRequest, AutoModeStatus, Binding, CooperateCommand, CooperateCommandsRequest,
    CooperateCommandsResponse, CooperateStatusArray, RtcError, StatusReport,
};
use crate::wire;
use crate::{Host, Time};
use pending::Pending;

/// How long a module has to answer a forwarded call unless the host says otherwise, in
/// milliseconds.
pub const DEADLINE_MS: u64 = 1_000;

/// The longest deadline a host may give modules, in milliseconds (a node's `--deadline-ms`).
pub const MAX_DEADLINE_MS: u64 = 60_000;

/// How much longer than the modules' deadline a host waits for the relay's answer to an
/// operator's call, in milliseconds, before it answers the call itself with a refusal. The relay
/// answers every call by the deadline ([`Relay::handle_timeout`]); this covers the relay's turn
/// and its publication, and a relay thread that has stopped turning.
pub const ANSWER_SLACK_MS: u64 = 2_000;

/// The longest a host waits for the relay's answer to an operator's call when modules have
/// `deadline_ms` to answer: the deadline and [`ANSWER_SLACK_MS`].
#[must_use]
pub const fn answer_wait_ms(deadline_ms: u64) -> u64 {
    deadline_ms.saturating_add(ANSWER_SLACK_MS)
}

/// The operator decisions an upstream RTC interface can take for one scene, and so the only
/// ones the relay forwards (`[COOP-RELAY-INEXPRESSIBLE.1]`).
pub const EXPRESSIBLE: [OperatorDecision; 2] =
    [OperatorDecision::Deactivate, OperatorDecision::Activate];

/// One call to a module, numbered by the relay.
#[derive(Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Debug)]
pub struct CallId(pub u64);

/// One operator's call, numbered by the host: a number is not given to a second call while the
/// first awaits its answer (the second would take its place).
#[derive(Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Debug)]
pub struct OperatorCall(pub u64);

/// A call to a module's RTC interface.
#[derive(Clone, PartialEq, Eq, Hash, Debug)]
pub enum ModuleRequest {
    /// `/planning/cooperate_commands/<name>`.
    Commands(CooperateCommandsRequest),
    /// `/planning/enable_auto_mode/<name>`.
    AutoMode(AutoModeRequest),
}

/// A module's answer to a [`ModuleRequest`] of the same kind.
#[derive(Clone, PartialEq, Eq, Hash, Debug)]
pub enum ModuleAnswer {
    /// The answer of `cooperate_commands`.
    Commands(CooperateCommandsResponse),
    /// The answer of `enable_auto_mode`: whether it was done.
    AutoMode(bool),
}

/// A call for the host to send.
#[derive(Clone, PartialEq, Eq, Hash, Debug)]
pub struct Forward {
    /// Its number, to give back with the answer.
    pub call: CallId,
    /// The interface it goes to.
    pub interface: String,
    /// The request.
    pub request: ModuleRequest,
}

/// Why a call is sent.
#[derive(Clone, Copy, PartialEq, Eq, Hash, Debug)]
enum Purpose {
    /// Part of an operator's call.
    Operator(OperatorCall),
    /// The relay's own, to make the module drive as the core decides.
    Correction,
}

#[derive(Clone, PartialEq, Eq, Hash, Debug)]
struct Call {
    interface: String,
    request: ModuleRequest,
    purpose: Purpose,
}

/// The engine, each module interface's link, and the calls on their way.
#[derive(Clone, PartialEq, Eq, Debug)]
pub struct Relay {
    engine: Engine,
    deadline_ms: u64,
    links: BTreeMap<String, Link>,
    /// Calls not handed out yet, in order.
    queued: VecDeque<(CallId, Call)>,
    /// Calls handed out, with their deadlines as readings in nanoseconds.
    flights: BTreeMap<CallId, (Call, i64)>,
    operators: BTreeMap<OperatorCall, Pending>,
    answers: VecDeque<(OperatorCall, wire::Response)>,
    next_call: u64,
}

impl Relay {
    /// A relay of every interface `engine` binds, each module given `deadline_ms` to answer.
    #[must_use]
    pub fn new(engine: Engine, deadline_ms: u64) -> Self {
        let links = engine
            .host()
            .rtc()
            .bindings()
            .iter()
            .map(|binding| (binding.name.clone(), Link::default()))
            .collect();
        Self {
            engine,
            deadline_ms,
            links,
            queued: VecDeque::new(),
            flights: BTreeMap::new(),
            operators: BTreeMap::new(),
            answers: VecDeque::new(),
            next_call: 0,
        }
    }

    /// The engine, to query.
    #[must_use]
    pub const fn engine(&self) -> &Engine {
        &self.engine
    }

    /// The core, to query.
    #[must_use]
    pub const fn state(&self) -> &State {
        self.engine.state()
    }

    /// The link of `interface`, to query.
    #[must_use]
    pub fn link(&self, interface: &str) -> Option<&Link> {
        self.links.get(interface)
    }

    /// The streams' messages, if a publication is due ([`Engine::poll_publication`]).
    pub fn poll_publication(&mut self, now: Now) -> Option<Publication> {
        self.engine.poll_publication(now)
    }

    /// Milliseconds from `now` until the host should call [`handle_timeout`](Self::handle_timeout)
    /// at the latest: the engine's timeout ([`Engine::until_timeout_ms`]) or the nearest
    /// deadline of a call to a module, whichever comes first (a deadline rounded up, so that it
    /// has passed then).
    #[must_use]
    pub fn until_timeout_ms(&self, now: Now) -> u64 {
        let deadline = self
            .flights
            .values()
            .map(|(_, deadline)| *deadline)
            .min()
            .map_or(u64::MAX, |deadline| {
                let left = deadline.saturating_sub(now.reading_ns).max(0);
                u64::try_from(left).unwrap_or(0).div_ceil(1_000_000)
            });
        self.engine.until_timeout_ms(now).min(deadline)
    }

    /// Whether nothing is on its way: no call queued or unanswered, no operator waiting.
    #[must_use]
    pub fn is_idle(&self) -> bool {
        self.queued.is_empty() && self.flights.is_empty() && self.operators.is_empty()
    }

    fn binding(&self, interface: &str) -> Option<&Binding> {
        self.engine
            .host()
            .rtc()
            .bindings()
            .iter()
            .find(|binding| binding.name == interface)
    }

    /// A status array of `interface` (`[COOP-RELAY-REPORT.1]`): each status reported through
    /// the interface's RTC adapter, each scene of the interface the array no longer lists
    /// removed. A late or repeated array, or one with an undefined constant, is refused whole;
    /// a status the adapter refuses is listed with its reason, and the others still count.
    ///
    /// # Errors
    /// [`ArrayError`]; nothing of the array reached the core (the core was still told the
    /// time).
    pub fn take_statuses(
        &mut self,
        interface: &str,
        array: &CooperateStatusArray,
        now: Now,
    ) -> Result<ArrayTaken, ArrayError> {
        self.engine.handle_timeout(now);
        let link = self
            .links
            .get(interface)
            .ok_or_else(|| ArrayError::UnknownInterface {
                name: interface.to_owned(),
            })?;
        let parsed = array.parse().map_err(|error| ArrayError::Constant {
            interface: interface.to_owned(),
            error,
        })?;
        if let Some(newest) = link.newest.filter(|&newest| array.stamp <= newest) {
            return Err(ArrayError::Late {
                interface: interface.to_owned(),
                stamp: array.stamp,
                newest,
            });
        }
        let mut taken = ArrayTaken::default();
        for (status, message) in parsed.iter().zip(&array.statuses) {
            let retired = self.state().retirement(status.id).is_some();
            if retired && status.phase.is_terminal() {
                // Upstream lists a finished scene until its module removes it.
                continue;
            }
            let Ok(report) = message.report() else {
                continue;
            };
            if let (Err(error), _) = self
                .engine
                .call(|host| report_sampled(host, interface, &report))
            {
                taken.refused.push((status.id, error));
            }
        }
        let listed: Vec<SceneId> = parsed.iter().map(|status| status.id).collect();
        let gone: Vec<SceneId> = {
            let rtc = self.engine.host().rtc();
            let state = self.engine.state();
            state
                .scenes()
                .map(|(id, _)| id)
                .filter(|id| !listed.contains(id))
                .filter(|&id| rtc.owner(state, id).is_some_and(|b| b.name == interface))
                .collect()
        };
        for id in gone {
            let (removed, _) = self
                .engine
                .call(|host| host.interface(interface)?.remove_cooperate_status(id));
            if removed.is_ok() {
                taken.removed.push(id);
            }
        }
        let idle = !self.busy(interface);
        if let Some(link) = self.links.get_mut(interface) {
            link.newest = Some(array.stamp);
            link.seen = parsed.iter().map(|s| (s.id, Seen::of(s))).collect();
            link.fresh |= idle;
        }
        self.correct(interface);
        Ok(taken)
    }

    /// The auto-mode status of `interface`.
    ///
    /// # Errors
    /// [`ArrayError::UnknownInterface`].
    pub fn take_auto_mode(
        &mut self,
        interface: &str,
        status: &AutoModeStatus,
        now: Now,
    ) -> Result<(), ArrayError> {
        self.engine.handle_timeout(now);
        let link = self
            .links
            .get_mut(interface)
            .ok_or_else(|| ArrayError::UnknownInterface {
                name: interface.to_owned(),
            })?;
        link.auto_mode = Some(status.is_auto_mode);
        self.correct(interface);
        Ok(())
    }

    /// Time between messages: calls past their deadline are unanswered, the core is told the
    /// time, and every idle module is corrected.
    pub fn handle_timeout(&mut self, now: Now) {
        self.engine.handle_timeout(now);
        let expired: Vec<CallId> = self
            .flights
            .iter()
            .filter(|(_, (_, deadline))| *deadline <= now.reading_ns)
            .map(|(&id, _)| id)
            .collect();
        for id in expired {
            let Some((flight, _)) = self.flights.remove(&id) else {
                continue;
            };
            if let Purpose::Operator(operator) = flight.purpose {
                if let Some(pending) = self.operators.get_mut(&operator) {
                    pending.expire(id);
                }
                self.finish(operator);
            }
        }
        let names: Vec<String> = self.links.keys().cloned().collect();
        for name in names {
            self.correct(&name);
        }
    }
}

impl Hash for Relay {
    /// Everything that decides what the relay does next, but not the engine's revision counter,
    /// which only labels publications.
    fn hash<H: Hasher>(&self, hasher: &mut H) {
        let state = self.engine.state();
        let rtc = self.engine.host().rtc();
        state.hash(hasher);
        self.engine.host().told_ms().hash(hasher);
        // The reading the core was last told of: the next step of the clock counts from it.
        self.engine.told(Time::default()).reading_ns.hash(hasher);
        for id in state
            .scenes()
            .map(|(id, _)| id)
            .chain(state.retired_by_id().map(|(id, _)| id))
        {
            rtc.owner(state, id).map(|b| b.name.as_str()).hash(hasher);
        }
        self.deadline_ms.hash(hasher);
        self.links.hash(hasher);
        self.queued.hash(hasher);
        self.flights.hash(hasher);
        self.operators.hash(hasher);
        for (operator, response) in &self.answers {
            operator.hash(hasher);
            response.status().hash(hasher);
        }
        self.next_call.hash(hasher);
    }
}

/// Reports `report` through `interface`. An array is a sample of the module's statuses: a
/// waiting or new scene the array shows succeeded or aborting ran in between, the only way there
/// upstream and here, so it is reported running first (`[COOP-RELAY-REPORT.1]`).
fn report_sampled(host: &mut Host, interface: &str, report: &StatusReport) -> Result<(), RtcError> {
    let unstated = report.sequence.is_none() && host.state().scene(report.id).is_none();
    let first = host
        .rtc()
        .bindings()
        .iter()
        .find(|binding| binding.name == interface)
        .filter(|binding| binding.sequences.len() > 1)
        .and_then(|binding| binding.sequences.first().cloned());
    let stated;
    let report = match first {
        // Upstream's status carries no sequence: a new scene of an interface that binds several
        // is its first's (avoidance: the shift out) (`[COOP-RELAY-REPORT.1]`).
        Some(sequence) if unstated => {
            stated = report.in_sequence(sequence);
            &stated
        }
        _ => report,
    };
    let phase = host.state().scene(report.id).map(cooperation::Scene::phase);
    let new = phase.is_none() && host.state().retirement(report.id).is_none();
    let waiting = new || phase == Some(Phase::Waiting);
    if waiting && matches!(report.phase, Phase::Succeeded | Phase::Aborting) {
        let running = StatusReport {
            phase: Phase::Running,
            ..*report
        };
        let mut trial = host.clone();
        trial
            .interface(interface)?
            .update_cooperate_status(&running)?;
        trial
            .interface(interface)?
            .update_cooperate_status(report)?;
        *host = trial;
        return Ok(());
    }
    host.interface(interface)?
        .update_cooperate_status(report)
        .map(drop)
}

/// An RTC command for scene `id` of `binding`'s interface.
fn rtc_command(binding: &Binding, id: SceneId, decision: Decision) -> CooperateCommand {
    CooperateCommand {
        uuid: id.into(),
        module: rtc::Module::new(binding.module_type.value()),
        command: rtc::Command::new(match decision {
            Decision::Activate => rtc::Command::ACTIVATE,
            Decision::Deactivate => rtc::Command::DEACTIVATE,
        }),
    }
}
