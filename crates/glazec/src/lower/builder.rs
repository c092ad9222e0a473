//! The naga implementation of the shading ops: values are IR expressions.
//!
//! [`ModuleBuilder`] owns a `naga::Module` under construction and a stack of functions being
//! built (a term's function is built to completion the first time the term is called, while the
//! caller waits on the stack). [`Expr`], [`ExprVec`] and [`ExprBool`] implement
//! [`Real`]/[`Vector`]/[`Logic`]: each operation appends an expression to the current function.
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
use std::ops::{Add, BitAnd, BitOr, Div, Mul, Neg, Not, Sub};

use naga::{
    BinaryOperator, Block, Expression, Function, FunctionArgument, FunctionResult, Handle, Literal, MathFunction,
    Module, Scalar as NagaScalar, Span, Statement, Type, TypeInner, UnaryOperator, VectorSize,
};

use crate::math::tables::TableId;
use crate::math::{Kind, Logic, Named, Real, Slot, Sum, TermDef, Vector};

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
    next_id: u32,
    const_names: Vec<String>,
    /// Named module constants already created, by (name, value bits).
    constants: HashMap<(String, [u32; 3], bool), Handle<naga::Constant>>,
    /// The table buffer, once used.
    tables_buffer: Option<Handle<naga::GlobalVariable>>,
}

/// The name of the table buffer in generated code.
pub const TABLES_BUFFER_NAME: &str = "glazec_tables";

/// The function that reads an entry of the table buffer.
const TABLE_CODE_FUNCTION: &str = "glazec_table_code";

