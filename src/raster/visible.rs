//! Visibility within one pixel, for `--aa exact` ([`super::coverage`]):
//! the tile sweep's state of each pixel ([`PixelStates`]) with its map of
//! what shows where, the convex geometry it stands on ([`subtract_with`],
//! [`disjoint`]), and the pairwise subtraction the tests check it against
//! (`subtract_pairwise`).

use super::coverage::{
    deferred_filter, shade_factor, shaded, Frag, CUT_LATER, EDGE_EPS, FILTER_LATER, POLY_COLOR,
    SEPARATION_EPS,
};
use super::crowd::{
    cone_at, span, AxisIndex, Crowd, HubIndex, AXIS_MAX_WIDTH, CROWD_MIN_SHOWERS,
    CROWD_RETRY_FACTOR, HUB_MAX_VERTICES,
};
use super::gather::Local;
use super::{tie_tolerance, Background, ScreenPoly};
use crate::geom::polygon::{area2, clip_axis, clip_line, pixel_square, AREA_EPS};
use glam::DVec2;

/// Where a pixel stands in the tile-order sweep of
/// `super::coverage::render_tile`.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
enum Status {
    /// What has shown (if anything) is pairwise disjoint, so the uncovered
    /// part is the square minus their areas, and it is never built: a pixel
    /// cut into texel cells or split between neighbours that only touch
    /// costs no subtraction at all. Each shower's visible part is its
    /// fragment.
    Disjoint,
    /// Wholly covered by pairwise disjoint showers (the whole square, most
    /// often): no uncovered part, and no map (each shower's visible part is
    /// its fragment).
    Covered,
    /// Partly covered, with overlaps: the uncovered part is the pixel's
    /// convex pieces, and the visible part of each shower is kept (the
    /// pixel's map, [`PixelStates::map`]).
    Open,
    /// Wholly covered, with its map.
    Closed,
}

/// A fragment that showed in a pixel, kept to check what comes later
/// against it (and to resolve the pixel again if that check fails).
#[derive(Clone, Copy)]
struct Shower {
    poly: u32,
    /// Vertices in the arena, or `len == 0` for the full pixel square.
    start: u32,
    len: u32,
    /// Nearness at the pixel centre, and least over the pixel.
    qc: f64,
    q_lo: f64,
    bb: [f64; 4],
    color: [f64; 3],
    /// The area of the pixel it shows in.
    area: f64,
    /// A [`CUT_LATER`] fragment: `color` is the box integral over the part
    /// that shows, so it changes when that part does.
    cut_later: bool,
}

/// What [`PixelStates::sweep`] reads of the tile to place and colour a
/// fragment.
pub(super) struct Shown<'a> {
    pub(super) polys: &'a [ScreenPoly],
    pub(super) locals: &'a [Local],
    pub(super) arena: &'a [DVec2],
    pub(super) colors: &'a [[f64; 3]],
}

/// The tile-order sweep's state of each pixel of a tile: what is still
/// uncovered, the colour and area of what has shown, and the fragments
/// that showed (the *showers*).
///
/// Fragments arrive in the tile's sweep order, nearest first by a bound,
/// not in each pixel's own order. Each is checked against every shower of
/// its pixel: it must be nowhere in front of it where they overlap
/// ([`front_of`] `<= 0` at the vertices of either, which bound their
/// overlap since it is affine, or no common interior). Then it hides
/// nothing that has shown, and what it shows is exactly its part of the
/// uncovered region: it is cut out of it, and its visible area is what it
/// removed. Fragments that showed nothing need no check: they lie under
/// showers, which are in front of them there.
///
/// Where the check fails (polygons crossing inside the pixel, or met out
/// of order) the newcomer *overtakes* ([`PixelStates::overtake`]): it
/// takes from each shower the part of that shower's visible pieces where
/// it is in front (the shower's pieces cut by the newcomer's part in front
/// of it, a convex polygon, as in the pairwise subtraction), and its part
/// of the uncovered region. That is exact for any arrangement (with no
/// cycle in the tie rule among the pixel's polygons, which takes depths
/// within about two tie tolerances: docs/rendering.md, *Visibility and
/// ties*), because the
/// showers' visible parts and the uncovered part partition the pixel and
/// every other fragment lies, at each of its points, behind the shower
/// there: what lies at a point is the newcomer if it is in front of the
/// shower there, and stays the shower otherwise. So once a pixel's showers
/// overlap, each one's visible part is kept (the pixel's *map*); while they
/// are pairwise disjoint, each one's visible part is its fragment. In a
/// pixel with a map, a fragment not behind all the showers overtakes
/// without the check: the overtake tests each shower as the check would.
///
/// Before the map, such a pixel was resolved again from its fragments by
/// pairwise subtraction, quadratic in its showers each time; at depth
/// (random tilted triangles) half of all fragments did so, and it took 71%
/// of the render's time (`perf`, 200,000 triangles of
/// `bench/aa_scaling.sh`). Pairwise subtraction is kept as the tests'
/// oracle (`subtract_pairwise`).
#[derive(Default)]
pub(super) struct PixelStates {
    status: Vec<Status>,
    /// Area-weighted linear-light colour of what has shown, and its area.
    /// Summed in the showers' order, so that the sums are the same bits
    /// however the pixel came to them; [`PixelStates::sums`] gives them.
    acc: Vec<[f64; 4]>,
    /// Whether `acc` is out of date: showers lost area to an overtake since
    /// it was summed.
    stale: Vec<bool>,
    /// Over the showers: the least nearness over the pixel, and the largest
    /// |nearness| at the centre (for the tie tolerance).
    floor: Vec<[f64; 2]>,
    /// The uncovered part of an [`Status::Open`] pixel, as convex pieces.
    open: Vec<Uncovered>,
    showers: Vec<Vec<Shower>>,
    /// The visible part of each shower of an [`Status::Open`] or
    /// [`Status::Closed`] pixel, as convex pieces: each shower's pieces
    /// together, in the showers' order (a shower's pieces are only ever
    /// added last, or replaced where they stand), so that an overtake finds
    /// them by bisection.
    map: Vec<Vec<Owned>>,
    /// Whether a pixel's showers come from more than one polygon. While they
    /// do not, a fragment of that polygon needs no check against them (its
    /// pieces never overlap), and skipping them one by one would cost a
    /// pixel under k pieces of one polygon O(k²): a concave polygon of a
    /// million vertices drawn on a few pixels has thousands per pixel.
    mixed: Vec<bool>,
    /// A crowded [`Status::Disjoint`] or [`Status::Covered`] pixel's showers
    /// indexed by their cones at a vertex most of their polygons share, or
    /// by their spans across a strip (`super::crowd`): such a pixel is then
    /// checked in O(log n) a fragment, not O(n).
    crowds: Vec<Option<Box<Crowd>>>,
    /// How many showers a pixel must have for the next attempt at an index.
    crowd_due: Vec<u32>,
    /// How many fragments overtook a shower (a count for the tests).
    pub(super) overtaken: u32,
    /// How many indexes were built (a count for the tests).
    pub(super) crowds_built: u32,
    /// How many pieces of the map overtakes visited (a count for the tests).
    pub(super) visited: u64,
}

/// The uncovered part of a pixel, as convex pieces, each with its bounding
/// box: [`cut_out`] tests every piece's box against the newcomer's, and a
/// pixel under thousands of pieces of one concave polygon has as many
/// pieces (finding each box again took a third of such a run).
#[derive(Default)]
struct Uncovered {
    pieces: Vec<Vec<DVec2>>,
    boxes: Vec<[f64; 4]>,
}

/// A convex piece of a pixel where one shower shows: a piece of the
/// pixel's map. The map and the uncovered pieces partition the pixel.
struct Owned {
    /// The shower's index in the pixel's list.
    shower: u32,
    verts: Vec<DVec2>,
}

/// A fragment on its way into [`PixelStates::sweep`].
struct Newcomer<'a> {
    f: &'a Frag,
    l: &'a Local,
    verts: &'a [DVec2],
    bb: [f64; 4],
    qc: f64,
    paint: Paint,
}

