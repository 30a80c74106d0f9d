//! PLY (Stanford polygon files): `ascii`, `binary_little_endian` and
//! `binary_big_endian`.
//!
//! The `vertex` element gives positions (`x y z`, any numeric type), and
//! optionally normals (`nx ny nz`), colours (`red green blue [alpha]`:
//! integers are sRGB-encoded, floats linear) and texture coordinates
//! (`u v`, `s t`, `texture_u texture_v`); the `face` element's
//! `vertex_indices` (or `vertex_index`) lists are fan-triangulated, and a
//! `tristrips` element's are triangle strips (as the Stanford tools and old
//! exporters wrote them: `-1` restarts a strip). Other elements are read
//! past and named in a warning; other properties are read past.
//! `comment TextureFile name` gives a base-colour texture. The whole file
//! is one object. A file in UTF-16 is refused, saying so.
//!
//! Header lines are read as the well-known readers (rply, trimesh, assimp)
//! read them: `comment` and `obj_info` lines are skipped, line ends may be
//! CRLF, and a line that starts with no PLY keyword at all (old Blender
//! exporters wrote `Created by Blender3D 247 - www.blender.org, source
//! file: …` without `comment`) is skipped with a warning naming it. A line
//! that starts with a keyword but is malformed stays an error: skipping it
//! would misread the body.

use std::path::Path;

use super::texture::decode;
use super::{fan, file_name, finish_scene, resolve_file, Extent, LoadLimits, Referenced};
use crate::error::{Error, Result};
use crate::math::unit;
use crate::mesh::{Material, Object, Scene, TextureRef, UvTransform, Wrap};
use crate::picture::srgb_decode_f32;

#[derive(Clone, Copy, Debug, PartialEq)]
enum Ty {
    I8,
    U8,
    I16,
    U16,
    I32,
    U32,
    F32,
    F64,
}

impl Ty {
    fn parse(s: &str) -> Option<Ty> {
        Some(match s {
            "char" | "int8" => Ty::I8,
            "uchar" | "uint8" => Ty::U8,
            "short" | "int16" => Ty::I16,
            "ushort" | "uint16" => Ty::U16,
            "int" | "int32" => Ty::I32,
            "uint" | "uint32" => Ty::U32,
            "float" | "float32" => Ty::F32,
            "double" | "float64" => Ty::F64,
            _ => return None,
        })
    }
    fn size(self) -> usize {
        match self {
            Ty::I8 | Ty::U8 => 1,
            Ty::I16 | Ty::U16 => 2,
            Ty::I32 | Ty::U32 | Ty::F32 => 4,
            Ty::F64 => 8,
        }
    }
    fn is_float(self) -> bool {
        matches!(self, Ty::F32 | Ty::F64)
    }
    /// Largest value of an integer type (for normalising colours).
    fn max(self) -> f64 {
        match self {
            Ty::I8 => 127.0,
            Ty::U8 => 255.0,
            Ty::I16 => 32767.0,
            Ty::U16 => 65535.0,
            Ty::I32 => 2147483647.0,
            Ty::U32 => 4294967295.0,
            Ty::F32 | Ty::F64 => 1.0,
        }
    }
}

#[derive(Debug)]
struct Prop {
    name: String,
    ty: Ty,
    /// For a list: the type of its count.
    list_count: Option<Ty>,
}

#[derive(Debug)]
struct Element {
    name: String,
    count: u64,
    props: Vec<Prop>,
}

#[derive(Clone, Copy, PartialEq)]
enum Format {
    Ascii,
    Little,
    Big,
}

/// The body after the header: a token stream or raw bytes.
struct Body<'a> {
    bytes: &'a [u8],
    pos: usize,
    format: Format,
}