/// Builds one `naga::Module`; see the module docs.
pub struct ModuleBuilder {
    state: RefCell<State>,
    pub types: CommonTypes,
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
                next_id: 0,
                const_names: Vec::new(),
                constants: HashMap::new(),
                tables_buffer: None,
            }),
            types,
        }
    }

    /// Runs `f` with mutable access to the module (types, globals, entry points).
    pub fn with_module<R>(&self, f: impl FnOnce(&mut Module) -> R) -> R {
        f(&mut self.state.borrow_mut().module)
    }

    pub fn finish(self) -> Module {
        self.state.into_inner().module
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

    /// Finishes the current function (closing its last emit range) and returns it.
    pub fn end_function(&self) -> Function {
        let mut state = self.state.borrow_mut();
        let Some(mut f) = state.stack.pop() else {
            unreachable!("end_function without begin_function");
        };
        close_emit(&mut f);
        f.function.body = f.block;
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

    /// The loop of [`Real::sum_over`] in the current function:
    ///
    /// ```text
    /// var index: u32 = 0u;  var total: vec3<f32> = vec3(0.0);  …
    /// loop {
    ///     <body at f32(index)>;  total = total + <term>;  …
    ///     continuing { index = index + 1u;  break if index >= count; }
    /// }
    /// ```
    fn sum_loop<'a>(&'a self, sum: &Sum, body: &dyn Fn(Expr<'a>) -> Vec<ExprVec<'a>>) -> Vec<ExprVec<'a>> {
        let u32_literal = |x| self.append(Expression::Literal(Literal::U32(x)));
        let index = self.local(sum.index, self.types.u32);
        self.store(index, u32_literal(0));
        let totals: Vec<_> = sum.totals.iter().map(|name| self.local(name, self.types.vec3)).collect();
        for &total in &totals {
            let zero = self.vector_handle(VVal::Const([0.0; 3]), None);
            self.store(total, zero);
        }
        let (body_block, ()) = self.block(|| {
            let counter = self.append(Expression::Load { pointer: index });
            let node = self.append(Expression::As { expr: counter, kind: naga::ScalarKind::Float, convert: Some(4) });
            let terms = body(self.scalar(node));
            debug_assert_eq!(terms.len(), totals.len(), "sum_over: one term per total");
            for (&total, term) in totals.iter().zip(terms) {
                let term = term.handle();
                let before = self.append(Expression::Load { pointer: total });
                let after = self.append(Expression::Binary { op: BinaryOperator::Add, left: before, right: term });
                self.store(total, after);
            }
        });
        let (continuing, done) = self.block(|| {
            let counter = self.append(Expression::Load { pointer: index });
            let next =
                self.append(Expression::Binary { op: BinaryOperator::Add, left: counter, right: u32_literal(1) });
            self.store(index, next);
            let count = u32_literal(sum.count);
            // (`block` closes the emit range inside `continuing`, where the condition must be.)
            self.append(Expression::Binary { op: BinaryOperator::GreaterEqual, left: next, right: count })
        });
        self.statement(Statement::Loop { body: body_block, continuing, break_if: Some(done) });
        totals.into_iter().map(|pointer| self.vector(self.append(Expression::Load { pointer }))).collect()
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

    pub fn scalar(&self, handle: Handle<Expression>) -> Expr<'_> {
        Expr { b: self, v: Val::Dyn(handle, self.current_id()), name: None }
    }

    pub fn vector(&self, handle: Handle<Expression>) -> ExprVec<'_> {
        ExprVec { b: self, v: VVal::Dyn(handle, self.current_id()), name: None }
    }

    pub fn constant(&self, x: f32) -> Expr<'_> {
        Expr { b: self, v: Val::Const(x), name: None }
    }

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

    /// The table buffer `glazec_tables: array<vec4<u32>, N>` (a uniform buffer; created on
    /// first use; its binding is assigned by `lower` once the module is complete), as a pointer
    /// expression. Entries are 16-bit codes, two to a word (`crate::math::tables::buffer`):
    /// entry i is the low (i even) or high half of component (i / 2) % 4 of element i / 8.
    ///
    /// Tables are read from a buffer rather than from constant arrays: naga's SPIR-V writer
    /// spills a dynamically indexed array *value* into a local variable at every access and
    /// lavapipe's compiler lowers that to a chain of selects. Even 16-entry curves folded from
    /// the tables made a two-coat shader take 3 s to compile (0.2 s from a buffer), and an
    /// 8,192-entry table took minutes. A uniform rather than a storage buffer: an eight-coat
    /// shader with runtime parameters compiled in 2.3 s instead of 6.0 s (all tables fit the
    /// 64 KiB that WebGPU guarantees for a uniform binding).
    fn tables_buffer(&self) -> Handle<Expression> {
        let global = {
            let mut state = self.state.borrow_mut();
            match state.tables_buffer {
                Some(h) => h,
                None => {
                    let module = &mut state.module;
                    // A fixed size, so that a device's bounds checks clamp to a constant
                    // instead of reading the buffer's length at every access.
                    let entries = std::num::NonZeroU32::new(crate::math::tables::buffer_vec4s() as u32)
                        .unwrap_or_else(|| unreachable!("the tables are not empty"));
                    let size = naga::ArraySize::Constant(entries);
                    let words = TypeInner::Vector { size: VectorSize::Quad, scalar: NagaScalar::U32 };
                    let words = insert_type(module, None, words);
                    let ty = insert_type(module, None, TypeInner::Array { base: words, size, stride: 16 });
                    let global = naga::GlobalVariable {
                        name: Some(TABLES_BUFFER_NAME.to_string()),
                        space: naga::AddressSpace::Uniform,
                        binding: Some(naga::ResourceBinding { group: 0, binding: u32::MAX }),
                        ty,
                        init: None,
                        memory_decorations: Default::default(),
                    };
                    let h = module.global_variables.append(global, Span::UNDEFINED);
                    state.tables_buffer = Some(h);
                    h
                }
            }
        };
        self.append(Expression::GlobalVariable(global))
    }

    /// `glazec_table_code(entry: u32) -> f32`: the 16-bit code of an entry of the table buffer
    /// (see [`Self::tables_buffer`]), created once per module.
    fn table_code_function(&self) -> Handle<Function> {
        if let Some(&f) = self.state.borrow().terms.get(TABLE_CODE_FUNCTION) {
            return f;
        }
        let argument = FunctionArgument { name: Some("entry".to_string()), ty: self.types.u32, binding: None };
        let result = FunctionResult { ty: self.types.f32, binding: None };
        self.begin_function(TABLE_CODE_FUNCTION, vec![argument], Some(result));
        let entry = self.argument(0);
        let literal = |x| self.append(Expression::Literal(Literal::U32(x)));
        let binary = |op, left, right| self.append(Expression::Binary { op, left, right });
        // Word entry / 2 holds entries entry (low half, entry even) and entry + 1; four words
        // make an element of the buffer.
        let word = binary(BinaryOperator::ShiftRight, entry, literal(1));
        self.name(word, "word");
        let base = self.tables_buffer();
        let pointer =
            self.append(Expression::Access { base, index: binary(BinaryOperator::ShiftRight, word, literal(2)) });
        let pointer =
            self.append(Expression::Access { base: pointer, index: binary(BinaryOperator::And, word, literal(3)) });
        let bits = self.append(Expression::Load { pointer });
        self.name(bits, "codes");
        let shift = binary(BinaryOperator::ShiftLeft, binary(BinaryOperator::And, entry, literal(1)), literal(4));
        let code = binary(BinaryOperator::And, binary(BinaryOperator::ShiftRight, bits, shift), literal(0xffff));
        let value = self.append(Expression::As { expr: code, kind: naga::ScalarKind::Float, convert: Some(4) });
        self.statement(Statement::Return { value: Some(value) });
        let function = self.end_function();
        let doc = [
            "The 16-bit code of entry `entry` of the table buffer: two codes to a 32-bit word, the even",
            "entry in the low half (`glazec tables`; each lookup scales the code to its table's range).",
        ];
        let handle = self.add_function(function, &doc);
        self.state.borrow_mut().terms.insert(TABLE_CODE_FUNCTION, handle);
        handle
    }

    fn scalar_handle(&self, v: Val, name: Option<ConstName>) -> Handle<Expression> {
        match v {
            Val::Const(x) => match name {
                Some(name) => self.named_constant(name, [x, 0.0, 0.0], false),
                None => self.literal(x),
            },
            Val::Dyn(h, id) => {
                self.check_owner(id);
                h
            }
        }
    }

    fn vector_handle(&self, v: VVal, name: Option<ConstName>) -> Handle<Expression> {
        if let (VVal::Const(c), Some(name)) = (v, name) {
            return self.named_constant(name, c, true);
        }
        match v {
            VVal::Const([x, y, z]) if x.to_bits() == y.to_bits() && y.to_bits() == z.to_bits() => {
                let value = self.literal(x);
                self.append(Expression::Splat { size: VectorSize::Tri, value })
            }
            VVal::Const(c) => {
                let components = c.iter().map(|&x| self.literal(x)).collect();
                self.append(Expression::Compose { ty: self.types.vec3, components })
            }
            VVal::Dyn(h, id) => {
                self.check_owner(id);
                h
            }
        }
    }

    fn bool_handle(&self, v: BVal) -> Handle<Expression> {
        match v {
            BVal::Const(b) => self.append(Expression::Literal(Literal::Bool(b))),
            BVal::Dyn(h, id) => {
                self.check_owner(id);
                h
            }
        }
    }

    fn slot_handle(&self, slot: Slot<Expr<'_>>) -> Handle<Expression> {
        match slot {
            Slot::S(x) => self.scalar_handle(x.v, x.name),
            Slot::V(v) => self.vector_handle(v.v, v.name),
        }
    }

    fn arg_key(&self, slot: Slot<Expr<'_>>) -> ArgKey {
        match slot {
            Slot::S(x) => match x.v {
                Val::Const(c) => ArgKey::Const([c.to_bits(), 0, 0]),
                Val::Dyn(..) => ArgKey::Dyn(self.scalar_handle(x.v, x.name)),
            },
            Slot::V(v) => match v.v {
                VVal::Const(c) => ArgKey::Const(c.map(f32::to_bits)),
                VVal::Dyn(..) => ArgKey::Dyn(self.vector_handle(v.v, v.name)),
            },
        }
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

    /// The function that implements `def`, building it on first use.
    fn term_function<'a>(
        &'a self,
        def: &'static TermDef,
        body: &dyn Fn(&[Slot<Expr<'a>>]) -> Slot<Expr<'a>>,
    ) -> Handle<Function> {
        if let Some(&f) = self.state.borrow().terms.get(def.name) {
            return f;
        }
        let arguments = def
            .params
            .iter()
            .map(|&(name, kind)| FunctionArgument {
                name: Some(name.to_string()),
                ty: self.kind_type(kind),
                binding: None,
            })
            .collect();
        let result = FunctionResult { ty: self.kind_type(def.ret), binding: None };
        self.begin_function(def.name, arguments, Some(result));
        let slots: Vec<Slot<Expr<'a>>> = def
            .params
            .iter()
            .enumerate()
            .map(|(i, &(_, kind))| {
                let h = self.argument(i as u32);
                match kind {
                    Kind::Scalar => Slot::S(self.scalar(h)),
                    Kind::Vec3 => Slot::V(self.vector(h)),
                }
            })
            .collect();
        let out = body(&slots);
        let value = self.slot_handle(out);
        self.statement(Statement::Return { value: Some(value) });
        let function = self.end_function();
        let handle = self.add_function(function, def.doc);
        self.state.borrow_mut().terms.insert(def.name, handle);
        handle
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

// ----- value types -------------------------------------------------------------------------------

#[derive(Clone, Copy, Debug)]
enum Val {
    Const(f32),
    Dyn(Handle<Expression>, u32),
}

#[derive(Clone, Copy, Debug)]
enum VVal {
    Const([f32; 3]),
    Dyn(Handle<Expression>, u32),
}

#[derive(Clone, Copy, Debug)]
enum BVal {
    Const(bool),
    Dyn(Handle<Expression>, u32),
}

/// An `f32` value: a constant not yet in the IR, or an IR expression.
#[derive(Clone, Copy)]
pub struct Expr<'a> {
    b: &'a ModuleBuilder,
    v: Val,
    /// A constant given a name with `named` becomes a named module constant (instead of a bare
    /// literal) where it meets runtime values; folding is unaffected.
    name: Option<ConstName>,
}

/// A `vec3<f32>` value.
#[derive(Clone, Copy)]
pub struct ExprVec<'a> {
    b: &'a ModuleBuilder,
    v: VVal,
    name: Option<ConstName>,
}

/// Index into the builder's table of constant names.
#[derive(Clone, Copy, Debug)]
struct ConstName(u32);

/// A `bool` value.
#[derive(Clone, Copy)]
pub struct ExprBool<'a> {
    b: &'a ModuleBuilder,
    v: BVal,
}

