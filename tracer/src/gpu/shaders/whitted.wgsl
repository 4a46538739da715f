// Whitted shading (`integrator/mod.rs`) and the render loop (`render.rs`):
// one invocation per pixel, its samples in order through the filter, each
// sample's tree of rays walked depth first from an explicit stack.
//
// const RAY_STACK: u32 (prepended): 2 (depth − 1) + 1 pending rays, the
// most a depth-first walk of a tree with three children a hit can hold.

// `Camera::ray`: the eye ray through image point (x, y) and lens point
// `lens` (unit disc), with its t_min (the hither plane) in w of the second.
struct EyeRay {
    o: vec3<f32>,
    d: vec3<f32>,
    t_min: f32,
}

fn camera_ray(x: f32, y: f32, lens: vec2<f32>) -> EyeRay {
    let pixel = P.lens.x;
    let aperture = P.lens.y;
    let focus = P.lens.z;
    let hither = P.lens.w;
    let sx = (x - f32(P.image.x) * 0.5) * pixel;
    let sy = (f32(P.image.y) * 0.5 - y) * pixel;
    let forward = P.forward.xyz;
    let dir = unit((forward + scaled(P.right.xyz, sx)) + scaled(P.up.xyz, sy));
    let cos_v = dot3(dir, forward);
    if aperture <= 0.0 {
        return EyeRay(P.eye.xyz, dir, div(hither, cos_v));
    }
    let focus_point = P.eye.xyz + scaled(dir, div(focus, cos_v));
    let lens_point = P.eye.xyz + scaled(scaled(P.right.xyz, lens.x) + scaled(P.up.xyz, lens.y), aperture);
    let d = unit(focus_point - lens_point);
    return EyeRay(lens_point, d, div(hither, dot3(d, forward)));
}

// `CubeMap::lookup`: the course's skybox lookup, nearest texel.
fn environment(d: vec3<f32>) -> vec3<f32> {
    let a = abs(d);
    var face: u32;
    var ma: f32;
    if a.x > a.y {
        face = select(0u, 1u, d.x >= 0.0);
        ma = a.x;
    } else {
        face = select(3u, 2u, d.y >= 0.0);
        ma = a.y;
    }
    if a.z > ma {
        face = select(5u, 4u, d.z >= 0.0);
        ma = a.z;
    }
    var st: vec2<f32>;
    switch face {
        case 0u: { st = vec2<f32>(-d.z, d.y); }
        case 1u: { st = vec2<f32>(d.z, d.y); }
        case 2u: { st = vec2<f32>(-d.x, -d.z); }
        case 3u: { st = vec2<f32>(-d.x, d.z); }
        case 4u: { st = vec2<f32>(-d.x, d.y); }
        default: { st = vec2<f32>(d.x, d.y); }
    }
    if !(ma > 0.0) {
        return vec3<f32>(0.0);
    }
    let s = (st.x / ma + 1.0) * 0.5;
    let t = (st.y / ma + 1.0) * 0.5;
    let f = P.faces[face];
    let x = min(u32(f32(f.x - 1u) * clamp(s, 0.0, 1.0)), f.x - 1u);
    let y = min(u32(f32(f.y - 1u) * clamp(t, 0.0, 1.0)), f.y - 1u);
    let row = f.y - 1u - y;
    let texel = env[f.z + row * f.x + x];
    return vec3<f32>(f32(texel & 0xffu), f32((texel >> 8u) & 0xffu), f32((texel >> 16u) & 0xffu)) / 255.0;
}

fn miss(d: vec3<f32>) -> vec3<f32> {
    if P.table_at.w != 0u {
        return environment(d);
    }
    return P.background.xyz;
}

// `WhittedMaterial`, unpacked.
struct Material {
    color: vec3<f32>,
    kd: f32,
    specular: vec3<f32>,
    ks: f32,
    shine: f32,
    t: f32,
    ior: f32,
    fresnel: bool,
}

fn material(k: u32) -> Material {
    let at = P.table_at.x + 3u * k;
    let a = tables[at];
    let b = tables[at + 1u];
    let c = tables[at + 2u];
    return Material(a.xyz, a.w, b.xyz, b.w, c.x, c.y, c.z, c.w != 0.0);
}

fn eta(m: Material, entering: bool) -> f32 {
    return select(m.ior, div(1.0, m.ior), entering);
}

