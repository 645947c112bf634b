//! Hostile input at the adapters' boundaries: the serde forms of the RTC messages (unknown and
//! repeated fields), the RTC adapter's arithmetic at its extremes, and the one base64 reader
//! both message families share. Each test names the class of input it refuses or survives.

use crate::common::forms::refuses_unknown_and_repeated_fields;
use crate::common::*;
use cooperation::*;
use cooperation_adapters::rtc::{self, Rtc};
use cooperation_adapters::Time;
use proptest::prelude::*;
use serde_json::json;

/// The RTC messages, as the adapter writes them and as requests arrive.
#[test]
fn rtc_forms_refuse_unknown_and_repeated_fields() {
    let (mut rtc, mut state) = rtc_setup(false);
    let mut interface = rtc
        .interface(&mut state, "lane_change_left")
        .expect("bound");
    interface
        .update_as_upstream(id(1), true, rtc::Lifecycle::RUNNING, 10.0, 60.0, true)
        .expect("registers");
    let stamp = Time::new(7, 5);
    let statuses = interface.view().cooperate_status_array(stamp);
    let mut objects = refuses_unknown_and_repeated_fields(&statuses);
    let request = rtc_commands(&[(id(1), rtc::Command::ACTIVATE)]);
    objects += refuses_unknown_and_repeated_fields(&request);
    let reply = interface.cooperate_commands(&request);
    objects += refuses_unknown_and_repeated_fields(&reply.response);
    objects += refuses_unknown_and_repeated_fields(&rtc.auto_mode_status_array(&state, stamp));
    objects += refuses_unknown_and_repeated_fields(&rtc::AutoModeRequest { enable: true });
    objects += refuses_unknown_and_repeated_fields(&rtc::AutoModeWithModuleRequest {
        module: rtc::Module::default(),
        enable: true,
    });
    objects += refuses_unknown_and_repeated_fields(&rtc.bindings()[0]);
    assert!(objects > 20, "only {objects} objects were tried");
}

// ---------------------------------------------------------------------------------------------
// RTC: arithmetic at the extremes, and one base64
// ---------------------------------------------------------------------------------------------

/// The adapter's bound on its routes adds the live count and the retired capacity: with the
/// largest capacity `State::new` accepts, it saturates instead of overflowing.
#[test]
fn rtc_route_bound_saturates_at_the_largest_capacity() {
    let mut rtc = Rtc::standard();
    let mut config = Config::new(rtc.policies(false));
    config.limits.retired_capacity = usize::MAX;
    let mut state = State::new(config).expect("valid");
    let mut interface = rtc
        .interface(&mut state, "lane_change_left")
        .expect("bound");
    interface
        .update_as_upstream(id(1), true, rtc::Lifecycle::RUNNING, 1.0, 2.0, false)
        .expect("registers");
    interface.remove_cooperate_status(id(1)).expect("removes");
    rtc.tick(&mut state, 1).expect("ticks");
    assert_eq!(rtc.route_count(), 1);
}

/// A stamp moved back saturates at both ends of the representable times, whatever its
/// `nanosec`; and no message is read with a `nanosec` of a second or more.
#[test]
fn rtc_time_saturates_and_nanosec_stays_below_a_second() {
    let latest = Time::new(i32::MAX, 999_999_999);
    assert_eq!(Time::new(i32::MAX, u32::MAX).before_ms(0), latest);
    assert_eq!(Time::new(i32::MAX, u32::MAX).before_ms(1), latest);
    assert_eq!(
        Time::new(0, 1_500_000_000).before_ms(0),
        Time::new(1, 500_000_000)
    );
    assert_eq!(
        Time::new(i32::MIN, 0).before_ms(u64::MAX),
        Time::new(i32::MIN, 0)
    );
    let error = serde_json::from_value::<Time>(json!({ "sec": 1, "nanosec": 1_000_000_000 }))
        .expect_err("a whole second");
    assert!(error.to_string().contains("nanosec"), "{error}");
    let time = serde_json::from_value::<Time>(json!({ "sec": -1, "nanosec": 999_999_999 }));
    assert_eq!(time.expect("in range"), Time::new(-1, 999_999_999));
    // One type with the AD API's time, read as rosbridge reads it: a field left out is 0.
    let time = serde_json::from_value::<Time>(json!({ "sec": 5 })).expect("reads");
    assert_eq!(time, Time::new(5, 0));
    let wire: cooperation_adapters::Time = time;
    assert_eq!(wire, cooperation_adapters::Time { sec: 5, nanosec: 0 });
}

proptest! {
    /// The one UUID reader (the RTC and AD API messages share the type) takes each byte
    /// string's canonical text, padded or not, and nothing whose last digit sets bits past the
    /// data.
    #[test]
    fn one_uuid_reads_base64_strictly(bytes in proptest::array::uniform16(any::<u8>()), last in 0u8..64) {
        let same: rtc::Uuid = cooperation_adapters::wire::Uuid { uuid: bytes };
        let canonical = same.to_base64();
        let alphabet = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
        let mut variant = canonical.clone().into_bytes();
        variant[21] = alphabet[usize::from(last)];
        let variant = String::from_utf8(variant).expect("ASCII");
        for text in [canonical.clone(), canonical.trim_end_matches('=').to_owned(), variant.clone()] {
            let read = serde_json::from_value::<rtc::Uuid>(json!({ "uuid": text })).ok().map(|u| u.uuid);
            // The last of 22 digits carries 2 bits of data and 4 past its end.
            prop_assert_eq!(read.is_some(), text != variant || last & 0x0f == 0, "{}", text);
            if text != variant {
                prop_assert_eq!(read, Some(bytes), "{}", text);
            }
        }
    }
}

/// The example of `docs/wire.md`: `…Dw==` is bytes 0 to 15; `…Dx==` sets bits past them.
#[test]
fn the_documented_base64_example() {
    let read = |text: &str| {
        cooperation_adapters::wire::from_json::<cooperation_adapters::wire::Uuid>(
            format!(r#"{{"uuid": "{text}"}}"#).as_bytes(),
        )
    };
    let bytes: [u8; 16] = core::array::from_fn(|i| u8::try_from(i).expect("below 16"));
    assert_eq!(
        read("AAECAwQFBgcICQoLDA0ODw==").expect("canonical").uuid,
        bytes
    );
    let error = read("AAECAwQFBgcICQoLDA0ODx==").expect_err("stray bits");
    assert!(
        error.to_string().contains("past the end of the data"),
        "{error}"
    );
}
