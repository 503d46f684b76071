//! `scene-render`'s stripe flags (seed 001, schema in `docs/stripe.md`): the
//! level-of-detail rule. The records' stripes are read by
//! [`crate::scene::stripe`].

use crate::stripe::LodMode;

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
