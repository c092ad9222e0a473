// The playground's renderer: a material's WGSL library (as glazec compiled it, unchanged) plus
// the page's own harness, drawn with WebGPU. The harness uses the library the way a renderer
// would (docs/generated-files.md, "What a library contains"): `<m>_eval` for the directional
// light, `<m>_ibl_lobes` looked up in the page's own prefiltered environment, the library's
// resources bound where `compile` says they are, and the page's in a bind group of its own.

import { buildEnvironment } from './environment.js';

/// The page's bind group (the library's default groups are 0, 1 and 2).
const PAGE_GROUP = 3;

/// The WGSL the page appends to material `name`'s library: a unit sphere seen along −z by an
/// orthographic camera (v = +z everywhere), lit by one directional light and the environment.
export function harness(name, iface) {
    const extra = (iface.params ? `, ${name}_params` : '') + (iface.sampler ? ', textures' : '');
    let textures = '';
    if (iface.sampler) {
        // glazec's own preview does the same: longitude/latitude uv, the tangent along +φ.
        textures += '        let uv = vec2<f32>(atan2(n.x, n.z) * 0.15915494 + 0.5, 0.5 - asin(clamp(n.y, -1.0, 1.0)) * 0.31830987);\n';
        if (iface.framed) {
            textures += '        let t = normalize(vec3<f32>(n.z, 0.0, -n.x) + vec3<f32>(1e-6, 0.0, 0.0));\n';
            textures += `        let textures = ${name}_textures(uv, n, t, cross(n, t));\n`;
        } else {
            textures += `        let textures = ${name}_textures(uv);\n`;
        }
    }
    return /* wgsl */ `
// The playground's harness for \`${name}\` (web/render.js): the library above, used as a renderer uses it.
struct PlaygroundFrame {
    // xyz: unit vector towards the light.
    light_direction: vec4<f32>,
    // rgb: the light's irradiance on a surface facing it (the radiance reflected is eval × this).
    light_radiance: vec4<f32>,
    // x: the environment's scale; y: exposure; z: 1 tone-maps (Khronos PBR Neutral), 0 clamps.
    shading: vec4<f32>,
    // xy: the view's half extent in sphere radii.
    view: vec4<f32>,
}

@group(${PAGE_GROUP}) @binding(0) var<uniform> playground: PlaygroundFrame;
@group(${PAGE_GROUP}) @binding(1) var playground_sampler: sampler;
@group(${PAGE_GROUP}) @binding(2) var playground_radiance: texture_2d<f32>;
@group(${PAGE_GROUP}) @binding(3) var playground_irradiance: texture_2d<f32>;

struct PlaygroundVarying {
    @builtin(position) position: vec4<f32>,
    @location(0) p: vec2<f32>,
}

// One triangle over the whole viewport; p in sphere radii, y up.
@vertex
fn playground_vs(@builtin(vertex_index) i: u32) -> PlaygroundVarying {
    let corner = vec2<f32>(f32((i << 1u) & 2u), f32(i & 2u)) * 2.0 - 1.0;
    return PlaygroundVarying(vec4<f32>(corner, 0.0, 1.0), corner * playground.view.xy);
}

// Equirectangular coordinates of unit direction d (y up), as the environment is laid out.
fn playground_uv(d: vec3<f32>) -> vec2<f32> {
    return vec2<f32>(atan2(d.x, d.z) * 0.15915494 + 0.5, acos(clamp(d.y, -1.0, 1.0)) * 0.31830987);
}

// The environment prefiltered for a GGX lobe of roughness r: level r·(N − 1).
fn playground_prefiltered(d: vec3<f32>, roughness: f32) -> vec3<f32> {
    let lod = clamp(roughness, 0.0, 1.0) * f32(textureNumLevels(playground_radiance) - 1u);
    return textureSampleLevel(playground_radiance, playground_sampler, playground_uv(d), lod).rgb;
}

// The irradiance around d over π.
fn playground_irradiance_at(d: vec3<f32>) -> vec3<f32> {
    return textureSampleLevel(playground_irradiance, playground_sampler, playground_uv(d), 0.0).rgb;
}

// Khronos 2024, "PBR Neutral Specification": a tone mapper that leaves base colours alone
// below its compression start.
fn playground_tonemap(c: vec3<f32>) -> vec3<f32> {
    let start = 0.76;
    let x = min(c.r, min(c.g, c.b));
    let offset = select(0.04, x - 6.25 * x * x, x < 0.08);
    let color = c - offset;
    let peak = max(color.r, max(color.g, color.b));
    if (peak < start) {
        return color;
    }
    let d = 1.0 - start;
    let new_peak = 1.0 - d * d / (peak + d - start);
    let g = 1.0 - 1.0 / (0.15 * (peak - new_peak) + 1.0);
    return mix(color * (new_peak / peak), vec3<f32>(new_peak), g);
}

// Linear to sRGB-encoded (IEC 61966-2-1), for an 8-bit canvas.
fn playground_srgb(c: vec3<f32>) -> vec3<f32> {
    let x = clamp(c, vec3<f32>(0.0), vec3<f32>(1.0));
    return select(1.055 * pow(x, vec3<f32>(1.0 / 2.4)) - 0.055, 12.92 * x, x <= vec3<f32>(0.0031308));
}

@fragment
fn playground_fs(in: PlaygroundVarying) -> @location(0) vec4<f32> {
    let p = in.p;
    let r2 = dot(p, p);
    var radiance: vec3<f32>;
    if (r2 < 1.0) {
        let n = vec3<f32>(p.x, p.y, sqrt(1.0 - r2));
        let v = vec3<f32>(0.0, 0.0, 1.0);
${textures}        radiance = ${name}_eval(n, v, playground.light_direction.xyz${extra}) * playground.light_radiance.rgb;
        let lobes = ${name}_ibl_lobes(n, v${extra});
        var ambient = lobes.irradiance.weight * playground_irradiance_at(lobes.irradiance.direction);
        for (var k = 0u; k < ${name}_ibl_specular_lobes; k++) {
            let lobe = lobes.specular[k];
            ambient += lobe.weight * playground_prefiltered(lobe.direction, lobe.roughness);
        }
        radiance += ambient * playground.shading.x;
    } else {
        // The sky behind the sphere, a little blurred.
        radiance = playground_prefiltered(normalize(vec3<f32>(0.5 * p, -1.0)), 0.3) * playground.shading.x;
    }
    var c = radiance * playground.shading.y;
    if (playground.shading.z > 0.5) {
        c = playground_tonemap(c);
    }
    return vec4<f32>(playground_srgb(c), 1.0);
}
`;
}

