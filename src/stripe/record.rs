//! The `"stripe"` object of a polygon record (schema in `docs/stripe.md`): the
//! seed's texture record (texture code → map, pattern vector, translation map;
//! modulation colour select; face colour code) as JSON that users edit with
//! ordinary tools, the way the seed's TRA/PVA commands examined and modified it.
//!
//! `src/stream/` keeps every field of a record in [`crate::stream::Record::fields`]; this
//! module reads `fields["stripe"]` from there, so the stream's typed API is
//! unchanged and tools that forward records pass the object through.

use super::map::InvalidMap;
use super::map::ModulationMap;
use super::tables::TableError;
use super::tables::{ColourTable, Select, Translation};
use super::vector::{Orientation, PatternVector, RefPlane};
use super::{Blend, BlendSelect, LodMode, Modulation, ScreenMapping, StripeTexture};
use crate::color::Rgb8;
use crate::geom::Shape;
use crate::stream::{resolve, Fields};
use crate::text::ParseError;
use glam::{DMat4, DVec3};
use serde_json::{Map, Value};
use std::path::Path;
use std::sync::Arc;

/// The keys a `"stripe"` object may have.
pub const KEYS: [&str; 15] = [
    "map",
    "spacing",
    "phase",
    "yaw",
    "pitch",
    "plane",
    "theta",
    "translation",
    "select",
    "code",
    "colors",
    "next_code",
    "next_color",
    "blend",
    "blend_select",
];

/// Keys of a `"stripe"` object read under an old spelling, as `(old, new)`:
/// `"colours"` was the table's key until issue 18 gave every key the
/// stream's one spelling, `color`. Still read, with a warning
/// ([`crate::scene::keys`]), so that streams written before keep working.
pub const OLD_KEYS: [(&str, &str); 1] = [("colours", "colors")];

/// Why a record's stripe texture cannot be used. Errors of the `"stripe"`
/// object name its field (`stripe.spacing: ...`), errors of its files the
/// file; the caller adds the record.
#[derive(Debug, thiserror::Error)]
pub enum StripeError {
    /// A field of the `"stripe"` object is wrong: the message names it.
    #[error("{0}")]
    Field(String),
    /// A file the object names could not be read.
    #[error("{}", path.display())]
    Read {
        /// The file, resolved against the stream's directory.
        path: std::path::PathBuf,
        /// The cause.
        #[source]
        error: std::io::Error,
    },
    /// A map, translation or colour-table file is malformed.
    #[error(transparent)]
    Parse(#[from] ParseError),
    /// A brightness or contrast out of range.
    #[error(transparent)]
    Table(#[from] TableError),
    /// A map that breaks the map rules.
    #[error(transparent)]
    Map(#[from] InvalidMap),
    /// The face gives the stripes no mapping.
    #[error(transparent)]
    Mapping(#[from] NoMapping),
}

/// Reads a file the `"stripe"` object names.
fn read_file(path: &Path) -> Result<Vec<u8>, StripeError> {
    crate::io::read_path(path).map_err(|error| StripeError::Read {
        path: path.to_path_buf(),
        error,
    })
}

/// How the record names its translation map.
#[derive(Clone, Debug, PartialEq)]
pub enum TranslationSpec {
    /// `"identity"` (or no `"translation"`): map values used as they are.
    Identity,
    /// `{"brightness": b}`: every intensity shifted by `b` sRGB codes
    /// (−255..=255, checked when loaded).
    Brightness(f64),
    /// `{"contrast": c}`: intensities scaled about the middle by `c`
    /// (0..=255, 1 the identity; checked when loaded).
    Contrast(f64),
    /// A translation map file, as written in the record.
    File(String),
}

/// A record's stripe texture, checked but not yet loaded.
#[derive(Clone, Debug, PartialEq)]
pub struct StripeSpec {
    /// The modulation map file, as written in the record.
    pub map: String,
    /// Orientation, spacing and phase. The phase is in map samples.
    pub vector: PatternVector,
    /// The translation map applied to each map value before modulating.
    pub translation: TranslationSpec,
    /// Which of R, G, B are modulated. Default value: all three.
    pub select: Select,
    /// Face colour code into the colour-code table; without it the record's
    /// `"color"` is the face colour.
    pub code: Option<u8>,
    /// A colour-code table file replacing entries of the default table
    /// (`"colors"`, or the old `"colours"`).
    pub colours: Option<String>,
    /// The next face colour (the TCA's `nc`, a colour code, or `"next_color"`
    /// as `[r, g, b]`) and the blend select (`bs`), when the Blend Flag
    /// (`bf`, `"blend"`) is set. Default value: `None`, the seed's plain
    /// modulation.
    pub blend: Option<BlendSpec>,
}

/// A stripe's blend to the next face colour, as the record gives it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct BlendSpec {
    /// The next face colour: a code into the colour-code table or a colour.
    pub next: NextColour,
    /// What the modulation blends towards it.
    pub select: BlendSelect,
}

/// Where the next face colour comes from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum NextColour {
    /// `"next_code"`: an entry of the colour-code table, as the seed's `nc`.
    Code(u8),
    /// `"next_color"`: `[r, g, b]`, 8-bit sRGB.
    Colour(Rgb8),
}

fn number(obj: &Map<String, Value>, key: &str) -> Result<Option<f64>, String> {
    match obj.get(key) {
        None => Ok(None),
        Some(v) => match v.as_f64() {
            Some(x) if x.is_finite() => Ok(Some(x)),
            _ => Err(format!("stripe.{key}: expected a number, found {v}")),
        },
    }
}

fn string<'a>(
    obj: &'a Map<String, Value>,
    key: &str,
    what: &str,
) -> Result<Option<&'a str>, String> {
    match obj.get(key) {
        None => Ok(None),
        Some(Value::String(s)) => Ok(Some(s)),
        Some(v) => Err(format!("stripe.{key}: expected {what}, found {v}")),
    }
}

