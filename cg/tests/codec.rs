//! The compressed-geometry codec: encode → decode round trips on random
//! meshes within the quantization bounds, hand-built streams for each
//! command decoded from the format's description (Java 3D API
//! Specification, appendix B), the fast and reference decoders agreeing on
//! valid and random streams, bad input, and `.cg` files. Real meshes, which
//! need a mesh loader, are round-tripped by holo's `tests/holoflick_cg.rs`.

use std::path::PathBuf;

use holo_cg::{
    decode, decode_reference, decode_with, encode, file::CgFile, read_cg_file, BlockKind, CgHeader, Decoded,
    EncodeOptions, Error, FileProblem, Mesh, Primitive, StreamProblem, Vertex,
};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

mod round_trip;
use round_trip::{check_round_trip, sorted_keys, TestMesh};

/// A random connected mesh: a jittered grid of `w × h` quads, each split
/// along a random diagonal, with smooth random normals and colours.
fn random_mesh(rng: &mut ChaCha8Rng, w: u32, h: u32) -> TestMesh {
    let mut m = TestMesh::default();
    let scale = 10f64.powf(rng.gen_range(-3.0..4.0));
    let offset = [rng.gen_range(-1e3..1e3), rng.gen_range(-1e3..1e3), rng.gen_range(-1e3..1e3)];
    for y in 0..=h {
        for x in 0..=w {
            let (fx, fy) = (f64::from(x) + rng.gen_range(-0.3..0.3), f64::from(y) + rng.gen_range(-0.3..0.3));
            let z = (fx * 0.3).sin() * (fy * 0.2).cos() * 2.0;
            m.positions.push([offset[0] + fx * scale, offset[1] + fy * scale, offset[2] + z * scale]);
            let n = [rng.gen_range(-1.0f32..1.0), rng.gen_range(-1.0f32..1.0), rng.gen_range(-1.0f32..1.0)];
            m.normals.push(if n.iter().all(|c| c.abs() < 1e-3) { [0.0, 0.0, 1.0] } else { n });
            m.colors.push([
                rng.gen_range(0.0..=1.0),
                rng.gen_range(0.0..=1.0),
                rng.gen_range(0.0..=1.0),
                rng.gen_range(0.0..=1.0),
            ]);
        }
    }
    let v = |x: u32, y: u32| y * (w + 1) + x;
    for y in 0..h {
        for x in 0..w {
            if rng.gen_bool(0.5) {
                m.triangles.push([v(x, y), v(x + 1, y), v(x + 1, y + 1)]);
                m.triangles.push([v(x, y), v(x + 1, y + 1), v(x, y + 1)]);
            } else {
                m.triangles.push([v(x, y), v(x + 1, y), v(x, y + 1)]);
                m.triangles.push([v(x + 1, y), v(x + 1, y + 1), v(x, y + 1)]);
            }
        }
    }
    m
}

const SETTINGS: [(u32, u32, u32); 4] = [(16, 9, 6), (10, 8, 6), (12, 4, 3), (6, 2, 0)];

#[test]
#[ignore = "slow: the full run takes it (README, Development)"]
fn random_meshes_round_trip_within_bounds() {
    let mut rng = ChaCha8Rng::seed_from_u64(6);
    for round in 0..12 {
        let (w, h) = (rng.gen_range(1..25), rng.gen_range(1..25));
        let m = random_mesh(&mut rng, w, h);
        for &(p, c, n) in &SETTINGS {
            for (with_n, with_c, alpha) in [
                (true, true, true),
                (true, true, false),
                (false, false, false),
                (true, false, false),
                (false, true, true),
            ] {
                let o = EncodeOptions { position_bits: p, color_bits: c, normal_bits: n, alpha };
                let (err, enc) = check_round_trip(
                    &m.positions,
                    with_n.then_some(&m.normals[..]),
                    with_c.then_some(&m.colors[..]),
                    &m.triangles,
                    &o,
                );
                if round == 0 {
                    println!("{w}x{h} {p}/{c}/{n} n{with_n} c{with_c} a{alpha}: {:?} {:?}", err, enc.stats);
                }
            }
        }
    }
}

/// Bits written MSB-first, independently of the library's writer.
#[derive(Default)]
struct Bits {
    bits: Vec<bool>,
}

