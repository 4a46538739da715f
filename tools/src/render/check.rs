//! `render --check`: validate NFF files and summarise what they hold.

use crate::input::Warnings;
use crate::render::scene_warnings::{scene_warnings, SceneWarning};
use nffkit_formats::nff::{self, escape, ParseOptions, Severity};
use nffkit_formats::{plural, Dialect, Scene, ShapeKind};
use nffkit_tracer::prepare::{prepare, PrepareOptions};
use std::fmt::Write as _;
use strum::VariantArray;

/// The outcome of checking one file.
pub struct CheckReport {
    /// Every diagnostic, rendered compiler-style.
    pub diagnostics: String,
    /// One line: counts of entities, primitives, lights, bounds.
    pub summary: String,
    /// Errors found (0 means the file is valid).
    pub errors: usize,
    /// The scene read, when the file is valid: handed back so that the
    /// caller decides when to free it.
    pub scene: Option<Scene>,
}

/// Check one file's bytes, `name` being how it is shown in messages;
/// warnings and notes are printed as `warnings` asks (errors always).
pub fn check_source(name: &str, src: &[u8], opts: &ParseOptions, warnings: Warnings) -> CheckReport {
    let mut out = crate::input::report(name, src, warnings);
    let mut print = |all: &[nff::Diagnostic]| {
        let mut text = String::new();
        for d in all.iter().filter(|d| warnings != Warnings::Hide || d.severity == Severity::Error) {
            text += &out.render(d).unwrap_or_default();
        }
        text + &out.held_back()
    };
    match nff::parse(src, opts) {
        Ok(parsed) => {
            let mut diagnostics = print(&parsed.diagnostics);
            let (scene_warnings, probed) = whole_scene_warnings(&parsed.scene);
            if warnings != Warnings::Hide {
                diagnostics.extend(scene_warnings.iter().map(|w| w.render(name)));
                if !probed {
                    diagnostics += &format!(
                        "note: the view was not probed for the backs of surfaces, nor polygons \
                         checked for overlaps in one plane ({} primitives, more than --check \
                         takes on); `render` does both\n --> {}\n",
                        parsed.scene.primitives.len(),
                        escape(name)
                    );
                }
            }
            let warnings = parsed.diagnostics.iter().filter(|d| d.severity == Severity::Warning).count()
                + scene_warnings.len();
            let notes = parsed.diagnostics.iter().filter(|d| d.severity == Severity::Note).count();
            let summary = summary(name, &parsed.scene, warnings, notes);
            CheckReport { diagnostics, summary, errors: 0, scene: Some(parsed.scene) }
        }
        Err(e) => {
            let diagnostics = print(&e.diagnostics);
            let errors = e.diagnostics.iter().filter(|d| d.severity == Severity::Error).count();
            let warnings = e.diagnostics.iter().filter(|d| d.severity == Severity::Warning).count();
            let summary = format!(
                "{}: INVALID, {errors} error{}, {warnings} warning{}",
                escape(name),
                plural(errors),
                plural(warnings)
            );
            CheckReport { diagnostics, summary, errors, scene: None }
        }
    }
}

/// Above this many primitives `--check` does not build a tracer to probe
/// the view (at this size that takes about 0.1 s; a million-triangle
/// polygon, 0.4 s and 230 MB).
const MAX_PROBED_PRIMITIVES: usize = 1 << 18;

/// The warnings about the scene as a whole, and whether its view was
/// probed: prepared as `render` would by default when it has a view and
/// no more than [`MAX_PROBED_PRIMITIVES`].
fn whole_scene_warnings(scene: &Scene) -> (Vec<SceneWarning>, bool) {
    let probe = scene.view.is_some() && scene.primitives.len() <= MAX_PROBED_PRIMITIVES;
    let prepared = probe.then(|| prepare(scene, &PrepareOptions::default()).ok()).flatten();
    (scene_warnings(scene, prepared.as_ref(), false), probe || scene.view.is_none())
}

/// What a P3F scene asks beyond NFF, for its summary line: `P3F (env
/// skybox, lens, 1 area light, spp 4, accel 2), `.
fn p3f_summary(scene: &Scene) -> String {
    let mut parts = Vec::new();
    if let Some(dir) = &scene.environment {
        parts.push(format!("env {}", escape(dir)));
    }
    if scene.view.as_ref().and_then(|v| v.lens).is_some_and(|l| l.aperture > 0.0) {
        parts.push("lens".to_string());
    }
    let areas = scene.lights.iter().filter(|l| l.area.is_some()).count();
    if areas > 0 {
        parts.push(format!("{areas} area light{}", plural(areas)));
    }
    let d = scene.directives;
    parts.extend(d.spp.map(|n| format!("spp {n}")));
    parts.extend(d.accel.map(|n| format!("accel {n}")));
    if parts.is_empty() {
        "P3F, ".to_string()
    } else {
        format!("P3F ({}), ", parts.join(", "))
    }
}

fn summary(name: &str, scene: &Scene, warnings: usize, notes: usize) -> String {
    let counts = scene.counts();
    let total: usize = counts.iter().sum();
    let mut out = format!("{}: ok, ", escape(name));
    if scene.dialect == Dialect::P3f {
        out += &p3f_summary(scene);
    }
    if let Some(v) = &scene.view {
        let _ = write!(out, "view {}x{}, ", v.resolution[0], v.resolution[1]);
    } else {
        out += "fragment (no view), ";
    }
    let _ = write!(
        out,
        "{} light{}, {} material{}, {total} primitive{}",
        scene.lights.len(),
        plural(scene.lights.len()),
        scene.materials.len(),
        plural(scene.materials.len()),
        plural(total)
    );
    let kinds: Vec<String> = ShapeKind::VARIANTS
        .iter()
        .map(|&k| (k, counts[k as usize]))
        .filter(|&(_, n)| n > 0)
        .map(|(k, n)| format!("{n} {}", if n == 1 { k.name() } else { k.plural() }))
        .collect();
    if !kinds.is_empty() {
        let _ = write!(out, " ({})", kinds.join(", "));
    }
    if let Some((lo, hi)) = scene.bounds() {
        let _ = write!(
            out,
            ", bounds ({:.4}, {:.4}, {:.4})..({:.4}, {:.4}, {:.4})",
            lo.x, lo.y, lo.z, hi.x, hi.y, hi.z
        );
    }
    let _ = write!(out, ", {warnings} warning{}", plural(warnings));
    if notes > 0 {
        let _ = write!(out, ", {notes} note{}", plural(notes));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn summary_counts_kinds() {
        let src = b"v\nfrom 0 0 5\nat 0 0 0\nup 0 1 0\nangle 45\nhither 1\nresolution 8 8\nl 1 1 1\n\
                    s 0 0 0 1\ns 1 1 1 1\nc 0 0 0 1 0 0 1 1\n";
        let r = check_source("t.nff", src, &ParseOptions::default(), Warnings::Summarise);
        assert_eq!(r.errors, 0);
        assert!(r.summary.contains("3 primitives (2 spheres, 1 cone)"), "{}", r.summary);
        assert!(
            r.summary.contains("bounds (-1.0000, -1.0000, -1.0000)..(2.0000, 2.0000, 2.0000)"),
            "{}",
            r.summary
        );
    }

    #[test]
    fn invalid_file_counts_errors() {
        // The cut-short `b` and the missing view are both reported.
        let r = check_source("t.nff", b"b 1 2\n", &ParseOptions::default(), Warnings::Summarise);
        assert_eq!(r.errors, 2);
        assert!(r.summary.contains("INVALID"));
        assert!(r.diagnostics.contains("t.nff:"));
    }
}