/// How a fragment's colour is known.
#[derive(Clone, Copy)]
enum Paint {
    /// Given.
    Known([f64; 3]),
    /// A [`FILTER_LATER`] fragment's: the filter at the pixel centre,
    /// evaluated once the fragment shows.
    FilterLater,
    /// A [`CUT_LATER`] fragment's: the box integral over the part of it
    /// that shows.
    CutLater,
}

impl Newcomer<'_> {
    /// This fragment as a shower of colour `color` over `area` of the pixel.
    fn shower(&self, color: [f64; 3], area: f64) -> Shower {
        Shower {
            area,
            cut_later: matches!(self.paint, Paint::CutLater),
            poly: self.f.poly,
            start: self.f.start,
            len: self.f.len,
            qc: self.qc,
            q_lo: self.qc - self.l.half_spread(),
            bb: self.bb,
            color,
        }
    }
}

impl PixelStates {
    /// Every pixel uncovered, for a tile of `n` pixels; the last tile's
    /// pieces go back to `pool`.
    pub(super) fn reset(&mut self, n: usize, pool: &mut Vec<Vec<DVec2>>) {
        for open in &mut self.open {
            pool.append(&mut open.pieces);
            open.boxes.clear();
        }
        for map in &mut self.map {
            pool.extend(map.drain(..).map(|o| o.verts));
        }
        for s in &mut self.showers {
            s.clear();
        }
        if self.open.len() < n {
            self.open.resize_with(n, Uncovered::default);
            self.showers.resize_with(n, Vec::new);
            self.map.resize_with(n, Vec::new);
        }
        self.mixed.clear();
        self.mixed.resize(n, false);
        self.crowds.clear();
        self.crowds.resize_with(n, || None);
        self.crowd_due.clear();
        self.crowd_due.resize(n, CROWD_MIN_SHOWERS as u32);
        self.status.clear();
        self.status.resize(n, Status::Disjoint);
        self.acc.clear();
        self.acc.resize(n, [0.0; 4]);
        self.stale.clear();
        self.stale.resize(n, false);
        self.floor.clear();
        self.floor.resize(n, [f64::INFINITY, 0.0]);
    }

    /// Whether the pixel is partly covered, with overlaps (so a fragment is
    /// only cut out of its uncovered part).
    #[inline]
    pub(super) fn is_open(&self, pixel: u32) -> bool {
        self.status[pixel as usize] == Status::Open
    }

    /// Whether `l` can show nothing in the pixel centred at `(cx, cy)`: the
    /// pixel is covered, and `l` is behind every shower over the whole
    /// pixel by more than the tie tolerance (so the check of
    /// [`PixelStates::sweep`] passes for it without its fragment).
    #[inline]
    pub(super) fn hides(&self, pixel: u32, l: &Local, cx: f64, cy: f64) -> bool {
        let p = pixel as usize;
        if !matches!(self.status[p], Status::Closed | Status::Covered) {
            return false;
        }
        let [q_lo, abs] = self.floor[p];
        let qc = l.q(cx, cy);
        qc + l.half_spread() + tie_tolerance(qc, abs, l.tie_floor) <= q_lo
    }

    /// Sweeps fragment `f` of pixel `(px, py)` (see [`PixelStates`]).
    pub(super) fn sweep(
        &mut self,
        f: &Frag,
        (px, py): (u32, u32),
        bb: Option<[f64; 4]>,
        t: &Shown,
        work: &mut Scratch,
    ) {
        let p = f.pixel as usize;
        let l = &t.locals[f.poly as usize];
        // A screen pattern's transparent texel: no fragment at all.
        let paint = match f.color {
            POLY_COLOR => match l
                .color
                .or_else(|| t.polys[l.global as usize].color_at(px, py))
            {
                Some(c) => Paint::Known(c),
                None => return,
            },
            FILTER_LATER => Paint::FilterLater,
            CUT_LATER => Paint::CutLater,
            i => Paint::Known(t.colors[i as usize]),
        };
        let square = pixel_square(px, py);
        let verts = frag_verts(f, t.arena, &square);
        let first_full =
            f.len == 0 && self.showers[p].is_empty() && self.status[p] == Status::Disjoint;
        let n = Newcomer {
            f,
            l,
            verts,
            bb: match bb {
                Some(bb) => bb,
                None if f.len == 0 => box_of(&square),
                None => bounds(verts),
            },
            qc: l.q(px as f64 + 0.5, py as f64 + 0.5),
            paint,
        };
        let status = self.status[p];
        if first_full {
            // The first fragment, and full: it is all the pixel shows so far
            // (the common case inside polygons; nothing to check or cut).
            if let Some(c) = paint_of(&n, [&square[..]], (px, py), t, work) {
                self.show(p, &n, 1.0, c);
                self.status[p] = Status::Covered;
            }
            return;
        }
        let key = self.crowd_key(p, &n, &square, t, &mut work.candidates);
        let candidates = key.is_some().then_some(&work.candidates[..]);
        let (in_order, overlaps) = self.check(p, &n, &square, t, candidates);
        if !in_order {
            self.overtake(p, &n, (px, py), &square, t, work);
            return;
        }
        let (seen2, whole) = match status {
            // Hidden: behind what covers the pixel.
            Status::Closed | Status::Covered => return,
            Status::Disjoint if !overlaps => {
                let seen2 = if f.len == 0 { 2.0 } else { area2(verts) };
                (seen2, true)
            }
            Status::Disjoint | Status::Open => {
                if status == Status::Disjoint {
                    self.build_open(p, &square, t.arena, work);
                }
                (self.cut(p, &n, &square, work), false)
            }
        };
        let area = 0.5 * seen2;
        let mut hits = std::mem::take(&mut work.hits);
        if area > AREA_EPS {
            // What shows of the fragment: all of it, or what the cut found
            // (its pieces of the map).
            let c = if whole {
                paint_of(&n, [verts], (px, py), t, work)
            } else {
                paint_of(&n, hits.iter().map(|h| &h[..]), (px, py), t, work)
            };
            if let Some(c) = c {
                self.show(p, &n, area, c);
                let shower = self.showers[p].len() as u32 - 1;
                if let Some(crowd) = self.crowds[p].as_mut() {
                    crowd.insert(shower, key);
                }
                let owned = hits.drain(..).map(|verts| Owned { shower, verts });
                self.map[p].extend(owned);
            }
        }
        work.pool.append(&mut hits);
        work.hits = hits;
        if self.status[p] == Status::Disjoint && self.acc[p][3] >= 1.0 - AREA_EPS {
            self.status[p] = Status::Covered;
        }
    }

    /// Whether `n` is nowhere in front of a shower of pixel `p` where they
    /// overlap; and, for a [`Status::Disjoint`] pixel, whether it overlaps
    /// any shower. In a pixel with a map only the quick tests are made,
    /// and `false` means that they did not settle it.
    ///
    /// `candidates`, from the pixel's index, are the only showers `n`
    /// can overlap (any other is apart from it, so it settles nothing):
    /// only they are tested.
    fn check(
        &self,
        p: usize,
        n: &Newcomer,
        square: &[DVec2; 4],
        t: &Shown,
        candidates: Option<&[u32]>,
    ) -> (bool, bool) {
        let track = self.status[p] == Status::Disjoint;
        let (l, qc) = (n.l, n.qc);
        let q_hi = qc + l.half_spread();
        let [floor, abs] = self.floor[p];
        let behind_all = q_hi + tie_tolerance(qc, abs, l.tie_floor) <= floor;
        if behind_all && !track {
            return (true, false);
        }
        let own = |c: &Shower| c.poly == n.f.poly;
        if self.only_pieces_of(p, n.f.poly) {
            return (true, false); // What the loop gives when it skips them all.
        }
        if matches!(self.status[p], Status::Open | Status::Closed) {
            // A pixel with a map: overtaking tests each shower as the loop
            // below would and takes what `n` is in front of in the same
            // pass, so `n` overtakes whether it is in order or not.
            // Render phase 1-9% less on `bench/aa_scaling.sh`'s triangles
            // at 200,000 and a million (three paired runs each).
            return (false, true);
        }
        let mut overlaps = false;
        // Whether `n` is in front of `c` somewhere they overlap.
        let mut in_front = |c: &Shower| {
            if own(c) {
                return false; // One polygon's pieces never overlap.
            }
            let cv = shape(c.start, c.len, t.arena, square);
            let apart = || boxes_apart(&n.bb, &c.bb) || disjoint(cv, n.verts);
            let behind = behind_all || q_hi + tie_tolerance(qc, c.qc, l.tie_floor) <= c.q_lo || {
                let d = front_of(l, &t.locals[c.poly as usize], qc, c.qc);
                let val = |v: &DVec2| d[0] * v.x + d[1] * v.y + d[2];
                n.verts.iter().all(|v| val(v) <= 0.0) || cv.iter().all(|v| val(v) <= 0.0)
            };
            if behind {
                overlaps = overlaps || (track && !apart());
                return false;
            }
            !apart()
        };
        let showers = &self.showers[p];
        let found = match candidates {
            Some(some) => some.iter().any(|&i| in_front(&showers[i as usize])),
            None => showers.iter().any(in_front),
        };
        if found {
            return (false, true);
        }
        (true, overlaps)
    }

