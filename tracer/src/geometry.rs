//! The primitive store: spheres, triangles, cones and infinite planes in flat
//! typed arrays, addressed by one dense `u32` id space (spheres first, then
//! triangles, cones, and planes last), so accelerators and mailboxes can index
//! any primitive. Planes have no bounds: accelerators are built over the
//! bounded ids `0..bounded_len()` and the planes are tested beside them (see
//! [`crate::accel::Intersector`]).
//!
//! Each shape has a cheap hit test returning distance (and barycentrics) and a
//! separate [`Geometry::surface`] that builds normals only for the final hit.

use crate::aabb::Aabb;
use crate::math::{max_of, normal_or_facing, triangle_t_error, RayQuery};
use glam::{Vec3A, Vec4};
use strum::{EnumCount, IntoStaticStr, VariantArray};

/// Which side of a surface may be hit.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Cull {
    /// Both sides (two-sided shading, transmissive objects).
    None,
    /// Only the front (outside of a sphere or cone, counter-clockwise side of
    /// a polygon): the spec's one-sided rule.
    Back,
    /// Only the back: negative radii, "inside visible only".
    Front,
}

/// A sphere: the centre in x, y, z and the (positive) radius in w of one
/// 16-byte vector, four spheres to a cache line. The centre reads back as
/// the same register (a `Vec3A`'s fourth lane is unspecified and ignored).
#[derive(Debug, Clone, Copy)]
pub(crate) struct Sphere(Vec4);

const _: () = assert!(std::mem::size_of::<Sphere>() == 16);

impl Sphere {
    /// The sphere at `center` of `radius` (positive).
    pub fn new(center: Vec3A, radius: f32) -> Sphere {
        Sphere(center.extend(radius))
    }

    /// Centre.
    #[inline(always)]
    pub fn center(&self) -> Vec3A {
        Vec3A::from_vec4(self.0)
    }

    /// Radius (positive).
    #[inline(always)]
    pub fn radius(&self) -> f32 {
        self.0.w
    }
}

/// A triangle (polygons and patches are triangulated at load).
#[derive(Debug, Clone, Copy)]
pub(crate) struct Triangle {
    /// Vertices, counter-clockwise seen from the front.
    pub v: [Vec3A; 3],
}

impl Triangle {
    /// The triangle's box.
    #[inline]
    pub fn bounds(&self) -> Aabb {
        let [a, b, c] = self.v;
        Aabb::new(a.min(b).min(c), a.max(b).max(c))
    }
}

/// An open cone or cylinder.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Cone {
    /// Centre of the base disc.
    pub base: Vec3A,
    /// Unit axis from base to apex.
    pub axis: Vec3A,
    /// Distance from base to apex.
    pub height: f32,
    /// Radius at the base.
    pub r0: f32,
    /// Radius change per unit of height.
    pub slope: f32,
}

/// An infinite plane (the course files' `pl`): the points `p` with
/// `n · p = n · point`.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Plane {
    /// A point on the plane.
    pub point: Vec3A,
    /// Unit normal; its side is the front.
    pub n: Vec3A,
}

/// The kinds of primitive, in the order of the id space. Counters are
/// arrays of `Kind::COUNT` indexed by kind (see [`crate::stats::PerKind`]),
/// so a new kind is counted and printed without touching the statistics
/// code. Unbounded kinds come last (see [`Geometry::bounded_len`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, EnumCount, VariantArray, IntoStaticStr)]
#[strum(serialize_all = "kebab-case")]
pub enum Kind {
    /// A sphere.
    Sphere,
    /// A triangle.
    Triangle,
    /// A cone or cylinder.
    Cone,
    /// An infinite plane.
    Plane,
}

/// The first kind without bounds: it and the kinds after it stay out of
/// every accelerator.
const FIRST_UNBOUNDED: Kind = Kind::Plane;
const _: () = assert!(FIRST_UNBOUNDED as usize == Kind::COUNT - 1, "unbounded kinds come last");

/// Per-primitive data the hit tests do not need: material, culling,
/// normals, where in the file it came from.
#[derive(Debug, Clone, Copy)]
pub(crate) struct PrimInfo {
    /// Index into the scene's materials.
    pub material: u32,
    /// For triangles from a `pp` patch: index into
    /// [`Geometry::patch_normals`]; [`PrimInfo::NO_PATCH`] for the rest.
    patch: u32,
    /// The line of the file the primitive came from (0: none), for
    /// messages.
    pub line: u32,
    /// Which side may be hit.
    pub cull: Cull,
}

