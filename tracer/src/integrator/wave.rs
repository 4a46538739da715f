//! A batch of eye rays traced as a wave. Packets are traced depth first,
//! as ever, while their spawned rays stay together; but the rays of a kind
//! that only a few lanes of a packet spawn (curved mirrors scatter a packet
//! within a bounce or two) are deferred. Once the batch's eye packets are
//! traced, the deferred rays are traced depth by depth: sorted by direction
//! octant and by where they start, and packed [`LANES`] at a time with the
//! rays that other packets deferred.
//!
//! A ray whose colour waits on a deferred ray becomes a node of the wave:
//! its colour summed so far, the factor its parent sees it through
//! (share × tint), and a child node for each later kind of spawned ray (a
//! leaf holding the child's radiance where that is known at once). Once
//! every deferred ray has been traced, the nodes are resolved depth by
//! depth from the deepest up, each adding its kinds in order: a child is
//! one depth below its parent, so its radiance is resolved before it is
//! added. These are the sums [`Whitted::li`] makes, in the same order, on
//! the same values, so every colour is bit for bit the one the ray-by-ray
//! path gives. (Within a depth no node waits on another's result, so the
//! reads of their children do not form one chain.)

use super::packet::LaneRadiance;
use super::{SampleId, ThreadState, Whitted};
use crate::accel::Intersector;
use crate::math::Ray;
use crate::packet::camera::EyeLanes;
use crate::packet::RayPacket;
use crate::simd::lanes::{first_lanes, set_lane, Lanes, LANES};
use glam::Vec3A;

/// Nodes a wave may hold before it defers no more rays: past it,
/// scattered rays are traced at once, as small packets, so that a deep ray
/// tree (a large `--depth` through glass) needs bounded memory (with the
/// deferred rays and the orders they are kept in, about 8 MB a thread).
/// balls_s4, mount_s7 and gears_s4 at 16 spp and mount_s7 at 64 spp need
/// at most 32,078. The tests' scenes are small: they reach a smaller cap.
const MAX_NODES: usize = if cfg!(test) { 2048 } else { 1 << 16 };

/// A node index meaning none (no node, no child of that kind).
pub(super) const NO_NODE: u32 = u32::MAX;

/// The index bits of a [`Wave::order`] entry.
const INDEX_MASK: u64 = (1 << 31) - 1;

/// Eye rays per wave: a wave closes once it holds at least this many.
const WAVE_EYE_RAYS: usize = 4096;

/// A ray whose colour waits on deferred rays.
#[derive(Debug, Clone, Copy)]
struct Node {
    /// Its colour summed so far; after [`Wave::resolve`], its radiance.
    color: Vec3A,
    /// What its parent sees its radiance through: share × tint.
    factor: Vec3A,
    /// Each kind's child node, or [`NO_NODE`].
    child: [u32; 3],
}

/// A deferred ray waiting for its depth's turn.
#[derive(Debug, Clone, Copy)]
struct Pending {
    ray: Ray,
    depth: u32,
    weight: f32,
    id: SampleId,
    node: u32,
}

/// Up to [`LANES`] eye rays to trace in a wave: aimed lane by lane, of
/// which samples, and with which filter weights.
pub(crate) struct EyeChunk {
    /// Where each lane's eye ray goes.
    pub eye: EyeLanes,
    /// Each lane's sample.
    pub ids: [SampleId; LANES],
    /// Each lane's filter weight (given back with its colour).
    pub weights: [f32; LANES],
    /// How many lanes are used.
    pub n: usize,
}

impl Default for EyeChunk {
    fn default() -> Self {
        EyeChunk { eye: EyeLanes::default(), ids: [SampleId::default(); LANES], weights: [0.0; LANES], n: 0 }
    }
}

/// An eye chunk traced in the wave: its lanes' radiance and filter
/// weights, and how many lanes it has.
#[derive(Debug, Clone)]
struct Traced {
    radiance: LaneRadiance,
    weights: [f32; LANES],
    n: usize,
}

/// The deferred rays and nodes of one wave.
#[derive(Debug, Default)]
pub(crate) struct Wave {
    nodes: Vec<Node>,
    chunks: Vec<Traced>,
    /// The deferred rays, of every depth (one vector, so that its memory
    /// is bounded by the node cap, whatever the depths).
    deferred: Vec<Pending>,
    /// The deepest depth a ray was deferred to.
    deepest: u32,
    /// The order one depth's rays are traced in: key << 31 | index.
    order: Vec<u64>,
    /// The nodes of each depth (of the ray they stand for, from 1), in
    /// the order they were made. The lists keep their room from wave to
    /// wave, all together at most twice the node cap (past it they are
    /// dropped), so that a thread's memory stays bounded whatever the
    /// depths of its waves.
    by_depth: Vec<Vec<u32>>,
}