impl Body<'_> {
    fn remaining(&self) -> usize {
        self.bytes.len() - self.pos
    }

    /// The next value; `None` when the body ends early or a token is not a number.
    fn read(&mut self, ty: Ty) -> Option<f64> {
        match self.format {
            Format::Ascii => {
                let b = self.bytes;
                while self.pos < b.len() && b[self.pos].is_ascii_whitespace() {
                    self.pos += 1;
                }
                let start = self.pos;
                while self.pos < b.len() && !b[self.pos].is_ascii_whitespace() {
                    self.pos += 1;
                }
                let tok = std::str::from_utf8(&b[start..self.pos]).ok()?;
                if tok.is_empty() {
                    return None;
                }
                tok.parse::<f64>().ok()
            }
            f => {
                let n = ty.size();
                let s = self.bytes.get(self.pos..self.pos + n)?;
                self.pos += n;
                let mut a = [0u8; 8];
                a[..n].copy_from_slice(s);
                if f == Format::Big {
                    a[..n].reverse();
                }
                Some(match ty {
                    Ty::I8 => a[0] as i8 as f64,
                    Ty::U8 => a[0] as f64,
                    Ty::I16 => i16::from_le_bytes([a[0], a[1]]) as f64,
                    Ty::U16 => u16::from_le_bytes([a[0], a[1]]) as f64,
                    Ty::I32 => i32::from_le_bytes([a[0], a[1], a[2], a[3]]) as f64,
                    Ty::U32 => u32::from_le_bytes([a[0], a[1], a[2], a[3]]) as f64,
                    Ty::F32 => f32::from_le_bytes([a[0], a[1], a[2], a[3]]) as f64,
                    Ty::F64 => f64::from_le_bytes(a),
                })
            }
        }
    }

    /// Fewest bytes one value of `ty` can take.
    fn min_size(&self, ty: Ty) -> usize {
        match self.format {
            Format::Ascii => 1,
            _ => ty.size(),
        }
    }
}

/// Find `end_header` and its line end; returns (header text, body offset).
fn split_header(bytes: &[u8]) -> Option<(String, usize)> {
    let key = b"end_header";
    let at = bytes.windows(key.len()).position(|w| w == key)?;
    let mut end = at + key.len();
    while end < bytes.len() && (bytes[end] == b' ' || bytes[end] == b'\t' || bytes[end] == b'\r') {
        end += 1;
    }
    if end < bytes.len() && bytes[end] == b'\n' {
        end += 1;
    } else if end < bytes.len() {
        return None;
    }
    Some((String::from_utf8_lossy(&bytes[..at]).into_owned(), end))
}

pub(crate) fn load(path: &Path, limits: &LoadLimits, files: &mut Referenced) -> Result<Scene> {
    let bytes = files.scene_file(path)?;
    let file = file_name(path);
    let stem = path.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_else(|| file.clone());
    let bad = |problem: String| Error::scene(path, problem);
    if let Some(encoding) = super::utf16(&bytes) {
        return Err(bad(format!("is {encoding} text; a PLY header is ASCII (save the file as ASCII or UTF-8)")));
    }
    if !bytes.starts_with(b"ply") {
        return Err(bad("not a PLY file (it does not start with \"ply\")".into()));
    }
    let (header, body_at) = split_header(&bytes).ok_or_else(|| bad("the PLY header has no end_header line".into()))?;
    let header = Header::read(path, &header)?;
    let mut reader = BodyReader {
        path,
        stem,
        file,
        limits,
        body: Body { bytes: &bytes, pos: body_at, format: header.format },
        data: Vertices::default(),
        warnings: header.warnings,
        seen_vertex: false,
    };
    for el in &header.elements {
        reader.element(el)?;
    }
    if !reader.seen_vertex {
        return Err(bad("the file has no vertex element".into()));
    }
    reader.into_scene(header.texture_file, files)
}

/// What the header declares: the body's format, its elements in order,
/// and the texture a `comment TextureFile` names.
struct Header {
    format: Format,
    elements: Vec<Element>,
    texture_file: Option<String>,
    /// Lines skipped as free text.
    warnings: Vec<String>,
}

/// The words a PLY header line can start with (Turk, "The PLY Polygon File
/// Format"; `obj_info` from the Stanford tools).
const KEYWORDS: [&str; 6] = ["format", "comment", "obj_info", "element", "property", "end_header"];