/// An entry of the colour-code table, 0..=255: `"code"` and `"next_code"`
/// take one alike.
fn colour_code(obj: &Map<String, Value>, key: &str) -> Result<Option<u8>, String> {
    match obj.get(key) {
        None => Ok(None),
        Some(v) => match v.as_u64().filter(|&c| c <= 255) {
            Some(c) => Ok(Some(c as u8)),
            None => Err(format!(
                "stripe.{key}: expected a colour code 0..=255, found {v}"
            )),
        },
    }
}

impl StripeSpec {
    /// The record's stripe texture, if it has a `"stripe"` field. Errors name
    /// the field as `stripe.KEY`.
    pub fn from_fields(fields: &Fields) -> Result<Option<StripeSpec>, StripeError> {
        let spec = fields.get("stripe").map(StripeSpec::from_value).transpose();
        spec.map_err(StripeError::Field)
    }

    /// Parses a `"stripe"` object.
    pub fn from_value(v: &Value) -> Result<StripeSpec, String> {
        let obj = v
            .as_object()
            .ok_or_else(|| format!("stripe: expected an object, found {v}"))?;
        let known = |k: &str| KEYS.contains(&k) || OLD_KEYS.iter().any(|(old, _)| *old == k);
        if let Some(k) = obj.keys().find(|k| !known(k)) {
            return Err(format!(
                "stripe.{k}: unknown key: expected one of {}",
                KEYS.join(", ")
            ));
        }
        let map = string(obj, "map", "the path of a modulation map")?
            .ok_or("stripe.map: missing: the path of the modulation map file")?
            .to_string();
        let spacing = number(obj, "spacing")?
            .ok_or("stripe.spacing: missing: the world distance w between map samples")?;
        let phase = number(obj, "phase")?.unwrap_or(0.0);
        let yaw = number(obj, "yaw")?;
        let pitch = number(obj, "pitch")?;
        let plane = string(obj, "plane", "\"xy\", \"yz\" or \"zx\"")?;
        let theta = number(obj, "theta")?;
        let has_yaw_pitch = yaw.is_some() || pitch.is_some();
        let has_plane = plane.is_some() || theta.is_some();
        let orientation = match (has_yaw_pitch, has_plane) {
            (true, true) => return Err("stripe: give yaw/pitch or plane/theta, not both".into()),
            (true, false) => Orientation::YawPitch {
                yaw: yaw.unwrap_or(0.0),
                pitch: pitch.unwrap_or(0.0),
            },
            (false, true) => {
                let p = plane.ok_or("stripe.theta: needs \"plane\": xy, yz or zx")?;
                Orientation::Plane {
                    plane: RefPlane::parse(p).ok_or_else(|| {
                        format!("stripe.plane: `{p}` is not a reference plane: expected xy, yz or zx")
                    })?,
                    theta: theta.unwrap_or(0.0),
                }
            }
            (false, false) => {
                return Err(
                    "stripe: missing orientation: give \"yaw\" (and \"pitch\") or \"plane\" and \"theta\""
                        .into(),
                )
            }
        };
        let vector =
            PatternVector::new(orientation, spacing, phase).map_err(|e| format!("stripe.{e}"))?;
        let translation = match obj.get("translation") {
            None => TranslationSpec::Identity,
            Some(Value::String(s)) if s == "identity" => TranslationSpec::Identity,
            Some(Value::String(s)) => TranslationSpec::File(s.clone()),
            Some(Value::Object(t)) if t.len() == 1 => {
                let (k, v) = t.iter().next().expect("one entry");
                let x = v.as_f64().filter(|x| x.is_finite()).ok_or_else(|| {
                    format!("stripe.translation.{k}: expected a number, found {v}")
                })?;
                let spec = match k.as_str() {
                    "brightness" => TranslationSpec::Brightness(x),
                    "contrast" => TranslationSpec::Contrast(x),
                    _ => {
                        return Err(format!(
                            "stripe.translation.{k}: unknown: expected brightness or contrast"
                        ))
                    }
                };
                // Check the range now, so the error belongs to the record.
                spec_table(&spec, Path::new("."))
                    .map_err(|e| format!("stripe.translation.{e:#}"))?;
                spec
            }
            Some(v) => {
                return Err(format!(
                    "stripe.translation: expected \"identity\", a file name, {{\"brightness\": b}} or {{\"contrast\": c}}, found {v}"
                ))
            }
        };
        let select = match string(obj, "select", "letters of r, g, b")? {
            None => Select::default(),
            Some(s) => Select::parse(s).map_err(|e| format!("stripe.{e}"))?,
        };
        let code = colour_code(obj, "code")?;
        let blend = blend_spec(obj)?;
        let what = "the path of a colour-code table";
        let colours = match (string(obj, "colors", what)?, string(obj, "colours", what)?) {
            (Some(_), Some(_)) => {
                return Err(
                    "stripe.colours: the old spelling of stripe.colors, given beside it: keep \"colors\""
                        .into(),
                )
            }
            (new, old) => new.or(old).map(str::to_string),
        };
        Ok(StripeSpec {
            map,
            vector,
            translation,
            select,
            code,
            colours,
            blend,
        })
    }

