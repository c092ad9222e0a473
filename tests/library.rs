//! The libraries a host imports: no entry point and no harness global in them, every
//! module-scope name the material's own, several of them in one shader (WGSL through naga,
//! GLSL and HLSL through glslang), the naga_oil flavour composed by `naga_oil`, and bindings
//! where the host chose them.

mod common;

use std::collections::HashMap;

use glazec::Target;
use glazec::lower::bindings::{Choice, Resource, Slot};
use naga::valid::{Capabilities, ValidationFlags, Validator};

/// wgpu's downlevel (and WebGL2's) limit on a uniform binding, in bytes.
const DOWNLEVEL_UNIFORM_LIMIT: usize = 16_384;
/// Random stacks drawn for the table-size check, and the seed.
const LITERAL_STACKS: usize = 64;
const LITERAL_SEED: u64 = 0x7461_626c;

/// The names glazec's harness declares at module scope.
const HARNESS_NAMES: [&str; 10] = [
    "pairs",
    "values",
    "dispatch",
    "light",
    "DirectionPair",
    "EvalDispatch",
    "PreviewLight",
    "PreviewVarying",
    "eval_pairs",
    "preview_fs",
];

/// The file `file` among `compiled`'s outputs for `target` (the harness's files included).
fn text(compiled: &glazec::Compiled, target: Target, file: &str) -> String {
    let artifacts = compiled.emit_with_harness(&[target]).expect("emits");
    let artifact = artifacts.iter().find(|a| a.file_name == file).unwrap_or_else(|| panic!("no {file}"));
    String::from_utf8(artifact.contents.clone()).expect("utf-8")
}

fn parse_and_validate(what: &str, source: &str) -> naga::Module {
    let module = naga::front::wgsl::parse_str(source)
        .unwrap_or_else(|e| panic!("{what} does not parse:\n{}", e.emit_to_string(source)));
    Validator::new(ValidationFlags::all(), Capabilities::default())
        .validate(&module)
        .unwrap_or_else(|e| panic!("{what} does not validate:\n{}", e.emit_to_string(source)));
    module
}

#[test]
fn libraries_hold_no_entry_point_no_harness_and_only_their_own_names() {
    for path in common::material_files() {
        let compiled = common::compile_file(&path);
        let m = &compiled.material.name;
        let source = text(&compiled, Target::Wgsl, &format!("{m}.wgsl"));
        let library = parse_and_validate(&format!("{m}.wgsl"), &source);
        assert!(library.entry_points.is_empty(), "{m}: entry points in the library");
        let prefix = format!("{m}_");
        let structs = glazec::model::camel_case(m);
        let names = library
            .functions
            .iter()
            .filter_map(|(_, f)| f.name.clone())
            .chain(library.global_variables.iter().filter_map(|(_, g)| g.name.clone()))
            .chain(library.constants.iter().filter_map(|(_, c)| c.name.clone()));
        for name in names {
            assert!(name.starts_with(&prefix), "{m}: `{name}` is not namespaced");
        }
        for (_, ty) in library.types.iter() {
            if let (Some(name), naga::TypeInner::Struct { .. }) = (&ty.name, &ty.inner) {
                assert!(name.starts_with(&structs), "{m}: struct `{name}` is not the material's");
            }
        }
        for harness in HARNESS_NAMES {
            // (Comments, which may say "white light: …", declare nothing.)
            let declared = source.lines().filter(|l| !l.trim_start().starts_with("//")).any(|l| {
                l.starts_with(&format!("fn {harness}("))
                    || l.starts_with(&format!("struct {harness} "))
                    || l.contains(&format!(" {harness}: "))
            });
            assert!(!declared, "{m}: the library declares the harness's `{harness}`");
        }
        // The GLSL and HLSL libraries: no `main`, no `#version`, no harness entry point.
        let glsl = text(&compiled, Target::Glsl, &format!("{m}.glsl"));
        assert!(!glsl.contains("void main(") && !glsl.contains("#version"), "{m}.glsl");
        let hlsli = text(&compiled, Target::Hlsl, &format!("{m}.hlsli"));
        assert!(!hlsli.contains("eval_pairs") && !hlsli.contains("SV_Target"), "{m}.hlsli");
    }
}

