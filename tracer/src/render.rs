//! The render loop: square tiles over all cores (rayon), each pixel a pure
//! function of its coordinates, so the image is the same for any thread count
//! and tile order. Counters are per tile and summed afterwards.

use crate::accel::{with_accel, Intersector, Tracer};
use crate::camera::Camera;
use crate::film::Film;
use crate::filter::{Filter, FilterKind};
pub use crate::integrator::ShadeSettings;
use crate::integrator::{EyeChunk, SampleId, ThreadState, Whitted};
use crate::packet::camera::EyeLanes;
use crate::prepare::RenderScene;
use crate::sampling::{concentric_disk, Sampler, SamplerKind};
use crate::shadow_cache::ShadowCache;
use crate::simd::lanes::LANES;
use crate::stats::Counters;
use crate::stopwatch::Stopwatch;
use glam::{Vec2, Vec3A};
use rayon::prelude::*;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Mutex, PoisonError};

/// Tile side in pixels.
pub const TILE: u32 = 16;

/// How to render.
#[derive(Debug, Clone)]
pub struct RenderSettings {
    /// Samples per pixel and their pattern. With one sample and
    /// `centre_single_sample`, the sample is the pixel centre (classic NFF).
    pub sampler: Sampler,
    /// Use the pixel centre when there is a single sample per pixel.
    pub centre_single_sample: bool,
    /// Reconstruction filter.
    pub filter: FilterKind,
    /// The shader's settings: depth, area lights, the weight below which
    /// rays are not traced, and the SPD testing procedure (which also
    /// traces one eye ray through each pixel corner, averaged per pixel).
    pub shade: ShadeSettings,
    /// Record traversal work per pixel.
    pub cost: bool,
    /// Test each light's last occluder first (see [`crate::shadow_cache`]);
    /// the image is the same either way.
    pub shadow_cache: bool,
    /// Trace coherent eye rays (a pixel's samples, or 4x4 pixel centres)
    /// and their shadow rays as SIMD packets (see `crate::packet`); the
    /// image is the same either way. Work-per-pixel images (`cost`) are
    /// always made ray by ray.
    pub packets: bool,
    /// Render only every n-th row (1: all), leaving the others black; for
    /// estimating the time of very slow renders from a subset of pixels.
    pub row_stride: u32,
    /// Render only these pixels of the image (a part for a render farm);
    /// `None` is the whole image. Each pixel is a pure function of its
    /// coordinates, so a part equals the same pixels of a full render.
    pub window: Option<PixelWindow>,
}

/// A rectangle of pixels: columns `x0..x1`, rows `y0..y1` (ends exclusive).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct PixelWindow {
    /// First column.
    pub x0: u32,
    /// One past the last column.
    pub x1: u32,
    /// First row.
    pub y0: u32,
    /// One past the last row.
    pub y1: u32,
}

impl PixelWindow {
    /// The whole image.
    pub fn full(width: u32, height: u32) -> PixelWindow {
        PixelWindow { x0: 0, x1: width, y0: 0, y1: height }
    }

    /// Width in pixels.
    pub fn width(&self) -> u32 {
        self.x1 - self.x0
    }

    /// Height in pixels.
    pub fn height(&self) -> u32 {
        self.y1 - self.y0
    }
}

impl Default for RenderSettings {
    fn default() -> Self {
        RenderSettings {
            sampler: Sampler::new(SamplerKind::MultiJittered, 1, 0).0,
            centre_single_sample: true,
            filter: FilterKind::Box,
            shade: ShadeSettings::default(),
            cost: false,
            shadow_cache: true,
            packets: true,
            row_stride: 1,
            window: None,
        }
    }
}

impl RenderSettings {
    /// The pixels to render of a `w` x `h` image: the window,
    /// cut to the image where it reaches past it (callers check), or the
    /// whole image.
    pub fn pixel_window(&self, w: u32, h: u32) -> PixelWindow {
        self.window.map_or(PixelWindow::full(w, h), |v| PixelWindow {
            x0: v.x0.min(w),
            x1: v.x1.clamp(v.x0.min(w), w),
            y0: v.y0.min(h),
            y1: v.y1.clamp(v.y0.min(h), h),
        })
    }

