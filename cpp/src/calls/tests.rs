//! The bridge's functions, called from Rust.

use super::*;

fn scene(n: u8) -> Uuid {
    let mut bytes = [0; 16];
    bytes[15] = n;
    Uuid { bytes }
}

fn at(sec: i32) -> Stamp {
    Stamp { sec, nanosec: 0 }
}

/// A safe, waiting report of `id` through the interface `name`, at `sec`.
fn report(core: &Core, sec: i32, name: &str, id: &Uuid) -> Told {
    update(
        core,
        at(sec),
        &find(core, name),
        id,
        true,
        0,
        1.0,
        1.0,
        false,
        false,
        "",
    )
}

#[test]
fn the_first_reading_is_time_zero_and_time_never_goes_back() {
    let core = Core::new(0).unwrap();
    let crosswalk = find(&core, "crosswalk");
    assert!(bind(&core, &crosswalk, true).ok);
    // An epoch reading: had the core started at 0, every scene would expire at once.
    assert!(advance(&core, at(1_700_000_000)).is_empty());
    let id = scene(1);
    assert!(report(&core, 1_700_000_000, "crosswalk", &id).outcome.ok);
    for second in 1..=10 {
        assert!(advance(&core, at(1_700_000_000 + second)).is_empty());
    }
    assert!(advance(&core, at(1_600_000_000)).is_empty(), "went back");
    assert!(is_registered(&core, &crosswalk, &id));
    assert_eq!(advance(&core, at(1_700_000_011)), vec![id]);
    assert!(!is_registered(&core, &crosswalk, &id));
}

#[test]
fn a_jump_of_the_clock_counts_the_step_limit() {
    let core = Core::new(0).unwrap();
    let crosswalk = find(&core, "crosswalk");
    assert!(bind(&core, &crosswalk, true).ok);
    assert!(advance(&core, at(100)).is_empty());
    let id = scene(3);
    assert!(report(&core, 100, "crosswalk", &id).outcome.ok);
    // A seek 20 s ahead, then 8 s of cycles: 9 s counted, within the time to live.
    assert!(advance(&core, at(120)).is_empty());
    for second in 121..=128 {
        assert!(advance(&core, at(second)).is_empty());
    }
    assert!(is_registered(&core, &crosswalk, &id));
    // Two more seconds, 11 s counted: the scene no longer reported expires.
    assert!(advance(&core, at(129)).is_empty());
    assert_eq!(advance(&core, at(130)), vec![id]);
}

/// `[COOP-ENGINE-TIME.1]`: a report, a command and an auto-mode switch are each made at
/// their own time, told in the same call, and each says which scenes expired first.
#[test]
fn each_call_is_made_at_its_own_time() {
    let core = Core::new(0).unwrap();
    let crosswalk = find(&core, "crosswalk");
    assert!(bind(&core, &crosswalk, true).ok);
    let (first, second) = (scene(4), scene(5));
    assert_eq!(
        report(&core, 0, "crosswalk", &first),
        told((Ok(()), Vec::new()))
    );
    for now in 1..=10 {
        assert!(report(&core, now, "crosswalk", &second).expired.is_empty());
    }
    // The first scene's time to live ran out: it expires before the report is made.
    assert_eq!(report(&core, 11, "crosswalk", &second).expired, vec![first]);
    assert!(
        !report(&core, 11, "crosswalk", &first).outcome.ok,
        "expired for good"
    );
    for now in 12..=21 {
        assert!(auto_mode(&core, at(now), &crosswalk, false)
            .expired
            .is_empty());
    }
    let command = CommandIn {
        uuid: second,
        module: module_type(&core, &crosswalk),
        command: rtc::Command::ACTIVATE,
    };
    let late = cooperate_commands(&core, at(22), &crosswalk, &[command]);
    assert_eq!(late.expired, vec![second]);
    assert!(!late.outcome.ok, "{late:?}");
    assert!(late.responses.iter().all(|entry| !entry.success));
}

