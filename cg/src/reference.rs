//! The reference decoder: slow and literal. It reads one bit at a time,
//! keeps each table as the list of setTable commands received (a lookup
//! takes the last command whose tag is a prefix of the header; nothing is
//! precomputed), and reads every body with the branch structure of Java 3D's
//! `GeometryDecompressor` (`processVertex`, `processSetColor`,
//! `processSetNormal`: which bits sit in the header, which come from the
//! body). The fast decoder ([`super::decode`]) instead reads each body as a
//! single bit string; tests make the two agree on random streams.

use super::bits::{BitByBit, StreamError};
use super::decode::{check_length, no_table};
use super::normals::NormalCode;
use super::state::{parse_set_table, Entry, Sink, State};
use crate::error::{StreamProblem, Table};

/// One table as the setTable commands that built it.
#[derive(Default)]
struct ListTable {
    /// (first entry, entry count, entry), in command order.
    commands: Vec<(usize, usize, Entry)>,
}

impl ListTable {
    fn lookup(&self, index: u32) -> Entry {
        let i = index as usize & 0x3F;
        self.commands
            .iter()
            .rev()
            .find(|(first, count, _)| i >= *first && i < first + count)
            .map(|c| c.2)
            .unwrap_or_default()
    }
}

struct Ref<'a> {
    r: BitByBit<'a>,
    tables: [ListTable; 3],
}

impl Ref<'_> {
    fn bits(&mut self, n: i64) -> Result<i64, StreamProblem> {
        if n < 0 {
            return Err(StreamProblem::NegativeBitCount { bits: n });
        }
        Ok(self.r.read(n as u32)? as i64)
    }
}

/// `BMASK[n]` of Java 3D.
fn bmask(n: i64) -> i64 {
    (1i64 << n) - 1
}

/// Java's `x << (32 - n) >> (32 - n)` for n in 1..=32; n = 0 keeps x (Java shifts by 32 ≡ 0).
fn java_sign_extend(x: i64, n: i64) -> i64 {
    if n == 0 {
        return x;
    }
    let x = x as i32;
    i64::from((x << (32 - n)) >> (32 - n))
}

/// Decode `bytes` into `sink`, slowly.
pub(crate) fn run(bytes: &[u8], sink: &mut impl Sink) -> Result<(), StreamError> {
    check_length(bytes)?;
    let mut d = Ref { r: BitByBit::new(bytes), tables: Default::default() };
    let mut st = State::new();
    let mut next: i64 = 0x01;
    while !d.r.at_end() {
        let at = d.r.position();
        let fail = |e: StreamProblem| e.at(at);
        let err = fail;
        let current = next;
        if current & 0xC0 == 0x40 {
            let (bn, bc) = (st.bundling_normal, st.bundling_color);
            next = d.bits(if bn || bc { 6 } else { 8 }).map_err(fail)?;
            let push = vertex(&mut d, &mut st, current).map_err(fail)?;
            if bn {
                let h = next | 0xC0;
                next = d.bits(if bc { 6 } else { 8 }).map_err(fail)?;
                set_normal(&mut d, &mut st, h, push).map_err(fail)?;
                st.finish_normal(sink).map_err(err)?;
            }
            if bc {
                let h = next | 0x80;
                next = d.bits(8).map_err(fail)?;
                set_color(&mut d, &mut st, h, push).map_err(fail)?;
                st.finish_color(sink).map_err(err)?;
            }
            let replace = st.last_replace;
            st.output_vertex(replace, sink).map_err(err)?;
            continue;
        }
        next = d.bits(8).map_err(fail)?;
        if current & 0xC0 == 0xC0 {
            set_normal(&mut d, &mut st, current, false).map_err(fail)?;
            st.finish_normal(sink).map_err(err)?;
        } else if current & 0xC0 == 0x80 {
            set_color(&mut d, &mut st, current, false).map_err(fail)?;
            st.finish_color(sink).map_err(err)?;
        } else if current & 0xE0 == 0x20 {
            let ii = d.bits(1).map_err(fail)?;
            let index = (current >> 1) & 0xF;
            let replace = (((current & 1) << 1) | ii) as u8;
            st.mesh_reference(index as usize).map_err(err)?;
            st.output_vertex(replace, sink).map_err(err)?;
        } else if current & 0xF8 == 0x18 {
            let ii = d.bits(3).map_err(fail)?;
            st.set_state(current & 1 != 0, (ii >> 2) & 1 != 0, (ii >> 1) & 1 != 0, sink).map_err(err)?;
        } else if current & 0xF8 == 0x10 {
            let ii = d.bits(15).map_err(fail)?;
            let (t, first, count, entry) = parse_set_table(current as u32, ii as u32);
            d.tables.get_mut(t).ok_or_else(|| err(no_table(t)))?.commands.push((first, count, entry));
        } else if current == 0x01 {
            let ct = d.bits(5).map_err(fail)?;
            d.bits(ct).map_err(fail)?;
        } else if current == 0x08 {
            d.bits(24).map_err(fail)?;
            d.bits(32).map_err(fail)?;
        } else if current == 0x07 {
            d.bits(8).map_err(fail)?;
        }
    }
    st.finish(sink).map_err(|problem| problem.at(d.r.position()))
}

