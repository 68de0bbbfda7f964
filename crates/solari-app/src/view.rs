//! `solari view`: the real-time renderer in a window. winit owns the window and the event
//! loop; the device is created for the window's surface; each redraw submits one frame
//! (without waiting for the GPU: reports arrive a frame or two late), draws it into the
//! surface texture through the renderer's presenter, and the overlay (`view_overlay`) on top.
//! Settings changed in the overlay, a resize or a dropped glTF rebuild what they touch
//! between frames; their errors are shown, never fatal. `--frames N` closes after N frames
//! with a screenshot, which is how the tests drive it under Xvfb.

use crate::view_overlay::{Controls, FrameFigures, Overlay};
use solari_app::cli::{RealtimeArgs, SceneArgs, ViewArgs};
use solari_app::fly_camera::{FlyCamera, MoveInput};
use solari_app::output::{ImageFormat, ImageOutputs, write_atomic};
use solari_app::quality_choice::{QualityReport, Target, resolve, table_scene_name};
use solari_denoise::DenoiserKind;
use solari_reference::image_io::encode_png_rgb8;
use solari_renderer::{QualityTier, RealtimeRenderer, RealtimeSettings};
use solari_scene::gpu::Gpu;
use solari_scene::gpu_scene::GpuScene;
use solari_scene::shaders::Backend;
use solari_scene::{Camera, Scene};
use std::collections::{HashSet, VecDeque};
use std::path::PathBuf;
use std::sync::Arc;
use std::time::{Duration, Instant};
use winit::application::ApplicationHandler;
use winit::event::{DeviceEvent, DeviceId, ElementState, MouseButton, WindowEvent};
use winit::event_loop::{ActiveEventLoop, ControlFlow, EventLoop};
use winit::keyboard::{KeyCode, PhysicalKey};
use winit::window::{Window, WindowId};

/// Opens the window and runs until it is closed (or `--frames` are done).
pub fn run(args: &ViewArgs) -> Result<(), String> {
    let settings = viewer_settings(args)?;
    let event_loop = EventLoop::new().map_err(|e| {
        format!(
            "cannot open a window ({e}): no display? Set DISPLAY (or run under Xvfb), or render \
             headless with `solari render --mode realtime`"
        )
    })?;
    event_loop.set_control_flow(ControlFlow::Poll);
    let mut app = App {
        args,
        settings,
        viewer: None,
        result: Ok(()),
    };
    event_loop.run_app(&mut app).map_err(|e| e.to_string())?;
    app.result
}

/// The starting settings: the command line's, with the fallback denoiser for "best
/// available" (the viewer's device is made for its window, without DLSS's Vulkan set-up).
fn viewer_settings(args: &ViewArgs) -> Result<RealtimeSettings, String> {
    let mut settings = args.check()?;
    match settings.denoiser {
        Some(DenoiserKind::DlssRr) => {
            return Err("the viewer does not run DLSS-RR: use --denoiser fallback or none".into());
        }
        None => settings.denoiser = Some(DenoiserKind::Fallback),
        Some(_) => {}
    }
    Ok(settings)
}

struct App<'a> {
    args: &'a ViewArgs,
    settings: RealtimeSettings,
    viewer: Option<Viewer>,
    result: Result<(), String>,
}

impl ApplicationHandler for App<'_> {
    fn resumed(&mut self, event_loop: &ActiveEventLoop) {
        if self.viewer.is_some() {
            return;
        }
        match Viewer::open(event_loop, self.args, self.settings) {
            Ok(v) => self.viewer = Some(v),
            Err(e) => {
                self.result = Err(e);
                event_loop.exit();
            }
        }
    }

    fn window_event(&mut self, event_loop: &ActiveEventLoop, _: WindowId, event: WindowEvent) {
        let Some(viewer) = &mut self.viewer else {
            return;
        };
        match viewer.on_event(event) {
            Ok(true) => {}
            Ok(false) => event_loop.exit(),
            Err(e) => {
                self.result = Err(e);
                event_loop.exit();
            }
        }
    }

    fn device_event(&mut self, _: &ActiveEventLoop, _: DeviceId, event: DeviceEvent) {
        if let (Some(viewer), DeviceEvent::MouseMotion { delta }) = (&mut self.viewer, event)
            && viewer.looking
        {
            viewer.session.camera.turn(delta.0 as f32, delta.1 as f32);
        }
    }

    fn about_to_wait(&mut self, _: &ActiveEventLoop) {
        if let Some(viewer) = &self.viewer {
            viewer.window.request_redraw();
        }
    }

    fn exiting(&mut self, _: &ActiveEventLoop) {
        // Frames still in flight are waited for before the device goes away.
        if let Some(viewer) = &mut self.viewer
            && let Err(e) = viewer.session.renderer.finish(&viewer.gpu)
        {
            log::warn!("finishing the last frames: {e}");
        }
    }
}

