//! Where the BVH's parts wait while they are built on all cores: an
//! array they are copied into as they are finished, in any order, and
//! scratch vectors to build them in.
//!
//! A scratch vector keeps its pages and stays in cache from one part to
//! the next, where a vector per part would take fresh pages (a fault each:
//! the heap's small blocks have no huge pages). The arena is one block; for
//! a large scene a big one, which the tools' allocator can serve from the
//! pages of big blocks freed before it (the file's primitives). Everything
//! goes with the arena once the parts are gathered.

use std::ops::Range;
use std::sync::{Mutex, MutexGuard};

/// Items laid end to end as their parts are finished.
pub(super) struct Arena<T> {
    items: Mutex<Vec<T>>,
    /// Scratch vectors not lent out: at most one per thread at work.
    scratch: Mutex<Vec<Vec<T>>>,
}

impl<T: Copy> Arena<T> {
    /// An arena with room for `items` items (it grows past them).
    pub fn new(items: usize) -> Arena<T> {
        Arena { items: Mutex::new(Vec::with_capacity(items)), scratch: Mutex::new(Vec::new()) }
    }

    /// `part` copied to the end: its place.
    pub fn push(&self, part: &[T]) -> Range<usize> {
        let mut items = lock(&self.items);
        let start = items.len();
        items.extend_from_slice(part);
        start..items.len()
    }

    /// The part `build` writes to an empty scratch vector, copied in: what
    /// `build` returns, and the part's place.
    pub fn build<R>(&self, build: impl FnOnce(&mut Vec<T>) -> R) -> (R, Range<usize>) {
        let mut scratch = lock(&self.scratch).pop().unwrap_or_default();
        scratch.clear();
        let made = build(&mut scratch);
        let place = self.push(&scratch);
        lock(&self.scratch).push(scratch);
        (made, place)
    }

    /// The items.
    pub fn into_items(self) -> Vec<T> {
        self.items.into_inner().unwrap_or_else(|poisoned| poisoned.into_inner())
    }
}

/// `m` locked, whether or not a thread panicked holding it.
fn lock<T>(m: &Mutex<T>) -> MutexGuard<'_, T> {
    m.lock().unwrap_or_else(|poisoned| poisoned.into_inner())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Parts pushed or built land end to end at the places returned, and
    /// a scratch vector comes back empty for the next part.
    #[test]
    fn parts_land_where_their_places_say() {
        let arena = Arena::new(2);
        let a = arena.push(&[1, 2, 3]);
        let (n, b) = arena.build(|v| {
            assert!(v.is_empty());
            v.extend([7, 8]);
            v.len()
        });
        let (_, c) = arena.build(|v: &mut Vec<i32>| {
            assert!(v.is_empty(), "a lent scratch vector starts empty");
            v.push(9);
        });
        assert_eq!((a, b, c, n), (0..3, 3..5, 5..6, 2));
        assert_eq!(arena.into_items(), [1, 2, 3, 7, 8, 9]);
    }
}