impl<'a> Expr<'a> {
    /// The IR handle of this value (materialising a constant as a literal).
    pub fn handle(self) -> Handle<Expression> {
        self.b.scalar_handle(self.v, self.name)
    }

    /// The constant value, if this is one.
    pub fn as_const(self) -> Option<f32> {
        match self.v {
            Val::Const(x) => Some(x),
            Val::Dyn(..) => None,
        }
    }

    fn dynamic(self, h: Handle<Expression>) -> Expr<'a> {
        Expr { b: self.b, v: Val::Dyn(h, self.b.current_id()), name: None }
    }

    fn binary(self, op: BinaryOperator, rhs: Expr<'a>) -> Expr<'a> {
        use BinaryOperator as B;
        match (self.v, rhs.v, op) {
            (Val::Const(a), Val::Const(b), _) => Expr { b: self.b, v: Val::Const(fold_binary(op, a, b)), name: None },
            (_, Val::Const(1.0), B::Multiply | B::Divide) => self,
            (Val::Const(1.0), _, B::Multiply) => rhs,
            (_, Val::Const(0.0), B::Add | B::Subtract) => self,
            (Val::Const(0.0), _, B::Add) => rhs,
            (Val::Const(c), _, B::Multiply) | (_, Val::Const(c), B::Multiply) if c == 0.0 => self.b.constant(0.0),
            _ => {
                let (left, right) = (self.handle(), rhs.handle());
                self.dynamic(self.b.append(Expression::Binary { op, left, right }))
            }
        }
    }

    fn unary_math(self, fun: MathFunction, fold: fn(f32) -> f32) -> Expr<'a> {
        match self.v {
            Val::Const(x) => self.b.constant(fold(x)),
            Val::Dyn(..) => self.dynamic(self.b.math(fun, &[self.handle()])),
        }
    }

    fn binary_math(self, fun: MathFunction, other: Expr<'a>, fold: fn(f32, f32) -> f32) -> Expr<'a> {
        match (self.v, other.v) {
            (Val::Const(a), Val::Const(b)) => self.b.constant(fold(a, b)),
            _ => {
                let args = [self.handle(), other.handle()];
                self.dynamic(self.b.math(fun, &args))
            }
        }
    }

    fn compare(self, op: BinaryOperator, other: Expr<'a>, fold: fn(f32, f32) -> bool) -> ExprBool<'a> {
        match (self.v, other.v) {
            (Val::Const(a), Val::Const(b)) => ExprBool { b: self.b, v: BVal::Const(fold(a, b)) },
            _ => {
                let (left, right) = (self.handle(), other.handle());
                let h = self.b.append(Expression::Binary { op, left, right });
                ExprBool { b: self.b, v: BVal::Dyn(h, self.b.current_id()) }
            }
        }
    }
}

fn fold_binary(op: BinaryOperator, a: f32, b: f32) -> f32 {
    match op {
        BinaryOperator::Add => a + b,
        BinaryOperator::Subtract => a - b,
        BinaryOperator::Multiply => a * b,
        BinaryOperator::Divide => a / b,
        _ => unreachable!("only arithmetic operators are folded"),
    }
}

macro_rules! scalar_ops {
    ($($trait:ident $method:ident $op:ident;)*) => {$(
        impl<'a> $trait for Expr<'a> {
            type Output = Expr<'a>;
            fn $method(self, rhs: Expr<'a>) -> Expr<'a> {
                self.binary(BinaryOperator::$op, rhs)
            }
        }
        impl<'a> $trait<f32> for Expr<'a> {
            type Output = Expr<'a>;
            fn $method(self, rhs: f32) -> Expr<'a> {
                self.binary(BinaryOperator::$op, self.b.constant(rhs))
            }
        }
    )*};
}

scalar_ops! {
    Add add Add;
    Sub sub Subtract;
    Mul mul Multiply;
    Div div Divide;
}

impl<'a> Neg for Expr<'a> {
    type Output = Expr<'a>;
    fn neg(self) -> Expr<'a> {
        match self.v {
            Val::Const(x) => self.b.constant(-x),
            Val::Dyn(..) => {
                self.dynamic(self.b.append(Expression::Unary { op: UnaryOperator::Negate, expr: self.handle() }))
            }
        }
    }
}

