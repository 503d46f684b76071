//! Palette indices of an indexed picture against its palette, checked once
//! the picture has decoded. The decoders expand an index past the palette
//! without a word: the `png` crate and the `image` crate's BMP decoder to
//! opaque black (their tables have 256 entries, the missing ones black),
//! the `gif` crate to transparent. The PNG specification (11.2.3, PLTE)
//! makes such an index an error, and libpng reports it. A hostile-input
//! review found a two-colour palette's index 5 drawn black, in PNG and BMP
//! (plain and RLE), and transparent in GIF.

/// The first palette index past the palette, and where it is.
#[derive(Debug, PartialEq, Eq)]
pub(super) struct PastPalette {
    pub(super) index: u8,
    /// Entries in the palette.
    pub(super) colours: usize,
    /// Its pixel (0-based, row 0 at the top).
    pub(super) x: u32,
    pub(super) y: u32,
}

/// The first pixel of an indexed PNG, GIF (its first frame, the one the
/// tools read) or BMP whose index is past its palette, in reading order;
/// `None` for any other picture, for a palette with every index the bit
/// depth can write (the common case: nothing is decoded again), and for
/// bytes the decoder refuses (the caller has decoded them already).
pub(super) fn first_past_palette(bytes: &[u8]) -> Option<PastPalette> {
    match bytes.get(..4)? {
        b"\x89PNG" => png_past_palette(bytes),
        b"GIF8" => gif_past_palette(bytes),
        [b'B', b'M', ..] => bmp_past_palette(bytes),
        _ => None,
    }
}

/// The first index past the palette of `colours` among `indices`, the
/// pixels of the rectangle at `(left, top)`, `width` wide, row by row;
/// `transparent` (GIF's) is no colour and so never past.
fn first_past(
    indices: impl IntoIterator<Item = u8>,
    colours: usize,
    transparent: Option<u8>,
    (left, top, width): (u32, u32, u32),
) -> Option<PastPalette> {
    let width = width.max(1) as usize;
    let (i, index) = indices
        .into_iter()
        .enumerate()
        .find(|&(_, index)| usize::from(index) >= colours && Some(index) != transparent)?;
    Some(PastPalette {
        index,
        colours,
        x: left + (i % width) as u32,
        y: top + (i / width) as u32,
    })
}

/// [`first_past_palette`] of a PNG. The indices are decoded whole, one
/// byte a pixel at most: a quarter of the RGBA picture the caller holds.
fn png_past_palette(bytes: &[u8]) -> Option<PastPalette> {
    let mut decoder = png::Decoder::new(std::io::Cursor::new(bytes));
    decoder.set_transformations(png::Transformations::IDENTITY);
    let mut reader = decoder.read_info().ok()?;
    let info = reader.info();
    if info.color_type != png::ColorType::Indexed {
        return None;
    }
    let depth = info.bit_depth as usize;
    let colours = info.palette.as_ref()?.len() / 3;
    if colours >= 1 << depth {
        return None;
    }
    let mut packed = vec![0; reader.output_buffer_size()?];
    let frame = reader.next_frame(&mut packed).ok()?;
    let width = frame.width as usize;
    let indices = packed
        .chunks_exact(frame.line_size)
        .flat_map(|line| (0..width).map(move |x| unpack(line, x, depth)));
    first_past(indices, colours, None, (0, 0, frame.width))
}

/// Index `x` of a row of indices packed `depth` bits each, from each byte's
/// most significant bits (PNG 7.2; BMP packs them so too).
fn unpack(row: &[u8], x: usize, depth: usize) -> u8 {
    let per_byte = 8 / depth;
    let shift = 8 - depth * (1 + x % per_byte);
    (row[x / per_byte] >> shift) & ((1u16 << depth) - 1) as u8
}

