//! The rig file (spec/rig.md): a capture's cameras written by hand or by a
//! script, as TOML or JSON (chosen by the extension), either camera by
//! camera (`[[cameras]]`) or as a rail or grid of parallel cameras. Every
//! error names the rig file and, where one is concerned, the camera by its
//! index and image.

use std::path::{Path, PathBuf};

use toml::{Table, Value};

use super::array::ArrayFrame;
use super::image::image_size;
use super::{look_rotation, Camera, DepthKind, DepthSource, ImageSource, Intrinsics, Pose, Rig};
use crate::error::{Error, Result};
use crate::math;

const TOP_KEYS: &[&str] = &["units", "focus_distance", "linear", "image_size", "cameras", "rail", "grid"];
const LENS_KEYS: &[&str] = &[
    "focal_length_mm",
    "sensor_width_mm",
    "sensor_height_mm",
    "focal_length_px",
    "horizontal_fov_deg",
    "k",
    "principal_point_px",
];
const CAMERA_KEYS: &[&str] =
    &["image", "name", "image_size", "position", "rotation", "look_at", "direction", "up", "r", "t", "depth"];
const ARRAY_KEYS: &[&str] = &["images", "centre", "direction", "up", "converge", "start", "depth"];
const RAIL_KEYS: &[&str] = &["count", "baseline", "axis"];
const GRID_KEYS: &[&str] = &["columns", "rows", "baseline_x", "baseline_y"];
const DEPTH_KEYS: &[&str] = &["file", "kind", "scale", "numerator", "offset"];

/// Read a rig file (`.toml` or `.json`). Image paths are relative to the
/// file's folder; each image's header is read for its size (and to find
/// missing files now rather than when resampling).
pub fn read_rig_file(path: &Path) -> Result<Rig> {
    let text = std::fs::read_to_string(path).map_err(|e| Error::io(path, e))?;
    let extension = path.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase);
    let table: Table = match extension.as_deref() {
        Some("toml") => {
            toml::from_str(&text).map_err(|e| Error::rig(path, format!("not a valid TOML rig file: {e}")))?
        }
        Some("json") => serde_json::from_str(&text).map_err(|e| {
            Error::rig(path, format!("not a valid JSON rig file (an object of the keys in spec/rig.md): {e}"))
        })?,
        _ => return Err(Error::rig(path, "a rig file's name must end in .toml or .json")),
    };
    let rig = parse(path, table).map_err(|problem| Error::rig(path, problem))?;
    rig.check()?;
    Ok(rig)
}

fn parse(path: &Path, table: Table) -> Result<Rig, String> {
    let dir = path.parent().unwrap_or(Path::new("."));
    let top = Keys::new(&table, "");
    top.only(&[TOP_KEYS, LENS_KEYS])?;
    let metres_per_unit = units(top.string("units")?.unwrap_or("m"))?;
    let focus = top.positive("focus_distance")?;
    let linear = top.boolean("linear")?.unwrap_or(false);
    let size = top.size("image_size")?;
    let lens = Lens::read(&top)?;
    let settings = Settings { dir, lens, size, focus };
    let cameras = match (table.get("cameras"), table.get("rail"), table.get("grid")) {
        (Some(c), None, None) => explicit(&settings, c)?,
        (None, Some(r), None) => array(&settings, r, Shape::Rail)?,
        (None, None, Some(g)) => array(&settings, g, Shape::Grid)?,
        (None, None, None) => return Err("the rig has no cameras: give [[cameras]], [rail] or [grid]".into()),
        _ => return Err("give only one of [[cameras]], [rail] and [grid]".into()),
    };
    let rig = Rig { source: path.display().to_string(), cameras, metres_per_unit, focus_distance: focus, linear };
    for (i, c) in rig.cameras.iter().enumerate() {
        if let Some(p) = c.problem_detail() {
            return Err(format!("camera {i} ({}): {p}", c.name));
        }
    }
    if let Some((a, b)) = rig.coincident_cameras() {
        let p = rig.cameras[a].pose.centre;
        return Err(format!(
            "cameras {a} ({}) and {b} ({}) are at the same position ({}, {}, {}): a copied pose? \
             (to use one viewpoint photographed twice, keep one of them)",
            rig.cameras[a].name, rig.cameras[b].name, p[0], p[1], p[2]
        ));
    }
    Ok(rig)
}

