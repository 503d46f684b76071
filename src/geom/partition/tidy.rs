//! What rounding leaves in a piece's ring that readers refuse, taken out
//! before the piece is written.
//!
//! Every reader takes only simple polygons, judged exactly on the world
//! polygon's flat view ([`crate::geom::simple::check`]). A piece of a
//! simple polygon is simple in exact arithmetic, but its vertices are
//! rounded twice, and each rounding can make it touch itself:
//!
//! 1. **In the plane.** Each crossing of a grid line is rounded on its own.
//!    Where the input's boundary runs along a grid line and back (a notch
//!    whose floor lies within rounding of a row), the clipped ring has a
//!    zero-width spike: [`drop_spikes`].
//! 2. **Mapped to the world** (`Frame::to_world`). Each vertex moves by up to
//!    about an ulp of the largest world coordinate. Features of the plane
//!    ring smaller than that can then fold or cross: where an input wall lies
//!    an ulp or two off a grid line, the plane ring has a staircase of
//!    ulp-sized steps, which the world's flat view sees as a repeated vertex,
//!    a fold, or two edges crossing: [`simple_in_world`].
//! 3. **Both.** Where a reflex vertex of the input lies on a grid line, or
//!    within rounding of one, a cell's piece is two parts that touch at that
//!    point, and the ring that walks both touches itself there: it is split
//!    into the two parts ([`simple_in_world`]).
//!
//! No vertex of a piece is moved: vertices are removed, only those within
//! rounding of the path through their neighbours, or rings split at a
//! vertex, so the pieces cover the same region to within that rounding.
//!
//! And before the cut, the input itself: one within the planarity
//! tolerance of its plane, simple as given, can cross itself once
//! projected onto the plane; it is projected along the readers' axis
//! instead ([`simple_on_plane`]).
//!
//! Nearly every piece and input needs none of this and is left as it was,
//! bit for bit.

use crate::geom::plane::{flat_view, flat_view_along, signed_area, PlanePolygon};
use crate::geom::simple::{check, find_contact, folds_back, Contact};
use glam::{DVec2, DVec3};

/// How far, in units of `f64::EPSILON` times the piece's largest world
/// coordinate (one to two ulps of it), a vertex may lie from the chord of
/// its two neighbours in the world's flat view for [`simple_in_world`] to
/// remove it: 16. `Frame::to_world` rounds each coordinate in two additions
/// and two products, and the plane ring it maps has ulp-sized features of
/// its own (an input wall an ulp or two off a grid line). Measured, over
/// fuzzers of adversarial concave polygons (combs, notches, staircases and
/// stars whose walls lie on grid lines or within ulps of them; tilted,
/// turned, up to 1e7 from the origin): the vertices removed lay within 0.78
/// of these units over 600 polygons (mine), within 5.3 over 3,000 (a review
/// of 2026-11-29's, 388 removals); one piece the review found needed 11.
/// Only pieces readers would refuse are touched, so the margin costs no
/// other output a bit.
pub const WORLD_ROUNDING_ULPS: f64 = 16.0;

/// [`WORLD_ROUNDING_ULPS`] of `largest`, a world coordinate's magnitude:
/// what the mapping's rounding can move a vertex by.
pub(super) fn world_rounding(largest: f64) -> f64 {
    WORLD_ROUNDING_ULPS * f64::EPSILON * largest
}

/// Removes from a piece's ring the zero-width spikes clipping leaves where
/// the input's boundary runs along a grid line and back: a vertex where the
/// ring turns straight back ([`folds_back`]), and a vertex the next repeats.
/// They bound no area, so the piece covers the same region without them.
/// A ring without them (nearly every piece) is left as it is, after one
/// pass that allocates nothing.
pub fn drop_spikes(ring: &mut Vec<DVec2>) {
    if let Some(keep) = spike_free(ring) {
        *ring = keep.iter().map(|&i| ring[i]).collect();
    }
}

/// What [`simple_in_world`] made of a piece.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum WorldPiece {
    /// Simple as readers judge it: to be written.
    Simple,
    /// Not simple, and its area (the plane ring's) is within what rounding
    /// its world vertices can change: no piece at all at this distance from
    /// the origin. Not to be written.
    Noise,
    /// Not simple by more than rounding, nor two parts touching at a point:
    /// left as far as the repair went. Seen from inputs off their plane
    /// (within the planarity tolerance), simple as given but not once
    /// projected to it, before [`simple_on_plane`] mended them; not seen
    /// since, in the property tests nor the fuzzers of docs/polyfill3.md.
    Tangled,
}

