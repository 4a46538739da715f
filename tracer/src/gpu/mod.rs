//! The GPU backend (`render --device gpu`): the same scene, camera,
//! samplers, filters, area lights, thin lens and Whitted shading as the CPU
//! path, traced by WGSL compute shaders through wgpu (Vulkan, Metal or
//! DX12), so a laptop's integrated GPU, a data-centre GPU without ray
//! tracing cores and a software Vulkan driver (lavapipe, in CI) all run it.
//!
//! The BVH is the CPU's: built by the same builder and uploaded as its
//! 4-wide nodes (`layout`). Each invocation renders one pixel, its samples
//! in order through the filter; each sample's tree of rays (mirror,
//! refracted) is walked depth first from an explicit stack, since shaders
//! cannot recurse. Samples are the CPU's: the samplers are pure functions of
//! pixel, index, dimension and seed, ported operation for operation, so the
//! images agree within floating-point differences (the GPU rounds divisions,
//! square roots and transcendentals its own way, decides triangle edges and
//! solves cones in single precision, and sums a pixel's rays in another
//! order).
//!
//! Work goes out in bands of rows, each a separate submission, so no single
//! dispatch runs long enough to trip a desktop's GPU watchdog, and progress
//! can be reported between bands.

mod layout;

use crate::aabb::{ENTRY_SLACK, SLAB_WIDEN};
use crate::film::Film;
use crate::math::gamma;
use crate::prepare::RenderScene;
use crate::render::{PixelWindow, Progress, RenderOutput, RenderSettings};
use crate::stats::Counters;
use crate::stopwatch::Stopwatch;
use glam::Vec3A;
use layout::{Params, SceneData, COUNTERS};
use std::borrow::Cow;
use std::sync::{Arc, Mutex};
use wgpu::util::DeviceExt;

/// What can go wrong on the GPU path, each with what to do about it.
#[derive(Debug, thiserror::Error)]
pub enum GpuError {
    /// No adapter: no GPU, or no Vulkan/Metal/DX12 driver for it.
    #[error(
        "no GPU adapter found ({0}); install a Vulkan driver (on Debian, `mesa-vulkan-drivers` gives \
         the lavapipe software driver) or render on the CPU"
    )]
    NoAdapter(String),
    /// The adapter refused a device.
    #[error("the GPU adapter {adapter} refused a device: {message}")]
    Device {
        /// The adapter's name.
        adapter: String,
        /// The driver's reason.
        message: String,
    },
    /// A buffer of the scene exceeds what the adapter can bind.
    #[error(
        "the scene does not fit on {adapter}: its {what} take {bytes} bytes, and the adapter binds at most \
         {limit} bytes per buffer; render it on the CPU"
    )]
    TooLarge {
        /// The adapter's name.
        adapter: String,
        /// Which data.
        what: &'static str,
        /// Their size.
        bytes: u64,
        /// The adapter's limit.
        limit: u64,
    },
    /// A setting the GPU path does not implement.
    #[error("{0} is not available with --device gpu; render on the CPU")]
    Unsupported(&'static str),
    /// wgpu reported an error (a shader or driver problem).
    #[error("the GPU ({adapter}) failed: {message}")]
    Failed {
        /// The adapter's name.
        adapter: String,
        /// wgpu's message.
        message: String,
    },
}

/// A GPU ready to render: the adapter's device and queue.
pub struct Gpu {
    device: wgpu::Device,
    queue: wgpu::Queue,
    info: wgpu::AdapterInfo,
    limits: wgpu::Limits,
    /// Whether the adapter has f64 arithmetic, which the shaders then use
    /// where the CPU does (triangle edges hit exactly, cones).
    f64: bool,
    /// Errors wgpu reports outside an error scope (none are expected; kept
    /// instead of wgpu's default, which panics).
    uncaptured: Arc<Mutex<Option<String>>>,
}

