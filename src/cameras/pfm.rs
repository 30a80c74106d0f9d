//! Portable Float Map (PFM), the format of depth and disparity maps in the
//! light-field and stereo benchmarks: a text header `PF` (colour) or `Pf`
//! (grey), `width height`, and a scale whose sign gives the byte order
//! (negative = little-endian), each followed by one whitespace byte; then
//! 32-bit floats, rows stored bottom to top. Samples are multiplied by the
//! scale's magnitude, as the HCI benchmark's reader does (its files, and
//! this writer's, say −1).

use std::io::Read;
use std::path::Path;

use super::{Camera, DepthKind};
use crate::error::{Error, Result};

/// Header bytes read before giving up on finding the samples (comments
/// included); real headers are a few dozen bytes.
const MAX_HEADER_BYTES: usize = 4096;

/// Read a PFM file: `(width, height, channels, samples)`, samples top row
/// first, interleaved per pixel when `channels` is 3. The header's size is
/// checked against the file's before anything is allocated.
pub fn read_pfm(path: &Path) -> Result<(usize, usize, usize, Vec<f32>)> {
    let bad = |problem: String| Error::rig(path, format!("not a readable PFM file: {problem}"));
    crate::output::regular_file(path).map_err(|problem| Error::rig(path, problem))?;
    let mut file = std::fs::File::open(path).map_err(|e| Error::io(path, e))?;
    let file_bytes = file.metadata().map_err(|e| Error::io(path, e))?.len();
    let mut head = Vec::with_capacity(MAX_HEADER_BYTES);
    (&mut file).take(MAX_HEADER_BYTES as u64).read_to_end(&mut head).map_err(|e| Error::io(path, e))?;
    let (channels, width, height, scale, header_bytes) = parse_header(&head).map_err(bad)?;
    let needed = (width as u64)
        .checked_mul(height as u64)
        .and_then(|n| n.checked_mul(channels as u64 * 4))
        .ok_or_else(|| bad(format!("{width}×{height} is too large")))?;
    let present = file_bytes.saturating_sub(header_bytes as u64);
    if present != needed {
        let what = if present < needed { "truncated" } else { "longer than its header says" };
        return Err(bad(format!(
            "{what}: {width}×{height}×{channels} floats need {needed} bytes after the header, the file has {present}"
        )));
    }
    let mut bytes = head.split_off(header_bytes);
    bytes.reserve_exact((needed as usize).saturating_sub(bytes.len()));
    file.read_to_end(&mut bytes).map_err(|e| Error::io(path, e))?;
    if bytes.len() as u64 != needed {
        return Err(bad("the file changed while being read".into()));
    }
    let magnitude = scale.abs();
    let little = scale < 0.0;
    let row = width * channels;
    let mut samples = vec![0f32; width * height * channels];
    for (stored, chunk) in bytes.chunks_exact(4 * row).enumerate() {
        // Stored bottom row first.
        let out = &mut samples[(height - 1 - stored) * row..][..row];
        for (o, b) in out.iter_mut().zip(chunk.chunks_exact(4)) {
            let b = [b[0], b[1], b[2], b[3]];
            let v = if little { f32::from_le_bytes(b) } else { f32::from_be_bytes(b) };
            *o = if magnitude == 1.0 { v } else { v * magnitude };
        }
    }
    Ok((width, height, channels, samples))
}

/// `(channels, width, height, scale, header length)`, or what is wrong.
fn parse_header(head: &[u8]) -> Result<(usize, usize, usize, f32, usize), String> {
    let mut at = 0;
    let mut tokens = Vec::new();
    while tokens.len() < 4 {
        while at < head.len() && head[at].is_ascii_whitespace() {
            at += 1;
        }
        if at < head.len() && head[at] == b'#' {
            while at < head.len() && head[at] != b'\n' {
                at += 1;
            }
            continue;
        }
        let start = at;
        while at < head.len() && !head[at].is_ascii_whitespace() {
            at += 1;
        }
        if at == head.len() {
            return Err("the header is incomplete".into());
        }
        tokens.push(String::from_utf8_lossy(&head[start..at]).into_owned());
    }
    // One whitespace byte ends the scale; the samples follow.
    let header_bytes = at + 1;
    let channels = match tokens[0].as_str() {
        "PF" => 3,
        "Pf" => 1,
        other => return Err(format!("the header starts with \"{}\", not PF or Pf", other.escape_debug())),
    };
    let dimension = |t: &str, what: &str| match t.parse::<usize>() {
        Ok(n) if n > 0 => Ok(n),
        _ => Err(format!("the {what} \"{}\" is not a positive whole number", t.escape_debug())),
    };
    let width = dimension(&tokens[1], "width")?;
    let height = dimension(&tokens[2], "height")?;
    let scale: f32 = tokens[3].parse().map_err(|_| format!("the scale \"{}\" is not a number", tokens[3]))?;
    if !(scale.is_finite() && scale != 0.0) {
        return Err(format!("the scale {scale} must be finite and non-zero"));
    }
    Ok((channels, width, height, scale, header_bytes))
}

