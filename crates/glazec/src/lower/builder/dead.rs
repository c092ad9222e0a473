//! Dead code out of a finished function: what the Rust source computes but the function's
//! result never reads. The layering code is shared with the CPU, which computes some values
//! only some callers use (a level's albedo towards l, where image-based lighting wants only v's;
//! a cosine the lobes of this material do not take); the generated function keeps only what
//! reaches a statement, as a person writing the shader would.
//!
//! A call whose result is unused is removed (every function the builder makes is pure: none
//! writes outside its own locals); a dead expression leaves its emit range and becomes a
//! literal no one reads, so that nothing counts it as a use of its operands and no backend
//! prints it. A function holding an expression or statement this pass does not know is left as
//! it is.

use naga::{Block, Expression, Function, Handle, Literal, Span, Statement};

/// Removes `function`'s dead calls and expressions (see the module docs).
pub(super) fn remove_dead_code(function: &mut Function) {
    let count = function.expressions.len();
    let mut operands = Vec::with_capacity(count);
    for (_, expression) in function.expressions.iter() {
        let Some(of) = expression_operands(expression) else { return };
        operands.push(of);
    }
    if !known_block(&function.body) {
        return;
    }
    let mut live = vec![false; count];
    let mut stack: Vec<Handle<Expression>> = Vec::new();
    for local in function.local_variables.iter() {
        stack.extend(local.1.init);
    }
    // Statements other than calls are roots; a call is one once its result is live (or it has
    // none). Repeat until no more calls come alive.
    let mut calls_live: Vec<bool> = Vec::new();
    loop {
        let mut index = 0;
        roots(&function.body, &live, &mut stack, &mut calls_live, &mut index);
        let mut changed = false;
        while let Some(handle) = stack.pop() {
            let i = handle.index();
            if live[i] {
                continue;
            }
            live[i] = true;
            changed = true;
            stack.extend(operands[i].iter().copied());
        }
        if !changed {
            break;
        }
    }
    let mut index = 0;
    prune(&mut function.body, &live, &calls_live, &mut index);
    let handles: Vec<Handle<Expression>> = function.expressions.iter().map(|(h, _)| h).collect();
    for handle in handles {
        if !live[handle.index()] && !function.expressions[handle].needs_pre_emit() {
            function.expressions[handle] = Expression::Literal(Literal::F32(0.0));
        }
    }
    function.named_expressions.retain(|handle, _| live[handle.index()]);
}

/// The expressions `expression` reads, or `None` for a kind this pass does not know.
fn expression_operands(expression: &Expression) -> Option<Vec<Handle<Expression>>> {
    use Expression as E;
    Some(match *expression {
        E::Literal(_)
        | E::Constant(_)
        | E::ZeroValue(_)
        | E::FunctionArgument(_)
        | E::GlobalVariable(_)
        | E::LocalVariable(_)
        | E::CallResult(_) => Vec::new(),
        E::Load { pointer } => vec![pointer],
        E::Binary { left, right, .. } => vec![left, right],
        E::Unary { expr, .. } | E::As { expr, .. } => vec![expr],
        E::Math { arg, arg1, arg2, arg3, .. } => [Some(arg), arg1, arg2, arg3].into_iter().flatten().collect(),
        E::Select { condition, accept, reject } => vec![condition, accept, reject],
        E::Splat { value, .. } => vec![value],
        E::Compose { ref components, .. } => components.clone(),
        E::Access { base, index } => vec![base, index],
        E::AccessIndex { base, .. } => vec![base],
        E::Swizzle { vector, .. } => vec![vector],
        E::Relational { argument, .. } => vec![argument],
        E::ImageSample { image, sampler, coordinate, array_index, offset, level, depth_ref, .. } => {
            let level = match level {
                naga::SampleLevel::Exact(h) | naga::SampleLevel::Bias(h) => vec![h],
                naga::SampleLevel::Gradient { x, y } => vec![x, y],
                naga::SampleLevel::Auto | naga::SampleLevel::Zero => Vec::new(),
            };
            [Some(image), Some(sampler), Some(coordinate), array_index, offset, depth_ref]
                .into_iter()
                .flatten()
                .chain(level)
                .collect()
        }
        E::ImageLoad { image, coordinate, array_index, sample, level } => {
            [Some(image), Some(coordinate), array_index, sample, level].into_iter().flatten().collect()
        }
        E::ImageQuery { image, ref query } => match *query {
            naga::ImageQuery::Size { level: Some(level) } => vec![image, level],
            _ => vec![image],
        },
        _ => return None,
    })
}

