//! Reading HoloFlicks with random access by frame number (spec §7, §9). The
//! file header, the frame index and the file-level chunks are read and
//! checked by [`HoloFlickReader::open`]; a frame is read and checked when it
//! is asked for. Key-frame references are resolved by reading the key frame
//! (the last four key frames used are kept, so playing frames in order reads
//! each key frame once).

use std::collections::HashMap;
use std::fs::File;
use std::io::{Read, Seek, SeekFrom};
use std::path::{Path, PathBuf};

use super::checksum;
use super::chunk::{self, check_tag, is_critical, padding};
use super::codec;
use super::error::{tag_text, Problem};
use super::model::{Frame, GeometryBlock, Info, ObjectRecord, ResolvedFrame, ResolvedObject};
use super::*;
use super::{At, ContainerError};

/// How many key frames a reader keeps decoded: a frame may use a background
/// stored at frame 0 and a set piece stored at a later key frame.
const KEY_FRAME_CACHE: usize = 4;

/// The stored objects of a key frame: id → (radiance scale, block).
type KeyFrameObjects = HashMap<u32, (f64, GeometryBlock)>;

#[derive(Clone, Copy, Debug)]
struct IndexEntry {
    offset: u64,
    length: u32,
    key_frame: bool,
}

/// A HoloFlick open for reading.
#[derive(Debug)]
pub struct HoloFlickReader {
    path: PathBuf,
    file: File,
    info: Info,
    index: Vec<IndexEntry>,
    /// The stored objects of the key frames used last, most recent first.
    cache: Vec<(u32, KeyFrameObjects)>,
    /// The file header's checksums of the index and of the file-level
    /// chunks (spec §3.3), in a file of version 1.1 or later.
    header_sums: Option<HeaderSums>,
}

#[derive(Clone, Copy, Debug)]
struct HeaderSums {
    index: u32,
    file_chunks: u32,
}

/// What the HEAD chunk says: the frame rate (numerator, denominator) and the
/// compressed-geometry version (major, minor, minor-minor).
type Head = ((u32, u32), [u32; 3]);

impl HoloFlickReader {
    /// Open a HoloFlick: reads and checks the file header, the frame index
    /// (every frame inside the file, in order, back to back) and the
    /// file-level chunks. Frames are read by [`read_frame`](Self::read_frame).
    pub fn open(path: impl AsRef<Path>) -> Result<HoloFlickReader> {
        let path = path.as_ref().to_path_buf();
        let io = |e| ContainerError::Io { path: path.clone(), source: e };
        let file = File::open(&path).map_err(io)?;
        let file_bytes = file.metadata().map_err(io)?.len();
        let mut reader = HoloFlickReader {
            path: path.clone(),
            file,
            info: Info { version: (0, 0), frames_per_second: (0, 0), geometry_version: [0; 3], text: Vec::new() },
            index: Vec::new(),
            cache: Vec::new(),
            header_sums: None,
        };
        let (index_offset, count) = reader.read_file_header(file_bytes)?;
        reader.index = reader.read_index(index_offset, count, file_bytes)?;
        let first_frame = reader.index.first().map_or(index_offset, |e| e.offset);
        reader.check_file_chunks_sum(first_frame)?;
        let head = reader.read_file_chunks(first_frame)?;
        let fail = |p: Problem| p.at(&path, None);
        let (fps, geometry_version) =
            head.ok_or_else(|| fail(Problem::Invalid("no HEAD chunk before the first frame".into())))?;
        if geometry_version[0] != GEOMETRY_VERSION[0] || geometry_version[1] != GEOMETRY_VERSION[1] {
            return Err(ContainerError::UnsupportedVersion {
                path,
                what: "compressed geometry",
                found: format!("{}.{}.{}", geometry_version[0], geometry_version[1], geometry_version[2]),
                supported: "1.0.x (Java 3D 1.5.2)",
            });
        }
        reader.info.frames_per_second = fps;
        reader.info.geometry_version = geometry_version;
        Ok(reader)
    }

