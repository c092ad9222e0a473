//! The layout test: for every shipped material and every generated layout case, the Rust
//! parameter struct glazec wrote and the uniform struct naga lays out agree, member for member.
//!
//! Three views of one layout are compared: `offset_of!`/`size_of` of the Rust struct (rustc's
//! layout), the member list the generator recorded from glazec's IR, and naga's own WGSL front
//! end parsing the emitted shader (independent of glazec's lowering).

use glazec_spheres::materials::{self, tunable_glaze};

/// The generated awkward cases (see build.rs): every sequence of `f32`/`vec3<f32>` members of
/// length 1 to 5.
mod cases {
    include!(concat!(env!("OUT_DIR"), "/layout_cases/glazec_materials.rs"));
}

/// 2 + 4 + 8 + 16 + 32 sequences.
const LAYOUT_CASES: usize = 62;

/// naga's layout of the struct `name` in `wgsl`: (member name, offset, size) and the span.
fn naga_layout(wgsl: &str, name: &str) -> (Vec<(String, u32, u32)>, u32) {
    let module = naga::front::wgsl::parse_str(wgsl).unwrap_or_else(|e| panic!("{name}: {}", e.emit_to_string(wgsl)));
    let mut layouter = naga::proc::Layouter::default();
    layouter.update(module.to_ctx()).expect("the module's types lay out");
    let (_, ty) = module
        .types
        .iter()
        .find(|(_, t)| t.name.as_deref() == Some(name))
        .unwrap_or_else(|| panic!("no struct {name} in the WGSL"));
    let naga::TypeInner::Struct { members, span } = &ty.inner else { panic!("{name} is not a struct") };
    let members = members.iter().map(|m| (m.name.clone().unwrap_or_default(), m.offset, layouter[m.ty].size)).collect();
    (members, *span)
}

/// The parts of a material's parameter description that the check reads (the shipped and the
/// case module each define their own `MaterialInfo` type).
struct Described<'a> {
    name: &'a str,
    wgsl: &'a str,
    struct_name: &'a str,
    size: usize,
    rust_size: usize,
    default_bytes: usize,
    members: Vec<(&'a str, usize, usize)>,
    rust_offsets: &'a [usize],
}

macro_rules! described {
    ($material:expr) => {
        $material.params.map(|p| Described {
            name: $material.name,
            wgsl: $material.wgsl,
            struct_name: p.struct_name,
            size: p.size,
            rust_size: p.rust_size,
            default_bytes: p.default_bytes.len(),
            members: p.members.iter().map(|m| (m.name, m.offset, m.size)).collect(),
            rust_offsets: p.rust_offsets,
        })
    };
}

fn check(params: Option<Described<'_>>) -> usize {
    let Some(params) = params else { return 0 };
    let (naga_members, naga_span) = naga_layout(params.wgsl, params.struct_name);
    let name = params.name;
    // glazec pads the uniform struct to a multiple of 16 bytes (what std140 and HLSL constant
    // buffers round to); WGSL text cannot spell trailing padding, so naga's front end reads
    // the unpadded size back.
    assert_eq!((naga_span as usize).next_multiple_of(16), params.size, "{name}: naga's struct size vs the generator's");
    assert_eq!(params.rust_size, params.size, "{name}: size_of the Rust struct");
    assert_eq!(params.default_bytes, params.size, "{name}: default bytes");
    assert_eq!(naga_members.len(), params.members.len(), "{name}: member count");
    for (i, ((naga_name, offset, size), member)) in naga_members.iter().zip(&params.members).enumerate() {
        let (member_name, member_offset, member_size) = *member;
        // naga's namer appends `_` to a name that ends in a digit (`p0` → `p0_`) in every
        // backend; the Rust field keeps the material's name.
        let written_as = if member_name.ends_with(|c: char| c.is_ascii_digit()) {
            format!("{member_name}_")
        } else {
            member_name.to_string()
        };
        assert_eq!(*naga_name, written_as, "{name}: member {i}");
        assert_eq!(*offset as usize, member_offset, "{name}.{naga_name}: naga offset vs recorded");
        assert_eq!(*size as usize, member_size, "{name}.{naga_name}: size");
        assert_eq!(params.rust_offsets[i], member_offset, "{name}.{naga_name}: offset_of! in the Rust struct");
    }
    naga_members.len()
}

