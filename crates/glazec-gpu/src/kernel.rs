//! The `eval_pairs` compute kernel on the device: f(wi, wo) for a buffer of direction pairs.

use std::time::{Duration, Instant};

use glam::Vec3;
use wgpu::util::DeviceExt;

use crate::shader::{self, ShaderPath};
use crate::textures;
use crate::{Gpu, RunError};
use glazec::Compiled;
use glazec::eval::Pair;
use glazec::lower::{EVAL_WORKGROUP_SIZE, PAIR_STRIDE, bindings, entry_points};
use glazec::model::{Material, ParamValue};

/// Most pairs one dispatch covers (65,535 workgroups of 64 invocations).
const MAX_PAIRS_PER_DISPATCH: usize = 65_535 * EVAL_WORKGROUP_SIZE as usize;

/// A material's `eval_pairs` kernel, loaded by one [`ShaderPath`].
pub struct EvalKernel {
    pub path: ShaderPath,
    pipeline: wgpu::ComputePipeline,
    layout: wgpu::BindGroupLayout,
    /// Group 1, for a material that reads textures (constant textures: see `crate::textures`).
    textures: Option<wgpu::BindGroupLayout>,
    bindings: bindings::Layout,
    /// The material's table uniform (`Compiled::tables_bytes`; empty without tables).
    tables: Vec<u8>,
    material: Material,
}

/// The material's table uniform (`lower::bindings::Layout::tables`): `Compiled::tables_bytes`.
pub(crate) fn tables_buffer(gpu: &Gpu, bytes: &[u8]) -> wgpu::Buffer {
    gpu.device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some("tables"),
        contents: bytes,
        usage: wgpu::BufferUsages::UNIFORM,
    })
}

/// The uniform block of a material's runtime parameters, laid out as `lower` declares it.
///
/// # Errors
/// [`RunError::ParamCount`] if `values` does not hold one value per parameter.
pub fn params_bytes(material: &Material, values: &[ParamValue]) -> Result<Vec<u8>, RunError> {
    if values.len() != material.params.len() {
        return Err(RunError::ParamCount { expected: material.params.len(), got: values.len() });
    }
    Ok(glazec::lower::params_bytes(material, values))
}

/// [`pairs_bytes`] with texture coordinates in the spare components: uv = (wi.w, wo.w).
pub fn pairs_bytes_at(pairs: &[Pair], uvs: &[[f32; 2]]) -> Vec<u8> {
    let mut bytes = Vec::with_capacity(pairs.len() * PAIR_STRIDE as usize);
    for (p, [u, v]) in pairs.iter().zip(uvs) {
        for x in [p.wi.x, p.wi.y, p.wi.z, *u, p.wo.x, p.wo.y, p.wo.z, *v] {
            bytes.extend_from_slice(&x.to_le_bytes());
        }
    }
    bytes
}

/// The `pairs` buffer: per pair `wi.xyz, 0, wo.xyz, 0` as little-endian f32.
pub fn pairs_bytes(pairs: &[Pair]) -> Vec<u8> {
    pairs_bytes_at(pairs, &vec![[0.0; 2]; pairs.len()])
}

fn layout_entry(binding: u32, ty: wgpu::BufferBindingType) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::COMPUTE | wgpu::ShaderStages::FRAGMENT,
        ty: wgpu::BindingType::Buffer { ty, has_dynamic_offset: false, min_binding_size: None },
        count: None,
    }
}

