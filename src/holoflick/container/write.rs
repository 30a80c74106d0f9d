//! Writing HoloFlicks: frames added one at a time (memory holds one encoded
//! frame, 16 index bytes per frame and the object ids of key frames), written
//! to a temporary file beside the destination and renamed into place by
//! [`HoloFlickWriter::finish`]. Spec §4–§8.

use std::collections::HashMap;
use std::io::{Seek, SeekFrom, Write};
use std::path::{Path, PathBuf};

use crate::output::AtomicFile;

use super::checksum;
use super::chunk::put_chunk;
use super::codec;
use super::model::{text_problem, Frame, GeometryBlock, ObjectRecord};
use super::*;
use super::{At, ContainerError};

/// How to write.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct HoloFlickWriteOptions {
    /// Frame rate, numerator / denominator (frames per second); both non-zero.
    pub frames_per_second: (u32, u32),
    /// Text entries (`title`, `source`, `software`, ..., spec §5.2), keys unique.
    pub text: Vec<(String, String)>,
    /// Replace an existing file at the destination (default: refuse).
    pub overwrite: bool,
}

impl Default for HoloFlickWriteOptions {
    /// 24 frames per second, `software` = this library, never overwrite.
    fn default() -> Self {
        HoloFlickWriteOptions {
            frames_per_second: (24, 1),
            text: vec![("software".into(), format!("holo {}", env!("CARGO_PKG_VERSION")))],
            overwrite: false,
        }
    }
}

/// What a finished write did.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct WriteReport {
    /// The file written.
    pub path: PathBuf,
    /// Frames in it.
    pub frames: u32,
    /// Its size.
    pub file_bytes: u64,
}

/// A HoloFlick being written. Dropping it without [`finish`](Self::finish)
/// removes the temporary file and leaves the destination untouched.
#[derive(Debug)]
pub struct HoloFlickWriter {
    path: PathBuf,
    overwrite: bool,
    out: AtomicFile,
    position: u64,
    index: Vec<(u64, u32, u32)>,
    /// Key frame → (object id → bytes of its geometry record).
    key_frames: HashMap<u32, HashMap<u32, u64>>,
}

impl HoloFlickWriter {
    /// Start a HoloFlick at `path`: refuses an existing file unless
    /// `options.overwrite`, and bad options.
    pub fn create(path: impl AsRef<Path>, options: &HoloFlickWriteOptions) -> Result<HoloFlickWriter> {
        let path = path.as_ref();
        let usage = |problem: String| ContainerError::Unstorable { path: path.to_path_buf(), problem };
        let (num, den) = options.frames_per_second;
        if num == 0 || den == 0 {
            return Err(usage(format!("frame rate {num}/{den}: numerator and denominator must be non-zero")));
        }
        if options.text.len() as u64 > MAX_TEXT_ENTRIES {
            return Err(usage(format!("{} text entries; at most {MAX_TEXT_ENTRIES}", options.text.len())));
        }
        for (i, (key, value)) in options.text.iter().enumerate() {
            if let Some(p) = text_problem(key, value) {
                return Err(usage(p));
            }
            if options.text[..i].iter().any(|(k, _)| k == key) {
                return Err(usage(format!("text key {key:?} given twice")));
            }
            if (key.len() + 1 + value.len()) as u64 > MAX_TEXT_BYTES {
                return Err(usage(format!("text {key:?} is longer than {MAX_TEXT_BYTES} bytes")));
            }
        }
        if !options.overwrite && path.exists() {
            return Err(ContainerError::Output {
                path: path.to_path_buf(),
                problem: crate::error::OutputProblem::Exists,
            });
        }
        let out = AtomicFile::create(path).map_err(|e| ContainerError::from_output(path, e))?;

        let mut head = Vec::with_capacity(256);
        head.extend_from_slice(&MAGIC);
        head.extend_from_slice(&VERSION_MAJOR.to_le_bytes());
        head.extend_from_slice(&VERSION_MINOR.to_le_bytes());
        head.extend_from_slice(&[0; 4]); // the index's checksum, set by finish
        head.extend_from_slice(&[0; 8]); // index offset, set by finish
        head.extend_from_slice(&[0; 4]); // frame count, set by finish
        head.extend_from_slice(&[0; 4]); // the file-level chunks' checksum, below
        put_chunk(&mut head, *b"HEAD", &codec::encode_head(options.frames_per_second));
        for (key, value) in &options.text {
            put_chunk(&mut head, *b"text", &codec::encode_text(key, value));
        }
        let file_chunks_sum = checksum::crc32(&head[FILE_HEADER_BYTES as usize..]);
        head[28..32].copy_from_slice(&file_chunks_sum.to_le_bytes());
        let mut writer = HoloFlickWriter {
            path: path.to_path_buf(),
            overwrite: options.overwrite,
            out,
            position: 0,
            index: Vec::new(),
            key_frames: HashMap::new(),
        };
        writer.put(&head)?;
        Ok(writer)
    }

    /// Frames added so far.
    pub fn frame_count(&self) -> u32 {
        self.index.len() as u32
    }