impl Gpu {
    /// The system's preferred high-performance adapter (`WGPU_BACKEND` and
    /// `WGPU_ADAPTER_NAME` choose another), with its own limits.
    pub fn new() -> Result<Gpu, GpuError> {
        let instance = wgpu::Instance::new(wgpu::InstanceDescriptor::new_without_display_handle_from_env());
        let options = wgpu::RequestAdapterOptions {
            power_preference: wgpu::PowerPreference::HighPerformance,
            ..Default::default()
        };
        let adapter = match std::env::var("WGPU_ADAPTER_NAME") {
            Ok(name) => pollster::block_on(wgpu::util::initialize_adapter_from_env(&instance, None))
                .map_err(|e| GpuError::NoAdapter(format!("WGPU_ADAPTER_NAME={name}: {e}")))?,
            Err(_) => pollster::block_on(instance.request_adapter(&options))
                .map_err(|e| GpuError::NoAdapter(e.to_string()))?,
        };
        let info = adapter.get_info();
        let limits = adapter.limits();
        let f64 = adapter.features().contains(wgpu::Features::SHADER_F64);
        let desc = wgpu::DeviceDescriptor {
            label: Some("nffkit"),
            required_features: if f64 { wgpu::Features::SHADER_F64 } else { wgpu::Features::empty() },
            required_limits: limits.clone(),
            experimental_features: wgpu::ExperimentalFeatures::disabled(),
            memory_hints: wgpu::MemoryHints::Performance,
            trace: wgpu::Trace::Off,
        };
        let (device, queue) = pollster::block_on(adapter.request_device(&desc))
            .map_err(|e| GpuError::Device { adapter: info.name.clone(), message: e.to_string() })?;
        let uncaptured = Arc::new(Mutex::new(None));
        let sink = uncaptured.clone();
        device.on_uncaptured_error(Arc::new(move |e: wgpu::Error| {
            if let Ok(mut slot) = sink.lock() {
                slot.get_or_insert_with(|| e.to_string());
            }
        }));
        Ok(Gpu { device, queue, info, limits, f64, uncaptured })
    }

    /// The adapter, for reports: "NVIDIA H100 (Vulkan, DiscreteGpu, f64)".
    pub fn description(&self) -> String {
        let f64 = if self.f64 { "f64" } else { "no f64: cones and exact triangle edges in f32" };
        format!("{} ({:?}, {:?}, {f64})", self.info.name, self.info.backend, self.info.device_type)
    }

    fn failed(&self, message: impl std::fmt::Display) -> GpuError {
        GpuError::Failed { adapter: self.info.name.clone(), message: message.to_string() }
    }

    /// Run `f` inside validation and out-of-memory error scopes, turning
    /// what they catch (or an uncaptured error) into a [`GpuError`].
    fn checked<T>(&self, f: impl FnOnce() -> Result<T, GpuError>) -> Result<T, GpuError> {
        let oom = self.device.push_error_scope(wgpu::ErrorFilter::OutOfMemory);
        let validation = self.device.push_error_scope(wgpu::ErrorFilter::Validation);
        let out = f();
        let v = pollster::block_on(validation.pop());
        let o = pollster::block_on(oom.pop());
        if let Some(e) = v.or(o) {
            return Err(self.failed(e));
        }
        if let Some(e) = self.uncaptured.lock().ok().and_then(|mut s| s.take()) {
            return Err(self.failed(e));
        }
        out
    }
}

/// A scene uploaded to the GPU with its render settings and compiled
/// pipeline, ready to render (repeatedly, for benchmarks).
pub struct GpuScene<'g> {
    gpu: &'g Gpu,
    params: Params,
    pipeline: wgpu::ComputePipeline,
    bind_group: wgpu::BindGroup,
    uniform: wgpu::Buffer,
    film: wgpu::Buffer,
    counters: wgpu::Buffer,
    window: PixelWindow,
    /// Side of a workgroup (`GROUP_SIDE` in the shaders).
    group: u32,
}

/// Pixel samples a band of rows holds at most: few enough that one
/// dispatch takes well under a second on a laptop's GPU.
const BAND_SAMPLES: u64 = 1 << 21;

/// How many bands a render may take: their counters have a slot each.
const MAX_BANDS: u32 = 4096;

/// What an eye-ray run measured.
#[derive(Debug, Clone, Copy)]
pub struct EyeRays {
    /// Rays traced (one per pixel).
    pub rays: u64,
    /// Rays that hit something.
    pub hits: u64,
    /// Wall time from submission to completion.
    pub seconds: f64,
}