// `fresnel_reflectance`: unpolarised Fresnel reflectance of a dielectric.
fn fresnel_reflectance(cos_in: f32, eta_v: f32) -> f32 {
    let cos_i = clamp(cos_in, 0.0, 1.0);
    let sin2_t = eta_v * eta_v * (1.0 - cos_i * cos_i);
    if sin2_t >= 1.0 {
        return 1.0;
    }
    let cos_t = sqrt(1.0 - sin2_t);
    let rs = (eta_v * cos_i - cos_t) / (eta_v * cos_i + cos_t);
    let rp = (cos_i - eta_v * cos_t) / (cos_i + eta_v * cos_t);
    return 0.5 * (rs * rs + rp * rp);
}

// Orthonormal vectors perpendicular to n (Duff et al. 2017), as `basis`.
fn basis_a(n: vec3<f32>) -> vec3<f32> {
    let sign = copysign(1.0, n.z);
    let a = -1.0 / (sign + n.z);
    let b = n.x * n.y * a;
    return vec3<f32>(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x);
}

fn basis_b(n: vec3<f32>) -> vec3<f32> {
    let sign = copysign(1.0, n.z);
    let a = -1.0 / (sign + n.z);
    let b = n.x * n.y * a;
    return vec3<f32>(b, sign + n.y * n.y * a, -n.y);
}

// Which sample of which pixel a ray belongs to.
struct SampleId {
    px: u32,
    py: u32,
    index: u32,
}

// `Whitted::light_position` and `PointLight::seen_from`: light k's
// position, or one sample of its area (its own dimension per depth).
fn light_position(k: u32, p: vec3<f32>, depth: u32, id: SampleId) -> vec3<f32> {
    let at = P.table_at.y + 4u * k;
    let center = tables[at].xyz;
    let has_rect = tables[at].w != 0.0;
    let size = P.shade.x;
    if size <= 0.0 && !has_rect {
        return center;
    }
    let dim = 2u + (depth - 1u) * P.counts.x + k;
    let u = sample(id.px, id.py, id.index, dim);
    if has_rect {
        return (center + scaled(tables[at + 2u].xyz, u.x - 0.5)) + scaled(tables[at + 3u].xyz, u.y - 0.5);
    }
    var offset: vec2<f32>;
    if P.shade.y == 0.0 {
        offset = (u - vec2<f32>(0.5)) * size;
    } else {
        offset = concentric_disk(u) * (0.5 * size);
    }
    let w = normalize_or_zero(p - center);
    if all(w == vec3<f32>(0.0)) {
        return center;
    }
    return (center + scaled(basis_a(w), offset.x)) + scaled(basis_b(w), offset.y);
}

// This invocation's counts, added to the band's counters at the end.
var<private> local_counts: array<u32, COUNTERS>;
const COUNT_EYE: u32 = 0u;
const COUNT_EYE_HITS: u32 = 1u;
const COUNT_SHADOW: u32 = 2u;
const COUNT_REFLECTED: u32 = 3u;
const COUNT_REFRACTED: u32 = 4u;

// What light k adds at a shaded point when nothing blocks it.
fn direct(k: u32, m: Material, ns: vec3<f32>, d: vec3<f32>, p: vec3<f32>, ng: vec3<f32>, depth: u32, id: SampleId) -> vec3<f32> {
    let pos = light_position(k, p, depth, id);
    let to_light = pos - p;
    let dist = length3(to_light);
    if dist == 0.0 {
        return vec3<f32>(0.0);
    }
    let l = div3(to_light, dist);
    let n_dot_l = dot3(ns, l);
    if n_dot_l <= 0.0 {
        return vec3<f32>(0.0);
    }
    let side = select(-ng, ng, dot3(ng, l) >= 0.0);
    local_counts[COUNT_SHADOW]++;
    // `shadow_ray`: from just off the surface to just short of the light.
    let origin = offset_ray_origin(p, side);
    let dir = unit(pos - origin);
    let end = offset_ray_origin(pos, -dir);
    let max_t = dot3(end - origin, dir);
    if !(max_t > 0.0) || occluded(make_query(origin, dir, 0.0), max_t) {
        return vec3<f32>(0.0);
    }
    let r = reflect_dir(-l, ns);
    var spec = 0.0;
    if m.ks > 0.0 {
        let base = max(dot3(r, -d), 0.0);
        // powf(0, 0) is 1; WGSL leaves pow(0, y) undefined.
        var power = select(0.0, 1.0, m.shine == 0.0);
        if base > 0.0 {
            power = pow(base, m.shine);
        }
        spec = m.ks * power;
    }
    let at = P.table_at.y + 4u * k;
    return tables[at + 1u].xyz * (m.kd * n_dot_l * m.color + spec * m.specular);
}

