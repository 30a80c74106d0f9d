//! Scene loaders: glTF 2.0 (`.gltf`, `.glb`), OBJ + MTL and PLY.
//!
//! [`SceneSource::open`] reads a file once (buffers, images, materials,
//! animations); [`SceneSource::scene_at`] then makes the [`Scene`] at any
//! animation time. OBJ and PLY files are not animated: every time gives the
//! same scene.
//!
//! Every error names the file and the object, material, texture or accessor
//! concerned; nothing in a file can make the loaders panic. What does not
//! stop a load (a primitive of points, degenerate triangles dropped, an
//! unknown material name, ...) is reported in [`Scene::warnings`].

mod gltf;
mod obj;
mod ply;
mod texture;

use std::path::{Path, PathBuf};

use super::{Object, Scene};
use crate::error::{Error, Result};
use crate::math::{cross, dot, length, sub};

/// Sizes the loaders refuse before allocating, so that a scene larger than
/// memory allows (or a damaged file claiming to be one) gives a clear error
/// naming the object instead of exhausting memory.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct LoadLimits {
    /// Most triangles in the whole scene (default 50 000 000).
    pub max_triangles: usize,
    /// Most texels in one texture (default 2²⁸).
    pub max_texture_texels: usize,
}

impl Default for LoadLimits {
    fn default() -> Self {
        LoadLimits { max_triangles: 50_000_000, max_texture_texels: 1 << 28 }
    }
}

/// The most bytes of a material library (MTL) read: real ones hold a few
/// kilobytes of text; a file past this is not one.
pub const MAX_MATERIAL_LIBRARY_BYTES: u64 = 256 << 20;

/// A scene file opened once; scenes at any animation time are made from it.
#[derive(Debug)]
pub struct SceneSource {
    path: PathBuf,
    inner: Inner,
    /// Every file read: the scene file, then those it refers to.
    files: Vec<PathBuf>,
}

#[derive(Debug)]
enum Inner {
    /// OBJ and PLY: one scene for all times.
    Static(Scene),
    /// glTF: geometry, materials and animations, posed on demand.
    Gltf(Box<gltf::GltfSource>),
}

/// The file extensions [`SceneSource::open`] understands.
pub const SUPPORTED_EXTENSIONS: &[&str] = &["gltf", "glb", "obj", "ply"];

impl SceneSource {
    /// Open a scene file with the default [`LoadLimits`]. The format is
    /// chosen by the extension: `.gltf`, `.glb`, `.obj` or `.ply` (any case).
    pub fn open(path: &Path) -> Result<SceneSource> {
        Self::open_with_limits(path, LoadLimits::default())
    }

    /// Open a scene file, refusing scenes beyond `limits`.
    pub fn open_with_limits(path: &Path, limits: LoadLimits) -> Result<SceneSource> {
        let ext = path.extension().and_then(|e| e.to_str()).map(|e| e.to_ascii_lowercase()).unwrap_or_default();
        let mut files = Referenced::default();
        let inner = match ext.as_str() {
            "gltf" | "glb" => Inner::Gltf(Box::new(gltf::GltfSource::open(path, &limits, &mut files)?)),
            "obj" => Inner::Static(obj::load(path, &limits, &mut files)?),
            "ply" => Inner::Static(ply::load(path, &limits, &mut files)?),
            _ => {
                return Err(Error::scene(
                    path,
                    format!(
                        "not a scene file this loader reads: the extension must be one of {}",
                        SUPPORTED_EXTENSIONS.iter().map(|e| format!(".{e}")).collect::<Vec<_>>().join(", ")
                    ),
                ))
            }
        };
        Ok(SceneSource { path: path.to_path_buf(), inner, files: files.files })
    }

    /// The file this source was opened from.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// Every file the scene was read from: the scene file and the files it
    /// refers to (material libraries, textures, glTF buffers and images).
    /// An output may be none of them.
    pub fn files(&self) -> &[PathBuf] {
        &self.files
    }

    /// Length of the animation in seconds: for glTF the largest input time
    /// of all animations; `None` when the scene is not animated.
    pub fn animation_duration_s(&self) -> Option<f64> {
        match &self.inner {
            Inner::Static(_) => None,
            Inner::Gltf(g) => g.animation_duration_s(),
        }
    }

