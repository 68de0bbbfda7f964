//! `solari info`.

use solari_app::cli::InfoArgs;

pub fn run(args: &InfoArgs) -> Result<(), String> {
    let (name, scene) = args.scene.load()?;
    let (gpu, backend) = args.scene.device()?;
    let s = scene.stats();
    let mut warnings = scene.warnings.lines();
    warnings.extend(solari_lights::LightList::build(&scene).report.lines());
    let camera = args.scene.pick_camera(&name, &scene)?;
    let (lo, hi) = scene.bounds();
    let environment = match &scene.environment_map {
        Some(m) => format!(
            "{} x {} map x {}, mean radiance {:.4}, {}",
            m.width(),
            m.height(),
            scene.environment_radiance,
            scene.environment_radiance * m.mean_radiance(),
            if scene.environment_is_light() {
                "sampled as a light"
            } else {
                "black"
            }
        ),
        None => format!("uniform {}", scene.environment_radiance),
    };
    if args.json {
        let v = serde_json::json!({
            "scene": name,
            "adapter": {"name": gpu.info.name, "backend": format!("{:?}", gpu.info.backend),
                        "device_type": format!("{:?}", gpu.info.device_type), "driver": gpu.info.driver_info,
                        "ray_query": gpu.has_ray_query()},
            "tracer": backend.name(),
            "stats": {"meshes": s.meshes, "instances": s.instances, "triangles": s.triangles,
                      "unique_triangles": s.unique_triangles, "emissive_triangles": s.emissive_triangles,
                      "lights": s.lights, "directional_lights": scene.directional_lights.len(),
                      "point_spot_lights": scene.punctual_lights.len(),
                      "textures": s.textures, "materials": scene.materials.len(), "cameras": scene.cameras.len()},
            "bounds": {"min": lo.to_array(), "max": hi.to_array()},
            "camera": camera.name,
            "environment": environment,
            "warnings": warnings,
        });
        println!(
            "{}",
            serde_json::to_string_pretty(&v).map_err(|e| e.to_string())?
        );
    } else {
        println!("scene      {name}");
        println!(
            "adapter    {} ({:?}, {:?}, {})",
            gpu.info.name, gpu.info.backend, gpu.info.device_type, gpu.info.driver_info
        );
        println!(
            "tracer     {} (ray queries {})",
            backend.name(),
            if gpu.has_ray_query() {
                "available"
            } else {
                "unavailable"
            }
        );
        println!("meshes     {}", s.meshes);
        println!("instances  {}", s.instances);
        println!("triangles  {} ({} unique)", s.triangles, s.unique_triangles);
        println!("emissive   {} triangles", s.emissive_triangles);
        println!(
            "lights     {} ({} directional, {} point/spot)",
            s.lights,
            scene.directional_lights.len(),
            scene.punctual_lights.len()
        );
        println!("bounds     {lo} .. {hi}");
        println!("textures   {}", s.textures);
        println!("environment {environment}");
        println!("camera     {}", camera.name);
        if warnings.is_empty() {
            println!("warnings   none");
        }
        for w in warnings {
            println!("warning    {w}");
        }
    }
    Ok(())
}
