//! Generalized strips to triangles, as Java 3D's back end
//! (`GeneralizedStrip.toStripsAndFans`, `toTriangles`, `toLineStrips`)
//! turns them, with front faces counter-clockwise.
//!
//! Replace codes: 0 = restart clockwise, 1 = restart counter-clockwise,
//! 2 = replace middle (fan), 3 = replace oldest (strip). A restart takes the
//! next two vertices whatever their codes, and the first vertex of a list is
//! a restart whatever its code (counter-clockwise unless it says 0).
//!
//! Two assemblers: [`JavaOrder`] keeps each vertex list and converts it at
//! its end exactly as Java does (all strips' triangles, then all fans', with
//! Java's vertex order inside each triangle), and [`Streaming`] emits each
//! triangle as soon as its vertex arrives, with the same orientation.

use super::state::{Sink, State};
use super::{BlockKind, QuantizedVertex, Vertex};
use crate::error::StreamProblem;

const RESTART_CW: u8 = 0;
const REPLACE_MIDDLE: u8 = 2;
const REPLACE_OLDEST: u8 = 3;

/// One vertex list's triangles as (strips, fans) of indices, Java's way.
/// `Err` when a restart lacks its two following vertices.
pub(crate) fn java_triangles(flags: &[u8]) -> Result<Vec<[usize; 3]>, StreamProblem> {
    let size = flags.len();
    if size == 0 {
        // Java throws here (GeneralizedStrip0); an empty list simply has no triangles.
        return Ok(Vec::new());
    }
    // Java emits all strip triangles, then all fan triangles.
    let mut out: Vec<[usize; 3]> = Vec::with_capacity(size);
    let mut fans: Vec<[usize; 3]> = Vec::new();
    let (mut start, mut length) = (0usize, 3usize);
    let mut cur = flags[0];
    let mut ccw = cur != RESTART_CW;
    let mut v = 3usize;
    let mut transition = false;
    if let Some(&f) = flags.get(v) {
        cur = f;
    }
    while let Some(&new) = flags.get(v) {
        if new == cur && new >= REPLACE_MIDDLE {
            length += 1;
            v += 1;
            continue;
        }
        if cur == REPLACE_MIDDLE {
            fan(start, length, ccw, transition, &mut fans);
        } else {
            strip(start, length, ccw, &mut out);
        }
        if new < REPLACE_MIDDLE {
            ccw = new != RESTART_CW;
            start = v;
            length = 3;
            v += 3;
            transition = false;
            if let Some(&f) = flags.get(v) {
                cur = f;
            }
        } else {
            if new == REPLACE_OLDEST {
                ccw = !ccw;
                start = v - 2;
                length = 3;
            } else {
                if length % 2 == 0 {
                    ccw = !ccw;
                }
                start = v - 3;
                length = 4;
            }
            v += 1;
            transition = true;
            cur = new;
        }
    }
    if v != size {
        return Err(StreamProblem::UnfinishedStrip);
    }
    if cur == REPLACE_MIDDLE {
        fan(start, length, ccw, transition, &mut fans);
    } else {
        strip(start, length, ccw, &mut out);
    }
    out.extend(fans);
    Ok(out)
}

/// The triangles of one strip run given as vertex indices `run(0..n)`
/// (Java's stripsToTriangles: odd triangles swap their first two vertices).
fn run_triangles(n: usize, run: impl Fn(usize) -> usize, out: &mut Vec<[usize; 3]>) {
    for j in 0..n.saturating_sub(2) {
        out.push(if j % 2 == 0 { [run(j), run(j + 1), run(j + 2)] } else { [run(j + 1), run(j), run(j + 2)] });
    }
}

/// A strip's triangles, its runs reversed into counter-clockwise order when
/// needed (Java's addStrip).
fn strip(start: usize, length: usize, ccw: bool, out: &mut Vec<[usize; 3]>) {
    if ccw {
        run_triangles(length, |i| start + i, out);
    } else if length % 2 == 1 {
        run_triangles(length, |i| start + length - 1 - i, out);
    } else if length == 4 {
        let order = [start, start + 2, start + 1, start + 3];
        run_triangles(4, |i| order[i], out);
    } else {
        out.push([start, start + 2, start + 1]);
        if length > 3 {
            run_triangles(length - 1, |i| start + 1 + i, out);
        }
    }
}

/// A fan's triangles (Java's addFan): a transition fan skips its first triangle.
fn fan(start: usize, length: usize, ccw: bool, transition: bool, out: &mut Vec<[usize; 3]>) {
    let mut f: smallvec::SmallVec<[usize; 16]> = smallvec::smallvec![start];
    if ccw {
        if !transition {
            f.push(start + 1);
        }
        f.extend(start + 2..start + length);
    } else {
        f.extend((start + 2..start + length).rev());
        if !transition {
            f.push(start + 1);
        }
    }
    for j in 0..f.len().saturating_sub(2) {
        out.push([f[0], f[j + 1], f[j + 2]]);
    }
}