impl<'g> GpuScene<'g> {
    /// Upload `scene` for rendering with `settings` on `gpu`: refuses what
    /// the GPU path does not do, and scenes larger than the adapter binds.
    pub fn new(
        gpu: &'g Gpu,
        scene: &RenderScene,
        settings: &RenderSettings,
    ) -> Result<GpuScene<'g>, GpuError> {
        if settings.shade.spd {
            return Err(GpuError::Unsupported("the SPD test procedure (--spd-stats)"));
        }
        if settings.cost {
            return Err(GpuError::Unsupported("a traversal-cost image"));
        }
        if settings.row_stride > 1 {
            return Err(GpuError::Unsupported("rendering every n-th row"));
        }
        let data = SceneData::new(scene, settings);
        let (w, h) = scene.camera.resolution();
        let window = settings.pixel_window(w, h);
        gpu.checked(|| GpuScene::upload(gpu, data, settings, window))
    }

    fn upload(
        gpu: &'g Gpu,
        data: SceneData,
        settings: &RenderSettings,
        window: PixelWindow,
    ) -> Result<GpuScene<'g>, GpuError> {
        let device = &gpu.device;
        let limit = gpu.limits.max_storage_buffer_binding_size.min(gpu.limits.max_buffer_size);
        let fits = |what: &'static str, bytes: u64| {
            if bytes > limit {
                Err(GpuError::TooLarge { adapter: gpu.info.name.clone(), what, bytes, limit })
            } else {
                Ok(())
            }
        };
        // A binding cannot be empty: a missing kind gets one zeroed element.
        // Otherwise the data is uploaded where it lies, not copied first.
        fn bytes_of<T: bytemuck::Pod>(v: &[T]) -> Cow<'_, [u8]> {
            if v.is_empty() {
                Cow::Owned(vec![0u8; std::mem::size_of::<T>().max(4)])
            } else {
                Cow::Borrowed(bytemuck::cast_slice(v))
            }
        }
        let storage = |label: &'static str, contents: Cow<[u8]>| -> Result<wgpu::Buffer, GpuError> {
            fits(label, contents.len() as u64)?;
            Ok(device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some(label),
                contents: &contents,
                usage: wgpu::BufferUsages::STORAGE,
            }))
        };
        let nodes = storage("BVH nodes", bytes_of(&data.nodes))?;
        let leaf_ids = storage("leaf primitive ids", bytes_of(&data.leaf_ids))?;
        let shapes = storage("primitives", bytes_of(&data.shapes))?;
        let info = storage("primitive materials", bytes_of(&data.info))?;
        let tables = storage("materials and lights", bytes_of(&data.tables))?;
        let env = storage("cube-map texels", bytes_of(&data.env))?;
        let film_bytes = window.width().max(1) as u64 * window.height().max(1) as u64 * 16;
        fits("image", film_bytes)?;
        let film = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("film"),
            size: film_bytes,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        let counters = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("counters"),
            size: (MAX_BANDS as usize * COUNTERS * 4) as u64,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let uniform = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("params"),
            size: std::mem::size_of::<Params>() as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("whitted"),
            source: wgpu::ShaderSource::Wgsl(
                shader_source(data.depth, settings.shade.max_depth, gpu.f64).into(),
            ),
        });
        // One pixel per workgroup on a CPU adapter: lavapipe 22.3 (Debian
        // 12's) gives some pixels of an 8 x 8 group wrong colours where
        // their ray trees differ (a single-pixel render of the same pixel is
        // right).
        let group = if gpu.info.device_type == wgpu::DeviceType::Cpu { 1 } else { 8 };
        let constants = [("GROUP_SIDE", group as f64)];
        let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some("whitted"),
            layout: None,
            module: &module,
            entry_point: Some("main"),
            compilation_options: wgpu::PipelineCompilationOptions {
                constants: &constants,
                ..Default::default()
            },
            cache: None,
        });
        let buffers = [&uniform, &nodes, &leaf_ids, &shapes, &info, &tables, &env, &film, &counters];
        let entries: Vec<wgpu::BindGroupEntry> = buffers
            .iter()
            .enumerate()
            .map(|(i, b)| wgpu::BindGroupEntry { binding: i as u32, resource: b.as_entire_binding() })
            .collect();
        let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("scene"),
            layout: &pipeline.get_bind_group_layout(0),
            entries: &entries,
        });
        let mut params = data.params;
        params.image[2] = window.x0;
        params.image[3] = window.y0;
        params.window[..2].copy_from_slice(&[window.width(), window.height()]);
        Ok(GpuScene { gpu, params, pipeline, bind_group, uniform, film, counters, window, group })
    }

    /// Render the image (the window the settings asked for).
    pub fn render(&self, progress: Progress) -> Result<RenderOutput, GpuError> {
        let run = self.gpu.checked(|| self.run(MODE_RENDER, progress, true))?;
        let pixels = run.film.iter().map(|p| Vec3A::new(p[0], p[1], p[2])).collect();
        let film = Film { width: self.window.width(), height: self.window.height(), pixels };
        let c = &run.counts;
        let counters = Counters {
            eye: c[0],
            eye_hits: c[1],
            shadow: c[2],
            reflected: c[3],
            refracted: c[4],
            ..Counters::default()
        };
        Ok(RenderOutput { film, cost: None, counters, seconds: run.seconds })
    }

    /// Trace one eye ray through each pixel centre of the window to its
    /// nearest hit, without shading: the eye-ray throughput.
    pub fn eye_rays(&self) -> Result<EyeRays, GpuError> {
        let run = self.gpu.checked(|| self.run(MODE_EYE_HITS, &|_, _| {}, false))?;
        Ok(EyeRays { rays: run.counts[0], hits: run.counts[1], seconds: run.seconds })
    }

    /// Dispatch the window band by band in `mode`, then read the counters
    /// back, and the film when `want_film`.
    fn run(&self, mode: u32, progress: Progress, want_film: bool) -> Result<Run, GpuError> {
        let (device, queue) = (&self.gpu.device, &self.gpu.queue);
        let (w, h) = (self.window.width(), self.window.height());
        if w == 0 || h == 0 {
            return Ok(Run { film: Vec::new(), counts: [0; COUNTERS], seconds: 0.0 });
        }
        let centre = self.params.render[0] != 0 || mode == MODE_EYE_HITS;
        let samples = if centre { 1 } else { self.params.sampler[1] as u64 };
        let rows = ((BAND_SAMPLES / (w as u64 * samples)) as u32).clamp(h.div_ceil(MAX_BANDS).max(1), h);
        let bands = h.div_ceil(rows);
        let mut encoder = device.create_command_encoder(&Default::default());
        encoder.clear_buffer(&self.counters, 0, None);
        queue.submit([encoder.finish()]);
        let t0 = Stopwatch::start();
        for band in 0..bands {
            let mut p = self.params;
            p.window[2..].copy_from_slice(&[band * rows, rows]);
            p.render[3] = mode;
            p.counts[2] = band;
            queue.write_buffer(&self.uniform, 0, bytemuck::bytes_of(&p));
            let mut encoder = device.create_command_encoder(&Default::default());
            {
                let mut pass = encoder.begin_compute_pass(&Default::default());
                pass.set_pipeline(&self.pipeline);
                pass.set_bind_group(0, &self.bind_group, &[]);
                pass.dispatch_workgroups(w.div_ceil(self.group), rows.div_ceil(self.group), 1);
            }
            queue.submit([encoder.finish()]);
            self.wait()?;
            progress(band as usize + 1, bands as usize);
        }
        let seconds = t0.seconds();
        let film: Vec<[f32; 4]> =
            if want_film { self.read(&self.film, w as u64 * h as u64 * 16)? } else { Vec::new() };
        let slots: Vec<u32> = self.read(&self.counters, bands as u64 * COUNTERS as u64 * 4)?;
        let mut counts = [0u64; COUNTERS];
        for band in slots.chunks(COUNTERS) {
            for (c, &n) in counts.iter_mut().zip(band) {
                *c += n as u64;
            }
        }
        Ok(Run { film, counts, seconds })
    }

    /// Block until the queue's work is done.
    fn wait(&self) -> Result<(), GpuError> {
        self.gpu.device.poll(wgpu::PollType::wait_indefinitely()).map(|_| ()).map_err(|e| self.gpu.failed(e))
    }

    /// The first `bytes` of `buffer`, copied back to the host.
    fn read<T: bytemuck::Pod>(&self, buffer: &wgpu::Buffer, bytes: u64) -> Result<Vec<T>, GpuError> {
        let device = &self.gpu.device;
        let staging = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("readback"),
            size: bytes,
            usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let mut encoder = device.create_command_encoder(&Default::default());
        encoder.copy_buffer_to_buffer(buffer, 0, &staging, 0, bytes);
        self.gpu.queue.submit([encoder.finish()]);
        let mapped = Arc::new(Mutex::new(None));
        let slot = mapped.clone();
        staging.slice(..).map_async(wgpu::MapMode::Read, move |r| {
            if let Ok(mut s) = slot.lock() {
                *s = Some(r);
            }
        });
        self.wait()?;
        match mapped.lock().ok().and_then(|mut s| s.take()) {
            Some(Ok(())) => {}
            Some(Err(e)) => return Err(self.gpu.failed(e)),
            None => return Err(self.gpu.failed("the read-back buffer was never mapped")),
        }
        let view = staging.slice(..).get_mapped_range().map_err(|e| self.gpu.failed(e))?;
        let out = bytemuck::cast_slice(&view).to_vec();
        drop(view);
        staging.unmap();
        Ok(out)
    }
}

