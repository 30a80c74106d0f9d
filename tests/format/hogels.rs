//! Hogels as pictures (`holo::hogels`, spec/hogels.md): named in raster
//! order, each picture its emitter's views with `+x` to the right and `+y`
//! at the top, and back: bit for bit where a sample is a code's value.

use std::path::Path;

use holo::format::{write, HoloFile, SampleType, WriteOptions};
use holo::geometry::{Geometry, Parallax, Views};
use holo::hogels::{
    export_hogels, export_hogels_file, hogel_file_names, import_hogels, read_hogel_manifest, MANIFEST, ORIENTATION,
};
use holo::picture::{srgb_encode, Bits, Tone, White};
use holo::pictures::{import_pictures_file, PictureSet};
use holo::progress::Silent;
use holo::views::ToneMapping;
use holo::Modulation;

/// 3 rows × 4 columns of emitters, 3 × 2 views (full parallax) or 3 views.
fn geometry(full: bool, rgb: bool) -> Geometry {
    let g = crate::full_parallax::geometry(3, 4, 3, 2, rgb);
    match full {
        true => g,
        false => Geometry { parallax: Parallax::Horizontal, vertical_views: None, ..g },
    }
}

/// Every sample a different 16-bit code's value at `tone`.
fn code_valued(g: Geometry, tone: &Tone) -> Modulation {
    let mut k: u64 = 0;
    Modulation::from_fn(g, |_, _, _, _| {
        k += 1;
        tone.sample(((k * 40503) % 65536) as u16)
    })
    .unwrap()
}

fn options(sample_type: SampleType) -> WriteOptions {
    WriteOptions { sample_type, ..WriteOptions::default() }
}

/// Export frame 0 of `file` as hogels into `dir` and import them into `back`, as f32.
fn round_trip(file: &Path, dir: &Path, back: &Path, white: White) -> (ToneMapping, Modulation) {
    let export = export_hogels_file(file, 0, dir, white, 16, false).unwrap();
    let manifest = read_hogel_manifest(&dir.join(MANIFEST)).unwrap();
    assert_eq!(manifest.tone, export.tone);
    let (g, tone) = (&manifest.geometry, &manifest.tone);
    import_pictures_file(PictureSet::Hogels, dir, g, tone, back, options(SampleType::F32), &Silent).unwrap();
    (export.tone, holo::read(back).unwrap())
}

#[test]
fn hogels_round_trip_bit_for_bit_at_16_bits_where_a_sample_is_a_code_s_value() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    for (full, rgb) in [(true, true), (true, false), (false, true)] {
        let white = 2.5;
        let m = code_valued(geometry(full, rgb), &Tone::new(white, Bits::Sixteen).unwrap());
        let name = format!("{full}-{rgb}");
        let file = d.join(format!("{name}.holo"));
        write(&file, &m, &options(SampleType::F32)).unwrap();
        let hogels = d.join(format!("{name}-hogels"));
        let (tone, back) = round_trip(&file, &hogels, &d.join(format!("{name}-back.holo")), White::Value(white));
        assert_eq!(tone, ToneMapping { white, bits: 16 });
        assert_eq!(back, m, "{name}");
    }
    // f16 samples, white at the largest: each within half a step of its
    // code, and the codes a fixed point: exported again, the same PNGs.
    let g = geometry(true, true);
    let m =
        Modulation::from_fn(g, |c, j, e, v| 0.013 + 0.37 * ((c * 31 + j * 17 + e * 7 + v * 3) % 23) as f32).unwrap();
    let file = d.join("f16.holo");
    write(&file, &m, &options(SampleType::F16)).unwrap();
    let stored = holo::read(&file).unwrap();
    let (tone, back) = round_trip(&file, &d.join("f16-hogels"), &d.join("f16-back.holo"), White::Max);
    assert_eq!(tone.white, stored.value_range().1);
    let e = |x: f32| srgb_encode(f64::from(x / tone.white));
    for (a, b) in stored.samples().iter().zip(back.samples()) {
        assert!((e(*a) - e(*b)).abs() <= 0.5 / 65535.0 + 1e-6, "{a} -> {b}");
    }
    export_hogels_file(&d.join("f16-back.holo"), 0, &d.join("again"), White::Value(tone.white), 16, false).unwrap();
    for name in hogel_file_names(stored.geometry()) {
        let (a, b) = (std::fs::read(d.join("f16-hogels").join(&name)), std::fs::read(d.join("again").join(&name)));
        assert_eq!(a.unwrap(), b.unwrap(), "{name}");
    }
}

