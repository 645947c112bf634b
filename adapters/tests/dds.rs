//! The services as the ROS 2 node serves them over DDS (`cooperation_adapters::dds`): the DDS names
//! and types `rmw_cyclonedds_cpp` gives them, the request header, and each service answered
//! from request bytes to reply bytes, malformed requests included. The node itself is tested
//! against Cyclone DDS by `tools/ros2-interop`.

use cooperation_adapters::cdr::{self, CDR_LE};
use cooperation_adapters::dds::{self, Endpoint, RequestHeader};
use cooperation_adapters::engine::{Engine, Handled, Now, Options, Reply, Request};
use cooperation_adapters::rtc::{self, CooperateStatus};
use cooperation_adapters::sync::{
    StatedSequence, SyncCooperateStatusRequest, SyncRequest, SyncResponse,
};
use cooperation_adapters::wire::*;
use cooperation_adapters::Time;

/// An engine with the built-in settings whose streams have published what it shows.
fn host() -> Engine {
    let config = cooperation_adapters::settings::load(None)
        .expect("the built-in settings")
        .config;
    let mut engine = Engine::new(config, Options::default()).expect("valid");
    assert!(engine.poll_publication(Now::default()).is_some());
    engine
}

const HEADER: RequestHeader = RequestHeader {
    guid: 0x0102_0304_0506_0708,
    seq: -2,
};

/// Frames `message`, reads it at `endpoint`, answers it, and reads the reply back.
fn call<R: serde::de::DeserializeOwned>(
    host: &mut Engine,
    endpoint: Endpoint,
    message: &impl serde::Serialize,
) -> (R, Handled) {
    let request = HEADER.frame(&cdr::to_vec(message).expect("encodes"));
    let (header, incoming) = endpoint.read(&request).expect("a readable header");
    assert_eq!(header, HEADER);
    let answered = host.handle(incoming, Now::new(0, Time::new(5, 0)));
    let reply = HEADER.frame(&dds::to_cdr(&answered.reply).expect("encodes"));
    let (header, body) = RequestHeader::split(&reply).expect("the reply's header");
    assert_eq!(header, HEADER, "the reply carries the request's header");
    (cdr::from_slice(&body).expect("the reply decodes"), answered)
}

fn scene(first: u8) -> rtc::Uuid {
    rtc::Uuid {
        uuid: core::array::from_fn(|i| first.wrapping_add(i as u8)),
    }
}

fn status(uuid: rtc::Uuid, safe: bool) -> CooperateStatus {
    CooperateStatus {
        uuid,
        safe,
        state: rtc::Lifecycle::new(rtc::Lifecycle::WAITING_FOR_EXECUTION),
        start_distance: 12.5,
        finish_distance: 20.0,
        // Fields the node fills: not read.
        stamp: Time::new(1, 2),
        command_status: rtc::Command::new(rtc::Command::ACTIVATE),
        auto_mode: true,
        ..CooperateStatus::default()
    }
}

#[test]
fn names_and_types_are_the_ones_rmw_cyclonedds_gives_them() {
    let expected = [
        (
            "rq/api/planning/cooperation/set_commandsRequest",
            "rr/api/planning/cooperation/set_commandsReply",
            "autoware_adapi_v1_msgs::srv::dds_::SetCooperationCommands_Request_",
            "autoware_adapi_v1_msgs::srv::dds_::SetCooperationCommands_Response_",
        ),
        (
            "rq/api/planning/cooperation/set_policiesRequest",
            "rr/api/planning/cooperation/set_policiesReply",
            "autoware_adapi_v1_msgs::srv::dds_::SetCooperationPolicies_Request_",
            "autoware_adapi_v1_msgs::srv::dds_::SetCooperationPolicies_Response_",
        ),
        (
            "rq/api/planning/cooperation/get_policiesRequest",
            "rr/api/planning/cooperation/get_policiesReply",
            "autoware_adapi_v1_msgs::srv::dds_::GetCooperationPolicies_Request_",
            "autoware_adapi_v1_msgs::srv::dds_::GetCooperationPolicies_Response_",
        ),
        (
            "rq/cooperation/rtc/syncRequest",
            "rr/cooperation/rtc/syncReply",
            "cooperation_server::srv::dds_::SyncCooperateStatus_Request_",
            "cooperation_server::srv::dds_::SyncCooperateStatus_Response_",
        ),
    ];
    for (endpoint, (request, reply, request_type, reply_type)) in
        Endpoint::ALL.into_iter().zip(expected)
    {
        assert_eq!(endpoint.request_topic(), request);
        assert_eq!(endpoint.reply_topic(), reply);
        assert_eq!(endpoint.request_type(), request_type);
        assert_eq!(endpoint.reply_type(), reply_type);
    }
    assert_eq!(
        dds::topic(VELOCITY_FACTORS),
        "rt/api/planning/velocity_factors"
    );
    assert_eq!(
        dds::type_name(STEERING_FACTORS_TYPE, ""),
        "autoware_adapi_v1_msgs::msg::dds_::SteeringFactorArray_"
    );
}