#[test]
fn every_library_concatenates_into_one_wgsl_module() {
    let mut all = String::new();
    let mut functions = 0;
    for path in common::material_files() {
        let compiled = common::compile_file(&path);
        all.push_str(&text(&compiled, Target::Wgsl, &format!("{}.wgsl", compiled.material.name)));
        all.push('\n');
        functions += compiled.library.functions.len();
    }
    let module = parse_and_validate("every library, concatenated", &all);
    assert_eq!(module.functions.len(), functions);
}

#[test]
fn every_glsl_and_hlsl_library_goes_into_one_shader() {
    if !common::tool_available("glslangValidator") {
        return;
    }
    let dir = tempfile::tempdir().expect("temp dir");
    let (mut glsl, mut hlsl) = (String::from("#version 450 core\n"), String::new());
    let mut calls = Vec::new();
    for path in common::material_files() {
        let compiled = common::compile_file(&path);
        let m = &compiled.material.name;
        glsl.push_str(&text(&compiled, Target::Glsl, &format!("{m}.glsl")));
        glsl.push('\n');
        let hlsli = format!("{m}.hlsli");
        std::fs::write(dir.path().join(&hlsli), text(&compiled, Target::Hlsl, &hlsli)).expect("writes");
        hlsl.push_str(&format!("#include \"{hlsli}\"\n"));
        if compiled.material.params.is_empty() {
            calls.push(format!("{m}_eval"));
        }
    }
    // Every parameterless material's eval, summed (GLSL: vec3; HLSL: float3).
    let sum = |vec: &str| {
        calls.iter().map(|f| format!(" + {f}({vec}(0, 0, 1), {vec}(0, 0, 1), {vec}(0, 0, 1))")).collect::<String>()
    };
    glsl.push_str(&format!(
        "layout(location = 0) out vec4 color;\nvoid main() {{ color = vec4(vec3(0){}, 1); }}\n",
        sum("vec3")
    ));
    hlsl.push_str(&format!("float4 main() : SV_Target0 {{ return float4(float3(0, 0, 0){}, 1); }}\n", sum("float3")));
    for (file, args) in
        [("all.frag", vec!["-V", "-S", "frag"]), ("all.hlsl", vec!["-D", "-V", "-S", "frag", "-e", "main"])]
    {
        let source = if file.ends_with(".frag") { &glsl } else { &hlsl };
        std::fs::write(dir.path().join(file), source).expect("writes");
        let out = std::process::Command::new("glslangValidator")
            .args(&args)
            .arg(dir.path().join(file))
            .arg("-o")
            .arg(dir.path().join("out.spv"))
            .output()
            .expect("runs glslang");
        assert!(out.status.success(), "{file}: {}", String::from_utf8_lossy(&out.stdout));
    }
}