thread_local! {
    /// The thread's wave between two batches, kept for its memory.
    static SPARE: std::cell::Cell<Wave> = std::cell::Cell::new(Wave::default());
}

impl Wave {
    /// Room for a full wave, asked for once a thread: vectors grown by
    /// doubling copy themselves into fresh pages, each a fault on first
    /// touch, while room reserved and not yet used costs none.
    fn reserve(&mut self) {
        if self.nodes.capacity() < MAX_NODES {
            self.nodes.reserve_exact(MAX_NODES);
            self.deferred.reserve_exact(MAX_NODES);
            self.order.reserve_exact(MAX_NODES);
        }
    }

    /// Forget the last wave.
    fn clear(&mut self) {
        self.nodes.clear();
        self.chunks.clear();
        self.deferred.clear();
        self.deepest = 0;
        if self.by_depth.iter().map(Vec::capacity).sum::<usize>() > 2 * MAX_NODES {
            self.by_depth = Vec::new();
        }
        self.by_depth.iter_mut().for_each(Vec::clear);
    }

    /// A new node of colour `color` so far, for a ray at `depth` (from 1),
    /// its children not yet known.
    pub(super) fn add_node(&mut self, color: Vec3A, depth: u32) -> u32 {
        let node = self.nodes.len() as u32;
        self.nodes.push(Node { color, factor: Vec3A::ONE, child: [NO_NODE; 3] });
        let level = depth.saturating_sub(1) as usize;
        if self.by_depth.len() <= level {
            self.by_depth.resize_with(level + 1, Vec::new);
        }
        self.by_depth[level].push(node);
        node
    }

    /// Whether rays may still be deferred ([`MAX_NODES`]).
    #[inline]
    pub(super) fn has_room(&self) -> bool {
        self.nodes.len() < MAX_NODES
    }

    /// Set `node`'s colour so far.
    #[inline]
    pub(super) fn set_color(&mut self, node: u32, color: Vec3A) {
        self.nodes[node as usize].color = color;
    }

    /// `node`'s spawned ray of `kind` is the node `child`, seen through
    /// `factor`.
    #[inline]
    pub(super) fn link(&mut self, node: u32, kind: usize, child: u32, factor: Vec3A) {
        self.nodes[child as usize].factor = factor;
        self.nodes[node as usize].child[kind] = child;
    }

    /// Defer `ray`, spawned of `kind` by `node`, to `depth`: it carries
    /// `weight`, and `node` sees it through `factor`.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn defer(
        &mut self,
        node: u32,
        kind: usize,
        ray: Ray,
        depth: u32,
        weight: f32,
        factor: Vec3A,
        id: SampleId,
    ) {
        let child = self.add_node(Vec3A::ZERO, depth);
        self.link(node, kind, child, factor);
        self.deepest = self.deepest.max(depth);
        self.deferred.push(Pending { ray, depth, weight, id, node: child });
    }

    /// Sort the rays deferred to `depth` into `order` by octant and
    /// origin; false when there are none.
    fn regroup(&mut self, depth: u32) -> bool {
        self.order.clear();
        let level = || self.deferred.iter().enumerate().filter(move |(_, p)| p.depth == depth);
        let (mut lo, mut hi) = (Vec3A::INFINITY, Vec3A::NEG_INFINITY);
        for (_, p) in level() {
            (lo, hi) = (lo.min(p.ray.o), hi.max(p.ray.o));
        }
        let extent = hi - lo;
        let scale = Vec3A::select(extent.cmpgt(Vec3A::ZERO), 1023.0 / extent, Vec3A::ZERO);
        // Key above, index below: sorting the words sorts by key, ties in
        // index order.
        let order = level().map(|(i, p)| regroup_key(p.ray, lo, scale) << 31 | i as u64);
        self.order.extend(order);
        if self.order.is_empty() {
            return false;
        }
        self.order.sort_unstable();
        true
    }

    /// Every node's radiance: its colour so far plus each kind's
    /// contribution in order, the deepest nodes first (their children,
    /// one depth down, resolved before them).
    fn resolve(&mut self) {
        let nodes = &mut self.nodes;
        for level in self.by_depth.iter().rev() {
            for &node in level {
                let n = nodes[node as usize];
                let mut color = n.color;
                for c in n.child.into_iter().filter(|&c| c != NO_NODE) {
                    let child = &nodes[c as usize];
                    color += child.factor * child.color;
                }
                nodes[node as usize].color = color;
            }
        }
    }

    /// Lane `i`'s radiance in `r`, once resolved.
    fn radiance(&self, r: &LaneRadiance, i: usize) -> Vec3A {
        if r.waiting >> i & 1 != 0 {
            self.nodes[r.node[i] as usize].color
        } else {
            r.color[i]
        }
    }
}