#[test]
fn refusals_are_explained_and_change_nothing() {
    let core = Core::new(0).unwrap();
    let id = scene(2);
    let unbound = report(&core, 0, "TestRTC", &id).outcome;
    assert!(
        !unbound.ok && unbound.warning.contains("TestRTC"),
        "{unbound:?}"
    );
    let unknown = find(&core, "TestRTC");
    assert!(!bind(&core, &unknown, true).ok);
    let name = &find(&core, "static_obstacle_avoidance_left");
    assert!(bind(&core, name, true).ok);
    // A report in `sequence`, its state `state`.
    let stated = |state, sequence| {
        update(
            &core,
            at(0),
            name,
            &id,
            true,
            state,
            1.0,
            1.0,
            false,
            true,
            sequence,
        )
        .outcome
    };
    let bad = stated(0, "a b");
    assert!(
        !bad.ok && bad.warning.starts_with("sequence \"a b\""),
        "{bad:?}"
    );
    let state = stated(9, "change");
    assert!(
        !state.ok && state.warning.contains("state.type is 9"),
        "{state:?}"
    );
    assert!(!is_registered(&core, name, &id));
    assert_eq!(is_rtc_enabled(&core, name, &id), Flag::Unknown);
    assert!(stated(0, "change").ok);
    assert_eq!(is_rtc_enabled(&core, name, &id), Flag::Yes);
    assert_eq!(module_type(&core, name), rtc::Module::AVOIDANCE_LEFT);
    assert_eq!(module_type(&core, &unknown), rtc::Module::NONE);
}

#[test]
fn the_benchmark_baseline_times_every_call() {
    let costs = crate::timing::time_rust_calls(10, 10);
    assert_eq!(costs.len(), 11);
    assert!(costs.iter().all(|cost| cost.nanos > 0.0), "{costs:?}");
}

/// The answers of every query about `uuid` through `handle`.
type Answered6 = (bool, bool, bool, bool, Flag, Flag);

fn through_bridge(core: &Core, handle: &Handle, uuid: &Uuid) -> Answered6 {
    (
        is_registered(core, handle, uuid),
        is_activated(core, handle, uuid),
        is_force_activated(core, handle, uuid),
        is_force_deactivated(core, handle, uuid),
        is_rtc_enabled(core, handle, uuid),
        is_terminated(core, handle, uuid),
    )
}

/// The same answers from the adapter's queries under the core's lock, with no snapshot.
fn through_core(core: &Core, handle: &Handle, uuid: &Uuid) -> Answered6 {
    let id = id(uuid);
    (
        view(core, handle, |view| view.is_registered(id)).unwrap_or(false),
        view(core, handle, |view| view.is_activated(id)).unwrap_or(false),
        view(core, handle, |view| view.is_force_activated(id)).unwrap_or(false),
        view(core, handle, |view| view.is_force_deactivated(id)).unwrap_or(false),
        flag(view(core, handle, |view| view.is_rtc_enabled(id))),
        flag(view(core, handle, |view| view.is_terminated(id))),
    )
}

/// A small deterministic source of choices (xorshift).
struct Choices(u64);

impl Choices {
    fn below(&mut self, bound: u64) -> u64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        self.0 % bound
    }
}

/// The scene numbered `n`.
fn numbered(n: usize) -> Uuid {
    let mut bytes = [0; 16];
    bytes[8..].copy_from_slice(&(n as u64 + 1).to_be_bytes());
    Uuid { bytes }
}

