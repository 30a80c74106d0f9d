//! Bytes ⇄ structures for the HoloFlick container: the file-level chunks
//! (spec §5) and frames (§6), over the chunk layout of [`super::chunk`]. Pure functions over byte slices;
//! the reader and writer add files, offsets and the index around them.
//!
//! Every decoder here takes bytes it does not trust: each read is checked
//! against the bytes left, and every count against its limit and the bytes
//! left before anything is allocated for it.

use super::chunk::{is_critical, put_chunk, Cursor, CHUNK_HEADER};
use super::error::{invalid, Problem};
use super::model::*;
use super::*;

/// Refuse frame `frame` of `path` when its geometry once references are
/// resolved (its own blocks and those it takes from key frames) passes
/// [`MAX_RESOLVED_BYTES`]: the reader and the writer hold frames to the
/// same limit, so the writer cannot make a frame the reader refuses.
pub(crate) fn check_resolved_bytes(path: &std::path::Path, frame: u32, bytes: u64) -> Result<(), ContainerError> {
    if bytes > MAX_RESOLVED_BYTES {
        return Err(ContainerError::TooLarge {
            path: path.to_path_buf(),
            at: At(Some(frame)),
            what: "the geometry bytes of the resolved frame",
            value: bytes,
            limit: MAX_RESOLVED_BYTES,
        });
    }
    Ok(())
}

fn put_u32(out: &mut Vec<u8>, x: u32) {
    out.extend_from_slice(&x.to_le_bytes());
}

fn put_f64s(out: &mut Vec<u8>, xs: &[f64]) {
    for x in xs {
        out.extend_from_slice(&x.to_le_bytes());
    }
}

fn put_matrix(out: &mut Vec<u8>, m: &Matrix4) {
    for row in m {
        put_f64s(out, row);
    }
}

// ---- file-level chunks (spec §5) ----

/// The `HEAD` payload.
pub(crate) fn encode_head(frames_per_second: (u32, u32)) -> Vec<u8> {
    let mut p = Vec::with_capacity(HEAD_BYTES);
    put_u32(&mut p, frames_per_second.0);
    put_u32(&mut p, frames_per_second.1);
    for v in GEOMETRY_VERSION {
        put_u32(&mut p, v);
    }
    put_u32(&mut p, 0);
    p
}

/// Frame rate and geometry version from a `HEAD` payload.
pub(crate) fn decode_head(payload: &[u8]) -> Result<((u32, u32), [u32; 3]), Problem> {
    let mut c = Cursor::new(payload);
    let what = "the HEAD chunk";
    let fps = (c.u32(what)?, c.u32(what)?);
    let version = [c.u32(what)?, c.u32(what)?, c.u32(what)?];
    c.u32(what)?;
    if fps.0 == 0 || fps.1 == 0 {
        return Err(invalid(format!("frame rate {}/{} must have a non-zero numerator and denominator", fps.0, fps.1)));
    }
    Ok((fps, version))
}

/// The `text` payload: key, NUL, value.
pub(crate) fn encode_text(key: &str, value: &str) -> Vec<u8> {
    let mut p = Vec::with_capacity(key.len() + 1 + value.len());
    p.extend_from_slice(key.as_bytes());
    p.push(0);
    p.extend_from_slice(value.as_bytes());
    p
}

pub(crate) fn decode_text(payload: &[u8]) -> Result<(String, String), Problem> {
    if payload.len() as u64 > MAX_TEXT_BYTES {
        return Err(Problem::TooLarge { what: "a text chunk", value: payload.len() as u64, limit: MAX_TEXT_BYTES });
    }
    let nul = payload.iter().position(|&b| b == 0).ok_or_else(|| invalid("a text chunk has no NUL after its key"))?;
    let key = std::str::from_utf8(&payload[..nul]).map_err(|_| invalid("a text key is not UTF-8"))?;
    let value = std::str::from_utf8(&payload[nul + 1..]).map_err(|_| invalid(format!("text {key:?} is not UTF-8")))?;
    if let Some(p) = text_problem(key, value) {
        return Err(invalid(p));
    }
    Ok((key.to_string(), value.to_string()))
}

