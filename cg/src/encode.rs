//! The encoder: quantize, dedupe vertices, meshify, build the three tables
//! from the data, write the commands with header forwarding and pad to a
//! multiple of 8 bytes as Java 3D's `CommandStream.end` does.
//!
//! Quantization rounds to the nearest step (Java 3D's compressor truncates),
//! so decoded values are within half a step: positions within 2^-bits of the
//! normalised frame, colours within 2^-bits (after clamping to what
//! `bits` can hold, see [`EncodeOptions`]), normals within
//! [`super::normal_error_bound_rad`].

use super::bits::BitWriter;
use super::huffman::{canonical_tags, limited_lengths, TableEntry};
use super::meshify::{meshify, Step};
use super::normals::{quantize_normal, NormalCode};
use super::CgHeader;
use crate::error::{Error, Result};
use std::collections::HashMap;

/// An indexed triangle mesh to encode.
#[derive(Clone, Copy, Debug)]
pub struct Mesh<'a> {
    /// Vertex positions in model units, any range.
    pub positions: &'a [[f64; 3]],
    /// Per-vertex normals (any non-zero length), or none.
    pub normals: Option<&'a [[f32; 3]]>,
    /// Per-vertex linear RGBA colours in [0, 1] (alpha sent only when
    /// [`EncodeOptions::alpha`]), or none.
    pub colors: Option<&'a [[f32; 4]]>,
    /// Triangles as vertex indices, counter-clockwise from the front.
    pub triangles: &'a [[u32; 3]],
}

/// Quantization knobs.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct EncodeOptions {
    /// Bits per position component, 1..=16 (Java 3D default 16): the
    /// normalised frame [-1, 1) is cut into 2^bits steps.
    pub position_bits: u32,
    /// Bits per colour component, 2..=16 (Java 3D default 9): the top bits
    /// of a signed 16-bit value, so [0, 1) gets 2^(bits-1) steps and values
    /// above 1 − 2^(1-bits) are clamped there.
    pub color_bits: u32,
    /// Bits per normal grid coordinate u and v, 0..=6 (Java 3D default 6).
    pub normal_bits: u32,
    /// Send colour alpha (RGBA; Java 3D's compressor always does for colour arrays).
    pub alpha: bool,
}

impl Default for EncodeOptions {
    fn default() -> Self {
        EncodeOptions { position_bits: 16, color_bits: 9, normal_bits: 6, alpha: true }
    }
}

/// What encoding produced.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct EncodeStats {
    /// Stream length in bytes.
    pub bytes: usize,
    /// Triangles encoded.
    pub triangles: usize,
    /// Distinct quantized vertices.
    pub unique_vertices: usize,
    /// Vertex commands sending data.
    pub vertices_sent: usize,
    /// Mesh-buffer references.
    pub mesh_buffer_hits: usize,
}

/// An encoded stream with the header Java 3D needs and the map back to model space.
#[derive(Clone, Debug, PartialEq)]
pub struct Encoded {
    /// The header to store beside the stream (or in a `.cg` file).
    pub header: CgHeader,
    /// The command stream, a multiple of 8 bytes long.
    pub bytes: Vec<u8>,
    /// Model-space centre of the bounds (model units).
    pub center: [f64; 3],
    /// Normalised units per model unit: `normalised = (model − center) × scale`,
    /// so `model = normalised / scale + center`.
    pub scale: f64,
    /// Sizes and counts.
    pub stats: EncodeStats,
}

impl Encoded {
    /// A decoded position (Java 3D's normalised frame) back in model units:
    /// `model = normalised / scale + center`.
    pub fn model_from_normalised(&self, normalised: [f32; 3]) -> [f64; 3] {
        [0, 1, 2].map(|k| f64::from(normalised[k]) / self.scale + self.center[k])
    }
}

/// One vertex's stream integers.
#[derive(Clone, Copy, PartialEq, Eq, Hash)]
struct QVertex {
    position: [i16; 3],
    normal: Option<NormalCode>,
    color: Option<[i16; 4]>,
}

/// Round `x` (in units of 1/32768) to a multiple of `step` within [lo, hi].
fn round_to(x: f64, step: i32, lo: i32, hi: i32) -> i16 {
    let q = (x / f64::from(step)).round() * f64::from(step);
    let q = if q.is_finite() { q } else { 0.0 };
    (q.clamp(f64::from(lo), f64::from(hi))) as i32 as i16
}

