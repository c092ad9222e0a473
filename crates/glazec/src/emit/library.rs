//! The library files and the harness files built on them (see the table in the parent module).

use naga::{Block, EntryPoint, Expression, Function, Module, ShaderStage, Span, Statement};

use super::items;
use super::polish::is_ident_char;
use crate::lower::bindings::Layout;

/// The names a library's own items start with: `<material>_` and `<Material>` (its structs).
fn own_prefixes(material: &str) -> [String; 2] {
    [format!("{material}_"), crate::model::camel_case(material)]
}

/// The names `text`'s items declare.
pub(super) fn declared_names(text: &str) -> Vec<&str> {
    items::items(text).iter().filter_map(|i| i.name).collect()
}

/// The items of `full` (the whole module's polished text) that `library` (the library's) does
/// not declare: the harness, to be read after the library.
pub(super) fn harness_items(full: &str, library: &str) -> String {
    let declared = declared_names(library);
    let mut out = String::new();
    for item in items::items(full) {
        if item.name.is_some_and(|n| declared.contains(&n)) {
            continue;
        }
        items::push(&mut out, &item);
    }
    trim_end(out)
}

/// The whole module with every library function's body replaced by a return of a zero value
/// (the harness's own items, written from it, are the same; the library's are written once, from
/// the library module). Library functions come first in the whole module's arena.
pub(super) fn harness_view(library: &Module, module: &Module) -> Module {
    let mut view = module.clone();
    for (_, f) in view.functions.iter_mut().take(library.functions.len()) {
        let result = f.result.as_ref().map(|r| r.ty);
        f.expressions = Default::default();
        f.local_variables = Default::default();
        f.named_expressions = Default::default();
        f.diagnostic_filter_leaf = None;
        let mut body = Block::new();
        let value = result.map(|ty| f.expressions.append(Expression::ZeroValue(ty), Span::UNDEFINED));
        body.push(Statement::Return { value }, Span::UNDEFINED);
        f.body = body;
    }
    view
}

/// A GLSL harness file: the entry point's shader as naga wrote it from the harness view, with the
/// library `#include`d in place of the library's items (glslang's and shaderc's
/// `GL_GOOGLE_include_directive`, as the HLSL harness includes its `.hlsli`). Its preamble
/// (`#version`, extensions, the compute shader's workgroup size) comes first, then the include,
/// then the harness's own items (polished by `polish`).
pub(super) fn glsl_entry(
    entry: &str,
    library_file: &str,
    declared: &[&str],
    polish: impl Fn(&str) -> String,
) -> String {
    let (mut preamble, mut own) = (String::new(), String::new());
    for line in entry.lines().take_while(|l| l.starts_with("#version")) {
        preamble.push_str(line);
        preamble.push('\n');
    }
    preamble.push_str("#extension GL_GOOGLE_include_directive : require\n");
    for item in items::items(entry) {
        let version = item.lines.iter().all(|l| l.starts_with("#version"));
        let is_preamble = item
            .lines
            .iter()
            .all(|l| l.starts_with('#') || l.starts_with("layout(local_size") || l.starts_with("precision "));
        if version {
            continue;
        } else if is_preamble && own.is_empty() {
            items::push(&mut preamble, &item);
        } else if !item.name.is_some_and(|n| declared.contains(&n)) {
            items::push(&mut own, &item);
        }
    }
    format!("{}\n#include \"{library_file}\"\n\n{}", trim_end(preamble), trim_end(polish(&own)))
}

/// A GLSL or HLSL library's text with naga's helpers guarded (see [`items::push_guarded`]).
pub(super) fn guarded(text: &str, material: &str) -> String {
    let own = own_prefixes(material);
    let own: Vec<&str> = own.iter().map(String::as_str).collect();
    let mut out = String::with_capacity(text.len() + text.len() / 8);
    for item in items::items(text) {
        items::push_guarded(&mut out, &item, &own);
    }
    trim_end(out)
}

fn trim_end(mut text: String) -> String {
    while text.ends_with("\n\n") {
        text.pop();
    }
    text
}

/// The GLSL 4.50 library, step 1: naga's GLSL backend writes a shader for one entry point, so
/// the library gets a fragment `main` that calls every function (with zero arguments) and reads
/// every uniform, which makes the backend write every function and resource.
pub(super) fn glsl_probe(library: &Module) -> Module {
    let mut module = library.clone();
    let mut main = Function { name: Some("main".to_string()), ..Function::default() };
    let mut body = Block::new();
    for (global, var) in library.global_variables.iter() {
        if var.space == naga::AddressSpace::Uniform {
            let pointer = main.expressions.append(Expression::GlobalVariable(global), Span::UNDEFINED);
            let value = main.expressions.append(Expression::Load { pointer }, Span::UNDEFINED);
            body.push(Statement::Emit(main.expressions.range_from(value.index())), Span::UNDEFINED);
        }
    }
    for (function, f) in library.functions.iter() {
        let arguments =
            f.arguments.iter().map(|a| main.expressions.append(Expression::ZeroValue(a.ty), Span::UNDEFINED)).collect();
        let result =
            f.result.as_ref().map(|_| main.expressions.append(Expression::CallResult(function), Span::UNDEFINED));
        body.push(Statement::Call { function, arguments, result }, Span::UNDEFINED);
    }
    main.body = body;
    module.entry_points.push(EntryPoint {
        name: "main".to_string(),
        stage: ShaderStage::Fragment,
        early_depth_test: None,
        workgroup_size: [0, 0, 0],
        workgroup_size_overrides: None,
        function: main,
        mesh_info: None,
        task_payload: None,
        incoming_ray_payload: None,
    });
    module
}

