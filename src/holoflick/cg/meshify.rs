//! The meshifier: orders triangles into generalized strips and decides which
//! vertices go into the 16-entry mesh buffer, so that each vertex is sent
//! about once and later uses cost a 9-bit mesh-buffer reference.
//!
//! Greedy: a strip continues across the window's newest edge (replace
//! oldest) or its fan edge (replace middle), choosing the neighbour whose new
//! vertex is already buffered, else the one with fewest unvisited neighbours.
//! When it cannot continue it restarts at the unvisited triangle with most
//! vertices in the buffer, so rows of strips follow each other and the
//! shared row of vertices is referenced, not resent. Every emitted triangle's
//! orientation is checked against the rules Java 3D's back end applies
//! (`GeneralizedStrip`): a continuation that would flip a triangle is not
//! taken.

/// One vertex command of the stream.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Step {
    /// Send the vertex's data; push it into the mesh buffer when `push`.
    Full { vertex: u32, replace: u8, push: bool },
    /// Reference the mesh-buffer entry `depth` pushes back (0 = newest).
    Reference { vertex: u32, depth: u8, replace: u8 },
}

const MESH_BUFFER: u64 = 16;
/// Bits of one vertex command without data (header and replace/push bits, or a reference).
const COMMAND_BITS: u64 = 9;
/// Rough bits of a vertex's data (position, normal, colour), the price of sending it twice.
const FULL_VERTEX_BITS: u64 = 60;
/// A strip stops after this many pushes, so that the next strip beside it
/// finds the shared row of vertices still in the 16-entry buffer.
const STRIP_PUSHES: u64 = 8;

/// A next triangle for the strip greedy: (cost, is a restart, tie-break,
/// triangle, for a continuation: new vertex, replace code, run, winding).
type Candidate = (u64, bool, usize, usize, Option<(u32, u8, Run, bool)>);

#[derive(Clone, Copy, PartialEq, Eq)]
enum Run {
    Pending,
    Strip(usize),
    Fan,
}

struct Meshifier<'a> {
    triangles: &'a [[u32; 3]],
    /// Triangles around each vertex: `incident[offsets[v]..offsets[v + 1]]`.
    offsets: Vec<usize>,
    incident: Vec<u32>,
    visited: Vec<bool>,
    /// Unvisited triangles around each vertex.
    remaining: Vec<u32>,
    /// Push serial of each vertex's latest push (u64::MAX: never).
    pushed_at: Vec<u64>,
    pushes: u64,
    /// Pushes since the last restart.
    strip_pushes: u64,
    /// Vertices sent at least once.
    sent: Vec<bool>,
    /// The last 16 pushed vertices, by serial % 16.
    fifo: [u32; 16],
    steps: Vec<Step>,
    window: [u32; 3],
    run: Run,
    ccw: bool,
}

/// Order `triangles` (indices below `vertex_count`) into vertex commands:
/// both strategies are tried and the one with fewer data-carrying vertices
/// (ties: fewer commands) is kept.
pub(crate) fn meshify(triangles: &[[u32; 3]], vertex_count: usize) -> Vec<Step> {
    let mut strips = Meshifier::new(triangles, vertex_count);
    strips.run_all();
    let mut fans = Meshifier::new(triangles, vertex_count);
    fans.run_fans();
    let cost = |steps: &[Step]| {
        let full = steps.iter().filter(|s| matches!(s, Step::Full { .. })).count();
        full * FULL_VERTEX_BITS as usize + steps.len() * COMMAND_BITS as usize
    };
    if cost(&fans.steps) < cost(&strips.steps) {
        fans.steps
    } else {
        strips.steps
    }
}

impl<'a> Meshifier<'a> {
    fn new(triangles: &'a [[u32; 3]], vertex_count: usize) -> Self {
        let mut counts = vec![0usize; vertex_count + 1];
        for t in triangles {
            for &v in t {
                counts[v as usize + 1] += 1;
            }
        }
        for i in 0..vertex_count {
            counts[i + 1] += counts[i];
        }
        let offsets = counts.clone();
        let mut fill = counts;
        let mut incident = vec![0u32; offsets[vertex_count]];
        for (ti, t) in triangles.iter().enumerate() {
            for &v in t {
                incident[fill[v as usize]] = ti as u32;
                fill[v as usize] += 1;
            }
        }
        let remaining: Vec<u32> = (0..vertex_count).map(|v| (offsets[v + 1] - offsets[v]) as u32).collect();
        Meshifier {
            triangles,
            offsets,
            incident,
            visited: vec![false; triangles.len()],
            remaining,
            pushed_at: vec![u64::MAX; vertex_count],
            pushes: 0,
            sent: vec![false; vertex_count],
            strip_pushes: 0,
            fifo: [0; 16],
            steps: Vec::with_capacity(triangles.len() * 3 / 2),
            window: [0; 3],
            run: Run::Pending,
            ccw: true,
        }
    }

