//! The table buffer in generated code: a material's own uniform of the table entries it can
//! read (named `<material>_tables` once `lower` namespaces the module) and the function that
//! reads one 16-bit code out of it. The buffer holds only the windows of the tables that the
//! material's lookups can reach (a lookup whose roughness and IOR are literals reaches one
//! slice per interpolation corner: 4 × 16 entries of a 2,048-entry table), in order of first
//! use, so that it stays small: inside the 16 KiB that wgpu's downlevel limits and WebGL2
//! guarantee for a uniform binding.

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

    /// `position + offset`: the entry of the module's table buffer for `position` within the
    /// window of `table` a fetch can reach. The offset is a placeholder until
    /// [`Self::finish_tables`] lays the buffer out.
    pub(super) fn table_entry(&self, table: crate::math::Codes, position: Handle<Expression>) -> Handle<Expression> {
        let offset = self.append(Expression::Literal(Literal::U32(0)));
        let add = self.append(Expression::Binary { op: BinaryOperator::Add, left: position, right: offset });
        let mut state = self.state.borrow_mut();
        let function = state.stack.last().and_then(|f| f.function.name.clone()).unwrap_or_default();
        state.table_fetches.push(super::TableFetch { function, add, offset, codes: table });
        add
    }

    /// Lays the table buffer out and returns its contents: per table, the windows its fetches
    /// reach, merged where they overlap or touch, one after another in order of first use (so a
    /// table's share is never more than the whole table). Then gives every fetch its offset
    /// (a fetch at offset 0 reads the entry itself) and the buffer its final size. Empty when no
    /// lookup reads the buffer.
    pub fn finish_tables(&self) -> Vec<u16> {
        let mut state = self.state.borrow_mut();
        // Per table (by its place in the catalogue's buffer), the windows its fetches reach.
        let mut tables: Vec<TableWindows> = Vec::new();
        for fetch in &state.table_fetches {
            let c = fetch.codes;
            let window = (c.start, c.start + c.len);
            match tables.iter_mut().find(|(offset, ..)| *offset == c.buffer_offset) {
                Some((_, _, windows)) => windows.push(window),
                None => tables.push((c.buffer_offset, c.codes, vec![window])),
            }
        }
        let mut codes: Vec<u16> = Vec::new();
        // (table, merged window, its offset in the buffer).
        let mut placed: Vec<(u32, (u32, u32), u32)> = Vec::new();
        for (table, table_codes, mut windows) in tables {
            windows.sort_unstable();
            let mut merged: Vec<(u32, u32)> = Vec::new();
            for (start, end) in windows {
                match merged.last_mut() {
                    Some(last) if start <= last.1 => last.1 = last.1.max(end),
                    _ => merged.push((start, end)),
                }
            }
            for (start, end) in merged {
                placed.push((table, (start, end), codes.len() as u32));
                codes.extend_from_slice(&table_codes[start as usize..(end as usize).min(table_codes.len())]);
            }
        }
        let fetches = std::mem::take(&mut state.table_fetches);
        for fetch in &fetches {
            let c = fetch.codes;
            let Some(&(_, (start, _), at)) = placed
                .iter()
                .find(|(table, (start, end), _)| *table == c.buffer_offset && *start <= c.start && c.start < *end)
            else {
                unreachable!("every fetch's window was placed")
            };
            let offset = at + (c.start - start);
            let Some((_, function)) =
                state.module.functions.iter_mut().find(|(_, f)| f.name.as_deref() == Some(fetch.function.as_str()))
            else {
                unreachable!("a fetch belongs to a finished function")
            };
            if offset == 0 {
                // entry = position: the call reads the position itself. The addition, now
                // unused, adds the literal to itself instead, so that it does not count as a
                // second use of the position (which a backend would then spell as a `let`).
                let Expression::Binary { left, .. } = function.expressions[fetch.add] else {
                    unreachable!("a fetch's entry is an addition")
                };
                replace_argument(&mut function.body, fetch.add, left);
                function.expressions[fetch.add] =
                    Expression::Binary { op: BinaryOperator::Add, left: fetch.offset, right: fetch.offset };
            } else {
                function.expressions[fetch.offset] = Expression::Literal(Literal::U32(offset));
            }
        }
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

/// A table's windows: (its place in the catalogue's buffer, its codes, [start, end) of each
/// window its fetches reach).
type TableWindows = (u32, &'static [u16], Vec<(u32, u32)>);

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

/// Replaces `from` by `to` among the arguments of every call in `block`, nested blocks included.
fn replace_argument(block: &mut naga::Block, from: Handle<Expression>, to: Handle<Expression>) {
    use naga::Statement as S;
    for statement in block.iter_mut() {
        match statement {
            S::Call { arguments, .. } => {
                for argument in arguments.iter_mut().filter(|a| **a == from) {
                    *argument = to;
                }
            }
            S::Block(inner) => replace_argument(inner, from, to),
            S::If { accept, reject, .. } => {
                replace_argument(accept, from, to);
                replace_argument(reject, from, to);
            }
            S::Loop { body, continuing, .. } => {
                replace_argument(body, from, to);
                replace_argument(continuing, from, to);
            }
            S::Switch { cases, .. } => cases.iter_mut().for_each(|c| replace_argument(&mut c.body, from, to)),
            _ => {}
        }
    }
}
