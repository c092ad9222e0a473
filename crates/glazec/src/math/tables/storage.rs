//! How the tables are stored: 16-bit fixed point over each table's range ([`Quantization`]), the
//! table file compiled into the crate (`crates/glazec/data/tables.bin`), and the buffer a shader
//! reads.

use std::sync::{Arc, OnceLock};

use super::catalogue::{Rounding, SPECS, TableId, TableSpec};

/// A table's 16-bit encoding: value = offset + scale·u.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Quantization {
    pub offset: f32,
    pub scale: f32,
}

impl Quantization {
    /// The encoding that spans `values` (a constant table gets scale 1).
    pub fn spanning(values: &[f32]) -> Quantization {
        let lo = values.iter().copied().fold(f32::INFINITY, f32::min);
        let hi = values.iter().copied().fold(f32::NEG_INFINITY, f32::max);
        let scale = if hi > lo { (hi - lo) / 65_535.0 } else { 1.0 };
        Quantization { offset: lo, scale }
    }

    /// The value of code `u`, in the f32 arithmetic a shader uses.
    pub fn decode(self, u: u16) -> f32 {
        f32::from(u) * self.scale + self.offset
    }

    /// The code of `value`, rounded as asked and clamped to the codes: the code whose decoded
    /// value is nearest, or the largest whose decoded value is not above `value` (judged by
    /// [`Self::decode`] itself, so that decoding and encoding again gives the same code).
    pub fn encode(self, value: f32, rounding: Rounding) -> u16 {
        let guess = ((value - self.offset) / self.scale).floor().clamp(0.0, 65_535.0) as u16;
        let candidates = [guess.saturating_sub(1), guess, guess.saturating_add(1)];
        match rounding {
            Rounding::Nearest => candidates
                .into_iter()
                .min_by(|&a, &b| (self.decode(a) - value).abs().total_cmp(&(self.decode(b) - value).abs()))
                .unwrap_or(guess),
            Rounding::Down => candidates.into_iter().rev().find(|&c| self.decode(c) <= value).unwrap_or(candidates[0]),
        }
    }
}

impl TableId {
    /// The table's values (compiled into the crate from `crates/glazec/data/tables.bin`), decoded.
    pub fn values(self) -> &'static Arc<[f32]> {
        &stored()[self as usize].values
    }

    /// The table's 16-bit codes, as stored.
    pub fn codes(self) -> &'static [u16] {
        &stored()[self as usize].codes
    }

    /// The table's encoding.
    pub fn quantization(self) -> Quantization {
        stored()[self as usize].quantization
    }

    /// Where the table starts in [`buffer`], in entries (16-bit codes).
    pub fn buffer_offset(self) -> u32 {
        TableId::ALL.iter().take_while(|&&id| id != self).map(|id| id.spec().len() as u32).sum()
    }
}

/// Every table's 16-bit codes, concatenated in [`SPECS`] order, two to a 32-bit word (entry i in
/// the low half of word i / 2 when i is even, the high half when odd), padded with zeros to whole
/// `vec4<u32>` elements: the contents of the table buffer a shader binds when a lookup has an
/// argument known only at run time (`crate::lower::bindings`). A shader decodes entry i of table
/// t as offset_t + scale_t·u ([`TableId::quantization`], literals in its lookup function).
pub fn buffer() -> Vec<u32> {
    let codes: Vec<u16> = TableId::ALL.iter().flat_map(|id| id.codes().iter().copied()).collect();
    let mut words: Vec<u32> =
        codes.chunks(2).map(|pair| u32::from(pair[0]) | u32::from(pair.get(1).copied().unwrap_or(0)) << 16).collect();
    words.resize(4 * buffer_vec4s(), 0);
    words
}

/// Entries (16-bit codes) of [`buffer`], without its padding.
pub fn buffer_len() -> usize {
    SPECS.iter().map(TableSpec::len).sum()
}

/// `vec4<u32>` elements of [`buffer`] (eight entries each).
pub fn buffer_vec4s() -> usize {
    buffer_len().div_ceil(8)
}

/// The table file, compiled in.
pub(super) const TABLE_FILE: &[u8] = include_bytes!("../../../data/tables.bin");

const MAGIC: &[u8; 8] = b"GLAZTAB2";

/// One stored table.
struct Stored {
    codes: Vec<u16>,
    quantization: Quantization,
    values: Arc<[f32]>,
}

/// Tables that replace the compiled-in ones on the CPU ([`evaluate_on_cpu_with`]); null: none.
static OVERRIDE: std::sync::atomic::AtomicPtr<Vec<Stored>> = std::sync::atomic::AtomicPtr::new(std::ptr::null_mut());

/// Makes every CPU evaluation in this process read `tables` (values per table, in [`SPECS`]
/// order, stored as [`encode`] would store them) instead of the compiled-in file. For
/// `glazec tables`, whose later tables are defined through the compiled math evaluated with the
/// tables it has just computed (`glazec_lab::bake`); shaders are not affected. Each call leaks
/// its tables (a few tens of kilobytes, a handful of times per generation).
pub fn evaluate_on_cpu_with(tables: &[Vec<f32>]) {
    let stored: Vec<Stored> = SPECS
        .iter()
        .zip(tables)
        .map(|(spec, values)| {
            let quantization = Quantization::spanning(values);
            let codes: Vec<u16> = values.iter().map(|&v| quantization.encode(v, spec.rounding)).collect();
            let values = codes.iter().map(|&u| quantization.decode(u)).collect();
            Stored { codes, quantization, values }
        })
        .collect();
    OVERRIDE.store(Box::into_raw(Box::new(stored)), std::sync::atomic::Ordering::Release);
}