/// Metres per unit of a `units` name.
fn units(name: &str) -> Result<f64, String> {
    Ok(match name {
        "m" => 1.0,
        "cm" => 0.01,
        "mm" => 0.001,
        "in" => 0.0254,
        other => {
            return Err(format!("unknown units \"{}\": use \"m\", \"cm\", \"mm\" or \"in\"", other.escape_debug()))
        }
    })
}

/// What every camera of the file shares.
struct Settings<'a> {
    dir: &'a Path,
    lens: Lens,
    size: Option<(usize, usize)>,
    focus: Option<f64>,
}

/// A path as written in the rig file, relative to its folder; Windows
/// separators are accepted everywhere.
fn resolve(dir: &Path, written: &str) -> PathBuf {
    let written = if cfg!(windows) { written.to_string() } else { written.replace('\\', "/") };
    let p = Path::new(&written);
    if p.is_absolute() {
        p.to_path_buf()
    } else {
        dir.join(p)
    }
}

/// The image's size from its header, checked against a declared size.
fn dimensions(file: &Path, declared: Option<(usize, usize)>, who: &str) -> Result<(usize, usize), String> {
    let (w, h) = image_size(file).map_err(|e| format!("{who}: {e}"))?;
    match declared {
        Some((dw, dh)) if (dw, dh) != (w, h) => {
            Err(format!("{who}: {} is {w}×{h}, the rig says {dw}×{dh}", file.display()))
        }
        _ => Ok((w, h)),
    }
}

fn explicit(s: &Settings, value: &Value) -> Result<Vec<Camera>, String> {
    let Value::Array(list) = value else {
        return Err("`cameras` must be a list of tables ([[cameras]] in TOML, an array of objects in JSON)".into());
    };
    let mut cameras = Vec::with_capacity(list.len());
    for (i, entry) in list.iter().enumerate() {
        let Value::Table(table) = entry else { return Err(format!("camera {i}: must be a table")) };
        let Some(image) = table.get("image").and_then(Value::as_str) else {
            return Err(format!("camera {i}: `image` (the picture's path, text) is missing"));
        };
        let name = match table.get("name") {
            Some(Value::String(n)) => n.clone(),
            Some(_) => return Err(format!("camera {i} ({image}): `name` must be text")),
            None => image.to_string(),
        };
        let who = format!("camera {i} ({name})");
        let keys = Keys::new(table, &who);
        keys.only(&[CAMERA_KEYS, LENS_KEYS])?;
        let file = resolve(s.dir, image);
        let size = dimensions(&file, keys.size("image_size")?.or(s.size), &who)?;
        let (fx, fy, principal) = Lens::read(&keys)?.resolve(&s.lens, size).map_err(|e| keys.err(e))?;
        let (cx, cy) = principal.unwrap_or(((size.0 as f64 - 1.0) / 2.0, (size.1 as f64 - 1.0) / 2.0));
        let pose = pose(&keys)?;
        let depth = depth(&keys, s.dir, &[], None)?;
        cameras.push(Camera {
            name,
            image: ImageSource::File(file),
            width: size.0,
            height: size.1,
            intrinsics: Intrinsics { fx, fy, cx, cy },
            pose,
            depth,
        });
    }
    Ok(cameras)
}

