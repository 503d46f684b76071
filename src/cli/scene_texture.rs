//! `scene-render`'s texture flags: how "object" and "uv" patterns are
//! placed and sampled (`crate::texture::place` does the placing).

use crate::color::Rgb8;
use crate::texture::boundary::{Boundary, Bounds};
use crate::texture::compose::Compose;
pub use crate::texture::filter::MAX_LOD_BIAS;
use crate::texture::filter::{Filter, Filters};
use crate::texture::mip::MipBuild;
use crate::texture::place::TextureSettings;
use crate::texture::skip::Skips;

/// How "object" and "uv" patterns are applied. Every flag but
/// --no-perspective-correction, --mip-build and --no-skip is a default: a
/// record's "pattern" key of the same name (`_` for `-`) overrides it for
/// that record (`crate::texture::state`).
#[derive(clap::Args, Debug, Clone)]
pub struct TextureArgs {
    /// What a pattern shows outside its bounds (texel columns and rows outside
    /// 0..SIZE), XGL's boundary conditions: repeat (XGL wrap; the tiling of patkit-stream(5)),
    /// transparent (the polygon's own colour, as if untextured), clamp (the
    /// --boundary-color), mirror, edge (the closest boundary texel). A record's "pattern"
    /// key "boundary" overrides it.
    #[arg(long, value_enum, value_name = "MODE", default_value_t = Boundary::Repeat)]
    pub boundary: Boundary,

    /// The boundary condition along u only (overrides --boundary). When u and
    /// v differ and both exceed the bounds, XGL's precedence decides:
    /// transparent, clamp, repeat, mirror, edge. A record's "boundary_u"
    /// overrides it.
    #[arg(long, value_enum, value_name = "MODE")]
    pub boundary_u: Option<Boundary>,

    /// The boundary condition along v only (overrides --boundary). A record's
    /// "boundary_v" overrides it.
    #[arg(long, value_enum, value_name = "MODE")]
    pub boundary_v: Option<Boundary>,

    /// The constant colour of --boundary clamp (`r,g,b` or `#rrggbb`). A
    /// record's "boundary_color" overrides it.
    #[arg(long, value_name = "COLOR", default_value = "0,0,0")]
    pub boundary_color: Rgb8,

    /// How texels combine with the polygon's "color" (XGL's composition
    /// methods, in linear light): replace, modulate (texel x color), blend
    /// (between --compose-color1 and --compose-color2 by the texel),
    /// blend-intrinsic (between color and --compose-color1), decal and
    /// decal-intrinsic (transparent texels show --compose-color1 or color;
    /// XGL allows decal only for maps with alpha: patterns with transparent
    /// texels). A record's "pattern" key "compose" overrides it.
    #[arg(long, value_enum, value_name = "METHOD", default_value_t = Compose::Replace)]
    pub compose: Compose,

    /// First constant colour of --compose blend, blend-intrinsic and decal.
    /// A record's "compose_color1" overrides it.
    #[arg(long, value_name = "COLOR", default_value = "0,0,0")]
    pub compose_color1: Rgb8,

    /// Second constant colour of --compose blend. A record's
    /// "compose_color2" overrides it.
    #[arg(long, value_name = "COLOR", default_value = "255,255,255")]
    pub compose_color2: Rgb8,

    /// Interpolate texture coordinates linearly on the screen instead of
    /// perspective-correctly (XGL's PERSP_NONE): faster hardware once, wrong
    /// under perspective; for reproducing such images.
    #[arg(long)]
    pub no_perspective_correction: bool,

    /// How a textured pixel is computed from the pattern: box (the exact
    /// area integral of the texels under the pixel, crisp, for fragments
    /// meeting up to 65,536 texels, 16,384 with transparent texels; beyond,
    /// the EWA estimate, reported: docs/rendering.md, Where exactness holds),
    /// point, bilinear
    /// (the base level), mip-point, mip-bilinear (the nearest MIP level),
    /// mip-point-linear, trilinear (the two nearest levels, mixed: XGL's six
    /// methods), ewa (elliptical weighted average, anisotropic). Sets both
    /// --min-filter and --mag-filter; a MIP filter or ewa magnifies with its
    /// base-level counterpart (point or bilinear). A record's "pattern" key
    /// "filter" overrides it (and these flags) for that record.
    #[arg(long, value_enum, value_name = "FILTER", default_value_t = Filter::Box)]
    pub filter: Filter,

