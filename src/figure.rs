//! A figure of one pixel's rays: the rays `raylab trace` records, drawn
//! in a slice of the scene, so that a lesson's drawing of a shadow ray, a
//! reflection, Snell's bend or sphere tracing's balls is the chapter's own
//! rays and cannot drift from the code.
//!
//! The slice is the plane through the camera that holds the first camera
//! ray and the camera's up direction (the vertical plane of the pixel's
//! column). The camera ray lies in it exactly; a ray that leaves it (a
//! shadow ray to a light off to the side) is drawn as its projection, and
//! each shape as the curve the plane cuts from it. It measures and draws;
//! the command line writes the file.

use std::fmt::Write as _;

use crate::course::Chapters;
use crate::ray_tree::{PixelTrace, TracedRay, light_paths_into_pixel, trace_pixel};
use crate::render::Stage;
use crate::seam::RayKind;
use crate::shapes::{Implicit, Shape};
use crate::{Ray, Vec3};

/// What to draw.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FigureOptions {
    /// Only this sample's rays (from 0); every sample's when `None`.
    pub sample: Option<usize>,
    /// How much nearer than the whole tree the view is, centred on the
    /// first camera ray's hit: 1 shows every ray; 1000 shows a
    /// thousandth of it, where a shadow ray's offset from its surface
    /// becomes visible.
    pub zoom: f32,
    /// How many of chapter 14's light paths that light the pixel to draw
    /// too (the first ones, in path order): each from its light through
    /// the scene to the point joined to the camera.
    pub light_paths: usize,
}

impl Default for FigureOptions {
    fn default() -> Self {
        FigureOptions {
            sample: None,
            zoom: 1.0,
            light_paths: 0,
        }
    }
}

/// Why a figure cannot be drawn.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum FigureError {
    #[error("pixel {x},{y} is outside the {width}x{height} image")]
    Outside {
        x: u32,
        y: u32,
        width: u32,
        height: u32,
    },
    #[error("sample {sample} does not exist: the pixel takes {count} (from 0)")]
    NoSample { sample: usize, count: usize },
    #[error("the zoom must be a finite number of at least 1, not {0}")]
    Zoom(f32),
}

/// The plane a figure is drawn in: `origin` and two unit axes, `across`
/// (the figure's x, along the first camera ray) and `upward` (its y).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Slice {
    pub origin: Vec3,
    pub across: Vec3,
    pub upward: Vec3,
}

impl Slice {
    /// The plane through `ray`'s origin that holds its direction and `up`,
    /// drawn with `up` upward (so that a level floor is level) and the
    /// ray's level part across; another plane holding the ray when it runs
    /// along `up`.
    pub fn through(ray: &Ray, up: Vec3) -> Slice {
        let direction = ray.dir.normalize();
        let upward = [up, Vec3::Y, Vec3::Z, Vec3::X]
            .into_iter()
            .map(Vec3::normalize)
            .find(|candidate| (direction - direction.dot(*candidate) * *candidate).length() > 1e-3)
            .unwrap_or(Vec3::Y);
        let across = (direction - direction.dot(upward) * upward).normalize();
        Slice {
            origin: ray.origin,
            across,
            upward,
        }
    }

    /// The plane's unit normal.
    pub fn normal(&self) -> Vec3 {
        self.across.cross(self.upward)
    }

    /// `point`'s coordinates in the plane (its projection's).
    pub fn coordinates(&self, point: Vec3) -> (f64, f64) {
        let offset = (point - self.origin).as_dvec3();
        (
            offset.dot(self.across.as_dvec3()),
            offset.dot(self.upward.as_dvec3()),
        )
    }

    /// How far `point` is from the plane, signed along [`Slice::normal`].
    pub fn height(&self, point: Vec3) -> f64 {
        (point - self.origin)
            .as_dvec3()
            .dot(self.normal().as_dvec3())
    }
}

