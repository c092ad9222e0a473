//! Stage 4, `validate`: naga's validator with every check on.
//!
//! **Input:** the `naga::Module` from `lower`. **Output:** the `ModuleInfo` that the backends
//! need (which expressions to bake, which globals each entry point uses).
//!
//! **Invariant:** every module `lower` builds passes; the tests check it on every shipped
//! material and on random stacks. A validation failure here is a bug in glazec, never a problem with the user's material:
//! `check` has already rejected every bad input, and `lower` only builds well-typed IR. It is
//! reported as an internal error carrying naga's full message. External validators
//! (`glslangValidator`, `spirv-val`) run over the emitted files in the test suite.

use naga::valid::{Capabilities, ModuleInfo, ValidationFlags, Validator};

/// naga rejected a module that `lower` built.
#[derive(Debug, thiserror::Error)]
#[error("internal error: naga rejected the generated module for `{material}`: {message}")]
pub struct ValidateError {
    pub material: String,
    pub message: String,
}

/// Validates `module` with all validation flags and the default capabilities.
///
/// # Errors
/// naga's validation error, rendered, if the module is invalid.
pub fn validate(material: &str, module: &naga::Module) -> Result<ModuleInfo, ValidateError> {
    run(material, module, ValidationFlags::all())
}

/// The `ModuleInfo` of `module` with none of the validator's optional checks: for a module made
/// from an already validated one by adding only calls of its functions with zero values (the
/// GLSL library's probe), whose arithmetic has passed every check. naga's analysis, which the
/// backends read, runs all the same.
///
/// # Errors
/// naga's validation error, rendered, if the module is invalid.
pub fn analyse(material: &str, module: &naga::Module) -> Result<ModuleInfo, ValidateError> {
    run(material, module, ValidationFlags::empty())
}

fn run(material: &str, module: &naga::Module, flags: ValidationFlags) -> Result<ModuleInfo, ValidateError> {
    Validator::new(flags, Capabilities::default())
        .validate(module)
        .map_err(|e| ValidateError { material: material.to_string(), message: e.emit_to_string("") })
}
