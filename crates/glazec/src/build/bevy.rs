//! The Bevy flavour of [`super::Build`] (`Build::bevy`): per material, a Bevy `Material` type and
//! the forward fragment shader that lights it with Bevy's own lights through the material's BRDF.
//!
//! For each material the build writes, beside the naga_oil library `<m>.naga_oil.wgsl`
//! (`#define_import_path glazec::<m>`, its resources at `#{MATERIAL_BIND_GROUP}`):
//!
//! * `<m>.bevy.wgsl`, the fragment shader: the light loop of `glazec_bevy::lighting` (Bevy's
//!   directional lights with their cascaded shadows, the cluster's point and spot lights with
//!   theirs, ambient light and the environment map) calling `<m>_eval` per light and
//!   `<m>_ibl_lobes` for the environment, then Bevy's post-lighting (fog, tonemapping);
//! * in `OUT_DIR/glazec_bevy_materials.rs`, a module `<m>` with the material type `<M>`
//!   (`#[derive(Asset, TypePath, AsBindGroup)]`): one public field per runtime parameter
//!   (`f32` or `Vec3`, combined by `AsBindGroup` into the uniform at binding 0, laid out as the
//!   library's `<M>Params`), the table uniform at binding 1 when the library reads tables, and
//!   one `Option<Handle<Image>>` per texture (the sampler at 2, the textures from 3);
//!   `Default` holds the material's defaults. `GlazecMaterialsPlugin` registers the shaders and
//!   a `MaterialPlugin` per material.
//!
//! The Rust text names `bevy` and `glazec_bevy` (the runtime crate, which holds the lighting
//! module): a crate that includes the module depends on both.

use std::fmt::Write as _;

use super::rust_module::rust_ident;
use crate::Compiled;
use crate::lower::bindings::{Choice, Resource, Slot};
use crate::model::{ParamValue, camel_case};

/// The generated Rust module's file name in the output directory.
pub const MODULE_FILE: &str = "glazec_bevy_materials.rs";

/// Bevy's material bind group (`MATERIAL_BIND_GROUP_INDEX` of Bevy 0.19); the naga_oil library
/// writes it as `#{MATERIAL_BIND_GROUP}`, which Bevy defines.
const MATERIAL_GROUP: u32 = 3;

/// The bindings of every material's library in Bevy's material bind group: the parameters at 0,
/// the tables at 1, the sampler at 2 and the textures from 3. glazec's own environment is not
/// placed, so the library has none: the fragment shader lights by Bevy's environment map through
/// `<m>_ibl_lobes`.
pub(super) fn choice() -> Choice {
    Choice::default()
        .with(Resource::Params, Slot::new(MATERIAL_GROUP, 0))
        .with(Resource::Tables, Slot::new(MATERIAL_GROUP, 1))
        .with(Resource::Textures, Slot::new(MATERIAL_GROUP, 2))
}

/// One material, with where its files were written.
pub(super) struct BevyMaterial<'a> {
    pub compiled: &'a Compiled,
    /// Absolute paths of `<m>.naga_oil.wgsl`, `<m>.bevy.wgsl` and `<m>.tables.bin` (if any).
    pub library: String,
    pub fragment: String,
    pub tables: Option<String>,
}

/// The file name of a material's fragment shader.
pub(super) fn fragment_file(material: &str) -> String {
    format!("{material}.bevy.wgsl")
}

