// The clay of Bowsher 2022 (§3.0.3, eq. 12–19; materials/clay.ron) written by hand, the way a
// person would write it for this kernel: in the local shading frame (n = +z), constants inlined,
// one function. It is the baseline that `cargo bench --bench kernel` compares glazec's generated
// WeidlichWilkie kernel against; the bench first checks that both give the same values.
//
// Water film: GGX (Walter et al. 2007) with roughness 0.35 (α = r²), Schlick Fresnel with
// F0 = 0.04 (η = 1.5), Schlick–GGX shadowing with k = (r + 1)²/8, absorption σa = 0.8 over
// thickness 0.25 along both refracted paths, t = (1 − G) + T21·G. Body: qualitative Oren–Nayar
// (seed eq. 17), albedo (0.72, 0.42, 0.30), σ = 0.6.

struct DirectionPair {
    wi: vec4<f32>,
    wo: vec4<f32>,
}

struct EvalDispatch {
    pair_count: u32,
}

@group(0) @binding(0) var<storage, read> pairs: array<DirectionPair>;
@group(0) @binding(1) var<storage, read_write> values: array<vec4<f32>>;
@group(0) @binding(2) var<uniform> dispatch: EvalDispatch;

const PI: f32 = 3.1415927;
const ALPHA: f32 = 0.1225;           // 0.35²
const K: f32 = 0.2278125;            // (0.35 + 1)² / 8
const F0: f32 = 0.04;                // ((1.5 − 1)/(1.5 + 1))²
const INV_IOR: f32 = 0.6666667;
const SIGMA_A_D: f32 = 0.2;          // 0.8 × 0.25
const ALBEDO: vec3<f32> = vec3<f32>(0.72, 0.42, 0.30);
const ON_A: f32 = 0.73913044;        // 1 − 0.5 σ²/(σ² + 0.33), σ = 0.6
const ON_B: f32 = 0.36;              // 0.45 σ²/(σ² + 0.09)
const COS_MIN: f32 = 1e-4;

fn clay(v: vec3<f32>, l: vec3<f32>) -> vec3<f32> {
    if (v.z <= 0.0 || l.z <= 0.0) {
        return vec3<f32>(0.0);
    }
    let nv = max(v.z, COS_MIN);
    let nl = max(l.z, COS_MIN);

    // The water film's microfacet lobe.
    let h = normalize(v + l);
    let a2 = ALPHA * ALPHA;
    let den = h.z * h.z * a2 + h.x * h.x + h.y * h.y;
    let d = a2 / (PI * den * den);
    let g = nv / (nv * (1.0 - K) + K) * (nl / (nl * (1.0 - K) + K));
    let m = 1.0 - clamp(dot(v, h), 0.0, 1.0);
    let fresnel = F0 + (1.0 - F0) * (m * m * m * m * m);
    let specular = d * g * fresnel / (4.0 * nv * nl);

    // Through the film to the clay.
    let t12 = 1.0 - fresnel;
    let vt = -refract(-v, vec3<f32>(0.0, 0.0, 1.0), INV_IOR);
    let lt = -refract(-l, vec3<f32>(0.0, 0.0, 1.0), INV_IOR);
    let nvt = max(vt.z, COS_MIN);
    let nlt = max(lt.z, COS_MIN);
    let absorption = exp(-SIGMA_A_D * (1.0 / nlt + 1.0 / nvt));
    let inner = t12 * g + (1.0 - g);
    let s = dot(vt, lt) - nvt * nlt;
    let oren_nayar = ALBEDO * ((ON_A + ON_B * max(s, 0.0) / max(nvt, nlt)) / PI);

    return specular + oren_nayar * (t12 * absorption * inner);
}

@compute @workgroup_size(64)
fn eval_pairs(@builtin(global_invocation_id) id: vec3<u32>) {
    if (id.x >= dispatch.pair_count) {
        return;
    }
    let pair = pairs[id.x];
    values[id.x] = vec4<f32>(clay(pair.wo.xyz, pair.wi.xyz), 0.0);
}