/// Two's-complement bits needed for `v` (0 for 0).
fn signed_bits(v: i32) -> u32 {
    if v == 0 {
        0
    } else if v > 0 {
        33 - v.leading_zeros()
    } else {
        33 - (!v).leading_zeros()
    }
}

fn unsigned_bits(v: u32) -> u32 {
    32 - v.leading_zeros()
}

/// A Huffman symbol: (data bits sent per component, absolute).
type Token = (u32, bool);

/// A value set ready to write once its table is known.
#[derive(Clone, Copy)]
struct Coded {
    token: Token,
    /// Components in stream units (multiples of 2^base shift): absolute
    /// values or deltas; unused components are 0.
    values: [i32; 4],
    /// Components sent.
    comps: usize,
    /// For absolute normals: the 6-bit sextant/octant index.
    index: Option<u32>,
}

/// A full vertex's position, normal and colour codes.
type CodedVertex = (Coded, Option<Coded>, Option<Coded>);

/// Candidate codings of one value set: absolute, and relative when the
/// decoder has a previous value to add to.
type Options = [Option<Coded>; 2];

/// Code `v` (stream units, multiples of 2^`shift`) absolutely and as a delta
/// from `last` (16-bit wrapping, as the decoder adds).
fn code_values(v: &[i32; 4], last: Option<[i32; 4]>, shift: u32, comps: usize) -> Options {
    let bits = |x: &[i32; 4]| x[..comps].iter().map(|&c| signed_bits(c >> shift)).max().unwrap_or(0);
    let absolute = Coded { token: (bits(v), true), values: *v, comps, index: None };
    let relative = last.map(|l| {
        let d = [0, 1, 2, 3].map(|k| v[k].wrapping_sub(l[k]) as i16 as i32);
        Coded { token: (bits(&d), false), values: d, comps, index: None }
    });
    [Some(absolute), relative]
}

/// Code a normal absolutely (index, u, v) and, when the decoder can reach
/// it, as the shortest delta (du, dv).
fn code_normal(n: NormalCode, last: Option<NormalCode>, shift: u32) -> Options {
    let abs_bits = unsigned_bits((n.u >> shift) as u32).max(unsigned_bits((n.v >> shift) as u32));
    let index = (u32::from(n.sextant) << 3) | u32::from(n.octant);
    let absolute = Coded { token: (abs_bits, true), values: [n.u, n.v, 0, 0], comps: 2, index: Some(index) };
    let Some(l) = last.filter(|l| l.sextant < 6 && n.sextant < 6) else { return [Some(absolute), None] };
    // Deltas the decoder turns into `n`: directly within the same sextant and
    // octant, or across one edge by the reflection Java 3D's
    // processSetNormal applies when the sum leaves the triangle.
    let mut options: Vec<(i32, i32)> = Vec::with_capacity(4);
    if l.sextant == n.sextant && l.octant == n.octant {
        options.push((n.u - l.u, n.v - l.v));
    }
    let u_mirror = [4, 5, 3, 2, 0, 1][usize::from(l.sextant)];
    if n.sextant == u_mirror && n.octant == l.octant && n.u > 0 {
        options.push((-n.u - l.u, n.v - l.v));
    }
    let v_flip = [2, 4, 1, 1, 2, 4][usize::from(l.sextant)];
    if n.sextant == l.sextant && n.octant == l.octant ^ v_flip && n.v > 0 {
        options.push((n.u - l.u, -n.v - l.v));
    }
    let uv_mirror = [2, 3, 0, 1, 5, 4][usize::from(l.sextant)];
    if n.sextant == uv_mirror && n.octant == l.octant && n.u + n.v < 64 {
        options.push((64 - n.u - l.u, 64 - n.v - l.v));
    }
    let best =
        options.into_iter().map(|(du, dv)| (signed_bits(du >> shift).max(signed_bits(dv >> shift)), du, dv)).min();
    let relative = best.map(|(rel_bits, du, dv)| Coded {
        token: (rel_bits, false),
        values: [du, dv, 0, 0],
        comps: 2,
        index: None,
    });
    [Some(absolute), relative]
}

