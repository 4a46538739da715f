//! The model's own lights (glTF KHR_lights_punctual) as NFF point lights:
//! a point light where it is, a spot light there too (NFF has no cone), a
//! directional light as a light far away against its direction (a
//! thousand model diagonals). Intensities are mapped as emission's are:
//! each light keeps its share of the power (colour × intensity), scaled so
//! the brightest channel of all of them together is 1.

use glam::DVec3;
use nffkit_formats::mesh::Mesh;
use nffkit_formats::Light;

/// NFF lights for `mesh`'s lights, placed by `place`; `bounds` is the
/// output's box. Empty when the model has none (or none that shines).
pub fn lights(mesh: &Mesh, place: impl Fn(DVec3) -> DVec3, bounds: (DVec3, DVec3)) -> Vec<Light> {
    let total = mesh.lights.iter().fold(DVec3::ZERO, |t, l| t + l.power.max(DVec3::ZERO));
    let brightest = total.max_element();
    if !(brightest > 0.0 && brightest.is_finite()) {
        return Vec::new();
    }
    let centre = (bounds.0 + bounds.1) * 0.5;
    let far = (bounds.1 - bounds.0).length().max(1.0) * 1000.0;
    mesh.lights
        .iter()
        .filter(|l| l.power.max_element() > 0.0)
        .map(|l| {
            let position = match l.kind {
                // The direction is turned by the placement like any vector:
                // only a uniform scale, which keeps it.
                "directional" => centre - l.direction * far,
                _ => place(l.position),
            };
            Light { area: None, position, color: Some(l.power.max(DVec3::ZERO) / brightest) }
        })
        .collect()
}

/// "2 point lights and 1 directional light from the file": what was made.
pub fn note(mesh: &Mesh) -> Option<String> {
    if mesh.lights.is_empty() {
        return None;
    }
    let count = |k: &str| mesh.lights.iter().filter(|l| l.kind == k).count();
    let parts: Vec<String> = [
        ("point", "point"),
        ("spot", "spot (as a point: NFF has no cone)"),
        ("directional", "directional (as a far light)"),
    ]
    .iter()
    .filter(|(k, _)| count(k) > 0)
    .map(|(k, shown)| format!("{} {shown}", count(k)))
    .collect();
    Some(format!("lights from the file's KHR_lights_punctual: {}", parts.join(", ")))
}