/// A curve a shape leaves in the slice.
#[derive(Debug, Clone, PartialEq)]
pub enum Section {
    /// A sphere's: the circle of this centre and radius.
    Circle { center: (f64, f64), radius: f64 },
    /// A plane's: the line `normal . p = offset` (`normal` a unit vector
    /// of the figure's coordinates).
    Line { normal: (f64, f64), offset: f64 },
    /// A triangle's, or a piece of an implicit surface's contour.
    Segment { from: (f64, f64), to: (f64, f64) },
}

/// The curve `shape` leaves in `slice`, within `view` for surfaces with no
/// formula for it (an implicit surface's contour is traced over a grid of
/// the view). Empty where the shape misses the plane.
pub fn sections(shape: &Shape, slice: &Slice, view: &View) -> Vec<Section> {
    match shape {
        Shape::Sphere(sphere) => {
            let height = slice.height(sphere.center());
            let radius = f64::from(sphere.radius());
            let squared = radius * radius - height * height;
            if squared > 0.0 {
                vec![Section::Circle {
                    center: slice.coordinates(sphere.center()),
                    radius: squared.sqrt(),
                }]
            } else {
                Vec::new()
            }
        }
        Shape::Plane(plane) => {
            let normal = plane.normal().as_dvec3();
            let (a, b) = (
                normal.dot(slice.across.as_dvec3()),
                normal.dot(slice.upward.as_dvec3()),
            );
            let length = a.hypot(b);
            // A plane parallel to the slice leaves no line in it.
            if length < 1e-9 {
                return Vec::new();
            }
            let offset = normal.dot((plane.point() - slice.origin).as_dvec3());
            vec![Section::Line {
                normal: (a / length, b / length),
                offset: offset / length,
            }]
        }
        Shape::Triangle(triangle) => {
            let corners = triangle.corners();
            let heights = corners.map(|corner| slice.height(corner));
            let mut ends = Vec::new();
            for (first, second) in [(0, 1), (1, 2), (2, 0)] {
                let (h1, h2) = (heights[first], heights[second]);
                if (h1 <= 0.0) != (h2 <= 0.0) {
                    let along = h1 / (h1 - h2);
                    let point = corners[first].as_dvec3()
                        + (corners[second].as_dvec3() - corners[first].as_dvec3()) * along;
                    ends.push(slice.coordinates(point.as_vec3()));
                }
            }
            match ends[..] {
                [from, to, ..] => vec![Section::Segment { from, to }],
                _ => Vec::new(),
            }
        }
        Shape::Implicit(surface) => contour(surface, slice, view),
    }
}

/// The rectangle of the slice a figure shows.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct View {
    pub min: (f64, f64),
    pub max: (f64, f64),
}

impl View {
    fn width(&self) -> f64 {
        self.max.0 - self.min.0
    }

    fn height(&self) -> f64 {
        self.max.1 - self.min.1
    }
}

/// How many cells across the grid an implicit surface's contour is traced
/// on: enough for a smooth curve at a figure's size (600 pixels).
const CONTOUR_CELLS: usize = 240;

/// The zero contour of `surface`'s function in `slice` within `view`, by
/// marching squares: in each cell of a grid whose corners' values change
/// sign, a segment between the edges' sign changes (placed by linear
/// interpolation).
fn contour(surface: &Implicit, slice: &Slice, view: &View) -> Vec<Section> {
    let cells = CONTOUR_CELLS;
    let step = (view.width() / cells as f64, view.height() / cells as f64);
    let at = |column: usize, row: usize| {
        (
            view.min.0 + step.0 * column as f64,
            view.min.1 + step.1 * row as f64,
        )
    };
    let point = |(x, y): (f64, f64)| {
        (slice.origin.as_dvec3() + slice.across.as_dvec3() * x + slice.upward.as_dvec3() * y)
            .as_vec3()
    };
    let values: Vec<f64> = (0..=cells)
        .flat_map(|row| (0..=cells).map(move |column| (column, row)))
        .map(|(column, row)| f64::from(surface.distance(point(at(column, row)))))
        .collect();
    let value = |column: usize, row: usize| values[row * (cells + 1) + column];
    let mut segments = Vec::new();
    for row in 0..cells {
        for column in 0..cells {
            let corners = [
                (column, row),
                (column + 1, row),
                (column + 1, row + 1),
                (column, row + 1),
            ];
            let mut crossings = Vec::with_capacity(4);
            for edge in 0..4 {
                let (a, b) = (corners[edge], corners[(edge + 1) % 4]);
                let (va, vb) = (value(a.0, a.1), value(b.0, b.1));
                if (va < 0.0) != (vb < 0.0) && va.is_finite() && vb.is_finite() {
                    let along = va / (va - vb);
                    let (pa, pb) = (at(a.0, a.1), at(b.0, b.1));
                    crossings.push((pa.0 + (pb.0 - pa.0) * along, pa.1 + (pb.1 - pa.1) * along));
                }
            }
            // Two crossings make one segment; four (a saddle) two, paired
            // in order round the cell.
            for pair in crossings.chunks_exact(2) {
                segments.push(Section::Segment {
                    from: pair[0],
                    to: pair[1],
                });
            }
        }
    }
    segments
}

