//! GLU quadrics (seed 002, ch. 7: `gluSphere`, `gluCylinder`, `gluDisk` with
//! `gluQuadricTexture`) as triangles with texture coordinates.
//!
//! The GLU conventions, kept here (GLU 1.3, `GLU_OUTSIDE`, so every triangle
//! runs counter-clockwise seen from outside, docs/stream-format.md):
//!
//! - **Sphere** of radius r about the z axis: `t` runs from 0 at z = -r to 1
//!   at z = r, linearly along the meridians; `s` runs from 0 at the +y axis,
//!   0.25 at -x, 0.5 at -y, 0.75 at +x, back to 1 at +y. A point is
//!   `(-r sin(πt) sin(2πs), r sin(πt) cos(2πs), -r cos(πt))`. This is the
//!   SGI reference GLU's `gluSphere`: slice i at angle 2πi/n from +y towards
//!   +x, with s = 1 - i/n; so a map of the Earth wrapped round it reads east
//!   to the right, seen from outside.
//! - **Cylinder** (`base` radius at z = 0, `top` at z = height; a cone when
//!   top is 0): `t` from 0 at z = 0 to 1 at z = height, `s` as the sphere's.
//! - **Disk** (inner and outer radius in the z = 0 plane, facing +z):
//!   `(s, t) = (0.5 + x/(2 outer), 0.5 + y/(2 outer))`.
//!
//! The seam: the last slice ends at s = 1, not back at 0. Its vertices
//! duplicate the first slice's positions with their own texture coordinate,
//! so no triangle's s wraps from 0.97 back to 0 across the whole texture (the
//! artefact seed 002's cylinder mapping corrects with its atan2 test).

use crate::geom::transform::Transform;
use crate::math;
use glam::{DMat4, DVec3};
use std::f64::consts::PI;

/// Fewest slices around the axis: fewer than 3 encloses no area.
pub const MIN_SLICES: u32 = 3;
/// Fewest stacks of a sphere: one stack would be two poles and no belt.
pub const MIN_SPHERE_STACKS: u32 = 2;
/// Most slices or stacks: 2^14 keeps a sphere under 2^29 triangles and its
/// chord error already below 1e-8 of its radius.
pub const MAX_SEGMENTS: u32 = 1 << 14;

/// Most copies of the pattern along s or t (`"repeat"`): 1e100, far past
/// any texel a float can place on a surface, yet small enough that the
/// texture coordinates, `s * side * repeat`, and the arithmetic of their
/// screen map stay finite. A repeat of 1e308 made them infinite: polyfill3
/// wrote `"uv": [[null, null], ...]` and scene-render dropped the quadric
/// as edge-on.
pub const MAX_REPEAT: f64 = 1e100;

/// Default chord tolerance, in pixels, of a quadric drawn without explicit
/// slices and stacks (`scene-render --quadric-tolerance`). The faceted
/// silhouette then lies within a quarter pixel of the true outline, so an
/// edge pixel's coverage is off by less than a quarter (a faint wobble of the
/// anti-aliased edge, not a visible corner), while a sphere 80 pixels across
/// needs only 40 slices and 20 stacks (1 600 triangles).
pub const DEFAULT_TOLERANCE_PX: f64 = 0.25;

/// Relative chord tolerance used when the pixel scale cannot be measured
/// (the bounding sphere reaches the eye plane of a perspective view, or the
/// view matrix squashes it): 1e-3 of the radius is under a pixel for any
/// quadric less than 2000 pixels across.
pub const FALLBACK_RELATIVE_TOLERANCE: f64 = 1e-3;

/// A quadric in its own coordinates.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Quadric {
    /// `gluSphere`: centred on the origin, poles on the z axis.
    Sphere {
        /// Radius, in own units (> 0).
        radius: f64,
    },
    /// `gluCylinder`: axis along +z from z = 0; a cone when `top` is 0.
    Cylinder {
        /// Radius at z = 0, in own units (>= 0; not 0 with `top` also 0).
        base: f64,
        /// Radius at z = `height`, in own units (>= 0).
        top: f64,
        /// Length along +z, in own units (> 0).
        height: f64,
    },
    /// `gluDisk`: an annulus in the z = 0 plane about the origin, facing +z.
    Disk {
        /// Radius of the hole, in own units (>= 0 and below `outer`; 0 is a
        /// full disk).
        inner: f64,
        /// Outer radius, in own units (> 0).
        outer: f64,
    },
}

