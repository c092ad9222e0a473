//! The table buffer in generated code: the uniform `glazec_tables` and the function that reads
//! one 16-bit code out of it (`crate::math::tables` lays the buffer out).

use naga::{
    BinaryOperator, Expression, Function, FunctionArgument, FunctionResult, Handle, Literal, Scalar as NagaScalar,
    Span, Statement, TypeInner, VectorSize,
};

use super::{ModuleBuilder, insert_type};

/// The name of the table buffer in generated code.
pub const TABLES_BUFFER_NAME: &str = "glazec_tables";

/// The function that reads an entry of the table buffer.
const TABLE_CODE_FUNCTION: &str = "glazec_table_code";

impl ModuleBuilder {
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
    pub(super) fn table_code_function(&self) -> Handle<Function> {
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
}
