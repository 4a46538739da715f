//! Ray packets find what single rays find: the same nearest hit (bit for
//! bit, with the same tie rule), the same occlusion and the same surface
//! records, for every primitive kind and side rule, with lanes masked off,
//! rays leaving surfaces, and the kernels of every instruction set this
//! processor has; shadow, mirror and refracted rays set up lane-wise are
//! the rays set up one by one. Renders with packets equal renders without.

use glam::Vec3A;
use nffkit_formats::nff::{self, ParseOptions};
use nffkit_tracer::accel::{Bvh, Grid, Intersector};
use nffkit_tracer::geometry::Geometry;
use nffkit_tracer::integrator::LightShape;
use nffkit_tracer::math::{Ray, RayQuery};
use nffkit_tracer::packet::{PacketHits, RayPacket, LANES, NO_PRIM};
use nffkit_tracer::prepare::{prepare, PrepareOptions};
use nffkit_tracer::render::{render, RenderSettings};
use nffkit_tracer::sampling::{Sampler, SamplerKind};
use nffkit_tracer::simd::Isa;
use nffkit_tracer::stats::Counters;
use proptest::prelude::*;

use crate::common::random_scene;

/// Up to sixteen rays: around a common origin and direction (coherent),
/// or anywhere; some leaving the surface a first ray hit. Lanes not in
/// `mask` stay empty.
fn rays(
    g: &Geometry,
    bvh: &Bvh,
    base: ([f32; 3], [f32; 3]),
    spread: f32,
    jitter: &[[f32; 6]],
    mask: u32,
) -> RayPacket {
    let mut p = RayPacket::new(std::iter::empty());
    let mut c = Counters::default();
    let mut scratch = bvh.scratch(g);
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
            if let Some(h) = bvh.intersect(g, &q, f32::INFINITY, &mut scratch, &mut c) {
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

/// Every lane of `p` through `isa`'s kernels and alone: equal hits and
/// equal occlusion.
#[allow(clippy::needless_range_loop)]
fn check(g: &Geometry, bvh: &Bvh, p: &RayPacket, isa: Isa) {
    let mut scratch = bvh.scratch(g);
    let mut c = Counters::default();
    let mut hits = PacketHits::new(p);
    bvh.intersect_packet_with(isa, g, p, &mut hits, &mut scratch, &mut c);
    let mut blockers = [NO_PRIM; LANES];
    bvh.occluders_packet_with(isa, g, p, p.active, &mut blockers, &mut scratch, &mut c);
    for i in 0..LANES {
        let q = p.query(i);
        let t_max = p.t_max.0[i];
        if p.active >> i & 1 == 0 {
            assert_eq!((hits.get(i), blockers[i]), (None, NO_PRIM), "masked lane {i} was traced");
            continue;
        }
        let alone = bvh.intersect_bounded(g, &q, t_max, &mut scratch, &mut c);
        assert_eq!(hits.get(i), alone, "{isa}: lane {i} nearest hit");
        let blocked = bvh.occluder_bounded(g, &q, t_max, &mut scratch, &mut c).is_some();
        assert_eq!(blockers[i] != NO_PRIM, blocked, "{isa}: lane {i} occlusion");
        if blocked {
            assert!(g.intersect(blockers[i], &q, t_max).is_some(), "{isa}: lane {i} blocker does not block");
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 48, ..ProptestConfig::default() })]

    #[test]
    fn packets_find_what_single_rays_find(
        seed in any::<u64>(),
        n in 1usize..300,
        one_sided in any::<bool>(),
        origin in prop::array::uniform3(-8.0f32..8.0),
        dir in prop::array::uniform3(-1.0f32..1.0),
        spread in prop::sample::select(vec![0.0f32, 0.05, 0.5, 4.0]),
        jitter in prop::collection::vec(prop::array::uniform6(-1.0f32..1.0), LANES),
        mask in any::<u16>(),
    ) {
        let g = random_scene(seed, n, one_sided);
        let bvh = Bvh::build(&g);
        let p = rays(&g, &bvh, (origin, dir), spread, &jitter, u32::from(mask) | 1);
        for isa in Isa::available() {
            check(&g, &bvh, &p, isa);
            check_surfaces(&g, &bvh, &p, isa);
        }
        // With planes: the accelerator-level packet queries against the
        // single ones, for the BVH and for the default lane-by-lane form.
        let grid = Grid::build(&g, 2.0, true);
        let (mut sb, mut sg) = (bvh.scratch(&g), grid.scratch(&g));
        let mut c = Counters::default();
        let (mut hb, mut hg) = (PacketHits::new(&p), PacketHits::new(&p));
        bvh.intersect_packet(&g, &p, &mut hb, &mut sb, &mut c);
        grid.intersect_packet(&g, &p, &mut hg, &mut sg, &mut c);
        let ob = bvh.occluders_packet(&g, &p, &mut sb, &mut c);
        let og = grid.occluders_packet(&g, &p, &mut sg, &mut c);
        for i in (0..LANES).filter(|i| p.active >> i & 1 != 0) {
            let (q, t_max) = (p.query(i), p.t_max.0[i]);
            let alone = bvh.intersect(&g, &q, t_max, &mut sb, &mut c);
            prop_assert_eq!(hb.get(i), alone);
            prop_assert_eq!(hg.get(i), alone);
            let blocked = bvh.occluded(&g, &q, t_max, &mut sb, &mut c);
            prop_assert_eq!(ob[i] != NO_PRIM, blocked);
            prop_assert_eq!(og[i] != NO_PRIM, blocked);
        }
    }
}

#[test]
fn the_kernels_of_every_instruction_set_agree_with_the_portable_ones() {
    // Coherent packets over a dense scene, where the lane-wise sphere and
    // triangle tests (not the single-ray fallbacks) do the work.
    let g = random_scene(11, 3000, false);
    let bvh = Bvh::build(&g);
    let available = Isa::available();
    assert!(available.contains(&Isa::Portable));
    let mut lanes_tested = 0;
    for k in 0..200 {
        let a = k as f32 * 0.61;
        let jitter: Vec<[f32; 6]> = (0..LANES)
            .map(|i| {
                let (x, y) = ((i % 4) as f32 / 3.0 - 0.5, (i / 4) as f32 / 3.0 - 0.5);
                [x, y, 0.0, x, y, 0.0]
            })
            .collect();
        let base = ([a.sin() * 9.0, a.cos() * 9.0, (a * 0.3).sin() * 3.0], [-a.sin(), -a.cos(), 0.1]);
        let p = rays(&g, &bvh, base, 0.3, &jitter, 0xffff);
        let mut scratch = bvh.scratch(&g);
        let mut c = Counters::default();
        let mut portable = PacketHits::new(&p);
        bvh.intersect_packet_with(Isa::Portable, &g, &p, &mut portable, &mut scratch, &mut c);
        for &isa in &available {
            let mut hits = PacketHits::new(&p);
            bvh.intersect_packet_with(isa, &g, &p, &mut hits, &mut scratch, &mut c);
            for i in 0..LANES {
                assert_eq!(hits.get(i), portable.get(i), "{isa} lane {i} of packet {k}");
            }
            check(&g, &bvh, &p, isa);
        }
        lanes_tested += portable.prim.iter().filter(|&&id| id != NO_PRIM).count();
    }
    assert!(lanes_tested > 500, "too few hits to compare: {lanes_tested}");
}

fn image(scene: &str, spp: u32, packets: bool, depth: u32) -> Vec<f32> {
    let path = format!("{}/../scenes/spd/{scene}.nff", env!("CARGO_MANIFEST_DIR"));
    let src = std::fs::read(path).unwrap();
    let scene = nff::parse(&src, &ParseOptions::default()).unwrap().scene;
    let opts = PrepareOptions { width: Some(40), height: Some(36), ..Default::default() };
    let p = prepare(&scene, &opts).unwrap();
    let settings = RenderSettings {
        sampler: Sampler::new(SamplerKind::MultiJittered, spp, 3).0,
        centre_single_sample: true,
        light_size: if spp > 4 { 0.3 } else { 0.0 },
        light_shape: LightShape::Square,
        max_depth: depth,
        packets,
        ..Default::default()
    };
    render(&p, &settings, &|_, _| {}).film.pixels.iter().flat_map(|p| p.to_array()).collect()
}

#[test]
fn renders_with_packets_equal_renders_without() {
    // Pixel centres in 4x4 blocks (1 spp), a pixel's samples (4, 16, and
    // 20: a full packet and a partial one), soft shadows, glass and mirrors.
    for (scene, spp) in
        [("balls_s2", 1), ("mount_s1", 16), ("balls_s1", 4), ("teapot_s1", 20), ("gears_s1", 16)]
    {
        let with = image(scene, spp, true, 6);
        let without = image(scene, spp, false, 6);
        assert!(with.iter().any(|&v| v > 0.0), "{scene}: black image");
        assert_eq!(with, without, "{scene} at {spp} spp");
    }
}

/// The hits' surface records made by [`surfaces`] for `isa` (lane-wise for
/// spheres and flat triangles, lane by lane for the rest) against the
/// single-ray records, bit for bit: point, normals turned to face the ray,
/// and which side was hit. Returns how many lanes hit a sphere, a triangle
/// and anything else.
fn check_surfaces(g: &Geometry, bvh: &Bvh, p: &RayPacket, isa: Isa) -> [usize; 3] {
    use nffkit_tracer::geometry::Kind;
    use nffkit_tracer::packet::lane;
    use nffkit_tracer::shadow_lanes::PointLanes;
    use nffkit_tracer::surface_lanes::surfaces;
    let (mut scratch, mut c) = (bvh.scratch(g), Counters::default());
    let mut hits = PacketHits::new(p);
    bvh.intersect_packet(g, p, &mut hits, &mut scratch, &mut c);
    let hit = (0..LANES).filter(|&i| hits.prim[i] != NO_PRIM).fold(0, |m, i| m | 1 << i);
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

#[test]
fn surfaces_of_many_hits_of_every_kind_equal_the_single_ray_records() {
    // Packets aimed into a dense scene, so that every kind is hit often.
    let g = random_scene(7, 3000, false);
    let bvh = Bvh::build(&g);
    let mut kinds = [0; 3];
    for k in 0..300 {
        let a = k as f32 * 0.37;
        let origin = [(a * 1.7).sin() * 3.0, (a * 2.3).cos() * 3.0, (a * 0.7).sin() * 3.0];
        let dir = [a.sin(), a.cos(), (a * 1.3).cos()];
        let jitter: Vec<[f32; 6]> =
            (0..LANES).map(|i| [0.0, 0.0, 0.0, (i % 4) as f32 - 1.5, (i / 4) as f32 - 1.5, 0.5]).collect();
        let p = rays(&g, &bvh, (origin, dir), 0.5, &jitter, 0xffff);
        for isa in Isa::available() {
            let found = check_surfaces(&g, &bvh, &p, isa);
            if isa == Isa::Portable {
                (0..3).for_each(|j| kinds[j] += found[j]);
            }
        }
    }
    assert!(kinds.iter().all(|&n| n > 200), "too few hits of some kind (sphere, triangle, other): {kinds:?}");
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 64, ..ProptestConfig::default() })]

    /// The mirror and refracted rays set up lane-wise are the rays
    /// `Whitted::spawn` sets up alone, bit for bit: directions (the mirror
    /// about the shading normal unless it dives below the surface), which
    /// lanes refract, and both origins.
    #[test]
    fn bounces_set_up_lane_wise_equal_the_scalar_setup(
        hits in prop::collection::vec((prop::array::uniform3(-3.0f32..3.0), prop::array::uniform3(-1.0f32..1.0), prop::array::uniform3(-0.3f32..0.3), prop::array::uniform3(-1.0f32..1.0), 0.4f32..2.5), LANES),
        tiny in any::<bool>(),
        want in any::<u16>(),
    ) {
        use nffkit_tracer::bounce_lanes::{bounces, BounceLanes};
        use nffkit_tracer::packet::lane;
        use nffkit_tracer::math::{offset_ray_origin, reflect, refract};
        use nffkit_tracer::packet::Lanes;
        use nffkit_tracer::shadow_lanes::PointLanes;
        let mut at = PointLanes::default();
        let (mut d, mut eta) = ([Lanes([0.0; LANES]); 3], Lanes([0.0; LANES]));
        let mut scalar = Vec::new();
        for (i, &(p, ng, tilt, dir, e)) in hits.iter().enumerate() {
            // Points near the origin (the offsets' float branch) too; the
            // normals face the ray, the shading normal tilted off the
            // geometric one as a patch's is.
            let p = Vec3A::from(p) * if tiny { 1e-3 } else { 1.0 };
            let ng = Vec3A::from(ng).normalize_or(Vec3A::Z);
            let ns = (ng + Vec3A::from(tilt)).normalize_or(ng);
            let mut dir = Vec3A::from(dir).normalize_or(-Vec3A::Z);
            if dir.dot(ng) > 0.0 { dir = -dir; }
            for a in 0..3 {
                (at.p[a].0[i], at.ng[a].0[i], at.ns[a].0[i], d[a].0[i]) = (p[a], ng[a], ns[a], dir[a]);
            }
            eta.0[i] = e;
            let r = reflect(dir, ns);
            let mirror = if r.dot(ng) > 0.0 { r } else { reflect(dir, ng) };
            let refracted = refract(dir, ns, e).filter(|t| t.dot(ng) < 0.0);
            scalar.push((offset_ray_origin(p, ng), mirror, offset_ray_origin(p, -ng), refracted));
        }
        let bits = |v: Vec3A| v.to_array().map(f32::to_bits);
        let want = u32::from(want);
        for isa in Isa::available() {
            let mut b = BounceLanes::default();
            bounces(isa, &at, &d, &eta, want, &mut b);
            prop_assert_eq!(b.refracts & !want, 0);
            for (i, (mo, md, ro, t)) in scalar.iter().enumerate().filter(|(i, _)| want >> i & 1 != 0) {
                prop_assert_eq!(bits(lane(&b.mirror_o, i)), bits(*mo), "{} lane {} mirror origin", isa, i);
                prop_assert_eq!(bits(lane(&b.mirror_d, i)), bits(*md), "{} lane {} mirror", isa, i);
                prop_assert_eq!(b.refracts >> i & 1 != 0, t.is_some(), "{} lane {} refracts", isa, i);
                if let Some(t) = t {
                    prop_assert_eq!(bits(lane(&b.refract_o, i)), bits(*ro), "{} lane {} refracted origin", isa, i);
                    prop_assert_eq!(bits(lane(&b.refract_d, i)), bits(*t), "{} lane {} refracted", isa, i);
                }
            }
        }
    }
}