/// Every query answers what the adapter's queries answer under the lock, after every kind of
/// change of the core, through the bridge or past it (`Shared::update` called directly), with
/// more scenes in an interface than its snapshot holds and fewer.
#[test]
fn the_snapshot_answers_as_the_core_after_every_change() {
    let core = Core::new(0).unwrap();
    let names = ["intersection", "crosswalk"];
    let handles: Vec<Box<Handle>> = names.iter().map(|name| find(&core, name)).collect();
    let unknown = find(&core, "TestRTC");
    for handle in &handles {
        assert!(bind(&core, handle, true).ok);
    }
    // More live scenes in one interface than a snapshot holds, to begin with: the snapshot
    // answers up to 16 and asks the core from 17 on.
    for n in 0..20 {
        assert!(report(&core, 0, names[0], &numbered(n)).outcome.ok);
        assert!(is_registered(&core, &handles[0], &numbered(n)));
        let lookup = handles[0]
            .snapshot
            .lookup(core.shared.changes(), &numbered(n).bytes);
        assert_eq!(
            lookup != Lookup::Ask,
            n < 16,
            "{} scenes: {lookup:?}",
            n + 1
        );
    }
    let mut choices = Choices(0x9e37_79b9_7f4a_7c15);
    let (mut now, mut held, mut too_many) = (0, 0, 0);
    for step in 0..3_000 {
        // The scenes in play: 24 numbers, moving on (an identifier is never used again once
        // its scene is over).
        let ids: Vec<Uuid> = (step / 50 * 4..step / 50 * 4 + 24).map(numbered).collect();
        let which = usize::try_from(choices.below(2)).unwrap();
        let (name, handle) = (names[which], &handles[which]);
        let uuid = ids[usize::try_from(choices.below(24)).unwrap()];
        let module = module_type(&core, handle);
        match choices.below(9) {
            0..=2 => {
                let state = u8::try_from(choices.below(6)).unwrap();
                let safe = choices.below(2) == 0;
                let requested = choices.below(4) == 0;
                let _ = update(
                    &core,
                    at(now),
                    handle,
                    &uuid,
                    safe,
                    state,
                    5.0,
                    9.0,
                    requested,
                    false,
                    "",
                );
            }
            3 | 4 => {
                let command = [rtc::Command::ACTIVATE, rtc::Command::DEACTIVATE]
                    [usize::try_from(choices.below(2)).unwrap()];
                let _ = cooperate_commands(
                    &core,
                    at(now),
                    handle,
                    &[CommandIn {
                        uuid,
                        module,
                        command,
                    }],
                );
            }
            5 => {
                let _ = auto_mode(&core, at(now), handle, choices.below(2) == 0);
            }
            6 => {
                let _ = if choices.below(8) == 0 {
                    clear(&core, handle)
                } else {
                    remove(&core, handle, &uuid)
                };
            }
            7 => {
                now += i32::try_from(choices.below(3)).unwrap();
                let _ = advance(&core, at(now));
            }
            _ => {
                // A change past the bridge: the auto mode set on the engine directly.
                let enable = choices.below(2) == 0;
                let _ = core.shared().update(|engine| {
                    engine.call(|host| {
                        host.interface(name)?
                            .auto_mode(&AutoModeRequest { enable })
                            .result
                    })
                });
            }
        }
        for handle in handles.iter().chain([&unknown]) {
            for uuid in &ids {
                let expected = through_core(&core, handle, uuid);
                // Twice: the first may make the snapshot again, the second reads it.
                assert_eq!(through_bridge(&core, handle, uuid), expected, "step {step}");
                assert_eq!(through_bridge(&core, handle, uuid), expected, "step {step}");
            }
            // The snapshot answers for an interface of up to 16 live scenes, and for no other.
            let live = view(&core, handle, |view| view.scenes().count()).unwrap_or(0);
            match handle.snapshot.lookup(core.shared.changes(), &ids[0].bytes) {
                Lookup::Current(_) => {
                    assert!(live <= 16, "{live} live scenes in the snapshot");
                    held += usize::from(live > 0);
                }
                Lookup::Ask => {
                    assert!(live > 16, "{live} live scenes, and the snapshot asks");
                    too_many += 1;
                }
            }
        }
    }
    // Both kinds of interface were met: one with live scenes its snapshot held, one too big
    // for it.
    assert!(held > 1_000 && too_many > 10, "{held} {too_many}");
}

/// A query made after another thread's change returned is never answered from before it: a
/// thread registers a scene and removes the one registered eight changes before, then counts
/// the change; a thread that read the count finds the scene registered last (unless the first
/// thread has since gone so far as to remove it).
#[test]
fn a_query_sees_every_change_made_before_it_on_another_thread() {
    use std::sync::atomic::{AtomicUsize, Ordering};

    let core = Core::new(0).unwrap();
    let handle = find(&core, "intersection");
    assert!(bind(&core, &handle, true).ok);
    let uuid_of = numbered;
    let made = AtomicUsize::new(0);
    let (rounds, kept) = (2_000, 8);
    std::thread::scope(|scope| {
        scope.spawn(|| {
            for n in 0..rounds {
                assert!(report(&core, 0, "intersection", &uuid_of(n)).outcome.ok);
                if n >= kept {
                    assert!(remove(&core, &handle, &uuid_of(n - kept)).ok);
                }
                made.store(n + 1, Ordering::Release);
            }
        });
        let mut checked = 0;
        while made.load(Ordering::Acquire) < rounds {
            let before = made.load(Ordering::Acquire);
            if before == 0 {
                continue;
            }
            let registered = is_registered(&core, &handle, &uuid_of(before - 1));
            let after = made.load(Ordering::Acquire);
            if after < before + kept - 1 {
                assert!(registered, "scene {} read as not registered", before - 1);
                checked += 1;
            }
        }
        assert!(checked > 0);
    });
}
