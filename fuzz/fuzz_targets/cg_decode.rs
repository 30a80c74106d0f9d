//! Any bytes given to the `.cg` file reader and to the raw stream decoders
//! give a result or an error, never a panic, an abort or an unbounded
//! allocation; the fast and reference decoders agree on every input, and
//! the streaming decoder hands out the same primitives.
#![no_main]

use holo_cg::{decode, decode_reference, decode_with, file::CgFile, BlockKind, CgHeader, Primitive, Vertex};
use libfuzzer_sys::fuzz_target;

fn agree(header: &CgHeader, bytes: &[u8]) {
    let fast = decode(header, bytes);
    let slow = decode_reference(header, bytes);
    match (&fast, &slow) {
        (Ok(a), Ok(b)) => assert_eq!(a, b, "fast and reference decoders differ"),
        (Err(a), Err(b)) => assert_eq!(a.to_string(), b.to_string()),
        _ => panic!("fast {fast:?} and reference {slow:?} disagree"),
    }
    let (mut triangles, mut lines, mut points) = (Vec::new(), Vec::new(), Vec::new());
    let streamed = decode_with(header, bytes, |p| match p {
        Primitive::Triangle(t) => triangles.push(t.map(key)),
        Primitive::Line(l) => lines.push(l.map(key)),
        Primitive::Point(v) => points.push(key(v)),
    });
    assert_eq!(streamed.is_ok(), fast.is_ok());
    if let Ok(d) = fast {
        // Triangles in another order, each maybe starting at another corner.
        let canonical = |ts: Vec<[Vec<u32>; 3]>| {
            let mut ts: Vec<_> = ts
                .into_iter()
                .map(|[a, b, c]| {
                    [[a.clone(), b.clone(), c.clone()], [b.clone(), c.clone(), a.clone()], [c, a, b]].into_iter().min()
                })
                .collect();
            ts.sort();
            ts
        };
        let java: Vec<[Vec<u32>; 3]> = d.triangles.iter().map(|t| t.each_ref().map(key)).collect();
        assert_eq!(canonical(triangles), canonical(java), "streaming and Java-order triangles differ");
        assert_eq!(lines, d.lines.iter().map(|l| l.each_ref().map(key)).collect::<Vec<_>>());
        assert_eq!(points, d.points.iter().map(key).collect::<Vec<_>>());
    }
}

/// Every bit of a vertex (floats compared as bits: NaN-safe, -0.0 distinct).
fn key(v: &Vertex) -> Vec<u32> {
    v.position.iter().chain(v.normal.iter().flatten()).chain(v.color.iter().flatten()).map(|c| c.to_bits()).collect()
}

fuzz_target!(|data: &[u8]| {
    if let Ok(file) = CgFile::parse(data, std::path::Path::new("fuzz.cg")) {
        for o in &file.objects {
            agree(&o.header, &o.bytes);
        }
    }
    // The raw stream, with the kind taken from the first byte.
    let (kind, stream) = match data.split_first() {
        Some((k, rest)) => ([BlockKind::Triangles, BlockKind::Lines, BlockKind::Points][usize::from(*k % 3)], rest),
        None => (BlockKind::Triangles, data),
    };
    let header = CgHeader { kind, normals: false, colors: false, alpha: false, version: [1, 0, 2] };
    agree(&header, stream);
});
