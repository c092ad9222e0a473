//! The table buffer in generated code: a material's own uniform of the tables it reads (named
//! `<material>_tables` once `lower` namespaces the module) and the function that reads one
//! 16-bit code out of it. The buffer holds only the tables the material uses, each whole, in
//! order of first use, so that it stays small (three 2,048-entry tables are 12 KiB, inside the
//! 16 KiB that wgpu's downlevel limits and WebGL2 guarantee for a uniform binding).

use naga::{
    BinaryOperator, Expression, Function, FunctionArgument, FunctionResult, Handle, Literal, Scalar as NagaScalar,
    Span, Statement, TypeInner, VectorSize,
};

use super::{ModuleBuilder, insert_type};

/// The name of the table buffer in generated code (before `lower` prefixes it with the material's).
pub const TABLES_BUFFER_NAME: &str = "glazec_tables";

/// The function that reads an entry of the table buffer.
const TABLE_CODE_FUNCTION: &str = "glazec_table_code";

impl ModuleBuilder {
    /// The table buffer `glazec_tables: array<vec4<u32>, N>` (a uniform buffer; created on
    /// first use; its size is set by [`Self::finish_tables`] and its binding by `lower`), as a
    /// pointer expression. Entries are 16-bit codes, two to a word: entry i is the low (i even)
    /// or high half of component (i / 2) % 4 of element i / 8.
    ///
    /// Tables are read from a buffer rather than from constant arrays: naga's SPIR-V writer
    /// spills a dynamically indexed array *value* into a local variable at every access and
    /// lavapipe's compiler lowers that to a chain of selects. Even 16-entry curves folded from
    /// the tables made a two-coat shader take 3 s to compile (0.2 s from a buffer), and an
    /// 8,192-entry table took minutes. A uniform rather than a storage buffer: an eight-coat
    /// shader with runtime parameters compiled in 2.3 s instead of 6.0 s.
    fn tables_buffer(&self) -> Handle<Expression> {
        let global = {
            let mut state = self.state.borrow_mut();
            match state.tables_buffer {
                Some(h) => h,
                None => {
                    let module = &mut state.module;
                    // A placeholder size until the module is complete.
                    let ty = tables_type(module, 1);
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

    /// Where the table whose codes are `codes` (at `buffer_offset` in the catalogue's buffer)
    /// starts in this module's table buffer, in entries: tables are added whole, in order of
    /// first use.
    pub(super) fn table_offset(&self, codes: &'static [u16], buffer_offset: u32) -> u32 {
        let mut state = self.state.borrow_mut();
        let mut offset = 0;
        for &(known, known_codes) in &state.tables_used {
            if known == buffer_offset {
                return offset;
            }
            offset += known_codes.len() as u32;
        }
        state.tables_used.push((buffer_offset, codes));
        offset
    }

    /// Gives the table buffer (if any) its final size and returns its contents: the codes of
    /// the tables used, concatenated (empty when no lookup reads the buffer).
    pub fn finish_tables(&self) -> Vec<u16> {
        let mut state = self.state.borrow_mut();
        let codes: Vec<u16> = state.tables_used.iter().flat_map(|(_, c)| c.iter().copied()).collect();
        if let Some(global) = state.tables_buffer {
            // A fixed size, so that a device's bounds checks clamp to a constant instead of
            // reading the buffer's length at every access.
            let vec4s = codes.len().div_ceil(8).max(1) as u32;
            let ty = tables_type(&mut state.module, vec4s);
            state.module.global_variables[global].ty = ty;
        }
        codes
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

/// `array<vec4<u32>, vec4s>`.
fn tables_type(module: &mut naga::Module, vec4s: u32) -> Handle<naga::Type> {
    let size = naga::ArraySize::Constant(std::num::NonZeroU32::new(vec4s).unwrap_or(std::num::NonZeroU32::MIN));
    let words = TypeInner::Vector { size: VectorSize::Quad, scalar: NagaScalar::U32 };
    let words = insert_type(module, None, words);
    insert_type(module, None, TypeInner::Array { base: words, size, stride: 16 })
}

/// Packs 16-bit codes two to a little-endian 32-bit word (the even entry in the low half),
/// padded with zeros to whole `vec4<u32>` elements: a table buffer's bytes.
pub fn table_bytes(codes: &[u16]) -> Vec<u8> {
    let mut words: Vec<u32> =
        codes.chunks(2).map(|pair| u32::from(pair[0]) | u32::from(pair.get(1).copied().unwrap_or(0)) << 16).collect();
    words.resize(words.len().next_multiple_of(4), 0);
    words.iter().flat_map(|w| w.to_le_bytes()).collect()
}