/// The bind-group layout of `eval_pairs` (group 0 of glazec's default bindings, which is where
/// glazec's runner compiles its materials: `glazec::compile`).
pub(crate) fn kernel_layout(gpu: &Gpu, optional: &bindings::Layout) -> wgpu::BindGroupLayout {
    // In binding order: wgpu's Vulkan backend numbers descriptors by position (see
    // `lower::bindings`), which passthrough SPIR-V must match.
    let mut entries = vec![
        layout_entry(optional.pairs, wgpu::BufferBindingType::Storage { read_only: true }),
        layout_entry(optional.values, wgpu::BufferBindingType::Storage { read_only: false }),
        layout_entry(optional.dispatch, wgpu::BufferBindingType::Uniform),
    ];
    if let Some(slot) = optional.params {
        entries.push(layout_entry(slot.binding, wgpu::BufferBindingType::Uniform));
    }
    if let Some(slot) = optional.tables {
        entries.push(layout_entry(slot.binding, wgpu::BufferBindingType::Uniform));
    }
    gpu.device
        .create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor { label: Some("eval_pairs"), entries: &entries })
}

/// The compute pipeline of an `eval_pairs` entry point and its bind-group layout.
fn pipeline(
    gpu: &Gpu,
    what: &str,
    module: &wgpu::ShaderModule,
    entry: &str,
    optional: &bindings::Layout,
    textures: Option<&wgpu::BindGroupLayout>,
) -> Result<(wgpu::ComputePipeline, wgpu::BindGroupLayout), RunError> {
    let layout = kernel_layout(gpu, optional);
    let mut groups = vec![Some(&layout)];
    if textures.is_some() {
        groups.push(textures);
    }
    let pipeline_layout = gpu.device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label: Some("eval_pairs"),
        bind_group_layouts: &groups,
        immediate_size: 0,
    });
    let pipeline = gpu.checked(what, || {
        gpu.device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some(what),
            layout: Some(&pipeline_layout),
            module,
            entry_point: Some(entry),
            compilation_options: Default::default(),
            cache: None,
        })
    })?;
    Ok((pipeline, layout))
}

/// Buffers and bind group for one dispatch.
struct Batch {
    bind_group: wgpu::BindGroup,
    textures: Option<wgpu::BindGroup>,
    values: wgpu::Buffer,
    count: usize,
}

impl EvalKernel {
    /// Loads the material's kernel by `path` and builds its pipeline.
    ///
    /// # Errors
    /// A [`RunError`] if the shader cannot be produced, compiled or accepted by the device.
    pub fn new(gpu: &Gpu, compiled: &Compiled, path: ShaderPath) -> Result<EvalKernel, RunError> {
        let loaded = shader::load(gpu, compiled, path, naga::ShaderStage::Compute, entry_points::EVAL_PAIRS)?;
        let optional = compiled.harness().map_err(glazec::emit::EmitError::from)?.layout.clone();
        let what = format!("{path} eval_pairs pipeline of `{}`", compiled.material.name);
        let material = &compiled.material;
        let texture_layout = textures::layout(gpu, material, false, wgpu::ShaderStages::COMPUTE);
        let pipeline_and_layout =
            pipeline(gpu, &what, &loaded.module, &loaded.entry, &optional, texture_layout.as_ref())?;
        let mut kernel = EvalKernel::assemble(path, pipeline_and_layout, optional, material.clone());
        kernel.textures = texture_layout;
        kernel.tables = compiled.tables_bytes();
        Ok(kernel)
    }

    /// A kernel from WGSL text written by hand with `eval_pairs`'s interface (`pairs`,
    /// `values` and `dispatch` at bindings 0–2; no parameters, tables or light): the benchmarks'
    /// hand-written baseline. Reported as the WGSL path.
    ///
    /// # Errors
    /// A [`RunError`] if the device rejects the shader.
    pub fn from_wgsl(gpu: &Gpu, label: &str, wgsl: &str) -> Result<EvalKernel, RunError> {
        let what = format!("hand-written eval_pairs `{label}`");
        let module = gpu.checked(&what, || {
            gpu.device.create_shader_module(wgpu::ShaderModuleDescriptor {
                label: Some(label),
                source: wgpu::ShaderSource::Wgsl(std::borrow::Cow::Borrowed(wgsl)),
            })
        })?;
        let optional = bindings::Layout {
            pairs: bindings::PAIRS,
            values: bindings::VALUES,
            dispatch: bindings::DISPATCH,
            ..Default::default()
        };
        let pipeline_and_layout = pipeline(gpu, &what, &module, entry_points::EVAL_PAIRS, &optional, None)?;
        // No parameters: an empty stand-in material gives `eval` an empty uniform.
        let material = Material {
            name: label.to_string(),
            method: glazec::model::Method::default(),
            coats: Vec::new(),
            base: glazec::model::Base::Lambert { albedo: glazec::model::Color::Lit([0.0; 3]) },
            params: Vec::new(),
            normals: Vec::new(),
        };
        Ok(EvalKernel::assemble(ShaderPath::Wgsl, pipeline_and_layout, optional, material))
    }