    /// Append the next frame and return its number. The frame must follow
    /// every rule of spec §6 (the reader's own checks); a reference must name
    /// an object stored in an earlier key frame of this file. A refused frame
    /// leaves the writer as it was.
    pub fn add_frame(&mut self, frame: &Frame) -> Result<u32> {
        let number = self.index.len() as u32;
        if self.index.len() as u64 >= MAX_FRAMES {
            return Err(ContainerError::TooLarge {
                path: self.path.clone(),
                at: At(Some(number)),
                what: "the number of frames",
                value: number as u64 + 1,
                limit: MAX_FRAMES,
            });
        }
        codec::check_frame(number, frame).map_err(|p| p.at(&self.path, Some(number)))?;
        let mut resolved = 0u64;
        for object in &frame.objects {
            match object {
                ObjectRecord::Stored(o) => resolved += o.block.cg_record().len() as u64,
                ObjectRecord::Reference(r) => {
                    let bad = |problem: &str| ContainerError::BadReference {
                        path: self.path.clone(),
                        frame: number,
                        object: r.id,
                        key_frame: r.key_frame,
                        problem: problem.into(),
                    };
                    let objects = self.key_frames.get(&r.key_frame).ok_or_else(|| bad("not a key frame"))?;
                    resolved += objects.get(&r.id).ok_or_else(|| bad("the key frame holds no such object"))?;
                }
            }
        }
        codec::check_resolved_bytes(&self.path, number, resolved)?;
        let bytes = codec::encode_frame(number, frame);
        if bytes.len() as u64 > MAX_FRAME_BYTES {
            return Err(ContainerError::TooLarge {
                path: self.path.clone(),
                at: At(Some(number)),
                what: "the frame's bytes",
                value: bytes.len() as u64,
                limit: MAX_FRAME_BYTES,
            });
        }
        let offset = self.position;
        self.put(&bytes)?;
        self.index.push((offset, bytes.len() as u32, frame.key_frame as u32));
        if frame.key_frame {
            let objects = frame
                .objects
                .iter()
                .filter_map(|o| match o {
                    ObjectRecord::Stored(s) => Some((s.id, s.block.cg_record().len() as u64)),
                    ObjectRecord::Reference(_) => None,
                })
                .collect();
            self.key_frames.insert(number, objects);
        }
        Ok(number)
    }

    /// Write the index, fill in the file header, and rename the file into
    /// place (spec §7).
    pub fn finish(mut self) -> Result<WriteReport> {
        let count = self.index.len() as u32;
        let index_offset = self.position;
        let mut p = Vec::with_capacity(16 + self.index.len() * INDEX_ENTRY as usize);
        p.extend_from_slice(&count.to_le_bytes());
        p.extend_from_slice(&[0; 4]);
        for &(offset, length, flags) in &self.index {
            p.extend_from_slice(&offset.to_le_bytes());
            p.extend_from_slice(&length.to_le_bytes());
            p.extend_from_slice(&flags.to_le_bytes());
        }
        let mut chunk = Vec::with_capacity(8 + p.len());
        put_chunk(&mut chunk, *b"INDX", &p);
        self.put(&chunk)?;
        let destination = self.path.clone();
        let io = |e| ContainerError::Io { path: destination.clone(), source: e };
        self.out.seek(SeekFrom::Start(12)).map_err(io)?;
        self.out.write_all(&checksum::crc32(&chunk).to_le_bytes()).map_err(io)?;
        self.out.write_all(&index_offset.to_le_bytes()).map_err(io)?;
        self.out.write_all(&count.to_le_bytes()).map_err(io)?;
        let file_bytes = self.position;
        let path = self.path.clone();
        self.out.commit(self.overwrite).map_err(|e| ContainerError::from_output(&path, e))?;
        Ok(WriteReport { path: self.path, frames: count, file_bytes })
    }

    fn put(&mut self, bytes: &[u8]) -> Result<()> {
        self.out.write_all(bytes).map_err(|e| ContainerError::Io { path: self.path.clone(), source: e })?;
        self.position += bytes.len() as u64;
        Ok(())
    }
}

/// Write geometry blocks as a Java 3D `.cg` file (format 1.0.2, all
/// big-endian): what `com.sun.j3d.utils.geometry.compression.CompressedGeometryFile`
/// reads. The blocks are copied unchanged (spec §6.4, "lifting a block out").
pub fn write_cg_file(path: impl AsRef<Path>, blocks: &[GeometryBlock], overwrite: bool) -> Result<u64> {
    let path = path.as_ref();
    if !overwrite && path.exists() {
        return Err(ContainerError::Output { path: path.to_path_buf(), problem: crate::error::OutputProblem::Exists });
    }
    // The layout is the codec's (`CgFile::to_bytes`, one place); blocks are
    // copied in unchanged.
    let file = crate::holoflick::cg::CgFile {
        version: GEOMETRY_VERSION,
        objects: blocks
            .iter()
            .map(|b| crate::holoflick::cg::CgObject { header: b.descriptor().cg_header(), bytes: b.stream().to_vec() })
            .collect(),
    };
    let out = file.to_bytes();
    crate::output::write_bytes_beside(path, &out, overwrite).map_err(|e| ContainerError::from_output(path, e))?;
    Ok(out.len() as u64)
}
