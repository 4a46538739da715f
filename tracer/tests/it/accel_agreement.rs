//! Grid, BVH and brute force agree on every hit; mailboxes change nothing but
//! the work. (The DDA's cell order is tested beside it, in `accel/grid.rs`.)

use glam::Vec3A;
use nffkit_tracer::accel::{BruteForce, Bvh, Grid, Intersector};
use nffkit_tracer::geometry::Geometry;
use nffkit_tracer::math::{Ray, RayQuery};
use nffkit_tracer::stats::Counters;
use proptest::prelude::*;

use crate::common::random_scene;

fn query(o: [f32; 3], d: [f32; 3]) -> Option<RayQuery> {
    let d = Vec3A::from(d);
    (d.length() > 1e-3).then(|| RayQuery::new(Ray::new(Vec3A::from(o), d), 0.0))
}

fn check<A: Intersector, B: Intersector>(g: &Geometry, a: &A, b: &B, q: &RayQuery) {
    let (mut sa, mut sb) = (a.scratch(g), b.scratch(g));
    let mut c = Counters::default();
    let ha = a.intersect(g, q, f32::INFINITY, &mut sa, &mut c);
    let hb = b.intersect(g, q, f32::INFINITY, &mut sb, &mut c);
    assert_eq!(ha, hb);
    for t_max in [0.5f32, 3.0, 8.0] {
        assert_eq!(a.occluded(g, q, t_max, &mut sa, &mut c), b.occluded(g, q, t_max, &mut sb, &mut c));
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 64, ..ProptestConfig::default() })]

    #[test]
    fn all_accelerators_find_the_same_hits(
        seed in any::<u64>(),
        n in 1usize..300,
        rays in prop::collection::vec((prop::array::uniform3(-8.0f32..8.0), prop::array::uniform3(-1.0f32..1.0)), 40),
        m in 0.0f32..4.0,
    ) {
        let g = random_scene(seed, n, false);
        let bvh = Bvh::build(&g);
        let grid = Grid::build(&g, m, true);
        let grid_plain = Grid::build(&g, m, false);
        for (o, d) in rays {
            let Some(q) = query(o, d) else { continue };
            check(&g, &BruteForce, &bvh, &q);
            check(&g, &BruteForce, &grid, &q);
            check(&g, &grid_plain, &grid, &q);
        }
    }
}

#[test]
fn mailboxes_save_tests_without_changing_hits() {
    let g = random_scene(7, 400, false);
    let (with, without) = (Grid::build(&g, 4.0, true), Grid::build(&g, 4.0, false));
    let (mut sw, mut so) = (with.scratch(&g), without.scratch(&g));
    let (mut cw, mut co) = (Counters::default(), Counters::default());
    for i in 0..2000 {
        let a = i as f32 * 0.37;
        let q =
            query([-9.0, a.sin() * 4.0, a.cos() * 4.0], [1.0, (a * 1.3).sin() * 0.3, (a * 0.7).cos() * 0.3])
                .unwrap();
        let hw = with.intersect(&g, &q, f32::INFINITY, &mut sw, &mut cw);
        let ho = without.intersect(&g, &q, f32::INFINITY, &mut so, &mut co);
        assert_eq!(hw, ho);
    }
    assert!(cw.mailbox_hits > 0);
    assert!(cw.total_tests() < co.total_tests());
    assert_eq!(cw.total_tests() + cw.mailbox_hits, co.total_tests());
}

#[test]
fn grid_with_m_zero_is_one_cell() {
    let g = random_scene(3, 50, false);
    let grid = Grid::build(&g, 0.0, true);
    assert_eq!(grid.dims, [1, 1, 1]);
}

#[test]
fn large_trees_built_in_parallel_agree_with_brute_force() {
    // Above the parallel-build threshold (65,536 primitives).
    let g = random_scene(5, 150_000, false);
    let bvh = Bvh::build(&g);
    for i in 0..150 {
        let a = i as f32 * 0.77;
        let q = query([a.sin() * 9.0, a.cos() * 9.0, (a * 0.3).sin() * 9.0], [-a.sin(), -a.cos() + 0.1, 0.2])
            .unwrap();
        check(&g, &BruteForce, &bvh, &q);
    }
}