    /// Could triangle `t` continue the strip?
    fn can_continue(&self, t: usize) -> bool {
        let [a, b, c] = self.window;
        [(b, c, 3u8), (a, c, 2u8)].iter().any(|&(x, y, replace)| {
            let tri = self.triangles[t];
            tri.contains(&x)
                && tri.contains(&y)
                && tri.iter().find(|&&v| v != x && v != y).is_some_and(|&w| self.predict(w, replace, t).is_some())
        })
    }

    /// Continue the strip with triangle `t` if the window allows it with the
    /// right orientation; true when done.
    fn try_continue(&mut self, t: usize) -> bool {
        let [a, b, c] = self.window;
        for (x, y, replace) in [(b, c, 3u8), (a, c, 2u8)] {
            let tri = self.triangles[t];
            if !tri.contains(&x) || !tri.contains(&y) {
                continue;
            }
            let Some(&w) = tri.iter().find(|&&v| v != x && v != y) else { continue };
            let Some((run, ccw)) = self.predict(w, replace, t) else { continue };
            self.mark(t);
            self.window = if replace == 3 { [b, c, w] } else { [a, c, w] };
            self.run = run;
            self.ccw = ccw;
            self.send(w, replace);
            return true;
        }
        false
    }

    /// Restart the strip with triangle `t`, rotated to begin at `first` when it is a corner.
    fn restart(&mut self, t: usize, first: Option<u32>) {
        let [i, j, k] = self.triangles[t];
        let pick = match first {
            Some(f) if f == j => [j, k, i],
            Some(f) if f == k => [k, i, j],
            _ => [i, j, k],
        };
        self.mark(t);
        self.strip_pushes = 0;
        self.window = pick;
        self.send(pick[0], 1);
        self.send(pick[1], 3);
        self.send(pick[2], 3);
        self.run = Run::Pending;
        self.ccw = true;
    }

    /// Tipsify-style order (Sander, Nehab and Barczak 2007, "Fast triangle
    /// reordering for vertex locality"): emit every triangle around a fan
    /// vertex in counter-clockwise order (a generalized-strip fan), then move
    /// to the neighbour that is oldest in the mesh buffer while its fan still
    /// fits before eviction.
    fn run_fans(&mut self) {
        let vertex_count = self.remaining.len();
        let mut dead: Vec<u32> = Vec::new();
        let mut cursor = 0usize;
        let mut active = false;
        let mut fan = (0..vertex_count).find(|&v| self.remaining[v] > 0).map(|v| v as u32);
        while let Some(f) = fan {
            let mut ring: Vec<u32> = Vec::new();
            // Around f, start where the counter-clockwise chain starts.
            for _ in 0..self.around(f).len() {
                let Some(mut t) = self.around(f).iter().map(|&t| t as usize).find(|&t| !self.visited[t]) else { break };
                // A triangle around f that continues the current strip saves a restart.
                let continuing = if active {
                    self.around(f).iter().map(|&u| u as usize).find(|&u| !self.visited[u] && self.can_continue(u))
                } else {
                    None
                };
                if let Some(u) = continuing {
                    t = u;
                }
                for _ in 0..if continuing.is_some() { 0 } else { self.around(f).len() } {
                    let x = corner_after(self.triangles[t], f);
                    // The triangle before t around f holds the directed edge x -> f.
                    match self
                        .around(f)
                        .iter()
                        .map(|&u| u as usize)
                        .find(|&u| !self.visited[u] && u != t && corner_after(self.triangles[u], x) == f)
                    {
                        Some(u) if u != t => t = u,
                        _ => break,
                    }
                }
                if !(active && self.try_continue(t)) {
                    self.restart(t, Some(f));
                    active = true;
                }
                ring.extend(self.triangles[t]);
                dead.extend(self.triangles[t]);
                // Follow the fan counter-clockwise while it continues.
                loop {
                    let y = corner_before(self.triangles[t], f);
                    let next = self
                        .around(f)
                        .iter()
                        .map(|&u| u as usize)
                        .find(|&u| !self.visited[u] && corner_after(self.triangles[u], f) == y);
                    match next {
                        Some(u) if self.try_continue(u) => {
                            t = u;
                            ring.extend(self.triangles[t]);
                            dead.extend(self.triangles[t]);
                        }
                        _ => break,
                    }
                }
            }
            // Next fan: the oldest buffered neighbour whose fan fits before it is evicted.
            let mut best: Option<(u64, u32)> = None;
            for &v in &ring {
                if self.remaining[v as usize] == 0 {
                    continue;
                }
                let p = match self.buffered(v) {
                    Some(d) if u64::from(d) + 1 + 2 * u64::from(self.remaining[v as usize]) <= MESH_BUFFER => {
                        u64::from(d) + 1
                    }
                    _ => 0,
                };
                if (&best).none_or(|b| p > b.0) {
                    best = Some((p, v));
                }
            }
            fan = match best {
                Some((_, v)) => Some(v),
                None => {
                    let mut next = None;
                    while let Some(v) = dead.pop() {
                        if self.remaining[v as usize] > 0 {
                            next = Some(v);
                            break;
                        }
                    }
                    if next.is_none() {
                        while cursor < vertex_count && self.remaining[cursor] == 0 {
                            cursor += 1;
                        }
                        next = (cursor < vertex_count).then_some(cursor as u32);
                    }
                    next
                }
            };
        }
    }