    /// The scene at `time_s` seconds: node translations, rotations, scales
    /// and morph-target weights sampled from all animations together
    /// (times outside the animation hold its first or last pose). Static
    /// formats give the same scene at every time.
    pub fn scene_at(&self, time_s: f64) -> Result<Scene> {
        if !time_s.is_finite() {
            return Err(Error::argument(
                "animation time",
                format!("{}: the animation time {time_s} s is not a finite number", self.path.display()),
            ));
        }
        match &self.inner {
            Inner::Static(scene) => Ok(scene.clone()),
            Inner::Gltf(g) => g.scene_at(&self.path, time_s),
        }
    }
}

/// How much of a file a scene refers to is read.
#[derive(Clone, Copy, Debug)]
pub(crate) enum Extent {
    /// The bytes the scene declares it holds (a glTF buffer's
    /// `byteLength`): what follows is not read.
    Declared(u64),
    /// All of it, which may be at most `bytes` long for what it is
    /// (`what`: "material library", "texture").
    AtMost {
        /// The most bytes such a file may hold.
        bytes: u64,
        /// What the file is, for the message.
        what: &'static str,
    },
}

/// The files a scene is read from, as the loaders read them: each must be
/// a regular file (a FIFO or a device would block or never end), read
/// only as far as the scene says or as far as such a file can be; each is
/// recorded, so the output is never one of them.
#[derive(Debug, Default)]
pub(crate) struct Referenced {
    files: Vec<PathBuf>,
}

impl Referenced {
    /// The bytes of `path` (recorded), read as `extent` says; an error names
    /// the file and the problem in a phrase (`"/dev/zero: not a regular
    /// file (a character device)"`) for the caller to put in its sentence.
    pub(crate) fn read(&mut self, path: &Path, extent: Extent) -> std::result::Result<Vec<u8>, String> {
        use std::io::Read;
        if !self.files.iter().any(|f| f == path) {
            self.files.push(path.to_path_buf());
        }
        let at = |e: std::io::Error| format!("{}: {e}", path.display());
        // Asked before it is opened: opening a FIFO waits for a writer.
        let regular = |m: &std::fs::Metadata| {
            if m.is_file() {
                return Ok(());
            }
            let kind = crate::output::special_kind(m).unwrap_or("a folder");
            Err(format!("{}: not a regular file ({kind})", path.display()))
        };
        regular(&std::fs::metadata(path).map_err(at)?)?;
        let file = std::fs::File::open(path).map_err(at)?;
        let metadata = file.metadata().map_err(at)?;
        regular(&metadata)?;
        let length = metadata.len();
        let take = match extent {
            Extent::Declared(bytes) => bytes.min(length),
            Extent::AtMost { bytes, what } if length > bytes => {
                return Err(format!("{}: is {length} bytes, more than a {what} can be ({bytes})", path.display()))
            }
            Extent::AtMost { .. } => length,
        };
        let mut bytes =
            Vec::with_capacity(usize::try_from(take).map_err(|_| format!("{}: too large", path.display()))?);
        // Never past what was measured: a file that grows while read is read as it was.
        file.take(take).read_to_end(&mut bytes).map_err(at)?;
        Ok(bytes)
    }

    /// The scene file itself, whole (recorded): a file that is not a
    /// regular one is a scene error, one the system cannot read an I/O
    /// error.
    pub(crate) fn scene_file(&mut self, path: &Path) -> Result<Vec<u8>> {
        let metadata = std::fs::metadata(path).map_err(|e| Error::io(path, e))?;
        if !metadata.is_file() {
            let kind = crate::output::special_kind(&metadata).unwrap_or("a folder");
            return Err(Error::scene(path, format!("not a regular file ({kind})")));
        }
        self.files.push(path.to_path_buf());
        std::fs::read(path).map_err(|e| Error::io(path, e))
    }
}

/// How many bytes a texture file can hold: every texel the limits allow,
/// at 16 bits and four components, plus room for the format's own.
pub(crate) fn texture_file_bytes(limits: &LoadLimits) -> u64 {
    (limits.max_texture_texels as u64).saturating_mul(8).saturating_add(1 << 20)
}