const _: () = assert!(std::mem::size_of::<PrimInfo>() == 16, "PrimInfo fits 16 bytes");

impl PrimInfo {
    const NO_PATCH: u32 = u32::MAX;

    /// The record of a primitive with `material` and `cull`, from `line`,
    /// with patch normals `patch`.
    pub fn new(material: u32, cull: Cull, patch: Option<u32>, line: u32) -> PrimInfo {
        PrimInfo { material, patch: patch.unwrap_or(Self::NO_PATCH), line, cull }
    }

    /// For triangles from a `pp` patch: index into [`Geometry::patch_normals`].
    #[inline]
    pub fn patch(&self) -> Option<u32> {
        (self.patch != Self::NO_PATCH).then_some(self.patch)
    }
}

/// A hit: enough to find the surface later, nothing more.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Hit {
    /// Distance along the ray.
    pub t: f32,
    /// Primitive id.
    pub prim: u32,
    /// Barycentric coordinates of vertices 1 and 2 (triangles only).
    pub u: f32,
    /// See `u`.
    pub v: f32,
}

impl Hit {
    /// Is this hit to be preferred over `best`? Nearer wins; at equal
    /// distance the lower id wins, so every accelerator picks the same one.
    #[inline]
    pub fn beats(&self, best: &Option<Hit>) -> bool {
        match best {
            None => true,
            Some(b) => self.t < b.t || (self.t == b.t && self.prim < b.prim),
        }
    }
}

/// The geometric record of a hit, built once per shaded point.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Surface {
    /// The point.
    pub p: Vec3A,
    /// Geometric normal, as the primitive defines its front.
    pub ng: Vec3A,
    /// Shading normal (interpolated for patches), on the same side as `ng`.
    pub ns: Vec3A,
}

/// All primitives of a scene. Built by filling the arrays (and `info` in
/// id order), then [`Geometry::assign_ids`].
#[derive(Debug, Default, Clone)]
pub(crate) struct Geometry {
    /// Spheres: ids `0..spheres.len()`.
    pub spheres: Vec<Sphere>,
    /// Triangles: the next ids.
    pub triangles: Vec<Triangle>,
    /// Cones: the next ids.
    pub cones: Vec<Cone>,
    /// Infinite planes: the last ids, outside every accelerator.
    pub planes: Vec<Plane>,
    /// Per-primitive data, indexed by id.
    pub info: Vec<PrimInfo>,
    /// Vertex normals of patch triangles.
    pub patch_normals: Vec<[Vec3A; 3]>,
    /// Whether any primitive culls a side; when none does (the default,
    /// two-sided shading) the hit tests skip looking the rule up.
    pub any_cull: bool,
    /// The first id of each kind, in [`Kind`] order, then the count of all.
    start: [u32; Kind::COUNT + 1],
}

impl Geometry {
    /// How many primitives of kind `k` there are.
    pub fn count(&self, k: Kind) -> usize {
        match k {
            Kind::Sphere => self.spheres.len(),
            Kind::Triangle => self.triangles.len(),
            Kind::Cone => self.cones.len(),
            Kind::Plane => self.planes.len(),
        }
    }

    /// Number the primitives: each kind's ids follow the previous kind's,
    /// in [`Kind`] order. Called once the arrays are filled.
    pub fn assign_ids(&mut self) {
        for (k, &kind) in Kind::VARIANTS.iter().enumerate() {
            self.start[k + 1] = self.start[k] + self.count(kind) as u32;
        }
        debug_assert_eq!(self.start[Kind::COUNT] as usize, self.info.len());
    }

    /// Number of primitives.
    #[inline]
    pub fn len(&self) -> usize {
        self.info.len()
    }

    /// Number of bounded primitives (all but the planes): the ids
    /// `0..bounded_len()` are what accelerators are built over.
    #[inline]
    pub fn bounded_len(&self) -> usize {
        self.start[FIRST_UNBOUNDED as usize] as usize
    }

    /// The first id of kind `k`.
    pub fn first_id(&self, k: Kind) -> u32 {
        self.start[k as usize]
    }