/// A piece as [`simple_in_world`] hands on the parts it split off: its
/// world ring and its plane ring, vertex for vertex.
pub type Part = (Vec<DVec3>, Vec<DVec2>);

/// Makes a piece's world polygon simple as its readers judge it, removing
/// the same vertices from its plane ring, or splitting both. A piece that
/// is simple already (nearly every one) costs the check every reader makes
/// and is left as it was.
///
/// A piece that is not simple and whose area is within what rounding its
/// world vertices can change ([`WORLD_ROUNDING_ULPS`] of the largest world
/// coordinate, times its perimeter) is [`WorldPiece::Noise`]: far from the
/// origin a sliver the plane still resolves can come out of the mapping as
/// a fold of no area, whose flat view (along whatever axis its noise
/// normal picks) crosses itself. Dropping it loses less than that bound.
/// The area is the plane ring's, exact where the world ring's is not.
///
/// Otherwise the world ring's flat view is first rid of spikes and repeats
/// as [`drop_spikes`] does in the plane. Then, while the check finds a
/// contact:
///
/// - the one of its vertices (the ends of the edges that meet) nearest the
///   chord of its neighbours is removed, if it lies within
///   [`WORLD_ROUNDING_ULPS`] of it: a feature smaller than the mapping's
///   rounding, which that rounding turned over. A vertex so removed can be
///   one the neighbouring cell keeps on their shared grid line: the two then
///   meet with a T-junction whose gap is within that rounding, instead of
///   vertex to vertex;
/// - else, where a vertex lies on another edge or vertex, or within
///   [`WORLD_ROUNDING_ULPS`] of an edge it crosses, the ring is split there
///   into two rings: the piece is two parts that touch at a point (a reflex
///   vertex of the input on a grid line, or within ulps of one), as the
///   partition writes the parts of a piece that falls apart. The part that
///   keeps the first vertex stays in `world` and `plane`; the other, made
///   simple the same way, is pushed onto `parts` unless it is noise.
///
/// The verdict is the first part's.
pub fn simple_in_world(
    world: &mut Vec<DVec3>,
    plane: &mut Vec<DVec2>,
    parts: &mut Vec<Part>,
) -> WorldPiece {
    debug_assert_eq!(world.len(), plane.len());
    if check(world).is_ok() {
        return WorldPiece::Simple;
    }
    let largest = world
        .iter()
        .fold(0.0f64, |m, p| m.max(p.abs().max_element()));
    let slack = world_rounding(largest);
    let n = world.len();
    let perimeter: f64 = (0..n)
        .map(|k| (world[(k + 1) % n] - world[k]).length())
        .sum();
    // What moving each vertex by `slack` can change the area by.
    if signed_area(plane).abs() <= slack * perimeter {
        return WorldPiece::Noise;
    }
    // Each pass removes a vertex, splits off a part, or returns.
    for _ in 0..n {
        let Some(flat) = flat_view(world) else {
            return WorldPiece::Simple;
        };
        if let Some(keep) = spike_free(&flat) {
            *world = keep.iter().map(|&i| world[i]).collect();
            *plane = keep.iter().map(|&i| plane[i]).collect();
            continue;
        }
        let Err(contact) = check(world) else {
            return WorldPiece::Simple;
        };
        let (k, d) = contact.nearest_to_chord(&flat);
        // NaN (coincident neighbours) is a spike, removed above.
        if d <= slack {
            world.remove(k);
            plane.remove(k);
            continue;
        }
        let Some(split) = touch(contact, &flat, slack) else {
            return WorldPiece::Tangled;
        };
        let (mut w, mut p) = split.cut(world, plane);
        if simple_in_world(&mut w, &mut p, parts) != WorldPiece::Noise {
            parts.push((w, p));
        }
    }
    match check(world) {
        Ok(()) => WorldPiece::Simple,
        Err(_) => WorldPiece::Tangled,
    }
}

