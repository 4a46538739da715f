// The CPU's double-precision steps, on adapters with f64 arithmetic.

// x / y rounded as the CPU's division rounds it. GPUs may divide by an
// approximate reciprocal (Vulkan allows 2.5 ulp), and an ulp in a
// direction or a distance changes which of two coincident surfaces a ray
// sees; the quotient rounded from f64 is the correctly rounded one but in
// the rarest halfway cases.
fn div(x: f32, y: f32) -> f32 {
    return f32(f64(x) / f64(y));
}

// a·b − c·d of f32 values: the products are exact in f64, so this is the
// CPU's value bit for bit.
fn exact_difference(a: f32, b: f32, c: f32, d: f32) -> f32 {
    return f32(f64(a) * f64(b) - f64(c) * f64(d));
}

// The open cone |p⊥| = r0 + slope·h, 0 ≤ h ≤ height: base and height in
// c0, axis and r0 in c1, slope in c2.x.
fn intersect_cone(c0: vec4<f32>, c1: vec4<f32>, c2: vec4<f32>, q: Query, t_max: f32, cull: u32) -> f32 {
    let axis = vec3<f64>(c1.xyz);
    let o = vec3<f64>(q.o) - vec3<f64>(c0.xyz);
    let d = vec3<f64>(q.d);
    let slope = f64(c2.x);
    let r0 = f64(c1.w);
    let height = f64(c0.w);
    let oa = dot(o, axis);
    let da = dot(d, axis);
    let op = o - axis * oa;
    let dp = d - axis * da;
    let r = r0 + slope * oa;
    let a = dot(dp, dp) - slope * slope * da * da;
    let b = 2.0lf * (dot(op, dp) - slope * r * da);
    let cc = dot(op, op) - r * r;
    var ts: array<f64, 2>;
    if abs(a) < 1e-14lf {
        if b == 0.0lf {
            return infinity();
        }
        ts[0] = -cc / b;
        ts[1] = ts[0];
    } else {
        let disc = b * b - 4.0lf * a * cc;
        if disc < 0.0lf {
            return infinity();
        }
        let qq = -0.5lf * (b + select(-sqrt(disc), sqrt(disc), b >= 0.0lf));
        let x = qq / a;
        let y = select(qq / a, cc / qq, qq != 0.0lf);
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
        if h < 0.0lf || h > height || r0 + slope * h < 0.0lf {
            continue;
        }
        if cull != CULL_NONE {
            let radial = o + d * t - axis * h;
            let front = dot(d, radial - axis * (slope * length(radial))) < 0.0lf;
            if front == (cull == CULL_BACK) {
                return tf;
            }
            continue;
        }
        return tf;
    }
    return infinity();
}