/// A scene on the device with its renderer and camera.
struct Session {
    name: String,
    scene: Scene,
    gpu_scene: GpuScene,
    renderer: RealtimeRenderer,
    start: Camera,
    camera: FlyCamera,
    // The settings the renderer was built with (`--quality auto` chooses them per scene).
    settings: RealtimeSettings,
    quality: Option<QualityReport>,
}

impl Session {
    fn load(
        gpu: &Gpu,
        backend: Backend,
        args: &SceneArgs,
        realtime: &RealtimeArgs,
        settings: RealtimeSettings,
        size: (u32, u32),
    ) -> Result<Self, String> {
        let (name, scene) = args.load()?;
        for warning in scene.warnings.lines() {
            log::warn!("{name}: {warning}");
        }
        let start = args.pick_camera(&name, &scene)?;
        let options = args.gpu_scene_options();
        let gpu_scene =
            GpuScene::new(gpu, &scene, backend, &options).map_err(|e| format!("{name}: {e}"))?;
        let target = Target {
            gpu,
            backend,
            scene: &scene,
            gpu_scene: &gpu_scene,
            camera: &start,
            size,
            table_name: table_scene_name(args),
        };
        let (settings, quality) = resolve(realtime, &target, settings)?;
        if let Some(q) = &quality {
            println!("{}", q.line());
        }
        let renderer =
            RealtimeRenderer::new(gpu, backend, &scene, &gpu_scene, size.0, size.1, settings)
                .map_err(|e| format!("{name}: {e}"))?;
        let camera = FlyCamera::new(&start, FlyCamera::speed_for(scene.bounds()));
        log::info!("{name}: {:?}", scene.stats());
        Ok(Self {
            name,
            scene,
            gpu_scene,
            renderer,
            start,
            camera,
            settings,
            quality,
        })
    }
}

struct Viewer {
    window: Arc<Window>,
    surface: wgpu::Surface<'static>,
    config: wgpu::SurfaceConfiguration,
    gpu: Gpu,
    backend: Backend,
    scene_args: SceneArgs,
    realtime_args: RealtimeArgs,
    settings: RealtimeSettings,
    session: Session,
    overlay: Overlay,
    controls: Controls,
    figures: FrameFigures,
    keys: HashSet<KeyCode>,
    looking: bool,
    last_frame: Option<Instant>,
    frame_times: VecDeque<Duration>,
    frames_left: Option<u32>,
    screenshot: Option<PathBuf>,
    screenshots_taken: u32,
    vsync: bool,
    // Set by events, acted on at the next redraw (between frames).
    resized: bool,
    rebuild: bool,
    dropped: Option<PathBuf>,
}

