//! The naga implementation of the shading ops: values are IR expressions.
//!
//! [`ModuleBuilder`] owns a `naga::Module` under construction and a stack of functions being
//! built (a term's function is built to completion the first time the term is called, while the
//! caller waits on the stack). [`Expr`], [`ExprVec`] and [`ExprBool`] implement
//! [`Real`](crate::math::Real)/[`Vector`](crate::math::Vector)/[`Logic`](crate::math::Logic): each operation appends an expression to the current function.
//!
//! Three duties that naga leaves to whoever builds IR by hand:
//!
//! * **Emit ranges.** Every expression that is not pre-emitted (literals, arguments, globals)
//!   must be covered by exactly one `Statement::Emit`; call results must not be. The builder
//!   keeps one open range and closes it before any statement or pre-emitted expression.
//! * **Constant folding.** naga does not fold. Values start as Rust constants and become IR only
//!   when they meet a runtime value, so literal arithmetic (`roughness²`, F0 from an IOR, whole
//!   slab integrals) is computed here, in f32, exactly as the CPU path computes it; a term whose
//!   arguments are all constants is evaluated, not called. Identities (x·1, x+0, 0·x) fold too;
//!   0·x → 0 is sound because every x in the formulas is finite by its guards.
//! * **Names.** Named `let`s come from the terms' source (see `shading_fn!`), so the generated
//!   code reads like the Rust it came from.
//!
//! Invariant: an expression handle is used only in the function that created it (checked in
//! debug builds via a function id carried by each value).

use std::cell::RefCell;
use std::collections::HashMap;

use naga::{
    AddressSpace, Binding, Block, Expression, Function, FunctionArgument, FunctionResult, GlobalVariable, Handle,
    Literal, MathFunction, MemoryDecorations, Module, ResourceBinding, Scalar as NagaScalar, Span, Statement,
    StructMember, Type, TypeInner, VectorSize,
};

use crate::math::Kind;

mod dead;
mod tables;
mod values;

pub use tables::{MAX_UNIFORM_BYTES, TABLES_BUFFER_NAME, table_bytes};
pub use values::{Expr, ExprBool, ExprVec};

/// Types the builder uses everywhere.
#[derive(Clone, Copy, Debug)]
pub struct CommonTypes {
    pub f32: Handle<Type>,
    pub u32: Handle<Type>,
    pub bool: Handle<Type>,
    pub vec2: Handle<Type>,
    pub vec3: Handle<Type>,
    pub vec4: Handle<Type>,
    pub uvec3: Handle<Type>,
}

struct FnState {
    function: Function,
    block: Block,
    emit_start: Option<usize>,
    id: u32,
    /// Results of the term calls made so far, by term and arguments: terms are pure and the
    /// functions straight-line, so a repeated call (the same table lookup for the three
    /// channels of a grey absorption, say) reuses the first result instead of calling again.
    calls: HashMap<CallKey, Handle<Expression>>,
}

