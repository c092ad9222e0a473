//! Where a material with runtime parameters should keep its tables: measured on the device.
//!
//! A lookup of the coat's single-scattering deficit (`coat_deficit`, 32 × 32 × 8 nodes, the
//! largest 3-D table) at runtime roughness and IOR, three ways:
//!
//! * **uniform**: the 16-bit codes in a uniform buffer, two to a word, and glazec's
//!   interpolation helper (8 fetches, weights in f32): what glazec emits.
//! * **texture, loads**: the codes in an `R16Uint` 3-D texture, 8 `textureLoad`s, the same
//!   weights.
//! * **texture, filtered**: the codes in an `R16Unorm` 3-D texture (exact: code/65535) and one
//!   `textureSampleLevel` with a linear sampler, the hardware interpolating.
//!
//! Each kernel evaluates 8 lookups per invocation at hashed coordinates; the report gives
//! lookups per second (median of interleaved dispatches, as a ratio to the uniform) and the
//! largest error against the same interpolation in f64 on the CPU.
//!
//! `cargo run --release -p glazec-gpu --example table_storage` (docs/speed.md, "Runtime
//! parameters: where the tables live"). The kernels below are an experiment written by hand,
//! not generated code.

use std::time::Instant;

use glazec::math::tables::TableId;
use wgpu::util::DeviceExt;

/// Invocations per dispatch (each evaluates `LOOKUPS` lookups).
const INVOCATIONS: u32 = 1 << 20;
const LOOKUPS: u32 = 8;
const WORKGROUP: u32 = 64;
/// Timed dispatches per kernel and round, and rounds (interleaved).
const REPEATS: usize = 7;
const ROUNDS: usize = 3;

/// What every kernel shares: the hashed coordinates and the output.
const COMMON: &str = r#"
@group(0) @binding(0) var<storage, read_write> out: array<f32>;
const NODES = vec3<f32>(32.0, 32.0, 8.0);
const SCALE: f32 = SCALE_VALUE;
const OFFSET: f32 = OFFSET_VALUE;
fn hash(x: u32) -> u32 {
    var h = x * 747796405u + 2891336453u;
    h = ((h >> ((h >> 28u) + 4u)) ^ h) * 277803737u;
    return (h >> 22u) ^ h;
}
fn coordinate(i: u32, k: u32) -> vec3<f32> {
    let h = vec3<u32>(hash(i * 24u + k * 3u), hash(i * 24u + k * 3u + 1u), hash(i * 24u + k * 3u + 2u));
    return vec3<f32>(h & vec3<u32>(65535u)) / 65535.0;
}
@compute @workgroup_size(64)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    var total = 0.0;
    for (var k = 0u; k < 8u; k++) {
        total += lookup(coordinate(id.x, k));
    }
    out[id.x] = total;
}
"#;

const UNIFORM: &str = r#"
@group(0) @binding(1) var<uniform> tables: array<vec4<u32>, 1024>;
fn table_code(entry: u32) -> f32 {
    let word = entry >> 1u;
    let codes = tables[word >> 2u][word & 3u];
    return f32((codes >> ((entry & 1u) << 4u)) & 65535u);
}
fn table_trilinear(corner: u32, strides: vec3<u32>, weights: vec3<f32>, scale: f32, offset: f32) -> f32 {
    let code_lll = table_code(corner);
    let code_ull = table_code(corner + strides.x);
    let code_lul = table_code(corner + strides.y);
    let code_uul = table_code(corner + strides.x + strides.y);
    let code_llu = table_code(corner + strides.z);
    let code_ulu = table_code(corner + strides.x + strides.z);
    let code_luu = table_code(corner + strides.y + strides.z);
    let code_uuu = table_code(corner + strides.x + strides.y + strides.z);
    let w = weights;
    let v = 1.0 - weights;
    return (code_lll * scale + offset) * (v.x * v.y * v.z) + (code_ull * scale + offset) * (w.x * v.y * v.z)
        + (code_lul * scale + offset) * (v.x * w.y * v.z) + (code_uul * scale + offset) * (w.x * w.y * v.z)
        + (code_llu * scale + offset) * (v.x * v.y * w.z) + (code_ulu * scale + offset) * (w.x * v.y * w.z)
        + (code_luu * scale + offset) * (v.x * w.y * w.z) + (code_uuu * scale + offset) * (w.x * w.y * w.z);
}
fn lookup(u: vec3<f32>) -> f32 {
    let node = u * (NODES - 1.0);
    let cell = min(floor(node), NODES - 2.0);
    let corner = u32(cell.x + cell.y * 32.0 + cell.z * 1024.0);
    return table_trilinear(corner, vec3<u32>(1u, 32u, 1024u), node - cell, SCALE, OFFSET);
}
"#;