#[test]
fn the_naga_oil_flavour_composes_with_naga_oil() {
    use naga_oil::compose::{
        ComposableModuleDescriptor, Composer, NagaModuleDescriptor, ShaderDefValue, ShaderLanguage, ShaderType,
    };
    let wet_clay = common::compile_file(&common::root().join("materials/wet_clay.ron"));
    // A second material with runtime parameters, bound after the first's resources.
    let glaze = common::compile_file(&common::root().join("materials/tunable_glaze.ron"))
        .with_bindings(&Choice::default().with(Resource::Params, Slot::new(0, 8)))
        .expect("binds");
    let mut composer = Composer::default();
    for compiled in [&wet_clay, &glaze] {
        let m = &compiled.material.name;
        let source = text(compiled, Target::NagaOil, &format!("{m}.naga_oil.wgsl"));
        assert!(source.starts_with("// Generated by glazec"), "{m}: header first");
        assert!(source.contains(&format!("#define_import_path glazec::{m}\n")), "{m}");
        // wet_clay's literals need no resource of its own (its tables are curves in the code);
        // the glaze's parameters and tables sit in the material's group, a placeholder.
        let own = source.contains("@group(#{MATERIAL_BIND_GROUP})");
        assert_eq!(own, compiled.layout.params.is_some() || compiled.uses_tables(), "{m}: the material's group");
        composer
            .add_composable_module(ComposableModuleDescriptor {
                source: &source,
                file_path: &format!("{m}.naga_oil.wgsl"),
                language: ShaderLanguage::Wgsl,
                ..Default::default()
            })
            .unwrap_or_else(|e| panic!("{m}: naga_oil rejects the module: {e:?}"));
    }
    let shader = r"
#import glazec::wet_clay::wet_clay_eval
#import glazec::tunable_glaze::{tunable_glaze_eval, tunable_glaze_params}

@fragment
fn fragment(@location(0) normal: vec3<f32>) -> @location(0) vec4<f32> {
    let n = normalize(normal);
    let v = vec3<f32>(0.0, 0.0, 1.0);
    let l = normalize(vec3<f32>(0.3, 0.4, 1.0));
    let shaded = wet_clay_eval(n, v, l) + tunable_glaze_eval(n, v, l, tunable_glaze_params);
    return vec4<f32>(shaded, 1.0);
}
";
    let defs = HashMap::from([("MATERIAL_BIND_GROUP".to_string(), ShaderDefValue::UInt(2))]);
    let module = composer
        .make_naga_module(NagaModuleDescriptor {
            source: shader,
            file_path: "host.wgsl",
            shader_type: ShaderType::Wgsl,
            shader_defs: defs,
            ..Default::default()
        })
        .unwrap_or_else(|e| panic!("naga_oil cannot compose the two materials: {e:?}"));
    Validator::new(ValidationFlags::all(), Capabilities::default())
        .validate(&module)
        .expect("the composed module validates");
    // The materials' own resources moved to group 2; neither library has glazec's environment.
    let groups: Vec<(String, u32, u32)> = module
        .global_variables
        .iter()
        .filter_map(|(_, g)| g.binding.map(|b| (g.name.clone().unwrap_or_default(), b.group, b.binding)))
        .collect();
    let params = groups.iter().find(|(n, ..)| n.contains("tunable_glaze_params")).expect("the glaze's parameters");
    assert_eq!((params.1, params.2), (2, 8), "{groups:?}");
    let tables = groups.iter().find(|(n, ..)| n.contains("tunable_glaze_tables")).expect("the glaze's tables");
    assert_eq!(tables.1, 2, "{groups:?}");
    assert!(!groups.iter().any(|(n, ..)| n.starts_with("wet_clay")), "wet_clay binds nothing: {groups:?}");
    assert!(!groups.iter().any(|(n, ..)| n.contains("radiance")), "no environment unless placed: {groups:?}");
}

#[test]
fn the_wgsl_libraries_are_wesl_modules() {
    use std::borrow::Cow;
    use wesl::VirtualResolver;
    let wet_clay = common::compile_file(&common::root().join("materials/wet_clay.ron"));
    let glaze = common::compile_file(&common::root().join("materials/tunable_glaze.ron"))
        .with_bindings(&Choice::default().with(Resource::Params, Slot::new(0, 8)))
        .expect("binds");
    let path = |p: &str| p.parse::<wesl::ModulePath>().unwrap_or_else(|e| panic!("{p}: {e:?}"));
    let mut resolver = VirtualResolver::new();
    for compiled in [&wet_clay, &glaze] {
        let m = &compiled.material.name;
        let library = text(compiled, Target::Wgsl, &format!("{m}.wgsl"));
        resolver.add_module(path(&format!("package::{m}")), Cow::Owned(library));
    }
    let main = r"
import package::wet_clay::wet_clay_eval;
import package::tunable_glaze::{tunable_glaze_eval, tunable_glaze_params};

@fragment
fn fragment(@location(0) normal: vec3<f32>) -> @location(0) vec4<f32> {
    let n = normalize(normal);
    let v = vec3<f32>(0.0, 0.0, 1.0);
    let l = normalize(vec3<f32>(0.3, 0.4, 1.0));
    return vec4<f32>(wet_clay_eval(n, v, l) + tunable_glaze_eval(n, v, l, tunable_glaze_params), 1.0);
}
";
    resolver.add_module(path("package::main"), Cow::Borrowed(main));
    let compiler = wesl::Wesl::new("").set_custom_resolver(resolver);
    let result = compiler.compile(&path("package::main")).unwrap_or_else(|e| panic!("WESL: {e}"));
    let module = parse_and_validate("the WESL compiler's output", &result.to_string());
    assert_eq!(module.entry_points.len(), 1);
    // Both BRDFs came through the imports (names as the WESL compiler mangles them).
    let names: Vec<String> = module.functions.iter().filter_map(|(_, f)| f.name.clone()).collect();
    for brdf in ["wet_clay_brdf", "tunable_glaze_brdf"] {
        assert!(names.iter().any(|n| n.contains(brdf)), "{brdf} missing from {names:?}");
    }
}

