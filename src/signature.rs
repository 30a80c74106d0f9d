//! The first bytes of the files holo reads and writes, so that any reader can
//! say what it was handed instead (a HoloFlick given to a `.holo` command, a
//! picture given as a scene) without importing the other format's code.

/// The first 8 bytes of every HoloFlick (`spec/holoflick.md` §4).
pub const HOLOFLICK: [u8; 8] = [0x89, b'H', b'F', b'L', b'K', 0x0D, 0x0A, 0x1A];
/// The first 4 bytes of every OpenEXR file (its magic number 20000630,
/// little-endian): a `.holo` file begins with them.
pub const OPENEXR: [u8; 4] = [0x76, 0x2f, 0x31, 0x01];
/// The first 8 bytes of every PNG picture (PNG specification §5.2).
pub const PNG: [u8; 8] = *b"\x89PNG\r\n\x1a\n";
/// The first 3 bytes of every JPEG picture: the start-of-image marker and
/// the first byte of the next marker (ITU-T T.81 Annex B).
pub const JPEG: [u8; 3] = [0xFF, 0xD8, 0xFF];
/// The first 4 bytes of a binary glTF (`.glb`) scene (glTF 2.0 §4.4.2).
pub const GLB: [u8; 4] = *b"glTF";

/// A kind of file that holo's users most often hand the wrong command.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FileKind {
    /// A HoloFlick (`.hflk`).
    HoloFlick,
    /// An OpenEXR file (`.holo` or `.exr`).
    OpenExr,
    /// A PNG picture.
    Png,
    /// A binary glTF scene (`.glb`).
    Glb,
}

/// What `head` (a file's first bytes, at least 8 when the file has them)
/// begins, when it is one of the kinds above.
pub fn kind_of(head: &[u8]) -> Option<FileKind> {
    if head.starts_with(&HOLOFLICK) {
        Some(FileKind::HoloFlick)
    } else if head.starts_with(&OPENEXR) {
        Some(FileKind::OpenExr)
    } else if head.starts_with(&PNG) {
        Some(FileKind::Png)
    } else if head.starts_with(&GLB) {
        Some(FileKind::Glb)
    } else {
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_kind_is_told_by_its_first_bytes_and_nothing_else_is() {
        let mut holoflick = HOLOFLICK.to_vec();
        holoflick.extend_from_slice(&[0; 8]);
        assert_eq!(kind_of(&holoflick), Some(FileKind::HoloFlick));
        assert_eq!(kind_of(&[0x76, 0x2f, 0x31, 0x01, 2, 0, 0, 0]), Some(FileKind::OpenExr));
        assert_eq!(kind_of(&PNG), Some(FileKind::Png));
        assert_eq!(kind_of(b"glTF\x02\0\0\0"), Some(FileKind::Glb));
        assert_eq!(kind_of(&HOLOFLICK[..7]), None, "a file cut short of its magic is no kind");
        assert_eq!(kind_of(b"# OBJ file"), None);
        assert_eq!(kind_of(&[]), None);
    }
}
