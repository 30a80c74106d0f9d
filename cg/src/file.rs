//! Java 3D's `.cg` resource files (`CompressedGeometryFile`), big-endian
//! throughout:
//!
//! | offset | size | field |
//! | --- | --- | --- |
//! | 0 | 4 | magic `0xBADDFAB4` |
//! | 4, 8, 12 | 4 each | version major, minor, minor-minor |
//! | 16 | 4 | object count |
//! | 20 | 4 | 0 |
//! | 24 | 8 | directory offset |
//!
//! From offset 32, each object is an 8-byte block header (stream size in
//! bytes; descriptor: bits 0–1 type 1 point / 2 line / 3 triangle, 0x04
//! normals, 0x08 colours, 0x10 alpha) and the stream. The directory, at an
//! 8-byte aligned offset after the last object, holds one 64-bit offset per
//! object. No bounds are stored; every object takes the file's version.
//!
//! This is the layout Java 3D 1.5.2's
//! `com.sun.j3d.utils.geometry.compression.CompressedGeometryFile` reads
//! and writes; Java 3D documents it only in that class's source.
//!
//! Writing a file is left to the caller: [`CgFile::to_bytes`] gives the
//! bytes, and how they reach the disk (a temporary file renamed into place,
//! what happens on an interrupt) is the application's output discipline,
//! not the codec's.

use std::path::Path;

use super::{decode, BlockKind, CgHeader, Decoded, Encoded};
use crate::error::{Error, FileProblem, Result};

/// `CompressedGeometryFile.MAGIC_NUMBER`.
pub const MAGIC: u32 = 0xBADD_FAB4;

/// One object of a `.cg` file.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct CgObject {
    /// Type and data present (version: the file's).
    pub header: CgHeader,
    /// The compressed stream.
    pub bytes: Vec<u8>,
}

/// A whole `.cg` file.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct CgFile {
    /// File version (major, minor, minor-minor).
    pub version: [u32; 3],
    /// The objects in directory order.
    pub objects: Vec<CgObject>,
}

fn be32(b: &[u8], at: usize) -> Option<u32> {
    b.get(at..at.checked_add(4)?).map(|s| u32::from_be_bytes([s[0], s[1], s[2], s[3]]))
}

fn be64(b: &[u8], at: usize) -> Option<u64> {
    let s = b.get(at..at.checked_add(8)?)?;
    let mut a = [0u8; 8];
    a.copy_from_slice(s);
    Some(u64::from_be_bytes(a))
}

impl CgFile {
    /// Parse a `.cg` file's bytes; `path` names it in errors. Checks the
    /// magic, that the directory and every object lie inside the file, in
    /// order, and that each stream fits its object. Safe on untrusted input:
    /// nothing is allocated before the sizes are checked against the file's.
    pub fn parse(bytes: &[u8], path: &Path) -> Result<CgFile> {
        let bad = |problem: FileProblem| Error::File { path: path.to_path_buf(), problem };
        let short = || bad(FileProblem::TooShort { bytes: bytes.len() });
        let magic = be32(bytes, 0).ok_or_else(short)?;
        if magic != MAGIC {
            return Err(bad(FileProblem::BadMagic { magic }));
        }
        let version =
            [be32(bytes, 4).ok_or_else(short)?, be32(bytes, 8).ok_or_else(short)?, be32(bytes, 12).ok_or_else(short)?];
        let count = be32(bytes, 16).ok_or_else(short)? as usize;
        let directory = be64(bytes, 24).ok_or_else(short)?;
        let len = bytes.len() as u64;
        let dir_end = (count as u64).checked_mul(8).and_then(|n| n.checked_add(directory));
        if directory < 32 || dir_end.map_or(true, |e| e > len) {
            return Err(bad(FileProblem::DirectoryOutside { objects: count, offset: directory, bytes: len }));
        }
        let offsets: Vec<u64> =
            (0..count).map(|i| be64(bytes, directory as usize + 8 * i).unwrap_or(u64::MAX)).collect();
        let mut objects = Vec::with_capacity(count);
        for (i, &start) in offsets.iter().enumerate() {
            let end = offsets.get(i + 1).copied().unwrap_or(directory);
            if start < 32 || end > directory || start.saturating_add(8) > end {
                return Err(bad(FileProblem::ObjectOutside { object: i, offset: start, end }));
            }
            let start = start as usize;
            let size = be32(bytes, start).unwrap_or(0) as u64;
            let descriptor = be32(bytes, start + 4).unwrap_or(0);
            let room = end - start as u64 - 8;
            let outside = FileProblem::StreamOutside { object: i, size, room };
            if size > room {
                return Err(bad(outside));
            }
            let kind = match descriptor & 3 {
                1 => BlockKind::Points,
                2 => BlockKind::Lines,
                3 => BlockKind::Triangles,
                _ => return Err(bad(FileProblem::NoPrimitive { object: i })),
            };
            let header = CgHeader {
                kind,
                normals: descriptor & 0x04 != 0,
                colors: descriptor & 0x08 != 0,
                alpha: descriptor & 0x10 != 0,
                version,
            };
            // Inside the file by the checks above; `get` rather than indexing, so no input can panic here.
            let data = bytes.get(start + 8..start + 8 + size as usize).ok_or_else(|| bad(outside))?;
            objects.push(CgObject { header, bytes: data.to_vec() });
        }
        Ok(CgFile { version, objects })
    }