impl Named for Expr<'_> {
    fn named(self, name: &str) -> Self {
        match self.v {
            Val::Dyn(h, _) => {
                self.b.name(h, name);
                self
            }
            Val::Const(_) => Expr { name: Some(self.b.const_name(name)), ..self },
        }
    }
}

impl<'a> Real for Expr<'a> {
    type Vec = ExprVec<'a>;
    type Bool = ExprBool<'a>;
    type Ctx = &'a ModuleBuilder;
    const IMMEDIATE: bool = false;

    fn ctx(self) -> &'a ModuleBuilder {
        self.b
    }
    fn constant(ctx: &'a ModuleBuilder, x: f32) -> Expr<'a> {
        ctx.constant(x)
    }
    fn sqrt(self) -> Self {
        self.unary_math(MathFunction::Sqrt, f32::sqrt)
    }
    fn exp(self) -> Self {
        self.unary_math(MathFunction::Exp, f32::exp)
    }
    fn ln(self) -> Self {
        self.unary_math(MathFunction::Log, f32::ln)
    }
    fn powf(self, exponent: Self) -> Self {
        self.binary_math(MathFunction::Pow, exponent, f32::powf)
    }
    fn abs(self) -> Self {
        self.unary_math(MathFunction::Abs, f32::abs)
    }
    fn floor(self) -> Self {
        self.unary_math(MathFunction::Floor, f32::floor)
    }
    fn min(self, other: Self) -> Self {
        self.binary_math(MathFunction::Min, other, f32::min)
    }
    fn max(self, other: Self) -> Self {
        self.binary_math(MathFunction::Max, other, f32::max)
    }
    fn lt(self, other: Self) -> ExprBool<'a> {
        self.compare(BinaryOperator::Less, other, |a, b| a < b)
    }
    fn gt(self, other: Self) -> ExprBool<'a> {
        self.compare(BinaryOperator::Greater, other, |a, b| a > b)
    }
    fn select(condition: ExprBool<'a>, accept: Self, reject: Self) -> Self {
        let b = condition.b;
        match (condition.v, accept.v, reject.v) {
            (BVal::Const(c), ..) => {
                if c {
                    accept
                } else {
                    reject
                }
            }
            (_, Val::Const(x), Val::Const(y)) if x.to_bits() == y.to_bits() => accept,
            _ => {
                let (condition, accept_h, reject_h) = (b.bool_handle(condition.v), accept.handle(), reject.handle());
                accept.dynamic(b.append(Expression::Select { condition, accept: accept_h, reject: reject_h }))
            }
        }
    }
    fn splat(self) -> ExprVec<'a> {
        match self.v {
            Val::Const(x) => ExprVec { b: self.b, v: VVal::Const([x; 3]), name: None },
            Val::Dyn(..) => {
                let value = self.handle();
                self.b.vector(self.b.append(Expression::Splat { size: VectorSize::Tri, value }))
            }
        }
    }
    fn vec3(x: Self, y: Self, z: Self) -> ExprVec<'a> {
        let b = x.b;
        match (x.v, y.v, z.v) {
            (Val::Const(x), Val::Const(y), Val::Const(z)) => ExprVec { b, v: VVal::Const([x, y, z]), name: None },
            _ => {
                let components = vec![x.handle(), y.handle(), z.handle()];
                b.vector(b.append(Expression::Compose { ty: b.types.vec3, components }))
            }
        }
    }
    fn known(self) -> Option<f32> {
        self.as_const()
    }
    fn fetch(table: TableId, index: Self) -> Self {
        let b = index.b;
        if let Val::Const(i) = index.v {
            let codes = table.codes();
            return b.constant(f32::from(codes[(i as usize).min(codes.len() - 1)]));
        }
        let expr = index.handle();
        let position = b.append(Expression::As { expr, kind: naga::ScalarKind::Uint, convert: Some(4) });
        let offset = b.append(Expression::Literal(Literal::U32(table.buffer_offset())));
        let entry = b.append(Expression::Binary { op: BinaryOperator::Add, left: position, right: offset });
        let function = b.table_code_function();
        index.dynamic(b.call(function, vec![entry]))
    }
    fn call(def: &'static TermDef, args: &[Slot<Self>], body: &dyn Fn(&[Slot<Self>]) -> Slot<Self>) -> Slot<Self> {
        let all_const = args.iter().all(|a| match a {
            Slot::S(x) => matches!(x.v, Val::Const(_)),
            Slot::V(v) => matches!(v.v, VVal::Const(_)),
        });
        let b = match args.first() {
            Some(Slot::S(x)) => x.b,
            Some(Slot::V(v)) => v.b,
            None => unreachable!("every term takes at least one argument"),
        };
        // A call with constant arguments is evaluated here: every operation in the body folds.
        if all_const {
            return body(args);
        }
        let key: CallKey = (def.name, args.iter().map(|&a| b.arg_key(a)).collect());
        let result = match b.earlier_call(&key) {
            Some(result) => result,
            None => {
                let function = b.term_function(def, body);
                let arguments = args.iter().map(|&a| b.slot_handle(a)).collect();
                let result = b.call(function, arguments);
                b.remember_call(key, result);
                result
            }
        };
        match def.ret {
            Kind::Scalar => Slot::S(b.scalar(result)),
            Kind::Vec3 => Slot::V(b.vector(result)),
        }
    }
    fn sum_over(b: &'a ModuleBuilder, sum: &Sum, body: &dyn Fn(Self) -> Vec<ExprVec<'a>>) -> Vec<ExprVec<'a>> {
        if !sum.fold {
            return b.sum_loop(sum, body);
        }
        let zero = ExprVec { b, v: VVal::Const([0.0; 3]), name: None };
        let mut totals = vec![zero; sum.totals.len()];
        for i in 0..sum.count {
            for (total, term) in totals.iter_mut().zip(body(b.constant(i as f32))) {
                *total = *total + term;
            }
        }
        totals
    }
}