fn vertex(d: &mut Ref, st: &mut State, header: i64) -> Result<bool, StreamProblem> {
    let gct = d.tables[0].lookup(header as u32);
    let data_len = i64::from(gct.sent_bits(Table::Position)?);
    let tag = i64::from(gct.tag_len);
    let ii = if 6 - 3 * data_len - tag > 0 {
        let num_bits = 6 - 3 * data_len - tag;
        if num_bits > 3 {
            // All three small: tag <= 6, data_len <= 16, num_bits 4..=6.
            return Err(StreamProblem::ReplaceBitsInHeader {
                tag_len: tag as u32,
                data_len: data_len as u32,
                header_bits: num_bits as u32,
            });
        }
        let jj = header & bmask(num_bits);
        d.bits(3 - num_bits)? | (jj << (3 - num_bits))
    } else {
        d.bits(3)?
    };
    let (mut x, mut y, mut z);
    x = header & bmask(6 - tag);
    if tag + data_len == 6 {
        y = d.bits(data_len)?;
        z = d.bits(data_len)?;
    } else if tag + data_len < 6 {
        x >>= 6 - tag - data_len;
        y = header & bmask(6 - tag - data_len);
        if tag + 2 * data_len == 6 {
            z = d.bits(data_len)?;
        } else if tag + 2 * data_len < 6 {
            y >>= 6 - tag - 2 * data_len;
            z = header & bmask(6 - tag - 2 * data_len);
            if tag + 3 * data_len < 6 {
                z >>= 6 - tag - 3 * data_len;
            } else if tag + 3 * data_len > 6 {
                let more = data_len - (6 - tag - 2 * data_len);
                z = (z << more) | d.bits(more)?;
            }
        } else {
            let more = data_len - (6 - tag - data_len);
            y = (y << more) | d.bits(more)?;
            z = d.bits(data_len)?;
        }
    } else {
        let more = data_len - (6 - tag);
        x = (x << more) | d.bits(more)?;
        y = d.bits(data_len)?;
        z = d.bits(data_len)?;
    }
    let s = gct.shift;
    let v = [x, y, z].map(|c| ((java_sign_extend(c, data_len) as i32) << s) as i16 as i32);
    st.last_replace = (ii >> 1) as u8;
    let push = ii & 1 != 0;
    st.apply_position(gct.absolute, v, push);
    Ok(push)
}

