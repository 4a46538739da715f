//! A look through the camera before rendering: a coarse grid of eye rays,
//! for what a renderer should say before it spends its time. NFF.TXT makes
//! every opaque object one-sided, but the renderer shades both sides by
//! default (most real files wind some polygons the wrong way); a view
//! filled by the backs of opaque surfaces is then drawn where the spec
//! would see through them, and lit edge-on it renders black.

use crate::accel::{with_accel, Intersector, Tracer};
use crate::geometry::{Cull, Hit};
use crate::math::{shadow_ray, RayQuery};
use crate::prepare::RenderScene;
use glam::{Vec2, Vec3A};

/// What the probe's eye rays hit.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct ViewProbe {
    /// Eye rays traced.
    pub rays: u32,
    /// Those that hit something.
    pub hits: u32,
    /// Those whose nearest hit is the back of an opaque surface that is
    /// drawn only because shading is two-sided (the spec's one-sided rule
    /// would cull it).
    pub back_faces: u32,
    /// The line of the file of the first such surface met (row by row from
    /// the top left), when known.
    pub first_back_face_line: Option<u32>,
}

impl ViewProbe {
    /// The share of the view that is such backs of surfaces.
    pub fn back_face_share(&self) -> f64 {
        if self.rays == 0 {
            0.0
        } else {
            self.back_faces as f64 / self.rays as f64
        }
    }
}

/// Trace `n` × `n` eye rays spread evenly over the image (through the
/// centres of an `n` × `n` grid of cells, pinhole) and tell what they hit.
pub fn probe_view(scene: &RenderScene, n: u32) -> ViewProbe {
    with_accel!(&scene.accel, a => probe_with(scene, a, n))
}

fn probe_with<I: Intersector>(scene: &RenderScene, accel: &I, n: u32) -> ViewProbe {
    let geom = &scene.geometry;
    let mut probe = ViewProbe::default();
    for_each_eye_ray(scene, accel, n, |q, hit| {
        probe.rays += 1;
        let Some(hit) = hit else { return };
        probe.hits += 1;
        let info = &geom.info[hit.prim as usize];
        let opaque = scene.materials[info.material as usize].t <= 0.0;
        let back = geom.surface(&hit, q).ng.dot(q.ray.d) > 0.0;
        if opaque && back && info.cull == Cull::None {
            probe.back_faces += 1;
            if info.line > 0 && probe.first_back_face_line.is_none() {
                probe.first_back_face_line = Some(info.line);
            }
        }
    });
    probe
}

/// Trace `n` × `n` pinhole eye rays through the centres of an `n` × `n`
/// grid of cells over the image, row by row from the top left, handing
/// each with its nearest hit to `f`.
fn for_each_eye_ray<I: Intersector>(
    scene: &RenderScene,
    accel: &I,
    n: u32,
    mut f: impl FnMut(&RayQuery, Option<Hit>),
) {
    let mut tracer = Tracer::new(accel, &scene.geometry);
    let (w, h) = scene.camera.resolution();
    for j in 0..n {
        for i in 0..n {
            let x = (i as f32 + 0.5) / n as f32 * w as f32;
            let y = (j as f32 + 0.5) / n as f32 * h as f32;
            let (ray, t_min) = scene.camera.ray(x, y, Vec2::ZERO);
            let q = RayQuery::new(ray, t_min);
            let hit = tracer.nearest(&q, f32::INFINITY);
            f(&q, hit);
        }
    }
}

/// A surface point an eye ray sees, for tools that judge a view's lighting
/// by their own measure (mesh2nff weighs a model's emitting faces against
/// framing lights).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sighting {
    /// The point.
    pub point: Vec3A,
    /// The shading normal, facing the eye.
    pub normal: Vec3A,
    /// The geometric normal, facing the eye (shadow rays start off it).
    ng: Vec3A,
    /// Kd × colour of the material.
    pub albedo: Vec3A,
    /// The material: 0 for the default, `k` for the file's `k`-th `f`.
    pub material: u32,
}

/// What `n` × `n` eye rays spread evenly over the image (as in
/// [`probe_view`]) see, one entry per ray that hits.
pub fn sightings(scene: &RenderScene, n: u32) -> Vec<Sighting> {
    with_accel!(&scene.accel, a => sightings_with(scene, a, n))
}

fn sightings_with<I: Intersector>(scene: &RenderScene, accel: &I, n: u32) -> Vec<Sighting> {
    let geom = &scene.geometry;
    let mut out = Vec::new();
    for_each_eye_ray(scene, accel, n, |q, hit| {
        let Some(hit) = hit else { return };
        let s = geom.surface(&hit, q);
        let info = &geom.info[hit.prim as usize];
        let m = &scene.materials[info.material as usize];
        let flip = if s.ng.dot(q.ray.d) < 0.0 { 1.0 } else { -1.0 };
        out.push(Sighting {
            point: s.p,
            normal: s.ns * flip,
            ng: s.ng * flip,
            albedo: m.kd * m.color,
            material: info.material,
        });
    });
    out
}

