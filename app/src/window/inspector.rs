//! The ray inspector in the window: the panel section listing one pixel's ray as the lecture
//! writes it ([`raylab::render::inspect`]: its centre ray, or a crack's marked sample's) and
//! where it meets its primitives, and the overlay
//! that draws that ray, its hit point and its shadow ray over the image while the inspector is
//! on. The pixel is answered again for each new view ([`super::follow`]); until the view
//! settles, the ray drawn is the last answer's, seen from where the camera has moved since.

use super::inspected::Detail;
use raylab::accel::Accel;
use raylab::camera::Projection;
use raylab::check::code::CodeInspection;
use raylab::geometry::{Hit, Method, Ray};
use raylab::render::inspect::Inspection;

/// The switch in the side panel.
pub fn switch(ui: &mut egui::Ui, on: &mut bool, inspected: bool) {
    ui.checkbox(on, "Ray inspector: left-click a pixel (I)");
    // (A line in every state: shown only before the first click, it went with that click,
    // and every row below moved up under the pointer.)
    ui.small(match (*on, inspected) {
        (true, false) => "click the image to follow one pixel's ray",
        (true, true) => "click another pixel to follow its ray",
        (false, _) => "off: a click on the image follows no ray",
    });
}

/// The least width (points) the inspector's rows stay readable in beside the image, its
/// panel's own width at start: where the window leaves its panel less, it floats instead
/// ([`Placement::Over`]). (Narrower, its rows' values are cut.)
pub const READABLE_WIDTH: f32 = WIDTH;

/// Width of the ray inspector's panel at start, in points.
pub const WIDTH: f32 = 330.0;

/// Where the inspector's fields were drawn.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Placement {
    /// In a panel of its own at the right of the image.
    Beside,
    /// In a window over the others (a window too narrow for the panel): movable, its rows
    /// scrolled.
    Over,
}

/// The right-hand panel the inspector's fields are shown in, `width` points wide at first and
/// `most` at most (the image beside it keeps the rest). Its width is the one last chosen by
/// dragging its edge: egui keeps the width the panel was last drawn at, which a narrow window
/// squeezes it to, so when the window has room again it is given that width back. Where
/// `most` is under [`READABLE_WIDTH`], a window `width` wide where the screen has room, at
/// first over the side panel, which leaves the image to click (in a 400-point window the
/// panel was 50 points wide, its rows cut off).
pub fn panel(
    ui: &mut egui::Ui,
    width: f32,
    most: f32,
    contents: impl FnOnce(&mut egui::Ui),
) -> Placement {
    if most < READABLE_WIDTH {
        let screen = ui.ctx().content_rect();
        let margin = 8.0;
        // (Its title bar moves it: a drag on its rows scrolls them.)
        // (Collapsible: in a window this small it may cover the whole image.)
        egui::Window::new("Ray inspector")
            .collapsible(true)
            .resizable(false)
            // (Below the menu bar, which it would hide, and kept there: in a short window its
            // first, unscrolled height had it moved up over the menu bar to fit the screen.)
            .default_pos(screen.left_top() + egui::vec2(margin, 4.0 * margin))
            .constrain_to(screen.with_min_y(screen.min.y + 4.0 * margin))
            .default_width(width.min(screen.width() - 2.0 * margin))
            .max_height(screen.height() - 9.0 * margin)
            .show(ui.ctx(), contents);
        return Placement::Over;
    }
    let id = egui::Id::new("inspector width");
    // (The width chosen, and the width drawn in the last frame.)
    let (chosen, last) = ui.ctx().data(|d| d.get_temp(id)).unwrap_or((width, width));
    let most = most.max(0.0);
    let mut panel = egui::Panel::right("inspector")
        .resizable(true)
        .default_size(width.min(most))
        .max_size(most);
    if last < chosen && most > last + 1.0 {
        panel = panel.exact_size(chosen.min(most));
    }
    let drawn = panel.show(ui, contents).response.rect.width();
    // (Where the window left it less than it takes, it was not squeezed: its width is chosen.)
    let chosen = if most > drawn + 1.0 { drawn } else { chosen };
    ui.ctx().data_mut(|d| d.insert_temp(id, (chosen, drawn)));
    Placement::Beside
}

/// The inspector's own panel: the last inspection's fields, the lecture's names.
pub fn fields(ui: &mut egui::Ui, ins: &Inspection) {
    ui.strong("Ray inspector");
    egui::Grid::new("inspector").striped(true).show(ui, |ui| {
        for (name, value) in rows(ins) {
            ui.label(name);
            ui.monospace(value);
            ui.end_row();
        }
    });
}

