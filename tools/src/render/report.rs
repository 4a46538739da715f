//! The statistics block that `render --stats` prints: what the scene holds,
//! how it was sampled, what the accelerator cost, and the rays and tests of
//! the render, per kind by name.

use nffkit_formats::plural;
use nffkit_tracer::prepare::RenderScene;
use nffkit_tracer::render::{RenderOutput, RenderSettings};
use nffkit_tracer::stats::Counters;
use std::fmt::Write as _;

/// Wall times measured around the render.
#[derive(Debug, Clone, Copy)]
pub struct Times {
    /// Reading and parsing the scene, seconds.
    pub parse: f64,
    /// The whole command so far, seconds.
    pub total: f64,
}

fn per(a: u64, b: u64) -> f64 {
    if b == 0 {
        0.0
    } else {
        a as f64 / b as f64
    }
}

/// The statistics block, one fact per line; `in_file` is the number of
/// primitives the file held.
pub fn statistics(
    name: &str,
    in_file: usize,
    prepared: &RenderScene,
    settings: &RenderSettings,
    out: &RenderOutput,
    times: Times,
) -> String {
    let counts = prepared.primitive_counts();
    let c = &out.counters;
    let info = prepared.accel_info();
    let (w, h) = prepared.camera.resolution();
    let rays = c.rays();
    let mut s = String::new();
    let made: Vec<String> = counts
        .iter()
        .filter(|&(_, n)| n > 0)
        .map(|(k, n)| format!("{n} {}{}", <&str>::from(k), plural(n as usize)))
        .collect();
    let made = if made.is_empty() { "nothing to render".to_string() } else { made.join(", ") };
    let _ = writeln!(s, "scene        {name}: {} primitives in the file -> {made}", in_file);
    let _ = writeln!(
        s,
        "image        {w}x{h}, {}, depth {}",
        settings.describe_sampling(&prepared.camera),
        settings.shade.max_depth
    );
    let _ = writeln!(
        s,
        "packets      {}",
        if settings.packets && !settings.cost {
            format!(
                "eye and shadow rays in packets of {}, kernels for {}",
                nffkit_tracer::simd::LANES,
                nffkit_tracer::simd::isa()
            )
        } else {
            "off (ray by ray)".into()
        }
    );
    let _ = writeln!(
        s,
        "accelerator  {}: {} {}, {:.2} MB, built in {:.1} ms{}",
        info.summary,
        info.nodes,
        info.unit,
        info.bytes as f64 / 1e6,
        info.build_seconds * 1e3,
        info.sah_cost.map_or(String::new(), |c| format!(", SAH cost {c:.2}"))
    );
    s += &counters(c);
    let _ = writeln!(
        s,
        "time         parse {:.3} s, render {:.3} s ({:.2} Mrays/s), total {:.3} s",
        times.parse,
        out.seconds,
        rays as f64 / out.seconds.max(1e-9) / 1e6,
        times.total
    );
    s
}

/// The rays, tests and traversal lines of the block: also what `nffmerge
/// --stats` prints for the summed counters of its parts.
pub fn counters(c: &Counters) -> String {
    let rays = c.rays();
    let by_kind: Vec<String> = c.tests.iter().map(|(k, n)| format!("{} {n}", <&str>::from(k))).collect();
    let mut s = String::new();
    let _ = writeln!(
        s,
        "rays         {rays} total: eye {} ({} hit), reflected {}, refracted {}, shadow {}",
        c.eye, c.eye_hits, c.reflected, c.refracted, c.shadow
    );
    let _ = writeln!(
        s,
        "tests        {} total ({:.2} per ray): {}",
        c.total_tests(),
        per(c.total_tests(), rays),
        by_kind.join(", ")
    );
    let _ = writeln!(
        s,
        "traversal    {} nodes/cells visited ({:.2} per ray), {} mailbox hits, {} shadow cache hits ({:.1}% of shadow rays)",
        c.visits,
        per(c.visits, rays),
        c.mailbox_hits,
        c.shadow_cache_hits,
        100.0 * per(c.shadow_cache_hits, c.shadow)
    );
    s
}