impl<'a> ExprVec<'a> {
    pub fn handle(self) -> Handle<Expression> {
        self.b.vector_handle(self.v, self.name)
    }

    fn dynamic(self, h: Handle<Expression>) -> ExprVec<'a> {
        self.b.vector(h)
    }

    fn binary(self, op: BinaryOperator, rhs: ExprVec<'a>) -> ExprVec<'a> {
        use BinaryOperator as B;
        let is = |v: VVal, c: f32| matches!(v, VVal::Const(k) if k == [c; 3]);
        match (self.v, rhs.v, op) {
            (VVal::Const(a), VVal::Const(b), _) => {
                ExprVec { b: self.b, v: VVal::Const([0, 1, 2].map(|i| fold_binary(op, a[i], b[i]))), name: None }
            }
            (_, r, B::Multiply | B::Divide) if is(r, 1.0) => self,
            (l, _, B::Multiply) if is(l, 1.0) => rhs,
            (_, r, B::Add | B::Subtract) if is(r, 0.0) => self,
            (l, _, B::Add) if is(l, 0.0) => rhs,
            (l, r, B::Multiply) if is(l, 0.0) || is(r, 0.0) => {
                ExprVec { b: self.b, v: VVal::Const([0.0; 3]), name: None }
            }
            _ => {
                let (left, right) = (self.handle(), rhs.handle());
                self.dynamic(self.b.append(Expression::Binary { op, left, right }))
            }
        }
    }

    /// vector ∘ scalar. naga's IR has a vector-scalar form only for multiplication (`v * s`);
    /// for division the scalar is splatted first.
    fn binary_scalar(self, op: BinaryOperator, rhs: Expr<'a>) -> ExprVec<'a> {
        match (self.v, rhs.v) {
            (_, Val::Const(c)) => self.binary(op, ExprVec { b: self.b, v: VVal::Const([c; 3]), name: None }),
            _ if op != BinaryOperator::Multiply => self.binary(op, rhs.splat()),
            _ => {
                let (left, right) = (self.handle(), rhs.handle());
                self.dynamic(self.b.append(Expression::Binary { op, left, right }))
            }
        }
    }

    fn map(self, fun: MathFunction, fold: fn(f32) -> f32) -> ExprVec<'a> {
        match self.v {
            VVal::Const(c) => ExprVec { b: self.b, v: VVal::Const(c.map(fold)), name: None },
            VVal::Dyn(..) => self.dynamic(self.b.math(fun, &[self.handle()])),
        }
    }

    fn zip(self, fun: MathFunction, other: ExprVec<'a>, fold: fn(f32, f32) -> f32) -> ExprVec<'a> {
        match (self.v, other.v) {
            (VVal::Const(a), VVal::Const(b)) => {
                ExprVec { b: self.b, v: VVal::Const([0, 1, 2].map(|i| fold(a[i], b[i]))), name: None }
            }
            _ => {
                let args = [self.handle(), other.handle()];
                self.dynamic(self.b.math(fun, &args))
            }
        }
    }

    fn component(self, index: u32) -> Expr<'a> {
        match self.v {
            VVal::Const(c) => self.b.constant(c[index as usize]),
            VVal::Dyn(..) => {
                let base = self.handle();
                self.b.scalar(self.b.append(Expression::AccessIndex { base, index }))
            }
        }
    }

    fn to_glam(c: [f32; 3]) -> glam::Vec3 {
        glam::Vec3::from_array(c)
    }
}