fn pose(k: &Keys) -> Result<Pose, String> {
    let position = k.numbers::<3>("position")?;
    let rotation = k.matrix("rotation")?;
    let look_at = k.numbers::<3>("look_at")?;
    let direction = k.numbers::<3>("direction")?;
    let up = k.numbers::<3>("up")?;
    match (k.matrix("r")?, k.numbers::<3>("t")?) {
        (Some(r), Some(t)) => {
            if position.is_some() || rotation.is_some() || look_at.is_some() || direction.is_some() || up.is_some() {
                return Err(k.err("`r` and `t` give the pose: leave out position, rotation, look_at, direction and up"));
            }
            // x_c = r X + t, so the centre is −rᵀ t.
            Ok(Pose { rotation: r, centre: math::scale(math::mat3_transpose_apply(&r, t), -1.0) })
        }
        (Some(_), None) | (None, Some(_)) => Err(k.err("`r` and `t` go together (x_camera = r·X + t)")),
        (None, None) => {
            let Some(position) = position else {
                return Err(k.err("`position` is missing (or give `r` and `t`)"));
            };
            let forward = match (rotation, look_at, direction) {
                (Some(r), None, None) => {
                    if up.is_some() {
                        return Err(k.err("`up` goes with look_at or direction, not with rotation"));
                    }
                    return Ok(Pose { rotation: r, centre: position });
                }
                (None, Some(target), None) => math::sub(target, position),
                (None, None, Some(d)) => d,
                _ => return Err(k.err("give exactly one of rotation, look_at and direction")),
            };
            let up = up.unwrap_or([0.0, 1.0, 0.0]);
            if math::length(forward) == 0.0 {
                return Err(k.err("the viewing direction is zero (look_at is the camera's position?)"));
            }
            let sine = math::length(math::cross(forward, up)) / (math::length(forward) * math::length(up));
            // NaN passes on to the calibration check, which names it.
            if sine <= 1e-9 {
                return Err(k.err(format!("up {up:?} is zero or parallel to the viewing direction {forward:?}")));
            }
            Ok(Pose { rotation: look_rotation(forward, math::scale(up, -1.0)), centre: position })
        }
    }
}

/// The `depth` table of a camera or array; `vars` fill a file pattern;
/// `disparity` is the array's `(b·f, b·f/F)` when it has one.
fn depth(
    k: &Keys,
    dir: &Path,
    vars: &[(&str, usize)],
    disparity: Option<(f64, f64)>,
) -> Result<Option<DepthSource>, String> {
    let Some(value) = k.table.get("depth") else { return Ok(None) };
    let Value::Table(table) = value else {
        return Err(k.err("`depth` must be a table: { file = ..., kind = \"z\" or \"disparity\", ... }"));
    };
    let who = if k.who.is_empty() { "depth".to_string() } else { format!("{}: depth", k.who) };
    let d = Keys::new(table, &who);
    d.only(&[DEPTH_KEYS])?;
    let Some(pattern) = d.string("file")? else { return Err(d.err("`file` (the PFM map's path) is missing")) };
    let file = resolve(dir, &expand(pattern, vars).map_err(|e| d.err(e))?);
    let kind = match d.string("kind")?.unwrap_or("z") {
        "z" => {
            if d.table.contains_key("numerator") || d.table.contains_key("offset") {
                return Err(d.err("`numerator` and `offset` are for kind = \"disparity\""));
            }
            DepthKind::Z { scale: d.positive("scale")?.unwrap_or(1.0) }
        }
        "disparity" => {
            if d.table.contains_key("scale") {
                return Err(d.err("`scale` is for kind = \"z\"; a disparity map has `numerator` and `offset`"));
            }
            let numerator = d.positive("numerator")?.or(disparity.map(|p| p.0));
            let Some(numerator) = numerator else {
                return Err(d.err("a disparity map needs `numerator` (baseline × focal length in pixels)"));
            };
            let offset = d.number("offset")?.or(disparity.map(|p| p.1)).unwrap_or(0.0);
            DepthKind::Disparity { numerator, offset }
        }
        other => return Err(d.err(format!("unknown kind \"{}\": use \"z\" or \"disparity\"", other.escape_debug()))),
    };
    Ok(Some(DepthSource { file, kind }))
}

