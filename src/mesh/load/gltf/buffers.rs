//! A glTF file's bytes: its buffers (a `.glb`'s own, `data:` URIs, files
//! beside it, each read only as far as it declares) and the typed reads of
//! accessors from them, every size and offset checked against the bytes
//! present.

use std::path::{Path, PathBuf};

use gltf::accessor::{DataType, Dimensions};

use super::super::{Extent, Referenced};
use crate::error::{Error, Result};

/// The bytes of every buffer, checked against their declared lengths.
pub(super) struct Buffers {
    pub(super) data: Vec<Vec<u8>>,
}

impl Buffers {
    pub(super) fn view<'b>(&'b self, view: &gltf::buffer::View) -> Result<&'b [u8], String> {
        let b = view.buffer().index();
        let data = self.data.get(b).ok_or_else(|| format!("buffer view {} uses missing buffer {b}", view.index()))?;
        let end = view.offset().checked_add(view.length());
        match end {
            Some(end) if end <= data.len() => Ok(&data[view.offset()..end]),
            _ => Err(format!(
                "buffer view {} covers bytes {}..{} of buffer {b}, which holds only {} bytes",
                view.index(),
                view.offset(),
                view.offset() as u128 + view.length() as u128,
                data.len()
            )),
        }
    }

    /// Every element of an accessor as `f64` components (normalised
    /// integers mapped to `[0, 1]` / `[−1, 1]`), with sparse substitution.
    /// Returns the numbers and the components per element. The error is a
    /// phrase to follow "accessor N".
    pub(super) fn read(&self, acc: &gltf::Accessor, max_count: usize) -> Result<(Vec<f64>, usize), String> {
        let dims = acc.dimensions();
        // Float 4×4 matrices (a skin's inverse bind matrices) have no column
        // padding; the smaller and integer ones, which nothing here reads, do.
        let float_mat4 = dims == Dimensions::Mat4 && acc.data_type() == DataType::F32;
        if matches!(dims, Dimensions::Mat2 | Dimensions::Mat3 | Dimensions::Mat4) && !float_mat4 {
            return Err("is a matrix other than float 4×4, which nothing here reads".into());
        }
        let comps = dims.multiplicity();
        let ctype = acc.data_type();
        let csize = ctype.size();
        let count = acc.count();
        let norm = acc.normalized();
        let elem = comps * csize;
        if count > max_count {
            return Err(format!("holds {count} elements, more than the {max_count} allowed here"));
        }
        let mut out;
        match acc.view() {
            Some(view) => {
                let bytes = self.view(&view)?;
                let stride = view.stride().unwrap_or(elem);
                if stride < elem {
                    return Err(format!(
                        "has elements of {elem} bytes but buffer view {} has a stride of {stride}",
                        view.index()
                    ));
                }
                let needed = if count == 0 {
                    Some(0)
                } else {
                    (count - 1)
                        .checked_mul(stride)
                        .and_then(|x| x.checked_add(acc.offset()))
                        .and_then(|x| x.checked_add(elem))
                };
                match needed {
                    Some(n) if n <= bytes.len() => {}
                    _ => {
                        return Err(format!(
                            "reaches past the end of buffer view {} ({count} elements of {elem} bytes from offset {} need {} bytes; the view has {})",
                            view.index(),
                            acc.offset(),
                            (count.max(1) as u128 - 1) * stride as u128 + acc.offset() as u128 + elem as u128,
                            bytes.len()
                        ));
                    }
                }
                out = Vec::with_capacity(count * comps);
                for i in 0..count {
                    let base = acc.offset() + i * stride;
                    for c in 0..comps {
                        let o = base + c * csize;
                        out.push(component(&bytes[o..o + csize], ctype, norm));
                    }
                }
            }
            None => {
                // No bytes bound the size of an all-zero (sparse) accessor.
                let cap = max_count.min(1 << 24);
                if count > cap {
                    return Err(format!(
                        "has no buffer view and {count} elements, more than the {cap} allowed without one"
                    ));
                }
                out = vec![0.0; count * comps];
            }
        }
        if let Some(sparse) = acc.sparse() {
            let n = sparse.count();
            let ind = sparse.indices();
            let ibytes = self.view(&ind.view())?;
            let isize = match ind.index_type() {
                gltf::accessor::sparse::IndexType::U8 => 1,
                gltf::accessor::sparse::IndexType::U16 => 2,
                gltf::accessor::sparse::IndexType::U32 => 4,
            };
            let vals = sparse.values();
            let vbytes = self.view(&vals.view())?;
            let ineed = n.checked_mul(isize).and_then(|x| x.checked_add(ind.offset()));
            let vneed = n.checked_mul(elem).and_then(|x| x.checked_add(vals.offset()));
            if !ineed.is_some_and(|x| x <= ibytes.len()) || !vneed.is_some_and(|x| x <= vbytes.len()) {
                return Err(format!("has {n} sparse values that reach past the end of their buffer views"));
            }
            for k in 0..n {
                let o = ind.offset() + k * isize;
                let idx = match isize {
                    1 => ibytes[o] as usize,
                    2 => u16::from_le_bytes([ibytes[o], ibytes[o + 1]]) as usize,
                    _ => u32::from_le_bytes([ibytes[o], ibytes[o + 1], ibytes[o + 2], ibytes[o + 3]]) as usize,
                };
                if idx >= count {
                    return Err(format!("has sparse index {idx} at position {k}, but only {count} elements"));
                }
                for c in 0..comps {
                    let o = vals.offset() + k * elem + c * csize;
                    out[idx * comps + c] = component(&vbytes[o..o + csize], ctype, norm);
                }
            }
        }
        Ok((out, comps))
    }
}

