//! A record's own texture state: the keys of its `"pattern"` object that
//! override `scene-render`'s texture flags for that record alone. XGL and
//! OpenGL bind filters, boundary conditions and composition to a texture
//! object, not to the frame (XGL's `Xgl_texture_desc`, GL's
//! `glTexParameter`); here the flags are the defaults and a record's keys
//! win (issue 19). The values are spelled as the flags' ([`Filter::name`],
//! [`Boundary::name`], [`Compose::name`]: one table per enum), the keys are
//! the flags' names with `_` for `-`.

use super::boundary::{Boundary, Bounds};
use super::compose::Compose;
use super::filter::{Filter, MAX_LOD_BIAS};
use super::place::TextureSettings;
use crate::color::Rgb8;
use serde_json::{Map, Value};

/// The keys of a `"pattern"` object this module reads (the placement keys,
/// `file`, `mode`, `incr`, ..., are [`crate::stream::PATTERN_KEYS`]).
pub const KEYS: [&str; 11] = [
    "filter",
    "min_filter",
    "mag_filter",
    "lod_bias",
    "boundary",
    "boundary_u",
    "boundary_v",
    "boundary_color",
    "compose",
    "compose_color1",
    "compose_color2",
];

/// The texture state a record's `"pattern"` sets; every field left out is
/// `None` and takes the flags' value ([`TextureState::over`]).
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct TextureState {
    /// `"filter"`: both filters, as `--filter` (a MIP filter or ewa
    /// magnifies with its base-level counterpart).
    pub filter: Option<Filter>,
    /// `"min_filter"`: the minification filter (overrides `"filter"`).
    pub min_filter: Option<Filter>,
    /// `"mag_filter"`: the magnification filter, one of box, point, bilinear
    /// (overrides `"filter"`).
    pub mag_filter: Option<Filter>,
    /// `"lod_bias"`: added to the MIP level of detail, at most
    /// [`MAX_LOD_BIAS`] either way.
    pub lod_bias: Option<f64>,
    /// `"boundary"`: the condition along both axes.
    pub boundary: Option<Boundary>,
    /// `"boundary_u"`: along u only (overrides `"boundary"`).
    pub boundary_u: Option<Boundary>,
    /// `"boundary_v"`: along v only (overrides `"boundary"`).
    pub boundary_v: Option<Boundary>,
    /// `"boundary_color"`: the constant colour of the clamp condition.
    pub boundary_color: Option<Rgb8>,
    /// `"compose"`: the composition method.
    pub compose: Option<Compose>,
    /// `"compose_color1"`, `"compose_color2"`: the composition's constants.
    pub compose_colors: [Option<Rgb8>; 2],
}

/// One of `all` by its name, or an error that repeats the value and lists
/// the valid names (`pattern.filter: `trilinar` is not a filter: expected
/// box, point, ...`), in the words of the stream's other field errors.
fn named<T: Copy>(
    obj: &Map<String, Value>,
    key: &str,
    what: &str,
    all: &[T],
    name: fn(T) -> &'static str,
) -> Result<Option<T>, String> {
    let expected = || all.iter().map(|&t| name(t)).collect::<Vec<_>>().join(", ");
    match obj.get(key) {
        None => Ok(None),
        Some(Value::String(s)) => all
            .iter()
            .copied()
            .find(|&t| name(t) == s)
            .map(Some)
            .ok_or_else(|| {
                format!(
                    "pattern.{key}: `{s}` is not {what}: expected {}",
                    expected()
                )
            }),
        Some(v) => Err(format!(
            "pattern.{key}: expected a string ({}), found {}",
            expected(),
            short(v)
        )),
    }
}

/// A colour as the record's `"color"` writes it (`[r, g, b]`) or as the
/// flags do (`"r,g,b"`, `"#rrggbb"`).
fn colour(obj: &Map<String, Value>, key: &str) -> Result<Option<Rgb8>, String> {
    let bad = |v: &Value| {
        format!(
            "pattern.{key}: expected [r,g,b] with each 0..=255, \"r,g,b\" or \"#rrggbb\", found {}",
            short(v)
        )
    };
    match obj.get(key) {
        None => Ok(None),
        Some(Value::String(s)) => s.parse::<Rgb8>().map(Some).map_err(|_| bad(&obj[key])),
        Some(v @ Value::Array(_)) => crate::stream::parse_color(v).map(Some).map_err(|_| bad(v)),
        Some(v) => Err(bad(v)),
    }
}