#[derive(Clone, Copy, PartialEq)]
enum Shape {
    Rail,
    Grid,
}

fn array(s: &Settings, value: &Value, shape: Shape) -> Result<Vec<Camera>, String> {
    let label = if shape == Shape::Rail { "rail" } else { "grid" };
    let Value::Table(table) = value else { return Err(format!("`{label}` must be a table")) };
    let k = Keys::new(table, label);
    k.only(&[ARRAY_KEYS, if shape == Shape::Rail { RAIL_KEYS } else { GRID_KEYS }])?;
    let required = |v: Option<usize>, key: &str| v.ok_or_else(|| k.err(format!("`{key}` is missing")));
    let (columns, rows) = match shape {
        Shape::Rail => (required(k.count("count")?, "count")?, 1),
        Shape::Grid => (required(k.count("columns")?, "columns")?, required(k.count("rows")?, "rows")?),
    };
    if columns == 0 || rows == 0 {
        return Err(k.err("an array needs at least one camera"));
    }
    let (bx, by) = match shape {
        Shape::Rail => (k.positive("baseline")?.ok_or_else(|| k.err("`baseline` is missing"))?, 0.0),
        Shape::Grid => {
            let bx = k.positive("baseline_x")?.ok_or_else(|| k.err("`baseline_x` is missing"))?;
            (bx, k.positive("baseline_y")?.unwrap_or(bx))
        }
    };
    let direction = k.numbers::<3>("direction")?.unwrap_or([0.0, 0.0, -1.0]);
    let up = k.numbers::<3>("up")?.unwrap_or([0.0, 1.0, 0.0]);
    let converge = k.boolean("converge")?.unwrap_or(s.focus.is_some());
    let converge = match (converge, s.focus) {
        (true, None) => return Err(k.err("`converge` needs the rig's focus_distance")),
        (true, Some(f)) => Some(f),
        (false, _) => None,
    };
    // By default the plane in focus passes through the world's origin, where
    // the display's hologram plane is.
    let centre = match (k.numbers::<3>("centre")?, s.focus) {
        (Some(c), _) => c,
        (None, Some(f)) if math::length(direction) > 0.0 => math::scale(direction, -f / math::length(direction)),
        (None, _) => [0.0; 3],
    };
    let frame = ArrayFrame::new(centre, direction, up).map_err(|e| k.err(e))?;
    let axis = match k.numbers::<3>("axis")? {
        Some(a) if math::length(a) > 0.0 && math::length(a).is_finite() => math::scale(a, 1.0 / math::length(a)),
        Some(a) => return Err(k.err(format!("the rail's axis {a:?} must be a non-zero direction"))),
        None => frame.right(),
    };
    let start = k.count("start")?.unwrap_or(0);
    let count = columns * rows;
    let names = images(&k, shape, columns, rows, start)?;
    let mut cameras = Vec::with_capacity(count);
    let mut size: Option<((usize, usize), usize)> = None;
    for (n, name) in names.into_iter().enumerate() {
        let (row, col) = (n / columns, n % columns);
        let who = format!("camera {n} ({name})");
        let file = resolve(s.dir, &name);
        let this = dimensions(&file, s.size, &who)?;
        match size {
            None => size = Some((this, n)),
            Some((first, m)) if first != this => {
                return Err(format!(
                    "{who}: {} is {}×{}, camera {m} is {}×{}; an array's pictures must all be one size (or give image_size)",
                    file.display(),
                    this.0,
                    this.1,
                    first.0,
                    first.1
                ))
            }
            Some(_) => {}
        }
        let (fx, fy, principal) = Lens::default().resolve(&s.lens, this).map_err(|e| format!("{who}: {e}"))?;
        let offset = match shape {
            Shape::Rail => math::scale(axis, (col as f64 - (columns as f64 - 1.0) / 2.0) * bx),
            Shape::Grid => math::add(
                math::scale(frame.right(), (col as f64 - (columns as f64 - 1.0) / 2.0) * bx),
                math::scale(frame.down(), (row as f64 - (rows as f64 - 1.0) / 2.0) * by),
            ),
        };
        let mut camera =
            frame.camera(name, ImageSource::File(file), this, (fx, fy), offset, converge).map_err(|e| k.err(e))?;
        // A given principal point is where the point of convergence is
        // pictured; the shift for convergence is added to it.
        if let Some((cx, cy)) = principal {
            camera.intrinsics.cx += cx - (this.0 as f64 - 1.0) / 2.0;
            camera.intrinsics.cy += cy - (this.1 as f64 - 1.0) / 2.0;
        }
        // Neighbours along a row are bx apart: disparity d = b·f/z − b·f/F.
        let disparity = Some((bx * fx, converge.map_or(0.0, |f| bx * fx / f)));
        let vars = [("i", start + n), ("row", start + row), ("col", start + col)];
        camera.depth = depth(&k, s.dir, &vars, disparity)?;
        cameras.push(camera);
    }
    Ok(cameras)
}

