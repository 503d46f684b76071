//! Lighting: ambient light plus Lambert diffuse reflection from directional
//! and point lights, in linear light (issue 23; seed 002's "texture
//! modulation" example lights a sphere with `GL_LIGHTING`/`GL_LIGHT0` and
//! modulates a texture by the lit colour; the thesis lists shading as future
//! work).
//!
//! The model is OpenGL's fixed-function one with `GL_COLOR_MATERIAL` on
//! ambient and diffuse, and no specular or emission term: a surface of
//! colour `C` (linear light) with unit normal `N` at point `X` is lit to
//!
//! ```text
//! C_lit = min(1, C * (A + sum over lights of I * max(0, N . L)))
//! ```
//!
//! per channel, where `A` is the ambient light, `I` a light's intensity and
//! `L` the unit vector from `X` towards the light (a directional light's is
//! the same everywhere; a point light's, `normalize(P - X)`, with no
//! attenuation, GL's default). Like GL, lighting is one-sided: the normal is
//! the front face's (counter-clockwise winding, or the record's own
//! normals), and a back face seen from behind gets only the ambient term
//! where its front is turned away from the light. The clamp is GL's.

use glam::DVec3;
use serde_json::Value;

/// The ambient light of a lit scene that gives none: OpenGL's default
/// `GL_LIGHT_MODEL_AMBIENT` (0.2, 0.2, 0.2), so that faces turned away from
/// every light are dim rather than black.
pub const DEFAULT_AMBIENT: [f64; 3] = [0.2; 3];

/// The keys of a `"light"` object.
pub const KEYS: [&str; 4] = ["direction", "position", "ambient", "intensity"];

/// How a lit scene shades a record (`"shade"`). Unlit scenes ignore it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Shade {
    /// Smooth where the record has per-vertex normals (quadrics always do,
    /// polygons with `"normals"`), else flat.
    #[default]
    Auto,
    /// One lit colour per polygon, from its plane's normal at its centroid.
    Flat,
    /// Lit colours at the vertices (their normals), interpolated.
    Smooth,
    /// Not lit: the record's own colour (a sky, a light's own shape).
    None,
}

impl Shade {
    /// Parses a record's `"shade"`.
    pub fn from_json(v: &Value) -> Result<Shade, String> {
        match v.as_str() {
            Some("auto") => Ok(Shade::Auto),
            Some("flat") => Ok(Shade::Flat),
            Some("smooth") => Ok(Shade::Smooth),
            Some("none") => Ok(Shade::None),
            _ => Err(format!(
                "shade: expected \"flat\", \"smooth\", \"none\" or \"auto\", found {v}"
            )),
        }
    }
}

/// One light source.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Source {
    /// A light at infinity (GL's `w = 0` position): `towards` is the unit
    /// vector from any surface point to the light, the reverse of the
    /// direction the light travels.
    Directional {
        /// Unit vector towards the light.
        towards: DVec3,
        /// Linear-light intensity per channel.
        intensity: [f64; 3],
    },
    /// A point light (GL's `w = 1` position), without attenuation.
    Point {
        /// Where it is, world coordinates.
        position: DVec3,
        /// Linear-light intensity per channel.
        intensity: [f64; 3],
    },
}

/// What one `{"light": {...}}` stream element adds to the scene.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum LightRecord {
    /// `{"ambient": a}`: ambient light, added to the scene's.
    Ambient([f64; 3]),
    /// `{"direction": [x, y, z]}` or `{"position": [x, y, z]}`, with an
    /// optional `"intensity"`.
    Source(Source),
}