    /// For a [`Status::Disjoint`] or [`Status::Covered`] pixel with an index
    /// (built here once it is due: `super::crowd`): `n`'s key in it, with
    /// the showers it must be checked against in `candidates`. `None` where
    /// every shower must be (no index, or `n` has no key in it).
    fn crowd_key(
        &mut self,
        p: usize,
        n: &Newcomer,
        square: &[DVec2; 4],
        t: &Shown,
        candidates: &mut Vec<u32>,
    ) -> Option<(f64, f64)> {
        if !matches!(self.status[p], Status::Disjoint | Status::Covered) {
            return None;
        }
        // A polygon's outline, for the cones of the hub index (which hold
        // its vertices' hull, so any polygon: `crowd::cone_at`).
        let outline = |local: u32| {
            let g = t.polys.get(t.locals[local as usize].global as usize)?;
            Some(g.verts())
        };
        let showers = &self.showers[p];
        if self.crowds[p].is_none() && self.only_pieces_of(p, n.f.poly) {
            // The check skips every shower of the newcomer's own polygon,
            // so an index would serve nothing yet: built here, each of the
            // polygon's fragments asked it for candidates, and a comb of
            // 8,000 teeth (one polygon) took 3.3 s, 80% in the index,
            // growing as the square of its teeth (a hostile-input review).
            // It is built once another polygon comes, from all the showers.
            return None;
        }
        if self.crowds[p].is_none() && showers.len() >= self.crowd_due[p] as usize {
            self.crowd_due[p] = self.crowd_due[p].saturating_mul(CROWD_RETRY_FACTOR as u32);
            let frag = |c: &Shower| shape(c.start, c.len, t.arena, square);
            let built = hub_of(showers, outline(n.f.poly), outline, frag)
                .or_else(|| axis_of(showers, outline(n.f.poly).unwrap_or(n.verts), frag));
            if let Some(crowd) = built {
                self.crowds[p] = Some(Box::new(crowd));
                self.crowds_built = self.crowds_built.saturating_add(1);
            }
        }
        let crowd = self.crowds[p].as_ref()?;
        if !indexable(n.verts) {
            return None;
        }
        let key = crowd.key(outline(n.f.poly), n.verts)?;
        candidates.clear();
        crowd.candidates(key, candidates);
        Some(key)
    }

    /// Whether every shower of pixel `p` (if any) is a piece of polygon
    /// `poly`: a fragment of `poly` then needs no check, and no index.
    fn only_pieces_of(&self, p: usize, poly: u32) -> bool {
        !self.mixed[p] && self.showers[p].first().is_none_or(|c| c.poly == poly)
    }

    /// Builds the uncovered part and the map of a [`Status::Disjoint`] or
    /// [`Status::Covered`] pixel: the square minus each shower, and each
    /// shower's fragment as its visible part (they are pairwise disjoint,
    /// and their fragments lie in the pixel: a row's band stands for a
    /// fragment only in an open pixel).
    fn build_open(&mut self, p: usize, square: &[DVec2; 4], arena: &[DVec2], work: &mut Scratch) {
        let open = &mut self.open[p];
        let mut whole = work.pool.pop().unwrap_or_default();
        whole.clear();
        whole.extend_from_slice(square);
        open.pieces.push(whole);
        open.boxes.push(box_of(square));
        for (i, c) in self.showers[p].iter().enumerate() {
            let cv = shape(c.start, c.len, arena, square);
            cut_out(open, cv, &c.bb, square, false, work);
            let mut verts = work.pool.pop().unwrap_or_default();
            verts.clear();
            verts.extend_from_slice(cv);
            self.map[p].push(Owned {
                shower: i as u32,
                verts,
            });
        }
        self.status[p] = if open.pieces.is_empty() {
            Status::Closed
        } else {
            Status::Open
        };
        // Checked no more: a pixel with a map is not.
        self.crowds[p] = None;
    }

    /// Cuts `n` out of the uncovered part of an [`Status::Open`] pixel;
    /// twice the area it removed, and what it removed left in `work.hits`
    /// as convex pieces.
    fn cut(&mut self, p: usize, n: &Newcomer, square: &[DVec2; 4], work: &mut Scratch) -> f64 {
        let open = &mut self.open[p];
        let seen2 = cut_out(open, n.verts, &n.bb, square, true, work);
        if open.pieces.is_empty() {
            self.status[p] = Status::Closed;
        }
        seen2
    }

    /// Adds `n` as a shower of pixel `p` where it took the convex pieces
    /// `taken` (its pieces of the map), if they have an area; their vertex
    /// lists then go back to the pool, and `taken` is `work.hits` again.
    fn show_taken(
        &mut self,
        p: usize,
        n: &Newcomer,
        (px, py): (u32, u32),
        t: &Shown,
        work: &mut Scratch,
        mut taken: Vec<Vec<DVec2>>,
    ) {
        let area = 0.5 * taken.iter().map(|h| area2(h)).sum::<f64>();
        let shown = if area > AREA_EPS {
            paint_of(n, taken.iter().map(|h| &h[..]), (px, py), t, work)
        } else {
            None
        };
        if let Some(c) = shown {
            self.show(p, n, area, c);
            let shower = self.showers[p].len() as u32 - 1;
            let owned = taken.drain(..).map(|verts| Owned { shower, verts });
            self.map[p].extend(owned);
        }
        work.pool.append(&mut taken);
        work.hits = taken;
    }

    /// Adds a shower to pixel `p`.
    fn show(&mut self, p: usize, n: &Newcomer, area: f64, c: [f64; 3]) {
        let acc = &mut self.acc[p];
        for ch in 0..3 {
            acc[ch] += area * c[ch];
        }
        acc[3] += area;
        let shower = n.shower(c, area);
        let showers = &mut self.showers[p];
        if showers.first().is_some_and(|f| f.poly != shower.poly) {
            self.mixed[p] = true;
        }
        showers.push(shower);
        let fl = &mut self.floor[p];
        *fl = [fmin(fl[0], shower.q_lo), fmax(fl[1], shower.qc.abs())];
    }

