//! Every pinned state count, in one table.
//!
//! A pin is the number of distinct states (and, where pinned, of generated successors) that one
//! checked configuration reaches. The tests assert these values, so a change in the reachable
//! state space is a one-line diff here to review; `cargo xtask docs` renders this table as
//! `docs/counts.md`, which the rest of the documentation links to instead of repeating a
//! number; and `cargo xtask docs --check` fails when the reach table of `docs/reach.md`
//! measured another count for a pinned configuration, or a page repeats a pinned count.
//!
//! The counts are the models', not targets: if one moves, find out why before changing it
//! (`docs/verification.md`).

/// One checked configuration and what it reaches.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Pin {
    /// The test that asserts it, as `file::function`.
    pub test: &'static str,
    /// The model, as the reach table names it.
    pub model: &'static str,
    /// The bounds, as the reach table writes them.
    pub bounds: &'static str,
    /// The search, as the reach table writes it.
    pub search: &'static str,
    /// Distinct states (after symmetry reduction where it is on).
    pub unique: usize,
    /// Successors handed to the checker, duplicates included; `None` where only the unique
    /// count is pinned.
    pub generated: Option<usize>,
}

/// The sequential model, 2 modules × 3 identifiers: the CI configuration and the main job's.
pub const SEQUENTIAL_2X3: Pin = Pin {
    test: "models/tests/exhaustive.rs::two_modules_three_scenes",
    model: "sequential",
    bounds: "2 × 3",
    search: "DFS, symmetry",
    unique: 994_453,
    generated: Some(37_365_722),
};

/// The sequential model, 3 modules × 3 identifiers.
pub const SEQUENTIAL_3X3: Pin = Pin {
    test: "models/tests/exhaustive.rs::three_modules_three_scenes",
    model: "sequential",
    bounds: "3 × 3",
    search: "DFS, symmetry",
    unique: 6_415_437,
    generated: Some(246_321_008),
};

/// The CI configuration breadth first over canonical states: the depth-first symmetric
/// search's classes, so its counts.
pub const SEQUENTIAL_2X3_CANONICAL: Pin = Pin {
    test: "models/tests/canonical.rs::two_modules_three_scenes_canonical",
    model: "sequential",
    bounds: "2 × 3",
    search: "BFS, canonical states",
    unique: SEQUENTIAL_2X3.unique,
    generated: SEQUENTIAL_2X3.generated,
};

/// 3 × 3 breadth first over canonical states: the depth-first symmetric counts.
pub const SEQUENTIAL_3X3_CANONICAL: Pin = Pin {
    test: "models/tests/canonical.rs::three_modules_three_scenes_canonical",
    model: "sequential",
    bounds: "3 × 3",
    search: "BFS, canonical states",
    unique: SEQUENTIAL_3X3.unique,
    generated: SEQUENTIAL_3X3.generated,
};

/// The CI configuration with the hashed table from the first scene: the same states.
pub const SEQUENTIAL_2X3_HASHED: Pin = Pin {
    test: "models/tests/exhaustive.rs::two_modules_three_scenes_hashed_table",
    model: "sequential, hashed table",
    bounds: "2 × 3",
    search: "DFS, symmetry",
    unique: SEQUENTIAL_2X3.unique,
    generated: None,
};

/// The hashed table, one module × 3 identifiers, without symmetry.
pub const SEQUENTIAL_1X3_HASHED: Pin = Pin {
    test: "models/tests/exhaustive.rs::one_module_three_scenes_hashed_table_without_symmetry",
    model: "sequential, hashed table",
    bounds: "1 × 3",
    search: "BFS",
    unique: 411_099,
    generated: Some(15_194_918),
};

/// The hashed table, one module × 4 identifiers with 3 live at once, to six steps.
pub const SEQUENTIAL_1X4_HASHED_6_STEPS: Pin = Pin {
    test: "models/tests/exhaustive.rs::one_module_three_live_scenes_hashed_table_to_six_steps",
    model: "sequential, hashed table, 3 live",
    bounds: "1 × 4",
    search: "BFS to 6 steps",
    unique: 462_801,
    generated: Some(5_400_961),
};

/// The sequential model, 2 × 2, breadth first without symmetry.
pub const SEQUENTIAL_2X2: Pin = Pin {
    test: "models/tests/exhaustive.rs::two_modules_two_scenes_without_symmetry",
    model: "sequential",
    bounds: "2 × 2",
    search: "BFS",
    unique: 26_601,
    generated: Some(699_884),
};

/// The sequential model, 2 × 2, depth first with symmetry.
pub const SEQUENTIAL_2X2_SYMMETRY: Pin = Pin {
    test: "models/tests/exhaustive.rs::two_modules_two_scenes_without_symmetry",
    model: "sequential",
    bounds: "2 × 2",
    search: "DFS, symmetry",
    unique: 13_345,
    generated: Some(350_352),
};