    /// The translation map file the spec names, resolved against `base`.
    pub fn translation_file(&self, base: &Path) -> Option<std::path::PathBuf> {
        match &self.translation {
            TranslationSpec::File(f) => Some(resolve(base, f)),
            _ => None,
        }
    }

    /// Reads the files the spec names, resolving relative paths against `base`
    /// (the stream's directory, [`crate::stream::base_dir`]).
    pub fn load(&self, base: &Path) -> Result<LoadedStripe, StripeError> {
        let map_path = resolve(base, &self.map);
        let map = ModulationMap::read_file(&map_path)?;
        let translation = spec_table(&self.translation, base)?;
        let colours = match &self.colours {
            None => ColourTable::default(),
            Some(f) => {
                let path = resolve(base, f);
                let bytes = read_file(&path)?;
                ColourTable::parse(&bytes, &path.display().to_string())?
            }
        };
        let modulation = Arc::new(Modulation::new(&map, &translation));
        Ok(LoadedStripe {
            spec: self.clone(),
            map,
            translation,
            colours,
            modulation,
        })
    }
}

/// The blend fields of a `"stripe"` object (seed 001's Face Color Data:
/// next face colour code `nc`, Blend Flag `bf` 0..1, Blend Select `bs`
/// 0..3). The seed gives the fields and their widths but not the arithmetic;
/// [`BlendSelect`] documents the reading taken here, and the two selects it
/// has no reading for are refused rather than guessed.
fn blend_spec(obj: &Map<String, Value>) -> Result<Option<BlendSpec>, String> {
    let flag = match obj.get("blend") {
        None => false,
        Some(Value::Bool(b)) => *b,
        Some(v) => match v.as_u64() {
            Some(0) => false,
            Some(1) => true,
            _ => {
                return Err(format!(
                    "stripe.blend: expected the blend flag, 0, 1, false or true, found {v}"
                ))
            }
        },
    };
    let next_code = colour_code(obj, "next_code")?;
    let next_colour = obj
        .get("next_color")
        .map(|v| crate::stream::parse_color(v).map_err(|e| format!("stripe.next_{e}")))
        .transpose()?;
    let select = match obj.get("blend_select") {
        None => BlendSelect::DarkToNext,
        Some(v) => match v.as_u64() {
            Some(0) => BlendSelect::DarkToNext,
            Some(1) => BlendSelect::BrightToNext,
            Some(n @ (2 | 3)) => {
                return Err(format!(
                    "stripe.blend_select: {n}: seed 001 gives Blend Select 0..3 but no arithmetic; \
                     0 (dark stripes take the next face colour) and 1 (bright ones do) are read \
                     here, {n} is not"
                ))
            }
            _ => return Err(format!("stripe.blend_select: expected 0 or 1, found {v}")),
        },
    };
    let next = match (next_code, next_colour) {
        (Some(_), Some(_)) => {
            return Err(
                "stripe.next_color: given beside stripe.next_code: give one next face colour"
                    .into(),
            )
        }
        (Some(c), None) => Some(NextColour::Code(c)),
        (None, Some(c)) => Some(NextColour::Colour(c)),
        (None, None) => None,
    };
    match (flag, next) {
        (true, Some(next)) => Ok(Some(BlendSpec { next, select })),
        (true, None) => Err(
            "stripe.blend: the blend flag is set but there is no next face colour: give \"next_code\" or \"next_color\""
                .into(),
        ),
        // As on the CIG, the next face colour and the select are kept in
        // the record and do nothing while the flag is clear.
        (false, _) => Ok(None),
    }
}