impl Viewer {
    fn open(
        event_loop: &ActiveEventLoop,
        args: &ViewArgs,
        settings: RealtimeSettings,
    ) -> Result<Self, String> {
        let attributes = Window::default_attributes()
            .with_title("Solari")
            .with_inner_size(winit::dpi::PhysicalSize::new(args.size.0, args.size.1));
        let window = Arc::new(
            event_loop
                .create_window(attributes)
                .map_err(|e| format!("cannot create the window: {e}"))?,
        );
        let instance = wgpu::Instance::new(
            Gpu::instance_descriptor()
                .with_display_handle(Box::new(event_loop.owned_display_handle())),
        );
        let surface = instance
            .create_surface(window.clone())
            .map_err(|e| format!("cannot draw into the window: {e}"))?;
        let adapter = Gpu::pick_adapter_where(&instance, |a| a.is_surface_supported(&surface))
            .map_err(|e| e.to_string())?;
        let (device, queue) =
            pollster::block_on(adapter.request_device(&Gpu::device_descriptor(&adapter)))
                .map_err(|e| format!("cannot open {}: {e}", adapter.get_info().name))?;
        let gpu = Gpu::from_parts(instance, adapter, device, queue);
        let backend = gpu
            .backend(args.scene.tracer()?)
            .map_err(|e| e.to_string())?;
        let config = surface_config(&surface, &gpu, window.inner_size(), !args.no_vsync)?;
        surface.configure(&gpu.device, &config);
        let size = (config.width, config.height);
        let session = Session::load(&gpu, backend, &args.scene, &args.realtime, settings, size)?;
        let settings = session.settings;
        let overlay = Overlay::new(&window, &gpu.device, config.format, !args.no_ui);
        let controls = controls_of(&settings, args.exposure, session.camera.speed);
        log::info!(
            "viewer: {} ({}), surface {:?} {}x{}",
            gpu.info.name,
            backend.name(),
            config.format,
            config.width,
            config.height
        );
        let figures = FrameFigures {
            device: format!("{} · {}", gpu.info.name, backend.name()),
            status: session
                .quality
                .as_ref()
                .map_or(String::new(), QualityReport::line),
            ..Default::default()
        };
        Ok(Self {
            window,
            surface,
            config,
            gpu,
            backend,
            scene_args: args.scene.clone(),
            realtime_args: args.realtime.clone(),
            settings,
            session,
            overlay,
            controls,
            figures,
            keys: HashSet::new(),
            looking: false,
            last_frame: None,
            frame_times: VecDeque::new(),
            frames_left: args.frames,
            screenshot: args.screenshot.clone(),
            screenshots_taken: 0,
            vsync: !args.no_vsync,
            resized: false,
            rebuild: false,
            dropped: None,
        })
    }

    /// Handles one window event; `Ok(false)` asks to close.
    fn on_event(&mut self, event: WindowEvent) -> Result<bool, String> {
        let used = self.overlay.on_event(&self.window, &event);
        match event {
            WindowEvent::CloseRequested => return Ok(false),
            WindowEvent::Resized(_) | WindowEvent::ScaleFactorChanged { .. } => self.resized = true,
            WindowEvent::DroppedFile(path) => self.dropped = Some(path),
            WindowEvent::MouseInput { state, button, .. }
                if button == MouseButton::Right && !(used && state.is_pressed()) =>
            {
                self.looking = state.is_pressed() && !self.overlay.wants_pointer();
            }
            WindowEvent::Focused(false) => {
                self.keys.clear();
                self.looking = false;
            }
            WindowEvent::KeyboardInput { event, .. } if !used && !self.overlay.wants_keyboard() => {
                if let PhysicalKey::Code(code) = event.physical_key {
                    if event.state == ElementState::Pressed {
                        self.keys.insert(code);
                        match code {
                            KeyCode::Escape => return Ok(false),
                            KeyCode::F1 if !event.repeat => {
                                self.overlay.visible = !self.overlay.visible
                            }
                            KeyCode::F12 if !event.repeat => self.take_screenshot(),
                            KeyCode::KeyR if !event.repeat => self.reset_camera(),
                            _ => {}
                        }
                    } else {
                        self.keys.remove(&code);
                    }
                }
            }
            WindowEvent::RedrawRequested => return self.redraw(),
            _ => {}
        }
        Ok(true)
    }

    fn reset_camera(&mut self) {
        let speed = self.session.camera.speed;
        self.session.camera = FlyCamera::new(&self.session.start, speed);
    }

    fn move_input(&self) -> MoveInput {
        let held = |keys: &[KeyCode]| keys.iter().any(|k| self.keys.contains(k));
        let axis = |plus: &[KeyCode], minus: &[KeyCode]| {
            f32::from(u8::from(held(plus))) - f32::from(u8::from(held(minus)))
        };
        MoveInput {
            forward: axis(
                &[KeyCode::KeyW, KeyCode::ArrowUp],
                &[KeyCode::KeyS, KeyCode::ArrowDown],
            ),
            right: axis(
                &[KeyCode::KeyD, KeyCode::ArrowRight],
                &[KeyCode::KeyA, KeyCode::ArrowLeft],
            ),
            up: axis(
                &[KeyCode::KeyE, KeyCode::Space],
                &[KeyCode::KeyQ, KeyCode::ControlLeft],
            ),
            fast: held(&[KeyCode::ShiftLeft, KeyCode::ShiftRight]),
        }
    }

