//! The `render` command and what belongs to it: the one place its flags
//! exist and become validated settings ([`args`]), running it ([`cli`]),
//! validating files (`--check`, [`check`]), a P3F scene's cube map
//! ([`environment`]), the statistics it prints
//! ([`report`], [`spd_published`]), the warnings about a scene as a whole
//! ([`scene_warnings`]: no lights, a light in a surface's plane, a view of
//! back faces), and render-farm parts with their checked merge ([`part`],
//! behind `nffmerge`).

pub mod args;
pub mod check;
pub mod cli;
pub mod coplanar;
pub mod environment;
pub mod part;
pub mod report;
pub mod scene_warnings;
pub mod spd_published;