const LOADS: &str = r#"
@group(0) @binding(1) var table: texture_3d<u32>;
fn code(p: vec3<u32>) -> f32 { return f32(textureLoad(table, p, 0).x); }
fn lookup(u: vec3<f32>) -> f32 {
    let node = u * (NODES - 1.0);
    let cell = min(floor(node), NODES - 2.0);
    let w = node - cell;
    let v = 1.0 - w;
    let c = vec3<u32>(cell);
    return (code(c) * SCALE + OFFSET) * (v.x * v.y * v.z)
        + (code(c + vec3(1u, 0u, 0u)) * SCALE + OFFSET) * (w.x * v.y * v.z)
        + (code(c + vec3(0u, 1u, 0u)) * SCALE + OFFSET) * (v.x * w.y * v.z)
        + (code(c + vec3(1u, 1u, 0u)) * SCALE + OFFSET) * (w.x * w.y * v.z)
        + (code(c + vec3(0u, 0u, 1u)) * SCALE + OFFSET) * (v.x * v.y * w.z)
        + (code(c + vec3(1u, 0u, 1u)) * SCALE + OFFSET) * (w.x * v.y * w.z)
        + (code(c + vec3(0u, 1u, 1u)) * SCALE + OFFSET) * (v.x * w.y * w.z)
        + (code(c + vec3(1u, 1u, 1u)) * SCALE + OFFSET) * (w.x * w.y * w.z);
}
"#;

const FILTERED: &str = r#"
@group(0) @binding(1) var table: texture_3d<f32>;
@group(0) @binding(2) var linear: sampler;
fn lookup(u: vec3<f32>) -> f32 {
    // Node i at texel centre (i + ½)/n.
    let at = (u * (NODES - 1.0) + 0.5) / NODES;
    return textureSampleLevel(table, linear, at, 0.0).x * (65535.0 * SCALE) + OFFSET;
}
"#;

#[derive(Clone, Copy, Debug)]
enum Storage {
    Uniform,
    Loads,
    Filtered,
}

impl Storage {
    fn name(self) -> &'static str {
        match self {
            Storage::Uniform => "uniform, glazec's helper",
            Storage::Loads => "R16Uint texture, 8 loads",
            Storage::Filtered => "R16Unorm texture, filtered",
        }
    }
}

struct Kernel {
    storage: Storage,
    pipeline: wgpu::ComputePipeline,
    bind_group: wgpu::BindGroup,
    out: wgpu::Buffer,
}

