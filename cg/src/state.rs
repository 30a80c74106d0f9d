//! Decoder state shared by the fast and the reference decoders: Huffman
//! table entries, the current position/colour/normal, the 16-entry mesh
//! buffer, and the "back end" that turns decoder output into vertices the
//! way Java 3D's `GeometryDecompressorShape3D` does (vertex formats,
//! global colour and normal, where a new vertex list starts).

use super::normals::{index_normal, normal_table, NormalCode, NormalTable};
use super::{QuantizedVertex, Vertex};
use crate::error::{StreamProblem, Table};

/// One entry of a decompression table (`HuffmanTableEntry` in Java 3D).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(crate) struct Entry {
    /// Tag length in bits, 0..=6.
    pub tag_len: u8,
    /// Data length before the right shift: 1..=16 for positions and colours, 0..=15 for normals.
    pub data_len: u8,
    /// Left shift applied to each decoded component.
    pub shift: u8,
    /// Absolute (replace) rather than relative (add).
    pub absolute: bool,
    /// Bits sent per component, `data_len - shift`, or [`Entry::INVALID`]
    /// when the shift exceeds the length: worked out once, when the table is
    /// set, for the fast decoder (the reference works it out at each use).
    pub sent: u8,
}

impl Entry {
    /// Bits sent per component, or an error when the shift exceeds the length
    /// (Java 3D would call `getBits` with a negative count and fail).
    #[inline(always)]
    pub(crate) fn sent_bits(&self, table: Table) -> Result<u32, StreamProblem> {
        if self.shift > self.data_len {
            return Err(self.shift_error(table));
        }
        Ok(u32::from(self.data_len - self.shift))
    }

    /// [`Self::sent`] of an entry whose shift exceeds its length.
    pub(crate) const INVALID: u8 = u8::MAX;

    /// [`Self::sent_bits`] as set with the table.
    #[inline(always)]
    pub(crate) fn sent(&self, table: Table) -> Result<u32, StreamProblem> {
        if self.sent == Self::INVALID {
            return Err(self.shift_error(table));
        }
        Ok(u32::from(self.sent))
    }

    #[cold]
    fn shift_error(&self, table: Table) -> StreamProblem {
        StreamProblem::ShiftExceedsLength { table, shift: self.shift, data_len: self.data_len }
    }
}

/// The fields of a setTable command: which table, the entries it fills, and the entry.
pub(crate) fn parse_set_table(header: u32, body: u32) -> (usize, usize, usize, Entry) {
    let table = ((header & 0x6) >> 1) as usize;
    let adr = ((header & 1) << 6) | ((body >> 9) & 0x3F);
    let mut data_len = ((body >> 5) & 0xF) as u8;
    if data_len == 0 && table != 2 {
        data_len = 16;
    }
    let shift = (body & 0xF) as u8;
    let absolute = (body >> 4) & 1 != 0;
    // Tag length = position of the leading 1 of the 7-bit address (0 for adr 0 or 1).
    let mut tag_len = 6u32;
    while tag_len > 0 && (adr >> tag_len) == 0 {
        tag_len -= 1;
    }
    let first = ((adr << (6 - tag_len)) & 0x3F) as usize;
    let count = 1usize << (6 - tag_len);
    let sent = data_len.checked_sub(shift).unwrap_or(Entry::INVALID);
    (table, first, count, Entry { tag_len: tag_len as u8, data_len, shift, absolute, sent })
}

/// A stream integer in the normalised frame (value / 32768, exact in f32).
#[inline(always)]
fn unit(v: i16) -> f32 {
    f32::from(v) * (1.0 / 32768.0)
}

#[cold]
fn outside_grid(code: NormalCode) -> StreamProblem {
    StreamProblem::NormalOutsideGrid { u: code.u, v: code.v }
}

/// One mesh-buffer slot (Java 3D `MeshBufferEntry`: all shorts).
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct MeshEntry {
    pub position: [i16; 3],
    /// The normal's code, u and v truncated to shorts as Java's slots hold them.
    pub normal: NormalCode,
    /// The float normal of `normal`, kept so a reference need not look it up
    /// again (same value: a code that decoded once decodes the same way; the
    /// short truncation only touches u, v of special normals, which ignore them).
    pub normal_f: [f32; 3],
    pub color: [i16; 4],
    /// `position` and `color` as floats (value / 32768), converted once when
    /// pushed so that a reference copies them.
    pub position_f: [f32; 3],
    pub color_f: [f32; 4],
}

