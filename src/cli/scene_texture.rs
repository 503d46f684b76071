//! `scene-render`'s direct texturing: placing a record's "object" or "uv"
//! pattern (SPEC §2) on its projected polygon, so that it is sampled per
//! pixel (`crate::texture`) instead of being exploded into texel polygons by
//! `polyfill3` first.

use crate::geom::plane::DEFAULT_PLANARITY_TOL;
use crate::geom::Placement;
use crate::raster::{ScreenPattern, View};
use crate::stream::{PatternMode, PatternRef};
use crate::texture::map::{object_uv, TexMap};
use crate::texture::PolyTexture;
use anyhow::Result;
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

/// The texture of a record placed in `mode` (object or uv) over the world
/// polygon `outline`; `None` when nothing of it is visible. `uv` are the
/// record's per-vertex coordinates.
pub fn place(
    view: &View,
    outline: &[DVec3],
    pref: &PatternRef,
    mode: PatternMode,
    uv: Option<&[[f64; 2]]>,
    texels: Arc<ScreenPattern>,
) -> Result<Option<PolyTexture>> {
    let coords: Vec<DVec2> = match (mode, uv) {
        (PatternMode::Uv, Some(uv)) => uv.iter().map(|t| DVec2::new(t[0], t[1])).collect(),
        (PatternMode::Uv, None) => {
            anyhow::bail!("pattern.mode is \"uv\" but the record has no \"uv\" coordinates")
        }
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
            )?
        }
    };
    if coords.len() != outline.len() {
        anyhow::bail!(
            "{} texture coordinates for {} vertices",
            coords.len(),
            outline.len()
        );
    }
    Ok(TexMap::fit(view, outline, &coords).map(|map| PolyTexture { texels, map }))
}