/// The lighting the page controls.
export const DEFAULT_LIGHTING = {
    /// Degrees above the horizon and from the view axis towards +x (the light's direction).
    elevation: 40,
    azimuth: 35,
    intensity: 3,
    environment: 1,
    exposure: 1,
    tonemap: true,
};

export class Renderer {
    /// A renderer on `canvas`. `present`: 'canvas' draws into the canvas's WebGPU context;
    /// 'readback' renders into a texture and copies it into the canvas through a 2D context
    /// (for browsers whose WebGPU cannot present to a canvas: headless Chromium with
    /// SwiftShader under its default GL compositor loses its device at the first
    /// `getCurrentTexture`).
    static async create(canvas, present = 'canvas') {
        if (!navigator.gpu) throw new Error('this browser has no WebGPU (navigator.gpu is missing)');
        const adapter = await navigator.gpu.requestAdapter();
        if (!adapter) throw new Error('WebGPU found no adapter');
        const device = await adapter.requestDevice();
        const environment = await buildEnvironment(device);
        const info = adapter.info ?? {};
        const name = `${info.vendor ?? ''} ${info.architecture ?? ''} ${info.description ?? ''}`.trim();
        return new Renderer(canvas, present, adapter, device, environment, name);
    }

    constructor(canvas, present, adapter, device, environment, name) {
        // The adapter is held for the page's lifetime: the device's work depends on it.
        Object.assign(this, { canvas, present, gpuAdapter: adapter, device, environment, adapter: name });
        if (present === 'canvas') {
            this.format = navigator.gpu.getPreferredCanvasFormat();
            this.context = canvas.getContext('webgpu');
            this.context.configure({ device, format: this.format, alphaMode: 'opaque' });
        } else {
            this.format = 'rgba8unorm';
            this.context2d = canvas.getContext('2d', { willReadFrequently: true });
            this.target = device.createTexture({
                size: [canvas.width, canvas.height],
                format: this.format,
                usage: GPUTextureUsage.RENDER_ATTACHMENT | GPUTextureUsage.COPY_SRC,
            });
            this.bytesPerRow = Math.ceil((4 * canvas.width) / 256) * 256;
            this.readback = device.createBuffer({ size: this.bytesPerRow * canvas.height, usage: GPUBufferUsage.COPY_DST | GPUBufferUsage.MAP_READ });
        }
        this.lighting = { ...DEFAULT_LIGHTING };
        this.frame = device.createBuffer({ size: 64, usage: GPUBufferUsage.UNIFORM | GPUBufferUsage.COPY_DST });
        this.sampler = device.createSampler({
            addressModeU: 'repeat',
            addressModeV: 'clamp-to-edge',
            magFilter: 'linear',
            minFilter: 'linear',
            mipmapFilter: 'linear',
        });
        this.material = null;
        // Readback frames: requested, on the canvas, and the one in flight.
        this.requested = 0;
        this.shown = 0;
        this.pending = null;
    }

