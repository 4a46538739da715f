//! Large arrays that are written whole, backed by transparent huge pages
//! where the kernel gives them. Each fresh 4 KiB page costs a page fault
//! on its first write (a trap, an allocation, zeroing), and the build's
//! primitive and node arrays run to thousands of pages; a 2 MiB page is
//! one fault. Most kernels give huge pages only to memory that asks
//! (`/sys/kernel/mm/transparent_hugepage/enabled` set to `madvise`), and
//! the tools' allocator does not ask: most of a render's heap is sparse,
//! where a huge page would be zeroed whole for a few bytes. So only arrays
//! filled from end to end ask, through [`vec_with_capacity`].

/// An empty vector with room for `capacity` elements, the whole 2 MiB
/// pages of its buffer advised for huge pages (a hint: the kernel may
/// decline, and off Linux nothing is asked). For arrays about to be
/// filled to `capacity`.
pub(crate) fn vec_with_capacity<T>(capacity: usize) -> Vec<T> {
    let v: Vec<T> = Vec::with_capacity(capacity);
    #[cfg(target_os = "linux")]
    advise(v.as_ptr().addr(), v.capacity() * std::mem::size_of::<T>());
    v
}

/// Size of a huge page (x86-64, and the usual arm64 kernel).
#[cfg_attr(not(target_os = "linux"), allow(dead_code))]
const HUGE: usize = 2 << 20;

/// Ask for huge pages on the huge pages wholly inside `len` bytes from
/// `start` (none, for a small buffer).
#[cfg(target_os = "linux")]
fn advise(start: usize, len: usize) {
    let pages = whole_pages(start, len);
    if !pages.is_empty() {
        // SAFETY: `madvise` with `MADV_HUGEPAGE` only marks the range as
        // wanting huge pages; it changes no contents and no mapping, and
        // the range lies inside a live allocation of ours. Its result is
        // ignored: a refusal leaves ordinary pages, which work the same.
        #[allow(unsafe_code)]
        unsafe {
            libc::madvise(pages.start as *mut libc::c_void, pages.len(), libc::MADV_HUGEPAGE);
        }
    }
}

/// The addresses of the huge pages wholly inside `len` bytes from `start`
/// (empty when there are none).
#[cfg_attr(not(target_os = "linux"), allow(dead_code))]
fn whole_pages(start: usize, len: usize) -> std::ops::Range<usize> {
    let first = start.next_multiple_of(HUGE);
    let end = (start + len) / HUGE * HUGE;
    first..end.max(first)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The advised range is every huge page inside the buffer and nothing
    /// outside it.
    #[test]
    fn only_whole_pages_inside_the_buffer_are_advised() {
        for start in [0, 1, 4096, HUGE - 1, HUGE, HUGE + 64, 7 * HUGE - 4096] {
            for len in [0, 1, HUGE - 1, HUGE, HUGE + 1, 2 * HUGE, 5 * HUGE + 4096] {
                let pages = whole_pages(start, len);
                assert!(pages.start.is_multiple_of(HUGE) && pages.end.is_multiple_of(HUGE), "{start} {len}");
                if pages.is_empty() {
                    // No huge page fits: the first boundary inside leaves
                    // less than a page before the end.
                    assert!(start.next_multiple_of(HUGE) + HUGE > start + len, "{start} {len}");
                } else {
                    assert!(pages.start >= start && pages.end <= start + len, "{start} {len}");
                    assert!(pages.start - start < HUGE && start + len - pages.end < HUGE, "{start} {len}");
                }
            }
        }
    }

    /// The vector is usable as asked for, small or spanning huge pages.
    #[test]
    fn vectors_fill_to_capacity() {
        for n in [0, 1, 1000, 3 << 20] {
            let mut v: Vec<u32> = vec_with_capacity(n);
            assert!(v.capacity() >= n);
            v.extend(0..n as u32);
            assert!(v.iter().copied().eq(0..n as u32));
        }
    }
}
