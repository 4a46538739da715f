// The samplers and filters of `sampling.rs` and `filter.rs`, operation for
// operation: the integer hashing is exact, so every sample is the CPU's up
// to the rounding of the few float steps.

// 1 - 2^-24, the largest float below one, and 2^-32.
const ONE_MINUS_EPSILON_BITS: u32 = 0x3f7fffffu;
const TWO_POW_MINUS_32_BITS: u32 = 0x2f800000u;

fn to_unit(x: u32) -> f32 {
    return min(f32(x) * bitcast<f32>(TWO_POW_MINUS_32_BITS), bitcast<f32>(ONE_MINUS_EPSILON_BITS));
}

fn is_pow2(n: u32) -> bool {
    return n != 0u && (n & (n - 1u)) == 0u;
}

// x / n, by an exact power-of-two scale where n is one (as `over`).
fn over(x: f32, n: u32) -> f32 {
    if is_pow2(n) {
        return x * bitcast<f32>((127u - countTrailingZeros(n)) << 23u);
    }
    return x / f32(n);
}

fn hash(x0: u32) -> u32 {
    var x = x0;
    x ^= x >> 16u;
    x *= 0x7feb352du;
    x ^= x >> 15u;
    x *= 0x846ca68bu;
    x ^= x >> 16u;
    return x;
}

fn hash4(a: u32, b: u32, c: u32, d: u32) -> u32 {
    return hash(hash(hash(hash(a) ^ b) ^ (c * 0x9e3779b9u)) ^ d);
}

// Kensler's permutation of 0..l (`permute`).
fn permute(i0: u32, l: u32, p: u32) -> u32 {
    if l <= 1u {
        return 0u;
    }
    var w = l - 1u;
    w |= w >> 1u;
    w |= w >> 2u;
    w |= w >> 4u;
    w |= w >> 8u;
    w |= w >> 16u;
    var i = i0;
    loop {
        i ^= p;
        i *= 0xe170893du;
        i ^= p >> 16u;
        i ^= (i & w) >> 4u;
        i ^= p >> 8u;
        i *= 0x0929eb3fu;
        i ^= p >> 23u;
        i ^= (i & w) >> 1u;
        i *= 1u | (p >> 27u);
        i *= 0x6935fa69u;
        i ^= (i & w) >> 11u;
        i *= 0x74dcb303u;
        i ^= (i & w) >> 2u;
        i *= 0x9e501cc3u;
        i ^= (i & w) >> 2u;
        i *= 0xc860a3dfu;
        i &= w;
        i ^= i >> 5u;
        if i < l {
            break;
        }
    }
    return (i + p) % l;
}

fn randfloat(i0: u32, p: u32) -> f32 {
    var i = i0;
    i ^= p;
    i ^= i >> 17u;
    i ^= i >> 10u;
    i *= 0xb36534e5u;
    i ^= i >> 12u;
    i ^= i >> 21u;
    i *= 0x93fc4795u;
    i ^= 0xdf6e307fu;
    i ^= i >> 17u;
    i *= 1u | (p >> 18u);
    return to_unit(i);
}

fn multi_jittered(s: u32, n: u32, p: u32, correlated: bool) -> vec2<f32> {
    let j = s / n;
    let k = s % n;
    var px: u32;
    var py: u32;
    if correlated {
        px = p * 0xa511e9b3u;
        py = p * 0x63d83595u;
    } else {
        px = hash(p ^ (k * 0xa511e9b3u));
        py = hash(p ^ (j * 0x63d83595u) ^ 0x55555555u);
    }
    let sx = permute(j, n, px);
    let sy = permute(k, n, py);
    let jx = randfloat(s, p * 0xa399d265u);
    let jy = randfloat(s, p * 0x711ad6a5u);
    let one = bitcast<f32>(ONE_MINUS_EPSILON_BITS);
    return vec2<f32>(
        min(over(f32(k) + over(f32(sx) + jx, n), n), one),
        min(over(f32(j) + over(f32(sy) + jy, n), n), one),
    );
}

fn sobol_dim1(i0: u32) -> u32 {
    var i = i0;
    var r = 0u;
    var v = 1u << 31u;
    while i != 0u {
        if (i & 1u) != 0u {
            r ^= v;
        }
        i >>= 1u;
        v ^= v >> 1u;
    }
    return r;
}

fn laine_karras(x0: u32, seed: u32) -> u32 {
    var x = x0 + seed;
    x ^= x * 0x6c50b47cu;
    x ^= x * 0xb82f1e52u;
    x ^= x * 0xc7afe638u;
    x ^= x * 0x8d22f6e6u;
    return x;
}

fn nested_uniform_scramble(x: u32, seed: u32) -> u32 {
    return reverseBits(laine_karras(reverseBits(x), seed));
}

// The pattern of (pixel, dimension): `Sampler::pattern`.
fn pattern(px: u32, py: u32, dim: u32) -> u32 {
    return hash4(px, py, dim, P.sampler.w);
}

