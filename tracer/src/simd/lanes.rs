//! A packet's lanes as plain data, the bottom layer every lane-wise kernel
//! and the vector types share: how many lanes a packet has, one `f32` per
//! lane aligned for vector loads, a bit per lane, and the helpers that move
//! one lane of a three-vector in and out.

use glam::Vec3A;

/// Rays in a packet: 16, one AVX-512 register of f32 (two AVX2 ones).
pub const LANES: usize = 16;

/// One bit per lane (bit `i`: lane `i`).
pub(crate) type Mask = u32;

/// Per-lane f32 values, aligned for vector loads.
#[derive(Debug, Clone, Copy, PartialEq)]
#[repr(C, align(64))]
pub(crate) struct Lanes(pub [f32; LANES]);

impl Lanes {
    /// Every lane 0.
    pub const ZERO: Lanes = Lanes([0.0; LANES]);
}

impl Default for Lanes {
    fn default() -> Self {
        Lanes::ZERO
    }
}

/// Lane `i` of three per-axis lane arrays, as a vector.
#[inline(always)]
pub(crate) fn lane(v: &[Lanes; 3], i: usize) -> Vec3A {
    Vec3A::new(v[0].0[i], v[1].0[i], v[2].0[i])
}

/// Set lane `i` of three per-axis lane arrays to `x`.
#[inline(always)]
pub(crate) fn set_lane(v: &mut [Lanes; 3], i: usize, x: Vec3A) {
    for a in 0..3 {
        v[a].0[i] = x[a];
    }
}

/// Call `f` with each lane of `mask`, lowest first.
#[inline(always)]
pub(crate) fn for_lanes(mut mask: Mask, mut f: impl FnMut(usize)) {
    while mask != 0 {
        let i = mask.trailing_zeros() as usize;
        mask &= mask - 1;
        f(i);
    }
}

/// The mask of lanes `0..n` (`n` at most [`LANES`]).
#[inline(always)]
pub(crate) fn first_lanes(n: usize) -> Mask {
    if n >= LANES {
        Mask::MAX >> (Mask::BITS as usize - LANES)
    } else {
        (1 << n) - 1
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn first_lanes_are_the_lowest() {
        assert_eq!(first_lanes(0), 0);
        assert_eq!(first_lanes(3), 0b111);
        assert_eq!(first_lanes(LANES), (1 << LANES) - 1);
        assert_eq!(first_lanes(LANES + 5), first_lanes(LANES));
    }

    #[test]
    fn lanes_of_a_mask_lowest_first() {
        let mut seen = vec![];
        for_lanes(0b1010_0001, |i| seen.push(i));
        assert_eq!(seen, [0, 5, 7]);
        let mut v = [Lanes::ZERO; 3];
        set_lane(&mut v, 4, Vec3A::new(1.0, 2.0, 3.0));
        assert_eq!((lane(&v, 4), lane(&v, 3)), (Vec3A::new(1.0, 2.0, 3.0), Vec3A::ZERO));
    }
}