    fn around(&self, v: u32) -> &[u32] {
        &self.incident[self.offsets[v as usize]..self.offsets[v as usize + 1]]
    }

    fn buffered(&self, v: u32) -> Option<u8> {
        let at = self.pushed_at[v as usize];
        (at != u64::MAX && self.pushes - at <= MESH_BUFFER).then(|| (self.pushes - 1 - at) as u8)
    }

    fn unvisited_neighbours(&self, t: usize) -> usize {
        let [a, b, c] = self.triangles[t];
        [(a, b), (b, c), (c, a)].iter().filter(|&&(x, y)| self.across(x, y, t).is_some()).count()
    }

    /// An unvisited triangle other than `not` with both `x` and `y`.
    fn across(&self, x: u32, y: u32, not: usize) -> Option<usize> {
        self.around(x)
            .iter()
            .map(|&t| t as usize)
            .find(|&t| t != not && !self.visited[t] && self.triangles[t].contains(&y))
    }

    fn mark(&mut self, t: usize) {
        self.visited[t] = true;
        for v in self.triangles[t] {
            self.remaining[v as usize] -= 1;
        }
    }

    fn send(&mut self, v: u32, replace: u8) {
        if let Some(depth) = self.buffered(v) {
            self.steps.push(Step::Reference { vertex: v, depth, replace });
            return;
        }
        self.sent[v as usize] = true;
        let push = self.needs_buffer(v);
        if push {
            self.strip_pushes += 1;
            self.pushed_at[v as usize] = self.pushes;
            self.fifo[(self.pushes % MESH_BUFFER) as usize] = v;
            self.pushes += 1;
        }
        self.steps.push(Step::Full { vertex: v, replace, push });
    }

    /// Will `v` be needed after the strip window has moved on: does it have
    /// an unvisited triangle beyond the 2 next to the window's newest edges?
    fn needs_buffer(&self, v: u32) -> bool {
        let [a, b, c] = self.window;
        let near = |t: usize| {
            let tri = self.triangles[t];
            [(b, c), (a, c), (a, b)].iter().any(|&(x, y)| tri.contains(&x) && tri.contains(&y))
        };
        let far = self.around(v).iter().filter(|&&t| !self.visited[t as usize] && !near(t as usize)).count();
        let close = self.around(v).iter().filter(|&&t| !self.visited[t as usize] && near(t as usize)).count();
        far > 0 || close > 1
    }