#[test]
fn every_shipped_material_struct_matches_naga() {
    let members: usize = materials::MATERIALS.iter().map(|m| check(described!(m))).sum();
    assert!(materials::MATERIALS.len() >= 9, "all shipped materials are in the module");
    assert!(members > 0, "at least one shipped material has runtime parameters");
}

#[test]
fn every_awkward_layout_case_matches_naga() {
    assert_eq!(cases::MATERIALS.len(), LAYOUT_CASES);
    for material in cases::MATERIALS {
        let pattern = material.name.trim_start_matches("layout_");
        let params = material.params.expect("every case has parameters");
        // The case really has the member sequence its name says (s = f32, c = vec3<f32>).
        let kinds: String = params.members.iter().map(|m| if m.wgsl_type == "f32" { 's' } else { 'c' }).collect();
        assert_eq!(kinds, pattern, "{}", material.name);
        assert_eq!(check(described!(material)), pattern.len());
    }
}

#[test]
fn a_vec3_after_a_scalar_starts_a_new_16_byte_slot_and_a_scalar_fills_its_tail() {
    let members = cases::layout_scs::PARAMS_MEMBERS;
    assert_eq!(members.iter().map(|m| m.offset).collect::<Vec<_>>(), [0, 16, 28]);
    assert_eq!(core::mem::size_of::<cases::layout_scs::Params>(), 32);
    let members = cases::layout_cc::PARAMS_MEMBERS;
    assert_eq!(members.iter().map(|m| m.offset).collect::<Vec<_>>(), [0, 16]);
}

#[test]
fn typed_defaults_are_the_bytes_the_shader_expects() {
    let params = tunable_glaze::Params::default();
    assert_eq!(bytemuck::bytes_of(&params), tunable_glaze::PARAMS_INFO.default_bytes);
    // Writing one member through the struct lands at naga's offset of that member.
    let changed = tunable_glaze::Params { glaze_thickness: 7.0, ..params };
    let offset = tunable_glaze::PARAMS_MEMBERS.iter().find(|m| m.name == "glaze_thickness").expect("member").offset;
    assert_eq!(bytemuck::bytes_of(&changed)[offset..offset + 4], 7.0_f32.to_le_bytes());
}

#[test]
fn binding_descriptions_match_the_wgsl() {
    for material in materials::MATERIALS {
        // The library and the harness after it.
        let whole = format!("{}\n{}", material.wgsl, material.wgsl_harness);
        let module = naga::front::wgsl::parse_str(&whole).expect("parses");
        let library = naga::front::wgsl::parse_str(material.wgsl).expect("parses");
        assert!(library.entry_points.is_empty(), "{}: the library has entry points", material.name);
        for binding in material.library_bindings {
            assert!(
                library.global_variables.iter().any(|(_, v)| v.name.as_deref() == Some(binding.name)
                    && v.binding.is_some_and(|b| b.group == binding.group && b.binding == binding.binding)),
                "{}: the library declares no `{}` at {}:{}",
                material.name,
                binding.name,
                binding.group,
                binding.binding
            );
        }
        for binding in material.preview_bindings.iter().chain(material.eval_pairs_bindings) {
            let var = module
                .global_variables
                .iter()
                .map(|(_, v)| v)
                .find(|v| v.binding.is_some_and(|b| b.group == binding.group && b.binding == binding.binding))
                .unwrap_or_else(|| panic!("{}: no global at binding {}", material.name, binding.binding));
            // naga renames a global that clashes with a function argument (`params` → `params_2`).
            let wgsl_name = var.name.clone().unwrap_or_default();
            assert!(wgsl_name.starts_with(binding.name), "{}: {} vs {wgsl_name}", material.name, binding.name);
        }
        assert!(material.preview_bindings.iter().all(|b| !b.stages.compute));
        assert!(material.eval_pairs_bindings.iter().all(|b| b.stages.compute && !b.stages.fragment));
    }
}