impl Bits {
    fn put(&mut self, value: u64, n: u32) {
        for i in (0..n).rev() {
            self.bits.push((value >> i) & 1 != 0);
        }
    }
    fn put_str(&mut self, s: &str) {
        for c in s.chars().filter(|c| *c == '0' || *c == '1') {
            self.bits.push(c == '1');
        }
    }
    fn bytes(&self) -> Vec<u8> {
        self.bits.chunks(8).map(|c| c.iter().enumerate().fold(0u8, |b, (i, &x)| b | (u8::from(x) << (7 - i)))).collect()
    }
}

/// Commands as (header bit string, body bit string), laid out with header
/// forwarding: the first body on the wire is the implicit no-op's 5-bit
/// count; each header precedes the previous command's body. The stream
/// ends after the last body with a no-op whose body pads to 32 bits.
fn forward(commands: &[(&str, &str)]) -> Vec<u8> {
    let mut b = Bits::default();
    let mut pending = "00000".to_string();
    for (h, body) in commands {
        b.put_str(h);
        b.put_str(&pending);
        pending = body.to_string();
    }
    // A no-op header, the last body, then the next header and the no-op's body.
    b.put_str("00000001");
    b.put_str(&pending);
    let len = b.bits.len() + 8 + 5;
    let pad = (32 - len % 32) % 32;
    let pad = if pad > 31 { pad - 32 } else { pad };
    b.put(0, 8);
    b.put(pad as u64, 5);
    b.put(0, pad as u32);
    assert_eq!(b.bits.len() % 32, 0);
    b.bytes()
}

fn tri_header() -> CgHeader {
    CgHeader { kind: BlockKind::Triangles, normals: false, colors: false, alpha: false, version: [1, 0, 2] }
}

fn decode_both(header: &CgHeader, bytes: &[u8]) -> holo_cg::Result<Decoded> {
    let fast = decode(header, bytes);
    let slow = decode_reference(header, bytes);
    match (&fast, &slow) {
        (Ok(a), Ok(b)) => assert_eq!(a, b),
        (Err(a), Err(b)) => assert_eq!(a.to_string(), b.to_string()),
        _ => panic!("fast {fast:?} and reference {slow:?} disagree"),
    }
    fast
}

fn p(v: &Vertex) -> [f32; 3] {
    v.position
}

/// Absolute and relative positions, a mesh-buffer reference, a strip (the
/// expected values are worked out from the format's text in the test).
fn stream_positions() -> Vec<u8> {
    forward(&[
        // setState: no bundled normals (header bit 0), body "c a x" = 000.
        ("00011000", "000"),
        // setTable position, tag "0" (address 0000010): data length 16 (sent as 0), absolute, shift 8.
        ("00010000", "000010 0000 1 1000"),
        // setTable position, tag "1" (address 0000011): data length 12, relative, shift 8.
        ("00010000", "000011 1100 0 1000"),
        // Vertex, tag 0, x = 01000000, y = 11000000, z = 00000000; header holds tag + 5 bits of x;
        // body: replace code 01 (restart counter-clockwise), push 1, then the rest of x, y, z.
        ("01 0 01000", "01 1 000 11000000 00000000"),
        // Vertex, tag 1, dx = 0001, dy = 1111, dz = 0111: header holds tag + dx + 1 bit of dy.
        ("01 1 0001 1", "11 0 111 0111"),
        // Vertex, tag 1, dx = 1000, dy = 0, dz = 0.
        ("01 1 1000 0", "11 0 000 0000"),
        // Mesh-buffer reference 0 (the first vertex), replace code 11.
        ("001 0000 1", "1"),
    ])
}

#[test]
fn hand_built_positions_strip_and_mesh_reference() {
    let bytes = stream_positions();
    let d = decode_both(&tri_header(), &bytes).expect("decode");
    let v0 = [0.5, -0.5, 0.0];
    let v1 = [16640.0 / 32768.0, -16640.0 / 32768.0, 1792.0 / 32768.0];
    let v2 = [14592.0 / 32768.0, -16640.0 / 32768.0, 1792.0 / 32768.0];
    // Replace codes 1, 3, 3, 3: one strip (0, 1, 2), (2, 1, 3); vertex 3 is vertex 0 again.
    let got: Vec<[[f32; 3]; 3]> = d.triangles.iter().map(|t| t.map(|v| p(&v))).collect();
    assert_eq!(got, vec![[v0, v1, v2], [v2, v1, v0]]);
    assert!(d.triangles.iter().flatten().all(|v| v.normal.is_none() && v.color.is_none()));
    assert_eq!(d.quantized[0][0].position, [16384, -16384, 0]);
}