macro_rules! vector_ops {
    ($($trait:ident $method:ident $op:ident;)*) => {$(
        impl<'a> $trait for ExprVec<'a> {
            type Output = ExprVec<'a>;
            fn $method(self, rhs: ExprVec<'a>) -> ExprVec<'a> {
                self.binary(BinaryOperator::$op, rhs)
            }
        }
    )*};
}

vector_ops! {
    Add add Add;
    Sub sub Subtract;
    Mul mul Multiply;
    Div div Divide;
}

impl<'a> Mul<f32> for ExprVec<'a> {
    type Output = ExprVec<'a>;
    fn mul(self, rhs: f32) -> ExprVec<'a> {
        self.binary_scalar(BinaryOperator::Multiply, self.b.constant(rhs))
    }
}

impl<'a> Mul<Expr<'a>> for ExprVec<'a> {
    type Output = ExprVec<'a>;
    fn mul(self, rhs: Expr<'a>) -> ExprVec<'a> {
        self.binary_scalar(BinaryOperator::Multiply, rhs)
    }
}

impl<'a> Div<Expr<'a>> for ExprVec<'a> {
    type Output = ExprVec<'a>;
    fn div(self, rhs: Expr<'a>) -> ExprVec<'a> {
        self.binary_scalar(BinaryOperator::Divide, rhs)
    }
}

