//! [`Outline`]: a screen polygon's vertices and its position in the stream,
//! packed so that a triangle's take 56 bytes and no heap block.

use glam::DVec2;
use std::fmt;

/// A [`super::ScreenPoly`]'s vertices (screen pixels) and its stream order.
///
/// The two share a type for the layout's sake: a frame holds every polygon
/// of the stream at once (bench/memory.sh), and most are triangles. With the
/// vertices a `SmallVec<[DVec2; 3]>` (a word of capacity beside 48 bytes of
/// vertices) and the order a `u32` beside it, a flat triangle's screen
/// polygon was 120 bytes. Here the inline-or-not tag and the order fill one
/// word, and the vertices of anything but a triangle are one heap block at
/// their exact count (a quad's 64 bytes, as the spilled `SmallVec`'s were),
/// so the screen polygon is 112 bytes
/// (`raster::project::tests::a_flat_triangle_is_112_bytes`).
#[derive(Clone)]
pub struct Outline(Repr);

#[derive(Clone)]
enum Repr {
    /// A triangle: the common case, no heap block.
    Triangle { order: u32, v: [DVec2; 3] },
    /// Any other vertex count.
    Heap { order: u32, v: Box<[DVec2]> },
}

impl Outline {
    /// The outline of `verts` at stream position `order`.
    pub fn new(verts: &[DVec2], order: u32) -> Outline {
        Outline(match *verts {
            [a, b, c] => Repr::Triangle {
                order,
                v: [a, b, c],
            },
            _ => Repr::Heap {
                order,
                v: verts.into(),
            },
        })
    }

    /// The vertices.
    #[inline]
    pub fn verts(&self) -> &[DVec2] {
        match &self.0 {
            Repr::Triangle { v, .. } => v,
            Repr::Heap { v, .. } => v,
        }
    }

    /// The position in the stream.
    #[inline]
    pub fn order(&self) -> u32 {
        match self.0 {
            Repr::Triangle { order, .. } | Repr::Heap { order, .. } => order,
        }
    }

    /// Whether the vertices are held inline (no heap block).
    #[cfg(test)]
    pub(super) fn is_inline(&self) -> bool {
        matches!(self.0, Repr::Triangle { .. })
    }
}

impl PartialEq for Outline {
    fn eq(&self, other: &Outline) -> bool {
        self.order() == other.order() && self.verts() == other.verts()
    }
}

impl fmt::Debug for Outline {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("Outline")
            .field("verts", &self.verts())
            .field("order", &self.order())
            .finish()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_triangle_is_inline_in_one_56_byte_value_and_other_counts_on_the_heap() {
        assert_eq!(std::mem::size_of::<Outline>(), 56);
        for n in 0..=6 {
            let pts: Vec<DVec2> = (0..n).map(|i| DVec2::new(i as f64, -0.5)).collect();
            let o = Outline::new(&pts, 7 + n as u32);
            assert_eq!(o.is_inline(), n == 3, "{n}");
            assert_eq!(o.verts(), &pts[..]);
            assert_eq!(o.order(), 7 + n as u32);
            assert_eq!(o.clone(), o);
        }
    }

    /// Equal when vertices and order are; the largest order is kept whole;
    /// printed as the two fields it packs.
    #[test]
    fn equality_is_the_vertices_and_the_order() {
        let t = [DVec2::X, DVec2::Y, DVec2::ONE];
        assert_eq!(Outline::new(&t, u32::MAX).order(), u32::MAX);
        assert_ne!(Outline::new(&t, 1), Outline::new(&t, 2));
        assert_ne!(Outline::new(&t, 1), Outline::new(&t[..2], 1));
        assert_eq!(
            format!("{:?}", Outline::new(&t, 4)),
            format!("Outline {{ verts: {t:?}, order: 4 }}")
        );
    }
}