/// The inspector's rows: each field's name and value.
fn rows(ins: &Inspection) -> Vec<(String, String)> {
    let v3 = |v: [f64; 3]| format!("{:.3} {:.3} {:.3}", v[0], v[1], v[2]);
    let f3 = |v: [f32; 3]| format!("{:.3} {:.3} {:.3}", v[0], v[1], v[2]);
    let mut rows = Vec::new();
    let mut row = |name: &str, value: String| rows.push((name.to_string(), value));
    let [i, j] = ins.pixel;
    row("pixel", format!("({i}, {j})"));
    // Which of the pixel's rays every field below is of: a crack's is its marked sample's.
    let [x, y] = ins.at;
    let centre = [x, y] == [i as f64 + 0.5, j as f64 + 0.5];
    let which = if centre { "the centre" } else { "sample" };
    // (The position on a line of its own: at 1920x1080 one line ran past the panel.)
    row(
        "ray through",
        format!("{which}\n({}, {})", short(x), short(y)),
    );
    row("(u, v, f)", v3(ins.uvf));
    row("d camera", v3(ins.d_camera));
    row("origin", f3(ins.ray.o));
    row("d world", f3(ins.ray.d));
    let Some(h) = &ins.hit else {
        row("hit", "none: the background".into());
        return rows;
    };
    row("hit", format!("primitive {}", h.prim));
    row("t", format!("{}", h.t));
    row("t exact", format!("{}", h.t_exact));
    row("decided by", h.decided_by.to_string());
    for (label, value) in h.terms.rows(v3) {
        row(label, value);
    }
    row("point", f3(h.point));
    let e = h.point_hit_error;
    row(
        "point error (hit)",
        format!("± {:.1e} {:.1e} {:.1e}", e[0], e[1], e[2]),
    );
    row("normal", f3(h.normal));
    row(
        "shadow ray",
        match (&h.shadow, h.blocked_by) {
            (None, _) => "none (D = 0)".into(),
            (Some(_), Some(p)) => format!("blocked by primitive {p}"),
            (Some(_), None) => "reaches the light".into(),
        },
    );
    row("rho", f3(h.rho));
    // A term the step's colour leaves out says so, in the names' column (N = 0.5 beside a
    // shadows colour without it read as part of it; beside the value it was cut at the
    // panel's default width).
    let name = |term: &'static str, used: bool| match used {
        true => term.to_string(),
        false => format!("{term} (not in step)"),
    };
    row(&name("D", ins.step.uses_direct()), f3(h.direct));
    if h.direct != h.direct_unshadowed {
        // (Blocked in a step with shadows: the D the shadow ray took away.)
        row("D unshadowed", f3(h.direct_unshadowed));
    }
    row(&name("N", ins.step.uses_indirect()), f3(h.indirect));
    // (Linear, as the renderer has it before sRGB clips it: 1.715 read as a mistake.)
    row(&format!("colour ({})", ins.step), f3(h.colour));
    if h.colour.iter().any(|&c| c > 1.0) {
        row("", "linear: > 1 shows as 1".into());
    }
    rows
}

/// `v` in the fewest digits that read back as it: an image position is an f32 (a sample's,
/// or one rounded so), which the crack rows print as such; as an f64 it took 16 digits and
/// ran past the panel's edge.
fn short(v: f64) -> String {
    match v as f32 as f64 == v {
        true => (v as f32).to_string(),
        false => v.to_string(),
    }
}

/// Where the inspected pixel's ray meets its primitives, and its crack ([`Detail`]).
pub fn crack_fields(ui: &mut egui::Ui, detail: &Detail) {
    ui.strong("Where the ray meets (decided exactly)");
    for (name, value) in detail.rows() {
        ui.horizontal_wrapped(|ui| {
            ui.strong(format!("{name}:"));
            ui.label(value);
        });
    }
}

/// The linked code's answer for the inspected pixel beside the exact one on the same ray.
pub fn code_fields(ui: &mut egui::Ui, yours: &CodeInspection) {
    ui.strong(&yours.name);
    let f3 = |v: [f32; 3]| format!("{:.6} {:.6} {:.6}", v[0], v[1], v[2]);
    let hit = |h: &Option<Hit>| match h {
        Some(h) => format!(
            "t {} primitive {}\n(u, v) ({}, {})",
            h.t, h.prim, h.b1, h.b2
        ),
        None => "miss".to_string(),
    };
    egui::Grid::new("code inspector")
        .striped(true)
        .show(ui, |ui| {
            let mut row = |name: &str, value: String| {
                ui.label(name);
                ui.monospace(value);
                ui.end_row();
            };
            row("d world", f3(yours.ray.d));
            row("raylab's d", f3(yours.raylab_ray.d));
            row("hit", hit(&yours.hit));
            row("exact", hit(&yours.exact));
            row("verdict", yours.verdict.name().to_string());
        });
}