impl LightRecord {
    /// Parses the value of a `"light"` key. Errors name the key as
    /// `light.KEY`.
    pub fn from_json(v: &Value) -> Result<LightRecord, String> {
        let obj = v
            .as_object()
            .ok_or_else(|| format!("light: expected an object, found {v}"))?;
        if let Some(k) = obj.keys().find(|k| !KEYS.contains(&k.as_str())) {
            return Err(format!(
                "light.{k}: unknown key: expected one of {}",
                KEYS.join(", ")
            ));
        }
        let kinds: Vec<&str> = ["direction", "position", "ambient"]
            .into_iter()
            .filter(|k| obj.contains_key(*k))
            .collect();
        let intensity = match obj.get("intensity") {
            None => [1.0; 3],
            Some(i) => channels(i, "light.intensity")?,
        };
        match kinds.as_slice() {
            ["ambient"] => {
                if obj.contains_key("intensity") {
                    return Err("light.intensity: an ambient light is given by \"ambient\" alone".into());
                }
                Ok(LightRecord::Ambient(channels(&obj["ambient"], "light.ambient")?))
            }
            ["direction"] => {
                let d = vector(&obj["direction"], "light.direction")?;
                // Normalized without squaring huge or tiny components
                // (`[1e300, 1e300, 1e300]` had "no direction"); an ordinary
                // direction gives the bits of `-d / d.length()`.
                let Some(unit) = crate::vector::direction(d) else {
                    return Err(format!(
                        "light.direction [{}, {}, {}]: has no direction",
                        d.x, d.y, d.z
                    ));
                };
                Ok(LightRecord::Source(Source::Directional {
                    towards: -unit,
                    intensity,
                }))
            }
            ["position"] => Ok(LightRecord::Source(Source::Point {
                position: vector(&obj["position"], "light.position")?,
                intensity,
            })),
            [] => Err("light: expected one of \"direction\" (a distant light), \"position\" (a point light) or \"ambient\"".into()),
            many => Err(format!("light: several kinds ({}): expected exactly one", many.join(", "))),
        }
    }
}

/// A number or `[r, g, b]`, each finite and at least 0: linear light.
fn channels(v: &Value, what: &str) -> Result<[f64; 3], String> {
    let bad = || format!("{what}: expected a number or [r, g, b] of numbers >= 0, found {v}");
    let c = match v {
        Value::Number(n) => [n.as_f64().ok_or_else(bad)?; 3],
        Value::Array(a) if a.len() == 3 => {
            let mut c = [0.0; 3];
            for (o, x) in c.iter_mut().zip(a) {
                *o = x.as_f64().ok_or_else(bad)?;
            }
            c
        }
        _ => return Err(bad()),
    };
    if c.iter().all(|x| x.is_finite() && *x >= 0.0) {
        Ok(c)
    } else {
        Err(bad())
    }
}

/// `[x, y, z]` of finite numbers.
fn vector(v: &Value, what: &str) -> Result<DVec3, String> {
    let bad = || format!("{what}: expected [x, y, z] of finite numbers, found {v}");
    let a = v.as_array().filter(|a| a.len() == 3).ok_or_else(bad)?;
    let mut c = [0.0; 3];
    for (o, x) in c.iter_mut().zip(a) {
        *o = x.as_f64().filter(|x| x.is_finite()).ok_or_else(bad)?;
    }
    Ok(DVec3::from_array(c))
}

/// The lights of a scene. Empty (no `"light"` element in the stream) means
/// an unlit scene: every record shows its own colour, as before lighting
/// existed.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Lights {
    /// Ambient light given by the stream, if any ([`DEFAULT_AMBIENT`] otherwise).
    ambient: Option<[f64; 3]>,
    /// The sources, in stream order.
    sources: Vec<Source>,
}

impl Lights {
    /// Adds one light element.
    pub fn add(&mut self, r: LightRecord) {
        match r {
            LightRecord::Ambient(a) => {
                let sum = self.ambient.get_or_insert([0.0; 3]);
                for ch in 0..3 {
                    sum[ch] += a[ch];
                }
            }
            LightRecord::Source(s) => self.sources.push(s),
        }
    }

    /// Whether the stream has no light at all (an unlit scene).
    pub fn is_empty(&self) -> bool {
        self.ambient.is_none() && self.sources.is_empty()
    }

    /// The ambient light in effect.
    pub fn ambient(&self) -> [f64; 3] {
        self.ambient.unwrap_or(DEFAULT_AMBIENT)
    }

    /// The light arriving per channel at `point` on a surface whose front
    /// faces along the unit `normal`: `A + sum I max(0, N . L)` (module doc).
    pub fn irradiance(&self, point: DVec3, normal: DVec3) -> [f64; 3] {
        let mut e = self.ambient();
        for s in &self.sources {
            let (towards, intensity) = match *s {
                Source::Directional { towards, intensity } => (towards, intensity),
                Source::Point {
                    position,
                    intensity,
                } => ((position - point).normalize_or_zero(), intensity),
            };
            let cos = normal.dot(towards).max(0.0);
            for ch in 0..3 {
                e[ch] += intensity[ch] * cos;
            }
        }
        e
    }