/// The scalar setup of a shadow ray (`Whitted::light_ray`): the light
/// direction, N·L, and the ray's query and length, or where it stops.
fn scalar_shadow_ray(
    p: Vec3A,
    ng: Vec3A,
    ns: Vec3A,
    pos: Vec3A,
) -> (bool, Option<(Vec3A, f32, RayQuery, f32)>) {
    let to_light = pos - p;
    let dist = to_light.length();
    if dist == 0.0 {
        return (false, None);
    }
    let l = to_light / dist;
    let n_dot_l = ns.dot(l);
    if n_dot_l <= 0.0 {
        return (false, None);
    }
    let side = if ng.dot(l) >= 0.0 { ng } else { -ng };
    let ray = nffkit_tracer::math::shadow_ray(p, pos, side);
    (true, ray.map(|(ray, max)| (l, n_dot_l, RayQuery::new(ray, 0.0), max)))
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 64, ..ProptestConfig::default() })]

    #[test]
    fn shadow_rays_set_up_lane_wise_equal_the_scalar_setup(
        points in prop::collection::vec((prop::array::uniform3(-3.0f32..3.0), prop::array::uniform3(-1.0f32..1.0), prop::array::uniform3(-1.0f32..1.0)), LANES),
        light in prop::array::uniform3(-4.0f32..4.0),
        tiny in any::<bool>(),
        valid in any::<u16>(),
    ) {
        use nffkit_tracer::packet::Lanes;
        use nffkit_tracer::shadow_lanes::{shadow_rays, LightLanes, PointLanes};
        let mut at = PointLanes::default();
        let mut pos = [Lanes([0.0; LANES]); 3];
        let mut scalar = Vec::new();
        for (i, (p, ng, ns)) in points.iter().enumerate() {
            // Near the origin (the offsets' float branch), exactly on the
            // light, and negative zeros, besides ordinary points.
            let scale = if tiny { 1e-3 } else { 1.0 };
            let mut p = Vec3A::from(*p) * scale;
            if i == 3 { p = Vec3A::new(-0.0, 0.0, -0.0); }
            let l = if i == 5 { p } else { Vec3A::from(light) };
            let (ng, ns) = (Vec3A::from(*ng).normalize_or(Vec3A::Z), Vec3A::from(*ns).normalize_or(Vec3A::Z));
            for a in 0..3 {
                (at.p[a].0[i], at.ng[a].0[i], at.ns[a].0[i], pos[a].0[i]) = (p[a], ng[a], ns[a], l[a]);
            }
            scalar.push(scalar_shadow_ray(p, ng, ns, l));
        }
        for isa in Isa::available() {
            let mut packet = RayPacket::new(std::iter::empty());
            let mut dirs = LightLanes::default();
            let valid = u32::from(valid);
            let lanes = shadow_rays(isa, &at, &pos, valid, &mut packet, &mut dirs);
            for (i, (counted, ray)) in scalar.iter().enumerate() {
                let on = valid >> i & 1 != 0;
                prop_assert_eq!(lanes.counted >> i & 1 != 0, on && *counted, "{} lane {} counted", isa, i);
                prop_assert_eq!(lanes.rays >> i & 1 != 0, on && ray.is_some(), "{} lane {} ray", isa, i);
                prop_assert_eq!(packet.active, lanes.rays);
                let (Some((l, n_dot_l, q, max)), true) = (ray, on) else { continue };
                let got = packet.query(i);
                let bits = |v: Vec3A| v.to_array().map(f32::to_bits);
                prop_assert_eq!(bits(got.ray.o), bits(q.ray.o), "{} lane {} origin", isa, i);
                prop_assert_eq!(bits(got.ray.d), bits(q.ray.d));
                prop_assert_eq!(bits(got.inv_d), bits(q.inv_d));
                prop_assert_eq!(bits(got.shear), bits(q.shear));
                prop_assert_eq!((got.neg, got.k, got.t_min), (q.neg, q.k, q.t_min));
                prop_assert_eq!(packet.t_max.0[i].to_bits(), max.to_bits());
                prop_assert_eq!(bits(nffkit_tracer::packet::lane(&dirs.l, i)), bits(*l));
                prop_assert_eq!(dirs.n_dot_l.0[i].to_bits(), n_dot_l.to_bits());
            }
        }
    }
}