#[test]
fn the_request_header_is_two_little_endian_integers_after_the_encapsulation() {
    let message = cdr::to_vec(&GetCooperationPoliciesRequest {}).expect("encodes");
    let framed = HEADER.frame(&message);
    assert_eq!(
        framed,
        [
            vec![0, 1, 0, 0],
            vec![8, 7, 6, 5, 4, 3, 2, 1],
            vec![0xfe, 0xff, 0xff, 0xff, 0xff, 0xff, 0xff, 0xff],
            vec![0],
        ]
        .concat()
    );
    assert_eq!(
        RequestHeader::split(&framed).expect("splits"),
        (HEADER, message)
    );
    // Cyclone's padding options (the encapsulation's last two bytes) are accepted.
    let mut padded = framed.clone();
    padded[3] = 3;
    padded.extend([0, 0, 0]);
    assert_eq!(RequestHeader::split(&padded).expect("splits").0, HEADER);
}

#[test]
fn a_request_without_its_headers_cannot_be_answered() {
    let endpoint = Endpoint::Ad(Service::GetPolicies);
    for short in [
        &[][..],
        &CDR_LE[..],
        &[0, 1, 0, 0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11][..],
    ] {
        let error = endpoint.read(short).expect_err("too short");
        assert!(error.message.contains("fewer than the 20"), "{error}");
    }
    let mut big_endian = HEADER.frame(&cdr::to_vec(&GetCooperationPoliciesRequest {}).expect("ok"));
    big_endian[1] = 0;
    let error = endpoint.read(&big_endian).expect_err("big-endian");
    assert!(error.message.contains("not little-endian"), "{error}");
}

#[test]
fn a_malformed_request_is_refused_with_the_readers_explanation_and_changes_nothing() {
    let mut host = host();
    let before = host.state().clone();
    for endpoint in Endpoint::ALL {
        // A count of a million elements in a request of a few bytes, or a truncated field.
        let framed = HEADER.frame(&[0, 1, 0, 0, 0x40, 0x42, 0x0f, 0x00, 1]);
        let (header, incoming) = endpoint.read(&framed).expect("the header reads");
        assert_eq!(header, HEADER);
        assert!(
            matches!(&incoming, Request::Malformed(e, _) if *e == endpoint),
            "{incoming:?}"
        );
        let answered = host.handle(incoming, Now::default());
        assert!(answered.change.revision.is_none() && !answered.change.publish);
        let message = match &answered.reply {
            Reply::Ad(response) => {
                assert_eq!(response.status().code, ResponseStatus::PARAMETER_ERROR);
                response.status().message.clone()
            }
            Reply::Sync(response) => response.message.clone(),
        };
        assert!(!answered.reply.success());
        assert!(
            message.starts_with("CDR at byte"),
            "{endpoint:?}: {message}"
        );
    }
    // A decision that is no constant: refused by the same reader the JSON form uses.
    let request = SetCooperationCommandsRequest {
        commands: vec![CooperationCommand {
            uuid: Uuid {
                uuid: scene(1).uuid,
            },
            cooperator: CooperationDecision { decision: 99 },
        }],
    };
    let (response, answered): (SetCooperationCommandsResponse, _) =
        call(&mut host, Endpoint::Ad(Service::SetCommands), &request);
    assert!(!response.status.success && answered.change.revision.is_none());
    assert!(response.status.message.contains("99"), "{response:?}");
    assert_eq!(host.state(), &before);
}