impl Quadric {
    /// The outward normal (not unit) of the surface at its point `p`, own
    /// coordinates, as GLU's `GLU_SMOOTH` gives it: a sphere's `p` itself; a
    /// cylinder's or cone's `(x/r, y/r, (base - top)/height)` at radius `r`,
    /// the cross product of the surface's tangents around and along the
    /// axis; a disk's +z. `None` at a cone's apex, where the surface has no
    /// tangent plane (the caller takes the triangle's own normal there).
    pub fn normal_at(&self, p: DVec3) -> Option<DVec3> {
        match *self {
            Quadric::Sphere { .. } => Some(p),
            Quadric::Cylinder { base, top, height } => {
                let r = crate::math::hypot(p.x, p.y);
                let scale = base.max(top);
                (r > APEX_RELATIVE * scale)
                    .then(|| DVec3::new(p.x / r, p.y / r, (base - top) / height))
            }
            Quadric::Disk { .. } => Some(DVec3::Z),
        }
    }
}

/// A cone's vertex this close to the axis, relative to the larger radius,
/// is its apex ([`Quadric::normal_at`]): GLU puts it exactly on the axis, so
/// any tolerance above rounding will do.
const APEX_RELATIVE: f64 = 1e-12;

/// One triangle: positions and GLU texture coordinates (s, t) in 0..=1.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Triangle {
    /// Vertex positions in the quadric's own coordinates, counter-clockwise
    /// seen from outside (`GLU_OUTSIDE`).
    pub v: [DVec3; 3],
    /// GLU texture coordinates `[s, t]` of each vertex, in 0..=1 (the module
    /// doc gives the mapping of each quadric).
    pub st: [[f64; 2]; 3],
}

/// Why a quadric cannot be tessellated. Fields are named as records spell
/// them, `sphere.radius`, `cone.base`.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum QuadricError {
    /// A radius or height that must be positive is not.
    #[error("{kind}.{field} {value} is not a positive number")]
    NotPositive {
        /// `sphere`, `cylinder`, `cone` or `disk`.
        kind: &'static str,
        /// The field: `radius`, `height`, `outer`.
        field: &'static str,
        /// Its value (maybe NaN or infinite).
        value: f64,
    },
    /// A radius that may be 0 is negative or not a number.
    #[error("{kind}.{field} {value} is not a number >= 0")]
    Negative {
        /// `cylinder`, `cone` or `disk`.
        kind: &'static str,
        /// The field: `base`, `top`, `inner`.
        field: &'static str,
        /// Its value.
        value: f64,
    },
    /// A cylinder with neither a base nor a top radius.
    #[error("{kind}: base and top radius are both 0")]
    NoRadius {
        /// `cylinder` or `cone`.
        kind: &'static str,
    },
    /// A disk whose hole is as large as the disk.
    #[error("disk: inner radius {inner} is not below outer radius {outer}")]
    InnerNotBelowOuter {
        /// `disk.inner`.
        inner: f64,
        /// `disk.outer`.
        outer: f64,
    },
    /// Slices or stacks out of range.
    #[error("{kind}: {what} {value}: expected {min} to {MAX_SEGMENTS}")]
    Segments {
        /// The quadric.
        kind: &'static str,
        /// `slices` or `stacks`.
        what: &'static str,
        /// The count asked for.
        value: u32,
        /// The least this quadric takes.
        min: u32,
    },
    /// The record's transform sends a vertex to infinity or NaN.
    #[error("{kind}: the transform moves a vertex out of the finite numbers")]
    NotFinite {
        /// The quadric.
        kind: &'static str,
    },
}

impl QuadricError {
    /// The error with the quadric named `kind`: a cone's record names its
    /// fields `cone.base`, although the cone is checked as the cylinder it is.
    pub fn for_kind(mut self, name: &'static str) -> QuadricError {
        match &mut self {
            QuadricError::NotPositive { kind, .. }
            | QuadricError::Negative { kind, .. }
            | QuadricError::NoRadius { kind }
            | QuadricError::Segments { kind, .. }
            | QuadricError::NotFinite { kind } => *kind = name,
            QuadricError::InnerNotBelowOuter { .. } => {}
        }
        self
    }
}

