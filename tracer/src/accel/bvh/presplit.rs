//! Splitting slivers before the build (early split clipping: Ernst and
//! Greiner, "Early Split Clipping for Bounding Volume Hierarchies", 2007;
//! with the split budget of Karras and Aila, "Fast Parallel Construction
//! of High-Quality Bounding Volume Hierarchies", 2013). A long thin
//! triangle's box is mostly empty space: the slivers a many-sided polygon
//! is cut into, such as the SPD gears' 144-gons. Every ray through that
//! space enters the box, and the SAH cannot separate one such box from its
//! neighbours. So a sliver is given several references, each the box of
//! the part of it between two planes across its longest axis: small boxes
//! that hug it.
//!
//! A triangle's pieces are boxes over the same id: a ray tests the same
//! triangle whichever piece leads it there, and the tie rule (the lowest
//! id) makes the nearest hit the same whatever the order, so images do not
//! change. What changes is how many boxes and tests a ray meets.
//!
//! The splits are a fixed share of the triangle count ([`BUDGET`]), handed
//! out by each sliver's priority, the cube root of the box area it wastes
//! (Karras and Aila's, less its weighting by how coarse a scene-grid plane
//! the sliver crosses, which changed nothing measurable on gears_s4).
//! Everything is computed per triangle, and the budget's scale from a sum
//! in a fixed order, so the references do not depend on the thread count.

use crate::aabb::Aabb;
use crate::geometry::{Geometry, Triangle};
use crate::math::largest_axis;
use glam::{DVec3, Vec3A};
use rayon::prelude::*;

/// Extra references at most, as a share of the triangle count. Karras and
/// Aila spend 30%; with only slivers cut, half that bought gears_s4 the
/// same ray rates at half the build cost.
const BUDGET: f64 = 0.15;

/// A triangle is a sliver, and may be cut, if its box's area is more than
/// this many times the least it could be cut to ([`ideal_area`]). A
/// well-shaped triangle's is two to four times; cutting those too made
/// more nodes and slowed teapot_s12 and mount_s7 by 4-7%.
const SLIVER: f32 = 16.0;

/// Most vertices of a triangle clipped to a slab.
const MAX_VERTS: usize = 5;

/// The splits each triangle of a scene gets.
pub(super) struct Presplit {
    /// Splits per triangle (index in `Geometry::triangles`).
    splits: Vec<u32>,
    /// References in all: the build's primitives, pieces counted.
    pub references: usize,
}

impl Presplit {
    /// The splits for `geom`'s triangles, or `None` when there are none
    /// (no slivers).
    pub fn plan(geom: &Geometry) -> Option<Presplit> {
        let tris = &geom.triangles;
        let budget = (BUDGET * tris.len() as f64) as u64;
        if budget == 0
            || geom.bounded_len() > u32::MAX as usize / 2
            || !tris.par_iter().any(|t| waste(t).is_some())
        {
            return None;
        }
        let priority: Vec<f64> = tris.par_iter().map(priority).collect();
        let candidates: Vec<f64> = priority.iter().copied().filter(|&p| p > 0.0).collect();
        // Summed in order: the same splits on any thread count.
        let total: f64 = candidates.iter().sum();
        if !(total > 0.0 && total.is_finite()) {
            return None;
        }
        let scale = fill(&candidates, budget, budget as f64 / total);
        let splits: Vec<u32> = priority.par_iter().map(|p| (p * scale) as u32).collect();
        let extra: usize = splits.par_iter().map(|&s| s as usize).sum();
        (extra > 0).then_some(Presplit { splits, references: geom.bounded_len() + extra })
    }

    /// Whether triangle `i` (index in `Geometry::triangles`) is cut.
    #[inline]
    pub fn is_cut(&self, i: usize) -> bool {
        self.splits[i] > 0
    }

    /// The triangles that are cut, in order.
    pub fn cut(&self) -> impl ParallelIterator<Item = usize> + '_ {
        (0..self.splits.len()).into_par_iter().filter(|&i| self.is_cut(i))
    }

    /// The boxes of triangle `i`'s pieces from piece `from` on, in order
    /// along its longest axis: its box alone when it gets no splits, else
    /// one per slab between equally spaced planes across that axis (a slab
    /// may be flat where the planes round to the same float). Together the
    /// pieces hold the whole triangle, each inside its box.
    pub fn pieces<'a>(&self, geom: &'a Geometry, i: usize, from: u32) -> impl Iterator<Item = Aabb> + 'a {
        let v = &geom.triangles[i].v;
        let bounds = geom.triangles[i].bounds();
        let n = self.splits[i] + 1;
        let size = bounds.size();
        let axis = largest_axis(size);
        let (start, length) = (bounds.min[axis] as f64, size[axis] as f64);
        let plane = move |k: u32| match k {
            0 => bounds.min[axis],
            _ if k == n => bounds.max[axis],
            _ => (start + length * k as f64 / n as f64) as f32,
        };
        let tri = v.map(|p| p.as_dvec3());
        (from..n)
            .map(move |k| if n == 1 { bounds } else { slab_box(&tri, &bounds, axis, plane(k), plane(k + 1)) })
    }
}