/// The image names of an array, row by row: a list, or a pattern with
/// `{i}` (and `{row}`, `{col}` for grids).
fn images(k: &Keys, shape: Shape, columns: usize, rows: usize, start: usize) -> Result<Vec<String>, String> {
    let count = columns * rows;
    match k.table.get("images") {
        Some(Value::String(pattern)) => {
            if count > 1 && !pattern.contains('{') {
                return Err(k.err(format!(
                    "the image pattern \"{pattern}\" has no {{i}}: every camera would get the same picture"
                )));
            }
            (0..count)
                .map(|n| {
                    let mut vars = vec![("i", start + n)];
                    if shape == Shape::Grid {
                        vars.extend([("row", start + n / columns), ("col", start + n % columns)]);
                    }
                    expand(pattern, &vars).map_err(|e| k.err(e))
                })
                .collect()
        }
        Some(Value::Array(list)) => {
            if list.len() != count {
                return Err(k.err(format!("`images` lists {} pictures for {count} cameras", list.len())));
            }
            list.iter()
                .map(|v| v.as_str().map(str::to_string).ok_or_else(|| k.err("`images` must list paths (text)")))
                .collect()
        }
        Some(_) => Err(k.err("`images` must be a pattern such as \"view_{i}.png\" or a list of paths")),
        None => Err(k.err("`images` is missing")),
    }
}

/// Fill `{name}` or `{name:0N}` (zero-padded to N digits) placeholders.
fn expand(pattern: &str, vars: &[(&str, usize)]) -> Result<String, String> {
    let mut out = String::new();
    let mut rest = pattern;
    while let Some(open) = rest.find('{') {
        out.push_str(&rest[..open]);
        let Some(close) = rest[open..].find('}') else {
            return Err(format!("\"{pattern}\" has a {{ without its }}"));
        };
        let inside = &rest[open + 1..open + close];
        let (name, width) = match inside.split_once(':') {
            Some((name, spec)) => match spec.strip_prefix('0').unwrap_or(spec).parse::<usize>() {
                Ok(w) if w <= 16 => (name, w),
                _ => return Err(format!("\"{pattern}\": {{{inside}}}: write the width as {{{name}:03}}")),
            },
            None => (inside, 0),
        };
        let Some(&(_, value)) = vars.iter().find(|(n, _)| *n == name) else {
            if vars.is_empty() {
                return Err(format!("\"{pattern}\": placeholders such as {{i}} are for rails and grids"));
            }
            let known: Vec<String> = vars.iter().map(|(n, _)| format!("{{{n}}}")).collect();
            return Err(format!("\"{pattern}\": unknown placeholder {{{inside}}} (use {})", known.join(", ")));
        };
        out.push_str(&format!("{value:0width$}"));
        rest = &rest[open + close + 1..];
    }
    out.push_str(rest);
    Ok(out)
}

