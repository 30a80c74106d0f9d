//! The fast decoder: a 64-bit word-refilled bit reader and Java 3D's
//! 64-entry table lookup per header. Command by command it does what
//! `GeometryDecompressor.processDecompression` of Java 3D 1.5.2 does (the
//! command set of Deering, "Geometry Compression", SIGGRAPH 1995, as the Java
//! 3D API Specification, appendix B "3D Geometry Compression", lays it out;
//! the crate docs list where Java 3D departs from it); [`super::reference`]
//! is the slow twin the tests compare it with.
//!
//! Each body is read as one "logical" bit string: the header's 6 low bits
//! followed by the body. For a vertex the 3 replace/push bits come first in
//! the body when the tag and data fill the header, else they finish the
//! header (Java's `processVertex` reads them before the rest of x/y/z).

use super::bits::{sign_extend, PastEnd, StreamError, WordReader};
use super::normals::NormalCode;
use super::state::{parse_set_table, Sink, State};
use crate::error::{StreamProblem, Table};

/// Decode `bytes` command by command into `sink`.
pub(crate) fn run(bytes: &[u8], sink: &mut impl Sink) -> Result<(), StreamError> {
    check_length(bytes)?;
    let mut r = WordReader::new(bytes);
    let mut st = State::new();
    // The first header is an implicit V_NO_OP whose body (a 5-bit count) starts the stream.
    let mut next: u32 = 0x01;
    while !r.at_end() {
        // Every read of a FAST command refills from `next`, the first byte
        // not yet buffered, which runs at most 63 bits ahead of the bits
        // read. The widest command (a vertex with bundled normal and colour
        // at the widest entries: 6 + 51 + 6 + 36 + 8 + 48 + 16 = 171 bits)
        // last loads from where its previous refill, at most 107 bits in,
        // left `next`: no load ends past 8 + (107 + 63) / 8 < 30 bytes from
        // here, and 40 leaves room to spare. Nearer the end reads are checked.
        next = if r.far_from_end(FAST_MARGIN_BYTES) {
            command::<true>(&mut r, &mut st, sink, next)?
        } else {
            command::<false>(&mut r, &mut st, sink, next)?
        };
    }
    st.finish(sink).map_err(|problem| problem.at(r.position()))
}

/// Bytes still to load beyond which a command's reads need no end checks (see [`run`]).
const FAST_MARGIN_BYTES: usize = 40;

/// Decode the command whose header is `current` (its body comes next in
/// `r`): returns the following header. `FAST`: `r` is far enough from the
/// end that no read can run past it.
#[inline(always)]
fn command<const FAST: bool>(
    r: &mut WordReader,
    st: &mut State,
    sink: &mut impl Sink,
    current: u32,
) -> Result<u32, StreamError> {
    let at = r.position();
    let err = |problem: StreamProblem| problem.at(at);
    let past = |_: PastEnd| StreamProblem::EndsInsideCommand.at(at);
    if current & 0xC0 == 0x40 {
        let (n, c) = (st.bundling_normal, st.bundling_color);
        let first = if n || c { 6 } else { 8 };
        let after = r.read::<FAST>(first).map_err(past)?;
        let push = vertex::<FAST>(r, st, current).map_err(|e| e.at(at))?;
        let mut pending = after;
        if n {
            let following = r.read::<FAST>(if c { 6 } else { 8 }).map_err(past)?;
            normal::<FAST>(r, st, pending, push).map_err(|e| e.at(at))?;
            st.finish_normal(sink).map_err(err)?;
            pending = following;
        }
        if c {
            let following = r.read::<FAST>(8).map_err(past)?;
            color::<FAST>(r, st, pending, push).map_err(|e| e.at(at))?;
            st.finish_color(sink).map_err(err)?;
            pending = following;
        }
        let replace = st.last_replace;
        st.output_vertex(replace, sink).map_err(err)?;
        return Ok(pending);
    }
    let next = r.read::<FAST>(8).map_err(past)?;
    match current {
        h if h & 0xC0 == 0xC0 => {
            normal::<FAST>(r, st, h, false).map_err(|e| e.at(at))?;
            st.finish_normal(sink).map_err(err)?;
        }
        h if h & 0xC0 == 0x80 => {
            color::<FAST>(r, st, h, false).map_err(|e| e.at(at))?;
            st.finish_color(sink).map_err(err)?;
        }
        h if h & 0xE0 == 0x20 => {
            let low = r.read::<FAST>(1).map_err(past)?;
            let replace = (((h & 1) << 1) | low) as u8;
            st.mesh_reference(((h >> 1) & 0xF) as usize).map_err(err)?;
            st.output_vertex(replace, sink).map_err(err)?;
        }
        h if h & 0xF8 == 0x18 => {
            let b = r.read::<FAST>(3).map_err(past)?;
            st.set_state(h & 1 != 0, (b >> 2) & 1 != 0, (b >> 1) & 1 != 0, sink).map_err(err)?;
        }
        h if h & 0xF8 == 0x10 => {
            let b = r.read::<FAST>(15).map_err(past)?;
            let (t, first, count, entry) = parse_set_table(h, b);
            let table = st.tables.get_mut(t).ok_or_else(|| err(no_table(t)))?;
            for e in table.iter_mut().skip(first).take(count) {
                *e = entry;
            }
        }
        0x08 => {
            r.read::<FAST>(24).map_err(past)?;
            r.read::<FAST>(32).map_err(past)?;
        }
        0x07 => {
            r.read::<FAST>(8).map_err(past)?;
        }
        0x01 => {
            let count = r.read::<FAST>(5).map_err(past)?;
            r.read::<FAST>(count).map_err(past)?;
        }
        // EOS and the unassigned opcodes have no body.
        _ => {}
    }
    Ok(next)
}

