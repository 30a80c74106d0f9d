//! What `holo info` computes, as a library call with a serialisable
//! result; the CLI only prints it.

use std::fmt;
use std::path::Path;

use serde::Serialize;

use crate::error::Result;
use crate::format::{FileInfo, HoloFile};

/// `holo info`: the headers plus, when asked, the value range of every frame.
#[derive(Clone, Debug, Serialize)]
pub struct Info {
    /// What the headers say.
    #[serde(flatten)]
    pub file: FileInfo,
    /// Uncompressed size of the samples, all frames.
    pub raw_bytes: u64,
    /// Smallest and largest sample of each frame (when values were read).
    pub value_ranges: Option<Vec<(f32, f32)>>,
}

/// Read the headers of `path` and, if `values`, every frame (verifying digests).
pub fn info(path: impl AsRef<Path>, values: bool) -> Result<Info> {
    let file = HoloFile::open(path)?;
    let value_ranges = if values {
        Some(
            (0..file.info().frames.len())
                .map(|i| file.read_frame(i).map(|m| m.value_range()))
                .collect::<Result<Vec<_>>>()?,
        )
    } else {
        None
    };
    Ok(Info { raw_bytes: file.info().raw_bytes(), file: file.info().clone(), value_ranges })
}

/// Whether two files hold the same content: same geometry, sample type and
/// frame digests (compression and data window may differ).
pub fn same_content(a: &Info, b: &Info) -> bool {
    // A full-parallax frame has a digest per view (spec §8).
    let digests = |i: &Info| {
        i.file
            .frames
            .iter()
            .flat_map(|f| {
                if f.views.is_empty() {
                    vec![f.digest.clone()]
                } else {
                    f.views.iter().map(|v| v.digest.clone()).collect()
                }
            })
            .collect::<Vec<_>>()
    };
    a.file.geometry == b.file.geometry
        && a.file.sample_type == b.file.sample_type
        && digests(a).iter().all(Option::is_some)
        && digests(a) == digests(b)
}

