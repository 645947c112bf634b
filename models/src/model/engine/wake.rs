//! The wait a host makes between calls (`[COOP-ENGINE-WAKE.1]`): what the engine asks, and what
//! the model's own count says it may be.

#[cfg(doc)]
use cooperation_adapters::engine::Engine;

use super::{EngineFault, EngineModel, EngineStep, PUBLISH_EVERY_MS};

impl EngineModel {
    /// How long the engine asks its host in `state` to wait before telling it the time again
    /// ([`Engine::until_timeout_ms`]), through a planted fault if there is one.
    pub(super) fn asked_wait(&self, state: &EngineStep) -> u64 {
        let (engine, now) = (&state.engine, state.now());
        let others = engine
            .until_publication_ms(now)
            .min(engine.until_step_limit_ms(now));
        match self.fault {
            Some(EngineFault::ExpiryUnasked) => others,
            Some(EngineFault::ExpiryEarly) => {
                others.min(engine.until_expiry_ms(now).saturating_sub(1))
            }
            _ => engine.until_timeout_ms(now),
        }
    }

    /// How long a host may wait in `state`, the core just told the time, by the model's own
    /// count (`[COOP-ENGINE-WAKE.1]`): until the earliest of a live scene's expiry in the
    /// core's time, the next periodic publication on the clock, and the step limit.
    pub(super) fn due_in(&self, state: &EngineStep) -> u64 {
        let ttl = self.config.limits.ttl_ms;
        let expiry = state
            .reported_core_ms
            .iter()
            .flatten()
            .map(|reported| reported + ttl + 1)
            .filter(|&expires| expires > state.core_ms)
            .map(|expires| expires - state.core_ms)
            .min()
            .unwrap_or(u64::MAX);
        let publication = state.published_at_ms.map_or(0, |at| {
            if state.clock_ms < at {
                0
            } else {
                (at + PUBLISH_EVERY_MS).saturating_sub(state.clock_ms)
            }
        });
        expiry.min(publication).min(self.max_step_ms())
    }
}
