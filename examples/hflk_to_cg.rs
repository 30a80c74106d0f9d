//! Lift the geometry blocks of a HoloFlick out into a Java 3D `.cg` file
//! (spec/holoflick.md §6.4): every object stored in any frame, in file order,
//! copied unchanged. Java 3D then reads them (`tests/peer/CgBlocks.java`).
//!
//! ```text
//! cargo run --example hflk_to_cg -- MOVIE.hflk OUT.cg
//! ```

use std::process::ExitCode;

use holo::holoflick::container::{write_cg_file, HoloFlickReader, ObjectRecord};

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let [input, output] = args.as_slice() else {
        eprintln!("usage: hflk_to_cg MOVIE.hflk OUT.cg");
        return ExitCode::FAILURE;
    };
    match lift(input, output) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("{e}");
            ExitCode::FAILURE
        }
    }
}

fn lift(input: &str, output: &str) -> holo::Result<()> {
    let mut reader = HoloFlickReader::open(input)?;
    let mut blocks = Vec::new();
    for n in 0..reader.frame_count() {
        for object in reader.read_stored_frame(n)?.objects {
            if let ObjectRecord::Stored(o) = object {
                println!("frame {n} object {}: {:?}", o.id, o.block);
                blocks.push(o.block);
            }
        }
    }
    let bytes = write_cg_file(output, &blocks, true)?;
    println!("{output}: {} objects, {bytes} bytes", blocks.len());
    Ok(())
}