/// The bit string "tag [index] components" split into the 6 header bits
/// and the rest (the table's expand rule makes it at least 6 bits long).
fn split_header(e: TableEntry, c: &Coded) -> (u32, Vec<(u64, u32)>) {
    let d = e.data_len - e.shift;
    let mut w = BitWriter::default();
    w.write(u64::from(e.tag), e.tag_len);
    if let Some(i) = c.index {
        w.write(u64::from(i), 6);
    }
    for &v in &c.values[..c.comps] {
        w.write(((v >> e.shift) as i64 as u64) & super::bits::mask(d), d);
    }
    let total = w.bit_len() as u32;
    let flat = w.into_bytes();
    let mut r = super::bits::BitByBit::new(&flat);
    let mut take = |n: u32| r.read(n).unwrap_or(0);
    if total < 6 {
        return ((take(total) << (6 - total)) as u32, Vec::new());
    }
    let h = take(6) as u32;
    let mut rest = Vec::new();
    let mut left = total - 6;
    while left > 0 {
        let n = left.min(32);
        rest.push((take(n), n));
        left -= n;
    }
    (h, rest)
}

/// Bits of one setTable command (8-bit header, 15-bit body).
const SET_TABLE_BITS: u64 = 23;

/// A table: the token set it holds, tag per token and the (data length,
/// shift) each token's entry gets after Java's "expand" rule (tag +
/// components × sent bits ≥ 6, data length ≥ 1 where 0 would mean 16).
/// A value whose own token is not in the set is sent with the next longer
/// token of the same kind (sign or zero extended), which frees tag space.
struct Table {
    id: u32,
    shift: u32,
    /// Components that share the header with the tag (3, or 2 for relative normals; 0: none).
    components: fn(Token) -> u32,
    /// Components sent per value.
    comps: u32,
    entries: HashMap<Token, TableEntry>,
}

impl Table {
    fn new(id: u32, shift: u32, comps: u32, components: fn(Token) -> u32) -> Self {
        Table { id, shift, components, comps, entries: HashMap::new() }
    }

    /// (sent bits, shift) of token `t` with a tag of `tag_len` bits.
    fn expand(&self, t: Token, tag_len: u32) -> (u32, u32) {
        let comps = (self.components)(t);
        let (mut sent, mut shift) = (t.0, self.shift);
        while (comps > 0 && tag_len + comps * sent < 6) || (self.id != 2 && sent + shift == 0) {
            shift = shift.saturating_sub(1);
            sent += 1;
        }
        (sent, shift)
    }

    /// Bits of one value with token `t` (in the set) and a `tag_len`-bit tag.
    fn value_bits(&self, t: Token, tag_len: u32) -> u64 {
        let index = if self.id == 2 && t.1 { 6 } else { 0 };
        u64::from(tag_len + self.comps * self.expand(t, tag_len).0 + index)
    }

    /// The token of `set` that carries values of token `t`.
    fn carrier(set: &[Token], t: Token) -> Option<Token> {
        set.iter().copied().filter(|u| u.1 == t.1 && u.0 >= t.0).min()
    }

    /// Tag lengths for `set` (sorted) under `counts` and the total bits of
    /// the values and the setTable commands.
    fn evaluate(&self, set: &[Token], counts: &HashMap<Token, u64>) -> (Vec<u32>, u64) {
        let mut freqs = vec![0u64; set.len()];
        for (&t, &c) in counts {
            if let Some(u) = Self::carrier(set, t) {
                if let Ok(k) = set.binary_search(&u) {
                    freqs[k] += c;
                }
            }
        }
        let lengths = limited_lengths(&freqs, 6);
        let total =
            set.iter().zip(&freqs).zip(&lengths).map(|((&t, &f), &l)| f * self.value_bits(t, l) + SET_TABLE_BITS).sum();
        (lengths, total)
    }

    /// Choose the token set from the value counts: start from every token
    /// used and merge tokens into the next longer one of the same kind while
    /// the exact total of tags, data and setTable commands drops.
    fn build(&mut self, counts: &HashMap<Token, u64>) -> u64 {
        let mut set: Vec<Token> = counts.keys().copied().collect();
        set.sort();
        let (mut lengths, mut total) = self.evaluate(&set, counts);
        loop {
            let mut best: Option<(u64, Vec<Token>, Vec<u32>)> = None;
            for k in 0..set.len() {
                if Self::carrier(&set[k + 1..], set[k]).is_none() {
                    continue;
                }
                let mut trial = set.clone();
                trial.remove(k);
                let (l, t) = self.evaluate(&trial, counts);
                if t < best.as_ref().map_or(total, |b| b.0) {
                    best = Some((t, trial, l));
                }
            }
            let Some((t, s, l)) = best else { break };
            (total, set, lengths) = (t, s, l);
        }
        let tags = canonical_tags(&lengths);
        self.entries.clear();
        for (k, &t) in set.iter().enumerate() {
            let tag_len = lengths[k];
            let (sent, shift) = self.expand(t, tag_len);
            self.entries.insert(t, TableEntry { tag: tags[k], tag_len, data_len: sent + shift, shift, absolute: t.1 });
        }
        total
    }

