//! Any bytes given to the `.cg` file reader and to the raw stream decoders
//! give a result or an error, never a panic, an abort or an unbounded
//! allocation; the fast and reference decoders agree on every input.
#![no_main]

use holo::holoflick::cg::{decode, decode_reference, decode_with, file::CgFile, BlockKind, CgHeader};
use libfuzzer_sys::fuzz_target;

fn agree(header: &CgHeader, bytes: &[u8]) {
    let fast = decode(header, bytes);
    let slow = decode_reference(header, bytes);
    match (&fast, &slow) {
        (Ok(a), Ok(b)) => assert_eq!(a, b, "fast and reference decoders differ"),
        (Err(a), Err(b)) => assert_eq!(a.to_string(), b.to_string()),
        _ => panic!("fast {fast:?} and reference {slow:?} disagree"),
    }
    let mut n = 0usize;
    assert_eq!(decode_with(header, bytes, |_| n += 1).is_ok(), fast.is_ok());
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