impl fmt::Display for Info {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let i = &self.file;
        let g = &i.geometry;
        let mm = |m: f64| m * 1e3;
        writeln!(f, "{}", i.path.display())?;
        writeln!(
            f,
            "  format        .holo {}.{} (OpenEXR), {} frame(s), pixel aspect ratio {:.4}",
            i.version.0,
            i.version.1,
            i.frames.len(),
            i.pixel_aspect
        )?;
        let colours: Vec<String> =
            g.channels.iter().map(|c| format!("{} {:.1} nm", c.name, c.wavelength_m * 1e9)).collect();
        match &g.vertical_views {
            None => {
                writeln!(
                    f,
                    "  size          {} hololines × {} emitters × {} views, {:?} parallax",
                    g.hololines, g.emitters, g.views.count, g.parallax
                )?;
                writeln!(
                    f,
                    "  channels      {} ({} EXR channels, {:?})",
                    colours.join(", "),
                    g.views.count * g.channels.len(),
                    i.sample_type
                )?;
            }
            Some(vertical) => {
                writeln!(
                    f,
                    "  size          {} emitter rows × {} emitters × {} × {} views (horizontal × vertical), full parallax",
                    g.hololines, g.emitters, g.views.count, vertical.count
                )?;
                writeln!(
                    f,
                    "  channels      {} ({} EXR channels in each of the {} parts of a frame, one per view, {:?})",
                    colours.join(", "),
                    g.channels.len(),
                    g.views_per_emitter(),
                    i.sample_type
                )?;
            }
        }
        writeln!(
            f,
            "  emitters      pitch {:.4} mm, x from {:.4} to {:.4} mm, plane z = {:.4} mm",
            mm(g.emitter_pitch_m),
            mm(g.emitter_x_m(0)),
            mm(g.emitter_x_m(g.emitters - 1)),
            mm(g.emitter_z_m)
        )?;
        writeln!(
            f,
            "  hololines     pitch {:.4} mm, y from {:.4} to {:.4} mm",
            mm(g.hololine_pitch_m),
            mm(g.hololine_y_m(0)),
            mm(g.hololine_y_m(g.hololines - 1))
        )?;
        writeln!(
            f,
            "  views         {:.3}° … {:.3}°, uniform in {}",
            g.views.first_theta_rad.to_degrees(),
            g.views.last_theta_rad.to_degrees(),
            g.views.spacing.name()
        )?;
        if let Some(vertical) = &g.vertical_views {
            writeln!(
                f,
                "  vertical      {:.3}° … {:.3}°, uniform in {} (positive up)",
                vertical.first_theta_rad.to_degrees(),
                vertical.last_theta_rad.to_degrees(),
                vertical.spacing.name()
            )?;
        }
        writeln!(
            f,
            "  viewer        line at z = {:.1} mm, y = {:.1} mm",
            mm(g.viewer_distance_m),
            mm(g.viewer_height_m)
        )?;
        writeln!(
            f,
            "  radiometry    {}, radiance = sample × {} ({})",
            i.radiometry.encoding, i.radiometry.scale, i.radiometry.unit
        )?;
        let ratio = i.file_bytes as f64 / self.raw_bytes.max(1) as f64;
        writeln!(
            f,
            "  on disk       {} bytes, {:.1}% of {} raw bytes, compression {}",
            i.file_bytes,
            100.0 * ratio,
            self.raw_bytes,
            i.compression.name()
        )?;
        if let Some(fps) = i.frames_per_second {
            writeln!(f, "  frame rate    {}", frame_rate_text(fps.0.into(), fps.1.into()))?;
        }
        writeln!(f, "  written by    {}", i.software.as_deref().unwrap_or("(unknown)"))?;
        if let Some(s) = &i.source {
            writeln!(f, "  source        {s}")?;
        }
        if let Some(m) = &i.placement {
            // Exactly (shortest round-trip form), row by row, in the form
            // `convert mesh --matrix` takes.
            let all: Vec<String> = m.iter().flatten().map(|x| x.to_string()).collect();
            writeln!(f, "  placement     input to display metres, row by row: {}", all.join(","))?;
        }
        for (k, frame) in i.frames.iter().enumerate() {
            let w = frame.data_window;
            let digest = match (&frame.digest, frame.views.len()) {
                (Some(d), _) => d.clone(),
                (None, 0) => "no digest".into(),
                (None, n) => format!("a digest for each of {n} views (`holo info --json` lists them)"),
            };
            write!(f, "  frame {:<7} data {}×{} at ({}, {}), {digest}", frame.number, w.width, w.height, w.x, w.y)?;
            if let Some(r) = self.value_ranges.as_ref().and_then(|v| v.get(k)) {
                write!(f, ", values {} … {}", r.0, r.1)?;
            }
            writeln!(f)?;
        }
        for u in &i.unknown_attributes {
            writeln!(f, "  ignored       unknown attribute {u}")?;
        }
        Ok(())
    }
}

/// A frame rate stored as the fraction `numerator / denominator` frames a
/// second, as a number with its unit: `24 frames/s`, `0.5 frames/s`; a
/// fraction that is not a whole number of thousandths is given as well,
/// `23.976 frames/s (24000/1001)`.
pub fn frame_rate_text(numerator: i64, denominator: u64) -> String {
    if denominator == 0 {
        return format!("{numerator}/0 frames/s (no rate)");
    }
    let rate = numerator as f64 / denominator as f64;
    if (i128::from(numerator) * 1000) % i128::from(denominator) == 0 {
        let text = format!("{rate:.3}");
        format!("{} frames/s", text.trim_end_matches('0').trim_end_matches('.'))
    } else {
        format!("{rate:.3} frames/s ({numerator}/{denominator})")
    }
}

#[cfg(test)]
mod tests {
    use super::frame_rate_text;

    #[test]
    fn frame_rates_are_numbers_with_units() {
        for (n, d, text) in [
            (24, 1, "24 frames/s"),
            (1, 2, "0.5 frames/s"),
            (2997, 100, "29.97 frames/s"),
            (24000, 1001, "23.976 frames/s (24000/1001)"),
            (30000, 1001, "29.970 frames/s (30000/1001)"),
            (1, 3, "0.333 frames/s (1/3)"),
        ] {
            assert_eq!(frame_rate_text(n, d), text);
        }
    }
}
