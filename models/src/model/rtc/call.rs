//! The RTC model's alphabet: every call of the adapter it makes, with fixed arguments, built
//! once and indexed by position.

use cooperation::{Module, Policy, SceneId, Sequence};
use cooperation_adapters::rtc::{self, Binding, CooperateCommand, CooperateCommandsRequest};
use cooperation_adapters::Time;
use serde::{Deserialize, Serialize};

use crate::model::describe::short;

/// The start distance every status report carries, in metres.
pub const START_DISTANCE: f32 = 10.0;
/// The finish distance every status report carries, in metres.
pub const FINISH_DISTANCE: f32 = 60.0;
/// A `State` value that none of the constants has (`[COOP-DEV-CONSTANTS.1]`).
pub const UNDEFINED_STATE: u8 = 7;
/// A `Command` value that neither constant has.
pub const UNDEFINED_COMMAND: u8 = 2;
/// A `Module` value that no constant has.
pub const UNDEFINED_MODULE: u8 = 250;
/// A defined module type that no interface of the model reports.
pub const UNBOUND_MODULE: u8 = rtc::Module::CROSSWALK;

/// One command of a request, in wire numbers, so that undefined values can be sent.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
pub struct Order {
    /// The scene.
    pub id: SceneId,
    /// The `module.type` the command carries.
    pub module: u8,
    /// The `command.type`: `DEACTIVATE` (0) or `ACTIVATE` (1), or an undefined value.
    pub command: u8,
}

/// A call of the RTC adapter with its arguments. Interfaces are positions in the model's
/// bindings.
#[derive(Clone, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(tag = "call", rename_all = "snake_case")]
pub enum Call {
    /// `Interface::update_cooperate_status` of the report read from a `CooperateStatus` (the
    /// sequence stated, if any),
    /// with the distances [`START_DISTANCE`] and [`FINISH_DISTANCE`].
    Update {
        /// The interface.
        interface: usize,
        /// The scene.
        id: SceneId,
        /// The sequence the owner states, if any.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        sequence: Option<Sequence>,
        /// The module's judgment.
        safe: bool,
        /// The `State` value reported.
        state: u8,
        /// Whether the owner asks the operator.
        requested: bool,
    },
    /// `Interface::remove_cooperate_status`.
    Remove {
        /// The interface.
        interface: usize,
        /// The scene.
        id: SceneId,
    },
    /// `Interface::clear_cooperate_status`.
    Clear {
        /// The interface.
        interface: usize,
    },
    /// `Interface::cooperate_commands` of an interface, or with `None` the external API's
    /// `Rtc::cooperate_commands`.
    Commands {
        /// The interface whose service is called, `None` for the external API.
        interface: Option<usize>,
        /// The request's commands, in order.
        orders: Vec<Order>,
    },
    /// `Interface::auto_mode`.
    AutoMode {
        /// The interface.
        interface: usize,
        /// Turn auto mode on or off.
        enable: bool,
    },
    /// `Rtc::auto_mode_with_module`.
    AutoModeWithModule {
        /// The `module.type` of the request.
        module: u8,
        /// Turn auto mode on or off.
        enable: bool,
    },
    /// `Rtc::tick` by one millisecond, the model's time-to-live.
    Tick,
    /// The AD API's `set_policies` for one module (the core's `SetPolicies`): an operator setting
    /// one sequence's policy beside the adapter.
    SetPolicy {
        /// The module.
        module: Module,
        /// Its policy.
        policy: Policy,
    },
}

impl Call {
    /// The interface the call goes through, if it is one interface's.
    #[must_use]
    pub const fn interface(&self) -> Option<usize> {
        match self {
            Self::Update { interface, .. }
            | Self::Remove { interface, .. }
            | Self::Clear { interface }
            | Self::AutoMode { interface, .. } => Some(*interface),
            Self::Commands { interface, .. } => *interface,
            Self::AutoModeWithModule { .. } | Self::Tick | Self::SetPolicy { .. } => None,
        }
    }
}

/// The `CooperateCommands` request of these orders.
#[must_use]
pub fn request(orders: &[Order]) -> CooperateCommandsRequest {
    CooperateCommandsRequest {
        stamp: Time::default(),
        commands: orders
            .iter()
            .map(|order| CooperateCommand {
                uuid: order.id.into(),
                module: rtc::Module::new(order.module),
                command: rtc::Command::new(order.command),
            })
            .collect(),
    }
}