    /// The ids of the infinite planes.
    #[inline]
    pub fn plane_ids(&self) -> std::ops::Range<u32> {
        self.bounded_len() as u32..self.len() as u32
    }

    /// The kind of primitive `id`, and its index in that kind's array.
    #[inline]
    pub fn locate(&self, id: u32) -> (Kind, usize) {
        // One comparison per boundary of the id space, spheres (the
        // commonest) first: a plain chain, which the primitive tests that
        // match on its kind fold into one dispatch.
        const _: () = assert!(Kind::COUNT == 4, "a new kind needs its boundary here");
        let s = &self.start;
        let kind = if id < s[1] {
            Kind::Sphere
        } else if id < s[2] {
            Kind::Triangle
        } else if id < s[3] {
            Kind::Cone
        } else {
            Kind::Plane
        };
        (kind, (id - s[kind as usize]) as usize)
    }

    /// Bounds of primitive `id`; infinite for a plane (accelerators never
    /// ask for those).
    pub fn bounds(&self, id: u32) -> Aabb {
        match self.locate(id) {
            (Kind::Sphere, i) => {
                let s = self.spheres[i];
                Aabb::new(s.center() - s.radius(), s.center() + s.radius())
            }
            (Kind::Triangle, i) => self.triangles[i].bounds(),
            (Kind::Cone, i) => {
                let c = self.cones[i];
                let apex = c.base + c.axis * c.height;
                let r1 = c.r0 + c.slope * c.height;
                // Per axis, a disc of radius r with unit normal a spans
                // r * sqrt(1 - a_i^2) around its centre.
                let e = (Vec3A::ONE - c.axis * c.axis).max(Vec3A::ZERO);
                let e = Vec3A::new(e.x.sqrt(), e.y.sqrt(), e.z.sqrt());
                let (e0, e1) = (e * c.r0.abs(), e * r1.abs());
                Aabb::new((c.base - e0).min(apex - e1), (c.base + e0).max(apex + e1))
            }
            (Kind::Plane, _) => Aabb::new(Vec3A::splat(f32::NEG_INFINITY), Vec3A::splat(f32::INFINITY)),
        }
    }

    /// Test primitive `id` against the ray within `(q.t_min, t_max)`.
    #[inline]
    pub fn intersect(&self, id: u32, q: &RayQuery, t_max: f32) -> Option<Hit> {
        let cull = if self.any_cull { self.info[id as usize].cull } else { Cull::None };
        let (t, u, v) = match self.locate(id) {
            (Kind::Sphere, i) => (intersect_sphere(&self.spheres[i], q, t_max, cull)?, 0.0, 0.0),
            (Kind::Triangle, i) => intersect_triangle(&self.triangles[i], q, t_max, cull)?,
            (Kind::Cone, i) => (intersect_cone(&self.cones[i], q, t_max, cull)?, 0.0, 0.0),
            (Kind::Plane, i) => (intersect_plane(&self.planes[i], q, t_max, cull)?, 0.0, 0.0),
        };
        Some(Hit { t, prim: id, u, v })
    }

    /// [`Geometry::intersect`] with the sphere test inline, for the
    /// single-ray BVH walk: spheres are the commonest primitive and the
    /// cheapest test, which a call costs the most.
    #[inline(always)]
    pub fn intersect_spheres_inline(&self, id: u32, q: &RayQuery, t_max: f32) -> Option<Hit> {
        // Sphere ids are those below the first boundary `Geometry::locate`
        // compares with; the comparison alone keeps the test's chain short.
        if id < self.start[1] && !self.any_cull {
            let t = intersect_sphere(&self.spheres[id as usize], q, t_max, Cull::None)?;
            return Some(Hit { t, prim: id, u: 0.0, v: 0.0 });
        }
        self.intersect(id, q, t_max)
    }