/// [`first_past_palette`] of a GIF's first frame, against its local colour
/// table or else the global one (GIF89a, 20 and 21). Its coordinates are
/// the logical screen's, as the decoded picture's are.
fn gif_past_palette(bytes: &[u8]) -> Option<PastPalette> {
    let mut options = gif::DecodeOptions::new();
    options.set_color_output(gif::ColorOutput::Indexed);
    // One byte a pixel of a picture within the tools' limit: the crate's
    // default of 50 MB left an 8000x8000 frame unchecked (a review).
    let limit = std::num::NonZeroU64::new(super::MAX_IMAGE_PIXELS).expect("not zero");
    options.set_memory_limit(gif::MemoryLimit::Bytes(limit));
    let mut decoder = options.read_info(bytes).ok()?;
    let global = decoder.global_palette().map(<[u8]>::len);
    let screen = (usize::from(decoder.width()), usize::from(decoder.height()));
    let frame = decoder.read_next_frame().ok()??;
    let colours = frame.palette.as_ref().map(Vec::len).or(global)? / 3;
    if colours >= 256 {
        return None;
    }
    let (left, top, width) = (
        usize::from(frame.left),
        usize::from(frame.top),
        usize::from(frame.width).max(1),
    );
    // Only what lands on the screen is drawn: an index off it is no fault
    // (a review found one refused).
    let on_screen = |i: usize| left + i % width < screen.0 && top + i / width < screen.1;
    let indices =
        (frame.buffer.iter().enumerate()).map(|(i, &index)| if on_screen(i) { index } else { 0 });
    first_past(
        indices,
        colours,
        frame.transparent,
        (left as u32, top as u32, width as u32),
    )
}

/// [`first_past_palette`] of a BMP with a palette shorter than its bit
/// depth allows (a `BITMAPINFOHEADER` or later whose `biClrUsed` says so):
/// plain rows of 1, 2, 4 or 8 bits, or RLE8 or RLE4 (Microsoft's "Bitmap
/// Compression"). Rows are stored bottom up unless the height is negative.
fn bmp_past_palette(bytes: &[u8]) -> Option<PastPalette> {
    let u16_at = |at: usize| Some(u16::from_le_bytes(bytes.get(at..at + 2)?.try_into().ok()?));
    let u32_at = |at: usize| Some(u32::from_le_bytes(bytes.get(at..at + 4)?.try_into().ok()?));
    let data = bytes.get(u32_at(10)? as usize..)?;
    if u32_at(14)? < 40 {
        return None; // An OS/2 core header: its palette is full.
    }
    let width = u32_at(18)? as i32;
    let height = u32_at(22)? as i32;
    let (depth, compression, used) = (u16_at(28)? as usize, u32_at(30)?, u32_at(46)? as usize);
    if !matches!(depth, 1 | 2 | 4 | 8) || used == 0 || used >= 1 << depth || width <= 0 {
        return None;
    }
    let (w, h) = (width as usize, height.unsigned_abs() as usize);
    // The picture's row of stored row `r`.
    let y = |r: usize| if height > 0 { h - 1 - r } else { r } as u32;
    let past = |index: u8, x: usize, r: usize| {
        // `then`, not `then_some`: `y(r)` overflows for a row past the
        // picture (RLE data may run on past it; a review's debug build).
        (usize::from(index) >= used && x < w && r < h).then(|| PastPalette {
            index,
            colours: used,
            x: x as u32,
            y: y(r),
        })
    };
    match (compression, depth) {
        (0, _) => {
            let stride = (depth * w).div_ceil(32) * 4;
            data.chunks_exact(stride)
                .take(h)
                .enumerate()
                .find_map(|(r, row)| (0..w).find_map(|x| past(unpack(row, x, depth), x, r)))
        }
        (1, 8) | (2, 4) => rle_past_palette(data, depth, past),
        _ => None,
    }
}