    /// The file header (spec §4): magic, a version this reader reads, where
    /// the index is and how many frames it lists.
    fn read_file_header(&mut self, file_bytes: u64) -> Result<(u64, u64)> {
        let path = self.path.clone();
        let fail = |p: Problem| p.at(&path, None);
        if file_bytes < FILE_HEADER_BYTES {
            return Err(fail(Problem::Truncated(format!(
                "the file header needs {FILE_HEADER_BYTES} bytes, the file has {file_bytes}"
            ))));
        }
        let header = self.read_at(0, FILE_HEADER_BYTES as usize, None)?;
        if header[..8] != MAGIC {
            return Err(fail(Problem::Invalid(
                "not a HoloFlick: the file does not start with the HoloFlick magic".into(),
            )));
        }
        let le16 = |i: usize| u16::from_le_bytes([header[i], header[i + 1]]);
        let (major, minor) = (le16(8), le16(10));
        if major != VERSION_MAJOR {
            return Err(ContainerError::UnsupportedVersion {
                path: path.clone(),
                what: "HoloFlick",
                found: format!("{major}.{minor}"),
                supported: "1.x",
            });
        }
        self.info.version = (major, minor);
        if minor >= 1 {
            let le32 = |i: usize| u32::from_le_bytes([header[i], header[i + 1], header[i + 2], header[i + 3]]);
            self.header_sums = Some(HeaderSums { index: le32(12), file_chunks: le32(28) });
        }
        let index_offset = u64::from_le_bytes(header[16..24].try_into().unwrap_or([0; 8]));
        let count = u32::from_le_bytes(header[24..28].try_into().unwrap_or([0; 4])) as u64;
        if index_offset == 0 {
            return Err(fail(Problem::Invalid("unfinished: the index offset is 0 (the writer did not finish)".into())));
        }
        Problem::at_most("the number of frames", count, MAX_FRAMES).map_err(fail)?;
        Ok((index_offset, count))
    }

    /// The frame index (spec §7): the last chunk, ending the file; every
    /// frame inside the file, in order, back to back.
    fn read_index(&mut self, index_offset: u64, count: u64, file_bytes: u64) -> Result<Vec<IndexEntry>> {
        let path = self.path.clone();
        let fail = |p: Problem| p.at(&path, None);
        let index_bytes = 16 + count * INDEX_ENTRY;
        if index_offset % 8 != 0 || index_offset < FILE_HEADER_BYTES + 8 {
            return Err(fail(Problem::Invalid(format!(
                "the index offset {index_offset} is not a valid chunk position"
            ))));
        }
        if index_offset > file_bytes || file_bytes - index_offset < index_bytes {
            return Err(fail(Problem::Truncated(format!(
                "the index of {count} frames needs {index_bytes} bytes at offset {index_offset}; the file has {file_bytes} bytes"
            ))));
        }
        if file_bytes - index_offset > index_bytes {
            return Err(fail(Problem::Invalid(format!(
                "{} bytes follow the index, which must end the file",
                file_bytes - index_offset - index_bytes
            ))));
        }
        let raw = self.read_at(index_offset, index_bytes as usize, None)?;
        if self.header_sums.is_some_and(|sums| checksum::crc32(&raw) != sums.index) {
            return Err(fail(Problem::Damaged("the frame index does not match its checksum".into())));
        }
        let mut c = chunk::Cursor::new(&raw);
        let (tag, payload) = c.chunk().map_err(fail)?.ok_or_else(|| fail(Problem::Truncated("the index".into())))?;
        if &tag != b"INDX" {
            return Err(fail(Problem::Invalid(format!(
                "the index offset points at a {:?} chunk, not INDX",
                tag_text(tag)
            ))));
        }
        let mut c = chunk::Cursor::new(payload);
        let listed = c.u32("the index").map_err(fail)? as u64;
        c.u32("the index").map_err(fail)?;
        if listed != count || c.remaining() as u64 != count * INDEX_ENTRY {
            return Err(fail(Problem::Invalid(format!(
                "the file header says {count} frames, the index lists {listed} in {} bytes",
                c.remaining()
            ))));
        }
        let mut index = Vec::with_capacity(count as usize);
        for _ in 0..count {
            let e = c.take(INDEX_ENTRY as usize, "an index entry").map_err(fail)?;
            let offset = u64::from_le_bytes(e[0..8].try_into().unwrap_or([0; 8]));
            let length = u32::from_le_bytes(e[8..12].try_into().unwrap_or([0; 4]));
            let flags = u32::from_le_bytes(e[12..16].try_into().unwrap_or([0; 4]));
            index.push(IndexEntry { offset, length, key_frame: flags & 1 != 0 });
        }
        for (n, e) in index.iter().enumerate() {
            let next = index.get(n + 1).map_or(index_offset, |f| f.offset);
            Problem::at_most("a frame's bytes", e.length as u64, MAX_FRAME_BYTES).map_err(fail)?;
            let end = e.offset.checked_add(e.length as u64 + padding(e.length as u64));
            if e.offset % 8 != 0 || e.offset < FILE_HEADER_BYTES + 8 || e.length < 16 || end != Some(next) {
                return Err(ContainerError::Invalid {
                    path: path.clone(),
                    at: At(Some(n as u32)),
                    problem: format!(
                        "the index places the frame at offset {} with {} bytes; frames must lie back to back after the file-level chunks, before the index at {index_offset}",
                        e.offset, e.length
                    ),
                });
            }
        }
        Ok(index)
    }