fn spec_table(spec: &TranslationSpec, base: &Path) -> Result<Translation, StripeError> {
    Ok(match spec {
        TranslationSpec::Identity => Translation::identity(),
        TranslationSpec::Brightness(b) => Translation::brightness(*b)?,
        TranslationSpec::Contrast(c) => Translation::contrast(*c)?,
        TranslationSpec::File(f) => {
            let path = resolve(base, f);
            let bytes = read_file(&path)?;
            Translation::parse(&bytes, &path.display().to_string())?
        }
    })
}

/// A stripe spec with its files read and its pyramid built.
#[derive(Clone, Debug)]
pub struct LoadedStripe {
    /// The record's stripe object, as checked.
    pub spec: StripeSpec,
    /// The modulation map read from `spec.map`.
    pub map: ModulationMap,
    /// The translation map `spec.translation` names, built or read.
    pub translation: Translation,
    /// The default colour-code table with `spec.colours`' entries applied.
    pub colours: ColourTable,
    /// The translated map's linear-light pyramid, shared by the faces
    /// that draw it.
    pub modulation: Arc<Modulation>,
}

impl LoadedStripe {
    /// The face colour: colour code `code` of the table, else the record's
    /// `"color"`, else `default`.
    pub fn face_colour(&self, record_colour: Option<Rgb8>, default: Rgb8) -> Rgb8 {
        match self.spec.code {
            Some(c) => self.colours.get(c),
            None => record_colour.unwrap_or(default),
        }
    }

