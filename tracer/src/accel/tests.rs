//! Every accelerator finds the same hits as brute force, and mailboxes
//! change nothing but the work. (The DDA's cell order is tested beside it,
//! in `grid.rs`; packet traversal in `bvh/packet.rs`.)

use super::*;
use crate::math::Ray;
use crate::testing::random_scene;
use glam::Vec3A;
use proptest::prelude::*;

fn query(o: [f32; 3], d: [f32; 3]) -> Option<RayQuery> {
    let d = Vec3A::from(d);
    (d.length() > 1e-3).then(|| RayQuery::new(Ray::new(Vec3A::from(o), d), 0.0))
}

/// What `accel` answers for the ray of `q`: its nearest hit, and whether it
/// is blocked within a few distances.
fn answers(g: &Geometry, accel: &Accel, q: &RayQuery) -> (Option<Hit>, [bool; 3]) {
    with_accel!(accel, a => {
        let mut tr = Tracer::new(a, g);
        (tr.nearest(q, f32::INFINITY), [0.5, 3.0, 8.0].map(|t_max| tr.occluded(q, t_max)))
    })
}

/// Every kind of accelerator (the grid with and without mailboxes, at
/// density `m`) over `g`, with its options.
fn every_accelerator(g: &Geometry, m: f32) -> Vec<(AccelOptions, Accel)> {
    let mut all = Vec::new();
    for &kind in AccelKind::ALL {
        for mailbox in [true, false] {
            let opts = AccelOptions { kind, grid_m: m, mailbox };
            all.push((opts, Accel::build(g, &opts)));
        }
    }
    all
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
        let reference = Accel::build(&g, &AccelOptions { kind: AccelKind::None, ..Default::default() });
        let all = every_accelerator(&g, m);
        for (o, d) in rays {
            let Some(q) = query(o, d) else { continue };
            let want = answers(&g, &reference, &q);
            for (opts, accel) in &all {
                prop_assert_eq!(answers(&g, accel, &q), want, "{:?}", opts);
            }
        }
    }
}

/// Axis-aligned walls through the origin (and at 0.5), as in a Cornell box
/// modelled from the origin, with a few random primitives: the case where
/// a ray leaving a wall starts within rounding of the wall's plane.
fn walls_through_the_origin(seed: u64) -> Geometry {
    use nffkit_formats::{Primitive, Scene, Shape, SourceLine};
    let mut rnd = crate::testing::uniform(seed);
    let mut scene = Scene::default();
    let s = 550.0;
    let quads: [[[f64; 3]; 4]; 5] = [
        [[0.0, 0.0, s], [0.0, 0.0, 0.0], [0.0, s, 0.0], [0.0, s, s]],
        [[0.0, 0.0, 0.0], [s, 0.0, 0.0], [s, 0.0, s], [0.0, 0.0, s]],
        [[0.0, 0.0, s], [s, 0.0, s], [s, s, s], [0.0, s, s]],
        [[0.0, s, 0.0], [s, s, 0.0], [s, s, s], [0.0, s, s]],
        [[0.5, 100.0, 100.0], [0.5, 200.0, 100.0], [0.5, 200.0, 300.0], [0.5, 100.0, 300.0]],
    ];
    for q in quads {
        let vertices = q.iter().map(|v| glam::DVec3::from(*v)).collect();
        scene.primitives.push(Primitive {
            shape: Shape::Polygon { vertices },
            material: None,
            line: SourceLine(0),
        });
    }
    for _ in 0..20 {
        let c = glam::DVec3::new(rnd() as f64, rnd() as f64, rnd() as f64) * s;
        scene.primitives.push(Primitive {
            shape: Shape::Sphere { center: c, radius: 5.0 + rnd() as f64 * 40.0 },
            material: None,
            line: SourceLine(0),
        });
    }
    crate::testing::geometry_of(&scene, false)
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 48, ..ProptestConfig::default() })]

    /// Rays from inside the box hit the walls; shadow rays leave the hit
    /// points (offset as the shader offsets them) toward lights near a
    /// wall's plane, in it, and anywhere: every accelerator answers alike.
    #[test]
    fn shadow_rays_leaving_walls_through_the_origin_agree(
        seed in any::<u64>(),
        eyes in prop::collection::vec((prop::array::uniform3(1.0f32..549.0), prop::array::uniform3(-1.0f32..1.0)), 30),
        lights in prop::collection::vec((0usize..3, prop::sample::select(vec![0.0f32, 1e-6, 1e-3, 0.5, 1.0, 549.0, 549.9, 550.0]), prop::array::uniform3(1.0f32..549.0)), 6),
    ) {
        let g = walls_through_the_origin(seed);
        let reference = Accel::build(&g, &AccelOptions { kind: AccelKind::None, ..Default::default() });
        let all = every_accelerator(&g, 2.0);
        for (o, d) in eyes {
            let Some(q) = query(o, d) else { continue };
            let want = answers(&g, &reference, &q);
            for (opts, accel) in &all {
                prop_assert_eq!(answers(&g, accel, &q), want, "eye ray, {:?}", opts);
            }
            let Some(hit) = want.0 else { continue };
            let s = g.surface(&hit, &q);
            let n = if s.ng.dot(q.ray.d) < 0.0 { s.ng } else { -s.ng };
            for &(axis, at, p) in &lights {
                // A light in (or near) a wall's plane: its coordinate on `axis`.
                let mut light = Vec3A::from(p);
                light[axis] = at;
                let side = if n.dot(light - s.p) >= 0.0 { n } else { -n };
                let Some((ray, max)) = crate::math::shadow_ray(s.p, light, side) else { continue };
                let sq = RayQuery::new(ray, 0.0);
                let blocked = |accel: &Accel| with_accel!(accel, a => Tracer::new(a, &g).occluded(&sq, max));
                let want = blocked(&reference);
                for (opts, accel) in &all {
                    prop_assert_eq!(blocked(accel), want, "shadow ray to {:?}, {:?}", light, opts);
                }
            }
        }
    }
}

#[test]
fn mailboxes_save_tests_without_changing_hits() {
    let g = random_scene(7, 400, false);
    let (with, without) = (Grid::build(&g, 4.0, true), Grid::build(&g, 4.0, false));
    let (mut tw, mut to) = (Tracer::new(&with, &g), Tracer::new(&without, &g));
    for i in 0..2000 {
        let a = i as f32 * 0.37;
        let q =
            query([-9.0, a.sin() * 4.0, a.cos() * 4.0], [1.0, (a * 1.3).sin() * 0.3, (a * 0.7).cos() * 0.3])
                .unwrap();
        assert_eq!(tw.nearest(&q, f32::INFINITY), to.nearest(&q, f32::INFINITY));
    }
    let (cw, co) = (tw.counters, to.counters);
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
    // Above the BVH's parallel-build threshold (65,536 primitives).
    let g = random_scene(5, 150_000, false);
    let bvh = Accel::build(&g, &AccelOptions::default());
    let brute = Accel::build(&g, &AccelOptions { kind: AccelKind::None, ..Default::default() });
    for i in 0..150 {
        let a = i as f32 * 0.77;
        let q = query([a.sin() * 9.0, a.cos() * 9.0, (a * 0.3).sin() * 9.0], [-a.sin(), -a.cos() + 0.1, 0.2])
            .unwrap();
        assert_eq!(answers(&g, &bvh, &q), answers(&g, &brute, &q));
    }
}
