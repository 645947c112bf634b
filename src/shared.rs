//! A thread-safe handle on a [`State`], for consumers that call from several threads at once
//! (a planning cycle, service callbacks).
//!
//! Every change goes through [`State::apply`] under one lock, so each input is applied whole
//! or (when rejected) not at all, and inputs from different threads are applied one after the
//! other: none is lost, none sees another half-done. Reads take the same lock and so see the
//! state between two inputs, never during one.

use std::sync::{Mutex, MutexGuard, PoisonError};

use crate::{
    Command, CommandsResponse, Input, PoliciesResponse, PolicySetting, Rejection, ResponseStatus,
    State, Transition,
};

/// A [`State`] behind a lock: `Send + Sync`, shareable through an `Arc`.
///
/// ```
/// use std::sync::Arc;
/// use cooperation::*;
///
/// let lane_change = Module::new(Behavior::LaneChange);
/// let shared = Arc::new(Shared::new(State::new(Config::new([(lane_change, Policy::Optional)]))?));
/// let id = SceneId::from_u128(7);
///
/// // The planning thread registers a scene ...
/// let planner = Arc::clone(&shared);
/// std::thread::spawn(move || {
///     let geometry = Geometry::velocity(12.0);
///     let register = Input::Register { id, module: lane_change, report: Report::new(Decision::Activate, geometry) };
///     planner.apply(&register).map(|t| t.rule)
/// })
/// .join()
/// .expect("the planning thread ran")?;
///
/// // ... and a service thread answers an operator.
/// let response = shared.set_commands(vec![Command { id, decision: OperatorDecision::Deactivate }]);
/// assert!(response.status.success);
/// assert_eq!(shared.read(|state| state.merged_decision(id)), Some(Decision::Deactivate));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Debug)]
pub struct Shared {
    state: Mutex<State>,
}

impl Shared {
    /// A handle owning `state`.
    #[must_use]
    pub const fn new(state: State) -> Self {
        Self {
            state: Mutex::new(state),
        }
    }

    /// The lock. A panic in another thread while it held the lock cannot have left the state
    /// half-changed: the only writer is `State::apply`, which decides before it writes and does
    /// not panic, and reads cannot write. So a poisoned lock is used as it is.
    fn lock(&self) -> MutexGuard<'_, State> {
        self.state.lock().unwrap_or_else(PoisonError::into_inner)
    }

    /// [`State::apply`] under the lock.
    pub fn apply(&self, input: &Input) -> Result<Transition, Rejection> {
        self.lock().apply(input)
    }

    /// Applies `inputs` in order under one acquisition of the lock, so no other thread's input
    /// lands between them (a planning cycle's updates, say), and returns each one's result, in
    /// the order of `inputs`. Each input is still applied or rejected on its own.
    pub fn apply_all<'a>(
        &self,
        inputs: impl IntoIterator<Item = &'a Input>,
    ) -> Vec<Result<Transition, Rejection>> {
        let mut state = self.lock();
        inputs.into_iter().map(|input| state.apply(input)).collect()
    }

    /// [`State::set_commands`] under the lock.
    pub fn set_commands(&self, commands: Vec<Command>) -> CommandsResponse {
        self.lock().set_commands(commands)
    }

    /// [`State::set_policies`] under the lock.
    pub fn set_policies(&self, policies: Vec<PolicySetting>) -> PoliciesResponse {
        self.lock().set_policies(policies)
    }

    /// [`State::get_policies`] under the lock.
    #[must_use]
    pub fn get_policies(&self) -> (ResponseStatus, Vec<PolicySetting>) {
        self.lock().get_policies()
    }

    /// Runs `change` on the state with the lock held, for adapters whose calls take a
    /// `&mut State`: the RTC interfaces ([`rtc::Rtc::interface`](crate::rtc::Rtc::interface)) or
    /// the JSON services. Nothing is lost by handing out the state: its only way to change is
    /// [`State::apply`], so whatever `change` does is a sequence of inputs, each applied whole or
    /// not at all, and no other thread's input lands between them. Keep it short; every other
    /// caller waits for it.
    ///
    /// ```
    /// use cooperation::*;
    ///
    /// let lane_change = Module::new(Behavior::LaneChange);
    /// let shared = Shared::new(State::new(Config::new([(lane_change, Policy::Optional)]))?);
    /// let id = SceneId::from_u128(7);
    /// let report = Report::new(Decision::Activate, Geometry::velocity(12.0));
    /// let rule = shared.update(|state| {
    ///     state.apply(&Input::Register { id, module: lane_change, report }).map(|t| t.rule)
    /// })?;
    /// assert_eq!(shared.read(|state| state.merged_decision(id)), Some(Decision::Activate));
    /// # let _ = rule;
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn update<R>(&self, change: impl FnOnce(&mut State) -> R) -> R {
        change(&mut self.lock())
    }

    /// Runs `query` on the state between two inputs: everything it reads is from one moment.
    /// Keep it short; every other caller waits for it.
    pub fn read<R>(&self, query: impl FnOnce(&State) -> R) -> R {
        query(&self.lock())
    }

    /// A copy of the state as it is now.
    #[must_use]
    pub fn snapshot(&self) -> State {
        self.lock().clone()
    }

    /// The state, when no other thread can reach the handle any more.
    #[must_use]
    pub fn into_inner(self) -> State {
        self.state
            .into_inner()
            .unwrap_or_else(PoisonError::into_inner)
    }
}

impl From<State> for Shared {
    fn from(state: State) -> Self {
        Self::new(state)
    }
}
