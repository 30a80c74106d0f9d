//! What a calibrated camera would have photographed of a mesh scene: the
//! ground truth of camera-array conversion, where pictures of a scene taken by a camera
//! array are converted to modulation and compared with converting the mesh
//! directly.
//!
//! The scene's coordinates are the camera's world coordinates, in metres.
//! Every pixel is ray cast through a bounding-volume hierarchy (`bvh.rs`) in f64 from the camera's
//! centre, box-filtered over `n × n` sub-pixel positions
//! `u + (a + ½)/n − ½`, `v + (b + ½)/n − ½`. Visibility and shading are
//! those of the display's reference renderer ([`crate::mesh::trace`]): the
//! surfaces in front of the camera that face it (or are double-sided) are
//! seen nearest first, each sending [`crate::mesh::shade::radiance`] with the view vector
//! pointing from the surface toward the camera, until an opaque one ends
//! the ray (see [`crate::mesh::Material::alpha_mode`]). A camera on the display's viewer line
//! therefore sees along each ray exactly what the display stores for it.

use std::io::Write;
use std::path::Path;

use rayon::prelude::*;

use super::Camera;
use crate::error::{Error, Result};
use crate::math::{dot, scale};
use crate::mesh::bvh::{Bvh, Triangle};
use crate::mesh::shade::Lighting;
use crate::mesh::trace::along_ray;
use crate::mesh::Scene;
use crate::picture::{encode_png, Bits, Colour, Tone};

/// A rendered camera picture, row by row from the top (pixel `(u, v)` at
/// index `v · width + u`).
#[derive(Clone, Debug, PartialEq)]
pub struct CameraPicture {
    /// Width in pixels.
    pub width: usize,
    /// Height in pixels.
    pub height: usize,
    /// Linear RGB radiance, box-filtered over the pixel (0 where nothing is seen).
    pub rgb: Vec<[f32; 3]>,
    /// Camera `z` (distance along the viewing direction, metres) of the
    /// visible point on the ray through the pixel's centre (the nearest, where
    /// see-through surfaces show several);
    /// `f32::INFINITY` where that ray meets nothing.
    pub depth_z: Vec<f32>,
}

/// The largest sub-pixel grid per axis.
const MAX_SAMPLES_PER_AXIS: usize = 64;

/// Render what `camera` sees of `scene` (camera world = scene coordinates,
/// metres) under exactly `lighting` (the scene's own lights are not added:
/// [`crate::mesh::render::RenderOptions::lighting_for`] gives those a render of
/// the scene uses), with `samples_per_pixel_axis²` rays per pixel.
pub fn camera_picture(
    scene: &Scene,
    lighting: &Lighting,
    camera: &Camera,
    samples_per_pixel_axis: usize,
) -> Result<CameraPicture> {
    let n = samples_per_pixel_axis;
    if n == 0 || n > MAX_SAMPLES_PER_AXIS {
        return Err(Error::argument(
            "samples per pixel",
            format!(
                "camera {}: {n} samples per pixel axis is out of range: choose 1 to {MAX_SAMPLES_PER_AXIS}",
                camera.name
            ),
        ));
    }
    if let Some(problem) = camera.problem() {
        return Err(Error::argument("camera", problem));
    }
    if let Some(problem) = scene.problem() {
        return Err(Error::scene(&scene.source, problem));
    }
    if let Some(bad) = lighting.lights.iter().find(|l| !crate::mesh::render::light_is_finite(l)) {
        return Err(Error::argument("lights", format!("a light is not finite or has a negative brightness: {bad:?}")));
    }
    if let Some(problem) = lighting.problem_with(scene) {
        return Err(Error::scene(&scene.source, problem));
    }
    let (width, height) = (camera.width, camera.height);
    // Each pixel holds 16 bytes (colour and depth).
    if width.checked_mul(height).map_or(true, |n| n > isize::MAX as usize / 16) {
        return Err(Error::argument(
            "picture size",
            format!("camera {}: {width}×{height} pixels do not fit in memory", camera.name),
        ));
    }
    let tracer = CameraTracer { scene, lighting, bvh: Bvh::new(scene), camera };
    let norm = 1.0 / (n * n) as f64;
    let rows: Vec<(Vec<[f32; 3]>, Vec<f32>)> = (0..height)
        .into_par_iter()
        .map(|v| {
            let mut rgb = Vec::with_capacity(width);
            let mut depth = Vec::with_capacity(width);
            for u in 0..width {
                let mut sum = [0.0f64; 3];
                for b in 0..n {
                    let sv = v as f64 + (b as f64 + 0.5) / n as f64 - 0.5;
                    for a in 0..n {
                        let su = u as f64 + (a as f64 + 0.5) / n as f64 - 0.5;
                        if let Some((l, _)) = tracer.trace(su, sv) {
                            for c in 0..3 {
                                sum[c] += l[c];
                            }
                        }
                    }
                }
                rgb.push(sum.map(|s| (s * norm) as f32));
                depth.push(tracer.trace(u as f64, v as f64).map_or(f32::INFINITY, |(_, z)| z as f32));
            }
            (rgb, depth)
        })
        .collect();
    let mut pic = CameraPicture {
        width,
        height,
        rgb: Vec::with_capacity(width * height),
        depth_z: Vec::with_capacity(width * height),
    };
    for (rgb, depth) in rows {
        pic.rgb.extend(rgb);
        pic.depth_z.extend(depth);
    }
    Ok(pic)
}