    /// The blend to the next face colour, its code looked up in the table,
    /// when the record sets the blend flag.
    pub fn blend(&self) -> Option<Blend> {
        self.spec.blend.map(|b| Blend {
            next: match b.next {
                NextColour::Code(c) => self.colours.get(c),
                NextColour::Colour(c) => c,
            },
            select: b.select,
        })
    }

    /// The per-pixel shader of a face of `shape` seen through `world_to_clip`
    /// (the shape's coordinates are the matrix's input: world coordinates, or
    /// an object's own under an instance transform) on a `width` x `height`
    /// image, with face colour `face`.
    pub fn texture_on(
        &self,
        shape: &Shape,
        world_to_clip: DMat4,
        width: u32,
        height: u32,
        mode: LodMode,
        face: Rgb8,
    ) -> Result<StripeTexture, NoMapping> {
        let (normal, point) = face_plane(shape).ok_or(NoMapping::NoPlane)?;
        let n = self.map.len();
        let mapping = ScreenMapping::from_matrix(
            world_to_clip,
            width,
            height,
            normal,
            point,
            self.spec.vector.gradient(n),
            self.spec.vector.p0(n),
        )
        .map_err(|_| NoMapping::EdgeOn)?;
        Ok(StripeTexture::new(
            Arc::clone(&self.modulation),
            mapping,
            self.spec.select,
            face,
            mode,
        ))
    }
}

/// Why a face has no stripe mapping on the screen.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum NoMapping {
    /// The face's vertices are collinear.
    NoPlane,
    /// The face is seen edge-on ([`super::mapping::EdgeOn`]): it covers no
    /// pixels, so a renderer skips it.
    EdgeOn,
}

impl std::fmt::Display for NoMapping {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            NoMapping::NoPlane => f.write_str("the face has no plane (its vertices are collinear)"),
            NoMapping::EdgeOn => super::mapping::EdgeOn.fmt(f),
        }
    }
}
impl std::error::Error for NoMapping {}

/// Loads the stripe textures of a stream, reading each file once: records
/// that name the same map and translation share one pyramid (the seed's
/// texture code: many faces, one map), so a scene of a thousand striped fields
/// costs one map read and one pyramid.
#[derive(Debug)]
pub struct StripeLoader {
    base: std::path::PathBuf,
    /// (map file, translation spec as written, colour-table file) → files
    /// and pyramid; the files as [`crate::stream::FileIds`] finds them, so
    /// however a record spells them. The translation is keyed by its
    /// `Debug` form because its numbers are f64 (no `Hash`); equal specs
    /// print equal.
    loaded: std::collections::HashMap<
        (std::path::PathBuf, String, Option<std::path::PathBuf>),
        LoadedStripe,
    >,
    /// Every file read, each once, in the order first read.
    files: Vec<std::path::PathBuf>,
    ids: crate::stream::FileIds,
}

impl StripeLoader {
    /// A loader resolving relative paths against `base` (the stream's
    /// directory, [`crate::stream::base_dir`]).
    pub fn new(base: &Path) -> StripeLoader {
        StripeLoader {
            base: base.to_path_buf(),
            loaded: Default::default(),
            files: Vec::new(),
            ids: Default::default(),
        }
    }

    /// The files read so far (maps, translation and colour tables), each
    /// once, as resolved against the stream's directory.
    pub fn files(&self) -> &[std::path::PathBuf] {
        &self.files
    }

