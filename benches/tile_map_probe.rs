//! A design probe for issue "Performance at scale", item 1 (a table, not a
//! timed test; not run in CI): would exact anti-aliasing be cheaper if
//! visibility were decided per tile between whole triangles, and the visible
//! map then integrated over the pixels by signed area, instead of cutting
//! every polygon into pixel fragments first (`raster::visible`)?
//!
//! For flat triangles under scene-render's default view (pixel coordinates,
//! nearness growing with z), as `bench/random_triangles.py` writes them, it
//! times, on one thread:
//!
//! 1. *Integration alone*: every triangle added to a frame buffer by signed
//!    area, colour-weighted, one pass over each edge row by row and a prefix
//!    sum along each row, as font rasterizers accumulate coverage. No
//!    visibility: the cost of this half of the route.
//! 2. *The tile map*: per 32-pixel tile, the triangles clipped to the tile,
//!    nearest first by their nearest point; the map is convex pieces (the
//!    uncovered part is a piece behind everything), found through a grid of
//!    4-pixel cells; each newcomer takes from each piece the part where it is
//!    in front (the overtake of `PixelStates`, with the tile for the pixel).
//!    Then the map's pieces are integrated as in 1. With a reference PAM
//!    (scene-render `--aa exact --size 1024x768 --background 20,20,80`), it
//!    counts the bytes of its own 8-bit image that differ.
//!
//! It knows nothing of ties, textures or lighting, and is not a renderer:
//! `bench/RESULTS-aa-scaling.md` (*The floor of the per-pixel design*) keeps
//! what it found.
//!
//! Run: `cargo bench --bench tile_map_probe -- SCENE.ndjson [REFERENCE.pam]`.

use glam::DVec2;
use patkit::geom::polygon::{area2, clip_axis, clip_line, AREA_EPS};
use std::time::Instant;

type P = DVec2;
const W: usize = 1024;
const H: usize = 768;
const TILE: usize = 32;
/// The side of a cell of a tile's grid of pieces, in pixels.
const CELL: usize = 4;
const CELLS: usize = TILE / CELL;
/// scene-render's `--background 20,20,80`.
const BACKGROUND: [u8; 3] = [20, 20, 80];

struct Triangle {
    verts: [P; 3],
    /// Nearness `q = a x + b y + c` over the screen (the vertices' z).
    plane: [f64; 3],
    linear: [f64; 3],
}

/// The scene's triangles, read as scene-render reads them; those with no
/// area on the screen are left out.
fn read(path: &str) -> Vec<Triangle> {
    let file = std::fs::File::open(path).unwrap_or_else(|e| panic!("{path}: {e}"));
    let decode = patkit::color::decode_table_f64();
    let mut out = Vec::new();
    patkit::stream::for_each_record(std::io::BufReader::new(file), path, |r| {
        let patkit::geom::Shape::Polygon(v) = r.shape else {
            panic!("{path}: only polygons")
        };
        assert_eq!(v.len(), 3, "{path}: only triangles");
        let c = r.color.expect("flat colours");
        let verts = [v[0], v[1], v[2]].map(|p| p.truncate());
        if let Some(plane) = plane_of(&[v[0], v[1], v[2]].map(|p| [p.x, p.y, p.z])) {
            let linear = c.0.map(|u| decode[u as usize]);
            out.push(Triangle {
                verts,
                plane,
                linear,
            });
        }
        Ok::<(), patkit::stream::StreamError>(())
    })
    .unwrap_or_else(|e| panic!("{e}"));
    out
}

/// z as an affine function of x and y through the three vertices.
fn plane_of(t: &[[f64; 3]; 3]) -> Option<[f64; 3]> {
    let (a, b, c) = (t[0], t[1], t[2]);
    let u = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
    let v = [c[0] - a[0], c[1] - a[1], c[2] - a[2]];
    let nz = u[0] * v[1] - u[1] * v[0];
    if nz.abs() < 1e-12 {
        return None;
    }
    let nx = u[1] * v[2] - u[2] * v[1];
    let ny = u[2] * v[0] - u[0] * v[2];
    let (zx, zy) = (-nx / nz, -ny / nz);
    Some([zx, zy, a[2] - zx * a[0] - zy * a[1]])
}

