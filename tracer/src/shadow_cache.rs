//! The shadow cache of Haines and Greenberg ("The Light Buffer", IEEE CG&A
//! 1986; the SPD lists its hits among a tracer's statistics): for each light
//! and each recursion level, the primitive that last blocked a shadow ray is
//! tested first, since neighbouring rays are usually blocked by the same one.
//!
//! The cache only changes the order of tests, never the answer (a shadow
//! ray's result is whether *anything* blocks it), so images are the same with
//! it or without. It belongs to one render thread and is cleared at the start
//! of every tile, so the counts it produces do not depend on which thread
//! rendered which tile.

/// Per-thread cache: one slot per (recursion level, light).
#[derive(Debug, Clone, Default)]
pub struct ShadowCache {
    slots: Vec<u32>,
    lights: usize,
}

const EMPTY: u32 = u32::MAX;

impl ShadowCache {
    /// A cache for `lights` lights and paths up to `max_depth` rays long;
    /// `enabled` false makes an empty cache that never remembers.
    pub fn new(lights: usize, max_depth: u32, enabled: bool) -> ShadowCache {
        let n = if enabled { lights * max_depth as usize } else { 0 };
        ShadowCache { slots: vec![EMPTY; n], lights }
    }

    #[inline]
    fn slot(&self, light: usize, depth: u32) -> usize {
        (depth as usize - 1) * self.lights + light
    }

    /// The last occluder of light `light`'s shadow rays at `depth` (1: from
    /// points seen by eye rays).
    #[inline]
    pub fn get(&self, light: usize, depth: u32) -> Option<u32> {
        self.slots.get(self.slot(light, depth)).copied().filter(|&id| id != EMPTY)
    }

    /// Remember `id` as the occluder of light `light` at `depth`.
    #[inline]
    pub fn set(&mut self, light: usize, depth: u32, id: u32) {
        let s = self.slot(light, depth);
        if let Some(slot) = self.slots.get_mut(s) {
            *slot = id;
        }
    }

    /// Forget everything (at the start of a tile).
    pub fn clear(&mut self) {
        self.slots.fill(EMPTY);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn remembers_per_light_and_depth_and_clears() {
        let mut c = ShadowCache::new(2, 3, true);
        assert_eq!(c.get(1, 2), None);
        c.set(1, 2, 7);
        c.set(0, 2, 9);
        assert_eq!((c.get(1, 2), c.get(0, 2), c.get(1, 1)), (Some(7), Some(9), None));
        c.clear();
        assert_eq!(c.get(1, 2), None);
        let mut off = ShadowCache::new(2, 3, false);
        off.set(1, 2, 7);
        assert_eq!(off.get(1, 2), None);
    }
}
