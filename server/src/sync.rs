//! The planning modules' service, `/cooperation/rtc/sync` ([`cooperation_adapters::sync`]): read
//! from JSON by [`read_json`], answered by the engine.

pub use cooperation_adapters::sync::*;