    /// The token a value of token `t` is sent with and its bits, if the table can carry it.
    fn carry(&self, t: Token) -> Option<(Token, u64)> {
        let u = self.entries.keys().copied().filter(|u| u.1 == t.1 && u.0 >= t.0).min()?;
        Some((u, self.value_bits(u, self.entries[&u].tag_len)))
    }

    fn entry(&self, t: Token) -> Result<TableEntry> {
        self.entries.get(&t).copied().ok_or_else(internal)
    }

    fn commands(&self) -> Vec<(u32, u32)> {
        let mut e: Vec<&TableEntry> = self.entries.values().collect();
        e.sort_by_key(|e| (e.tag_len, e.tag));
        e.iter().map(|e| e.command(self.id)).collect()
    }
}

/// Pick one option per value set: first the fewest data bits (relative on
/// ties), then a few rounds of the cheapest under the tables the previous
/// choice built; returns the choice with the fewest total bits, its tables built.
fn choose(options: &[Options], table: &mut Table) -> Vec<usize> {
    let naive = |c: &Coded| u64::from(c.comps as u32 * c.token.0) + if c.index.is_some() { 6 } else { 0 };
    let mut choice: Vec<usize> = options
        .iter()
        .map(|o| match o {
            [Some(a), Some(r)] if naive(r) <= naive(a) => 1,
            [None, Some(_)] => 1,
            _ => 0,
        })
        .collect();
    let counts = |choice: &[usize]| {
        let mut m: HashMap<Token, u64> = HashMap::new();
        for (o, &k) in options.iter().zip(choice) {
            if let Some(c) = &o[k] {
                *m.entry(c.token).or_insert(0) += 1;
            }
        }
        m
    };
    let mut best = (table.build(&counts(&choice)), choice.clone());
    for _ in 0..3 {
        let next: Vec<usize> = options
            .iter()
            .zip(&choice)
            .map(|(o, &k)| {
                let cost = |j: usize| o[j].and_then(|c| table.carry(c.token)).map(|x| x.1);
                match (cost(0), cost(1)) {
                    (Some(a), Some(r)) if r <= a => 1,
                    (None, Some(_)) => 1,
                    (Some(_), _) => 0,
                    _ => k,
                }
            })
            .collect();
        if next == choice {
            break;
        }
        choice = next;
        let total = table.build(&counts(&choice));
        if total < best.0 {
            best = (total, choice.clone());
        }
    }
    table.build(&counts(&best.1));
    best.1
}

/// Commands with header forwarding: each header is written before the
/// previous command's body (the first body is the implicit no-op's count).
struct CommandWriter {
    w: BitWriter,
    pending: Vec<(u64, u32)>,
}

impl CommandWriter {
    fn new() -> Self {
        CommandWriter { w: BitWriter::default(), pending: vec![(0, 5)] }
    }

    fn add(&mut self, header: u32, header_len: u32, body: Vec<(u64, u32)>) {
        self.w.write(u64::from(header), header_len);
        for (v, n) in std::mem::replace(&mut self.pending, body) {
            self.w.write(v, n);
        }
    }

    /// Flush with variable no-ops so that the stream ends on a 64-bit
    /// boundary right after a body (the decoder then stops; the last
    /// header read is never executed).
    fn finish(mut self) -> Vec<u8> {
        // The no-op whose body (5-bit count + that many bits) pads.
        self.add(0x01, 8, Vec::new());
        loop {
            let after = self.w.bit_len() + 8 + 5;
            let need = ((64 - after % 64) % 64) as u32;
            if need <= 31 {
                self.w.write(0, 8);
                self.w.write(u64::from(need), 5);
                self.w.write(0, need);
                break;
            }
            // Run one more no-op: its header, then the pending one's body.
            self.w.write(0x01, 8);
            let c = need - 32;
            self.w.write(u64::from(c), 5);
            self.w.write(0, c);
        }
        self.w.into_bytes()
    }
}