/// Whether every statement of `block` is one this pass knows.
fn known_block(block: &Block) -> bool {
    block.iter().all(|statement| match statement {
        Statement::Emit(_) | Statement::Store { .. } | Statement::Call { .. } | Statement::Return { .. } => true,
        Statement::If { accept, reject, .. } => known_block(accept) && known_block(reject),
        Statement::Loop { body, continuing, .. } => known_block(body) && known_block(continuing),
        Statement::Block(inner) => known_block(inner),
        _ => false,
    })
}

/// Pushes the expressions `block`'s statements read onto `stack`: every non-call statement's,
/// and a call's arguments where its result is `live` (or it has none). `calls_live[k]` records
/// whether the k-th call (in walking order, `index`) is kept.
fn roots(
    block: &Block,
    live: &[bool],
    stack: &mut Vec<Handle<Expression>>,
    calls_live: &mut Vec<bool>,
    index: &mut usize,
) {
    for statement in block.iter() {
        match statement {
            Statement::Store { pointer, value } => stack.extend([*pointer, *value]),
            Statement::Return { value } => stack.extend(*value),
            Statement::If { condition, accept, reject } => {
                stack.push(*condition);
                roots(accept, live, stack, calls_live, index);
                roots(reject, live, stack, calls_live, index);
            }
            Statement::Loop { body, continuing, break_if } => {
                stack.extend(*break_if);
                roots(body, live, stack, calls_live, index);
                roots(continuing, live, stack, calls_live, index);
            }
            Statement::Block(inner) => roots(inner, live, stack, calls_live, index),
            Statement::Call { arguments, result, .. } => {
                let kept = result.is_none_or(|r| live[r.index()]);
                if *index == calls_live.len() {
                    calls_live.push(false);
                }
                if kept && !calls_live[*index] {
                    calls_live[*index] = true;
                    stack.extend(arguments.iter().copied());
                }
                *index += 1;
            }
            _ => {}
        }
    }
}

/// Drops the calls that are not kept and the dead expressions from the emit ranges of `block`.
fn prune(block: &mut Block, live: &[bool], calls_live: &[bool], index: &mut usize) {
    let mut out = Block::with_capacity(block.len());
    let taken = std::mem::take(block);
    for statement in taken.iter().cloned() {
        match statement {
            Statement::Emit(range) => {
                // Split the range around its dead expressions.
                let mut start: Option<Handle<Expression>> = None;
                let mut last: Option<Handle<Expression>> = None;
                for handle in range.clone() {
                    if live[handle.index()] {
                        start.get_or_insert(handle);
                        last = Some(handle);
                    } else if let (Some(first), Some(end)) = (start.take(), last.take()) {
                        out.push(Statement::Emit(naga::Range::new_from_bounds(first, end)), Span::UNDEFINED);
                    }
                }
                if let (Some(first), Some(end)) = (start, last) {
                    out.push(Statement::Emit(naga::Range::new_from_bounds(first, end)), Span::UNDEFINED);
                }
            }
            Statement::Call { function, arguments, result } => {
                if calls_live[*index] {
                    out.push(Statement::Call { function, arguments, result }, Span::UNDEFINED);
                }
                *index += 1;
            }
            Statement::If { condition, mut accept, mut reject } => {
                prune(&mut accept, live, calls_live, index);
                prune(&mut reject, live, calls_live, index);
                out.push(Statement::If { condition, accept, reject }, Span::UNDEFINED);
            }
            Statement::Loop { mut body, mut continuing, break_if } => {
                prune(&mut body, live, calls_live, index);
                prune(&mut continuing, live, calls_live, index);
                out.push(Statement::Loop { body, continuing, break_if }, Span::UNDEFINED);
            }
            Statement::Block(mut inner) => {
                prune(&mut inner, live, calls_live, index);
                out.push(Statement::Block(inner), Span::UNDEFINED);
            }
            other => out.push(other, Span::UNDEFINED),
        }
    }
    *block = out;
}
