//! The scene in the shaders' layout (`shaders/scene.wgsl` declares the
//! same structures): the BVH's 4-wide nodes as they are (128 bytes, boxes
//! in structure-of-arrays form), the primitives in one array of `vec4`s
//! per kind after kind, per-primitive data, and the small tables
//! (materials, lights, the filter's CDF) in another. Building these is
//! plain CPU work, tested without a GPU.

use crate::accel::{Accel, Bvh, Node4, MAX, MIN};
use crate::filter::Filter;
use crate::geometry::{Cull, Kind};
use crate::light::LightShape;
use crate::prepare::RenderScene;
use crate::render::RenderSettings;
use crate::sampling::SamplerKind;
use bytemuck::{Pod, Zeroable};
use glam::Vec3A;
use std::borrow::Cow;

/// `Params` of `scene.wgsl`.
#[repr(C)]
#[derive(Debug, Clone, Copy, Pod, Zeroable)]
pub(crate) struct Params {
    pub eye: [f32; 4],
    pub forward: [f32; 4],
    pub right: [f32; 4],
    pub up: [f32; 4],
    pub lens: [f32; 4],
    pub background: [f32; 4],
    pub image: [u32; 4],
    pub window: [u32; 4],
    pub sampler: [u32; 4],
    pub render: [u32; 4],
    pub shade: [f32; 4],
    pub counts: [u32; 4],
    pub ids: [u32; 4],
    pub shape_at: [u32; 4],
    pub table_at: [u32; 4],
    pub faces: [[u32; 4]; 6],
}

/// `Node` of `scene.wgsl`: a [`Node4`] with its unused slots marked.
#[repr(C)]
#[derive(Debug, Clone, Copy, Pod, Zeroable)]
pub(crate) struct GpuNode {
    lo: [[f32; 4]; 3],
    hi: [[f32; 4]; 3],
    child: [u32; 4],
    count: [u32; 4],
}

/// A slot's count when the slot is empty (`UNUSED` in the shaders).
pub(crate) const UNUSED: u32 = u32::MAX;

/// Counter slots per dispatch (`COUNTERS` in the shaders).
pub(crate) const COUNTERS: usize = 8;

impl GpuNode {
    fn new(n: &Node4) -> GpuNode {
        let mut g = GpuNode {
            lo: n.bounds[MIN].map(|v| v.to_array()),
            hi: n.bounds[MAX].map(|v| v.to_array()),
            child: n.child,
            count: n.count,
        };
        // Empty slots carry infinite boxes on the CPU; here they are
        // marked and zeroed, so no infinity reaches the GPU's arithmetic.
        for slot in 0..4 {
            if !n.used(slot) {
                g.count[slot] = UNUSED;
                for a in 0..3 {
                    g.lo[a][slot] = 0.0;
                    g.hi[a][slot] = 0.0;
                }
            }
        }
        g
    }
}

/// Everything the shaders read, ready to upload.
pub(crate) struct SceneData {
    pub nodes: Vec<GpuNode>,
    pub leaf_ids: Vec<u32>,
    pub shapes: Vec<[f32; 4]>,
    pub info: Vec<[u32; 4]>,
    pub tables: Vec<[f32; 4]>,
    pub env: Vec<u32>,
    /// The template of the uniform block: everything but the window and
    /// the band, which each dispatch sets.
    pub params: Params,
    /// Levels of the tree (a root alone is 1): the walk's stack holds three
    /// entries per level.
    pub depth: u32,
}

fn v4(v: Vec3A, w: f32) -> [f32; 4] {
    [v.x, v.y, v.z, w]
}

/// The code of a sampler kind in `sampling.wgsl`'s `sample_of`.
pub(crate) fn sampler_code(kind: SamplerKind) -> u32 {
    match kind {
        SamplerKind::Random => 0,
        SamplerKind::Regular => 1,
        SamplerKind::Jittered => 2,
        SamplerKind::NRooks => 3,
        SamplerKind::MultiJittered => 4,
        SamplerKind::CorrelatedMultiJittered => 5,
        SamplerKind::Hammersley => 6,
        SamplerKind::Sobol => 7,
    }
}

/// The scene's BVH: the one it was prepared with, or one built now when it
/// was prepared with another accelerator (the GPU walks only BVHs).
fn bvh(scene: &RenderScene) -> Cow<'_, Bvh> {
    match &scene.accel {
        Accel::Bvh(b) => Cow::Borrowed(b),
        _ => Cow::Owned(Bvh::build(&scene.geometry)),
    }
}

