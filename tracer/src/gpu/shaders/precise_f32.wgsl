// The CPU's double-precision steps in single precision, on adapters
// without f64 arithmetic: triangles' exact edge hits go by the f32 edge
// functions, and shadow rays leaving a cone may see it again (speckles of
// self-shadowing, which the CPU's f64 avoids).

fn div(x: f32, y: f32) -> f32 {
    return x / y;
}

fn exact_difference(a: f32, b: f32, c: f32, d: f32) -> f32 {
    return a * b - c * d;
}

// The open cone |p⊥| = r0 + slope·h, 0 ≤ h ≤ height: base and height in
// c0, axis and r0 in c1, slope in c2.x.
fn intersect_cone(c0: vec4<f32>, c1: vec4<f32>, c2: vec4<f32>, q: Query, t_max: f32, cull: u32) -> f32 {
    let axis = c1.xyz;
    let o = q.o - c0.xyz;
    let d = q.d;
    let slope = c2.x;
    let r0 = c1.w;
    let height = c0.w;
    let oa = dot(o, axis);
    let da = dot(d, axis);
    let op = o - axis * oa;
    let dp = d - axis * da;
    let r = r0 + slope * oa;
    let a = dot(dp, dp) - slope * slope * da * da;
    let b = 2.0 * (dot(op, dp) - slope * r * da);
    let cc = dot(op, op) - r * r;
    var ts: array<f32, 2>;
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
        let qq = -0.5 * (b + copysign(sqrt(disc), b));
        let x = qq / a;
        let y = select(qq / a, cc / qq, qq != 0.0);
        ts[0] = min(x, y);
        ts[1] = max(x, y);
    }
    for (var i = 0u; i < 2u; i++) {
        let t = ts[i];
        if !in_range(t, q, t_max) {
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
                return t;
            }
            continue;
        }
        return t;
    }
    return infinity();
}