/// setTable names table 3: Java 3D indexes past its three tables.
pub(crate) fn no_table(table: usize) -> StreamProblem {
    StreamProblem::NoSuchTable { table }
}

/// Java 3D's decoder refills 4 bytes at a time: any other length reads past the buffer.
pub(crate) fn check_length(bytes: &[u8]) -> Result<(), StreamError> {
    if bytes.len() % 4 != 0 {
        return Err(StreamProblem::Length { bytes: bytes.len() }.at(0));
    }
    Ok(())
}

/// A vertex body: returns the mesh-buffer push bit.
#[inline(always)]
fn vertex<const FAST: bool>(r: &mut WordReader, st: &mut State, header: u32) -> Result<bool, StreamProblem> {
    let e = st.tables[0][(header & 0x3F) as usize];
    let d = e.sent(Table::Position)?;
    let tag = u32::from(e.tag_len);
    let n = tag + 3 * d;
    let head = u64::from(header) & low_bits(6 - tag);
    let (rpm, bits) = if n >= 6 {
        // The 3 replace/push bits, then the rest of x/y/z: at most 51 bits.
        if !r.ensure::<FAST>(3 + n - 6) {
            return Err(StreamProblem::EndsInsideCommand);
        }
        let rpm = r.take(3) as u32;
        let rest = r.take(n - 6);
        (rpm, (head << (n - 6)) | rest)
    } else {
        let in_header = 6 - n;
        if in_header > 3 {
            return Err(StreamProblem::ReplaceBitsInHeader { tag_len: tag, data_len: d, header_bits: in_header });
        }
        let rpm =
            ((u64::from(header) & low_bits(in_header)) << (3 - in_header)) as u32 | r.read::<FAST>(3 - in_header)?;
        (rpm, head >> in_header)
    };
    let x = sign_extend(bits >> (2 * d), d) << e.shift;
    let y = sign_extend(bits >> d, d) << e.shift;
    let z = sign_extend(bits, d) << e.shift;
    let push = rpm & 1 != 0;
    st.last_replace = (rpm >> 1) as u8;
    st.apply_position(e.absolute, [x, y, z], push);
    Ok(push)
}

/// A mask of the `n` low bits for the header's `n <= 6` (no 64-bit case to test).
#[inline(always)]
fn low_bits(n: u32) -> u64 {
    debug_assert!(n <= 6);
    (1u64 << n) - 1
}

/// The next `n` bits (`n <= 48`, a body's rest) with one end-of-stream check (none when `FAST`).
#[inline(always)]
fn take_checked<const FAST: bool>(r: &mut WordReader, n: u32) -> Result<u64, PastEnd> {
    if r.ensure::<FAST>(n) {
        Ok(r.take(n))
    } else {
        Err(PastEnd)
    }
}

/// A colour body (header's 6 low bits + body).
#[inline(always)]
fn color<const FAST: bool>(r: &mut WordReader, st: &mut State, header: u32, push: bool) -> Result<(), StreamProblem> {
    let e = st.tables[1][(header & 0x3F) as usize];
    let d = e.sent(Table::Color)?;
    let tag = u32::from(e.tag_len);
    let n = tag + 3 * d;
    let head = u64::from(header) & low_bits(6 - tag);
    let bits = if n >= 6 { (head << (n - 6)) | take_checked::<FAST>(r, n - 6)? } else { head >> (6 - n) };
    // Alpha follows the body; when r, g, b leave room for it inside the
    // header, Java 3D's processSetColor masks it to 0 (a bug kept on purpose:
    // Java decides what such streams mean).
    let a = if st.doing_alpha && n >= 6 { r.read::<FAST>(d)? } else { 0 };
    let s = e.shift;
    let values = [
        sign_extend(bits >> (2 * d), d) << s,
        sign_extend(bits >> d, d) << s,
        sign_extend(bits, d) << s,
        sign_extend(u64::from(a), d) << s,
    ];
    st.apply_color(e.absolute, values, push);
    Ok(())
}

/// A normal body (header's 6 low bits + body).
#[inline(always)]
fn normal<const FAST: bool>(r: &mut WordReader, st: &mut State, header: u32, push: bool) -> Result<(), StreamProblem> {
    let e = st.tables[2][(header & 0x3F) as usize];
    let d = e.sent(Table::Normal)?;
    let tag = u32::from(e.tag_len);
    let head = u64::from(header) & low_bits(6 - tag);
    if e.absolute {
        let index = (head << tag) as u32 | r.read::<FAST>(tag)?;
        let u = (r.read::<FAST>(d)? as i32) << e.shift;
        let v = (r.read::<FAST>(d)? as i32) << e.shift;
        st.set_normal_code(NormalCode { sextant: ((index >> 3) & 7) as u8, octant: (index & 7) as u8, u, v }, push)?;
    } else {
        let n = tag + 2 * d;
        let bits = if n >= 6 { (head << (n - 6)) | take_checked::<FAST>(r, n - 6)? } else { head >> (6 - n) };
        let du = sign_extend(bits >> d, d) << e.shift;
        let dv = sign_extend(bits, d) << e.shift;
        st.add_normal_delta(du, dv, push)?;
    }
    Ok(())
}
