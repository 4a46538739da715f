//! The library behind nffkit's command-line tools. Binaries in `src/bin/` are
//! thin shells of argument parsing over these functions, so tests and other
//! tools call exactly the same code.
// One exception, with its reasoning: `input::map` (memory-mapping large
// scene files).
#![deny(unsafe_code)]

/// Every tool allocates through mimalloc: reading a big scene makes
/// hundreds of thousands of small allocations on two threads at once, and
/// glibc's per-thread arenas grow a page range at a time (a system call and
/// a lock on the address space each). Declared here, in the library every
/// binary links, so all of them (and the tests) use the same allocator.
/// Built without transparent huge pages (the crate's `no_thp`): a render's
/// heap is sparse, and the kernel zeroes a huge page whole when it is
/// first touched, so huge pages cost memory and system time for the parts
/// of each that are never written.
#[global_allocator]
static ALLOCATOR: mimalloc::MiMalloc = mimalloc::MiMalloc;

pub mod bench;
pub mod cli_util;
pub mod convert;
pub mod demo;
pub mod gen;
pub mod input;
pub mod memory;
pub mod mesh2nff;
pub mod outputs;
pub mod qa;
pub mod render;
pub mod spd;