#[test]
fn a_request_over_the_size_limit_is_refused_unread() {
    let mut message = CDR_LE.to_vec();
    message.resize(MAX_REQUEST_BYTES + 5, 0);
    let (_, incoming) = Endpoint::Sync
        .read(&HEADER.frame(&message))
        .expect("the header reads");
    match incoming {
        Request::Malformed(Endpoint::Sync, error) => {
            assert!(error.contains("at most 1048576 bytes"), "{error}");
        }
        other => panic!("{other:?}"),
    }
}

#[test]
fn the_sync_request_in_cdr_reads_as_its_json_form_does() {
    let request = SyncCooperateStatusRequest {
        interface: "avoidance_left".to_owned(),
        statuses: vec![status(scene(1), false)],
        sequences: vec![StatedSequence {
            uuid: scene(1),
            sequence: cooperation::Sequence::Return,
        }],
        removed: vec![scene(9)],
    };
    let (_, incoming) = Endpoint::Sync
        .read(&HEADER.frame(&cdr::to_vec(&request).expect("encodes")))
        .expect("reads");
    let json = format!(
        r#"{{"interface": "avoidance_left",
            "statuses": [{{"uuid": {{"uuid": {:?}}}, "safe": false,
                           "state": {{"type": 0}}, "start_distance": 12.5, "finish_distance": 20.0}}],
            "sequences": [{{"uuid": {{"uuid": {:?}}}, "sequence": "return"}}],
            "removed": [{{"uuid": {:?}}}]}}"#,
        scene(1).uuid,
        scene(1).uuid,
        scene(9).uuid
    );
    let from_json: SyncRequest = serde_json::from_str(&json).expect("the JSON form reads");
    assert_eq!(incoming, Request::Sync(from_json));
}

#[test]
fn a_modules_scene_reaches_the_operator_and_takes_a_command_over_cdr() {
    let mut host = host();
    // The policies, as the settings file says.
    let (policies, answered): (GetCooperationPoliciesResponse, _) = call(
        &mut host,
        Endpoint::Ad(Service::GetPolicies),
        &GetCooperationPoliciesRequest {},
    );
    assert!(policies.status.success && answered.change.revision.is_none());
    assert_eq!(
        policies.policies,
        get_policies(host.state(), &GetCooperationPoliciesRequest {}).policies
    );
    assert!(!policies.policies.is_empty());

    // A module reports a scene.
    let report = SyncCooperateStatusRequest {
        interface: "intersection".to_owned(),
        statuses: vec![status(scene(1), false)],
        ..SyncCooperateStatusRequest::default()
    };
    let (synced, answered): (SyncResponse, _) = call(&mut host, Endpoint::Sync, &report);
    assert!(synced.success, "{synced:?}");
    assert!(answered.change.revision.is_some() && answered.change.publish);
    assert_eq!(synced.activations.len(), 1);
    assert!(!synced.activations[0].activated);
    let factors = velocity_factors(host.state(), Time::default());
    assert_eq!(factors.factors.len(), 1);
    assert_eq!(factors.factors[0].cooperation.len(), 1);

    // The operator activates it; the module learns it on its next sync.
    let command = SetCooperationCommandsRequest {
        commands: vec![CooperationCommand {
            uuid: Uuid {
                uuid: scene(1).uuid,
            },
            cooperator: CooperationDecision {
                decision: CooperationDecision::ACTIVATE,
            },
        }],
    };
    let (response, answered): (SetCooperationCommandsResponse, _) =
        call(&mut host, Endpoint::Ad(Service::SetCommands), &command);
    assert!(response.status.success, "{response:?}");
    assert!(answered.change.revision.is_some() && answered.change.publish);
    let (synced, _): (SyncResponse, _) = call(&mut host, Endpoint::Sync, &report);
    let activation = synced.activations[0];
    assert!(activation.activated && activation.force_activated && !activation.force_deactivated);

    // A command for a scene nobody reported is refused, and changes nothing.
    let before = host.state().clone();
    let mut unknown = command.clone();
    unknown.commands[0].uuid.uuid = scene(7).uuid;
    let (response, answered): (SetCooperationCommandsResponse, _) =
        call(&mut host, Endpoint::Ad(Service::SetCommands), &unknown);
    assert!(!response.status.success && !response.status.message.is_empty());
    assert!(answered.change.revision.is_none());
    assert_eq!(host.state(), &before);

    // The module removes it: the streams, which showed it, must show it gone.
    assert!(host.poll_publication(Now::default()).is_some());
    let removal = SyncCooperateStatusRequest {
        interface: "intersection".to_owned(),
        removed: vec![scene(1)],
        ..SyncCooperateStatusRequest::default()
    };
    let (synced, answered): (SyncResponse, _) = call(&mut host, Endpoint::Sync, &removal);
    assert!(synced.success && answered.change.publish, "{synced:?}");
    assert!(velocity_factors(host.state(), Time::default())
        .factors
        .is_empty());
}