/// A JSON value shortened for an error message.
fn short(v: &Value) -> String {
    let s = v.to_string();
    match s.char_indices().nth(40) {
        Some((i, _)) => format!("{}...", &s[..i]),
        None => s,
    }
}

impl TextureState {
    /// The state of a `"pattern"` object (anything else has none: the stream
    /// refuses a pattern that is not an object). Every value is checked here,
    /// when the record is read; errors name the key (`pattern.filter: ...`)
    /// and the caller adds the record.
    pub fn from_pattern(pattern: &Value) -> Result<TextureState, String> {
        let Some(obj) = pattern.as_object() else {
            return Ok(TextureState::default());
        };
        let filter = |k| named(obj, k, "a filter", &Filter::ALL, Filter::name);
        let boundary = |k| {
            named(
                obj,
                k,
                "a boundary condition",
                &Boundary::ALL,
                Boundary::name,
            )
        };
        let mag_filter = filter("mag_filter")?;
        if let Some(m) = mag_filter.filter(|m| !m.magnifies()) {
            return Err(format!(
                "pattern.mag_filter: `{}`: magnification samples the base level only \
                 (as OpenGL's GL_TEXTURE_MAG_FILTER): expected box, point or bilinear",
                m.name()
            ));
        }
        let lod_bias = match obj.get("lod_bias") {
            None => None,
            Some(v) => match v.as_f64() {
                Some(b) if b.is_finite() && b.abs() <= MAX_LOD_BIAS => Some(b),
                _ => {
                    return Err(format!(
                        "pattern.lod_bias: expected a number of MIP levels from \
                         -{MAX_LOD_BIAS} to {MAX_LOD_BIAS}, found {}",
                        short(v)
                    ))
                }
            },
        };
        Ok(TextureState {
            filter: filter("filter")?,
            min_filter: filter("min_filter")?,
            mag_filter,
            lod_bias,
            boundary: boundary("boundary")?,
            boundary_u: boundary("boundary_u")?,
            boundary_v: boundary("boundary_v")?,
            boundary_color: colour(obj, "boundary_color")?,
            compose: named(
                obj,
                "compose",
                "a composition method",
                &Compose::ALL,
                Compose::name,
            )?,
            compose_colors: [
                colour(obj, "compose_color1")?,
                colour(obj, "compose_color2")?,
            ],
        })
    }

    /// Whether the record sets nothing (the flags apply unchanged).
    pub fn is_empty(&self) -> bool {
        *self == TextureState::default()
    }

    /// XGL's decal rule ([`Compose::check`]) for the record's own
    /// `"compose"`, checked when the pattern is loaded so that the error
    /// names the key, not the flag. `has_alpha`: the pattern has transparent
    /// texels.
    pub fn check(&self, has_alpha: bool) -> Result<(), String> {
        match self.compose {
            Some(c) => c
                .check(has_alpha)
                .map_err(|e| format!("pattern.{}", e.worded("compose"))),
            None => Ok(()),
        }
    }

