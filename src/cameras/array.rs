//! Planar arrays of parallel cameras (rails, grids, the light-field
//! benchmarks, quilts): one orientation for all, each camera displaced from
//! the array's middle, and, when the array converges, principal points
//! shifted so that every view is centred on one point in front of the middle
//! (the "shifted sensor" that gives zero disparity at the focus distance).

use super::{look_rotation, Camera, ImageSource, Intrinsics, Pose};
use crate::math;

/// The middle of an array and the orientation its cameras share.
pub(crate) struct ArrayFrame {
    /// Middle of the array, world units.
    pub(crate) centre: [f64; 3],
    /// World to camera, rows = right, down, forward.
    pub(crate) rotation: math::Mat3,
}

impl ArrayFrame {
    /// Cameras around `centre` looking along `direction`, with world `up`
    /// as picture up. The error says which vector is unusable.
    pub(crate) fn new(centre: [f64; 3], direction: [f64; 3], up: [f64; 3]) -> Result<ArrayFrame, String> {
        let finite = |v: [f64; 3]| v.iter().all(|x| x.is_finite());
        if !(finite(centre) && finite(direction) && finite(up)) {
            return Err("the array's centre, direction and up must be finite".into());
        }
        if math::length(direction) == 0.0 {
            return Err("the viewing direction is the zero vector".into());
        }
        let sine = math::length(math::cross(direction, up)) / (math::length(direction) * math::length(up));
        if sine.is_nan() || sine <= 1e-9 {
            return Err(format!("up {up:?} is zero or parallel to the viewing direction {direction:?}"));
        }
        Ok(ArrayFrame { centre, rotation: look_rotation(direction, math::scale(up, -1.0)) })
    }

    /// The cameras' right (world, unit).
    pub(crate) fn right(&self) -> [f64; 3] {
        self.rotation[0]
    }

    /// The cameras' picture-down direction (world, unit).
    pub(crate) fn down(&self) -> [f64; 3] {
        self.rotation[1]
    }

    /// The cameras' viewing direction (world, unit).
    pub(crate) fn forward(&self) -> [f64; 3] {
        self.rotation[2]
    }

    /// A camera displaced by `offset` (world) from the middle, with focal
    /// lengths `fx`, `fy` pixels; centred on the point `converge` units in
    /// front of the middle when given, else with a centred principal point.
    pub(crate) fn camera(
        &self,
        name: String,
        image: ImageSource,
        (width, height): (usize, usize),
        (fx, fy): (f64, f64),
        offset: [f64; 3],
        converge: Option<f64>,
    ) -> Result<Camera, String> {
        let mut camera = Camera {
            name,
            image,
            width,
            height,
            intrinsics: Intrinsics::centred(width, height, fx, fy),
            pose: Pose { rotation: self.rotation, centre: math::add(self.centre, offset) },
            depth: None,
        };
        if let Some(f) = converge {
            let point = math::add(self.centre, math::scale(self.forward(), f));
            if !camera.centre_on(point) {
                return Err(format!(
                    "camera {}: the point the array converges on ({f} in front of its middle) is not in front of it",
                    camera.name
                ));
            }
        }
        Ok(camera)
    }
}