// ---- frames (spec §6) ----

/// The whole `FRAM` chunk of frame `number`, padding included, its `sums`
/// chunk first. The frame must have passed [`check_frame`].
pub(crate) fn encode_frame(number: u32, frame: &Frame) -> Vec<u8> {
    let mut head = Vec::with_capacity(8);
    put_u32(&mut head, number);
    put_u32(&mut head, frame.key_frame as u32);
    // The sub-chunks, and where each lies (for its checksum, spec §3.3).
    let mut p = Vec::new();
    let mut chunks = Vec::with_capacity(4 + frame.objects.len());
    let mut put = |p: &mut Vec<u8>, tag: [u8; 4], payload: &[u8]| {
        let start = p.len();
        put_chunk(p, tag, payload);
        chunks.push(start..start + CHUNK_HEADER + payload.len());
    };

    let mut q = Vec::with_capacity(COUCH_BYTES);
    put_f64s(&mut q, &frame.couch.min_m);
    put_f64s(&mut q, &frame.couch.max_m);
    put(&mut p, *b"COUC", &q);

    q.clear();
    put_u32(&mut q, frame.lights.len() as u32);
    put_u32(&mut q, LIGHT_RECORD as u32);
    for light in &frame.lights {
        let (kind, vector, colour) = match light {
            SpecularLight::Directional { direction, irradiance } => (1, direction, irradiance),
            SpecularLight::Point { position_m, intensity } => (2, position_m, intensity),
        };
        put_u32(&mut q, kind);
        put_u32(&mut q, 0);
        put_f64s(&mut q, vector);
        put_f64s(&mut q, colour);
    }
    put(&mut p, *b"LGHT", &q);

    q.clear();
    put_u32(&mut q, frame.materials.len() as u32);
    put_u32(&mut q, MATERIAL_RECORD as u32);
    for m in &frame.materials {
        put_u32(&mut q, model_code(m.model));
        put_u32(&mut q, 0);
        put_f64s(&mut q, &m.specular);
        put_f64s(&mut q, &[m.exponent]);
    }
    put(&mut p, *b"MATL", &q);

    q.clear();
    put_u32(&mut q, frame.bindings.len() as u32);
    put_u32(&mut q, 0);
    for b in &frame.bindings {
        put_u32(&mut q, b.object_id);
        put_u32(&mut q, b.material);
        put_u32(&mut q, b.lights.len() as u32);
        for &l in &b.lights {
            put_u32(&mut q, l);
        }
    }
    put(&mut p, *b"BIND", &q);

    for object in &frame.objects {
        q.clear();
        match object {
            ObjectRecord::Stored(o) => {
                put_u32(&mut q, o.id);
                put_u32(&mut q, GEOM_HEADER as u32);
                put_f64s(&mut q, &[o.radiance_scale]);
                put_matrix(&mut q, &o.world_from_object);
                q.extend_from_slice(o.block.cg_record());
                put(&mut p, *b"GEOM", &q);
            }
            ObjectRecord::Reference(r) => {
                put_u32(&mut q, r.id);
                put_u32(&mut q, r.key_frame);
                put_matrix(&mut q, &r.world_from_object);
                put(&mut p, *b"KREF", &q);
            }
        }
    }
    let payload = super::checksum::seal_frame(&head, &p, &chunks);
    let mut out = Vec::with_capacity(CHUNK_HEADER + payload.len());
    put_chunk(&mut out, *b"FRAM", &payload);
    out
}

fn model_code(m: SpecularModel) -> u32 {
    match m {
        SpecularModel::Phong => 1,
        SpecularModel::Blinn => 2,
    }
}