/// The sequential model, 1 × 2, breadth first without symmetry.
pub const SEQUENTIAL_1X2: Pin = Pin {
    test: "models/tests/exhaustive.rs::one_module_two_scenes",
    model: "sequential",
    bounds: "1 × 2",
    search: "BFS",
    unique: 3_719,
    generated: Some(95_737),
};

/// The sequential model, 1 × 2, depth first with symmetry.
pub const SEQUENTIAL_1X2_SYMMETRY: Pin = Pin {
    test: "models/tests/exhaustive.rs::one_module_two_scenes",
    model: "sequential",
    bounds: "1 × 2",
    search: "DFS, symmetry",
    unique: 1_879,
    generated: Some(47_973),
};

/// The sequential model, 2 × 3 with one scene live and one retired identifier remembered.
pub const SEQUENTIAL_FORGETTING: Pin = Pin {
    test: "models/tests/exhaustive.rs::forgetting_retired_identifiers",
    model: "sequential, 1 live, 1 retired remembered",
    bounds: "2 × 3",
    search: "BFS",
    unique: 73_249,
    generated: Some(2_230_742),
};

/// The network model: the planner and two operators, 2 identifiers.
pub const NETWORK: Pin = Pin {
    test: "models/tests/exhaustive.rs::network_two_operators_two_scenes",
    model: "network",
    bounds: "2 ids",
    search: "BFS",
    unique: 160_656,
    generated: None,
};

/// The network model, one operator whose views carry whole statuses, 2 identifiers.
pub const NETWORK_STATUS_VIEWS: Pin = Pin {
    test: "models/tests/exhaustive.rs::network_one_operator_two_scenes_status_views",
    model: "network, 1 operator, status views",
    bounds: "2 ids",
    search: "BFS",
    unique: 1_059_336,
    generated: None,
};

/// The RTC model: the two lane-change interfaces, 3 identifiers.
pub const RTC_2X3: Pin = Pin {
    test: "models/tests/rtc_model.rs::two_interfaces_three_scenes",
    model: "rtc",
    bounds: "2 × 3",
    search: "DFS, symmetry",
    unique: 1_968_042,
    generated: None,
};

/// The RTC model: one avoidance interface, a change and a return live at once.
pub const RTC_AVOIDANCE: Pin = Pin {
    test: "models/tests/rtc_model.rs::avoidance_change_and_return",
    model: "rtc, one avoidance interface, 2 live",
    bounds: "1 × 2",
    search: "DFS, symmetry",
    unique: 363_472,
    generated: None,
};

/// The RTC model: both avoidance interfaces, one scene live at a time.
pub const RTC_TWO_AVOIDANCES: Pin = Pin {
    test: "models/tests/rtc_model.rs::two_avoidance_interfaces",
    model: "rtc, both avoidance interfaces",
    bounds: "2 × 2",
    search: "DFS, symmetry",
    unique: 317_268,
    generated: None,
};

/// The RTC model: the two lane-change interfaces, 3 identifiers, 2 live, a quota of 2 live
/// scenes per interface.
pub const RTC_QUOTA: Pin = Pin {
    test: "models/tests/rtc_model.rs::two_interfaces_three_scenes_with_a_quota",
    model: "rtc, a quota of 2 per interface",
    bounds: "2 × 3",
    search: "DFS, symmetry",
    unique: 2_010_378,
    generated: None,
};

/// The relay model: an operator and one upstream planning module, 1 identifier, 2 operator
/// calls, 1 module move, 1 loss, a status array ahead of its auto-mode status.
pub const RELAY_1: Pin = Pin {
    test: "models/tests/relay_model.rs::the_relay_meets_its_rules",
    model: "relay",
    bounds: "1 id, 2 calls, 1 move, 1 loss, split",
    search: "BFS",
    unique: 423_772,
    generated: None,
};

/// The batch model: pairs of inputs applied all or none, 1 module × 2 identifiers, one live and
/// one retired at most.
pub const BATCH: Pin = Pin {
    test: "models/tests/batch_model.rs::a_sequence_applies_all_or_none",
    model: "batch",
    bounds: "1 × 2, pairs, 1 live, 1 retired",
    search: "BFS",
    unique: 2_322,
    generated: None,
};

/// The relay model with 2 identifiers (a long check).
pub const RELAY_2: Pin = Pin {
    test: "models/tests/relay_model.rs::the_relay_meets_its_rules_with_two_scenes",
    model: "relay",
    bounds: "2 ids, 2 calls, 1 move, 1 loss",
    search: "BFS",
    unique: 4_211_772,
    generated: None,
};

/// The relay model with 2 module moves, so that a scene runs and then finishes or aborts (a long
/// check).
pub const RELAY_1_TWO_MOVES: Pin = Pin {
    test: "models/tests/relay_model.rs::the_relay_meets_its_rules_with_two_module_moves",
    model: "relay",
    bounds: "1 id, 2 calls, 2 moves, 1 loss, split",
    search: "BFS",
    unique: 3_627_878,
    generated: None,
};

