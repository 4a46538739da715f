//! The ray statistics the SPD publishes for its seven databases at their
//! standard sizes (the table in the SPD Readme, "Database Analysis"), and
//! the side-by-side comparison `render --spd-stats` prints.
//!
//! The figures assume the SPD testing procedure: 512x512 pixels with one eye
//! ray per pixel corner (513x513), depth 5, reflection rays at every
//! reflector and transmitter, no reflection counted as refraction. The
//! Readme says a classical ray tracer should come within about 10%.

use nffkit_formats::Scene;
use nffkit_tracer::stats::Counters;
use std::fmt::Write as _;

/// One database's published row.
#[derive(Debug, Clone, Copy)]
pub struct Published {
    /// Database name.
    pub name: &'static str,
    /// The SPD program's size factor that gives these figures.
    pub size: u32,
    /// Primitives in the file ("total prim.").
    pub primitives: usize,
    /// Lights.
    pub lights: usize,
    /// Eye rays that hit an object.
    pub eye_hits: u64,
    /// Reflection rays.
    pub reflected: u64,
    /// Refraction rays.
    pub refracted: u64,
    /// Shadow rays.
    pub shadow: u64,
}

/// The SPD Readme's table, by database.
pub const PUBLISHED: [Published; 7] = [
    row("balls", 4, 7382, 3, [263169, 175095, 0, 954368]),
    row("gears", 4, 9345, 5, [245086, 304643, 207564, 2246955]),
    row("mount", 6, 8196, 1, [173125, 354769, 354769, 412922]),
    row("rings", 7, 8401, 3, [263169, 315236, 0, 1085002]),
    row("teapot", 12, 9264, 2, [161120, 225248, 0, 407656]),
    row("tetra", 6, 4096, 1, [49788, 0, 0, 46112]),
    row("tree", 11, 8191, 7, [169836, 0, 0, 1097419]),
];

const fn row(name: &'static str, size: u32, primitives: usize, lights: usize, r: [u64; 4]) -> Published {
    Published {
        name,
        size,
        primitives,
        lights,
        eye_hits: r[0],
        reflected: r[1],
        refracted: r[2],
        shadow: r[3],
    }
}

/// The published database `scene` is, recognised by its primitive and light
/// counts (no two databases share both).
pub fn recognise(scene: &Scene) -> Option<&'static Published> {
    PUBLISHED.iter().find(|p| p.primitives == scene.primitives.len() && p.lights == scene.lights.len())
}

/// The comparison table: published figures beside `ours`, with the
/// difference in percent. `width`x`height` is the rendered image; the
/// figures are for 512x512 only, so other sizes get a note instead.
pub fn comparison(p: &Published, ours: &Counters, width: u32, height: u32) -> String {
    let mut s =
        format!("SPD published figures: {} at size {} (SPD Readme, Database Analysis)\n", p.name, p.size);
    if (width, height) != (512, 512) {
        let _ = writeln!(s, "  (not compared: they are for 512x512 images, this one is {width}x{height})");
        return s;
    }
    let _ = writeln!(s, "  {:<14} {:>10} {:>10} {:>9}", "", "published", "nffkit", "diff");
    let rows = [
        ("eye hit rays", p.eye_hits, ours.eye_hits),
        ("reflect rays", p.reflected, ours.reflected),
        ("refract rays", p.refracted, ours.refracted),
        ("shadow rays", p.shadow, ours.shadow),
    ];
    for (label, published, got) in rows {
        let _ = writeln!(s, "  {label:<14} {published:>10} {got:>10} {:>9}", percent(published, got));
    }
    s
}

/// Signed difference of `got` from `published` in percent; rows published
/// as 0 match only 0.
pub fn difference(published: u64, got: u64) -> Option<f64> {
    match (published, got) {
        (0, 0) => Some(0.0),
        (0, _) => None,
        _ => Some((got as f64 - published as f64) / published as f64 * 100.0),
    }
}

fn percent(published: u64, got: u64) -> String {
    match difference(published, got) {
        Some(d) => format!("{d:+.2}%"),
        None => "new".into(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn no_two_databases_share_primitive_and_light_counts() {
        for (i, a) in PUBLISHED.iter().enumerate() {
            for b in &PUBLISHED[i + 1..] {
                assert!((a.primitives, a.lights) != (b.primitives, b.lights), "{} {}", a.name, b.name);
            }
        }
    }

    #[test]
    fn differences_are_signed_percentages() {
        assert_eq!(difference(200, 210), Some(5.0));
        assert_eq!(difference(200, 190), Some(-5.0));
        assert_eq!(difference(0, 0), Some(0.0));
        assert_eq!(difference(0, 3), None);
        let c = Counters { eye_hits: 263169, reflected: 175095, shadow: 1000000, ..Default::default() };
        let t = comparison(&PUBLISHED[0], &c, 512, 512);
        assert!(t.contains("shadow rays        954368    1000000    +4.78%"), "{t}");
        assert!(comparison(&PUBLISHED[0], &c, 64, 64).contains("not compared"));
    }
}
