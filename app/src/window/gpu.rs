//! The GPU side: the framebuffer (a texture at the render resolution) shown as an egui image
//! in the area beside the panel, and egui drawn to the window's surface in one pass.
//!
//! The framebuffer is registered with egui-wgpu as a native texture, so the image is laid out by
//! egui (scaled to fit with its aspect ratio) and never sits under the panel. The texture is
//! `Rgba8Unorm` holding our sRGB-encoded bytes, which is what egui expects of its textures.
//!
//! The surface is wgpu's own: a frame whose surface went out of date (the window was resized
//! between reading its size and drawing: X11's Vulkan drivers then answer every texture of the
//! old size as suboptimal or out of date) is configured at the window's size now and tried once
//! more, else skipped and drawn again. (`pixels` 0.17, used before, retried at the size it had
//! cached, forever: the window froze during a resize.)

use egui_wgpu::{Renderer, RendererOptions, ScreenDescriptor};
use std::sync::Arc;
use std::time::{Duration, Instant};
use winit::dpi::PhysicalSize;
use winit::window::Window;

/// The device, the window's surface, the framebuffer and the egui renderer.
pub struct Gpu {
    device: wgpu::Device,
    queue: wgpu::Queue,
    window: Arc<Window>,
    surface: wgpu::Surface<'static>,
    /// The surface's configuration: its size is the window's, in physical pixels.
    config: wgpu::SurfaceConfiguration,
    framebuffer: wgpu::Texture,
    renderer: Renderer,
    /// The framebuffer as an egui texture.
    pub texture_id: egui::TextureId,
    /// The framebuffer size (the render resolution of the image shown).
    pub buffer_size: (u32, u32),
    /// Fail the next draw as a lost surface would (the script's `lose-surface`).
    pub lose_next_draw: bool,
    /// Resize the window during the next draw (the script's `resize-in-draw`).
    pub resize_in_next_draw: Option<PhysicalSize<u32>>,
}

/// An RGBA8 image read back from the GPU.
pub struct Capture {
    pub width: u32,
    pub height: u32,
    pub rgba: Vec<u8>,
}

/// The surface's next texture, or why there is none to draw on.
enum Next {
    Texture(wgpu::SurfaceTexture),
    Not(Drawn),
}

/// What a draw did.
pub enum Drawn {
    /// The frame is on screen (read back too where asked).
    Shown(Option<Capture>),
    /// The window hid the surface (minimised, covered) or the driver timed out: nothing to show.
    Hidden,
    /// The surface was out of date even at the window's size now: draw again.
    Skipped,
}

impl Gpu {
    /// Creates the surface, device and renderers; a clear error if no adapter can be had.
    pub fn new(
        window: Arc<Window>,
        surface: (u32, u32),
        buffer: (u32, u32),
    ) -> Result<Self, String> {
        let no_device = |e: String| {
            format!(
                "cannot open a graphics device ({e}); a Vulkan, Metal or DX12 adapter is needed \
                 (on Linux without a GPU install Mesa's lavapipe: mesa-vulkan-drivers)"
            )
        };
        let backends = wgpu::Backends::from_env().unwrap_or(wgpu::Backends::PRIMARY);
        let instance = wgpu::Instance::new(wgpu::InstanceDescriptor {
            backends,
            ..wgpu::InstanceDescriptor::new_without_display_handle().with_env()
        });
        let window_surface =
            (instance.create_surface(window.clone())).map_err(|e| no_device(e.to_string()))?;
        let (adapter, device, queue) =
            pollster::block_on(open_device(&instance, &window_surface)).map_err(no_device)?;
        let capabilities = window_surface.get_capabilities(&adapter);
        // The first sRGB format the surface offers: egui's colours are blended in linear light.
        let format = (capabilities.formats.iter().find(|f| f.is_srgb()).copied())
            .unwrap_or(wgpu::TextureFormat::Bgra8UnormSrgb);
        let config = wgpu::SurfaceConfiguration {
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT,
            format,
            // (wgpu refuses a 0×0 surface: a window minimised from the start.)
            width: surface.0.max(1),
            height: surface.1.max(1),
            present_mode: wgpu::PresentMode::AutoVsync,
            desired_maximum_frame_latency: 2,
            alpha_mode: wgpu::CompositeAlphaMode::Auto,
            view_formats: vec![],
        };
        window_surface.configure(&device, &config);
        let mut renderer = Renderer::new(
            &device,
            format,
            RendererOptions {
                dithering: false,
                ..Default::default()
            },
        );
        let framebuffer = framebuffer(&device, buffer);
        let view = framebuffer.create_view(&wgpu::TextureViewDescriptor::default());
        let texture_id =
            renderer.register_native_texture_with_sampler_options(&device, &view, sampler());
        Ok(Self {
            device,
            queue,
            window,
            surface: window_surface,
            config,
            framebuffer,
            renderer,
            texture_id,
            buffer_size: buffer,
            lose_next_draw: false,
            resize_in_next_draw: None,
        })
    }