    /// `n`, in front of a shower of pixel `p` somewhere they overlap, takes
    /// what it covers of the uncovered part and, from each shower, the part
    /// of its visible pieces where `n` is in front (see [`PixelStates`]);
    /// the showers' areas, colours and the pixel's sums follow.
    #[allow(clippy::too_many_arguments)]
    fn overtake(
        &mut self,
        p: usize,
        n: &Newcomer,
        (px, py): (u32, u32),
        square: &[DVec2; 4],
        t: &Shown,
        work: &mut Scratch,
    ) {
        if matches!(self.status[p], Status::Disjoint | Status::Covered) {
            self.build_open(p, square, t.arena, work);
        }
        if self.status[p] == Status::Open {
            self.cut(p, n, square, work);
        }
        // `n`'s part in front of each shower (an empty run where it has none):
        // `n` cut by the line where their nearness is equal, as the pairwise
        // subtraction cuts it.
        let Scratch {
            next,
            pool,
            occ,
            occ_of,
            a,
            b,
            hits,
            kept,
            cutter,
            texels,
            ..
        } = work;
        let showers = &mut self.showers[p];
        occ.clear();
        occ_of.clear();
        // The line's value at each vertex of `n`, found once for the tests
        // and the clip (`clip_line` found them again: it took 2.3% of a
        // whole run's instructions on 200,000 random triangles).
        let mut sides = [0.0f64; SPLIT_MAX];
        let m = n.verts.len();
        for (i, c) in showers.iter().enumerate() {
            if c.poly == n.f.poly {
                continue; // One polygon's pieces never overlap.
            }
            let at = occ.len();
            let d = front_of(n.l, &t.locals[c.poly as usize], n.qc, c.qc);
            let val = |v: &DVec2| d[0] * v.x + d[1] * v.y + d[2];
            if m <= SPLIT_MAX {
                let (mut all_in, mut all_out) = (true, true);
                for (s, v) in sides.iter_mut().zip(n.verts) {
                    *s = val(v);
                    all_in &= *s >= 0.0;
                    all_out &= *s <= 0.0;
                }
                if all_in {
                    occ.extend_from_slice(n.verts);
                } else if !all_out {
                    clip_sides(n.verts, &sides[..m], occ);
                }
            } else if n.verts.iter().all(|v| val(v) >= 0.0) {
                occ.extend_from_slice(n.verts);
            } else if !n.verts.iter().all(|v| val(v) <= 0.0) {
                clip_line(n.verts, d, occ);
            }
            if occ.len() - at < 3 || area2(&occ[at..]) <= 2.0 * AREA_EPS {
                occ.truncate(at);
            } else {
                occ_of.push((i as u32, at as u32, occ.len() as u32, bounds(&occ[at..])));
            }
        }
        // Each piece of the map loses that part to `n`. Only the pieces of
        // the showers `n` has a part in front of are visited: the map lists
        // each shower's pieces together, in the showers' order (asserted
        // below), so they are found by galloping on from the last shower's,
        // and replaced where they stand, so that the order is as if the
        // whole map had been walked.
        // Walked, it cost a pixel under k pieces of one concave polygon and
        // a triangle O(k) a fragment, O(k²) in all (a 30,000-vertex star and
        // one triangle, 16x16: 78% of the run in the walk).
        let map = &mut self.map[p];
        debug_assert!(map.windows(2).all(|w| w[0].shower <= w[1].shower));
        let pixel = box_of(square);
        let counted = texels.estimated;
        let (mut lost, mut gone) = (false, false);
        let mut cursor = 0;
        for &(shower, from, to, obb) in occ_of.iter() {
            let lo = cursor + gallop(&map[cursor..], |o| o.shower < shower);
            let hi = lo + gallop(&map[lo..], |o| o.shower <= shower);
            let o = &occ[from as usize..to as usize];
            kept.clear();
            let mut prepared = false;
            let mut cut = false;
            self.visited = self.visited.saturating_add((hi - lo) as u64);
            for piece in &mut map[lo..hi] {
                let verts = std::mem::take(&mut piece.verts);
                if boxes_apart(&bounds(&verts), &obb) {
                    kept.push(Owned { shower, verts });
                    continue;
                }
                if !prepared {
                    cutter.prepare(o, pixel);
                    prepared = true;
                }
                next.clear();
                match subtract_with(&verts, cutter, next, a, b, pool) {
                    None => kept.push(Owned { shower, verts }),
                    Some(s2) => {
                        cut = true;
                        if s2 > 0.0 {
                            // `subtract_with` leaves `piece ∩ o` in its `cur`.
                            let mut hit = pool.pop().unwrap_or_default();
                            hit.clear();
                            hit.extend_from_slice(a);
                            hits.push(hit);
                        }
                        kept.extend(next.drain(..).map(|verts| Owned { shower, verts }));
                        pool.push(verts);
                    }
                }
            }
            let end = lo + kept.len();
            map.splice(lo..hi, kept.drain(..));
            cursor = end;
            if !cut {
                continue;
            }
            lost = true;
            // Its new area and, if coloured by what shows, its new colour.
            let c = &mut showers[shower as usize];
            c.area = 0.5
                * map[lo..end]
                    .iter()
                    .fold(0.0, |sum, o| sum + area2(&o.verts));
            gone |= c.area <= AREA_EPS;
            if c.cut_later && c.area > AREA_EPS {
                // Counted as estimated when it first showed; what shows of it
                // now is a part of that.
                let l = &t.locals[c.poly as usize];
                let frag = if c.len == 0 {
                    &[][..]
                } else {
                    &t.arena[c.start as usize..(c.start + c.len) as usize]
                };
                let pieces = map[lo..end].iter().map(|o| &o.verts[..]);
                let recoloured = cut_texture(t, l, pieces, (px, py), frag, texels);
                c.color = recoloured.unwrap_or(c.color);
            }
        }
        texels.estimated = counted;
        if lost {
            self.overtaken = self.overtaken.saturating_add(1);
        }
        if gone {
            // Those left with no area are gone.
            let to = &mut work.renumbered;
            to.clear();
            let mut next = 0;
            for c in showers.iter() {
                to.push(if c.area > AREA_EPS { next } else { u32::MAX });
                next += u32::from(c.area > AREA_EPS);
            }
            showers.retain(|c| c.area > AREA_EPS);
            map.retain_mut(|o| {
                o.shower = to[o.shower as usize];
                if o.shower == u32::MAX {
                    work.pool.push(std::mem::take(&mut o.verts));
                }
                o.shower != u32::MAX
            });
        }
        let taken = std::mem::take(&mut work.hits);
        self.show_taken(p, n, (px, py), t, work, taken);
        if gone {
            // The least nearness and whether the showers are of one polygon
            // may have changed with those gone.
            let showers = &self.showers[p];
            self.mixed[p] = showers.iter().any(|c| c.poly != showers[0].poly);
            self.floor[p] = showers.iter().fold([f64::INFINITY, 0.0], |[lo, abs], c| {
                [fmin(lo, c.q_lo), fmax(abs, c.qc.abs())]
            });
        }
        // The colour sums are found again when the pixel is coloured, as
        // they would be here: summed in the showers' order, whatever
        // changed. Summed here, they cost each fragment O(k) again.
        self.stale[p] |= lost;
    }

    /// The pixel's area-weighted linear-light colour and its covered area:
    /// each sum over the showers in their order.
    pub(super) fn sums(&self, pixel: u32) -> [f64; 4] {
        let p = pixel as usize;
        if !self.stale[p] {
            return self.acc[p];
        }
        let mut acc = [0.0; 4];
        for c in &self.showers[p] {
            for ch in 0..3 {
                acc[ch] += c.area * c.color[ch];
            }
            acc[3] += c.area;
        }
        acc
    }

    /// The pixel's colour.
    pub(super) fn colour(&self, pixel: u32, bg: &Background, px: u32, py: u32) -> [f32; 3] {
        let [r, g, b, covered] = self.sums(pixel);
        blend_background([r, g, b], covered, bg, px, py)
    }
}

/// `v.partition_point(pred)`, found in steps doubling from the front: O(log
/// i) for the answer i, so that searches each starting where the last one
/// ended cost no more than one walk of `v` (a binary search from scratch
/// each would cost O(log n) each, more than the walk when `n` is in front
/// of most of a pixel's showers).
fn gallop<T>(v: &[T], pred: impl Fn(&T) -> bool) -> usize {
    // Everything before `lo` is known to satisfy `pred`.
    let (mut lo, mut step) = (0, 1);
    while lo + step <= v.len() && pred(&v[lo + step - 1]) {
        lo += step;
        step *= 2;
    }
    let hi = (lo + step).min(v.len());
    lo + v[lo..hi].partition_point(pred)
}