/// Where vertices go: implemented by the triangle assemblers.
pub(crate) trait Sink {
    /// The decoder's current vertex ([`State::float_vertex`],
    /// [`State::quantized_vertex`]) with its generalized-strip replace code (0..=3).
    fn vertex(&mut self, state: &State, replace: u8) -> Result<(), StreamProblem>;
    /// The current vertex list ends (Java 3D builds a Shape3D from it).
    fn end_list(&mut self) -> Result<(), StreamProblem>;
}

/// Everything a decoder carries between commands.
pub(crate) struct State {
    pub tables: [[Entry; 64]; 3],
    pub position: [i16; 3],
    pub color: [i16; 4],
    /// `color` as floats (value / 32768), kept beside it: converting where
    /// the integers are computed, rather than reading them back later,
    /// avoids a store-forwarding stall per vertex.
    pub color_f: [f32; 4],
    pub normal: NormalCode,
    pub normal_f: [f32; 3],
    pub mesh: [MeshEntry; 16],
    /// Slot of the most recent push (Java starts at 15 so the first push lands in 0).
    pub mesh_index: usize,
    /// Pushes so far, capped at 16: references deeper than this are refused.
    pub pushes: usize,
    /// Java's `meshState`: may a mesh-buffer reference take the slot's normal / colour.
    pub use_mesh_normal: bool,
    pub use_mesh_color: bool,
    pub bundling_normal: bool,
    pub bundling_color: bool,
    pub doing_alpha: bool,
    /// Back end: a setState has been seen (Java's vertex list exists).
    pub list_open: bool,
    pub list_vertices: u64,
    pub format_normals: bool,
    pub global_normal: Option<(NormalCode, [f32; 3])>,
    pub global_color: Option<[i16; 4]>,
    /// Replace code of the vertex being decoded.
    pub last_replace: u8,
    /// Java 3D's normal table, as floats.
    pub normal_table: &'static NormalTable,
    /// The vertex the back end outputs now, kept up to date as position,
    /// normal, colour and the list's format change (so that outputting a
    /// vertex is a copy; [`Self::derived_vertex`] works it out from the
    /// integers instead, and the reference decoder outputs that).
    pub out: Vertex,
}

impl State {
    pub(crate) fn new() -> Self {
        State {
            tables: [[Entry::default(); 64]; 3],
            position: [0; 3],
            color: [0; 4],
            color_f: [0.0; 4],
            normal: NormalCode::default(),
            normal_f: [0.0; 3],
            // Java's zeroed slots: code (0, 0, 0, 0), whose normal is the table's first entry.
            mesh: [MeshEntry {
                normal_f: index_normal(normal_table(), NormalCode::default()).unwrap_or_default(),
                ..MeshEntry::default()
            }; 16],
            mesh_index: 15,
            pushes: 0,
            use_mesh_normal: false,
            use_mesh_color: false,
            bundling_normal: false,
            bundling_color: false,
            doing_alpha: false,
            list_open: false,
            list_vertices: 0,
            format_normals: false,
            global_normal: None,
            global_color: None,
            last_replace: 0,
            normal_table: normal_table(),
            out: Vertex::default(),
        }
    }

    /// Bring `out.normal` up to date: the global normal once one is set,
    /// else the current one; none unless the list has normals.
    #[inline(always)]
    fn refresh_normal(&mut self) {
        self.out.normal = if self.format_normals {
            Some(match &self.global_normal {
                Some((_, f)) => *f,
                None => self.normal_f,
            })
        } else {
            None
        };
    }

    /// Bring `out.color` up to date: bundled (alpha 1 unless the stream
    /// sends alpha), else the global colour with alpha 1, else none.
    #[inline(always)]
    fn refresh_color(&mut self) {
        self.out.color = if self.bundling_color {
            let c = self.color_f;
            Some([c[0], c[1], c[2], if self.doing_alpha { c[3] } else { 1.0 }])
        } else {
            self.global_color.map(|c| [unit(c[0]), unit(c[1]), unit(c[2]), 1.0])
        };
    }

    /// setState: new bundling flags, and (back end) a new vertex list.
    pub(crate) fn set_state(
        &mut self,
        normals: bool,
        colors: bool,
        alpha: bool,
        sink: &mut impl Sink,
    ) -> Result<(), StreamProblem> {
        self.bundling_normal = normals;
        self.bundling_color = colors;
        self.doing_alpha = alpha;
        if self.list_open {
            sink.end_list()?;
        }
        self.list_open = true;
        self.list_vertices = 0;
        self.format_normals = normals;
        self.refresh_normal();
        self.refresh_color();
        Ok(())
    }

