// Rays and the primitive tests of `math.rs` and `geometry.rs`. Where the
// CPU computes in f64 (triangle edges hit exactly, cones), the shaders take
// their helpers and the cone's precision (`Real`) from `precise_f64.wgsl`
// on adapters with f64 and from `precise_f32.wgsl` on others.

// Rounding-error bounds and the slab widening (`aabb.rs`), bit for bit as
// the CPU computes them; `gpu/mod.rs` writes their values here.
// const GAMMA2_BITS, GAMMA3_BITS, GAMMA5_BITS, SLAB_WIDEN_BITS,
// ENTRY_SLACK_BITS: u32 (prepended).

const INFINITY_BITS: u32 = 0x7f800000u;
const CULL_NONE: u32 = 0u;
const CULL_BACK: u32 = 1u;

fn infinity() -> f32 {
    return bitcast<f32>(INFINITY_BITS);
}

// `RayQuery`: the ray with what its tests share.
struct Query {
    o: vec3<f32>,
    d: vec3<f32>,
    inv: vec3<f32>,
    t_min: f32,
    // The triangle test's axis permutation and shear.
    k: vec3<u32>,
    shear: vec3<f32>,
}

// Sums of products as the CPU rounds them: each product rounded, then
// summed in glam's order. GPU compilers fuse a product into the sum that
// follows (one rounding instead of two); multiplying by `P.shade.w`, a 1
// from the uniforms that no compiler can fold, keeps the product's own
// rounding, and a fused (x·y)·1 + z rounds as x·y + z does.
fn one() -> f32 {
    return P.shade.w;
}

fn dot3(a: vec3<f32>, b: vec3<f32>) -> f32 {
    let p = (a * b) * one();
    return (p.x + p.y) + p.z;
}

// a·s, rounded, for adding to something.
fn scaled(a: vec3<f32>, s: f32) -> vec3<f32> {
    return (a * s) * one();
}

fn cross3(a: vec3<f32>, b: vec3<f32>) -> vec3<f32> {
    return (a.yzx * b.zxy) * one() - (a.zxy * b.yzx) * one();
}

fn length3(v: vec3<f32>) -> f32 {
    return sqrt(dot3(v, v));
}

fn div3(v: vec3<f32>, s: f32) -> vec3<f32> {
    return vec3<f32>(div(v.x, s), div(v.y, s), div(v.z, s));
}

// `Vec3A::normalize`: divided by the length.
fn unit(v: vec3<f32>) -> vec3<f32> {
    return div3(v, length3(v));
}

fn make_query(o: vec3<f32>, d: vec3<f32>, t_min: f32) -> Query {
    // Rounded as the CPU's division: the box test's slack covers the
    // rounding of exact operations, not of an approximate reciprocal.
    let inv = clamp(vec3<f32>(div(1.0, d.x), div(1.0, d.y), div(1.0, d.z)), vec3<f32>(-1e30), vec3<f32>(1e30));
    let a = abs(d);
    var kz = 2u;
    if a.x >= a.y && a.x >= a.z {
        kz = 0u;
    } else if a.y >= a.z {
        kz = 1u;
    }
    var kx = (kz + 1u) % 3u;
    var ky = (kx + 1u) % 3u;
    if d[kz] < 0.0 {
        let swap = kx;
        kx = ky;
        ky = swap;
    }
    let shear = vec3<f32>(div(d[kx], d[kz]), div(d[ky], d[kz]), div(1.0, d[kz]));
    return Query(o, d, inv, t_min, vec3<u32>(kx, ky, kz), shear);
}

// `offset_ray_origin`: p moved off its surface along n by a few ulps of
// its own magnitude (Wächter and Binder, Ray Tracing Gems ch. 6).
fn offset_ray_origin(p: vec3<f32>, n: vec3<f32>) -> vec3<f32> {
    var out: vec3<f32>;
    for (var i = 0u; i < 3u; i++) {
        let of_i = i32(256.0 * n[i]);
        let bits = bitcast<i32>(p[i]);
        let moved = bitcast<f32>(bits + select(of_i, -of_i, p[i] < 0.0));
        out[i] = select(moved, p[i] + n[i] / 65536.0, abs(p[i]) < 1.0 / 32.0);
    }
    return out;
}

