//! The trace tools' integration tests, in one test binary so that they are built and linked
//! once: each module is one file or folder of this one.

#[path = "cli/main.rs"]
mod cli;
mod cli_output;
mod docs;
mod geometry_numbers;
mod hostile;
mod hostile_lines;
mod hostile_messages;
mod seed;
mod versions;
