//! The GLB container (glTF 2.0 §4.4): a 12-byte header, a JSON chunk padded with spaces
//! and an optional BIN chunk padded with zeros, each to a multiple of 4 bytes.

const MAGIC: &[u8; 4] = b"glTF";
const JSON: &[u8; 4] = b"JSON";
const BIN: &[u8; 4] = b"BIN\0";

/// Wraps a JSON document and a binary buffer into a GLB file.
pub fn assemble(json: &[u8], bin: &[u8]) -> Vec<u8> {
    let pad = |n: usize| (4 - n % 4) % 4;
    let json_len = json.len() + pad(json.len());
    let bin_len = bin.len() + pad(bin.len());
    let mut total = 12 + 8 + json_len;
    if !bin.is_empty() {
        total += 8 + bin_len;
    }
    let mut out = Vec::with_capacity(total);
    out.extend_from_slice(MAGIC);
    out.extend_from_slice(&2u32.to_le_bytes());
    out.extend_from_slice(&(total as u32).to_le_bytes());
    out.extend_from_slice(&(json_len as u32).to_le_bytes());
    out.extend_from_slice(JSON);
    out.extend_from_slice(json);
    out.resize(out.len() + pad(json.len()), b' ');
    if !bin.is_empty() {
        out.extend_from_slice(&(bin_len as u32).to_le_bytes());
        out.extend_from_slice(BIN);
        out.extend_from_slice(bin);
        out.resize(out.len() + pad(bin.len()), 0);
    }
    out
}

/// Splits a GLB into its JSON text and BIN chunk (for tests and tools); `None` if `glb` is
/// not a well-formed GLB.
pub fn split(glb: &[u8]) -> Option<(&[u8], &[u8])> {
    let u32_at = |i: usize| -> Option<usize> {
        Some(u32::from_le_bytes(glb.get(i..i + 4)?.try_into().ok()?) as usize)
    };
    if glb.get(..4)? != MAGIC || u32_at(4)? != 2 || u32_at(8)? != glb.len() {
        return None;
    }
    let jl = u32_at(12)?;
    if glb.get(16..20)? != JSON {
        return None;
    }
    let json = glb.get(20..20 + jl)?;
    let rest = 20 + jl;
    if rest == glb.len() {
        return Some((json, &[]));
    }
    let bl = u32_at(rest)?;
    if glb.get(rest + 4..rest + 8)? != BIN {
        return None;
    }
    Some((json, glb.get(rest + 8..rest + 8 + bl)?))
}