/// Every call the model tries in every state. Closed under renaming the identifiers (every
/// call naming some identifiers is there for every other choice of them, or is refused before
/// any identifier is read), so that symmetry reduction is sound.
///
/// Per interface and identifier: status updates reporting each state, safe and unsafe for the
/// live states, requested while waiting or running, stating no sequence and, through an
/// interface bound to several, each of its sequences; removal. Per interface: an undefined
/// state, a clear, commands for one scene or two (activate one, deactivate the other), the
/// auto-mode switch both ways; through an interface bound to several sequences, a report
/// stating a sequence it is not bound to, and the AD API's policy of each of its modules, both
/// ways. Through the external API: the same commands (with module type
/// `NONE`: matched by identifier), a scene named twice, an undefined command, an undefined
/// module type, an empty request, a request over the batch limit; the auto-mode switch of each
/// bound module type, of a type no interface reports, and of an undefined type. Time.
#[must_use]
pub fn alphabet(bindings: &[Binding], ids: &[SceneId], max_batch: usize) -> Vec<Call> {
    use rtc::Lifecycle as S;
    let (act, deact) = (rtc::Command::ACTIVATE, rtc::Command::DEACTIVATE);
    let first = ids.first().copied().unwrap_or(SceneId::from_u128(1));
    let mut calls = Vec::new();
    let reports = [
        (S::WAITING_FOR_EXECUTION, false, false),
        (S::WAITING_FOR_EXECUTION, true, false),
        (S::WAITING_FOR_EXECUTION, true, true),
        (S::RUNNING, false, false),
        (S::RUNNING, true, false),
        (S::RUNNING, true, true),
        (S::ABORTING, false, false),
        (S::ABORTING, true, false),
        (S::SUCCEEDED, true, false),
        (S::FAILED, true, false),
    ];
    let commands = |module: u8| {
        let single = ids.iter().flat_map(move |&id| {
            [act, deact].map(|command| {
                vec![Order {
                    id,
                    module,
                    command,
                }]
            })
        });
        let pairs = ids.iter().flat_map(move |&a| {
            ids.iter().filter(move |&&b| b != a).map(move |&b| {
                vec![
                    Order {
                        id: a,
                        module,
                        command: act,
                    },
                    Order {
                        id: b,
                        module,
                        command: deact,
                    },
                ]
            })
        });
        single.chain(pairs)
    };
    for (interface, binding) in bindings.iter().enumerate() {
        // An interface bound to one sequence is reported to without one, as upstream's are.
        let several = binding.sequences.len() > 1;
        let stated: Vec<Option<Sequence>> = if several {
            core::iter::once(None)
                .chain(binding.sequences.iter().copied().map(Some))
                .collect()
        } else {
            vec![None]
        };
        for &id in ids {
            for &sequence in &stated {
                for (state, safe, requested) in reports {
                    calls.push(Call::Update {
                        interface,
                        id,
                        sequence,
                        safe,
                        state,
                        requested,
                    });
                }
            }
            calls.push(Call::Remove { interface, id });
        }
        calls.push(Call::Update {
            interface,
            id: first,
            sequence: None,
            safe: true,
            state: UNDEFINED_STATE,
            requested: false,
        });
        let unbound = Sequence::ALL
            .into_iter()
            .find(|sequence| !binding.sequences.contains(sequence));
        if let (true, Some(unbound)) = (several, unbound) {
            calls.push(Call::Update {
                interface,
                id: first,
                sequence: Some(unbound),
                safe: true,
                state: S::WAITING_FOR_EXECUTION,
                requested: false,
            });
            for &sequence in &binding.sequences {
                for policy in [Policy::Optional, Policy::Required] {
                    calls.push(Call::SetPolicy {
                        module: Module::with_sequence(binding.behavior, sequence),
                        policy,
                    });
                }
            }
        }
        calls.push(Call::Clear { interface });
        let own = rtc::Module::from(binding.module_type).r#type;
        for orders in commands(own) {
            calls.push(Call::Commands {
                interface: Some(interface),
                orders,
            });
        }
        for enable in [true, false] {
            calls.push(Call::AutoMode { interface, enable });
        }
    }
    let none = rtc::Module::NONE;
    let mut external: Vec<Vec<Order>> = commands(none).collect();
    for &id in ids {
        external.push(vec![
            Order {
                id,
                module: none,
                command: act,
            },
            Order {
                id,
                module: none,
                command: deact,
            },
        ]);
    }
    external.push(vec![Order {
        id: first,
        module: none,
        command: UNDEFINED_COMMAND,
    }]);
    external.push(vec![Order {
        id: first,
        module: UNDEFINED_MODULE,
        command: act,
    }]);
    external.push(Vec::new());
    let over: Vec<Order> = ids
        .iter()
        .cycle()
        .take(max_batch + 1)
        .map(|&id| Order {
            id,
            module: none,
            command: act,
        })
        .collect();
    external.push(over);
    calls.extend(external.into_iter().map(|orders| Call::Commands {
        interface: None,
        orders,
    }));
    let mut types: Vec<u8> = bindings
        .iter()
        .map(|b| rtc::Module::from(b.module_type).r#type)
        .collect();
    types.dedup();
    types.extend([UNBOUND_MODULE, UNDEFINED_MODULE]);
    for module in types {
        for enable in [true, false] {
            calls.push(Call::AutoModeWithModule { module, enable });
        }
    }
    calls.push(Call::Tick);
    calls
}

/// A `State` value's constant name.
#[must_use]
pub fn state_name(state: u8) -> String {
    match state {
        rtc::Lifecycle::WAITING_FOR_EXECUTION => "WAITING_FOR_EXECUTION".to_owned(),
        rtc::Lifecycle::RUNNING => "RUNNING".to_owned(),
        rtc::Lifecycle::ABORTING => "ABORTING".to_owned(),
        rtc::Lifecycle::SUCCEEDED => "SUCCEEDED".to_owned(),
        rtc::Lifecycle::FAILED => "FAILED".to_owned(),
        other => format!("undefined state {other}"),
    }
}

fn command_name(command: u8) -> String {
    match command {
        rtc::Command::ACTIVATE => "ACTIVATE".to_owned(),
        rtc::Command::DEACTIVATE => "DEACTIVATE".to_owned(),
        other => format!("undefined command {other}"),
    }
}

fn module_name(module: u8) -> String {
    rtc::Module::new(module).module_type().map_or_else(
        |_| format!("undefined module type {module}"),
        |t| t.to_string(),
    )
}

/// One call in words; `names` are the interfaces' names.
#[must_use]
pub fn describe(call: &Call, names: &[String]) -> String {
    let name = |i: &usize| names.get(*i).map_or("?", String::as_str).to_owned();
    match call {
        Call::Update {
            interface,
            id,
            sequence,
            safe,
            state,
            requested,
        } => format!(
            "{}.update_cooperate_status{}({}, {}{}, {}{})",
            name(interface),
            if sequence.is_some() { "_in" } else { "" },
            short(*id),
            sequence.map_or_else(String::new, |s| format!("{}, ", sequence_name(s))),
            if *safe { "safe" } else { "unsafe" },
            state_name(*state),
            if *requested { ", requested" } else { "" }
        ),
        Call::Remove { interface, id } => {
            format!(
                "{}.remove_cooperate_status({})",
                name(interface),
                short(*id)
            )
        }
        Call::Clear { interface } => format!("{}.clear_cooperate_status()", name(interface)),
        Call::Commands { interface, orders } => {
            let list: Vec<String> = orders
                .iter()
                .map(|o| {
                    format!(
                        "{} {} ({})",
                        short(o.id),
                        command_name(o.command),
                        module_name(o.module)
                    )
                })
                .collect();
            let to = interface
                .as_ref()
                .map_or_else(|| "external API".to_owned(), name);
            format!("{to}.cooperate_commands([{}])", list.join(", "))
        }
        Call::AutoMode { interface, enable } => {
            format!("{}.auto_mode(enable = {enable})", name(interface))
        }
        Call::AutoModeWithModule { module, enable } => format!(
            "external API auto_mode_with_module({}, enable = {enable})",
            module_name(*module)
        ),
        Call::Tick => "rtc.tick(1 ms)".to_owned(),
        Call::SetPolicy { module, policy } => {
            format!("AD API set_policies({module} {policy})")
        }
    }
}

/// A sequence as the AD API names it, the empty one said so.
fn sequence_name(sequence: Sequence) -> String {
    match sequence {
        Sequence::Empty => "empty sequence".to_owned(),
        other => other.as_str().to_owned(),
    }
}
