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

const RESTART_CW: u8 = 0;
const REPLACE_MIDDLE: u8 = 2;
const REPLACE_OLDEST: u8 = 3;

/// One vertex list's triangles as (strips, fans) of indices, Java's way.
/// `Err` when a restart lacks its two following vertices.
pub(crate) fn java_triangles(flags: &[u8]) -> Result<Vec<[usize; 3]>, String> {
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
        return Err("a strip restart is not followed by two more vertices".into());
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
pub(crate) fn java_lines(flags: &[u8]) -> Result<Vec<[usize; 2]>, String> {
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
        return Err("a line strip restart is not followed by another vertex".into());
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

    /// [`Self::new`] for the reference decoder: vertices by [`State::derived_vertex`].
    pub(crate) fn derived(kind: BlockKind) -> Self {
        JavaOrder { derive: true, ..Self::new(kind) }
    }
}

impl Sink for JavaOrder {
    fn vertex(&mut self, state: &State, replace: u8) -> Result<(), String> {
        let v = if self.derive { state.derived_vertex() } else { state.float_vertex() };
        self.list.push((state.quantized_vertex(), v));
        self.flags.push(replace);
        Ok(())
    }

    fn end_list(&mut self) -> Result<(), String> {
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

/// A primitive as the streaming decoder hands it over: its vertices lent
/// (copying three 48-byte vertices per triangle was a quarter of the
/// streaming decoder's time).
#[derive(Clone, Copy, Debug)]
pub enum Primitive<'a> {
    /// A point (point blocks).
    Point(&'a Vertex),
    /// A line segment (line blocks).
    Line([&'a Vertex; 2]),
    /// A triangle, counter-clockwise seen from its front (triangle blocks).
    Triangle([&'a Vertex; 3]),
}

#[derive(Clone, Copy, PartialEq, Eq)]
enum Run {
    /// Just restarted: the fourth vertex decides strip or fan.
    Pending,
    /// A strip of this many vertices so far.
    Strip(usize),
    Fan,
}

/// Emits each primitive as its last vertex arrives: memory is the last three vertices.
pub(crate) struct Streaming<F> {
    kind: BlockKind,
    f: F,
    /// Vertex storage; `window` says which slot holds the oldest, middle and
    /// newest. A new vertex is written once, into the slot it takes.
    slots: [Vertex; 3],
    window: [usize; 3],
    /// Vertices in the window (a list starts empty).
    filled: usize,
    /// Vertices still owed to the current restart.
    need: usize,
    ccw: bool,
    run: Run,
}

impl<F: FnMut(Primitive)> Streaming<F> {
    pub(crate) fn new(kind: BlockKind, f: F) -> Self {
        Streaming {
            kind,
            f,
            slots: [Vertex::default(); 3],
            window: [0, 1, 2],
            filled: 0,
            need: 0,
            ccw: true,
            run: Run::Pending,
        }
    }

    /// Emit the triangle of slots `listed`, reversed when the run is clockwise.
    #[inline(always)]
    fn emit(&mut self, listed: [usize; 3]) {
        let [p, q, r] = if self.ccw { listed } else { [listed[0], listed[2], listed[1]] };
        (self.f)(Primitive::Triangle([&self.slots[p], &self.slots[q], &self.slots[r]]));
    }
}

impl<F: FnMut(Primitive)> Sink for Streaming<F> {
    #[inline]
    fn vertex(&mut self, state: &State, replace: u8) -> Result<(), String> {
        match self.kind {
            BlockKind::Points => {
                (self.f)(Primitive::Point(&state.float_vertex()));
                return Ok(());
            }
            BlockKind::Lines => {
                if self.filled == 0 || (self.need == 0 && replace < REPLACE_MIDDLE) {
                    self.slots[1] = state.float_vertex();
                    self.filled = 1;
                    self.need = 1;
                } else {
                    self.slots[0] = self.slots[1];
                    self.slots[1] = state.float_vertex();
                    self.need = 0;
                    (self.f)(Primitive::Line([&self.slots[0], &self.slots[1]]));
                }
                return Ok(());
            }
            BlockKind::Triangles => {}
        }
        let [a, b, c] = self.window;
        if self.filled == 0 || (self.need == 0 && replace < REPLACE_MIDDLE) {
            self.ccw = replace != RESTART_CW;
            self.window = [0, 1, 2];
            self.slots[0] = state.float_vertex();
            self.filled = 1;
            self.need = 2;
            self.run = Run::Pending;
        } else if self.need > 0 {
            self.slots[self.filled] = state.float_vertex();
            self.filled += 1;
            self.need -= 1;
            if self.need == 0 {
                self.emit([0, 1, 2]);
            }
        } else if replace == REPLACE_OLDEST {
            // The new vertex takes the oldest's slot.
            self.slots[a] = state.float_vertex();
            let listed = match self.run {
                Run::Fan => {
                    self.ccw = !self.ccw;
                    self.run = Run::Strip(3);
                    [b, c, a]
                }
                Run::Pending | Run::Strip(_) => {
                    let len = match self.run {
                        Run::Strip(l) => l + 1,
                        _ => 4,
                    };
                    self.run = Run::Strip(len);
                    if (len - 3) % 2 == 0 {
                        [b, c, a]
                    } else {
                        [c, b, a]
                    }
                }
            };
            self.window = [b, c, a];
            self.emit(listed);
        } else {
            if let Run::Strip(len) = self.run {
                if len % 2 == 0 {
                    self.ccw = !self.ccw;
                }
            }
            // The new vertex takes the middle's slot.
            self.slots[b] = state.float_vertex();
            self.run = Run::Fan;
            self.window = [a, c, b];
            self.emit([a, c, b]);
        }
        Ok(())
    }

    fn end_list(&mut self) -> Result<(), String> {
        let incomplete = self.filled > 0 && self.need > 0;
        self.filled = 0;
        self.need = 0;
        if incomplete {
            return Err(match self.kind {
                BlockKind::Lines => "a line strip restart is not followed by another vertex".into(),
                _ => "a strip restart is not followed by two more vertices".into(),
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