impl Quadric {
    /// The quadric's GLU name, as records and errors spell it (a cone is a
    /// cylinder with a zero top: [`QuadricError::for_kind`] renames it).
    pub fn kind(&self) -> &'static str {
        match self {
            Quadric::Sphere { .. } => "sphere",
            Quadric::Cylinder { .. } => "cylinder",
            Quadric::Disk { .. } => "disk",
        }
    }

    /// Checks the radii and height: every one positive (an inner disk radius
    /// or a cone's top may be 0).
    pub fn check(&self) -> Result<(), QuadricError> {
        let kind = self.kind();
        let pos = |field: &'static str, value: f64| {
            if value.is_finite() && value > 0.0 {
                Ok(())
            } else {
                Err(QuadricError::NotPositive { kind, field, value })
            }
        };
        let nonneg = |field: &'static str, value: f64| {
            if value.is_finite() && value >= 0.0 {
                Ok(())
            } else {
                Err(QuadricError::Negative { kind, field, value })
            }
        };
        match *self {
            Quadric::Sphere { radius } => pos("radius", radius),
            Quadric::Cylinder { base, top, height } => {
                nonneg("base", base)?;
                nonneg("top", top)?;
                pos("height", height)?;
                if base == 0.0 && top == 0.0 {
                    return Err(QuadricError::NoRadius { kind });
                }
                Ok(())
            }
            Quadric::Disk { inner, outer } => {
                nonneg("inner", inner)?;
                pos("outer", outer)?;
                if inner >= outer {
                    return Err(QuadricError::InnerNotBelowOuter { inner, outer });
                }
                Ok(())
            }
        }
    }

    /// A sphere enclosing the quadric, centre and radius, in its own
    /// coordinates: what [`tolerance_at`] projects.
    pub fn bounding_sphere(&self) -> (DVec3, f64) {
        match *self {
            Quadric::Sphere { radius } => (DVec3::ZERO, radius),
            Quadric::Cylinder { base, top, height } => (
                DVec3::new(0.0, 0.0, height / 2.0),
                math::hypot(base.max(top), height / 2.0),
            ),
            Quadric::Disk { outer, .. } => (DVec3::ZERO, outer),
        }
    }

    /// The largest radius of the quadric: what its chord error scales with.
    pub fn max_radius(&self) -> f64 {
        match *self {
            Quadric::Sphere { radius } => radius,
            Quadric::Cylinder { base, top, .. } => base.max(top),
            Quadric::Disk { outer, .. } => outer,
        }
    }

    /// Slices and stacks (loops for a disk) so that no point of the faces
    /// strays more than `tolerance` (same units as the radius) from the true
    /// surface. A chord spanning angle θ strays by its sagitta `r (1 -
    /// cos(θ/2))`; slices span 2π/n. A sphere's face is curved both ways, and
    /// its centre sits inside by about the sum of the two sagittas (seen
    /// pole-on, the silhouette is the ring nearest the equator, already a
    /// stack's sagitta in, cut by the slices' chords), so the sphere gives
    /// each direction half the tolerance; its stacks span π/n of a meridian.
    /// A cylinder's and a disk's other direction is straight, so one stack or
    /// loop is exact and the slices get the whole tolerance.
    pub fn segments_for(&self, tolerance: f64) -> (u32, u32) {
        let r = self.max_radius();
        let tolerance = match self {
            Quadric::Sphere { .. } => tolerance / 2.0,
            _ => tolerance,
        };
        let n_for = |span: f64| -> u32 {
            let ratio = (1.0 - tolerance / r).clamp(-1.0, 1.0);
            let half = math::acos(ratio);
            if half <= 0.0 || !half.is_finite() {
                return MAX_SEGMENTS;
            }
            ((span / (2.0 * half)).ceil() as u32).clamp(1, MAX_SEGMENTS)
        };
        let slices = n_for(2.0 * PI).max(MIN_SLICES);
        let stacks = match self {
            Quadric::Sphere { .. } => n_for(PI).max(MIN_SPHERE_STACKS),
            _ => 1,
        };
        (slices, stacks)
    }

    /// The quadric as triangles, counter-clockwise seen from outside, with
    /// GLU texture coordinates. Triangles that collapse at a pole or a cone's
    /// apex are left out.
    pub fn tessellate(&self, slices: u32, stacks: u32) -> Result<Vec<Triangle>, QuadricError> {
        let mut out = Vec::with_capacity(2 * (slices as usize) * (stacks as usize));
        self.for_each_triangle(slices, stacks, |t| {
            out.push(t);
            Ok::<(), QuadricError>(())
        })?;
        Ok(out)
    }

    /// How many triangles [`Quadric::tessellate`] makes, computed without
    /// making them, so a budget can be checked first: two per quad, less one
    /// for each of a quad's rings that is a single point (a sphere's poles,
    /// a cone's apex, a full disk's centre), whose triangle there has no
    /// area and is left out. Exact unless distinct points round to the same
    /// one (radii near the smallest `f64`), and never too small.
    pub fn triangle_bound(&self, slices: u32, stacks: u32) -> u64 {
        let collapsed = |t: f64| -> u64 {
            let radius = match *self {
                Quadric::Sphere { .. } => {
                    if t == 0.0 || t == 1.0 {
                        0.0
                    } else {
                        1.0
                    }
                }
                Quadric::Cylinder { base, top, .. } => base + (top - base) * t,
                Quadric::Disk { inner, outer } => inner + (outer - inner) * t,
            };
            (radius == 0.0) as u64
        };
        (0..stacks)
            .map(|j| {
                let (t0, t1) = (j as f64 / stacks as f64, (j + 1) as f64 / stacks as f64);
                2u64.saturating_sub(collapsed(t0) + collapsed(t1)) * slices as u64
            })
            .sum()
    }

    /// [`Quadric::tessellate`]'s triangles handed to `each` one at a time, in
    /// the same order, so a tool that writes them as it goes (`polyfill3`)
    /// holds none of them: ten million triangles of a large sphere took 2.3 GB
    /// as a list (issue 17, item 2).
    pub fn for_each_triangle<E: From<QuadricError>>(
        &self,
        slices: u32,
        stacks: u32,
        mut each: impl FnMut(Triangle) -> Result<(), E>,
    ) -> Result<(), E> {
        self.check()?;
        let min_stacks = match self {
            Quadric::Sphere { .. } => MIN_SPHERE_STACKS,
            _ => 1,
        };
        let segments = |what: &'static str, value: u32, min: u32| {
            if (min..=MAX_SEGMENTS).contains(&value) {
                Ok(())
            } else {
                Err(QuadricError::Segments {
                    kind: self.kind(),
                    what,
                    value,
                    min,
                })
            }
        };
        segments("slices", slices, MIN_SLICES)?;
        segments("stacks", stacks, min_stacks)?;
        // Angle from +y towards -x, so s = 0.25 lands on -x (GLU: s = 1 - i/n
        // at angle 2πi/n from +y towards +x).
        let around = |s: f64| {
            let a = 2.0 * PI * s;
            // Exact at the whole turn (s = 1), so the seam column matches
            // column 0 bit for bit. Not at the quarter turns: the radians of
            // a quarter give a cosine of 6.1e-17 (math::sin_cos_degrees is
            // exact there, but moving to it would move every vertex a bit).
            let (sin, cos) = if s == 1.0 {
                (0.0, 1.0)
            } else {
                math::sin_cos(a)
            };
            (-sin, cos)
        };
        let point = |s: f64, t: f64| -> DVec3 {
            let (sin, cos) = around(s);
            match *self {
                Quadric::Sphere { radius } => {
                    let ring = if t == 0.0 || t == 1.0 {
                        0.0
                    } else {
                        radius * math::sin(PI * t)
                    };
                    DVec3::new(ring * sin, ring * cos, -radius * math::cos(PI * t))
                }
                Quadric::Cylinder { base, top, height } => {
                    let r = base + (top - base) * t;
                    DVec3::new(r * sin, r * cos, height * t)
                }
                Quadric::Disk { inner, outer } => {
                    let r = inner + (outer - inner) * t;
                    DVec3::new(r * sin, r * cos, 0.0)
                }
            }
        };
        let st_of = |s: f64, t: f64, p: DVec3| -> [f64; 2] {
            match *self {
                Quadric::Disk { outer, .. } => {
                    [0.5 + p.x / (2.0 * outer), 0.5 + p.y / (2.0 * outer)]
                }
                _ => [s, t],
            }
        };
        for j in 0..stacks {
            let (t0, t1) = (j as f64 / stacks as f64, (j + 1) as f64 / stacks as f64);
            for i in 0..slices {
                let (s0, s1) = (i as f64 / slices as f64, (i + 1) as f64 / slices as f64);
                let q = [(s0, t0), (s0, t1), (s1, t1), (s1, t0)];
                let mut quad = q.map(|(s, t)| {
                    let p = point(s, t);
                    (p, st_of(s, t, p))
                });
                // With s turning from +y towards -x, the listed order runs
                // clockwise seen from outside a sphere or cylinder: reverse
                // it. A disk (facing +z, its radius as t) already runs
                // counter-clockwise.
                if !matches!(self, Quadric::Disk { .. }) {
                    quad.reverse();
                }
                for tri in [[0, 1, 2], [0, 2, 3]] {
                    let [a, b, c] = tri.map(|k| quad[k]);
                    if a.0 == b.0 || b.0 == c.0 || a.0 == c.0 {
                        continue;
                    }
                    each(Triangle {
                        v: [a.0, b.0, c.0],
                        st: [a.1, b.1, c.1],
                    })?;
                }
            }
        }
        Ok(())
    }
}

