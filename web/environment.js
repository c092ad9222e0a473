// The playground's environment: an analytic sky, prefiltered on the GPU into the two images a
// material's `<m>_ibl_lobes` are looked up in (the split sum of Karis 2013, "Real Shading in
// Unreal Engine 4"), laid out as glazec's own renderer lays them out (crates/glazec-gpu,
// environment.rs):
//
// * radiance: equirectangular (u = ½ + atan2(d.x, d.z)/2π, v = acos(d.y)/π, y up), 512 × 256,
//   LEVELS mip levels; level k is the sky convolved with a GGX lobe of roughness r = k/(LEVELS − 1)
//   (α = r²) around each texel's direction, with n = v = r, weighted by n·l;
// * irradiance: E(d)/π, 64 × 32, the cosine-weighted mean of the sky around d.
//
// The sky is a function, not an image, so each sample evaluates it exactly: no pyramid, no
// filtered importance sampling. Both images are rgba16float, filtered linearly within and
// between levels; a constant sky stays exactly constant (the weights are normalised).

export const LEVELS = 7;
const WIDTH = 512;
const IRRADIANCE_WIDTH = 64;
/// GGX samples per texel of a prefiltered level, cosine samples per irradiance texel.
const PREFILTER_SAMPLES = 256;
const IRRADIANCE_SAMPLES = 1024;

// The sky (linear radiance, y up): a blue zenith over a bright horizon, a darker ground, and one
// soft rectangular light box up and to the left of the viewer, whose reflection shows how sharp
// a coat is.
const SKY = /* wgsl */ `
fn sky(d: vec3<f32>) -> vec3<f32> {
    let up = clamp(d.y, -1.0, 1.0);
    let zenith = vec3<f32>(0.22, 0.38, 0.75);
    let horizon = vec3<f32>(0.95, 0.92, 0.85);
    let ground = vec3<f32>(0.16, 0.14, 0.12);
    let above = mix(horizon, zenith, sqrt(max(up, 0.0)));
    let below = mix(vec3<f32>(0.35, 0.31, 0.27), ground, sqrt(max(-up, 0.0)));
    var radiance = mix(below, above, smoothstep(-0.02, 0.02, up));
    // The light box: 36° by 24°, centred 35° up and 40° to the left of the view axis (+z).
    let centre = normalize(vec3<f32>(-0.54, 0.57, 0.62));
    let right = normalize(cross(vec3<f32>(0.0, 1.0, 0.0), centre));
    let top = cross(centre, right);
    let along = dot(d, centre);
    if (along > 0.0) {
        let x = abs(dot(d, right) / along) / tan(0.314);
        let y = abs(dot(d, top) / along) / tan(0.209);
        let inside = (1.0 - smoothstep(0.85, 1.0, x)) * (1.0 - smoothstep(0.85, 1.0, y));
        radiance += vec3<f32>(4.0, 3.9, 3.7) * inside;
    }
    return radiance;
}
`;

