//! The GPU side: a `pixels` framebuffer at the render resolution, shown as an egui image in
//! the area beside the panel, and egui drawn on pixels' device and queue in one pass.
//!
//! pixels uploads the framebuffer into its texture inside `render_with`; that texture is
//! registered with egui-wgpu as a native texture, so the image is laid out by egui (scaled to
//! fit with its aspect ratio) and never sits under the panel. The texture is `Rgba8Unorm`
//! holding our sRGB-encoded bytes, which is what egui expects of its textures.

use egui_wgpu::{Renderer, RendererOptions, ScreenDescriptor};
use pixels::{wgpu, Pixels, PixelsBuilder, SurfaceTexture};
use std::sync::Arc;
use winit::window::Window;

/// pixels, the egui renderer, and the registered framebuffer texture.
pub struct Gpu {
    pixels: Pixels<'static>,
    renderer: Renderer,
    /// The framebuffer as an egui texture.
    pub texture_id: egui::TextureId,
    /// The framebuffer size (the render resolution of the image shown).
    pub buffer_size: (u32, u32),
    surface_size: (u32, u32),
    /// Fail the next draw as a lost surface would (the script's `lose-surface`).
    pub lose_next_draw: bool,
}

/// An RGBA8 image read back from the GPU.
pub struct Capture {
    pub width: u32,
    pub height: u32,
    pub rgba: Vec<u8>,
}

impl Gpu {
    /// Creates the surface, device and renderers; a clear error if no adapter can be had.
    pub fn new(
        window: Arc<Window>,
        surface: (u32, u32),
        buffer: (u32, u32),
    ) -> Result<Self, String> {
        let backends = wgpu::Backends::from_env().unwrap_or(wgpu::Backends::PRIMARY);
        let pixels = PixelsBuilder::new(
            buffer.0,
            buffer.1,
            SurfaceTexture::new(surface.0, surface.1, window),
        )
        .texture_format(wgpu::TextureFormat::Rgba8Unorm)
        .wgpu_backend(backends)
        // The high-performance adapter (a discrete GPU before an integrated one, any GPU
        // before a CPU driver), unless WGPU_POWER_PREF says otherwise; WGPU_ADAPTER_NAME
        // picks one by name before this is asked.
        .request_adapter_options(wgpu::RequestAdapterOptions {
            power_preference: wgpu::PowerPreference::from_env()
                .unwrap_or(wgpu::PowerPreference::HighPerformance),
            force_fallback_adapter: false,
            compatible_surface: None,
        })
        .enable_vsync(true)
        .build()
        .map_err(|e| {
            format!(
                "cannot open a graphics device ({e}); a Vulkan, Metal or DX12 adapter is needed \
                     (on Linux without a GPU install Mesa's lavapipe: mesa-vulkan-drivers)"
            )
        })?;
        let mut renderer = Renderer::new(
            pixels.device(),
            pixels.render_texture_format(),
            RendererOptions {
                dithering: false,
                ..Default::default()
            },
        );
        let view = pixels
            .texture()
            .create_view(&wgpu::TextureViewDescriptor::default());
        let texture_id =
            renderer.register_native_texture(pixels.device(), &view, wgpu::FilterMode::Linear);
        Ok(Self {
            pixels,
            renderer,
            texture_id,
            buffer_size: buffer,
            surface_size: surface,
            lose_next_draw: false,
        })
    }

    /// Largest texture side the device takes.
    pub fn max_texture_side(&self) -> usize {
        self.pixels.device().limits().max_texture_dimension_2d as usize
    }

    /// Shows a rendered RGBA8 image, resizing the framebuffer when its size changed.
    pub fn set_frame(&mut self, width: u32, height: u32, rgba: &[u8]) -> Result<(), String> {
        if (width, height) != self.buffer_size {
            self.pixels
                .resize_buffer(width, height)
                .map_err(|e| format!("framebuffer {width}x{height}: {e}"))?;
            let view = self
                .pixels
                .texture()
                .create_view(&wgpu::TextureViewDescriptor::default());
            self.renderer.update_egui_texture_from_wgpu_texture(
                self.pixels.device(),
                &view,
                wgpu::FilterMode::Linear,
                self.texture_id,
            );
            self.buffer_size = (width, height);
        }
        let frame = self.pixels.frame_mut();
        if frame.len() != rgba.len() {
            return Err(format!(
                "frame of {} bytes for a {} byte buffer",
                rgba.len(),
                frame.len()
            ));
        }
        frame.copy_from_slice(rgba);
        Ok(())
    }

    /// Follows the window's size in physical pixels; 0×0 (minimised) is skipped.
    pub fn resize_surface(&mut self, width: u32, height: u32) -> Result<(), String> {
        if width == 0 || height == 0 || (width, height) == self.surface_size {
            return Ok(());
        }
        self.pixels
            .resize_surface(width, height)
            .map_err(|e| format!("surface {width}x{height}: {e}"))?;
        self.surface_size = (width, height);
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
    ) -> Result<Option<Capture>, String> {
        if std::mem::take(&mut self.lose_next_draw) {
            return Err(
                "drawing failed: the window surface was lost (injected); drawing again".into(),
            );
        }
        let screen = ScreenDescriptor {
            size_in_pixels: [self.surface_size.0, self.surface_size.1],
            pixels_per_point,
        };
        let renderer = &mut self.renderer;
        let format = self.pixels.render_texture_format();
        let mut readback: Option<(wgpu::Buffer, u32)> = None;
        let (sw, sh) = self.surface_size;
        self.pixels
            .render_with(|encoder, target, ctx| {
                for (id, delta) in &textures.set {
                    renderer.update_texture(&ctx.device, &ctx.queue, *id, delta);
                }
                let extra =
                    renderer.update_buffers(&ctx.device, &ctx.queue, encoder, paint_jobs, &screen);
                ctx.queue.submit(extra);
                egui_pass(renderer, encoder, target, paint_jobs, &screen);
                if capture {
                    let tex = ctx.device.create_texture(&wgpu::TextureDescriptor {
                        label: Some("raylab capture"),
                        size: wgpu::Extent3d {
                            width: sw,
                            height: sh,
                            depth_or_array_layers: 1,
                        },
                        mip_level_count: 1,
                        sample_count: 1,
                        dimension: wgpu::TextureDimension::D2,
                        format,
                        usage: wgpu::TextureUsages::RENDER_ATTACHMENT
                            | wgpu::TextureUsages::COPY_SRC,
                        view_formats: &[],
                    });
                    let view = tex.create_view(&wgpu::TextureViewDescriptor::default());
                    egui_pass(renderer, encoder, &view, paint_jobs, &screen);
                    let row = (sw * 4).div_ceil(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT)
                        * wgpu::COPY_BYTES_PER_ROW_ALIGNMENT;
                    let buffer = ctx.device.create_buffer(&wgpu::BufferDescriptor {
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
                        wgpu::Extent3d {
                            width: sw,
                            height: sh,
                            depth_or_array_layers: 1,
                        },
                    );
                    readback = Some((buffer, row));
                }
                Ok(())
            })
            .map_err(|e| format!("drawing the window: {e}"))?;
        for id in &textures.free {
            self.renderer.free_texture(id);
        }
        let Some((buffer, row)) = readback else {
            return Ok(None);
        };
        let slice = buffer.slice(..);
        slice.map_async(wgpu::MapMode::Read, |_| {});
        self.pixels
            .device()
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
        Ok(Some(Capture {
            width: sw,
            height: sh,
            rgba,
        }))
    }
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
