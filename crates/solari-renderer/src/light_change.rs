//! How much the lights changed between two light lists, by power: the signal for the world
//! cache and ReSTIR GI to shorten their histories after a light is switched.

use solari_lights::LightList;
use std::collections::HashMap;

/// The share of the lights' power that changes above which `RealtimeRenderer::set_lights`
/// has the world cache and ReSTIR GI shorten their histories (10%). Lights that only move
/// keep their power and count nothing (the cache's adaptive blend follows those); a light
/// flickering by more than this share of the whole scene's power on every call keeps the
/// histories short.
pub const LIGHT_CHANGE_SHARE: f32 = 0.1;

/// The power that changed between `old` and `new` as a share of the power present in
/// either: Σ |new − old| / Σ max(new, old) over the lights of both, matched by their stable
/// keys (a light added or removed changes by all of its power). 0 for two lists of the same
/// powers (also when empty), 1 when no light's power is kept. An environment map is a light
/// of the list like any other (its factor changed, its power changes; a new map is a new
/// light); a uniform environment colour is not a light (`Scene::environment_is_light`) and
/// is not counted.
pub fn power_change_share(old: &LightList, new: &LightList) -> f32 {
    let mut both: HashMap<_, (f64, f64)> = HashMap::new();
    for (k, p) in old.keys.iter().zip(&old.power) {
        both.entry(*k).or_default().0 += f64::from(*p);
    }
    for (k, p) in new.keys.iter().zip(&new.power) {
        both.entry(*k).or_default().1 += f64::from(*p);
    }
    let (mut changed, mut present) = (0.0, 0.0);
    for (before, after) in both.values() {
        changed += (after - before).abs();
        present += before.max(*after);
    }
    if present > 0.0 && (changed / present).is_finite() {
        (changed / present) as f32
    } else {
        0.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;
    use solari_scene::model::{PunctualKind, PunctualLight, Scene};

    fn bulb(name: &str, x: f32, power: f32) -> PunctualLight {
        PunctualLight {
            name: name.into(),
            kind: PunctualKind::Point,
            position: Vec3::new(x, 1.0, 0.0),
            direction: Vec3::NEG_Y,
            intensity: Vec3::splat(power),
            range: None,
            radius: 0.0,
        }
    }

    fn list(lights: &[PunctualLight]) -> LightList {
        LightList::build(&Scene {
            punctual_lights: lights.to_vec(),
            ..Default::default()
        })
    }

    #[test]
    fn switches_count_and_moves_do_not() {
        let (a, b) = (bulb("a", 0.0, 3.0), bulb("b", 2.0, 1.0));
        let two = list(&[a.clone(), b.clone()]);
        assert_eq!(power_change_share(&two, &two), 0.0);
        // Moved: the same keys and powers.
        let moved = list(&[bulb("a", 5.0, 3.0), bulb("b", -2.0, 1.0)]);
        assert_eq!(power_change_share(&two, &moved), 0.0);
        // b switched off (left out of the list): a quarter of the power.
        let off = list(std::slice::from_ref(&a));
        let share = power_change_share(&two, &off);
        assert!((share - 0.25).abs() < 1e-6, "{share}");
        // And on again: the same share the other way.
        assert!((power_change_share(&off, &two) - 0.25).abs() < 1e-6);
        // a halved: 1.5 of 4.
        let dimmer = list(&[bulb("a", 0.0, 1.5), b]);
        let share = power_change_share(&two, &dimmer);
        assert!((share - 0.375).abs() < 1e-6, "{share}");
        // Every light replaced, and empty lists.
        assert_eq!(power_change_share(&two, &list(&[])), 1.0);
        assert_eq!(power_change_share(&list(&[]), &list(&[])), 0.0);
    }

    /// An environment map counts by its power: its factor doubled changes half the power
    /// present beside nothing else; the uniform colour (not a light) counts nothing.
    #[test]
    fn an_environment_map_counts_and_a_uniform_sky_does_not() {
        use solari_scene::EnvironmentMap;
        use std::sync::Arc;
        let map = Arc::new(EnvironmentMap::new(4, 2, vec![Vec3::splat(0.5); 8]).unwrap());
        let sky = |factor: f32| {
            LightList::build(&Scene {
                environment_map: Some(map.clone()),
                environment_radiance: Vec3::splat(factor),
                ..Default::default()
            })
        };
        let share = power_change_share(&sky(1.0), &sky(2.0));
        assert!((share - 0.5).abs() < 1e-6, "{share}");
        assert_eq!(power_change_share(&sky(1.0), &sky(1.0)), 0.0);
        // Switched off (a black factor: no longer a light).
        assert_eq!(power_change_share(&sky(1.0), &sky(0.0)), 1.0);
        let uniform = |c: f32| {
            LightList::build(&Scene {
                environment_radiance: Vec3::splat(c),
                ..Default::default()
            })
        };
        assert_eq!(power_change_share(&uniform(1.0), &uniform(5.0)), 0.0);
    }
}
