//! Counters of the work a render did. Each thread counts into its own
//! [`Counters`]; they are summed after the render (never shared while
//! rendering), so counting costs no synchronisation and is deterministic.

pub use crate::geometry::Kind;
use std::ops::{AddAssign, Index, IndexMut};
use strum::{EnumCount, VariantArray};

/// One count per primitive [`Kind`], indexed by the kind itself.
#[derive(Debug, Default, Clone, Copy, PartialEq, Eq)]
pub struct PerKind([u64; Kind::COUNT]);

impl PerKind {
    /// Each kind with its count, in declaration order.
    pub fn iter(&self) -> impl Iterator<Item = (Kind, u64)> + '_ {
        Kind::VARIANTS.iter().map(|&k| (k, self[k]))
    }

    /// The sum over all kinds.
    pub fn total(&self) -> u64 {
        self.0.iter().sum()
    }
}

impl Index<Kind> for PerKind {
    type Output = u64;
    #[inline(always)]
    fn index(&self, k: Kind) -> &u64 {
        &self.0[k as usize]
    }
}

impl IndexMut<Kind> for PerKind {
    #[inline(always)]
    fn index_mut(&mut self, k: Kind) -> &mut u64 {
        &mut self.0[k as usize]
    }
}

impl AddAssign for PerKind {
    fn add_assign(&mut self, o: PerKind) {
        for (a, b) in self.0.iter_mut().zip(o.0) {
            *a += b;
        }
    }
}

/// Rays by kind and the work their traversal did.
#[derive(Debug, Default, Clone, Copy, PartialEq, Eq)]
pub struct Counters {
    /// Eye (primary) rays.
    pub eye: u64,
    /// Eye rays that hit something (the SPD's "eye hit rays").
    pub eye_hits: u64,
    /// Reflected rays (including those of total internal reflection).
    pub reflected: u64,
    /// Refracted rays.
    pub refracted: u64,
    /// Shadow rays.
    pub shadow: u64,
    /// Primitive intersection tests by kind.
    pub tests: PerKind,
    /// Accelerator nodes (BVH) or cells (grid) visited.
    pub visits: u64,
    /// Primitive tests skipped because the mailbox had seen the primitive.
    pub mailbox_hits: u64,
    /// Shadow rays found blocked by the shadow cache's primitive.
    pub shadow_cache_hits: u64,
}

impl Counters {
    /// All rays.
    pub fn rays(&self) -> u64 {
        self.eye + self.reflected + self.refracted + self.shadow
    }

    /// All primitive tests.
    pub fn total_tests(&self) -> u64 {
        self.tests.total()
    }

    /// A measure of traversal work for the per-pixel cost image.
    pub fn work(&self) -> u64 {
        self.total_tests() + self.visits
    }
}

impl AddAssign for Counters {
    fn add_assign(&mut self, o: Counters) {
        self.eye += o.eye;
        self.eye_hits += o.eye_hits;
        self.reflected += o.reflected;
        self.refracted += o.refracted;
        self.shadow += o.shadow;
        self.tests += o.tests;
        self.visits += o.visits;
        self.mailbox_hits += o.mailbox_hits;
        self.shadow_cache_hits += o.shadow_cache_hits;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_kind_has_its_own_counter() {
        // Kinds index the array by discriminant: they must be 0..COUNT in
        // declaration order, each counted and listed once.
        let mut c = PerKind::default();
        for (i, &k) in Kind::VARIANTS.iter().enumerate() {
            assert_eq!(k as usize, i);
            c[k] += i as u64 + 1;
        }
        let listed: Vec<u64> = c.iter().map(|(_, n)| n).collect();
        assert_eq!(listed, (1..=Kind::COUNT as u64).collect::<Vec<_>>());
        assert_eq!(c.total(), (Kind::COUNT * (Kind::COUNT + 1) / 2) as u64);
    }
}