// A ray waiting to be traced: where it starts, its direction, the share of
// the pixel it carries (colour), its weight (the product of the Ks and T
// factors, for --min-weight) and its depth.
struct Pending {
    o: vec3<f32>,
    t_min: f32,
    d: vec3<f32>,
    weight: f32,
    share: vec3<f32>,
    depth: u32,
}

// The rays waiting to be traced, and how many.
struct RayStack {
    rays: array<Pending, RAY_STACK>,
    count: u32,
}

fn push(s: ptr<function, RayStack>, o: vec3<f32>, d: vec3<f32>, weight: f32, share: vec3<f32>, depth: u32) {
    (*s).rays[(*s).count] = Pending(o, 0.0, d, weight, share, depth);
    (*s).count++;
}

// `mirror`: by the shading normal, or the geometric one where an
// interpolated normal would send the ray into the surface.
fn mirror_dir(d: vec3<f32>, ns: vec3<f32>, ng: vec3<f32>) -> vec3<f32> {
    let r = reflect_dir(d, ns);
    if dot3(r, ng) > 0.0 {
        return r;
    }
    return reflect_dir(d, ng);
}

// `Whitted::li`, without recursion: the radiance along an eye ray.
fn radiance(eye: EyeRay, id: SampleId) -> vec3<f32> {
    var color = vec3<f32>(0.0);
    var pending: RayStack;
    pending.rays[0] = Pending(eye.o, eye.t_min, eye.d, 1.0, vec3<f32>(1.0), 1u);
    pending.count = 1u;
    while pending.count > 0u {
        pending.count--;
        let r = pending.rays[pending.count];
        let q = make_query(r.o, r.d, r.t_min);
        let hit = nearest(q, infinity());
        if hit.prim == UNUSED {
            color += r.share * miss(r.d);
        } else {
            color += r.share * shade(&pending, q, hit, r, id);
        }
    }
    return color;
}

// What a hit sends back along its ray (`Whitted::li` but for the rays it
// spawns, which go on `pending`): the ambient term and each light whose
// shadow ray is clear.
fn shade(pending: ptr<function, RayStack>, q: Query, hit: Hit, r: Pending, id: SampleId) -> vec3<f32> {
    if r.depth == 1u {
        local_counts[COUNT_EYE_HITS]++;
    }
    let s = surface(hit, q);
    let m = material(info[hit.prim].x);
    let entering = dot3(s.ng, r.d) < 0.0;
    let flip = select(-1.0, 1.0, entering);
    let ng = s.ng * flip;
    let ns = s.ns * flip;
    var local = P.background.w * m.kd * m.color;
    for (var k = 0u; k < P.counts.x; k++) {
        local += direct(k, m, ns, r.d, s.p, ng, r.depth, id);
    }
    if r.depth < P.render.z {
        spawn(pending, s.p, ng, ns, r, m, entering);
    }
    return local;
}

