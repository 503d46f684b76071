//! The pattern vector (seed 001, "Pattern Vector Data", Fig. 1 and 2): the
//! direction across the stripes `N_p`, the spacing `w` (world units per map
//! sample) and the start sample point `p` (the phase).
//!
//! The texture coordinate of a world point `X` is
//!
//! `P(X) = P0 + K_p N_p · X`, with `K_p = 1 / (N w)` and `P0 = p / N`,
//!
//! where `N` is the map length. The seed writes `K_p = 1/1024w` and
//! `P0 = p/1024` for its 1024-entry maps; with `N` in place of 1024 one map
//! sample still spans `w` world units whatever the map's length ("A scaling
//! factor of one foot will produce a Texture Pattern that will extend 1024 feet
//! before repeating"). `P` counts map periods: sample `floor(P N) mod N`.
//!
//! # Orientation and world axes
//!
//! The seed's data base is East/North/vertical; this toolchain's world is
//! right-handed with y up (docs/camera.md). They are matched as **East = +x, Up = +y,
//! North = −z** (so South is +z, the right-handed completion).
//!
//! * Yaw and pitch (the examine/modify commands `PVA pn,st,sp,ya,pi`; routines
//!   ORNVRN/ORNVDN): yaw is "measured from East which is defined as the X axis",
//!   counter-clockwise seen from above (East 0°, North 90°), **0 ≤ yaw ≤ 360**;
//!   pitch is the elevation above the horizontal, **−90 ≤ pitch ≤ 90** (the
//!   seed's ranges). `N_p = (cos pitch cos yaw, sin pitch, −cos pitch sin yaw)`.
//!   The seed's ORNVRN nudges yaw off 90°/270° and pitch off 0°/±90° by 0.001°
//!   because it goes through `tan`; sines and cosines need no such nudge.
//! * A reference plane and θ (Fig. 2, "Fixed Environment"), from the seed's
//!   words rather than its OCR'd table: `zx` the horizontal plane (θ = 0 North,
//!   positive East): `N_p = (sin θ, 0, −cos θ)`; `yz` the vertical north–south
//!   plane (θ = 0 Up, positive North): `N_p = (0, cos θ, −sin θ)`; `xy` the
//!   vertical east–west plane (θ = 0 East, positive Down):
//!   `N_p = (cos θ, −sin θ, 0)`. **−360 ≤ θ ≤ 360.** The seed's "moving model"
//!   column needs models with their own axes, which the polygon stream does not
//!   have.

use crate::math;
use glam::DVec3;
use std::fmt;

/// The seed's three reference planes, named by the world axes they contain.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RefPlane {
    /// Horizontal (farmland, rivers, runway stripes).
    Zx,
    /// Vertical north–south.
    Yz,
    /// Vertical east–west.
    Xy,
}

impl RefPlane {
    /// The plane a record's `"plane"` names: `zx`, `yz` or `xy`, either
    /// letter order; `None` for anything else.
    pub fn parse(s: &str) -> Option<RefPlane> {
        match s {
            "zx" | "xz" => Some(RefPlane::Zx),
            "yz" | "zy" => Some(RefPlane::Yz),
            "xy" | "yx" => Some(RefPlane::Xy),
            _ => None,
        }
    }

    /// The plane's canonical name, as [`RefPlane::parse`] reads it.
    pub fn name(self) -> &'static str {
        match self {
            RefPlane::Zx => "zx",
            RefPlane::Yz => "yz",
            RefPlane::Xy => "xy",
        }
    }

    /// The seed's name for the plane.
    pub fn seed_name(self) -> &'static str {
        match self {
            RefPlane::Zx => "horizontal",
            RefPlane::Yz => "vertical north-south",
            RefPlane::Xy => "vertical east-west",
        }
    }
}

