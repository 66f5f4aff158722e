//! Everything a render needs besides the scene and camera, in one struct.

use crate::geometry::Method;
use std::fmt;
use std::str::FromStr;

/// Largest accepted image side in pixels.
pub const MAX_SIDE: u32 = crate::limits::MAX_IMAGE_SIDE;
/// Largest accepted image area in pixels (a 16k × 8k image: 512 MiB of RGBA8).
pub const MAX_PIXELS: u64 = 1 << 27;
/// Largest supersampling factor per axis (16 × 16 = 256 rays per pixel).
pub const MAX_SPP: u32 = 16;

/// The lab's shading steps (the camera step is the camera itself, not a shading step).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum LabStep {
    /// Step 1: the colour of the closest surface, no light.
    #[default]
    Flat,
    /// Step 3: direct light from the point light, ρ·P·max(n·r̂, 0)/(4πr²).
    Direct,
    /// Step 4: direct light blocked by a shadow ray.
    Shadows,
    /// Step 5: shadows plus the lab's constant indirect term, ρ·(D + N).
    Indirect,
}

impl LabStep {
    /// All steps in lab order.
    pub const ALL: [LabStep; 4] = [
        LabStep::Flat,
        LabStep::Direct,
        LabStep::Shadows,
        LabStep::Indirect,
    ];

    /// The CLI / UI name.
    pub fn name(self) -> &'static str {
        match self {
            LabStep::Flat => "flat",
            LabStep::Direct => "direct",
            LabStep::Shadows => "shadows",
            LabStep::Indirect => "indirect",
        }
    }

    /// Whether the step casts shadow rays.
    pub fn casts_shadows(self) -> bool {
        matches!(self, LabStep::Shadows | LabStep::Indirect)
    }

    /// One line for the UI and `--help`.
    pub fn explanation(self) -> &'static str {
        match self {
            LabStep::Flat => "colour of the closest surface, no light",
            LabStep::Direct => "point light: colour * P max(n.r, 0) / (4 pi r^2)",
            LabStep::Shadows => "direct light, blocked where a shadow ray hits something",
            LabStep::Indirect => "shadows plus the lab's constant indirect light N",
        }
    }
}

impl fmt::Display for LabStep {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for LabStep {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        LabStep::ALL
            .into_iter()
            .find(|m| m.name() == s)
            .ok_or_else(|| {
                format!("unknown step '{s}' (expected flat, direct, shadows or indirect)")
            })
    }
}

/// Render parameters.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct RenderSettings {
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
    /// Lab step (shading).
    pub step: LabStep,
    /// Supersampling: n × n stratified samples per pixel.
    pub spp: u32,
    /// Ray/triangle method.
    pub method: Method,
    /// Trace camera rays of small scenes against only the triangles whose screen bounds meet
    /// each 16×16 tile (same image, faster); off only to measure what it saves.
    pub tile_culling: bool,
    /// The "cracks" view: paint magenta every camera ray that `method` lets through where the
    /// exact adaptive method hits (or the reverse), so the lecture's method can be seen
    /// leaking at shared edges ([`crate::render::is_crack`]).
    pub cracks: bool,
}

impl Default for RenderSettings {
    fn default() -> Self {
        Self {
            width: 640,
            height: 480,
            step: LabStep::Flat,
            spp: 1,
            method: Method::Adaptive,
            tile_culling: true,
            cracks: false,
        }
    }
}

/// A setting out of range.
#[derive(Debug, thiserror::Error, PartialEq, Eq)]
pub enum SettingsError {
    /// Width or height 0 or too large.
    #[error("image size {0}x{1} is out of range (each side 1..={MAX_SIDE}, at most {MAX_PIXELS} pixels)")]
    Size(u32, u32),
    /// Supersampling out of range.
    #[error("supersampling {0} is out of range (1..={MAX_SPP} samples per axis)")]
    Spp(u32),
    /// The pixel buffer does not fit the image.
    #[error("pixel buffer holds {0} bytes, the {1}x{2} RGBA8 image needs {3}")]
    Buffer(usize, u32, u32, usize),
    /// A pixel outside the image.
    #[error("pixel ({0}, {1}) is outside the {2}x{3} image")]
    Pixel(u32, u32, u32, u32),
}

impl RenderSettings {
    /// Checks sizes and sampling.
    pub fn validate(&self) -> Result<(), SettingsError> {
        let (w, h) = (self.width, self.height);
        if w == 0 || h == 0 || w > MAX_SIDE || h > MAX_SIDE || w as u64 * h as u64 > MAX_PIXELS {
            return Err(SettingsError::Size(w, h));
        }
        if self.spp == 0 || self.spp > MAX_SPP {
            return Err(SettingsError::Spp(self.spp));
        }
        Ok(())
    }

    /// Bytes of the RGBA8 image.
    pub fn buffer_len(&self) -> usize {
        self.width as usize * self.height as usize * 4
    }
}
