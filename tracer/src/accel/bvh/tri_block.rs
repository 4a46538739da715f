//! Leaves of two to four triangles, laid out for one ray to test all of
//! them at once: each leaf's vertices in structure-of-arrays form, one
//! SIMD lane per triangle (glam's `Vec4`, SSE on x86-64), as Embree tests
//! a leaf's triangles. The single-ray walk tests such a leaf in one pass
//! instead of one watertight test per triangle.
//!
//! The test repeats [`crate::geometry::intersect_triangle`] operation for
//! operation on each lane, so every lane finds bit for bit what the
//! scalar test finds; a lane on an edge in single precision (the scalar
//! test's double-precision path) is left to the scalar test. Scenes where
//! some primitive culls a side have no blocks.

use super::wide::Node4;
use crate::geometry::{Geometry, Kind};
use crate::math::{triangle_t_error, RayQuery};
use glam::Vec4;
use rayon::prelude::*;

/// Most triangles a block holds: one per lane.
const WIDTH: usize = 4;

/// A block's rows: each vertex's three coordinates.
const ROWS: usize = 9;

/// Nodes whose blocks are counted, then written, as one job.
const NODE_RUN: usize = 1 << 10;

/// The blocks of a tree's leaves of two to four triangles, packed: a
/// block of `n` triangles is nine rows of `n` floats (`row[3 * vertex +
/// axis]`, lanes in leaf order), read as vectors of four, whose lanes past
/// `n` (the next row's floats, or padding at the end) are ignored.
#[derive(Debug, Clone, Default)]
pub(crate) struct TriangleBlocks {
    rows: Vec<f32>,
    /// Per position in the tree's primitive ids where a blocked leaf
    /// starts, its block's first float plus one, else 0; empty when there
    /// are no blocks.
    at: Vec<u32>,
}

/// One leaf's block: its rows onwards, and how many triangles it holds.
#[derive(Clone, Copy)]
pub(crate) struct TriangleBlock<'a> {
    rows: &'a [f32],
    n: usize,
}

/// What one ray found in a block: the lanes hit within the limit, the
/// lanes the scalar test must decide, and each lane's distance and
/// barycentrics (meaningful in `found` lanes only).
pub(crate) struct BlockHits {
    pub found: u32,
    pub slow: u32,
    pub t: [f32; WIDTH],
    pub u: [f32; WIDTH],
    pub v: [f32; WIDTH],
}

/// `a > b ? a : b` lane by lane: [`crate::math::max_of`], as the scalar
/// test takes it.
#[inline(always)]
fn max_of(a: Vec4, b: Vec4) -> Vec4 {
    Vec4::select(a.cmpgt(b), a, b)
}

impl TriangleBlocks {
    /// The blocks of the leaves of `nodes` that hold two to four triangles
    /// (ids in `prims`); none when the scene has no such leaf or some
    /// primitive culls a side.
    pub fn build(geom: &Geometry, nodes: &[Node4], prims: &[u32]) -> TriangleBlocks {
        if geom.any_cull || geom.triangles.len() < 2 {
            return TriangleBlocks::default();
        }
        let blocked = |run| blocked_leaves(geom, run, prims);
        // Counted first, run by run on all cores, so that every float is
        // written once, where it stays, in node order whatever the cores.
        let floats: Vec<usize> = nodes
            .par_chunks(NODE_RUN)
            .map(|run| blocked(run).map(|(_, ids)| ROWS * ids.len()).sum())
            .collect();
        let total = floats.iter().sum::<usize>() + WIDTH - 1;
        // (No block: only the padding. Offsets past u32: no blocks.)
        if total < ROWS || u32::try_from(total).is_err() {
            return TriangleBlocks::default();
        }
        // (Zeroed memory is not written until it is used.)
        let mut rows = vec![0.0; total];
        rows[total - (WIDTH - 1)..].fill(f32::NAN);
        let mut parts = Vec::with_capacity(floats.len());
        let mut rest = rows.as_mut_slice();
        for &n in &floats {
            let (part, tail) = std::mem::take(&mut rest).split_at_mut(n);
            parts.push(part);
            rest = tail;
        }
        // Each run's blocks, written, with where each leaf starts in the
        // ids and its block's offset within the run's part.
        let written: Vec<Vec<(usize, usize)>> = nodes
            .par_chunks(NODE_RUN)
            .zip(parts)
            .map(|(run, part)| {
                let (mut at, mut leaves) = (0, Vec::new());
                for (start, ids) in blocked(run) {
                    write_block(geom, ids, &mut part[at..at + ROWS * ids.len()]);
                    leaves.push((start, at));
                    at += ROWS * ids.len();
                }
                leaves
            })
            .collect();
        let mut at = vec![0; prims.len()];
        let mut base = 0;
        for (leaves, floats) in written.iter().zip(&floats) {
            for &(start, offset) in leaves {
                at[start] = (base + offset) as u32 + 1;
            }
            base += floats;
        }
        TriangleBlocks { rows, at }
    }