    /// Normals and point of a hit.
    pub fn surface(&self, hit: &Hit, q: &RayQuery) -> Surface {
        let p = q.ray.at(hit.t);
        match self.locate(hit.prim) {
            (Kind::Sphere, i) => {
                let s = self.spheres[i];
                let n = normal_or_facing(((p - s.center()) / s.radius()).normalize(), q.ray.d);
                Surface { p, ng: n, ns: n }
            }
            (Kind::Triangle, i) => {
                let [a, b, c] = self.triangles[i].v;
                let ng = normal_or_facing((b - a).cross(c - a).normalize(), q.ray.d);
                // The point from barycentrics is more exact than o + t d.
                let w = 1.0 - hit.u - hit.v;
                let p = a * w + b * hit.u + c * hit.v;
                let ns = match self.info[hit.prim as usize].patch() {
                    Some(k) => {
                        let [n0, n1, n2] = self.patch_normals[k as usize];
                        let n = (n0 * w + n1 * hit.u + n2 * hit.v).normalize_or_zero();
                        if n == Vec3A::ZERO {
                            ng
                        } else if n.dot(ng) < 0.0 {
                            -n
                        } else {
                            n
                        }
                    }
                    None => ng,
                };
                Surface { p, ng, ns }
            }
            (Kind::Cone, i) => {
                let c = self.cones[i];
                let rel = p - c.base;
                let radial = (rel - c.axis * rel.dot(c.axis)).normalize_or_zero();
                // Gradient of |p_perp| - (r0 + slope * h).
                let n = normal_or_facing((radial - c.axis * c.slope).normalize(), q.ray.d);
                Surface { p, ng: n, ns: n }
            }
            (Kind::Plane, i) => {
                let pl = self.planes[i];
                // Far along a grazing ray o + t d strays off the plane;
                // projecting back keeps shadow-ray origins on the right side.
                let p = p - pl.n * pl.n.dot(p - pl.point);
                Surface { p, ng: pl.n, ns: pl.n }
            }
        }
    }
}

/// Ray-sphere test in the numerically careful form of Haines et al.,
/// "Precision Improvements for Ray/Sphere Intersection" (Ray Tracing Gems,
/// 2019): the discriminant from the perpendicular distance, the near root
/// from the stable quadratic formula.
#[inline]
pub(crate) fn intersect_sphere(s: &Sphere, q: &RayQuery, t_max: f32, cull: Cull) -> Option<f32> {
    let f = q.ray.o - s.center();
    let b = -f.dot(q.ray.d);
    let l = f + b * q.ray.d;
    let r2 = s.radius() * s.radius();
    let disc = r2 - l.length_squared();
    if disc < 0.0 {
        return None;
    }
    let c = f.length_squared() - r2;
    let qq = b + disc.sqrt().copysign(b);
    let (mut t0, mut t1) = if qq == 0.0 { (0.0, 0.0) } else { (c / qq, qq) };
    if t0 > t1 {
        std::mem::swap(&mut t0, &mut t1);
    }
    // The near root enters the sphere (outside, front); the far one leaves.
    let ok = |t: f32| t > q.t_min && t < t_max;
    match cull {
        Cull::None => {
            if ok(t0) {
                Some(t0)
            } else if ok(t1) {
                Some(t1)
            } else {
                None
            }
        }
        Cull::Back => ok(t0).then_some(t0),
        Cull::Front => ok(t1).then_some(t1),
    }
}

/// Ray against an infinite plane: `t = n · (point − o) / n · d`.
#[inline]
pub(crate) fn intersect_plane(pl: &Plane, q: &RayQuery, t_max: f32, cull: Cull) -> Option<f32> {
    let denom = pl.n.dot(q.ray.d);
    // denom < 0: the ray meets the front side.
    let culled = match cull {
        Cull::None => false,
        Cull::Back => denom >= 0.0,
        Cull::Front => denom <= 0.0,
    };
    if denom == 0.0 || culled {
        return None;
    }
    let t = pl.n.dot(pl.point - q.ray.o) / denom;
    (t > q.t_min && t < t_max).then_some(t)
}

/// Watertight ray-triangle test (Woop, Benthin and Wald, JCGT 2013): edge
/// functions in a sheared space where the ray is the z axis, so rays through
/// a shared edge hit exactly one of the two triangles and never leak.
/// Returns `(t, u, v)` with `u`, `v` the barycentrics of vertices 1 and 2.
#[inline]
pub(crate) fn intersect_triangle(
    tri: &Triangle,
    q: &RayQuery,
    t_max: f32,
    cull: Cull,
) -> Option<(f32, f32, f32)> {
    // One copy of the test per axis permutation (the six that
    // `RayQuery::new` makes), so that a vertex's coordinates are picked by
    // constant lanes: picked by a variable index, they went through memory,
    // nine times a test.
    let test = |k: [usize; 3]| intersect_triangle_permuted(tri, q, t_max, cull, k);
    match q.k {
        [1, 2, 0] => test([1, 2, 0]),
        [2, 1, 0] => test([2, 1, 0]),
        [2, 0, 1] => test([2, 0, 1]),
        [0, 2, 1] => test([0, 2, 1]),
        [0, 1, 2] => test([0, 1, 2]),
        [1, 0, 2] => test([1, 0, 2]),
        k => test(k),
    }
}

