//! Placing a record's "object" or "uv" pattern (docs/stream-format.md) on its projected
//! polygon: the texel coordinates of its vertices, then the screen → texel
//! map, so that the pattern is sampled per pixel instead of being exploded
//! into texel polygons by `polyfill3` first.

use super::boundary::{Boundary, Bounds};
use super::compose::Compose;
use super::filter::Filters;
use super::map::{object_uv, ObjectUvError, TexMap};
use super::skip::Skips;
use super::PolyTexture;
use crate::color::Rgb8;
use crate::error::OptionError;
use crate::geom::plane::DEFAULT_PLANARITY_TOL;
use crate::geom::Placement;
use crate::stream::{PatternMode, PatternRef};
use crate::texture::Texels;
use crate::view::View;
use glam::{DVec2, DVec3};
use std::sync::Arc;

/// `polyfill3`'s defaults for a record's missing placement fields (its
/// `--incr 1 --rotate 0 --horz 0 --vert 0`), so both paths place a pattern
/// the same way.
pub const DEFAULT_PLACEMENT: Placement = Placement {
    incr: 1.0,
    horz: 0.0,
    vert: 0.0,
};

/// How placed patterns are applied (`scene-render`'s texture flags).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TextureSettings {
    /// XGL's boundary conditions per axis. Default value: repeat (docs/stream-format.md).
    pub bounds: Bounds,
    /// The constant colour of [`Boundary::Clamp`]. Default value: black.
    pub boundary_color: Rgb8,
    /// How texels combine with the polygon's colour. Default value: replace.
    pub compose: Compose,
    /// The composition's two constant colours. Default value: black, white.
    pub compose_colors: [Rgb8; 2],
    /// Minification and magnification filters. Default value: the exact box.
    pub filters: Filters,
    /// Interpolate texel coordinates perspective-correctly; `false` is XGL's
    /// `PERSP_NONE`. Default value: true.
    pub perspective_correction: bool,
    /// Which work-saving skips are on (`scene-render --no-skip`, for
    /// benchmarks). Default value: all.
    pub skips: Skips,
}

impl TextureSettings {
    /// Every field's default value (listed on the fields): repeat, replace,
    /// the exact box filter, perspective correction, every skip on.
    pub const DEFAULT: TextureSettings = TextureSettings {
        bounds: Bounds {
            u: Boundary::Repeat,
            v: Boundary::Repeat,
        },
        boundary_color: Rgb8([0, 0, 0]),
        compose: Compose::Replace,
        compose_colors: [Rgb8([0, 0, 0]), Rgb8([255, 255, 255])],
        filters: Filters::BOX,
        perspective_correction: true,
        skips: Skips::ALL,
    };
}

impl Default for TextureSettings {
    fn default() -> Self {
        TextureSettings::DEFAULT
    }
}

/// Why a pattern cannot be placed on a record.
#[derive(Clone, Debug, PartialEq)]
pub enum PlaceError {
    /// `pattern.mode` is "uv" but the record has no "uv" field.
    MissingUv,
    /// The "uv" field has a different length from the outline.
    UvCount {
        /// Number of `[u, v]` pairs in the record's `"uv"`.
        uv: usize,
        /// Number of vertices of the outline.
        vertices: usize,
    },
    /// Object placement failed (no plane, or no grid).
    Object(ObjectUvError),
    /// The composition needs texels with alpha (XGL's decal rules).
    Compose(OptionError),
}

impl std::fmt::Display for PlaceError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            PlaceError::MissingUv => {
                write!(
                    f,
                    "pattern.mode is \"uv\" but the record has no \"uv\" coordinates"
                )
            }
            PlaceError::UvCount { uv, vertices } => {
                write!(f, "{uv} texture coordinates for {vertices} vertices")
            }
            PlaceError::Object(e) => e.fmt(f),
            PlaceError::Compose(e) => e.fmt(f),
        }
    }
}

impl std::error::Error for PlaceError {}

fn linear(c: Rgb8) -> [f64; 3] {
    c.to_linear_f64()
}

/// The texture of a record placed in `mode` (object or uv) over the world
/// polygon `outline`; `None` when nothing of it is visible. `uv` are the
/// record's per-vertex coordinates; `color` the record's own colour (XGL's
/// intrinsic colour).
#[allow(clippy::too_many_arguments)]
pub fn place(
    settings: &TextureSettings,
    color: Rgb8,
    view: &View,
    outline: &[DVec3],
    pref: &PatternRef,
    mode: PatternMode,
    uv: Option<&[[f64; 2]]>,
    texels: Arc<Texels>,
) -> Result<Option<PolyTexture>, PlaceError> {
    let coords: Vec<DVec2> = match (mode, uv) {
        (PatternMode::Uv, Some(uv)) => uv.iter().map(|t| DVec2::new(t[0], t[1])).collect(),
        (PatternMode::Uv, None) => return Err(PlaceError::MissingUv),
        _ => {
            let place = Placement {
                incr: pref.incr.unwrap_or(DEFAULT_PLACEMENT.incr),
                horz: pref.horz.unwrap_or(DEFAULT_PLACEMENT.horz),
                vert: pref.vert.unwrap_or(DEFAULT_PLACEMENT.vert),
            };
            object_uv(
                outline,
                place,
                pref.rotate.unwrap_or(0.0),
                DEFAULT_PLANARITY_TOL,
            )
            .map_err(PlaceError::Object)?
        }
    };
    settings
        .compose
        .check(texels.has_alpha())
        .map_err(PlaceError::Compose)?;
    if coords.len() != outline.len() {
        return Err(PlaceError::UvCount {
            uv: coords.len(),
            vertices: outline.len(),
        });
    }
    Ok(
        TexMap::fit(view, outline, &coords, settings.perspective_correction).map(|map| {
            PolyTexture {
                texels,
                map,
                bounds: settings.bounds,
                intrinsic: linear(color),
                constant: linear(settings.boundary_color),
                compose: settings.compose,
                compose_colors: settings.compose_colors.map(linear),
                filters: settings.filters,
                skips: settings.skips,
            }
        }),
    )
}