struct CameraTracer<'a> {
    scene: &'a Scene,
    lighting: &'a Lighting,
    bvh: Bvh,
    camera: &'a Camera,
}

impl CameraTracer<'_> {
    /// Radiance along the ray through pixel `(u, v)` and the camera `z` of
    /// the point seen, or `None` when the ray meets nothing.
    fn trace(&self, u: f64, v: f64) -> Option<([f64; 3], f64)> {
        let r = self.camera.ray(u, v);
        let scene = self.scene;
        // The light travels along −r, toward the camera: a front face has its
        // normal against r (the display's test `n·d > 0` with d = −r).
        let shown = |tri: &Triangle, n| scene.objects[tri.object as usize].material.double_sided || dot(n, r) < 0.0;
        let (l, t) = along_ray(scene, self.lighting, &self.bvh, self.camera.pose.centre, r, scale(r, -1.0), shown)?;
        Some((l, t * dot(r, self.camera.axis())))
    }
}

/// Write a camera picture as a 16-bit sRGB PNG (tone-mapped as every
/// picture is, [`crate::picture`], at exposure 1: radiance 1 is white) and,
/// if asked, its depth as a grey PFM (camera `z` in metres, infinity where
/// nothing was seen). Each file is written whole through a temporary file
/// and replaces an existing file of that name.
pub fn write_camera_picture(pic: &CameraPicture, png_path: &Path, pfm_depth_path: Option<&Path>) -> Result<()> {
    let n = pic.width * pic.height;
    if pic.rgb.len() != n || pic.depth_z.len() != n || n == 0 {
        return Err(Error::argument(
            "picture",
            format!(
                "{}: the picture is inconsistent: {}×{} pixels, {} colours, {} depths",
                png_path.display(),
                pic.width,
                pic.height,
                pic.rgb.len(),
                pic.depth_z.len()
            ),
        ));
    }
    let tone = Tone::unit(Bits::Sixteen);
    let png = encode_png(pic.width, pic.height, Colour::Rgb, &tone, None, |x, y| pic.rgb[y * pic.width + x])
        .map_err(|e| e.naming(png_path))?;
    crate::output::write_bytes_beside(png_path, &png, true)?;
    if let Some(path) = pfm_depth_path {
        write_pfm_grey(path, pic.width, pic.height, &pic.depth_z)?;
    }
    Ok(())
}

