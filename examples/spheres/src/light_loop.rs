//! A program's own shader around glazec's libraries: two meshes (spheres), two materials, two
//! directional lights, and a light loop in the program's WGSL (`light_loop.wgsl`) that calls
//! `wet_clay_eval` and `tunable_glaze_eval`.
//!
//! The program owns bind group 0 (its camera and lights) and gives the materials group 1, where
//! build.rs put their resources (`Build::bind_material`); the layout of group 1 is read from the
//! generated `LIBRARY_BINDINGS`. The frame is linear radiance in an `Rgba32Float` target, and the
//! shading normal in a second one (so that a test can recompute any pixel on the CPU).

use std::borrow::Cow;

use wgpu::util::DeviceExt;

use crate::light_materials::{glazec_layout, tunable_glaze, wet_clay};
use crate::render::{RenderError, Renderer, read_buffer};

/// The program's shader, after which the libraries are not needed by name.
const SHADER: &str = include_str!("light_loop.wgsl");

/// The two lights: (unit direction towards the light, radiance).
pub const LIGHTS: [([f32; 3], [f32; 3]); 2] =
    [([-0.48, 0.6, 0.64], [2.6, 2.45, 2.2]), ([0.7, -0.1, std::f32::consts::FRAC_1_SQRT_2], [0.5, 0.65, 0.9])];
/// Towards the viewer (an orthographic camera looking down −z).
pub const TO_VIEWER: [f32; 3] = [0.0, 0.0, 1.0];
/// The meshes: each material on a unit sphere centred here.
pub const SPHERES: [(&str, [f32; 3]); 2] = [("wet_clay", [-1.15, 0.0, 0.0]), ("tunable_glaze", [1.15, 0.0, 0.0])];
/// The camera sees x ∈ [−HALF_WIDTH, HALF_WIDTH] and y ∈ [−HALF_WIDTH/2, HALF_WIDTH/2]: frames
/// are twice as wide as they are high.
pub const HALF_WIDTH: f32 = 2.4;

const RADIANCE_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Float;
const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;

/// Stacks and slices of the sphere meshes.
const STACKS: u32 = 64;
const SLICES: u32 = 128;

/// A rendered frame: per pixel, row by row from the top, linear radiance (alpha 1 on a mesh, 0
/// elsewhere) and the shading normal (w 1 on a mesh).
pub struct Frame {
    pub width: u32,
    pub height: u32,
    pub radiance: Vec<[f32; 4]>,
    pub normal: Vec<[f32; 4]>,
}

/// A unit sphere at `centre`: (position, normal) vertices and triangle indices.
fn sphere(centre: [f32; 3]) -> (Vec<[f32; 6]>, Vec<u32>) {
    let mut vertices = Vec::new();
    for i in 0..=STACKS {
        let theta = std::f32::consts::PI * i as f32 / STACKS as f32;
        for j in 0..=SLICES {
            let phi = std::f32::consts::TAU * j as f32 / SLICES as f32;
            let n = [theta.sin() * phi.cos(), theta.cos(), theta.sin() * phi.sin()];
            vertices.push([centre[0] + n[0], centre[1] + n[1], centre[2] + n[2], n[0], n[1], n[2]]);
        }
    }
    let mut indices = Vec::new();
    let row = SLICES + 1;
    for i in 0..STACKS {
        for j in 0..SLICES {
            let (a, b) = (i * row + j, (i + 1) * row + j);
            indices.extend([a, b, a + 1, a + 1, b, b + 1]);
        }
    }
    (vertices, indices)
}

/// The orthographic camera as WGSL's column-major `mat4x4<f32>`: x/HALF_WIDTH, 2y/HALF_WIDTH, and
/// depth 0.5 − z/4 (nearer is smaller), then `to_viewer`.
fn camera_bytes() -> Vec<u8> {
    let s = 1.0 / HALF_WIDTH;
    let columns: [f32; 16] = [s, 0.0, 0.0, 0.0, 0.0, 2.0 * s, 0.0, 0.0, 0.0, 0.0, -0.25, 0.0, 0.0, 0.0, 0.5, 1.0];
    let to_viewer = [TO_VIEWER[0], TO_VIEWER[1], TO_VIEWER[2], 0.0];
    columns.iter().chain(&to_viewer).flat_map(|x| x.to_le_bytes()).collect()
}

fn lights_bytes() -> Vec<u8> {
    LIGHTS.iter().flat_map(|(d, r)| [d[0], d[1], d[2], 0.0, r[0], r[1], r[2], 0.0]).flat_map(f32::to_le_bytes).collect()
}

