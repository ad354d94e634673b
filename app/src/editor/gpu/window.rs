//! The editor's window: winit events, the wgpu surface, and one frame as
//! input → edits → solve → render (the 3D viewport, then egui on top).

use crate::editor::document::EditorDocument;
use crate::editor::files::{Autosave, RecentFiles};
use crate::editor::live::CompareMode;
use crate::editor::state::{EditorState, SOLVER_BUDGET};
use crate::editor::ui::{Pending, UiState};
use std::path::PathBuf;
use std::sync::Arc;
use std::time::Instant;
use taut_render::passes::surface::GHOST;
use taut_render::renderer::Attachments;
use taut_render::{
    AdapterPreference, Gpu, GpuSurface, Renderer, Scene, ShownMesh, SurfaceCache, TargetFormats, offscreen,
};
use winit::application::ApplicationHandler;
use winit::event::WindowEvent;
use winit::event_loop::{ActiveEventLoop, ControlFlow, EventLoop};
use winit::window::{Window, WindowId};

/// The scene the editor opens when no file is given.
const DEFAULT_SCENE: &str = include_str!("../../../../assets/default.taut");

/// How the editor starts.
#[derive(Debug, Default)]
pub struct Startup {
    /// A file to open instead of the default scene.
    pub file: Option<PathBuf>,
    /// The first display mode: "shaded", "zebra" or "curvature".
    pub view: String,
}

/// Runs the editor until its window closes.
pub fn run(startup: Startup) -> Result<(), String> {
    let event_loop = EventLoop::new().map_err(|e| format!("cannot open a window: {e} (is a display available?)"))?;
    event_loop.set_control_flow(ControlFlow::Wait);
    let mut app = App { startup: Some(startup), running: None, error: None };
    event_loop.run_app(&mut app).map_err(|e| format!("the window system failed: {e}"))?;
    match app.error {
        Some(e) => Err(e),
        None => Ok(()),
    }
}

struct App {
    startup: Option<Startup>,
    running: Option<Running>,
    error: Option<String>,
}

struct Running {
    window: Arc<Window>,
    gpu: Gpu,
    /// The window's drawing target (wgpu's surface).
    screen: wgpu::Surface<'static>,
    config: wgpu::SurfaceConfiguration,
    renderer: Renderer,
    attachments: Attachments,
    egui_state: egui_winit::State,
    egui_renderer: egui_wgpu::Renderer,
    editor: EditorState,
    ui: UiState,
    /// The surface on the GPU: its mesh generations, colour values and display frame.
    surface_gpu: SurfaceCache<(u64, u64, u64, taut_render::DisplayFrame)>,
    /// The other scheme's surface of the compare view, drawn as a ghost.
    ghost: Ghost,
    /// The Coons patches of the Curves workspace.
    patches: crate::editor::curves_render::PatchSurface,
    /// The original mesh of a cage made from a mesh, drawn as a second ghost.
    original_ghost: crate::editor::cage_from_mesh::OriginalGhost,
    title: String,
    /// When egui wants the next frame (a tooltip delay, a cursor blink), if not at once.
    repaint_at: Option<Instant>,
}

impl ApplicationHandler for App {
    fn resumed(&mut self, event_loop: &ActiveEventLoop) {
        let Some(startup) = self.startup.take() else { return };
        match Running::new(event_loop, startup) {
            Ok(running) => self.running = Some(running),
            Err(e) => {
                self.error = Some(e);
                event_loop.exit();
            }
        }
    }

    fn window_event(&mut self, event_loop: &ActiveEventLoop, _id: WindowId, event: WindowEvent) {
        let Some(running) = &mut self.running else { return };
        let response = running.egui_state.on_window_event(&running.window, &event);
        // egui asks to repaint after every redraw; honouring that would redraw for ever. A frame
        // that needs another one says so itself (see the end of `frame`).
        let repaint = response.repaint && !matches!(event, WindowEvent::RedrawRequested);
        match event {
            WindowEvent::CloseRequested => {
                running.editor.request(Pending::Quit, &mut running.ui);
                running.window.request_redraw();
            }
            WindowEvent::Resized(size) => running.resize(size.width, size.height),
            WindowEvent::DroppedFile(path) => {
                running.editor.request(Pending::Open(Some(path)), &mut running.ui);
                running.window.request_redraw();
            }
            WindowEvent::RedrawRequested => {
                running.frame();
                if running.ui.quit {
                    if let Some(a) = &running.editor.autosave {
                        let _ = a.clear();
                    }
                    event_loop.exit();
                }
            }
            _ => {}
        }
        if repaint {
            running.window.request_redraw();
        }
    }