/// Encode a triangle mesh into a compressed-geometry stream Java 3D 1.5.2
/// decodes. Errors: options out of range, attribute arrays of the wrong
/// length, indices out of range, non-finite positions.
pub fn encode(mesh: &Mesh, options: &EncodeOptions) -> Result<Encoded> {
    let o = options;
    check_input(mesh, o)?;
    let n = mesh.positions.len();
    let (center, scale) = normalising_frame(mesh.positions, o.position_bits);
    let pos_step = 1i32 << (16 - o.position_bits);
    let col_step = 1i32 << (16 - o.color_bits);

    // Quantize and merge vertices whose stream integers are equal.
    let mut ids: HashMap<QVertex, u32> = HashMap::new();
    let mut unique: Vec<QVertex> = Vec::new();
    let mut remap = Vec::with_capacity(n);
    for i in 0..n {
        let p = mesh.positions[i];
        let position =
            [0, 1, 2].map(|k| round_to((p[k] - center[k]) * scale * 32768.0, pos_step, -32768, 32768 - pos_step));
        let normal = mesh.normals.map(|a| quantize_normal(a[i], o.normal_bits));
        let color = mesh.colors.map(|a| {
            let c = a[i];
            let q = |x: f32| round_to(f64::from(x) * 32768.0, col_step, 0, 32768 - col_step);
            [q(c[0]), q(c[1]), q(c[2]), if o.alpha { q(c[3]) } else { 0 }]
        });
        let qv = QVertex { position, normal, color };
        let id = *ids.entry(qv).or_insert_with(|| {
            unique.push(qv);
            (unique.len() - 1) as u32
        });
        remap.push(id);
    }
    let triangles: Vec<[u32; 3]> = mesh.triangles.iter().map(|t| t.map(|i| remap[i as usize])).collect();
    let steps = meshify(&triangles, unique.len());

    // Code every value set against the decoder's current state.
    let has_n = mesh.normals.is_some();
    let has_c = mesh.colors.is_some();
    let pos_shift = 16 - o.position_bits;
    let col_shift = 16 - o.color_bits;
    let nor_shift = 6 - o.normal_bits;
    let comps = if o.alpha { 4 } else { 3 };
    let mut pos_table = Table::new(0, pos_shift, 3, |_| 3);
    let mut col_table = Table::new(1, col_shift, comps as u32, |_| 3);
    let mut nor_table = Table::new(2, nor_shift, 2, |t| if t.1 { 0 } else { 2 });
    // Every full vertex's options (the deltas follow the decoder's state,
    // which does not depend on how earlier values were coded).
    let (mut pos_opts, mut nor_opts, mut col_opts) = (Vec::new(), Vec::new(), Vec::new());
    let mut cur: Option<QVertex> = None;
    let wide = |a: [i16; 3]| [i32::from(a[0]), i32::from(a[1]), i32::from(a[2]), 0];
    for s in &steps {
        match *s {
            Step::Reference { vertex, .. } => cur = unique.get(vertex as usize).copied(),
            Step::Full { vertex, .. } => {
                let Some(&v) = unique.get(vertex as usize) else { return Err(internal()) };
                pos_opts.push(code_values(&wide(v.position), cur.map(|c| wide(c.position)), pos_shift, 3));
                if let Some(nv) = v.normal {
                    nor_opts.push(code_normal(nv, cur.and_then(|c| c.normal), nor_shift));
                }
                if let Some(cv) = v.color {
                    let last = cur.and_then(|c| c.color).map(|l| l.map(i32::from));
                    col_opts.push(code_values(&cv.map(i32::from), last, col_shift, comps));
                }
                cur = Some(v);
            }
        }
    }
    // The chosen option of each value set, sent with the token its table carries it by.
    let pick = |opts: &[Options], table: &mut Table| -> Result<Vec<Coded>> {
        let choice = choose(opts, table);
        opts.iter()
            .zip(choice)
            .map(|(o, k)| {
                let mut c = o[k].ok_or_else(internal)?;
                c.token = table.carry(c.token).ok_or_else(internal)?.0;
                Ok(c)
            })
            .collect()
    };
    let pos_coded = pick(&pos_opts, &mut pos_table)?;
    let nor_coded = pick(&nor_opts, &mut nor_table)?;
    let col_coded = pick(&col_opts, &mut col_table)?;
    let (mut pi, mut ni, mut ci) = (pos_coded.into_iter(), nor_coded.into_iter(), col_coded.into_iter());
    let mut coded: Vec<Option<CodedVertex>> = Vec::with_capacity(steps.len());
    for s in &steps {
        coded.push(match s {
            Step::Reference { .. } => None,
            Step::Full { .. } => {
                let p = pi.next().ok_or_else(internal)?;
                let nc = if has_n { Some(ni.next().ok_or_else(internal)?) } else { None };
                let cc = if has_c { Some(ci.next().ok_or_else(internal)?) } else { None };
                Some((p, nc, cc))
            }
        });
    }

    let mut cw = CommandWriter::new();
    // setState: header 00011xxn, body "c a 0".
    cw.add(0x18 | u32::from(has_n), 8, vec![((u64::from(has_c) << 2) | (u64::from(has_c && o.alpha) << 1), 3)]);
    for t in [&pos_table, &col_table, &nor_table] {
        for (h, b) in t.commands() {
            cw.add(h, 8, vec![(u64::from(b), 15)]);
        }
    }
    let mut stats =
        EncodeStats { triangles: mesh.triangles.len(), unique_vertices: unique.len(), ..EncodeStats::default() };
    for (s, c) in steps.iter().zip(&coded) {
        match (*s, c) {
            (Step::Reference { depth, replace, .. }, _) => {
                stats.mesh_buffer_hits += 1;
                let h = 0x20 | (u32::from(depth & 15) << 1) | u32::from(replace >> 1);
                cw.add(h, 8, vec![(u64::from(replace & 1), 1)]);
            }
            (Step::Full { replace, push, .. }, Some((p, nc, cc))) => {
                stats.vertices_sent += 1;
                let rpm = (u64::from(replace) << 1) | u64::from(push);
                let (h6, rest) = split_header(pos_table.entry(p.token)?, p);
                let mut body = vec![(rpm, 3)];
                body.extend(rest);
                cw.add(0x40 | h6, 8, body);
                if let Some(nc) = nc {
                    let (h6, rest) = split_header(nor_table.entry(nc.token)?, nc);
                    cw.add(h6, 6, rest);
                }
                if let Some(cc) = cc {
                    let (h6, rest) = split_header(col_table.entry(cc.token)?, cc);
                    cw.add(h6, 6, rest);
                }
            }
            (Step::Full { .. }, None) => return Err(internal()),
        }
    }
    let bytes = cw.finish();
    stats.bytes = bytes.len();
    let header = CgHeader::triangles(has_n, has_c, has_c && o.alpha);
    Ok(Encoded { header, bytes, center, scale, stats })
}