    /// One frame: pending changes, camera, render, present, overlay.
    fn redraw(&mut self) -> Result<bool, String> {
        self.apply_pending();
        let now = Instant::now();
        if let Some(last) = self.last_frame.replace(now) {
            let dt = now - last;
            // The median of the last 31 frames: steady, and blind to the first frames'
            // pipeline builds and to rebuilds.
            if self.frame_times.len() == 31 {
                self.frame_times.pop_front();
            }
            self.frame_times.push_back(dt);
            // On the stack: no allocation per frame.
            let mut sorted = [Duration::ZERO; 31];
            let n = self.frame_times.len();
            for (s, t) in sorted.iter_mut().zip(&self.frame_times) {
                *s = *t;
            }
            sorted[..n].sort_unstable();
            self.figures.wall = Some(sorted[n / 2]);
            let input = self.move_input();
            self.session
                .camera
                .advance(&input, dt.as_secs_f32().min(0.25));
        }
        let camera = self.session.camera.camera();
        let s = &mut self.session;
        match s
            .renderer
            .submit(&self.gpu, &s.scene, &s.gpu_scene, &camera)
        {
            Ok(Some(report)) => {
                self.figures.non_finite += report.finite.iter().map(|f| f.non_finite).sum::<u64>();
                // One frame in `--time-every` carries times: the overlay keeps showing the
                // last timed report until the next (any report where none are timed).
                let shown_timed = self
                    .figures
                    .report
                    .as_ref()
                    .is_some_and(|r| r.gpu_span_ms.is_some());
                if report.gpu_span_ms.is_some() || !shown_timed {
                    self.figures.report = Some(report);
                }
            }
            Ok(None) => {}
            Err(e) => return Err(format!("frame {}: {e}", self.figures.frames)),
        }
        self.figures.frames += 1;
        self.figures.scene.clone_from(&self.session.name);
        self.figures.output = self.session.renderer.size();
        self.figures.render = self.settings.render_size(self.figures.output);

        let before = self.controls.clone();
        let requests = self.overlay.update(
            &self.window,
            &self.gpu.device,
            &self.gpu.queue,
            &self.figures,
            &mut self.controls,
        );
        self.present()?;
        if self.controls != before {
            self.take_controls(&before);
        }
        if requests.reset_camera {
            self.reset_camera();
        }
        if requests.screenshot {
            self.take_screenshot();
        }
        if let Some(left) = &mut self.frames_left {
            *left -= 1;
            if *left == 0 {
                if self.screenshot.is_some() {
                    self.screenshot_now()?;
                }
                return Ok(false);
            }
        }
        Ok(true)
    }

    /// Draws the last frame and the overlay into the window.
    fn present(&mut self) -> Result<(), String> {
        let texture = match self.surface.get_current_texture() {
            wgpu::CurrentSurfaceTexture::Success(t) => t,
            wgpu::CurrentSurfaceTexture::Suboptimal(t) => {
                self.resized = true;
                t
            }
            wgpu::CurrentSurfaceTexture::Outdated | wgpu::CurrentSurfaceTexture::Lost => {
                self.resized = true;
                return Ok(());
            }
            // Skip the frame: the window is hidden or the compositor is slow.
            wgpu::CurrentSurfaceTexture::Timeout | wgpu::CurrentSurfaceTexture::Occluded => {
                return Ok(());
            }
            wgpu::CurrentSurfaceTexture::Validation => {
                return Err("the window's surface refused a frame".into());
            }
        };
        let view = texture.texture.create_view(&Default::default());
        // The surface can lag a resize by a frame; the presenter refuses a size mismatch.
        if (self.config.width, self.config.height) == self.session.renderer.size() {
            self.draw_into(&view)?;
        }
        self.window.pre_present_notify();
        self.gpu.queue.present(texture);
        Ok(())
    }

    fn draw_into(&mut self, view: &wgpu::TextureView) -> Result<(), String> {
        self.session
            .renderer
            .present(&self.gpu, view, self.controls.exposure)
            .map_err(|e| e.to_string())?;
        let mut encoder = self.gpu.device.create_command_encoder(&Default::default());
        self.overlay
            .paint(&self.gpu.device, &self.gpu.queue, &mut encoder, view);
        self.gpu.queue.submit([encoder.finish()]);
        Ok(())
    }

