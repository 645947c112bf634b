//! The RTC compatibility adapter: upstream's edge cases (`upstream-rtc` notes §6) as they apply
//! here, the statuses it publishes, and the messages' JSON shapes and round trips.
//!
//! One binary with a module per concern, over one fixture: the standard bindings and a state
//! configured from them.

mod auto_mode;
mod checks;
mod commands;
mod lifecycle;
mod messages;
mod scenes;
mod sequences;
mod statuses;
mod upstream;

use crate::common::*;
use cooperation::*;
use cooperation_adapters::rtc::{self, Rtc};

const LEFT: &str = "lane_change_left";

/// The standard bindings, and a state configured from them, as most tests start.
struct Fixture {
    rtc: Rtc,
    state: State,
}

impl Fixture {
    /// Upstream's `enable_rtc`: `false` puts every bound module's policy at optional.
    fn new(enable_rtc: bool) -> Self {
        let (rtc, state) = rtc_setup(enable_rtc);
        Self { rtc, state }
    }

    /// A status report from interface `name` (distances 10 and 60, not requested): the rules
    /// the core fired.
    fn report(
        &mut self,
        name: &str,
        id: SceneId,
        safe: bool,
        rtc_state: u8,
    ) -> Result<Vec<Rule>, rtc::RtcError> {
        let mut interface = self.rtc.interface(&mut self.state, name).expect("bound");
        let transitions = interface.update_as_upstream(id, safe, rtc_state, 10.0, 60.0, false)?;
        Ok(transitions.into_iter().map(|t| t.rule).collect())
    }

    /// One command through interface `name`'s `CooperateCommands`: whether it succeeded.
    fn command(&mut self, name: &str, id: SceneId, command: u8) -> bool {
        let mut interface = self.rtc.interface(&mut self.state, name).expect("bound");
        let reply = interface.cooperate_commands(&rtc_commands(&[(id, command)]));
        assert_eq!(reply.response.responses.len(), 1);
        let success = reply.response.responses[0].success;
        assert_eq!(success, reply.result.is_ok(), "{reply:?}");
        success
    }

    /// Interface `name`'s auto-mode switch; it always succeeds.
    fn auto_mode(&mut self, name: &str, enable: bool) {
        let reply = self
            .rtc
            .interface(&mut self.state, name)
            .expect("bound")
            .auto_mode(&rtc::AutoModeRequest { enable });
        assert!(reply.response.success, "{reply:?}");
    }
}