/// How the stripes are oriented.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Orientation {
    /// Degrees; see the module docs for ranges and axes.
    YawPitch {
        /// Counter-clockwise from East (+x) seen from above, 0..=360.
        yaw: f64,
        /// Elevation above the horizontal, −90..=90.
        pitch: f64,
    },
    /// A reference plane and the angle θ in it, degrees.
    Plane {
        /// The plane `N_p` lies in.
        plane: RefPlane,
        /// Angle of `N_p` from the plane's zero direction, −360..=360
        /// (zero and sense per plane in the module docs).
        theta: f64,
    },
}

/// The seed's yaw range, degrees.
pub const YAW_RANGE: (f64, f64) = (0.0, 360.0);
/// The seed's pitch range, degrees.
pub const PITCH_RANGE: (f64, f64) = (-90.0, 90.0);
/// The accepted θ range, degrees (one turn either way).
pub const THETA_RANGE: (f64, f64) = (-360.0, 360.0);

/// A bad pattern-vector value, naming the field as the record spells it.
#[derive(Clone, Debug, PartialEq)]
pub struct VectorError(pub String);

impl fmt::Display for VectorError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.0)
    }
}
impl std::error::Error for VectorError {}

fn in_range(name: &str, v: f64, (lo, hi): (f64, f64)) -> Result<(), VectorError> {
    if !v.is_finite() {
        return Err(VectorError(format!("{name}: {v} is not a finite number")));
    }
    if !(lo..=hi).contains(&v) {
        return Err(VectorError(format!(
            "{name}: {v} is out of range: expected {lo} to {hi} degrees"
        )));
    }
    Ok(())
}

impl Orientation {
    /// Checks the angles against their ranges.
    pub fn check(self) -> Result<Self, VectorError> {
        match self {
            Orientation::YawPitch { yaw, pitch } => {
                in_range("yaw", yaw, YAW_RANGE)?;
                in_range("pitch", pitch, PITCH_RANGE)?;
            }
            Orientation::Plane { theta, .. } => in_range("theta", theta, THETA_RANGE)?,
        }
        Ok(self)
    }

    /// The unit pattern vector `N_p` in world coordinates.
    pub fn normal(self) -> DVec3 {
        match self {
            Orientation::YawPitch { yaw, pitch } => {
                let (sy, cy) = math::sin_cos_degrees(yaw);
                let (sp, cp) = math::sin_cos_degrees(pitch);
                DVec3::new(cp * cy, sp, -cp * sy)
            }
            Orientation::Plane { plane, theta } => {
                let (s, c) = math::sin_cos_degrees(theta);
                match plane {
                    RefPlane::Zx => DVec3::new(s, 0.0, -c),
                    RefPlane::Yz => DVec3::new(0.0, c, -s),
                    RefPlane::Xy => DVec3::new(c, -s, 0.0),
                }
            }
        }
    }

    /// Yaw and pitch of the pattern vector (the seed's ORNVDN): yaw in
    /// `[0, 360)`, pitch in `[−90, 90]`. Straight up or down has yaw 0.
    pub fn yaw_pitch(self) -> (f64, f64) {
        if let Orientation::YawPitch { yaw, pitch } = self {
            return (yaw, pitch);
        }
        let n = self.normal();
        let horizontal = math::hypot(n.x, n.z);
        let pitch = math::atan2(n.y, horizontal).to_degrees();
        let yaw = if horizontal < f64::EPSILON {
            0.0
        } else {
            math::atan2(-n.z, n.x).to_degrees().rem_euclid(360.0)
        };
        (yaw, pitch)
    }
}

/// A pattern vector: orientation, spacing `w` and start sample point `p`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PatternVector {
    /// The direction `N_p` across the stripes.
    pub orientation: Orientation,
    /// World units per map sample, > 0.
    pub spacing: f64,
    /// The start sample point `p`, in map samples (any finite value; the map repeats).
    pub phase: f64,
}