#[test]
fn an_unknown_interface_is_refused_as_a_whole() {
    let mut host = host();
    let request = SyncCooperateStatusRequest {
        interface: "no_such_module".to_owned(),
        statuses: vec![status(scene(1), true)],
        ..SyncCooperateStatusRequest::default()
    };
    let (synced, answered): (SyncResponse, _) = call(&mut host, Endpoint::Sync, &request);
    assert!(
        !synced.success && synced.message.contains("no_such_module"),
        "{synced:?}"
    );
    assert!(answered.change.revision.is_none());
}

/// A sync's stated sequences count against `max_batch` with its statuses and removals, each
/// names a scene a status of the same sync reports, and each scene's is stated once; a sync
/// that breaks one of these is refused as a whole and changes nothing.
#[test]
fn a_syncs_sequences_are_counted_matched_and_stated_once() {
    let stated = |uuid, sequence| StatedSequence { uuid, sequence };
    let refusals = [
        (
            vec![status(scene(1), true)],
            vec![
                stated(scene(1), cooperation::Sequence::Change),
                stated(scene(1), cooperation::Sequence::Change),
            ],
            "(sequences[0] did): a scene's sequence is stated once",
        ),
        (
            vec![status(scene(1), true)],
            vec![
                stated(scene(1), cooperation::Sequence::Change),
                stated(scene(2), cooperation::Sequence::Return),
            ],
            "which no status of this sync reports",
        ),
        (
            vec![status(scene(1), true)],
            (0..1024)
                .map(|_| stated(scene(1), cooperation::Sequence::Change))
                .collect(),
            "1025 statuses, sequences and removals, more than the 1024",
        ),
    ];
    for (statuses, sequences, reason) in refusals {
        let mut host = host();
        let request = SyncCooperateStatusRequest {
            interface: "static_obstacle_avoidance_left".to_owned(),
            statuses,
            sequences,
            ..SyncCooperateStatusRequest::default()
        };
        let (synced, answered): (SyncResponse, _) = call(&mut host, Endpoint::Sync, &request);
        assert!(
            !synced.success && synced.message.contains(reason),
            "{reason}: {synced:?}"
        );
        assert!(synced.results.is_empty(), "{synced:?}");
        assert!(answered.change.revision.is_none());
        assert_eq!(host.state().scenes().count(), 0, "nothing registered");
    }
    // The same scene with its sequence stated once registers in that sequence.
    let mut host = host();
    let request = SyncCooperateStatusRequest {
        interface: "static_obstacle_avoidance_left".to_owned(),
        statuses: vec![status(scene(1), true)],
        sequences: vec![stated(scene(1), cooperation::Sequence::Return)],
        ..SyncCooperateStatusRequest::default()
    };
    let (synced, _): (SyncResponse, _) = call(&mut host, Endpoint::Sync, &request);
    assert!(synced.success, "{synced:?}");
    let (_, scene) = host.state().scenes().next().expect("registered");
    assert_eq!(scene.module().sequence, cooperation::Sequence::Return);
}