fn reflect_dir(d: vec3<f32>, n: vec3<f32>) -> vec3<f32> {
    return d - scaled(n, 2.0 * dot3(d, n));
}

fn normal_or_facing(v: vec3<f32>, d: vec3<f32>) -> vec3<f32> {
    let l2 = dot3(v, v);
    if l2 > 0.0 && l2 < 1e38 {
        return div3(v, sqrt(l2));
    }
    return -d;
}

fn normalize_or_zero(v: vec3<f32>) -> vec3<f32> {
    let l2 = dot3(v, v);
    if l2 > 0.0 && l2 < 1e38 {
        return v * div(1.0, sqrt(l2));
    }
    return vec3<f32>(0.0);
}

fn copysign(a: f32, b: f32) -> f32 {
    return bitcast<f32>((bitcast<u32>(a) & 0x7fffffffu) | (bitcast<u32>(b) & 0x80000000u));
}

// A hit: distance, primitive id, barycentrics; `prim == UNUSED` for none.
struct Hit {
    t: f32,
    prim: u32,
    u: f32,
    v: f32,
}

fn no_hit() -> Hit {
    return Hit(infinity(), UNUSED, 0.0, 0.0);
}

fn in_range(t: f32, q: Query, t_max: f32) -> bool {
    return t > q.t_min && t < t_max;
}

// The sphere test of Haines et al., "Precision Improvements for Ray/Sphere
// Intersection" (Ray Tracing Gems, 2019). Returns infinity for a miss.
fn intersect_sphere(s: vec4<f32>, q: Query, t_max: f32, cull: u32) -> f32 {
    let f = q.o - s.xyz;
    let b = -dot3(f, q.d);
    let l = f + scaled(q.d, b);
    let r2 = s.w * s.w;
    let disc = r2 - dot3(l, l);
    if disc < 0.0 {
        return infinity();
    }
    let c = dot3(f, f) - r2;
    let qq = b + copysign(sqrt(disc), b);
    var t0 = 0.0;
    var t1 = 0.0;
    if qq != 0.0 {
        t0 = div(c, qq);
        t1 = qq;
    }
    if t0 > t1 {
        let swap = t0;
        t0 = t1;
        t1 = swap;
    }
    let ok0 = in_range(t0, q, t_max);
    let ok1 = in_range(t1, q, t_max);
    if cull == CULL_NONE {
        if ok0 {
            return t0;
        }
        if ok1 {
            return t1;
        }
    } else if cull == CULL_BACK {
        if ok0 {
            return t0;
        }
    } else if ok1 {
        return t1;
    }
    return infinity();
}

// `geometry::intersect_cone` in `Real`, the precision the precise file
// chooses (f64 as on the CPU where the adapter has it), with that file's
// `with_sign_of`: the open cone |p⊥| = r0 + slope·h, 0 ≤ h ≤ height, with
// base and height in c0, axis and r0 in c1, slope in c2.x.
fn intersect_cone(c0: vec4<f32>, c1: vec4<f32>, c2: vec4<f32>, q: Query, t_max: f32, cull: u32) -> f32 {
    let axis = vec3<Real>(c1.xyz);
    let o = vec3<Real>(q.o) - vec3<Real>(c0.xyz);
    let d = vec3<Real>(q.d);
    let slope = Real(c2.x);
    let r0 = Real(c1.w);
    let height = Real(c0.w);
    let oa = dot(o, axis);
    let da = dot(d, axis);
    let op = o - axis * oa;
    let dp = d - axis * da;
    let r = r0 + slope * oa;
    let a = dot(dp, dp) - slope * slope * da * da;
    let b = 2.0 * (dot(op, dp) - slope * r * da);
    let cc = dot(op, op) - r * r;
    var ts: array<Real, 2>;
    if abs(a) < 1e-14 {
        if b == 0.0 {
            return infinity();
        }
        ts[0] = -cc / b;
        ts[1] = ts[0];
    } else {
        let disc = b * b - 4.0 * a * cc;
        if disc < 0.0 {
            return infinity();
        }
        let qq = -0.5 * (b + with_sign_of(sqrt(disc), b));
        let x = qq / a;
        let y = select(qq / a, cc / qq, qq != 0.0);
        ts[0] = min(x, y);
        ts[1] = max(x, y);
    }
    for (var i = 0u; i < 2u; i++) {
        let t = ts[i];
        let tf = f32(t);
        if !in_range(tf, q, t_max) {
            continue;
        }
        let h = oa + t * da;
        if h < 0.0 || h > height || r0 + slope * h < 0.0 {
            continue;
        }
        if cull != CULL_NONE {
            let radial = o + d * t - axis * h;
            let front = dot(d, radial - axis * (slope * length(radial))) < 0.0;
            if front == (cull == CULL_BACK) {
                return tf;
            }
            continue;
        }
        return tf;
    }
    return infinity();
}

