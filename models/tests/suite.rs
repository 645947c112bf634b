//! The models' tests, in one test binary so that they are built and linked once: each module
//! is one file of this folder. The checker allocates through mimalloc, as the model-checking
//! command does.

#[global_allocator]
static GLOBAL: mimalloc::MiMalloc = mimalloc::MiMalloc;

mod batch_model;
mod canonical;
mod cli;
mod coverage;
mod engine_model;
mod exhaustive;
mod faults;
mod library;
mod model_only;
mod network_engine;
mod reductions;
mod relay;
mod relay_model;
mod rtc_model;
mod simulate;