    /// The triangle Java's back end outputs if `w` follows the window with
    /// `replace`, the new run and winding; None if it would be flipped
    /// against triangle `t`.
    fn predict(&self, w: u32, replace: u8, t: usize) -> Option<(Run, bool)> {
        let [a, b, c] = self.window;
        let (listed, run, ccw) = if replace == 3 {
            match self.run {
                Run::Fan => ([b, c, w], Run::Strip(3), !self.ccw),
                Run::Pending | Run::Strip(_) => {
                    let len = if let Run::Strip(l) = self.run { l + 1 } else { 4 };
                    (if (len - 3) % 2 == 0 { [b, c, w] } else { [c, b, w] }, Run::Strip(len), self.ccw)
                }
            }
        } else {
            let flip = matches!(self.run, Run::Strip(l) if l % 2 == 0);
            ([a, c, w], Run::Fan, self.ccw ^ flip)
        };
        let out = if ccw { listed } else { [listed[0], listed[2], listed[1]] };
        same_orientation(out, self.triangles[t]).then_some((run, ccw))
    }

    /// Estimated bits of sending `w` for triangle `t` beyond the unavoidable
    /// (each vertex's first send, one command per triangle): a re-send of an
    /// evicted vertex, or a push that evicts a vertex still needed. `pushes`
    /// counts the pushes this candidate makes before `w`.
    fn vertex_cost(&self, w: u32, t: usize, pushes: &mut u64) -> u64 {
        if self.buffered(w).is_some() {
            return COMMAND_BITS;
        }
        let mut cost = COMMAND_BITS;
        if self.sent[w as usize] {
            cost += FULL_VERTEX_BITS;
        }
        if self.remaining[w as usize] > 1 {
            let serial = self.pushes + *pushes;
            if serial >= MESH_BUFFER {
                let old = self.fifo[(serial % MESH_BUFFER) as usize];
                let still = self.remaining[old as usize] - u32::from(self.triangles[t].contains(&old));
                if still > 0 && self.pushed_at[old as usize] == serial - MESH_BUFFER {
                    cost += FULL_VERTEX_BITS;
                }
            }
            *pushes += 1;
        }
        cost
    }

    fn run_all(&mut self) {
        let mut cursor = 0usize;
        let mut active = false;
        loop {
            // Candidates: (cost, is restart, unvisited neighbours, triangle, continuation data).
            let mut best: Option<Candidate> = None;
            let better =
                |best: &Option<Candidate>, key: (u64, bool, usize)| best.as_ref().none_or(|b| key < (b.0, b.1, b.2));
            if active && self.strip_pushes < STRIP_PUSHES {
                let [a, b, c] = self.window;
                for (x, y, replace) in [(b, c, 3u8), (a, c, 2u8)] {
                    for &t in self.around(x) {
                        let t = t as usize;
                        if self.visited[t] || !self.triangles[t].contains(&y) {
                            continue;
                        }
                        let Some(&w) = self.triangles[t].iter().find(|&&v| v != x && v != y) else { continue };
                        let Some((run, ccw)) = self.predict(w, replace, t) else { continue };
                        let cost = self.vertex_cost(w, t, &mut 0);
                        let key = (cost, false, self.unvisited_neighbours(t));
                        if better(&best, key) {
                            best = Some((key.0, key.1, key.2, t, Some((w, replace, run, ccw))));
                        }
                    }
                }
            }
            for k in 0..self.pushes.min(MESH_BUFFER) {
                let v = self.fifo[((self.pushes - 1 - k) % MESH_BUFFER) as usize];
                for &t in self.around(v) {
                    let t = t as usize;
                    if self.visited[t] {
                        continue;
                    }
                    let mut pushes = 0;
                    let cost = 2 * COMMAND_BITS
                        + self.triangles[t].iter().map(|&u| self.vertex_cost(u, t, &mut pushes)).sum::<u64>();
                    // Among equal costs, use the oldest buffered vertices before they go.
                    let oldest = self.triangles[t].iter().filter_map(|&u| self.buffered(u)).max().unwrap_or(0);
                    let key = (cost, true, 16 - usize::from(oldest));
                    if better(&best, key) {
                        best = Some((key.0, key.1, key.2, t, None));
                    }
                }
            }
            let (t, continuation) = match best {
                Some((_, _, _, t, c)) => (t, c),
                None => {
                    while cursor < self.triangles.len() && self.visited[cursor] {
                        cursor += 1;
                    }
                    if cursor == self.triangles.len() {
                        break;
                    }
                    (cursor, None)
                }
            };
            if let Some((w, replace, run, ccw)) = continuation {
                let [a, b, c] = self.window;
                self.mark(t);
                self.window = if replace == 3 { [b, c, w] } else { [a, c, w] };
                self.send(w, replace);
                self.run = run;
                self.ccw = ccw;
                continue;
            }
            // Restart: rotate so that the strip can go on across (b, c), else fan across (a, c).
            let [i, j, k] = self.triangles[t];
            let rotations = [[i, j, k], [j, k, i], [k, i, j]];
            let pick = rotations
                .iter()
                .copied()
                .max_by_key(|r| (self.across(r[1], r[2], t).is_some(), self.across(r[0], r[2], t).is_some()))
                .unwrap_or([i, j, k]);
            self.mark(t);
            self.strip_pushes = 0;
            self.window = pick;
            self.send(pick[0], 1);
            self.send(pick[1], 3);
            self.send(pick[2], 3);
            self.run = Run::Pending;
            self.ccw = true;
            active = true;
        }
    }
}