/// Bundled normal and colour: the 6-bit sub-headers, special and table
/// normals, a mesh-buffer reference restoring normal and colour.
fn stream_bundled() -> Vec<u8> {
    let vertex =
        |x: &str, rep_push: &str, rest: &str| -> (String, String) { (format!("01{x}"), format!("{rep_push}{rest}")) };
    let (h1, b1) = vertex("011111", "011", "11 10000000 00000001");
    let (h2, b2) = vertex("001000", "111", "00 00000000 00000000");
    let (h3, b3) = vertex("000000", "111", "00 01000000 00000000");
    forward(&[
        // setState: bundle normals (header bit 0 = 1); body: colour 1, alpha 0.
        ("00011001", "100"),
        // Position: tag length 0 (address 0000001), data 16, absolute, shift 8.
        ("00010000", "000001 0000 1 1000"),
        // Colour (table 1): tag length 0, data 16, absolute, shift 8.
        ("00010010", "000001 0000 1 1000"),
        // Normal (table 2): tag length 0, data 6, absolute, shift 0.
        ("00010100", "000001 0110 1 0000"),
        // Vertex 1: x = 01111111 (0.9921875), y = 10000000 (-1), z = 00000001; restart, push.
        (&h1, &b1),
        // Its normal: sextant 6, octant 4 = +y (special); u, v = 0.
        ("110100", "000000 000000"),
        // Its colour: r = 01000000, g = 00100000, b = 01111111.
        ("010000", "00 00100000 01111111"),
        // Vertex 2: x = 00100000, y = 0, z = 0; replace oldest, push.
        (&h2, &b2),
        // Normal: sextant 0, octant 0, (u, v) = (0, 0): the table's first entry.
        ("000000", "000000 000000"),
        // Colour: black.
        ("000000", "00 00000000 00000000"),
        // Vertex 3: x = 0, y = 01000000 (0.5), z = 0; replace oldest, push.
        (&h3, &b3),
        // Normal: sextant 7, octant 2 = -z.
        ("111010", "000000 000000"),
        // Colour: r = g = b = 01111111.
        ("011111", "11 01111111 01111111"),
        // Mesh-buffer reference 2 = vertex 1 with its normal and colour; replace oldest.
        ("001 0010 1", "1"),
    ])
}

/// The triangles of [`stream_bundled`], worked out by hand.
fn expected_bundled() -> Vec<[Vertex; 3]> {
    let c = |r: f32, g: f32, b: f32| Some([r / 32768.0, g / 32768.0, b / 32768.0, 1.0]);
    let table00 = {
        // (u, v) = (0, 0): psi = 0, theta = asin(tan(MAXY)) = 45 degrees, truncated to s1.14.
        let th = (0.615479709f64).tan().asin();
        let t = |x: f64| (f64::from((x * 16384.0) as i32) / 16384.0) as f32;
        [t(th.cos()), 0.0, t(th.sin())]
    };
    let v1 = Vertex {
        position: [32512.0 / 32768.0, -1.0, 256.0 / 32768.0],
        normal: Some([0.0, 1.0, 0.0]),
        color: c(16384.0, 8192.0, 32512.0),
    };
    let v2 = Vertex { position: [0.25, 0.0, 0.0], normal: Some(table00), color: c(0.0, 0.0, 0.0) };
    let v3 =
        Vertex { position: [0.0, 0.5, 0.0], normal: Some([-0.0, -0.0, -1.0]), color: c(32512.0, 32512.0, 32512.0) };
    vec![[v1, v2, v3], [v3, v2, v1]]
}

#[test]
fn hand_built_bundled_normal_and_colour() {
    let h = CgHeader { kind: BlockKind::Triangles, normals: true, colors: true, alpha: false, version: [1, 0, 2] };
    let d = decode_both(&h, &stream_bundled()).expect("decode");
    assert_eq!(d.triangles, expected_bundled());
}

