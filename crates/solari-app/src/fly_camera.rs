//! The viewer's fly camera: a position and a heading (yaw about +Y, pitch) moved by keys and
//! turned by the mouse, turned into the [`Camera`] the renderer takes. Kept apart from the
//! window code so that its arithmetic is tested without a display.

use glam::{EulerRot, Mat4, Quat, Vec3};
use solari_scene::Camera;

/// Pitch stays this far from straight up or down, where yaw would be undefined.
const PITCH_LIMIT: f32 = 1.55;

/// Which movement keys are held, as signed axes (-1, 0 or 1 each).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct MoveInput {
    /// Forward (W) minus back (S).
    pub forward: f32,
    /// Right (D) minus left (A).
    pub right: f32,
    /// Up (E, Space) minus down (Q, Ctrl), along world +Y.
    pub up: f32,
    /// Hold to move `FlyCamera::FAST` times faster (Shift).
    pub fast: bool,
}

/// A camera flown through the scene (see the module docs).
#[derive(Clone, Debug, PartialEq)]
pub struct FlyCamera {
    /// World-space position.
    pub position: Vec3,
    /// Heading about +Y in radians (0 looks down -Z).
    pub yaw: f32,
    /// Elevation in radians, within ±1.55 (about 89°).
    pub pitch: f32,
    /// Speed in scene units per second.
    pub speed: f32,
    /// Radians per pixel of mouse motion.
    pub sensitivity: f32,
    // Field of view, aspect and near plane come from the starting camera.
    lens: Camera,
    // Where it started: until it moves, the starting camera is returned as it is.
    start: (Vec3, f32, f32),
}

impl FlyCamera {
    /// How much faster the camera moves with `MoveInput::fast`.
    pub const FAST: f32 = 4.0;

    /// Starts at `camera`'s position and heading (roll and scale in its transform are
    /// dropped), moving at `speed` units per second; a non-finite or non-positive speed
    /// becomes 1.
    pub fn new(camera: &Camera, speed: f32) -> Self {
        let (_, rotation, position) = camera.transform.to_scale_rotation_translation();
        let forward = (rotation * Vec3::NEG_Z).normalize_or(Vec3::NEG_Z);
        let pitch = forward
            .y
            .clamp(-1.0, 1.0)
            .asin()
            .clamp(-PITCH_LIMIT, PITCH_LIMIT);
        // Looking straight up or down, any yaw will do.
        let yaw = if forward.x.abs() + forward.z.abs() > 1e-6 {
            (-forward.x).atan2(-forward.z)
        } else {
            0.0
        };
        let position = if position.is_finite() {
            position
        } else {
            Vec3::ZERO
        };
        let yaw = if yaw.is_finite() { yaw } else { 0.0 };
        let pitch = if pitch.is_finite() { pitch } else { 0.0 };
        Self {
            position,
            yaw,
            pitch,
            speed: if speed.is_finite() && speed > 0.0 {
                speed
            } else {
                1.0
            },
            sensitivity: 0.003,
            lens: camera.clone(),
            start: (position, yaw, pitch),
        }
    }

    /// A speed for a scene of bounds `(lo, hi)`: its diagonal crossed in about 8 s (1 unit/s
    /// for empty or unbounded scenes).
    pub fn speed_for(bounds: (Vec3, Vec3)) -> f32 {
        let d = (bounds.1 - bounds.0).length();
        if d.is_finite() && d > 0.0 {
            d / 8.0
        } else {
            1.0
        }
    }

    /// The unit direction the camera looks along.
    pub fn forward(&self) -> Vec3 {
        self.rotation() * Vec3::NEG_Z
    }

    /// Moves by `input` over `seconds` (non-finite or negative times move nothing).
    pub fn advance(&mut self, input: &MoveInput, seconds: f32) {
        if !(seconds.is_finite() && seconds > 0.0) {
            return;
        }
        let rotation = self.rotation();
        let step = self.speed * seconds * if input.fast { Self::FAST } else { 1.0 };
        let axis = |v: f32| {
            if v.is_finite() {
                v.clamp(-1.0, 1.0)
            } else {
                0.0
            }
        };
        let motion = rotation * Vec3::NEG_Z * axis(input.forward)
            + rotation * Vec3::X * axis(input.right)
            + Vec3::Y * axis(input.up);
        self.position += motion.normalize_or_zero() * step;
    }

    /// Turns by a mouse motion of `(dx, dy)` pixels (right and down positive).
    pub fn turn(&mut self, dx: f32, dy: f32) {
        if !(dx.is_finite() && dy.is_finite()) {
            return;
        }
        self.yaw = (self.yaw - dx * self.sensitivity).rem_euclid(std::f32::consts::TAU);
        self.pitch = (self.pitch - dy * self.sensitivity).clamp(-PITCH_LIMIT, PITCH_LIMIT);
    }

    /// The renderer's camera: the starting camera's lens at this position and heading (the
    /// starting camera itself, roll and all, until the camera moves or turns, so an untouched
    /// viewer renders exactly what `solari render` does).
    pub fn camera(&self) -> Camera {
        if (self.position, self.yaw, self.pitch) == self.start {
            return self.lens.clone();
        }
        Camera {
            transform: Mat4::from_rotation_translation(self.rotation(), self.position),
            ..self.lens.clone()
        }
    }