    /// Whether each pixel takes the one classic NFF eye ray through its
    /// centre: one sample, no pattern asked for, a pinhole camera.
    pub fn pixel_centre_only(&self, camera: &Camera) -> bool {
        self.sampler.spp == 1 && self.centre_single_sample && camera.aperture == 0.0
    }

    /// How the eye rays are placed, for reports: "1 ray through each pixel
    /// centre", "16 spp multi-jittered, filter box", or the SPD procedure.
    pub fn describe_sampling(&self, camera: &Camera) -> String {
        if self.shade.spd {
            "SPD test procedure (pixel corners)".into()
        } else if self.pixel_centre_only(camera) {
            "1 ray through each pixel centre".into()
        } else {
            format!("{} spp {}, filter {}", self.sampler.spp, self.sampler.kind, self.filter)
        }
    }
}

/// What a render produced.
#[derive(Debug, Clone)]
pub struct RenderOutput {
    /// The image.
    pub film: Film,
    /// Traversal work per pixel, when asked for.
    pub cost: Option<Vec<u64>>,
    /// Summed counters.
    pub counters: Counters,
    /// Wall time of the render loop.
    pub seconds: f64,
}

/// Called with (tiles done, tiles in all) as tiles finish.
pub type Progress<'a> = &'a (dyn Fn(usize, usize) + Sync);

/// Render `scene`.
pub fn render(scene: &RenderScene, settings: &RenderSettings, progress: Progress) -> RenderOutput {
    with_accel!(&scene.accel, a => render_with(scene, a, settings, progress))
}

/// The points a render evaluates: `width` x `height` of them, starting at
/// (`x0`, `y0`).
struct Raster {
    x0: u32,
    y0: u32,
    width: u32,
    height: u32,
}

fn render_with<I: Intersector>(
    scene: &RenderScene,
    accel: &I,
    settings: &RenderSettings,
    progress: Progress,
) -> RenderOutput {
    let t0 = Stopwatch::start();
    let (w, h) = scene.camera.resolution();
    let shader = Whitted { scene, sampler: &settings.sampler, settings: settings.shade };
    let filter = Filter::new(settings.filter);
    let out = if settings.shade.spd {
        // (w+1) x (h+1) corner rays, each pixel the mean of its four corners.
        let grid = Raster { x0: 0, y0: 0, width: w + 1, height: h + 1 };
        let (corners, cost, counters) = run_tiles(&grid, accel, scene, settings, progress, |pts, th, out| {
            eye_rays(&shader, settings, pts, th, out, |x, y| Vec2::new(x as f32, y as f32))
        });
        let mut film = Film::new(w, h);
        for y in 0..h {
            for x in 0..w {
                let c = |dx, dy| corners[((y + dy) * (w + 1) + x + dx) as usize];
                film.pixels[(y * w + x) as usize] = (c(0, 0) + c(1, 0) + c(0, 1) + c(1, 1)) * 0.25;
            }
        }
        let cost =
            cost.map(|c| (0..w * h).map(|i| c[((i / w) * (w + 1) + i % w) as usize]).collect::<Vec<_>>());
        RenderOutput { film, cost, counters, seconds: 0.0 }
    } else {
        let win = settings.pixel_window(w, h);
        let grid = Raster { x0: win.x0, y0: win.y0, width: win.width(), height: win.height() };
        let stride = settings.row_stride.max(1);
        let (pixels, cost, counters) = run_tiles(&grid, accel, scene, settings, progress, |pts, th, out| {
            if stride > 1 {
                // Skipped rows stay black; the rest go one by one.
                for (pt, o) in pts.iter().zip(out.iter_mut()) {
                    if pt.1.is_multiple_of(stride) {
                        pixels(
                            &shader,
                            &filter,
                            settings,
                            std::slice::from_ref(pt),
                            th,
                            std::slice::from_mut(o),
                        );
                    }
                }
            } else {
                pixels(&shader, &filter, settings, pts, th, out);
            }
        });
        RenderOutput {
            film: Film { width: grid.width, height: grid.height, pixels },
            cost,
            counters,
            seconds: 0.0,
        }
    };
    RenderOutput { seconds: t0.seconds(), ..out }
}