    /// Check the file-level chunks' bytes (from the end of the file header
    /// to the first frame) against the file header's checksum (spec §3.3),
    /// read in blocks so that memory does not grow with them.
    fn check_file_chunks_sum(&mut self, first_frame: u64) -> Result<()> {
        let Some(sums) = self.header_sums else { return Ok(()) };
        let mut crc = crc32fast::Hasher::new();
        let mut position = FILE_HEADER_BYTES;
        while position < first_frame {
            let block = (first_frame - position).min(1 << 20);
            crc.update(&self.read_at(position, block as usize, None)?);
            position += block;
        }
        if crc.finalize() != sums.file_chunks {
            return Err(Problem::Damaged("the file-level chunks (HEAD, text) do not match their checksum".into())
                .at(&self.path, None));
        }
        Ok(())
    }

    /// The file-level chunks (spec §5) between the header and the first
    /// frame: one HEAD first, text entries, unknown ancillary chunks skipped.
    fn read_file_chunks(&mut self, first_frame: u64) -> Result<Option<Head>> {
        let path = self.path.clone();
        let fail = |p: Problem| p.at(&path, None);
        let mut position = FILE_HEADER_BYTES;
        let mut chunks = 0u64;
        let mut head = None;
        while position < first_frame {
            chunks += 1;
            Problem::at_most("the number of file-level chunks", chunks, MAX_FILE_CHUNKS).map_err(fail)?;
            if first_frame - position < 8 {
                return Err(fail(Problem::Invalid(format!(
                    "{} stray bytes before the first frame",
                    first_frame - position
                ))));
            }
            let h = self.read_at(position, 8, None)?;
            let tag = [h[0], h[1], h[2], h[3]];
            check_tag(tag).map_err(fail)?;
            let len = u32::from_le_bytes([h[4], h[5], h[6], h[7]]) as u64;
            let end = position + 8 + len + padding(len);
            if end > first_frame {
                return Err(fail(Problem::Invalid(format!(
                    "chunk {:?} at offset {position} ({len} bytes) runs into the frames at {first_frame}",
                    tag_text(tag)
                ))));
            }
            if head.is_none() && &tag != b"HEAD" {
                return Err(fail(Problem::Invalid(format!(
                    "the first chunk is {:?}; a HoloFlick starts with HEAD",
                    tag_text(tag)
                ))));
            }
            match &tag {
                b"HEAD" if head.is_some() => return Err(fail(Problem::Invalid("two HEAD chunks".into()))),
                b"HEAD" => {
                    Problem::at_most("the HEAD chunk", len, MAX_TEXT_BYTES).map_err(fail)?;
                    let payload = self.read_at(position + 8, len as usize, None)?;
                    head = Some(codec::decode_head(&payload).map_err(fail)?);
                }
                b"text" => {
                    Problem::at_most("a text chunk", len, MAX_TEXT_BYTES).map_err(fail)?;
                    let entries = self.info.text.len() as u64 + 1;
                    Problem::at_most("the number of text chunks", entries, MAX_TEXT_ENTRIES).map_err(fail)?;
                    let payload = self.read_at(position + 8, len as usize, None)?;
                    let (key, value) = codec::decode_text(&payload).map_err(fail)?;
                    if self.info.text.iter().any(|(k, _)| *k == key) {
                        return Err(fail(Problem::Invalid(format!("text key {key:?} appears twice"))));
                    }
                    self.info.text.push((key, value));
                }
                _ if is_critical(tag) => return Err(fail(Problem::UnknownChunk(tag))),
                _ => {}
            }
            position = end;
        }
        Ok(head)
    }