    /// Applies a resize, a settings change or a dropped file before the next frame.
    fn apply_pending(&mut self) {
        if let Some(path) = self.dropped.take() {
            self.load_dropped(path);
        }
        let size = self.window.inner_size();
        if self.resized && size.width > 0 && size.height > 0 {
            self.resized = false;
            match surface_config(&self.surface, &self.gpu, size, self.vsync) {
                Ok(config) => {
                    self.surface.configure(&self.gpu.device, &config);
                    let changed =
                        (config.width, config.height) != (self.config.width, self.config.height);
                    self.config = config;
                    self.rebuild |= changed;
                }
                Err(e) => self.figures.status = e,
            }
        }
        if self.rebuild {
            self.rebuild = false;
            if let Err(e) = self.rebuild_renderer() {
                self.figures.status = e;
            }
        }
    }

    /// A new renderer for the current settings and window size; the old one stays on error.
    fn rebuild_renderer(&mut self) -> Result<(), String> {
        let s = &mut self.session;
        s.renderer.finish(&self.gpu).map_err(|e| e.to_string())?;
        let size = (self.config.width, self.config.height);
        let started = Instant::now();
        s.renderer = RealtimeRenderer::new(
            &self.gpu,
            self.backend,
            &s.scene,
            &s.gpu_scene,
            size.0,
            size.1,
            self.settings,
        )
        .map_err(|e| format!("settings not applied: {e}"))?;
        self.figures.report = None;
        log::info!(
            "renderer rebuilt at {}x{} in {:.2} s",
            size.0,
            size.1,
            started.elapsed().as_secs_f64()
        );
        Ok(())
    }

    /// Turns edited controls into settings (a tier sets several knobs at once).
    fn take_controls(&mut self, before: &Controls) {
        let c = &mut self.controls;
        self.session.camera.speed = c.speed;
        let mut s = self.settings;
        if c.tier != before.tier
            && let Some(tier) = c.tier
        {
            s = tier.apply(&s);
        } else {
            s.gi = c.gi;
            s.specular_gi = c.specular_gi;
            s.di.temporal = c.di_reuse;
            s.di.spatial = c.di_reuse;
            // A choice made here is the user's, not the light-count rule's.
            if c.di_reuse != before.di_reuse {
                s.di.reuse_light_threshold = 0;
            }
            s.denoiser = Some(c.denoiser);
            s.view = c.view;
        }
        if let Err(e) = s.validate() {
            self.figures.status = format!("not applied: {e}");
        } else if s != self.settings {
            self.settings = s;
            self.rebuild = true;
        }
        *c = controls_of(&self.settings, c.exposure, c.speed);
    }

    fn load_dropped(&mut self, path: PathBuf) {
        let ext = path
            .extension()
            .map(|e| e.to_string_lossy().to_ascii_lowercase());
        if !matches!(ext.as_deref(), Some("gltf" | "glb")) {
            self.figures.status = format!("{}: not a .gltf or .glb file", path.display());
            return;
        }
        let args = SceneArgs {
            scene: Some(path),
            generated: None,
            light_field: None,
            camera: None,
            asset_root: None,
            ..self.scene_args.clone()
        };
        if let Err(e) = self.session.renderer.finish(&self.gpu) {
            log::warn!("finishing the last frames: {e}");
        }
        let size = (self.config.width, self.config.height);
        let started = Instant::now();
        match Session::load(
            &self.gpu,
            self.backend,
            &args,
            &self.realtime_args,
            self.settings,
            size,
        ) {
            Ok(session) => {
                self.figures.status = format!(
                    "loaded {} in {:.1} s{}",
                    session.name,
                    started.elapsed().as_secs_f64(),
                    session
                        .quality
                        .as_ref()
                        .map_or(String::new(), |q| format!("; {}", q.line()))
                );
                self.settings = session.settings;
                self.controls =
                    controls_of(&self.settings, self.controls.exposure, self.controls.speed);
                self.session = session;
                self.controls.speed = self.session.camera.speed;
                self.figures.report = None;
                self.figures.non_finite = 0;
            }
            Err(e) => {
                log::error!("{e}");
                self.figures.status = e;
            }
        }
    }

    /// F12: the next free solari-view-N.png, or `--screenshot`.
    fn take_screenshot(&mut self) {
        if let Err(e) = self.screenshot_now() {
            log::error!("{e}");
            self.figures.status = e;
        }
    }