/// The camera ray (cyan) from its eye to its hit, the hit point (a ring), and the shadow ray
/// (yellow when it reaches the light, red when blocked), projected with the current view
/// onto the image drawn at `rect` (image size `size` pixels). Where `hidden` says a world
/// point lies behind the scene from the eye now, the ray is drawn thin and faint: a shadow
/// ray passing behind the box is not drawn over it.
pub fn draw(
    painter: &egui::Painter,
    rect: egui::Rect,
    size: (u32, u32),
    projection: &Projection,
    ins: &Inspection,
    hidden: impl Fn([f64; 3]) -> bool,
) {
    let to_screen = |p: [f64; 2]| {
        egui::pos2(
            rect.min.x + (p[0] / size.0 as f64) as f32 * rect.width(),
            rect.min.y + (p[1] / size.1 as f64) as f32 * rect.height(),
        )
    };
    let painter = painter.with_clip_rect(rect);
    // (In f64: 20 units from a camera 10⁹ away, an f32 point is off by up to 32.)
    let at = |o: [f32; 3], d: [f32; 3], t: f32| {
        [0, 1, 2].map(|k| f64::from(o[k]) + f64::from(t) * f64::from(d[k]))
    };
    let end = match &ins.hit {
        Some(h) => h.t,
        None => 1e3 * ins.ray.d.iter().map(|c| c.abs()).fold(1.0, f32::max),
    };
    const RING: f32 = 6.0;
    // (A segment shorter than the ring's radius is the camera ray seen end on, from the view
    // it was traced in: drawn, it would hide the pixel the ring shows.)
    let segment = |a: [f64; 3], b: [f64; 3], colour: egui::Color32| {
        let Some((p, q)) = clip(projection, a, b) else {
            return;
        };
        if to_screen(p).distance(to_screen(q)) < RING {
            return;
        }
        for (a, b, hidden) in pieces(a, b, &hidden) {
            if let Some((p, q)) = clip(projection, a, b) {
                let stroke = match hidden {
                    true => egui::Stroke::new(1.0, colour.gamma_multiply(0.4)),
                    false => egui::Stroke::new(2.0, colour),
                };
                painter.line_segment([to_screen(p), to_screen(q)], stroke);
            }
        }
    };
    // (From 2% along: the eye itself projects nowhere, and just in front of it a projection
    // through a near-zero depth rounds to anywhere on screen.)
    segment(
        at(ins.ray.o, ins.ray.d, 0.02 * end),
        at(ins.ray.o, ins.ray.d, end),
        egui::Color32::from_rgb(0, 220, 255),
    );
    // (Hollow: the pixel inside, a crack's mark say, stays in sight.)
    let ring = |c: egui::Pos2| {
        painter.circle_stroke(c, RING, egui::Stroke::new(2.0, egui::Color32::WHITE));
    };
    let Some(h) = &ins.hit else {
        // A miss (a leak stepped to with N, say) has its ring too, round the pixel its ray
        // goes through: a 2-pixel dot was hard to find.
        if let Some(p) = projection.project_f64(at(ins.ray.o, ins.ray.d, end)) {
            ring(to_screen(p));
        }
        return;
    };
    if let Some(s) = &h.shadow {
        let colour = match h.blocked_by {
            Some(_) => egui::Color32::from_rgb(255, 60, 60),
            None => egui::Color32::from_rgb(255, 220, 0),
        };
        segment(at(s.o, s.d, 0.0), at(s.o, s.d, 1.0), colour);
    }
    if let Some(p) = projection.project(h.point) {
        ring(to_screen(p));
    }
}

/// How many pieces an overlay segment is cut into, each drawn as seen or hidden by its middle.
const PIECES: usize = 48;

/// Segment a–b in [`PIECES`] pieces, each with whether `hidden` holds at its middle.
fn pieces(
    a: [f64; 3],
    b: [f64; 3],
    hidden: &impl Fn([f64; 3]) -> bool,
) -> Vec<([f64; 3], [f64; 3], bool)> {
    let point = |s: f64| [0, 1, 2].map(|k| a[k] + s * (b[k] - a[k]));
    let at = |i: usize| i as f64 / PIECES as f64;
    (0..PIECES)
        .map(|i| {
            let middle = point((at(i) + at(i + 1)) / 2.0);
            (point(at(i)), point(at(i + 1)), hidden(middle))
        })
        .collect()
}