/// The engine model: a host driving the service engine, 2 identifiers, its clock to 3 ms.
pub const ENGINE_2: Pin = Pin {
    test: "models/tests/engine_model.rs::the_engine_meets_its_rules",
    model: "engine",
    bounds: "2 ids, 3 ms",
    search: "BFS",
    unique: 328_030,
    generated: None,
};

/// The engine model with a clock that jumps: a step limit of 1 ms, 2 identifiers, its clock
/// to 2 ms.
pub const ENGINE_JUMPS: Pin = Pin {
    test: "models/tests/engine_model.rs::a_jumping_clock_retires_no_scene_before_its_time",
    model: "engine, jumping clock",
    bounds: "2 ids, 2 ms, step limit 1 ms",
    search: "BFS",
    unique: 217_050,
    generated: None,
};

/// The engine model with the module's reports and the operator's commands made through the
/// RTC interface in the engine's process, as the C++ class makes them: 2 identifiers, its clock
/// to 2 ms.
pub const ENGINE_IN_PROCESS: Pin = Pin {
    test: "models/tests/engine_model.rs::a_command_in_the_process_is_made_at_its_time",
    model: "engine, the C++ class's door",
    bounds: "2 ids, 2 ms",
    search: "BFS",
    unique: 167_214,
    generated: None,
};

/// The engine model with a clock that goes back 1 ms once, 2 identifiers, its clock to 3 ms.
pub const ENGINE_REWINDS: Pin = Pin {
    test: "models/tests/engine_model.rs::a_clock_that_goes_back_counts_on_from_its_reading",
    model: "engine, clock going back",
    bounds: "2 ids, 3 ms, back 1 ms once",
    search: "BFS",
    unique: 3_131_344,
    generated: None,
};

/// The engine model's message check: 2 steering scenes starting at every special distance.
pub const ENGINE_GEOMETRY_STEERING: Pin = Pin {
    test: "models/tests/engine_model.rs::the_messages_are_the_specs_at_every_special_distance",
    model: "engine, steering geometry",
    bounds: "2 ids, 0 ms",
    search: "BFS",
    unique: 2_890,
    generated: None,
};

/// The engine model's message check: 2 velocity scenes starting at every special distance.
pub const ENGINE_GEOMETRY_VELOCITY: Pin = Pin {
    test: "models/tests/engine_model.rs::the_messages_are_the_specs_at_every_special_distance",
    model: "engine, velocity geometry",
    bounds: "2 ids, 0 ms",
    search: "BFS",
    unique: 2_890,
    generated: None,
};

/// The network model through the service engine: two operators, 2 identifiers.
pub const NETWORK_ENGINE: Pin = Pin {
    test: "models/tests/network_engine.rs::network_through_the_engine_two_operators",
    model: "network through the engine",
    bounds: "2 ids",
    search: "BFS",
    unique: 48_798,
    generated: None,
};

/// The network model through the service engine, one operator told whole statuses.
pub const NETWORK_ENGINE_STATUS_VIEWS: Pin = Pin {
    test: "models/tests/network_engine.rs::network_through_the_engine_status_views",
    model: "network through the engine, status views",
    bounds: "2 ids, 1 operator",
    search: "BFS",
    unique: 370_309,
    generated: None,
};

/// Every pin, in the order `docs/counts.md` lists them.
pub const ALL: [Pin; 30] = [
    SEQUENTIAL_1X2,
    SEQUENTIAL_1X2_SYMMETRY,
    SEQUENTIAL_2X2,
    SEQUENTIAL_2X2_SYMMETRY,
    SEQUENTIAL_2X3,
    SEQUENTIAL_2X3_CANONICAL,
    SEQUENTIAL_3X3,
    SEQUENTIAL_3X3_CANONICAL,
    SEQUENTIAL_FORGETTING,
    SEQUENTIAL_2X3_HASHED,
    SEQUENTIAL_1X3_HASHED,
    SEQUENTIAL_1X4_HASHED_6_STEPS,
    NETWORK,
    NETWORK_STATUS_VIEWS,
    NETWORK_ENGINE,
    NETWORK_ENGINE_STATUS_VIEWS,
    RTC_2X3,
    RTC_AVOIDANCE,
    RTC_TWO_AVOIDANCES,
    RTC_QUOTA,
    ENGINE_2,
    ENGINE_JUMPS,
    ENGINE_IN_PROCESS,
    ENGINE_REWINDS,
    ENGINE_GEOMETRY_STEERING,
    ENGINE_GEOMETRY_VELOCITY,
    RELAY_1,
    RELAY_2,
    RELAY_1_TWO_MOVES,
    BATCH,
];

/// The pin of the configuration the reach table names so, if one is pinned.
#[must_use]
pub fn find(model: &str, bounds: &str, search: &str) -> Option<Pin> {
    ALL.into_iter()
        .find(|pin| pin.model == model && pin.bounds == bounds && pin.search == search)
}
