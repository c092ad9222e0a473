//! The table buffer in generated code: a material's own uniform of the table entries it can
//! read (named `<material>_tables` once `lower` namespaces the module) and the function that
//! reads one 16-bit code out of it. The buffer holds only the windows of the tables that the
//! material's lookups can reach (a lookup whose roughness and IOR are literals reaches one
//! slice per interpolation corner: 4 × 16 entries of a 2,048-entry table), in order of first
//! use, so that it stays small: inside the 16 KiB that wgpu's downlevel limits and WebGL2
//! guarantee for a uniform binding.

use naga::{
    BinaryOperator, Expression, Function, FunctionArgument, FunctionResult, Handle, Literal, Scalar as NagaScalar,
    ScalarKind, Span, Statement, TypeInner, VectorSize,
};

use super::values::Expr;
use super::{ModuleBuilder, insert_type};
use crate::math::Real;
use crate::math::TableCodes;
use crate::math::tables::corner_sum;

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

    /// Multilinear interpolation of `table` in `cells` (per axis, the lower node's index and
    /// the upper node's weight; at least one known only at run time): the entry of the cell's
    /// lowest corner in the table buffer, then a call of the module's interpolation helper
    /// ([`Self::interpolation_function`]) with the strides between corners, the weights and the
    /// table's quantisation.
    ///
    /// The buffer holds a *block* for the lookup: the windows of the table that its corners can
    /// reach. Axes known only at run time span their whole range; a known axis adds its upper
    /// node to the window while that keeps the window contiguous in the table (its stride is at
    /// most the window's length), and otherwise the block repeats the window at the upper node
    /// (so a slice at literal roughness and IOR is 4 windows of the direction axis, not the
    /// table between them).
    pub(super) fn table_interpolation<'a>(&'a self, table: &TableCodes, cells: &[(Expr<'a>, Expr<'a>)]) -> Expr<'a> {
        let zero = self.constant(0.0);
        // The runtime part of the lowest corner's entry, Σ cell·stride over the runtime axes;
        // the known part, `start`; and the window that the runtime axes reach.
        let (mut index, mut start, mut window, mut stride) = (zero, 0u32, 1u32, 1u32);
        let mut table_strides = Vec::with_capacity(cells.len());
        for (&(i, _), &n) in cells.iter().zip(&table.nodes) {
            match i.known() {
                Some(cell) => start += cell as u32 * stride,
                None => {
                    index = index + i * stride as f32;
                    window += (n - 1) * stride;
                }
            }
            table_strides.push(stride);
            stride *= n;
        }
        // The whole window from the lowest corner to the highest, contiguous in the table.
        let contiguous = window
            + cells.iter().zip(&table_strides).filter(|((i, _), _)| i.known().is_some()).map(|(_, &s)| s).sum::<u32>();
        // The known axes, by increasing stride: contiguous in the window while they can be, then
        // repeating the block.
        let mut starts = vec![start];
        let mut strides = table_strides.clone();
        let mut repeated = Vec::new();
        for (axis, &(i, _)) in cells.iter().enumerate() {
            if i.known().is_none() {
                continue;
            }
            if starts.len() == 1 && table_strides[axis] <= window {
                window += table_strides[axis];
            } else {
                strides[axis] = starts.len() as u32 * window;
                repeated.push(axis);
                let upper: Vec<u32> = starts.iter().map(|s| s + table_strides[axis]).collect();
                starts.extend(upper);
            }
        }
        let position = self.append(Expression::As { expr: index.handle(), kind: ScalarKind::Uint, convert: Some(4) });
        let offset = self.append(Expression::Literal(Literal::U32(0)));
        let entry = self.append(Expression::Binary { op: BinaryOperator::Add, left: position, right: offset });
        let u32_literal = |x| self.append(Expression::Literal(Literal::U32(x)));
        let stride_literals: Vec<Handle<Expression>> = strides.into_iter().map(u32_literal).collect();
        {
            let mut state = self.state.borrow_mut();
            let function = state.stack.last().and_then(|f| f.function.name.clone()).unwrap_or_default();
            let block = super::TableBlock { table: table.buffer_offset, codes: table.codes, starts, window };
            let repeated = repeated.iter().map(|&axis| (stride_literals[axis], table_strides[axis])).collect();
            state.table_fetches.push(super::TableFetch { function, add: entry, offset, block, repeated, contiguous });
        }
        let vector = |components: Vec<Handle<Expression>>, scalar| match components.len() {
            1 => components[0],
            k => {
                let ty = axes_type(self, k, scalar);
                self.append(Expression::Compose { ty, components })
            }
        };
        let strides = vector(stride_literals, NagaScalar::U32);
        let weights = vector(cells.iter().map(|&(_, w)| w.handle()).collect(), NagaScalar::F32);
        let scale = self.constant(table.scale).handle();
        let offset = self.constant(table.offset).handle();
        let function = self.interpolation_function(cells.len());
        let value = self.call(function, vec![entry, strides, weights, scale, offset]);
        self.name(value, "value");
        self.scalar(value)
    }

    /// The module's interpolation helper for tables of `axes` axes (1 to 4), created on first
    /// use: `glazec_table_trilinear(corner: u32, strides: vec3<u32>, weights: vec3<f32>,
    /// scale: f32, offset: f32) -> f32` and its siblings `_linear` (scalars), `_bilinear` and
    /// `_quadrilinear`. It sums the corners of a cell whose lowest corner is entry `corner` of the
    /// table buffer, the corner one node up an axis `strides[axis]` entries further, each code
    /// decoded as scale·code + offset: the CPU's [`corner_sum`], term for term.
    fn interpolation_function(&self, axes: usize) -> Handle<Function> {
        const NAMES: [&str; 4] =
            ["glazec_table_linear", "glazec_table_bilinear", "glazec_table_trilinear", "glazec_table_quadrilinear"];
        let name = NAMES[axes - 1];
        if let Some(&f) = self.state.borrow().terms.get(name) {
            return f;
        }
        let vector = |scalar| axes_type(self, axes, scalar);
        let argument = |name: &str, ty| FunctionArgument { name: Some(name.to_string()), ty, binding: None };
        let arguments = vec![
            argument("corner", self.types.u32),
            argument("strides", vector(NagaScalar::U32)),
            argument("weights", vector(NagaScalar::F32)),
            argument("scale", self.types.f32),
            argument("offset", self.types.f32),
        ];
        let result = FunctionResult { ty: self.types.f32, binding: None };
        let code = self.table_code_function();
        self.begin_function(name, arguments, Some(result));
        let (lowest, strides, weights) = (self.argument(0), self.argument(1), self.argument(2));
        let (scale, offset) = (self.scalar(self.argument(3)), self.scalar(self.argument(4)));
        let component = |vector, axis: usize| match axes {
            1 => vector,
            _ => self.append(Expression::AccessIndex { base: vector, index: axis as u32 }),
        };
        let axis_strides: Vec<Handle<Expression>> = (0..axes).map(|a| component(strides, a)).collect();
        let axis_weights: Vec<Expr<'_>> = (0..axes).map(|a| self.scalar(component(weights, a))).collect();
        let total = corner_sum(&axis_weights, scale, offset, |corner| {
            // Corner names list the lower (l) or upper (u) node per axis, first axis first: `code_lul`.
            let corner_name: String = (0..axes).map(|a| if corner >> a & 1 == 1 { 'u' } else { 'l' }).collect();
            let mut at = lowest;
            for (axis, &stride) in axis_strides.iter().enumerate() {
                if corner >> axis & 1 == 1 {
                    at = self.append(Expression::Binary { op: BinaryOperator::Add, left: at, right: stride });
                }
            }
            let value = self.call(code, vec![at]);
            self.name(value, &format!("code_{corner_name}"));
            self.scalar(value)
        });
        self.statement(Statement::Return { value: Some(total.handle()) });
        let function = self.end_function();
        let doc = [
            "Multilinear interpolation in a table of the table buffer: the sum over the cell's corners",
            "of their values, scale·code + offset, each weighted by the product over the axes of the",
            "upper node's weight or one minus it. `corner` is the lowest corner's entry; one node up an axis",
            "is `strides` entries further.",
        ];
        let handle = self.add_function(function, &doc);
        self.state.borrow_mut().terms.insert(name, handle);
        handle
    }

    /// Lays the table buffer out and returns its contents, then gives every lookup its offset
    /// (a lookup at offset 0 reads its runtime position itself) and the buffer its final size.
    /// Empty when no lookup reads the buffer.
    ///
    /// A block of a single window shares the table's merged windows: per table, the windows
    /// such blocks reach, merged where they overlap or touch, one after another in order of
    /// first use (so a table's share is never more than the whole table). A block of repeated
    /// windows (a slice) follows once for every distinct block. Where that is larger than
    /// reading every slice's whole window from the lowest corner to the highest, contiguous in
    /// the table and merged with the others (the helper then stepping by the table's own
    /// strides), the buffer is laid out that way instead: it is then never more than the tables
    /// the material's method reads, all of which fit in [`MAX_UNIFORM_BYTES`].
    pub fn finish_tables(&self) -> Vec<u16> {
        let mut state = self.state.borrow_mut();
        let mut fetches = std::mem::take(&mut state.table_fetches);
        let (mut codes, mut offsets) = lay_out(&fetches);
        // The slices as contiguous windows instead, merged with the rest: kept if smaller.
        let contiguous: Vec<super::TableFetch> = fetches
            .iter()
            .map(|f| {
                let mut f = f.clone();
                f.block.starts.truncate(1);
                f.block.window = if f.repeated.is_empty() { f.block.window } else { f.contiguous };
                f
            })
            .collect();
        let (merged_codes, merged_offsets) = lay_out(&contiguous);
        if merged_codes.len() < codes.len() {
            for fetch in &fetches {
                for &(literal, stride) in &fetch.repeated {
                    set_literal(&mut state.module, &fetch.function, literal, stride);
                }
            }
            (codes, offsets, fetches) = (merged_codes, merged_offsets, contiguous);
        }
        for (fetch, offset) in fetches.iter().zip(offsets) {
            let Some((_, function)) =
                state.module.functions.iter_mut().find(|(_, f)| f.name.as_deref() == Some(fetch.function.as_str()))
            else {
                unreachable!("a lookup belongs to a finished function")
            };
            if offset == 0 {
                // entry = position: the call reads the position itself. The addition, now
                // unused, adds the literal to itself instead, so that it does not count as a
                // second use of the position (which a backend would then spell as a `let`).
                let Expression::Binary { left, .. } = function.expressions[fetch.add] else {
                    unreachable!("a lookup's entry is an addition")
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

/// The largest uniform binding WebGPU guarantees (`maxUniformBufferBindingSize`), in bytes: the
/// tables' budget per method.
pub use crate::math::tables::TABLE_BUDGET as MAX_UNIFORM_BYTES;

/// The buffer's codes for `fetches` and each fetch's offset (see
/// [`ModuleBuilder::finish_tables`]).
fn lay_out(fetches: &[super::TableFetch]) -> (Vec<u16>, Vec<u32>) {
    // Per table (by its place in the catalogue's buffer), the windows its single-window blocks
    // reach.
    let mut tables: Vec<TableWindows> = Vec::new();
    for fetch in fetches.iter().filter(|f| f.block.starts.len() == 1) {
        let b = &fetch.block;
        let window = (b.starts[0], b.starts[0] + b.window);
        match tables.iter_mut().find(|(table, ..)| *table == b.table) {
            Some((_, _, windows)) => windows.push(window),
            None => tables.push((b.table, b.codes, vec![window])),
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
    // Repeated-window blocks, each once.
    let mut repeated: Vec<(&super::TableBlock, u32)> = Vec::new();
    for fetch in fetches.iter().filter(|f| f.block.starts.len() > 1) {
        if repeated.iter().all(|(b, _)| **b != fetch.block) {
            repeated.push((&fetch.block, codes.len() as u32));
            for &start in &fetch.block.starts {
                let window = start as usize..((start + fetch.block.window) as usize).min(fetch.block.codes.len());
                codes.extend_from_slice(&fetch.block.codes[window]);
            }
        }
    }
    let offsets = fetches
        .iter()
        .map(|fetch| {
            let b = &fetch.block;
            if b.starts.len() == 1 {
                let Some(&(_, (start, _), at)) = placed
                    .iter()
                    .find(|(table, (start, end), _)| *table == b.table && *start <= b.starts[0] && b.starts[0] < *end)
                else {
                    unreachable!("every lookup's window was placed")
                };
                at + (b.starts[0] - start)
            } else {
                let Some(&(_, at)) = repeated.iter().find(|(placed, _)| *placed == b) else {
                    unreachable!("every lookup's block was placed")
                };
                at
            }
        })
        .collect();
    (codes, offsets)
}

/// Sets the `u32` literal `literal` of function `function` to `value`.
fn set_literal(module: &mut naga::Module, function: &str, literal: Handle<Expression>, value: u32) {
    let Some((_, f)) = module.functions.iter_mut().find(|(_, f)| f.name.as_deref() == Some(function)) else {
        unreachable!("a lookup belongs to a finished function")
    };
    f.expressions[literal] = Expression::Literal(Literal::U32(value));
}

/// A table's windows: (its place in the catalogue's buffer, its codes, [start, end) of each
/// window its fetches reach).
type TableWindows = (u32, &'static [u16], Vec<(u32, u32)>);

/// The type of one value per axis of a table of `axes` axes: `scalar` itself for one axis, a
/// vector of `axes` components for more.
fn axes_type(b: &ModuleBuilder, axes: usize, scalar: NagaScalar) -> Handle<naga::Type> {
    let inner = match axes {
        1 => TypeInner::Scalar(scalar),
        k => TypeInner::Vector { size: [VectorSize::Bi, VectorSize::Tri, VectorSize::Quad][k - 2], scalar },
    };
    b.with_module(|module| insert_type(module, None, inner))
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