/// One vertex list's line strips (Java's toLineStrips): restarts begin a new strip.
pub(crate) fn java_lines(flags: &[u8]) -> Result<Vec<[usize; 2]>, StreamProblem> {
    let size = flags.len();
    if size == 0 {
        return Ok(Vec::new());
    }
    let mut out = Vec::new();
    let (mut start, mut length, mut v) = (0usize, 2usize, 2usize);
    while let Some(&f) = flags.get(v) {
        if f >= REPLACE_MIDDLE {
            length += 1;
            v += 1;
        } else {
            out.extend((start..start + length - 1).map(|i| [i, i + 1]));
            start = v;
            length = 2;
            v += 2;
        }
    }
    if v != size {
        return Err(StreamProblem::UnfinishedLine);
    }
    out.extend((start..start + length - 1).map(|i| [i, i + 1]));
    Ok(out)
}

/// What [`JavaOrder`] collects.
#[derive(Default)]
pub(crate) struct Collected {
    pub triangles: Vec<[Vertex; 3]>,
    pub quantized: Vec<[QuantizedVertex; 3]>,
    pub lines: Vec<[Vertex; 2]>,
    pub points: Vec<Vertex>,
}

/// Keeps each vertex list and converts it at its end, in Java's order.
pub(crate) struct JavaOrder {
    kind: BlockKind,
    /// Take each vertex as [`State::derived_vertex`] works it out (the
    /// reference decoder) rather than as the state keeps it.
    derive: bool,
    list: Vec<(QuantizedVertex, Vertex)>,
    flags: Vec<u8>,
    pub out: Collected,
}

impl JavaOrder {
    pub(crate) fn new(kind: BlockKind) -> Self {
        JavaOrder { kind, derive: false, list: Vec::new(), flags: Vec::new(), out: Collected::default() }
    }

    /// [`Self::new`] for a stream of `bytes` bytes: room for as many
    /// vertices as it can hold (each takes at least 9 bits, a mesh-buffer
    /// reference), so that the list does not grow by copying (which had
    /// been most of the time); at most 65 536 (6 MB, only the pages used
    /// are touched), longer lists grow from there.
    pub(crate) fn for_stream(kind: BlockKind, bytes: usize) -> Self {
        let most = (bytes * 8 / 9).min(1 << 16);
        let mut j = Self::new(kind);
        j.list.reserve(most);
        j.flags.reserve(most);
        j
    }

    /// [`Self::new`] for the reference decoder: vertices by [`State::derived_vertex`].
    pub(crate) fn derived(kind: BlockKind) -> Self {
        JavaOrder { derive: true, ..Self::new(kind) }
    }
}

impl Sink for JavaOrder {
    fn vertex(&mut self, state: &State, replace: u8) -> Result<(), StreamProblem> {
        let v = if self.derive { state.derived_vertex() } else { state.float_vertex() };
        self.list.push((state.quantized_vertex(), v));
        self.flags.push(replace);
        Ok(())
    }

    fn end_list(&mut self) -> Result<(), StreamProblem> {
        match self.kind {
            BlockKind::Triangles => {
                // A list's triangles never outnumber its vertices: one
                // allocation per list, not a doubling series.
                self.out.triangles.reserve(self.list.len());
                self.out.quantized.reserve(self.list.len());
                for t in java_triangles(&self.flags)? {
                    let (a, b, c) = (&self.list[t[0]], &self.list[t[1]], &self.list[t[2]]);
                    self.out.triangles.push([a.1, b.1, c.1]);
                    self.out.quantized.push([a.0, b.0, c.0]);
                }
            }
            BlockKind::Lines => {
                for l in java_lines(&self.flags)? {
                    self.out.lines.push([self.list[l[0]].1, self.list[l[1]].1]);
                }
            }
            BlockKind::Points => self.out.points.extend(self.list.iter().map(|p| p.1)),
        }
        self.list.clear();
        self.flags.clear();
        Ok(())
    }
}

