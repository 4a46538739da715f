//! What the benchmarks (`nffbench`, `raybench`) measure inside the tracer:
//! eye and shadow rays traced without shading, one by one and as packets,
//! on one thread. Eye rays are set up inside the timed loops, as Embree's
//! benchmark makes its rays; shadow rays, which need the eye rays' hits,
//! are set up before. Public for those binaries only (hidden from the docs):
//! it is the one door into the private core, so the core's types stay
//! private.

use crate::accel::{with_accel, Intersector, Tracer};
use crate::math::{shadow_ray, RayQuery};
use crate::packet::camera::{self, EyeLanes};
use crate::packet::{PacketHits, RayPacket};
use crate::prepare::RenderScene;
use crate::simd::lanes::first_lanes;
use glam::Vec2;
use std::time::Instant;

/// Per-thread ray throughput on one scene.
#[derive(Debug, Clone, Copy)]
pub struct RayRates {
    /// Eye rays per second on one thread, in millions.
    pub eye: f64,
    /// Eye rays that hit (to check against Embree's "primary hits").
    pub eye_hits: u64,
    /// Shadow rays per second on one thread, in millions.
    pub shadow: f64,
    /// Shadow rays traced (one per light per eye hit facing it).
    pub shadow_rays: u64,
    /// Eye rays per second on one thread as packets of 4x4 pixel centres
    /// (each set up lane-wise, as the renderer's eye packets), in millions.
    pub eye_packet: f64,
    /// Eye rays that hit, traced as packets (must equal `eye_hits`).
    pub eye_packet_hits: u64,
    /// Shadow rays per second as packets (16 neighbouring rays toward one
    /// light), in millions.
    pub shadow_packet: f64,
}

/// Best of `runs` timings of `f`, in seconds.
pub fn best_of(runs: u32, mut f: impl FnMut()) -> f64 {
    (0..runs.max(1))
        .map(|_| {
            let t0 = Instant::now();
            f();
            t0.elapsed().as_secs_f64()
        })
        .fold(f64::INFINITY, f64::min)
}

/// Eye and shadow rays of `scene` on the calling thread, best of `runs`.
pub fn ray_rates(scene: &RenderScene, runs: u32) -> RayRates {
    with_accel!(&scene.accel, acc => rates_with(scene, &mut Tracer::new(acc, &scene.geometry), runs))
}

/// The pixel-centre eye rays of `scene`'s camera, traced one by one on the
/// calling thread (nearest hit only, no shading): how many, and how many
/// hit.
pub fn eye_rays(scene: &RenderScene) -> (u64, u64) {
    with_accel!(&scene.accel, acc => {
        let mut tr = Tracer::new(acc, &scene.geometry);
        let (w, h) = scene.camera.resolution();
        (u64::from(w) * u64::from(h), eye_hits(scene, &mut tr))
    })
}

/// How many of the pixel-centre eye rays hit, traced one by one by `tr`:
/// hits are counted, not kept, as Embree's benchmark counts them. Each ray
/// is set up before the one ahead of it is traced, so that its square
/// root and divisions run beside that traversal rather than before its
/// own (the renderer sets up its eye rays sixteen at a time).
fn eye_hits<I: Intersector>(scene: &RenderScene, tr: &mut Tracer<I>) -> u64 {
    let mut queries = eye_queries(scene);
    let Some(mut q) = queries.next() else { return 0 };
    let mut hits = 0;
    loop {
        let next = queries.next();
        hits += u64::from(tr.nearest(&q, f32::INFINITY).is_some());
        let Some(n) = next else { return hits };
        q = n;
    }
}

/// The pixel-centre eye queries of `scene`'s camera, row by row, each
/// set up when it is asked for (as Embree's benchmark makes its rays).
fn eye_queries(scene: &RenderScene) -> impl Iterator<Item = RayQuery> + '_ {
    let (w, h) = scene.camera.resolution();
    (0..h).flat_map(move |y| (0..w).map(move |x| (x, y))).map(|(x, y)| {
        let (ray, t_min) = scene.camera.ray(x as f32 + 0.5, y as f32 + 0.5, Vec2::ZERO);
        RayQuery::new(ray, t_min)
    })
}