    /// The lit colour of a surface of linear colour `colour` at `point`
    /// with unit front `normal`: `min(1, C * irradiance)` per channel.
    pub fn lit(&self, colour: [f64; 3], point: DVec3, normal: DVec3) -> [f64; 3] {
        let e = self.irradiance(point, normal);
        [0, 1, 2].map(|ch| (colour[ch] * e[ch]).min(1.0))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    #[test]
    fn very_long_and_short_light_directions_have_a_direction() {
        // [1e300, 1e300, 1e300]'s squared length overflowed: "has no direction".
        let s = 1.0 / 3f64.sqrt();
        for (d, towards) in [
            ([1e300, 1e300, 1e300], DVec3::splat(-s)),
            ([0.0, -1e200, 0.0], DVec3::Y),
            ([0.0, 0.0, 1e-200], DVec3::NEG_Z),
            ([-1e-200, -1e-200, -1e-200], DVec3::splat(s)),
        ] {
            let LightRecord::Source(Source::Directional { towards: t, .. }) =
                LightRecord::from_json(&json!({ "direction": d })).unwrap()
            else {
                panic!("{d:?}: not directional");
            };
            assert!((t - towards).length() < 1e-15, "{d:?}: {t}");
        }
        // An ordinary direction: -d / |d|, bit for bit.
        let d = DVec3::new(0.3, -2.0, 5.0);
        assert_eq!(
            LightRecord::from_json(&json!({"direction": d.to_array()})).unwrap(),
            LightRecord::Source(Source::Directional {
                towards: -d / d.length(),
                intensity: [1.0; 3]
            })
        );
    }

    #[test]
    fn light_records_parse_and_refuse_with_the_key_named() {
        assert_eq!(
            LightRecord::from_json(&json!({"direction": [0, 0, -2]})).unwrap(),
            LightRecord::Source(Source::Directional {
                towards: DVec3::Z,
                intensity: [1.0; 3]
            })
        );
        assert_eq!(
            LightRecord::from_json(&json!({"ambient": [0.1, 0.2, 0.3]})).unwrap(),
            LightRecord::Ambient([0.1, 0.2, 0.3])
        );
        for (v, needle) in [
            (
                json!({"direction": [0, 0, 0]}),
                "light.direction [0, 0, 0]: has no direction",
            ),
            (
                json!({"position": [0, 1]}),
                "light.position: expected [x, y, z]",
            ),
            (
                json!({"ambient": -1}),
                "light.ambient: expected a number or [r, g, b] of numbers >= 0",
            ),
            (
                json!({"direction": [0, 0, 1], "position": [0, 0, 1]}),
                "light: several kinds (direction, position)",
            ),
            (json!({"colour": 1}), "light.colour: unknown key"),
            (json!({}), "light: expected one of"),
            (
                json!({"ambient": 1, "intensity": 2}),
                "light.intensity: an ambient light",
            ),
            (json!(3), "light: expected an object"),
        ] {
            let e = LightRecord::from_json(&v).unwrap_err();
            assert!(e.contains(needle), "{v}: {e}");
        }
    }

    #[test]
    fn lambert_with_ambient_clamped_per_channel() {
        let mut l = Lights::default();
        assert!(l.is_empty());
        l.add(LightRecord::Source(Source::Directional {
            towards: DVec3::Z,
            intensity: [1.0, 0.5, 0.0],
        }));
        // GL's default ambient when the stream gives none.
        assert_eq!(l.irradiance(DVec3::ZERO, DVec3::Z), [1.2, 0.7, 0.2]);
        // 60 degrees off the light: cos = 1/2.
        let n = DVec3::new(0.0, (3f64).sqrt() / 2.0, 0.5);
        let e = l.irradiance(DVec3::ZERO, n);
        assert!((e[0] - 0.7).abs() < 1e-15 && (e[1] - 0.45).abs() < 1e-15);
        // Turned away: ambient only.
        assert_eq!(l.irradiance(DVec3::ZERO, -DVec3::Z), [0.2; 3]);
        assert_eq!(
            l.lit([1.0, 0.5, 0.5], DVec3::ZERO, DVec3::Z),
            [1.0, 0.35, 0.1]
        );
        l.add(LightRecord::Ambient([0.0; 3]));
        assert_eq!(l.irradiance(DVec3::ZERO, -DVec3::Z), [0.0; 3]);
        // A point light: the direction depends on the surface point.
        let mut p = Lights::default();
        p.add(LightRecord::Ambient([0.0; 3]));
        p.add(LightRecord::Source(Source::Point {
            position: DVec3::new(0.0, 0.0, 10.0),
            intensity: [1.0; 3],
        }));
        assert_eq!(p.irradiance(DVec3::ZERO, DVec3::Z), [1.0; 3]);
        let e = p.irradiance(DVec3::new(10.0, 0.0, 0.0), DVec3::Z);
        assert!((e[0] - std::f64::consts::FRAC_1_SQRT_2).abs() < 1e-15);
    }
}