/// The frame number, flags and sub-chunks of a `FRAM` chunk (`chunk` is the
/// whole chunk as the index locates it, padding excluded).
pub(crate) fn decode_frame(chunk: &[u8]) -> Result<(u32, Frame), Problem> {
    let mut outer = Cursor::new(chunk);
    let tag: [u8; 4] = outer.array("the frame's chunk header")?;
    if &tag != b"FRAM" {
        return Err(invalid(format!(
            "the index points at a {:?} chunk, not a FRAM chunk",
            super::error::tag_text(tag)
        )));
    }
    let len = outer.u32("the frame's chunk header")? as usize;
    if len != outer.remaining() {
        return Err(invalid(format!("the FRAM chunk says {len} payload bytes, the index {} bytes", outer.remaining())));
    }
    if len % 8 != 0 {
        return Err(invalid(format!("the FRAM payload is {len} bytes, not a multiple of 8")));
    }
    let mut c = Cursor::new(outer.take(len, "the frame")?);
    let number = c.u32("the frame header")?;
    let flags = c.u32("the frame header")?;
    let mut frame = Frame {
        key_frame: flags & 1 != 0,
        couch: ViewerCouch { min_m: [0.0; 3], max_m: [0.0; 3] },
        lights: Vec::new(),
        materials: Vec::new(),
        bindings: Vec::new(),
        objects: Vec::new(),
    };
    const ORDER: [&[u8; 4]; 4] = [b"COUC", b"LGHT", b"MATL", b"BIND"];
    let mut stage = 0;
    while let Some((tag, payload)) = c.chunk()? {
        let known = ORDER.iter().position(|t| **t == tag);
        if let Some(k) = known {
            if k != stage {
                return Err(invalid(format!(
                    "chunk {} found where {} was expected (order: COUC, LGHT, MATL, BIND, objects)",
                    super::error::tag_text(tag),
                    if stage < 4 { super::error::tag_text(*ORDER[stage]) } else { "an object".into() }
                )));
            }
            stage += 1;
        }
        match &tag {
            b"COUC" => {
                let mut q = Cursor::new(payload);
                frame.couch = ViewerCouch { min_m: q.vec3("the COUC chunk")?, max_m: q.vec3("the COUC chunk")? };
            }
            b"LGHT" => frame.lights = decode_lights(payload)?,
            b"MATL" => frame.materials = decode_materials(payload)?,
            b"BIND" => frame.bindings = decode_bindings(payload)?,
            b"GEOM" | b"KREF" => {
                if stage < 4 {
                    return Err(invalid(format!(
                        "object chunk {} before the {} chunk",
                        super::error::tag_text(tag),
                        super::error::tag_text(*ORDER[stage])
                    )));
                }
                Problem::at_most("the number of objects", frame.objects.len() as u64 + 1, MAX_OBJECTS)?;
                let object =
                    if &tag == b"GEOM" { ObjectRecord::Stored(decode_geom(payload)?) } else { decode_kref(payload)? };
                frame.objects.push(object);
            }
            _ if is_critical(tag) => return Err(Problem::UnknownChunk(tag)),
            _ => {}
        }
    }
    if stage < 4 {
        return Err(invalid(format!("the frame has no {} chunk", super::error::tag_text(*ORDER[stage]))));
    }
    Ok((number, frame))
}

/// Count and record size of a list chunk, checked against the bytes present.
fn list<'a>(payload: &'a [u8], name: &str, limit: u64, known: usize) -> Result<(Vec<&'a [u8]>, usize), Problem> {
    let mut c = Cursor::new(payload);
    let what = format!("the {name} chunk");
    let count = c.u32(&what)? as u64;
    let size = c.u32(&what)? as usize;
    if count > limit {
        return Err(Problem::TooLarge {
            what: if name == "LGHT" { "the number of lights" } else { "the number of materials" },
            value: count,
            limit,
        });
    }
    if size < known || size % 8 != 0 {
        return Err(invalid(format!("{name} records of {size} bytes; at least {known} and a multiple of 8 needed")));
    }
    if count * size as u64 != c.remaining() as u64 {
        return Err(Problem::Truncated(format!(
            "{name} declares {count} records of {size} bytes, {} bytes present",
            c.remaining()
        )));
    }
    let records = (0..count).map(|_| c.take(size, &what)).collect::<Result<Vec<_>, _>>()?;
    Ok((records, size))
}