// Sample `index` of pattern `p`: `Sampler::sample_of`.
fn sample_of(p: u32, index: u32) -> vec2<f32> {
    let count = P.sampler.y;
    let n = P.sampler.z;
    switch P.sampler.x {
        case 0u: { // random
            return vec2<f32>(randfloat(index, p), randfloat(index, p ^ 0x9e3779b9u));
        }
        case 1u: { // regular
            let s = permute(index, count, p);
            return vec2<f32>(over(f32(s % n) + 0.5, n), over(f32(s / n) + 0.5, n));
        }
        case 2u: { // jittered
            let s = permute(index, count, p);
            let jx = randfloat(s, p ^ 0x68bc21ebu);
            let jy = randfloat(s, p ^ 0x02e5be93u);
            return vec2<f32>(over(f32(s % n) + jx, n), over(f32(s / n) + jy, n));
        }
        case 3u: { // n-rooks
            let s = permute(index, count, p);
            let col = permute(s, count, p * 0xa511e9b3u);
            let jx = randfloat(s, p ^ 0x68bc21ebu);
            let jy = randfloat(s, p ^ 0x02e5be93u);
            return vec2<f32>(over(f32(col) + jx, count), over(f32(s) + jy, count));
        }
        case 4u, 5u: { // multi-jittered, correlated multi-jittered
            return multi_jittered(permute(index, count, p), n, p, P.sampler.x == 5u);
        }
        case 6u: { // Hammersley
            let s = permute(index, count, p);
            let shift = randfloat(0u, p ^ 0x5bd1e995u);
            let x = over(f32(s) + 0.5, count) + shift;
            let y = f32(reverseBits(s) ^ hash(p ^ 0x1b873593u)) * bitcast<f32>(TWO_POW_MINUS_32_BITS);
            return vec2<f32>(x - floor(x), min(y, bitcast<f32>(ONE_MINUS_EPSILON_BITS)));
        }
        default: { // Sobol, Owen-scrambled
            let s = nested_uniform_scramble(index, hash(p));
            let x = nested_uniform_scramble(reverseBits(s), hash(p ^ 0x2545f491u));
            let y = nested_uniform_scramble(sobol_dim1(s), hash(p ^ 0x9e3779b9u));
            return vec2<f32>(to_unit(x), to_unit(y));
        }
    }
}

fn sample(px: u32, py: u32, index: u32, dim: u32) -> vec2<f32> {
    return sample_of(pattern(px, py, dim), index);
}

// Shirley and Chiu's concentric map of the square onto the unit disc.
fn concentric_disk(u: vec2<f32>) -> vec2<f32> {
    let o = 2.0 * u - vec2<f32>(1.0);
    if o.x == 0.0 && o.y == 0.0 {
        return vec2<f32>(0.0);
    }
    let quarter_pi = 0.7853981633974483;
    var r: f32;
    var theta: f32;
    if abs(o.x) > abs(o.y) {
        r = o.x;
        theta = quarter_pi * (o.y / o.x);
    } else {
        r = o.y;
        theta = 2.0 * quarter_pi - quarter_pi * (o.x / o.y);
    }
    return vec2<f32>(r * cos(theta), r * sin(theta));
}

// Filters (`FilterKind` in declaration order): box, tent, Gaussian, Mitchell.
fn filter_radius(kind: u32) -> f32 {
    switch kind {
        case 0u: { return 0.5; }
        case 1u: { return 1.0; }
        case 2u: { return 1.5; }
        default: { return 2.0; }
    }
}

fn filter_eval(kind: u32, x: f32) -> f32 {
    let ax = abs(x);
    switch kind {
        case 0u: { return select(0.0, 1.0, ax <= 0.5); }
        case 1u: { return max(1.0 - ax, 0.0); }
        case 2u: {
            return max(exp(-x * x / 0.5) - exp(-1.5 * 1.5 / 0.5), 0.0);
        }
        default: {
            let b = 1.0 / 3.0;
            let c = 1.0 / 3.0;
            if ax < 1.0 {
                return ((12.0 - 9.0 * b - 6.0 * c) * ax * ax * ax + (-18.0 + 12.0 * b + 6.0 * c) * ax * ax
                    + (6.0 - 2.0 * b)) / 6.0;
            } else if ax < 2.0 {
                return ((-b - 6.0 * c) * ax * ax * ax + (6.0 * b + 30.0 * c) * ax * ax
                    + (-12.0 * b - 48.0 * c) * ax + (8.0 * b + 24.0 * c)) / 6.0;
            }
            return 0.0;
        }
    }
}

const FILTER_TABLE: u32 = 256u;

fn cdf(i: u32) -> f32 {
    let at = P.table_at.z * 4u + i;
    return tables[at / 4u][at % 4u];
}

// `Filter::sample_1d`: the inverse of the tabulated CDF of |filter|.
fn filter_sample_1d(kind: u32, u: f32) -> f32 {
    // The first entry greater than u (a partition point), by bisection.
    var lo = 0u;
    var hi = FILTER_TABLE + 1u;
    while lo < hi {
        let mid = (lo + hi) / 2u;
        if cdf(mid) <= u {
            lo = mid + 1u;
        } else {
            hi = mid;
        }
    }
    let i = clamp(lo, 1u, FILTER_TABLE) - 1u;
    let c0 = cdf(i);
    let c1 = cdf(i + 1u);
    var t = 0.5;
    if c1 > c0 {
        t = (u - c0) / (c1 - c0);
    }
    let r = filter_radius(kind);
    return -r + (f32(i) + t) / f32(FILTER_TABLE) * 2.0 * r;
}

// `Filter::sample`: a pixel offset distributed like |filter|, and the
// filter's sign there as the sample's weight.
fn filter_sample(u: vec2<f32>) -> vec3<f32> {
    let kind = P.render.y;
    if kind == 0u {
        return vec3<f32>(u - vec2<f32>(0.5), 1.0);
    }
    let x = filter_sample_1d(kind, u.x);
    let y = filter_sample_1d(kind, u.y);
    let w = filter_eval(kind, x) * filter_eval(kind, y);
    return vec3<f32>(x, y, select(1.0, -1.0, w < 0.0));
}