/// What one run read back.
struct Run {
    film: Vec<[f32; 4]>,
    counts: [u64; COUNTERS],
    seconds: f64,
}

/// `MODE_RENDER` and `MODE_EYE_HITS` of `scene.wgsl`.
const MODE_RENDER: u32 = 0;
const MODE_EYE_HITS: u32 = 1;

/// The shaders, concatenated after the constants that size their stacks
/// for this scene (three BVH entries per level, 2 (depth − 1) + 1 pending
/// rays) and carry the CPU's rounding bounds bit for bit.
fn shader_source(tree_depth: u32, max_depth: u32, f64: bool) -> String {
    let bits = |x: f32| format!("0x{:08x}u", x.to_bits());
    let prelude = format!(
        "const BVH_STACK: u32 = {}u;\nconst RAY_STACK: u32 = {}u;\n\
         const GAMMA2_BITS: u32 = {};\nconst GAMMA3_BITS: u32 = {};\nconst GAMMA5_BITS: u32 = {};\n\
         const SLAB_WIDEN_BITS: u32 = {};\nconst ENTRY_SLACK_BITS: u32 = {};\n",
        // Rounded up, so that most scenes share one shader (and drivers'
        // shader caches).
        (3 * tree_depth).next_multiple_of(32),
        2 * max_depth.max(1) - 1,
        bits(gamma(2)),
        bits(gamma(3)),
        bits(gamma(5)),
        bits(SLAB_WIDEN),
        bits(ENTRY_SLACK),
    );
    [
        prelude.as_str(),
        include_str!("shaders/scene.wgsl"),
        include_str!("shaders/sampling.wgsl"),
        include_str!("shaders/geometry.wgsl"),
        if f64 { include_str!("shaders/precise_f64.wgsl") } else { include_str!("shaders/precise_f32.wgsl") },
        include_str!("shaders/bvh.wgsl"),
        include_str!("shaders/whitted.wgsl"),
    ]
    .join("\n")
}