/// One ray as the figure draws it: from its origin to what it met (or to
/// the end of its range, or out of the view when the range has none).
#[derive(Debug, Clone, PartialEq)]
pub struct DrawnRay {
    pub kind: RayKind,
    pub from: (f64, f64),
    pub to: (f64, f64),
    /// Where it met something, and the shading normal there (a unit
    /// vector of the figure's coordinates, as projected).
    pub hit: Option<((f64, f64), (f64, f64))>,
    /// A shadow ray, or a light path's ray toward the camera, that
    /// something blocked.
    pub blocked: bool,
    /// How far the ray's origin is off the plane (0 for the camera ray).
    pub off_plane: f64,
}

/// The balls sphere tracing steps through along one ray of an implicit
/// surface: each centred on a point of the march with the radius the
/// distance bound allows there (`|f| / L`), as the slice cuts them.
#[derive(Debug, Clone, PartialEq)]
pub struct Ball {
    pub center: (f64, f64),
    pub radius: f64,
}

/// What a figure shows, before it is drawn.
#[derive(Debug, Clone, PartialEq)]
pub struct Figure {
    pub chapter: u8,
    pub pixel: (u32, u32),
    pub slice: Slice,
    pub view: View,
    pub sections: Vec<(String, Vec<Section>)>,
    pub rays: Vec<DrawnRay>,
    pub balls: Vec<Ball>,
    /// The smallest and largest offset of a secondary ray's origin from
    /// the surface it leaves, in scene units: what a zoomed figure shows.
    pub offsets: Option<(f64, f64)>,
}

/// The most balls drawn along one ray: sphere tracing near a grazing
/// surface takes many tiny steps, which draw as one smudge.
const MAX_BALLS: usize = 48;