impl Header {
    /// The header's lines after the first (`ply`), each checked.
    fn read(path: &Path, header: &str) -> Result<Header> {
        let bad = |problem: String| Error::scene(path, problem);
        let mut format = None;
        let mut elements: Vec<Element> = Vec::new();
        let mut texture_file: Option<String> = None;
        let mut warnings = Vec::new();
        for (i, raw) in header.lines().enumerate().skip(1) {
            let ln = i + 1;
            let line = raw.trim();
            let toks: Vec<&str> = line.split_ascii_whitespace().collect();
            match toks.as_slice() {
                [] => {}
                ["format", f, ..] => {
                    format = Some(match *f {
                        "ascii" => Format::Ascii,
                        "binary_little_endian" => Format::Little,
                        "binary_big_endian" => Format::Big,
                        other => return Err(bad(format!("header line {ln}: unknown format \"{other}\""))),
                    })
                }
                ["comment", rest @ ..] => {
                    if rest.first().is_some_and(|k| k.eq_ignore_ascii_case("texturefile")) && rest.len() > 1 {
                        let pos = line.find(rest[0]).map(|p| p + rest[0].len()).unwrap_or(line.len());
                        texture_file = Some(line[pos..].trim().to_string());
                    }
                }
                ["obj_info", ..] => {}
                ["element", name, count] => {
                    let count: u64 = count.parse().map_err(|_| {
                        bad(format!(
                            "header line {ln}: element \"{name}\" has the count \"{count}\", not a whole number"
                        ))
                    })?;
                    elements.push(Element { name: name.to_string(), count, props: Vec::new() });
                }
                ["property", "list", ct, it, name] => {
                    let (Some(c), Some(t)) = (Ty::parse(ct), Ty::parse(it)) else {
                        return Err(bad(format!("header line {ln}: property \"{name}\" has an unknown type")));
                    };
                    if c.is_float() {
                        return Err(bad(format!(
                            "header line {ln}: list property \"{name}\" has a floating-point count type"
                        )));
                    }
                    let e = elements
                        .last_mut()
                        .ok_or_else(|| bad(format!("header line {ln}: property before any element")))?;
                    e.props.push(Prop { name: name.to_string(), ty: t, list_count: Some(c) });
                }
                ["property", ty, name] => {
                    let t = Ty::parse(ty).ok_or_else(|| {
                        bad(format!("header line {ln}: property \"{name}\" has the unknown type \"{ty}\""))
                    })?;
                    let e = elements
                        .last_mut()
                        .ok_or_else(|| bad(format!("header line {ln}: property before any element")))?;
                    e.props.push(Prop { name: name.to_string(), ty: t, list_count: None });
                }
                [first, ..] if !KEYWORDS.contains(first) => warnings.push(format!(
                    "{}: header line {ln}: \"{line}\" starts with no PLY keyword; skipped as a comment",
                    path.display()
                )),
                _ => return Err(bad(format!("header line {ln}: cannot understand \"{line}\""))),
            }
        }
        let format = format.ok_or_else(|| bad("the PLY header has no format line".into()))?;
        Ok(Header { format, elements, texture_file, warnings })
    }
}

/// The vertex data and faces read from the body.
#[derive(Default)]
struct Vertices {
    positions: Vec<[f64; 3]>,
    normals: Vec<[f32; 3]>,
    colours: Vec<[f32; 4]>,
    uvs: Vec<[f32; 2]>,
    triangles: Vec<[u32; 3]>,
}

/// Reads the body's elements in the header's order: the first `vertex`
/// element and the `face` element into [`Vertices`], others read past.
struct BodyReader<'a> {
    path: &'a Path,
    stem: String,
    file: String,
    limits: &'a LoadLimits,
    body: Body<'a>,
    data: Vertices,
    warnings: Vec<String>,
    seen_vertex: bool,
}

