//! Hostile bytes into the CDR reader, as every AD API request, response and factor array and
//! the RTC status array. No read may panic; whatever reads writes no more bytes than it read
//! (padding is not read, so its values may differ), and what it writes is a fixpoint.
#![no_main]

use cooperation_adapters::cdr;
use cooperation_adapters::rtc::CooperateStatusArray;
use cooperation_adapters::wire::*;
use libfuzzer_sys::fuzz_target;
use serde::{de::DeserializeOwned, Serialize};

fn fixpoint<T: DeserializeOwned + Serialize + PartialEq + core::fmt::Debug>(data: &[u8]) {
    let Ok(message) = cdr::from_slice::<T>(data) else {
        return;
    };
    let written = cdr::to_vec(&message).expect("what reads, writes");
    assert!(written.len() <= data.len(), "wrote more than it read");
    // Floats read back bit for bit, but NaN is not equal to itself: compare the bytes again.
    let again = cdr::from_slice::<T>(&written).expect("what it writes, reads");
    assert_eq!(cdr::to_vec(&again).expect("writes"), written, "not a fixpoint");
}

fuzz_target!(|data: &[u8]| {
    fixpoint::<SetCooperationCommandsRequest>(data);
    fixpoint::<SetCooperationPoliciesRequest>(data);
    fixpoint::<GetCooperationPoliciesRequest>(data);
    fixpoint::<SetCooperationCommandsResponse>(data);
    fixpoint::<GetCooperationPoliciesResponse>(data);
    fixpoint::<VelocityFactorArray>(data);
    fixpoint::<SteeringFactorArray>(data);
    fixpoint::<CooperateStatusArray>(data);
});