/// A random prefix code: lengths 0..=6 with Kraft sum 1, as (tag, length).
fn random_code(rng: &mut ChaCha8Rng) -> Vec<(u32, u32)> {
    // Split the 6-bit space recursively.
    fn split(rng: &mut ChaCha8Rng, prefix: u32, len: u32, out: &mut Vec<(u32, u32)>) {
        if len == 6 || (len > 0 && rng.gen_bool(0.45)) || (len == 0 && rng.gen_bool(0.1)) {
            out.push((prefix, len));
        } else {
            split(rng, prefix << 1, len + 1, out);
            split(rng, (prefix << 1) | 1, len + 1, out);
        }
    }
    let mut out = Vec::new();
    split(rng, 0, 0, &mut out);
    out
}

/// A random stream of every command kind, mostly valid: random tables
/// (any tag lengths, data lengths and shifts), bundling changes, vertices,
/// mesh-buffer references, global normals and colours, no-ops of all kinds.
/// Bodies are written as the logical bit string "header's 6 bits + body".
fn random_stream(rng: &mut ChaCha8Rng) -> Vec<u8> {
    let mut cmds: Vec<(String, String)> = Vec::new();
    let bits = |v: u64, n: u32| -> String { (0..n).rev().map(|i| if (v >> i) & 1 == 1 { '1' } else { '0' }).collect() };
    // Per table: (tag, tag length, data length, shift, absolute).
    type Entries = Vec<(u32, u32, u32, u32, bool)>;
    let mut tables: Vec<Entries> = vec![vec![], vec![], vec![]];
    let (mut bn, mut bc, mut alpha) = (rng.gen_bool(0.5), rng.gen_bool(0.5), rng.gen_bool(0.5));
    cmds.push((
        format!("00011{}{}", bits(rng.gen_range(0..4), 2), u8::from(bn)),
        format!("{}{}{}", u8::from(bc), u8::from(alpha), 0),
    ));
    for t in 0..3u64 {
        for (tag, len) in random_code(rng) {
            let max_data = if t == 2 { 7 } else { 16 };
            let data = rng.gen_range(if t == 2 { 0 } else { 1 }..=max_data);
            let shift = if rng.gen_bool(0.95) { rng.gen_range(0..=data.min(15)) } else { rng.gen_range(0..16) };
            let abs = rng.gen_bool(0.5);
            tables[t as usize].push((tag, len, data, shift, abs));
            let adr = (1u64 << len) | u64::from(tag);
            cmds.push((
                format!("00010{}{}", bits(t, 2), adr >> 6),
                format!(
                    "{}{}{}{}",
                    bits(adr & 63, 6),
                    bits(u64::from(data) & 15, 4),
                    u8::from(abs),
                    bits(u64::from(shift), 4)
                ),
            ));
        }
    }
    let mut pushes = 0;
    // The logical string "tag data..." as (6-bit header, rest).
    let split6 = |s: String| -> (String, String) {
        let s = format!("{s:0<6}");
        (s[..6].to_string(), s[6..].to_string())
    };
    for _ in 0..rng.gen_range(0..60) {
        match rng.gen_range(0..100) {
            0..=59 => {
                let (tag, len, data, shift, _) = tables[0][rng.gen_range(0..tables[0].len())];
                let d = data.saturating_sub(shift);
                let p = format!("{}{}", bits(u64::from(tag), len), bits(rng.gen::<u64>(), 3 * d));
                let rep = rng.gen_range(0..4u64);
                let push = rng.gen_bool(0.6);
                pushes += u32::from(push);
                let rpm = bits((rep << 1) | u64::from(push), 3);
                let (h, b) = if p.len() >= 6 {
                    (p[..6].to_string(), format!("{rpm}{}", &p[6..]))
                } else {
                    let k = 6 - p.len();
                    let k3 = k.min(3);
                    (format!("{p}{}{}", &rpm[..k3], "0".repeat(k - k3)), rpm[k3..].to_string())
                };
                cmds.push((format!("01{h}"), b));
                if bn {
                    let (tag, len, data, shift, abs) = tables[2][rng.gen_range(0..tables[2].len())];
                    let d = data.saturating_sub(shift);
                    let s = if abs {
                        format!(
                            "{}{}{}",
                            bits(u64::from(tag), len),
                            bits(rng.gen_range(0..64), 6),
                            bits(rng.gen_range(0..=64u64 >> shift.min(6)), 2 * d)
                        )
                    } else {
                        format!("{}{}", bits(u64::from(tag), len), bits(rng.gen::<u64>(), 2 * d))
                    };
                    let (h, b) = split6(s);
                    cmds.push((h, b));
                }
                if bc {
                    let (tag, len, data, shift, _) = tables[1][rng.gen_range(0..tables[1].len())];
                    let d = data.saturating_sub(shift);
                    let comps = if alpha { 4 } else { 3 };
                    let (h, b) = split6(format!("{}{}", bits(u64::from(tag), len), bits(rng.gen::<u64>(), comps * d)));
                    cmds.push((h, b));
                }
            }
            60..=74 => {
                let depth = rng.gen_range(0..pushes.clamp(1, 16));
                let rep = rng.gen_range(0..4u64);
                cmds.push((format!("001{}{}", bits(u64::from(depth), 4), rep >> 1), bits(rep & 1, 1)));
            }
            75..=79 => {
                let (tag, len, data, shift, _) = tables[1][rng.gen_range(0..tables[1].len())];
                let d = data.saturating_sub(shift);
                let comps = if alpha { 4 } else { 3 };
                let (h, b) = split6(format!("{}{}", bits(u64::from(tag), len), bits(rng.gen::<u64>(), comps * d)));
                cmds.push((format!("10{h}"), b));
            }
            80..=84 => {
                let (tag, len, data, shift, abs) = tables[2][rng.gen_range(0..tables[2].len())];
                let d = data.saturating_sub(shift);
                let s = if abs {
                    format!(
                        "{}{}{}",
                        bits(u64::from(tag), len),
                        bits(rng.gen_range(0..64), 6),
                        bits(rng.gen_range(0..32), 2 * d)
                    )
                } else {
                    format!("{}{}", bits(u64::from(tag), len), bits(rng.gen::<u64>(), 2 * d))
                };
                let (h, b) = split6(s);
                cmds.push((format!("11{h}"), b));
            }
            85..=87 => {
                bn = rng.gen_bool(0.5);
                bc = rng.gen_bool(0.5);
                alpha = rng.gen_bool(0.5);
                cmds.push((
                    format!("00011{}{}", bits(rng.gen_range(0..4), 2), u8::from(bn)),
                    format!("{}{}0", u8::from(bc), u8::from(alpha)),
                ));
            }
            88..=90 => {
                let n = rng.gen_range(0..32u64);
                cmds.push(("00000001".into(), format!("{}{}", bits(n, 5), bits(rng.gen(), n as u32))));
            }
            91..=92 => cmds.push(("00001000".into(), bits(rng.gen(), 56))),
            93..=94 => cmds.push(("00000111".into(), bits(rng.gen(), 8))),
            _ => cmds.push((bits(rng.gen_range(2..7), 8), String::new())),
        }
    }
    let refs: Vec<(&str, &str)> = cmds.iter().map(|(h, b)| (h.as_str(), b.as_str())).collect();
    forward(&refs)
}

