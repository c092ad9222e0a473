//! A headless sphere renderer driven by the descriptions glazec generates.
//!
//! The generated `preview_vs` draws a full-screen triangle and `preview_fs` shades a unit sphere
//! under the directional light in its `light` uniform. A frame is the sum of a few such passes
//! (a key light, a rim light and a sky fill), added by the blend unit into an `Rgba16Float`
//! target, read back, exposed and encoded as 8-bit sRGB.

use std::borrow::Cow;

use wgpu::util::DeviceExt;

use crate::materials::{PreviewLight, glazec_layout};

/// The render target: blendable floating point.
const TARGET_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;

/// The lights of a frame: (direction towards the light in view space, radiance).
pub const LIGHTS: [([f32; 3], [f32; 3]); 3] =
    [([-0.5, 0.6, 0.62], [2.4, 2.3, 2.1]), ([0.8, 0.3, -0.5], [0.8, 0.9, 1.1]), ([0.0, 1.0, 0.2], [0.25, 0.3, 0.4])];

/// Why a frame could not be made.
#[derive(Debug)]
pub enum RenderError {
    /// No Vulkan adapter (install `mesa-vulkan-drivers` for lavapipe).
    NoAdapter(String),
    Device(String),
    /// wgpu rejected a pipeline, a bind group or a buffer.
    Validation(String),
}

impl std::fmt::Display for RenderError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            RenderError::NoAdapter(e) => write!(f, "no Vulkan adapter: {e}"),
            RenderError::Device(e) => write!(f, "cannot open the device: {e}"),
            RenderError::Validation(e) => write!(f, "wgpu: {e}"),
        }
    }
}

impl std::error::Error for RenderError {}

/// A device and queue.
pub struct Renderer {
    pub device: wgpu::Device,
    pub queue: wgpu::Queue,
    pub adapter_name: String,
}

impl Renderer {
    /// Opens the first Vulkan adapter (lavapipe on a machine without a GPU).
    ///
    /// # Errors
    /// [`RenderError::NoAdapter`] or [`RenderError::Device`].
    pub fn new() -> Result<Self, RenderError> {
        let mut descriptor = wgpu::InstanceDescriptor::new_without_display_handle();
        descriptor.backends = wgpu::Backends::VULKAN;
        let instance = wgpu::Instance::new(descriptor);
        let adapter = pollster::block_on(instance.request_adapter(&wgpu::RequestAdapterOptions::default()))
            .map_err(|e| RenderError::NoAdapter(e.to_string()))?;
        let adapter_name = adapter.get_info().name;
        let (device, queue) = pollster::block_on(adapter.request_device(&wgpu::DeviceDescriptor::default()))
            .map_err(|e| RenderError::Device(e.to_string()))?;
        Ok(Renderer { device, queue, adapter_name })
    }

    /// For tests: the device, or `None` with a visible "SKIPPED" line when there is no adapter —
    /// a panic instead under `GLAZEC_REQUIRE_GPU=1` (set in CI).
    ///
    /// # Panics
    /// With `GLAZEC_REQUIRE_GPU=1` and no adapter, or when the device cannot be opened.
    pub fn or_skip() -> Option<Self> {
        match Renderer::new() {
            Ok(r) => {
                eprintln!("rendering on {}", r.adapter_name);
                Some(r)
            }
            Err(e @ RenderError::NoAdapter(_)) => {
                if std::env::var("GLAZEC_REQUIRE_GPU").is_ok_and(|v| v == "1") {
                    panic!("GLAZEC_REQUIRE_GPU=1 but {e}");
                }
                eprintln!("SKIPPED: {e}");
                None
            }
            Err(e) => panic!("{e}"),
        }
    }

    /// Runs `make` inside a validation error scope.
    pub(crate) fn checked<T>(&self, make: impl FnOnce() -> T) -> Result<T, RenderError> {
        let scope = self.device.push_error_scope(wgpu::ErrorFilter::Validation);
        let value = make();
        match pollster::block_on(scope.pop()) {
            Some(e) => Err(RenderError::Validation(e.to_string())),
            None => Ok(value),
        }
    }
}

/// One material's preview pipeline, its bind groups (one per light) and its parameter buffer.
pub struct SpherePipeline {
    pipeline: wgpu::RenderPipeline,
    groups: Vec<wgpu::BindGroup>,
    /// The uniform buffer of the material's `Params`, when it has runtime parameters.
    pub params_buffer: Option<wgpu::Buffer>,
}