    /// Largest texture side the device takes.
    pub fn max_texture_side(&self) -> usize {
        self.device.limits().max_texture_dimension_2d as usize
    }

    /// Shows a rendered RGBA8 image, resizing the framebuffer when its size changed.
    pub fn set_frame(&mut self, width: u32, height: u32, rgba: &[u8]) -> Result<(), String> {
        let max = self.max_texture_side() as u32;
        if width == 0 || height == 0 || width > max || height > max {
            return Err(format!(
                "framebuffer {width}x{height}: the device takes 1 to {max} pixels a side"
            ));
        }
        if rgba.len() != width as usize * height as usize * 4 {
            return Err(format!(
                "frame of {} bytes for a {width}x{height} framebuffer",
                rgba.len()
            ));
        }
        if (width, height) != self.buffer_size {
            self.framebuffer = framebuffer(&self.device, (width, height));
            let view = (self.framebuffer).create_view(&wgpu::TextureViewDescriptor::default());
            self.renderer
                .update_egui_texture_from_wgpu_texture_with_sampler_options(
                    &self.device,
                    &view,
                    sampler(),
                    self.texture_id,
                );
            self.buffer_size = (width, height);
        }
        self.queue.write_texture(
            self.framebuffer.as_image_copy(),
            rgba,
            wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(width * 4),
                rows_per_image: Some(height),
            },
            self.framebuffer.size(),
        );
        Ok(())
    }

    /// Follows the window's size in physical pixels; 0×0 (minimised) is skipped.
    pub fn resize_surface(&mut self, width: u32, height: u32) -> Result<(), String> {
        if width == 0 || height == 0 || (width, height) == (self.config.width, self.config.height) {
            return Ok(());
        }
        self.configure(width, height)
    }

    /// The surface's next texture: tried again once at the window's size now where the surface
    /// is out of date; never more (see the module's docs).
    fn next_texture(&mut self) -> Result<Next, String> {
        for _ in 0..2 {
            match self.surface.get_current_texture() {
                wgpu::CurrentSurfaceTexture::Success(texture) => return Ok(Next::Texture(texture)),
                wgpu::CurrentSurfaceTexture::Occluded | wgpu::CurrentSurfaceTexture::Timeout => {
                    return Ok(Next::Not(Drawn::Hidden))
                }
                wgpu::CurrentSurfaceTexture::Validation => {
                    return Err("drawing the window: the surface failed validation".into())
                }
                wgpu::CurrentSurfaceTexture::Suboptimal(texture) => {
                    // (Dropped before the surface is configured again, which wgpu requires.)
                    drop(texture);
                    self.configure_at_window_size("suboptimal")?;
                }
                wgpu::CurrentSurfaceTexture::Outdated => {
                    self.configure_at_window_size("out of date")?;
                }
                wgpu::CurrentSurfaceTexture::Lost => self.configure_at_window_size("lost")?,
            }
        }
        Ok(Next::Not(Drawn::Skipped))
    }

    /// Configures the surface again, at the window's size now (a minimised window's: the size
    /// it had).
    fn configure_at_window_size(&mut self, why: &str) -> Result<(), String> {
        let size = self.window.inner_size();
        match size.width == 0 || size.height == 0 {
            true => self.configure(self.config.width, self.config.height)?,
            false => self.configure(size.width, size.height)?,
        }
        let (w, h) = (self.config.width, self.config.height);
        log::info!("the window's surface was {why}: configured at {w}x{h}");
        Ok(())
    }

    /// Configures the surface at `width`×`height`, within the device's bound.
    fn configure(&mut self, width: u32, height: u32) -> Result<(), String> {
        let max = self.max_texture_side() as u32;
        if width > max || height > max {
            return Err(format!(
                "surface {width}x{height}: the device draws at most {max} pixels a side"
            ));
        }
        (self.config.width, self.config.height) = (width, height);
        self.surface.configure(&self.device, &self.config);
        Ok(())
    }

    /// Draws egui's output (which includes the framebuffer image) to the window; with
    /// `capture`, draws the same commands into an offscreen texture too and reads it back.
    pub fn draw(
        &mut self,
        paint_jobs: &[egui::ClippedPrimitive],
        textures: &egui::TexturesDelta,
        pixels_per_point: f32,
        capture: bool,
    ) -> Result<Drawn, String> {
        if std::mem::take(&mut self.lose_next_draw) {
            return Err(
                "drawing failed: the window surface was lost (injected); drawing again".into(),
            );
        }
        if let Some(size) = self.resize_in_next_draw.take() {
            // (The window system applies it when it gets to it: wait a second at most.)
            let _ = self.window.request_inner_size(size);
            let until = Instant::now() + Duration::from_secs(1);
            while self.window.inner_size() != size && Instant::now() < until {
                std::thread::sleep(Duration::from_millis(5));
            }
        }
        let frame = match self.next_texture()? {
            Next::Texture(frame) => frame,
            Next::Not(drawn) => return Ok(drawn),
        };
        let (sw, sh) = (self.config.width, self.config.height);
        let screen = ScreenDescriptor {
            size_in_pixels: [sw, sh],
            pixels_per_point,
        };
        let (device, queue, renderer) = (&self.device, &self.queue, &mut self.renderer);
        let format = self.config.format;
        let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
            label: Some("raylab frame"),
        });
        for (id, delta) in &textures.set {
            renderer.update_texture(device, queue, *id, delta);
        }
        let extra = renderer.update_buffers(device, queue, &mut encoder, paint_jobs, &screen);
        queue.submit(extra);
        let target = (frame.texture).create_view(&wgpu::TextureViewDescriptor::default());
        egui_pass(renderer, &mut encoder, &target, paint_jobs, &screen);
        let readback = capture.then(|| {
            let usage = wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC;
            let tex = texture(device, "raylab capture", (sw, sh), format, usage);
            let view = tex.create_view(&wgpu::TextureViewDescriptor::default());
            egui_pass(renderer, &mut encoder, &view, paint_jobs, &screen);
            let row = (sw * 4).div_ceil(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT)
                * wgpu::COPY_BYTES_PER_ROW_ALIGNMENT;
            let buffer = device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("raylab capture readback"),
                size: row as u64 * sh as u64,
                usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
                mapped_at_creation: false,
            });
            encoder.copy_texture_to_buffer(
                tex.as_image_copy(),
                wgpu::TexelCopyBufferInfo {
                    buffer: &buffer,
                    layout: wgpu::TexelCopyBufferLayout {
                        offset: 0,
                        bytes_per_row: Some(row),
                        rows_per_image: Some(sh),
                    },
                },
                tex.size(),
            );
            (buffer, row)
        });
        queue.submit(Some(encoder.finish()));
        frame.present();
        for id in &textures.free {
            self.renderer.free_texture(id);
        }
        let Some((buffer, row)) = readback else {
            return Ok(Drawn::Shown(None));
        };
        let slice = buffer.slice(..);
        slice.map_async(wgpu::MapMode::Read, |_| {});
        (self.device)
            .poll(wgpu::PollType::wait_indefinitely())
            .map_err(|e| format!("reading the window back: {e}"))?;
        let data = slice.get_mapped_range();
        let bgra = matches!(
            format,
            wgpu::TextureFormat::Bgra8Unorm | wgpu::TextureFormat::Bgra8UnormSrgb
        );
        let mut rgba = Vec::with_capacity((sw * sh * 4) as usize);
        for y in 0..sh as usize {
            let line = &data[y * row as usize..][..sw as usize * 4];
            for px in line.chunks_exact(4) {
                if bgra {
                    rgba.extend_from_slice(&[px[2], px[1], px[0], 255]);
                } else {
                    rgba.extend_from_slice(&[px[0], px[1], px[2], 255]);
                }
            }
        }
        Ok(Drawn::Shown(Some(Capture {
            width: sw,
            height: sh,
            rgba,
        })))
    }
}

