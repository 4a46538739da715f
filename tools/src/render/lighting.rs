//! Warnings about how a scene is lit, shared by `render` and `render --check`:
//! a scene with no lights renders black (background aside) unless ambient
//! light is asked for, and several public NFF files have none, or only
//! dialect lights that `--lenient` skipped.

use nffkit_formats::Scene;

/// The warning to print when `scene` has no lights and nothing else lights
/// it (`ambient`: whether `--ambient` is on).
pub fn unlit_warning(scene: &Scene, ambient: bool) -> Option<String> {
    if !scene.lights.is_empty() || scene.primitives.is_empty() || ambient {
        return None;
    }
    Some(
        "the scene has no lights (`l`): its objects render black; \
         `render --ambient spd` (or a value) lights them evenly"
            .into(),
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use nffkit_formats::nff::{parse, ParseOptions};

    fn scene(src: &str) -> Scene {
        parse(src.as_bytes(), &ParseOptions { fragment: true, ..Default::default() }).unwrap().scene
    }

    #[test]
    fn warns_only_for_objects_without_any_light() {
        assert!(unlit_warning(&scene("s 0 0 0 1\n"), false).is_some());
        assert!(unlit_warning(&scene("s 0 0 0 1\n"), true).is_none());
        assert!(unlit_warning(&scene("l 1 1 1\ns 0 0 0 1\n"), false).is_none());
        assert!(unlit_warning(&scene("b 1 1 1\n"), false).is_none());
    }
}
