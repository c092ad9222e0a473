// The light-loop scene's own shader: a mesh pipeline with its own camera and lights, shading each
// mesh with a glazec material library. The program prepends the libraries of `wet_clay` and
// `tunable_glaze` (their WGSL, from build.rs) to this text; nothing else of glazec is used.

struct Camera {
    view_proj: mat4x4<f32>,
    // The direction towards the viewer (orthographic: the same at every point), w unused.
    to_viewer: vec4<f32>,
}

struct Light {
    // Towards the light, unit length; w unused.
    direction: vec4<f32>,
    radiance: vec4<f32>,
}

struct Lights {
    lights: array<Light, 2>,
}

@group(0) @binding(0) var<uniform> camera: Camera;
@group(0) @binding(1) var<uniform> scene_lights: Lights;

struct VertexIn {
    @location(0) position: vec3<f32>,
    @location(1) normal: vec3<f32>,
}

struct VertexOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) normal: vec3<f32>,
}

// Radiance, and the shading normal (for the program's test, which recomputes the pixel on the CPU).
struct FragmentOut {
    @location(0) radiance: vec4<f32>,
    @location(1) normal: vec4<f32>,
}

@vertex
fn vs_main(in: VertexIn) -> VertexOut {
    return VertexOut(camera.view_proj * vec4<f32>(in.position, 1.0), in.normal);
}

@fragment
fn fs_wet_clay(in: VertexOut) -> FragmentOut {
    let n = normalize(in.normal);
    let v = camera.to_viewer.xyz;
    var radiance = vec3<f32>(0.0);
    for (var i = 0u; i < 2u; i++) {
        let light = scene_lights.lights[i];
        radiance += wet_clay_eval(n, v, light.direction.xyz) * light.radiance.xyz;
    }
    return FragmentOut(vec4<f32>(radiance, 1.0), vec4<f32>(n, 1.0));
}

@fragment
fn fs_tunable_glaze(in: VertexOut) -> FragmentOut {
    let n = normalize(in.normal);
    let v = camera.to_viewer.xyz;
    var radiance = vec3<f32>(0.0);
    for (var i = 0u; i < 2u; i++) {
        let light = scene_lights.lights[i];
        radiance += tunable_glaze_eval(n, v, light.direction.xyz, tunable_glaze_params) * light.radiance.xyz;
    }
    return FragmentOut(vec4<f32>(radiance, 1.0), vec4<f32>(n, 1.0));
}