/// Levels of the tree. The builder writes every node before its children
/// (`wide::fill` and `parts`), so one pass in array order sees each
/// parent's level before its children need it.
fn tree_depth(nodes: &[Node4]) -> u32 {
    let mut level = vec![0u32; nodes.len()];
    let mut deepest = 0;
    for i in 0..nodes.len() {
        let l = if i == 0 { 1 } else { level[i] };
        level[i] = l;
        deepest = deepest.max(l);
        for slot in 0..4 {
            if nodes[i].used(slot) && nodes[i].count[slot] == 0 {
                level[nodes[i].child[slot] as usize] = l + 1;
            }
        }
    }
    deepest
}

impl SceneData {
    /// Lay `scene` out for the shaders, rendered with `settings`.
    pub fn new(scene: &RenderScene, settings: &RenderSettings) -> SceneData {
        let g = &scene.geometry;
        let bvh = bvh(scene);
        let (wide, prims) = bvh.nodes();
        let nodes: Vec<GpuNode> = wide.iter().map(GpuNode::new).collect();
        let mut shapes: Vec<[f32; 4]> = g.spheres.iter().map(|s| v4(s.center(), s.radius())).collect();
        let tri_at = shapes.len();
        shapes.extend(g.triangles.iter().flat_map(|t| t.v.map(|v| v4(v, 0.0))));
        let cone_at = shapes.len();
        shapes.extend(
            g.cones.iter().flat_map(|c| [v4(c.base, c.height), v4(c.axis, c.r0), [c.slope, 0.0, 0.0, 0.0]]),
        );
        let plane_at = shapes.len();
        shapes.extend(g.planes.iter().flat_map(|p| [v4(p.point, 0.0), v4(p.n, 0.0)]));
        let patch_at = shapes.len();
        shapes.extend(g.patch_normals.iter().flat_map(|n| n.map(|v| v4(v, 0.0))));
        let info = g
            .info
            .iter()
            .map(|i| {
                let cull = match i.cull {
                    Cull::None => 0,
                    Cull::Back => 1,
                    Cull::Front => 2,
                };
                [i.material, i.patch().unwrap_or(UNUSED), cull, 0]
            })
            .collect();

        let mut tables: Vec<[f32; 4]> = Vec::new();
        for m in &scene.materials {
            tables.push(v4(m.color, m.kd));
            tables.push(v4(m.specular, m.ks));
            tables.push([m.shine, m.t, m.ior, if m.fresnel { 1.0 } else { 0.0 }]);
        }
        let light_at = tables.len();
        for l in &scene.lights {
            let (u, v) = l.rect.map_or((Vec3A::ZERO, Vec3A::ZERO), |r| (r.u, r.v));
            tables.push(v4(l.position, if l.rect.is_some() { 1.0 } else { 0.0 }));
            tables.push(v4(l.intensity, 0.0));
            tables.push(v4(u, 0.0));
            tables.push(v4(v, 0.0));
        }
        let cdf_at = tables.len();
        let filter = Filter::new(settings.filter);
        tables.extend(filter.cdf().chunks(4).map(|c| {
            let mut q = [0.0; 4];
            q[..c.len()].copy_from_slice(c);
            q
        }));

        let mut env = Vec::new();
        let mut faces = [[0u32; 4]; 6];
        if let Some(map) = &scene.environment {
            for (f, face) in faces.iter_mut().zip(map.faces()) {
                let (w, h, rgb) = face.texels();
                *f = [w, h, env.len() as u32, 0];
                env.extend(rgb.iter().map(|&[r, g, b]| r as u32 | (g as u32) << 8 | (b as u32) << 16));
            }
        }

        let cam = &scene.camera;
        let (forward, right, up, pixel) = cam.frame();
        let (w, h) = cam.resolution();
        let s = &settings.sampler;
        let params = Params {
            eye: v4(cam.eye, 0.0),
            forward: v4(forward, 0.0),
            right: v4(right, 0.0),
            up: v4(up, 0.0),
            lens: [pixel, cam.aperture, cam.focus, cam.hither],
            background: v4(scene.background, scene.ambient),
            // The window's corner and size: `GpuScene::new`; the band:
            // each dispatch.
            image: [w, h, 0, 0],
            window: [0; 4],
            sampler: [sampler_code(s.kind), s.spp, s.side(), s.seed],
            render: [
                settings.pixel_centre_only(cam) as u32,
                filter_code(settings),
                settings.shade.max_depth.max(1),
                0,
            ],
            shade: [
                settings.shade.light_size,
                match settings.shade.light_shape {
                    LightShape::Square => 0.0,
                    LightShape::Disk => 1.0,
                },
                settings.shade.min_weight,
                1.0,
            ],
            counts: [scene.lights.len() as u32, g.any_cull as u32, 0, 0],
            ids: [
                g.first_id(Kind::Triangle),
                g.first_id(Kind::Cone),
                g.first_id(Kind::Plane),
                g.len() as u32,
            ],
            shape_at: [tri_at as u32, cone_at as u32, plane_at as u32, patch_at as u32],
            table_at: [0, light_at as u32, cdf_at as u32, scene.environment.is_some() as u32],
            faces,
        };
        SceneData {
            depth: tree_depth(wide),
            nodes,
            leaf_ids: prims.to_vec(),
            shapes,
            info,
            tables,
            env,
            params,
        }
    }
}