proptest! {
    #[test]
    fn packets_built_from_rays_hold_the_queries_of_the_rays(
        rays in prop::collection::vec((prop::array::uniform3(-5.0f32..5.0), prop::array::uniform3(-1.0f32..1.0), 0.0f32..1.0), 1..=LANES),
        axis in 0usize..4,
    ) {
        // Some directions along an axis, with negative zeros beside.
        let rays: Vec<(Ray, f32, f32)> = rays
            .iter()
            .enumerate()
            .filter_map(|(i, &(o, d, t_min))| {
                let mut d = Vec3A::from(d);
                if i % 3 == 0 && axis < 3 {
                    d = Vec3A::from(std::array::from_fn::<f32, 3, _>(|a| if a == axis { -1.0 } else { -0.0 }));
                }
                (d.length() > 1e-3).then(|| (Ray::new(Vec3A::from(o), d), t_min, 10.0))
            })
            .collect();
        let p = RayPacket::new(rays.iter().copied());
        prop_assert_eq!(p.len(), rays.len());
        let bits = |v: Vec3A| v.to_array().map(f32::to_bits);
        for (i, &(ray, t_min, t_max)) in rays.iter().enumerate() {
            let (got, want) = (p.query(i), RayQuery::new(ray, t_min));
            prop_assert_eq!(bits(got.inv_d), bits(want.inv_d));
            prop_assert_eq!(bits(got.shear), bits(want.shear));
            prop_assert_eq!((got.neg, got.k, got.t_min.to_bits()), (want.neg, want.k, want.t_min.to_bits()));
            prop_assert_eq!((bits(got.ray.o), bits(got.ray.d)), (bits(want.ray.o), bits(want.ray.d)));
            prop_assert_eq!(p.t_max.0[i], t_max);
        }
        let ks: Vec<_> = rays.iter().map(|&(r, t, _)| RayQuery::new(r, t).k).collect();
        prop_assert_eq!(p.shared_k, ks.iter().all(|k| *k == ks[0]).then_some(ks[0]));
    }
}
