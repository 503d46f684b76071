//! What a pattern shows outside its bounds (texel columns and rows outside
//! `0..SIZE`, or `0..W` and `0..H` of an image): XGL's boundary conditions (XGL Programmer's Guide, texture
//! chapter, "Boundary Conditions": the `u_boundary`, `v_boundary` fields of
//! `Xgl_texture_mipmap_desc`).

/// One direction's boundary condition.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
#[cfg_attr(feature = "cli", derive(clap::ValueEnum))]
pub enum Boundary {
    /// `XGL_TEXTURE_BOUNDARY_WRAP`: the pattern repeats (the tiling of patkit-stream(5);
    /// OpenGL's `GL_REPEAT`).
    #[default]
    Repeat,
    /// `XGL_TEXTURE_BOUNDARY_TRANSPARENT`: "finish rendering as though
    /// texturing were not being done": the polygon's own colour.
    Transparent,
    /// `XGL_TEXTURE_BOUNDARY_CLAMP`: a constant colour (`--boundary-color`).
    Clamp,
    /// `XGL_TEXTURE_BOUNDARY_MIRROR`: every other copy reversed.
    Mirror,
    /// `XGL_TEXTURE_BOUNDARY_CLAMP_BOUNDARY`: the closest boundary texel
    /// (OpenGL's clamp to edge).
    Edge,
}

impl Boundary {
    /// Every condition, in the order of `--boundary`'s help.
    pub const ALL: [Boundary; 5] = [
        Boundary::Repeat,
        Boundary::Transparent,
        Boundary::Clamp,
        Boundary::Mirror,
        Boundary::Edge,
    ];

    /// The name on the command line and in a record's `"pattern"`: the one
    /// table of spellings (a test in `cli::scene_texture` checks that clap's
    /// agree).
    pub fn name(self) -> &'static str {
        match self {
            Boundary::Repeat => "repeat",
            Boundary::Transparent => "transparent",
            Boundary::Clamp => "clamp",
            Boundary::Mirror => "mirror",
            Boundary::Edge => "edge",
        }
    }

    /// XGL's order of precedence when u and v both exceed the bounds and their
    /// conditions differ: transparent, clamp, wrap, mirror, clamp-boundary
    /// (lower is stronger).
    fn precedence(self) -> u8 {
        match self {
            Boundary::Transparent => 0,
            Boundary::Clamp => 1,
            Boundary::Repeat => 2,
            Boundary::Mirror => 3,
            Boundary::Edge => 4,
        }
    }
}

/// Where a texel cell index lands.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Lookup {
    /// This texel of the pattern.
    Texel(u32, u32),
    /// The polygon's own colour.
    Intrinsic,
    /// The constant boundary colour.
    Constant,
}

/// The boundary conditions of one pattern placement.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub struct Bounds {
    /// The condition along u (texel columns `k`, left to right).
    pub u: Boundary,
    /// The condition along v (texel rows `j`, row 0 at the bottom).
    pub v: Boundary,
}

/// Index `i` of a `size`-texel axis under one condition; `None` for the
/// conditions that leave the pattern (transparent, clamp).
fn axis(mode: Boundary, i: i64, size: i64) -> Option<u32> {
    if (0..size).contains(&i) {
        return Some(i as u32);
    }
    match mode {
        Boundary::Repeat => Some(i.rem_euclid(size) as u32),
        Boundary::Mirror => {
            let m = i.rem_euclid(2 * size);
            Some(if m < size { m } else { 2 * size - 1 - m } as u32)
        }
        Boundary::Edge => Some(i.clamp(0, size - 1) as u32),
        Boundary::Transparent | Boundary::Clamp => None,
    }
}

fn special(mode: Boundary) -> Lookup {
    if mode == Boundary::Transparent {
        Lookup::Intrinsic
    } else {
        Lookup::Constant
    }
}

impl Bounds {
    /// The same condition along both axes.
    pub fn both(b: Boundary) -> Bounds {
        Bounds { u: b, v: b }
    }

    /// The lookup of texel cell (k, j) of a `width x height` store. When
    /// both indices are out of bounds under different conditions, the
    /// stronger one by XGL's precedence applies to both.
    pub fn lookup(&self, k: i64, j: i64, width: u32, height: u32) -> Lookup {
        let (w, h) = (width as i64, height as i64);
        let (out_u, out_v) = (!(0..w).contains(&k), !(0..h).contains(&j));
        let (mu, mv) = if out_u && out_v && self.u != self.v {
            let m = if self.u.precedence() < self.v.precedence() {
                self.u
            } else {
                self.v
            };
            (m, m)
        } else {
            (self.u, self.v)
        };
        match (axis(mu, k, w), axis(mv, j, h)) {
            (Some(c), Some(r)) => Lookup::Texel(c, r),
            (None, _) => special(mu),
            (_, None) => special(mv),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_condition_maps_indices_as_xgl_describes() {
        let idx = |b, i| match Bounds::both(b).lookup(i, 0, 16, 16) {
            Lookup::Texel(c, _) => Some(c),
            _ => None,
        };
        assert_eq!(idx(Boundary::Repeat, -1), Some(15));
        assert_eq!(idx(Boundary::Repeat, 17), Some(1));
        assert_eq!(idx(Boundary::Mirror, -1), Some(0));
        assert_eq!(idx(Boundary::Mirror, 16), Some(15));
        assert_eq!(idx(Boundary::Mirror, 32), Some(0));
        assert_eq!(idx(Boundary::Edge, -5), Some(0));
        assert_eq!(idx(Boundary::Edge, 99), Some(15));
        assert_eq!(
            Bounds::both(Boundary::Transparent).lookup(16, 3, 16, 16),
            Lookup::Intrinsic
        );
        assert_eq!(
            Bounds::both(Boundary::Clamp).lookup(3, -1, 16, 16),
            Lookup::Constant
        );
    }

    #[test]
    fn precedence_decides_only_when_both_exceed() {
        let b = Bounds {
            u: Boundary::Repeat,
            v: Boundary::Clamp,
        };
        // Only u out: u's condition.
        assert_eq!(b.lookup(17, 3, 16, 16), Lookup::Texel(1, 3));
        // Only v out: v's.
        assert_eq!(b.lookup(3, 17, 16, 16), Lookup::Constant);
        // Both out: clamp outranks wrap.
        assert_eq!(b.lookup(17, -1, 16, 16), Lookup::Constant);
        let m = Bounds {
            u: Boundary::Mirror,
            v: Boundary::Repeat,
        };
        // Both out: wrap outranks mirror, for both coordinates.
        assert_eq!(m.lookup(-1, -1, 16, 16), Lookup::Texel(15, 15));
    }

    #[test]
    fn each_axis_uses_its_own_side() {
        let b = Bounds::both(Boundary::Repeat);
        assert_eq!(b.lookup(17, 5, 32, 4), Lookup::Texel(17, 1));
        let m = Bounds::both(Boundary::Mirror);
        assert_eq!(m.lookup(32, 4, 32, 4), Lookup::Texel(31, 3));
        let e = Bounds::both(Boundary::Edge);
        assert_eq!(e.lookup(-3, 9, 32, 4), Lookup::Texel(0, 3));
        let t = Bounds::both(Boundary::Transparent);
        assert_eq!(t.lookup(20, 4, 32, 4), Lookup::Intrinsic);
        assert_eq!(t.lookup(20, 3, 32, 4), Lookup::Texel(20, 3));
    }
}
