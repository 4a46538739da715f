//! The tools' allocator. Small blocks come from mimalloc: reading a big
//! scene makes hundreds of thousands of small allocations on two threads
//! at once, and glibc's per-thread arenas grow a page range at a time (a
//! system call and a lock on the address space each).
//!
//! Big blocks (a scene's primitives, the geometry's arrays, the BVH's
//! nodes, a raster) are dense: they are written whole, once. On Linux they
//! are mapped straight from the kernel, advised for transparent huge pages
//! and grown in place by `mremap`:
//! - a huge page is one fault where small pages take 512, and on a virtual
//!   machine a fault can cost microseconds;
//! - a growing vector's doubling moves its pages instead of copying them
//!   into fresh ones;
//! - a freed block's pages, already touched, go to the next big block
//!   (one spare range is kept).
//!
//! The rest of the heap is sparse (a thread's pages are partly used), and
//! the kernel zeroes a huge page whole when it is first touched, so mimalloc
//! is built without huge pages (its `no_thp`, which turns them off for the
//! whole process). On kernels that can (Linux 6.18 and later), the first big
//! block turns them back on for advised ranges only; elsewhere big blocks
//! stay in small pages.

use std::alloc::{GlobalAlloc, Layout};

/// The allocator every tool, and the tests, allocate through.
pub struct Heap;

/// Blocks at least this large (in bytes) are mapped by [`Heap`] itself.
pub const BIG: usize = 4 << 20;

#[cfg(target_os = "linux")]
#[allow(unsafe_code)]
mod mapped {
    use std::sync::atomic::{AtomicBool, Ordering};
    use std::sync::Mutex;

    /// A huge page: mappings start on one and are whole numbers of them,
    /// so every part of a block may be one.
    const HUGE: usize = 2 << 20;

    /// `prctl`'s `PR_THP_DISABLE_EXCEPT_ADVISED` (Linux 6.18): huge pages
    /// off except where `madvise` asked for them.
    const EXCEPT_ADVISED: libc::c_ulong = 1 << 1;

    static ADVISED_ONLY: AtomicBool = AtomicBool::new(false);

    /// The spare pages of freed blocks, handed to the next block that
    /// fits: they are touched already, so reusing them costs no faults (a
    /// scene's freed primitives become its BVH).
    pub static SPARE: Spare = Spare::new();

    /// The most spare memory kept.
    const SPARE_MAX: usize = 128 << 20;

    /// One range of spare pages, `(address, length)`: the larger of the
    /// last two freed blocks, at most [`SPARE_MAX`] bytes.
    pub struct Spare(Mutex<(usize, usize)>);

    /// Whole huge pages covering `size` bytes.
    pub fn length(size: usize) -> usize {
        size.div_ceil(HUGE) * HUGE
    }

    /// Huge pages allowed where advised, once per process. (mimalloc,
    /// built with `no_thp`, turned them off for the process at start.)
    fn allow_advised() {
        if !ADVISED_ONLY.swap(true, Ordering::Relaxed) {
            // SAFETY: sets a flag of this process's memory map; no memory is touched.
            // An older kernel refuses the flag and huge pages stay off.
            unsafe { libc::prctl(libc::PR_SET_THP_DISABLE, 1, EXCEPT_ADVISED, 0, 0) };
        }
    }

    /// A fresh zeroed mapping of `len` bytes (a multiple of [`HUGE`])
    /// starting on a huge page, or null.
    unsafe fn reserve(len: usize) -> *mut u8 {
        let prot = libc::PROT_READ | libc::PROT_WRITE;
        let flags = libc::MAP_PRIVATE | libc::MAP_ANONYMOUS;
        let p = libc::mmap(std::ptr::null_mut(), len + HUGE, prot, flags, -1, 0);
        if p == libc::MAP_FAILED {
            return std::ptr::null_mut();
        }
        // The slack before and after the aligned part goes back.
        let head = (HUGE - p as usize % HUGE) % HUGE;
        if head > 0 {
            libc::munmap(p, head);
        }
        let start = p.cast::<u8>().add(head);
        libc::munmap(start.add(len).cast(), HUGE - head);
        start
    }

    /// A fresh zeroed mapping of `len` bytes advised for huge pages, or null.
    pub unsafe fn map(len: usize) -> *mut u8 {
        allow_advised();
        let p = reserve(len);
        if !p.is_null() {
            libc::madvise(p.cast(), len, libc::MADV_HUGEPAGE);
        }
        p
    }

    /// The mapping at `p`, `old` bytes long, made `new` long, or null. It
    /// grows in place where the addresses after it are free; else its
    /// pages move (they are not copied) to a fresh mapping on a huge page
    /// boundary, where huge pages stay whole.
    pub unsafe fn remap(p: *mut u8, old: usize, new: usize) -> *mut u8 {
        if new == old || libc::mremap(p.cast(), old, new, 0) != libc::MAP_FAILED {
            return p;
        }
        moved(p, old, new)
    }