    /// Builds the pipeline and resources for `out` (a successful `compile` result), to be drawn
    /// once assigned to `material`. Throws with WebGPU's messages when the browser rejects the
    /// shader.
    async prepare(out) {
        const device = this.device;
        const code = out.wgsl + '\n' + harness(out.name, out.interface);
        device.pushErrorScope('validation');
        const module = device.createShaderModule({ code, label: out.name });
        const info = await module.getCompilationInfo();
        const errors = info.messages.filter((m) => m.type === 'error');
        if (errors.length) {
            await device.popErrorScope();
            throw new Error(errors.map((m) => `${m.lineNum}:${m.linePos} ${m.message}`).join('\n'));
        }
        const iface = out.interface;
        // The layouts, group by group: the library's resources where compile put them, then the page's.
        const entries = [[], [], [], []];
        const visibility = GPUShaderStage.FRAGMENT;
        if (iface.params) entries[iface.params.group].push({ binding: iface.params.binding, visibility, buffer: { type: 'uniform' } });
        if (iface.tables) entries[iface.tables.group].push({ binding: iface.tables.binding, visibility, buffer: { type: 'uniform' } });
        if (iface.sampler) entries[iface.sampler.group].push({ binding: iface.sampler.binding, visibility, sampler: {} });
        for (const t of iface.textures) entries[t.slot.group].push({ binding: t.slot.binding, visibility, texture: {} });
        entries[PAGE_GROUP].push(
            { binding: 0, visibility: visibility | GPUShaderStage.VERTEX, buffer: { type: 'uniform' } },
            { binding: 1, visibility, sampler: {} },
            { binding: 2, visibility, texture: {} },
            { binding: 3, visibility, texture: {} },
        );
        const layouts = entries.map((e) => device.createBindGroupLayout({ entries: e }));
        const pipeline = await device.createRenderPipelineAsync({
            layout: device.createPipelineLayout({ bindGroupLayouts: layouts }),
            vertex: { module, entryPoint: 'playground_vs' },
            fragment: { module, entryPoint: 'playground_fs', targets: [{ format: this.format }] },
        });
        // The resources.
        const uniform = (bytes) => {
            const buffer = device.createBuffer({ size: Math.max(16, bytes.byteLength), usage: GPUBufferUsage.UNIFORM | GPUBufferUsage.COPY_DST });
            device.queue.writeBuffer(buffer, 0, bytes);
            return buffer;
        };
        const params = new Float32Array(Math.max(out.params_size, 16) / 4);
        for (const p of out.params) params.set(p.default, p.offset / 4);
        const paramsBuffer = uniform(params);
        const resources = [[], [], [], []];
        if (iface.params) resources[iface.params.group].push({ binding: iface.params.binding, resource: { buffer: paramsBuffer } });
        if (iface.tables) resources[iface.tables.group].push({ binding: iface.tables.binding, resource: { buffer: uniform(new Uint8Array(out.tables)) } });
        if (iface.sampler) resources[iface.sampler.group].push({ binding: iface.sampler.binding, resource: this.sampler });
        for (const t of iface.textures) {
            // No image in the playground: a flat normal for a normal map, else a mid-grey texel
            // (the middle of the read's range, what `glazec eval` assumes).
            const texel = t.normal_map ? [128, 128, 255, 255] : [128, 128, 128, 128];
            const texture = device.createTexture({ size: [1, 1], format: 'rgba8unorm', usage: GPUTextureUsage.TEXTURE_BINDING | GPUTextureUsage.COPY_DST });
            device.queue.writeTexture({ texture }, new Uint8Array(texel), { bytesPerRow: 4 }, [1, 1]);
            resources[t.slot.group].push({ binding: t.slot.binding, resource: texture.createView() });
        }
        resources[PAGE_GROUP].push(
            { binding: 0, resource: { buffer: this.frame } },
            { binding: 1, resource: this.sampler },
            { binding: 2, resource: this.environment.radiance.createView() },
            { binding: 3, resource: this.environment.irradiance.createView() },
        );
        const groups = layouts.map((layout, i) => device.createBindGroup({ layout, entries: resources[i] }));
        const error = await device.popErrorScope();
        if (error) throw new Error(error.message);
        return { out, pipeline, groups, params, paramsBuffer, code };
    }