    /// Set the current normal's code, computing its float value as Java
    /// does, then the optional push into the slot the vertex just pushed
    /// (Java's slots hold shorts: u and v are truncated there).
    #[inline(always)]
    pub(crate) fn set_normal_code(&mut self, code: NormalCode, push: bool) -> Result<(), StreamProblem> {
        let Some(n) = index_normal(self.normal_table, code) else { return Err(outside_grid(code)) };
        self.normal = code;
        self.normal_f = n;
        if self.format_normals && self.global_normal.is_none() {
            self.out.normal = Some(n);
        }
        if push {
            let slot = &mut self.mesh[self.mesh_index];
            slot.normal = NormalCode { u: i32::from(code.u as i16), v: i32::from(code.v as i16), ..code };
            slot.normal_f = n;
        }
        Ok(())
    }

    /// Apply a relative normal change with Java 3D's wrap rules
    /// (`GeometryDecompressor.processSetNormal`): one reflection across the
    /// edge the delta crossed, changing sextant or octant.
    #[inline(always)]
    pub(crate) fn add_normal_delta(&mut self, du: i32, dv: i32, push: bool) -> Result<(), StreamProblem> {
        let mut c = self.normal;
        c.u = c.u.wrapping_add(du);
        c.v = c.v.wrapping_add(dv);
        if !(c.u >= 0 && c.v >= 0 && c.u.wrapping_add(c.v) <= 64) {
            if c.u < 0 && c.v >= 0 {
                c.u = c.u.wrapping_neg();
                c.sextant = match c.sextant {
                    0 => 4,
                    1 => 5,
                    2 => 3,
                    3 => 2,
                    4 => 0,
                    5 => 1,
                    s => s,
                };
            } else if c.u >= 0 && c.v < 0 {
                c.v = c.v.wrapping_neg();
                c.octant ^= match c.sextant {
                    1 | 5 => 4,
                    0 | 4 => 2,
                    2 | 3 => 1,
                    _ => 0,
                };
            } else if c.u.wrapping_add(c.v) > 64 {
                c.u = 64i32.wrapping_sub(c.u);
                c.v = 64i32.wrapping_sub(c.v);
                c.sextant = match c.sextant {
                    0 => 2,
                    1 => 3,
                    2 => 0,
                    3 => 1,
                    4 => 5,
                    5 => 4,
                    s => s,
                };
            } else {
                return Err(StreamProblem::NormalDeltaOutside { du, dv });
            }
        }
        self.set_normal_code(c, push)
    }

    /// After a setNormal body: (back end) the global normal.
    #[inline]
    pub(crate) fn finish_normal(&mut self, sink: &mut impl Sink) -> Result<(), StreamProblem> {
        self.use_mesh_normal = false;
        if !self.bundling_normal {
            if !self.list_open {
                return Err(StreamProblem::NormalBeforeSetState);
            }
            if !self.format_normals {
                if self.list_vertices > 0 {
                    sink.end_list()?;
                    self.list_vertices = 0;
                }
                self.format_normals = true;
            }
            self.global_normal = Some((self.normal, self.normal_f));
            self.refresh_normal();
        }
        Ok(())
    }

    /// After a setColor body: (back end) the global colour.
    #[inline]
    pub(crate) fn finish_color(&mut self, sink: &mut impl Sink) -> Result<(), StreamProblem> {
        self.use_mesh_color = false;
        if !self.bundling_color {
            if !self.list_open {
                return Err(StreamProblem::ColorBeforeSetState);
            }
            if self.list_vertices > 0 {
                sink.end_list()?;
                self.list_vertices = 0;
            }
            self.global_color = Some(self.color);
            self.refresh_color();
        }
        Ok(())
    }

    /// Apply a colour body's components (`values` already shifted), then the
    /// optional push into the slot [`Self::apply_position`] just pushed.
    ///
    /// The colour is built in a local and stored whole: writing the fields
    /// one by one and reading the array back stalls store forwarding.
    #[inline(always)]
    pub(crate) fn apply_color(&mut self, absolute: bool, values: [i32; 4], push: bool) {
        let old = if absolute { [0i16; 4] } else { self.color };
        let alpha = if self.doing_alpha { old[3].wrapping_add(values[3] as i16) } else { self.color[3] };
        let c = [
            old[0].wrapping_add(values[0] as i16),
            old[1].wrapping_add(values[1] as i16),
            old[2].wrapping_add(values[2] as i16),
            alpha,
        ];
        let f = c.map(unit);
        self.color = c;
        self.color_f = f;
        if self.bundling_color {
            self.out.color = Some([f[0], f[1], f[2], if self.doing_alpha { f[3] } else { 1.0 }]);
        }
        if push {
            let slot = &mut self.mesh[self.mesh_index];
            slot.color = c;
            slot.color_f = f;
        }
    }