/// [`intersect_triangle`] with the axis permutation `k` (`q.k`, as a
/// constant where the caller can make it one).
#[inline(always)]
fn intersect_triangle_permuted(
    tri: &Triangle,
    q: &RayQuery,
    t_max: f32,
    cull: Cull,
    [kx, ky, kz]: [usize; 3],
) -> Option<(f32, f32, f32)> {
    let s = q.shear;
    let a = tri.v[0] - q.ray.o;
    let b = tri.v[1] - q.ray.o;
    let c = tri.v[2] - q.ray.o;
    let (ax, ay) = (a[kx] - s.x * a[kz], a[ky] - s.y * a[kz]);
    let (bx, by) = (b[kx] - s.x * b[kz], b[ky] - s.y * b[kz]);
    let (cx, cy) = (c[kx] - s.x * c[kz], c[ky] - s.y * c[kz]);
    let mut u = cx * by - cy * bx;
    let mut v = ax * cy - ay * cx;
    let mut w = bx * ay - by * ax;
    if u == 0.0 || v == 0.0 || w == 0.0 {
        // Exactly on an edge in single precision: decide in double.
        u = (cx as f64 * by as f64 - cy as f64 * bx as f64) as f32;
        v = (ax as f64 * cy as f64 - ay as f64 * cx as f64) as f32;
        w = (bx as f64 * ay as f64 - by as f64 * ax as f64) as f32;
    }
    if (u < 0.0 || v < 0.0 || w < 0.0) && (u > 0.0 || v > 0.0 || w > 0.0) {
        return None;
    }
    let det = u + v + w;
    if det == 0.0 {
        return None;
    }
    // det > 0 means the ray sees the counter-clockwise (front) side.
    match cull {
        Cull::Back if det < 0.0 => return None,
        Cull::Front if det > 0.0 => return None,
        _ => {}
    }
    let (az, bz, cz) = (s.z * a[kz], s.z * b[kz], s.z * c[kz]);
    let t_scaled = u * az + v * bz + w * cz;
    let t = t_scaled / det;
    if !(t > q.t_min && t < t_max) {
        return None;
    }
    let inv = 1.0 / det;
    let max = |p: f32, q: f32, r: f32| max_of(max_of(p.abs(), q.abs()), r.abs());
    let (max_x, max_y, max_z) = (max(ax, bx, cx), max(ay, by, cy), max(az, bz, cz));
    if t <= triangle_t_error(max_x, max_y, max_z, max(u, v, w), inv.abs()) {
        return None;
    }
    Some((t, v * inv, w * inv))
}