/// The scale `s` with about the most splits Σ⌊pᵢ·s⌋ within `budget`
/// (`priority` holds the candidates' priorities, all positive):
/// flooring the budget's share (`start`, where Σ pᵢ·s is the budget)
/// would leave up to one split per candidate unspent. At `start` the sum
/// is within the budget, and one split per candidate more is beyond it;
/// a dozen bisections between the two come within 1/4096 of that gap.
fn fill(priority: &[f64], budget: u64, start: f64) -> f64 {
    let spent = |s: f64| {
        priority.par_chunks(1 << 14).map(|run| run.iter().map(|p| (p * s) as u64).sum::<u64>()).sum::<u64>()
    };
    let (mut lo, mut hi) = (start, start * (1.0 + priority.len() as f64 / budget as f64));
    for _ in 0..12 {
        let mid = 0.5 * (lo + hi);
        if spent(mid) <= budget {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    lo
}

/// The box area a sliver wastes: its box's surface area less the least
/// it could be cut to ([`ideal_area`]); `None` for a triangle that is not
/// a sliver ([`SLIVER`]), or has NaN coordinates or no area (no ray hits
/// it).
fn waste(t: &Triangle) -> Option<f32> {
    let (box_area, ideal) = (2.0 * t.bounds().half_area(), ideal_area(&t.v));
    (box_area > SLIVER * ideal && ideal > 0.0).then_some(box_area - ideal)
}

/// A sliver's priority for splits, the cube root of the box area it wastes
/// (Karras and Aila); zero for a triangle that is not a sliver.
fn priority(t: &Triangle) -> f64 {
    let p = waste(t).map_or(0.0, |w| w.cbrt() as f64);
    if p.is_finite() && p > 0.0 {
        p
    } else {
        0.0
    }
}

/// The box of the part of triangle `tri` (whose box is `bounds`) with
/// `lo <= x[axis] <= hi`: the part's vertices in double precision, rounded
/// outwards to floats, kept inside `bounds` and the slab. Conservative
/// however the clipping rounds; the slab itself if clipping leaves nothing.
fn slab_box(tri: &[DVec3; 3], bounds: &Aabb, axis: usize, lo: f32, hi: f32) -> Aabb {
    let mut above = [DVec3::ZERO; MAX_VERTS];
    let mut part = [DVec3::ZERO; MAX_VERTS];
    let n = clip(tri, axis, lo as f64, true, &mut above);
    let n = clip(&above[..n], axis, hi as f64, false, &mut part);
    let mut b = *bounds;
    if n > 0 {
        let (mut min, mut max) = (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY));
        for p in &part[..n] {
            min = min.min(*p);
            max = max.max(*p);
        }
        let down = Vec3A::from_array(min.to_array().map(|x| (x as f32).next_down()));
        let up = Vec3A::from_array(max.to_array().map(|x| (x as f32).next_up()));
        b = Aabb { min: down.max(bounds.min), max: up.min(bounds.max) };
    }
    b.min[axis] = lo;
    b.max[axis] = hi;
    b
}

/// Sutherland–Hodgman: the polygon `poly` clipped to the side of the plane
/// `x[axis] = c` (`above`: `>= c`), written to `out`; its vertex count.
fn clip(poly: &[DVec3], axis: usize, c: f64, above: bool, out: &mut [DVec3; MAX_VERTS]) -> usize {
    let inside = |p: DVec3| if above { p[axis] >= c } else { p[axis] <= c };
    let mut n = 0;
    for (i, &p) in poly.iter().enumerate() {
        let q = poly[(i + 1) % poly.len()];
        for x in [inside(p).then_some(p), (inside(p) != inside(q)).then(|| crossing(p, q, axis, c))]
            .into_iter()
            .flatten()
        {
            // (A convex polygon cut by one plane gains one vertex at most.)
            if n < MAX_VERTS {
                out[n] = x;
                n += 1;
            }
        }
    }
    n
}

/// Where the segment `p`–`q` crosses the plane `x[axis] = c`.
fn crossing(p: DVec3, q: DVec3, axis: usize, c: f64) -> DVec3 {
    let mut x = p + (q - p) * ((c - p[axis]) / (q[axis] - p[axis]));
    x[axis] = c;
    x
}

/// The surface area a triangle's box tends to as the triangle is cut ever
/// finer: twice the sum of its projected areas on the three axis planes,
/// the sum of the absolute components of (b − a) × (c − a).
fn ideal_area(v: &[Vec3A; 3]) -> f32 {
    (v[1] - v[0]).cross(v[2] - v[0]).abs().element_sum()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testing::uniform;

    /// Points spread over the triangle, corners and edges included, in
    /// double precision.
    fn points(v: &[Vec3A; 3]) -> impl Iterator<Item = DVec3> + '_ {
        let n = 24;
        (0..=n).flat_map(move |i| {
            (0..=n - i).map(move |j| {
                let (u, w) = (i as f64 / n as f64, j as f64 / n as f64);
                let [a, b, c] = v.map(|p| p.as_dvec3());
                a + (b - a) * u + (c - a) * w
            })
        })
    }

    /// Whether `b` holds `p`, give or take the rounding of `p` itself
    /// (about 1e-16 relative; a float's spacing is 6e-8 relative).
    fn contains(b: &Aabb, p: DVec3) -> bool {
        let slack = |x: f64| 1e-12 * (1.0 + x.abs());
        (0..3).all(|a| b.min[a] as f64 - slack(p[a]) <= p[a] && p[a] <= b.max[a] as f64 + slack(p[a]))
    }

    /// Pieces of slivers, triangles flat on an axis plane and random
    /// triangles: as many as the splits allow at most, each inside the
    /// triangle's box, and together holding every point of the triangle.
    #[test]
    fn pieces_cover_the_triangle_inside_its_box() {
        let mut rnd = uniform(0x5eed_0f5b_1175);
        let mut cut = 0;
        for k in 0..3000 {
            let mut p = || Vec3A::new(rnd() * 8.0 - 4.0, rnd() * 8.0 - 4.0, rnd() * 8.0 - 4.0);
            let (a, b) = (p(), p());
            let (b, c) = match k % 3 {
                0 => (b, p()),
                // A sliver: the third vertex next to the second.
                1 => (b, a + (b - a) * 0.999 + Vec3A::splat(1e-4)),
                // Flat on an axis plane, one edge along an axis.
                _ => (Vec3A::new(b.x, b.y, a.z), Vec3A::new(b.x, a.y, a.z)),
            };
            let v = [a, b, c];
            let splits = k as u32 % 9;
            let plan = Presplit { splits: vec![splits], references: 0 };
            let g = crate::testing::triangles(&[v.map(|p| p.to_array())]);
            let boxes: Vec<Aabb> = plan.pieces(&g, 0, 0).collect();
            assert_eq!(boxes.len(), splits as usize + 1);
            cut += usize::from(boxes.len() > 1);
            let bounds = g.triangles[0].bounds();
            for b in &boxes {
                assert!(
                    b.min.cmpge(bounds.min).all() && b.max.cmple(bounds.max).all(),
                    "{b:?} outside {bounds:?}"
                );
            }
            for q in points(&v) {
                assert!(boxes.iter().any(|b| contains(b, q)), "{q} of {v:?} in no piece of {boxes:?}");
            }
        }
        assert!(cut > 2000, "{cut}");
    }

    /// A sliver's pieces are much smaller than its box.
    #[test]
    fn a_sliver_s_pieces_hug_it() {
        let v = [Vec3A::new(-4.0, -4.0, 0.0), Vec3A::new(4.0, 4.0, 0.0), Vec3A::new(4.0, 4.01, 0.0)];
        let plan = Presplit { splits: vec![7], references: 0 };
        let g = crate::testing::triangles(&[v.map(|p| p.to_array())]);
        let pieces: f32 = plan.pieces(&g, 0, 0).map(|b| b.half_area()).sum();
        assert!(pieces < g.triangles[0].bounds().half_area() / 6.0, "{pieces}");
    }

    /// Slivers get the splits, small well-shaped triangles none, and the
    /// budget is kept.
    #[test]
    fn the_budget_goes_to_the_slivers() {
        // A sliver across the scene, then nineteen small triangles.
        let mut tris = vec![[[-4.0, -4.0, 0.0], [4.0, 4.0, 0.0], [4.0, 4.01, 0.0]]];
        for k in 0..19 {
            let (x, y) = ((k % 5) as f32 * 1.9 - 4.0, (k / 5) as f32 * 1.9 - 4.0);
            tris.push([[x, y, 1.0], [x + 0.1, y, 1.0], [x, y + 0.1, 1.0]]);
        }
        let g = crate::testing::triangles(&tris);
        let plan = Presplit::plan(&g).expect("a sliver to split");
        assert_eq!(plan.splits[1..], [0; 19]);
        assert_eq!(plan.splits[0], 3, "all three splits of the budget");
        assert_eq!(plan.references, 23);
        assert_eq!(plan.pieces(&g, 0, 0).count(), 4);
        assert_eq!(
            plan.pieces(&g, 0, 1).collect::<Vec<_>>(),
            plan.pieces(&g, 0, 0).skip(1).collect::<Vec<_>>()
        );
        assert_eq!(plan.cut().collect::<Vec<_>>(), [0]);
    }

    /// Gears as the SPD draws them: star polygons of many sides, flat and
    /// on edge, which the loader triangulates into slivers.
    fn gears(seed: u64, count: usize) -> Geometry {
        use nffkit_formats::{Primitive, Scene, Shape, SourceLine};
        let mut rnd = uniform(seed);
        let mut scene = Scene::default();
        for g in 0..count {
            let c = DVec3::new(rnd() as f64 * 6.0 - 3.0, rnd() as f64 * 6.0 - 3.0, (g % 6) as f64 * 0.4);
            let (teeth, r) = (24 + (g % 6) * 4, 0.5 + rnd() as f64);
            let vertices = (0..2 * teeth)
                .map(|k| {
                    let a = std::f64::consts::PI * k as f64 / teeth as f64;
                    let radius = if k % 2 == 0 { r } else { r * 0.8 };
                    let (x, y) = (radius * a.cos(), radius * a.sin());
                    // Every other gear stands on edge.
                    c + if g % 2 == 0 { DVec3::new(x, y, 0.0) } else { DVec3::new(x, 0.0, y) }
                })
                .collect();
            scene.primitives.push(Primitive {
                shape: Shape::Polygon { vertices },
                material: None,
                line: SourceLine(0),
            });
        }
        crate::testing::geometry_of(&scene, false)
    }

    /// The BVH over the pieces of slivers finds what brute force finds, ray
    /// by ray (through the triangle blocks too) and in packets, nearest
    /// hits and blockers alike.
    #[test]
    fn a_bvh_over_pieces_finds_what_brute_force_finds() {
        use crate::accel::{BruteForce, Bvh, Tracer};
        use crate::math::{Ray, RayQuery};
        use crate::packet::{PacketHits, NO_PRIM};
        use crate::simd::lanes::LANES;
        let mut packets = 0;
        for seed in 1..=4u64 {
            let g = gears(seed, 6);
            let plan = Presplit::plan(&g).expect("slivers to cut");
            assert!(
                plan.references > g.bounded_len() + g.bounded_len() / 10,
                "{} references",
                plan.references
            );
            let bvh = Bvh::build(&g);
            let (mut tb, mut tf) = (Tracer::new(&bvh, &g), Tracer::new(&BruteForce, &g));
            let mut rnd = uniform(seed * 77);
            for _ in 0..300 {
                let mut p = || Vec3A::new(rnd() * 8.0 - 4.0, rnd() * 8.0 - 4.0, rnd() * 4.0 - 1.0);
                let (from, at) = (p() * 2.0, p() * 0.7);
                let base = (from.to_array(), (at - from).to_array());
                let jitter: Vec<[f32; 6]> = (0..LANES).map(|_| [0.0; 6].map(|_| rnd() * 2.0 - 1.0)).collect();
                let packet = crate::testing::rays(&g, &bvh, base, 0.2, &jitter, 0xffff);
                let mut hits = PacketHits::new(&packet);
                tb.nearest_packet(&packet, &mut hits);
                let blockers = tb.occluders_packet(&packet);
                for i in (0..LANES).filter(|i| packet.active >> i & 1 != 0) {
                    let (q, t_max) = (packet.query(i), packet.t_max.0[i]);
                    let want = tf.nearest(&q, t_max);
                    assert_eq!(tb.nearest(&q, t_max), want, "seed {seed} lane {i}");
                    assert_eq!(hits.get(i), want, "seed {seed} packet lane {i}");
                    let blocked = tf.occluded(&q, t_max);
                    assert_eq!(tb.occluded(&q, t_max), blocked);
                    assert_eq!(blockers.0[i] != NO_PRIM, blocked);
                }
                packets += usize::from(hits.found() != 0);
                // A lone ray from far away, through the whole scene.
                let q = RayQuery::new(Ray::new(from * 3.0, at - from * 3.0), 0.0);
                assert_eq!(tb.nearest(&q, f32::INFINITY), tf.nearest(&q, f32::INFINITY));
            }
        }
        assert!(packets > 300, "{packets} packets hit something");
    }

    /// The references, pieces and all, are the same on any thread count,
    /// over more than one run of ids.
    #[test]
    fn references_do_not_depend_on_the_thread_count() {
        let g = gears(9, 160);
        assert!(g.bounded_len() > 8192, "{} triangles", g.bounded_len());
        let on = |threads: usize| {
            let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().expect("a thread pool");
            let prims = pool.install(|| super::super::build::build_prims(&g));
            prims.iter().map(|p| (p.id(), p.bounds())).collect::<Vec<_>>()
        };
        let one = on(1);
        assert!(one.len() > g.bounded_len() + g.bounded_len() / 10, "{} references", one.len());
        assert!(one == on(3), "one thread against three");
    }
}