impl BodyReader<'_> {
    fn bad(&self, problem: String) -> Error {
        Error::scene(self.path, problem)
    }

    /// The error for entry `k` of `el` that the body cannot hold.
    fn truncated(&self, el: &Element, k: usize) -> Error {
        self.bad(format!(
            "element \"{}\" entry {k}: the file ends early or holds something that is not a number",
            el.name
        ))
    }

    fn element(&mut self, el: &Element) -> Result<()> {
        // Every element takes at least this many bytes: refuse counts the
        // file cannot hold before allocating anything for them.
        let body = &self.body;
        let min: usize = el.props.iter().map(|p| body.min_size(p.list_count.unwrap_or(p.ty))).sum::<usize>().max(1);
        let remaining = body.remaining();
        if el.count.saturating_mul(min as u64) > remaining as u64 {
            return Err(self.bad(format!(
                "element \"{}\" declares {} entries of at least {min} bytes, but only {remaining} bytes follow the header",
                el.name, el.count
            )));
        }
        match el.name.as_str() {
            "vertex" if !self.seen_vertex => {
                self.seen_vertex = true;
                self.vertices(el)
            }
            "face" => self.faces(el, List::Polygons),
            "tristrips" => self.faces(el, List::Strips),
            _ => {
                let mut vals = vec![0.0f64; el.props.len()];
                for k in 0..el.count as usize {
                    read_entry(&mut self.body, el, &mut vals, None).map_err(|_| self.truncated(el, k))?;
                }
                if el.count > 0 {
                    let what = if el.name == "vertex" {
                        "a second element \"vertex\"".to_string()
                    } else {
                        format!("element \"{}\"", el.name)
                    };
                    self.warnings.push(format!(
                        "{}: {what} ({} entries) is not something holo draws; skipped",
                        self.file, el.count
                    ));
                }
                Ok(())
            }
        }
    }

    /// The vertex element: positions (finite), and normals, colours and
    /// texture coordinates when it has their properties.
    fn vertices(&mut self, el: &Element) -> Result<()> {
        let find =
            |names: &[&str]| el.props.iter().position(|p| p.list_count.is_none() && names.contains(&p.name.as_str()));
        let (Some(x), Some(y), Some(z)) = (find(&["x"]), find(&["y"]), find(&["z"])) else {
            return Err(self.bad("element \"vertex\" lacks one of the properties x, y, z".into()));
        };
        let nrm = (find(&["nx"]), find(&["ny"]), find(&["nz"]));
        let col = (
            find(&["red", "diffuse_red", "r"]),
            find(&["green", "diffuse_green", "g"]),
            find(&["blue", "diffuse_blue", "b"]),
        );
        let alpha = find(&["alpha", "diffuse_alpha", "a"]);
        let uv = match (find(&["u", "s", "texture_u", "texture_s"]), find(&["v", "t", "texture_v", "texture_t"])) {
            (Some(u), Some(v)) => Some((u, v)),
            _ => None,
        };
        let count = el.count as usize;
        self.data.positions.reserve_exact(count);
        let mut vals = vec![0.0f64; el.props.len()];
        for k in 0..count {
            read_entry(&mut self.body, el, &mut vals, None).map_err(|_| self.truncated(el, k))?;
            let p = [vals[x], vals[y], vals[z]];
            if let Some(c) = p.iter().find(|c| !c.is_finite()) {
                return Err(self.bad(format!("object \"{}\": vertex {k} has the coordinate {c}", self.stem)));
            }
            let d = &mut self.data;
            d.positions.push(p);
            if let (Some(a), Some(b), Some(c)) = nrm {
                d.normals.push([vals[a] as f32, vals[b] as f32, vals[c] as f32]);
            }
            if let (Some(r), Some(g), Some(b)) = col {
                let ch = |i: usize| {
                    let t = el.props[i].ty;
                    if t.is_float() {
                        vals[i] as f32
                    } else {
                        srgb_decode_f32((vals[i] / t.max()).clamp(0.0, 1.0) as f32)
                    }
                };
                let a = alpha.map_or(1.0, |i| (vals[i] / el.props[i].ty.max()) as f32);
                d.colours.push([ch(r), ch(g), ch(b), a]);
            }
            if let Some((u, v)) = uv {
                // PLY writers (MeshLab) put v up, as OBJ does; ours points down.
                d.uvs.push([vals[u] as f32, (1.0 - vals[v]) as f32]);
            }
        }
        Ok(())
    }

    /// The `face` element (each `vertex_indices` list fan-triangulated) or
    /// the `tristrips` element (each list triangle strips, see [`strips`]),
    /// within the triangle limit.
    fn faces(&mut self, el: &Element, kind: List) -> Result<()> {
        let stem = &self.stem;
        let Some(li) = el
            .props
            .iter()
            .position(|p| p.list_count.is_some() && (p.name == "vertex_indices" || p.name == "vertex_index"))
        else {
            return Err(self.bad(format!("element \"{}\" has no vertex_indices list", el.name)));
        };
        if el.props.iter().any(|p| p.list_count.is_some() && p.name == "texcoord") {
            self.warnings
                .push(format!("{}: object \"{stem}\": per-face texcoord lists are not supported; ignored", self.file));
        }
        let max_triangles = self.limits.max_triangles;
        if kind == List::Polygons && el.count > max_triangles as u64 {
            return Err(self.bad(format!(
                "object \"{stem}\": {} faces, more than the limit of {max_triangles} triangles",
                el.count
            )));
        }
        let count = el.count as usize;
        self.data.triangles.reserve(count);
        let mut vals = vec![0.0f64; el.props.len()];
        let mut poly: Vec<u32> = Vec::new();
        for k in 0..count {
            poly.clear();
            let entry = if kind == List::Polygons { "face" } else { "strip" };
            read_entry(&mut self.body, el, &mut vals, Some((li, &mut poly, kind))).map_err(|e| match e {
                Some(msg) => self.bad(format!("object \"{stem}\": {entry} {k}: {msg}")),
                None => self.truncated(el, k),
            })?;
            match kind {
                List::Polygons => fan(&poly, &mut self.data.triangles),
                List::Strips => strips(&poly, &mut self.data.triangles),
            }
            if self.data.triangles.len() > max_triangles {
                return Err(self
                    .bad(format!("object \"{stem}\": {entry} {k}: more than the limit of {max_triangles} triangles")));
            }
        }
        Ok(())
    }

    /// The scene of one object named after the file, with the texture the
    /// header names (if any) as its base colour.
    fn into_scene(mut self, texture_file: Option<String>, files: &mut Referenced) -> Result<Scene> {
        let (path, file, stem) = (self.path, self.file.clone(), self.stem.clone());
        let bad = |problem: String| Error::scene(path, problem);
        let mut scene = Scene { source: file.clone(), ..Scene::default() };
        let mut material = Material { name: stem.clone(), ..Material::default() };
        let d = self.data;
        if let Some(name) = texture_file {
            let dir = path.parent().map(Path::to_path_buf).unwrap_or_default();
            let p = resolve_file(&dir, &name).ok_or_else(|| {
                bad(format!(
                    "object \"{stem}\": texture \"{name}\" (comment TextureFile) not found in {}",
                    dir.display()
                ))
            })?;
            let extent = Extent::AtMost { bytes: super::texture_file_bytes(self.limits), what: "texture" };
            let tb = files
                .read(&p, extent)
                .map_err(|e| bad(format!("object \"{stem}\": texture \"{name}\" cannot be read: {e}")))?;
            let t = decode(&tb, &name, true, [Wrap::Repeat; 2], self.limits)
                .map_err(|e| bad(format!("object \"{stem}\": texture \"{name}\" {e}")))?;
            scene.textures.push(t);
            material.base_colour_texture =
                Some(TextureRef { texture: 0, uv_set: 0, transform: UvTransform::default() });
            if d.uvs.is_empty() {
                self.warnings.push(format!(
                    "{file}: object \"{stem}\": a texture is named but the vertices have no texture coordinates"
                ));
            }
        }
        let normals = match d.normals.iter().map(|&n| unit(n)).collect::<Option<Vec<_>>>() {
            Some(unit_normals) => unit_normals,
            None => {
                self.warnings.push(format!(
                    "{file}: object \"{stem}\": some normals are zero or not finite; the object is shaded flat"
                ));
                Vec::new()
            }
        };
        scene.objects.push(Object {
            name: stem,
            positions: d.positions,
            normals,
            tangents: Vec::new(),
            uv_sets: if d.uvs.is_empty() { Vec::new() } else { vec![d.uvs] },
            colours: d.colours,
            triangles: d.triangles,
            material,
        });
        scene.warnings = self.warnings;
        finish_scene(path, &mut scene)?;
        Ok(scene)
    }
}

