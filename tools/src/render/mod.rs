//! The `render` command and what belongs to it: the one place its flags
//! exist and become validated settings ([`args`]), running it ([`cli`]),
//! validating files (`--check`, [`check`]), the statistics it prints
//! ([`report`], [`spd_published`]), the no-lights warning ([`lighting`]),
//! and render-farm parts with their checked merge ([`part`], behind
//! `nffmerge`).

pub mod args;
pub mod check;
pub mod cli;
pub mod lighting;
pub mod part;
pub mod report;
pub mod spd_published;