/// Pixel `pixel` of `stage`, traced by the chapters `C` and laid out in
/// its slice (see the module's documentation).
pub fn figure<C: Chapters>(
    stage: &Stage<'_, C>,
    chapter: u8,
    pixel: (u32, u32),
    options: &FigureOptions,
) -> Result<Figure, FigureError> {
    if !(options.zoom.is_finite() && options.zoom >= 1.0) {
        return Err(FigureError::Zoom(options.zoom));
    }
    let (x, y) = pixel;
    let traced: PixelTrace = trace_pixel(stage, pixel).ok_or(FigureError::Outside {
        x,
        y,
        width: stage.settings.width,
        height: stage.settings.height,
    })?;
    if let Some(sample) = options.sample
        && sample >= traced.samples.len()
    {
        return Err(FigureError::NoSample {
            sample,
            count: traced.samples.len(),
        });
    }
    let roots: Vec<&TracedRay> = traced.chosen(options.sample).map(|(_, ray)| ray).collect();
    let Some(first) = roots.first() else {
        return Err(FigureError::NoSample {
            sample: options.sample.unwrap_or(0),
            count: 0,
        });
    };
    // The scene's up, not the image's: a camera looking down tilts the
    // image's, and the floor would be drawn slanted.
    let slice = Slice::through(&first.ray, stage.scene().camera.up);
    let light_paths = light_paths_into_pixel(stage, pixel, options.light_paths);
    let mut all = Vec::new();
    for root in roots.iter().copied().chain(&light_paths) {
        flatten(root, &mut all);
    }
    let view = view_of(&slice, &all, first, options.zoom);
    let mut rays = Vec::with_capacity(all.len());
    let mut balls = Vec::new();
    let mut offsets: Option<(f64, f64)> = None;
    for traced in &all {
        rays.push(drawn(traced, &slice, &view));
        if let Some(hit) = &traced.hit
            && let Some(Shape::Implicit(surface)) = stage.shapes().get(hit.shape)
        {
            balls.extend(march_balls(
                surface,
                &traced.ray,
                traced.t_min,
                hit.t,
                &slice,
            ));
        }
        for child in &traced.children {
            if let Some(hit) = &traced.hit {
                let offset = f64::from((child.ray.origin - hit.point).length());
                offsets = Some(match offsets {
                    Some((low, high)) => (low.min(offset), high.max(offset)),
                    None => (offset, offset),
                });
            }
        }
    }
    let sections = stage
        .shapes()
        .iter()
        .enumerate()
        .map(|(index, shape)| {
            let name = stage.name(index).unwrap_or("?").to_string();
            (name, sections(shape, &slice, &view))
        })
        .filter(|(_, cut)| !cut.is_empty())
        .collect();
    Ok(Figure {
        chapter,
        pixel,
        slice,
        view,
        sections,
        rays,
        balls,
        offsets,
    })
}

fn flatten<'t>(ray: &'t TracedRay, into: &mut Vec<&'t TracedRay>) {
    into.push(ray);
    for child in &ray.children {
        flatten(child, into);
    }
}

/// The view: every ray's ends with a margin, as a square (so that angles
/// are drawn true); `zoom` times nearer around the first camera ray's hit.
fn view_of(slice: &Slice, rays: &[&TracedRay], first: &TracedRay, zoom: f32) -> View {
    let mut points = Vec::new();
    for ray in rays {
        points.push(slice.coordinates(ray.ray.origin));
        if let Some(hit) = &ray.hit {
            points.push(slice.coordinates(hit.point));
        } else if ray.t_max.is_finite() {
            points.push(slice.coordinates(ray.ray.at(ray.t_max)));
        }
    }
    let (mut low, mut high) = ((f64::MAX, f64::MAX), (f64::MIN, f64::MIN));
    for (x, y) in points
        .iter()
        .copied()
        .filter(|(x, y)| x.is_finite() && y.is_finite())
    {
        low = (low.0.min(x), low.1.min(y));
        high = (high.0.max(x), high.1.max(y));
    }
    if low.0 > high.0 {
        (low, high) = ((-1.0, -1.0), (1.0, 1.0));
    }
    let side = (high.0 - low.0).max(high.1 - low.1).max(1e-6) * 1.25;
    let zoomed = side / f64::from(zoom);
    let center = match (&first.hit, zoom > 1.0) {
        (Some(hit), true) => slice.coordinates(hit.point),
        _ => ((low.0 + high.0) / 2.0, (low.1 + high.1) / 2.0),
    };
    View {
        min: (center.0 - zoomed / 2.0, center.1 - zoomed / 2.0),
        max: (center.0 + zoomed / 2.0, center.1 + zoomed / 2.0),
    }
}

