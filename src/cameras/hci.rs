//! A full-parallax frame as an HCI 4D light field benchmark folder
//! (Honauer, Johannsen, Kondermann and Goldluecke, ACCV 2016; the reader
//! is [`super::read::read_hci`], whose text gives the benchmark's camera
//! conventions): `input_CamNNN.png` per view, 8-bit sRGB RGB, and
//! `parameters.cfg`, with the sections and keys the benchmark's
//! `file_io.read_parameters` reads (`[intrinsics]`, `[extrinsics]`,
//! `[meta]`), plus a manifest `holo-hci.json` written last as a set.
//!
//! **The grid.** Camera `NNN = row · V + column` (`num_cams_x = V`
//! horizontal views, `num_cams_y = W` vertical views) is view
//! `(h, k) = (column, W − 1 − row)`: the benchmark's camera rows step *down*
//! (row 0 the top row of cameras, which look up at the scene from above),
//! while holo's vertical views count *up* (view `W − 1` is sent up the
//! most, toward a viewer above); its columns step right, as `h` does.
//! Camera 40 of 9 × 9 is the middle view.
//!
//! **What is exact.** Each picture is view `(h, k)` sample for sample: one
//! pixel per emitter, column `e` from the left, row `j` from the top, as
//! `export-views` draws it (an oblique parallel projection of the scene
//! along `(tan θ_h, tan φ_k, 1)`). The grid's size, the numbering, the
//! picture size, and the depth where the views agree (the emitter plane:
//! disparity 0 at `focus_distance_m`) are the file's.
//!
//! **What is a convention.** The benchmark's cameras are pinholes; the
//! views are parallel projections. `parameters.cfg` describes the pinholes
//! that match them best: on the viewer's plane `z = D` (`s = D − z_e` from
//! the emitter plane), camera `(h, k)` at `s · (tan θ_h, tan φ_k)` from the
//! emitter grid's centre, unrotated (holo's axes are Blender's: `x` right,
//! `y` up, a camera looking along `−z`), focused at the emitter plane,
//! with a sensor as large as the emitter grid's larger side at a focal
//! length of `s` (one pixel per emitter pitch at the emitter plane). Such a
//! camera sees the emitter plane exactly as its view does, and a point off
//! it as its view does to first order in its depth over `s` (its rays fan
//! out where the view's are parallel). The baseline is the horizontal
//! views' spacing at the viewer (`s · Δ tan θ`); views not evenly spaced in
//! `tan`, a vertical spacing unlike the horizontal, pixels that are not
//! square or views not centred on the display's normal are said, as the
//! benchmark's single baseline, square pixels and centred grid cannot hold
//! them. The file holds no depth: `disp_min`/`disp_max` (and the frustum's)
//! are ±1 pixel, the depth the views resolve either side of the emitter
//! plane (a point beyond it moves more than one emitter between
//! neighbouring views), not the scene's; `fstop` 100 (all in focus: the
//! views are pinhole-sharp); `depth_map_scale` 1 (no depth maps are
//! written); `scene` the file's name, `category` `holo`.

use std::path::{Path, PathBuf};
use std::time::{SystemTime, UNIX_EPOCH};

use serde::{Deserialize, Serialize};

use crate::error::{Error, Result};
use crate::format::{view_digits, HoloFile};
use crate::geometry::Geometry;
use crate::output::{check_set_output, FileSet, SetFile};
use crate::picture::{encode_png, Bits, Colour, Tone, White};
use crate::views::{check_frame_and_white, white_of_frame, PictureChannels, ToneMapping};

/// The benchmark's parameter file.
pub const PARAMETERS: &str = "parameters.cfg";

/// The manifest written next to the pictures.
pub const MANIFEST: &str = "holo-hci.json";

/// The relative error in a derived camera number (a baseline, a grid
/// position, a pixel's shape) beyond which it is said.
const TOLERANCE: f64 = 0.01;

