//! The viewer's on-screen overlay (egui, drawn by egui-wgpu into the window's texture): frame
//! and per-pass GPU times, the renderer's main toggles, a status line and the key help. It
//! reads and edits a [`Controls`] value; the viewer applies what changed.

use solari_denoise::DenoiserKind;
use solari_renderer::{FrameReport, FrameView, GiMode, PASS_NAMES, QualityTier};
use solari_scene::gbuffer_debug::GBufferChannel;
use std::time::Duration;

/// What the overlay shows and lets the user change.
#[derive(Clone, Debug, PartialEq)]
pub struct Controls {
    /// GI mode.
    pub gi: GiMode,
    /// Denoiser (none or fallback in the viewer).
    pub denoiser: DenoiserKind,
    /// What the frame shows.
    pub view: FrameView,
    /// Specular GI on.
    pub specular_gi: bool,
    /// ReSTIR DI reuse (temporal and spatial) on.
    pub di_reuse: bool,
    /// The tier the knobs match (`None`: hand-tuned).
    pub tier: Option<QualityTier>,
    /// Exposure in EV.
    pub exposure: f32,
    /// Camera speed in units per second.
    pub speed: f32,
}

/// What a click asked for, beside edits of [`Controls`].
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Requests {
    /// Write a screenshot.
    pub screenshot: bool,
    /// Put the camera back where it started.
    pub reset_camera: bool,
}

/// Frame figures the overlay prints.
#[derive(Clone, Debug, Default)]
pub struct FrameFigures {
    /// Scene name.
    pub scene: String,
    /// Adapter and tracing backend.
    pub device: String,
    /// Output size and render size.
    pub output: (u32, u32),
    /// The lighting passes' size (below the output with an internal scale).
    pub render: (u32, u32),
    /// Frames rendered.
    pub frames: u64,
    /// Wall time between frames (the median of the last 31).
    pub wall: Option<Duration>,
    /// The latest report (GPU times arrive a frame or two late).
    pub report: Option<FrameReport>,
    /// Non-finite values counted so far (with the detector on).
    pub non_finite: u64,
    /// The last message (a written screenshot, a load error).
    pub status: String,
}

/// egui's context, its winit glue and its wgpu renderer for one window.
pub struct Overlay {
    ctx: egui::Context,
    state: egui_winit::State,
    renderer: egui_wgpu::Renderer,
    jobs: Vec<egui::ClippedPrimitive>,
    pixels_per_point: f32,
    /// Whether the overlay is drawn (F1).
    pub visible: bool,
}

impl Overlay {
    /// Sets up egui for `window`, drawing into textures of `format`.
    pub fn new(
        window: &winit::window::Window,
        device: &wgpu::Device,
        format: wgpu::TextureFormat,
        visible: bool,
    ) -> Self {
        let ctx = egui::Context::default();
        let max_texture = device.limits().max_texture_dimension_2d as usize;
        let state = egui_winit::State::new(
            ctx.clone(),
            egui::ViewportId::ROOT,
            window,
            Some(window.scale_factor() as f32),
            None,
            Some(max_texture),
        );
        let renderer = egui_wgpu::Renderer::new(device, format, Default::default());
        Self {
            ctx,
            state,
            renderer,
            jobs: Vec::new(),
            pixels_per_point: window.scale_factor() as f32,
            visible,
        }
    }

    /// Passes a window event to egui; true when egui used it (the camera should not).
    pub fn on_event(
        &mut self,
        window: &winit::window::Window,
        event: &winit::event::WindowEvent,
    ) -> bool {
        self.visible && self.state.on_window_event(window, event).consumed
    }

    /// Whether egui wants the keyboard (a focused widget).
    pub fn wants_keyboard(&self) -> bool {
        self.visible && self.ctx.egui_wants_keyboard_input()
    }