fn decode_lights(payload: &[u8]) -> Result<Vec<SpecularLight>, Problem> {
    decode_records(payload, "LGHT", MAX_LIGHTS, LIGHT_RECORD, |i, c| {
        let what = "a light";
        let kind = c.u32(what)?;
        c.u32(what)?;
        let (vector, colour) = (c.vec3(what)?, c.vec3(what)?);
        match kind {
            1 => Ok(SpecularLight::Directional { direction: vector, irradiance: colour }),
            2 => Ok(SpecularLight::Point { position_m: vector, intensity: colour }),
            k => Err(invalid(format!("light {i} has kind {k}; 1 (directional) and 2 (point) are defined"))),
        }
    })
}

fn decode_materials(payload: &[u8]) -> Result<Vec<SpecularMaterial>, Problem> {
    decode_records(payload, "MATL", MAX_MATERIALS, MATERIAL_RECORD, |i, c| {
        let what = "a material";
        let model = match c.u32(what)? {
            1 => SpecularModel::Phong,
            2 => SpecularModel::Blinn,
            k => return Err(invalid(format!("material {i} has model {k}; 1 (Phong) and 2 (Blinn) are defined"))),
        };
        c.u32(what)?;
        Ok(SpecularMaterial { specular: c.vec3(what)?, exponent: c.f64(what)?, model })
    })
}

/// The records of a list chunk, each decoded by `record(index, cursor)` from
/// its first `known` bytes (a later minor version may append fields).
fn decode_records<T>(
    payload: &[u8],
    name: &str,
    limit: u64,
    known: usize,
    record: impl Fn(usize, &mut Cursor) -> Result<T, Problem>,
) -> Result<Vec<T>, Problem> {
    let (records, _) = list(payload, name, limit, known)?;
    records.into_iter().enumerate().map(|(i, r)| record(i, &mut Cursor::new(r))).collect()
}

fn decode_bindings(payload: &[u8]) -> Result<Vec<Binding>, Problem> {
    let mut c = Cursor::new(payload);
    let what = "the BIND chunk";
    let count = c.u32(what)? as u64;
    c.u32(what)?;
    Problem::at_most("the number of bindings", count, MAX_OBJECTS)?;
    // Each binding takes at least 12 bytes.
    if count * 12 > c.remaining() as u64 {
        return Err(Problem::Truncated(format!("BIND declares {count} bindings, {} bytes present", c.remaining())));
    }
    let mut bindings = Vec::with_capacity(count as usize);
    for _ in 0..count {
        let object_id = c.u32(what)?;
        let material = c.u32(what)?;
        let n = c.u32(what)? as u64;
        Problem::at_most("the lights of a binding", n, MAX_LIGHTS)?;
        if n * 4 > c.remaining() as u64 {
            return Err(Problem::Truncated(format!(
                "a binding of object {object_id} lists {n} lights, {} bytes present",
                c.remaining()
            )));
        }
        let lights = (0..n).map(|_| c.u32(what)).collect::<Result<Vec<_>, _>>()?;
        bindings.push(Binding { object_id, material, lights });
    }
    if c.remaining() != 0 {
        return Err(invalid(format!("{} bytes after the last binding", c.remaining())));
    }
    Ok(bindings)
}

fn decode_geom(payload: &[u8]) -> Result<GeometryObject, Problem> {
    let mut c = Cursor::new(payload);
    let what = "a GEOM chunk";
    let id = c.u32(what)?;
    let header = c.u32(what)? as usize;
    let radiance_scale = c.f64(what)?;
    let world_from_object = c.matrix(what)?;
    if header < GEOM_HEADER || header % 8 != 0 || header > payload.len() {
        return Err(invalid(format!(
            "object {id}: geometry block offset {header} (at least {GEOM_HEADER}, a multiple of 8, inside the {}-byte chunk)",
            payload.len()
        )));
    }
    let block = GeometryBlock::from_cg_record(&payload[header..]).map_err(|e| invalid(format!("object {id}: {e}")))?;
    Ok(GeometryObject { id, world_from_object, radiance_scale, block })
}

