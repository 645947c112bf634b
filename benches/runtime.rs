//! Runtime benchmarks: the library against an upstream-style linear registry, in the same run.
//!
//! `cargo bench --bench runtime` times four groups, each with the library (`library`) and the
//! baseline (`baseline`, [`workload::baseline::LinearRegistry`]) side by side:
//!
//! - `cycle/N`: one planning cycle with N live scenes over 8 modules; here also
//!   `baseline-per-module` ([`workload::baseline::PerModuleRegistry`]);
//! - `phase/{update,query,outputs}/N`: the three parts of that cycle timed one by one, at
//!   N = 1, 10, 1 000 and 10 000;
//! - `commands/K`: one `set_commands` batch of K commands, 10 000 live scenes;
//! - `policy/N`: one policy change of a module with N live scenes;
//! - `churn/N`: one registration plus one removal, N live scenes.
//!
//! Before timing it counts heap allocations per steady-state cycle on both sides and writes
//! them to `target/criterion/allocations.json`. `tools/bench_report.py` turns the results into
//! `docs/performance.md`.

use std::alloc::System;
use std::hint::black_box;
use std::time::Duration;

use cooperation::{OperatorDecision, Policy, PolicySetting, State};
use criterion::measurement::WallTime;
use criterion::{BatchSize, BenchmarkGroup, BenchmarkId, Criterion, SamplingMode, Throughput};
use stats_alloc::{Region, StatsAlloc, INSTRUMENTED_SYSTEM};

mod workload;

use workload::baseline::{LinearRegistry, PerModuleRegistry};
use workload::{Outputs, Planner, Registry, MODULES};

#[global_allocator]
static GLOBAL: &StatsAlloc<System> = &INSTRUMENTED_SYSTEM;

/// The numbers of live scenes.
const SCENES: [usize; 5] = [1, 10, 100, 1_000, 10_000];
/// The sizes of the command batches.
const BATCHES: [usize; 3] = [1, 100, 10_000];
/// The live scenes while command batches are timed.
const COMMAND_SCENES: usize = 10_000;

/// Cycles run before counting, so that the output buffers have grown to size.
const WARM_CYCLES: u64 = 3;
/// Cycles counted.
const COUNTED_CYCLES: u64 = 10;

/// Heap allocations and bytes per steady-state cycle of a planner with `scenes` scenes.
fn allocations_per_cycle<R: Registry>(scenes: usize) -> (u64, u64) {
    let mut planner = Planner::<R>::new(scenes);
    let mut out = Outputs::default();
    for _ in 0..WARM_CYCLES {
        black_box(planner.cycle(&mut out));
    }
    let region = Region::new(GLOBAL);
    for _ in 0..COUNTED_CYCLES {
        black_box(planner.cycle(&mut out));
    }
    let change = region.change();
    (
        (change.allocations + change.reallocations) as u64 / COUNTED_CYCLES,
        change.bytes_allocated as u64 / COUNTED_CYCLES,
    )
}

/// Counts allocations per steady-state cycle for every N, prints them and writes them as JSON
/// next to criterion's results.
fn report_allocations() {
    let mut rows = Vec::new();
    for scenes in SCENES {
        let (library, library_bytes) = allocations_per_cycle::<State>(scenes);
        let (baseline, baseline_bytes) = allocations_per_cycle::<LinearRegistry>(scenes);
        println!(
            "allocations per steady-state cycle, N = {scenes}: library {library} \
             ({library_bytes} bytes), baseline {baseline} ({baseline_bytes} bytes)"
        );
        rows.push(format!(
            "{{\"scenes\": {scenes}, \"library\": {library}, \"library_bytes\": {library_bytes}, \
             \"baseline\": {baseline}, \"baseline_bytes\": {baseline_bytes}}}"
        ));
    }
    let json = format!(
        "{{\"counted_cycles\": {COUNTED_CYCLES}, \"rows\": [\n  {}\n]}}\n",
        rows.join(",\n  ")
    );
    let dir = std::env::var_os("CARGO_TARGET_DIR")
        .map_or_else(|| "target".into(), std::path::PathBuf::from)
        .join("criterion");
    let written = std::fs::create_dir_all(&dir)
        .and_then(|()| std::fs::write(dir.join("allocations.json"), json));
    if let Err(error) = written {
        eprintln!("could not write allocations.json: {error}");
    }
}

