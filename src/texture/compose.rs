//! How a texel's colour combines with the polygon's own (intrinsic) colour:
//! XGL's composition methods (`Xgl_texture_op`, XGL Programmer's Guide,
//! texture chapter, "Composition Method"). Computed in linear light.
//!
//! A `.pat` texel is an RGB colour or transparent: a four-channel map whose
//! alpha is 0 or 1. XGL makes the decal methods "only available when a
//! four-channel texture map is used"; a pattern without transparent texels
//! carries no alpha, so decal with it is an error.

use crate::error::OptionError;

/// The composition method.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
#[cfg_attr(feature = "cli", derive(clap::ValueEnum))]
pub enum Compose {
    /// `XGL_TEXTURE_OP_REPLACE`: the texel replaces the polygon's colour
    /// (patkit-stream(5); transparent texels show what is behind).
    #[default]
    Replace,
    /// `XGL_TEXTURE_OP_MODULATE`: texel times the polygon's colour.
    Modulate,
    /// `XGL_TEXTURE_OP_BLEND`: two constants blended by the texel,
    /// `c1 (1 - t) + c2 t` per channel.
    Blend,
    /// `XGL_TEXTURE_OP_BLEND_INTRINSIC`: the polygon's colour and a
    /// constant blended by the texel, `color (1 - t) + c1 t`.
    BlendIntrinsic,
    /// `XGL_TEXTURE_OP_DECAL`: the texel where opaque, the constant `c1`
    /// where transparent.
    Decal,
    /// `XGL_TEXTURE_OP_DECAL_INTRINSIC`: the texel where opaque, the
    /// polygon's colour where transparent.
    DecalIntrinsic,
}

impl Compose {
    /// Every method, in the order of `--compose`'s help.
    pub const ALL: [Compose; 6] = [
        Compose::Replace,
        Compose::Modulate,
        Compose::Blend,
        Compose::BlendIntrinsic,
        Compose::Decal,
        Compose::DecalIntrinsic,
    ];

    /// The name on the command line and in a record's `"pattern"`: the one
    /// table of spellings (a test in `cli::scene_texture` checks that clap's
    /// agree).
    pub fn name(self) -> &'static str {
        match self {
            Compose::Replace => "replace",
            Compose::Modulate => "modulate",
            Compose::Blend => "blend",
            Compose::BlendIntrinsic => "blend-intrinsic",
            Compose::Decal => "decal",
            Compose::DecalIntrinsic => "decal-intrinsic",
        }
    }

    /// XGL's restriction: decal needs a map with alpha (a pattern with
    /// transparent texels). The error names the method.
    pub fn check(self, has_alpha: bool) -> Result<(), OptionError> {
        match self {
            Compose::Decal | Compose::DecalIntrinsic if !has_alpha => Err(OptionError::new(
                "",
                "compose",
                format!(
                    " {}: XGL's decal methods need a four-channel map, and this \
                     pattern has no transparent texels (no alpha)",
                    self.name()
                ),
            )),
            _ => Ok(()),
        }
    }

    /// The composed colour of a texel (`None` = transparent), with the
    /// polygon's colour `intrinsic` and the constants `c1`, `c2`, all linear.
    #[inline]
    pub fn apply(
        self,
        texel: Option<[f64; 3]>,
        intrinsic: [f64; 3],
        c1: [f64; 3],
        c2: [f64; 3],
    ) -> Option<[f64; 3]> {
        let mix = |a: [f64; 3], b: [f64; 3], t: [f64; 3]| {
            [0, 1, 2].map(|i| a[i] * (1.0 - t[i]) + b[i] * t[i])
        };
        match (self, texel) {
            (Compose::Decal, None) => Some(c1),
            (Compose::DecalIntrinsic, None) => Some(intrinsic),
            (_, None) => None,
            (Compose::Replace | Compose::Decal | Compose::DecalIntrinsic, t) => t,
            (Compose::Modulate, Some(t)) => Some([0, 1, 2].map(|i| t[i] * intrinsic[i])),
            (Compose::Blend, Some(t)) => Some(mix(c1, c2, t)),
            (Compose::BlendIntrinsic, Some(t)) => Some(mix(intrinsic, c1, t)),
        }
    }
}