/// The chord tolerance, in the quadric's own units, that keeps chords within
/// `tolerance_px` pixels when `own_to_clip` (the view's world-to-clip matrix
/// times the quadric's placement) draws it on a `width` x `height` image.
///
/// The bounding sphere (centre c, radius r) is projected at its nearest
/// depth: one own unit covers at most `max(W/2 |∇x_clip|, H/2 |∇y_clip|) / w`
/// pixels, where the gradients are the clip matrix's first two rows (their
/// length also carries any scaling of the placement) and `w` the clip w. For
/// a perspective view `w` grows with the distance from the eye, so the
/// nearest point of the sphere, `w(c) - r |∇w|`, is where the pixels per unit
/// peak; for a parallel view `w` is 1 everywhere. When that nearest `w` is not
/// positive (the sphere reaches the eye plane) or the scale is not finite,
/// [`FALLBACK_RELATIVE_TOLERANCE`] of the radius is used.
pub fn tolerance_at(
    q: &Quadric,
    own_to_clip: DMat4,
    width: u32,
    height: u32,
    tolerance_px: f64,
) -> f64 {
    let (c, r) = q.bounding_sphere();
    let rows = own_to_clip.transpose();
    let (rx, ry, rw) = (rows.x_axis, rows.y_axis, rows.w_axis);
    let w_center = rw.truncate().dot(c) + rw.w;
    let w_near = w_center - r * rw.truncate().length();
    let grad = (width as f64 / 2.0 * rx.truncate().length())
        .max(height as f64 / 2.0 * ry.truncate().length());
    let px_per_unit = grad / w_near;
    let tol = tolerance_px / px_per_unit;
    if w_near > 0.0 && tol.is_finite() && tol > 0.0 {
        tol
    } else {
        r * FALLBACK_RELATIVE_TOLERANCE
    }
}