#[cfg(test)]
mod tests {
    use super::*;

    fn validate(source: &str, caps: naga::valid::Capabilities) -> Result<(), String> {
        let module = naga::front::wgsl::parse_str(source).map_err(|e| e.emit_to_string(source))?;
        naga::valid::Validator::new(naga::valid::ValidationFlags::all(), caps)
            .validate(&module)
            .map(|_| ())
            .map_err(|e| e.emit_to_string(source))
    }

    /// The assembled shaders parse and validate (as wgpu would before
    /// running them) in both precisions, with no GPU needed; the f32
    /// variant needs no f64.
    #[test]
    fn shaders_validate_in_both_precisions() {
        let none = naga::valid::Capabilities::empty();
        validate(&shader_source(12, 6, false), none).unwrap();
        validate(&shader_source(12, 6, true), naga::valid::Capabilities::FLOAT64).unwrap();
        assert!(validate(&shader_source(12, 6, true), none).is_err(), "the f64 variant needs the capability");
    }

    #[test]
    fn stacks_are_sized_for_the_tree_and_the_depth() {
        let source = shader_source(21, 6, false);
        assert!(source.contains("const BVH_STACK: u32 = 64u;"), "3 x 21 rounded up to 32s");
        assert!(source.contains("const RAY_STACK: u32 = 11u;"), "2 (6 - 1) + 1");
        assert!(shader_source(1, 1, false).contains("const RAY_STACK: u32 = 1u;"));
    }
}
