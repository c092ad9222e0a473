//! The folding value types of the builder: [`Expr`], [`ExprVec`] and [`ExprBool`] implement
//! [`Real`]/[`Vector`]/[`Logic`]. A value is a Rust constant until it meets a runtime value; then
//! each operation appends an expression to the function being built (see the [builder](super)).

use std::ops::{Add, BitAnd, BitOr, Div, Mul, Neg, Not, Sub};

use naga::{
    BinaryOperator, Expression, Function, FunctionArgument, FunctionResult, Handle, Literal, MathFunction, Statement,
    UnaryOperator, VectorSize,
};

use super::{ArgKey, CallKey, ConstName, ModuleBuilder};
use crate::math::{Kind, Logic, Named, Real, Slot, Sum, TermDef, Vector};

impl ModuleBuilder {
    pub fn scalar(&self, handle: Handle<Expression>) -> Expr<'_> {
        Expr { b: self, v: Val::Dyn(handle, self.current_id()), name: None }
    }

    pub fn vector(&self, handle: Handle<Expression>) -> ExprVec<'_> {
        ExprVec { b: self, v: VVal::Dyn(handle, self.current_id()), name: None }
    }

    pub fn constant(&self, x: f32) -> Expr<'_> {
        Expr { b: self, v: Val::Const(x), name: None }
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

    /// The function that implements `def`, building it on first use.
    /// A table lookup with the arguments that are literals here (`literals[i]`) built into it:
    /// its parameters are the others, and its cells along the literal axes are constants, so
    /// that it reads only the slices they select (the table block of `tables.rs`). The first
    /// specialisation of a table is named `<lookup>_slice`, later ones `<lookup>_slice_b`, `_c`, …
    fn specialised_lookup<'a>(
        &'a self,
        def: &'static TermDef,
        literals: &[Option<f32>],
        body: &dyn Fn(&[Slot<Expr<'a>>]) -> Slot<Expr<'a>>,
    ) -> Handle<Function> {
        let key = (def.name, literals.iter().map(|l| l.map(f32::to_bits)).collect::<Vec<_>>());
        if let Some(&f) = self.state.borrow().specialised.get(&key) {
            return f;
        }
        // One argument known only at run time: the lookup along its axis is a closed form.
        let curve = match literals.iter().filter(|l| l.is_none()).count() {
            1 if self.curves.get() => {
                crate::math::tables::TableId::ALL.iter().find(|id| id.spec().term.name == def.name).map(|&id| {
                    let axis = literals.iter().position(Option::is_none).unwrap_or(0);
                    let fixed: Vec<f32> = literals.iter().map(|l| l.unwrap_or(0.0)).collect();
                    (axis, crate::math::tables::Curve::of_table(id, axis, &fixed))
                })
            }
            _ => None,
        };
        let kind = if curve.is_some() { "curve" } else { "slice" };
        let earlier = self.state.borrow().specialised.iter().filter(|((name, _), _)| *name == def.name).count();
        let name = match earlier {
            0 => format!("{}_{kind}", def.name),
            k => format!("{}_{kind}_{}", def.name, char::from(b'a' + (k % 26) as u8)),
        };
        let dynamic: Vec<(usize, &(&str, Kind))> =
            def.params.iter().enumerate().filter(|(i, _)| literals[*i].is_none()).collect();
        let arguments = dynamic
            .iter()
            .map(|&(_, &(name, kind))| FunctionArgument {
                name: Some(name.to_string()),
                ty: self.kind_type(kind),
                binding: None,
            })
            .collect();
        let result = FunctionResult { ty: self.kind_type(def.ret), binding: None };
        self.begin_function(&name, arguments, Some(result));
        let mut next = 0;
        let slots: Vec<Slot<Expr<'a>>> = def
            .params
            .iter()
            .zip(literals)
            .map(|(&(_, kind), literal)| match literal {
                Some(x) => Slot::S(self.constant(*x)),
                None => {
                    let h = self.argument(next);
                    next += 1;
                    match kind {
                        Kind::Scalar => Slot::S(self.scalar(h)),
                        Kind::Vec3 => Slot::V(self.vector(h)),
                    }
                }
            })
            .collect();
        let out = match &curve {
            Some((axis, curve)) => match slots[*axis] {
                Slot::S(x) => Slot::S(curve.evaluate(x)),
                Slot::V(_) => unreachable!("table arguments are scalars"),
            },
            None => body(&slots),
        };
        let value = self.slot_handle(out);
        self.statement(Statement::Return { value: Some(value) });
        let function = self.end_function();
        let fixed: Vec<String> = def
            .params
            .iter()
            .zip(literals)
            .filter_map(|(&(param, _), literal)| literal.map(|x| format!("{param} = {x}")))
            .collect();
        let mut doc: Vec<String> = def.summary().iter().map(|l| l.to_string()).collect();
        doc.push(match &curve {
            Some((axis, curve)) => format!(
                "Here {} (literals): piecewise linear along `{}` through {} of its {} nodes (u counts them), {}; no table read.",
                fixed.join(", "),
                def.params[*axis].0,
                curve.kept(),
                curve.nodes,
                match curve.form {
                    crate::math::tables::Form::Hinges { .. } => "as hinges max(u, knot)·Δslope",
                    crate::math::tables::Form::Pieces { .. } => "piece by piece, (clamp(u, a, b) − a)·slope",
                }
            ),
            None => format!("Here {} (literals): only the table slices they select.", fixed.join(", ")),
        });
        let doc: Vec<&str> = doc.iter().map(String::as_str).collect();
        let handle = self.add_function(function, &doc);
        self.state.borrow_mut().specialised.insert(key, handle);
        handle
    }

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
        let handle = self.add_function(function, def.summary());
        self.state.borrow_mut().terms.insert(def.name, handle);
        handle
    }
}

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
    fn acos(self) -> Self {
        self.unary_math(MathFunction::Acos, f32::acos)
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
    fn table_curves(b: &'a ModuleBuilder) -> bool {
        b.curves.get()
    }
    fn interpolate_at_runtime(table: &crate::math::TableCodes, cells: &[(Self, Self)]) -> Option<Self> {
        Some(cells[0].0.b.table_interpolation(table, cells))
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
                let literals: Vec<Option<f32>> = args
                    .iter()
                    .map(|a| match a {
                        Slot::S(x) => x.as_const(),
                        Slot::V(_) => None,
                    })
                    .collect();
                let (function, arguments) = if is_table_lookup(def) && literals.iter().any(Option::is_some) {
                    let function = b.specialised_lookup(def, &literals, body);
                    let dynamic = args.iter().zip(&literals).filter(|(_, l)| l.is_none());
                    (function, dynamic.map(|(&a, _)| b.slot_handle(a)).collect())
                } else {
                    (b.term_function(def, body), args.iter().map(|&a| b.slot_handle(a)).collect())
                };
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

/// Whether `def` is a table's lookup (whose literal arguments are worth building in: they fix
/// which slices of the table a shader needs bound).
fn is_table_lookup(def: &TermDef) -> bool {
    crate::math::tables::SPECS.iter().any(|spec| spec.term.name == def.name)
}