    /// `spec` with its files read, from the cache when another record named
    /// the same files.
    pub fn load(&mut self, spec: &StripeSpec) -> Result<LoadedStripe, StripeError> {
        let (map, colours) = (
            resolve(&self.base, &spec.map),
            spec.colours.as_ref().map(|c| resolve(&self.base, c)),
        );
        let key = (
            self.ids.file(&map).to_path_buf(),
            format!("{:?}", spec.translation),
            colours.as_ref().map(|c| self.ids.file(c).to_path_buf()),
        );
        let shared = match self.loaded.get(&key) {
            Some(l) => l,
            None => {
                let l = spec.load(&self.base)?;
                let read = [Some(map), spec.translation_file(&self.base), colours];
                for f in read.into_iter().flatten() {
                    if !self.files.contains(&f) {
                        self.files.push(f);
                    }
                }
                self.loaded.entry(key).or_insert(l)
            }
        };
        Ok(LoadedStripe {
            spec: spec.clone(),
            ..shared.clone()
        })
    }
}

/// The plane of a shape: unit normal (Newell's method, so a slightly
/// non-planar polygon gets its best-fit normal) and a point on it. The 2D
/// primitives lie in z = 0 facing +z.
pub fn face_plane(shape: &Shape) -> Option<(DVec3, DVec3)> {
    match shape {
        Shape::Polygon(v) => {
            let mut n = DVec3::ZERO;
            for i in 0..v.len() {
                let (a, b) = (v[i], v[(i + 1) % v.len()]);
                n += DVec3::new(
                    (a.y - b.y) * (a.z + b.z),
                    (a.z - b.z) * (a.x + b.x),
                    (a.x - b.x) * (a.y + b.y),
                );
            }
            let len = n.length();
            (len > 0.0 && len.is_finite()).then(|| (n / len, v[0]))
        }
        _ => Some((DVec3::Z, DVec3::ZERO)),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::Vertices;
    use serde_json::json;

    fn spec(v: Value) -> Result<StripeSpec, String> {
        StripeSpec::from_value(&v)
    }

    #[test]
    fn the_old_colours_spelling_is_read_and_not_beside_colors() {
        let old = spec(json!({"map": "m.map", "spacing": 1, "yaw": 0, "colours": "c.ct"})).unwrap();
        assert_eq!(old.colours.as_deref(), Some("c.ct"));
        let both = spec(
            json!({"map": "m.map", "spacing": 1, "yaw": 0, "colours": "c.ct", "colors": "d.ct"}),
        );
        assert!(both.unwrap_err().contains("keep \"colors\""));
    }

    #[test]
    fn a_full_record_parses() {
        let s = spec(
            json!({"map": "furrow.map", "spacing": 0.5, "phase": 12, "yaw": 30, "pitch": -10,
            "translation": {"contrast": 1.5}, "select": "g", "code": 20, "colors": "c.ct"}),
        )
        .unwrap();
        assert_eq!(s.map, "furrow.map");
        assert_eq!(s.vector.spacing, 0.5);
        assert_eq!(s.vector.phase, 12.0);
        assert_eq!(
            s.vector.orientation,
            Orientation::YawPitch {
                yaw: 30.0,
                pitch: -10.0
            }
        );
        assert_eq!(s.translation, TranslationSpec::Contrast(1.5));
        assert_eq!(s.select, Select([false, true, false]));
        assert_eq!((s.code, s.colours.as_deref()), (Some(20), Some("c.ct")));
        let p = spec(
            json!({"map": "m", "spacing": 1, "plane": "zx", "theta": 45, "translation": "t.tm"}),
        )
        .unwrap();
        assert_eq!(
            p.vector.orientation,
            Orientation::Plane {
                plane: RefPlane::Zx,
                theta: 45.0
            }
        );
        assert_eq!(p.translation, TranslationSpec::File("t.tm".into()));
        assert_eq!(p.select, Select::default());
    }

    #[test]
    fn a_subnormal_stripe_spacing_is_refused() {
        let spacing = |w: f64| spec(json!({"map": "m", "spacing": w, "yaw": 0}));
        assert_eq!(
            spacing(1e-320).unwrap_err(),
            "stripe.spacing: 1e-320 is too small: expected at least 2.2250738585072014e-308, \
             the least normal number, for the stripes' gradient 1 / (N w) to be finite"
        );
        assert!(spacing(1e-310).is_err());
        assert!(spacing(f64::MIN_POSITIVE).is_ok());
    }

    #[test]
    fn bad_values_are_named_by_field() {
        let base = json!({"map": "m", "spacing": 1, "yaw": 0});
        let with = |k: &str, v: Value| {
            let mut o = base.clone();
            o[k] = v;
            spec(o).unwrap_err()
        };
        assert_eq!(with("spacing", json!(0)), "stripe.spacing: 0 is not positive: the spacing w is the world distance between map samples");
        assert!(with("spacing", json!(-2.5)).starts_with("stripe.spacing: -2.5 is not positive"));
        assert_eq!(
            with("yaw", json!(400)),
            "stripe.yaw: 400 is out of range: expected 0 to 360 degrees"
        );
        assert_eq!(
            with("pitch", json!(-91)),
            "stripe.pitch: -91 is out of range: expected -90 to 90 degrees"
        );
        assert!(with("select", json!("rq")).contains("stripe.select: `rq`: `q` is not a colour"));
        assert!(with("code", json!(256)).contains("stripe.code: expected a colour code 0..=255"));
        assert!(with("translation", json!({"brightness": 999}))
            .contains("stripe.translation.brightness: 999 is out of range"));
        assert!(
            with("translation", json!({"gamma": 2})).contains("stripe.translation.gamma: unknown")
        );
        assert!(with("plane", json!("zx")).contains("not both"));
        assert!(with("spaceing", json!(1)).contains("stripe.spaceing: unknown key"));
        assert!(with("colours", json!(7)).contains("stripe.colours: expected the path"));
        assert!(spec(json!({"map": "m", "spacing": 1}))
            .unwrap_err()
            .contains("missing orientation"));
        assert!(spec(json!({"spacing": 1, "yaw": 0}))
            .unwrap_err()
            .contains("stripe.map: missing"));
        assert!(spec(json!({"map": "m", "yaw": 0}))
            .unwrap_err()
            .contains("stripe.spacing: missing"));
        assert!(
            spec(json!({"map": "m", "spacing": 1, "plane": "xz", "theta": 500}))
                .unwrap_err()
                .contains("stripe.theta: 500")
        );
        assert!(spec(json!({"map": "m", "spacing": 1, "plane": "up"}))
            .unwrap_err()
            .contains("`up` is not a reference plane"));
        assert!(spec(json!([1]))
            .unwrap_err()
            .contains("stripe: expected an object"));
    }

    #[test]
    fn records_without_stripe_have_none() {
        let fields = json!({"vertices": [[0,0],[1,0],[0,1]]});
        assert!(matches!(
            StripeSpec::from_fields(&fields.as_object().unwrap().clone().into()),
            Ok(None)
        ));
    }

    #[test]
    fn newell_normal_follows_counter_clockwise_order() {
        let sq = Shape::Polygon(Vertices::from([
            DVec3::new(0.0, 0.0, 0.0),
            DVec3::new(1.0, 0.0, 0.0),
            DVec3::new(1.0, 0.0, -1.0),
            DVec3::new(0.0, 0.0, -1.0),
        ]));
        // Counter-clockwise seen from above (x right, north = -z up the page): the normal points up.
        let (n, _) = face_plane(&sq).unwrap();
        assert!((n - DVec3::Y).length() < 1e-15, "{n}");
        let line = Shape::Polygon(Vertices::from([DVec3::ZERO, DVec3::X, DVec3::X * 2.0]));
        assert_eq!(face_plane(&line), None);
    }
}