/// A primitive as the streaming decoder hands it over: its vertices lent,
/// not copied (three 48-byte copies per triangle were a twentieth of the
/// streaming decoder's instructions).
#[derive(Clone, Copy, Debug)]
pub enum Primitive<'a> {
    /// A point (point blocks).
    Point(&'a Vertex),
    /// A line segment (line blocks).
    Line([&'a Vertex; 2]),
    /// A triangle, counter-clockwise seen from its front (triangle blocks).
    Triangle([&'a Vertex; 3]),
}

/// A restart's window: slots 0, 1, 2.
const WINDOW_RESTART: u32 = 0x02_01_00;

/// The three slots of a packed window, each masked to 0..=3.
#[inline(always)]
fn slots_of(window: u32) -> [usize; 3] {
    [0, 8, 16].map(|shift| ((window >> shift) & 3) as usize)
}

/// Emits each primitive as its last vertex arrives: memory is the last three vertices.
///
/// Triangles: after a restart's three vertices, each vertex makes one
/// triangle with two of the window's: replace-oldest (a strip step) drops
/// the oldest, replace-middle (a fan step) the middle. Orientation needs one
/// bit: the first triangle is reversed when the restart says clockwise;
/// every strip step flips it and a fan step keeps it. (That is Java 3D's
/// `GeneralizedStrip` bookkeeping — a strip's odd triangles swap, a fan
/// after a strip of even length changes direction — folded into one rule;
/// the tests hold it to [`java_triangles`] on random streams.) The steady
/// state is branch-free: strips and fans alternate as the data says.
pub(crate) struct Streaming<F> {
    kind: BlockKind,
    f: F,
    /// Vertex storage (a fourth slot so that indices masked by 3 need no
    /// bounds check). A new vertex is written once, into the slot it takes.
    slots: [Vertex; 4],
    /// The slots of the oldest, middle and newest vertex in bytes 0, 1, 2:
    /// packed so that it is stored and loaded whole (three byte stores read
    /// back as one load would stall store forwarding at every vertex).
    window: u32,
    /// Vertices of the current restart received: triangles 0..=3 (3: the
    /// window is full), lines 0..=2 (2: a segment has been drawn).
    filled: u8,
    /// Emit the window's triangle as (oldest, newest, middle) rather than
    /// (oldest, middle, newest).
    flip: bool,
}

impl<F: FnMut(Primitive)> Streaming<F> {
    pub(crate) fn new(kind: BlockKind, f: F) -> Self {
        Streaming { kind, f, slots: [Vertex::default(); 4], window: WINDOW_RESTART, filled: 0, flip: false }
    }

    /// Emit the window's triangle in the orientation `flip` says.
    #[inline(always)]
    fn emit(&mut self) {
        let [a, b, c] = slots_of(self.window);
        let (q, r) = if self.flip { (c, b) } else { (b, c) };
        (self.f)(Primitive::Triangle([&self.slots[a], &self.slots[q], &self.slots[r]]));
    }

    /// A triangle vertex with its replace code.
    #[inline(always)]
    fn triangle_vertex(&mut self, state: &State, replace: u8) {
        if self.filled == 3 && replace >= REPLACE_MIDDLE {
            // A strip step takes the oldest's slot, a fan step the middle's.
            let [a, b, c] = slots_of(self.window);
            let strip = replace == REPLACE_OLDEST;
            let (slot, keep) = if strip { (a, b) } else { (b, a) };
            self.slots[slot] = state.float_vertex();
            self.window = (keep | (c << 8) | (slot << 16)) as u32;
            self.flip ^= strip;
            self.emit();
            return;
        }
        if self.filled == 3 || self.filled == 0 {
            // A restart (the first vertex of a list is one whatever its code).
            self.filled = 0;
            self.window = WINDOW_RESTART;
            self.flip = replace == RESTART_CW;
        }
        // The restart's vertices fill the window in order.
        self.slots[usize::from(self.filled & 3)] = state.float_vertex();
        self.filled += 1;
        if self.filled == 3 {
            self.emit();
        }
    }
}

impl<F: FnMut(Primitive)> Sink for Streaming<F> {
    #[inline(always)]
    fn vertex(&mut self, state: &State, replace: u8) -> Result<(), StreamProblem> {
        match self.kind {
            BlockKind::Triangles => self.triangle_vertex(state, replace),
            BlockKind::Points => (self.f)(Primitive::Point(&state.float_vertex())),
            BlockKind::Lines => {
                // A line strip: a restart takes one more vertex, then each vertex adds a segment.
                if self.filled == 0 || (self.filled == 2 && replace < REPLACE_MIDDLE) {
                    self.slots[1] = state.float_vertex();
                    self.filled = 1;
                } else {
                    self.slots[0] = self.slots[1];
                    self.slots[1] = state.float_vertex();
                    self.filled = 2;
                    (self.f)(Primitive::Line([&self.slots[0], &self.slots[1]]));
                }
            }
        }
        Ok(())
    }

    fn end_list(&mut self) -> Result<(), StreamProblem> {
        let incomplete = match self.kind {
            BlockKind::Triangles => self.filled == 1 || self.filled == 2,
            BlockKind::Lines => self.filled == 1,
            BlockKind::Points => false,
        };
        self.filled = 0;
        if incomplete {
            return Err(match self.kind {
                BlockKind::Lines => StreamProblem::UnfinishedLine,
                _ => StreamProblem::UnfinishedStrip,
            });
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn strip_of_four_ccw() {
        // Flags 1,3,3,3: one strip of 4 vertices: (0,1,2) and (2,1,3).
        assert_eq!(java_triangles(&[1, 3, 3, 3]).unwrap(), vec![[0, 1, 2], [2, 1, 3]]);
    }

    #[test]
    fn fan_and_transitions() {
        // Restart, then replace-middle twice: fan around 0.
        assert_eq!(java_triangles(&[1, 3, 3, 2, 2]).unwrap(), vec![[0, 1, 2], [0, 2, 3], [0, 3, 4]]);
        // A clockwise restart reverses every triangle.
        assert_eq!(java_triangles(&[0, 3, 3]).unwrap(), vec![[2, 1, 0]]);
        // Restart without two followers.
        assert!(java_triangles(&[1, 3, 3, 1, 3]).is_err());
        assert!(java_triangles(&[1]).is_err());
    }
}