/// `<m>.bevy.wgsl`: the material's forward fragment shader for Bevy.
pub(super) fn fragment_shader(c: &Compiled) -> String {
    let m = &c.material;
    let name = &m.name;
    let header = crate::emit::header(name, &c.origin);
    let has_params = m.uniform_params().next().is_some();
    let has_textures = !m.textures().is_empty();
    let framed = !m.normals.is_empty();
    let mut imports = vec![format!("{name}_eval"), format!("{name}_ibl_lobes"), format!("{name}_ibl_specular_lobes")];
    let mut extra = String::new();
    if has_params {
        imports.push(format!("{name}_params"));
        extra.push_str(&format!(", {name}_params"));
    }
    if has_textures {
        imports.push(format!("{name}_textures"));
        extra.push_str(", textures");
    }
    let mut out = header;
    let _ = writeln!(
        out,
        "// The forward fragment shader of the Bevy material `{}`: Bevy's lights, shadows and environment\n\
         // map (glazec_bevy::lighting) through `{name}_eval` and `{name}_ibl_lobes`.",
        camel_case(name)
    );
    out.push_str("#import bevy_pbr::forward_io::{VertexOutput, FragmentOutput}\n");
    out.push_str("#import glazec_bevy::lighting\n");
    let _ = writeln!(out, "#import glazec::{name}::{{{}}}\n", imports.join(", "));
    out.push_str(
        "@fragment\nfn fragment(in: VertexOutput, @builtin(front_facing) is_front: bool) -> FragmentOutput {\n",
    );
    out.push_str("    let s = lighting::surface(in, is_front);\n");
    if has_textures {
        out.push_str("#ifdef VERTEX_UVS_A\n    let uv = in.uv;\n#else\n    let uv = vec2(0.0);\n#endif\n");
        if framed {
            out.push_str(
                "#ifdef VERTEX_TANGENTS\n    let frame = lighting::tangent_frame(s.n, in.world_tangent);\n\
                 #else\n    let frame = lighting::tangent_frame(s.n, lighting::any_tangent(s.n));\n#endif\n",
            );
            let _ = writeln!(out, "    let textures = {name}_textures(uv, s.n, frame.t, frame.b);");
        } else {
            let _ = writeln!(out, "    let textures = {name}_textures(uv);");
        }
    }
    out.push_str("    var radiance = vec3(0.0);\n");
    out.push_str("    for (var i = 0u; i < lighting::directional_count(); i++) {\n");
    out.push_str("        let light = lighting::directional(s, i);\n");
    let _ = writeln!(out, "        radiance += {name}_eval(s.n, s.v, light.l{extra}) * light.radiance;");
    out.push_str("    }\n");
    out.push_str("    for (var i = lighting::first_clustered(s); i < lighting::end_clustered(s); i++) {\n");
    out.push_str("        let light = lighting::clustered(s, i);\n");
    let _ = writeln!(out, "        radiance += {name}_eval(s.n, s.v, light.l{extra}) * light.radiance;");
    out.push_str("    }\n");
    out.push_str("    // The environment map and the ambient light, through the material's lobes (split sum).\n");
    let _ = writeln!(out, "    var lobes = {name}_ibl_lobes(s.n, s.v{extra});");
    out.push_str("    var albedo = lobes.irradiance.weight;\n");
    out.push_str(
        "    radiance += lobes.irradiance.weight * lighting::environment_irradiance(s, lobes.irradiance.direction);\n",
    );
    let _ = writeln!(out, "    for (var k = 0u; k < {name}_ibl_specular_lobes; k++) {{");
    out.push_str("        let lobe = lobes.specular[k];\n");
    out.push_str(
        "        radiance += lobe.weight * lighting::environment_radiance(s, lobe.direction, lobe.roughness);\n",
    );
    out.push_str("        albedo += lobe.weight;\n    }\n");
    out.push_str("    radiance += albedo * lighting::ambient();\n");
    out.push_str("    var out: FragmentOutput;\n    out.color = lighting::finish(s, radiance);\n    return out;\n}\n");
    out
}