pub(super) fn component(b: &[u8], t: DataType, norm: bool) -> f64 {
    match t {
        DataType::I8 => {
            let v = b[0] as i8 as f64;
            if norm {
                (v / 127.0).max(-1.0)
            } else {
                v
            }
        }
        DataType::U8 => {
            let v = b[0] as f64;
            if norm {
                v / 255.0
            } else {
                v
            }
        }
        DataType::I16 => {
            let v = i16::from_le_bytes([b[0], b[1]]) as f64;
            if norm {
                (v / 32767.0).max(-1.0)
            } else {
                v
            }
        }
        DataType::U16 => {
            let v = u16::from_le_bytes([b[0], b[1]]) as f64;
            if norm {
                v / 65535.0
            } else {
                v
            }
        }
        DataType::U32 => {
            let v = u32::from_le_bytes([b[0], b[1], b[2], b[3]]) as f64;
            if norm {
                v / 4294967295.0
            } else {
                v
            }
        }
        DataType::F32 => f32::from_le_bytes([b[0], b[1], b[2], b[3]]) as f64,
    }
}

/// Decode a `data:` URI's payload (base64 or percent-encoded).
pub(super) fn data_uri(uri: &str) -> Option<Result<Vec<u8>, String>> {
    let rest = uri.strip_prefix("data:")?;
    let Some((meta, payload)) = rest.split_once(',') else {
        return Some(Err("is a data: URI without a ',' before its payload".into()));
    };
    if meta.ends_with(";base64") {
        Some(base64(payload).ok_or_else(|| "is a data: URI whose base64 payload is malformed".to_string()))
    } else {
        Some(Ok(percent_decode(payload).into_bytes()))
    }
}

pub(super) fn base64(s: &str) -> Option<Vec<u8>> {
    let mut out = Vec::with_capacity(s.len() / 4 * 3);
    let mut acc = 0u32;
    let mut bits = 0;
    for c in s.bytes() {
        let v = match c {
            b'A'..=b'Z' => c - b'A',
            b'a'..=b'z' => c - b'a' + 26,
            b'0'..=b'9' => c - b'0' + 52,
            b'+' | b'-' => 62,
            b'/' | b'_' => 63,
            b'=' => break,
            b' ' | b'\n' | b'\r' | b'\t' => continue,
            _ => return None,
        };
        acc = (acc << 6) | v as u32;
        bits += 6;
        if bits >= 8 {
            bits -= 8;
            out.push((acc >> bits) as u8);
            acc &= (1 << bits) - 1;
        }
    }
    Some(out)
}

pub(super) fn percent_decode(s: &str) -> String {
    let b = s.as_bytes();
    let mut out = Vec::with_capacity(b.len());
    let mut i = 0;
    while i < b.len() {
        if b[i] == b'%' && i + 2 < b.len() {
            let hex = |c: u8| (c as char).to_digit(16);
            if let (Some(h), Some(l)) = (hex(b[i + 1]), hex(b[i + 2])) {
                out.push((h * 16 + l) as u8);
                i += 3;
                continue;
            }
        }
        out.push(b[i]);
        i += 1;
    }
    String::from_utf8_lossy(&out).into_owned()
}

/// Read a file a glTF URI names, relative to the glTF's folder, as far as
/// `extent` says (a buffer: the bytes it declares).
pub(super) fn read_uri(dir: &Path, uri: &str, files: &mut Referenced, extent: Extent) -> Result<Vec<u8>, String> {
    if let Some(r) = data_uri(uri) {
        return r;
    }
    if uri.contains("://") {
        return Err(format!("is at \"{uri}\", which is not a local file"));
    }
    let rel = percent_decode(uri);
    let p: PathBuf = super::super::resolve_file(dir, &rel).unwrap_or_else(|| dir.join(&rel));
    files.read(&p, extent).map_err(|e| format!("cannot be read: {e}"))
}

/// The bytes of every buffer (the GLB binary chunk, a data URI or a file
/// beside `path`), each at least as long as it declares.
pub(super) fn read_buffers(path: &Path, dir: &Path, g: &gltf::Gltf, files: &mut Referenced) -> Result<Vec<Vec<u8>>> {
    let mut data = Vec::new();
    for b in g.document.buffers() {
        let d = match b.source() {
            gltf::buffer::Source::Bin => g.blob.clone().ok_or_else(|| {
                Error::scene(
                    path,
                    format!("buffer {} refers to the GLB binary chunk, but the file has none", b.index()),
                )
            })?,
            gltf::buffer::Source::Uri(uri) => read_uri(dir, uri, files, Extent::Declared(b.length() as u64))
                .map_err(|e| Error::scene(path, format!("buffer {} {e}", b.index())))?,
        };
        if d.len() < b.length() {
            return Err(Error::scene(
                path,
                format!("buffer {} declares {} bytes but holds only {}", b.index(), b.length(), d.len()),
            ));
        }
        data.push(d);
    }
    Ok(data)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn base64_and_percent() {
        assert_eq!(base64("aGVsbG8=").unwrap(), b"hello");
        assert_eq!(percent_decode("a%20b%zz%"), "a b%zz%");
    }
}
