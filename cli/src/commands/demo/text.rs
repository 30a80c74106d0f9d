//! What `holo demo` says: one line a file, what it is and where it is.

use std::fmt;

use super::chain::Demo;
use holo::report::frame_rate_text;

impl fmt::Display for Demo {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let [hololines, emitters, views] = self.size;
        let (images, fb_width, fb_height) = self.fringe_images;
        let m = &self.movie;
        let first = self.sheet_eyes_x_mm.first().copied().unwrap_or(0.0);
        let last = self.sheet_eyes_x_mm.last().copied().unwrap_or(0.0);
        writeln!(
            f,
            "holo demo: a {} hologram of the bundled cow, step by step, in {:.1} s",
            self.layout, self.seconds
        )?;
        writeln!(f, "  {}: the scene, {} triangles", self.scene.display(), self.triangles)?;
        writeln!(
            f,
            "  {}: its light field, {views} views of {hololines} hololines × {emitters} emitters, rendered in {:.2} s",
            self.holo_file.display(),
            self.convert_seconds
        )?;
        writeln!(f, "  {}: those views as a Looking Glass quilt of {} tiles", self.quilt.display(), self.quilt_tiles)?;
        let (hololine, samples) = &self.fringe_zoom;
        writeln!(
            f,
            "  {}: the fringes the display is sent ({images} images of {fb_width} × {fb_height}, assembled in {:.2} s) \
             and hololine {hololine}'s chirps, samples {} to {}",
            self.fringe_picture.display(),
            self.assemble_seconds,
            samples.start,
            samples.end
        )?;
        writeln!(
            f,
            "  {}: what {} eyes {:.0} mm away see, from x = {first:+.0} to {last:+.0} mm (scalar diffraction, {:.2} s)",
            self.eyes_sheet.display(),
            self.sheet_eyes_x_mm.len(),
            self.eye_distance_mm,
            self.view_seconds
        )?;
        writeln!(
            f,
            "  {}: an eye moving across the viewing zone and back, an animated PNG of {} frames",
            self.eyes_moving.display(),
            self.moving_eyes_x_mm.len()
        )?;
        let fp = &self.full_parallax;
        let [rows, columns, views_h, views_v] = fp.size;
        writeln!(f, "Full parallax (a hogel per emitter: views up and down as well):")?;
        writeln!(
            f,
            "  {}: the cow with {views_h} × {views_v} views of {rows} rows × {columns} emitters, rendered and written in {:.2} s",
            fp.holo_file.display(),
            fp.convert_seconds
        )?;
        let heights: Vec<String> = fp.eyes_y_mm.iter().map(|y| format!("{y:+.0}")).collect();
        writeln!(
            f,
            "  {}: what eyes {:.0} mm away at y = {} mm see of its rays ({:.2} s)",
            fp.eyes_sheet.display(),
            fp.eye_distance_mm,
            heights.join(", "),
            fp.view_seconds
        )?;
        let rate =
            m.frames_per_second.map_or(String::new(), |(n, d)| format!(" at {}", frame_rate_text(n.into(), d.into())));
        writeln!(f, "The movie:")?;
        writeln!(f, "  {}: an animated scene, {} frames taken{rate}", m.scene.display(), m.frames)?;
        writeln!(
            f,
            "  {}: its HoloFlick, {} micropolygons, {} bytes, encoded in {:.2} s",
            m.holoflick.display(),
            m.micropolygons,
            m.holoflick_bytes,
            m.seconds[0]
        )?;
        writeln!(
            f,
            "  {}: its light field, {} frames, drawn in {:.2} s",
            m.holo_file.display(),
            m.frames,
            m.seconds[1]
        )?;
        writeln!(
            f,
            "  {}: what an eye in the middle sees of each frame ({:.2} s)",
            m.frames_picture.display(),
            m.seconds[2]
        )?;
        writeln!(f, "The fringe images themselves, for the display (8-bit PNG, {images} a frame):")?;
        for (file, frames) in [(&self.holo_file, 1), (&m.holo_file, m.frames)] {
            let fringes = file.with_file_name("fringes");
            writeln!(
                f,
                "  holo assemble {} --layout {} -o {}    ({} fringe images)",
                file.display(),
                self.layout,
                fringes.display(),
                images * frames
            )?;
        }
        Ok(())
    }
}