/// Write a grey PFM (`Pf`, little-endian, scale −1) from samples top row
/// first.
pub fn write_pfm(path: &Path, width: usize, height: usize, samples: &[f32]) -> Result<()> {
    if width == 0 || height == 0 || width.checked_mul(height) != Some(samples.len()) {
        return Err(Error::argument(
            "samples",
            format!("{}: {} samples do not make a {width}×{height} grey map", path.display(), samples.len()),
        ));
    }
    let mut bytes = format!("Pf\n{width} {height}\n-1\n").into_bytes();
    bytes.reserve(samples.len() * 4);
    for row in samples.chunks_exact(width).rev() {
        for v in row {
            bytes.extend_from_slice(&v.to_le_bytes());
        }
    }
    crate::output::write_bytes_beside(path, &bytes, true)
}

/// The camera's depth map as camera `z` per pixel (world units, top row
/// first), or `None` when the camera has none. Disparity maps are turned
/// into depth with the rig's `z = numerator / (d + offset)`; samples that
/// give no positive finite depth (holes, infinity) become NaN.
pub fn load_depth(camera: &Camera) -> Result<Option<Vec<f32>>> {
    let Some(depth) = &camera.depth else { return Ok(None) };
    let (w, h, channels, samples) = read_pfm(&depth.file)?;
    if (w, h, channels) != (camera.width, camera.height, 1) {
        return Err(Error::rig(
            &depth.file,
            format!(
                "camera {}: the depth map is {w}×{h} with {channels} channel(s), the camera needs {}×{} grey",
                camera.name, camera.width, camera.height
            ),
        ));
    }
    let z = |s: f32| -> f32 {
        let z = match depth.kind {
            DepthKind::Z { scale } => f64::from(s) * scale,
            DepthKind::Disparity { numerator, offset } => numerator / (f64::from(s) + offset),
        };
        if z > 0.0 && z.is_finite() {
            z as f32
        } else {
            f32::NAN
        }
    };
    Ok(Some(samples.into_iter().map(z).collect()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn round_trip_keeps_samples_and_orientation() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("d.pfm");
        let samples: Vec<f32> = (0..12).map(|i| i as f32 * 0.5 - 1.0).collect();
        write_pfm(&path, 4, 3, &samples).unwrap();
        let bytes = std::fs::read(&path).unwrap();
        assert!(bytes.starts_with(b"Pf\n4 3\n-1\n"));
        // The first stored row is the bottom one.
        assert_eq!(&bytes[10..14], &samples[8].to_le_bytes());
        assert_eq!(read_pfm(&path).unwrap(), (4, 3, 1, samples));
    }

    #[test]
    fn big_endian_colour_with_comment_and_scale() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("c.pfm");
        let mut bytes = b"PF\n# made here\n2 1\n2.0\n".to_vec();
        for v in [1.0f32, 2.0, 3.0, 4.0, 5.0, 6.0] {
            bytes.extend_from_slice(&v.to_be_bytes());
        }
        std::fs::write(&path, bytes).unwrap();
        assert_eq!(read_pfm(&path).unwrap(), (2, 1, 3, vec![2.0, 4.0, 6.0, 8.0, 10.0, 12.0]));
    }

    #[test]
    fn bad_files_are_refused_without_allocating() {
        let dir = tempfile::tempdir().unwrap();
        let cases: [(&[u8], &str); 7] = [
            (b"Pf\n4 3\n-1\n\0\0\0\0", "truncated"),
            (b"Pf\n100000 100000\n-1\n\0\0\0\0", "truncated"),
            (b"Pf\n18446744073709551615 18446744073709551615\n-1\n", "too large"),
            (b"P6\n4 3\n255\n", "not PF or Pf"),
            (b"Pf\n0 3\n-1\n", "positive whole number"),
            (b"Pf\n4 3\n0\n", "non-zero"),
            (b"Pf\n4", "incomplete"),
        ];
        for (i, (bytes, want)) in cases.iter().enumerate() {
            let path = dir.path().join(format!("bad{i}.pfm"));
            std::fs::write(&path, bytes).unwrap();
            let e = read_pfm(&path).unwrap_err().to_string();
            assert!(e.contains(want) && e.contains(&format!("bad{i}.pfm")), "case {i}: {e}");
        }
        let e = write_pfm(&dir.path().join("w.pfm"), 3, 3, &[0.0; 8]).unwrap_err().to_string();
        assert!(e.contains("8 samples"), "{e}");
    }
}