fn drawn(traced: &TracedRay, slice: &Slice, view: &View) -> DrawnRay {
    let from = slice.coordinates(traced.ray.origin);
    let end = match &traced.hit {
        Some(hit) => hit.point,
        None if traced.t_max.is_finite() => traced.ray.at(traced.t_max),
        // A ray to infinity: far enough to leave the view whatever its
        // direction.
        None => {
            let reach = (view.width() + view.height()) as f32 * 2.0;
            let distance = (traced.ray.origin - slice.origin).length() + reach;
            traced.ray.at(distance / traced.ray.dir.length().max(1e-30))
        }
    };
    let hit = traced.hit.as_ref().map(|hit| {
        let normal = hit.shading_normal.as_dvec3();
        let (a, b) = (
            normal.dot(slice.across.as_dvec3()),
            normal.dot(slice.upward.as_dvec3()),
        );
        let length = a.hypot(b).max(1e-12);
        (slice.coordinates(hit.point), (a / length, b / length))
    });
    DrawnRay {
        kind: traced.kind,
        from,
        to: slice.coordinates(end),
        hit,
        // A shadow ray, or a light path's ray toward the camera, that met
        // something on its way.
        blocked: matches!(traced.kind, RayKind::Shadow | RayKind::ToCamera) && traced.hit.is_some(),
        off_plane: slice.height(traced.ray.origin),
    }
}

/// The march of `ray` toward `surface` from `t_min` to its hit at `t_hit`:
/// steps of `|f| / L`, as chapter 12's lesson derives them, each point's
/// ball as the slice cuts it.
fn march_balls(surface: &Implicit, ray: &Ray, t_min: f32, t_hit: f32, slice: &Slice) -> Vec<Ball> {
    let lipschitz = surface.lipschitz().max(1.0);
    let Some((enter, _)) = surface.span(ray, t_min, t_hit) else {
        return Vec::new();
    };
    let mut t = enter.max(t_min);
    let mut balls = Vec::new();
    while t < t_hit && balls.len() < MAX_BALLS {
        let point = ray.at(t);
        let radius = f64::from(surface.distance(point).abs() / lipschitz);
        let height = slice.height(point);
        if radius * radius > height * height {
            balls.push(Ball {
                center: slice.coordinates(point),
                radius: (radius * radius - height * height).sqrt(),
            });
        }
        let step = (radius as f32) / ray.dir.length();
        if !(step > 1e-5 * t_hit.max(1.0)) {
            break;
        }
        t += step;
    }
    balls
}

/// The colour a ray kind is drawn in, and its name in the legend.
fn ray_style(kind: RayKind) -> &'static str {
    match kind {
        RayKind::Primary => "#222222",
        RayKind::Shadow => "#e08a00",
        RayKind::Reflection => "#1f77b4",
        RayKind::Refraction => "#17a398",
        RayKind::Bounce => "#8e44ad",
        RayKind::Light => "#e377c2",
        RayKind::ToCamera => "#8c564b",
    }
}

/// The figure's side in SVG pixels.
const SIDE: f64 = 600.0;