    fn rotation(&self) -> Quat {
        Quat::from_euler(EulerRot::YXZ, self.yaw, self.pitch, 0.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{Rng, SeedableRng};
    use rand_pcg::Pcg32;

    fn camera_at(eye: Vec3, target: Vec3) -> Camera {
        Camera::look_at("test", eye, target, Vec3::Y, 0.8)
    }

    #[test]
    fn an_untouched_camera_is_the_starting_one_and_a_rebuilt_one_matches_it() {
        let mut rng = Pcg32::seed_from_u64(3);
        for _ in 0..500 {
            let eye = Vec3::new(rng.random(), rng.random(), rng.random()) * 20.0 - 10.0;
            let mut dir = Vec3::new(rng.random(), rng.random(), rng.random()) * 2.0 - 1.0;
            // Keep clear of straight up and down, where look_at has no heading.
            dir.y = dir.y.clamp(-0.9, 0.9);
            let start = camera_at(eye, eye + dir.normalize() * 3.0);
            let mut fly = FlyCamera::new(&start, 2.0);
            assert_eq!(fly.camera(), start);
            assert!(fly.forward().distance(dir.normalize()) < 1e-4, "{dir:?}");
            // Turned away and back: the rebuilt transform, not the stored one.
            fly.turn(100.0, 0.0);
            fly.turn(-100.0, 0.0);
            let rebuilt = fly.camera().transform;
            for c in 0..4 {
                let d = (rebuilt.col(c) - start.transform.col(c))
                    .abs()
                    .max_element();
                assert!(
                    d < 1e-3,
                    "column {c}: {rebuilt:?} against {:?}",
                    start.transform
                );
            }
            assert_eq!(fly.camera().yfov, start.yfov);
        }
    }

    #[test]
    fn moves_at_its_speed_along_its_axes() {
        let start = camera_at(Vec3::ZERO, Vec3::new(0.0, 0.0, -1.0));
        let mut fly = FlyCamera::new(&start, 2.0);
        let forward = MoveInput {
            forward: 1.0,
            ..Default::default()
        };
        fly.advance(&forward, 0.5);
        assert!(fly.position.distance(Vec3::new(0.0, 0.0, -1.0)) < 1e-5);
        // Diagonal moves are no faster; Shift is FAST times faster.
        let diagonal = MoveInput {
            forward: 1.0,
            right: 1.0,
            up: 1.0,
            fast: true,
        };
        let before = fly.position;
        fly.advance(&diagonal, 0.25);
        let step = fly.position - before;
        assert!((step.length() - 2.0 * 0.25 * FlyCamera::FAST).abs() < 1e-4);
        assert!(step.x > 0.0 && step.y > 0.0 && step.z < 0.0, "{step:?}");
        // Bad times and axes move nothing, or within the unit axes.
        let here = fly.position;
        for dt in [f32::NAN, f32::INFINITY, -1.0, 0.0] {
            fly.advance(&forward, dt);
        }
        fly.advance(
            &MoveInput {
                forward: f32::NAN,
                right: 1e30,
                ..Default::default()
            },
            1.0,
        );
        assert!(fly.position.is_finite());
        assert!((fly.position - here).length() <= 2.0 + 1e-4);
    }

    #[test]
    fn turning_wraps_the_heading_and_clamps_the_pitch() {
        let start = camera_at(Vec3::ZERO, Vec3::new(0.0, 0.0, -1.0));
        let mut fly = FlyCamera::new(&start, 1.0);
        fly.turn(0.0, -1e6);
        assert_eq!(fly.pitch, PITCH_LIMIT);
        fly.turn(0.0, 1e6);
        assert_eq!(fly.pitch, -PITCH_LIMIT);
        fly.turn(1e7, 0.0);
        assert!((0.0..std::f32::consts::TAU).contains(&fly.yaw));
        let before = fly.clone();
        fly.turn(f32::NAN, 1.0);
        assert_eq!(fly, before);
        assert!(fly.camera().transform.is_finite());
    }

    #[test]
    fn degenerate_starting_cameras_give_a_finite_camera() {
        let down = camera_at(Vec3::new(0.0, 5.0, 0.0), Vec3::ZERO);
        let mut broken = down.clone();
        broken.transform = Mat4::from_cols_array(&[f32::NAN; 16]);
        for start in [down, broken] {
            for speed in [f32::NAN, -3.0, 0.0, f32::INFINITY] {
                let mut fly = FlyCamera::new(&start, speed);
                assert_eq!(fly.speed, 1.0);
                assert!(fly.position.is_finite() && fly.yaw.is_finite() && fly.pitch.is_finite());
                fly.turn(1.0, 1.0);
                assert!(fly.camera().transform.is_finite());
            }
        }
        assert_eq!(
            FlyCamera::speed_for((Vec3::splat(f32::INFINITY), Vec3::ZERO)),
            1.0
        );
        assert_eq!(
            FlyCamera::speed_for((Vec3::ZERO, Vec3::new(0.0, 0.0, 8.0))),
            1.0
        );
    }
}