/// What [`simple_on_plane`] made of an input's ring in its plane.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum OnPlane {
    /// Simple as projected: left as it was, bit for bit (nearly every input).
    Simple,
    /// Projected along the axis readers drop, and simple so.
    AlongAxis,
    /// Still meets itself there, within rounding (a vertex within an ulp
    /// of another edge, say): left as projected orthogonally, bit for bit,
    /// and cut so, the pieces mended as they are written (`simple_in_world`).
    MeetsItself(Contact),
}

/// Makes an input's ring in its plane simple where projecting its vertices
/// (`world`) onto the plane made it meet itself.
///
/// Readers judge an input on its flat view ([`flat_view`]: two of each
/// vertex's world coordinates, as written); the partition cuts the
/// orthogonal projection onto the best-fit plane, [`PlanePolygon::points`].
/// An input off its plane (within the planarity tolerance) can be simple on
/// the first and cross itself on the second, where it has features as
/// small as its distance off the plane: two vertices 3.5e-7 apart, a
/// notch's tip that close to another edge.
///
/// A ring that is simple (nearly every one) costs one check
/// ([`find_contact`]) and is left as it was, bit for bit. Otherwise each
/// vertex is projected onto the plane along the axis the flat view drops,
/// not along the normal: the two coordinates readers look at are kept, and
/// the third is the plane's there, so the ring in the plane is an affine
/// image of the flat view readers took as simple (with the same winding and
/// area), simple but for rounding. A vertex `d` off the plane then moves by
/// up to `sqrt(3) d` in space and `sqrt(2) d` in the plane, where the
/// orthogonal projection moves it by `d`: the flat view drops the normal's
/// largest component, at least `1/sqrt(3)` of it. The arithmetic is
/// relative to the frame's origin, as `Frame::to_plane`'s: far from the
/// world's origin, a coordinate solved for in world units would be rounded
/// to an ulp of the offset (2e-9 at 1e7), more than many inputs are off
/// their plane. What rounding leaves is mended as for the partition's
/// pieces (`simple_in_world`): spikes and repeats are dropped, and, while
/// the ring meets itself, the vertex of the contact nearest the chord of
/// its neighbours is removed if it lies within 16 `EPSILON`s of the largest
/// world coordinate of it.
///
/// An input that still meets itself (a contact within an ulp, which
/// neither projection resolves) gets its orthogonal projection back and is
/// cut as before this repair, [`OnPlane::MeetsItself`]: its pieces are
/// mended as they are written, which kept such inputs readable.
pub fn simple_on_plane(poly: &mut PlanePolygon, world: &[DVec3]) -> OnPlane {
    let Some(first) = find_contact(&poly.points) else {
        return OnPlane::Simple;
    };
    debug_assert_eq!(world.len(), poly.points.len());
    let frame = poly.frame;
    // No flat view: readers let it through as collinear, which the plane
    // fit would have refused as without area. And the axis is the largest
    // component of the readers' normal, at least 0.577 of it; far less of
    // the plane's means the two normals disagree (a ring crossing itself
    // as given, whose loops cancel): no projection along it is sound.
    let axis = match flat_view_along(world) {
        Some((_, axis)) if frame.normal[axis].abs() >= 0.5 => axis,
        _ => return OnPlane::MeetsItself(first),
    };
    // Along the axis: d . normal = 0 solved for d[axis], d = p - origin.
    let mut ring: Vec<DVec2> = world
        .iter()
        .map(|&p| {
            let mut d = p - frame.origin;
            d[axis] -= d.dot(frame.normal) / frame.normal[axis];
            DVec2::new(d.dot(frame.ex), d.dot(frame.ey))
        })
        .collect();
    let largest = frame.origin.abs().max_element() + poly.size;
    let slack = world_rounding(largest);
    loop {
        drop_spikes(&mut ring);
        let Some(contact) = find_contact(&ring) else {
            // Fewer than 3 vertices left: the input was spikes only.
            if ring.len() < 3 {
                return OnPlane::MeetsItself(first);
            }
            poly.points = ring;
            return OnPlane::AlongAxis;
        };
        let (k, d) = contact.nearest_to_chord(&ring);
        // NaN (coincident neighbours) is a spike, dropped above.
        if d.is_nan() || d > slack {
            return OnPlane::MeetsItself(first);
        }
        ring.remove(k);
    }
}