fn decode_kref(payload: &[u8]) -> Result<ObjectRecord, Problem> {
    let mut c = Cursor::new(payload);
    let what = "a KREF chunk";
    Ok(ObjectRecord::Reference(KeyFrameReference {
        id: c.u32(what)?,
        key_frame: c.u32(what)?,
        world_from_object: c.matrix(what)?,
    }))
}

// ---- rules on a decoded frame (spec §6.7) ----

fn finite(xs: &[f64]) -> bool {
    xs.iter().all(|x| x.is_finite())
}

/// Every rule of spec §6 that a frame alone can break (references are
/// resolved by the reader, checked against key frames by the writer).
pub(crate) fn check_frame(number: u32, frame: &Frame) -> Result<(), Problem> {
    let limit = |what, value: usize, limit: u64| Problem::at_most(what, value as u64, limit);
    limit("the number of objects", frame.objects.len(), MAX_OBJECTS)?;
    limit("the number of lights", frame.lights.len(), MAX_LIGHTS)?;
    limit("the number of materials", frame.materials.len(), MAX_MATERIALS)?;
    limit("the number of bindings", frame.bindings.len(), MAX_OBJECTS)?;

    let ViewerCouch { min_m, max_m } = frame.couch;
    if !finite(&min_m) || !finite(&max_m) || (0..3).any(|k| min_m[k] > max_m[k]) {
        return Err(invalid(format!("viewer's couch {min_m:?}–{max_m:?} m is not a finite box with min ≤ max")));
    }
    for (i, light) in frame.lights.iter().enumerate() {
        let (vector, colour) = match light {
            SpecularLight::Directional { direction, irradiance } => {
                let len = crate::math::length(*direction);
                if (len - 1.0).abs().is_nan() || (len - 1.0).abs() > UNIT_TOLERANCE {
                    return Err(invalid(format!("light {i}: direction {direction:?} is not of unit length")));
                }
                (direction, irradiance)
            }
            SpecularLight::Point { position_m, intensity } => (position_m, intensity),
        };
        if !finite(vector) || !finite(colour) || colour.iter().any(|&x| x < 0.0) {
            return Err(invalid(format!("light {i}: values must be finite and its colour not negative")));
        }
    }
    for (i, m) in frame.materials.iter().enumerate() {
        if !finite(&m.specular) || m.specular.iter().any(|&x| x < 0.0) || !(m.exponent.is_finite() && m.exponent >= 0.0)
        {
            return Err(invalid(format!(
                "material {i}: specular {:?} and exponent {} must be finite and not negative",
                m.specular, m.exponent
            )));
        }
    }
    let mut ids = std::collections::HashSet::with_capacity(frame.objects.len());
    for object in &frame.objects {
        let id = object.id();
        if !ids.insert(id) {
            return Err(invalid(format!("object id {id} appears twice")));
        }
        if let Some(p) = transform_problem(object.world_from_object()) {
            return Err(invalid(format!("object {id}: {p}")));
        }
        match object {
            ObjectRecord::Stored(o) => {
                if !(o.radiance_scale.is_finite() && o.radiance_scale > 0.0) {
                    return Err(invalid(format!(
                        "object {id}: radiance scale {} must be finite and positive",
                        o.radiance_scale
                    )));
                }
            }
            ObjectRecord::Reference(r) => {
                if frame.key_frame {
                    return Err(invalid(format!(
                        "object {id}: a key frame holds no references, but it refers to frame {}",
                        r.key_frame
                    )));
                }
                if r.key_frame >= number {
                    return Err(invalid(format!(
                        "object {id} refers to frame {}, which is not earlier than this frame",
                        r.key_frame
                    )));
                }
            }
        }
    }
    let mut bound = std::collections::HashSet::with_capacity(frame.bindings.len());
    for b in &frame.bindings {
        if !ids.contains(&b.object_id) {
            return Err(invalid(format!("a binding names object {}, which the frame does not hold", b.object_id)));
        }
        if !bound.insert(b.object_id) {
            return Err(invalid(format!("object {} has two bindings", b.object_id)));
        }
        if b.material as usize >= frame.materials.len() {
            return Err(invalid(format!(
                "the binding of object {} names material {} of {}",
                b.object_id,
                b.material,
                frame.materials.len()
            )));
        }
        let mut seen = std::collections::HashSet::with_capacity(b.lights.len());
        for &l in &b.lights {
            if l as usize >= frame.lights.len() || !seen.insert(l) {
                return Err(invalid(format!(
                    "the binding of object {} names light {l} (of {}) out of range or twice",
                    b.object_id,
                    frame.lights.len()
                )));
            }
        }
    }
    Ok(())
}

