//! Wavefront OBJ with MTL material libraries.
//!
//! One [`Object`] per (group, material) pair that has faces: `o`, `g` and
//! `usemtl` switch the current pair. Vertices are deduplicated per
//! `(v, vt, vn)` triple within an object. Polygons are fan-triangulated.

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use super::texture::{decode, generate_tangents};
use super::{fan, file_name, finish_scene, resolve_file, Extent, LoadLimits, Referenced};
use crate::error::{Error, Result};
use crate::math::unit;
use crate::mesh::{Material, Object, Scene, Texture, TextureRef, UvTransform, Wrap};

const NONE: u32 = u32::MAX;

/// Faces of one (group, material) pair being collected.
struct Builder {
    group: String,
    material: String,
    /// Unique `(v, vt, vn)` triples (global indices, `NONE` when absent).
    corners: Vec<(u32, u32, u32)>,
    map: HashMap<(u32, u32, u32), u32>,
    triangles: Vec<[u32; 3]>,
}

/// Logical lines: `\r\n` accepted, `\` continues a line, `#` starts a
/// comment, a UTF-8 byte-order mark (as Windows editors write) skipped.
/// Yields (first physical line number, text).
fn logical_lines(text: &str) -> Vec<(usize, String)> {
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let mut out = Vec::new();
    let mut cur = String::new();
    let mut start = 0;
    for (i, raw) in text.split('\n').enumerate() {
        let line = raw.strip_suffix('\r').unwrap_or(raw);
        if cur.is_empty() {
            start = i + 1;
        }
        let trimmed = line.trim_end();
        if let Some(head) = trimmed.strip_suffix('\\') {
            cur.push_str(head);
            cur.push(' ');
            continue;
        }
        cur.push_str(line);
        let mut l = std::mem::take(&mut cur);
        if let Some(h) = l.find('#') {
            l.truncate(h);
        }
        out.push((start, l));
    }
    if !cur.is_empty() {
        out.push((start, cur));
    }
    out
}

fn numbers(path: &Path, line: usize, what: &str, toks: &[&str]) -> Result<Vec<f64>> {
    toks.iter()
        .map(|t| {
            t.parse::<f64>().map_err(|_| Error::scene(path, format!("line {line}: {what}: \"{t}\" is not a number")))
        })
        .collect()
}

/// At least three numbers for `what` ("vertex 4"), whose numbers are `parts`.
fn three_numbers(path: &Path, line: usize, what: &str, parts: &str, toks: &[&str]) -> Result<Vec<f64>> {
    if toks.len() < 3 {
        return Err(Error::scene(path, format!("line {line}: {what} has fewer than 3 {parts}")));
    }
    numbers(path, line, what, toks)
}

pub(crate) fn load(path: &Path, limits: &LoadLimits, files: &mut Referenced) -> Result<Scene> {
    let bytes = files.scene_file(path)?;
    let text = text_of(path, &bytes)?;
    let mut parser = Parser::new(path, limits, files);
    for (ln, line) in logical_lines(&text) {
        let toks: Vec<&str> = line.split_ascii_whitespace().collect();
        let Some((&kw, args)) = toks.split_first() else { continue };
        parser.statement(ln, kw, args)?;
    }
    parser.finish()
}

/// The text of an OBJ or MTL file, which must be UTF-8 (ASCII is): a file
/// in UTF-16 (as some Windows tools save text) or another encoding is
/// refused, saying which, rather than read as nothing. Bytes that are not
/// UTF-8 inside comments are let pass; they say nothing to the reader.
fn text_of<'b>(path: &Path, bytes: &'b [u8]) -> Result<std::borrow::Cow<'b, str>> {
    if let Some(encoding) = super::utf16(bytes) {
        return Err(Error::scene(
            path,
            format!("is {encoding} text; holo reads OBJ and MTL files in UTF-8 (save it as UTF-8)"),
        ));
    }
    let text = String::from_utf8_lossy(bytes);
    if let std::borrow::Cow::Owned(_) = text {
        for (i, line) in bytes.split(|&b| b == b'\n').enumerate() {
            let statement = line.split(|&b| b == b'#').next().unwrap_or(line);
            if let Err(e) = std::str::from_utf8(statement) {
                let byte = statement[e.valid_up_to()];
                return Err(Error::scene(
                    path,
                    format!(
                        "line {} is not UTF-8 text (byte 0x{byte:02X}); holo reads OBJ and MTL files in UTF-8 (save it as UTF-8)",
                        i + 1
                    ),
                ));
            }
        }
    }
    Ok(text)
}