impl PatternVector {
    /// Checks every value: angles in range, `spacing > 0`, finite phase.
    pub fn new(orientation: Orientation, spacing: f64, phase: f64) -> Result<Self, VectorError> {
        let orientation = orientation.check()?;
        if !spacing.is_finite() || spacing <= 0.0 {
            return Err(VectorError(format!(
                "spacing: {spacing} is not positive: the spacing w is the world distance between map samples"
            )));
        }
        // `K_p = 1 / (N w)` is finite for every map size N >= 1 exactly when
        // w is a normal number: a spacing of 1e-320 made it infinite and the
        // polygon was dropped as edge-on.
        if spacing < f64::MIN_POSITIVE {
            return Err(VectorError(format!(
                "spacing: {spacing:e} is too small: expected at least {:e}, the least normal number, \
                 for the stripes' gradient 1 / (N w) to be finite",
                f64::MIN_POSITIVE
            )));
        }
        if !phase.is_finite() {
            return Err(VectorError(format!(
                "phase: {phase} is not a finite number"
            )));
        }
        Ok(PatternVector {
            orientation,
            spacing,
            phase,
        })
    }

    /// `K_p N_p`: the gradient of `P` in world space, for a map of `n` entries.
    pub fn gradient(&self, n: usize) -> DVec3 {
        self.orientation.normal() * self.k_p(n)
    }

    /// `K_p = 1 / (N w)`.
    pub fn k_p(&self, n: usize) -> f64 {
        1.0 / (n as f64 * self.spacing)
    }

    /// `P0 = p / N`, with `p` first reduced modulo `N` when it is a whole
    /// map or more (exactly: the remainder of floats is exact), since the map
    /// repeats. Unreduced, a phase of 1e17 left `P0` no fractional part to
    /// place the stripes by (each multiple of 4 drew another picture of a
    /// 4-entry map) and 1e308 drew nothing (a hostile-input review); a phase
    /// within one map is used as given, as before.
    pub fn p0(&self, n: usize) -> f64 {
        let n = n as f64;
        let p = if self.phase.abs() >= n {
            self.phase.rem_euclid(n)
        } else {
            self.phase
        };
        p / n
    }

    /// `P(X) = P0 + K_p N_p · X`, in map periods: the seed's formula, which
    /// the screen mapping evaluates incrementally and the tests check it by.
    #[cfg(test)]
    pub(crate) fn p_at(&self, x: DVec3, n: usize) -> f64 {
        self.p0(n) + self.gradient(n).dot(x)
    }

