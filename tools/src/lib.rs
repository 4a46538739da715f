//! The library behind nffkit's command-line tools. Binaries in `src/bin/` are
//! thin shells of argument parsing over these functions, so tests and other
//! tools call exactly the same code.
// Two exceptions, with their reasoning: `input::map` (memory-mapping large
// scene files) and `heap` (the allocator).
#![deny(unsafe_code)]

/// Every tool allocates through [`heap::Heap`]: mimalloc, big blocks in
/// huge pages. Declared here, in the library every binary links, so all of
/// them (and the tests) use the same allocator.
#[global_allocator]
static ALLOCATOR: heap::Heap = heap::Heap;

pub mod bench;
pub mod cli_util;
pub mod convert;
pub mod demo;
pub mod gen;
pub mod heap;
pub mod input;
pub mod memory;
pub mod mesh2nff;
pub mod outputs;
pub mod qa;
pub mod render;
pub mod spd;
