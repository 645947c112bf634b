//! One test per rule of spec §5, named after the rule's tag.

mod operators;
mod owners;
mod time;