fn set_color(d: &mut Ref, st: &mut State, header: i64, push: bool) -> Result<(), StreamProblem> {
    let gct = d.tables[1].lookup(header as u32);
    let dl = i64::from(gct.sent_bits(Table::Color)?);
    let tag = i64::from(gct.tag_len);
    let alpha = st.doing_alpha;
    let mut r = header & bmask(6 - tag);
    let (mut g, mut b);
    let mut a = 0;
    if tag + dl == 6 {
        g = d.bits(dl)?;
        b = d.bits(dl)?;
        if alpha {
            a = d.bits(dl)?;
        }
    } else if tag + dl < 6 {
        r >>= 6 - tag - dl;
        g = header & bmask(6 - tag - dl);
        if tag + 2 * dl == 6 {
            b = d.bits(dl)?;
            if alpha {
                a = d.bits(dl)?;
            }
        } else if tag + 2 * dl < 6 {
            g >>= 6 - tag - 2 * dl;
            b = header & bmask(6 - tag - 2 * dl);
            if tag + 3 * dl == 6 {
                if alpha {
                    a = d.bits(dl)?;
                }
            } else if tag + 3 * dl < 6 {
                b >>= 6 - tag - 3 * dl;
                // Java masks alpha with BMASK[6 - tag - 4*len] and shifts by
                // 6 - tag - 3*len: for the only lengths that get here (0 and 1)
                // that leaves 0.
                if alpha {
                    let m = 6 - tag - 4 * dl;
                    a = if m > 0 { (header & bmask(m)) >> (6 - tag - 3 * dl) } else { 0 };
                }
            } else {
                let more = dl - (6 - tag - 2 * dl);
                b = (b << more) | d.bits(more)?;
                if alpha {
                    a = d.bits(dl)?;
                }
            }
        } else {
            let more = dl - (6 - tag - dl);
            g = (g << more) | d.bits(more)?;
            b = d.bits(dl)?;
            if alpha {
                a = d.bits(dl)?;
            }
        }
    } else {
        let more = dl - (6 - tag);
        r = (r << more) | d.bits(more)?;
        g = d.bits(dl)?;
        b = d.bits(dl)?;
        if alpha {
            a = d.bits(dl)?;
        }
    }
    let s = gct.shift;
    let v = [r, g, b, a].map(|c| ((java_sign_extend(c, dl) as i32) << s) as i16 as i32);
    st.apply_color(gct.absolute, v, push);
    Ok(())
}

fn set_normal(d: &mut Ref, st: &mut State, header: i64, push: bool) -> Result<(), StreamProblem> {
    let gct = d.tables[2].lookup(header as u32);
    let dl = i64::from(gct.sent_bits(Table::Normal)?);
    let tag = i64::from(gct.tag_len);
    let s = gct.shift;
    if gct.absolute {
        let mut index = header & bmask(6 - tag);
        if tag != 0 {
            index = (index << tag) | d.bits(tag)?;
        }
        let u = (d.bits(dl)? as i32) << s;
        let v = (d.bits(dl)? as i32) << s;
        st.set_normal_code(NormalCode { sextant: ((index >> 3) & 7) as u8, octant: (index & 7) as u8, u, v }, push)?;
    } else {
        let mut du = header & bmask(6 - tag);
        let dv;
        if tag + dl < 6 {
            du >>= 6 - tag - dl;
            let mut w = header & bmask(6 - tag - dl);
            if tag + 2 * dl < 6 {
                w >>= 6 - tag - 2 * dl;
            } else if tag + 2 * dl > 6 {
                let more = dl - (6 - tag - dl);
                w = (w << more) | d.bits(more)?;
            }
            dv = w;
        } else if tag + dl > 6 {
            let more = dl - (6 - tag);
            du = (du << more) | d.bits(more)?;
            dv = d.bits(dl)?;
        } else {
            dv = d.bits(dl)?;
        }
        let du = (java_sign_extend(du, dl) as i32) << s;
        let dv = (java_sign_extend(dv, dl) as i32) << s;
        st.add_normal_delta(du, dv, push)?;
    }
    Ok(())
}