impl<'a> Neg for ExprVec<'a> {
    type Output = ExprVec<'a>;
    fn neg(self) -> ExprVec<'a> {
        match self.v {
            VVal::Const(c) => ExprVec { b: self.b, v: VVal::Const(c.map(|x| -x)), name: None },
            VVal::Dyn(..) => {
                let expr = self.handle();
                self.dynamic(self.b.append(Expression::Unary { op: UnaryOperator::Negate, expr }))
            }
        }
    }
}

impl Named for ExprVec<'_> {
    fn named(self, name: &str) -> Self {
        match self.v {
            VVal::Dyn(h, _) => {
                self.b.name(h, name);
                self
            }
            VVal::Const(_) => ExprVec { name: Some(self.b.const_name(name)), ..self },
        }
    }
}

impl<'a> Vector for ExprVec<'a> {
    type Real = Expr<'a>;

    fn dot(self, other: Self) -> Expr<'a> {
        match (self.v, other.v) {
            (VVal::Const(a), VVal::Const(b)) => self.b.constant(Self::to_glam(a).dot(Self::to_glam(b))),
            _ => {
                let args = [self.handle(), other.handle()];
                self.b.scalar(self.b.math(MathFunction::Dot, &args))
            }
        }
    }
    fn cross(self, other: Self) -> Self {
        match (self.v, other.v) {
            (VVal::Const(a), VVal::Const(b)) => {
                ExprVec { b: self.b, v: VVal::Const(Self::to_glam(a).cross(Self::to_glam(b)).to_array()), name: None }
            }
            _ => {
                let args = [self.handle(), other.handle()];
                self.dynamic(self.b.math(MathFunction::Cross, &args))
            }
        }
    }
    fn normalize(self) -> Self {
        match self.v {
            VVal::Const(c) => {
                ExprVec { b: self.b, v: VVal::Const(Vector::normalize(Self::to_glam(c)).to_array()), name: None }
            }
            VVal::Dyn(..) => self.dynamic(self.b.math(MathFunction::Normalize, &[self.handle()])),
        }
    }
    fn x(self) -> Expr<'a> {
        self.component(0)
    }
    fn y(self) -> Expr<'a> {
        self.component(1)
    }
    fn z(self) -> Expr<'a> {
        self.component(2)
    }
    fn exp(self) -> Self {
        self.map(MathFunction::Exp, f32::exp)
    }
    fn sqrt(self) -> Self {
        self.map(MathFunction::Sqrt, f32::sqrt)
    }
    fn min(self, other: Self) -> Self {
        self.zip(MathFunction::Min, other, f32::min)
    }
    fn max(self, other: Self) -> Self {
        self.zip(MathFunction::Max, other, f32::max)
    }
    fn select(condition: ExprBool<'a>, accept: Self, reject: Self) -> Self {
        let b = condition.b;
        match (condition.v, accept.v, reject.v) {
            (BVal::Const(c), ..) => {
                if c {
                    accept
                } else {
                    reject
                }
            }
            _ => {
                let (condition, accept_h, reject_h) = (b.bool_handle(condition.v), accept.handle(), reject.handle());
                accept.dynamic(b.append(Expression::Select { condition, accept: accept_h, reject: reject_h }))
            }
        }
    }
    fn is_known_zero(self) -> bool {
        matches!(self.v, VVal::Const(c) if c == [0.0; 3])
    }
    fn is_known(self) -> bool {
        matches!(self.v, VVal::Const(_))
    }
    fn refract(self, normal: Self, eta: Expr<'a>) -> Self {
        match (self.v, normal.v, eta.v) {
            (VVal::Const(i), VVal::Const(n), Val::Const(e)) => {
                let r = Self::to_glam(i).refract(Self::to_glam(n), e);
                ExprVec { b: self.b, v: VVal::Const(r.to_array()), name: None }
            }
            _ => {
                let args = [self.handle(), normal.handle(), eta.handle()];
                self.dynamic(self.b.math(MathFunction::Refract, &args))
            }
        }
    }
}