/// File name of camera `index` of `count`: `input_Cam040.png` (three
/// digits, more for a thousand cameras or more, so names sort in index
/// order, as the benchmark's reader lists them).
pub fn camera_file_name(index: usize, count: usize) -> String {
    let digits = view_digits(count);
    format!("input_Cam{index:0digits$}.png")
}

/// The benchmark's camera number of view `(h, k)` of `g`: row `W − 1 − k`
/// (rows step down, vertical views up), column `h`.
pub fn camera_of_view(g: &Geometry, h: usize, k: usize) -> usize {
    (g.vertical_view_count() - 1 - k) * g.views.count + h
}

/// The view `(h, k)` that camera `index` shows (the inverse of [`camera_of_view`]).
pub fn view_of_camera(g: &Geometry, index: usize) -> (usize, usize) {
    let (row, column) = (index / g.views.count, index % g.views.count);
    (column, g.vertical_view_count() - 1 - row)
}

/// One camera of the manifest.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct HciCamera {
    /// Its picture, `input_CamNNN.png`.
    pub name: String,
    /// The view it shows: horizontal, vertical.
    pub view: [usize; 2],
}

/// The manifest: the geometry, the tone mapping, which view each camera
/// shows, and every file of the set (the pictures and `parameters.cfg`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct HciManifest {
    /// The frame's geometry.
    pub geometry: Geometry,
    /// The tone mapping of the pictures (8 bits).
    pub tone: ToneMapping,
    /// Every camera, in index order.
    pub cameras: Vec<HciCamera>,
    /// Every file with its size and SHA-256.
    #[serde(default)]
    pub files: Vec<SetFile>,
}

/// The numbers of `parameters.cfg`, in the benchmark's units (its keys, with
/// the unit each names).
#[derive(Clone, Debug, PartialEq)]
pub struct HciParameters {
    /// `focal_length_mm`.
    pub focal_length_mm: f64,
    /// `image_resolution_x_px`: emitters.
    pub image_resolution_x_px: usize,
    /// `image_resolution_y_px`: emitter rows.
    pub image_resolution_y_px: usize,
    /// `sensor_size_mm`: of the picture's larger side.
    pub sensor_size_mm: f64,
    /// `fstop`.
    pub fstop: f64,
    /// `num_cams_x`: horizontal views.
    pub num_cams_x: usize,
    /// `num_cams_y`: vertical views.
    pub num_cams_y: usize,
    /// `baseline_mm`: between neighbouring cameras.
    pub baseline_mm: f64,
    /// `focus_distance_m`: from the cameras to the emitter plane.
    pub focus_distance_m: f64,
    /// `center_cam_{x,y,z}_m`: the grid's centre, display metres.
    pub center_cam_m: [f64; 3],
    /// `center_cam_{rx,ry,rz}_rad`: Blender Euler XYZ angles (0: looking along `−z`).
    pub center_cam_rad: [f64; 3],
    /// `disp_min`, `disp_max`: pixels between neighbouring cameras.
    pub disparity_px: [f64; 2],
    /// `scene`: the file's name.
    pub scene: String,
    /// `date`: of the export, `YYYY-MM-DD` (UTC).
    pub date: String,
}

