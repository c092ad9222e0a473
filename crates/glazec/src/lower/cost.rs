//! The static size of a generated module's shading code (what the simplifier and the benchmark
//! weigh).

/// Expressions and transcendental calls (exp, log, pow, sqrt, trigonometry) over the module's
/// functions: the static size of the shading code.
pub fn static_cost(module: &naga::Module) -> (usize, usize) {
    use naga::{Expression, MathFunction as M};
    let mut expressions = 0;
    let mut transcendental = 0;
    for (_, f) in module.functions.iter() {
        expressions += f.expressions.len();
        transcendental += f
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
    }
    (expressions, transcendental)
}