fn main() {
    let instance = wgpu::Instance::new({
        let mut d = wgpu::InstanceDescriptor::new_without_display_handle();
        d.backends = wgpu::Backends::VULKAN;
        d
    });
    let mut adapters = pollster::block_on(instance.enumerate_adapters(wgpu::Backends::VULKAN));
    adapters.sort_by_key(|a| a.get_info().device_type != wgpu::DeviceType::Cpu);
    let Some(adapter) = adapters.into_iter().next() else {
        eprintln!("no Vulkan adapter (install mesa-vulkan-drivers for lavapipe)");
        std::process::exit(1);
    };
    let info = adapter.get_info();
    let features = wgpu::Features::TEXTURE_FORMAT_16BIT_NORM;
    if !adapter.features().contains(features) {
        eprintln!("{} has no 16-bit normalised textures", info.name);
        std::process::exit(1);
    }
    let (device, queue) = pollster::block_on(adapter.request_device(&wgpu::DeviceDescriptor {
        label: Some("table_storage"),
        required_features: features,
        ..Default::default()
    }))
    .expect("device");

    let id = TableId::CoatDeficit;
    let codes = id.codes();
    let q = id.quantization();
    assert_eq!(codes.len(), 32 * 32 * 8);
    let words: Vec<u32> = codes.chunks(2).map(|p| u32::from(p[0]) | u32::from(p[1]) << 16).collect();
    let uniform = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some("tables"),
        contents: bytemuck::cast_slice(&words),
        usage: wgpu::BufferUsages::UNIFORM,
    });
    let texture = |format| {
        device.create_texture_with_data(
            &queue,
            &wgpu::TextureDescriptor {
                label: Some("table"),
                size: wgpu::Extent3d { width: 32, height: 32, depth_or_array_layers: 8 },
                mip_level_count: 1,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D3,
                format,
                usage: wgpu::TextureUsages::TEXTURE_BINDING,
                view_formats: &[],
            },
            wgpu::util::TextureDataOrder::LayerMajor,
            bytemuck::cast_slice(codes),
        )
    };
    let integer = texture(wgpu::TextureFormat::R16Uint).create_view(&Default::default());
    let normalised = texture(wgpu::TextureFormat::R16Unorm).create_view(&Default::default());
    let sampler = device.create_sampler(&wgpu::SamplerDescriptor {
        mag_filter: wgpu::FilterMode::Linear,
        min_filter: wgpu::FilterMode::Linear,
        ..Default::default()
    });

    let kernel = |storage: Storage| {
        let body = match storage {
            Storage::Uniform => UNIFORM,
            Storage::Loads => LOADS,
            Storage::Filtered => FILTERED,
        };
        let source = format!("{COMMON}{body}")
            .replace("SCALE_VALUE", &format!("{:e}", q.scale))
            .replace("OFFSET_VALUE", &format!("{:e}", q.offset));
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some(storage.name()),
            source: wgpu::ShaderSource::Wgsl(source.into()),
        });
        let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some(storage.name()),
            layout: None,
            module: &module,
            entry_point: Some("main"),
            compilation_options: Default::default(),
            cache: None,
        });
        let out = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("out"),
            size: u64::from(INVOCATIONS) * 4,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        let mut entries = vec![wgpu::BindGroupEntry { binding: 0, resource: out.as_entire_binding() }];
        match storage {
            Storage::Uniform => {
                entries.push(wgpu::BindGroupEntry { binding: 1, resource: uniform.as_entire_binding() })
            }
            Storage::Loads => entries
                .push(wgpu::BindGroupEntry { binding: 1, resource: wgpu::BindingResource::TextureView(&integer) }),
            Storage::Filtered => {
                entries.push(wgpu::BindGroupEntry {
                    binding: 1,
                    resource: wgpu::BindingResource::TextureView(&normalised),
                });
                entries.push(wgpu::BindGroupEntry { binding: 2, resource: wgpu::BindingResource::Sampler(&sampler) });
            }
        }
        let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: None,
            layout: &pipeline.get_bind_group_layout(0),
            entries: &entries,
        });
        Kernel { storage, pipeline, bind_group, out }
    };
    let dispatch = |k: &Kernel| {
        let mut encoder = device.create_command_encoder(&Default::default());
        {
            let mut pass = encoder.begin_compute_pass(&Default::default());
            pass.set_pipeline(&k.pipeline);
            pass.set_bind_group(0, &k.bind_group, &[]);
            pass.dispatch_workgroups(INVOCATIONS / WORKGROUP, 1, 1);
        }
        queue.submit([encoder.finish()]);
        device.poll(wgpu::PollType::wait_indefinitely()).expect("device idle");
    };
    let kernels: Vec<Kernel> = [Storage::Uniform, Storage::Loads, Storage::Filtered].map(kernel).into();

    // Accuracy: a sample of invocations against f64 interpolation of the decoded codes.
    let reference = |i: u32| -> f64 {
        (0..LOOKUPS)
            .map(|k| {
                let u = coordinate(i, k);
                let nodes = [32usize, 32, 8];
                let mut cell = [0usize; 3];
                let mut w = [0f64; 3];
                for a in 0..3 {
                    let node = f64::from(u[a]) * (nodes[a] - 1) as f64;
                    cell[a] = (node.floor() as usize).min(nodes[a] - 2);
                    w[a] = node - cell[a] as f64;
                }
                let mut total = 0.0;
                for corner in 0..8 {
                    let mut weight = 1.0;
                    let mut at = [0usize; 3];
                    for a in 0..3 {
                        let upper = corner >> a & 1;
                        at[a] = cell[a] + upper;
                        weight *= if upper == 1 { w[a] } else { 1.0 - w[a] };
                    }
                    let code = f64::from(codes[at[0] + 32 * at[1] + 1024 * at[2]]);
                    total += (code * f64::from(q.scale) + f64::from(q.offset)) * weight;
                }
                total
            })
            .sum()
    };
    let sample: Vec<u32> = (0..INVOCATIONS).step_by(97).collect();
    let mut errors = Vec::new();
    for k in &kernels {
        dispatch(k);
        let read = device.create_buffer(&wgpu::BufferDescriptor {
            label: None,
            size: u64::from(INVOCATIONS) * 4,
            usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let mut encoder = device.create_command_encoder(&Default::default());
        encoder.copy_buffer_to_buffer(&k.out, 0, &read, 0, u64::from(INVOCATIONS) * 4);
        queue.submit([encoder.finish()]);
        read.slice(..).map_async(wgpu::MapMode::Read, |r| r.expect("mapped"));
        device.poll(wgpu::PollType::wait_indefinitely()).expect("device idle");
        let values: Vec<f32> = bytemuck::cast_slice(&read.slice(..).get_mapped_range().expect("mapped range")).to_vec();
        // Per lookup: the sum of 8 divided by 8.
        let worst = sample
            .iter()
            .map(|&i| (f64::from(values[i as usize]) - reference(i)).abs() / f64::from(LOOKUPS))
            .fold(0.0, f64::max);
        errors.push(worst);
    }

    let mut times = vec![Vec::new(); kernels.len()];
    for _ in 0..ROUNDS {
        for (k, t) in kernels.iter().zip(&mut times) {
            dispatch(k);
            for _ in 0..REPEATS {
                let start = Instant::now();
                dispatch(k);
                t.push(start.elapsed().as_secs_f64());
            }
        }
    }
    let medians: Vec<f64> = times
        .into_iter()
        .map(|mut t| {
            t.sort_by(f64::total_cmp);
            t[t.len() / 2]
        })
        .collect();
    println!("{} [{:?}, {}]", info.name, info.backend, info.driver_info);
    println!(
        "coat_deficit (32 × 32 × 8), {INVOCATIONS} invocations × {LOOKUPS} lookups, median of {} dispatches",
        ROUNDS * REPEATS
    );
    println!();
    println!("| storage | M lookups/s | time vs uniform | largest error |");
    println!("|---|---|---|---|");
    for ((k, s), e) in kernels.iter().zip(&medians).zip(&errors) {
        let rate = f64::from(INVOCATIONS * LOOKUPS) / s / 1e6;
        println!("| {} | {rate:.0} | {:.2}× | {e:.1e} |", k.storage.name(), s / medians[0]);
    }
}

/// The coordinates the kernels hash for invocation `i`, lookup `k` (as in `COMMON`).
fn coordinate(i: u32, k: u32) -> [f32; 3] {
    let hash = |x: u32| {
        let h = x.wrapping_mul(747_796_405).wrapping_add(2_891_336_453);
        let h = ((h >> ((h >> 28) + 4)) ^ h).wrapping_mul(277_803_737);
        (h >> 22) ^ h
    };
    let base = i.wrapping_mul(24).wrapping_add(k * 3);
    [0, 1, 2].map(|j| (hash(base.wrapping_add(j)) & 65535) as f32 / 65535.0)
}