/// The first index of RLE8 or RLE4 data (`depth` 8 or 4) for which `past`
/// says so, given its stored row and column.
fn rle_past_palette(
    data: &[u8],
    depth: usize,
    past: impl Fn(u8, usize, usize) -> Option<PastPalette>,
) -> Option<PastPalette> {
    // Index `k` of a run: RLE4 alternates a byte's high and low nibbles.
    let nth = |b: u8, k: usize| {
        if depth == 8 {
            b
        } else {
            b >> (4 * (1 - k % 2)) & 15
        }
    };
    let (mut at, mut x, mut r) = (0, 0, 0);
    while let (Some(&n), Some(&b)) = (data.get(at), data.get(at + 1)) {
        at += 2;
        let n = usize::from(n);
        match (n, b) {
            (1.., _) => {
                if let Some(p) = (0..n).find_map(|k| past(nth(b, k), x + k, r)) {
                    return Some(p);
                }
                x += n;
            }
            (0, 0) => (x, r) = (0, r + 1),
            (0, 1) => return None,
            (0, 2) => {
                let (dx, dy) = (*data.get(at)?, *data.get(at + 1)?);
                (x, r, at) = (x + usize::from(dx), r + usize::from(dy), at + 2);
            }
            (0, k) => {
                let k = usize::from(k);
                let bytes = if depth == 8 { k } else { k.div_ceil(2) };
                let run = data.get(at..at + bytes)?;
                let index = |j: usize| {
                    if depth == 8 {
                        run[j]
                    } else {
                        nth(run[j / 2], j)
                    }
                };
                if let Some(p) = (0..k).find_map(|j| past(index(j), x + j, r)) {
                    return Some(p);
                }
                (x, at) = (x + k, at + bytes + bytes % 2);
            }
        }
    }
    None
}

#[cfg(test)]
mod tests {
    use super::{first_past_palette, PastPalette};

    /// An indexed PNG of `width` x `rows.len()` at bit depth `depth`, rows
    /// already packed, with a palette of `colours` entries; written by the
    /// `png` encoder, an independent route to the bytes.
    fn indexed(width: u32, depth: png::BitDepth, colours: usize, rows: &[u8]) -> Vec<u8> {
        let mut out = Vec::new();
        let height = (rows.len() / ((width as usize * depth as usize).div_ceil(8))) as u32;
        let mut e = png::Encoder::new(&mut out, width, height);
        e.set_color(png::ColorType::Indexed);
        e.set_depth(depth);
        e.set_palette((0..colours * 3).map(|i| i as u8).collect::<Vec<_>>());
        e.write_header().unwrap().write_image_data(rows).unwrap();
        out
    }

    #[test]
    fn an_index_past_the_palette_is_found_where_it_is() {
        use png::BitDepth::{Eight, Four, One, Two};
        // Eight bits: index 5 of two colours, at (2, 1).
        let png = indexed(3, Eight, 2, &[0, 1, 1, 1, 0, 5]);
        let past = PastPalette {
            index: 5,
            colours: 2,
            x: 2,
            y: 1,
        };
        assert_eq!(first_past_palette(&png), Some(past));
        // Two bits a pixel, three colours: 0b00_01_10_11, the fourth is 3.
        let png = indexed(4, Two, 3, &[0b0001_1011]);
        let found = first_past_palette(&png).unwrap();
        assert_eq!((found.index, found.x, found.y), (3, 3, 0));
        // Four bits, five colours, padding bits of an odd width ignored.
        let png = indexed(3, Four, 5, &[0x01, 0x2F, 0x4F, 0x30]);
        let found = first_past_palette(&png).unwrap();
        assert_eq!((found.index, found.x, found.y), (15, 1, 1));
        // In range, or a full palette: nothing.
        assert_eq!(first_past_palette(&indexed(3, Eight, 6, &[0, 1, 5])), None);
        assert_eq!(first_past_palette(&indexed(8, One, 2, &[0xA5])), None);
        assert_eq!(first_past_palette(b"not a png"), None);
    }
}

#[cfg(test)]
mod other_formats {
    use super::first_past_palette;

    /// A BMP with a `BITMAPINFOHEADER`, `used` palette entries and pixel
    /// `data` as stored, written out field by field (Microsoft's layout).
    fn bmp(
        width: i32,
        height: i32,
        depth: u16,
        compression: u32,
        used: u32,
        data: &[u8],
    ) -> Vec<u8> {
        let offset = 14 + 40 + 4 * used;
        let mut b = b"BM".to_vec();
        b.extend((offset + data.len() as u32).to_le_bytes());
        b.extend([0; 4]);
        b.extend(offset.to_le_bytes());
        b.extend(40u32.to_le_bytes());
        b.extend(width.to_le_bytes());
        b.extend(height.to_le_bytes());
        b.extend(1u16.to_le_bytes());
        b.extend(depth.to_le_bytes());
        b.extend(compression.to_le_bytes());
        b.extend((data.len() as u32).to_le_bytes());
        b.extend([0; 8]);
        b.extend(used.to_le_bytes());
        b.extend([0; 4]);
        b.extend((0..used).flat_map(|i| [i as u8 * 40, 0, 0, 0]));
        b.extend(data);
        b
    }

