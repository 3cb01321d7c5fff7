//! Reading a figure: any PNG (RGB, RGBA, grey, grey + alpha, indexed; 1 to 16 bits per sample)
//! becomes an 8-bit RGB raster, with transparency composited over white paper.

use std::io::Read;
use std::path::Path;

use png::{ColorType, Decoder, Limits, Transformations};

use crate::error::{GearError, Result};

/// Largest image accepted, in pixels (a 600 dpi A3 page is about 70 million).
const MAX_PIXELS: u64 = 200_000_000;

/// An 8-bit RGB raster, row-major from the top-left pixel.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct RgbImage {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// `width * height` pixels, row by row from the top.
    pub pixels: Vec<[u8; 3]>,
}

impl RgbImage {
    /// An image from packed RGB bytes (3 per pixel, row-major), e.g. the buffer of a plotters
    /// `BitMapBackend`; `None` when the length does not match the size.
    pub fn from_rgb_bytes(width: u32, height: u32, bytes: &[u8]) -> Option<Self> {
        let n = usize::try_from(u64::from(width) * u64::from(height)).ok()?;
        if bytes.len() != n.checked_mul(3)? {
            return None;
        }
        let pixels = bytes.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect();
        Some(RgbImage {
            width,
            height,
            pixels,
        })
    }

    /// The pixel at column `x`, row `y` (both inside the image).
    pub fn get(&self, x: u32, y: u32) -> [u8; 3] {
        self.pixels[y as usize * self.width as usize + x as usize]
    }
}

/// Reads the PNG file at `path`.
pub fn read_png(path: &Path) -> Result<RgbImage> {
    let file = std::fs::File::open(path).map_err(GearError::io(path))?;
    decode_png(std::io::BufReader::new(file)).map_err(|message| {
        GearError::io(path)(std::io::Error::new(
            std::io::ErrorKind::InvalidData,
            message,
        ))
    })
}

/// Decodes a PNG stream (first frame of an animated PNG); the error is a readable message.
pub fn decode_png<R: Read>(reader: R) -> std::result::Result<RgbImage, String> {
    let bad = |e: png::DecodingError| format!("not a readable PNG image ({e})");
    let mut decoder = Decoder::new_with_limits(reader, Limits { bytes: 1 << 30 });
    // Palette and low-bit grey expand to 8 bits, tRNS to alpha, 16-bit samples are stripped.
    decoder.set_transformations(Transformations::normalize_to_color8());
    let mut reader = decoder.read_info().map_err(bad)?;
    let (w, h) = reader.info().size();
    if w == 0 || h == 0 || u64::from(w) * u64::from(h) > MAX_PIXELS {
        return Err(format!(
            "image of {w} x {h} pixels is empty or too large (limit {MAX_PIXELS} pixels)"
        ));
    }
    let mut buf = vec![0u8; reader.output_buffer_size()];
    let info = reader.next_frame(&mut buf).map_err(bad)?;
    let (w, h) = (info.width, info.height);
    let channels = match info.color_type {
        ColorType::Grayscale => 1,
        ColorType::GrayscaleAlpha => 2,
        ColorType::Rgb => 3,
        ColorType::Rgba => 4,
        ColorType::Indexed => return Err("indexed PNG was not expanded to RGB".into()),
    };
    if info.line_size == 0 {
        return Err("PNG image has empty rows".into());
    }
    let mut pixels = Vec::with_capacity(w as usize * h as usize);
    for row in buf.chunks(info.line_size).take(h as usize) {
        for px in row.chunks_exact(channels).take(w as usize) {
            pixels.push(to_rgb(px));
        }
    }
    if pixels.len() != w as usize * h as usize {
        return Err("PNG image data is truncated".into());
    }
    Ok(RgbImage {
        width: w,
        height: h,
        pixels,
    })
}