/// `(fx, fy, principal point)` in pixels; no principal point means the
/// picture's centre.
type Pixels = (f64, f64, Option<(f64, f64)>);

/// Focal length and principal point as a table gives them.
#[derive(Clone, Default)]
struct Lens {
    focal_mm: Option<f64>,
    sensor_width_mm: Option<f64>,
    sensor_height_mm: Option<f64>,
    focal_px: Option<[f64; 2]>,
    fov_deg: Option<f64>,
    k: Option<[[f64; 3]; 3]>,
    principal: Option<[f64; 2]>,
}

impl Lens {
    fn read(k: &Keys) -> Result<Lens, String> {
        let focal_px = match k.table.get("focal_length_px") {
            None => None,
            Some(Value::Array(_)) => k.numbers::<2>("focal_length_px")?,
            Some(_) => k.positive("focal_length_px")?.map(|f| [f, f]),
        };
        Ok(Lens {
            focal_mm: k.positive("focal_length_mm")?,
            sensor_width_mm: k.positive("sensor_width_mm")?,
            sensor_height_mm: k.positive("sensor_height_mm")?,
            focal_px,
            fov_deg: k.number("horizontal_fov_deg")?,
            k: k.matrix("k")?,
            principal: k.numbers::<2>("principal_point_px")?,
        })
    }

    fn focal_choices(&self) -> Vec<&'static str> {
        let mut c = Vec::new();
        for (given, name) in [
            (self.focal_mm.is_some(), "focal_length_mm"),
            (self.focal_px.is_some(), "focal_length_px"),
            (self.fov_deg.is_some(), "horizontal_fov_deg"),
            (self.k.is_some(), "k"),
        ] {
            if given {
                c.push(name);
            }
        }
        c
    }

    /// `(fx, fy, principal point)` for a picture of `size`: this table's
    /// focal length if it gives one, else `defaults`'; the principal point
    /// is `None` when the picture's centre is meant.
    fn resolve(&self, defaults: &Lens, (w, h): (usize, usize)) -> Result<Pixels, String> {
        let source = if self.focal_choices().is_empty() { defaults } else { self };
        let choices = source.focal_choices();
        if choices.len() > 1 {
            return Err(format!("give one focal length, not {}", choices.join(" and ")));
        }
        if source.k.is_some() && source.principal.is_some() {
            return Err("`k` holds the principal point: leave out principal_point_px".into());
        }
        let (w, h) = (w as f64, h as f64);
        let mut principal = None;
        let (fx, fy) = match choices.first() {
            None => {
                return Err("no focal length: give focal_length_mm with sensor_width_mm, focal_length_px, \
                            horizontal_fov_deg or k (for the camera or at the top of the file)"
                    .into())
            }
            Some(&"focal_length_mm") => {
                let f = source.focal_mm.unwrap_or_default();
                let Some(sw) = self.sensor_width_mm.or(defaults.sensor_width_mm) else {
                    return Err("focal_length_mm needs sensor_width_mm".into());
                };
                let fx = f / sw * w;
                (fx, self.sensor_height_mm.or(defaults.sensor_height_mm).map_or(fx, |sh| f / sh * h))
            }
            Some(&"focal_length_px") => source.focal_px.map_or((0.0, 0.0), |f| (f[0], f[1])),
            Some(&"horizontal_fov_deg") => {
                let fov = source.fov_deg.unwrap_or_default();
                if !(fov > 0.0 && fov < 180.0) {
                    return Err(format!("horizontal_fov_deg must be between 0 and 180 (got {fov})"));
                }
                // The picture spans w pixel widths, edge to edge.
                let fx = w / 2.0 / (fov.to_radians() / 2.0).tan();
                (fx, fx)
            }
            Some(_) => {
                let k = source.k.unwrap_or_default();
                if k[1][0] != 0.0 || k[2][0] != 0.0 || k[2][1] != 0.0 || k[2][2] == 0.0 {
                    return Err(
                        "`k` must be upper triangular with k33 ≠ 0 ([[fx, 0, cx], [0, fy, cy], [0, 0, 1]])".into()
                    );
                }
                let k = k.map(|row| row.map(|x| x / k[2][2]));
                if k[0][1].abs() > 1e-6 * k[0][0].abs() {
                    return Err(format!("`k` has skew {}: skewed pixels are not supported", k[0][1]));
                }
                principal = Some((k[0][2], k[1][2]));
                (k[0][0], k[1][1])
            }
        };
        // The camera's own principal point wins over the defaults' (and k's).
        let principal = self.principal.map(|p| (p[0], p[1])).or(principal).or(defaults.principal.map(|p| (p[0], p[1])));
        Ok((fx, fy, principal))
    }
}