// `Whitted::spawn` and `choose_rays`: the mirror and refracted rays of a
// hit, under the Fresnel rule or the plain NFF one.
fn spawn(pending: ptr<function, RayStack>, p: vec3<f32>, ng: vec3<f32>, ns: vec3<f32>, r: Pending, m: Material, entering: bool) {
    let d = r.d;
    var refracted = false;
    var t_dir: vec3<f32>;
    if m.t > 0.0 {
        // `refract`: Snell's law, none on total internal reflection.
        let e = eta(m, entering);
        let cos_i = -dot3(d, ns);
        let k = 1.0 - (e * e) * (1.0 - (cos_i * cos_i) * one()) * one();
        if k >= 0.0 {
            t_dir = unit(scaled(d, e) + scaled(ns, (e * cos_i) * one() - sqrt(k)));
            refracted = dot3(t_dir, ng) < 0.0;
        }
    }
    let min_w = P.shade.z;
    let tir = m.t > 0.0 && !refracted;
    let depth = r.depth + 1u;
    let mirror_o = offset_ray_origin(p, ng);
    let mirror_d = mirror_dir(d, ns, ng);
    let t_o = offset_ray_origin(p, -ng);
    if m.fresnel && m.t > 0.0 {
        var kr = 1.0;
        if !tir {
            kr = fresnel_reflectance(-dot3(d, ns), eta(m, entering));
        }
        if kr > 0.0 && r.weight * kr >= min_w {
            local_counts[COUNT_REFLECTED]++;
            push(pending, mirror_o, mirror_d, r.weight * kr, r.share * kr * m.specular, depth);
        }
        let share = m.t * (1.0 - kr);
        if refracted && share > 0.0 && r.weight * share >= min_w {
            local_counts[COUNT_REFRACTED]++;
            push(pending, t_o, t_dir, r.weight * share, r.share * share, depth);
        }
        return;
    }
    if m.ks > 0.0 && r.weight * m.ks >= min_w {
        local_counts[COUNT_REFLECTED]++;
        push(pending, mirror_o, mirror_d, r.weight * m.ks, r.share * m.ks * m.specular, depth);
    }
    // Total internal reflection: the transmitted share reflects.
    if tir && r.weight * m.t >= min_w {
        local_counts[COUNT_REFLECTED]++;
        push(pending, mirror_o, mirror_d, r.weight * m.t, r.share * m.t * m.specular, depth);
    }
    if refracted && r.weight * m.t >= min_w {
        local_counts[COUNT_REFRACTED]++;
        push(pending, t_o, t_dir, r.weight * m.t, r.share * m.t, depth);
    }
}

// One pixel: `render::pixel`.
fn pixel(px: u32, py: u32) -> vec3<f32> {
    let centre_only = P.render.x != 0u;
    if centre_only {
        local_counts[COUNT_EYE]++;
        let eye = camera_ray(f32(px) + 0.5, f32(py) + 0.5, vec2<f32>(0.0));
        return radiance(eye, SampleId(px, py, 0u));
    }
    let position = pattern(px, py, 0u);
    let lens = pattern(px, py, 1u);
    let spp = P.sampler.y;
    var sum = vec3<f32>(0.0);
    var weights = 0.0;
    for (var index = 0u; index < spp; index++) {
        let fs = filter_sample(sample_of(position, index));
        var disk = vec2<f32>(0.0);
        if P.lens.y > 0.0 {
            disk = concentric_disk(sample_of(lens, index));
        }
        local_counts[COUNT_EYE]++;
        let eye = camera_ray(f32(px) + 0.5 + fs.x, f32(py) + 0.5 + fs.y, disk);
        sum += fs.z * radiance(eye, SampleId(px, py, index));
        weights += fs.z;
    }
    // `resolve`: by the weights, or the count where negative lobes leave
    // too little weight.
    if weights > 0.5 {
        return sum / weights;
    }
    return sum / f32(spp);
}

var<workgroup> group_counts: array<atomic<u32>, COUNTERS>;

// Side of a workgroup: 8 on GPUs; 1 on a CPU adapter, where lavapipe 22.3
// (Debian 12's) mixes up the colours of lanes whose ray trees differ.
override GROUP_SIDE: u32 = 8u;

@compute @workgroup_size(GROUP_SIDE, GROUP_SIDE, 1)
fn main(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(local_invocation_index) lid: u32) {
    let x = gid.x;
    let y = P.window.z + gid.y;
    if x < P.window.x && y < P.window.z + P.window.w && y < P.window.y {
        let px = P.image.z + x;
        let py = P.image.w + y;
        var out: vec4<f32>;
        if P.render.w == MODE_EYE_HITS {
            local_counts[COUNT_EYE]++;
            let eye = camera_ray(f32(px) + 0.5, f32(py) + 0.5, vec2<f32>(0.0));
            let hit = nearest(make_query(eye.o, eye.d, eye.t_min), infinity());
            if hit.prim != UNUSED {
                local_counts[COUNT_EYE_HITS]++;
            }
            out = vec4<f32>(hit.t, bitcast<f32>(hit.prim), eye.d.x, eye.d.y);
        } else {
            out = vec4<f32>(pixel(px, py), 1.0);
        }
        film[y * P.window.x + x] = out;
    }
    for (var i = 0u; i < COUNTERS; i++) {
        if local_counts[i] != 0u {
            atomicAdd(&group_counts[i], local_counts[i]);
        }
    }
    workgroupBarrier();
    if lid == 0u {
        for (var i = 0u; i < COUNTERS; i++) {
            let n = atomicLoad(&group_counts[i]);
            if n != 0u {
                atomicAdd(&counters[P.counts.z * COUNTERS + i], n);
            }
        }
    }
}