fn bbox(v: &[P]) -> [f64; 4] {
    v.iter()
        .fold([f64::MAX, f64::MAX, f64::MIN, f64::MIN], |b, p| {
            [
                b[0].min(p[0]),
                b[1].min(p[1]),
                b[2].max(p[0]),
                b[3].max(p[1]),
            ]
        })
}

fn apart(a: &[f64; 4], b: &[f64; 4]) -> bool {
    a[2] <= b[0] || b[2] <= a[0] || a[3] <= b[1] || b[3] <= a[1]
}

/// The convex pieces of `p \ o` (`o` convex, counter-clockwise) into `out`,
/// and `p ∩ o` left in `inside`; `false`, with nothing pushed, where `p`
/// misses `o`. (The renderer's own, `raster::visible::subtract`, is
/// private to it.)
fn subtract(
    p: &[P],
    o: &[P],
    out: &mut Vec<Vec<P>>,
    inside: &mut Vec<P>,
    tmp: &mut Vec<P>,
) -> bool {
    inside.clear();
    inside.extend_from_slice(p);
    let mut cut = false;
    for i in 0..o.len() {
        let (a, b) = (o[i], o[(i + 1) % o.len()]);
        let l = [
            a[1] - b[1],
            b[0] - a[0],
            (b[1] - a[1]) * a[0] - (b[0] - a[0]) * a[1],
        ];
        let side = |v: &P| l[0] * v[0] + l[1] * v[1] + l[2];
        let any_in = inside.iter().any(|v| side(v) > 0.0);
        if !inside.iter().any(|v| side(v) < 0.0) {
            continue;
        }
        if !any_in {
            if !cut {
                inside.clear();
                return false;
            }
            out.push(std::mem::take(inside));
            return true;
        }
        tmp.clear();
        clip_line(inside, [-l[0], -l[1], -l[2]], tmp);
        if tmp.len() >= 3 && area2(tmp) > 2.0 * AREA_EPS {
            out.push(tmp.clone());
        }
        cut = true;
        tmp.clear();
        clip_line(inside, l, tmp);
        std::mem::swap(inside, tmp);
        if inside.len() < 3 {
            inside.clear();
            return true;
        }
    }
    true
}

/// Adds the signed area of edge `a -> b` of a counter-clockwise polygon,
/// times `c`, to `cells`: `rows` rows of `width` columns from origin `o`,
/// each row two cells longer (the part of the edge's row right of the last
/// column lands there). A row's cells take the differences of the edge's
/// coverage of the pixels (each pixel's share right of the edge, averaged
/// over the row), so a prefix sum along the row gives each pixel's area.
/// Points are clamped into the cells, which the callers' geometry lies in.
fn edge(cells: &mut [[f64; 3]], (width, rows): (usize, usize), o: P, a: P, b: P, c: [f64; 3]) {
    let (stride, right) = (width + 2, width as f64);
    let k = |v: f64, hi: f64| v.clamp(0.0, hi);
    let (a, b) = (
        DVec2::new(k(a.x - o.x, right), k(a.y - o.y, rows as f64)),
        DVec2::new(k(b.x - o.x, right), k(b.y - o.y, rows as f64)),
    );
    let (a, b, sign) = match a[1].partial_cmp(&b[1]) {
        Some(std::cmp::Ordering::Less) => (a, b, -1.0),
        Some(std::cmp::Ordering::Greater) => (b, a, 1.0),
        _ => return,
    };
    let dxdy = (b[0] - a[0]) / (b[1] - a[1]);
    let mut x = a[0];
    for row in a[1].floor() as usize..(b[1].ceil() as usize).min(rows) {
        let dy = (row as f64 + 1.0).min(b[1]) - (row as f64).max(a[1]);
        let next = (x + dxdy * dy).clamp(0.0, right);
        let d = sign * dy;
        let mut add = |i: usize, w: f64| {
            let cell = &mut cells[row * stride + i];
            for ch in 0..3 {
                cell[ch] += w * c[ch];
            }
        };
        let (lo, hi) = (x.min(next), x.max(next));
        let (i0, i1) = (lo.floor() as usize, hi.ceil() as usize);
        if i1 <= i0 + 1 {
            // Within one column: the part right of the edge's middle is carried.
            let f = 0.5 * (x + next) - i0 as f64;
            add(i0, d * (1.0 - f));
            add(i0 + 1, d * f);
        } else {
            // Across columns, with the edge's x uniform over [lo, hi] (`s` per
            // unit): pixel j's coverage is s (1 - f0)² / 2 for the first,
            // s (j + 1/2 - lo) between, 1 - s f1² / 2 for the last-but-one
            // (f1 how far the edge goes into the last column) and 1 after.
            let s = 1.0 / (hi - lo);
            let f0 = lo - i0 as f64;
            let first = 0.5 * s * (1.0 - f0) * (1.0 - f0);
            let f1 = hi - i1 as f64 + 1.0;
            let last = 0.5 * s * f1 * f1;
            add(i0, d * first);
            let mut sum = first;
            for i in i0 + 1..i1 - 1 {
                let upto = s * (i as f64 + 0.5 - lo);
                add(i, d * (upto - sum));
                sum = upto;
            }
            add(i1 - 1, d * (1.0 - last - sum));
            add(i1, d * last);
        }
        x = next;
    }
}