#[test]
fn fast_and_reference_decoders_agree_on_random_streams() {
    let mut rng = ChaCha8Rng::seed_from_u64(1_000_006);
    let (mut ok, mut err, mut streamed_primitives) = (0, 0, 0);
    for _ in 0..3000 {
        let bytes = random_stream(&mut rng);
        let kind = [BlockKind::Triangles, BlockKind::Lines, BlockKind::Points][rng.gen_range(0..3)];
        let h = CgHeader { kind, ..tri_header() };
        match decode_both(&h, &bytes) {
            Ok(_) => ok += 1,
            Err(_) => err += 1,
        }
        // The streaming decoder agrees on success or failure, and on the
        // primitives: the same triangles (in another order), lines and points.
        let (mut tris, mut lines, mut points) = (Vec::new(), Vec::new(), Vec::new());
        let streamed = decode_with(&h, &bytes, |p| match p {
            Primitive::Triangle(t) => tris.push(t.map(|v| *v)),
            Primitive::Line(l) => lines.push(l.map(|v| *v)),
            Primitive::Point(v) => points.push(*v),
        });
        let java = decode(&h, &bytes);
        assert_eq!(streamed.is_ok(), java.is_ok());
        if let Ok(d) = java {
            assert_eq!(sorted_keys(&tris), sorted_keys(&d.triangles), "streaming and Java-order triangles differ");
            assert_eq!(lines, d.lines);
            assert_eq!(points, d.points);
            streamed_primitives += tris.len() + lines.len() + points.len();
        }
    }
    println!("{ok} decoded, {err} refused, {streamed_primitives} primitives streamed");
    assert!(ok > 300 && err > 300, "{ok} decoded, {err} refused: the generator should exercise both");
    assert!(
        streamed_primitives > 3000,
        "{streamed_primitives} primitives: the comparison should have something to compare"
    );
}

