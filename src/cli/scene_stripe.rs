//! `scene-render`'s stripe textures (seed 001, `crate::stripe`, schema in
//! `docs/stripe.md`): the flags that choose the level-of-detail rule, and the
//! per-record step from a `"stripe"` object to the per-pixel shader on the
//! projected face.

use crate::color::Rgb8;
use crate::view::View;
use crate::geom::Shape;
use crate::stripe::record::{LoadedStripe, NoMapping, StripeLoader, StripeSpec};
use crate::stripe::{LodMode, StripeTexture};
use anyhow::Result;
use std::sync::Arc;

/// Which levels of a stripe map's pyramid a pixel reads (`--stripe-lod`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default, clap::ValueEnum)]
pub enum StripeLod {
    /// The single level nearest to the pixel's footprint.
    Nearest,
    /// A continuous level, blended linearly between the two nearest levels.
    #[default]
    Blended,
}

/// How stripe textures are filtered.
#[derive(clap::Args, Debug, Clone)]
pub struct StripeArgs {
    /// Level of detail of stripe textures (docs/stripe.md): blended reads the
    /// two levels around the pixel's footprint (the gradient length of the
    /// texture coordinate) and blends them by the continuous fraction a;
    /// nearest reads the one nearest level.
    #[arg(long, value_enum, value_name = "MODE", default_value_t = StripeLod::Blended)]
    pub stripe_lod: StripeLod,

    /// Stripe textures by the Compuscene III rule of seed 001 (Fig. 7): level =
    /// the binary exponent of the larger derivative ΔP_max, blend factor a in
    /// 4 bits, one table entry per level. Cheaper and coarser than blended.
    #[arg(long, conflicts_with = "stripe_lod")]
    pub cig_compat: bool,
}

impl StripeArgs {
    /// The LOD rule the flags select. Default value: [`LodMode::Blend`].
    pub fn mode(&self) -> LodMode {
        match (self.cig_compat, self.stripe_lod) {
            (true, _) => LodMode::Cig,
            (false, StripeLod::Nearest) => LodMode::Nearest,
            (false, StripeLod::Blended) => LodMode::Blend,
        }
    }
}

/// The face colour of a stripe record with neither a colour code nor a
/// `"color"`: white, so that the face shows the translated map itself (a
/// black face, the default of untextured records, would hide it entirely).
pub const DEFAULT_FACE: Rgb8 = Rgb8::WHITE;

/// A record's stripe texture as read: files loaded, face colour decided; it
/// becomes a [`StripeTexture`] when the record is projected.
#[derive(Clone, Debug)]
pub struct RecordStripe {
    pub loaded: Arc<LoadedStripe>,
    pub face: Rgb8,
}

/// The stripe texture of a record's `fields`, if it has one. Errors name the
/// field (`stripe.spacing: ...`) or the file; the caller adds the record.
pub fn read(
    loader: &mut StripeLoader,
    fields: &serde_json::Map<String, serde_json::Value>,
    colour: Option<Rgb8>,
) -> Result<Option<RecordStripe>> {
    let Some(spec) = StripeSpec::from_fields(fields).map_err(anyhow::Error::msg)? else {
        return Ok(None);
    };
    let loaded = loader.load(&spec)?;
    let face = loaded.face_colour(colour, DEFAULT_FACE);
    Ok(Some(RecordStripe {
        loaded: Arc::new(loaded),
        face,
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
) -> Result<Option<StripeTexture>> {
    match s.loaded.texture_on(
        &Shape::Polygon(outline.to_vec()),
        view.world_to_clip,
        view.width,
        view.height,
        mode,
        s.face,
    ) {
        Ok(t) => Ok(Some(t)),
        Err(NoMapping::EdgeOn) => Ok(None),
        Err(e) => Err(e.into()),
    }
}