#[test]
fn each_hogel_is_named_in_raster_order_and_shows_its_views_right_and_up() {
    let dir = tempfile::tempdir().unwrap();
    let g = geometry(true, false);
    let (v, w) = (g.views.count, g.vertical_view_count());
    // Sample (j, e, h, k) = a code that names all four.
    let tone = Tone::new(1.0, Bits::Sixteen).unwrap();
    let code = |j: usize, e: usize, h: usize, k: usize| (((j * 4 + e) * 3 + h) * 2 + k) as u16 * 100 + 7;
    let m = Modulation::from_fn(g.clone(), |_, j, e, view| {
        let (h, k) = g.view_of_index(view);
        tone.sample(code(j, e, h, k))
    })
    .unwrap();
    let written = export_hogels(&m, dir.path(), &ToneMapping { white: 1.0, bits: 16 }, false).unwrap();
    // Row 0 first, each row from the left; sorted names are that order.
    let names: Vec<String> = written.iter().map(|p| p.file_name().unwrap().to_string_lossy().into_owned()).collect();
    assert_eq!(names[0], "hogel_000_000.png");
    assert_eq!(names[1], "hogel_000_001.png");
    assert_eq!(names[4], "hogel_001_000.png");
    assert_eq!(names.last().unwrap(), MANIFEST);
    let mut sorted = names[..names.len() - 1].to_vec();
    sorted.sort();
    assert_eq!(sorted, names[..names.len() - 1]);
    // Hogel (1, 2): pixel column h is view h, the top row the highest vertical view.
    let png = std::fs::read(dir.path().join("hogel_001_002.png")).unwrap();
    let picture = holo::picture::decode::decode(std::io::Cursor::new(png)).unwrap();
    assert_eq!((picture.width, picture.channels), (v, 1));
    let grey = picture.grey16();
    for y in 0..w {
        for x in 0..v {
            assert_eq!(grey[y * v + x], code(1, 2, x, w - 1 - y), "pixel ({x}, {y})");
        }
    }
    let manifest = read_hogel_manifest(&dir.path().join(MANIFEST)).unwrap();
    assert_eq!((manifest.orientation.as_str(), manifest.files.len()), (ORIENTATION, 12));
    assert_eq!(import_hogels(dir.path(), &g, &manifest.tone).unwrap(), m);
}

#[test]
fn a_mixed_set_or_a_manifest_of_another_orientation_is_refused_naming_the_file() {
    let dir = tempfile::tempdir().unwrap();
    let g = geometry(true, true);
    let m = code_valued(g.clone(), &Tone::unit(Bits::Sixteen));
    let tone = ToneMapping::default();
    export_hogels(&m, dir.path(), &tone, false).unwrap();
    // Not replaced unless asked.
    let err = export_hogels(&m, dir.path(), &tone, false).unwrap_err().to_string();
    assert!(err.contains(MANIFEST), "{err}");
    std::fs::copy(dir.path().join("hogel_000_000.png"), dir.path().join("hogel_002_003.png")).unwrap();
    let err = import_hogels(dir.path(), &g, &tone).unwrap_err().to_string();
    assert!(err.contains("hogel_002_003.png"), "{err}");
    export_hogels(&m, dir.path(), &tone, true).unwrap();
    let path = dir.path().join(MANIFEST);
    let text = std::fs::read_to_string(&path).unwrap().replace(ORIENTATION, "x = W - 1 - k, y = h");
    std::fs::write(&path, text).unwrap();
    let err = import_hogels(dir.path(), &g, &tone).unwrap_err().to_string();
    assert!(err.contains(MANIFEST) && err.contains("x = W - 1 - k"), "{err}");
    // A picture of the wrong size says what the geometry needs.
    let other = dir.path().join("other");
    export_hogels(&m, &other, &tone, false).unwrap();
    std::fs::remove_file(other.join(MANIFEST)).unwrap();
    let mut wider = g.clone();
    wider.views = Views::tan_spaced(4, -0.25, 0.25);
    let err = import_hogels(&other, &wider, &tone).unwrap_err().to_string();
    assert!(err.contains("hogel_000_000.png") && err.contains("horizontal × vertical views = 4×2"), "{err}");
}

#[test]
fn a_bad_frame_or_tone_is_refused_before_a_folder_is_made() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("f.holo");
    write(&file, &code_valued(geometry(true, true), &Tone::unit(Bits::Sixteen)), &options(SampleType::F16)).unwrap();
    let out = dir.path().join("hogels");
    let err = export_hogels_file(&file, 3, &out, White::Value(1.0), 16, false).unwrap_err().to_string();
    assert!(err.contains("f.holo") && err.contains("frame"), "{err}");
    let err = export_hogels_file(&file, 0, &out, White::Value(1.0), 12, false).unwrap_err().to_string();
    assert!(err.contains("12 bits"), "{err}");
    assert!(!out.exists());
    // The input itself is no output, even with --force.
    assert!(export_hogels_file(&file, 0, &file, White::Max, 8, true).is_err());
    assert!(HoloFile::open(&file).is_ok());
}