/// Counter-clockwise vertices of a triangle.
fn ccw(t: &Triangle) -> [P; 3] {
    let v = t.verts;
    if area2(&v) < 0.0 {
        [v[2], v[1], v[0]]
    } else {
        v
    }
}

/// Measure 1, every triangle integrated over the frame, no visibility: the median
/// of three runs (the first also meets the buffer's pages), in seconds.
fn integrate_alone(tris: &[Triangle]) {
    let mut runs: Vec<f64> = (0..3).map(|_| integrate_once(tris)).collect();
    runs.sort_by(f64::total_cmp);
    println!("  integration alone: {:.3} s, median of 3", runs[1]);
}

/// One run of [`integrate_alone`]; checks the coverage against the areas.
fn integrate_once(tris: &[Triangle]) -> f64 {
    // Counter-clockwise, in tile order, side by side in memory, as a
    // renderer that bins by tiles meets them.
    let mut order: Vec<[P; 3]> = tris.iter().map(ccw).collect();
    order.sort_by_key(|v| {
        let c = [0, 1].map(|k| (v.iter().map(|p| p[k]).sum::<f64>() / 3.0).max(0.0));
        ((c[1] / TILE as f64) as u32, (c[0] / TILE as f64) as u32)
    });
    // A margin for the triangles that reach out of the frame.
    let pad = 64;
    let (width, rows) = (W + 2 * pad, H + 2 * pad);
    let stride = width + 2;
    let start = Instant::now();
    let mut cells = vec![[0.0; 3]; stride * rows];
    let o = DVec2::splat(-(pad as f64));
    for v in order {
        for i in 0..3 {
            // Colour 1 in each channel: as much arithmetic as a colour, and
            // the coverage checks against the triangles' areas.
            edge(&mut cells, (width, rows), o, v[i], v[(i + 1) % 3], [1.0; 3]);
        }
    }
    let mut covered = 0.0;
    for row in cells.chunks_exact(stride) {
        let mut run = 0.0;
        for c in row {
            run += c[0];
            covered += run;
        }
    }
    let seconds = start.elapsed().as_secs_f64();
    let areas: f64 = tris.iter().map(|t| 0.5 * area2(&t.verts).abs()).sum();
    assert!(
        (covered - areas).abs() <= 1e-9 * areas,
        "coverage {covered} px², the triangles' areas {areas}"
    );
    seconds
}

struct Piece {
    verts: Vec<P>,
    bb: [f64; 4],
    /// `None` for the uncovered part, behind everything.
    plane: Option<[f64; 3]>,
    linear: [f64; 3],
    alive: bool,
}

/// One tile's map and the grid that finds its pieces.
struct TileMap {
    origin: P,
    pieces: Vec<Piece>,
    grid: Vec<Vec<u32>>,
    /// The newcomer each piece was last met by.
    met: Vec<u32>,
}

impl TileMap {
    fn cells_of(&self, bb: &[f64; 4]) -> impl Iterator<Item = usize> {
        let c = |v: f64, o: f64| (((v - o) / CELL as f64).max(0.0) as usize).min(CELLS - 1);
        let (x0, y0) = (c(bb[0], self.origin[0]), c(bb[1], self.origin[1]));
        let (x1, y1) = (c(bb[2], self.origin[0]), c(bb[3], self.origin[1]));
        (y0..=y1).flat_map(move |y| (x0..=x1).map(move |x| y * CELLS + x))
    }