/// A table's values, with errors naming `who` (a camera, "rail", ...) and
/// the key.
struct Keys<'a> {
    table: &'a Table,
    who: String,
}

impl<'a> Keys<'a> {
    fn new(table: &'a Table, who: &str) -> Keys<'a> {
        Keys { table, who: who.to_string() }
    }

    fn err(&self, problem: impl std::fmt::Display) -> String {
        if self.who.is_empty() {
            problem.to_string()
        } else {
            format!("{}: {problem}", self.who)
        }
    }

    fn only(&self, allowed: &[&[&str]]) -> Result<(), String> {
        for key in self.table.keys() {
            if !allowed.iter().any(|list| list.contains(&key.as_str())) {
                let known: Vec<&str> = allowed.iter().flat_map(|l| l.iter().copied()).collect();
                return Err(self.err(format!("unknown key `{key}` (known here: {})", known.join(", "))));
            }
        }
        Ok(())
    }

    fn number(&self, key: &str) -> Result<Option<f64>, String> {
        match self.table.get(key) {
            None => Ok(None),
            Some(v) => number(v).map(Some).ok_or_else(|| self.err(format!("`{key}` must be a number"))),
        }
    }

    fn positive(&self, key: &str) -> Result<Option<f64>, String> {
        match self.number(key)? {
            Some(x) if !(x > 0.0 && x.is_finite()) => {
                Err(self.err(format!("`{key}` must be a positive number (got {x})")))
            }
            x => Ok(x),
        }
    }

    fn count(&self, key: &str) -> Result<Option<usize>, String> {
        match self.table.get(key) {
            None => Ok(None),
            Some(Value::Integer(n)) if *n >= 0 => Ok(Some(*n as usize)),
            Some(_) => Err(self.err(format!("`{key}` must be a whole number, 0 or more"))),
        }
    }

    fn boolean(&self, key: &str) -> Result<Option<bool>, String> {
        match self.table.get(key) {
            None => Ok(None),
            Some(Value::Boolean(b)) => Ok(Some(*b)),
            Some(_) => Err(self.err(format!("`{key}` must be true or false"))),
        }
    }

    fn string(&self, key: &str) -> Result<Option<&'a str>, String> {
        match self.table.get(key) {
            None => Ok(None),
            Some(Value::String(s)) => Ok(Some(s.as_str())),
            Some(_) => Err(self.err(format!("`{key}` must be text"))),
        }
    }

    fn numbers<const N: usize>(&self, key: &str) -> Result<Option<[f64; N]>, String> {
        let Some(v) = self.table.get(key) else { return Ok(None) };
        numbers::<N>(v).map(Some).ok_or_else(|| self.err(format!("`{key}` must be a list of {N} numbers")))
    }