    /// Where the first index past the palette is: index, x, y.
    fn found(bytes: &[u8]) -> Option<(u8, u32, u32)> {
        first_past_palette(bytes).map(|p| (p.index, p.x, p.y))
    }

    /// Every stored form of BMP, with the pixels laid out by hand; the
    /// `image` crate decodes each (so the layouts are BMP's).
    #[test]
    fn bmp_indices_past_the_palette_are_found_in_every_stored_form() {
        // 8 bits, bottom up: stored row 0 is the picture's last.
        let plain8 = bmp(3, 2, 8, 0, 2, &[0, 5, 1, 0, 1, 1, 0, 0]);
        // 4 bits, top down, rows padded to four bytes; 5 colours.
        let plain4 = bmp(3, -2, 4, 0, 5, &[0x01, 0x20, 0, 0, 0x4F, 0x30, 0, 0]);
        // RLE8: a run of four 1s, end of row; a delta of one, three
        // absolute pixels (padded to an even count of bytes), end of file.
        let rle8 = bmp(
            4,
            2,
            8,
            1,
            3,
            &[4, 1, 0, 0, 0, 2, 1, 0, 0, 3, 2, 6, 0, 0, 0, 1],
        );
        // RLE4: a run alternating 1 and 2, then absolute 2, 1, 5.
        let rle4 = bmp(6, 1, 4, 2, 3, &[3, 0x12, 0, 3, 0x21, 0x50, 0, 1]);
        for (bytes, want) in [
            (&plain8, (5, 1, 1)),
            (&plain4, (15, 1, 1)),
            (&rle8, (6, 2, 0)),
            (&rle4, (5, 5, 0)),
        ] {
            image::load_from_memory(bytes).expect("a BMP the decoder reads");
            assert_eq!(found(bytes), Some(want));
        }
        // In range, a full palette, or past the row's end (not drawn).
        assert_eq!(found(&bmp(3, 2, 8, 0, 6, &[0, 5, 1, 0, 1, 1, 0, 0])), None);
        assert_eq!(found(&bmp(3, 2, 8, 0, 0, &[0, 5, 1, 0, 1, 1, 0, 0])), None);
        assert_eq!(found(&bmp(2, 1, 8, 1, 2, &[2, 1, 1, 9, 0, 1])), None);
        // RLE data running on past the last row, in range: no fault, and no
        // overflow working out the row of what is not drawn (a review).
        let extra = bmp(2, 2, 8, 1, 2, &[2, 0, 0, 0, 2, 1, 0, 0, 2, 5, 0, 1]);
        assert_eq!(found(&extra), None);
    }

    /// A GIF's first frame against its colour table, transparency apart;
    /// written by the `gif` encoder.
    #[test]
    fn gif_indices_past_the_colour_table_are_found_on_the_screen() {
        // A GIF of a two-colour table: a screen, and one frame of
        // (width, height) at (1, 1).
        let gif = |screen: (u16, u16), size: (u16, u16), indices: &[u8], transparent| {
            let mut out = Vec::new();
            let mut e =
                gif::Encoder::new(&mut out, screen.0, screen.1, &[255, 0, 0, 0, 255, 0]).unwrap();
            let frame = gif::Frame {
                left: 1,
                top: 1,
                width: size.0,
                height: size.1,
                transparent,
                buffer: indices.to_vec().into(),
                ..gif::Frame::default()
            };
            e.write_frame(&frame).unwrap();
            drop(e);
            out
        };
        let past = gif((4, 3), (3, 2), &[0, 1, 1, 1, 3, 0], None);
        image::load_from_memory(&past).expect("a GIF the decoder reads");
        assert_eq!(found(&past), Some((3, 2, 2)));
        assert_eq!(
            found(&gif((4, 3), (3, 2), &[0, 1, 1, 1, 3, 0], Some(3))),
            None
        );
        // Off the 2x2 screen nothing is drawn, so nothing is past (a review).
        assert_eq!(found(&gif((2, 2), (2, 2), &[0, 1, 1, 3], None)), None);
    }
}