/// A grey PFM (`Pf`): header, scale −1 (little-endian), then the rows from
/// the bottom of the picture to the top, as the format requires. `values`
/// are row by row from the top.
fn write_pfm_grey(path: &Path, width: usize, height: usize, values: &[f32]) -> Result<()> {
    crate::output::write_atomically(path, true, |out| {
        let io = |e| Error::io(path, e);
        write!(out, "Pf\n{width} {height}\n-1.0\n").map_err(io)?;
        for row in values.chunks_exact(width).rev() {
            for x in row {
                out.write_all(&x.to_le_bytes()).map_err(io)?;
            }
        }
        Ok(())
    })?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cameras::{look_rotation, ImageSource, Intrinsics, Pose};
    use crate::geometry::{channel_weights, rgb_channels, Geometry, Views};
    use crate::mesh::rays::{Rays, Shading, Supersample};
    use crate::mesh::shade::SpecularModel;
    use crate::mesh::trace::{eye_picture, TraceRenderer};
    use crate::mesh::{Light, Material, Object};

    /// 12 hololines of 1 mm, 20 emitters of 1 mm, 16 views over ±15°,
    /// emitter plane 10 mm in front of the hologram, viewer at 400 mm.
    fn geometry() -> Geometry {
        let mut g = Geometry::centred(
            12,
            20,
            Views::tan_spaced(16, -15f64.to_radians(), 15f64.to_radians()),
            1e-3,
            1e-3,
            0.010,
            0.400,
            rgb_channels(),
        );
        g.viewer_height_m = 0.004;
        g
    }

    /// A camera at `(x, y_v, D)` on the viewer line looking toward −z whose
    /// pixel `(e, j)` is the ray through emitter `e` of hololine `j`.
    fn display_camera(g: &Geometry, x: f64) -> Camera {
        let span = g.viewer_distance_m - g.emitter_z_m;
        Camera {
            name: "on the viewer line".into(),
            image: ImageSource::File("unused.png".into()),
            width: g.emitters,
            height: g.hololines,
            intrinsics: Intrinsics {
                fx: span / g.emitter_pitch_m,
                fy: span / g.hololine_pitch_m,
                cx: (x - g.emitter_left_x_m) / g.emitter_pitch_m,
                cy: (g.hololine_top_y_m - g.viewer_height_m) / g.hololine_pitch_m,
            },
            pose: Pose {
                rotation: look_rotation([0.0, 0.0, -1.0], [0.0, -1.0, 0.0]),
                centre: [x, g.viewer_height_m, g.viewer_distance_m],
            },
            depth: None,
        }
    }

    /// A rectangle `[x0, x1] × [y0, y1]` at `z`, facing +z (the viewer).
    fn quad(name: &str, x: [f64; 2], y: [f64; 2], z: f64, material: Material) -> Object {
        Object {
            name: name.into(),
            positions: vec![[x[0], y[0], z], [x[1], y[0], z], [x[1], y[1], z], [x[0], y[1], z]],
            triangles: vec![[0, 1, 2], [0, 2, 3]],
            material,
            ..Object::default()
        }
    }

    fn emissive(rgb: [f32; 3]) -> Material {
        Material { base_colour: [0.0, 0.0, 0.0, 1.0], specular: [0.0; 3], emissive: rgb, ..Material::default() }
    }

    fn scene(objects: Vec<Object>) -> Scene {
        Scene { source: "test scene".into(), objects, ..Scene::default() }
    }

    fn lit() -> Lighting {
        Lighting {
            lights: vec![
                Light::Directional {
                    direction: crate::math::normalize([0.4, -0.5, -1.0]),
                    irradiance: [3.0, 2.5, 2.0],
                    name: "key".into(),
                },
                Light::Point { position: [0.02, 0.03, 0.1], intensity: [0.01, 0.012, 0.008], name: "point".into() },
                Light::Ambient { radiance: [0.05; 3] },
            ],
            model: SpecularModel::Blinn,
        }
    }

    /// A tilted, shiny, vertex-coloured surface: its radiance depends on the
    /// view vector, so agreeing with the display's renderer tests that the
    /// same vector is used.
    fn shiny_scene() -> Scene {
        let mut o = quad(
            "shiny",
            [-0.015, 0.015],
            [-0.01, 0.012],
            0.0,
            Material { base_colour: [0.6, 0.4, 0.3, 1.0], specular: [0.5; 3], shininess: 40.0, ..Material::default() },
        );
        // Tilt it: z varies with x and y.
        for p in &mut o.positions {
            p[2] = 0.3 * p[0] - 0.2 * p[1];
        }
        o.colours = vec![[1.0, 0.5, 0.5, 1.0], [0.5, 1.0, 0.5, 1.0], [0.5, 0.5, 1.0, 1.0], [1.0, 1.0, 1.0, 1.0]];
        scene(vec![o])
    }

    fn rel(a: f64, b: f64) -> f64 {
        (a - b).abs() / a.abs().max(b.abs()).max(1e-30)
    }

    #[test]
    fn a_camera_on_the_viewer_line_sees_what_the_display_renderer_stores() {
        let g = geometry();
        let s = shiny_scene();
        let lighting = lit();
        for eye_x in [0.0, 0.031, -0.052] {
            let cam = display_camera(&g, eye_x);
            let pic = camera_picture(&s, &lighting, &cam, 1).unwrap();
            let eye = eye_picture(&s, &lighting, &g, eye_x, 0.0, 1).unwrap();
            let mut seen = 0;
            for j in 0..g.hololines {
                for e in 0..g.emitters {
                    for c in 0..3 {
                        let want = eye[(j * g.emitters + e) * 3 + c] as f64;
                        let got = pic.rgb[j * g.emitters + e][c] as f64;
                        assert!(rel(got, want) < 1e-6, "eye {eye_x} j {j} e {e} c {c}: {got} vs {want}");
                        seen += usize::from(want > 0.0);
                    }
                }
            }
            assert!(seen > g.hololines * g.emitters, "the surface fills most of the picture ({seen})");
        }
        // The same through TraceRenderer::trace, in f64, for one ray per view.
        let rays = Rays::new(&g, Supersample::new(1, 1)).unwrap();
        let weights = channel_weights(&["R", "G", "B"]);
        let tracer = TraceRenderer::new(Shading {
            scene: &s,
            lighting: &lighting,
            weights: &weights,
            rays: &rays,
            geometry: &g,
        });
        let span = g.viewer_distance_m - g.emitter_z_m;
        for (j, e, v) in [(3, 7, 0), (6, 10, 8), (9, 15, 15)] {
            let slope = rays.sub_view_slope[v];
            let x = g.emitter_x_m(e);
            let cam = display_camera(&g, x + slope * span);
            let want = tracer.trace(x, rays.hololine_y_m[j], slope, rays.hololine_slope[j]).unwrap();
            let got = CameraTracer { scene: &s, lighting: &lighting, bvh: Bvh::new(&s), camera: &cam }
                .trace(e as f64, j as f64)
                .unwrap()
                .0;
            for c in 0..3 {
                assert!(rel(got[c], want[c]) < 1e-9, "{j} {e} {v}: {got:?} vs {want:?}");
            }
        }
    }

    #[test]
    fn an_emissive_square_lands_where_projection_puts_it_at_its_depth() {
        let g = geometry();
        let z = -0.02;
        let glow = [0.8, 0.5, 0.25];
        let s = scene(vec![quad("square", [-0.0042, 0.0031], [-0.0023, 0.0027], z, emissive(glow))]);
        let cam = display_camera(&g, 0.017);
        let pic = camera_picture(&s, &Lighting { lights: vec![], model: SpecularModel::Blinn }, &cam, 3).unwrap();
        let (lo, _) = cam.project([-0.0042, -0.0023, z]).unwrap();
        let (hi, _) = cam.project([0.0031, 0.0027, z]).unwrap();
        // Picture y runs down: the square's top (y = 0.0027) is at the smaller v.
        let (u0, u1, v0, v1) = (lo[0], hi[0], hi[1], lo[1]);
        let (mut inside, mut outside) = (0, 0);
        for v in 0..pic.height {
            for u in 0..pic.width {
                let (uf, vf) = (u as f64, v as f64);
                let i = v * pic.width + u;
                if uf > u0 + 0.5 && uf < u1 - 0.5 && vf > v0 + 0.5 && vf < v1 - 0.5 {
                    inside += 1;
                    for (got, want) in pic.rgb[i].iter().zip(glow) {
                        assert!(rel(f64::from(*got), f64::from(want)) < 1e-6, "({u}, {v}): {:?}", pic.rgb[i]);
                    }
                    let want = g.viewer_distance_m - z;
                    assert!((f64::from(pic.depth_z[i]) - want).abs() < 1e-6 * want, "{}", pic.depth_z[i]);
                } else if uf < u0 - 0.5 || uf > u1 + 0.5 || vf < v0 - 0.5 || vf > v1 + 0.5 {
                    outside += 1;
                    assert_eq!(pic.rgb[i], [0.0; 3], "({u}, {v})");
                    assert_eq!(pic.depth_z[i], f32::INFINITY);
                }
            }
        }
        assert!(inside >= 4 && outside > 100, "{inside} {outside}");
    }

    #[test]
    fn sub_pixels_average_over_the_pixel() {
        let g = geometry();
        let cam = display_camera(&g, 0.0);
        // An emitting half-plane whose edge is at the emitter plane, through
        // the centre of pixel column 9 (emitter 9): sub-samples at ±¼ pixel
        // fall on each side of it.
        let x_edge = g.emitter_x_m(9);
        let s = scene(vec![quad("half", [-1.0, x_edge], [-1.0, 1.0], g.emitter_z_m, emissive([1.0; 3]))]);
        let none = Lighting { lights: vec![], model: SpecularModel::Blinn };
        let pic = camera_picture(&s, &none, &cam, 2).unwrap();
        let row = 5 * pic.width;
        assert_eq!(pic.rgb[row + 8], [1.0; 3]);
        assert_eq!(pic.rgb[row + 9], [0.5; 3]);
        assert_eq!(pic.rgb[row + 10], [0.0; 3]);
    }

    #[test]
    fn the_nearer_surface_hides_the_farther_and_back_faces_are_invisible() {
        let g = geometry();
        let cam = display_camera(&g, 0.0);
        let none = Lighting { lights: vec![], model: SpecularModel::Blinn };
        let far = quad("far", [-0.1, 0.1], [-0.1, 0.1], -0.03, emissive([0.0, 0.0, 1.0]));
        let near = quad("near", [-0.1, 0.1], [-0.1, 0.1], 0.02, emissive([1.0, 0.0, 0.0]));
        for objects in [vec![far.clone(), near.clone()], vec![near.clone(), far.clone()]] {
            let pic = camera_picture(&scene(objects), &none, &cam, 1).unwrap();
            assert_eq!(pic.rgb[60], [1.0, 0.0, 0.0]);
            assert!((f64::from(pic.depth_z[60]) - (g.viewer_distance_m - 0.02)).abs() < 1e-6);
        }
        // The near square turned away from the camera: the far one shows through.
        let mut back = near.clone();
        back.triangles = vec![[0, 2, 1], [0, 3, 2]];
        let pic = camera_picture(&scene(vec![far.clone(), back.clone()]), &none, &cam, 1).unwrap();
        assert_eq!(pic.rgb[60], [0.0, 0.0, 1.0]);
        assert!((f64::from(pic.depth_z[60]) - (g.viewer_distance_m + 0.03)).abs() < 1e-6);
        let pic = camera_picture(&scene(vec![back.clone()]), &none, &cam, 1).unwrap();
        assert_eq!((pic.rgb[60], pic.depth_z[60]), ([0.0; 3], f32::INFINITY));
        // Unless it is double-sided.
        back.material.double_sided = true;
        let pic = camera_picture(&scene(vec![far, back]), &none, &cam, 1).unwrap();
        assert_eq!(pic.rgb[60], [1.0, 0.0, 0.0]);
    }

    #[test]
    fn bad_requests_are_named() {
        let g = geometry();
        let none = Lighting { lights: vec![], model: SpecularModel::Blinn };
        let cam = display_camera(&g, 0.0);
        let err = camera_picture(&scene(vec![]), &none, &cam, 0).unwrap_err().to_string();
        assert!(err.contains("on the viewer line") && err.contains("samples per pixel"), "{err}");
        let mut bad = cam.clone();
        bad.intrinsics.fx = -1.0;
        let err = camera_picture(&scene(vec![]), &none, &bad, 1).unwrap_err().to_string();
        assert!(err.contains("focal length"), "{err}");
        let mut o = quad("broken", [0.0, 1.0], [0.0, 1.0], 0.0, Material::default());
        o.triangles.push([0, 1, 9]);
        let err = camera_picture(&scene(vec![o]), &none, &cam, 1).unwrap_err().to_string();
        assert!(err.contains("test scene") && err.contains("broken"), "{err}");
    }

    #[test]
    fn sixteen_bit_png_and_pfm_round_trip() {
        let dir = tempfile::tempdir().unwrap();
        let (w, h) = (3, 2);
        let rgb = vec![[0.2, 0.5, 0.0], [1.0, 2.0, 0.001], [0.0; 3], [0.75, 0.1, 0.3], [0.04, 0.9, 0.6], [0.5; 3]];
        let depth_z = vec![1.0, 2.5, f32::INFINITY, 0.25, 4.0, 8.0];
        let pic = CameraPicture { width: w, height: h, rgb: rgb.clone(), depth_z: depth_z.clone() };
        let png = dir.path().join("c.png");
        let pfm = dir.path().join("c.pfm");
        write_camera_picture(&pic, &png, Some(&pfm)).unwrap();
        let img = crate::picture::decode::open(&png).unwrap();
        assert_eq!((img.width, img.height, img.channels, img.bits()), (w, h, 3, crate::picture::Bits::Sixteen));
        let img = img.rgb16();
        for (i, want) in rgb.iter().enumerate() {
            let p = &img[3 * i..3 * i + 3];
            for c in 0..3 {
                let got = crate::picture::srgb_decode(f64::from(p[c]) / 65535.0);
                let want = f64::from(want[c]).clamp(0.0, 1.0);
                // Half a 16-bit step of the encoded value, in linear terms.
                assert!((got - want).abs() < 2e-5, "pixel {i} channel {c}: {got} vs {want}");
            }
        }
        let bytes = std::fs::read(&pfm).unwrap();
        let header = b"Pf\n3 2\n-1.0\n";
        assert_eq!(&bytes[..header.len()], header);
        let values: Vec<f32> =
            bytes[header.len()..].chunks_exact(4).map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]])).collect();
        // Bottom row first.
        assert_eq!(values, [0.25, 4.0, 8.0, 1.0, 2.5, f32::INFINITY]);
        let empty = CameraPicture { width: 0, height: 0, rgb: vec![], depth_z: vec![] };
        let err = write_camera_picture(&empty, &png, None).unwrap_err().to_string();
        assert!(err.contains("c.png"), "{err}");
    }
}
