//! What the ray inspector follows and says: its pixel ([`Inspected`]) and what it says of
//! that pixel's crack ([`Detail`]), which the viewer holds, `follow` answers and the
//! inspector draws.

use super::cracks;
use raylab::camera::Camera;
use raylab::check::{LabCode, Verdict};
use raylab::geometry::{Hit, Location, Method, Shape};
use raylab::render::Stage;

/// The pixel the inspector follows, and the frame it was answered for.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Inspected {
    /// A pixel of the view F5 and copy as command write, of which the image shown is a crop
    /// ([`super::viewer::Viewer::view_offset`] columns in): under the inspector's panel
    /// where that crop leaves it out.
    pub pixel: (u32, u32),
    /// The size of the image shown.
    pub size: (u32, u32),
    /// The focal length (pixels) of the view it was answered for.
    pub focal: f64,
    pub generation: u64,
    /// The pixel as chosen (a click, a crack stepped to), with its view's size and focal
    /// length: the one followed, so that a zoom out and back, or a ray that left the image
    /// for a while, comes back to the pixel chosen.
    pub chosen: Chosen,
}

/// A pixel of the view F5 writes, of `size`, at focal length `focal`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Chosen {
    pub pixel: (u32, u32),
    pub size: (u32, u32),
    pub focal: f64,
}

/// What the inspector says of its pixel's crack.
#[derive(Clone, Debug, PartialEq)]
pub struct Detail {
    /// Who answered: the method, or the linked code.
    pub who: String,
    pub code: bool,
    /// The image position traced: the pixel's centre, its first marked sample, or one given
    /// (`raylab inspect --at`); `sample`: off the centre.
    pub at: (f32, f32),
    pub sample: bool,
    /// That ray's answer graded against the exact one.
    pub verdict: Verdict,
    /// Whether the cracks view marks the pixel in the frame shown.
    pub marked: bool,
    /// The window's cracks view is off: nothing is marked, and the row says why.
    pub view_off: bool,
    /// The exact hit's primitive and where the ray meets it.
    pub exact: Option<(u32, Location)>,
    /// The answer's primitive, where it is not the exact one, and where the ray meets it.
    pub given: Option<(u32, Location)>,
}

impl Detail {
    /// The crack of the ray through image position `pos` of an image of `size`, as `job`
    /// traces it (`shapes`: every primitive, for linked code). `marked`: whether the cracks
    /// view marks it, or None to say so from the verdict alone (`raylab inspect`, which has no
    /// frame counted). A ray off its pixel's centre is named a sample, one at the centre (an
    /// odd count's middle sample too) the centre, as the `ray through` row names it.
    pub fn of_ray(
        job: (&Stage, &Camera, Method, Option<&dyn LabCode>),
        shapes: &[Shape],
        size: (u32, u32),
        pos: (f32, f32),
        marked: Option<bool>,
    ) -> Self {
        let (stage, _, method, code) = job;
        let (ray, given, exact) = cracks::answers(job, shapes, size, pos);
        let scene = stage.scene();
        let verdict = cracks::classify(scene.len(), |p| scene.shape(p), &ray, exact, given);
        let marked = marked.unwrap_or_else(|| cracks::is_marked(verdict, code.is_some()));
        let on = |p: u32| (p, scene.shape(p).locate(&ray));
        let differs = |g: &Hit| exact.is_none_or(|e| e.prim != g.prim);
        let centre = (pos.0.floor() + 0.5, pos.1.floor() + 0.5);
        Detail {
            who: code.map_or(method.name().to_string(), |c| c.name().to_string()),
            code: code.is_some(),
            at: pos,
            sample: pos != centre,
            verdict,
            marked,
            view_off: false,
            exact: exact.map(|h| on(h.prim)),
            given: (given.filter(differs))
                .filter(|h| (h.prim as usize) < scene.len())
                .map(|h| on(h.prim)),
        }
    }

    /// The crack of pixel `pixel` at n×n samples, as the cracks view and the inspector take
    /// it: its first marked sample (in the count's order), or else its centre ray, unmarked.
    pub fn of_pixel(
        job: (&Stage, &Camera, Method, Option<&dyn LabCode>),
        shapes: &[Shape],
        size: (u32, u32),
        pixel: (u32, u32),
        n: u32,
    ) -> Self {
        let samples = (0..n).flat_map(|sy| (0..n).map(move |sx| (sx, sy)));
        let mut marked = samples
            .map(|sample| cracks::sample_position(pixel, sample, n))
            .map(|pos| Detail::of_ray(job, shapes, size, pos, None))
            .filter(|d| d.marked);
        let centre = (pixel.0 as f32 + 0.5, pixel.1 as f32 + 0.5);
        (marked.next()).unwrap_or_else(|| Detail::of_ray(job, shapes, size, centre, Some(false)))
    }

    /// `name: value` rows, as the inspector shows them (and a scripted run prints them).
    pub fn rows(&self) -> Vec<(String, String)> {
        let v = self.verdict;
        let ray = match self.sample {
            true => "the sample",
            false => "the centre ray",
        };
        let crack = match (self.marked, self.view_off) {
            (true, _) => format!("{} (marked {})", v.name(), cracks::mark_name(v, self.code)),
            (false, false) => format!("not marked ({ray}: {})", v.name()),
            (false, true) => format!("{ray}: {} (show cracks is off)", v.name()),
        };
        let (x, y) = self.at;
        let traced = match self.sample {
            true => format!("sample ({x}, {y}) of the pixel"),
            false => format!("the pixel's centre ({x}, {y})"),
        };
        let on = |h: &Option<(u32, Location)>| match h {
            Some((p, at)) => format!("primitive {p}, {at}"),
            None => "none".to_string(),
        };
        let given = match (v, &self.exact) {
            // (A miss is no "exact one" to lie at.)
            (Verdict::Right, None) => "none, as the exact ray".to_string(),
            (Verdict::Right, Some(_)) => "the exact one".to_string(),
            _ => on(&self.given),
        };
        // (Always the same rows: the inspector's layout stays put as its pixel changes.)
        vec![
            ("crack".to_string(), crack),
            ("traced".to_string(), traced),
            ("exact hit lies".to_string(), on(&self.exact)),
            (format!("{} hit lies", self.who), given),
        ]
    }

    /// One line for the status: the verdict and where the exact hit lies.
    pub fn summary(&self) -> String {
        let exact = match &self.exact {
            Some((p, at)) => format!("exact hit on primitive {p}, {at}"),
            None => "the exact ray meets nothing".to_string(),
        };
        format!("{} by {}; {exact}", self.verdict.name(), self.who)
    }
}