    /// Whether the pointer is over the overlay or dragging one of its widgets.
    pub fn wants_pointer(&self) -> bool {
        self.visible && self.ctx.egui_wants_pointer_input()
    }

    /// Builds this frame's overlay from `figures`, editing `controls`; uploads its textures.
    pub fn update(
        &mut self,
        window: &winit::window::Window,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        figures: &FrameFigures,
        controls: &mut Controls,
    ) -> Requests {
        let mut requests = Requests::default();
        if !self.visible {
            self.jobs.clear();
            return requests;
        }
        let input = self.state.take_egui_input(window);
        let output = self.ctx.run_pass(input, |ctx| {
            panel(ctx, figures, controls, &mut requests);
            pass_window(ctx, figures.report.as_ref());
        });
        self.state
            .handle_platform_output(window, output.platform_output);
        self.pixels_per_point = output.pixels_per_point;
        self.jobs = self.ctx.tessellate(output.shapes, output.pixels_per_point);
        for (id, deltas) in &output.textures_delta.set {
            for delta in deltas {
                self.renderer.update_texture(device, queue, *id, delta);
            }
        }
        for id in &output.textures_delta.free {
            self.renderer.free_texture(id);
        }
        requests
    }

    /// Draws the last [`Overlay::update`] over `target` (whose contents are kept).
    pub fn paint(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        encoder: &mut wgpu::CommandEncoder,
        target: &wgpu::TextureView,
    ) {
        if !self.visible || self.jobs.is_empty() {
            return;
        }
        let size = target.texture().size();
        let screen = egui_wgpu::ScreenDescriptor {
            size_in_pixels: [size.width, size.height],
            pixels_per_point: self.pixels_per_point,
        };
        let extra = self
            .renderer
            .update_buffers(device, queue, encoder, &self.jobs, &screen);
        queue.submit(extra);
        let pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("solari_view/overlay"),
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view: target,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Load,
                    store: wgpu::StoreOp::Store,
                },
            })],
            depth_stencil_attachment: None,
            timestamp_writes: None,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        self.renderer
            .render(&mut pass.forget_lifetime(), &self.jobs, &screen);
    }
}

const GI_MODES: [(GiMode, &str); 4] = [
    (GiMode::Off, "off"),
    (GiMode::WorldCache, "world cache"),
    (GiMode::Path, "path (1 bounce)"),
    (GiMode::Restir, "ReSTIR GI"),
];

