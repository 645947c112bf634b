//! Hostile bytes into every AD API message decoder and its conversion into core types. No
//! decode or conversion may panic; whatever decodes writes back to JSON that decodes to the
//! same JSON again.
#![no_main]

use cooperation_adapters::wire::*;
use libfuzzer_sys::fuzz_target;
use serde::{de::DeserializeOwned, Serialize};

fn fixpoint<T: DeserializeOwned + Serialize>(data: &[u8]) -> Option<T> {
    let message: T = from_json(data).ok()?;
    let first = to_json(&message);
    match from_json::<T>(&first) {
        Ok(again) => assert_eq!(to_json(&again), first, "not a fixpoint"),
        // JSON has no infinity: a float32 field given a number beyond its range is infinite
        // and written as null, which does not read back.
        Err(_) => assert!(
            first.windows(4).any(|w| w == b"null"),
            "written JSON does not read back"
        ),
    }
    Some(message)
}

fuzz_target!(|data: &[u8]| {
    if let Some(request) = fixpoint::<SetCooperationCommandsRequest>(data) {
        let _ = request.to_commands();
    }
    if let Some(request) = fixpoint::<SetCooperationPoliciesRequest>(data) {
        let _ = request.to_policies();
    }
    if let Some(factors) = fixpoint::<VelocityFactorArray>(data) {
        let _ = factors.to_factors();
    }
    if let Some(factors) = fixpoint::<SteeringFactorArray>(data) {
        let _ = factors.to_factors();
    }
    let _ = fixpoint::<CooperationStatus>(data);
    let _ = fixpoint::<GetCooperationPoliciesResponse>(data);
    let _ = fixpoint::<SetCooperationCommandsResponse>(data);
});
