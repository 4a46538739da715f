//! Counters of the work a render did. Each thread counts into its own
//! [`Counters`]; they are summed after the render (never shared while
//! rendering), so counting costs no synchronisation and is deterministic.

use std::ops::AddAssign;

/// Rays by kind and the work their traversal did.
#[derive(Debug, Default, Clone, Copy, PartialEq, Eq)]
pub struct Counters {
    /// Eye (primary) rays.
    pub eye: u64,
    /// Reflected rays.
    pub reflected: u64,
    /// Refracted rays (including reflections spawned by total internal
    /// reflection of a transmitter).
    pub refracted: u64,
    /// Shadow rays.
    pub shadow: u64,
    /// Primitive intersection tests by kind: spheres, triangles, cones.
    pub tests: [u64; 3],
    /// Accelerator nodes (BVH) or cells (grid) visited.
    pub visits: u64,
    /// Primitive tests skipped because the mailbox had seen the primitive.
    pub mailbox_hits: u64,
}

impl Counters {
    /// All rays.
    pub fn rays(&self) -> u64 {
        self.eye + self.reflected + self.refracted + self.shadow
    }

    /// All primitive tests.
    pub fn total_tests(&self) -> u64 {
        self.tests.iter().sum()
    }

    /// A measure of traversal work for the per-pixel cost image.
    pub fn work(&self) -> u64 {
        self.total_tests() + self.visits
    }
}

impl AddAssign for Counters {
    fn add_assign(&mut self, o: Counters) {
        self.eye += o.eye;
        self.reflected += o.reflected;
        self.refracted += o.refracted;
        self.shadow += o.shadow;
        for i in 0..3 {
            self.tests[i] += o.tests[i];
        }
        self.visits += o.visits;
        self.mailbox_hits += o.mailbox_hits;
    }
}