    fn about_to_wait(&mut self, event_loop: &ActiveEventLoop) {
        let Some(running) = &mut self.running else { return };
        if running.editor.busy() {
            running.window.request_redraw();
            return;
        }
        // Wake for what egui scheduled (a tooltip, a blinking cursor) and for the autosave;
        // otherwise sleep until the next event.
        let now = Instant::now();
        let wake = [running.repaint_at, Some(running.editor.next_autosave())].into_iter().flatten().min();
        match wake {
            Some(at) if at <= now => {
                running.repaint_at = None;
                running.window.request_redraw();
            }
            Some(at) => event_loop.set_control_flow(ControlFlow::WaitUntil(at)),
            None => event_loop.set_control_flow(ControlFlow::Wait),
        }
    }
}

impl Running {
    fn new(event_loop: &ActiveEventLoop, startup: Startup) -> Result<Self, String> {
        let attributes = Window::default_attributes()
            .with_title("Taut")
            .with_inner_size(winit::dpi::LogicalSize::new(1280.0, 800.0));
        let window = Arc::new(event_loop.create_window(attributes).map_err(|e| format!("cannot open a window: {e}"))?);
        let instance = wgpu::Instance::new(wgpu::InstanceDescriptor::new_without_display_handle_from_env());
        let surface =
            instance.create_surface(window.clone()).map_err(|e| format!("cannot draw into the window: {e}"))?;
        let gpu = Gpu::for_surface(instance, &surface, AdapterPreference::Hardware).map_err(|e| e.to_string())?;
        let size = window.inner_size();
        let mut config = surface
            .get_default_config(&gpu.adapter, size.width.max(1), size.height.max(1))
            .ok_or("the GPU cannot draw into this window")?;
        // The 3D passes write linear colour and egui adapts to the format: use an sRGB one.
        let formats = surface.get_capabilities(&gpu.adapter).formats;
        if let Some(srgb) = formats.iter().copied().find(|f| f.is_srgb()) {
            config.format = srgb;
        }
        surface.configure(&gpu.device, &config);
        let mut targets = TargetFormats::for_adapter(&gpu.adapter, config.format);
        if gpu.adapter.get_info().device_type == wgpu::DeviceType::Cpu {
            // A software rasteriser pays four times per pixel for MSAA: stay live without it
            // (lines and stripes keep their own anti-aliasing in the shaders).
            targets.samples = 1;
        }
        let renderer = Renderer::new(&gpu, targets);
        let attachments = Attachments::new(&gpu.device, &targets, config.width, config.height);
        let egui_ctx = egui::Context::default();
        let egui_state = egui_winit::State::new(
            egui_ctx,
            egui::ViewportId::ROOT,
            &window,
            Some(window.scale_factor() as f32),
            None,
            None,
        );
        let egui_renderer = egui_wgpu::Renderer::new(&gpu.device, config.format, egui_wgpu::RendererOptions::default());

        let recent = RecentFiles::load();
        let autosave = Autosave::in_data_folder();
        let mut notice = None;
        let document = match &startup.file {
            Some(path) => EditorDocument::open(path).unwrap_or_else(|e| {
                notice = Some(format!("could not open {}: {e}", path.display()));
                default_document()
            }),
            None => default_document(),
        };
        let recovery = autosave.as_ref().and_then(|a| a.pending());
        let mut editor = EditorState::new(document, recent, autosave);
        editor.view.display.mode = match startup.view.as_str() {
            "shaded" => crate::editor::state::DisplayMode::Shaded,
            "curvature" => crate::editor::state::DisplayMode::Curvature,
            _ => crate::editor::state::DisplayMode::Zebra,
        };
        if let Some(path) = startup.file.as_ref().filter(|_| notice.is_none()) {
            let _ = editor.recent.add(path);
        }
        if let Some(text) = notice {
            editor.notify(text, true);
        }
        let ui = UiState { recovery, ..Default::default() };
        let title = format!("Taut — {}", editor.document.title());
        window.set_title(&title);
        Ok(Running {
            window,
            gpu,
            screen: surface,
            config,
            renderer,
            attachments,
            egui_state,
            egui_renderer,
            editor,
            ui,
            surface_gpu: SurfaceCache::default(),
            ghost: Ghost::default(),
            patches: Default::default(),
            original_ghost: Default::default(),
            title,
            repaint_at: None,
        })
    }

