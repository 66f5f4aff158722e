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
    /// Whether the cracks view has marked the frame: the row says so where it has not.
    pub marks: Marks,
    /// The exact hit's primitive and where the ray meets it.
    pub exact: Option<(u32, Location)>,
    /// The answer's primitive, where it is not the exact one, and where the ray meets it.
    pub given: Option<(u32, Location)>,
}

/// Where the cracks view stands on the frame the inspector answers.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Marks {
    /// Counted (or, for `raylab inspect`, what the view marks).
    Counted,
    /// Being counted: a pixel not marked yet may be.
    Counting,
    /// Show cracks is off: nothing is marked.
    Off,
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
            marks: Marks::Counted,
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
        let crack = match (self.marked, self.marks) {
            (true, _) => format!("{} (marked {})", v.name(), cracks::mark_name(v, self.code)),
            (false, Marks::Counted) => format!("not marked ({ray}: {})", v.name()),
            (false, Marks::Counting) => {
                format!("{ray}: {} (the frame's cracks are being counted)", v.name())
            }
            (false, Marks::Off) => format!("{ray}: {} (show cracks is off)", v.name()),
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

#[cfg(test)]
mod tests {
    use super::*;

    /// The crack row says where the cracks view stands: a pixel not marked yet is not called
    /// "not marked" while its frame's cracks are counted, nor with show cracks off.
    #[test]
    fn the_crack_row_says_whether_the_frame_is_counted() {
        let detail = |marks| Detail {
            who: "moller".into(),
            code: false,
            at: (3.5, 4.5),
            sample: false,
            verdict: Verdict::Right,
            marked: false,
            marks,
            exact: None,
            given: None,
        };
        let crack = |marks| detail(marks).rows()[0].1.clone();
        assert_eq!(crack(Marks::Counted), "not marked (the centre ray: right)");
        assert_eq!(
            crack(Marks::Counting),
            "the centre ray: right (the frame's cracks are being counted)"
        );
        assert_eq!(
            crack(Marks::Off),
            "the centre ray: right (show cracks is off)"
        );
    }
}