/// The wgpu layout entry for one generated binding description.
fn layout_entry(binding: &glazec_layout::Binding) -> wgpu::BindGroupLayoutEntry {
    let buffer = |ty| wgpu::BindingType::Buffer {
        ty,
        has_dynamic_offset: false,
        min_binding_size: wgpu::BufferSize::new(binding.min_size),
    };
    let ty = match (binding.access, binding.role) {
        (glazec_layout::Access::Uniform, _) => buffer(wgpu::BufferBindingType::Uniform),
        (glazec_layout::Access::StorageReadOnly, _) => buffer(wgpu::BufferBindingType::Storage { read_only: true }),
        (glazec_layout::Access::StorageReadWrite, _) => buffer(wgpu::BufferBindingType::Storage { read_only: false }),
        (glazec_layout::Access::Handle, glazec_layout::Role::Sampler) => {
            wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Filtering)
        }
        (glazec_layout::Access::Handle, _) => wgpu::BindingType::Texture {
            sample_type: wgpu::TextureSampleType::Float { filterable: true },
            view_dimension: wgpu::TextureViewDimension::D2,
            multisampled: false,
        },
    };
    let mut visibility = wgpu::ShaderStages::NONE;
    for (used, stage) in [
        (binding.stages.vertex, wgpu::ShaderStages::VERTEX),
        (binding.stages.fragment, wgpu::ShaderStages::FRAGMENT),
        (binding.stages.compute, wgpu::ShaderStages::COMPUTE),
    ] {
        if used {
            visibility |= stage;
        }
    }
    wgpu::BindGroupLayoutEntry { binding: binding.binding, visibility, ty, count: None }
}

impl SpherePipeline {
    /// Builds the pipeline of `material` from its generated WGSL and binding descriptions; the
    /// parameter buffer starts with the material's defaults.
    ///
    /// # Errors
    /// [`RenderError::Validation`] if wgpu rejects something.
    pub fn new(renderer: &Renderer, material: &glazec_layout::MaterialInfo) -> Result<Self, RenderError> {
        let device = &renderer.device;
        let bindings = material.preview_bindings;
        let entries: Vec<wgpu::BindGroupLayoutEntry> = bindings.iter().map(layout_entry).collect();
        let layout = renderer.checked(|| {
            device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some(material.name),
                entries: &entries,
            })
        })?;
        let module = renderer.checked(|| {
            device.create_shader_module(wgpu::ShaderModuleDescriptor {
                label: Some(material.name),
                // glazec's harness (its preview entry points) read after the library.
                source: wgpu::ShaderSource::Wgsl(Cow::Owned(format!("{}\n{}", material.wgsl, material.wgsl_harness))),
            })
        })?;
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some(material.name),
            bind_group_layouts: &[Some(&layout)],
            immediate_size: 0,
        });
        let pipeline = renderer.checked(|| create_pipeline(device, &module, &pipeline_layout, material.name))?;

        let uniform = |label, contents: &[u8]| {
            device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some(label),
                contents,
                usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            })
        };
        let params_buffer = material.params.map(|p| uniform("params", p.default_bytes));
        let tables_buffer = material.uses_tables.then(|| uniform("tables", material.tables));
        let mut groups = Vec::new();
        for (direction, radiance) in LIGHTS {
            let [x, y, z] = direction;
            let norm = (x * x + y * y + z * z).sqrt();
            let light = PreviewLight {
                direction: [x / norm, y / norm, z / norm, 0.0],
                radiance: [radiance[0], radiance[1], radiance[2], 0.0],
            };
            let light_buffer = uniform("light", bytemuck::bytes_of(&light));
            let mut entries = Vec::new();
            for binding in bindings {
                let buffer = match binding.role {
                    glazec_layout::Role::Params => params_buffer.as_ref(),
                    glazec_layout::Role::Tables => tables_buffer.as_ref(),
                    glazec_layout::Role::Light => Some(&light_buffer),
                    _ => None,
                };
                let Some(buffer) = buffer else {
                    return Err(RenderError::Validation(format!("no buffer for `{}`", binding.name)));
                };
                entries.push(wgpu::BindGroupEntry { binding: binding.binding, resource: buffer.as_entire_binding() });
            }
            let group = renderer.checked(|| {
                device.create_bind_group(&wgpu::BindGroupDescriptor { label: None, layout: &layout, entries: &entries })
            })?;
            groups.push(group);
        }
        Ok(SpherePipeline { pipeline, groups, params_buffer })
    }

    /// Renders one frame (`size` × `size`) and reads it back as linear RGBA.
    ///
    /// # Errors
    /// [`RenderError::Validation`] if the read-back fails.
    pub fn render(&self, renderer: &Renderer, size: u32) -> Result<Vec<[f32; 4]>, RenderError> {
        let device = &renderer.device;
        let extent = wgpu::Extent3d { width: size, height: size, depth_or_array_layers: 1 };
        let texture = device.create_texture(&wgpu::TextureDescriptor {
            label: Some("sphere"),
            size: extent,
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: TARGET_FORMAT,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
            view_formats: &[],
        });
        let view = texture.create_view(&Default::default());
        let corners: [f32; 6] = [-1.0, -1.0, 3.0, -1.0, -1.0, 3.0];
        let corner_buffer = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("corners"),
            contents: bytemuck::cast_slice(&corners),
            usage: wgpu::BufferUsages::VERTEX,
        });
        let mut encoder = device.create_command_encoder(&Default::default());
        {
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("sphere"),
                color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                    view: &view,
                    depth_slice: None,
                    resolve_target: None,
                    ops: wgpu::Operations {
                        load: wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT),
                        store: wgpu::StoreOp::Store,
                    },
                })],
                ..Default::default()
            });
            pass.set_pipeline(&self.pipeline);
            pass.set_vertex_buffer(0, corner_buffer.slice(..));
            for group in &self.groups {
                pass.set_bind_group(0, group, &[]);
                pass.draw(0..3, 0..1);
            }
        }
        let row = (size * 8).next_multiple_of(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT);
        let readback = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("readback"),
            size: u64::from(row) * u64::from(size),
            usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
            mapped_at_creation: false,
        });
        encoder.copy_texture_to_buffer(
            wgpu::TexelCopyTextureInfo {
                texture: &texture,
                mip_level: 0,
                origin: wgpu::Origin3d::ZERO,
                aspect: wgpu::TextureAspect::All,
            },
            wgpu::TexelCopyBufferInfo {
                buffer: &readback,
                layout: wgpu::TexelCopyBufferLayout { offset: 0, bytes_per_row: Some(row), rows_per_image: Some(size) },
            },
            extent,
        );
        renderer.queue.submit([encoder.finish()]);
        let bytes = read_buffer(device, &readback)?;
        let mut pixels = Vec::with_capacity((size * size) as usize);
        for y in 0..size as usize {
            for px in bytes[y * row as usize..][..size as usize * 8].chunks_exact(8) {
                let h = |i: usize| half::f16::from_le_bytes([px[i], px[i + 1]]).to_f32();
                pixels.push([h(0), h(2), h(4), h(6)]);
            }
        }
        Ok(pixels)
    }
}