/// What a list of vertex indices is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum List {
    /// A polygon (`face`), fan-triangulated.
    Polygons,
    /// Triangle strips (`tristrips`), `-1` starting a new strip.
    Strips,
}

/// A strip's restart (`-1` in the file) among the indices read.
const RESTART: u32 = u32::MAX;

/// The triangles of triangle strips as old exporters wrote them (the
/// Stanford tools' `tristrips`): vertex indices, [`RESTART`] starting a
/// new strip. Triangle `i` of a strip over `v₀ v₁ v₂ …` is
/// `(vᵢ, vᵢ₊₁, vᵢ₊₂)` for even `i` and `(vᵢ₊₁, vᵢ, vᵢ₊₂)` for odd `i`, so
/// every triangle keeps the first one's winding (the parity starts again
/// with each strip). Triangles that repeat a vertex (the joins exporters
/// write between strips) are dropped.
fn strips(indices: &[u32], out: &mut Vec<[u32; 3]>) {
    for strip in indices.split(|&i| i == RESTART) {
        for (i, w) in strip.windows(3).enumerate() {
            let t = if i % 2 == 0 { [w[0], w[1], w[2]] } else { [w[1], w[0], w[2]] };
            if t[0] != t[1] && t[1] != t[2] && t[0] != t[2] {
                out.push(t);
            }
        }
    }
}