impl<'a> ExprBool<'a> {
    fn logical(self, op: BinaryOperator, rhs: ExprBool<'a>, fold: fn(bool, bool) -> bool) -> ExprBool<'a> {
        match (self.v, rhs.v) {
            (BVal::Const(a), BVal::Const(b)) => ExprBool { b: self.b, v: BVal::Const(fold(a, b)) },
            _ => {
                let (left, right) = (self.b.bool_handle(self.v), self.b.bool_handle(rhs.v));
                let h = self.b.append(Expression::Binary { op, left, right });
                ExprBool { b: self.b, v: BVal::Dyn(h, self.b.current_id()) }
            }
        }
    }

    pub fn handle(self) -> Handle<Expression> {
        self.b.bool_handle(self.v)
    }
}

impl<'a> BitAnd for ExprBool<'a> {
    type Output = ExprBool<'a>;
    fn bitand(self, rhs: Self) -> Self {
        self.logical(BinaryOperator::LogicalAnd, rhs, |a, b| a && b)
    }
}

impl<'a> BitOr for ExprBool<'a> {
    type Output = ExprBool<'a>;
    fn bitor(self, rhs: Self) -> Self {
        self.logical(BinaryOperator::LogicalOr, rhs, |a, b| a || b)
    }
}

impl<'a> Not for ExprBool<'a> {
    type Output = ExprBool<'a>;
    fn not(self) -> Self {
        match self.v {
            BVal::Const(c) => ExprBool { b: self.b, v: BVal::Const(!c) },
            BVal::Dyn(..) => {
                let expr = self.handle();
                let h = self.b.append(Expression::Unary { op: UnaryOperator::LogicalNot, expr });
                ExprBool { b: self.b, v: BVal::Dyn(h, self.b.current_id()) }
            }
        }
    }
}

impl Named for ExprBool<'_> {
    fn named(self, name: &str) -> Self {
        if let BVal::Dyn(h, _) = self.v {
            self.b.name(h, name);
        }
        self
    }
}

impl Logic for ExprBool<'_> {}