/// The GLSL 4.50 library, step 2, from the probe's polished text: the `#version` line and the
/// `main` are dropped, and the resources, which naga names after their binding
/// (`_group_0_binding_3_fs`), get the library's names back (their blocks are `<name>_block`).
pub(super) fn glsl_library(material: &str, library: &Module, polished: String) -> String {
    let mut renamed = polished;
    for (_, var) in library.global_variables.iter() {
        let (Some(rb), Some(name)) = (var.binding, var.name.as_deref()) else { continue };
        let naga_name = format!("_group_{}_binding_{}_fs", rb.group, rb.binding);
        renamed = replace_word(&renamed, &naga_name, name);
    }
    let mut blocks = String::with_capacity(renamed.len());
    for line in renamed.lines() {
        match rename_block(line) {
            Some(line) => blocks.push_str(&line),
            None => blocks.push_str(line),
        }
        blocks.push('\n');
    }
    let renamed = blocks;
    let own = own_prefixes(material);
    let own: Vec<&str> = own.iter().map(String::as_str).collect();
    let mut out = String::with_capacity(renamed.len() + renamed.len() / 8);
    for item in items::items(&renamed) {
        if item.name == Some("main") || item.lines.iter().all(|l| l.starts_with("#version")) {
            continue;
        }
        items::push_guarded(&mut out, &item, &own);
    }
    trim_end(out)
}

/// A uniform block line `layout(…) uniform <T>_block_<n><Stage> { <type> <name>…; };` with the
/// block named `<name>_block`; `None` for any other line.
fn rename_block(line: &str) -> Option<String> {
    let at = line.find(" uniform ")?;
    let rest = &line[at + " uniform ".len()..];
    let brace = rest.find(" { ")?;
    let block = &rest[..brace];
    if !block.contains("_block_") {
        return None;
    }
    let member = rest[brace + 3..].split_whitespace().nth(1).unwrap_or_default();
    let member: String = member.chars().take_while(|c| c.is_ascii_alphanumeric() || *c == '_').collect();
    Some(line.replacen(block, &format!("{member}_block"), 1))
}

/// `text` with every whole-word `from` replaced by `to`.
fn replace_word(text: &str, from: &str, to: &str) -> String {
    let mut out = String::with_capacity(text.len());
    let mut copied = 0;
    for (at, _) in text.match_indices(from) {
        let before = text[..at].chars().next_back();
        let after = text[at + from.len()..].chars().next();
        if before.is_some_and(is_ident_char) || after.is_some_and(is_ident_char) {
            continue;
        }
        out.push_str(&text[copied..at]);
        out.push_str(to);
        copied = at + from.len();
    }
    out.push_str(&text[copied..]);
    out
}

/// The naga_oil flavour of the WGSL library (Bevy ≤ 0.19, wgsl_bindgen): `#define_import_path
/// glazec::<material>` first, and the bind group of the material's own resources (parameters,
/// tables, textures) replaced by the shader-def placeholder `#{MATERIAL_BIND_GROUP}`, which the
/// host defines (Bevy: 2, or 3 from Bevy 0.17). The environment keeps its group: engines light
/// by their own environment maps.
pub(super) fn naga_oil(material: &str, wgsl_library: &str, layout: &Layout) -> String {
    let mut own: Vec<String> = layout.textures.iter().map(|(n, _)| n.clone()).collect();
    if layout.params.is_some() {
        own.push(format!("{material}_params"));
    }
    if layout.tables.is_some() {
        own.push(format!("{material}_tables"));
    }
    let mut out = format!("#define_import_path glazec::{material}\n\n");
    let lines: Vec<&str> = wgsl_library.lines().collect();
    for (i, line) in lines.iter().enumerate() {
        let declares_own = lines.get(i + 1).is_some_and(|next| {
            next.starts_with("var") && items_name(next).is_some_and(|n| own.iter().any(|o| o == n))
        });
        if declares_own && line.starts_with("@group(") {
            let close = line.find(')').unwrap_or(0);
            out.push_str("@group(#{MATERIAL_BIND_GROUP})");
            out.push_str(&line[close + 1..]);
        } else {
            out.push_str(line);
        }
        out.push('\n');
    }
    out
}

fn items_name(line: &str) -> Option<&str> {
    items::items(line).first().and_then(|i| i.name)
}