    fn resize(&mut self, width: u32, height: u32) {
        if width == 0 || height == 0 {
            return;
        }
        self.config.width = width;
        self.config.height = height;
        self.screen.configure(&self.gpu.device, &self.config);
        self.attachments = Attachments::new(&self.gpu.device, &self.renderer.targets, width, height);
        self.window.request_redraw();
    }

    fn frame(&mut self) {
        let started = Instant::now();
        // Input → edits.
        let raw_input = self.egui_state.take_egui_input(&self.window);
        let (editor, ui_state) = (&mut self.editor, &mut self.ui);
        let mut output = self.egui_state.egui_ctx().clone().run_ui(raw_input, |ui| editor.ui(ui, ui_state));
        self.egui_state.handle_platform_output(&self.window, output.platform_output);
        // Solve.
        self.editor.step_solver(SOLVER_BUDGET);
        self.editor.refresh_values();
        self.editor.autosave_if_due();
        // Setting the title makes the window system send events, and every event a redraw: set it
        // only when it changes, or an idle editor redraws for ever.
        let title = format!("Taut — {}", self.editor.document.title());
        if title != self.title {
            self.window.set_title(&title);
            self.title = title;
        }
        // Render.
        self.upload_surface();
        self.ghost.upload(&self.gpu, &self.editor);
        self.patches.upload(&self.gpu, &self.editor);
        self.original_ghost.upload(&self.gpu, &self.editor);
        let mut overlays = self.editor.workspace_overlays();
        // The window's legend is drawn by egui in the viewport's strip (see `legend.rs`).
        overlays.legend = None;
        // Reference pictures behind or over the model, in both workspaces (curves are traced over them).
        let references =
            self.editor.references.quads(&self.editor.document.doc().reference_images, &self.editor.view.display_frame);
        let scene = match self.patches.scene(&self.editor, self.surface_gpu.surface(), &overlays) {
            Some(scene) => Scene { viewport: self.ui.viewport_px, reference_images: &references, ..scene },
            None => Scene {
                overlays: Some(&overlays),
                viewport: self.ui.viewport_px,
                ghost: self.ghost.shown(&self.editor),
                second_ghost: self.original_ghost.shown(&self.editor),
                clip_plane: self.editor.clip_plane(),
                reference_images: &references,
                ..Scene::new(self.editor.view.camera, self.surface_gpu.surface(), self.editor.surface_mode())
            },
        };
        // egui's texture changes are applied whether or not this frame reaches the screen.
        let mut textures = std::mem::take(&mut output.textures_delta);
        for (id, deltas) in &textures.set {
            for delta in deltas {
                self.egui_renderer.update_texture(&self.gpu.device, &self.gpu.queue, *id, delta);
            }
        }
        textures.set.clear();
        for id in std::mem::take(&mut textures.free) {
            self.egui_renderer.free_texture(&id);
        }
        let frame = match self.screen.get_current_texture() {
            wgpu::CurrentSurfaceTexture::Success(t) | wgpu::CurrentSurfaceTexture::Suboptimal(t) => t,
            wgpu::CurrentSurfaceTexture::Outdated | wgpu::CurrentSurfaceTexture::Lost => {
                self.screen.configure(&self.gpu.device, &self.config);
                self.window.request_redraw();
                return;
            }
            _ => {
                self.window.request_redraw();
                return;
            }
        };
        let view = frame.texture.create_view(&Default::default());
        let device = &self.gpu.device;
        let queue = &self.gpu.queue;
        let mut encoder = device.create_command_encoder(&Default::default());
        self.renderer.encode(device, queue, &mut encoder, &view, &self.attachments, &scene);

        let ppp = output.pixels_per_point;
        let jobs = self.egui_state.egui_ctx().tessellate(output.shapes, ppp);
        let screen = egui_wgpu::ScreenDescriptor {
            size_in_pixels: [self.config.width, self.config.height],
            pixels_per_point: ppp,
        };
        let mut extra = self.egui_renderer.update_buffers(device, queue, &mut encoder, &jobs, &screen);
        {
            let pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("egui"),
                color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                    view: &view,
                    depth_slice: None,
                    resolve_target: None,
                    ops: wgpu::Operations { load: wgpu::LoadOp::Load, store: wgpu::StoreOp::Store },
                })],
                depth_stencil_attachment: None,
                timestamp_writes: None,
                occlusion_query_set: None,
                multiview_mask: None,
            });
            self.egui_renderer.render(&mut pass.forget_lifetime(), &jobs, &screen);
        }
        extra.push(encoder.finish());
        queue.submit(extra);
        queue.present(frame);
        if let Some(path) = self.ui.screenshot.take() {
            self.screenshot(&path);
        }
        self.editor.frame_time = started.elapsed();
        let delay = output.viewport_output.values().map(|v| v.repaint_delay).min();
        if self.editor.busy() || self.editor.curves_busy() || delay.is_some_and(|d| d.is_zero()) {
            self.window.request_redraw();
        } else if let Some(d) = delay.filter(|d| *d < std::time::Duration::from_secs(3600)) {
            self.repaint_at = Some(Instant::now() + d);
        }
    }

    /// Uploads the surface when the solver moved it or the curvature values changed.
    fn upload_surface(&mut self) {
        let Some(surface) = &self.editor.surface else {
            self.surface_gpu.clear();
            return;
        };
        let mesh = surface.mesh();
        let frame = self.editor.view.display_frame;
        let key = (mesh.topology_generation(), mesh.generation(), surface.values_id, frame);
        let values = surface.values.as_ref().map(|(v, _, _)| v.as_slice());
        let shown = ShownMesh { mesh, normals: surface.scheme.normals(), values };
        self.surface_gpu.show(&self.gpu, key, shown, &frame);
    }

    /// Saves the viewport (without the panels) as a PNG of its size on screen.
    fn screenshot(&mut self, path: &std::path::Path) {
        let [_, _, w, h] = self.ui.viewport_px.unwrap_or([0, 0, self.config.width, self.config.height]);
        let overlays = self.editor.workspace_overlays();
        let references =
            self.editor.references.quads(&self.editor.document.doc().reference_images, &self.editor.view.display_frame);
        let scene = self.patches.scene(&self.editor, self.surface_gpu.surface(), &overlays).unwrap_or_else(|| Scene {
            clip_plane: self.editor.clip_plane(),
            ..Scene::new(self.editor.view.camera, self.surface_gpu.surface(), self.editor.surface_mode())
                .with_overlays(&overlays)
        });
        let scene = Scene { reference_images: &references, ..scene };
        // An off-screen picture needs a format the read-back understands.
        let targets = TargetFormats::for_adapter(&self.gpu.adapter, wgpu::TextureFormat::Rgba8UnormSrgb);
        let mut renderer = Renderer::new(&self.gpu, targets);
        match offscreen::render_image(&self.gpu, &mut renderer, &scene, w, h)
            .and_then(|img| offscreen::save_png(&img, path))
        {
            Ok(()) => self.editor.notify(format!("saved the screenshot {}", path.display()), false),
            Err(e) => self.editor.notify(format!("could not save the screenshot: {e}"), true),
        }
    }
}