#[test]
fn bindings_go_where_the_host_chooses() {
    let glaze = common::compile_file(&common::root().join("materials/tunable_glaze.ron"));
    let choice = Choice::default().with(Resource::Params, Slot::new(3, 0)).with(Resource::Environment, Slot::new(1, 4));
    let rebound = glaze.with_bindings(&choice).expect("binds");
    let wgsl = text(&rebound, Target::Wgsl, "tunable_glaze.wgsl");
    for declaration in [
        "@group(3) @binding(0) \nvar<uniform> tunable_glaze_params: TunableGlazeParams;",
        // The tables follow the parameters.
        "@group(3) @binding(1) \nvar<uniform> tunable_glaze_tables:",
        "@group(1) @binding(4) \nvar tunable_glaze_environment_sampler: sampler;",
        "@group(1) @binding(5) \nvar tunable_glaze_radiance: texture_2d<f32>;",
        "@group(1) @binding(6) \nvar tunable_glaze_irradiance: texture_2d<f32>;",
    ] {
        assert!(wgsl.contains(declaration), "missing:\n{declaration}\nin\n{wgsl}");
    }
    assert!(wgsl.contains("\nfn tunable_glaze_ibl("), "placing the environment adds `_ibl`");
    assert_eq!(rebound.layout.params, Some(Slot::new(3, 0)));
    // The harness takes the lowest free bindings of group 0.
    let harness = &rebound.harness().expect("the harness validates").layout;
    assert_eq!((harness.pairs, harness.values, harness.dispatch), (0, 1, 2));
    // Two resources in one place are refused, naming both.
    let clash = glaze.with_bindings(
        &Choice::default().with(Resource::Environment, Slot::new(2, 0)).with(Resource::Tables, Slot::new(2, 1)),
    );
    let message = clash.err().map(|e| e.to_string()).unwrap_or_default();
    assert!(message.contains("tunable_glaze_tables") && message.contains("tunable_glaze_radiance"), "{message}");
}

/// Without a place for glazec's environment the library has neither it nor `<m>_ibl`; the
/// harness has both, in group 2, or in the first group the library leaves empty.
#[test]
fn the_environment_is_the_harness_s_unless_placed() {
    let glaze = common::compile_file(&common::root().join("materials/tunable_glaze.ron"));
    let library = text(&glaze, Target::Wgsl, "tunable_glaze.wgsl");
    assert!(!library.contains("var tunable_glaze_radiance") && !library.contains("fn tunable_glaze_ibl("), "{library}");
    assert!(library.contains("fn tunable_glaze_ibl_lobes("), "the lobes stay the library's");
    let harness = text(&glaze, Target::Wgsl, "tunable_glaze.harness.wgsl");
    assert!(harness.contains("@group(2) @binding(1) \nvar tunable_glaze_radiance"), "{harness}");
    assert!(harness.contains("\nfn tunable_glaze_ibl("), "{harness}");
    assert!(glaze.layout.environment.is_empty(), "the library's layout has no environment");
    let names = |c: &glazec::Compiled| {
        c.harness().expect("the harness validates").layout.environment.iter().map(|(_, s)| *s).collect::<Vec<_>>()
    };
    assert_eq!(names(&glaze), [Slot::new(2, 0), Slot::new(2, 1), Slot::new(2, 2)]);
    // The host's parameters and tables in group 2 move the harness's environment to group 3.
    let moved = glaze.with_bindings(&Choice::default().with(Resource::Params, Slot::new(2, 0))).expect("binds");
    assert_eq!(names(&moved), [Slot::new(3, 0), Slot::new(3, 1), Slot::new(3, 2)]);
    let harness = text(&moved, Target::Wgsl, "tunable_glaze.harness.wgsl");
    assert!(harness.contains("@group(3) @binding(0) \nvar tunable_glaze_environment_sampler"), "{harness}");
}