#[test]
fn random_bytes_never_panic_and_decoders_agree() {
    let mut rng = ChaCha8Rng::seed_from_u64(66);
    for i in 0..5000 {
        let len = 4 * rng.gen_range(0..64) + if i % 10 == 0 { rng.gen_range(1..4) } else { 0 };
        let mut bytes: Vec<u8> = (0..len).map(|_| rng.gen()).collect();
        // Often start with a real setState so that more than the first command is tried.
        if rng.gen_bool(0.7) && bytes.len() >= 2 {
            bytes[0] = 0x18 | rng.gen_range(0..2);
            bytes[1] = (bytes[1] & 0b0000_0111) | (rng.gen_range(0..8) << 3);
        }
        let _ = decode_both(&tri_header(), &bytes);
        let _ = decode_with(&tri_header(), &bytes, |_| {});
        let _ = CgFile::parse(&bytes, std::path::Path::new("random.cg"));
    }
}

fn error_of(bytes: &[u8]) -> String {
    match decode_both(&tri_header(), bytes) {
        Ok(d) => panic!("decoded {} triangles but should fail", d.triangles.len()),
        Err(e) => {
            println!("error as expected: {e}");
            e.to_string()
        }
    }
}

#[test]
fn bad_streams_give_clear_errors() {
    let state = ("00011000", "000");
    let table = ("00010000", "000001 0000 1 1000");
    let vertex = ("01 000000", "01 1 00 00000000 00000000");
    // A mesh-buffer reference before any push.
    assert!(error_of(&forward(&[state, table, ("001 0000 1", "1")])).contains("only 0 vertices have been pushed"));
    // The error is data too, not only text.
    let e = decode(&tri_header(), &forward(&[state, table, ("001 0000 1", "1")])).unwrap_err();
    let deep = StreamProblem::MeshReferenceTooDeep { depth: 0, pushes: 0 };
    assert!(matches!(e, Error::Stream { bit: 47, problem } if problem == deep), "{e:?}");
    // A reference deeper than the pushes so far.
    assert!(error_of(&forward(&[state, table, vertex, ("001 0011 1", "1")])).contains("reference 3 but only 1"));
    // A vertex before any setState.
    assert!(error_of(&forward(&[table, vertex])).contains("before any setState"));
    // A table entry shifting by more than its length (data 4, shift 9).
    assert!(
        error_of(&forward(&[state, ("00010000", "000001 0100 1 1001"), vertex])).contains("more than its data length")
    );
    // A vertex through an entry never loaded: Java's zeroed entry leaves 6 header bits for 3 replace bits.
    assert!(error_of(&forward(&[state, vertex])).contains("replace/push bits"));
    // A restart without two following vertices.
    assert!(error_of(&forward(&[state, table, vertex, vertex])).contains("restart"));
    // A normal outside the grid: absolute, u = 65 (7 bits, data length 7).
    let nstate = ("00011001", "000");
    let ntable = ("00010100", "000001 0111 1 0000");
    let e = error_of(&forward(&[
        nstate,
        table,
        ntable,
        ("01 000000", "01 1 00 00000000 00000000"),
        ("000000", "1000001 0000000"),
    ]));
    assert!(e.contains("outside the 64-step grid"), "{e}");
    // Truncated: the last word of a valid stream removed, and a length not a multiple of 4.
    let good = forward(&[state, table, vertex, vertex, vertex]);
    assert_eq!(decode_both(&tri_header(), &good).expect("valid").triangles.len(), 1);
    assert!(error_of(&good[..good.len() - 2]).contains("not a whole number of 4-byte words"));
    for cut in (0..good.len()).step_by(4) {
        // Shorter streams fail or hold fewer triangles; none panics.
        if let Ok(d) = decode_both(&tri_header(), &good[..cut]) {
            assert!(d.triangles.is_empty());
        }
    }
    // Reserved opcodes 0x02..0x06 and 0x09..0x0F are no-ops in Java 3D 1.5.2, and here.
    let with_reserved = forward(&[state, ("00000011", ""), table, ("00001111", ""), vertex, vertex, vertex]);
    assert_eq!(decode_both(&tri_header(), &with_reserved).expect("reserved opcodes").triangles.len(), 1);
    // A newer format version.
    let v2 = CgHeader { version: [1, 1, 0], ..tri_header() };
    assert!(matches!(decode(&v2, &good), Err(Error::UnsupportedVersion { version: [1, 1, 0] })));
}