/// Which tables the CPU reads: changes when [`evaluate_on_cpu_with`] replaces them (for caches of
/// values derived from them).
pub(super) fn generation() -> usize {
    OVERRIDE.load(std::sync::atomic::Ordering::Acquire) as usize
}

fn stored() -> &'static [Stored] {
    let replaced = OVERRIDE.load(std::sync::atomic::Ordering::Acquire);
    if !replaced.is_null() {
        // SAFETY: set only by `evaluate_on_cpu_with` from a leaked box, never freed.
        return unsafe { &*replaced };
    }
    static TABLES: OnceLock<Vec<Stored>> = OnceLock::new();
    TABLES.get_or_init(|| match decode_codes(TABLE_FILE) {
        Ok(tables) => tables
            .into_iter()
            .map(|(quantization, codes)| {
                let values = codes.iter().map(|&u| quantization.decode(u)).collect();
                Stored { codes, quantization, values }
            })
            .collect(),
        // The file ships with the crate and a test decodes it; a mismatch is a build of
        // inconsistent sources, not bad user input.
        Err(e) => panic!("crates/glazec/data/tables.bin does not match the table layout ({e}); run `glazec tables`"),
    })
}

/// The table file: magic, table count, then per table its name (u8 length + UTF-8), its entry
/// count (u32), its encoding's offset and scale (f32) and its codes (u16, rounded as its spec
/// says), all little-endian, in [`SPECS`] order.
pub fn encode(tables: &[Vec<f32>]) -> Vec<u8> {
    let mut bytes = MAGIC.to_vec();
    bytes.extend_from_slice(&(tables.len() as u32).to_le_bytes());
    for (spec, values) in SPECS.iter().zip(tables) {
        let q = Quantization::spanning(values);
        bytes.push(spec.name.len() as u8);
        bytes.extend_from_slice(spec.name.as_bytes());
        bytes.extend_from_slice(&(values.len() as u32).to_le_bytes());
        bytes.extend_from_slice(&q.offset.to_le_bytes());
        bytes.extend_from_slice(&q.scale.to_le_bytes());
        for &v in values {
            bytes.extend_from_slice(&q.encode(v, spec.rounding).to_le_bytes());
        }
    }
    bytes
}

/// Reads a table file, checking it against [`SPECS`]: the decoded values.
pub fn decode(bytes: &[u8]) -> Result<Vec<Vec<f32>>, String> {
    Ok(decode_codes(bytes)?.into_iter().map(|(q, codes)| codes.iter().map(|&u| q.decode(u)).collect()).collect())
}

/// Reads the tables a table file holds by name, whatever its layout: for every table of [`SPECS`],
/// its decoded values if the file has a table of that name and size (`glazec tables
/// --glossy-only` keeps the others of an existing file).
pub fn decode_by_name(bytes: &[u8]) -> Vec<Option<Vec<f32>>> {
    let mut found: Vec<Option<Vec<f32>>> = vec![None; SPECS.len()];
    let mut at = 12;
    let word = |b: &[u8]| u32::from_le_bytes([b[0], b[1], b[2], b[3]]);
    if bytes.get(..8) != Some(MAGIC.as_slice()) {
        return found;
    }
    while at < bytes.len() {
        let Some(&name_len) = bytes.get(at) else { break };
        let Some(name) = bytes.get(at + 1..at + 1 + name_len as usize) else { break };
        at += 1 + name_len as usize;
        let Some(header) = bytes.get(at..at + 12) else { break };
        let (len, offset, scale) =
            (word(header) as usize, f32::from_bits(word(&header[4..])), f32::from_bits(word(&header[8..])));
        at += 12;
        let Some(codes) = bytes.get(at..at + 2 * len) else { break };
        at += 2 * len;
        let q = Quantization { offset, scale };
        let values: Vec<f32> = codes.chunks_exact(2).map(|c| q.decode(u16::from_le_bytes([c[0], c[1]]))).collect();
        if let Some(i) = SPECS.iter().position(|spec| spec.name.as_bytes() == name && spec.len() == len) {
            found[i] = Some(values);
        }
    }
    found
}

/// Reads a table file: each table's encoding and codes.
fn decode_codes(bytes: &[u8]) -> Result<Vec<(Quantization, Vec<u16>)>, String> {
    let mut at = 0;
    let mut take = |n: usize| -> Result<&[u8], String> {
        let s = bytes.get(at..at + n).ok_or("truncated")?;
        at += n;
        Ok(s)
    };
    if take(8)? != MAGIC {
        return Err("not a glazec table file (of this version)".into());
    }
    let word = |b: &[u8]| u32::from_le_bytes([b[0], b[1], b[2], b[3]]);
    if word(take(4)?) as usize != SPECS.len() {
        return Err("wrong table count".into());
    }
    let mut tables = Vec::new();
    for spec in &SPECS {
        let name_len = take(1)?[0] as usize;
        if take(name_len)? != spec.name.as_bytes() {
            return Err(format!("expected table {}", spec.name));
        }
        if word(take(4)?) as usize != spec.len() {
            return Err(format!("{} has the wrong size", spec.name));
        }
        let offset = f32::from_bits(word(take(4)?));
        let scale = f32::from_bits(word(take(4)?));
        let codes = take(2 * spec.len())?.chunks_exact(2).map(|c| u16::from_le_bytes([c[0], c[1]])).collect();
        tables.push((Quantization { offset, scale }, codes));
    }
    if at != bytes.len() {
        return Err("trailing bytes".into());
    }
    Ok(tables)
}

/// Bytes of table data compiled into the crate (two per entry).
pub fn total_bytes() -> usize {
    SPECS.iter().map(|s| 2 * s.len()).sum()
}