    /// Whether there are any blocks.
    #[inline(always)]
    pub fn is_empty(&self) -> bool {
        self.at.is_empty()
    }

    /// The block of the leaf of `n` primitives that starts at `start` in
    /// the tree's ids, if it has one.
    #[inline(always)]
    pub fn get(&self, start: usize, n: usize) -> Option<TriangleBlock<'_>> {
        let at = *self.at.get(start)? as usize;
        (at != 0).then(|| TriangleBlock { rows: &self.rows[at - 1..], n })
    }

    /// Bytes held.
    pub fn bytes(&self) -> usize {
        (self.rows.len() + self.at.len()) * 4
    }
}

/// The leaves of `run` (nodes over `prims`) that get a block: their
/// starts in `prims`, and their ids.
fn blocked_leaves<'a>(
    geom: &'a Geometry,
    run: &'a [Node4],
    prims: &'a [u32],
) -> impl Iterator<Item = (usize, &'a [u32])> + 'a {
    let triangle = |id: &u32| geom.locate(*id).0 == Kind::Triangle;
    run.iter().flat_map(move |node| {
        (0..4).filter_map(move |s| {
            let (start, count) = (node.child[s] as usize, node.count[s] as usize);
            let ids = prims.get(start..start + count).filter(|_| node.used(s))?;
            ((2..=WIDTH).contains(&count) && ids.iter().all(triangle)).then_some((start, ids))
        })
    })
}

/// The rows of the block of triangles `ids` into `out`.
fn write_block(geom: &Geometry, ids: &[u32], out: &mut [f32]) {
    for (lane, &id) in ids.iter().enumerate() {
        let v = &geom.triangles[geom.locate(id).1].v;
        for row in 0..ROWS {
            out[row * ids.len() + lane] = v[row / 3][row % 3];
        }
    }
}

impl TriangleBlock<'_> {
    /// Row `row` as a vector (lanes past the block's triangles ignored).
    #[inline(always)]
    fn row(&self, row: usize) -> Vec4 {
        Vec4::from_slice(&self.rows[row * self.n..])
    }

    /// The watertight test of `q` against every lane, accepting distances
    /// in `(q.t_min, limit)`.
    #[inline(always)]
    pub fn hit(&self, q: &RayQuery, limit: f32) -> BlockHits {
        let [kx, ky, kz] = q.k;
        let o = q.ray.o.to_array();
        let (ox, oy, oz) = (Vec4::splat(o[kx]), Vec4::splat(o[ky]), Vec4::splat(o[kz]));
        let s = q.shear;
        let (sx, sy, sz) = (Vec4::splat(s.x), Vec4::splat(s.y), Vec4::splat(s.z));
        let vertex = |v: usize| [kx, ky, kz].map(|axis| self.row(3 * v + axis));
        let ([a_x, a_y, a_z], [b_x, b_y, b_z], [c_x, c_y, c_z]) = (vertex(0), vertex(1), vertex(2));
        let (a_x, a_y, a_z) = (a_x - ox, a_y - oy, a_z - oz);
        let (b_x, b_y, b_z) = (b_x - ox, b_y - oy, b_z - oz);
        let (c_x, c_y, c_z) = (c_x - ox, c_y - oy, c_z - oz);
        let (ax, ay) = (a_x - sx * a_z, a_y - sy * a_z);
        let (bx, by) = (b_x - sx * b_z, b_y - sy * b_z);
        let (cx, cy) = (c_x - sx * c_z, c_y - sy * c_z);
        let u = cx * by - cy * bx;
        let v = ax * cy - ay * cx;
        let w = bx * ay - by * ax;
        let zero = Vec4::ZERO;
        let edge = u.cmpeq(zero) | v.cmpeq(zero) | w.cmpeq(zero);
        let any_neg = u.cmplt(zero) | v.cmplt(zero) | w.cmplt(zero);
        let any_pos = u.cmpgt(zero) | v.cmpgt(zero) | w.cmpgt(zero);
        let det = u + v + w;
        let lanes = (1 << self.n) - 1;
        let slow = edge.bitmask() & lanes;
        // Inside all edges (or outside all: seen from the back), det != 0.
        let within = !(any_neg & any_pos).bitmask() & !det.cmpeq(zero).bitmask() & !slow & lanes;
        let mut out = BlockHits { found: 0, slow, t: [0.0; WIDTH], u: [0.0; WIDTH], v: [0.0; WIDTH] };
        if within == 0 {
            return out;
        }
        let (az, bz, cz) = (sz * a_z, sz * b_z, sz * c_z);
        let t = (u * az + v * bz + w * cz) / det;
        let inside = (Vec4::splat(q.t_min).cmplt(t) & t.cmplt(Vec4::splat(limit))).bitmask() & within;
        if inside == 0 {
            return out;
        }
        let inv = Vec4::ONE / det;
        let max = |p: Vec4, q: Vec4, r: Vec4| max_of(max_of(p.abs(), q.abs()), r.abs());
        let (max_x, max_y, max_z) = (max(ax, bx, cx), max(ay, by, cy), max(az, bz, cz));
        let error = triangle_t_error(max_x, max_y, max_z, max(u, v, w), inv.abs());
        out.found = inside & !t.cmple(error).bitmask();
        out.t = t.to_array();
        out.u = (v * inv).to_array();
        out.v = (w * inv).to_array();
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::accel::bvh::Bvh;
    use crate::accel::Tracer;
    use crate::geometry::{intersect_triangle, Cull, Triangle};
    use crate::math::Ray;
    use crate::testing::{geometry_of, uniform};
    use glam::{DVec3, Vec3A};
    use nffkit_formats::{Primitive, Scene, Shape, SourceLine};

    /// Boxes (twelve triangles each), triangles, quads and spheres, none
    /// culling a side, placed by `rnd`.
    fn boxes_and_triangles(n: usize, rnd: &mut impl FnMut() -> f32) -> Geometry {
        let mut scene = Scene::default();
        for i in 0..n {
            let mut p = || DVec3::new(rnd() as f64, rnd() as f64, rnd() as f64);
            let c = p() * 10.0 - 5.0;
            let shape = match i % 4 {
                0 => Shape::aabb(c, c + p()),
                1 => Shape::Polygon { vertices: vec![c, c + p() - 0.5, c + p() - 0.5] },
                2 => Shape::Polygon {
                    vertices: vec![c, c + DVec3::X, c + DVec3::new(1.0, 1.0, 0.0), c + DVec3::Y],
                },
                _ => Shape::Sphere { center: c, radius: 0.1 + p().x * 0.5 },
            };
            scene.primitives.push(Primitive { shape, material: None, line: SourceLine(0) });
        }
        geometry_of(&scene, false)
    }

    /// The single-ray walk finds with blocks what it finds without them,
    /// ray by ray: the nearest hit's bits, the first blocker (which the
    /// shadow cache keeps), and the counts of tests and visits.
    #[test]
    fn blocks_change_nothing_the_walk_finds_or_counts() {
        let mut rnd = uniform(0x3c6e_f372_fe94_f82b);
        let (mut blocked_leaves, mut hits) = (0, 0);
        for seed in 0..12 {
            let g = boxes_and_triangles(150 + seed * 20, &mut rnd);
            let with = Bvh::build(&g);
            let without = Bvh { blocks: TriangleBlocks::default(), ..with.clone() };
            blocked_leaves += with.blocks.at.iter().filter(|&&at| at != 0).count();
            let (mut a, mut b) = (Tracer::new(&with, &g), Tracer::new(&without, &g));
            let mut aim = Tracer::new(&with, &g);
            for _ in 0..400 {
                let o = Vec3A::new(rnd(), rnd(), rnd()) * 14.0 - 7.0;
                // At a triangle, near a vertex (or a shared edge or corner).
                let tri = &g.triangles[(rnd() * g.triangles.len() as f32) as usize % g.triangles.len()];
                let d = tri.v[0] + (tri.v[1] - tri.v[0]) * (rnd() * 0.3) - o;
                if d.length() < 1e-3 {
                    continue;
                }
                let mut q = RayQuery::new(Ray::new(o, d), 0.0);
                if let Some(h) = aim.nearest(&q, f32::INFINITY).filter(|_| rnd() < 0.5) {
                    // Leaving the surface it hit, as a secondary ray does.
                    q = RayQuery::new(Ray::new(q.ray.at(h.t), Vec3A::new(d.z, d.x, -d.y)), 0.0);
                }
                let t_max = [f32::INFINITY, 2.0, 6.0][(rnd() * 3.0) as usize % 3];
                let found = a.nearest(&q, t_max);
                assert_eq!(found, b.nearest(&q, t_max), "{q:?}");
                hits += usize::from(found.is_some());
                assert_eq!(a.occluder(&q, t_max), b.occluder(&q, t_max), "{q:?}");
            }
            assert_eq!(a.counters, b.counters, "scene {seed}");
        }
        assert!(blocked_leaves > 2000 && hits > 1500, "{blocked_leaves} leaves blocked, {hits} hits");
    }

    /// The blocks, written run by run on all cores, are the same bits on
    /// one thread as on three, over enough nodes for several runs.
    #[test]
    fn blocks_do_not_depend_on_the_thread_count() {
        let g = boxes_and_triangles(4000, &mut uniform(0x94d0_49bb_1331_11eb));
        let on = |threads: usize| {
            let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().expect("a thread pool");
            let bvh = pool.install(|| Bvh::build(&g));
            assert!(bvh.wide.len() > 2 * NODE_RUN, "{} nodes", bvh.wide.len());
            (bvh.blocks.rows.iter().map(|f| f.to_bits()).collect::<Vec<_>>(), bvh.blocks.at)
        };
        let one = on(1);
        assert!(one.1.iter().filter(|&&at| at != 0).count() > 1000);
        assert!(one == on(3), "one thread against three");
    }

    /// Every lane finds what the scalar test finds, bit for bit, or is
    /// left to it: random triangles, triangles sharing edges and vertices
    /// (rays through them land on edges), flat and degenerate ones, rays
    /// along axes, limits that cut hits off.
    #[test]
    fn each_lane_is_the_scalar_triangle_test() {
        let mut rnd = uniform(0x51_7cc1_b727_220a);
        let mut coord = |grid: bool| {
            let x = rnd() * 4.0 - 2.0;
            if grid {
                (x * 4.0).round() * 0.25
            } else {
                x
            }
        };
        let (mut hits, mut slow, mut tested) = (0, 0, 0);
        for round in 0..20_000 {
            let grid = round % 3 == 0;
            let mut p = || Vec3A::new(coord(grid), coord(grid), coord(grid));
            let shared = [p(), p()];
            let count = 2 + round % 3;
            let tris: Vec<Triangle> = (0..count)
                .map(|i| match (round % 4, i) {
                    // Fans around a shared edge, and a degenerate one.
                    (0, _) => Triangle { v: [shared[0], shared[1], p()] },
                    (1, 1) => Triangle { v: [shared[0], shared[0], p()] },
                    _ => Triangle { v: [p(), p(), p()] },
                })
                .collect();
            let o = p() * 2.0;
            // At a shared vertex, or near a triangle's centre.
            let centre = |t: &Triangle| (t.v[0] + t.v[1] + t.v[2]) / 3.0;
            let aim = if grid { shared[0] } else { centre(&tris[round % count]) + p() * 0.05 };
            let mut d = aim - o;
            if round % 5 == 0 {
                d = Vec3A::new(0.0, d.y, 0.0);
            }
            if d == Vec3A::ZERO {
                continue;
            }
            let q = RayQuery::new(Ray::new(o, d), [0.0, 0.5][round % 2]);
            let limit = [f32::INFINITY, 4.0, 1.0][round / 3 % 3];
            // Packed as the tree packs them; the lanes past the block read
            // its next row, or the padding.
            let mut rows: Vec<f32> =
                (0..ROWS).flat_map(|row| tris.iter().map(move |t| t.v[row / 3][row % 3])).collect();
            rows.extend([f32::NAN; WIDTH - 1]);
            let got = TriangleBlock { rows: &rows, n: count }.hit(&q, limit);
            assert_eq!(got.found & !0xf, 0);
            assert_eq!(got.found & got.slow, 0, "a lane both found and left");
            for (lane, tri) in tris.iter().enumerate() {
                tested += 1;
                if got.slow >> lane & 1 != 0 {
                    slow += 1;
                    continue;
                }
                let want = intersect_triangle(tri, &q, limit, Cull::None);
                let bits = |(t, u, v): (f32, f32, f32)| [t, u, v].map(f32::to_bits);
                match want {
                    None => assert!(got.found >> lane & 1 == 0, "lane {lane} hit {tri:?} by {q:?}"),
                    Some(h) => {
                        assert!(got.found >> lane & 1 != 0, "lane {lane} missed {tri:?} by {q:?}");
                        assert_eq!(bits((got.t[lane], got.u[lane], got.v[lane])), bits(h));
                        hits += 1;
                    }
                }
            }
            // Unused lanes never hit.
            assert_eq!(got.found >> count, 0);
        }
        assert!(hits > 5000 && slow > 50 && tested > 50_000, "{hits} hits, {slow} slow of {tested}");
    }
}
