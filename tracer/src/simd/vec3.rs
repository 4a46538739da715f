//! Three-vectors of lanes (`[V; 3]`, one vector per axis) and the glam
//! operations the lane-wise kernels repeat, each in glam's exact order of
//! operations so a lane computes the bits the single-ray code computes:
//! dot products sum x, then y, then z; `normalize` divides by the square
//! root of that dot product; `cross` subtracts the same two products per
//! axis; [`offset`] is [`crate::math::offset_ray_origin`].
//!
//! (No closures or `array::map` in these helpers: those are separate
//! functions compiled without the kernel's instruction set, and the vector
//! intrinsics inside them would not be inlined.)

use super::lanes::Lanes;
use super::vector::{F32s, Simd};

/// Group `g` of three lane arrays.
#[inline(always)]
pub(crate) fn load3<V: F32s>(s: Simd<V>, a: &[Lanes; 3], g: usize) -> [V; 3] {
    [s.load(&a[0].0, g), s.load(&a[1].0, g), s.load(&a[2].0, g)]
}

/// Store `v` as group `g` of three lane arrays.
#[inline(always)]
pub(crate) fn store3<V: F32s>(v: [V; 3], a: &mut [Lanes; 3], g: usize) {
    v[0].store(&mut a[0].0, g);
    v[1].store(&mut a[1].0, g);
    v[2].store(&mut a[2].0, g);
}

/// glam's `dot`.
#[inline(always)]
pub(crate) fn dot<V: F32s>(a: [V; 3], b: [V; 3]) -> V {
    a[0].mul(b[0]).add(a[1].mul(b[1])).add(a[2].mul(b[2]))
}

/// `a + b`.
#[inline(always)]
pub(crate) fn add3<V: F32s>(a: [V; 3], b: [V; 3]) -> [V; 3] {
    [a[0].add(b[0]), a[1].add(b[1]), a[2].add(b[2])]
}

/// `a - b`.
#[inline(always)]
pub(crate) fn sub3<V: F32s>(a: [V; 3], b: [V; 3]) -> [V; 3] {
    [a[0].sub(b[0]), a[1].sub(b[1]), a[2].sub(b[2])]
}

/// `s * a` (a scalar per lane times a vector).
#[inline(always)]
pub(crate) fn scale3<V: F32s>(s: V, a: [V; 3]) -> [V; 3] {
    [s.mul(a[0]), s.mul(a[1]), s.mul(a[2])]
}

/// `a / s`.
#[inline(always)]
pub(crate) fn div3<V: F32s>(a: [V; 3], s: V) -> [V; 3] {
    [a[0].div(s), a[1].div(s), a[2].div(s)]
}

/// `-a`.
#[inline(always)]
pub(crate) fn neg3<V: F32s>(a: [V; 3]) -> [V; 3] {
    [a[0].neg(), a[1].neg(), a[2].neg()]
}

/// `m ? a : b` for each axis.
#[inline(always)]
pub(crate) fn select3<V: F32s>(m: V::M, a: [V; 3], b: [V; 3]) -> [V; 3] {
    [V::select(m, a[0], b[0]), V::select(m, a[1], b[1]), V::select(m, a[2], b[2])]
}

/// glam's `normalize`.
#[inline(always)]
pub(crate) fn normalize<V: F32s>(v: [V; 3]) -> [V; 3] {
    div3(v, dot(v, v).sqrt())
}

/// glam's `cross`.
#[inline(always)]
pub(crate) fn cross<V: F32s>(l: [V; 3], r: [V; 3]) -> [V; 3] {
    [
        l[1].mul(r[2]).sub(r[1].mul(l[2])),
        l[2].mul(r[0]).sub(r[2].mul(l[0])),
        l[0].mul(r[1]).sub(r[0].mul(l[1])),
    ]
}

/// [`crate::math::offset_ray_origin`]`(p, n)`.
#[inline(always)]
pub(crate) fn offset<V: F32s>(p: [V; 3], n: [V; 3]) -> [V; 3] {
    [offset1(p[0], n[0]), offset1(p[1], n[1]), offset1(p[2], n[2])]
}

#[inline(always)]
fn offset1<V: F32s>(p: V, n: V) -> V {
    let s = Simd::of(p);
    let zero = s.splat(0.0);
    let of = s.splat(256.0).mul(n).to_i32_bits();
    let delta = V::select(p.lt(zero), zero.to_i32_bits().sub_i32(of), of);
    let moved = p.add_i32(delta);
    let near_zero = p.copysign(zero).lt(s.splat(1.0 / 32.0));
    V::select(near_zero, p.add(s.splat(1.0 / 65536.0).mul(n)), moved)
}