impl Figure {
    /// The figure as SVG text: the shapes' curves in grey, each ray in its
    /// kind's colour (a blocked shadow ray dashed), hits as dots with
    /// their shading normals, sphere tracing's balls, and a legend.
    pub fn svg(&self) -> String {
        let scale = SIDE / self.view.width();
        let map =
            |(x, y): (f64, f64)| ((x - self.view.min.0) * scale, (self.view.max.1 - y) * scale);
        let mut out = String::new();
        let legend_height = 22.0 * (3 + RayKind::ALL.len()) as f64;
        let _ = writeln!(
            out,
            "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{SIDE}\" height=\"{}\" \
             viewBox=\"0 0 {SIDE} {}\" font-family=\"sans-serif\" font-size=\"13\">",
            SIDE + legend_height,
            SIDE + legend_height
        );
        let _ = writeln!(
            out,
            "<title>chapter {}, pixel {},{}: its rays in the slice through the camera ray</title>",
            self.chapter, self.pixel.0, self.pixel.1
        );
        let _ = writeln!(
            out,
            "<clipPath id=\"view\"><rect width=\"{SIDE}\" height=\"{SIDE}\"/></clipPath>"
        );
        let _ = writeln!(
            out,
            "<rect width=\"{SIDE}\" height=\"{SIDE}\" fill=\"white\" stroke=\"#999\"/>"
        );
        let _ = writeln!(out, "<g clip-path=\"url(#view)\">");
        for (name, cut) in &self.sections {
            let _ = writeln!(
                out,
                "<g stroke=\"#9a9a9a\" stroke-width=\"2\" fill=\"none\"><title>{}</title>",
                escape(name)
            );
            for section in cut {
                match section {
                    Section::Circle { center, radius } if radius * scale < HUGE_RADIUS => {
                        let (cx, cy) = map(*center);
                        let _ = writeln!(
                            out,
                            "<circle cx=\"{}\" cy=\"{}\" r=\"{}\"/>",
                            short(cx),
                            short(cy),
                            short(radius * scale)
                        );
                    }
                    Section::Circle { center, radius } => {
                        let points: Vec<String> = arc_in_view(*center, *radius, &self.view)
                            .into_iter()
                            .map(|point| {
                                let (x, y) = map(point);
                                format!("{},{}", short(x), short(y))
                            })
                            .collect();
                        let _ = writeln!(out, "<polyline points=\"{}\"/>", points.join(" "));
                    }
                    Section::Line { normal, offset } => {
                        if let Some((from, to)) = line_in_view(*normal, *offset, &self.view) {
                            segment(&mut out, map(from), map(to), "");
                        }
                    }
                    Section::Segment { from, to } => segment(&mut out, map(*from), map(*to), ""),
                }
            }
            let _ = writeln!(out, "</g>");
        }
        for ball in &self.balls {
            let (cx, cy) = map(ball.center);
            let _ = writeln!(
                out,
                "<circle cx=\"{}\" cy=\"{}\" r=\"{}\" fill=\"#2a9d8f\" fill-opacity=\"0.08\" \
                 stroke=\"#2a9d8f\" stroke-width=\"1\"/>",
                short(cx),
                short(cy),
                short(ball.radius * scale)
            );
        }
        for ray in &self.rays {
            let dash = if ray.blocked {
                " stroke-dasharray=\"6 4\""
            } else {
                ""
            };
            let style = format!(
                " stroke=\"{}\" stroke-width=\"2\"{dash}",
                ray_style(ray.kind)
            );
            segment(&mut out, map(ray.from), map(ray.to), &style);
            let (fx, fy) = map(ray.from);
            let _ = writeln!(
                out,
                "<circle cx=\"{}\" cy=\"{}\" r=\"2.5\" fill=\"{}\"/>",
                short(fx),
                short(fy),
                ray_style(ray.kind)
            );
            if let Some((point, normal)) = ray.hit
                && ray.kind != RayKind::Shadow
            {
                let (px, py) = map(point);
                let length = 40.0;
                let _ = writeln!(
                    out,
                    "<line x1=\"{}\" y1=\"{}\" x2=\"{}\" y2=\"{}\" stroke=\"#2ca02c\" \
                     stroke-width=\"1.5\"/>",
                    short(px),
                    short(py),
                    short(px + normal.0 * length),
                    short(py - normal.1 * length)
                );
                let _ = writeln!(
                    out,
                    "<circle cx=\"{}\" cy=\"{}\" r=\"3.5\" fill=\"#d62728\"/>",
                    short(px),
                    short(py)
                );
            }
        }
        let _ = writeln!(out, "</g>");
        self.legend(&mut out, scale);
        out.push_str("</svg>\n");
        out
    }