/// Radiance along `count` chunks of up to [`LANES`] eye rays:
/// `aim(c, chunk)` aims chunk `c`, and `take(c, weights, colours)` gets
/// its lanes' filter weights and colours, chunk after chunk in order. With
/// packets on, the chunks go in waves ([`Whitted::trace_waves`]), else ray
/// by ray. The colours are the same either way.
pub(crate) fn trace_chunks<I: Intersector>(
    shader: &Whitted,
    settings: &RenderSettings,
    count: usize,
    th: &mut ThreadState<I>,
    mut aim: impl FnMut(usize, &mut EyeChunk),
    mut take: impl FnMut(usize, &[f32], &[Vec3A]),
) {
    if settings.packets {
        shader.trace_waves(count, th, aim, take);
        return;
    }
    let mut chunk = EyeChunk::default();
    let mut colors = [Vec3A::ZERO; LANES];
    for c in 0..count {
        aim(c, &mut chunk);
        let n = chunk.n.min(LANES);
        th.tracer.counters.eye += n as u64;
        shader.li_eyes_by_ray(&chunk, th, &mut colors[..n]);
        take(c, &chunk.weights[..n], &colors[..n]);
    }
}

/// One eye ray per point of `pts`, through the raster position `raster`
/// gives it (with the lens centre), its colour to `out`; [`LANES`]
/// neighbouring points a chunk.
#[inline]
fn eye_rays<I: Intersector>(
    shader: &Whitted,
    settings: &RenderSettings,
    pts: &[(u32, u32)],
    th: &mut ThreadState<I>,
    out: &mut [Vec3A],
    raster: impl Fn(u32, u32) -> Vec2,
) {
    let aim = |c: usize, chunk: &mut EyeChunk| {
        let of_chunk = &pts[c * LANES..((c + 1) * LANES).min(pts.len())];
        for (i, &(px, py)) in of_chunk.iter().enumerate() {
            chunk.ids[i] = SampleId { px, py, index: 0 };
            chunk.eye.set(i, raster(px, py), Vec2::ZERO);
        }
        chunk.n = of_chunk.len();
    };
    let take = |c: usize, _: &[f32], colors: &[Vec3A]| {
        out[c * LANES..c * LANES + colors.len()].copy_from_slice(colors);
    };
    trace_chunks(shader, settings, pts.len().div_ceil(LANES), th, aim, take);
}

/// The pixels `pts`, each its samples through the filter, weighted by the
/// filter's sign, its colour to `out`. A pixel's samples go [`LANES`] to a
/// chunk, and its sum is taken in sample order.
fn pixels<I: Intersector>(
    shader: &Whitted,
    filter: &Filter,
    settings: &RenderSettings,
    pts: &[(u32, u32)],
    th: &mut ThreadState<I>,
    out: &mut [Vec3A],
) {
    let camera = &shader.scene.camera;
    if settings.pixel_centre_only(camera) {
        eye_rays(shader, settings, pts, th, out, |x, y| Vec2::new(x as f32 + 0.5, y as f32 + 0.5));
        return;
    }
    let sampler = &settings.sampler;
    let per_pixel = (sampler.spp as usize).div_ceil(LANES);
    // The pixel last aimed, with its patterns.
    let mut aiming: Option<(usize, PixelSamples)> = None;
    let aim = |c: usize, chunk: &mut EyeChunk| {
        let (p, first) = (c / per_pixel, (c % per_pixel * LANES) as u32);
        let (px, py) = pts[p];
        let (_, samples) = match &mut aiming {
            Some(last) if last.0 == p => last,
            slot => slot.insert((p, PixelSamples::new(camera, sampler, filter, px, py))),
        };
        let n = (sampler.spp - first).min(LANES as u32) as usize;
        for (i, id) in chunk.ids[..n].iter_mut().enumerate() {
            *id = SampleId { px, py, index: first + i as u32 };
        }
        samples.points(first, &mut chunk.eye, &mut chunk.weights[..n]);
        chunk.n = n;
    };
    let (mut sum, mut weights) = (Vec3A::ZERO, 0.0);
    let take = |c: usize, w: &[f32], colors: &[Vec3A]| {
        for (&w, &color) in w.iter().zip(colors) {
            sum += w * color;
            weights += w;
        }
        if c % per_pixel == per_pixel - 1 {
            out[c / per_pixel] = resolve(sum, weights, sampler.spp);
            (sum, weights) = (Vec3A::ZERO, 0.0);
        }
    };
    trace_chunks(shader, settings, pts.len() * per_pixel, th, aim, take);
}