    /// The file.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// Version, frame rate, geometry version and text entries.
    pub fn info(&self) -> &Info {
        &self.info
    }

    /// Number of frames.
    pub fn frame_count(&self) -> u32 {
        self.index.len() as u32
    }

    /// Whether the index marks frame `n` as a key frame (`false` past the end).
    pub fn is_key_frame(&self, n: u32) -> bool {
        self.index.get(n as usize).is_some_and(|e| e.key_frame)
    }

    /// The byte offset and length of frame `n`'s chunk, as the index gives them.
    pub fn frame_location(&self, n: u32) -> Option<(u64, u32)> {
        self.index.get(n as usize).map(|e| (e.offset, e.length))
    }

    /// Frame `n` exactly as stored: references are left unresolved. Checks
    /// every rule a frame alone can break (spec §6.7).
    pub fn read_stored_frame(&mut self, n: u32) -> Result<Frame> {
        let entry = *self.index.get(n as usize).ok_or_else(|| ContainerError::NoFrame {
            path: self.path.clone(),
            frame: n,
            frames: self.index.len(),
        })?;
        let bytes = self.read_at(entry.offset, entry.length as usize, Some(n))?;
        let fail = |p: Problem| p.at(&self.path, Some(n));
        // Damage is found before the bytes are interpreted (spec §3.3).
        let required = self.header_sums.is_some();
        checksum::verify_frame(bytes.get(chunk::CHUNK_HEADER..).unwrap_or(&[]), required).map_err(fail)?;
        let (number, frame) = codec::decode_frame(&bytes).map_err(fail)?;
        if number != n {
            return Err(fail(Problem::Invalid(format!("the frame's chunk says it is frame {number}"))));
        }
        if frame.key_frame != entry.key_frame {
            return Err(fail(Problem::Invalid(format!(
                "the index says key frame: {}, the frame says {}",
                entry.key_frame, frame.key_frame
            ))));
        }
        codec::check_frame(n, &frame).map_err(fail)?;
        Ok(frame)
    }