    /// Sets runtime parameter `name` (one number or three) and writes the uniform.
    setParam(name, value) {
        const m = this.material;
        const p = m?.out.params.find((q) => q.name === name);
        if (!p) return;
        m.params.set(value, p.offset / 4);
        this.device.queue.writeBuffer(m.paramsBuffer, 0, m.params);
    }

    /// The light's unit direction (towards the light) from elevation and azimuth in degrees.
    lightDirection() {
        const e = (this.lighting.elevation * Math.PI) / 180;
        const a = (this.lighting.azimuth * Math.PI) / 180;
        return [Math.cos(e) * Math.sin(a), Math.sin(e), Math.cos(e) * Math.cos(a)];
    }

    /// Draws a frame; resolves when a frame drawn after this call is on the canvas.
    async render() {
        if (this.present !== 'readback') return this.draw(this.context.getCurrentTexture().createView());
        // One readback in flight; requests made meanwhile share the next frame.
        const ticket = ++this.requested;
        while (this.shown < ticket) {
            if (!this.pending) {
                const covers = this.requested;
                this.pending = this.draw(this.target.createView())
                    .then(() => (this.shown = Math.max(this.shown, covers)))
                    .finally(() => (this.pending = null));
            }
            await this.pending;
        }
    }

    async draw(view) {
        const m = this.material;
        if (!m) return;
        const { width, height } = this.canvas;
        const l = this.lighting;
        // The sphere fills 90% of the shorter side.
        const scale = 1 / 0.9;
        const aspect = width / height;
        const extent = aspect >= 1 ? [scale * aspect, scale] : [scale, scale / aspect];
        const frame = new Float32Array([
            ...this.lightDirection(), 0,
            l.intensity, l.intensity, l.intensity, 0,
            l.environment, l.exposure, l.tonemap ? 1 : 0, 0,
            extent[0], extent[1], 0, 0,
        ]);
        this.device.queue.writeBuffer(this.frame, 0, frame);
        const encoder = this.device.createCommandEncoder();
        const pass = encoder.beginRenderPass({
            colorAttachments: [{ view, loadOp: 'clear', storeOp: 'store', clearValue: [0, 0, 0, 1] }],
        });
        pass.setPipeline(m.pipeline);
        m.groups.forEach((g, i) => pass.setBindGroup(i, g));
        pass.draw(3);
        pass.end();
        if (this.present === 'readback') {
            encoder.copyTextureToBuffer({ texture: this.target }, { buffer: this.readback, bytesPerRow: this.bytesPerRow }, [width, height]);
        }
        this.device.queue.submit([encoder.finish()]);
        if (this.present === 'readback') {
            await this.readback.mapAsync(GPUMapMode.READ);
            const rows = new Uint8Array(this.readback.getMappedRange());
            const image = new ImageData(width, height);
            for (let y = 0; y < height; y++) {
                image.data.set(rows.subarray(y * this.bytesPerRow, y * this.bytesPerRow + 4 * width), 4 * width * y);
            }
            this.readback.unmap();
            this.context2d.putImageData(image, 0, 0);
        }
    }
}