fn intersect_plane(point: vec3<f32>, n: vec3<f32>, q: Query, t_max: f32, cull: u32) -> f32 {
    let denom = dot3(n, q.d);
    var culled = false;
    if cull == CULL_BACK {
        culled = denom >= 0.0;
    } else if cull != CULL_NONE {
        culled = denom <= 0.0;
    }
    if denom == 0.0 || culled {
        return infinity();
    }
    let t = div(dot3(n, point - q.o), denom);
    if in_range(t, q, t_max) {
        return t;
    }
    return infinity();
}

fn max3_abs(p: f32, q: f32, r: f32) -> f32 {
    return max(max(abs(p), abs(q)), abs(r));
}

// Woop, Benthin and Wald's watertight test (JCGT 2013). Returns
// (t, u, v), t infinite for a miss.
fn intersect_triangle(a0: vec3<f32>, b0: vec3<f32>, c0: vec3<f32>, q: Query, t_max: f32, cull: u32) -> vec3<f32> {
    let miss = vec3<f32>(infinity(), 0.0, 0.0);
    let kx = q.k.x;
    let ky = q.k.y;
    let kz = q.k.z;
    let s = q.shear;
    let a = a0 - q.o;
    let b = b0 - q.o;
    let c = c0 - q.o;
    let one = one();
    let ax = a[kx] - (s.x * a[kz]) * one;
    let ay = a[ky] - (s.y * a[kz]) * one;
    let bx = b[kx] - (s.x * b[kz]) * one;
    let by = b[ky] - (s.y * b[kz]) * one;
    let cx = c[kx] - (s.x * c[kz]) * one;
    let cy = c[ky] - (s.y * c[kz]) * one;
    var u = (cx * by) * one - (cy * bx) * one;
    var v = (ax * cy) * one - (ay * cx) * one;
    var w = (bx * ay) * one - (by * ax) * one;
    if u == 0.0 || v == 0.0 || w == 0.0 {
        // Exactly on an edge in single precision: decide exactly.
        u = exact_difference(cx, by, cy, bx);
        v = exact_difference(ax, cy, ay, cx);
        w = exact_difference(bx, ay, by, ax);
    }
    if (u < 0.0 || v < 0.0 || w < 0.0) && (u > 0.0 || v > 0.0 || w > 0.0) {
        return miss;
    }
    let det = u + v + w;
    if det == 0.0 {
        return miss;
    }
    if (cull == CULL_BACK && det < 0.0) || (cull > CULL_BACK && det > 0.0) {
        return miss;
    }
    let az = s.z * a[kz];
    let bz = s.z * b[kz];
    let cz = s.z * c[kz];
    let t = div((u * az) * one + (v * bz) * one + (w * cz) * one, det);
    if !in_range(t, q, t_max) {
        return miss;
    }
    let inv = div(1.0, det);
    // `triangle_t_error`: the test's rounding error bound on t (pbrt-v4).
    let max_x = max3_abs(ax, bx, cx);
    let max_y = max3_abs(ay, by, cy);
    let max_z = max3_abs(az, bz, cz);
    let max_e = max3_abs(u, v, w);
    let g2 = bitcast<f32>(GAMMA2_BITS);
    let g3 = bitcast<f32>(GAMMA3_BITS);
    let g5 = bitcast<f32>(GAMMA5_BITS);
    let delta_z = g3 * max_z;
    let delta_x = g5 * (max_x + max_z);
    let delta_y = g5 * (max_y + max_z);
    let delta_e = 2.0 * (g2 * max_x * max_y + delta_y * max_x + delta_x * max_y);
    let error = 3.0 * (g3 * max_e * max_z + delta_e * max_z + delta_z * max_e) * abs(inv);
    if t <= error {
        return miss;
    }
    return vec3<f32>(t, v * inv, w * inv);
}