/// Cuts the convex `v` (bounding box `bb`) out of the convex pieces `open`
/// of the pixel `square`; twice the area it removed.
fn cut_out(
    open: &mut Uncovered,
    v: &[DVec2],
    bb: &[f64; 4],
    square: &[DVec2; 4],
    keep_hits: bool,
    work: &mut Scratch,
) -> f64 {
    if v == square {
        // The whole pixel: all that was open is seen.
        let seen2 = open.pieces.iter().map(|piece| area2(piece)).sum();
        if keep_hits {
            work.hits.append(&mut open.pieces);
        } else {
            work.pool.append(&mut open.pieces);
        }
        open.boxes.clear();
        return seen2;
    }
    let pixel = box_of(square);
    let mut seen2 = 0.0;
    let (next, next_boxes) = (&mut work.next, &mut work.next_boxes);
    next.clear();
    next_boxes.clear();
    // Found for the first piece `v` meets, and kept for the others.
    let mut prepared = false;
    for (piece, piece_bb) in open.pieces.drain(..).zip(open.boxes.drain(..)) {
        if boxes_apart(&piece_bb, bb) {
            next.push(piece);
            next_boxes.push(piece_bb);
            continue;
        }
        if !prepared {
            work.cutter.prepare(v, pixel);
            prepared = true;
        }
        let before = next.len();
        match subtract_with(
            &piece,
            &work.cutter,
            next,
            &mut work.a,
            &mut work.b,
            &mut work.pool,
        ) {
            None => {
                next.push(piece);
                next_boxes.push(piece_bb);
            }
            Some(s2) => {
                seen2 += s2;
                if keep_hits && s2 > 0.0 {
                    // `subtract_with` leaves `piece ∩ v` in its `cur`.
                    let mut hit = work.pool.pop().unwrap_or_default();
                    hit.clear();
                    hit.extend_from_slice(&work.a);
                    work.hits.push(hit);
                }
                next_boxes.extend(next[before..].iter().map(|r| bounds(r)));
                work.pool.push(piece);
            }
        }
    }
    std::mem::swap(&mut open.pieces, next);
    std::mem::swap(&mut open.boxes, next_boxes);
    seen2
}

/// Per-tile buffers of the per-pixel visibility, reused from pixel to pixel.
#[derive(Default)]
pub(super) struct Scratch {
    next: Vec<Vec<DVec2>>,
    next_boxes: Vec<[f64; 4]>,
    /// Vertex lists no longer in use, kept for their allocations: the convex
    /// subtraction makes and drops several small pieces per fragment pair, and
    /// recycling them keeps the allocator out of the inner loop.
    pub(super) pool: Vec<Vec<DVec2>>,
    a: Vec<DVec2>,
    b: Vec<DVec2>,
    /// An overtaking fragment's part in front of each shower, each one's
    /// run of `occ` and its box in `occ_of`.
    occ: Vec<DVec2>,
    occ_of: Vec<(u32, u32, u32, [f64; 4])>,
    /// A shower's pieces of the map as the overtake leaves them.
    kept: Vec<Owned>,
    /// Each shower's new index once those with no area left are gone.
    renumbered: Vec<u32>,
    /// The occluder's lines of the subtraction under way.
    cutter: Cutter,
    /// What a fragment's cut removed from the uncovered part (and took from
    /// the showers, when it overtakes): the convex pieces of it that show.
    hits: Vec<Vec<DVec2>>,
    /// The showers a fragment is checked against, from the pixel's index
    /// (`super::crowd`).
    candidates: Vec<u32>,
    /// Buffers of the texel cut of [`CUT_LATER`] fragments, and the count
    /// of those estimated.
    pub(super) texels: crate::texture::cells::Scratch,
}

/// The colour `n` shows with, where `visible` are the convex pieces of it
/// that show (read only for a [`Paint::CutLater`] one); `None` where it
/// shows no opaque area.
fn paint_of<'a>(
    n: &Newcomer,
    visible: impl IntoIterator<Item = &'a [DVec2]>,
    at: (u32, u32),
    t: &Shown,
    work: &mut Scratch,
) -> Option<[f64; 3]> {
    match n.paint {
        Paint::Known(c) => Some(c),
        Paint::FilterLater => Some(deferred_filter(t.polys, n.l, at.0, at.1)),
        Paint::CutLater => {
            let frag = if n.f.len == 0 { &[][..] } else { n.verts };
            cut_texture(t, n.l, visible, at, frag, &mut work.texels)
        }
    }
}

/// `c` under the smooth lighting of `l`'s polygon over its fragment `frag`
/// (empty: the whole pixel), as the fragments coloured when made are lit
/// ([`shade_factor`]).
fn lit(t: &Shown, l: &Local, at: (u32, u32), frag: &[DVec2], c: [f64; 3]) -> [f64; 3] {
    match shade_factor(&t.polys[l.global as usize], at, frag) {
        Some(f) => shaded(c, f),
        None => c,
    }
}

/// The box integral of the texture or the stripes of `l`'s polygon over
/// `visible`, pieces of pixel `(px, py)` of its fragment `frag` (empty: the
/// whole pixel), lit ([`crate::texture::cells::integrate`],
/// [`crate::stripe::StripeTexture::visible_linear`]); what either
/// estimated is counted in `texels`.
///
/// Smooth lighting: a texture's cell pieces each take the factor at their
/// own area centroid, so the product of texels and factor is integrated
/// exactly wherever the factor is affine on the screen (a parallel
/// projection). Stripes take the factor at the fragment's centroid, as
/// fragments coloured when made do ([`lit`]).
fn cut_texture<'a>(
    t: &Shown,
    l: &Local,
    visible: impl IntoIterator<Item = &'a [DVec2]>,
    (px, py): (u32, u32),
    frag: &[DVec2],
    texels: &mut crate::texture::cells::Scratch,
) -> Option<[f64; 3]> {
    let p = &t.polys[l.global as usize];
    if let Some(stripe) = p.stripe() {
        let (c, estimated) = stripe.visible_linear(px, py, visible)?;
        texels.estimated += estimated as u64;
        return Some(lit(t, l, (px, py), frag, c.map(f64::from)));
    }
    let tex = p.texture().expect("CUT_LATER fragments are textured");
    let factor = p.shade().map(|shade| {
        move |piece: &[DVec2]| {
            let c = crate::geom::polygon::area_centroid(piece)
                .unwrap_or_else(|| crate::geom::polygon::vertex_mean(piece));
            shade.at(c.x, c.y)
        }
    });
    let factor = factor.as_ref().map(|f| f as &dyn Fn(&[DVec2]) -> [f64; 3]);
    crate::texture::cells::integrate(visible, px, py, tex, factor, texels)
}

/// The `len` vertices from `start` in `arena`, or the pixel `square` for
/// `len == 0`: how fragments and showers name their shape.
fn shape<'a>(start: u32, len: u32, arena: &'a [DVec2], square: &'a [DVec2; 4]) -> &'a [DVec2] {
    if len == 0 {
        square
    } else {
        &arena[start as usize..(start + len) as usize]
    }
}

fn frag_verts<'a>(f: &Frag, arena: &'a [DVec2], square: &'a [DVec2; 4]) -> &'a [DVec2] {
    shape(f.start, f.len, arena, square)
}

/// `q_G - q_F` as an affine function, shifted by the tie rule: positive where G
/// is in front of F. The later polygon wins within [`tie_tolerance`] (painter's order).
/// `qg` and `qf` are `g.q(at)` and `f.q(at)` at the point the tie is decided
/// (the pixel centre), passed in because they are the same for every pair.
fn front_of(g: &Local, f: &Local, qg: f64, qf: f64) -> [f64; 3] {
    let d = [
        g.plane[0] - f.plane[0],
        g.plane[1] - f.plane[1],
        g.plane[2] - f.plane[2],
    ];
    let bias = tie_tolerance(qg, qf, g.tie_floor);
    let c = if g.order > f.order {
        d[2] + bias
    } else {
        d[2] - bias
    };
    [d[0], d[1], c]
}

/// What [`subtract_pairwise`] reads besides the fragments (each one's
/// nearness at the pixel centre, where the tie rule is evaluated, and
/// whether it is present) and what it finds: the visible area of each
/// fragment that shows.
#[cfg(test)]
#[derive(Default)]
pub(super) struct Pairwise {
    pub(super) qc: Vec<f64>,
    pub(super) alive: Vec<bool>,
    pub(super) seen: Vec<(u32, f64)>,
}

