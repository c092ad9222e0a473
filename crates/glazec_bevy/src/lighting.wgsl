// Bevy's lights, shadows, environment map and post-lighting for a glazec material's fragment
// shader: everything of Bevy's forward `apply_pbr_lighting` except its BRDF, which the
// generated shader replaces by the material's own `<m>_eval` and `<m>_ibl_lobes`.
//
// Radiometry is Bevy's: a directional light's `color` is its colour times its illuminance
// (lux); a point or spot light's `color_inverse_square_range.rgb` its colour times its
// intensity (candela), attenuated by Bevy's own `getDistanceAttenuation` (inverse square with
// its smooth range cut-off) and, for a spot, the cone of `spot_light`; everything is scaled by
// the view's exposure at the end, as `apply_pbr_lighting` does.
#define_import_path glazec_bevy::lighting

#import bevy_pbr::forward_io::VertexOutput
#import bevy_pbr::mesh_view_bindings as view_bindings
#import bevy_pbr::mesh_view_types
#import bevy_pbr::mesh_types::MESH_FLAGS_SHADOW_RECEIVER_BIT
#import bevy_pbr::clustered_forward as clustering
#import bevy_pbr::shadows
#import bevy_pbr::lighting::{getDistanceAttenuation, LayerLightingInput}
#import bevy_pbr::pbr_types
#import bevy_pbr::pbr_functions::main_pass_post_lighting_processing
#ifdef VERTEX_OUTPUT_INSTANCE_INDEX
#import bevy_pbr::mesh_bindings::mesh
#endif
#ifdef ENVIRONMENT_MAP
#import bevy_pbr::environment_map
#endif

// The shaded point, as every light needs it.
struct Surface {
    // The interpolated world-space normal, facing the viewer's side of the triangle.
    n: vec3<f32>,
    // Unit vector towards the viewer.
    v: vec3<f32>,
    world_position: vec4<f32>,
    frag_coord: vec4<f32>,
    // Depth in view space (cascade selection) and the cluster's light ranges.
    view_z: f32,
    ranges: clustering::ClusterableObjectIndexRanges,
    // Whether the mesh receives shadows (`NotShadowReceiver` clears it).
    receives_shadows: bool,
}

// One light at the surface: the unit direction towards it, and the radiance factor that
// multiplies `<m>_eval(n, v, l)` (colour × illuminance, attenuation and shadow included).
struct Light {
    l: vec3<f32>,
    radiance: vec3<f32>,
}

fn surface(in: VertexOutput, is_front: bool) -> Surface {
    var s: Surface;
    let normal = normalize(in.world_normal);
    s.n = select(-normal, normal, is_front);
    let is_orthographic = view_bindings::view.clip_from_view[3].w == 1.0;
    if is_orthographic {
        s.v = normalize(vec3<f32>(
            view_bindings::view.clip_from_world[0].z,
            view_bindings::view.clip_from_world[1].z,
            view_bindings::view.clip_from_world[2].z,
        ));
    } else {
        s.v = normalize(view_bindings::view.world_position.xyz - in.world_position.xyz);
    }
    s.world_position = in.world_position;
    s.frag_coord = in.position;
    s.view_z = dot(vec4<f32>(
        view_bindings::view.view_from_world[0].z,
        view_bindings::view.view_from_world[1].z,
        view_bindings::view.view_from_world[2].z,
        view_bindings::view.view_from_world[3].z,
    ), in.world_position);
    let cluster = clustering::view_fragment_cluster_index(in.position.xy, s.view_z, is_orthographic);
    s.ranges = clustering::unpack_clusterable_object_index_ranges(cluster);
#ifdef VERTEX_OUTPUT_INSTANCE_INDEX
    s.receives_shadows = (mesh[in.instance_index].flags & MESH_FLAGS_SHADOW_RECEIVER_BIT) != 0u;
#else
    s.receives_shadows = true;
#endif
    return s;
}

fn directional_count() -> u32 {
    return view_bindings::lights.n_directional_lights;
}

// Directional light `i`, with its cascaded shadow map.
fn directional(s: Surface, i: u32) -> Light {
    let light = &view_bindings::lights.directional_lights[i];
    var shadow = 1.0;
    if s.receives_shadows
        && ((*light).flags & mesh_view_types::DIRECTIONAL_LIGHT_FLAGS_SHADOWS_ENABLED_BIT) != 0u {
        shadow = shadows::fetch_directional_shadow(i, s.world_position, s.n, s.view_z, s.frag_coord.xy);
    }
    return Light((*light).direction_to_light, (*light).color.rgb * shadow);
}

// The clustered point and spot lights of the surface's cluster are the indices
// [first_clustered(s), end_clustered(s)).
fn first_clustered(s: Surface) -> u32 {
    return s.ranges.first_point_light_index_offset;
}

fn end_clustered(s: Surface) -> u32 {
    return s.ranges.first_reflection_probe_index_offset;
}