/// A quadric record of the polygon stream (docs/objects.md): the quadric,
/// its slices and stacks when the record gives them, how many copies of the
/// pattern wrap it, and its placement.
#[derive(Clone, Debug, PartialEq)]
pub struct QuadricShape {
    /// The quadric and its dimensions, in own coordinates.
    pub quadric: Quadric,
    /// The record's key (`sphere`, `cylinder`, `cone`, `disk`), for messages.
    pub kind: &'static str,
    /// Segments around the axis. Default value: chosen from the tolerance.
    pub slices: Option<u32>,
    /// Segments along the axis (a disk's `loops`). Default value: chosen from
    /// the tolerance.
    pub stacks: Option<u32>,
    /// Copies of the pattern along s and t. Default value: `[1, 1]`, one copy
    /// wrapping the whole quadric as GLU's 0..1 texture coordinates do.
    pub repeat: [f64; 2],
    /// The record's `"transform"`, own coordinates to the record's space.
    /// Default value: the identity.
    pub transform: Transform,
}

/// One triangle ready to draw: positions in the record's space (the
/// placement applied) and texture coordinates in texels.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TexelTriangle {
    /// Vertex positions in the record's space (the record's transform applied).
    pub v: [DVec3; 3],
    /// Texture coordinates `[u, v]` of each vertex in texels: GLU's (s, t)
    /// times the pattern size times `repeat`, v = 0 at the pattern's bottom row.
    pub uv: [[f64; 2]; 3],
    /// The surface's outward unit normal at each vertex, in the record's
    /// space ([`Quadric::normal_at`] moved by [`Transform::apply_normal`]),
    /// for smooth lighting (GLU's `GLU_SMOOTH` normals).
    pub n: [DVec3; 3],
}

impl QuadricShape {
    /// Slices and stacks: the record's own, or else the fewest within
    /// `tolerance` (own units), each direction independently.
    pub fn segments(&self, tolerance: f64) -> (u32, u32) {
        let (sl, st) = self.quadric.segments_for(tolerance);
        (self.slices.unwrap_or(sl), self.stacks.unwrap_or(st))
    }