/// The visible area of each live fragment, in `s.seen` in `frags`' order: F
/// minus the part of every other fragment G in front of it (G cut by the
/// line where their nearness is equal, so a convex polygon), by convex
/// subtraction. Exact for any arrangement, interpenetration included, and
/// quadratic in the fragments: the tests' oracle for the sweep, which finds
/// the same areas front to back and overtakes where its order fails.
#[cfg(test)]
pub(super) fn subtract_pairwise(
    locals: &[Local],
    frags: &[Frag],
    arena: &[DVec2],
    square: &[DVec2; 4],
    s: &mut Pairwise,
) {
    let pixel = box_of(square);
    let (mut next, mut pool) = (Vec::new(), Vec::new());
    let (mut occ, mut a, mut b) = (Vec::new(), Vec::new(), Vec::new());
    s.seen.clear();
    for i in (0..frags.len()).filter(|&i| s.alive[i]) {
        let f = &frags[i];
        let fp = &locals[f.poly as usize];
        let mut pieces = vec![frag_verts(f, arena, square).to_vec()];
        for (j, g) in frags.iter().enumerate() {
            // One polygon's pieces never hide each other.
            if !s.alive[j] || g.poly == f.poly {
                continue;
            }
            let gv = frag_verts(g, arena, square);
            let d = front_of(&locals[g.poly as usize], fp, s.qc[j], s.qc[i]);
            if gv.iter().all(|v| d[0] * v.x + d[1] * v.y + d[2] <= 0.0) {
                continue; // G is behind F wherever G is.
            }
            occ.clear();
            clip_line(gv, d, &mut occ);
            if occ.len() < 3 || area2(&occ) <= 2.0 * AREA_EPS {
                continue;
            }
            let mut left = Vec::new();
            for piece in pieces {
                if subtract(&piece, &occ, pixel, &mut next, &mut a, &mut b, &mut pool).is_none() {
                    left.push(piece);
                }
                left.append(&mut next);
            }
            pieces = left;
        }
        let area: f64 = pieces.iter().map(|p| area2(p)).sum::<f64>() * 0.5;
        if area > AREA_EPS {
            s.seen.push((i as u32, area));
        }
    }
}

/// Adds the background over the part of the pixel no fragment covers.
pub(super) fn blend_background(
    mut acc: [f64; 3],
    covered: f64,
    bg: &Background,
    px: u32,
    py: u32,
) -> [f32; 3] {
    let rest = 1.0 - covered;
    if rest > AREA_EPS {
        let b = bg.at(px, py);
        for ch in 0..3 {
            acc[ch] += rest * b[ch];
        }
    }
    acc.map(|c| c as f32)
}

/// `a.min(b)` for numbers that are not NaN (screen geometry is finite by
/// construction: the stream rejects NaN and the clipper keeps `w > 0`). One
/// instruction, where `f64::min` and `f64::max` with their NaN handling took
/// 13% of `render_tile`'s samples in a profile of a deep scene.
#[inline(always)]
pub(super) fn fmin(a: f64, b: f64) -> f64 {
    if b < a {
        b
    } else {
        a
    }
}

/// `a.max(b)` for numbers that are not NaN; see [`fmin`].
#[inline(always)]
pub(super) fn fmax(a: f64, b: f64) -> f64 {
    if b > a {
        b
    } else {
        a
    }
}

/// Bounding box `[x0, y0, x1, y1]` of a vertex list.
pub(super) fn bounds(v: &[DVec2]) -> [f64; 4] {
    v.iter().fold(
        [f64::MAX, f64::MAX, f64::MIN, f64::MIN],
        |[x0, y0, x1, y1], p| [fmin(x0, p.x), fmin(y0, p.y), fmax(x1, p.x), fmax(y1, p.y)],
    )
}

/// The part of the convex `v` in the box `[x0, y0, x1, y1]`, into `out`
/// (`tmp` scratch), clipped as the fragments are made: rows first, then
/// columns, each crossing made from its inside endpoint.
pub(super) fn clip_to_box(
    v: &[DVec2],
    [x0, y0, x1, y1]: &[f64; 4],
    tmp: &mut Vec<DVec2>,
    out: &mut Vec<DVec2>,
) {
    tmp.clear();
    clip_axis(v, 1, *y0, true, tmp);
    out.clear();
    clip_axis(tmp, 1, *y1, false, out);
    tmp.clear();
    clip_axis(out, 0, *x0, true, tmp);
    out.clear();
    clip_axis(tmp, 0, *x1, false, out);
}

/// Whether a fragment may be left out of a check by an index: none of its
/// edges is shorter than [`EDGE_EPS`]. The separating-axis test skips
/// such an edge, so without the index two fragments apart only across one
/// were taken as overlapping, and cut, which removes nothing but can move
/// the last bit of a sum (a review built two polygons rounding their
/// corners at a hub with chains of 0.7e-9 pixel edges: one float32 step of
/// one pixel's PFM). Such a fragment is tested, not indexed, so the
/// check's decisions are those it made without the index.
fn indexable(frag: &[DVec2]) -> bool {
    let n = frag.len();
    (0..n).all(|i| separates((frag[if i + 1 == n { 0 } else { i + 1 }] - frag[i]).length()))
}

/// Whether [`disjoint`] tries an edge of length `len` as a separating
/// axis: one no longer than [`EDGE_EPS`] has a direction that is noise.
/// [`indexable`] asks the same question, so what the index leaves out is
/// what this test would find apart.
fn separates(len: f64) -> bool {
    len > EDGE_EPS
}

/// The index of `showers` by their cones at the vertex of `outline` (the
/// newcomer's polygon) that most of their polygons share, if at least half
/// of them do. `outline_of` gives a shower's polygon, `frag_of` its
/// fragment.
fn hub_of<'a>(
    showers: &[Shower],
    outline: Option<&[DVec2]>,
    outline_of: impl Fn(u32) -> Option<&'a [DVec2]>,
    frag_of: impl Fn(&Shower) -> &'a [DVec2],
) -> Option<Crowd> {
    // Each polygon's outline is searched once, not once a shower: the
    // pieces of a concave polygon come thousands to a pixel, and its outline
    // may have a million vertices (a 30,000-vertex star and a triangle at
    // 16x16 spent half its time here).
    let mut polys: Vec<u32> = showers.iter().map(|c| c.poly).collect();
    polys.sort_unstable();
    polys.dedup();
    let shared = |hub: &DVec2| {
        let at: Vec<bool> = (polys.iter())
            .map(|&poly| outline_of(poly).is_some_and(|v| v.contains(hub)))
            .collect();
        let at_hub = |c: &&Shower| polys.binary_search(&c.poly).is_ok_and(|i| at[i]);
        showers.iter().filter(at_hub).count()
    };
    let (count, hub) = outline
        .filter(|v| v.len() <= HUB_MAX_VERTICES)?
        .iter()
        .map(|h| (shared(h), *h))
        .max_by_key(|m| m.0)?;
    if 2 * count < showers.len() {
        return None;
    }
    let mut index = HubIndex::new(hub);
    for (i, c) in showers.iter().enumerate() {
        let cone = outline_of(c.poly).and_then(|v| cone_at(v, hub));
        index.insert(i as u32, cone.filter(|_| indexable(frag_of(c))));
    }
    Some(Crowd::Hub(index))
}

