//! The chunk layout every part of a HoloFlick shares (spec §3.1): a
//! four-letter tag, a little-endian u32 payload length, the payload, zero
//! padding to a multiple of 8; and the reader over untrusted bytes that the
//! decoders use. Below both the codec (`codec.rs`) and the checksums
//! (`checksum.rs`), which write and read chunks alike.

use super::error::{invalid, Problem};
use super::model::Matrix4;

/// Bytes of a chunk header: tag and little-endian u32 payload length.
pub(crate) const CHUNK_HEADER: usize = 8;

/// Zero bytes that follow a payload of `len` bytes (spec §3.1).
pub(crate) fn padding(len: u64) -> u64 {
    (8 - len % 8) % 8
}

pub(crate) fn is_critical(tag: [u8; 4]) -> bool {
    tag[0].is_ascii_uppercase()
}

/// A chunk: its tag and payload.
pub(crate) type Chunk<'a> = ([u8; 4], &'a [u8]);

/// A reader over untrusted bytes.
pub(crate) struct Cursor<'a> {
    data: &'a [u8],
    pos: usize,
}

impl<'a> Cursor<'a> {
    pub(crate) fn new(data: &'a [u8]) -> Self {
        Cursor { data, pos: 0 }
    }

    pub(crate) fn remaining(&self) -> usize {
        self.data.len() - self.pos
    }

    pub(crate) fn take(&mut self, n: usize, what: &str) -> Result<&'a [u8], Problem> {
        if n > self.remaining() {
            return Err(Problem::Truncated(format!("{what} needs {n} bytes, {} left", self.remaining())));
        }
        let s = &self.data[self.pos..self.pos + n];
        self.pos += n;
        Ok(s)
    }

    pub(crate) fn array<const N: usize>(&mut self, what: &str) -> Result<[u8; N], Problem> {
        let s = self.take(N, what)?;
        let mut a = [0u8; N];
        a.copy_from_slice(s);
        Ok(a)
    }

    pub(crate) fn u32(&mut self, what: &str) -> Result<u32, Problem> {
        Ok(u32::from_le_bytes(self.array(what)?))
    }

    pub(crate) fn f64(&mut self, what: &str) -> Result<f64, Problem> {
        Ok(f64::from_le_bytes(self.array(what)?))
    }

    pub(crate) fn vec3(&mut self, what: &str) -> Result<[f64; 3], Problem> {
        Ok([self.f64(what)?, self.f64(what)?, self.f64(what)?])
    }

    pub(crate) fn matrix(&mut self, what: &str) -> Result<Matrix4, Problem> {
        let mut m = [[0.0; 4]; 4];
        for row in m.iter_mut() {
            for x in row.iter_mut() {
                *x = self.f64(what)?;
            }
        }
        Ok(m)
    }

    /// The next chunk (tag, payload) and its padding, or `None` at the end.
    pub(crate) fn chunk(&mut self) -> Result<Option<Chunk<'a>>, Problem> {
        if self.remaining() == 0 {
            return Ok(None);
        }
        let tag: [u8; 4] = self.array("a chunk header")?;
        check_tag(tag)?;
        let len = self.u32("a chunk header")? as usize;
        let payload = self.take(len, &format!("chunk {:?}", super::error::tag_text(tag)))?;
        let pad = padding(len as u64) as usize;
        self.take(pad, "chunk padding")?;
        Ok(Some((tag, payload)))
    }
}

/// A tag is four ASCII letters (spec §3.1).
pub(crate) fn check_tag(tag: [u8; 4]) -> Result<(), Problem> {
    if tag.iter().all(u8::is_ascii_alphabetic) {
        Ok(())
    } else {
        Err(invalid(format!("chunk tag {:?} is not four ASCII letters", super::error::tag_text(tag))))
    }
}

/// Append a chunk with its padding.
pub(crate) fn put_chunk(out: &mut Vec<u8>, tag: [u8; 4], payload: &[u8]) {
    out.extend_from_slice(&tag);
    out.extend_from_slice(&(payload.len() as u32).to_le_bytes());
    out.extend_from_slice(payload);
    out.resize(out.len() + padding(payload.len() as u64) as usize, 0);
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn chunks_are_padded_to_8() {
        for len in 0..20 {
            let mut out = Vec::new();
            put_chunk(&mut out, *b"test", &vec![1; len]);
            assert_eq!(out.len() % 8, 0);
            assert_eq!(out.len(), CHUNK_HEADER + len + padding(len as u64) as usize);
        }
    }
}