/// Whether the scene stands between `eye` and world point `p` (for [`draw`]): a shadow query
/// from the eye that stops a thousandth short of `p`, which may lie on a surface (the hit
/// point, a light on a wall).
pub fn hides(accel: &Accel, method: Method, eye: [f64; 3], p: [f64; 3]) -> bool {
    let d = [0, 1, 2].map(|k| (p[k] - eye[k]) as f32);
    let ray = Ray::new(eye.map(|c| c as f32), d);
    accel.any_hit(&ray, method, 0.0, 0.999, u32::MAX)
}

/// The part of segment a–b in front of the camera, projected (image pixels), or `None`.
fn clip(projection: &Projection, a: [f64; 3], b: [f64; 3]) -> Option<([f64; 2], [f64; 2])> {
    let point = |s: f64| [0, 1, 2].map(|k| a[k] + s * (b[k] - a[k]));
    let (pa, pb) = (projection.project_f64(a), projection.project_f64(b));
    match (pa, pb) {
        (Some(p), Some(q)) => Some((p, q)),
        (None, None) => None,
        // One end behind the eye: the last point in front, by bisection along the segment.
        (Some(p), None) | (None, Some(p)) => {
            let front_is_a = pa.is_some();
            let (mut inside, mut outside) = if front_is_a { (0.0, 1.0) } else { (1.0, 0.0) };
            for _ in 0..30 {
                let mid = 0.5 * (inside + outside);
                match projection.project_f64(point(mid)) {
                    Some(_) => inside = mid,
                    None => outside = mid,
                }
            }
            Some((p, projection.project_f64(point(inside))?))
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use raylab::render::{LabStep, Stage};
    use raylab::Scene;

    /// D and N say where a step's colour leaves them out: N in every step but the last, D
    /// in the flat one.
    #[test]
    fn the_terms_a_step_leaves_out_say_so() {
        let stage = Stage::new(Scene::cornell(), raylab::accel::AccelChoice::Auto);
        let camera = raylab::camera::Camera::cornell(64);
        let names = |step: LabStep| {
            let settings = raylab::render::RenderSettings {
                width: 64,
                height: 48,
                step,
                ..Default::default()
            };
            let ins = raylab::render::inspect::inspect(&stage, &camera, &settings, 32, 40)
                .expect("a pixel of the image");
            rows(&ins)
                .into_iter()
                .map(|(name, _)| name)
                .collect::<Vec<_>>()
        };
        for step in LabStep::ALL {
            let names = names(step);
            let has = |name: &str| names.iter().any(|n| n == name);
            let d_out = step == LabStep::Flat;
            let n_out = step != LabStep::Indirect;
            assert_eq!(has("D (not in step)"), d_out, "{step}: {names:?}");
            assert_eq!(has("D"), !d_out, "{step}: {names:?}");
            assert_eq!(has("N (not in step)"), n_out, "{step}: {names:?}");
            assert_eq!(has("N"), !n_out, "{step}: {names:?}");
        }
    }

    #[test]
    fn a_segment_behind_a_wall_is_hidden_only_where_the_wall_covers_it() {
        // A wall across z = 0 for |x| <= 1 (two triangles), the eye at z = -3 on the axis; a
        // segment along x at z = 1 from x = -3 to 3 is hidden where the wall is between: its
        // middle third seen from the eye's line of sight through |x| <= 1 at z = 0, so
        // |x| < 4/3 at z = 1 (the lines through the eye and the wall's edges).
        use raylab::geometry::{Shape, Triangle};
        use raylab::scene::cornell::{AMBIENT, LIGHT};
        let wall = [
            Triangle([[-1.0, -1.0, 0.0], [1.0, -1.0, 0.0], [1.0, 1.0, 0.0]]),
            Triangle([[-1.0, -1.0, 0.0], [1.0, 1.0, 0.0], [-1.0, 1.0, 0.0]]),
        ];
        let shapes = wall.map(Shape::Triangle).to_vec();
        let scene = Scene::new("wall", shapes, vec![[1.0; 3]; 2], LIGHT, AMBIENT);
        let stage = Stage::new(scene, raylab::accel::AccelChoice::Auto);
        let eye = [0.0, 0.0, -3.0];
        let hidden = |p: [f64; 3]| hides(stage.accel(), Method::Watertight, eye, p);
        let pieces = pieces([-3.0, 0.0, 1.0], [3.0, 0.0, 1.0], &hidden);
        for (a, b, hidden) in pieces {
            let middle = (a[0] + b[0]) / 2.0;
            assert_eq!(hidden, middle.abs() < 4.0 / 3.0, "x = {middle}");
        }
        // The wall's own points and the eye's side are seen; a point on the wall is not
        // hidden by the wall it lies on.
        assert!(!hidden([0.5, 0.5, 0.0]));
        assert!(!hidden([0.5, 0.5, -1.0]));
        assert!(hidden([0.5, 0.5, 0.01]));
    }
}