/// The eye rays of one pixel's samples: its patterns computed once (a
/// pinhole camera ignores the lens sample).
pub(crate) struct PixelSamples<'a> {
    sampler: &'a Sampler,
    filter: &'a Filter,
    position: u32,
    lens: Option<u32>,
    px: u32,
    py: u32,
}

impl<'a> PixelSamples<'a> {
    #[inline]
    pub(crate) fn new(
        camera: &'a Camera,
        sampler: &'a Sampler,
        filter: &'a Filter,
        px: u32,
        py: u32,
    ) -> Self {
        let position = sampler.pattern(px, py, 0);
        let lens = (camera.aperture > 0.0).then(|| sampler.pattern(px, py, 1));
        PixelSamples { sampler, filter, position, lens, px, py }
    }

    /// Sample `index`'s raster point, point on the unit lens disc and
    /// filter weight ([`PixelSamples::points`] of one sample).
    #[inline]
    pub(crate) fn point(&self, index: u32) -> (Vec2, Vec2, f32) {
        let lens = self.lens.map_or(Vec2::ZERO, |p| self.sampler.sample_of(p, index));
        self.point_from(self.sampler.sample_of(self.position, index), lens)
    }

    /// Where the eye rays of samples `first..first + weights.len()` (at
    /// most [`LANES`]) are aimed, their patterns' samples made together:
    /// raster and lens points in `eye`, lane by lane, and their filter
    /// weights in `weights`.
    #[inline]
    pub(crate) fn points(&self, first: u32, eye: &mut EyeLanes, weights: &mut [f32]) {
        let n = weights.len();
        let (mut position, mut lens) = ([Vec2::ZERO; LANES], [Vec2::ZERO; LANES]);
        self.sampler.samples_of(self.position, first, &mut position[..n]);
        if let Some(p) = self.lens {
            self.sampler.samples_of(p, first, &mut lens[..n]);
        }
        for (i, w) in weights.iter_mut().enumerate() {
            let (raster, on_lens, weight) = self.point_from(position[i], lens[i]);
            eye.set(i, raster, on_lens);
            *w = weight;
        }
    }

    /// The raster point, the point on the unit lens disc and the filter
    /// weight of a pixel sample `u` and a lens sample `l`.
    #[inline(always)]
    fn point_from(&self, u: Vec2, l: Vec2) -> (Vec2, Vec2, f32) {
        let (offset, weight) = self.filter.sample(u);
        let lens = if self.lens.is_some() { concentric_disk(l) } else { Vec2::ZERO };
        let (x, y) = (self.px as f32 + 0.5 + offset.x, self.py as f32 + 0.5 + offset.y);
        (Vec2::new(x, y), lens, weight)
    }
}

/// A pixel's colour from its samples' filter-weighted sum: divided by the
/// weights, or by the sample count where negative lobes (Mitchell) leave
/// too little weight to divide by.
#[inline]
pub(crate) fn resolve(sum: Vec3A, weights: f32, spp: u32) -> Vec3A {
    if weights > 0.5 {
        sum / weights
    } else {
        sum / spp as f32
    }
}

/// What the tiles write into as they finish: the whole raster's colours,
/// their costs when asked for, and the counts.
struct Canvas {
    pixels: Vec<Vec3A>,
    cost: Vec<u64>,
    counters: Counters,
}

/// Side of the pixel blocks a tile's points are ordered in when packets
/// are on: 4x4 fills one packet of [`LANES`] pixel-centre rays.
const BLOCK: u32 = 4;
const _: () = assert!((BLOCK * BLOCK) as usize == LANES);

