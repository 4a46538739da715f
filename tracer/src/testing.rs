//! Scenes and random streams for the crate's unit tests.

use crate::accel::{Bvh, Tracer};
use crate::geometry::{Cull, Geometry, Kind, PrimInfo, Sphere, Triangle};
use crate::material::WhittedMaterial;
use crate::math::{Ray, RayQuery};
use crate::packet::surface::surfaces;
use crate::packet::{PacketHits, PointLanes, RayPacket};
use crate::prepare::build_geometry;
use crate::simd::lanes::{lane, LANES};
use crate::simd::Isa;
use glam::{DVec3, Vec3A};
use nffkit_formats::{Primitive, Scene, Shape, SourceLine};

/// A fixed xorshift stream of floats in [0, 1).
pub fn uniform(seed: u64) -> impl FnMut() -> f32 {
    let mut s = seed;
    move || {
        s ^= s << 13;
        s ^= s >> 7;
        s ^= s << 17;
        (s >> 40) as f32 / (1u64 << 24) as f32
    }
}

/// `n` two-sided spheres, sphere `i` at `place(i)` = (centre, radius).
pub fn spheres(n: usize, mut place: impl FnMut(usize) -> (Vec3A, f32)) -> Geometry {
    let mut g = Geometry::default();
    for i in 0..n {
        let (center, radius) = place(i);
        g.spheres.push(Sphere::new(center, radius));
        g.info.push(PrimInfo::new(0, Cull::None, None, 0));
    }
    g.assign_ids();
    g
}

/// Two-sided triangles with vertices `v`.
pub fn triangles(v: &[[[f32; 3]; 3]]) -> Geometry {
    let mut g = Geometry::default();
    for t in v {
        g.triangles.push(Triangle { v: t.map(Vec3A::from_array) });
        g.info.push(PrimInfo::new(0, Cull::None, None, 0));
    }
    g.assign_ids();
    g
}

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
            2 => Shape::cone(c, 0.1 + rnd() * 0.5, c + jitter(&mut rnd), rnd() * 0.3),
            3 => Shape::patch(
                vec![c, c + DVec3::X, c + DVec3::new(rnd(), 1.0, rnd())],
                vec![DVec3::Z, DVec3::new(0.1, 0.0, 1.0), DVec3::new(0.0, 0.2, 1.0)],
            ),
            _ if i % 24 == 4 => Shape::plane([c, c + DVec3::X, c + DVec3::new(rnd(), rnd(), 1.0)]),
            _ => Shape::aabb(c, c + DVec3::new(rnd(), rnd(), rnd())),
        };
        scene.primitives.push(Primitive { shape, material: None, line: SourceLine(0) });
    }
    geometry_of(&scene, one_sided)
}

/// A white diffuse material.
pub fn white() -> WhittedMaterial {
    WhittedMaterial {
        color: Vec3A::ONE,
        specular: Vec3A::ONE,
        fresnel: false,
        kd: 1.0,
        ks: 0.0,
        shine: 1.0,
        t: 0.0,
        ior: 1.0,
    }
}

/// The primitives of `scene`, all in one white diffuse material.
pub fn geometry_of(scene: &Scene, one_sided: bool) -> Geometry {
    build_geometry(scene, &[white()], one_sided)
}

/// Up to sixteen rays for packet tests: around a common origin and
/// direction (coherent), or anywhere; some leaving the surface a first ray
/// hit (found with `bvh`). Lanes not in `mask` stay empty.
pub fn rays(
    g: &Geometry,
    bvh: &Bvh,
    base: ([f32; 3], [f32; 3]),
    spread: f32,
    jitter: &[[f32; 6]],
    mask: u32,
) -> RayPacket {
    let mut p = RayPacket::empty();
    let mut tr = Tracer::new(bvh, g);
    for (i, j) in jitter.iter().enumerate().take(LANES) {
        if mask >> i & 1 == 0 {
            continue;
        }
        let o = Vec3A::from(base.0) + Vec3A::new(j[0], j[1], j[2]) * spread;
        let d = Vec3A::from(base.1) + Vec3A::new(j[3], j[4], j[5]) * spread * 0.2;
        if d.length() < 1e-3 {
            continue;
        }
        let mut q = RayQuery::new(Ray::new(o, d), 0.0);
        if i % 5 == 4 {
            // Leave the surface this ray hits, as a secondary ray does.
            if let Some(h) = tr.nearest(&q, f32::INFINITY) {
                let d2 = Vec3A::new(j[4], j[5], j[3]);
                if d2.length() > 1e-3 {
                    q = RayQuery::new(Ray::new(q.ray.at(h.t), d2), 0.0);
                }
            }
        }
        let t_max = if i % 3 == 0 { f32::INFINITY } else { 1.0 + 8.0 * j[0].abs() };
        p.set(i, q, t_max);
    }
    p
}

/// The hits' surface records made by [`surfaces`] for `isa` (lane-wise for
/// spheres and flat triangles, lane by lane for the rest) against the
/// single-ray records, bit for bit: point, normals turned to face the ray,
/// and which side was hit. Returns how many lanes hit a sphere, a triangle
/// and anything else.
pub fn check_surfaces(g: &Geometry, bvh: &Bvh, p: &RayPacket, isa: Isa) -> [usize; 3] {
    let mut tr = Tracer::new(bvh, g);
    let mut hits = PacketHits::new(p);
    tr.nearest_packet(p, &mut hits);
    let hit = hits.found();
    let bits = |v: Vec3A| v.to_array().map(f32::to_bits);
    let mut at = PointLanes::default();
    let entering = surfaces(isa, g, p, &hits, hit, &mut at);
    assert_eq!(entering & !hit, 0, "{isa}: a lane without a hit enters");
    let mut kinds = [0; 3];
    for i in (0..LANES).filter(|i| hit >> i & 1 != 0) {
        let q = p.query(i);
        let s = g.surface(&hits.get(i).unwrap(), &q);
        let enters = s.ng.dot(q.ray.d) < 0.0;
        let flip = if enters { 1.0 } else { -1.0 };
        assert_eq!(entering >> i & 1 != 0, enters, "{isa} lane {i} side");
        assert_eq!(bits(lane(&at.p, i)), bits(s.p), "{isa} lane {i} point");
        assert_eq!(bits(lane(&at.ng, i)), bits(s.ng * flip), "{isa} lane {i} normal");
        assert_eq!(bits(lane(&at.ns, i)), bits(s.ns * flip), "{isa} lane {i} shading normal");
        kinds[match g.locate(hits.prim[i]).0 {
            Kind::Sphere => 0,
            Kind::Triangle => 1,
            _ => 2,
        }] += 1;
    }
    kinds
}
