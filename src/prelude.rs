//! What a first program needs, in one line: `use holo::prelude::*;`.
//!
//! A scene, a capture or a pattern into a `.holo` file; the file read,
//! checked and inspected; a display's layout and its fringes. Everything
//! else is one module away, under the step of the data flow it belongs to
//! (the crate's front page maps them).

pub use crate::assemble::output::{assemble_file, AssembleOptions};
pub use crate::assemble::{load_layout, Assembler};
pub use crate::cameras::convert::{convert_camera_files, CameraConvertOptions};
pub use crate::error::{Error, Result};
pub use crate::format::{read, write, FileInfo, HoloFile, Region, WriteOptions};
pub use crate::geometry::{Geometry, Views};
pub use crate::layout::{builtin, Layout};
pub use crate::mesh::convert::{convert_mesh, ConvertOptions};
pub use crate::modulation::{Band, Modulation};
pub use crate::pattern::{Pattern, PatternKind};
pub use crate::progress::{Progress, Silent};
pub use crate::validate::validate;