impl HciParameters {
    /// The parameters of `g`'s views as an HCI grid (see the module's
    /// text), and what they cannot say of it. `g` must be full parallax
    /// with two or more views along one axis.
    pub fn of_geometry(g: &Geometry, scene: &str, date: &str) -> (HciParameters, Vec<String>) {
        let vertical = g.vertical_views.clone().unwrap_or_else(|| g.views.clone());
        let (v, w) = (g.views.count, vertical.count);
        let s = g.viewer_distance_m - g.emitter_z_m;
        // Where each camera sits on the viewer's plane, from the emitter grid's centre.
        let centre = [
            0.5 * (g.emitter_x_m(0) + g.emitter_x_m(g.emitters - 1)),
            0.5 * (g.hololine_y_m(0) + g.hololine_y_m(g.hololines - 1)),
        ];
        let xs: Vec<f64> = (0..v).map(|h| s * g.views.theta_rad(h).tan()).collect();
        let ys: Vec<f64> = (0..w).map(|k| s * vertical.theta_rad(k).tan()).collect();
        let step = |p: &[f64]| (p.len() > 1).then(|| (p[p.len() - 1] - p[0]) / (p.len() - 1) as f64);
        let (bx, by) = (step(&xs), step(&ys));
        let baseline = bx.or(by).unwrap_or(0.0);
        let middle = |p: &[f64]| 0.5 * (p[0] + p[p.len() - 1]);
        let mut warnings = Vec::new();
        if let (Some(bx), Some(by)) = (bx, by) {
            if (bx - by).abs() > TOLERANCE * bx.abs() {
                warnings.push(format!(
                    "the horizontal views are {} mm apart at the viewer and the vertical {} mm; the benchmark's \
                     cameras have one baseline, and {PARAMETERS} gives the horizontal",
                    mm(bx),
                    mm(by)
                ));
            }
        }
        // The worst distance of a camera from its place on an even grid, in baselines.
        let off_grid = |p: &[f64], b: Option<f64>| {
            let Some(b) = b else { return 0.0 };
            let mid = middle(p);
            let n = p.len() as f64;
            p.iter()
                .enumerate()
                .map(|(i, x)| (x - mid - (i as f64 - (n - 1.0) / 2.0) * b).abs() / b)
                .fold(0.0, f64::max)
        };
        let worst = off_grid(&xs, bx).max(off_grid(&ys, by));
        if worst > TOLERANCE {
            warnings.push(format!(
                "the views are not evenly spaced in tan: the cameras of {PARAMETERS}'s even grid are up to {:.0} % of \
                 a baseline from where the views point",
                100.0 * worst
            ));
        }
        let grid_centre = [centre[0] + middle(&xs), centre[1] + middle(&ys)];
        let off_axis = (grid_centre[0] - centre[0]).hypot(grid_centre[1] - centre[1]);
        if off_axis > TOLERANCE * baseline {
            warnings.push(format!(
                "the views are not centred on the display's normal: the middle of the grid is {} mm from the line \
                 through the emitters' centre, and the benchmark's cameras converge on the point in front of the \
                 grid's middle, where the pictures are centred on the emitters'",
                mm(off_axis)
            ));
        }
        if (g.hololine_pitch_m - g.emitter_pitch_m).abs() > TOLERANCE * g.emitter_pitch_m {
            warnings.push(format!(
                "a picture's pixel is {} mm wide and {} mm tall (an emitter's pitch and a row's); the benchmark's \
                 pixels are square, and {PARAMETERS} takes the emitter pitch",
                mm(g.emitter_pitch_m),
                mm(g.hololine_pitch_m)
            ));
        }
        if v != w {
            warnings.push(format!(
                "the grid is {v} × {w} cameras; the benchmark's own scenes are square, and its python-tools' \
                 read_lightfield places pictures as if they were (it takes the column modulo num_cams_y)"
            ));
        }
        let parameters = HciParameters {
            focal_length_mm: s * 1e3,
            image_resolution_x_px: g.emitters,
            image_resolution_y_px: g.hololines,
            sensor_size_mm: g.emitters.max(g.hololines) as f64 * g.emitter_pitch_m * 1e3,
            fstop: 100.0,
            num_cams_x: v,
            num_cams_y: w,
            baseline_mm: baseline * 1e3,
            focus_distance_m: s,
            center_cam_m: [grid_centre[0], grid_centre[1], g.viewer_distance_m],
            center_cam_rad: [0.0; 3],
            disparity_px: [-1.0, 1.0],
            scene: scene.to_string(),
            date: date.to_string(),
        };
        (parameters, warnings)
    }