    /// [`Quadric::triangle_bound`] at the segments `tolerance` gives.
    pub fn triangle_bound(&self, tolerance: f64) -> u64 {
        let (slices, stacks) = self.segments(tolerance);
        self.quadric.triangle_bound(slices, stacks)
    }

    /// The triangles of the quadric at `tolerance` (own units, used only for
    /// the segment counts the record leaves out), moved by the record's
    /// transform, with GLU's (s, t) scaled to texels of a `width x height`
    /// store: `u = s * width * repeat[0]`, `v = t * height * repeat[1]`, so
    /// t = 0 (GLU's first texture row, the sphere's -z pole) is the pattern's
    /// bottom row 0.
    pub fn texel_triangles(
        &self,
        tolerance: f64,
        size: (u32, u32),
    ) -> Result<Vec<TexelTriangle>, QuadricError> {
        let mut out = Vec::new();
        self.for_each_texel_triangle(tolerance, size, |t| {
            out.push(t);
            Ok::<(), QuadricError>(())
        })?;
        Ok(out)
    }

    /// [`QuadricShape::texel_triangles`] handed to `each` one at a time; a
    /// triangle with a coordinate that is not finite stops it with
    /// [`QuadricError::NotFinite`].
    pub fn for_each_texel_triangle<E: From<QuadricError>>(
        &self,
        tolerance: f64,
        (width, height): (u32, u32),
        mut each: impl FnMut(TexelTriangle) -> Result<(), E>,
    ) -> Result<(), E> {
        let (slices, stacks) = self.segments(tolerance);
        let (su, sv) = (
            width as f64 * self.repeat[0],
            height as f64 * self.repeat[1],
        );
        self.quadric
            .for_each_triangle(slices, stacks, |t| {
                let face = (t.v[1] - t.v[0]).cross(t.v[2] - t.v[0]);
                let normal = |p: DVec3| {
                    let own = self.quadric.normal_at(p).unwrap_or(face);
                    self.transform.apply_normal(own)
                };
                let t = TexelTriangle {
                    v: t.v.map(|p| self.transform.apply(p)),
                    uv: t.st.map(|[s, t]| [s * su, t * sv]),
                    n: t.v.map(normal),
                };
                if t.v.iter().any(|p| !p.is_finite()) {
                    return Err(Stop::Caller(E::from(QuadricError::NotFinite {
                        kind: self.kind,
                    })));
                }
                each(t).map_err(Stop::Caller)
            })
            .map_err(|e| match e {
                Stop::Quadric(q) => E::from(q.for_kind(self.kind)),
                Stop::Caller(e) => e,
            })
    }
}

/// Why [`QuadricShape::for_each_texel_triangle`] stopped: the tessellation's
/// own error (renamed for the record's kind) or the caller's.
enum Stop<E> {
    Quadric(QuadricError),
    Caller(E),
}

