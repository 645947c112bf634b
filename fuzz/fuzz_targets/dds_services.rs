//! Hostile bytes into the ROS 2 node's services over DDS (`cooperation_adapters::dds`, answered by
//! the engine, `cooperation_adapters::engine`): the first
//! byte picks the endpoint (`set_commands`, `set_policies`, `get_policies`, the modules' sync)
//! and whether the rest is the whole sample as it arrived or only the message after a valid
//! encapsulation and request header. No request may panic; a request that reads is answered,
//! its reply carries the request's header and reads back as the endpoint's response; a refused
//! or malformed request (and `get_policies`) leaves the node's core and RTC interfaces as they
//! were; the core keeps its invariants.
#![no_main]

use std::sync::OnceLock;

use cooperation_adapters::cdr;
use cooperation_adapters::dds::{self, Endpoint, RequestHeader};
use cooperation_adapters::engine::{Engine, Now, Options, Reply, Request};
use cooperation_adapters::sync::SyncResponse;
use cooperation_adapters::wire::*;
use libfuzzer_sys::fuzz_target;

/// The node's engine as it starts, with the built-in settings (read once).
fn start() -> Engine {
    static START: OnceLock<Engine> = OnceLock::new();
    START
        .get_or_init(|| {
            let config = cooperation_adapters::settings::load(None).expect("the built-in settings").config;
            Engine::new(config, Options::default()).expect("valid")
        })
        .clone()
}

/// The reply reads back as the endpoint's response and writes the same bytes again (compared
/// as bytes: a distance a module reported may be NaN, which equals nothing).
fn reads_back(outgoing: &Reply, reply: &[u8]) {
    fn again<T: serde::de::DeserializeOwned + serde::Serialize>(
        bytes: &[u8],
    ) -> Result<Vec<u8>, cdr::CdrError> {
        cdr::to_vec(&cdr::from_slice::<T>(bytes)?)
    }
    let written = match outgoing {
        Reply::Ad(Response::SetCommands(_)) => again::<SetCooperationCommandsResponse>(reply),
        Reply::Ad(Response::SetPolicies(_)) => again::<SetCooperationPoliciesResponse>(reply),
        Reply::Ad(Response::GetPolicies(_)) => again::<GetCooperationPoliciesResponse>(reply),
        Reply::Sync(_) => again::<SyncResponse>(reply),
    };
    assert_eq!(
        written.as_deref(),
        Ok(reply),
        "the reply reads back as written"
    );
}

fuzz_target!(|data: &[u8]| {
    let Some((&selector, rest)) = data.split_first() else {
        return;
    };
    let endpoint = Endpoint::ALL[usize::from(selector % 4)];
    let header = RequestHeader {
        guid: u64::from(selector),
        seq: 1,
    };
    let framed = if selector & 4 == 0 {
        let mut message = cdr::CDR_LE.to_vec();
        message.extend_from_slice(rest);
        header.frame(&message)
    } else {
        rest.to_vec()
    };
    let mut engine = start();
    let Ok((read_header, incoming)) = endpoint.read(&framed) else {
        return;
    };
    let malformed = matches!(incoming, Request::Malformed(..));
    let before = engine.clone();
    let answered = engine.handle(incoming, Now::default());
    let reply = dds::to_cdr(&answered.reply).expect("every reply writes");
    let framed_reply = read_header.frame(&reply);
    let (echoed, body) = RequestHeader::split(&framed_reply).expect("the reply's header");
    assert_eq!(
        echoed, read_header,
        "the reply carries the request's header"
    );
    reads_back(&answered.reply, &body);
    // A sync that fails in part applied its other entries; one refused as a whole did nothing.
    let refused = match &answered.reply {
        Reply::Ad(response) => !response.status().success,
        Reply::Sync(response) => !response.message.is_empty(),
    };
    let changed = answered.change.revision.is_some();
    let unchanged = malformed || refused || endpoint == Endpoint::Ad(Service::GetPolicies);
    if unchanged {
        assert!(
            engine.host() == before.host(),
            "{endpoint:?}: a refusal changed the node"
        );
        assert!(!changed);
    }
    assert_eq!(
        changed,
        engine.host() != before.host(),
        "changed is what happened"
    );
    assert_eq!(engine.state().check_invariants(), Ok(()));
});