fn internal() -> Error {
    Error::Internal
}

/// Centre (model units) and scale (normalised units per model unit) that
/// map the positions into the stream's frame, as Java 3D's
/// `CompressionStream` does: the largest extent maps to ±(1 − 2^(1-bits)),
/// one step inside the frame.
fn normalising_frame(positions: &[[f64; 3]], position_bits: u32) -> ([f64; 3], f64) {
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    for p in positions {
        for k in 0..3 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    let (center, range) = if positions.is_empty() {
        ([0.0; 3], 0.0)
    } else {
        ([0, 1, 2].map(|k| (lo[k] + hi[k]) / 2.0), (0..3).map(|k| hi[k] - lo[k]).fold(0.0, f64::max))
    };
    let pos_step = 1i32 << (16 - position_bits);
    let inside = 1.0 - f64::from(pos_step) / 32768.0;
    let scale = if range > 0.0 { 2.0 / range * inside } else { 1.0 };
    (center, scale)
}

/// The checks [`encode`] makes before any work.
fn check_input(mesh: &Mesh, o: &EncodeOptions) -> Result<()> {
    if !(1..=16).contains(&o.position_bits) || !(2..=16).contains(&o.color_bits) || o.normal_bits > 6 {
        return Err(Error::BitsOutOfRange { position: o.position_bits, color: o.color_bits, normal: o.normal_bits });
    }
    let n = mesh.positions.len();
    let lengths = [("normals", mesh.normals.map(<[_]>::len)), ("colours", mesh.colors.map(<[_]>::len))];
    if let Some((attribute, Some(len))) = lengths.into_iter().find(|(_, len)| len.is_some_and(|l| l != n)) {
        return Err(Error::AttributeLength { positions: n, attribute, len });
    }
    let max = u32::MAX as usize / 2;
    if n > max {
        return Err(Error::TooManyVertices { vertices: n, max });
    }
    if let Some((index, &triangle)) =
        mesh.triangles.iter().enumerate().find(|(_, t)| t.iter().any(|&i| i as usize >= n))
    {
        return Err(Error::IndexOutOfRange { index, triangle, vertices: n });
    }
    if let Some(vertex) = mesh.positions.iter().position(|p| p.iter().any(|c| !c.is_finite())) {
        return Err(Error::NonFinitePosition { vertex });
    }
    Ok(())
}