/// The filter's code in `sampling.wgsl` (`FilterKind` in declaration
/// order).
fn filter_code(settings: &RenderSettings) -> u32 {
    use crate::filter::FilterKind;
    match settings.filter {
        FilterKind::Box => 0,
        FilterKind::Tent => 1,
        FilterKind::Gaussian => 2,
        FilterKind::Mitchell => 3,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::prepare::{prepare, PrepareOptions};

    fn scene(src: &str) -> RenderScene {
        let parsed = nffkit_formats::nff::parse(src.as_bytes(), &Default::default()).unwrap();
        prepare(&parsed.scene, &PrepareOptions { width: Some(8), height: Some(8), ..Default::default() })
            .unwrap()
    }

    const VIEW: &str = "v\nfrom 0 0 -10\nat 0 0 0\nup 0 1 0\nangle 40\nhither 1\nresolution 8 8\n";

    #[test]
    fn every_kind_lands_at_its_offsets() {
        let src = format!(
            "{VIEW}l 1 2 3\nf 1 0 0 1 0 0 0 0\ns 0 0 0 1\ns 3 0 0 0.5\n\
             f 0 1 0 1 0 0 0 0\np 3\n0 0 0\n1 0 0\n0 1 0\nc\n0 0 0 1\n0 2 0 0.5\npp 3\n0 0 1 0 0 1\n1 0 1 0 0 1\n0 1 1 0 0 1\n"
        );
        let s = scene(&src);
        let d = SceneData::new(&s, &RenderSettings::default());
        let p = d.params;
        // Two spheres, two triangles, one cone, no planes.
        assert_eq!(p.ids, [2, 4, 5, 5]);
        assert_eq!(p.shape_at, [2, 2 + 6, 2 + 6 + 3, 2 + 6 + 3]);
        assert_eq!(d.shapes[1], [3.0, 0.0, 0.0, 0.5]);
        // The patch triangle's normals follow the planes, indexed by info.
        let patched = d.info.iter().filter(|i| i[1] != UNUSED).count();
        assert_eq!(patched, 1);
        assert_eq!(d.shapes.len(), 2 + 6 + 3 + 3);
        // Materials: three vec4s each, then the light, then the CDF.
        assert_eq!(p.table_at[1] as usize, 3 * s.materials.len());
        assert_eq!(d.tables[p.table_at[1] as usize], [1.0, 2.0, 3.0, 0.0]);
        assert_eq!(d.tables.len() - p.table_at[2] as usize, 257usize.div_ceil(4));
    }

    #[test]
    fn empty_slots_are_marked_and_the_depth_counted() {
        let mut src = String::from(VIEW);
        src.push_str("f 1 1 1 1 0 0 0 0\n");
        for i in 0..200 {
            src.push_str(&format!("s {} {} 0 0.1\n", i % 20, i / 20));
        }
        let s = scene(&src);
        let d = SceneData::new(&s, &RenderSettings::default());
        let Accel::Bvh(b) = &s.accel else { panic!("a BVH") };
        let (wide, _) = b.nodes();
        assert_eq!(d.nodes.len(), wide.len());
        for (g, n) in d.nodes.iter().zip(wide) {
            for slot in 0..4 {
                assert_eq!(g.count[slot] == UNUSED, !n.used(slot));
                if n.used(slot) {
                    assert_eq!(g.lo[0][slot], n.bounds[MIN][0][slot]);
                }
            }
        }
        assert!(d.depth >= 2 && d.depth <= 8, "{}", d.depth);
        // A lone leaf is one level.
        let one = scene(&format!("{VIEW}f 1 1 1 1 0 0 0 0\ns 0 0 0 1\n"));
        assert_eq!(SceneData::new(&one, &RenderSettings::default()).depth, 1);
    }
}
