//! The static size of a generated module's shading code (what the simplifier and the benchmark
//! weigh).

/// Expressions and transcendental calls (exp, log, pow, sqrt, trigonometry) over the module's
/// functions: the static size of the shading code.
pub fn static_cost(module: &naga::Module) -> (usize, usize) {
    module.functions.iter().map(|(_, f)| function_cost(f)).fold((0, 0), |(e, t), (fe, ft)| (e + fe, t + ft))
}

/// Expressions and transcendental calls of one function's own body.
fn function_cost(f: &naga::Function) -> (usize, usize) {
    use naga::{Expression, MathFunction as M};
    let transcendental = f
        .expressions
        .iter()
        .filter(|(_, e)| {
            matches!(
                e,
                Expression::Math {
                    fun: M::Exp
                        | M::Exp2
                        | M::Log
                        | M::Log2
                        | M::Pow
                        | M::Sqrt
                        | M::InverseSqrt
                        | M::Sin
                        | M::Cos
                        | M::Tan
                        | M::Asin
                        | M::Acos
                        | M::Atan
                        | M::Atan2,
                    ..
                }
            )
        })
        .count();
    (f.expressions.len(), transcendental)
}

/// What one call of a function costs when run: its expressions, memory loads (of a resource:
/// a uniform, storage buffer or texture) and transcendental calls, with every function it calls
/// counted at each call as if inlined (a loop's body once). The measure `glazec bench` reports
/// per material for `<m>_brdf`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct CallCost {
    pub expressions: usize,
    pub loads: usize,
    pub transcendental: usize,
}

/// [`CallCost`] of the function named `name` (`None` if the module has none).
pub fn call_cost(module: &naga::Module, name: &str) -> Option<CallCost> {
    let (handle, _) = module.functions.iter().find(|(_, f)| f.name.as_deref() == Some(name))?;
    let mut memo = std::collections::HashMap::new();
    Some(cost_of(module, handle, &mut memo))
}

fn cost_of(
    module: &naga::Module,
    handle: naga::Handle<naga::Function>,
    memo: &mut std::collections::HashMap<naga::Handle<naga::Function>, CallCost>,
) -> CallCost {
    use naga::{AddressSpace, Expression};
    if let Some(&c) = memo.get(&handle) {
        return c;
    }
    let f = &module.functions[handle];
    let (expressions, transcendental) = function_cost(f);
    // A load whose pointer leads back to a global in a resource address space.
    let resource = |mut e: naga::Handle<Expression>| loop {
        match f.expressions[e] {
            Expression::Access { base, .. } | Expression::AccessIndex { base, .. } => e = base,
            Expression::GlobalVariable(g) => {
                break matches!(module.global_variables[g].space, AddressSpace::Uniform | AddressSpace::Storage { .. });
            }
            _ => break false,
        }
    };
    let loads = f
        .expressions
        .iter()
        .filter(|(_, e)| match e {
            Expression::Load { pointer } => resource(*pointer),
            Expression::ImageSample { .. } | Expression::ImageLoad { .. } => true,
            _ => false,
        })
        .count();
    let mut total = CallCost { expressions, loads, transcendental };
    let mut calls = Vec::new();
    collect_calls(&f.body, &mut calls);
    for callee in calls {
        let c = cost_of(module, callee, memo);
        total.expressions += c.expressions;
        total.loads += c.loads;
        total.transcendental += c.transcendental;
    }
    memo.insert(handle, total);
    total
}

fn collect_calls(block: &naga::Block, out: &mut Vec<naga::Handle<naga::Function>>) {
    use naga::Statement as S;
    for statement in block.iter() {
        match statement {
            S::Call { function, .. } => out.push(*function),
            S::Block(inner) => collect_calls(inner, out),
            S::If { accept, reject, .. } => {
                collect_calls(accept, out);
                collect_calls(reject, out);
            }
            S::Loop { body, continuing, .. } => {
                collect_calls(body, out);
                collect_calls(continuing, out);
            }
            S::Switch { cases, .. } => cases.iter().for_each(|c| collect_calls(&c.body, out)),
            _ => {}
        }
    }
}