/// The index of `showers` by their fragments' spans (`frag_of`) on the
/// axis, of x, y and the normal to the longest edge of `outline` (the
/// newcomer's polygon, or its fragment), on which the most are at most
/// [`AXIS_MAX_WIDTH`] wide, if at least half of them are.
fn axis_of<'a>(
    showers: &[Shower],
    outline: &[DVec2],
    frag_of: impl Fn(&Shower) -> &'a [DVec2],
) -> Option<Crowd> {
    let edges = outline.iter().zip(outline.iter().cycle().skip(1));
    let longest = edges
        .map(|(a, b)| *b - *a)
        .max_by(|a, b| a.length_squared().total_cmp(&b.length_squared()))?;
    let across = longest.perp().normalize_or_zero();
    let narrow = |axis: DVec2| {
        let fits = |c: &&Shower| {
            let (lo, hi) = span(frag_of(c), axis);
            hi - lo <= AXIS_MAX_WIDTH
        };
        showers.iter().filter(fits).count()
    };
    let axes = [DVec2::X, DVec2::Y, across];
    let (count, axis) = axes
        .into_iter()
        .filter(|a| *a != DVec2::ZERO)
        .map(|a| (narrow(a), a))
        .max_by_key(|m| m.0)?;
    if 2 * count < showers.len() {
        return None;
    }
    let mut index = AxisIndex::new(axis);
    for (i, c) in showers.iter().enumerate() {
        let frag = frag_of(c);
        index.insert(i as u32, indexable(frag).then(|| span(frag, axis)));
    }
    Some(Crowd::Axis(index))
}

/// The box `[x0, y0, x1, y1]` of a pixel square.
fn box_of(square: &[DVec2; 4]) -> [f64; 4] {
    [square[0].x, square[0].y, square[2].x, square[2].y]
}

/// Whether two boxes share no interior (touching counts as apart).
fn boxes_apart(a: &[f64; 4], b: &[f64; 4]) -> bool {
    a[2] <= b[0] || b[2] <= a[0] || a[3] <= b[1] || b[3] <= a[1]
}

/// Whether two convex counter-clockwise polygons have no interior in common:
/// some edge of one has the whole other on its outer side (separating axis;
/// touching along an edge, within [`SEPARATION_EPS`], counts as disjoint).
fn disjoint(a: &[DVec2], b: &[DVec2]) -> bool {
    let separated = |p: &[DVec2], q: &[DVec2]| {
        let n = p.len();
        (0..n).any(|i| {
            let (s, e) = (p[i], p[if i + 1 == n { 0 } else { i + 1 }]);
            let dir = e - s;
            let len = dir.length();
            separates(len)
                && q.iter()
                    .all(|&v| dir.perp_dot(v - s) <= SEPARATION_EPS * len)
        })
    };
    separated(a, b) || separated(b, a)
}

/// Longest piece [`subtract_with`] splits in one pass (its sides on the stack);
/// longer ones, which a pixel's pieces never are in practice, are clipped
/// twice instead, with the same result.
const SPLIT_MAX: usize = 32;

/// Splits the convex `poly` by a line whose value at each vertex is
/// `sides`: the part where it is `>= 0` into `inside`, the part where it is
/// `<= 0` into `outside`. Bit for bit what `clip_line` gives with the line
/// and with its negation (negating a line negates its values exactly, and
/// each crossing is made from the same endpoint as there).
fn split(poly: &[DVec2], sides: &[f64], inside: &mut Vec<DVec2>, outside: &mut Vec<DVec2>) {
    let n = poly.len();
    if n == 0 {
        return;
    }
    let mut step = |a: DVec2, b: DVec2, da: f64, db: f64| {
        clip_step(a, b, da, db, inside);
        clip_step(a, b, -da, -db, outside);
    };
    // The edges in order, the closing one last: by pairs, with no index
    // wrapping round (that and the bounds checks were a third of this).
    for (v, d) in poly.windows(2).zip(sides.windows(2)) {
        step(v[0], v[1], d[0], d[1]);
    }
    step(poly[n - 1], poly[0], sides[n - 1], sides[0]);
}

/// Appends to `out` the part of the convex `poly` where a line is `>= 0`,
/// its value at each vertex being `sides`: bit for bit what `clip_line`
/// appends for that line (the same steps, edge by edge in its order).
fn clip_sides(poly: &[DVec2], sides: &[f64], out: &mut Vec<DVec2>) {
    let n = poly.len();
    if n == 0 {
        return;
    }
    for (v, d) in poly.windows(2).zip(sides.windows(2)) {
        clip_step(v[0], v[1], d[0], d[1], out);
    }
    clip_step(poly[n - 1], poly[0], sides[n - 1], sides[0], out);
}

/// One edge `a -> b` of a Sutherland–Hodgman pass keeping `d >= 0` (`da`,
/// `db` at its ends), pushing what `clip_line` pushes for it.
#[inline(always)]
fn clip_step(a: DVec2, b: DVec2, da: f64, db: f64, out: &mut Vec<DVec2>) {
    if da >= 0.0 {
        out.push(a);
        if db < 0.0 && da > 0.0 {
            out.push(a + (b - a) * (da / (da - db)));
        }
    } else if db > 0.0 {
        out.push(b + (a - b) * (db / (db - da)));
    }
}

/// [`subtract_with`], finding `o`'s [`Cutter`] itself (the tests' entry).
#[cfg(test)]
pub(super) fn subtract(
    p: &[DVec2],
    o: &[DVec2],
    pixel: [f64; 4],
    out: &mut Vec<Vec<DVec2>>,
    cur: &mut Vec<DVec2>,
    tmp: &mut Vec<DVec2>,
    pool: &mut Vec<Vec<DVec2>>,
) -> Option<f64> {
    let mut cutter = Cutter::default();
    cutter.prepare(o, pixel);
    subtract_with(p, &cutter, out, cur, tmp, pool)
}

/// The lines [`subtract_with`] cuts by, found once for an occluder `o` in
/// a pixel and kept for every piece of the pixel's uncovered part or map it
/// cuts: they were found again for each piece, its edges counted in a pass
/// of their own (3.8 million subtractions over 200,000 random triangles).
#[derive(Default)]
pub(super) struct Cutter {
    /// The lines of `o`'s edges that are not skipped, longest edge first.
    lines: Vec<[f64; 3]>,
    /// Fewer than three edges longer than [`EDGE_EPS`]: no interior.
    thin: bool,
}

impl Cutter {
    /// Makes this the cutter of `o` in the pixel `[x0, y0, x1, y1]`: the
    /// line of each edge of `o`, but for those no longer than [`EDGE_EPS`]
    /// (counted: fewer than three such edges leave `o` no interior) and
    /// those along a side of the pixel.
    fn prepare(&mut self, o: &[DVec2], [x0, y0, x1, y1]: [f64; 4]) {
        self.lines.clear();
        let mut edges = 0;
        let mut edge = |a: DVec2, b: DVec2| {
            let e = b - a;
            if e.length_squared() <= EDGE_EPS * EDGE_EPS {
                return;
            }
            edges += 1;
            if (e.x == 0.0 && (a.x == x0 || a.x == x1)) || (e.y == 0.0 && (a.y == y0 || a.y == y1))
            {
                return;
            }
            // Left of a->b: (b - a) x (p - a) >= 0, as a*x + b*y + c.
            self.lines.push([-e.y, e.x, e.y * a.x - e.x * a.y]);
        };
        // Every edge, the closing one last (sorted below).
        for w in o.windows(2) {
            edge(w[0], w[1]);
        }
        if let (Some(&first), Some(&last)) = (o.first(), o.last()) {
            edge(last, first);
        }
        self.thin = edges < 3;
        // Longest edge first (a line's (a, b) is its edge turned a quarter,
        // so its squared length is the edge's). `subtract_with` keeps what
        // lies beyond each line across all of the piece still being cut, so
        // a short edge's line, taken first, splits the whole piece; taken
        // after the long ones, only the narrow part between them. In a fan
        // of 2,748 interpenetrating slivers in two pixels the open pieces
        // otherwise multiply: 98 s to render, 23.5 s this way, the same
        // PNG (a hostile-input fuzz; test
        // `a_short_edge_cuts_only_what_the_long_ones_leave`). The pieces
        // cover the same region either way; their rounding differs, in
        // bench/same_images.sh at most 2.98e-8 in a PFM, no 8-bit byte.
        self.lines
            .sort_by(|a, b| (b[0] * b[0] + b[1] * b[1]).total_cmp(&(a[0] * a[0] + a[1] * a[1])));
    }
}