/// The encoding of text that is UTF-16 or UTF-32 (as some Windows tools
/// save text): a byte-order mark, or a NUL in every other byte of its start
/// and in no other; `None` for anything else.
pub(crate) fn utf16(bytes: &[u8]) -> Option<&'static str> {
    for (mark, encoding) in [
        (&[0xFF, 0xFE, 0, 0][..], "UTF-32 (little-endian)"),
        (&[0, 0, 0xFE, 0xFF], "UTF-32 (big-endian)"),
        (&[0xFF, 0xFE], "UTF-16 (little-endian)"),
        (&[0xFE, 0xFF], "UTF-16 (big-endian)"),
    ] {
        if bytes.starts_with(mark) {
            return Some(encoding);
        }
    }
    let head = &bytes[..bytes.len().min(512) & !1];
    if head.len() < 4 {
        return None;
    }
    let nuls = |first: usize| head.iter().skip(first).step_by(2).filter(|&&b| b == 0).count();
    let pairs = head.len() / 2;
    match (nuls(0), nuls(1)) {
        (0, odd) if odd == pairs => Some("UTF-16 (little-endian)"),
        (even, 0) if even == pairs => Some("UTF-16 (big-endian)"),
        _ => None,
    }
}

/// The file name alone, for messages inside a problem sentence.
pub(crate) fn file_name(path: &Path) -> String {
    path.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_else(|| path.display().to_string())
}

/// Check an object made by a loader and tidy it: every position finite,
/// every index in range, attributes one per vertex; zero-area triangles are
/// dropped and counted in one warning. Returns `false` (after a warning)
/// when no triangle is left.
pub(crate) fn finish_object(path: &Path, obj: &mut Object, warnings: &mut Vec<String>) -> Result<bool> {
    let name = &obj.name;
    for (i, p) in obj.positions.iter().enumerate() {
        if let Some(k) = p.iter().position(|c| !c.is_finite()) {
            return Err(Error::scene(
                path,
                format!("object \"{name}\": vertex {i} has a {} coordinate {}", ["x", "y", "z"][k], p[k]),
            ));
        }
    }
    let n = obj.positions.len();
    let lengths = [("normals", obj.normals.len()), ("tangents", obj.tangents.len()), ("colours", obj.colours.len())];
    for (what, len) in lengths.into_iter().chain(obj.uv_sets.iter().map(|s| ("texture coordinates", s.len()))) {
        if len != 0 && len != n {
            return Err(Error::scene(
                path,
                format!("object \"{name}\": {len} {what} for {n} vertices (there must be one per vertex)"),
            ));
        }
    }
    for (t, tri) in obj.triangles.iter().enumerate() {
        if let Some(&bad) = tri.iter().find(|&&i| i as usize >= n) {
            return Err(Error::scene(
                path,
                format!("object \"{name}\": triangle {t} uses vertex {bad}, but the object has {n} vertices"),
            ));
        }
    }
    let before = obj.triangles.len();
    let positions = &obj.positions;
    // The edges and their largest component.
    let edges = |t: &[u32; 3]| {
        let [a, b, c] = t.map(|i| positions[i as usize]);
        let (u, v) = (sub(b, a), sub(c, a));
        (u.iter().chain(&v).fold(0f64, |m, x| m.max(x.abs())), u, v)
    };
    if let Some(t) = obj.triangles.iter().position(|t| edges(t).0.is_infinite()) {
        let corners = obj.triangles[t].map(|i| positions[i as usize]);
        return Err(Error::scene(
            path,
            format!(
                "object \"{name}\": triangle {t} has corners {corners:?}, too far apart to compute with (an edge \
                 overflows a double)"
            ),
        ));
    }
    obj.triangles.retain(|t| {
        let (k, u, v) = edges(t);
        if (1e-100..1e100).contains(&k) {
            // |u × v|² as it has always been computed: exactly zero for a
            // degenerate triangle, and no under- or overflow at these sizes.
            let cr = cross(u, v);
            dot(cr, cr) > 0.0
        } else {
            // Scaled to the largest component first, so that a scene in units
            // of 1e-200 or 1e300 is not taken for zero area.
            k > 0.0 && length(cross(u.map(|x| x / k), v.map(|x| x / k))) > 0.0
        }
    });
    let dropped = before - obj.triangles.len();
    if dropped > 0 {
        warnings.push(format!(
            "{}: object \"{name}\": {dropped} of {before} triangles have zero area and were dropped",
            file_name(path)
        ));
    }
    if obj.triangles.is_empty() {
        warnings.push(format!("{}: object \"{name}\" has no triangles and is left out", file_name(path)));
        return Ok(false);
    }
    Ok(true)
}