/// The text of `glazec_bevy_materials.rs`.
pub(super) fn module_text(materials: &[BevyMaterial<'_>]) -> String {
    let mut out = String::new();
    let _ = writeln!(
        out,
        "// Generated by glazec {} (build.rs API, Bevy flavour) for {} material(s). Do not edit: it is rewritten on every build.\n",
        crate::VERSION,
        materials.len()
    );
    for m in materials {
        write_material(&mut out, m);
    }
    out.push_str("/// Registers every material's shaders and `MaterialPlugin` (and `glazec_bevy::GlazecPlugin`,\n");
    out.push_str("/// the lighting module they import). Add it after `DefaultPlugins`.\n");
    out.push_str("pub struct GlazecMaterialsPlugin;\n\n");
    out.push_str("impl bevy::app::Plugin for GlazecMaterialsPlugin {\n");
    out.push_str("    fn build(&self, app: &mut bevy::app::App) {\n");
    out.push_str("        if !app.is_plugin_added::<glazec_bevy::GlazecPlugin>() {\n");
    out.push_str("            app.add_plugins(glazec_bevy::GlazecPlugin);\n        }\n");
    for m in materials {
        let _ = writeln!(out, "        {}::register(app);", rust_ident(&m.compiled.material.name));
    }
    out.push_str("    }\n}\n");
    out
}

fn write_material(out: &mut String, bm: &BevyMaterial<'_>) {
    let c = bm.compiled;
    let m = &c.material;
    let name = &m.name;
    let ty = camel_case(name);
    let file = c.origin.file.as_deref().unwrap_or_default();
    let _ = writeln!(out, "/// Material `{name}` for Bevy, compiled from `{file}`.");
    let _ = writeln!(out, "pub mod {} {{", rust_ident(name));
    out.push_str("    #![allow(dead_code)]\n");
    out.push_str("    use bevy::prelude::*;\n");
    out.push_str("    use bevy::render::render_resource::AsBindGroup;\n");
    out.push_str("    use bevy::shader::ShaderRef;\n\n");
    let _ = writeln!(out, "    pub const NAME: &str = {name:?};");
    let _ = writeln!(out, "    /// The material's library (naga_oil, `#define_import_path glazec::{name}`).");
    let _ = writeln!(out, "    pub const LIBRARY: &str = include_str!({:?});", bm.library);
    out.push_str("    /// The forward fragment shader: Bevy's lights through the material's BRDF.\n");
    let _ = writeln!(out, "    pub const FRAGMENT: &str = include_str!({:?});", bm.fragment);
    let _ =
        writeln!(out, "    pub const LIBRARY_SHADER: Handle<Shader> = bevy::asset::uuid_handle!({:?});", uuid(name, 1));
    let _ = writeln!(
        out,
        "    pub const FRAGMENT_SHADER: Handle<Shader> = bevy::asset::uuid_handle!({:?});",
        uuid(name, 2)
    );
    let table_words = c.tables_bytes().len() / 16;
    if let Some(tables) = &bm.tables {
        out.push_str("    /// The table uniform's contents (`glazec tables`): the tables the library reads.\n");
        let _ = writeln!(out, "    pub const TABLES: &[u8] = include_bytes!({tables:?});");
    }
    out.push('\n');
    let _ = writeln!(
        out,
        "    /// `{name}` as a Bevy material: its runtime parameters are the public fields (a change shows"
    );
    out.push_str("    /// in the next frame), its textures `Option<Handle<Image>>` (white when `None`).\n");
    out.push_str("    #[derive(Asset, TypePath, AsBindGroup, Clone, Debug)]\n");
    let _ = writeln!(out, "    pub struct {ty} {{");
    for (_, p) in m.uniform_params() {
        let rust = match p.default {
            ParamValue::Scalar(_) => "f32",
            ParamValue::Rgb(_) => "Vec3",
        };
        let ([lo, hi], each) = (p.range, if rust == "Vec3" { " per component" } else { "" });
        let _ = writeln!(out, "        /// Accepts [{lo}, {hi}]{each}.");
        let _ = writeln!(out, "        #[uniform(0)]\n        pub {}: {rust},", rust_ident(&p.name));
    }
    if bm.tables.is_some() {
        out.push_str("        /// The table uniform (`TABLES`, from `Default`): glazec's data, not a parameter.\n");
        let _ = writeln!(out, "        #[uniform(1)]\n        pub tables: [UVec4; {table_words}],");
    }
    for (i, texture) in m.textures().iter().enumerate() {
        if i == 0 {
            out.push_str("        #[sampler(2)]\n");
        }
        let _ =
            writeln!(out, "        #[texture({})]\n        pub {}: Option<Handle<Image>>,", 3 + i, rust_ident(texture));
    }
    out.push_str("    }\n\n");
    let _ = writeln!(out, "    impl Default for {ty} {{");
    out.push_str("        fn default() -> Self {\n            Self {\n");
    for (_, p) in m.uniform_params() {
        let value = match p.default {
            ParamValue::Scalar(x) => format!("{x:?}"),
            ParamValue::Rgb([r, g, b]) => format!("Vec3::new({r:?}, {g:?}, {b:?})"),
        };
        let _ = writeln!(out, "                {}: {value},", rust_ident(&p.name));
    }
    if bm.tables.is_some() {
        out.push_str("                tables: glazec_bevy::table_words(TABLES),\n");
    }
    for texture in m.textures() {
        let _ = writeln!(out, "                {}: None,", rust_ident(texture));
    }
    out.push_str("            }\n        }\n    }\n\n");
    let _ = writeln!(out, "    impl Material for {ty} {{");
    out.push_str("        fn fragment_shader() -> ShaderRef {\n            ShaderRef::Handle(FRAGMENT_SHADER)\n        }\n    }\n\n");
    out.push_str("    /// Adds the shaders to `Assets<Shader>` and the material's `MaterialPlugin`.\n");
    out.push_str("    pub fn register(app: &mut App) {\n");
    out.push_str("        let mut shaders = app.world_mut().resource_mut::<Assets<Shader>>();\n");
    let _ = writeln!(
        out,
        "        let _ = shaders.insert(&LIBRARY_SHADER, Shader::from_wgsl(LIBRARY, \"glazec/{name}/{name}.naga_oil.wgsl\"));"
    );
    let _ = writeln!(
        out,
        "        let _ = shaders.insert(&FRAGMENT_SHADER, Shader::from_wgsl(FRAGMENT, \"glazec/{name}/{}\"));",
        fragment_file(name)
    );
    let _ = writeln!(out, "        app.add_plugins(MaterialPlugin::<{ty}>::default());");
    out.push_str("    }\n}\n\n");
}

/// A fixed UUID for a material's shader handle: two FNV-1a hashes (the source hash of
/// [`crate::origin`]) of the name and `which`, as a version-8 (custom) UUID, so that handles are
/// stable across builds and distinct between materials.
fn uuid(name: &str, which: u8) -> String {
    let hash = |salt: &str| crate::origin::source_hash(format!("{salt}/{name}/{which}").as_bytes());
    let mut u = [0u8; 16];
    u[..8].copy_from_slice(&hash("glazec").to_be_bytes());
    u[8..].copy_from_slice(&hash("bevy").to_be_bytes());
    u[6] = (u[6] & 0x0f) | 0x80; // version 8
    u[8] = (u[8] & 0x3f) | 0x80; // RFC 4122 variant
    let hex: String = u.iter().map(|b| format!("{b:02x}")).collect();
    format!("{}-{}-{}-{}-{}", &hex[0..8], &hex[8..12], &hex[12..16], &hex[16..20], &hex[20..32])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shader_handles_are_valid_distinct_uuids() {
        let a = uuid("clay", 1);
        assert_eq!(a.len(), 36);
        assert_eq!(&a[14..15], "8", "version 8: {a}");
        assert!(matches!(&a[19..20], "8" | "9" | "a" | "b"), "variant: {a}");
        assert_ne!(a, uuid("clay", 2));
        assert_ne!(a, uuid("clay_", 1));
        assert_eq!(a, uuid("clay", 1));
    }
}
