//! Helpers shared by the tracer's integration tests.

use glam::{DVec3, Vec3A};
use nffkit_formats::{Primitive, Scene, Shape, SourceLine};
use nffkit_tracer::geometry::Geometry;
use nffkit_tracer::material::WhittedMaterial;
use nffkit_tracer::prepare::build_geometry;

/// A random scene of every kind of primitive (spheres, triangles, cones,
/// patches, planes and boxes), one-sided or not.
pub fn random_scene(seed: u64, n: usize, one_sided: bool) -> Geometry {
    let mut s = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
    let mut rnd = move || {
        s ^= s << 13;
        s ^= s >> 7;
        s ^= s << 17;
        (s >> 11) as f64 / (1u64 << 53) as f64
    };
    let mut scene = Scene::default();
    for i in 0..n {
        let c = DVec3::new(rnd() * 10.0 - 5.0, rnd() * 10.0 - 5.0, rnd() * 10.0 - 5.0);
        let jitter = |r: &mut dyn FnMut() -> f64| DVec3::new(r(), r(), r()) * 2.0 - 1.0;
        let shape = match i % 6 {
            0 | 5 => Shape::Sphere { center: c, radius: if i % 12 == 5 { -0.5 } else { 0.1 + rnd() * 0.8 } },
            1 => Shape::Polygon { vertices: (0..3).map(|_| c + jitter(&mut rnd)).collect() },
            2 => Shape::Cone {
                base: c,
                base_radius: 0.1 + rnd() * 0.5,
                apex: c + jitter(&mut rnd),
                apex_radius: rnd() * 0.3,
            },
            3 => Shape::Patch {
                vertices: vec![c, c + DVec3::X, c + DVec3::new(rnd(), 1.0, rnd())],
                normals: vec![DVec3::Z, DVec3::new(0.1, 0.0, 1.0), DVec3::new(0.0, 0.2, 1.0)],
            },
            _ if i % 24 == 4 => Shape::Plane { points: [c, c + DVec3::X, c + DVec3::new(rnd(), rnd(), 1.0)] },
            _ => Shape::Box { min: c, max: c + DVec3::new(rnd(), rnd(), rnd()) },
        };
        scene.primitives.push(Primitive { shape, material: None, line: SourceLine(0) });
    }
    let m = WhittedMaterial { color: Vec3A::ONE, kd: 1.0, ks: 0.0, shine: 1.0, t: 0.0, ior: 1.0 };
    build_geometry(&scene, &[m], one_sided)
}