/// The adapter (WGPU_ADAPTER_NAME's where set, else the high-performance one: a discrete GPU
/// before an integrated one, any GPU before a CPU driver, unless WGPU_POWER_PREF says
/// otherwise), its device (with the adapter's limits) and queue.
async fn open_device(
    instance: &wgpu::Instance,
    surface: &wgpu::Surface<'_>,
) -> Result<(wgpu::Adapter, wgpu::Device, wgpu::Queue), String> {
    let named = wgpu::util::initialize_adapter_from_env(instance, Some(surface)).await;
    let adapter = match named {
        Ok(adapter) => adapter,
        Err(_) => instance
            .request_adapter(&wgpu::RequestAdapterOptions {
                power_preference: wgpu::PowerPreference::from_env()
                    .unwrap_or(wgpu::PowerPreference::HighPerformance),
                force_fallback_adapter: false,
                compatible_surface: Some(surface),
            })
            .await
            .map_err(|e| e.to_string())?,
    };
    let (device, queue) = adapter
        .request_device(&wgpu::DeviceDescriptor {
            required_limits: adapter.limits(),
            ..Default::default()
        })
        .await
        .map_err(|e| e.to_string())?;
    Ok((adapter, device, queue))
}

/// The framebuffer texture: sampled by egui, written from the CPU.
/// How the image is sampled: a magnified pixel stays one square of its colour (the inspector
/// picks pixels, and a blurred edge would hide which one a crack is), a reduced one is blended.
fn sampler() -> wgpu::SamplerDescriptor<'static> {
    wgpu::SamplerDescriptor {
        label: Some("raylab framebuffer"),
        mag_filter: wgpu::FilterMode::Nearest,
        min_filter: wgpu::FilterMode::Linear,
        ..Default::default()
    }
}