impl Compose {
    /// [`Compose::apply`] on a premultiplied linear RGBA texel `p` (alpha
    /// `p[3]`, for filtered texels whose alpha lies between 0 and 1). Every
    /// method is affine in (colour, alpha), so composing each texel and then
    /// filtering equals filtering and then composing; at alpha 0 and 1 it is
    /// exactly [`Compose::apply`] premultiplied.
    #[inline]
    pub fn apply_premultiplied(
        self,
        p: [f64; 4],
        intrinsic: [f64; 3],
        c1: [f64; 3],
        c2: [f64; 3],
    ) -> [f64; 4] {
        let a = p[3];
        let rgb = |f: &dyn Fn(usize) -> f64| [f(0), f(1), f(2)];
        match self {
            Compose::Replace => p,
            Compose::Modulate => {
                let c = rgb(&|i| p[i] * intrinsic[i]);
                [c[0], c[1], c[2], a]
            }
            Compose::Blend => {
                let c = rgb(&|i| a * c1[i] + (c2[i] - c1[i]) * p[i]);
                [c[0], c[1], c[2], a]
            }
            Compose::BlendIntrinsic => {
                let c = rgb(&|i| a * intrinsic[i] + (c1[i] - intrinsic[i]) * p[i]);
                [c[0], c[1], c[2], a]
            }
            // The texel over the constant (or the polygon's colour): opaque.
            Compose::Decal => {
                let c = rgb(&|i| p[i] + (1.0 - a) * c1[i]);
                [c[0], c[1], c[2], 1.0]
            }
            Compose::DecalIntrinsic => {
                let c = rgb(&|i| p[i] + (1.0 - a) * intrinsic[i]);
                [c[0], c[1], c[2], 1.0]
            }
        }
    }

    /// Whether this method shows a colour for transparent texels too (so a
    /// textured polygon is opaque everywhere).
    pub fn fills_transparent(self) -> bool {
        matches!(self, Compose::Decal | Compose::DecalIntrinsic)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const I: [f64; 3] = [0.5, 0.25, 1.0];
    const C1: [f64; 3] = [1.0, 0.0, 0.0];
    const C2: [f64; 3] = [0.0, 0.0, 1.0];

    #[test]
    fn each_method_combines_as_xgl_describes() {
        let t = Some([1.0, 0.5, 0.0]);
        assert_eq!(Compose::Replace.apply(t, I, C1, C2), t);
        assert_eq!(
            Compose::Modulate.apply(t, I, C1, C2),
            Some([0.5, 0.125, 0.0])
        );
        // XGL's example: blend between red and blue, per channel:
        // r = 1 (1 - 0.25) + 0, b = 0 + 1 * 0.5.
        let tb = Some([0.25, 0.5, 0.5]);
        assert_eq!(Compose::Blend.apply(tb, I, C1, C2), Some([0.75, 0.0, 0.5]));
        assert_eq!(
            Compose::BlendIntrinsic.apply(t, I, C1, C2),
            Some([1.0, 0.125, 1.0])
        );
        assert_eq!(Compose::Decal.apply(t, I, C1, C2), t);
        assert_eq!(Compose::Decal.apply(None, I, C1, C2), Some(C1));
        assert_eq!(Compose::DecalIntrinsic.apply(None, I, C1, C2), Some(I));
        assert_eq!(Compose::Modulate.apply(None, I, C1, C2), None);
    }

    #[test]
    fn premultiplied_composition_agrees_with_apply_at_alpha_0_and_1() {
        let t = [0.25, 0.5, 0.75];
        for m in Compose::ALL {
            let opaque = m.apply_premultiplied([t[0], t[1], t[2], 1.0], I, C1, C2);
            let want = m.apply(Some(t), I, C1, C2).unwrap();
            for i in 0..3 {
                assert!((opaque[i] - want[i]).abs() < 1e-15, "{m:?}");
            }
            let clear = m.apply_premultiplied([0.0; 4], I, C1, C2);
            match m.apply(None, I, C1, C2) {
                None => assert_eq!(clear[3], 0.0, "{m:?}"),
                Some(c) => assert_eq!(clear, [c[0], c[1], c[2], 1.0], "{m:?}"),
            }
        }
    }

    #[test]
    fn decal_without_alpha_is_refused() {
        assert!(Compose::Decal
            .check(false)
            .unwrap_err()
            .to_string()
            .contains("decal"));
        assert!(Compose::DecalIntrinsic.check(false).is_err());
        assert!(Compose::Decal.check(true).is_ok());
        assert!(Compose::Modulate.check(false).is_ok());
    }
}