    fn legend(&self, out: &mut String, scale: f64) {
        let mut y = SIDE + 18.0;
        let scale_text = format!(
            "the view is {} scene units across; hits red, their shading normals green",
            compact(SIDE / scale),
        );
        let _ = writeln!(
            out,
            "<text x=\"8\" y=\"{y}\">{}</text>",
            escape(&scale_text)
        );
        if let Some((low, high)) = self.offsets {
            y += 22.0;
            let _ = writeln!(
                out,
                "<text x=\"8\" y=\"{y}\">new rays start {} to {} off the point they leave</text>",
                compact(low),
                compact(high)
            );
        }
        for kind in RayKind::ALL {
            let count = self.rays.iter().filter(|ray| ray.kind == kind).count();
            if count == 0 {
                continue;
            }
            y += 22.0;
            let _ = writeln!(
                out,
                "<line x1=\"8\" y1=\"{}\" x2=\"40\" y2=\"{}\" stroke=\"{}\" stroke-width=\"2\"/>\
                 <text x=\"48\" y=\"{}\">{} ({count}){}</text>",
                y - 4.0,
                y - 4.0,
                ray_style(kind),
                y,
                kind.name(),
                if matches!(kind, RayKind::Shadow | RayKind::ToCamera) {
                    "; dashed where blocked"
                } else {
                    ""
                }
            );
        }
        if !self.balls.is_empty() {
            y += 22.0;
            let _ = writeln!(
                out,
                "<circle cx=\"24\" cy=\"{}\" r=\"7\" fill=\"#2a9d8f\" fill-opacity=\"0.08\" \
                 stroke=\"#2a9d8f\"/><text x=\"48\" y=\"{y}\">sphere tracing's steps: balls of \
                 radius |f| / L ({})</text>",
                y - 4.0,
                self.balls.len()
            );
        }
    }
}

/// A circle this many SVG pixels across or more is drawn as the arc of it
/// near the view (a zoomed figure's sphere): viewers draw such circles
/// poorly, and its coordinates would leave the range they draw.
const HUGE_RADIUS: f64 = 1e5;

/// Points of the circle of `center` and `radius` around the point of it
/// nearest the view's centre, spanning twice the view's diagonal.
fn arc_in_view(center: (f64, f64), radius: f64, view: &View) -> Vec<(f64, f64)> {
    let middle = (
        (view.min.0 + view.max.0) / 2.0,
        (view.min.1 + view.max.1) / 2.0,
    );
    let facing = (middle.1 - center.1).atan2(middle.0 - center.0);
    let half_span = (2.0 * view.width().hypot(view.height()) / radius).min(std::f64::consts::PI);
    (0..=64)
        .map(|step| {
            let angle = facing + half_span * (f64::from(step) / 32.0 - 1.0);
            (
                center.0 + radius * angle.cos(),
                center.1 + radius * angle.sin(),
            )
        })
        .collect()
}

/// The part of the line `normal . p = offset` inside `view`, if any.
fn line_in_view(normal: (f64, f64), offset: f64, view: &View) -> Option<((f64, f64), (f64, f64))> {
    let mut ends = Vec::new();
    // Where it crosses each side of the view.
    for x in [view.min.0, view.max.0] {
        if normal.1.abs() > 1e-12 {
            let y = (offset - normal.0 * x) / normal.1;
            if (view.min.1..=view.max.1).contains(&y) {
                ends.push((x, y));
            }
        }
    }
    for y in [view.min.1, view.max.1] {
        if normal.0.abs() > 1e-12 {
            let x = (offset - normal.1 * y) / normal.0;
            if (view.min.0..=view.max.0).contains(&x) {
                ends.push((x, y));
            }
        }
    }
    match ends[..] {
        [from, to, ..] => Some((from, to)),
        _ => None,
    }
}

fn segment(out: &mut String, (x1, y1): (f64, f64), (x2, y2): (f64, f64), style: &str) {
    let _ = writeln!(
        out,
        "<line x1=\"{}\" y1=\"{}\" x2=\"{}\" y2=\"{}\"{style}/>",
        short(x1),
        short(y1),
        short(x2),
        short(y2)
    );
}

/// A coordinate in SVG pixels with two decimals: finer than any screen,
/// and the same text on every machine for the same rays. Far ends are
/// held to a range SVG viewers draw.
fn short(x: f64) -> String {
    let held = if x.is_finite() {
        x.clamp(-1e6, 1e6)
    } else {
        0.0
    };
    let text = format!("{held:.2}");
    if text == "-0.00" { "0.00".into() } else { text }
}

/// A length of the scene in three significant digits.
fn compact(x: f64) -> String {
    if x == 0.0 {
        "0".into()
    } else if (1e-3..1e4).contains(&x.abs()) {
        let digits = (2 - x.abs().log10().floor() as i32).max(0) as usize;
        format!("{x:.digits$}")
    } else {
        format!("{x:.2e}")
    }
}