    /// The text of `parameters.cfg`.
    pub fn to_cfg(&self) -> String {
        let [x, y, z] = self.center_cam_m.map(decimal);
        let [rx, ry, rz] = self.center_cam_rad.map(decimal);
        let [disp_min, disp_max] = self.disparity_px.map(decimal);
        format!(
            "[intrinsics]\nfocal_length_mm = {}\nimage_resolution_x_px = {}\nimage_resolution_y_px = {}\n\
             sensor_size_mm = {}\nfstop = {}\n\n\
             [extrinsics]\nnum_cams_x = {}\nnum_cams_y = {}\nbaseline_mm = {}\nfocus_distance_m = {}\n\
             center_cam_x_m = {x}\ncenter_cam_y_m = {y}\ncenter_cam_z_m = {z}\n\
             center_cam_rx_rad = {rx}\ncenter_cam_ry_rad = {ry}\ncenter_cam_rz_rad = {rz}\n\n\
             [meta]\nscene = {}\ncategory = holo\ndate = {}\nversion = holo {}\nauthors = holo export-hci\n\
             contact = \ndisp_min = {disp_min}\ndisp_max = {disp_max}\nfrustum_disp_min = {disp_min}\n\
             frustum_disp_max = {disp_max}\ndepth_map_scale = 1.0\n",
            decimal(self.focal_length_mm),
            self.image_resolution_x_px,
            self.image_resolution_y_px,
            decimal(self.sensor_size_mm),
            decimal(self.fstop),
            self.num_cams_x,
            self.num_cams_y,
            decimal(self.baseline_mm),
            decimal(self.focus_distance_m),
            self.scene,
            self.date,
            env!("CARGO_PKG_VERSION"),
        )
    }
}

/// A number as the benchmark's files write one: the shortest decimal that
/// reads back as it, with a decimal point (`100.0`, `0.49`).
fn decimal(x: f64) -> String {
    let text = format!("{x}");
    if text.contains('.') {
        text
    } else {
        text + ".0"
    }
}

/// A length in metres as millimetres for a message.
fn mm(length_m: f64) -> String {
    crate::geometry::millimetres_text(length_m)
}

/// A file name as a `[meta] scene` value: letters, digits, `-`, `_` and
/// `.` kept, anything else (which an INI reader could take as syntax or
/// interpolation) `_`.
fn scene_name(path: &Path) -> String {
    let stem = path.file_stem().map_or_else(|| "holo".into(), |s| s.to_string_lossy().into_owned());
    stem.chars().map(|c| if c.is_ascii_alphanumeric() || "-_.".contains(c) { c } else { '_' }).collect()
}

/// Today's date, UTC, `YYYY-MM-DD`.
fn utc_date(now: SystemTime) -> String {
    let days = now.duration_since(UNIX_EPOCH).map_or(0, |d| d.as_secs() / 86_400) as i64;
    // Days since 1970-01-01 to the civil date (proleptic Gregorian), by
    // 400-year eras of 146 097 days counted from 0000-03-01.
    let z = days + 719_468;
    let era = z.div_euclid(146_097);
    let day_of_era = z.rem_euclid(146_097);
    let year_of_era = (day_of_era - day_of_era / 1460 + day_of_era / 36_524 - day_of_era / 146_096) / 365;
    let day_of_year = day_of_era - (365 * year_of_era + year_of_era / 4 - year_of_era / 100);
    let month_from_march = (5 * day_of_year + 2) / 153;
    let day = day_of_year - (153 * month_from_march + 2) / 5 + 1;
    let month = if month_from_march < 10 { month_from_march + 3 } else { month_from_march - 9 };
    let year = year_of_era + era * 400 + i64::from(month <= 2);
    format!("{year:04}-{month:02}-{day:02}")
}

/// What [`export_hci_file`] wrote.
#[derive(Clone, Debug, PartialEq)]
pub struct HciExport {
    /// Every file written, the manifest last.
    pub written: Vec<PathBuf>,
    /// The tone mapping, its white level resolved to the number used.
    pub tone: ToneMapping,
    /// What `parameters.cfg` says.
    pub parameters: HciParameters,
    /// What it cannot say of the file's views.
    pub warnings: Vec<String>,
}