/// The corner after `v` in `t`'s counter-clockwise order (`v` itself if absent).
fn corner_after(t: [u32; 3], v: u32) -> u32 {
    match t.iter().position(|&x| x == v) {
        Some(i) => t[(i + 1) % 3],
        None => v,
    }
}

/// The corner before `v` in `t`'s counter-clockwise order.
fn corner_before(t: [u32; 3], v: u32) -> u32 {
    match t.iter().position(|&x| x == v) {
        Some(i) => t[(i + 2) % 3],
        None => v,
    }
}

/// `a` is a cyclic rotation of `b`.
fn same_orientation(a: [u32; 3], b: [u32; 3]) -> bool {
    a == b || a == [b[1], b[2], b[0]] || a == [b[2], b[0], b[1]]
}

/// `Option::is_none_or` for Rust 1.80.
trait NoneOr<T> {
    fn none_or(self, f: impl FnOnce(&T) -> bool) -> bool;
}

impl<T> NoneOr<T> for &Option<T> {
    fn none_or(self, f: impl FnOnce(&T) -> bool) -> bool {
        match self {
            None => true,
            Some(x) => f(x),
        }
    }
}

impl<T> NoneOr<T> for Option<&T> {
    fn none_or(self, f: impl FnOnce(&T) -> bool) -> bool {
        match self {
            None => true,
            Some(x) => f(x),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::holoflick::cg::strip::java_triangles;

    /// The steps decode (as Java's back end would) to exactly the input triangles, oriented.
    fn check(triangles: &[[u32; 3]], vertex_count: usize) -> Vec<Step> {
        let steps = meshify(triangles, vertex_count);
        let ids: Vec<u32> = steps
            .iter()
            .map(|s| match *s {
                Step::Full { vertex, .. } | Step::Reference { vertex, .. } => vertex,
            })
            .collect();
        let flags: Vec<u8> = steps
            .iter()
            .map(|s| match *s {
                Step::Full { replace, .. } | Step::Reference { replace, .. } => replace,
            })
            .collect();
        let mut got: Vec<[u32; 3]> =
            java_triangles(&flags).unwrap().iter().map(|t| canonical([ids[t[0]], ids[t[1]], ids[t[2]]])).collect();
        let mut want: Vec<[u32; 3]> = triangles.iter().map(|&t| canonical(t)).collect();
        got.sort();
        want.sort();
        assert_eq!(got, want);
        steps
    }

    fn canonical(t: [u32; 3]) -> [u32; 3] {
        let r = [t, [t[1], t[2], t[0]], [t[2], t[0], t[1]]];
        *r.iter().min().unwrap()
    }

    #[test]
    fn grid_round_trips_and_reuses_vertices() {
        let (w, h) = (30u32, 20u32);
        let mut tris = Vec::new();
        for y in 0..h {
            for x in 0..w {
                let v = |x: u32, y: u32| y * (w + 1) + x;
                tris.push([v(x, y), v(x + 1, y), v(x + 1, y + 1)]);
                tris.push([v(x, y), v(x + 1, y + 1), v(x, y + 1)]);
            }
        }
        let steps = check(&tris, ((w + 1) * (h + 1)) as usize);
        let full = steps.iter().filter(|s| matches!(s, Step::Full { .. })).count();
        let vertices = ((w + 1) * (h + 1)) as usize;
        println!("{} triangles, {} steps, {} full vertices of {}", tris.len(), steps.len(), full, vertices);
        // Long rows cannot all stay in a 16-entry buffer; bound what the meshifier achieves.
        assert!(full < vertices * 13 / 10, "{full} full vertices for {vertices}");
    }
}
