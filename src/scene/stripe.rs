//! A record's stripe texture (seed 001, [`crate::stripe`], schema in
//! `docs/stripe.md`): read with the record, turned into the per-pixel shader
//! of each projected face.

use crate::color::Rgb8;
use crate::geom::Shape;
use crate::stripe::record::{LoadedStripe, NoMapping, StripeError, StripeLoader, StripeSpec};
use crate::stripe::{LodMode, StripeTexture};
use crate::view::View;
use std::sync::Arc;

/// The face colour of a stripe record with neither a colour code nor a
/// `"color"`: white, so that the face shows the translated map itself (a
/// black face, the default of untextured records, would hide it entirely).
pub const DEFAULT_FACE: Rgb8 = Rgb8::WHITE;

/// A record's stripe texture as read: files loaded, face colour decided; it
/// becomes a [`StripeTexture`] when the record is projected.
#[derive(Clone, Debug)]
pub struct RecordStripe {
    /// The maps and tables the record names, loaded once per file.
    pub loaded: Arc<LoadedStripe>,
    /// The face colour the translation modulates.
    pub face: Rgb8,
    /// The blend to the next face colour, when the blend flag is set.
    pub blend: Option<crate::stripe::Blend>,
}

/// The stripe texture of a record's `fields`, if it has one. Errors name the
/// field (`stripe.spacing: ...`) or the file; the caller adds the record.
pub fn read(
    loader: &mut StripeLoader,
    fields: &crate::stream::Fields,
    colour: Option<Rgb8>,
) -> Result<Option<RecordStripe>, StripeError> {
    let Some(spec) = StripeSpec::from_fields(fields)? else {
        return Ok(None);
    };
    let loaded = loader.load(&spec)?;
    let face = loaded.face_colour(colour, DEFAULT_FACE);
    let blend = loaded.blend();
    Ok(Some(RecordStripe {
        loaded: Arc::new(loaded),
        face,
        blend,
    }))
}

/// The shader of a projected face: `outline` in the coordinates `view`'s
/// matrix takes (an object's own under an instance). `Ok(None)` when the face
/// is seen edge-on (it covers no pixels; the projection's rounding can still
/// leave it a sliver, which is then not drawn).
pub fn shader(
    s: &RecordStripe,
    view: &View,
    outline: &[glam::DVec3],
    mode: LodMode,
) -> Result<Option<StripeTexture>, NoMapping> {
    match s.loaded.texture_on(
        &Shape::Polygon(outline.into()),
        view.world_to_clip,
        view.width,
        view.height,
        mode,
        s.face,
    ) {
        Ok(t) => Ok(Some(match &s.blend {
            Some(b) => t.with_blend(b),
            None => t,
        })),
        Err(NoMapping::EdgeOn) => Ok(None),
        Err(e) => Err(e),
    }
}