fn create_pipeline(
    device: &wgpu::Device,
    module: &wgpu::ShaderModule,
    layout: &wgpu::PipelineLayout,
    label: &str,
) -> wgpu::RenderPipeline {
    let add = wgpu::BlendComponent {
        src_factor: wgpu::BlendFactor::One,
        dst_factor: wgpu::BlendFactor::One,
        operation: wgpu::BlendOperation::Add,
    };
    let corner = [wgpu::VertexAttribute { format: wgpu::VertexFormat::Float32x2, offset: 0, shader_location: 0 }];
    device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: Some(label),
        layout: Some(layout),
        vertex: wgpu::VertexState {
            module,
            entry_point: Some("preview_vs"),
            compilation_options: Default::default(),
            buffers: &[Some(wgpu::VertexBufferLayout {
                array_stride: 8,
                step_mode: wgpu::VertexStepMode::Vertex,
                attributes: &corner,
            })],
        },
        primitive: wgpu::PrimitiveState::default(),
        depth_stencil: None,
        multisample: wgpu::MultisampleState::default(),
        fragment: Some(wgpu::FragmentState {
            module,
            entry_point: Some("preview_fs"),
            compilation_options: Default::default(),
            targets: &[Some(wgpu::ColorTargetState {
                format: TARGET_FORMAT,
                blend: Some(wgpu::BlendState { color: add, alpha: add }),
                write_mask: wgpu::ColorWrites::ALL,
            })],
        }),
        multiview_mask: None,
        cache: None,
    })
}

/// 8-bit sRGB of linear pixels over a dark background (alpha 0 = not on the sphere).
pub fn encode_srgb(linear: &[[f32; 4]]) -> Vec<u8> {
    let srgb = |x: f32| {
        let x = x.clamp(0.0, 1.0);
        let v = if x <= 0.003_130_8 { 12.92 * x } else { 1.055 * x.powf(1.0 / 2.4) - 0.055 };
        (v * 255.0).round() as u8
    };
    linear
        .iter()
        .flat_map(|px| if px[3] > 0.0 { [srgb(px[0]), srgb(px[1]), srgb(px[2])] } else { [18, 18, 22] })
        .collect()
}

/// Maps a `MAP_READ` buffer whose copies were submitted and returns its bytes.
pub(crate) fn read_buffer(device: &wgpu::Device, buffer: &wgpu::Buffer) -> Result<Vec<u8>, RenderError> {
    let slice = buffer.slice(..);
    let (sender, receiver) = std::sync::mpsc::channel();
    slice.map_async(wgpu::MapMode::Read, move |r| {
        let _ = sender.send(r);
    });
    device.poll(wgpu::PollType::wait_indefinitely()).map_err(|e| RenderError::Validation(e.to_string()))?;
    match receiver.recv() {
        Ok(Ok(())) => {}
        Ok(Err(e)) => return Err(RenderError::Validation(e.to_string())),
        Err(e) => return Err(RenderError::Validation(e.to_string())),
    }
    let bytes = slice.get_mapped_range().map_err(|e| RenderError::Validation(e.to_string()))?.to_vec();
    Ok(bytes)
}

/// Writes an RGB8 image as PNG.
///
/// # Errors
/// I/O or encoder errors.
pub fn write_png(
    path: &std::path::Path,
    width: u32,
    height: u32,
    rgb: &[u8],
) -> Result<(), Box<dyn std::error::Error>> {
    let file = std::io::BufWriter::new(std::fs::File::create(path)?);
    let mut encoder = png::Encoder::new(file, width, height);
    encoder.set_color(png::ColorType::Rgb);
    encoder.set_depth(png::BitDepth::Eight);
    encoder.write_header()?.write_image_data(rgb)?;
    Ok(())
}