    fn matrix(&self, key: &str) -> Result<Option<[[f64; 3]; 3]>, String> {
        let Some(Value::Array(rows)) = self.table.get(key) else {
            return match self.table.get(key) {
                None => Ok(None),
                Some(_) => Err(self.err(format!("`{key}` must be 3 rows of 3 numbers"))),
            };
        };
        let rows: Option<Vec<[f64; 3]>> = rows.iter().map(numbers::<3>).collect();
        match rows {
            Some(r) if r.len() == 3 => Ok(Some([r[0], r[1], r[2]])),
            _ => Err(self.err(format!("`{key}` must be 3 rows of 3 numbers"))),
        }
    }

    fn size(&self, key: &str) -> Result<Option<(usize, usize)>, String> {
        match self.table.get(key) {
            None => Ok(None),
            Some(Value::Array(a)) => match a.as_slice() {
                [Value::Integer(w), Value::Integer(h)] if *w > 0 && *h > 0 => Ok(Some((*w as usize, *h as usize))),
                _ => Err(self.err(format!("`{key}` must be [width, height] in pixels, both positive"))),
            },
            Some(_) => Err(self.err(format!("`{key}` must be [width, height] in pixels, both positive"))),
        }
    }
}

fn number(v: &Value) -> Option<f64> {
    match v {
        Value::Integer(i) => Some(*i as f64),
        Value::Float(f) => Some(*f),
        _ => None,
    }
}

fn numbers<const N: usize>(v: &Value) -> Option<[f64; N]> {
    let Value::Array(a) = v else { return None };
    if a.len() != N {
        return None;
    }
    let mut out = [0.0; N];
    for (o, v) in out.iter_mut().zip(a) {
        *o = number(v)?;
    }
    Some(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn patterns_fill_and_pad() {
        let vars = [("i", 7), ("row", 0), ("col", 7)];
        assert_eq!(expand("v_{i}.png", &vars).unwrap(), "v_7.png");
        assert_eq!(expand("r{row:02}_c{col:03}.png", &vars).unwrap(), "r00_c007.png");
        assert!(expand("v_{j}.png", &vars).unwrap_err().contains("unknown placeholder {j}"));
        assert!(expand("v_{i.png", &vars).unwrap_err().contains("without"));
        assert!(expand("v_{i}.png", &[]).unwrap_err().contains("rails and grids"));
    }

    #[test]
    fn units_are_named() {
        assert_eq!(units("mm").unwrap(), 0.001);
        assert!(units("furlong").unwrap_err().contains("unknown units \"furlong\""));
    }

    #[test]
    fn lens_choices() {
        let table: Table = toml::from_str("horizontal_fov_deg = 90.0").unwrap();
        let own = Lens::read(&Keys::new(&table, "")).unwrap();
        let (fx, fy, p) = own.resolve(&Lens::default(), (100, 50)).unwrap();
        assert!((fx - 50.0).abs() < 1e-12 && fx == fy && p.is_none());
        let table: Table = toml::from_str("focal_length_mm = 50\nsensor_width_mm = 36\nsensor_height_mm = 24").unwrap();
        let top = Lens::read(&Keys::new(&table, "")).unwrap();
        let (fx, fy, _) = Lens::default().resolve(&top, (360, 240)).unwrap();
        assert!((fx - 500.0).abs() < 1e-9 && (fy - 500.0).abs() < 1e-9);
        let table: Table = toml::from_str("k = [[100, 0, 10], [0, 90, 20], [0, 0, 1]]").unwrap();
        let k = Lens::read(&Keys::new(&table, "")).unwrap();
        assert_eq!(k.resolve(&top, (1, 1)).unwrap(), (100.0, 90.0, Some((10.0, 20.0))));
        let e = Lens::default().resolve(&Lens::default(), (1, 1)).unwrap_err();
        assert!(e.contains("no focal length"), "{e}");
    }
}
