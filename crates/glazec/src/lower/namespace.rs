//! Making a lowered material a library a host can import: its module-scope names prefixed with
//! the material's name, and its resources moved to the bindings the host chose.

use std::collections::BTreeMap;

use naga::{Function, GlobalVariable, Handle, Module};

use super::layout::bindings::{self, Choice, Clash, ENVIRONMENT_GROUP, Layout, Slot, TEXTURES_GROUP};

/// Where the items that [`prefix`] renames start in a module's arenas: everything from
/// `Start::default()`, or only what was added after [`Start::of`] a module.
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct Start {
    functions: usize,
    constants: usize,
    globals: usize,
}

impl Start {
    /// The items `module` does not hold yet.
    pub(super) fn of(module: &Module) -> Start {
        Start {
            functions: module.functions.len(),
            constants: module.constants.len(),
            globals: module.global_variables.len(),
        }
    }
}

/// Prefixes every function (except `public`, already named `<material>_…`), constant and global
/// of `module` from `start` on with `<material>_`; a leading `glazec_` is dropped first
/// (`glazec_table_code` → `<material>_table_code`). Struct types keep their names: they are
/// `<Material>Params` and `<Material>Textures` already. Local names are the functions' own and
/// stay as they are.
pub(super) fn prefix(module: &mut Module, material: &str, public: &[Option<Handle<Function>>], start: Start) {
    let rename = |name: &mut Option<String>| {
        if let Some(name) = name {
            let base = name.strip_prefix("glazec_").unwrap_or(name);
            *name = format!("{material}_{base}");
        }
    };
    for (handle, function) in module.functions.iter_mut().skip(start.functions) {
        if !public.contains(&Some(handle)) {
            rename(&mut function.name);
        }
    }
    for (_, constant) in module.constants.iter_mut().skip(start.constants) {
        rename(&mut constant.name);
    }
    for (_, global) in module.global_variables.iter_mut().skip(start.globals) {
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

/// Binds the harness's resources (the globals after the first `library` ones): `pairs`,
/// `values`, `dispatch` and `light` in group 0, each at the lowest binding still free there; and
/// glazec's environment, where the library has not got it, at its default place (group 2 from
/// binding 0, where glazec's runner binds it), or in the first group the library leaves empty
/// if the host put other resources in group 2.
pub(super) fn place_harness(module: &mut Module, library: usize, layout: &mut Layout) {
    let group = bindings::GROUP;
    let library_bindings: Vec<naga::ResourceBinding> =
        module.global_variables.iter().take(library).filter_map(|(_, g)| g.binding).collect();
    let mut taken: Vec<u32> = library_bindings.iter().filter(|b| b.group == group).map(|b| b.binding).collect();
    let environment_group =
        (ENVIRONMENT_GROUP..).find(|&g| library_bindings.iter().all(|b| b.group != g)).unwrap_or(ENVIRONMENT_GROUP);
    for (_, global) in module.global_variables.iter_mut().skip(library) {
        let Some(binding) = global.binding.as_mut() else { continue };
        if binding.group == ENVIRONMENT_GROUP {
            binding.group = environment_group;
            let slot = Slot::new(binding.group, binding.binding);
            layout.environment.push((global.name.clone().unwrap_or_default(), slot));
            continue;
        }
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
    layout.environment.sort_by_key(|(_, s)| *s);
}