    /// The distance in world units before the pattern repeats: `N w`.
    pub fn period(&self, n: usize) -> f64 {
        n as f64 * self.spacing
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_phase_of_whole_maps_places_the_stripes_as_none() {
        let yp = |yaw, pitch| Orientation::YawPitch { yaw, pitch };
        let at = |phase: f64| {
            PatternVector::new(yp(0.0, 0.0), 1.0, phase)
                .unwrap()
                .p_at(DVec3::new(0.3, 0.0, -7.25), 4)
        };
        for phase in [4.0, -8.0, 4e15, 4e17, 8e20, 4e307] {
            assert_eq!(at(phase), at(0.0), "phase {phase}");
        }
        assert_eq!(at(1e308), at(1e308 % 4.0));
        assert_eq!(at(6.0), at(2.0));
        assert_eq!(at(-5.0), at(3.0));
        // Within one map, the phase as given.
        assert_eq!(
            PatternVector::new(yp(0.0, 0.0), 1.0, 3.5).unwrap().p0(4),
            3.5 / 4.0
        );
    }

    /// Unit vectors built from sines and cosines of degrees agree to this.
    const TRIG: f64 = 1e-15;

    fn close(a: DVec3, b: DVec3) -> bool {
        (a - b).abs().max_element() < TRIG
    }

    #[test]
    fn compass_directions_follow_the_seeds_words() {
        let yp = |yaw, pitch| Orientation::YawPitch { yaw, pitch }.normal();
        assert!(close(yp(0.0, 0.0), DVec3::X), "East is +x");
        assert!(close(yp(90.0, 0.0), DVec3::NEG_Z), "North is -z");
        assert!(close(yp(123.0, 90.0), DVec3::Y), "pitch 90 is up");
        let pl = |plane, theta| Orientation::Plane { plane, theta }.normal();
        assert!(
            close(pl(RefPlane::Zx, 0.0), DVec3::NEG_Z),
            "horizontal: 0 = North"
        );
        assert!(close(pl(RefPlane::Zx, 90.0), DVec3::X), "positive East");
        assert!(close(pl(RefPlane::Yz, 0.0), DVec3::Y), "N-S: 0 = Up");
        assert!(
            close(pl(RefPlane::Yz, 90.0), DVec3::NEG_Z),
            "positive North"
        );
        assert!(close(pl(RefPlane::Xy, 0.0), DVec3::X), "E-W: 0 = East");
        assert!(close(pl(RefPlane::Xy, 90.0), DVec3::NEG_Y), "positive Down");
    }

    #[test]
    fn yaw_pitch_round_trips_through_the_normal() {
        for &(yaw, pitch) in &[(0.0, 0.0), (45.0, 30.0), (200.0, -60.0), (359.0, 89.0)] {
            let n = Orientation::YawPitch { yaw, pitch }.normal();
            let back_yaw = math::atan2(-n.z, n.x).to_degrees().rem_euclid(360.0);
            assert!(
                (back_yaw - yaw).abs() < 1e-9
                    && (math::asin(n.y).to_degrees() - pitch).abs() < 1e-9
            );
        }
        let (yaw, pitch) = Orientation::Plane {
            plane: RefPlane::Zx,
            theta: 90.0,
        }
        .yaw_pitch();
        assert!(yaw.abs() < 1e-9 && pitch.abs() < 1e-9, "{yaw} {pitch}");
        let (yaw, pitch) = Orientation::Plane {
            plane: RefPlane::Xy,
            theta: 90.0,
        }
        .yaw_pitch();
        assert_eq!((yaw, pitch), (0.0, -90.0));
    }

    #[test]
    fn p_advances_one_sample_per_spacing() {
        let v = PatternVector::new(
            Orientation::YawPitch {
                yaw: 0.0,
                pitch: 0.0,
            },
            2.0,
            3.0,
        )
        .unwrap();
        let n = 1024;
        assert_eq!(v.k_p(n), 1.0 / 2048.0);
        assert_eq!(v.p_at(DVec3::ZERO, n) * n as f64, 3.0);
        assert_eq!(v.p_at(DVec3::new(2.0, 5.0, 7.0), n) * n as f64, 4.0);
        assert_eq!(v.period(n), 2048.0);
    }

    #[test]
    fn bad_values_are_named() {
        let yp = |yaw, pitch| Orientation::YawPitch { yaw, pitch };
        let e = |r: Result<PatternVector, VectorError>| r.unwrap_err().to_string();
        assert_eq!(
            e(PatternVector::new(yp(0.0, 0.0), 0.0, 0.0)),
            "spacing: 0 is not positive: the spacing w is the world distance between map samples"
        );
        assert!(e(PatternVector::new(yp(0.0, 0.0), -1.0, 0.0)).contains("spacing: -1"));
        assert_eq!(
            e(PatternVector::new(yp(361.0, 0.0), 1.0, 0.0)),
            "yaw: 361 is out of range: expected 0 to 360 degrees"
        );
        assert!(e(PatternVector::new(yp(-1.0, 0.0), 1.0, 0.0)).contains("yaw: -1 is out of range"));
        assert_eq!(
            e(PatternVector::new(yp(0.0, 90.5), 1.0, 0.0)),
            "pitch: 90.5 is out of range: expected -90 to 90 degrees"
        );
        let pl = Orientation::Plane {
            plane: RefPlane::Yz,
            theta: 400.0,
        };
        assert!(e(PatternVector::new(pl, 1.0, 0.0)).contains("theta: 400 is out of range"));
        assert!(e(PatternVector::new(yp(0.0, 0.0), 1.0, f64::NAN)).contains("phase"));
    }
}