/// Where a ring touches itself, to be split there ([`simple_in_world`]).
#[derive(Clone, Copy, Debug)]
enum Touch {
    /// Vertex `vertex` lies on edge `edge` (or within rounding of it).
    OnEdge { vertex: usize, edge: usize },
    /// Vertices `a < b` are the same point.
    SamePoint { a: usize, b: usize },
}

/// The touch a contact is, if it is one: a vertex at another, a vertex on
/// an edge, or an end of one of two crossing or overlapping edges within
/// `slack` of the other (measured in the flat view `flat`).
fn touch(contact: Contact, flat: &[DVec2], slack: f64) -> Option<Touch> {
    let n = flat.len();
    match contact {
        Contact::SamePoint { a, b } => Some(Touch::SamePoint { a, b }),
        Contact::VertexOnEdge { vertex, edge, .. } => Some(Touch::OnEdge { vertex, edge }),
        Contact::Cross { a, b, .. } | Contact::Overlap { a, b, .. } => {
            let off_edge = |v: usize, e: usize| {
                let (p, q, x) = (flat[e], flat[(e + 1) % n], flat[v]);
                let t = ((x - p).dot(q - p) / (q - p).length_squared()).clamp(0.0, 1.0);
                (p + (q - p) * t - x).length()
            };
            [(a, b), ((a + 1) % n, b), (b, a), ((b + 1) % n, a)]
                .into_iter()
                .map(|(v, e)| (v, e, off_edge(v, e)))
                .filter(|&(_, _, d)| d <= slack)
                .min_by(|x, y| x.2.total_cmp(&y.2))
                .map(|(vertex, edge, _)| Touch::OnEdge { vertex, edge })
        }
    }
}

impl Touch {
    /// Splits the ring in two: one part stays in `world` and `plane`, the
    /// other is returned. A vertex on an edge starts both parts (one runs
    /// from it to the edge's start, the other from the edge's end back to
    /// it); two vertices at one point split the ring between them. Both
    /// parts keep the ring's order, so its winding.
    fn cut(self, world: &mut Vec<DVec3>, plane: &mut Vec<DVec2>) -> Part {
        let n = world.len();
        // The part cut off, in ring order, and the vertex both parts keep.
        let (off, shared): (Vec<usize>, Option<usize>) = match self {
            Touch::SamePoint { a, b } => ((a..b).collect(), None),
            Touch::OnEdge { vertex, edge } => {
                let len = (edge + n - vertex) % n + 1;
                ((0..len).map(|i| (vertex + i) % n).collect(), Some(vertex))
            }
        };
        let mut stays = vec![true; n];
        for &i in &off {
            stays[i] = Some(i) == shared;
        }
        let cut_off: Part = (
            off.iter().map(|&i| world[i]).collect(),
            off.iter().map(|&i| plane[i]).collect(),
        );
        let stay: Vec<usize> = (0..n).filter(|&i| stays[i]).collect();
        *world = stay.iter().map(|&i| world[i]).collect();
        *plane = stay.iter().map(|&i| plane[i]).collect();
        cut_off
    }
}