    fn add(&mut self, verts: Vec<P>, plane: Option<[f64; 3]>, linear: [f64; 3]) {
        let id = self.pieces.len() as u32;
        let bb = bbox(&verts);
        for cell in self.cells_of(&bb).collect::<Vec<_>>() {
            self.grid[cell].push(id);
        }
        self.pieces.push(Piece {
            verts,
            bb,
            plane,
            linear,
            alive: true,
        });
        self.met.push(u32::MAX);
    }
}

#[derive(Default)]
struct Counts {
    visibility: f64,
    integration: f64,
    pieces: u64,
    cuts: u64,
}

/// Measure 2, the tile map: the frame's linear colours, bottom row first.
fn tile_map(tris: &[Triangle], counts: &mut Counts) -> Vec<[f64; 3]> {
    let (tw, th) = (W / TILE, H / TILE);
    let mut bins = vec![Vec::new(); tw * th];
    for (i, t) in tris.iter().enumerate() {
        let bb = bbox(&t.verts);
        let f = |v: f64, n: usize| ((v / TILE as f64).max(0.0) as usize).min(n - 1);
        for ty in f(bb[1], th)..=f(bb[3], th) {
            for tx in f(bb[0], tw)..=f(bb[2], tw) {
                bins[ty * tw + tx].push(i);
            }
        }
    }
    let bg = BACKGROUND.map(|u| patkit::color::decode_table_f64()[u as usize]);
    let mut frame = vec![[0.0; 3]; W * H];
    let (mut tmp, mut inside, mut taken) = (Vec::new(), Vec::new(), Vec::new());
    let mut rest: Vec<Vec<P>> = Vec::new();
    for (tile, bin) in bins.iter().enumerate() {
        let start = Instant::now();
        let o = DVec2::new((tile % tw * TILE) as f64, (tile / tw * TILE) as f64);
        let (x1, y1) = (o.x + TILE as f64, o.y + TILE as f64);
        let mut map = TileMap {
            origin: o,
            pieces: Vec::new(),
            grid: vec![Vec::new(); CELLS * CELLS],
            met: Vec::new(),
        };
        let square = vec![
            o,
            DVec2::new(x1, o.y),
            DVec2::new(x1, y1),
            DVec2::new(o.x, y1),
        ];
        map.add(square, None, bg);
        let mut order = Vec::new();
        for &i in bin {
            let mut v = ccw(&tris[i]).to_vec();
            // Cut to the tile, the crossings on its sides exactly.
            for (axis, value, keep_above) in [
                (0, o.x, true),
                (0, x1, false),
                (1, o.y, true),
                (1, y1, false),
            ] {
                tmp.clear();
                clip_axis(&v, axis, value, keep_above, &mut tmp);
                std::mem::swap(&mut v, &mut tmp);
            }
            if v.len() >= 3 && area2(&v) > 2.0 * AREA_EPS {
                let p = tris[i].plane;
                let nearest = v.iter().map(|q| p[0] * q[0] + p[1] * q[1] + p[2]);
                order.push((nearest.fold(f64::MIN, f64::max), i, v));
            }
        }
        order.sort_by(|a, b| b.0.total_cmp(&a.0));
        for (n, (_, i, v)) in order.into_iter().enumerate() {
            let t = &tris[i];
            let bb = bbox(&v);
            for cell in map.cells_of(&bb).collect::<Vec<_>>() {
                let ids = std::mem::take(&mut map.grid[cell]);
                for &id in &ids {
                    let pc = &map.pieces[id as usize];
                    if map.met[id as usize] == n as u32 || !pc.alive || apart(&pc.bb, &bb) {
                        continue;
                    }
                    map.met[id as usize] = n as u32;
                    // The newcomer's part in front of this piece.
                    let front = match pc.plane {
                        None => v.clone(),
                        Some(q) => {
                            let d = [0, 1, 2].map(|k| t.plane[k] - q[k]);
                            let val = |p: &P| d[0] * p[0] + d[1] * p[1] + d[2];
                            if v.iter().all(|p| val(p) >= 0.0) {
                                v.clone()
                            } else if v.iter().all(|p| val(p) <= 0.0)
                                || pc.verts.iter().all(|p| val(p) <= 0.0)
                            {
                                continue;
                            } else {
                                let mut f = Vec::new();
                                clip_line(&v, d, &mut f);
                                if f.len() < 3 || area2(&f) <= 2.0 * AREA_EPS {
                                    continue;
                                }
                                f
                            }
                        }
                    };
                    counts.cuts += 1;
                    rest.clear();
                    if !subtract(&pc.verts, &front, &mut rest, &mut inside, &mut tmp) {
                        continue;
                    }
                    if inside.len() >= 3 && area2(&inside) > 2.0 * AREA_EPS {
                        taken.push(std::mem::take(&mut inside));
                    }
                    let (plane, linear) = (pc.plane, pc.linear);
                    map.pieces[id as usize].alive = false;
                    // What is left lies outside the newcomer's part: not
                    // met again by it (the two sides of a cut are made
                    // from different endpoints, so they may overlap by a
                    // rounding, and a remainder met again would be cut
                    // again without end).
                    for piece in rest.drain(..) {
                        map.add(piece, plane, linear);
                        *map.met.last_mut().expect("just added") = n as u32;
                    }
                }
                // Pieces added to this cell meanwhile are kept after the old.
                let added = std::mem::replace(&mut map.grid[cell], ids);
                map.grid[cell].extend(added);
                let pieces = &map.pieces;
                map.grid[cell].retain(|&id| pieces[id as usize].alive);
            }
            for piece in taken.drain(..) {
                map.add(piece, Some(t.plane), t.linear);
            }
        }
        let integrating = Instant::now();
        counts.visibility += (integrating - start).as_secs_f64();
        let stride = TILE + 2;
        let mut cells = vec![[0.0; 3]; stride * TILE];
        for pc in map.pieces.iter().filter(|p| p.alive) {
            counts.pieces += 1;
            for k in 0..pc.verts.len() {
                let b = pc.verts[(k + 1) % pc.verts.len()];
                edge(&mut cells, (TILE, TILE), o, pc.verts[k], b, pc.linear);
            }
        }
        for (r, row) in cells.chunks_exact(stride).enumerate() {
            let mut run = [0.0; 3];
            let at = (o[1] as usize + r) * W + o[0] as usize;
            for (c, px) in row[..TILE].iter().zip(&mut frame[at..at + TILE]) {
                for ch in 0..3 {
                    run[ch] += c[ch];
                }
                *px = run;
            }
        }
        counts.integration += integrating.elapsed().as_secs_f64();
    }
    frame
}