fn panel(ctx: &egui::Context, f: &FrameFigures, c: &mut Controls, requests: &mut Requests) {
    egui::Window::new("Solari")
        .default_pos([8.0, 8.0])
        .default_width(260.0)
        .resizable(false)
        .show(ctx, |ui| {
            // The file's name: a full path would widen the panel.
            let name = std::path::Path::new(&f.scene)
                .file_name()
                .map_or(f.scene.clone(), |n| n.to_string_lossy().into_owned());
            ui.label(name).on_hover_text(&f.scene);
            ui.small(&f.device);
            ui.small(format!(
                "{}×{} output, lighting at {}×{}",
                f.output.0, f.output.1, f.render.0, f.render.1
            ));
            let gpu_ms: Option<f64> = f.report.as_ref().and_then(|r| {
                let times: Vec<f64> = r.passes.iter().filter_map(|p| p.gpu_ms).collect();
                (!times.is_empty()).then(|| times.iter().sum())
            });
            ui.label(format!(
                "frame {} · wall {} · GPU {}",
                f.frames,
                f.wall.map_or("–".into(), |w| format!(
                    "{:.2} ms ({:.0} fps)",
                    w.as_secs_f64() * 1e3,
                    1.0 / w.as_secs_f64().max(1e-9)
                )),
                gpu_ms.map_or("–".into(), |ms| format!("{ms:.2} ms"))
            ));
            if f.non_finite > 0 {
                ui.colored_label(
                    egui::Color32::LIGHT_RED,
                    format!("{} non-finite values so far", f.non_finite),
                );
            }
            ui.separator();
            let before = c.tier;
            egui::ComboBox::from_label("quality")
                .selected_text(c.tier.map_or("custom", |t| t.name()))
                .show_ui(ui, |ui| {
                    for t in QualityTier::ALL {
                        ui.selectable_value(&mut c.tier, Some(t), t.name());
                    }
                });
            if c.tier != before {
                // The viewer applies the tier and reads the knobs back.
                return;
            }
            egui::ComboBox::from_label("GI")
                .selected_text(GI_MODES.iter().find(|m| m.0 == c.gi).map_or("?", |m| m.1))
                .show_ui(ui, |ui| {
                    for (mode, name) in GI_MODES {
                        ui.selectable_value(&mut c.gi, mode, name);
                    }
                });
            ui.checkbox(&mut c.specular_gi, "specular GI");
            ui.checkbox(&mut c.di_reuse, "ReSTIR DI reuse")
                .on_hover_text(
                    "From the command line (--di-reuse auto) reuse is skipped on scenes of few \
                 lights under the fallback denoiser; toggling here sets it for every scene",
                );
            egui::ComboBox::from_label("denoiser")
                .selected_text(c.denoiser.name())
                .show_ui(ui, |ui| {
                    for d in [DenoiserKind::None, DenoiserKind::Fallback] {
                        ui.selectable_value(&mut c.denoiser, d, d.name());
                    }
                });
            egui::ComboBox::from_label("view")
                .selected_text(view_label(c.view))
                .show_ui(ui, |ui| {
                    let views = [FrameView::Lit, FrameView::Indirect, FrameView::WorldCache]
                        .into_iter()
                        .chain(GBufferChannel::ALL.map(FrameView::GBuffer));
                    for v in views {
                        ui.selectable_value(&mut c.view, v, view_label(v));
                    }
                });
            ui.add(egui::Slider::new(&mut c.exposure, -8.0..=8.0).text("exposure EV"));
            ui.add(
                egui::Slider::new(&mut c.speed, 0.01..=1000.0)
                    .logarithmic(true)
                    .text("speed /s"),
            );
            ui.horizontal(|ui| {
                requests.screenshot = ui.button("screenshot (F12)").clicked();
                requests.reset_camera = ui.button("reset camera (R)").clicked();
            });
            if !f.status.is_empty() {
                ui.small(&f.status);
            }
            ui.small(
                "WASD move · Q/E down/up · right-drag look · Shift fast · F1 overlay · \
                 drop a .gltf/.glb · Esc quit",
            );
        });
}

/// The passes that ran and their GPU times, in a window at the top right.
// The view's name in the overlay.
fn view_label(v: FrameView) -> String {
    match v {
        FrameView::Lit => "lit".into(),
        FrameView::Indirect => "indirect light alone".into(),
        FrameView::WorldCache => "world cache cells".into(),
        FrameView::GBuffer(c) => format!("G-buffer: {}", c.name()),
    }
}

fn pass_window(ctx: &egui::Context, report: Option<&FrameReport>) {
    egui::Window::new("GPU ms per pass")
        .anchor(egui::Align2::RIGHT_TOP, [-8.0, 8.0])
        .resizable(false)
        .collapsible(true)
        .show(ctx, |ui| pass_table(ui, report));
}

fn pass_table(ui: &mut egui::Ui, report: Option<&FrameReport>) {
    let Some(report) = report else {
        ui.small("waiting for the first report");
        return;
    };
    egui::Grid::new("passes").striped(true).show(ui, |ui| {
        for name in PASS_NAMES {
            let Some(pass) = report.passes.iter().find(|p| p.name == name) else {
                continue;
            };
            if !pass.ran {
                continue;
            }
            ui.small(name);
            ui.small(
                pass.gpu_ms
                    .map_or("untimed".into(), |ms| format!("{ms:.3}")),
            );
            ui.end_row();
        }
    });
}