/// The state of reading one OBJ file: the vertex data seen so far, the
/// objects being collected, the current group and material, the material
/// libraries read and what was skipped.
struct Parser<'a> {
    path: &'a Path,
    files: &'a mut Referenced,
    dir: PathBuf,
    file: String,
    stem: String,
    limits: &'a LoadLimits,
    warnings: Vec<String>,
    positions: Vec<[f64; 3]>,
    vcolours: Vec<Option<[f32; 3]>>,
    uvs: Vec<[f32; 2]>,
    normals: Vec<[f32; 3]>,
    builders: Vec<Builder>,
    index: HashMap<(String, String), usize>,
    group: String,
    material: String,
    current: Option<usize>,
    mtl: MtlLibrary,
    total_triangles: usize,
    short_faces: usize,
    ignored_elements: usize,
    poly: Vec<u32>,
}

impl<'a> Parser<'a> {
    fn new(path: &'a Path, limits: &'a LoadLimits, files: &'a mut Referenced) -> Parser<'a> {
        let file = file_name(path);
        let stem = path.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_else(|| file.clone());
        Parser {
            path,
            files,
            dir: path.parent().map(Path::to_path_buf).unwrap_or_default(),
            file,
            group: stem.clone(),
            stem,
            limits,
            warnings: Vec::new(),
            positions: Vec::new(),
            vcolours: Vec::new(),
            uvs: Vec::new(),
            normals: Vec::new(),
            builders: Vec::new(),
            index: HashMap::new(),
            material: String::new(),
            current: None,
            mtl: MtlLibrary::default(),
            total_triangles: 0,
            short_faces: 0,
            ignored_elements: 0,
            poly: Vec::new(),
        }
    }

    /// One statement `kw args` of logical line `ln`.
    fn statement(&mut self, ln: usize, kw: &str, args: &[&str]) -> Result<()> {
        let path = self.path;
        match kw {
            "v" => {
                let what = format!("vertex {}", self.positions.len() + 1);
                let v = three_numbers(path, ln, &what, "coordinates", args)?;
                if let Some(x) = v[..3].iter().find(|x| !x.is_finite()) {
                    return Err(Error::scene(
                        path,
                        format!("line {ln}: object \"{}\": {what} has the coordinate {x}", self.group),
                    ));
                }
                self.positions.push([v[0], v[1], v[2]]);
                // `v x y z r g b`: colours as the common writers (MeshLab,
                // assimp) store them, which is without any transfer
                // function applied; they are taken as linear.
                self.vcolours.push((v.len() >= 6).then(|| [v[3] as f32, v[4] as f32, v[5] as f32]));
            }
            "vt" => {
                let v = numbers(path, ln, &format!("texture coordinate {}", self.uvs.len() + 1), args)?;
                let u = v.first().copied().unwrap_or(0.0);
                let w = v.get(1).copied().unwrap_or(0.0);
                // OBJ's v points up; ours (glTF's) points down from row 0.
                self.uvs.push([u as f32, (1.0 - w) as f32]);
            }
            "vn" => {
                let v = three_numbers(path, ln, &format!("normal {}", self.normals.len() + 1), "components", args)?;
                self.normals.push([v[0] as f32, v[1] as f32, v[2] as f32]);
            }
            "f" | "fo" => self.face(ln, args)?,
            "o" | "g" => {
                self.group = if args.is_empty() { self.stem.clone() } else { args.join(" ") };
                self.current = None;
            }
            "usemtl" => {
                self.material = args.join(" ");
                self.current = None;
            }
            "mtllib" => self.material_libraries(ln, args)?,
            "l" | "p" | "curv" | "curv2" | "surf" => self.ignored_elements += 1,
            _ => {}
        }
        Ok(())
    }

    /// The object faces now go to: the current (group, material) pair's.
    fn builder(&mut self) -> usize {
        if let Some(b) = self.current {
            return b;
        }
        let key = (self.group.clone(), self.material.clone());
        let builders = &mut self.builders;
        let (group, material) = (&self.group, &self.material);
        let b = *self.index.entry(key).or_insert_with(|| {
            builders.push(Builder {
                group: group.clone(),
                material: material.clone(),
                corners: Vec::new(),
                map: HashMap::new(),
                triangles: Vec::new(),
            });
            builders.len() - 1
        });
        self.current = Some(b);
        b
    }

    /// A face: its corners resolved to (v, vt, vn) triples, deduplicated in
    /// their object, fan-triangulated within the triangle limit.
    fn face(&mut self, ln: usize, args: &[&str]) -> Result<()> {
        let b = self.builder();
        let path = self.path;
        let lens = (self.positions.len(), self.uvs.len(), self.normals.len());
        let bl = &mut self.builders[b];
        let poly = &mut self.poly;
        poly.clear();
        for tok in args {
            let mut parts = tok.split('/');
            let resolve = |s: Option<&str>, len: usize, what: &str| -> Result<u32> {
                let Some(s) = s.filter(|s| !s.is_empty()) else { return Ok(NONE) };
                let i: i64 = s.parse().map_err(|_| {
                    Error::scene(
                        path,
                        format!("line {ln}: object \"{}\": face corner \"{tok}\" is not made of integers", bl.group),
                    )
                })?;
                let r = if i > 0 { i - 1 } else { len as i64 + i };
                if i == 0 || r < 0 || r >= len as i64 {
                    return Err(Error::scene(
                        path,
                        format!(
                            "line {ln}: object \"{}\": face corner \"{tok}\" refers to {what} {i}, but only {len} are defined before it",
                            bl.group
                        ),
                    ));
                }
                Ok(r as u32)
            };
            let v = resolve(parts.next(), lens.0, "vertex")?;
            let vt = resolve(parts.next(), lens.1, "texture coordinate")?;
            let vn = resolve(parts.next(), lens.2, "normal")?;
            if v == NONE {
                return Err(Error::scene(
                    path,
                    format!("line {ln}: object \"{}\": face corner \"{tok}\" has no vertex", bl.group),
                ));
            }
            let next = bl.corners.len() as u32;
            let id = *bl.map.entry((v, vt, vn)).or_insert(next);
            if id == next {
                bl.corners.push((v, vt, vn));
            }
            poly.push(id);
        }
        if poly.len() < 3 {
            self.short_faces += 1;
            return Ok(());
        }
        self.total_triangles += poly.len() - 2;
        if self.total_triangles > self.limits.max_triangles {
            return Err(Error::scene(
                path,
                format!(
                    "line {ln}: object \"{}\": the scene reaches more than the limit of {} triangles",
                    bl.group, self.limits.max_triangles
                ),
            ));
        }
        fan(poly, &mut bl.triangles);
        Ok(())
    }

    /// `mtllib`: one library whose name may hold spaces, or several.
    fn material_libraries(&mut self, ln: usize, args: &[&str]) -> Result<()> {
        let dir = &self.dir;
        let whole = args.join(" ");
        let names: Vec<String> = if resolve_file(dir, &whole).is_some() || args.len() <= 1 {
            vec![whole]
        } else {
            args.iter().map(|s| s.to_string()).collect()
        };
        for name in names {
            // As assimp and trimesh do: the geometry is still drawn, with the
            // default material for what the library would have defined.
            let Some(p) = resolve_file(dir, &name) else {
                self.warnings.push(format!(
                    "{}: line {ln}: material library \"{name}\" (mtllib) not found in {}; its materials are drawn \
                     with the default material",
                    self.file,
                    dir.display()
                ));
                continue;
            };
            self.mtl.read(&p, self.limits, self.files, &mut self.warnings)?;
        }
        Ok(())
    }

    /// The scene: one object per (group, material) pair with faces, and
    /// the warnings for what was skipped.
    fn finish(mut self) -> Result<Scene> {
        let file = self.file.clone();
        if self.short_faces > 0 {
            self.warnings.push(format!("{file}: {} faces with fewer than 3 corners were skipped", self.short_faces));
        }
        if self.ignored_elements > 0 {
            self.warnings.push(format!(
                "{file}: {} points, lines, curves or surfaces were ignored (only faces are drawn)",
                self.ignored_elements
            ));
        }
        let mut scene = Scene { source: file, ..Scene::default() };
        let builders = std::mem::take(&mut self.builders);
        let mut per_group: HashMap<&str, usize> = HashMap::new();
        for b in &builders {
            *per_group.entry(b.group.as_str()).or_default() += 1;
        }
        let mut unknown_materials: Vec<String> = Vec::new();
        for b in &builders {
            let name = if per_group.get(b.group.as_str()).copied().unwrap_or(0) > 1 && !b.material.is_empty() {
                format!("{} ({})", b.group, b.material)
            } else {
                b.group.clone()
            };
            let material = self.material_of(b, &name, &mut unknown_materials);
            let o = self.object(b, name, material);
            scene.objects.push(o);
        }
        scene.textures = self.mtl.textures;
        scene.warnings = self.warnings;
        finish_scene(self.path, &mut scene)?;
        Ok(scene)
    }

    /// The material `b` uses: the default without `usemtl`, else the
    /// library's, else (with one warning per name) the default renamed.
    fn material_of(&mut self, b: &Builder, name: &str, unknown_materials: &mut Vec<String>) -> Material {
        if b.material.is_empty() {
            Material::default()
        } else if let Some(m) = self.mtl.materials.get(&b.material) {
            m.clone()
        } else {
            if !unknown_materials.contains(&b.material) {
                unknown_materials.push(b.material.clone());
                self.warnings.push(format!(
                    "{}: object \"{name}\": material \"{}\" (usemtl) is not in any material library; the default material is used",
                    self.file, b.material
                ));
            }
            Material { name: b.material.clone(), ..Material::default() }
        }
    }

    /// The object of `b`'s faces: its corners' positions, texture
    /// coordinates, normals and colours, and tangents for a normal map.
    fn object(&mut self, b: &Builder, name: String, material: Material) -> Object {
        let file = &self.file;
        let c = &b.corners;
        let mut o = Object {
            name: name.clone(),
            positions: c.iter().map(|&(v, _, _)| self.positions[v as usize]).collect(),
            triangles: b.triangles.clone(),
            material,
            ..Object::default()
        };
        if c.iter().any(|&(_, vt, _)| vt != NONE) {
            o.uv_sets.push(
                c.iter().map(|&(_, vt, _)| if vt == NONE { [0.0, 0.0] } else { self.uvs[vt as usize] }).collect(),
            );
        }
        if c.iter().any(|&(_, _, vn)| vn != NONE) {
            let ns: Option<Vec<[f32; 3]>> = c.iter().map(|&(_, _, vn)| unit(*self.normals.get(vn as usize)?)).collect();
            match ns {
                Some(ns) => o.normals = ns,
                None => self.warnings.push(format!(
                    "{file}: object \"{name}\": some corners have no normal (or a zero one); the object is shaded flat"
                )),
            }
        }
        if c.iter().any(|&(v, _, _)| self.vcolours[v as usize].is_some()) {
            o.colours = c
                .iter()
                .map(|&(v, _, _)| {
                    let k = self.vcolours[v as usize].unwrap_or([1.0; 3]);
                    [k[0], k[1], k[2], 1.0]
                })
                .collect();
        }
        if let Some(nt) = &o.material.normal_texture {
            match (o.normals.is_empty(), o.uv_sets.get(nt.uv_set)) {
                (false, Some(uv)) => {
                    if o.positions.iter().all(|p| p.iter().all(|x| x.is_finite())) {
                        o.tangents = generate_tangents(&o.positions, &o.normals, uv, &o.triangles);
                    }
                }
                _ => self.warnings.push(format!(
                    "{file}: object \"{name}\": the normal map needs normals and texture coordinates, which the object lacks; it is not used"
                )),
            }
        }
        o
    }
}

/// Materials and the textures they use, from one or more `.mtl` files.
#[derive(Default)]
struct MtlLibrary {
    materials: HashMap<String, Material>,
    textures: Vec<Texture>,
    cache: HashMap<(PathBuf, bool, [u8; 2]), usize>,
}

/// Options of a `map_*` statement that matter here.
struct MapSpec {
    file: String,
    transform: UvTransform,
    clamp: bool,
    bump_multiplier: f32,
}

/// Split `[-option args...]* file name` into options and the file name.
fn parse_map(args: &[&str]) -> MapSpec {
    let mut spec =
        MapSpec { file: String::new(), transform: UvTransform::default(), clamp: false, bump_multiplier: 1.0 };
    let mut i = 0;
    let is_num = |s: &str| s.parse::<f64>().is_ok();
    let (mut offset, mut scale) = ([0.0f32; 2], [1.0f32; 2]);
    while i < args.len() && args[i].starts_with('-') && !is_num(args[i]) {
        let opt = args[i].to_ascii_lowercase();
        i += 1;
        let nums = |max: usize, i: &mut usize| -> Vec<f32> {
            let mut v = Vec::new();
            while v.len() < max && *i < args.len() && is_num(args[*i]) {
                v.push(args[*i].parse::<f32>().unwrap_or(0.0));
                *i += 1;
            }
            v
        };
        match opt.as_str() {
            "-o" => {
                let v = nums(3, &mut i);
                offset = [v.first().copied().unwrap_or(0.0), v.get(1).copied().unwrap_or(0.0)];
            }
            "-s" => {
                let v = nums(3, &mut i);
                scale = [v.first().copied().unwrap_or(1.0), v.get(1).copied().unwrap_or(1.0)];
            }
            "-t" => {
                nums(3, &mut i);
            }
            "-mm" => {
                nums(2, &mut i);
            }
            "-bm" => {
                if let Some(v) = nums(1, &mut i).first() {
                    spec.bump_multiplier = *v;
                }
            }
            "-clamp" => {
                if i < args.len() {
                    spec.clamp = args[i].eq_ignore_ascii_case("on");
                    i += 1;
                }
            }
            "-blendu" | "-blendv" | "-cc" | "-imfchan" | "-type" => i += 1,
            _ => {
                nums(3, &mut i);
            }
        }
    }
    // MTL's transform acts on OBJ coordinates (v up): u' = s·u + o. In ours
    // (v' = 1 − v) that is v' = s_v·v + (1 − s_v − o_v).
    spec.transform = UvTransform { offset: [offset[0], 1.0 - scale[1] - offset[1]], rotation_rad: 0.0, scale };
    spec.file = args[i.min(args.len())..].join(" ");
    spec
}

/// The error for a file a scene refers to that cannot be read as one
/// (`problem` begins with its path, which the error names).
fn referenced(path: &Path, problem: String) -> Error {
    let problem = problem.strip_prefix(&format!("{}: ", path.display())).unwrap_or(&problem).to_string();
    Error::scene(path, problem)
}

impl MtlLibrary {
    fn read(
        &mut self,
        path: &Path,
        limits: &LoadLimits,
        files: &mut Referenced,
        warnings: &mut Vec<String>,
    ) -> Result<()> {
        let extent = Extent::AtMost { bytes: super::MAX_MATERIAL_LIBRARY_BYTES, what: "material library" };
        let bytes = files.read(path, extent).map_err(|problem| referenced(path, problem))?;
        let text = text_of(path, &bytes)?;
        let dir = path.parent().map(Path::to_path_buf).unwrap_or_default();
        let file = file_name(path);
        let mut cur: Option<Material> = None;
        for (ln, line) in logical_lines(&text) {
            let toks: Vec<&str> = line.split_ascii_whitespace().collect();
            let Some((&kw_as_written, args)) = toks.split_first() else { continue };
            let kw = kw_as_written.to_ascii_lowercase();
            if kw == "newmtl" {
                if let Some(m) = cur.take() {
                    self.materials.insert(m.name.clone(), m);
                }
                cur = Some(Material { name: args.join(" "), ..Material::default() });
                continue;
            }
            let Some(m) = cur.as_mut() else { continue };
            let mname = m.name.clone();
            let mut rgb = |args: &[&str]| -> Result<Option<[f32; 3]>> {
                if args.first().is_some_and(|a| a.eq_ignore_ascii_case("spectral") || a.eq_ignore_ascii_case("xyz")) {
                    warnings.push(format!(
                        "{file}: material \"{mname}\": line {ln}: {kw_as_written} {} is not supported; ignored",
                        args[0]
                    ));
                    return Ok(None);
                }
                let v = numbers(path, ln, &format!("material \"{mname}\": {kw_as_written}"), args)?;
                Ok(match v.len() {
                    0 => None,
                    1 | 2 => Some([v[0] as f32; 3]),
                    _ => Some([v[0] as f32, v[1] as f32, v[2] as f32]),
                })
            };
            match kw.as_str() {
                "kd" => {
                    if let Some(c) = rgb(args)? {
                        m.base_colour = [c[0], c[1], c[2], m.base_colour[3]];
                    }
                }
                "ks" => {
                    if let Some(c) = rgb(args)? {
                        m.specular = c;
                    }
                }
                "ke" => {
                    if let Some(c) = rgb(args)? {
                        m.emissive = c;
                    }
                }
                "ns" => {
                    let v = numbers(path, ln, &format!("material \"{mname}\": Ns"), args)?;
                    if let Some(&n) = v.first() {
                        m.shininess = n as f32;
                    }
                }
                "map_kd" | "map_ke" | "norm" => {
                    let spec = parse_map(args);
                    let srgb = kw != "norm";
                    // A texture file that is missing is said and left out,
                    // as assimp and trimesh read such files.
                    let Some(t) =
                        self.texture(path, &dir, &mname, kw_as_written, &spec, srgb, limits, files, warnings)?
                    else {
                        continue;
                    };
                    let r = TextureRef { texture: t, uv_set: 0, transform: spec.transform };
                    match kw.as_str() {
                        "map_kd" => m.base_colour_texture = Some(r),
                        "map_ke" => {
                            if m.emissive == [0.0; 3] {
                                m.emissive = [1.0; 3];
                            }
                            m.emissive_texture = Some(r)
                        }
                        _ => {
                            m.normal_texture = Some(r);
                            m.normal_scale = spec.bump_multiplier;
                        }
                    }
                }
                "bump" | "map_bump" => warnings.push(format!(
                    "{file}: material \"{mname}\": the {kw_as_written} map is taken as a height map, which is not supported; ignored (use `norm` for a tangent-space normal map)"
                )),
                _ => {}
            }
        }
        if let Some(m) = cur.take() {
            self.materials.insert(m.name.clone(), m);
        }
        Ok(())
    }

