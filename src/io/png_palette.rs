//! Palette indices of an indexed PNG against its palette, checked once the
//! picture has decoded: the `png` crate expands an index past the `PLTE`
//! table to opaque black without a word (its palette table has 256 entries,
//! the missing ones black), where the PNG specification (11.2.3, PLTE)
//! makes such an index an error and libpng reports it. A hostile-input
//! review found a two-colour palette's index 5 drawn black.

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

/// The first index of an indexed PNG past its palette, in reading order;
/// `None` for any other picture, for a palette with every index the bit
/// depth can write (the common case: nothing is decoded again), and for
/// bytes the decoder refuses (the caller has decoded them already).
///
/// The indices are decoded whole, one byte a pixel at most: a quarter of
/// the RGBA picture the caller holds.
pub(super) fn first_past_palette(bytes: &[u8]) -> Option<PastPalette> {
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
    let mut indices = vec![0; reader.output_buffer_size()?];
    let frame = reader.next_frame(&mut indices).ok()?;
    let per_byte = 8 / depth;
    let mask = (1u16 << depth) as u8 - 1;
    for (y, line) in indices.chunks_exact(frame.line_size).enumerate() {
        for x in 0..frame.width as usize {
            // Pixels are packed from the most significant bits (PNG 7.2).
            let shift = 8 - depth * (1 + x % per_byte);
            let index = (line[x / per_byte] >> shift) & mask;
            if usize::from(index) >= colours {
                return Some(PastPalette {
                    index,
                    colours,
                    x: x as u32,
                    y: y as u32,
                });
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