/// A benchmark group measuring wall time.
type Group<'a> = BenchmarkGroup<'a, WallTime>;

/// Sets the sampling of the next benchmarks: 30 samples, or for slow ones (about 0.1 s an
/// iteration) criterion's minimum of 10 samples of one iteration each.
fn sampling(group: &mut Group<'_>, slow: bool) {
    if slow {
        group.sampling_mode(SamplingMode::Flat).sample_size(10);
    } else {
        group.sampling_mode(SamplingMode::Auto).sample_size(30);
    }
}

/// Times planning cycles of a planner with `scenes` scenes, built when the benchmark runs.
fn cycles<R: Registry>(group: &mut Group<'_>, name: &str, scenes: usize) {
    let mut planner = None;
    let mut out = Outputs::default();
    group.bench_function(BenchmarkId::new(name, scenes), |b| {
        let planner = planner.get_or_insert_with(|| Planner::<R>::new(scenes));
        b.iter(|| black_box(planner.cycle(&mut out)));
    });
}

fn cycle(c: &mut Criterion) {
    let mut group = c.benchmark_group("cycle");
    group
        .warm_up_time(Duration::from_secs(1))
        .measurement_time(Duration::from_secs(5));
    for scenes in SCENES {
        group.throughput(Throughput::Elements(scenes as u64));
        sampling(&mut group, false);
        cycles::<State>(&mut group, "library", scenes);
        sampling(&mut group, scenes >= 10_000);
        cycles::<LinearRegistry>(&mut group, "baseline", scenes);
        cycles::<PerModuleRegistry>(&mut group, "baseline-per-module", scenes);
    }
    group.finish();
}

/// The numbers of live scenes the cycle is timed part by part at.
const PHASE_SCENES: [usize; 4] = [1, 10, 1_000, 10_000];

/// Times each part of a planning cycle on its own, on a planner with `scenes` scenes: the
/// owners' updates, the merged-decision queries, and the status and factor lists.
fn phases<R: Registry>(group: &mut Group<'_>, name: &str, scenes: usize) {
    let mut planner = Planner::<R>::new(scenes);
    let mut out = Outputs::default();
    planner.cycle(&mut out);
    group.bench_function(BenchmarkId::new(format!("update/{name}"), scenes), |b| {
        b.iter(|| black_box(planner.update_all()));
    });
    group.bench_function(BenchmarkId::new(format!("query/{name}"), scenes), |b| {
        b.iter(|| black_box(planner.decide_all()));
    });
    group.bench_function(BenchmarkId::new(format!("outputs/{name}"), scenes), |b| {
        b.iter(|| planner.registry.outputs(black_box(&mut out)));
    });
}

fn phase(c: &mut Criterion) {
    let mut group = c.benchmark_group("phase");
    group
        .warm_up_time(Duration::from_millis(500))
        .measurement_time(Duration::from_secs(2));
    for scenes in PHASE_SCENES {
        group.throughput(Throughput::Elements(scenes as u64));
        sampling(&mut group, false);
        phases::<State>(&mut group, "library", scenes);
        sampling(&mut group, scenes >= 10_000);
        phases::<LinearRegistry>(&mut group, "baseline", scenes);
    }
    group.finish();
}

