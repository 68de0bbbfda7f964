//! `render_setup.json`: a side file giving a camera and an environment to assets without them.
//!
//! Format (all fields optional):
//! `{"camera": {"eye": [x,y,z], "target": [x,y,z], "up": [x,y,z], "yfov_deg": f, "aspect": f},
//!   "environment_radiance": [r,g,b]}`. Its camera is appended as camera `render_setup`, and
//! is the default camera only when the file itself has none.

use crate::error::SceneError;
use crate::model::{Camera, Scene};
use glam::Vec3;
use std::path::Path;

/// Reads the side file at `path` and applies it to `scene`.
pub fn apply(path: &Path, scene: &mut Scene) -> Result<(), SceneError> {
    let bad = |reason: String| SceneError::BadSideFile {
        file: path.into(),
        reason,
    };
    // A camera and a colour need a few hundred bytes; a megabyte is generous.
    let bytes = crate::asset_io::read_file_limited(path, 1 << 20).map_err(&bad)?;
    let text = String::from_utf8(bytes).map_err(|_| bad("not UTF-8 text".into()))?;
    let json: serde_json::Value =
        serde_json::from_str(&text).map_err(|e| bad(format!("not JSON: {e}")))?;
    let vec3 = |v: &serde_json::Value, what: &str| -> Result<Vec3, SceneError> {
        let a = v
            .as_array()
            .filter(|a| a.len() == 3)
            .ok_or_else(|| bad(format!("{what} must be [x, y, z]")))?;
        let f: Vec<f32> = a
            .iter()
            .filter_map(|x| x.as_f64())
            .map(|x| x as f32)
            .collect();
        let v = Vec3::from_slice(&f);
        if f.len() != 3 || !v.is_finite() {
            return Err(bad(format!("{what} must be three finite numbers")));
        }
        Ok(v)
    };
    if let Some(cam) = json.get("camera") {
        let eye = vec3(
            cam.get("eye").unwrap_or(&serde_json::Value::Null),
            "camera.eye",
        )?;
        let target = vec3(
            cam.get("target").unwrap_or(&serde_json::Value::Null),
            "camera.target",
        )?;
        let up = match cam.get("up") {
            Some(u) => vec3(u, "camera.up")?,
            None => Vec3::Y,
        };
        let yfov_deg = cam.get("yfov_deg").and_then(|v| v.as_f64()).unwrap_or(45.0) as f32;
        if !(yfov_deg > 0.0 && yfov_deg < 180.0) || (target - eye).length_squared() == 0.0 {
            return Err(bad(
                "camera needs eye != target and 0 < yfov_deg < 180".into()
            ));
        }
        let mut c = Camera::look_at("render_setup", eye, target, up, yfov_deg.to_radians());
        c.aspect = cam.get("aspect").and_then(|v| v.as_f64()).map(|a| a as f32);
        c.znear = ((target - eye).length() * 1e-3).max(1e-6);
        c.validate().map_err(&bad)?;
        scene.cameras.push(c);
    }
    if let Some(env) = json.get("environment_radiance") {
        let e = vec3(env, "environment_radiance")?;
        if e.min_element() < 0.0 || e.max_element() > crate::validate::MAX_RADIANCE {
            return Err(bad(format!(
                "environment_radiance must be within [0, {:e}]",
                crate::validate::MAX_RADIANCE
            )));
        }
        scene.environment_radiance = e;
    }
    Ok(())
}