    /// The file's bytes, as Java 3D writes them: objects from offset 32,
    /// zero padding to 8 bytes, the directory; the version is the highest of
    /// 1.0.0 and the objects' versions.
    pub fn to_bytes(&self) -> Vec<u8> {
        let version = self.objects.iter().map(|o| o.header.version).fold(self.version.max([1, 0, 0]), |a, b| a.max(b));
        let mut out = vec![0u8; 32];
        let mut offsets = Vec::with_capacity(self.objects.len());
        for o in &self.objects {
            offsets.push(out.len() as u64);
            let kind = match o.header.kind {
                BlockKind::Points => 1u32,
                BlockKind::Lines => 2,
                BlockKind::Triangles => 3,
            };
            let descriptor = kind
                | (u32::from(o.header.normals) << 2)
                | (u32::from(o.header.colors) << 3)
                | (u32::from(o.header.alpha) << 4);
            out.extend_from_slice(&(o.bytes.len() as u32).to_be_bytes());
            out.extend_from_slice(&descriptor.to_be_bytes());
            out.extend_from_slice(&o.bytes);
        }
        while out.len() % 8 != 0 {
            out.push(0);
        }
        let directory = out.len() as u64;
        for off in offsets {
            out.extend_from_slice(&off.to_be_bytes());
        }
        out[0..4].copy_from_slice(&MAGIC.to_be_bytes());
        for (k, v) in version.iter().enumerate() {
            out[4 + 4 * k..8 + 4 * k].copy_from_slice(&v.to_be_bytes());
        }
        out[16..20].copy_from_slice(&(self.objects.len() as u32).to_be_bytes());
        out[24..32].copy_from_slice(&directory.to_be_bytes());
        out
    }

    /// Read a `.cg` file.
    pub fn read(path: &Path) -> Result<CgFile> {
        let bytes = std::fs::read(path).map_err(|source| Error::Io { path: path.to_path_buf(), source })?;
        CgFile::parse(&bytes, path)
    }

    /// A one-object file holding `encoded`'s stream, at its version (the
    /// centre and scale, which no `.cg` file stores, are left out).
    pub fn from_encoded(encoded: &Encoded) -> CgFile {
        CgFile {
            version: encoded.header.version,
            objects: vec![CgObject { header: encoded.header, bytes: encoded.bytes.clone() }],
        }
    }
}

/// Read a `.cg` file and decode every object as Java 3D does
/// ([`super::decode`]): triangles in Java's normalised frame and order.
/// Errors name the file and the object.
pub fn read_cg_file(path: &Path) -> Result<Vec<Decoded>> {
    let file = CgFile::read(path)?;
    file.objects
        .iter()
        .enumerate()
        .map(|(object, o)| {
            decode(&o.header, &o.bytes).map_err(|e| Error::Object {
                path: path.to_path_buf(),
                object,
                source: Box::new(e),
            })
        })
        .collect()
}