/// Ray against the open surface |p⊥| = r0 + slope·h, 0 ≤ h ≤ height, in
/// world space with the axis frame expressed by dot products.
///
/// Computed in f64: the quadratic loses too many digits in f32 for rays
/// leaving the surface itself (shadow rays would see speckles of self
/// shadowing), and cones are few, so the cost does not matter.
#[inline]
pub(crate) fn intersect_cone(c: &Cone, q: &RayQuery, t_max: f32, cull: Cull) -> Option<f32> {
    let d64 = |v: Vec3A| glam::DVec3::new(v.x as f64, v.y as f64, v.z as f64);
    let axis = d64(c.axis);
    let (o, d) = (d64(q.ray.o) - d64(c.base), d64(q.ray.d));
    let (slope, r0, height) = (c.slope as f64, c.r0 as f64, c.height as f64);
    let (oa, da) = (o.dot(axis), d.dot(axis));
    let (op, dp) = (o - axis * oa, d - axis * da);
    let r = r0 + slope * oa;
    let a = dp.length_squared() - slope * slope * da * da;
    let b = 2.0 * (op.dot(dp) - slope * r * da);
    let cc = op.length_squared() - r * r;
    let (t0, t1) = if a.abs() < 1e-14 {
        if b == 0.0 {
            return None;
        }
        let t = -cc / b;
        (t, t)
    } else {
        let disc = b * b - 4.0 * a * cc;
        if disc < 0.0 {
            return None;
        }
        let qq = -0.5 * (b + disc.sqrt().copysign(b));
        let (x, y) = (qq / a, if qq != 0.0 { cc / qq } else { qq / a });
        (x.min(y), x.max(y))
    };
    for t in [t0, t1] {
        let tf = t as f32;
        if !(tf > q.t_min && tf < t_max) {
            continue;
        }
        let h = oa + t * da;
        if h < 0.0 || h > height || r0 + slope * h < 0.0 {
            continue; // beyond the ends, or on the mirrored nappe
        }
        if cull != Cull::None {
            let p = o + d * t;
            let radial = p - axis * h;
            let front = d.dot(radial - axis * (slope * radial.length())) < 0.0;
            if front == (cull == Cull::Back) {
                return Some(tf);
            }
            continue;
        }
        return Some(tf);
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::Ray;

    fn q(o: [f32; 3], d: [f32; 3]) -> RayQuery {
        RayQuery::new(Ray::new(Vec3A::from(o), Vec3A::from(d)), 0.0)
    }

    const UNIT: Sphere = Sphere(Vec4::new(0.0, 0.0, 0.0, 1.0));

    #[test]
    fn sphere_hit_miss_grazing_inside() {
        let t = intersect_sphere(&UNIT, &q([0.0, 0.0, -5.0], [0.0, 0.0, 1.0]), 100.0, Cull::None).unwrap();
        assert!((t - 4.0).abs() < 1e-5);
        assert!(intersect_sphere(&UNIT, &q([0.0, 1.5, -5.0], [0.0, 0.0, 1.0]), 100.0, Cull::None).is_none());
        let graze = intersect_sphere(&UNIT, &q([0.0, 0.999, -5.0], [0.0, 0.0, 1.0]), 100.0, Cull::None);
        assert!(graze.is_some());
        let inside =
            intersect_sphere(&UNIT, &q([0.0, 0.0, 0.0], [0.0, 0.0, 1.0]), 100.0, Cull::None).unwrap();
        assert!((inside - 1.0).abs() < 1e-6);
        assert!(intersect_sphere(&UNIT, &q([0.0, 0.0, -5.0], [0.0, 0.0, 1.0]), 3.0, Cull::None).is_none());
    }

    #[test]
    fn sphere_far_away_is_still_precise() {
        let s = Sphere::new(Vec3A::new(0.0, 0.0, 10000.0), 0.01);
        let t = intersect_sphere(&s, &q([0.0, 0.0, 0.0], [0.0, 0.0, 1.0]), 1e9, Cull::None).unwrap();
        assert!((t - 9999.99).abs() < 2e-3, "{t}");
    }

    #[test]
    fn sphere_culling_and_negative_radius() {
        let from_inside = q([0.0, 0.0, 0.0], [0.0, 0.0, 1.0]);
        assert!(intersect_sphere(&UNIT, &from_inside, 100.0, Cull::Back).is_none());
        assert!(intersect_sphere(&UNIT, &from_inside, 100.0, Cull::Front).is_some());
        let outside = q([0.0, 0.0, -5.0], [0.0, 0.0, 1.0]);
        // Inside visible only: the ray passes the front and hits the back wall.
        let t = intersect_sphere(&UNIT, &outside, 100.0, Cull::Front).unwrap();
        assert!((t - 6.0).abs() < 1e-5);
    }

    fn tri() -> Triangle {
        Triangle { v: [Vec3A::new(0.0, 0.0, 0.0), Vec3A::new(1.0, 0.0, 0.0), Vec3A::new(0.0, 1.0, 0.0)] }
    }

    #[test]
    fn triangle_hit_barycentrics_and_sides() {
        let front = q([0.25, 0.5, 1.0], [0.0, 0.0, -1.0]);
        let (t, u, v) = intersect_triangle(&tri(), &front, 10.0, Cull::None).unwrap();
        assert!((t - 1.0).abs() < 1e-6 && (u - 0.25).abs() < 1e-6 && (v - 0.5).abs() < 1e-6);
        assert!(intersect_triangle(&tri(), &front, 10.0, Cull::Back).is_some());
        assert!(intersect_triangle(&tri(), &front, 10.0, Cull::Front).is_none());
        let back = q([0.25, 0.25, -1.0], [0.0, 0.0, 1.0]);
        assert!(intersect_triangle(&tri(), &back, 10.0, Cull::Back).is_none());
        assert!(intersect_triangle(&tri(), &back, 10.0, Cull::None).is_some());
        assert!(intersect_triangle(&tri(), &q([0.8, 0.8, 1.0], [0.0, 0.0, -1.0]), 10.0, Cull::None).is_none());
    }

    #[test]
    fn shared_edges_do_not_leak() {
        // A quad split along its diagonal; rays aimed exactly at the diagonal
        // (and at random points) must hit at least one of the two halves.
        let a =
            Triangle { v: [Vec3A::new(0.0, 0.0, 0.0), Vec3A::new(1.0, 0.0, 0.0), Vec3A::new(1.0, 1.0, 0.0)] };
        let b =
            Triangle { v: [Vec3A::new(0.0, 0.0, 0.0), Vec3A::new(1.0, 1.0, 0.0), Vec3A::new(0.0, 1.0, 0.0)] };
        let mut state = 12345u32;
        let mut rnd = || {
            state ^= state << 13;
            state ^= state >> 17;
            state ^= state << 5;
            state as f32 / u32::MAX as f32
        };
        for i in 0..20000 {
            let s = if i % 2 == 0 { rnd() } else { 0.0 };
            let x = 0.01 + 0.98 * rnd();
            let target = Vec3A::new(x, if i % 2 == 0 { s } else { x }, 0.0);
            let o = Vec3A::new(rnd() * 4.0 - 2.0, rnd() * 4.0 - 2.0, 1.0 + rnd() * 3.0);
            let rq = RayQuery::new(Ray::new(o, target - o), 0.0);
            let hit = intersect_triangle(&a, &rq, 100.0, Cull::None).is_some()
                || intersect_triangle(&b, &rq, 100.0, Cull::None).is_some();
            assert!(hit, "ray {i} from {o} to {target} leaked");
        }
    }

    /// The test's copies for the six axis permutations each give what the
    /// test with the permutation read at run time gives, bit for bit,
    /// for rays along every major axis, both ways, hitting and missing.
    #[test]
    fn each_permutation_copy_is_the_test_with_that_permutation() {
        let mut rnd = crate::testing::uniform(0x5eed_7a11_9e37_79b9);
        let mut seen = std::collections::BTreeSet::new();
        let (mut hits, mut edge) = (0, 0);
        for i in 0..6000 {
            let mut v = || Vec3A::new(rnd() * 2.0 - 1.0, rnd() * 2.0 - 1.0, rnd() * 2.0 - 1.0);
            let t = Triangle { v: [v(), v(), v()] };
            let o = v() * 4.0;
            // Aimed at a vertex now and then (the double-precision path),
            // else near the triangle.
            let target = if i % 7 == 0 { t.v[i % 3] } else { (t.v[0] + t.v[1] + t.v[2]) / 3.0 + v() * 0.6 };
            let rq = RayQuery::new(Ray::new(o, target - o), 0.0);
            seen.insert(rq.k);
            for cull in [Cull::None, Cull::Back, Cull::Front] {
                let fixed = intersect_triangle(&t, &rq, 100.0, cull);
                let read = intersect_triangle_permuted(&t, &rq, 100.0, cull, std::hint::black_box(rq.k));
                let bits = |h: Option<(f32, f32, f32)>| h.map(|(t, u, v)| [t, u, v].map(f32::to_bits));
                assert_eq!(bits(fixed), bits(read), "ray {i}, permutation {:?}, {cull:?}", rq.k);
                hits += usize::from(fixed.is_some());
            }
            edge += usize::from(i % 7 == 0);
        }
        assert_eq!(seen.len(), 6, "permutations seen: {seen:?}");
        assert!(hits > 2000 && edge > 500, "{hits} hits");
    }

    fn cylinder() -> Cone {
        Cone { base: Vec3A::ZERO, axis: Vec3A::Z, height: 2.0, r0: 1.0, slope: 0.0 }
    }

    #[test]
    fn cylinder_hits_outside_and_inside_and_ends_are_open() {
        let t =
            intersect_cone(&cylinder(), &q([-5.0, 0.0, 1.0], [1.0, 0.0, 0.0]), 100.0, Cull::None).unwrap();
        assert!((t - 4.0).abs() < 1e-5);
        // Along the axis through the open ends: no hit.
        assert!(
            intersect_cone(&cylinder(), &q([0.0, 0.0, -5.0], [0.0, 0.0, 1.0]), 100.0, Cull::None).is_none()
        );
        // Above the top: miss.
        assert!(
            intersect_cone(&cylinder(), &q([-5.0, 0.0, 2.5], [1.0, 0.0, 0.0]), 100.0, Cull::None).is_none()
        );
        // Inside only (negative radii): the far wall.
        let t =
            intersect_cone(&cylinder(), &q([-5.0, 0.0, 1.0], [1.0, 0.0, 0.0]), 100.0, Cull::Front).unwrap();
        assert!((t - 6.0).abs() < 1e-5);
        // One-sided: from inside nothing is visible.
        assert!(
            intersect_cone(&cylinder(), &q([0.0, 0.0, 1.0], [1.0, 0.0, 0.0]), 100.0, Cull::Back).is_none()
        );
    }

    #[test]
    fn plane_hits_from_both_sides_and_culls() {
        let pl = Plane { point: Vec3A::new(0.0, -1.0, 0.0), n: Vec3A::Y };
        let down = q([3.0, 2.0, -7.0], [0.0, -1.0, 0.0]);
        assert_eq!(intersect_plane(&pl, &down, 100.0, Cull::None), Some(3.0));
        assert_eq!(intersect_plane(&pl, &down, 100.0, Cull::Back), Some(3.0));
        assert_eq!(intersect_plane(&pl, &down, 100.0, Cull::Front), None);
        let up = q([0.0, -3.0, 0.0], [0.0, 1.0, 0.0]);
        assert_eq!(intersect_plane(&pl, &up, 100.0, Cull::None), Some(2.0));
        assert_eq!(intersect_plane(&pl, &up, 100.0, Cull::Back), None);
        assert_eq!(intersect_plane(&pl, &q([0.0, 0.0, 0.0], [1.0, 0.0, 0.0]), 100.0, Cull::None), None);
        assert_eq!(intersect_plane(&pl, &down, 2.5, Cull::None), None);
    }

    #[test]
    fn cone_with_arbitrary_axis() {
        // Cone from (0,0,0) radius 1 to (2,0,0) radius 0.5, probed at x = 1
        // where the radius is 0.75.
        let c = Cone { base: Vec3A::ZERO, axis: Vec3A::X, height: 2.0, r0: 1.0, slope: -0.25 };
        let t = intersect_cone(&c, &q([1.0, -5.0, 0.0], [0.0, 1.0, 0.0]), 100.0, Cull::None).unwrap();
        assert!((t - 4.25).abs() < 1e-5, "{t}");
        let mut g = Geometry {
            cones: vec![c],
            info: vec![PrimInfo::new(0, Cull::None, None, 0)],
            ..Default::default()
        };
        g.assign_ids();
        let b = g.bounds(0);
        assert!((b.min.y + 1.0).abs() < 1e-6 && (b.max.x - 2.0).abs() < 1e-6);
        let rq = q([1.0, -5.0, 0.0], [0.0, 1.0, 0.0]);
        let hit = g.intersect(0, &rq, 100.0).unwrap();
        let n = g.surface(&hit, &rq).ng;
        // Normal tilts towards +x because the cone narrows along +x.
        assert!(n.y < -0.9 && n.x > 0.1, "{n}");
    }

    #[test]
    fn a_point_computed_at_a_sphere_centre_faces_the_ray() {
        // Far along a ray (o ~ 2e16) a hit on a unit sphere can round to its
        // very centre: the normal had no direction and came out NaN.
        let g = crate::testing::spheres(1, |_| (Vec3A::ZERO, 0.5));
        let rq = q([0.0, 0.0, 0.0], [0.0, 0.6, 0.8]);
        let n = g.surface(&Hit { t: 0.0, prim: 0, u: 0.0, v: 0.0 }, &rq).ng;
        assert_eq!(n, -rq.ray.d);
    }
}