/// The 4x4 blocks of pixels of a `w` x `h` image, row by row: each
/// block's pixels, row by row (fewer at the right and bottom edges).
fn pixel_blocks(w: u32, h: u32) -> impl Iterator<Item = impl Iterator<Item = (u32, u32)>> {
    let corners = (0..h.div_ceil(4)).flat_map(move |by| (0..w.div_ceil(4)).map(move |bx| (bx * 4, by * 4)));
    corners.map(move |(x0, y0)| {
        (y0..(y0 + 4).min(h)).flat_map(move |y| (x0..(x0 + 4).min(w)).map(move |x| (x, y)))
    })
}

/// The eye packet of `pixels` (at most 16, lane by lane), aimed at their
/// centres through `lanes` and set up lane-wise by the renderer's own
/// kernel ([`camera::eye_rays`]) into `packet`.
fn eye_packet(
    scene: &RenderScene,
    pixels: impl Iterator<Item = (u32, u32)>,
    lanes: &mut EyeLanes,
    packet: &mut RayPacket,
) {
    let mut n = 0;
    for (x, y) in pixels {
        lanes.set(n, Vec2::new(x as f32 + 0.5, y as f32 + 0.5), Vec2::ZERO);
        n += 1;
    }
    camera::eye_rays(crate::simd::isa(), &scene.camera, lanes, first_lanes(n), packet);
}

fn rates_with<I: Intersector>(scene: &RenderScene, tr: &mut Tracer<I>, runs: u32) -> RayRates {
    let (w, h) = scene.camera.resolution();
    let geom = &scene.geometry;
    let eye_count = u64::from(w) * u64::from(h);
    let mut eye_hits = 0;
    let eye_s = best_of(runs, || {
        eye_hits = self::eye_hits(scene, tr);
    });
    // The shadow rays the shader would trace from each hit (shading normal
    // facing the light), built once and then timed alone: one by one, and
    // as the renderer packs them, per 4x4 block of pixels and per light.
    let mut shadow = Vec::new();
    let mut shadow_packets = Vec::new();
    let (mut eye_lanes, mut p) = (EyeLanes::default(), RayPacket::empty());
    for pixels in pixel_blocks(w, h) {
        eye_packet(scene, pixels, &mut eye_lanes, &mut p);
        let mut block_hits = PacketHits::new(&p);
        tr.nearest_packet(&p, &mut block_hits);
        for light in &scene.lights {
            let mut packet = RayPacket::empty();
            for i in 0..p.len() {
                let Some(hit) = block_hits.get(i) else { continue };
                let q = p.query(i);
                let s = geom.surface(&hit, &q);
                let n = if s.ng.dot(q.ray.d) < 0.0 { s.ng } else { -s.ng };
                if n.dot(light.position - s.p) <= 0.0 {
                    continue;
                }
                if let Some((ray, max)) = shadow_ray(s.p, light.position, n) {
                    let sq = RayQuery::new(ray, 0.0);
                    shadow.push((sq, max));
                    packet.set(i, sq, max);
                }
            }
            if !packet.is_empty() {
                shadow_packets.push(packet);
            }
        }
    }
    let mut blocked = 0;
    let shadow_s = best_of(runs, || {
        blocked = shadow.iter().filter(|(q, max)| tr.occluded(q, *max)).count();
    });
    std::hint::black_box(blocked);
    // The same eye rays as packets of 4x4 neighbouring pixels, each set up
    // lane-wise as the renderer sets up its eye packets, inside the timed
    // loop (as Embree's benchmark makes its packets).
    let mut packet_hits = 0;
    let mut packet = RayPacket::empty();
    let eye_packet_s = best_of(runs, || {
        packet_hits = 0;
        for pixels in pixel_blocks(w, h) {
            eye_packet(scene, pixels, &mut eye_lanes, &mut packet);
            let mut hits = PacketHits::new(&packet);
            tr.nearest_packet(&packet, &mut hits);
            packet_hits += u64::from(hits.found().count_ones());
        }
    });
    let shadow_packet_s = best_of(runs, || {
        blocked = 0;
        for p in &shadow_packets {
            blocked += tr.occluders_packet(p).found().count_ones() as usize;
        }
    });
    std::hint::black_box(blocked);
    RayRates {
        eye: eye_count as f64 / eye_s / 1e6,
        eye_hits,
        shadow: shadow.len() as f64 / shadow_s.max(1e-9) / 1e6,
        shadow_rays: shadow.len() as u64,
        eye_packet: eye_count as f64 / eye_packet_s / 1e6,
        eye_packet_hits: packet_hits,
        shadow_packet: shadow.len() as f64 / shadow_packet_s.max(1e-9) / 1e6,
    }
}