    /// [`remap`] where the mapping cannot grow in place.
    pub unsafe fn moved(p: *mut u8, old: usize, new: usize) -> *mut u8 {
        let to = reserve(new);
        if to.is_null() {
            return to;
        }
        let flags = libc::MREMAP_MAYMOVE | libc::MREMAP_FIXED;
        let q = libc::mremap(p.cast(), old, new, flags, to);
        if q == libc::MAP_FAILED {
            libc::munmap(to.cast(), new);
            return std::ptr::null_mut();
        }
        // (The advice is the mapping's: it moves and grows with it.)
        q.cast()
    }

    /// Give the `len` bytes at `p` back to the kernel.
    pub unsafe fn unmap(p: *mut u8, len: usize) {
        libc::munmap(p.cast(), len);
    }

    impl Spare {
        pub const fn new() -> Spare {
            Spare(Mutex::new((0, 0)))
        }

        /// A block of `len` bytes (not zeroed): the spare pages' first part
        /// where they are enough (the rest stays spare), else the spare range
        /// grown, else a fresh mapping; null when there is no memory.
        pub unsafe fn take(&self, len: usize) -> *mut u8 {
            let mut range = self.0.lock().unwrap_or_else(|poisoned| poisoned.into_inner());
            let (at, have) = *range;
            if have >= len {
                *range = if have > len { (at + len, have - len) } else { (0, 0) };
                return at as *mut u8;
            }
            *range = (0, 0);
            drop(range);
            if have == 0 {
                return map(len);
            }
            let p = remap(at as *mut u8, have, len);
            if p.is_null() {
                unmap(at as *mut u8, have);
            }
            p
        }

        /// Free the block at `p`, `len` bytes long: its pages become the spare
        /// range if they are more than it holds (and not too many), else go
        /// back to the kernel.
        pub unsafe fn free(&self, p: *mut u8, len: usize) {
            if len > SPARE_MAX {
                return unmap(p, len);
            }
            let mut range = self.0.lock().unwrap_or_else(|poisoned| poisoned.into_inner());
            let (at, have) = *range;
            if len <= have {
                drop(range);
                return unmap(p, len);
            }
            *range = (p as usize, len);
            drop(range);
            if have > 0 {
                unmap(at as *mut u8, have);
            }
        }
    }
}

impl Heap {
    /// Whether a block of this layout is mapped by [`Heap`]: decided by the
    /// layout alone, which `dealloc` and `realloc` are given unchanged.
    #[inline(always)]
    fn mapped(size: usize, align: usize) -> bool {
        cfg!(target_os = "linux") && size >= BIG && align <= 4096
    }
}