const PREFILTER = /* wgsl */ `
${SKY}
struct Level {
    size: vec2<f32>,
    // GGX roughness of the level; below 0: the irradiance.
    roughness: f32,
    samples: u32,
}
@group(0) @binding(0) var<uniform> level: Level;

@vertex
fn vs(@builtin(vertex_index) i: u32) -> @builtin(position) vec4<f32> {
    return vec4<f32>(vec2<f32>(f32((i << 1u) & 2u), f32(i & 2u)) * 2.0 - 1.0, 0.0, 1.0);
}

// The direction at equirectangular coordinates uv (inverse of the lookup's).
fn direction(uv: vec2<f32>) -> vec3<f32> {
    let phi = (uv.x - 0.5) * 6.2831853;
    let theta = uv.y * 3.1415927;
    return vec3<f32>(sin(theta) * sin(phi), cos(theta), sin(theta) * cos(phi));
}

fn radical_inverse(i: u32) -> f32 {
    return f32(reverseBits(i)) * 2.3283064e-10;
}

// An orthonormal pair perpendicular to unit n (Duff et al. 2017, "Building an Orthonormal Basis, Revisited").
fn basis(n: vec3<f32>) -> mat3x3<f32> {
    let s = select(-1.0, 1.0, n.z >= 0.0);
    let a = -1.0 / (s + n.z);
    let b = n.x * n.y * a;
    return mat3x3<f32>(vec3<f32>(1.0 + s * n.x * n.x * a, s * b, -s * n.x), vec3<f32>(b, s + n.y * n.y * a, -n.y), n);
}

@fragment
fn fs(@builtin(position) position: vec4<f32>) -> @location(0) vec4<f32> {
    let d = direction(position.xy / level.size);
    if (level.roughness == 0.0) {
        return vec4<f32>(sky(d), 1.0);
    }
    let frame = basis(d);
    var sum = vec3<f32>(0.0);
    var total = 0.0;
    for (var i = 0u; i < level.samples; i++) {
        let xi = vec2<f32>((f32(i) + 0.5) / f32(level.samples), radical_inverse(i));
        let phi = 6.2831853 * xi.y;
        if (level.roughness < 0.0) {
            // Cosine-weighted directions around d: the mean is E(d)/π.
            let r = sqrt(xi.x);
            let l = frame * vec3<f32>(r * cos(phi), r * sin(phi), sqrt(max(1.0 - xi.x, 0.0)));
            sum += sky(l);
            total += 1.0;
        } else {
            // GGX half vectors (Walter et al. 2007, eq. 35–36), reflected about with n = v = d.
            let alpha = level.roughness * level.roughness;
            let cos_h = sqrt((1.0 - xi.x) / (1.0 + (alpha * alpha - 1.0) * xi.x));
            let sin_h = sqrt(max(1.0 - cos_h * cos_h, 0.0));
            let h = frame * vec3<f32>(sin_h * cos(phi), sin_h * sin(phi), cos_h);
            let l = 2.0 * dot(d, h) * h - d;
            let n_dot_l = dot(d, l);
            if (n_dot_l > 0.0) {
                sum += sky(l) * n_dot_l;
                total += n_dot_l;
            }
        }
    }
    return vec4<f32>(sum / max(total, 1e-6), 1.0);
}
`;

/// Prefilters the sky: { radiance, irradiance } textures (rgba16float), ready to sample.
export async function buildEnvironment(device) {
    const format = 'rgba16float';
    const module = device.createShaderModule({ code: PREFILTER, label: 'playground sky' });
    const layout = device.createBindGroupLayout({
        entries: [{ binding: 0, visibility: GPUShaderStage.FRAGMENT, buffer: { type: 'uniform' } }],
    });
    const pipeline = await device.createRenderPipelineAsync({
        layout: device.createPipelineLayout({ bindGroupLayouts: [layout] }),
        vertex: { module, entryPoint: 'vs' },
        fragment: { module, entryPoint: 'fs', targets: [{ format }] },
    });
    const usage = GPUTextureUsage.TEXTURE_BINDING | GPUTextureUsage.RENDER_ATTACHMENT;
    const radiance = device.createTexture({ size: [WIDTH, WIDTH / 2], mipLevelCount: LEVELS, format, usage });
    const irradiance = device.createTexture({ size: [IRRADIANCE_WIDTH, IRRADIANCE_WIDTH / 2], format, usage });
    const encoder = device.createCommandEncoder();
    const pass = (view, width, roughness, samples) => {
        const uniform = device.createBuffer({ size: 16, usage: GPUBufferUsage.UNIFORM | GPUBufferUsage.COPY_DST });
        const data = new ArrayBuffer(16);
        new Float32Array(data, 0, 3).set([width, width / 2, roughness]);
        new Uint32Array(data, 12, 1)[0] = samples;
        device.queue.writeBuffer(uniform, 0, data);
        const group = device.createBindGroup({ layout, entries: [{ binding: 0, resource: { buffer: uniform } }] });
        const p = encoder.beginRenderPass({ colorAttachments: [{ view, loadOp: 'clear', storeOp: 'store', clearValue: [0, 0, 0, 1] }] });
        p.setPipeline(pipeline);
        p.setBindGroup(0, group);
        p.draw(3);
        p.end();
    };
    for (let k = 0; k < LEVELS; k++) {
        const view = radiance.createView({ baseMipLevel: k, mipLevelCount: 1 });
        pass(view, WIDTH >> k, k / (LEVELS - 1), PREFILTER_SAMPLES);
    }
    pass(irradiance.createView(), IRRADIANCE_WIDTH, -1, IRRADIANCE_SAMPLES);
    device.queue.submit([encoder.finish()]);
    await device.queue.onSubmittedWorkDone();
    return { radiance, irradiance };
}