/// The group-1 layout entries of both materials' libraries (what build.rs put there).
fn material_entries() -> Vec<&'static glazec_layout::Binding> {
    let mut entries: Vec<_> = [&wet_clay::INFO, &tunable_glaze::INFO]
        .iter()
        .flat_map(|m| m.library_bindings)
        .filter(|b| b.group == 1)
        .collect();
    entries.sort_by_key(|b| b.binding);
    entries
}

/// The scene's pipelines, buffers and bind groups.
pub struct LightLoop {
    pipelines: [wgpu::RenderPipeline; 2],
    groups: [wgpu::BindGroup; 2],
    meshes: [(wgpu::Buffer, wgpu::Buffer, u32); 2],
    /// `tunable_glaze`'s parameter uniform: write a `tunable_glaze::Params` to change it.
    pub glaze_params: wgpu::Buffer,
}

impl LightLoop {
    /// Builds the shader (both libraries, then the program's own text), the pipelines and the
    /// buffers.
    ///
    /// # Errors
    /// wgpu rejected something.
    pub fn new(renderer: &Renderer) -> Result<LightLoop, RenderError> {
        let device = &renderer.device;
        let source = [wet_clay::WGSL, tunable_glaze::WGSL, SHADER].join("\n");
        let module = renderer.checked(|| {
            device.create_shader_module(wgpu::ShaderModuleDescriptor {
                label: Some("light loop"),
                source: wgpu::ShaderSource::Wgsl(Cow::Owned(source)),
            })
        })?;
        let uniform = |binding, visibility| wgpu::BindGroupLayoutEntry {
            binding,
            visibility,
            ty: wgpu::BindingType::Buffer {
                ty: wgpu::BufferBindingType::Uniform,
                has_dynamic_offset: false,
                min_binding_size: None,
            },
            count: None,
        };
        let program_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("camera and lights"),
            entries: &[uniform(0, wgpu::ShaderStages::VERTEX_FRAGMENT), uniform(1, wgpu::ShaderStages::FRAGMENT)],
        });
        let material_bindings = material_entries();
        let material_entries: Vec<_> =
            material_bindings.iter().map(|b| uniform(b.binding, wgpu::ShaderStages::FRAGMENT)).collect();
        let material_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("materials"),
            entries: &material_entries,
        });
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("light loop"),
            bind_group_layouts: &[Some(&program_layout), Some(&material_layout)],
            immediate_size: 0,
        });
        let pipeline = |fragment: &str| {
            renderer.checked(|| {
                device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                    label: Some(fragment),
                    layout: Some(&pipeline_layout),
                    vertex: wgpu::VertexState {
                        module: &module,
                        entry_point: Some("vs_main"),
                        compilation_options: Default::default(),
                        buffers: &[Some(wgpu::VertexBufferLayout {
                            array_stride: 24,
                            step_mode: wgpu::VertexStepMode::Vertex,
                            attributes: &wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x3],
                        })],
                    },
                    primitive: wgpu::PrimitiveState::default(),
                    depth_stencil: Some(wgpu::DepthStencilState {
                        format: DEPTH_FORMAT,
                        depth_write_enabled: Some(true),
                        depth_compare: Some(wgpu::CompareFunction::Less),
                        stencil: Default::default(),
                        bias: Default::default(),
                    }),
                    multisample: wgpu::MultisampleState::default(),
                    fragment: Some(wgpu::FragmentState {
                        module: &module,
                        entry_point: Some(fragment),
                        compilation_options: Default::default(),
                        targets: &[Some(RADIANCE_FORMAT.into()), Some(RADIANCE_FORMAT.into())],
                    }),
                    multiview_mask: None,
                    cache: None,
                })
            })
        };
        let pipelines = [pipeline("fs_wet_clay")?, pipeline("fs_tunable_glaze")?];

        let init = |label, contents: &[u8], usage| {
            device.create_buffer_init(&wgpu::util::BufferInitDescriptor { label: Some(label), contents, usage })
        };
        let camera = init("camera", &camera_bytes(), wgpu::BufferUsages::UNIFORM);
        let lights = init("lights", &lights_bytes(), wgpu::BufferUsages::UNIFORM);
        let glaze_params = init(
            "tunable_glaze params",
            bytemuck::bytes_of(&tunable_glaze::Params::default()),
            wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
        );
        let glaze_tables = init("tunable_glaze tables", tunable_glaze::TABLES, wgpu::BufferUsages::UNIFORM);
        let program_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("camera and lights"),
            layout: &program_layout,
            entries: &[
                wgpu::BindGroupEntry { binding: 0, resource: camera.as_entire_binding() },
                wgpu::BindGroupEntry { binding: 1, resource: lights.as_entire_binding() },
            ],
        });
        // Only the glaze binds anything of its own: wet_clay's literals need no resource.
        let buffer_for = |b: &glazec_layout::Binding| match b.role {
            glazec_layout::Role::Params => &glaze_params,
            _ => &glaze_tables,
        };
        let entries: Vec<_> = material_bindings
            .iter()
            .map(|b| wgpu::BindGroupEntry { binding: b.binding, resource: buffer_for(b).as_entire_binding() })
            .collect();
        let material_group = renderer.checked(|| {
            device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("materials"),
                layout: &material_layout,
                entries: &entries,
            })
        })?;
        let mesh = |centre| {
            let (vertices, indices) = sphere(centre);
            let vertices = init("vertices", bytemuck::cast_slice(&vertices), wgpu::BufferUsages::VERTEX);
            let count = indices.len() as u32;
            (vertices, init("indices", bytemuck::cast_slice(&indices), wgpu::BufferUsages::INDEX), count)
        };
        Ok(LightLoop {
            pipelines,
            groups: [program_group, material_group],
            meshes: [mesh(SPHERES[0].1), mesh(SPHERES[1].1)],
            glaze_params,
        })
    }

    /// Renders a `width` × `width/2` frame and reads it back.
    ///
    /// # Errors
    /// wgpu rejected something.
    pub fn render(&self, renderer: &Renderer, width: u32) -> Result<Frame, RenderError> {
        let device = &renderer.device;
        let height = width / 2;
        let extent = wgpu::Extent3d { width, height, depth_or_array_layers: 1 };
        let texture = |label, format, usage| {
            device.create_texture(&wgpu::TextureDescriptor {
                label: Some(label),
                size: extent,
                mip_level_count: 1,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format,
                usage,
                view_formats: &[],
            })
        };
        let targets = wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC;
        let radiance = texture("radiance", RADIANCE_FORMAT, targets);
        let normal = texture("normal", RADIANCE_FORMAT, targets);
        let depth = texture("depth", DEPTH_FORMAT, wgpu::TextureUsages::RENDER_ATTACHMENT);
        let views = [&radiance, &normal].map(|t| t.create_view(&Default::default()));
        let depth_view = depth.create_view(&Default::default());
        let mut encoder = device.create_command_encoder(&Default::default());
        {
            let attachment = |view| {
                Some(wgpu::RenderPassColorAttachment {
                    view,
                    depth_slice: None,
                    resolve_target: None,
                    ops: wgpu::Operations {
                        load: wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT),
                        store: wgpu::StoreOp::Store,
                    },
                })
            };
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("light loop"),
                color_attachments: &[attachment(&views[0]), attachment(&views[1])],
                depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                    view: &depth_view,
                    depth_ops: Some(wgpu::Operations { load: wgpu::LoadOp::Clear(1.0), store: wgpu::StoreOp::Store }),
                    stencil_ops: None,
                }),
                timestamp_writes: None,
                occlusion_query_set: None,
                multiview_mask: None,
            });
            pass.set_bind_group(0, &self.groups[0], &[]);
            pass.set_bind_group(1, &self.groups[1], &[]);
            for (pipeline, (vertices, indices, count)) in self.pipelines.iter().zip(&self.meshes) {
                pass.set_pipeline(pipeline);
                pass.set_vertex_buffer(0, vertices.slice(..));
                pass.set_index_buffer(indices.slice(..), wgpu::IndexFormat::Uint32);
                pass.draw_indexed(0..*count, 0, 0..1);
            }
        }
        let row = width * 16;
        let readback = [&radiance, &normal].map(|t| {
            let buffer = device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("readback"),
                size: u64::from(row * height),
                usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
                mapped_at_creation: false,
            });
            encoder.copy_texture_to_buffer(
                t.as_image_copy(),
                wgpu::TexelCopyBufferInfo {
                    buffer: &buffer,
                    layout: wgpu::TexelCopyBufferLayout { offset: 0, bytes_per_row: Some(row), rows_per_image: None },
                },
                extent,
            );
            buffer
        });
        renderer.checked(|| renderer.queue.submit([encoder.finish()]))?;
        let mut images = Vec::new();
        for buffer in &readback {
            let bytes = read_buffer(device, buffer)?;
            images.push(bytemuck::cast_slice::<u8, [f32; 4]>(&bytes).to_vec());
        }
        let normal = images.pop().unwrap_or_default();
        let radiance = images.pop().unwrap_or_default();
        Ok(Frame { width, height, radiance, normal })
    }
}
