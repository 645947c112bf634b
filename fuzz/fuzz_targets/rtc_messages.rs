//! Hostile bytes into every RTC message decoder and through the RTC adapter, one line after
//! another on one adapter. Each newline-separated line is read as every `tier4_rtc_msgs`
//! message in its rosbridge JSON form: whatever decodes writes JSON that decodes to the same
//! message (a fixpoint), and parses into core types exactly when its constants are defined, the
//! error naming the first undefined one. What decodes is then sent to an adapter over the
//! standard bindings with scenes registered through three interfaces and one retired: a status
//! (or each of an array's) is `updateCooperateStatus` of the interface its module type names
//! (stating the sequence its UUID's last byte picks, where the interface binds several), a
//! command request both the external `CooperateCommands` and that of the interface its first
//! command names, an auto-mode request `AutoMode` of the interface the line's length picks or
//! `AutoModeWithModule`, a bare UUID `removeCooperateStatus` of its owner, a bare `{"type": n}`
//! `clearCooperateStatus` of the interface with module type `n`, a number a tick of that many
//! milliseconds, and a time the stamp of what the adapter publishes. No call may panic; a
//! refused call leaves the adapter and the state unchanged; every reply answers every command
//! with the call's outcome; the state keeps its invariants and the routes their bound; and the
//! status arrays the adapter publishes parse and are fixpoints too.
#![no_main]

use core::fmt::Debug;

use cooperation::{Config, Decision, Limits, Phase, SceneId, Sequence, State};
use cooperation_adapters::rtc::{
    self, AutoModeRequest, AutoModeResponse, AutoModeStatus, AutoModeStatusArray,
    AutoModeWithModuleRequest, AutoModeWithModuleResponse, CooperateCommand,
    CooperateCommandsRequest, CooperateCommandsResponse, CooperateResponse, CooperateStatus,
    CooperateStatusArray, FieldError, ModuleType, Rtc, RtcError, StatusReport, Uuid,
};
use cooperation_adapters::Time;
use libfuzzer_sys::fuzz_target;
use serde::{de::DeserializeOwned, Serialize};

/// Decodes `line` as a `T` and checks that it writes JSON that decodes to it again.
fn fixpoint<T: DeserializeOwned + Serialize + PartialEq + Debug>(line: &[u8]) -> Option<T> {
    let message: T = serde_json::from_slice(line).ok()?;
    check_fixpoint(&message);
    Some(message)
}

fn check_fixpoint<T: DeserializeOwned + Serialize + PartialEq + Debug>(message: &T) {
    let Ok(first) = serde_json::to_vec(message) else {
        panic!("a message does not write")
    };
    match serde_json::from_slice::<T>(&first) {
        Ok(again) => {
            assert_eq!(&again, message, "not a fixpoint");
            assert_eq!(
                serde_json::to_vec(&again).ok(),
                Some(first),
                "written twice differently"
            );
        }
        // JSON has no infinity: a float32 distance given a number beyond its range is infinite
        // and written as null, which does not read back.
        Err(_) => assert!(
            first.windows(4).any(|w| w == b"null"),
            "written JSON does not read back"
        ),
    }
}