/// Why a transform is not a finite, invertible affine map (spec §6.4).
pub(crate) fn transform_problem(m: &Matrix4) -> Option<String> {
    if !m.iter().all(|row| finite(row)) {
        return Some("the transform has a non-finite entry".into());
    }
    if m[3] != [0.0, 0.0, 0.0, 1.0] {
        return Some(format!("the transform's last row is {:?}, not [0, 0, 0, 1]", m[3]));
    }
    let det = m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
        + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
    if det == 0.0 || !det.is_finite() {
        return Some("the transform is not invertible".into());
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::holoflick::container::chunk::padding;

    fn frame() -> Frame {
        Frame {
            key_frame: false,
            couch: ViewerCouch { min_m: [-1.0; 3], max_m: [1.0; 3] },
            lights: vec![SpecularLight::Point { position_m: [0.0, 1.0, 0.0], intensity: [1.0; 3] }],
            materials: vec![SpecularMaterial { specular: [0.5; 3], exponent: 10.0, model: SpecularModel::Phong }],
            bindings: vec![Binding { object_id: 7, material: 0, lights: vec![0] }],
            objects: vec![ObjectRecord::Reference(KeyFrameReference {
                id: 7,
                key_frame: 0,
                world_from_object: IDENTITY,
            })],
        }
    }

    #[test]
    fn frames_round_trip_and_skip_unknown_ancillary_chunks() {
        let f = frame();
        check_frame(3, &f).unwrap();
        let bytes = encode_frame(3, &f);
        assert_eq!(decode_frame(&bytes).unwrap(), (3, f.clone()));

        // Insert an unknown ancillary sub-chunk after COUC and fix the FRAM
        // length (the checksums are not this decoder's business).
        let mut payload = bytes[8..16].to_vec();
        let mut rest = Cursor::new(&bytes[16..]);
        let (tag, sums) = rest.chunk().unwrap().unwrap();
        assert_eq!(tag, *b"sums");
        let (tag, couc) = rest.chunk().unwrap().unwrap();
        assert_eq!(tag, *b"COUC");
        put_chunk(&mut payload, tag, couc);
        put_chunk(&mut payload, *b"zzzz", b"from a later minor version");
        let after = 16 + 8 + sums.len() + padding(sums.len() as u64) as usize + 8 + couc.len();
        payload.extend_from_slice(&bytes[after..]);
        let mut longer = Vec::new();
        put_chunk(&mut longer, *b"FRAM", &payload);
        assert_eq!(decode_frame(&longer).unwrap(), (3, f));

        // The same chunk marked critical is refused by name.
        let critical = [b'Z', b'z', b'z', b'z'];
        let at = longer.windows(4).position(|w| w == b"zzzz").unwrap();
        longer[at..at + 4].copy_from_slice(&critical);
        assert_eq!(decode_frame(&longer).unwrap_err(), Problem::UnknownChunk(critical));
    }

    #[test]
    fn transforms_must_be_affine_and_invertible() {
        assert!(transform_problem(&IDENTITY).is_none());
        let mut m = IDENTITY;
        m[3][2] = 0.1;
        assert!(transform_problem(&m).unwrap().contains("last row"));
        let mut m = IDENTITY;
        m[1] = [0.0, 0.0, 0.0, 5.0];
        assert!(transform_problem(&m).unwrap().contains("not invertible"));
        let mut m = IDENTITY;
        m[0][3] = f64::INFINITY;
        assert!(transform_problem(&m).unwrap().contains("non-finite"));
    }
}