#[allow(unsafe_code)]
// SAFETY: each block is freed or resized by the side that made it, as
// `Heap::mapped` decides from its layout; mapped blocks are page-aligned,
// which meets any alignment they are chosen for.
unsafe impl GlobalAlloc for Heap {
    #[inline]
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        #[cfg(target_os = "linux")]
        if Heap::mapped(layout.size(), layout.align()) {
            return mapped::SPARE.take(mapped::length(layout.size()));
        }
        mimalloc::MiMalloc.alloc(layout)
    }

    #[inline]
    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        #[cfg(target_os = "linux")]
        if Heap::mapped(layout.size(), layout.align()) {
            // Fresh mappings read as zeros.
            return mapped::map(mapped::length(layout.size()));
        }
        mimalloc::MiMalloc.alloc_zeroed(layout)
    }

    #[inline]
    unsafe fn dealloc(&self, p: *mut u8, layout: Layout) {
        #[cfg(target_os = "linux")]
        if Heap::mapped(layout.size(), layout.align()) {
            return mapped::SPARE.free(p, mapped::length(layout.size()));
        }
        mimalloc::MiMalloc.dealloc(p, layout)
    }

    #[inline]
    unsafe fn realloc(&self, p: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        let align = layout.align();
        match (Heap::mapped(layout.size(), align), Heap::mapped(new_size, align)) {
            (false, false) => mimalloc::MiMalloc.realloc(p, layout, new_size),
            #[cfg(target_os = "linux")]
            (true, true) => mapped::remap(p, mapped::length(layout.size()), mapped::length(new_size)),
            // Across the threshold: a new block, the bytes kept copied.
            _ => {
                let new = Layout::from_size_align_unchecked(new_size, align);
                let q = self.alloc(new);
                if !q.is_null() {
                    std::ptr::copy_nonoverlapping(p, q, layout.size().min(new_size));
                    self.dealloc(p, layout);
                }
                q
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::BIG;

    /// Byte `i` of a block: a pattern no two neighbouring pages share.
    fn pattern(i: usize) -> u8 {
        (i % 251) as u8
    }

    /// A vector grown from small through big (mimalloc to mapped), grown
    /// while mapped (in place or moved) and shrunk back to small keeps its
    /// bytes at every step.
    #[test]
    fn blocks_keep_their_bytes_across_sizes() {
        let mut v: Vec<u8> = Vec::new();
        for step in [1000, BIG - 1, BIG + 1, 3 * BIG + 12345, 7 * BIG] {
            let len = v.len();
            v.extend((len..step).map(pattern));
            assert!(v.iter().enumerate().all(|(i, &b)| b == pattern(i)), "grown to {step}");
        }
        for keep in [5 * BIG, BIG, 100] {
            v.truncate(keep);
            v.shrink_to_fit();
            assert!(
                v.len() == keep && v.iter().enumerate().all(|(i, &b)| b == pattern(i)),
                "shrunk to {keep}"
            );
        }
    }

    /// A freed block's pages go to the next blocks that fit, part by
    /// part; a smaller freed block does not displace a larger spare one; a
    /// block larger than the spare pages grows them, keeping their bytes.
    #[cfg(target_os = "linux")]
    #[test]
    #[allow(unsafe_code)]
    fn freed_pages_are_reused() {
        use super::mapped::{length, Spare};
        let spare = Spare::new();
        let (two, four) = (length(1), length(BIG));
        // SAFETY: each block is written within its length and freed once,
        // with its length.
        unsafe {
            let p = spare.take(four);
            *p.add(four - 1) = 9;
            spare.free(p, four);
            let (a, b) = (spare.take(two), spare.take(two));
            assert_eq!((a, b), (p, p.add(two)), "the spare pages, part by part");
            assert_eq!(*b.add(two - 1), 9, "reused, not zeroed");
            let c = spare.take(two);
            assert!(c != a && c != b, "a fresh mapping once they are used");
            spare.free(b, two);
            spare.free(c, two);
            assert_eq!(spare.take(two), b, "kept over a block no larger");
            spare.free(b, two);
            let grown = spare.take(3 * two);
            assert_eq!(*grown.add(two - 1), 9, "the spare pages grown");
            *grown.add(3 * two - 1) = 1;
            spare.free(a, two);
            spare.free(grown, 3 * two);
            assert_eq!(spare.take(3 * two), grown, "a larger block displaces the spare one");
            super::mapped::unmap(grown, 3 * two);
        }
    }

    /// A mapping that cannot grow in place moves whole to a huge page
    /// boundary, its bytes kept and its tail zeroed.
    #[cfg(target_os = "linux")]
    #[test]
    #[allow(unsafe_code)]
    fn moved_blocks_keep_their_bytes() {
        use super::mapped::{length, map, moved, unmap};
        let (old, new) = (length(BIG + 1), length(3 * BIG));
        // SAFETY: the block is used within its length and unmapped once.
        unsafe {
            let p = map(old);
            assert!(!p.is_null());
            for i in (0..old).step_by(997) {
                *p.add(i) = pattern(i);
            }
            let q = moved(p, old, new);
            assert!(!q.is_null() && (q as usize).is_multiple_of(2 << 20));
            assert!((0..old).step_by(997).all(|i| *q.add(i) == pattern(i)));
            assert!((old..new).step_by(4096).all(|i| *q.add(i) == 0));
            unmap(q, new);
        }
    }

    /// Zeroed big blocks read as zeros, even where a freed block was
    /// written just before; alignments up to a page are met.
    #[test]
    fn zeroed_and_aligned_blocks() {
        for _ in 0..3 {
            let z = vec![0u64; BIG];
            assert!(z.iter().all(|&x| x == 0));
            let mut dirty = vec![1u64; BIG];
            dirty[BIG - 1] = 2;
            drop(dirty);
        }
        #[repr(align(4096))]
        struct Page([u8; 4096]);
        let pages: Vec<Page> = (0..BIG / 4096 + 3).map(|_| Page([3; 4096])).collect();
        assert_eq!(pages.as_ptr() as usize % 4096, 0);
        assert!(pages.iter().all(|p| p.0[4095] == 3));
    }

    /// On Linux, a big block (grown by doubling, so remapped) starts on a
    /// huge page, in a mapping advised for huge pages where the kernel has them.
    #[cfg(target_os = "linux")]
    #[test]
    fn big_blocks_are_advised_for_huge_pages() {
        let mut v: Vec<u32> = Vec::new();
        v.extend(0..(3 * BIG as u32));
        let at = v.as_ptr() as usize;
        assert_eq!(at % (2 << 20), 0, "starts on a huge page");
        if !std::path::Path::new("/sys/kernel/mm/transparent_hugepage").exists() {
            return;
        }
        let smaps = std::fs::read_to_string("/proc/self/smaps").expect("/proc/self/smaps");
        let mut inside = false;
        let mut flags = None;
        for line in smaps.lines() {
            let range = line.split_whitespace().next().and_then(|r| r.split_once('-'));
            if let Some((lo, hi)) = range.filter(|_| !line.starts_with("VmFlags")) {
                if let (Ok(lo), Ok(hi)) = (usize::from_str_radix(lo, 16), usize::from_str_radix(hi, 16)) {
                    inside = lo <= at && at < hi;
                    continue;
                }
            }
            if inside && line.starts_with("VmFlags:") {
                flags = Some(line.to_string());
            }
        }
        let flags = flags.expect("the block's mapping in smaps");
        assert!(flags.split_whitespace().any(|f| f == "hg"), "{flags}");
        assert!(v.iter().enumerate().all(|(i, &x)| x == i as u32));
    }
}