/// Finish a scene: drop objects without triangles (already warned about)
/// and refuse a scene with no triangles at all.
pub(crate) fn finish_scene(path: &Path, scene: &mut Scene) -> Result<()> {
    let mut objects = std::mem::take(&mut scene.objects);
    let mut kept = Vec::with_capacity(objects.len());
    for mut o in objects.drain(..) {
        // A texture needs its coordinate set; without it the texture is
        // left out (with a warning) rather than sampled at garbage.
        let (uv_sets, n_textures) = (o.uv_sets.len(), scene.textures.len());
        let m = &mut o.material;
        let mut none = None;
        let metallic_roughness = match &mut m.metallic_roughness {
            Some(mr) => &mut mr.texture,
            None => &mut none,
        };
        for (slot, r) in [
            ("base colour", &mut m.base_colour_texture),
            ("normal", &mut m.normal_texture),
            ("emissive", &mut m.emissive_texture),
            ("metallic-roughness", metallic_roughness),
        ] {
            if let Some(t) = r {
                if t.texture >= n_textures || t.uv_set >= uv_sets {
                    scene.warnings.push(format!(
                        "{}: object \"{}\": the {slot} texture of material \"{}\" uses texture coordinate set {}, which the object lacks; the texture is not used",
                        file_name(path),
                        o.name,
                        m.name,
                        t.uv_set
                    ));
                    *r = None;
                }
            }
        }
        if m.normal_texture.is_none() {
            o.tangents.clear();
        }
        if finish_object(path, &mut o, &mut scene.warnings)? {
            kept.push(o);
        }
    }
    scene.objects = kept;
    if scene.triangle_count() == 0 {
        return Err(Error::scene(path, "no triangles in the scene"));
    }
    Ok(())
}

/// Fan-triangulate a polygon given as vertex indices: `(0, i, i + 1)`.
pub(crate) fn fan(poly: &[u32], out: &mut Vec<[u32; 3]>) {
    for i in 1..poly.len().saturating_sub(1) {
        out.push([poly[0], poly[i], poly[i + 1]]);
    }
}

/// Find a file named in a scene file, tolerating the habits of exporters:
/// the name as given (relative to `dir` unless absolute), then with Windows
/// `\` separators turned into `/`, then matching every component
/// case-insensitively. Returns `None` when nothing matches.
pub(crate) fn resolve_file(dir: &Path, name: &str) -> Option<PathBuf> {
    let name = name.trim();
    if name.is_empty() {
        return None;
    }
    // Anything there but a folder: the reader says what is wrong with a
    // file that is not a regular one.
    let found = |p: &Path| p.exists() && !p.is_dir();
    let as_given = dir.join(name);
    if found(&as_given) {
        return Some(as_given);
    }
    let slashed = name.replace('\\', "/");
    let p = dir.join(&slashed);
    if found(&p) {
        return Some(p);
    }
    // Case-insensitive walk, component by component.
    let (mut cur, rest) = match slashed.strip_prefix('/') {
        Some(rest) => (PathBuf::from("/"), rest),
        None => (dir.to_path_buf(), &slashed[..]),
    };
    let parts: Vec<&str> = rest.split('/').filter(|s| !s.is_empty() && *s != ".").collect();
    for (k, part) in parts.iter().enumerate() {
        if *part == ".." {
            cur.push("..");
            continue;
        }
        let direct = cur.join(part);
        if direct.exists() {
            cur = direct;
            continue;
        }
        let found = std::fs::read_dir(&cur).ok()?.flatten().find(|e| {
            e.file_name().to_str().is_some_and(|n| n.eq_ignore_ascii_case(part))
                && (k + 1 == parts.len() || e.path().is_dir())
        })?;
        cur = found.path();
    }
    found(&cur).then_some(cur)
}