/// Where a ray goes in its depth's order: its direction's octant, then the
/// Morton code of its origin quantized to 10 bits an axis over the depth's
/// origins (`lo`, and `scale` to 0..1023).
#[inline]
fn regroup_key(ray: Ray, lo: Vec3A, scale: Vec3A) -> u64 {
    let d = ray.d;
    let octant = u64::from(d.x < 0.0) | u64::from(d.y < 0.0) << 1 | u64::from(d.z < 0.0) << 2;
    // `as` saturates (NaN from an unbounded origin gives 0): any key will do
    // for such a ray, whose colour does not depend on its group.
    let q = ((ray.o - lo) * scale).to_array().map(|v| v as u32);
    octant << 30 | spread(q[0]) | spread(q[1]) << 1 | spread(q[2]) << 2
}

/// The low 10 bits of `v` spread to every third bit.
#[inline]
fn spread(v: u32) -> u64 {
    let mut x = u64::from(v & 0x3ff);
    x = (x | x << 16) & 0x0300_00ff;
    x = (x | x << 8) & 0x0300_f00f;
    x = (x | x << 4) & 0x030c_30c3;
    (x | x << 2) & 0x0924_9249
}

impl Whitted<'_> {
    /// Trace `count` eye chunks as waves of about [`WAVE_EYE_RAYS`] eye
    /// rays: `aim(c, chunk)` aims chunk `c`, and `take(c, weights,
    /// colours)` gets its lanes' filter weights and colours, chunk after
    /// chunk in order. Chunks of one ray are traced as single rays, the
    /// rest as packets; the colours are the same either way.
    pub(crate) fn trace_waves<I: Intersector>(
        &self,
        count: usize,
        th: &mut ThreadState<I>,
        mut aim: impl FnMut(usize, &mut EyeChunk),
        mut take: impl FnMut(usize, &[f32], &[Vec3A]),
    ) {
        let mut wave = SPARE.take();
        wave.reserve();
        let mut chunk = EyeChunk::default();
        let mut first = 0;
        while first < count {
            wave.clear();
            let (mut end, mut eyes) = (first, 0);
            while end < count && eyes < WAVE_EYE_RAYS {
                aim(end, &mut chunk);
                self.wave_eyes(&chunk, th, &mut wave);
                (end, eyes) = (end + 1, eyes + chunk.n);
            }
            self.finish_wave(th, &mut wave);
            for (c, t) in (first..end).zip(&wave.chunks) {
                let colors: [Vec3A; LANES] = std::array::from_fn(|i| wave.radiance(&t.radiance, i));
                take(c, &t.weights[..t.n], &colors[..t.n]);
            }
            first = end;
        }
        SPARE.set(wave);
    }

    /// Trace `chunk`'s eye rays into `wave`.
    fn wave_eyes<I: Intersector>(&self, chunk: &EyeChunk, th: &mut ThreadState<I>, wave: &mut Wave) {
        let n = chunk.n.min(LANES);
        th.tracer.counters.eye += n as u64;
        let mut radiance = LaneRadiance::default();
        if n == 1 {
            self.li_eyes_by_ray(chunk, th, &mut radiance.color[..1]);
        } else {
            self.li_eye_packet(&chunk.eye, &chunk.ids[..n], th, wave, &mut radiance);
        }
        wave.chunks.push(Traced { radiance, weights: chunk.weights, n });
    }

    /// Radiance along the eye rays of `chunk`'s first `out.len()` lanes,
    /// ray by ray, into `out`.
    pub(crate) fn li_eyes_by_ray<I: Intersector>(
        &self,
        chunk: &EyeChunk,
        th: &mut ThreadState<I>,
        out: &mut [Vec3A],
    ) {
        for (i, color) in out.iter_mut().enumerate() {
            let (ray, t_min) = chunk.eye.ray(i, &self.scene.camera);
            *color = self.li(ray, t_min, 1, 1.0, chunk.ids[i], th);
        }
    }

    /// Trace the wave's deferred rays depth by depth, regrouped, then
    /// resolve every node's radiance.
    fn finish_wave<I: Intersector>(&self, th: &mut ThreadState<I>, wave: &mut Wave) {
        let mut depth = 2;
        while depth <= wave.deepest {
            if wave.regroup(depth) {
                let order = std::mem::take(&mut wave.order);
                for group in order.chunks(LANES) {
                    let (mut o, mut d) = ([Lanes::ZERO; 3], [Lanes::ZERO; 3]);
                    let mut weights = Lanes::ZERO;
                    let mut ids = [SampleId::default(); LANES];
                    let mut radiance = LaneRadiance::default();
                    for (i, &k) in group.iter().enumerate() {
                        let p = &wave.deferred[(k & INDEX_MASK) as usize];
                        set_lane(&mut o, i, p.ray.o);
                        set_lane(&mut d, i, p.ray.d);
                        (weights.0[i], ids[i], radiance.node[i]) = (p.weight, p.id, p.node);
                        radiance.waiting |= 1 << i;
                    }
                    let packet = RayPacket::from_lanes(&o, &d, first_lanes(group.len()));
                    self.li_lanes(&packet, &weights, depth, &ids, th, wave, &mut radiance);
                }
                wave.order = order;
            }
            depth += 1;
        }
        wave.resolve();
    }
}