    fn screenshot_now(&mut self) -> Result<(), String> {
        let path = match &self.screenshot {
            Some(p) => p.clone(),
            None => loop {
                self.screenshots_taken += 1;
                let p = PathBuf::from(format!("solari-view-{}.png", self.screenshots_taken));
                if !p.exists() {
                    break p;
                }
            },
        };
        let s = &mut self.session;
        s.renderer.finish(&self.gpu).map_err(|e| e.to_string())?;
        let (w, h) = s.renderer.size();
        match ImageFormat::for_path(&path)? {
            ImageFormat::Exr => {
                let pixels = s
                    .renderer
                    .read_output(&self.gpu)
                    .map_err(|e| e.to_string())?;
                let rgb: Vec<[f32; 3]> = pixels.iter().map(|p| [p[0], p[1], p[2]]).collect();
                ImageOutputs {
                    files: vec![(path.clone(), ImageFormat::Exr)],
                }
                .write(w, h, &rgb, Some(0.0))?;
            }
            ImageFormat::Png => {
                let rgb = self.capture((w, h))?;
                write_atomic(&path, &encode_png_rgb8(w, h, &rgb)?)?;
            }
        }
        self.figures.status = format!("wrote {}", path.display());
        println!("wrote {}", path.display());
        Ok(())
    }

    /// The window's picture (frame and overlay) drawn again into a texture and read back as
    /// 8-bit RGB.
    fn capture(&mut self, size: (u32, u32)) -> Result<Vec<u8>, String> {
        let format = self.config.format;
        let texture = self.gpu.texture_2d(
            "solari_view/screenshot",
            size,
            format,
            wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
        );
        self.draw_into(&texture.create_view(&Default::default()))?;
        let bytes = self
            .gpu
            .read_texture(&texture, wgpu::TextureAspect::All)
            .map_err(|e| e.to_string())?;
        let bgra = matches!(
            format,
            wgpu::TextureFormat::Bgra8Unorm | wgpu::TextureFormat::Bgra8UnormSrgb
        );
        Ok(bytes
            .chunks_exact(4)
            .flat_map(|p| {
                if bgra {
                    [p[2], p[1], p[0]]
                } else {
                    [p[0], p[1], p[2]]
                }
            })
            .collect())
    }
}

/// The overlay's view of `settings`.
fn controls_of(settings: &RealtimeSettings, exposure: f32, speed: f32) -> Controls {
    Controls {
        gi: settings.gi,
        denoiser: settings.denoiser.unwrap_or(DenoiserKind::Fallback),
        view: settings.view,
        specular_gi: settings.specular_gi,
        di_reuse: settings.di.temporal && settings.di.spatial,
        tier: QualityTier::of(settings),
        exposure,
        speed,
    }
}

/// An 8-bit RGBA/BGRA surface format at the window's size (plain unorm first: egui blends
/// in sRGB space and warns on sRGB targets; the presenter encodes sRGB itself): the presenter writes
/// every one of them, and screenshots read them back byte for byte.
fn surface_config(
    surface: &wgpu::Surface,
    gpu: &Gpu,
    size: winit::dpi::PhysicalSize<u32>,
    vsync: bool,
) -> Result<wgpu::SurfaceConfiguration, String> {
    use wgpu::TextureFormat as F;
    let caps = surface.get_capabilities(&gpu.adapter);
    let format = [
        F::Bgra8Unorm,
        F::Rgba8Unorm,
        F::Bgra8UnormSrgb,
        F::Rgba8UnormSrgb,
    ]
    .into_iter()
    .find(|f| caps.formats.contains(f))
    .ok_or_else(|| {
        format!(
            "the window offers no 8-bit RGBA format (only {:?})",
            caps.formats
        )
    })?;
    let present_mode = if vsync {
        wgpu::PresentMode::AutoVsync
    } else {
        wgpu::PresentMode::AutoNoVsync
    };
    Ok(wgpu::SurfaceConfiguration {
        usage: wgpu::TextureUsages::RENDER_ATTACHMENT,
        format,
        color_space: wgpu::SurfaceColorSpace::Auto,
        width: size.width.max(1),
        height: size.height.max(1),
        desired_maximum_frame_latency: 2,
        present_mode,
        alpha_mode: wgpu::CompositeAlphaMode::Auto,
        view_formats: vec![],
    })
}