    #[allow(clippy::too_many_arguments)]
    fn texture(
        &mut self,
        mtl: &Path,
        dir: &Path,
        material: &str,
        kw: &str,
        spec: &MapSpec,
        srgb: bool,
        limits: &LoadLimits,
        files: &mut Referenced,
        warnings: &mut Vec<String>,
    ) -> Result<Option<usize>> {
        let file = file_name(mtl);
        let name = spec.file.trim();
        let found = resolve_file(dir, name).or_else(|| {
            // Last resort for absolute paths from another machine
            // (`C:\Users\...\wood.png`): the file name in the MTL's folder.
            let base = name.rsplit(['/', '\\']).next().unwrap_or(name);
            let p = resolve_file(dir, base)?;
            warnings.push(format!(
                "{file}: material \"{material}\": {kw} texture \"{name}\" not found there; using \"{base}\" next to the material library"
            ));
            Some(p)
        });
        let Some(p) = found else {
            let folder = if dir.as_os_str().is_empty() { Path::new(".") } else { dir };
            warnings.push(format!(
                "{file}: material \"{material}\": {kw} texture \"{name}\" not found (looked in {}); drawn without it",
                folder.display()
            ));
            return Ok(None);
        };
        let wrap = if spec.clamp { [Wrap::ClampToEdge; 2] } else { [Wrap::Repeat; 2] };
        let key = (p.clone(), srgb, wrap.map(|w| w as u8));
        if let Some(&i) = self.cache.get(&key) {
            return Ok(Some(i));
        }
        let extent = Extent::AtMost { bytes: super::texture_file_bytes(limits), what: "texture" };
        let bytes = files.read(&p, extent).map_err(|problem| {
            Error::scene(mtl, format!("material \"{material}\": {kw} texture \"{name}\" cannot be read: {problem}"))
        })?;
        let t = decode(&bytes, &file_name(&p), srgb, wrap, limits)
            .map_err(|e| Error::scene(mtl, format!("material \"{material}\": {kw} texture \"{name}\" {e}")))?;
        self.textures.push(t);
        self.cache.insert(key, self.textures.len() - 1);
        Ok(Some(self.textures.len() - 1))
    }
}