/// A term call's identity: the term's name and each argument (a constant's bits or an
/// expression handle).
type CallKey = (&'static str, Vec<ArgKey>);

#[derive(Clone, PartialEq, Eq, Hash)]
enum ArgKey {
    Const([u32; 3]),
    Dyn(Handle<Expression>),
}

struct State {
    module: Module,
    stack: Vec<FnState>,
    terms: HashMap<&'static str, Handle<Function>>,
    /// Table lookups specialised for literal arguments, by term and the literal (or `None`) in
    /// each argument position.
    specialised: HashMap<(&'static str, Vec<Option<u32>>), Handle<Function>>,
    next_id: u32,
    const_names: Vec<String>,
    /// Named module constants already created, by (name, value bits).
    constants: HashMap<(String, [u32; 3], bool), Handle<naga::Constant>>,
    /// The table buffer, once used.
    tables_buffer: Option<Handle<naga::GlobalVariable>>,
    /// Every table block a lookup reads, with the function and the expression of its offset
    /// literal, which [`ModuleBuilder::finish_tables`] sets once the buffer is laid out.
    table_fetches: Vec<TableFetch>,
}

/// One lookup's read of the table buffer (see `tables.rs`).
#[derive(Clone)]
struct TableFetch {
    /// The function's name (unique in a module under construction).
    function: String,
    /// The `Add` of the lookup's runtime position and the offset literal.
    add: Handle<Expression>,
    offset: Handle<Expression>,
    block: TableBlock,
    /// The stride literals of the axes whose windows `block` repeats, with the table's own
    /// stride there, and the length of the window from the lowest corner to the highest in the
    /// table: what the fetch reads instead when the buffer would grow too large.
    repeated: Vec<(Handle<Expression>, u32)>,
    contiguous: u32,
}

/// What a lookup reads of a table: `window` entries from each of `starts`, laid out one after
/// another in the buffer (one start: a window the buffer may share with other lookups).
#[derive(Clone, PartialEq, Eq)]
struct TableBlock {
    /// The table's place in the catalogue's buffer (its identity).
    table: u32,
    codes: &'static [u16],
    starts: Vec<u32>,
    window: u32,
}

/// Index into the builder's table of constant names.
#[derive(Clone, Copy, Debug)]
pub(super) struct ConstName(pub(super) u32);

/// Builds one `naga::Module`; see the module docs.
pub struct ModuleBuilder {
    state: RefCell<State>,
    pub types: CommonTypes,
    /// Whether a table lookup with one runtime argument becomes a curve in the code
    /// (`math::tables::Curve`): for a material without runtime parameters, whose CPU evaluation
    /// sums the same curves (`math::tables::with_curves`).
    pub curves: std::cell::Cell<bool>,
}

fn insert_type(module: &mut Module, name: Option<&str>, inner: TypeInner) -> Handle<Type> {
    module.types.insert(Type { name: name.map(str::to_string), inner }, Span::UNDEFINED)
}

impl Default for ModuleBuilder {
    fn default() -> Self {
        Self::new()
    }
}

impl ModuleBuilder {
    pub fn new() -> Self {
        let mut module = Module::default();
        let vector = |size, scalar| TypeInner::Vector { size, scalar };
        let types = CommonTypes {
            f32: insert_type(&mut module, None, TypeInner::Scalar(NagaScalar::F32)),
            u32: insert_type(&mut module, None, TypeInner::Scalar(NagaScalar::U32)),
            bool: insert_type(&mut module, None, TypeInner::Scalar(NagaScalar::BOOL)),
            vec2: insert_type(&mut module, None, vector(VectorSize::Bi, NagaScalar::F32)),
            vec3: insert_type(&mut module, None, vector(VectorSize::Tri, NagaScalar::F32)),
            vec4: insert_type(&mut module, None, vector(VectorSize::Quad, NagaScalar::F32)),
            uvec3: insert_type(&mut module, None, vector(VectorSize::Tri, NagaScalar::U32)),
        };
        ModuleBuilder {
            state: RefCell::new(State {
                module,
                stack: Vec::new(),
                terms: HashMap::new(),
                specialised: HashMap::new(),
                next_id: 0,
                const_names: Vec::new(),
                constants: HashMap::new(),
                tables_buffer: None,
                table_fetches: Vec::new(),
            }),
            types,
            curves: std::cell::Cell::new(false),
        }
    }

    /// Runs `f` with mutable access to the module (types, globals, entry points).
    pub fn with_module<R>(&self, f: impl FnOnce(&mut Module) -> R) -> R {
        f(&mut self.state.borrow_mut().module)
    }

    pub fn finish(self) -> Module {
        self.state.into_inner().module
    }

    /// A copy of the module as built so far.
    pub fn snapshot(&self) -> Module {
        self.state.borrow().module.clone()
    }

    /// The table buffer, if a lookup reads it.
    pub fn tables_global(&self) -> Option<Handle<GlobalVariable>> {
        self.state.borrow().tables_buffer
    }

    pub fn kind_type(&self, kind: Kind) -> Handle<Type> {
        match kind {
            Kind::Scalar => self.types.f32,
            Kind::Vec3 => self.types.vec3,
        }
    }

    // ----- functions -------------------------------------------------------------------------

    /// Starts a new function; expressions now go into it until [`Self::end_function`].
    pub fn begin_function(&self, name: &str, arguments: Vec<FunctionArgument>, result: Option<FunctionResult>) {
        let mut state = self.state.borrow_mut();
        let id = state.next_id;
        state.next_id += 1;
        let function = Function { name: Some(name.to_string()), arguments, result, ..Function::default() };
        state.stack.push(FnState { function, block: Block::new(), emit_start: None, id, calls: HashMap::new() });
    }

    /// Finishes the current function (closing its last emit range, without its dead code:
    /// [`dead`]) and returns it.
    pub fn end_function(&self) -> Function {
        let mut state = self.state.borrow_mut();
        let Some(mut f) = state.stack.pop() else {
            unreachable!("end_function without begin_function");
        };
        close_emit(&mut f);
        f.function.body = f.block;
        dead::remove_dead_code(&mut f.function);
        f.function
    }

    /// The `index`-th argument of the current function.
    pub fn argument(&self, index: u32) -> Handle<Expression> {
        self.append(Expression::FunctionArgument(index))
    }

    fn current_id(&self) -> u32 {
        self.state.borrow().stack.last().map_or(u32::MAX, |f| f.id)
    }

    /// Appends an expression to the current function, keeping emit ranges right.
    pub fn append(&self, expression: Expression) -> Handle<Expression> {
        let mut state = self.state.borrow_mut();
        let Some(f) = state.stack.last_mut() else {
            unreachable!("expression built outside of a function");
        };
        if expression.needs_pre_emit() {
            close_emit(f);
        } else if f.emit_start.is_none() {
            f.emit_start = Some(f.function.expressions.len());
        }
        f.function.expressions.append(expression, Span::UNDEFINED)
    }

    /// Appends a statement to the current function's body.
    pub fn statement(&self, statement: Statement) {
        let mut state = self.state.borrow_mut();
        let Some(f) = state.stack.last_mut() else {
            unreachable!("statement outside of a function");
        };
        close_emit(f);
        f.block.push(statement, Span::UNDEFINED);
    }

    /// `if (condition) { return; }` in the current function.
    pub fn return_if(&self, condition: Handle<Expression>) {
        let mut accept = Block::new();
        accept.push(Statement::Return { value: None }, Span::UNDEFINED);
        self.statement(Statement::If { condition, accept, reject: Block::new() });
    }

    /// Names an expression of the current function (`let name = …` in every backend).
    pub fn name(&self, handle: Handle<Expression>, name: &str) {
        let mut state = self.state.borrow_mut();
        let Some(f) = state.stack.last_mut() else { return };
        let expression = &f.function.expressions[handle];
        if expression.needs_pre_emit() || f.function.named_expressions.contains_key(&handle) {
            return;
        }
        f.function.named_expressions.insert(handle, name.to_string());
    }

    /// Calls `function` with `arguments`; returns the result expression.
    pub fn call(&self, function: Handle<Function>, arguments: Vec<Handle<Expression>>) -> Handle<Expression> {
        let mut state = self.state.borrow_mut();
        let Some(f) = state.stack.last_mut() else {
            unreachable!("call outside of a function");
        };
        // A call result is defined by its Call statement and must not be inside an Emit range.
        close_emit(f);
        let result = f.function.expressions.append(Expression::CallResult(function), Span::UNDEFINED);
        f.block.push(Statement::Call { function, arguments, result: Some(result) }, Span::UNDEFINED);
        result
    }

    /// A local variable of the current function (no initialiser), as its pointer expression.
    fn local(&self, name: &str, ty: Handle<Type>) -> Handle<Expression> {
        let variable = {
            let mut state = self.state.borrow_mut();
            let Some(f) = state.stack.last_mut() else {
                unreachable!("local variable outside of a function");
            };
            let variable = naga::LocalVariable { name: Some(name.to_string()), ty, init: None };
            f.function.local_variables.append(variable, Span::UNDEFINED)
        };
        self.append(Expression::LocalVariable(variable))
    }

    /// `pointer = value;` in the current block.
    fn store(&self, pointer: Handle<Expression>, value: Handle<Expression>) {
        self.statement(Statement::Store { pointer, value });
    }

    /// Builds a nested block: statements and expressions that `build` adds go into a new block,
    /// which is returned; term calls made inside are not reused after it (their results are
    /// not in scope there).
    fn block<R>(&self, build: impl FnOnce() -> R) -> (Block, R) {
        let (outer, calls) = {
            let mut state = self.state.borrow_mut();
            let Some(f) = state.stack.last_mut() else {
                unreachable!("block outside of a function");
            };
            close_emit(f);
            (std::mem::take(&mut f.block), f.calls.clone())
        };
        let result = build();
        let mut state = self.state.borrow_mut();
        let Some(f) = state.stack.last_mut() else {
            unreachable!("block outside of a function");
        };
        close_emit(f);
        f.calls = calls;
        (std::mem::replace(&mut f.block, outer), result)
    }

    /// Adds a finished function to the module.
    pub fn add_function(&self, function: Function, doc: &[&str]) -> Handle<Function> {
        let mut state = self.state.borrow_mut();
        let handle = state.module.functions.append(function, Span::UNDEFINED);
        if !doc.is_empty() {
            let docs = state.module.doc_comments.get_or_insert_with(Default::default);
            docs.functions.insert(handle, doc.iter().map(|l| l.trim().to_string()).collect());
        }
        handle
    }

    // ----- values ----------------------------------------------------------------------------

    fn literal(&self, x: f32) -> Handle<Expression> {
        self.append(Expression::Literal(Literal::F32(x)))
    }

    fn check_owner(&self, id: u32) {
        debug_assert_eq!(id, self.current_id(), "expression used outside the function that built it");
    }

    fn const_name(&self, name: &str) -> ConstName {
        let mut state = self.state.borrow_mut();
        state.const_names.push(name.to_string());
        ConstName(state.const_names.len() as u32 - 1)
    }

    /// A named module constant holding `value` (a scalar, or a vec3 when `vector`).
    fn named_constant(&self, name: ConstName, value: [f32; 3], vector: bool) -> Handle<Expression> {
        let constant = {
            let mut state = self.state.borrow_mut();
            let name = state.const_names[name.0 as usize].clone();
            let key = (name.clone(), value.map(f32::to_bits), vector);
            match state.constants.get(&key) {
                Some(&h) => h,
                None => {
                    let module = &mut state.module;
                    let literal = |m: &mut Module, x: f32| {
                        m.global_expressions.append(Expression::Literal(Literal::F32(x)), Span::UNDEFINED)
                    };
                    let (ty, init) = if vector {
                        let components = value.iter().map(|&x| literal(module, x)).collect();
                        let ty = self.types.vec3;
                        (ty, module.global_expressions.append(Expression::Compose { ty, components }, Span::UNDEFINED))
                    } else {
                        (self.types.f32, literal(module, value[0]))
                    };
                    let h = module.constants.append(naga::Constant { name: Some(name), ty, init }, Span::UNDEFINED);
                    state.constants.insert(key, h);
                    h
                }
            }
        };
        self.append(Expression::Constant(constant))
    }

    fn earlier_call(&self, key: &CallKey) -> Option<Handle<Expression>> {
        self.state.borrow().stack.last().and_then(|f| f.calls.get(key).copied())
    }

    fn remember_call(&self, key: CallKey, result: Handle<Expression>) {
        if let Some(f) = self.state.borrow_mut().stack.last_mut() {
            f.calls.insert(key, result);
        }
    }

    pub(crate) fn math(&self, fun: MathFunction, args: &[Handle<Expression>]) -> Handle<Expression> {
        self.append(Expression::Math {
            fun,
            arg: args[0],
            arg1: args.get(1).copied(),
            arg2: args.get(2).copied(),
            arg3: None,
        })
    }
}

fn close_emit(f: &mut FnState) {
    if let Some(start) = f.emit_start.take() {
        if f.function.expressions.len() > start {
            let range = f.function.expressions.range_from(start);
            f.block.push(Statement::Emit(range), Span::UNDEFINED);
        }
    }
}

/// A module-scope resource at `binding` (any group).
pub fn global_in(
    b: &ModuleBuilder,
    name: &str,
    space: AddressSpace,
    binding: ResourceBinding,
    ty: Handle<Type>,
) -> Handle<GlobalVariable> {
    b.with_module(|m| {
        m.global_variables.append(
            GlobalVariable {
                name: Some(name.to_string()),
                space,
                binding: Some(binding),
                ty,
                init: None,
                memory_decorations: MemoryDecorations::empty(),
            },
            Span::UNDEFINED,
        )
    })
}

pub fn argument(name: &str, ty: Handle<Type>, binding: Option<Binding>) -> FunctionArgument {
    FunctionArgument { name: Some(name.to_string()), ty, binding }
}

pub fn struct_type(
    b: &ModuleBuilder,
    name: &str,
    members: &[(&str, Handle<Type>, u32, Option<Binding>)],
    span: u32,
) -> Handle<Type> {
    let members = members
        .iter()
        .map(|(name, ty, offset, binding)| StructMember {
            name: Some((*name).to_string()),
            ty: *ty,
            binding: binding.clone(),
            offset: *offset,
        })
        .collect();
    b.with_module(|m| {
        m.types
            .insert(Type { name: Some(name.to_string()), inner: TypeInner::Struct { members, span } }, Span::UNDEFINED)
    })
}

pub fn runtime_array(b: &ModuleBuilder, base: Handle<Type>, stride: u32) -> Handle<Type> {
    b.with_module(|m| {
        m.types.insert(
            Type { name: None, inner: TypeInner::Array { base, size: naga::ArraySize::Dynamic, stride } },
            Span::UNDEFINED,
        )
    })
}