/// The first undefined constant among a message's `module`, `command` and `state` values, as
/// the field the parser names; `None` if every one is defined.
fn first_undefined(
    module: u8,
    (command_field, command): (&'static str, u8),
    state: Option<u8>,
) -> Option<String> {
    if ModuleType::from_value(module).is_none() {
        return Some("module.type".to_owned());
    }
    if command > rtc::Command::ACTIVATE {
        return Some(format!("{command_field}.type"));
    }
    match state {
        Some(state) if state > rtc::Lifecycle::FAILED => Some("state.type".to_owned()),
        _ => None,
    }
}

/// A parse result checked against the field the first undefined constant should be named by.
fn check_parse<T: Debug>(result: &Result<T, FieldError>, undefined: Option<String>) {
    match (result, undefined) {
        (Ok(_), None) => {}
        (Err(error), Some(field)) => assert_eq!(error.field.to_string(), field, "{error}"),
        (result, undefined) => panic!("parsed as {result:?}, expected {undefined:?} undefined"),
    }
}

fn check_status(status: &CooperateStatus) -> Option<String> {
    let undefined = first_undefined(
        status.module.r#type,
        ("command_status", status.command_status.r#type),
        Some(status.state.r#type),
    );
    let parsed = status.parse();
    check_parse(&parsed, undefined.clone());
    if let Ok(parsed) = parsed {
        assert_eq!(rtc::Module::from(parsed.module), status.module);
        assert_eq!(rtc::Command::from(parsed.command), status.command_status);
        assert_eq!(rtc::Lifecycle::from(parsed.phase), status.state);
        assert_eq!(Uuid::from(parsed.id), status.uuid);
        assert_eq!(parsed.module_decision == Decision::Activate, status.safe);
    }
    undefined
}

fn check_command(command: &CooperateCommand) -> Option<String> {
    let undefined = first_undefined(
        command.module.r#type,
        ("command", command.command.r#type),
        None,
    );
    let parsed = command.parse();
    check_parse(&parsed, undefined.clone());
    if let Ok(parsed) = parsed {
        assert_eq!(Uuid::from(parsed.id), command.uuid);
    }
    undefined
}

/// The first undefined constant of a list, with the list's field and index prefixed.
fn first_in<T>(list: &str, items: &[T], check: impl Fn(&T) -> Option<String>) -> Option<String> {
    items
        .iter()
        .enumerate()
        .find_map(|(index, item)| Some(format!("{list}[{index}].{}", check(item)?)))
}

/// The adapter under test: the standard bindings, every bound module required, small limits,
/// scenes 1 (lane change, waiting), 2 (intersection, running) and 3 (crosswalk, requested)
/// live and 4 (crosswalk) removed.
fn start() -> (Rtc, State) {
    let mut rtc = Rtc::standard();
    let config = Config {
        policies: rtc.policies(true),
        limits: Limits {
            ttl_ms: 1_000,
            max_scenes: 8,
            retired_capacity: 8,
            max_batch: 16,
        },
    };
    let Ok(mut state) = State::new(config) else {
        unreachable!("a valid configuration")
    };
    for (n, name, phase) in [
        (1, "lane_change_left", rtc::Lifecycle::WAITING_FOR_EXECUTION),
        (2, "intersection", rtc::Lifecycle::RUNNING),
        (3, "crosswalk", rtc::Lifecycle::WAITING_FOR_EXECUTION),
        (4, "crosswalk", rtc::Lifecycle::WAITING_FOR_EXECUTION),
    ] {
        let Ok(mut interface) = rtc.interface(&mut state, name) else {
            unreachable!("a bound interface")
        };
        let distance = 10.0 * n as f32;
        let Ok(phase) = rtc::Lifecycle::new(phase).phase() else {
            unreachable!("a lifecycle constant")
        };
        let mut report = StatusReport::new(id(n), n % 2 == 0, phase, distance, distance + 5.0);
        report.requested = n == 3;
        let update = interface.update_cooperate_status(&report);
        assert!(update.is_ok(), "{update:?}");
    }
    let Ok(mut crosswalk) = rtc.interface(&mut state, "crosswalk") else {
        unreachable!("a bound interface")
    };
    assert!(crosswalk.remove_cooperate_status(id(4)).is_ok());
    (rtc, state)
}

fn id(n: u128) -> SceneId {
    SceneId::from_u128(n)
}

/// The first interface whose statuses carry module type `value`.
fn interface_for(rtc: &Rtc, value: u8) -> Option<String> {
    rtc.bindings()
        .iter()
        .find(|binding| binding.module_type.value() == value)
        .map(|binding| binding.name.clone())
}

/// Runs one adapter call; a refused call must leave the adapter and the state as they were.
fn call<T>(
    rtc: &mut Rtc,
    state: &mut State,
    stamp: Time,
    run: impl FnOnce(&mut Rtc, &mut State) -> Result<T, RtcError>,
) -> Option<T> {
    let before = (rtc.clone(), state.clone());
    let result = run(rtc, state);
    if let Err(error) = &result {
        assert!(
            before.0 == *rtc && before.1 == *state,
            "refused with {error:?}, yet changed"
        );
    }
    check(rtc, state, stamp);
    result.ok()
}

/// What holds after every call.
fn check(rtc: &Rtc, state: &State, stamp: Time) {
    assert_eq!(state.check_invariants(), Ok(()));
    let limits = state.limits();
    assert!(rtc.route_count() <= limits.max_scenes + limits.retired_capacity + 1);
    // Every scene registered through the adapter, so every one has its interface.
    for (id, _) in state.scenes() {
        let Some(owner) = rtc.owner(state, id) else {
            panic!("live scene {id} has no interface")
        };
        let Ok(view) = rtc.view(state, &owner.name) else {
            panic!("the owner of {id} cannot be viewed")
        };
        assert!(view.is_registered(id));
        assert_eq!(
            view.is_activated(id),
            state.merged_decision(id) == Some(Decision::Activate)
        );
        assert_eq!(view.is_terminated(id), Some(false));
    }
    let published = rtc.cooperate_status_array(state, stamp);
    assert_eq!(published.statuses.len(), state.scene_count());
    assert!(
        published.parse().is_ok(),
        "the adapter published an undefined constant"
    );
    check_fixpoint(&published);
    let auto_modes = rtc.auto_mode_status_array(state, stamp);
    assert_eq!(auto_modes.statuses.len(), rtc.bindings().len());
    check_fixpoint(&auto_modes);
}

/// The sequence a status states: none through an interface bound to one, else the one its
/// UUID's last byte picks among the interface's.
fn sequence_for(rtc: &Rtc, name: &str, uuid: &Uuid) -> Option<Sequence> {
    let sequences = &rtc.bindings().iter().find(|b| b.name == name)?.sequences;
    let last = usize::from(*uuid.uuid.last()?);
    (sequences.len() > 1)
        .then(|| sequences.iter().nth(last % sequences.len()).copied())
        .flatten()
}

/// `updateCooperateStatus` of the interface the status's module type names.
fn update(rtc: &mut Rtc, state: &mut State, stamp: Time, status: &CooperateStatus) {
    let Some(name) = interface_for(rtc, status.module.r#type) else {
        return;
    };
    let id = SceneId::from(status.uuid);
    let terminal = matches!(status.state.phase(), Ok(Phase::Succeeded | Phase::Failed));
    let sequence = sequence_for(rtc, &name, &status.uuid);
    let updated = call(rtc, state, stamp, |rtc, state| {
        let mut interface = rtc.interface(state, &name)?;
        let report = status.report()?;
        let report = match sequence {
            Some(sequence) => report.in_sequence(sequence),
            None => report,
        };
        interface.update_cooperate_status(&report)
    });
    if updated.is_some() {
        let Ok(view) = rtc.view(state, &name) else {
            unreachable!("a bound interface")
        };
        if terminal {
            assert_eq!(view.is_terminated(id), Some(true));
        } else {
            assert!(view.is_registered(id));
        }
    }
}

/// The checks every command reply must pass, given the request's first undefined constant.
fn check_reply(
    request: &CooperateCommandsRequest,
    reply: &rtc::Reply<CooperateCommandsResponse>,
    undefined: Option<&String>,
) {
    let responses = &reply.response.responses;
    assert_eq!(responses.len(), request.commands.len());
    for (response, command) in responses.iter().zip(&request.commands) {
        assert_eq!(response.success, reply.result.is_ok());
        assert_eq!(
            (response.uuid, response.module),
            (command.uuid, command.module)
        );
    }
    if let Some(field) = undefined {
        match &reply.result {
            Err(RtcError::Field(error)) => assert_eq!(&error.field.to_string(), field),
            other => panic!("{field} undefined, answered {other:?}"),
        }
    }
}

fn commands(
    rtc: &mut Rtc,
    state: &mut State,
    stamp: Time,
    request: &CooperateCommandsRequest,
    undefined: Option<String>,
) {
    call(rtc, state, stamp, |rtc, state| {
        let reply = rtc.cooperate_commands(state, request);
        check_reply(request, &reply, undefined.as_ref());
        reply.result
    });
    let first = request
        .commands
        .first()
        .map_or(rtc::Module::LANE_CHANGE_LEFT, |c| c.module.r#type);
    let Some(name) = interface_for(rtc, first) else {
        return;
    };
    call(rtc, state, stamp, |rtc, state| {
        let reply = rtc.interface(state, &name)?.cooperate_commands(request);
        check_reply(request, &reply, undefined.as_ref());
        reply.result
    });
}

fn auto_mode(
    rtc: &mut Rtc,
    state: &mut State,
    stamp: Time,
    request: &AutoModeRequest,
    pick: usize,
) {
    let Some(name) = rtc
        .bindings()
        .get(pick % rtc.bindings().len().max(1))
        .map(|binding| binding.name.clone())
    else {
        return;
    };
    let done = call(rtc, state, stamp, |rtc, state| {
        let reply = rtc.interface(state, &name)?.auto_mode(request);
        assert_eq!(reply.response.success, reply.result.is_ok());
        reply.result
    });
    if done.is_some() {
        let Ok(view) = rtc.view(state, &name) else {
            unreachable!("a bound interface")
        };
        assert_eq!(view.auto_mode_status().is_auto_mode, request.enable);
    }
}

fn auto_mode_with_module(
    rtc: &mut Rtc,
    state: &mut State,
    stamp: Time,
    request: &AutoModeWithModuleRequest,
) {
    let module = request.module.module_type();
    let bound = interface_for(rtc, request.module.r#type).is_some();
    call(rtc, state, stamp, |rtc, state| {
        let reply = rtc.auto_mode_with_module(state, request);
        assert_eq!(reply.response.success, reply.result.is_ok());
        match (&module, &reply.result) {
            (Err(_), Err(RtcError::Field(error))) => {
                assert_eq!(error.field.to_string(), "module.type")
            }
            (Ok(module), Err(RtcError::NoInterface { module: asked })) => {
                assert!(!bound);
                assert_eq!(asked, module);
            }
            (Ok(_), Ok(_)) => assert!(bound),
            (module, result) => panic!("module {module:?} answered {result:?}"),
        }
        reply.result
    });
    if let (Ok(module), true) = (module, bound) {
        for status in rtc.auto_mode_status_array(state, stamp).statuses {
            if status.module == rtc::Module::from(module) {
                assert_eq!(status.is_auto_mode, request.enable);
            }
        }
    }
}

fuzz_target!(|data: &[u8]| {
    let (mut rtc, mut state) = start();
    let mut stamp = Time::new(100, 0);
    for line in data.split(|b| *b == b'\n') {
        if let Some(time) = fixpoint::<Time>(line) {
            for ms in [0, 1, 1_000, u64::MAX] {
                let _ = time.before_ms(ms);
            }
            stamp = time;
        }
        if let Ok(elapsed_ms) = serde_json::from_slice::<u64>(line) {
            call(&mut rtc, &mut state, stamp, |rtc, state| {
                rtc.tick(state, elapsed_ms)
            });
        }
        if let Some(uuid) = fixpoint::<Uuid>(line) {
            let id = SceneId::from(uuid);
            assert_eq!(Uuid::from(id), uuid);
            let owner = rtc.owner(&state, id).map(|binding| binding.name.clone());
            let name = owner.unwrap_or_else(|| "lane_change_left".to_owned());
            call(&mut rtc, &mut state, stamp, |rtc, state| {
                rtc.interface(state, &name)?.remove_cooperate_status(id)
            });
        }
        if let Some(module) = fixpoint::<rtc::Module>(line) {
            let module_type = module.module_type();
            let undefined = ModuleType::from_value(module.r#type).is_none();
            check_parse(&module_type, undefined.then(|| "type".to_owned()));
            if let Ok(module_type) = module_type {
                assert_eq!(rtc::Module::from(module_type), module);
                match module_type.legacy_value() {
                    Some(legacy) => {
                        assert_eq!(ModuleType::from_legacy_value(legacy), Some(module_type));
                    }
                    None => assert_eq!(module_type, ModuleType::Roundabout),
                }
            }
            if let Some(name) = interface_for(&rtc, module.r#type) {
                call(&mut rtc, &mut state, stamp, |rtc, state| {
                    rtc.interface(state, &name)?.clear_cooperate_status()
                });
            }
        }
        if let Some(command) = fixpoint::<rtc::Command>(line) {
            match command.decision() {
                Ok(decision) => assert_eq!(rtc::Command::from(decision), command),
                Err(error) => {
                    assert!(command.r#type > rtc::Command::ACTIVATE);
                    assert_eq!(error.field.to_string(), "type");
                }
            }
        }
        if let Some(phase) = fixpoint::<rtc::Lifecycle>(line) {
            match phase.phase() {
                Ok(decoded) => assert_eq!(rtc::Lifecycle::from(decoded), phase),
                Err(error) => {
                    assert!(phase.r#type > rtc::Lifecycle::FAILED);
                    assert_eq!(error.field.to_string(), "type");
                }
            }
        }
        if let Some(status) = fixpoint::<CooperateStatus>(line) {
            check_status(&status);
            update(&mut rtc, &mut state, stamp, &status);
        }
        if let Some(array) = fixpoint::<CooperateStatusArray>(line) {
            let undefined = first_in("statuses", &array.statuses, check_status);
            check_parse(&array.parse(), undefined);
            for status in &array.statuses {
                update(&mut rtc, &mut state, stamp, status);
            }
        }
        if let Some(command) = fixpoint::<CooperateCommand>(line) {
            check_command(&command);
        }
        if let Some(request) = fixpoint::<CooperateCommandsRequest>(line) {
            let undefined = first_in("commands", &request.commands, check_command);
            check_parse(&request.parse(), undefined.clone());
            commands(&mut rtc, &mut state, stamp, &request, undefined);
        }
        if let Some(request) = fixpoint::<AutoModeRequest>(line) {
            auto_mode(&mut rtc, &mut state, stamp, &request, line.len());
        }
        if let Some(request) = fixpoint::<AutoModeWithModuleRequest>(line) {
            auto_mode_with_module(&mut rtc, &mut state, stamp, &request);
        }
        let _ = fixpoint::<CooperateResponse>(line);
        let _ = fixpoint::<CooperateCommandsResponse>(line);
        let _ = fixpoint::<AutoModeStatus>(line);
        let _ = fixpoint::<AutoModeStatusArray>(line);
        let _ = fixpoint::<AutoModeResponse>(line);
        let _ = fixpoint::<AutoModeWithModuleResponse>(line);
    }
});