// `Geometry::intersect`: primitive `id` within (q.t_min, t_max).
fn intersect(id: u32, q: Query, t_max: f32) -> Hit {
    var cull = CULL_NONE;
    if P.counts.y != 0u {
        cull = info[id].z;
    }
    var h = Hit(infinity(), id, 0.0, 0.0);
    if id < P.ids.x {
        h.t = intersect_sphere(shapes[id], q, t_max, cull);
    } else if id < P.ids.y {
        let at = P.shape_at.x + 3u * (id - P.ids.x);
        let r = intersect_triangle(shapes[at].xyz, shapes[at + 1u].xyz, shapes[at + 2u].xyz, q, t_max, cull);
        h.t = r.x;
        h.u = r.y;
        h.v = r.z;
    } else if id < P.ids.z {
        let at = P.shape_at.y + 3u * (id - P.ids.y);
        h.t = intersect_cone(shapes[at], shapes[at + 1u], shapes[at + 2u], q, t_max, cull);
    } else {
        let at = P.shape_at.z + 2u * (id - P.ids.z);
        h.t = intersect_plane(shapes[at].xyz, shapes[at + 1u].xyz, q, t_max, cull);
    }
    return h;
}

// `Surface`: the point, the geometric normal and the shading normal.
struct Surface {
    p: vec3<f32>,
    ng: vec3<f32>,
    ns: vec3<f32>,
}

// `Geometry::surface`.
fn surface(hit: Hit, q: Query) -> Surface {
    let id = hit.prim;
    let p = q.o + scaled(q.d, hit.t);
    if id < P.ids.x {
        let s = shapes[id];
        let n = normal_or_facing(div3(p - s.xyz, s.w), q.d);
        return Surface(p, n, n);
    } else if id < P.ids.y {
        let at = P.shape_at.x + 3u * (id - P.ids.x);
        let a = shapes[at].xyz;
        let b = shapes[at + 1u].xyz;
        let c = shapes[at + 2u].xyz;
        let ng = normal_or_facing(cross3(b - a, c - a), q.d);
        let w = 1.0 - hit.u - hit.v;
        let pb = (scaled(a, w) + scaled(b, hit.u)) + scaled(c, hit.v);
        var ns = ng;
        let patch_id = info[id].y;
        if patch_id != UNUSED {
            let pn = P.shape_at.w + 3u * patch_id;
            let n = normalize_or_zero((scaled(shapes[pn].xyz, w) + scaled(shapes[pn + 1u].xyz, hit.u)) + scaled(shapes[pn + 2u].xyz, hit.v));
            if all(n == vec3<f32>(0.0)) {
                ns = ng;
            } else if dot3(n, ng) < 0.0 {
                ns = -n;
            } else {
                ns = n;
            }
        }
        return Surface(pb, ng, ns);
    } else if id < P.ids.z {
        let at = P.shape_at.y + 3u * (id - P.ids.y);
        let base = shapes[at].xyz;
        let axis = shapes[at + 1u].xyz;
        let slope = shapes[at + 2u].x;
        let rel = p - base;
        let radial = normalize_or_zero(rel - scaled(axis, dot3(rel, axis)));
        let n = normal_or_facing(radial - scaled(axis, slope), q.d);
        return Surface(p, n, n);
    }
    let at = P.shape_at.z + 2u * (id - P.ids.z);
    let point = shapes[at].xyz;
    let n = shapes[at + 1u].xyz;
    return Surface(p - scaled(n, dot3(n, p - point)), n, n);
}