// Clustered light `index` (a point light, or a spot light from `first_spot_light_index_offset`
// on), with its cube or spot shadow map.
fn clustered(s: Surface, index: u32) -> Light {
    let id = clustering::get_clusterable_object_id(index);
    let light = &view_bindings::clustered_lights.data[id];
    let to_light = (*light).position_radius.xyz - s.world_position.xyz;
    let distance_squared = dot(to_light, to_light);
    let l = to_light * inverseSqrt(max(distance_squared, 1e-8));
    var attenuation = getDistanceAttenuation(distance_squared, (*light).color_inverse_square_range.w);
    let is_spot = index >= s.ranges.first_spot_light_index_offset;
    if is_spot {
        // Bevy's `spot_light`: the cone's smooth edge from the packed direction and angles.
        var spot_dir = vec3<f32>((*light).light_custom_data.x, 0.0, (*light).light_custom_data.y);
        spot_dir.y = sqrt(max(0.0, 1.0 - spot_dir.x * spot_dir.x - spot_dir.z * spot_dir.z));
        if ((*light).flags & mesh_view_types::POINT_LIGHT_FLAGS_SPOT_LIGHT_Y_NEGATIVE) != 0u {
            spot_dir.y = -spot_dir.y;
        }
        let cone = saturate(dot(-spot_dir, l) * (*light).light_custom_data.z + (*light).light_custom_data.w);
        attenuation *= cone * cone;
    }
    var shadow = 1.0;
    if s.receives_shadows && ((*light).flags & mesh_view_types::POINT_LIGHT_FLAGS_SHADOWS_ENABLED_BIT) != 0u {
        if is_spot {
            shadow = shadows::fetch_spot_shadow(id, s.world_position, s.n, (*light).shadow_map_near_z, s.frag_coord.xy);
        } else {
            shadow = shadows::fetch_point_shadow(id, s.world_position, s.n, s.frag_coord.xy);
        }
    }
    return Light(l, (*light).color_inverse_square_range.rgb * attenuation * shadow);
}

// Bevy's ambient light: a uniform radiance from every direction, which a material reflects by
// its directional albedo (the sum of its image-based-lighting lobes' weights).
fn ambient() -> vec3<f32> {
    return view_bindings::lights.ambient_color.rgb;
}

// The environment map (`EnvironmentMapLight` on the camera, or light probes) prefiltered by a
// GGX lobe of roughness `roughness` around `direction`, in Bevy's units (its intensity
// applied); 0 without an environment map.
fn environment_radiance(s: Surface, direction: vec3<f32>, roughness: f32) -> vec3<f32> {
#ifdef ENVIRONMENT_MAP
    var layer: LayerLightingInput;
    // N = R: Bevy's own pull towards the normal is skipped, glazec's lobe direction has it.
    layer.N = direction;
    layer.R = direction;
    layer.NdotV = 1.0;
    layer.perceptual_roughness = roughness;
    layer.roughness = roughness * roughness;
    var ranges = s.ranges;
    return environment_map::compute_radiances(layer, &ranges, s.world_position.xyz, true).radiance;
#else
    return vec3(0.0);
#endif
}

// The environment map's irradiance around `direction` over π (Bevy's diffuse map).
fn environment_irradiance(s: Surface, direction: vec3<f32>) -> vec3<f32> {
#ifdef ENVIRONMENT_MAP
    var layer: LayerLightingInput;
    layer.N = direction;
    layer.R = direction;
    layer.NdotV = 1.0;
    layer.perceptual_roughness = 1.0;
    layer.roughness = 1.0;
    var ranges = s.ranges;
    return environment_map::compute_radiances(layer, &ranges, s.world_position.xyz, false).irradiance;
#else
    return vec3(0.0);
#endif
}

// The fragment's colour from the reflected radiance: the view's exposure, then Bevy's
// post-lighting (distance fog, tonemapping and debanding when they are on).
fn finish(s: Surface, radiance: vec3<f32>) -> vec4<f32> {
    var pbr_input = pbr_types::pbr_input_new();
    pbr_input.world_position = s.world_position;
    pbr_input.frag_coord = s.frag_coord;
    pbr_input.material.flags = pbr_types::STANDARD_MATERIAL_FLAGS_FOG_ENABLED_BIT;
    let color = vec4<f32>(radiance * view_bindings::view.exposure, 1.0);
    return main_pass_post_lighting_processing(pbr_input, color);
}

// A tangent frame at the shading normal, for normal maps.
struct Frame {
    t: vec3<f32>,
    b: vec3<f32>,
}

// The frame (t, b) at `n` from a mesh's MikkTSpace tangent (w: the bitangent's sign), t made
// perpendicular to n (Gram–Schmidt), as Bevy's `calculate_tbn_mikktspace` builds it.
fn tangent_frame(n: vec3<f32>, tangent: vec4<f32>) -> Frame {
    let t = normalize(tangent.xyz - n * dot(n, tangent.xyz));
    let handedness = select(1.0, -1.0, tangent.w < 0.0);
    return Frame(t, cross(n, t) * handedness);
}

// Some tangent at `n`, for a normal-mapped material on a mesh without tangents (the map's
// orientation is then arbitrary; `Mesh::generate_tangents` gives the real one).
fn any_tangent(n: vec3<f32>) -> vec4<f32> {
    let up = select(vec3(0.0, 1.0, 0.0), vec3(1.0, 0.0, 0.0), abs(n.y) > 0.9);
    return vec4(normalize(cross(up, n)), 1.0);
}