    /// The settings for this record: `flags` (the tool's, already resolved)
    /// with the record's keys in their place. The record's keys resolve
    /// among themselves as the flags do (`"filter"` sets both filters, a
    /// `"min_filter"` overrides it; `"boundary"` both axes, `"boundary_u"`
    /// overrides it), and what the record leaves out keeps the flags' value.
    pub fn over(&self, flags: &TextureSettings) -> TextureSettings {
        if self.is_empty() {
            return *flags;
        }
        let mut s = *flags;
        s.filters.min = self.min_filter.or(self.filter).unwrap_or(s.filters.min);
        s.filters.mag = self
            .mag_filter
            .or(self.filter.map(Filter::mag_counterpart))
            .unwrap_or(s.filters.mag);
        s.filters.lod_bias = self.lod_bias.unwrap_or(s.filters.lod_bias);
        s.bounds = Bounds {
            u: self.boundary_u.or(self.boundary).unwrap_or(s.bounds.u),
            v: self.boundary_v.or(self.boundary).unwrap_or(s.bounds.v),
        };
        s.boundary_color = self.boundary_color.unwrap_or(s.boundary_color);
        s.compose = self.compose.unwrap_or(s.compose);
        for (c, own) in s.compose_colors.iter_mut().zip(self.compose_colors) {
            *c = own.unwrap_or(*c);
        }
        s
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    fn state(v: Value) -> Result<TextureState, String> {
        TextureState::from_pattern(&v)
    }

    #[test]
    fn every_name_of_every_enum_parses_back() {
        for f in Filter::ALL {
            let s = state(json!({"min_filter": f.name()})).unwrap();
            assert_eq!(s.min_filter, Some(f));
        }
        for b in Boundary::ALL {
            assert_eq!(
                state(json!({"boundary": b.name()})).unwrap().boundary,
                Some(b)
            );
        }
        for c in Compose::ALL {
            assert_eq!(
                state(json!({"compose": c.name()})).unwrap().compose,
                Some(c)
            );
        }
    }

    #[test]
    fn bad_values_repeat_the_value_and_list_the_valid_ones() {
        let e = state(json!({"filter": "trilinar"})).unwrap_err();
        assert!(e.starts_with("pattern.filter: `trilinar` is not a filter: expected box, point, bilinear, mip-point"), "{e}");
        let e = state(json!({"boundary": "wrap"})).unwrap_err();
        assert!(
            e.contains("`wrap`") && e.contains("repeat, transparent, clamp, mirror, edge"),
            "{e}"
        );
        let e = state(json!({"compose": 3})).unwrap_err();
        assert!(
            e.contains("pattern.compose: expected a string") && e.contains("found 3"),
            "{e}"
        );
        let e = state(json!({"mag_filter": "trilinear"})).unwrap_err();
        assert!(e.contains("expected box, point or bilinear"), "{e}");
        for bad in [json!(17), json!("1"), json!(-16.5)] {
            let e = state(json!({ "lod_bias": bad })).unwrap_err();
            assert!(
                e.contains("pattern.lod_bias: expected a number of MIP levels from -16 to 16"),
                "{e}"
            );
        }
        let e = state(json!({"boundary_color": [0, 0, 256]})).unwrap_err();
        assert!(
            e.contains("pattern.boundary_color: expected [r,g,b]") && e.contains("256"),
            "{e}"
        );
    }

    #[test]
    fn colours_take_the_record_and_the_flag_spellings() {
        for v in [json!([255, 0, 16]), json!("255,0,16"), json!("#ff0010")] {
            let s = state(json!({ "compose_color2": v })).unwrap();
            assert_eq!(s.compose_colors, [None, Some(Rgb8([255, 0, 16]))]);
        }
    }

    #[test]
    fn keys_resolve_as_the_flags_and_fall_back_to_them() {
        let mut flags = TextureSettings::DEFAULT;
        flags.filters.min = Filter::Point;
        flags.filters.lod_bias = 2.0;
        flags.bounds = Bounds::both(Boundary::Mirror);
        flags.compose = Compose::Modulate;
        assert_eq!(TextureState::default().over(&flags), flags);
        let s = state(json!({"filter": "trilinear", "boundary": "clamp", "boundary_v": "edge"}))
            .unwrap()
            .over(&flags);
        assert_eq!(
            (s.filters.min, s.filters.mag),
            (Filter::Trilinear, Filter::Bilinear)
        );
        assert_eq!(s.filters.lod_bias, 2.0);
        assert_eq!(
            s.bounds,
            Bounds {
                u: Boundary::Clamp,
                v: Boundary::Edge
            }
        );
        assert_eq!(s.compose, Compose::Modulate);
        let s = state(
            json!({"filter": "ewa", "mag_filter": "point", "lod_bias": -1, "compose": "replace"}),
        )
        .unwrap()
        .over(&flags);
        assert_eq!((s.filters.min, s.filters.mag), (Filter::Ewa, Filter::Point));
        assert_eq!(s.filters.lod_bias, -1.0);
        assert_eq!(s.compose, Compose::Replace);
        assert_eq!(s.bounds, flags.bounds);
    }

    #[test]
    fn a_decal_of_the_record_names_its_key() {
        let s = state(json!({"compose": "decal"})).unwrap();
        let e = s.check(false).unwrap_err();
        assert!(e.starts_with("pattern.compose decal: XGL's decal"), "{e}");
        assert!(s.check(true).is_ok());
    }
}