/// The vertices to keep of a ring seen as `view` so that it has no spike
/// nor repeated vertex ([`drop_spikes`]), or `None` when it has none. The
/// ring is walked once as a stack (a removal can make a spike of the
/// vertices either side, which the stack meets next), then at the join of
/// its end and start: linear in the ring.
fn spike_free(view: &[DVec2]) -> Option<Vec<usize>> {
    let m = view.len();
    let spike = |k: usize| {
        let (a, b, c) = (view[(k + m - 1) % m], view[k], view[(k + 1) % m]);
        b == c || folds_back(a, b, c)
    };
    if m < 3 || !(0..m).any(spike) {
        return None;
    }
    let mut kept: Vec<usize> = Vec::with_capacity(m);
    let last = |kept: &[usize]| kept.last().map(|&i| view[i]);
    for (i, &p) in view.iter().enumerate() {
        if last(&kept) == Some(p) {
            continue;
        }
        while let [.., a, b] = kept[..] {
            if !folds_back(view[a], view[b], p) {
                break;
            }
            kept.pop();
            if last(&kept) == Some(p) {
                kept.pop();
            }
        }
        kept.push(i);
    }
    // The join: only the vertices either side of it can still be spikes.
    let at = |kept: &[usize], i: usize| view[kept[i]];
    let mut start = 0;
    while kept.len() - start >= 3 {
        let (n, s) = (kept.len(), start);
        if at(&kept, n - 1) == at(&kept, s)
            || folds_back(at(&kept, n - 2), at(&kept, n - 1), at(&kept, s))
        {
            kept.pop();
        } else if folds_back(at(&kept, n - 1), at(&kept, s), at(&kept, s + 1)) {
            start += 1;
        } else {
            break;
        }
    }
    kept.drain(..start);
    Some(kept)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Twice the signed area, by the shoelace formula (the check's own,
    /// not `polygon::area2`).
    fn shoelace(r: &[DVec2]) -> f64 {
        (0..r.len())
            .map(|k| r[k].perp_dot(r[(k + 1) % r.len()]))
            .sum()
    }

    #[test]
    fn spikes_and_repeats_leave_a_cell_and_nothing_else_does() {
        let v = |x: f64, y: f64| DVec2::new(x, y);
        let square = vec![v(0.0, 0.0), v(1.0, 0.0), v(1.0, 1.0), v(0.0, 1.0)];
        // A square with a spike up its left side (the comb's notch of
        // review 2026-11-29, where the spike's tip was the first vertex), a
        // repeat, a spike at the join, and a spike on a spike.
        let cases: [&[(f64, f64)]; 5] = [
            &[(0.0, 1.5), (0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)],
            &[(0.0, 0.0), (1.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)],
            &[(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0), (0.0, 1.5)],
            &[
                (0.0, 0.0),
                (1.0, 0.0),
                (2.0, 0.0),
                (3.0, 0.0),
                (1.0, 0.0),
                (1.0, 1.0),
                (0.0, 1.0),
            ],
            &[(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)],
        ];
        for case in cases {
            let case: Vec<DVec2> = case.iter().map(|&(x, y)| v(x, y)).collect();
            let mut ring = case.clone();
            drop_spikes(&mut ring);
            assert_eq!(shoelace(&ring), shoelace(&square), "{case:?}");
            assert_eq!(ring.len(), 4, "{case:?} gave {ring:?}");
            for p in &square {
                assert!(ring.contains(p), "{case:?} gave {ring:?}");
            }
            assert!(
                crate::geom::simple::find_contact(&ring).is_none(),
                "{case:?} gave {ring:?}"
            );
        }
        // Collinear vertices that go straight on are kept.
        let mut run = vec![
            v(0.0, 0.0),
            v(1.0, 0.0),
            v(2.0, 0.0),
            v(2.0, 1.0),
            v(0.0, 1.0),
        ];
        let before = run.clone();
        drop_spikes(&mut run);
        assert_eq!(run, before);
    }

    fn p3(v: &[[f64; 3]]) -> Vec<DVec3> {
        v.iter().map(|&a| DVec3::from(a)).collect()
    }

    /// Two pieces polyfill3 wrote before `simple_in_world` (a fuzzer's
    /// combs, review of 2026-11-29), which every reader refused: a fold
    /// of one ulp up a wall, with a repeated vertex ("runs along itself"),
    /// and a staircase of a few ulps at a corner ("crosses itself"). Each
    /// comes out simple with the vertices named removed and nothing else.
    #[test]
    fn world_rings_that_rounding_folded_or_crossed_come_out_simple() {
        let y0 = 3.2553364891256056;
        let y1 = 3.255336489125606;
        let z = -7.40447979333866;
        let folded = p3(&[
            [19.1, 2.3, -7.699999999999999],
            [20.1, 2.3, -7.699999999999999],
            [20.1, y0, z],
            [19.1, y0, z],
            [19.1, y1, z],
            [19.1, y1, z],
        ]);
        let crossed = p3(&[
            [-0.01580958427500828, -0.22304720810862308, 0.0],
            [-0.06674285960673623, -0.3091041744970707, 0.0],
            [0.019314106781711353, -0.3600374498287986, 0.0],
            [0.01931410678171136, -0.3600374498287986, 0.0],
            [0.0193141067817105, -0.3600374498287981, 0.0],
            [0.07024738211343844, -0.27398048344035053, 0.0],
        ]);
        for (world, kept) in [(folded, [0, 1, 2, 3]), (crossed, [0, 1, 4, 5])] {
            assert!(check(&world).is_err());
            // The plane ring goes along: here a copy of the flat view.
            let mut plane: Vec<DVec2> = world.iter().map(|p| p.truncate()).collect();
            let mut w = world.clone();
            assert_eq!(
                simple_in_world(&mut w, &mut plane, &mut Vec::new()),
                WorldPiece::Simple
            );
            assert_eq!(w, kept.map(|i| world[i]));
            assert_eq!(plane, kept.map(|i| world[i].truncate()));
            assert!(check(&w).is_ok());
        }
    }

    /// Two pieces polyfill3 wrote before splitting (a review's pentagons,
    /// 2026-11-29): a notch's tip on a grid column, exactly (level) and 2
    /// ulps off it (tilted, where the mapping put it on the column). Each
    /// cell's piece is two parts touching at the tip, and was written as
    /// one ring ("vertex 1 lies on edge 4"); it comes out as the two parts,
    /// each simple, which cover what the ring did.
    #[test]
    fn parts_that_touch_at_a_point_are_split_there() {
        let level = p3(&[
            [0.53125, 0.75, 0.0],
            [0.5, 0.8, 0.0],
            [0.75, 0.9, 0.0],
            [0.75, 1.0, 0.0],
            [0.5, 1.0, 0.0],
            [0.5, 0.75, 0.0],
        ]);
        let tilted = p3(&[
            [1.6, 3.0165023668442044, -7.478359845003995],
            [1.6, 2.7776682445628027, -7.55223989666933],
            [1.6454545454545455, 2.7776682445628027, -7.55223989666933],
            [1.6, 2.825435069019083, -7.537463886336263],
            [1.8222222222222226, 3.0165023668442044, -7.478359845003995],
        ]);
        // The parts' vertices, as indices into the ring: the one that stays,
        // and the one split off.
        for (ring, stays, off) in [
            (level, vec![0, 1, 5], vec![1, 2, 3, 4]),
            (tilted, vec![1, 2, 3], vec![3, 4, 0]),
        ] {
            assert!(check(&ring).is_err());
            let flat = |w: &[DVec3]| w.iter().map(|p| p.truncate()).collect::<Vec<_>>();
            let (mut w, mut plane, mut parts) = (ring.clone(), flat(&ring), Vec::new());
            assert_eq!(
                simple_in_world(&mut w, &mut plane, &mut parts),
                WorldPiece::Simple
            );
            assert_eq!(w, stays.iter().map(|&i| ring[i]).collect::<Vec<_>>());
            assert_eq!(plane, flat(&w));
            let [(w2, p2)] = &parts[..] else {
                panic!("{parts:?}");
            };
            assert_eq!(*w2, off.iter().map(|&i| ring[i]).collect::<Vec<_>>());
            assert_eq!(*p2, flat(w2));
            assert!(check(&w).is_ok() && check(w2).is_ok());
            let (whole, split) = (shoelace(&flat(&ring)), shoelace(&plane) + shoelace(p2));
            assert!((whole - split).abs() <= 1e-15 * whole, "{whole} {split}");
        }
    }

    /// A simple piece is left as it was, bit for bit. A crossing larger
    /// than rounding (a square whose last edge is pulled through its
    /// first) is not the repair's to hide, and a ring far from the origin
    /// whose area is within rounding is noise.
    #[test]
    fn simple_pieces_are_untouched_and_real_crossings_are_left() {
        let square = p3(&[
            [0.0, 0.0, 1.0],
            [1.0, 0.0, 1.0],
            [1.0, 1.0, 1.0],
            [0.5, 1.0, 1.0],
            [0.0, 1.0, 1.0],
        ]);
        let pulled = pulled_square();
        // 3e6 from the origin (a fuzzer's tilted comb): a sliver the plane
        // resolved, mapped to a triangle and back along one of its sides.
        let far_sliver = p3(&[
            [3000003.057259763, 1000000.1185327356, -1999999.6881286777],
            [3000002.998729748, 1000000.407270364, -1999999.8440643388],
            [3000003.325418608, 1000000.4734934742, -1999999.8440643388],
            [3000002.9987297487, 1000000.4072703641, -1999999.8440643388],
        ]);
        for (ring, made) in [
            (square, WorldPiece::Simple),
            (far_sliver, WorldPiece::Noise),
            (pulled, WorldPiece::Tangled),
        ] {
            let mut w = ring.clone();
            let mut plane: Vec<DVec2> = w.iter().map(|p| p.truncate()).collect();
            assert_eq!(
                simple_in_world(&mut w, &mut plane, &mut Vec::new()),
                made,
                "{ring:?}"
            );
            assert_eq!(w, ring);
        }
    }

    /// A square whose last edge is pulled through its first: a real
    /// crossing, by far more than rounding.
    fn pulled_square() -> Vec<DVec3> {
        p3(&[
            [0.0, 0.0, 1.0],
            [2.0, 0.0, 1.0],
            [2.0, 2.0, 1.0],
            [0.0, 2.0, 1.0],
            [1.0, -1.0, 1.0],
        ])
    }

    /// Inputs simple as readers judge them whose projection onto their
    /// plane meets itself: the review's quadrilateral (vertices 1 and 2
    /// 3.5e-7 apart: edges 0 and 2 crossed) and notch (its tip within its
    /// distance off the plane of another edge: edges 1 and 3 crossed). Each
    /// comes out simple, projected along the axis the flat view drops, each
    /// vertex within `sqrt(2)` times the distance off the plane of where
    /// the orthogonal projection put it, with the same area. A simple ring
    /// is left bit for bit, and so is one that meets itself as given.
    #[test]
    fn inputs_that_projection_made_cross_are_projected_along_the_readers_axis() {
        use crate::geom::plane::map_to_plane;
        let quad = p3(&[
            [1.5, 0.3, 0.0],
            [0.90982636, 0.545175, 0.35355339],
            [0.90982636, 0.545175, 0.353553],
            [0.6, 2.0, 1.8],
        ]);
        let notch = p3(&[
            [-1.9014292945093982, -5.67270629170941, -31260.54190259487],
            [-1.8849057000107814, -5.686284134770423, -31260.509178832246],
            [-1.8847218339996177, -5.722358576610978, -31260.52423979094],
            [-1.9013538296999375, -5.68750918211886, -31260.548082760488],
            [-1.8847665375279228, -5.713585406395296, -31260.520577027713],
        ]);
        // The quadrilateral's vertices 1 and 2 differ only along the axis
        // the flat view drops: readers see one vertex, and so does the cut.
        for (given, rotate, kept) in [
            (quad, 270.0, [0, 1, 3].as_slice()),
            (notch, 0.0, &[0, 1, 2, 3, 4]),
        ] {
            assert!(check(&given).is_ok());
            let mut poly = map_to_plane(&given, rotate, 1e-6).unwrap();
            assert!(find_contact(&poly.points).is_some(), "{given:?}");
            let orthogonal = poly.points.clone();
            let deviation = given
                .iter()
                .map(|&p| (p - poly.frame.origin).dot(poly.frame.normal).abs())
                .fold(0.0, f64::max);
            assert_eq!(simple_on_plane(&mut poly, &given), OnPlane::AlongAxis);
            assert!(find_contact(&poly.points).is_none(), "{given:?}");
            assert_eq!(poly.points.len(), kept.len());
            for (p, &i) in poly.points.iter().zip(kept) {
                let moved = (*p - orthogonal[i]).length();
                assert!(moved <= 2f64.sqrt() * deviation * (1.0 + 1e-6), "{moved:e}");
            }
            let area = |r: &[DVec2]| shoelace(r) / 2.0;
            assert!((area(&poly.points) - area(&orthogonal)).abs() <= 1e-12 * area(&orthogonal));
        }

        let square = p3(&[
            [0.0, 0.0, 1.0],
            [1.0, 0.0, 1.0],
            [1.0, 1.0, 1.0],
            [0.0, 1.0, 1.0],
        ]);
        let pulled = pulled_square();
        for ring in [square, pulled] {
            let mut poly = map_to_plane(&ring, 30.0, 1e-6).unwrap();
            let given = poly.clone();
            let made = simple_on_plane(&mut poly, &ring);
            assert_eq!(poly, given);
            match check(&ring) {
                Ok(()) => assert_eq!(made, OnPlane::Simple),
                Err(_) => assert!(matches!(made, OnPlane::MeetsItself(_))),
            }
        }
    }
}