/// For each sighting (rows) and each light position (columns), N·L when
/// the light is on the side the normal faces and nothing blocks the way,
/// else 0: what a point light of unit intensity gives the point's diffuse
/// shading.
pub fn light_reaching(scene: &RenderScene, seen: &[Sighting], lights: &[Vec3A]) -> Vec<f32> {
    with_accel!(&scene.accel, a => light_reaching_with(scene, a, seen, lights))
}

fn light_reaching_with<I: Intersector>(
    scene: &RenderScene,
    accel: &I,
    seen: &[Sighting],
    lights: &[Vec3A],
) -> Vec<f32> {
    let mut tracer = Tracer::new(accel, &scene.geometry);
    let mut out = Vec::with_capacity(seen.len() * lights.len());
    for s in seen {
        for &pos in lights {
            let l = (pos - s.point).normalize_or_zero();
            let n_dot_l = s.normal.dot(l);
            let side = if s.ng.dot(l) >= 0.0 { s.ng } else { -s.ng };
            let clear = n_dot_l > 0.0
                && shadow_ray(s.point, pos, side)
                    .is_some_and(|(ray, max)| !tracer.occluded(&RayQuery::new(ray, 0.0), max));
            out.push(if clear { n_dot_l } else { 0.0 });
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::prepare::{prepare, PrepareOptions};
    use nffkit_formats::nff::{parse, ParseOptions};

    const VIEW: &str = "v\nfrom 0 0 5\nat 0 0 0\nup 0 1 0\nangle 30\nhither 1\nresolution 32 32\n";

    fn probe(body: &str, one_sided: bool) -> ViewProbe {
        let scene = parse(format!("{VIEW}{body}").as_bytes(), &ParseOptions::default()).unwrap().scene;
        let prepared = prepare(&scene, &PrepareOptions { one_sided, ..Default::default() }).unwrap();
        probe_view(&prepared, 8)
    }

    // A square filling the view, counter-clockwise (its front) seen from
    // the camera or clockwise (its back).
    const FRONT: &str = "p 4\n-2 -2 0\n2 -2 0\n2 2 0\n-2 2 0\n";
    const BACK: &str = "p 4\n-2 -2 0\n-2 2 0\n2 2 0\n2 -2 0\n";

    #[test]
    fn the_back_of_an_opaque_polygon_is_counted_with_its_line() {
        let p = probe(BACK, false);
        assert_eq!((p.rays, p.hits, p.back_faces), (64, 64, 64));
        assert_eq!(p.first_back_face_line, Some(8));
        assert_eq!(probe(FRONT, false).back_faces, 0);
    }

    #[test]
    fn sightings_face_the_eye_and_lights_reach_only_unblocked_fronts() {
        let scene =
            parse(format!("{VIEW}f 0.5 1 1 0.8 0 1 0 1\n{BACK}").as_bytes(), &ParseOptions::default())
                .unwrap()
                .scene;
        let prepared = prepare(&scene, &PrepareOptions::default()).unwrap();
        let seen = sightings(&prepared, 4);
        assert_eq!(seen.len(), 16);
        assert!(seen
            .iter()
            .all(|s| s.normal == Vec3A::Z && s.material == 1 && s.albedo == Vec3A::new(0.4, 0.8, 0.8)));
        // In front, head on; in front, at 60 degrees; behind the square.
        let lights = [
            Vec3A::new(0.0, 0.0, 100.0),
            Vec3A::new(0.0, 1e4 * 3f32.sqrt(), 1e4),
            Vec3A::new(0.0, 0.0, -3.0),
        ];
        let reach = light_reaching(&prepared, &seen[..1], &lights);
        assert!(
            (reach[0] - 1.0).abs() < 1e-3 && (reach[1] - 0.5).abs() < 1e-3 && reach[2] == 0.0,
            "{reach:?}"
        );
        // A strip off to the side, out of view, blocks a low light.
        let low = [Vec3A::new(50.0, 0.0, 1.0)];
        assert!(light_reaching(&prepared, &seen[..1], &low)[0] > 0.01);
        let strip = "p 4\n10 -9 0.05\n10 9 0.05\n10 9 1.5\n10 -9 1.5\n";
        let scene = parse(format!("{VIEW}{BACK}{strip}").as_bytes(), &ParseOptions::default()).unwrap().scene;
        let prepared = prepare(&scene, &PrepareOptions::default()).unwrap();
        let seen = sightings(&prepared, 4);
        assert_eq!(seen.len(), 16, "the strip is out of view");
        assert_eq!(light_reaching(&prepared, &seen[..1], &low)[0], 0.0);
    }

    #[test]
    fn culled_or_transmissive_backs_are_not_counted() {
        // One-sided rendering culls it: nothing is hit.
        let p = probe(BACK, true);
        assert_eq!((p.hits, p.back_faces), (0, 0));
        // Glass is two-sided under the spec too.
        let glass = format!("f 1 1 1 0 0 0 0.9 1.5\n{BACK}");
        assert_eq!(probe(&glass, false).back_faces, 0);
    }
}