#[test]
fn every_truncation_of_encoded_streams_is_handled() {
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    let m = random_mesh(&mut rng, 6, 5);
    let mesh =
        Mesh { positions: &m.positions, normals: Some(&m.normals), colors: Some(&m.colors), triangles: &m.triangles };
    let enc = encode(&mesh, &EncodeOptions::default()).expect("encode");
    for cut in 0..enc.bytes.len() {
        match decode_both(&enc.header, &enc.bytes[..cut]) {
            // Only the final padding (no-ops, under 8 bytes) may go unnoticed.
            Ok(d) => assert!(
                d.triangles.len() < m.triangles.len() || cut + 8 > enc.bytes.len(),
                "cut at {cut} decoded everything"
            ),
            Err(e) => assert!(!e.to_string().is_empty()),
        }
    }
    // Flipped bits: any result, never a panic, both decoders agreeing.
    for _ in 0..2000 {
        let mut b = enc.bytes.clone();
        let i = rng.gen_range(0..b.len());
        b[i] ^= 1 << rng.gen_range(0..8);
        let _ = decode_both(&enc.header, &b);
    }
}

/// `.cg` bytes laid out by hand from the format table (not by the library's writer).
fn hand_cg(objects: &[(u32, &[u8])]) -> Vec<u8> {
    let mut body = Vec::new();
    let mut offsets = Vec::new();
    for (descriptor, stream) in objects {
        offsets.push(32 + body.len() as u64);
        body.extend((stream.len() as u32).to_be_bytes());
        body.extend(descriptor.to_be_bytes());
        body.extend(*stream);
    }
    while body.len() % 8 != 0 {
        body.push(0);
    }
    let mut out = Vec::new();
    for v in [0xBADD_FAB4u32, 1, 0, 2, objects.len() as u32, 0] {
        out.extend(v.to_be_bytes());
    }
    out.extend((32 + body.len() as u64).to_be_bytes());
    out.extend(body);
    for o in offsets {
        out.extend(o.to_be_bytes());
    }
    out
}

/// A file of the repository's `fixtures/cg/`, beside this crate's folder.
fn fixture(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../fixtures/cg").join(name)
}

/// fixtures/cg/hand-two-objects.cg: the two hand-built streams as a
/// two-object file (triangles; then triangles with normals and colours).
/// `HOLO_WRITE_FIXTURES=1` rewrites it.
#[test]
fn hand_made_cg_fixture_reads() {
    let (a, b) = (stream_positions(), stream_bundled());
    let bytes = hand_cg(&[(3, &a), (3 | 0x04 | 0x08, &b)]);
    let path = fixture("hand-two-objects.cg");
    if std::env::var_os("HOLO_WRITE_FIXTURES").is_some() {
        std::fs::create_dir_all(path.parent().unwrap()).unwrap();
        std::fs::write(&path, &bytes).unwrap();
    }
    assert_eq!(std::fs::read(&path).expect("fixture"), bytes, "the fixture is the hand layout");
    let file = CgFile::read(&path).expect("read");
    assert_eq!(file.version, [1, 0, 2]);
    assert_eq!(file.objects.len(), 2);
    assert_eq!(
        file.objects[1].header,
        CgHeader { kind: BlockKind::Triangles, normals: true, colors: true, alpha: false, version: [1, 0, 2] }
    );
    assert_eq!(file.to_bytes(), bytes, "writing gives back the same bytes");
    let decoded = read_cg_file(&path).expect("decode");
    assert_eq!(decoded[0].triangles.len(), 2);
    assert_eq!(decoded[1].triangles, expected_bundled());
}