#[test]
fn the_command_line_binds_where_asked_and_refuses_a_clash() {
    let dir = tempfile::tempdir().expect("tmp");
    let out_dir = dir.path().to_str().expect("utf-8");
    let args = ["compile", "materials/tunable_glaze.ron", "--target", "wgsl", "-o", out_dir];
    let out = common::glazec(&[&args[..], &["--bind", "params=2:0", "--bind", "environment=3:0"]].concat());
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let wgsl = std::fs::read_to_string(dir.path().join("tunable_glaze/tunable_glaze.wgsl")).expect("written");
    assert!(wgsl.contains("@group(2) @binding(0) \nvar<uniform> tunable_glaze_params"), "{wgsl}");
    assert!(wgsl.contains("@group(3) @binding(1) \nvar tunable_glaze_radiance"), "{wgsl}");

    let clash_dir = tempfile::tempdir().expect("tmp");
    let clash_out = clash_dir.path().to_str().expect("utf-8");
    let out = common::glazec(&[
        "compile",
        "materials/tunable_glaze.ron",
        "-o",
        clash_out,
        "--bind",
        "params=2:1",
        "--bind",
        "environment=2:0",
    ]);
    assert_eq!(out.status.code(), Some(2), "{}", String::from_utf8_lossy(&out.stderr));
    assert!(
        String::from_utf8_lossy(&out.stderr).contains("would both be bound at 2:"),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert_eq!(std::fs::read_dir(clash_dir.path()).expect("lists").count(), 0, "nothing written");
    let bad = common::glazec(&["compile", "materials/clay.ron", "-o", clash_out, "--bind", "params=two"]);
    assert_eq!(bad.status.code(), Some(2));
}

/// docs/generated-files.md quotes each shipped material's table-uniform size.
#[test]
fn the_documented_table_sizes_are_current() {
    let chapter = std::fs::read_to_string(common::root().join("docs/generated-files.md")).expect("chapter");
    for path in common::material_files() {
        let compiled = common::compile_file(&path);
        let m = &compiled.material.name;
        let size = compiled.tables_bytes().len();
        let cell = if size == 0 { "none".to_string() } else { group_thousands(size) };
        let row = format!("| `{m}` | {cell} |");
        assert!(chapter.contains(&row), "docs/generated-files.md lacks the row {row}");
    }
}

fn group_thousands(n: usize) -> String {
    let digits = n.to_string();
    let mut out = String::new();
    for (i, c) in digits.chars().enumerate() {
        if i > 0 && (digits.len() - i).is_multiple_of(3) {
            out.push(',');
        }
        out.push(c);
    }
    out
}

/// A material whose numbers are all literals binds only the table slices its lookups select:
/// every such shipped material and random stack (up to eight coats) fits the downlevel limit.
#[test]
fn literal_materials_fit_the_downlevel_uniform_limit() {
    use proptest::strategy::{Strategy, ValueTree};
    use proptest::test_runner::{Config, RngSeed, TestRunner};
    let mut checked = 0;
    let mut largest = 0;
    for path in common::material_files() {
        let compiled = common::compile_file(&path);
        if compiled.material.params.is_empty() {
            let size = compiled.tables_bytes().len();
            assert!(size <= DOWNLEVEL_UNIFORM_LIMIT, "{}: {size} bytes of tables", compiled.material.name);
            largest = largest.max(size);
            checked += 1;
        }
    }
    let mut runner = TestRunner::new(Config { rng_seed: RngSeed::Fixed(LITERAL_SEED), ..Config::default() });
    for _ in 0..LITERAL_STACKS {
        let stack = common::stacks::stack().new_tree(&mut runner).expect("a stack").current().literal();
        let text = common::stacks::Writer { next_param: 0 }.material(&stack);
        let compiled = glazec::compile(&text).unwrap_or_else(|e| panic!("{e:?}\n{text}"));
        assert!(compiled.material.params.is_empty(), "{text}");
        let size = compiled.tables_bytes().len();
        assert!(size <= DOWNLEVEL_UNIFORM_LIMIT, "{size} bytes of tables for\n{text}");
        largest = largest.max(size);
        checked += 1;
    }
    eprintln!("{checked} literal materials, largest table uniform {largest} bytes (limit {DOWNLEVEL_UNIFORM_LIMIT})");
    assert!(checked > LITERAL_STACKS, "{checked} literal materials");
}

/// A material whose parameters are all literals reads no resource: its lookups are curves in
/// the code, and glazec's environment is not placed.
#[test]
fn literal_materials_declare_no_resource() {
    let mut literal = 0;
    for path in common::material_files() {
        let compiled = common::compile_file(&path);
        if !compiled.material.params.is_empty() {
            continue;
        }
        literal += 1;
        let m = &compiled.material.name;
        let library = text(&compiled, Target::Wgsl, &format!("{m}.wgsl"));
        let vars: Vec<&str> = library.lines().filter(|l| l.starts_with("var")).collect();
        assert!(vars.is_empty(), "{m}: {vars:?}");
        assert!(!compiled.uses_tables(), "{m}");
    }
    assert!(literal >= 10, "the shipped literal materials were checked");
}

/// A call's result has a name in every language: its own, or its function's without the
/// material's prefix (naga's backends print every call result as `_e<N>`; `emit::polish` names
/// them). Only values naga bakes on its own (an expression used twice) keep an `_e<N>`.
#[test]
fn call_results_are_named() {
    for path in common::material_files() {
        let compiled = common::compile_file(&path);
        let m = compiled.material.name.clone();
        for (target, file) in [
            (Target::Wgsl, format!("{m}.wgsl")),
            (Target::Glsl, format!("{m}.glsl")),
            (Target::Hlsl, format!("{m}.hlsli")),
        ] {
            let text = text(&compiled, target, &file);
            let unnamed: Vec<&str> = text
                .lines()
                .filter(|l| {
                    let Some(at) = l.find("_e") else { return false };
                    let rest = &l[at + 2..];
                    let digits = rest.chars().take_while(char::is_ascii_digit).count();
                    digits > 0
                        && rest[digits..].trim_start().starts_with('=')
                        && rest[digits..].contains(&format!("{m}_"))
                })
                .collect();
            assert!(unnamed.is_empty(), "{file}: unnamed call results:\n{}", unnamed.join("\n"));
            if text.contains("g_smith_ggx_correlated") {
                assert!(text.contains("lambda_v"), "{file}: G₂'s two Λ are named after their directions");
            }
        }
    }
}

/// Every value a library's function names is read, and every call's result is used: the
/// layering code shared with the CPU computes some values only other callers need, and the
/// generated functions leave them out (`lower::builder::dead`).
#[test]
fn libraries_hold_no_dead_code() {
    // The shipped materials, and a coated conductor with runtime parameters, whose hemisphere
    // sums are loops (the pass keeps what a loop's statements read).
    let conductor = "Conductor(roughness: Param(\"cr\", 0.2), eta: (0.27, 0.68, 1.22), k: (3.61, 2.63, 2.29))";
    let coat = "Coat(lobe: Ggx(roughness: Param(\"rough\", 0.3)), ior: Param(\"ior\", 1.5))";
    let looped = format!("Material(name: \"tunable_copper\", layers: [{coat}, {conductor}])");
    let looped = glazec::compile(&looped).unwrap_or_else(|e| panic!("{e:?}"));
    assert!(text(&looped, Target::Wgsl, "tunable_copper.wgsl").contains("loop {"), "the sums are loops");
    let shipped = common::material_files().into_iter().map(|path| common::compile_file(&path));
    for compiled in shipped.chain([looped]) {
        let (library, info) = (&compiled.library, &compiled.library_info);
        for (handle, function) in library.functions.iter() {
            let name = function.name.as_deref().unwrap_or_default();
            let uses = &info[handle];
            for (expression, local) in &function.named_expressions {
                assert!(uses[*expression].ref_count > 0, "{name}: `{local}` is never read");
            }
            let mut results = Vec::new();
            calls(&function.body, &mut results);
            for result in results {
                assert!(uses[result].ref_count > 0, "{name}: a call's result is never used");
            }
        }
    }
}

/// The results of `block`'s calls, nested blocks included.
fn calls(block: &naga::Block, out: &mut Vec<naga::Handle<naga::Expression>>) {
    for statement in block.iter() {
        match statement {
            naga::Statement::Call { result: Some(result), .. } => out.push(*result),
            naga::Statement::If { accept, reject, .. } => {
                calls(accept, out);
                calls(reject, out);
            }
            naga::Statement::Loop { body, continuing, .. } => {
                calls(body, out);
                calls(continuing, out);
            }
            naga::Statement::Block(inner) => calls(inner, out),
            _ => {}
        }
    }
}