/// Times `k`-command batches on a planner, alternating the decision so every batch changes
/// something.
fn command_batches<R: Registry>(group: &mut Group<'_>, name: &str, k: usize) {
    let mut planner = None;
    let mut turn = 0;
    group.bench_function(BenchmarkId::new(name, k), |b| {
        let (planner, batches) = planner.get_or_insert_with(|| {
            let planner = Planner::<R>::new(COMMAND_SCENES);
            let batches = [
                planner.commands(k, OperatorDecision::Activate),
                planner.commands(k, OperatorDecision::Deactivate),
            ];
            (planner, batches)
        });
        b.iter_batched(
            || {
                turn += 1;
                batches[turn % 2].clone()
            },
            |batch| black_box(planner.registry.set_commands(batch)),
            BatchSize::SmallInput,
        );
    });
}

fn commands(c: &mut Criterion) {
    let mut group = c.benchmark_group("commands");
    group
        .warm_up_time(Duration::from_millis(500))
        .measurement_time(Duration::from_secs(2));
    for k in BATCHES {
        group.throughput(Throughput::Elements(k as u64));
        sampling(&mut group, false);
        command_batches::<State>(&mut group, "library", k);
        sampling(&mut group, k >= 10_000);
        command_batches::<LinearRegistry>(&mut group, "baseline", k);
    }
    group.finish();
}

/// Times policy changes of the one module of a planner with `scenes` scenes, alternating
/// between optional and required.
fn policy_changes<R: Registry>(group: &mut Group<'_>, name: &str, scenes: usize) {
    let mut planner = None;
    let module = MODULES[0].0;
    let mut turn = 0;
    group.bench_function(BenchmarkId::new(name, scenes), |b| {
        let planner =
            planner.get_or_insert_with(|| Planner::<R>::with_modules(&MODULES[..1], scenes));
        b.iter_batched(
            || {
                turn += 1;
                let policy = if turn % 2 == 0 {
                    Policy::Optional
                } else {
                    Policy::Required
                };
                vec![PolicySetting { module, policy }]
            },
            |settings| black_box(planner.registry.set_policies(settings)),
            BatchSize::SmallInput,
        );
    });
}

fn policy(c: &mut Criterion) {
    let mut group = c.benchmark_group("policy");
    group
        .warm_up_time(Duration::from_millis(500))
        .measurement_time(Duration::from_secs(2));
    sampling(&mut group, false);
    for scenes in SCENES {
        policy_changes::<State>(&mut group, "library", scenes);
        policy_changes::<LinearRegistry>(&mut group, "baseline", scenes);
    }
    group.finish();
}

/// Times registration and retirement churn with `scenes` live scenes; the library's memory of
/// retired identifiers is full first.
fn churns<R: Registry>(group: &mut Group<'_>, name: &str, scenes: usize) {
    let mut planner = None;
    group.bench_function(BenchmarkId::new(name, scenes), |b| {
        let planner = planner.get_or_insert_with(|| {
            let mut planner = Planner::<R>::new(scenes);
            planner.fill_retired();
            planner
        });
        b.iter(|| planner.churn());
    });
}

fn churn(c: &mut Criterion) {
    let mut group = c.benchmark_group("churn");
    group
        .warm_up_time(Duration::from_millis(500))
        .measurement_time(Duration::from_secs(2));
    sampling(&mut group, false);
    for scenes in SCENES {
        churns::<State>(&mut group, "library", scenes);
        churns::<LinearRegistry>(&mut group, "baseline", scenes);
    }
    group.finish();
}

fn main() {
    // `cargo test --benches` runs every benchmark once in test mode; that, listing and
    // profiling (`--profile-time`) skip the allocation report.
    let quick = std::env::args().any(|arg| ["--test", "--list", "--profile-time"].contains(&&*arg));
    if !quick {
        report_allocations();
    }
    let mut criterion = Criterion::default().configure_from_args();
    cycle(&mut criterion);
    phase(&mut criterion);
    commands(&mut criterion);
    policy(&mut criterion);
    churn(&mut criterion);
    criterion.final_summary();
}