/// Write frame `frame` of the full-parallax `.holo` file `holo_path` as an
/// HCI benchmark folder `dir` (`holo export-hci`): a picture per view, read
/// one view at a time (each view's digest checked), white level `white`
/// chosen among every sample of the frame. The file, the frame and the
/// output are checked before any work; nothing is in place until every
/// file is complete.
pub fn export_hci_file(holo_path: &Path, frame: usize, dir: &Path, white: White, overwrite: bool) -> Result<HciExport> {
    let file = HoloFile::open(holo_path)?;
    let g = file.geometry();
    let Some(vertical) = &g.vertical_views else {
        return Err(Error::unsupported(
            holo_path,
            format!(
                "is horizontal parallax ({} views in a row); an HCI light field is a 2-D grid of views \
                 (`holo export-views` writes the row)",
                g.views.count
            ),
        ));
    };
    if g.views.count < 2 && vertical.count < 2 {
        return Err(Error::unsupported(
            holo_path,
            "has one view; an HCI light field needs two or more along an axis for its baseline",
        ));
    }
    check_frame_and_white(&file, holo_path, frame, white, dir)?;
    let count = g.views_per_emitter();
    let names: Vec<String> = (0..count).map(|i| camera_file_name(i, count)).collect();
    let mut set_names = names.clone();
    set_names.push(PARAMETERS.to_string());
    let _claim = check_set_output(dir, MANIFEST, &set_names, &[holo_path], overwrite)?;
    let (parameters, warnings) = HciParameters::of_geometry(g, &scene_name(holo_path), &utc_date(SystemTime::now()));
    let tone = ToneMapping { white: white_of_frame(&file, frame, white)?, bits: 8 };
    let png_tone = Tone::new(tone.white, Bits::Eight).map_err(|e| e.naming(dir))?;
    let channels = PictureChannels::new(g);
    let mut set = FileSet::create(dir, MANIFEST)?;
    let mut cameras = Vec::with_capacity(count);
    for (index, name) in names.iter().enumerate() {
        let (h, k) = view_of_camera(g, index);
        let view = file.read_view(frame, h, k)?;
        // The benchmark reads RGB pictures: a one-wavelength file's are grey in all three.
        let pixel_size = Some([g.emitter_pitch_m, g.hololine_pitch_m]);
        let png = encode_png(g.emitters, g.hololines, Colour::Rgb, &png_tone, pixel_size, |e, j| {
            channels.pixel(|c| view.get(c, j, e, 0))
        })
        .map_err(|e| e.naming(&dir.join(name)))?;
        set.add_bytes(name, &png)?;
        cameras.push(HciCamera { name: name.clone(), view: [h, k] });
    }
    set.add_bytes(PARAMETERS, parameters.to_cfg().as_bytes())?;
    let written = set.commit(overwrite, |files| {
        let manifest =
            HciManifest { geometry: g.clone(), tone: tone.clone(), cameras: cameras.clone(), files: files.to_vec() };
        serde_json::to_string_pretty(&manifest)
            .map(String::into_bytes)
            .map_err(|e| Error::encode(dir.join(MANIFEST), "JSON", e))
    })?;
    Ok(HciExport { written, tone, parameters, warnings })
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::time::Duration;

    #[test]
    fn dates_are_the_civil_calendar_s() {
        let at = |days: u64| utc_date(UNIX_EPOCH + Duration::from_secs(days * 86_400 + 3_600));
        assert_eq!(at(0), "1970-01-01");
        assert_eq!(at(59), "1970-03-01");
        // 2000-02-29 (a leap day of a century year), 2024-12-31, 2100-03-01 (2100 is no leap year).
        assert_eq!(at(11_016), "2000-02-29");
        assert_eq!(at(20_088), "2024-12-31");
        assert_eq!(at(47_541), "2100-03-01");
    }

    #[test]
    fn scene_names_keep_what_an_ini_reader_takes_as_text() {
        assert_eq!(scene_name(Path::new("dir/spot-2.holo")), "spot-2");
        assert_eq!(scene_name(Path::new("100% [a]=b.holo")), "100___a__b");
    }
}