fn escape(text: &str) -> String {
    text.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shapes::{Plane, Sphere, Triangle};

    fn slice() -> Slice {
        Slice::through(
            &Ray {
                origin: Vec3::ZERO,
                dir: Vec3::new(0.0, 0.0, -2.0),
            },
            Vec3::Y,
        )
    }

    fn view() -> View {
        View {
            min: (-10.0, -10.0),
            max: (10.0, 10.0),
        }
    }

    #[test]
    fn the_slice_holds_the_ray_and_up() {
        let slice = slice();
        assert_eq!(slice.across, Vec3::new(0.0, 0.0, -1.0));
        assert_eq!(slice.upward, Vec3::Y);
        assert_eq!(slice.coordinates(Vec3::new(0.0, 2.0, -3.0)), (3.0, 2.0));
        assert_eq!(slice.height(Vec3::new(4.0, 2.0, -3.0)), 4.0);
        // A ray looking down: up stays upward, so a floor stays level.
        let down = Slice::through(
            &Ray {
                origin: Vec3::ZERO,
                dir: Vec3::new(0.0, -1.0, -1.0),
            },
            Vec3::Y,
        );
        assert!(down.across.abs_diff_eq(Vec3::NEG_Z, 1e-6), "{down:?}");
        assert_eq!(down.upward, Vec3::Y);
        // Straight up: another plane that holds it.
        let vertical = Slice::through(
            &Ray {
                origin: Vec3::ZERO,
                dir: Vec3::Y,
            },
            Vec3::Y,
        );
        assert_eq!(vertical.upward, Vec3::Z);
        assert_eq!(vertical.across, Vec3::Y);
    }

    #[test]
    fn a_sphere_off_the_plane_leaves_a_smaller_circle_or_none() {
        let near = Shape::Sphere(Sphere::new(Vec3::new(3.0, 0.0, -5.0), 5.0));
        assert_eq!(
            sections(&near, &slice(), &view()),
            vec![Section::Circle {
                center: (5.0, 0.0),
                radius: 4.0
            }]
        );
        let far = Shape::Sphere(Sphere::new(Vec3::new(6.0, 0.0, -5.0), 5.0));
        assert!(sections(&far, &slice(), &view()).is_empty());
    }

    #[test]
    fn a_floor_leaves_a_level_line_and_a_parallel_plane_none() {
        let floor = Shape::Plane(Plane::new(Vec3::new(0.0, -1.0, 0.0), Vec3::Y));
        assert_eq!(
            sections(&floor, &slice(), &view()),
            vec![Section::Line {
                normal: (0.0, 1.0),
                offset: -1.0
            }]
        );
        let wall = Shape::Plane(Plane::new(Vec3::new(3.0, 0.0, 0.0), Vec3::X));
        assert!(sections(&wall, &slice(), &view()).is_empty());
    }

    #[test]
    fn a_triangle_across_the_plane_leaves_the_segment_between_its_edges() {
        let triangle = Shape::Triangle(Triangle::new(
            Vec3::new(-1.0, 0.0, -2.0),
            Vec3::new(1.0, 0.0, -2.0),
            Vec3::new(1.0, 2.0, -2.0),
        ));
        let cut = sections(&triangle, &slice(), &view());
        let [Section::Segment { from, to }] = cut[..] else {
            panic!("{cut:?}");
        };
        let mut ends = [from, to];
        ends.sort_by(|a, b| a.1.total_cmp(&b.1));
        assert_eq!(ends, [(2.0, 0.0), (2.0, 1.0)]);
    }

    #[test]
    fn a_line_is_cut_to_the_view() {
        let ends = line_in_view((0.0, 1.0), -1.0, &view()).expect("inside");
        assert_eq!(ends, ((-10.0, -1.0), (10.0, -1.0)));
        assert_eq!(line_in_view((0.0, 1.0), -11.0, &view()), None);
    }
}
