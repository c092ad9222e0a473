//! Making a lowered material a library a host can import: its module-scope names prefixed with
//! the material's name, and its resources moved to the bindings the host chose.

use std::collections::BTreeMap;

use naga::{Function, GlobalVariable, Handle, Module};

use super::layout::bindings::{self, Choice, Clash, ENVIRONMENT_GROUP, Layout, Slot, TEXTURES_GROUP};

/// Prefixes every function (except `public`, already named `<material>_…`), constant and global
/// of `module` with `<material>_`; a leading `glazec_` is dropped first (`glazec_table_code` →
/// `<material>_table_code`). Struct types keep their names: they are `<Material>Params` and
/// `<Material>Textures` already. Local names are the functions' own and stay as they are.
pub(super) fn prefix(module: &mut Module, material: &str, public: &[Option<Handle<Function>>]) {
    let rename = |name: &mut Option<String>| {
        if let Some(name) = name {
            let base = name.strip_prefix("glazec_").unwrap_or(name);
            *name = format!("{material}_{base}");
        }
    };
    for (handle, function) in module.functions.iter_mut() {
        if !public.contains(&Some(handle)) {
            rename(&mut function.name);
        }
    }
    for (_, constant) in module.constants.iter_mut() {
        rename(&mut constant.name);
    }
    for (_, global) in module.global_variables.iter_mut() {
        rename(&mut global.name);
    }
}

/// Moves the library's resources (every global of `module` so far) to where `choice` puts them
/// and returns where they are. Resources are recognised by the default place `lower` built them
/// at: the parameters and the tables by handle, the textures and the environment by group.
///
/// # Errors
/// Two resources would share a slot.
pub(super) fn place(
    module: &mut Module,
    choice: &Choice,
    params: Option<Handle<GlobalVariable>>,
    tables: Option<Handle<GlobalVariable>>,
) -> Result<Layout, Clash> {
    let mut layout = Layout::default();
    let mut taken: BTreeMap<Slot, String> = BTreeMap::new();
    for (handle, global) in module.global_variables.iter_mut() {
        let Some(binding) = global.binding.as_mut() else { continue };
        let name = global.name.clone().unwrap_or_default();
        let slot = if Some(handle) == params {
            let slot = choice.params();
            layout.params = Some(slot);
            slot
        } else if Some(handle) == tables {
            let slot = choice.tables(params.is_some());
            layout.tables = Some(slot);
            slot
        } else if binding.group == TEXTURES_GROUP {
            let slot = choice.textures().after(binding.binding);
            layout.textures.push((name.clone(), slot));
            slot
        } else if binding.group == ENVIRONMENT_GROUP {
            let slot = choice.environment().after(binding.binding);
            layout.environment.push((name.clone(), slot));
            slot
        } else {
            unreachable!("`lower` creates no other library resource")
        };
        if let Some(first) = taken.insert(slot, name.clone()) {
            return Err(Clash { first, second: name, slot });
        }
        *binding = naga::ResourceBinding { group: slot.group, binding: slot.binding };
    }
    layout.textures.sort_by_key(|(_, s)| *s);
    layout.environment.sort_by_key(|(_, s)| *s);
    Ok(layout)
}

/// Binds the harness's resources (the globals after the first `library` ones: `pairs`,
/// `values`, `dispatch`, `light`) in group 0, each at the lowest binding still free there.
pub(super) fn place_harness(module: &mut Module, library: usize, layout: &mut Layout) {
    let group = bindings::GROUP;
    let mut taken: Vec<u32> = module
        .global_variables
        .iter()
        .take(library)
        .filter_map(|(_, g)| g.binding)
        .filter(|b| b.group == group)
        .map(|b| b.binding)
        .collect();
    for (_, global) in module.global_variables.iter_mut().skip(library) {
        let Some(binding) = global.binding.as_mut() else { continue };
        let free = (0..).find(|b| !taken.contains(b)).unwrap_or_default();
        taken.push(free);
        *binding = naga::ResourceBinding { group, binding: free };
        match global.name.as_deref() {
            Some("pairs") => layout.pairs = free,
            Some("values") => layout.values = free,
            Some("dispatch") => layout.dispatch = free,
            Some("light") => layout.light = Some(free),
            other => unreachable!("the harness creates no resource {other:?}"),
        }
    }
}