    /// Apply a position body's components, then the optional push (built
    /// in a local and stored whole, as [`Self::apply_color`]).
    #[inline(always)]
    pub(crate) fn apply_position(&mut self, absolute: bool, values: [i32; 3], push: bool) {
        let old = if absolute { [0i16; 3] } else { self.position };
        let p = [
            old[0].wrapping_add(values[0] as i16),
            old[1].wrapping_add(values[1] as i16),
            old[2].wrapping_add(values[2] as i16),
        ];
        let f = p.map(unit);
        self.position = p;
        self.out.position = f;
        if push {
            self.mesh_index = (self.mesh_index + 1) & 15;
            self.pushes = (self.pushes + 1).min(16);
            let slot = &mut self.mesh[self.mesh_index];
            slot.position = p;
            slot.position_f = f;
        }
    }

    /// A mesh-buffer reference `depth` pushes back (0 = most recent).
    #[inline]
    pub(crate) fn mesh_reference(&mut self, depth: usize) -> Result<(), StreamProblem> {
        if depth >= self.pushes {
            return Err(StreamProblem::MeshReferenceTooDeep { depth, pushes: self.pushes });
        }
        let entry = &self.mesh[(self.mesh_index + 16 - depth) & 15];
        self.position = entry.position;
        self.out.position = entry.position_f;
        if self.bundling_normal && self.use_mesh_normal {
            self.normal = entry.normal;
            self.normal_f = entry.normal_f;
            if self.global_normal.is_none() {
                // format_normals holds while bundling normals.
                self.out.normal = Some(entry.normal_f);
            }
        }
        if self.bundling_color && self.use_mesh_color {
            let (c, f) = (entry.color, entry.color_f);
            let alpha = self.doing_alpha;
            self.color = [c[0], c[1], c[2], if alpha { c[3] } else { self.color[3] }];
            self.color_f = [f[0], f[1], f[2], if alpha { f[3] } else { self.color_f[3] }];
            self.out.color = Some([f[0], f[1], f[2], if alpha { f[3] } else { 1.0 }]);
        }
        Ok(())
    }

    /// Output the current vertex (after a vertex command or a mesh-buffer reference).
    #[inline(always)]
    pub(crate) fn output_vertex(&mut self, replace: u8, sink: &mut impl Sink) -> Result<(), StreamProblem> {
        if !self.list_open {
            return Err(StreamProblem::VertexBeforeSetState);
        }
        self.use_mesh_normal = true;
        self.use_mesh_color = true;
        self.list_vertices += 1;
        sink.vertex(self, replace)
    }

    /// The normal the back end gives the current vertex: the global normal
    /// once one is set, else the current one; none unless the list has normals.
    #[inline(always)]
    fn output_normal(&self) -> Option<(NormalCode, [f32; 3])> {
        if !self.format_normals {
            return None;
        }
        Some(self.global_normal.unwrap_or((self.normal, self.normal_f)))
    }

    /// The colour the back end gives the current vertex (bundled, else the
    /// global colour with alpha 1, else none) as stream integers.
    #[inline(always)]
    fn output_color(&self) -> Option<([i16; 4], bool)> {
        if self.bundling_color {
            Some((self.color, self.doing_alpha))
        } else {
            self.global_color.map(|c| (c, false))
        }
    }

    /// The current vertex in the normalised frame (kept up to date).
    #[inline(always)]
    pub(crate) fn float_vertex(&self) -> Vertex {
        self.out
    }

    /// The current vertex in the normalised frame, worked out from the
    /// integers and the back end's rules rather than kept up to date: the
    /// reference decoder outputs this, so the tests that make the two
    /// decoders agree check [`Self::float_vertex`] too.
    pub(crate) fn derived_vertex(&self) -> Vertex {
        let normal = self.output_normal().map(|(code, f)| index_normal(self.normal_table, code).unwrap_or(f));
        let color = self
            .output_color()
            .map(|(c, alpha)| [unit(c[0]), unit(c[1]), unit(c[2]), if alpha { unit(c[3]) } else { 1.0 }]);
        Vertex { position: self.position.map(unit), normal, color }
    }

    /// The current vertex as stream integers.
    #[inline(always)]
    pub(crate) fn quantized_vertex(&self) -> QuantizedVertex {
        QuantizedVertex {
            position: self.position,
            normal: self.output_normal().map(|n| n.0),
            color: self.output_color().map(|c| c.0),
        }
    }

    /// The end of the stream: the back end builds its last Shape3D.
    pub(crate) fn finish(&mut self, sink: &mut impl Sink) -> Result<(), StreamProblem> {
        if self.list_open {
            sink.end_list()?;
        }
        Ok(())
    }
}