/// The bytes of `frame` encoded as scene-render encodes (top row first)
/// that differ from the PAM `reference`'s, by how much: (count, largest).
fn compare(frame: &[[f64; 3]], reference: &str) -> (usize, u8) {
    let bytes = std::fs::read(reference).unwrap_or_else(|e| panic!("{reference}: {e}"));
    let end = b"ENDHDR\n";
    let at = bytes
        .windows(end.len())
        .position(|w| w == end)
        .expect("a PAM")
        + end.len();
    let (mut differ, mut most) = (0, 0);
    let ours = (0..H).rev().flat_map(|y| frame[y * W..(y + 1) * W].iter());
    let ours = ours.flat_map(|px| px.map(|c| patkit::color::linear_to_srgb(c as f32)));
    for (a, &b) in ours.zip(&bytes[at..]) {
        if a != b {
            differ += 1;
            most = most.max(a.abs_diff(b));
        }
    }
    (differ, most)
}

fn main() {
    let args: Vec<String> = std::env::args()
        .skip(1)
        .filter(|a| a != "--bench")
        .collect();
    let Some(scene) = args.first() else {
        eprintln!("usage: cargo bench --bench tile_map_probe -- SCENE.ndjson [REFERENCE.pam]");
        std::process::exit(2);
    };
    let tris = read(scene);
    println!("{scene}: {} triangles", tris.len());
    integrate_alone(&tris);
    let mut counts = Counts::default();
    let frame = tile_map(&tris, &mut counts);
    println!(
        "  tile map: visibility {:.3} s, integration {:.3} s; {} visible pieces after {} cuts",
        counts.visibility, counts.integration, counts.pieces, counts.cuts
    );
    if let Some(reference) = args.get(1) {
        let (differ, most) = compare(&frame, reference);
        println!("  against {reference}: {differ} bytes differ, by at most {most}");
    }
}