/// A second surface drawn translucent over the first: the compare view's other scheme.
#[derive(Debug, Default)]
struct Ghost {
    cache: SurfaceCache<(u64, u64, taut_render::DisplayFrame)>,
}

impl Ghost {
    /// Uploads the comparison surface when it changed; drops it when the compare view is off.
    fn upload(&mut self, gpu: &taut_render::Gpu, editor: &crate::editor::state::EditorState) {
        let Some(other) = editor.comparison.as_ref().filter(|_| editor.view.display.compare == CompareMode::Ghost)
        else {
            self.cache.clear();
            return;
        };
        let mesh = other.scheme.mesh();
        let key = (mesh.topology_generation(), mesh.generation(), editor.view.display_frame);
        let shown = ShownMesh { mesh, normals: other.scheme.normals(), values: None };
        self.cache.show(gpu, key, shown, &editor.view.display_frame);
    }

    fn shown(&self, editor: &crate::editor::state::EditorState) -> Option<(&GpuSurface, [f32; 4])> {
        (editor.view.display.compare == CompareMode::Ghost)
            .then_some(self.cache.surface())
            .flatten()
            .map(|g| (g, GHOST))
    }
}

fn default_document() -> EditorDocument {
    let doc = taut_core::Document::from_json(DEFAULT_SCENE, std::path::Path::new("default.taut"))
        .expect("the bundled default scene is valid");
    EditorDocument::new(doc, None)
}
