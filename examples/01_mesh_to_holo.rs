//! A mesh scene to a `.holo` file in one call.
//!
//! ```text
//! cargo run --example 01_mesh_to_holo
//! ```
//!
//! Renders the bundled "Spot" cow (an OBJ with a texture) for the MIT Mark I
//! display and writes one frame of modulation to `spot.holo` in a new folder
//! under the system's temporary folder, which it prints. For a scene of your
//! own, change `SCENE` (OBJ, glTF/GLB or PLY; an animated glTF gives one frame
//! per 1/30 s).

use std::error::Error;
use std::path::{Path, PathBuf};

use holo::mesh::convert::{convert_mesh, ConvertOptions};
use holo::progress::Silent;

/// The scene to render.
const SCENE: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/fixtures/mesh/spot/spot.obj");

fn main() -> Result<(), Box<dyn Error>> {
    // A new folder each run, kept: nothing a user had is replaced, and the
    // file stays to be looked at.
    let folder = tempfile::Builder::new().prefix("holo-example-").tempdir()?.keep();
    let file = run(&folder)?;
    println!("wrote {}", file.display());
    println!("look at it with: holo info {}", file.display());
    Ok(())
}

/// Convert [`SCENE`] into `folder/spot.holo`; returns the file's path.
pub fn run(folder: &Path) -> Result<PathBuf, Box<dyn Error>> {
    // A display profile fixes the geometry: where the emitters and hololines
    // are (metres), the view directions (radians) and the colour channels.
    let layout = holo::layout::mark1();
    let output = folder.join("spot.holo");

    // The defaults fit the scene into the display's volume, light it with
    // its own lights (or three default ones when it has none), and write
    // f16 samples with ZIP compression. `write.overwrite` is false: an
    // existing `spot.holo` is refused before any work.
    let options = ConvertOptions::default();
    let report = convert_mesh(Path::new(SCENE), &layout.geometry, &output, &options, &Silent)?;

    println!("{} triangles in {} objects, {}", report.triangles, report.objects, report.placed);
    for warning in &report.warnings {
        println!("warning: {warning}");
    }
    println!("{} bytes, frame digest {}", report.written.file_bytes, report.written.digests[0]);
    Ok(report.path)
}