/// Appends the convex pieces of `p \ o` (both convex, counter-clockwise;
/// `cutter` is `o`'s in the pixel, [`Cutter::prepare`]) to `out`: for each
/// edge of `o`, longest first, the part of `p` to its right is outside
/// `o` and kept; the rest goes on to the next edge, and what is left at the
/// end lies in `o` and is dropped. New pieces take their vertex lists from
/// `pool`.
/// Returns twice the area of what was dropped, `p ∩ o`; or `None`, with
/// nothing appended, where `p` lies wholly outside `o` (or `o` has no
/// interior): `p \ o` is then `p` itself, which the caller keeps without a
/// copy.
///
/// An `o` with fewer than three edges longer than [`EDGE_EPS`] has no
/// interior and removes nothing (without this check, all of `p` would be
/// "left at the end" and dropped).
///
/// `p` lies in the pixel `[x0, y0, x1, y1]`: an edge of `o` along a side of
/// it (exactly, as the axis clipping makes them) has all of `p` inside and
/// is skipped. A fragment's pixel-border edges are half of its edges.
///
/// Where `cur` lies strictly on one side of an edge's line, the two clips
/// would return `cur` unchanged and nothing (or nothing and `cur`): that case
/// is decided from the signs alone and the clips are skipped. The signs are
/// the very values `clip_line` computes (negating a line negates them
/// exactly in IEEE arithmetic), so the pieces are bit for bit the same.
fn subtract_with(
    p: &[DVec2],
    cutter: &Cutter,
    out: &mut Vec<Vec<DVec2>>,
    cur: &mut Vec<DVec2>,
    tmp: &mut Vec<DVec2>,
    pool: &mut Vec<Vec<DVec2>>,
) -> Option<f64> {
    if cutter.thin {
        return None;
    }

    let keep = |piece: &[DVec2], out: &mut Vec<Vec<DVec2>>, pool: &mut Vec<Vec<DVec2>>| {
        let mut v = pool.pop().unwrap_or_default();
        v.clear();
        v.extend_from_slice(piece);
        out.push(v);
    };
    cur.clear();
    cur.extend_from_slice(p);
    // Whether `cur` is no longer `p`.
    let mut cut = false;
    // Each vertex's side of a line, computed once (kept for the split when
    // the piece fits on the stack); only those of `cur` are read.
    let mut sides = [0.0f64; SPLIT_MAX];
    for &line in &cutter.lines {
        if cur.len() < 3 {
            return Some(0.0);
        }
        let side = |v: &DVec2| line[0] * v.x + line[1] * v.y + line[2];
        let m = cur.len();
        let (inside, outside) = if m > SPLIT_MAX {
            (
                cur.iter().all(|v| side(v) > 0.0),
                cur.iter().all(|v| side(v) < 0.0),
            )
        } else {
            let (mut inside, mut outside) = (true, true);
            for (d, v) in sides.iter_mut().zip(cur.iter()) {
                *d = side(v);
                inside &= *d > 0.0;
                outside &= *d < 0.0;
            }
            (inside, outside)
        };
        if inside {
            continue; // Wholly inside this edge: nothing outside it.
        }
        if outside {
            // Wholly outside this edge, so outside `o`: kept whole.
            if !cut {
                return None;
            }
            if area2(cur) > 2.0 * AREA_EPS {
                keep(cur, out, pool);
            }
            return Some(0.0);
        }
        cut = true;
        if m > SPLIT_MAX {
            tmp.clear();
            clip_line(cur, [-line[0], -line[1], -line[2]], tmp);
            if tmp.len() >= 3 && area2(tmp) > 2.0 * AREA_EPS {
                keep(tmp, out, pool);
            }
            tmp.clear();
            clip_line(cur, line, tmp);
        } else {
            // The same two clips in one pass.
            let mut part = pool.pop().unwrap_or_default();
            part.clear();
            tmp.clear();
            split(cur, &sides[..m], tmp, &mut part);
            if part.len() >= 3 && area2(&part) > 2.0 * AREA_EPS {
                out.push(part);
            } else {
                pool.push(part);
            }
        }
        std::mem::swap(cur, tmp);
    }
    Some(if cur.len() < 3 { 0.0 } else { area2(cur) })
}

#[cfg(test)]
mod debris {
    use super::*;

    fn v(x: f64, y: f64) -> DVec2 {
        DVec2::new(x, y)
    }

    #[test]
    fn near_duplicate_vertices_neither_separate_nor_cut() {
        // Clipping leaves a crossing a hair from a vertex: a tiny edge whose
        // direction is noise. It must not make overlapping polygons "disjoint"
        // nor keep the whole polygon as "outside" the occluder.
        let tri = [v(0.0, 0.0), v(1.0, 0.0), v(0.0, 1.0)];
        let with_debris = [
            v(0.0, 0.0),
            v(1.0, 0.0),
            v(1.0, 0.0),
            v(1.0 - 1e-14, 1e-14),
            v(0.0, 1.0),
        ];
        let small = [v(0.1, 0.1), v(0.3, 0.1), v(0.1, 0.3)];
        assert!(!disjoint(&with_debris, &small));
        assert!(!disjoint(&small, &with_debris));
        let (mut out, mut a, mut b, mut pool) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
        // A box wider than the shapes: no edge of theirs lies on its sides.
        let wide = [-1.0, -1.0, 2.0, 2.0];
        let cut = subtract(
            &small,
            &with_debris,
            wide,
            &mut out,
            &mut a,
            &mut b,
            &mut pool,
        );
        assert!(cut.is_some(), "the debris hides the small triangle");
        let left: f64 = out.iter().map(|p| area2(p)).sum();
        assert!(left.abs() < 1e-12, "{out:?}");
        out.clear();
        let cut = subtract(&tri, &tri, wide, &mut out, &mut a, &mut b, &mut pool);
        assert!(cut.is_some());
        assert!(out.iter().map(|p| area2(p)).sum::<f64>().abs() < 1e-12);
    }

    #[test]
    fn a_short_edge_cuts_only_what_the_long_ones_leave() {
        // A sliver whose short edge comes first in its own order. Cut by
        // that edge's line (x + y = 1.4) first, the square's whole corner
        // beyond it would be one piece (area 0.18) and the sliver's long
        // edges would cut the rest; longest first, the short edge cuts
        // only the wedge between them.
        let sliver = [v(0.9, 0.5), v(0.88, 0.52), v(0.1, 0.1)];
        let square = pixel_square(0, 0);
        let (mut out, mut a, mut b, mut pool) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
        let pixel = [0.0, 0.0, 1.0, 1.0];
        let cut = subtract(&square, &sliver, pixel, &mut out, &mut a, &mut b, &mut pool);
        let hidden2 = cut.expect("the sliver lies in the square");
        let sliver2 = area2(&sliver);
        assert!((hidden2 - sliver2).abs() < 1e-15, "{hidden2} {sliver2}");
        let left2: f64 = out.iter().map(|p| area2(p)).sum();
        assert!((left2 + hidden2 - 2.0).abs() < 1e-15, "{left2}");
        // Wholly beyond the short edge's line (to its right, or on it):
        // one piece, a sliver of the wedge.
        let [ax, ay] = [0.9, 0.5];
        let beyond = |p: &DVec2| (0.88 - ax) * (p.y - ay) - (0.52 - ay) * (p.x - ax) <= 1e-12;
        let far: Vec<_> = out.iter().filter(|p| p.iter().all(beyond)).collect();
        assert_eq!(far.len(), 1, "{out:?}");
        assert!(
            area2(far[0]) < 0.01,
            "{:?}: area {}",
            far[0],
            area2(far[0]) / 2.0
        );
    }
}

#[cfg(test)]
mod tests {
    use super::gallop;
    use proptest::prelude::*;

    proptest! {
        /// The galloping search is the binary one, from any start of a
        /// sorted list (each search of the overtake starts where the last
        /// one ended).
        #[test]
        fn gallop_finds_what_partition_point_finds(
            mut v in proptest::collection::vec(0u32..40, 0..200),
            key in 0u32..42,
        ) {
            v.sort_unstable();
            for start in 0..=v.len() {
                let rest = &v[start..];
                prop_assert_eq!(gallop(rest, |&x| x < key), rest.partition_point(|&x| x < key));
                prop_assert_eq!(gallop(rest, |&x| x <= key), rest.partition_point(|&x| x <= key));
            }
        }
    }
}