#[test]
fn cg_files_round_trip_and_bad_files_fail() {
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    let m = random_mesh(&mut rng, 9, 7);
    let mesh =
        Mesh { positions: &m.positions, normals: Some(&m.normals), colors: Some(&m.colors), triangles: &m.triangles };
    let folder = tempfile::tempdir().unwrap();
    let path = folder.path().join("mesh.cg");
    let enc = encode(&mesh, &EncodeOptions { position_bits: 10, color_bits: 8, normal_bits: 6, alpha: true }).unwrap();
    std::fs::write(&path, CgFile::from_encoded(&enc).to_bytes()).unwrap();
    let decoded = read_cg_file(&path).unwrap();
    assert_eq!(decoded.len(), 1);
    assert_eq!(decoded[0], decode(&enc.header, &enc.bytes).unwrap());
    // Decoded positions map back to model space within half a 10-bit step of the largest extent.
    let extent = (0..3)
        .map(|k| {
            let (lo, hi) =
                m.positions.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), p| (l.min(p[k]), h.max(p[k])));
            hi - lo
        })
        .fold(0.0, f64::max);
    let first = decoded[0].triangles[0][0].position;
    let model = enc.model_from_normalised(first);
    let nearest = m
        .positions
        .iter()
        .map(|p| (0..3).map(|k| (p[k] - model[k]).abs()).fold(0.0, f64::max))
        .fold(f64::INFINITY, f64::min);
    assert!(nearest <= extent / 1024.0 * 0.51 + 1e-9, "{nearest} from the nearest input vertex (extent {extent})");
    let bytes = std::fs::read(&path).unwrap();
    // Java's block descriptor: triangle (3) | normals (4) | colours (8) | alpha (16).
    assert_eq!(u32::from_be_bytes(bytes[36..40].try_into().unwrap()), 3 | 4 | 8 | 16);
    let bad = |b: &[u8], what: &str| {
        let e = CgFile::parse(b, std::path::Path::new("bad.cg")).expect_err(what).to_string();
        println!("{what}: {e}");
        assert!(e.starts_with("bad.cg"), "{e}");
    };
    bad(&bytes[..20], "truncated header");
    let e = CgFile::parse(&bytes[..20], std::path::Path::new("bad.cg")).unwrap_err();
    assert!(matches!(e, Error::File { problem: FileProblem::TooShort { bytes: 20 }, .. }), "{e:?}");
    let mut b = bytes.clone();
    b[0] = 0;
    bad(&b, "bad magic");
    let mut b = bytes.clone();
    b[16..20].copy_from_slice(&u32::MAX.to_be_bytes());
    bad(&b, "absurd object count");
    let mut b = bytes.clone();
    b[24..32].copy_from_slice(&u64::MAX.to_be_bytes());
    bad(&b, "directory past the end");
    let mut b = bytes.clone();
    b[32..36].copy_from_slice(&u32::MAX.to_be_bytes());
    bad(&b, "object larger than its block");
    let mut b = bytes.clone();
    b[39] &= !3;
    bad(&b, "geometry type 0");
    let mut b = bytes.clone();
    let dir = u64::from_be_bytes(b[24..32].try_into().unwrap()) as usize;
    b[dir..dir + 8].copy_from_slice(&(1u64 << 40).to_be_bytes());
    bad(&b, "object offset past the directory");
    // A well-formed file with an object that does not decode: the error names the file and the object.
    let broken = folder.path().join("broken.cg");
    std::fs::write(&broken, hand_cg(&[(3, &stream_positions()), (3, &[0u8; 6])])).unwrap();
    let e = read_cg_file(&broken).unwrap_err();
    assert!(matches!(e, Error::Object { object: 1, .. }), "{e:?}");
    assert!(e.to_string().starts_with(&format!("{}: object 1: ", broken.display())), "{e}");
    // Every truncation of the file fails cleanly.
    for cut in 0..bytes.len() {
        assert!(CgFile::parse(&bytes[..cut], std::path::Path::new("cut.cg")).is_err());
    }
}