    /// The filter where the pattern is minified (a pixel spans more than one
    /// texel after --lod-bias; XGL's filter1): overrides --filter. A
    /// record's "min_filter" overrides it.
    #[arg(long, value_enum, value_name = "FILTER")]
    pub min_filter: Option<Filter>,

    /// The filter where the pattern is magnified (XGL's filter2): box, point
    /// or bilinear (the MIP filters have nothing to do there, as in OpenGL).
    /// A record's "mag_filter" overrides it.
    #[arg(long, value_enum, value_name = "FILTER")]
    pub mag_filter: Option<Filter>,

    /// Added to the MIP level of detail (log2 of texels per pixel), XGL's
    /// depth_interp_factor: 1.0 is one level blurrier, -1.0 one level
    /// sharper (and more aliased). A record's "pattern" key "lod_bias"
    /// overrides it.
    #[arg(
        long,
        value_name = "F",
        default_value_t = 0.0,
        allow_negative_numbers = true
    )]
    pub lod_bias: f64,

    /// The filter that builds MIP levels (in linear light, only when some
    /// pixel minifies under a MIP filter or ewa): mitchell (XGL's choice) or
    /// box.
    #[arg(long, value_enum, value_name = "FILTER", default_value_t = MipBuild::Mitchell)]
    pub mip_build: MipBuild,

    /// For benchmarks only: turn off the listed work-saving skips, a comma
    /// list of hidden (filter every opaque textured fragment, shown or not),
    /// mip (build MIP levels for every pattern up front), transparent (visit
    /// transparent texel runs in the box filter), magnify (cut fragments
    /// inside one texel cell). The output is the same; only the time differs
    /// (bench/skips.sh).
    #[arg(long, value_name = "LIST", hide = true)]
    pub no_skip: Option<String>,
}

impl TextureArgs {
    /// The filters, checked: the mag filter must work on the base level,
    /// and the bias must be a finite number of levels.
    pub fn filters(&self) -> std::result::Result<Filters, String> {
        if !self.lod_bias.is_finite() || self.lod_bias.abs() > MAX_LOD_BIAS {
            return Err(format!(
                "--lod-bias {}: expected a number of MIP levels from -{MAX_LOD_BIAS} to {MAX_LOD_BIAS}",
                self.lod_bias
            ));
        }
        let mag = match self.mag_filter {
            Some(m) if !m.magnifies() => {
                return Err(format!(
                    "--mag-filter {}: magnification samples the base level only \
                     (as OpenGL's GL_TEXTURE_MAG_FILTER); use box, point or bilinear",
                    m.name()
                ))
            }
            Some(m) => m,
            None => self.filter.mag_counterpart(),
        };
        Ok(Filters {
            min: self.min_filter.unwrap_or(self.filter),
            mag,
            lod_bias: self.lod_bias,
            build: self.mip_build,
        })
    }

    /// The library's settings from the flags, checked (see [`Self::filters`]).
    pub fn settings(&self) -> std::result::Result<TextureSettings, String> {
        Ok(TextureSettings {
            bounds: Bounds {
                u: self.boundary_u.unwrap_or(self.boundary),
                v: self.boundary_v.unwrap_or(self.boundary),
            },
            boundary_color: self.boundary_color,
            compose: self.compose,
            compose_colors: [self.compose_color1, self.compose_color2],
            filters: self.filters()?,
            perspective_correction: !self.no_perspective_correction,
            skips: match &self.no_skip {
                Some(list) => Skips::all_but(list).map_err(|e| format!("--no-skip {list}: {e}"))?,
                None => Skips::ALL,
            },
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::texture::state::TextureState;
    use clap::ValueEnum;

    /// The flags' spellings are clap's (from the variant names), the
    /// records' the library's `name()`: they must agree, variant by variant.
    fn agree<T: ValueEnum + Copy + PartialEq + std::fmt::Debug>(
        all: &[T],
        name: fn(T) -> &'static str,
    ) {
        assert_eq!(T::value_variants().len(), all.len());
        for &v in T::value_variants() {
            let flag = v.to_possible_value().expect("no hidden values");
            assert_eq!(flag.get_name(), name(v), "{v:?}");
            assert!(all.contains(&v), "{v:?} missing from ALL");
        }
    }

    #[test]
    fn flag_and_record_spellings_agree_for_every_variant() {
        agree(&Filter::ALL, Filter::name);
        agree(&Boundary::ALL, Boundary::name);
        agree(&Compose::ALL, Compose::name);
        for f in Filter::ALL {
            let s = TextureState::from_pattern(&serde_json::json!({ "filter": f.name() }));
            assert_eq!(s.unwrap().filter, Some(f));
        }
    }
}
