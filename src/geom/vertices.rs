//! [`Vertices`]: a polygon record's vertex list, a quad's or less held
//! inline.

use glam::DVec3;
use std::fmt;
use std::ops::Deref;

/// How many vertices a [`Vertices`] holds without a heap block: a quad's,
/// polyfill3's cells.
pub const INLINE: usize = 4;

/// A polygon record's vertices: a triangle's or a quad's (polyfill3's
/// cells) held in the [`super::Shape`] itself, more on the heap, at their
/// exact count.
///
/// A million triangles kept a million 72-byte blocks (80 with `malloc`'s
/// header) besides their shapes (bench/memory.sh), and reading a polyfill3
/// stream made and freed a block a cell; reading either is 5-8% faster
/// without (the read phase, paired runs).
///
/// Its own type rather than a `SmallVec<[DVec3; 4]>`: the length and the
/// inline-or-not tag fit in one byte here, whose spare values also tell
/// [`super::Shape`]'s variants apart, so a polygon's shape is 104 bytes
/// where the `SmallVec` (a whole word of length beside the vertices) made
/// it 112, and a scene's part 136 (`scene::part_tests`).
#[derive(Clone)]
pub struct Vertices(Repr);

#[derive(Clone)]
enum Repr {
    /// `len` of the vertices in `v` (`len <= INLINE`); the rest are zero.
    Inline {
        len: u8,
        v: [DVec3; INLINE],
    },
    Heap(Box<[DVec3]>),
}

impl Vertices {
    /// Whether the vertices are held inline (no heap block).
    pub fn is_inline(&self) -> bool {
        matches!(self.0, Repr::Inline { .. })
    }
}

impl Deref for Vertices {
    type Target = [DVec3];

    #[inline]
    fn deref(&self) -> &[DVec3] {
        match &self.0 {
            Repr::Inline { len, v } => &v[..*len as usize],
            Repr::Heap(b) => b,
        }
    }
}

impl From<&[DVec3]> for Vertices {
    fn from(s: &[DVec3]) -> Vertices {
        if s.len() <= INLINE {
            let mut v = [DVec3::ZERO; INLINE];
            v[..s.len()].copy_from_slice(s);
            Vertices(Repr::Inline {
                len: s.len() as u8,
                v,
            })
        } else {
            Vertices(Repr::Heap(s.into()))
        }
    }
}

impl<const N: usize> From<[DVec3; N]> for Vertices {
    fn from(a: [DVec3; N]) -> Vertices {
        Vertices::from(&a[..])
    }
}

impl From<Vec<DVec3>> for Vertices {
    fn from(v: Vec<DVec3>) -> Vertices {
        if v.len() <= INLINE {
            Vertices::from(&v[..])
        } else {
            Vertices(Repr::Heap(v.into_boxed_slice()))
        }
    }
}

impl PartialEq for Vertices {
    fn eq(&self, other: &Vertices) -> bool {
        **self == **other
    }
}

impl fmt::Debug for Vertices {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_list().entries(self.iter()).finish()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_quad_is_inline_and_a_pentagon_on_the_heap_with_the_same_vertices() {
        for n in 0..=7 {
            let pts: Vec<DVec3> = (0..n).map(|i| DVec3::new(i as f64, 1.0, 2.0)).collect();
            for v in [Vertices::from(&pts[..]), Vertices::from(pts.clone())] {
                assert_eq!(v.is_inline(), n <= INLINE, "{n}");
                assert_eq!(&v[..], &pts[..]);
                assert_eq!(format!("{v:?}"), format!("{pts:?}"));
            }
        }
    }

    /// Equality is the vertices', whatever the storage: a list of three
    /// made from a longer list's prefix equals one made inline.
    #[test]
    fn equal_lists_compare_equal() {
        let a = Vertices::from([DVec3::X, DVec3::Y, DVec3::Z]);
        let b = Vertices::from(vec![DVec3::X, DVec3::Y, DVec3::Z]);
        assert_eq!(a, b);
        assert_ne!(a, Vertices::from([DVec3::X, DVec3::Y]));
    }
}