/// Read one entry of an element: scalars into `vals`; lists are read past,
/// except the one at `list.0`, whose items (vertex indices, with strip
/// restarts for [`List::Strips`]) go to `list.1`. Err(None): the body
/// ended early or held a non-number; Err(Some): a bad vertex index.
fn read_entry(
    body: &mut Body,
    el: &Element,
    vals: &mut [f64],
    mut list: Option<(usize, &mut Vec<u32>, List)>,
) -> std::result::Result<(), Option<String>> {
    for (i, p) in el.props.iter().enumerate() {
        match p.list_count {
            None => vals[i] = body.read(p.ty).ok_or(None)?,
            Some(ct) => {
                let n = body.read(ct).ok_or(None)?;
                if n.is_nan() || n < 0.0 || n.fract() != 0.0 {
                    return Err(Some(format!("list \"{}\" has the length {n}", p.name)));
                }
                let n = n as usize;
                if n.saturating_mul(body.min_size(p.ty)) > body.remaining() {
                    return Err(None);
                }
                let keep = list.as_ref().is_some_and(|(li, _, _)| *li == i);
                let restarts = list.as_ref().is_some_and(|(_, _, kind)| *kind == List::Strips);
                for _ in 0..n {
                    let v = body.read(p.ty).ok_or(None)?;
                    if keep {
                        let index = if restarts && v == -1.0 {
                            RESTART
                        } else if v.is_nan() || v < 0.0 || v.fract() != 0.0 || v > u32::MAX as f64 - 1.0 {
                            return Err(Some(format!("vertex index {v} is not a valid index")));
                        } else {
                            v as u32
                        };
                        if let Some((_, out, _)) = list.as_mut() {
                            out.push(index);
                        }
                    }
                }
            }
        }
    }
    Ok(())
}