/// One decoded sample group (grey, grey + alpha, RGB or RGBA) as RGB over a white background.
fn to_rgb(px: &[u8]) -> [u8; 3] {
    let (rgb, alpha) = match *px {
        [g] => ([g, g, g], 255),
        [g, a] => ([g, g, g], a),
        [r, g, b] => ([r, g, b], 255),
        [r, g, b, a, ..] => ([r, g, b], a),
        [] => ([255; 3], 0),
    };
    let a = u32::from(alpha);
    // c * a + 255 * (1 - a), rounded; the result is at most 255.
    rgb.map(|c| ((u32::from(c) * a + 255 * (255 - a) + 127) / 255) as u8)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn encode(w: u32, h: u32, color: ColorType, depth: png::BitDepth, data: &[u8]) -> Vec<u8> {
        encode_with(w, h, color, depth, data, |_| {})
    }

    fn encode_with(
        w: u32,
        h: u32,
        color: ColorType,
        depth: png::BitDepth,
        data: &[u8],
        setup: impl FnOnce(&mut png::Encoder<&mut Vec<u8>>),
    ) -> Vec<u8> {
        let mut out = Vec::new();
        {
            let mut enc = png::Encoder::new(&mut out, w, h);
            enc.set_color(color);
            enc.set_depth(depth);
            setup(&mut enc);
            let mut writer = enc.write_header().unwrap();
            writer.write_image_data(data).unwrap();
        }
        out
    }

    #[test]
    fn every_colour_type_becomes_rgb() {
        use png::BitDepth::*;
        let rgb = encode(2, 1, ColorType::Rgb, Eight, &[255, 0, 0, 0, 0, 255]);
        assert_eq!(
            decode_png(&rgb[..]).unwrap().pixels,
            [[255, 0, 0], [0, 0, 255]]
        );

        let rgba = encode(2, 1, ColorType::Rgba, Eight, &[0, 0, 0, 255, 0, 0, 0, 0]);
        assert_eq!(decode_png(&rgba[..]).unwrap().pixels, [[0; 3], [255; 3]]);

        let grey = encode(2, 1, ColorType::Grayscale, Eight, &[10, 200]);
        assert_eq!(decode_png(&grey[..]).unwrap().pixels, [[10; 3], [200; 3]]);

        let ga = encode(1, 1, ColorType::GrayscaleAlpha, Eight, &[0, 128]);
        assert_eq!(decode_png(&ga[..]).unwrap().pixels, [[127; 3]]);

        // 16-bit big-endian samples: the high byte survives.
        let deep = encode(
            1,
            1,
            ColorType::Rgb,
            Sixteen,
            &[0x12, 0x34, 0xAB, 0xCD, 0, 1],
        );
        assert_eq!(decode_png(&deep[..]).unwrap().pixels, [[0x12, 0xAB, 0]]);

        // 1-bit grey: 0b1010 -> white, black, white, black.
        let bits = encode(4, 1, ColorType::Grayscale, One, &[0b1010_0000]);
        let img = decode_png(&bits[..]).unwrap();
        assert_eq!(img.pixels, [[255; 3], [0; 3], [255; 3], [0; 3]]);

        let pal = encode_with(3, 1, ColorType::Indexed, Eight, &[1, 0, 1], |e| {
            e.set_palette(vec![0, 114, 178, 213, 94, 0]);
        });
        let img = decode_png(&pal[..]).unwrap();
        assert_eq!(img.pixels, [[213, 94, 0], [0, 114, 178], [213, 94, 0]]);
        assert_eq!((img.width, img.height), (3, 1));
    }

    #[test]
    fn garbage_is_an_error() {
        assert!(decode_png(&b"not a png"[..]).is_err());
        let rgb = encode(2, 2, ColorType::Rgb, png::BitDepth::Eight, &[7; 12]);
        assert!(decode_png(&rgb[..rgb.len() - 20]).is_err());
        assert!(RgbImage::from_rgb_bytes(2, 2, &[0; 11]).is_none());
        assert_eq!(
            RgbImage::from_rgb_bytes(1, 1, &[1, 2, 3])
                .unwrap()
                .get(0, 0),
            [1, 2, 3]
        );
    }
}