    /// Frame `n` with every key-frame reference resolved to the geometry the
    /// key frame stores (spec §6.6).
    pub fn read_frame(&mut self, n: u32) -> Result<ResolvedFrame> {
        let frame = self.read_stored_frame(n)?;
        let mut resolved_bytes = 0u64;
        let mut objects = Vec::with_capacity(frame.objects.len());
        let mut key_frames: Vec<u32> = Vec::new();
        for object in &frame.objects {
            if let ObjectRecord::Reference(r) = object {
                if !key_frames.contains(&r.key_frame) {
                    key_frames.push(r.key_frame);
                }
            }
        }
        // Resolve grouped by key frame, so each is read at most once.
        let mut found: HashMap<u32, (f64, GeometryBlock, u32)> = HashMap::new();
        for &k in &key_frames {
            self.load_key_frame(n, k, &frame)?;
            if let Some((_, stored)) = self.cache.first() {
                for object in &frame.objects {
                    if let ObjectRecord::Reference(r) = object {
                        if r.key_frame == k {
                            let (scale, block) = stored.get(&r.id).ok_or_else(|| ContainerError::BadReference {
                                path: self.path.clone(),
                                frame: n,
                                object: r.id,
                                key_frame: k,
                                problem: "the key frame holds no such object".into(),
                            })?;
                            found.insert(r.id, (*scale, block.clone(), k));
                        }
                    }
                }
            }
        }
        for object in &frame.objects {
            let r = match object {
                ObjectRecord::Stored(o) => ResolvedObject {
                    id: o.id,
                    world_from_object: o.world_from_object,
                    radiance_scale: o.radiance_scale,
                    block: o.block.clone(),
                    stored_in_frame: n,
                },
                ObjectRecord::Reference(r) => {
                    let (radiance_scale, block, k) =
                        found.get(&r.id).cloned().ok_or_else(|| ContainerError::BadReference {
                            path: self.path.clone(),
                            frame: n,
                            object: r.id,
                            key_frame: r.key_frame,
                            problem: "not resolved".into(),
                        })?;
                    ResolvedObject {
                        id: r.id,
                        world_from_object: r.world_from_object,
                        radiance_scale,
                        block,
                        stored_in_frame: k,
                    }
                }
            };
            resolved_bytes += r.block.cg_record().len() as u64;
            codec::check_resolved_bytes(&self.path, n, resolved_bytes)?;
            objects.push(r);
        }
        Ok(ResolvedFrame { number: n, frame, objects })
    }

    /// Make key frame `k` the first of the cached ones (frame `n` refers to it).
    fn load_key_frame(&mut self, n: u32, k: u32, frame: &Frame) -> Result<()> {
        if let Some(i) = self.cache.iter().position(|(cached, _)| *cached == k) {
            let entry = self.cache.remove(i);
            self.cache.insert(0, entry);
            return Ok(());
        }
        let object = frame
            .objects
            .iter()
            .find_map(|o| match o {
                ObjectRecord::Reference(r) if r.key_frame == k => Some(r.id),
                _ => None,
            })
            .unwrap_or(0);
        let path = self.path.clone();
        let bad = |problem: String| ContainerError::BadReference {
            path: path.clone(),
            frame: n,
            object,
            key_frame: k,
            problem,
        };
        if k >= n {
            return Err(bad("not an earlier frame".into()));
        }
        if !self.is_key_frame(k) {
            return Err(bad("not a key frame".into()));
        }
        let key = self.read_stored_frame(k).map_err(|e| bad(format!("the key frame is unreadable ({e})")))?;
        let stored = key
            .objects
            .into_iter()
            .filter_map(|o| match o {
                ObjectRecord::Stored(s) => Some((s.id, (s.radiance_scale, s.block))),
                ObjectRecord::Reference(_) => None,
            })
            .collect();
        self.cache.truncate(KEY_FRAME_CACHE - 1);
        self.cache.insert(0, (k, stored));
        Ok(())
    }

    /// `len` bytes at `offset`; a short file is reported as truncation.
    fn read_at(&mut self, offset: u64, len: usize, frame: Option<u32>) -> Result<Vec<u8>> {
        let io = |e| ContainerError::Io { path: self.path.clone(), source: e };
        self.file.seek(SeekFrom::Start(offset)).map_err(io)?;
        // Callers pass lengths checked against the file's size at `open`;
        // `take` stops at the end should the file have shrunk since.
        let mut buf = Vec::with_capacity(len);
        (&mut self.file).take(len as u64).read_to_end(&mut buf).map_err(io)?;
        if buf.len() < len {
            return Err(ContainerError::Truncated {
                path: self.path.clone(),
                at: At(frame),
                what: format!("{len} bytes needed at offset {offset}, {} present", buf.len()),
            });
        }
        Ok(buf)
    }
}