impl<E> From<QuadricError> for Stop<E> {
    fn from(e: QuadricError) -> Self {
        Stop::Quadric(e)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_triangle_bound_is_the_count_tessellate_makes() {
        let shapes = [
            Quadric::Sphere { radius: 2.0 },
            Quadric::Cylinder {
                base: 1.0,
                top: 0.5,
                height: 2.0,
            },
            Quadric::Cylinder {
                base: 1.0,
                top: 0.0,
                height: 2.0,
            },
            Quadric::Cylinder {
                base: 0.0,
                top: 3.0,
                height: 1.0,
            },
            Quadric::Disk {
                inner: 0.0,
                outer: 1.0,
            },
            Quadric::Disk {
                inner: 0.5,
                outer: 1.0,
            },
        ];
        for q in shapes {
            for (slices, stacks) in [(3, 2), (4, 2), (7, 5), (32, 16)] {
                let made = q.tessellate(slices, stacks).unwrap().len() as u64;
                assert_eq!(
                    q.triangle_bound(slices, stacks),
                    made,
                    "{q:?} {slices}x{stacks}"
                );
            }
        }
    }

    fn normal(t: &Triangle) -> DVec3 {
        (t.v[1] - t.v[0]).cross(t.v[2] - t.v[0])
    }

    #[test]
    fn glu_texture_coordinates_and_the_seam() {
        let tris = Quadric::Sphere { radius: 2.0 }.tessellate(4, 2).unwrap();
        // 4 slices x 2 stacks, each stack's pole triangle collapsed: 8 triangles.
        assert_eq!(tris.len(), 8);
        for t in &tris {
            for (p, st) in t.v.iter().zip(&t.st) {
                // s = 0.25 is -x, s = 0 is +y; t = 0 is z = -r.
                if (st[0] - 0.25).abs() < 1e-12 && (st[1] - 0.5).abs() < 1e-12 {
                    assert!((*p - DVec3::new(-2.0, 0.0, 0.0)).length() < 1e-12);
                }
                if st[1] == 0.0 {
                    assert_eq!(p.z, -2.0);
                }
            }
            // No triangle's s spans more than one slice: nothing wraps.
            let (lo, hi) =
                t.st.iter()
                    .fold((2.0f64, -1.0f64), |(a, b), x| (a.min(x[0]), b.max(x[0])));
            assert!(hi - lo <= 0.25 + 1e-12, "{t:?}");
            // Counter-clockwise seen from outside: the normal points away from the centre.
            let c = (t.v[0] + t.v[1] + t.v[2]) / 3.0;
            assert!(normal(t).dot(c) > 0.0, "{t:?}");
        }
        // The seam column (s = 1) sits exactly on column 0 (s = 0).
        let seam: Vec<DVec3> = tris
            .iter()
            .flat_map(|t| {
                t.v.iter()
                    .zip(&t.st)
                    .filter(|(_, st)| st[0] == 1.0)
                    .map(|(p, _)| *p)
            })
            .collect();
        assert!(!seam.is_empty());
        assert!(seam.iter().all(|p| p.x == 0.0 && p.y >= 0.0));
    }

    #[test]
    fn cylinder_cone_and_disk_face_outwards() {
        for q in [
            Quadric::Cylinder {
                base: 1.0,
                top: 1.0,
                height: 3.0,
            },
            Quadric::Cylinder {
                base: 2.0,
                top: 0.0,
                height: 1.0,
            },
        ] {
            for t in q.tessellate(16, 3).unwrap() {
                let c = (t.v[0] + t.v[1] + t.v[2]) / 3.0;
                let radial = DVec3::new(c.x, c.y, 0.0);
                assert!(normal(&t).dot(radial) > 0.0, "{q:?} {t:?}");
            }
        }
        let disk = Quadric::Disk {
            inner: 0.5,
            outer: 2.0,
        }
        .tessellate(8, 2)
        .unwrap();
        for t in &disk {
            assert!(normal(t).z > 0.0);
            for (p, st) in t.v.iter().zip(&t.st) {
                assert!((st[0] - (0.5 + p.x / 4.0)).abs() < 1e-15);
            }
        }
    }

    #[test]
    fn chord_error_stays_below_the_tolerance() {
        let q = Quadric::Sphere { radius: 40.0 };
        for tol in [1.0, 0.1, 1.0 / 256.0] {
            let (slices, stacks) = q.segments_for(tol);
            // Each direction of a sphere gets half the tolerance.
            let tol = tol / 2.0;
            // The sagitta of one slice and one stack.
            let sag = |span: f64| 40.0 * (1.0 - math::cos(span / 2.0));
            assert!(sag(2.0 * PI / slices as f64) <= tol);
            assert!(sag(PI / stacks as f64) <= tol);
            // And not wastefully fine: one slice fewer would exceed it.
            assert!(sag(2.0 * PI / (slices - 1) as f64) > tol || slices == MIN_SLICES);
        }
    }

    #[test]
    fn bad_quadrics_are_errors() {
        let e = |q: Quadric, sl, st| q.tessellate(sl, st).unwrap_err().to_string();
        assert!(
            e(Quadric::Sphere { radius: 0.0 }, 8, 8).contains("sphere.radius 0 is not a positive")
        );
        assert!(e(Quadric::Sphere { radius: -1.0 }, 8, 8).contains("not a positive"));
        assert!(e(Quadric::Sphere { radius: 1.0 }, 2, 8).contains("slices 2: expected 3"));
        assert!(e(Quadric::Sphere { radius: 1.0 }, 8, 1).contains("stacks 1: expected 2"));
        assert!(e(
            Quadric::Cylinder {
                base: 0.0,
                top: 0.0,
                height: 1.0
            },
            8,
            1
        )
        .contains("both 0"));
        assert!(e(
            Quadric::Disk {
                inner: 2.0,
                outer: 1.0
            },
            8,
            1
        )
        .contains("not below outer"));
        assert!(e(Quadric::Sphere { radius: f64::NAN }, 8, 8).contains("not a positive"));
    }

    #[test]
    fn the_pixel_tolerance_becomes_own_units_at_the_nearest_depth() {
        let q = Quadric::Sphere { radius: 10.0 };
        // glOrtho(0, 200, 0, 200, ...) on 200x200: one unit is one pixel.
        let ortho = DMat4::orthographic_rh_gl(0.0, 200.0, 0.0, 200.0, -100.0, 100.0);
        assert!((tolerance_at(&q, ortho, 200, 200, 0.25) - 0.25).abs() < 1e-12);
        // Placed at twice the size, a pixel is half an own unit.
        let scaled = ortho * DMat4::from_scale(DVec3::splat(2.0));
        assert!((tolerance_at(&q, scaled, 200, 200, 0.25) - 0.125).abs() < 1e-12);
        // Perspective: pixels per unit are (H/2) f / w at the nearest point,
        // w = d - r for a sphere d in front of the eye.
        let fovy = 60f64.to_radians();
        let persp = DMat4::perspective_rh_gl(fovy, 1.0, 1.0, 1000.0);
        let f = 1.0 / math::tan(fovy / 2.0);
        for d in [50.0, 200.0] {
            let at = persp * DMat4::from_translation(DVec3::new(0.0, 0.0, -d));
            let want = 0.25 / (100.0 * f / (d - 10.0));
            assert!((tolerance_at(&q, at, 200, 200, 0.25) - want).abs() < 1e-12 * want.max(1.0));
        }
        // A sphere around the eye: the relative fallback.
        let around = persp * DMat4::from_translation(DVec3::new(0.0, 0.0, -5.0));
        assert_eq!(
            tolerance_at(&q, around, 200, 200, 0.25),
            10.0 * FALLBACK_RELATIVE_TOLERANCE
        );
    }

    #[test]
    fn texel_triangles_scale_repeat_and_move() {
        let shape = QuadricShape {
            quadric: Quadric::Cylinder {
                base: 1.0,
                top: 1.0,
                height: 2.0,
            },
            kind: "cylinder",
            slices: Some(4),
            stacks: Some(1),
            repeat: [2.0, 3.0],
            transform: Transform::translate(DVec3::new(10.0, 0.0, 0.0)),
        };
        let tris = shape.texel_triangles(1.0, (16, 16)).unwrap();
        assert_eq!(tris.len(), 8);
        let (mut umax, mut vmax) = (0.0f64, 0.0f64);
        for t in &tris {
            for (p, uv) in t.v.iter().zip(&t.uv) {
                assert!((DVec3::new(p.x - 10.0, p.y, 0.0).length() - 1.0).abs() < 1e-12);
                umax = umax.max(uv[0]);
                vmax = vmax.max(uv[1]);
            }
        }
        // s and t reach 1: 16 texels x 2 copies around, x 3 along.
        assert_eq!((umax, vmax), (32.0, 48.0));
        // Explicit counts win over the tolerance; missing ones follow it.
        let fine = QuadricShape {
            slices: None,
            ..shape
        };
        assert_eq!(
            fine.segments(1e-3).0,
            Quadric::Cylinder {
                base: 1.0,
                top: 1.0,
                height: 2.0
            }
            .segments_for(1e-3)
            .0
        );
    }

    proptest::proptest! {
        #[test]
        fn sphere_vertices_lie_on_it_and_no_triangle_wraps(
            radius in 0.01f64..1e4,
            slices in 3u32..64,
            stacks in 2u32..64,
        ) {
            let tris = Quadric::Sphere { radius }.tessellate(slices, stacks).unwrap();
            // Every quad but the pole triangles' collapsed halves.
            proptest::prop_assert_eq!(tris.len() as u32, 2 * slices * stacks - 2 * slices);
            for t in &tris {
                for p in &t.v {
                    proptest::prop_assert!((p.length() - radius).abs() <= 1e-12 * radius);
                }
                let s: Vec<f64> = t.st.iter().map(|x| x[0]).collect();
                let span = s.iter().cloned().fold(f64::MIN, f64::max) - s.iter().cloned().fold(f64::MAX, f64::min);
                // One slice at most: nothing wraps from s near 1 back to 0.
                proptest::prop_assert!(span <= 1.0 / slices as f64 + 1e-12);
                for st in &t.st {
                    proptest::prop_assert!((0.0..=1.0).contains(&st[0]) && (0.0..=1.0).contains(&st[1]));
                }
            }
        }
    }
}