fn framebuffer(device: &wgpu::Device, size: (u32, u32)) -> wgpu::Texture {
    let usage = wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST;
    let format = wgpu::TextureFormat::Rgba8Unorm;
    texture(device, "raylab framebuffer", size, format, usage)
}

/// A plain 2D texture of `width`×`height`, one mip level, one sample.
fn texture(
    device: &wgpu::Device,
    label: &str,
    (width, height): (u32, u32),
    format: wgpu::TextureFormat,
    usage: wgpu::TextureUsages,
) -> wgpu::Texture {
    device.create_texture(&wgpu::TextureDescriptor {
        label: Some(label),
        size: wgpu::Extent3d {
            width,
            height,
            depth_or_array_layers: 1,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format,
        usage,
        view_formats: &[],
    })
}

fn egui_pass(
    renderer: &Renderer,
    encoder: &mut wgpu::CommandEncoder,
    target: &wgpu::TextureView,
    paint_jobs: &[egui::ClippedPrimitive],
    screen: &ScreenDescriptor,
) {
    let mut pass = encoder
        .begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("raylab egui"),
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view: target,
                resolve_target: None,
                depth_slice: None,
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Clear(wgpu::Color {
                        r: 0.02,
                        g: 0.02,
                        b: 0.025,
                        a: 1.0,
                    }),
                    store: wgpu::StoreOp::Store,
                },
            })],
            depth_stencil_attachment: None,
            timestamp_writes: None,
            occlusion_query_set: None,
            multiview_mask: None,
        })
        .forget_lifetime();
    renderer.render(&mut pass, paint_jobs, screen);
}