    fn assemble(
        path: ShaderPath,
        (pipeline, layout): (wgpu::ComputePipeline, wgpu::BindGroupLayout),
        bindings: bindings::Layout,
        material: Material,
    ) -> EvalKernel {
        EvalKernel { path, pipeline, layout, textures: None, bindings, tables: Vec::new(), material }
    }

    fn batch(&self, gpu: &Gpu, pairs: &[Pair], params: &[u8], param_values: &[ParamValue]) -> Batch {
        let constants = textures::constant_textures(&self.material, param_values);
        self.batch_with(gpu, &pairs_bytes(pairs), pairs.len(), params, &constants)
    }

    fn batch_with(
        &self,
        gpu: &Gpu,
        pairs_bytes: &[u8],
        count: usize,
        params: &[u8],
        images: &[(String, textures::TextureImage)],
    ) -> Batch {
        let init = |label, contents: &[u8], usage| {
            gpu.device.create_buffer_init(&wgpu::util::BufferInitDescriptor { label: Some(label), contents, usage })
        };
        let pairs_buffer = init("pairs", pairs_bytes, wgpu::BufferUsages::STORAGE);
        let mut dispatch = [0u8; 16];
        dispatch[..4].copy_from_slice(&(count as u32).to_le_bytes());
        let dispatch_buffer = init("dispatch", &dispatch, wgpu::BufferUsages::UNIFORM);
        let values = gpu.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("values"),
            size: (count.max(1) * 16) as u64,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        let params_buffer = (!params.is_empty()).then(|| init("params", params, wgpu::BufferUsages::UNIFORM));
        let mut entries = vec![
            wgpu::BindGroupEntry { binding: self.bindings.pairs, resource: pairs_buffer.as_entire_binding() },
            wgpu::BindGroupEntry { binding: self.bindings.values, resource: values.as_entire_binding() },
            wgpu::BindGroupEntry { binding: self.bindings.dispatch, resource: dispatch_buffer.as_entire_binding() },
        ];
        if let (Some(b), Some(slot)) = (&params_buffer, self.bindings.params) {
            entries.push(wgpu::BindGroupEntry { binding: slot.binding, resource: b.as_entire_binding() });
        }
        let tables = self.bindings.tables.map(|slot| (slot.binding, tables_buffer(gpu, &self.tables)));
        if let Some((binding, buffer)) = &tables {
            entries.push(wgpu::BindGroupEntry { binding: *binding, resource: buffer.as_entire_binding() });
        }
        let bind_group = gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: None,
            layout: &self.layout,
            entries: &entries,
        });
        let textures =
            self.textures.as_ref().map(|layout| textures::bind_group(gpu, layout, &self.material, images, false));
        Batch { bind_group, textures, values, count }
    }

    fn dispatch(&self, gpu: &Gpu, batch: &Batch) {
        let mut encoder = gpu.device.create_command_encoder(&Default::default());
        {
            let mut pass = encoder.begin_compute_pass(&Default::default());
            pass.set_pipeline(&self.pipeline);
            pass.set_bind_group(0, &batch.bind_group, &[]);
            if let Some(textures) = &batch.textures {
                pass.set_bind_group(1, textures, &[]);
            }
            pass.dispatch_workgroups((batch.count as u32).div_ceil(EVAL_WORKGROUP_SIZE), 1, 1);
        }
        gpu.queue.submit([encoder.finish()]);
    }

    /// f(wi, wo) for every pair, with the given parameter values (one per material parameter).
    ///
    /// # Errors
    /// A wrong number of parameter values, or a failure to read the results back.
    pub fn eval(&self, gpu: &Gpu, pairs: &[Pair], params: &[ParamValue]) -> Result<Vec<Vec3>, RunError> {
        let bytes = params_bytes(&self.material, params)?;
        self.run_chunks(gpu, pairs.len(), |range| self.batch(gpu, &pairs[range], &bytes, params))
    }

    /// f(wi, wo) for every pair with the material's textures bound to `images` (exact texels,
    /// nearest sampling, wrap), each pair sampling them at its `uvs` entry.
    ///
    /// # Errors
    /// A wrong number of parameter values or uvs, or a failure to read the results back.
    pub fn eval_textured(
        &self,
        gpu: &Gpu,
        pairs: &[Pair],
        uvs: &[[f32; 2]],
        params: &[ParamValue],
        images: &[(String, textures::TextureImage)],
    ) -> Result<Vec<Vec3>, RunError> {
        if uvs.len() != pairs.len() {
            return Err(RunError::UvCount { pairs: pairs.len(), uvs: uvs.len() });
        }
        let bytes = params_bytes(&self.material, params)?;
        let mut bound = textures::constant_textures(&self.material, params);
        bound.retain(|(name, _)| !images.iter().any(|(n, _)| n == name));
        bound.extend(images.iter().cloned());
        self.run_chunks(gpu, pairs.len(), |range| {
            let count = range.len();
            self.batch_with(gpu, &pairs_bytes_at(&pairs[range.clone()], &uvs[range]), count, &bytes, &bound)
        })
    }

    /// Dispatches `count` pairs in chunks of at most one dispatch, each prepared by `batch_for`,
    /// and reads the values back in order.
    fn run_chunks(
        &self,
        gpu: &Gpu,
        count: usize,
        mut batch_for: impl FnMut(std::ops::Range<usize>) -> Batch,
    ) -> Result<Vec<Vec3>, RunError> {
        let mut out = Vec::with_capacity(count);
        for start in (0..count).step_by(MAX_PAIRS_PER_DISPATCH) {
            let end = (start + MAX_PAIRS_PER_DISPATCH).min(count);
            let batch = batch_for(start..end);
            self.dispatch(gpu, &batch);
            let bytes = gpu.read_buffer(&batch.values, ((end - start) * 16) as u64)?;
            out.extend(bytes.chunks_exact(16).map(|v| {
                let f = |i: usize| f32::from_le_bytes([v[i], v[i + 1], v[i + 2], v[i + 3]]);
                Vec3::new(f(0), f(4), f(8))
            }));
        }
        Ok(out)
    }

    /// Wall-clock time of `repeats` dispatches over `pairs` (at most one dispatch's worth), each
    /// measured from submission until the device is idle, after one warm-up dispatch.
    ///
    /// # Errors
    /// A wrong number of parameter values, or a device failure.
    pub fn time_dispatches(
        &self,
        gpu: &Gpu,
        pairs: &[Pair],
        params: &[ParamValue],
        repeats: usize,
    ) -> Result<Vec<Duration>, RunError> {
        let values = params;
        let params = params_bytes(&self.material, params)?;
        let pairs = &pairs[..pairs.len().min(MAX_PAIRS_PER_DISPATCH)];
        let batch = self.batch(gpu, pairs, &params, values);
        self.dispatch(gpu, &batch);
        gpu.wait()?;
        let mut times = Vec::with_capacity(repeats);
        for _ in 0..repeats {
            let start = Instant::now();
            self.dispatch(gpu, &batch);
            gpu.wait()?;
            times.push(start.elapsed());
        }
        Ok(times)
    }
}