/// Evaluate `f` at every point of `grid`, tile by tile on all cores: a
/// tile's points at once (in 4x4 blocks with packets, row by row without;
/// `f` fills one colour per point), or with `want_cost` one point at a
/// time, recording the traversal work each took.
fn run_tiles<I: Intersector>(
    grid: &Raster,
    accel: &I,
    scene: &RenderScene,
    settings: &RenderSettings,
    progress: Progress,
    f: impl Fn(&[(u32, u32)], &mut ThreadState<I>, &mut [Vec3A]) + Sync,
) -> (Vec<Vec3A>, Option<Vec<u64>>, Counters) {
    let block = if settings.packets && !settings.cost { BLOCK } else { 1 };
    let want_cost = settings.cost;
    let (max_depth, shadow_cache) = (settings.shade.max_depth, settings.shadow_cache);
    let tiles_x = grid.width.div_ceil(TILE);
    let tiles_y = grid.height.div_ceil(TILE);
    let total = (tiles_x * tiles_y) as usize;
    let done = AtomicUsize::new(0);
    // Each tile's colours go straight into the raster's (a few hundred
    // stores under a lock no other tile holds for long), so the tiles'
    // own buffers are freed and reused as they finish.
    let n = (grid.width * grid.height) as usize;
    let canvas = Mutex::new(Canvas {
        pixels: vec![Vec3A::ZERO; n],
        cost: if want_cost { vec![0; n] } else { Vec::new() },
        counters: Counters::default(),
    });
    (0..tiles_x * tiles_y)
        .into_par_iter()
        // One tile per job, so an idle thread can always take the next
        // (rayon otherwise cuts the range into a few long runs, and a run of
        // costly tiles leaves one thread working alone); the thread state is
        // then made per tile, a few small allocations per 256 pixels.
        .with_max_len(1)
        .for_each_init(
            || ThreadState {
                tracer: Tracer::new(accel, &scene.geometry),
                shadow_cache: ShadowCache::new(scene.lights.len(), max_depth, shadow_cache),
            },
            |th, tile| {
                th.shadow_cache.clear();
                let (tx, ty) = (tile % tiles_x * TILE, tile / tiles_x * TILE);
                let (x1, y1) = ((tx + TILE).min(grid.width), (ty + TILE).min(grid.height));
                // The tile's points, 4x4 blocks one after another with
                // packets (so that each chunk of LANES pixel centres is a
                // block), else row by row.
                let mut pts = Vec::with_capacity(((x1 - tx) * (y1 - ty)) as usize);
                for by in (ty..y1).step_by(block as usize) {
                    for bx in (tx..x1).step_by(block as usize) {
                        for y in by..(by + block).min(y1) {
                            pts.extend((bx..(bx + block).min(x1)).map(|x| (grid.x0 + x, grid.y0 + y)));
                        }
                    }
                }
                let mut colors = vec![Vec3A::ZERO; pts.len()];
                let mut costs = vec![0u64; if want_cost { pts.len() } else { 0 }];
                if want_cost {
                    for (k, &pt) in pts.iter().enumerate() {
                        let work = th.tracer.counters.work();
                        f(&[pt], th, std::slice::from_mut(&mut colors[k]));
                        costs[k] = th.tracer.counters.work() - work;
                    }
                } else {
                    f(&pts, th, &mut colors);
                }
                // Each tile takes its thread's counters, leaving them zeroed.
                let tile_counters = std::mem::take(&mut th.tracer.counters);
                let at = |(x, y): (u32, u32)| {
                    (y - grid.y0) as usize * grid.width as usize + (x - grid.x0) as usize
                };
                {
                    let mut c = canvas.lock().unwrap_or_else(PoisonError::into_inner);
                    for (&pt, &color) in pts.iter().zip(&colors) {
                        c.pixels[at(pt)] = color;
                    }
                    // (No costs unless asked for.)
                    for (&pt, &cost) in pts.iter().zip(&costs) {
                        c.cost[at(pt)] = cost;
                    }
                    c.counters += tile_counters;
                }
                let n = done.fetch_add(1, Ordering::Relaxed) + 1;
                progress(n, total);
            },
        );
    let Canvas { pixels, cost, counters } = canvas.into_inner().unwrap_or_else(PoisonError::into_inner);
    (pixels, want_cost.then_some(cost), counters)
}