#[cfg(test)]
mod tests {
    use crate::prepare::{prepare, PrepareOptions};
    use crate::render::{render, RenderSettings};
    use crate::sampling::{Sampler, SamplerKind};
    use nffkit_formats::nff::{parse, ParseOptions};
    use std::fmt::Write;

    /// A heap of small mirror and glass balls over a floor: packets
    /// scatter within a bounce or two, and glass spawns two kinds of rays,
    /// so deferred rays and rays traced at once mix in one colour's sum.
    fn heap() -> String {
        let mut s = String::from(
            "v\nfrom 0 -5 3\nat 0 0 0.4\nup 0 0 1\nangle 35\nhither 0.01\nresolution 20 16\n\
             b 0.2 0.3 0.5\nl 3 -4 6\nl -3 -2 5\nf 0.9 0.9 0.9 0.8 0 1 0 1\n\
             p 4\n-5 -5 0\n5 -5 0\n5 5 0\n-5 5 0\n",
        );
        for i in 0..27 {
            let (x, y, z) = ((i % 3) as f32 - 1.0, (i / 3 % 3) as f32 - 1.0, (i / 9) as f32);
            let material = match i % 3 {
                0 => "f 1 0.8 0.6 0.3 0.6 20 0 1",
                1 => "f 0.8 0.9 1 0.1 0.4 30 0.8 1.5",
                _ => "f 0.6 0.6 0.6 0.2 0.3 10 0.5 1.33",
            };
            writeln!(s, "{material}\ns {} {} {} 0.42", x * 0.8, y * 0.8, 0.4 + z * 0.75).unwrap();
        }
        s
    }

    /// Every colour the waves give, with their deferred and regrouped
    /// rays, is bit for bit the ray-by-ray colour: at 1, 4 (chunks smaller
    /// than a packet) and 16 samples, with area lights, a lens, Fresnel
    /// glass, a weight cut-off, and the SPD's corner rays.
    #[test]
    fn waves_give_the_ray_by_ray_colours() {
        let scene = parse(heap().as_bytes(), &ParseOptions::default()).unwrap().scene;
        for (fresnel, aperture) in [(false, None), (true, None), (false, Some(0.2))] {
            let opts = PrepareOptions { fresnel, aperture, focus: Some(5.0), ..Default::default() };
            let prepared = prepare(&scene, &opts).unwrap();
            for (spp, light_size, min_weight, spd) in
                [(1, 0.0, 0.0, false), (4, 0.5, 0.0, false), (16, 0.0, 0.05, false), (1, 0.0, 0.0, true)]
            {
                let image = |packets: bool| {
                    let mut s = RenderSettings {
                        sampler: Sampler::new(SamplerKind::MultiJittered, spp, 7).0,
                        centre_single_sample: spp == 1,
                        packets,
                        ..Default::default()
                    };
                    (s.shade.light_size, s.shade.min_weight, s.shade.spd) = (light_size, min_weight, spd);
                    render(&prepared, &s, &|_, _| {})
                };
                let (waves, rays) = (image(true), image(false));
                let case = format!("spp {spp}, light {light_size}, min weight {min_weight}, spd {spd}");
                let case = format!("{case}, fresnel {fresnel}, lens {aperture:?}");
                assert_eq!(waves.film.pixels, rays.film.pixels, "{case}");
                assert_eq!(waves.counters.rays(), rays.counters.rays(), "{case}");
            }
        }
    }
}
