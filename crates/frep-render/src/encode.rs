//! Image encoders:
//! - PNG (`png`, fast compression);
//! - JPEG (`jpeg-encoder`);
//! - lossy WebP (libwebp through the `webp` crate, behind the default `webp`
//!   feature).
//!
//! The pure-Rust `image-webp` only writes lossless WebP, which is several
//! times larger for rendered images.

use std::path::Path;

use serde::{Deserialize, Serialize};

use crate::image::Image;

/// An output image format.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum ImageFormat {
    /// PNG, lossless (quality is ignored).
    Png,
    /// JPEG, quality 1–100.
    Jpeg,
    /// Lossy WebP, quality 1–100 (needs the `webp` feature).
    Webp,
}

impl ImageFormat {
    /// The format named by a path's extension (`png`, `jpg`/`jpeg`, `webp`;
    /// case-insensitive).
    pub fn from_path(path: &Path) -> Option<ImageFormat> {
        let ext = path.extension()?.to_str()?.to_ascii_lowercase();
        Self::from_extension(&ext)
    }

    /// The format for an extension or name (`png`, `jpg`, `jpeg`, `webp`).
    pub fn from_extension(ext: &str) -> Option<ImageFormat> {
        match ext.to_ascii_lowercase().as_str() {
            "png" => Some(ImageFormat::Png),
            "jpg" | "jpeg" => Some(ImageFormat::Jpeg),
            "webp" => Some(ImageFormat::Webp),
            _ => None,
        }
    }

    /// The usual file extension (without the dot).
    pub fn extension(self) -> &'static str {
        match self {
            ImageFormat::Png => "png",
            ImageFormat::Jpeg => "jpg",
            ImageFormat::Webp => "webp",
        }
    }

    /// The MIME type.
    pub fn mime(self) -> &'static str {
        match self {
            ImageFormat::Png => "image/png",
            ImageFormat::Jpeg => "image/jpeg",
            ImageFormat::Webp => "image/webp",
        }
    }
}

/// Why an image could not be encoded.
#[derive(Debug, thiserror::Error)]
pub enum EncodeError {
    /// The image is larger than the format allows (JPEG: 65 535, WebP:
    /// 16 383 pixels a side) or empty.
    #[error("image size {width}x{height} not supported by the format")]
    TooLarge {
        /// Image width.
        width: u32,
        /// Image height.
        height: u32,
    },
    /// The pixel buffer does not hold `width * height * 4` bytes.
    #[error("pixel buffer size does not match the image")]
    BadBuffer,
    /// The format was not compiled in.
    #[error("{0:?} support not compiled in")]
    Unsupported(ImageFormat),
    /// The encoder failed.
    #[error("encoder failed: {0}")]
    Encoder(String),
}

impl From<EncodeError> for std::io::Error {
    fn from(e: EncodeError) -> Self {
        std::io::Error::other(e)
    }
}

/// Encodes `img` in `format`; `quality` (1–100, clamped) applies to JPEG and
/// WebP. Opaque images are written without alpha.
pub fn encode(img: &Image, format: ImageFormat, quality: u8) -> Result<Vec<u8>, EncodeError> {
    if img.rgba.len() != img.width as usize * img.height as usize * 4 {
        return Err(EncodeError::BadBuffer);
    }
    let too_large = EncodeError::TooLarge {
        width: img.width,
        height: img.height,
    };
    if img.width == 0 || img.height == 0 {
        return Err(too_large);
    }
    let quality = quality.clamp(1, 100);
    match format {
        ImageFormat::Png => encode_png(img),
        ImageFormat::Jpeg => {
            if img.width > 65_535 || img.height > 65_535 {
                return Err(too_large);
            }
            let mut out = Vec::new();
            let enc = jpeg_encoder::Encoder::new(&mut out, quality);
            enc.encode(
                &img.rgba,
                img.width as u16,
                img.height as u16,
                jpeg_encoder::ColorType::Rgba,
            )
            .map_err(|e| EncodeError::Encoder(e.to_string()))?;
            Ok(out)
        }
        ImageFormat::Webp => encode_webp(img, quality, too_large),
    }
}

fn encode_png(img: &Image) -> Result<Vec<u8>, EncodeError> {
    let mut out = Vec::new();
    let opaque = img.is_opaque();
    {
        let mut enc = png::Encoder::new(&mut out, img.width, img.height);
        enc.set_color(if opaque {
            png::ColorType::Rgb
        } else {
            png::ColorType::Rgba
        });
        enc.set_depth(png::BitDepth::Eight);
        enc.set_compression(png::Compression::Fast);
        let mut w = enc
            .write_header()
            .map_err(|e| EncodeError::Encoder(e.to_string()))?;
        let data = if opaque {
            img.to_rgb()
        } else {
            img.rgba.clone()
        };
        w.write_image_data(&data)
            .map_err(|e| EncodeError::Encoder(e.to_string()))?;
        w.finish()
            .map_err(|e| EncodeError::Encoder(e.to_string()))?;
    }
    Ok(out)
}

/// Encodes an 8-bit grey-scale image (`data.len() == width * height`) as PNG.
pub fn encode_png_gray(data: &[u8], width: u32, height: u32) -> Result<Vec<u8>, EncodeError> {
    if data.len() != width as usize * height as usize {
        return Err(EncodeError::BadBuffer);
    }
    let mut out = Vec::new();
    {
        let mut enc = png::Encoder::new(&mut out, width, height);
        enc.set_color(png::ColorType::Grayscale);
        enc.set_depth(png::BitDepth::Eight);
        enc.set_compression(png::Compression::Fast);
        let mut w = enc
            .write_header()
            .map_err(|e| EncodeError::Encoder(e.to_string()))?;
        w.write_image_data(data)
            .map_err(|e| EncodeError::Encoder(e.to_string()))?;
        w.finish()
            .map_err(|e| EncodeError::Encoder(e.to_string()))?;
    }
    Ok(out)
}

#[cfg(feature = "webp")]
fn encode_webp(img: &Image, quality: u8, too_large: EncodeError) -> Result<Vec<u8>, EncodeError> {
    if img.width > 16_383 || img.height > 16_383 {
        return Err(too_large);
    }
    let rgb;
    let enc = if img.is_opaque() {
        rgb = img.to_rgb();
        webp::Encoder::from_rgb(&rgb, img.width, img.height)
    } else {
        webp::Encoder::from_rgba(&img.rgba, img.width, img.height)
    };
    let mem = enc
        .encode_simple(false, quality as f32)
        .map_err(|e| EncodeError::Encoder(format!("{e:?}")))?;
    Ok(mem.to_vec())
}

#[cfg(not(feature = "webp"))]
fn encode_webp(_: &Image, _: u8, _: EncodeError) -> Result<Vec<u8>, EncodeError> {
    Err(EncodeError::Unsupported(ImageFormat::Webp))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::camera::{Aabb, Camera};
    use crate::image::{shade, Lighting};
    use crate::synthetic::sphere_hits;

    pub(crate) fn test_image(size: u32) -> Image {
        let b = Aabb::new([-1.0; 3], [1.0; 3]);
        let cam = Camera::orbit(&b, 30.0, 20.0, Some(35.0));
        shade(
            &sphere_hits(&cam, size, size, [0.0; 3], 0.8, None),
            &Lighting::default(),
        )
    }

    fn decode_png(bytes: &[u8]) -> (png::OutputInfo, Vec<u8>) {
        let dec = png::Decoder::new(std::io::Cursor::new(bytes));
        let mut r = dec.read_info().unwrap();
        let mut buf = vec![0; r.output_buffer_size().unwrap()];
        let info = r.next_frame(&mut buf).unwrap();
        buf.truncate(info.buffer_size());
        (info, buf)
    }

    #[test]
    fn format_from_path() {
        assert_eq!(
            ImageFormat::from_path(Path::new("a/b.PNG")),
            Some(ImageFormat::Png)
        );
        assert_eq!(
            ImageFormat::from_path(Path::new("x.jpeg")),
            Some(ImageFormat::Jpeg)
        );
        assert_eq!(
            ImageFormat::from_path(Path::new("x.jpg")),
            Some(ImageFormat::Jpeg)
        );
        assert_eq!(
            ImageFormat::from_path(Path::new("x.webp")),
            Some(ImageFormat::Webp)
        );
        assert_eq!(ImageFormat::from_path(Path::new("x.gif")), None);
        assert_eq!(ImageFormat::from_path(Path::new("x")), None);
        for f in [ImageFormat::Png, ImageFormat::Jpeg, ImageFormat::Webp] {
            assert_eq!(ImageFormat::from_extension(f.extension()), Some(f));
        }
    }

    #[test]
    fn png_round_trips() {
        let img = test_image(40);
        let bytes = encode(&img, ImageFormat::Png, 0).unwrap();
        let (info, data) = decode_png(&bytes);
        assert_eq!((info.width, info.height), (40, 40));
        assert_eq!(info.color_type, png::ColorType::Rgb);
        assert_eq!(data, img.to_rgb());
        // With transparency, alpha is kept.
        let mut t = img.clone();
        t.set_pixel(0, 0, [1, 2, 3, 4]);
        let (info, data) = decode_png(&encode(&t, ImageFormat::Png, 0).unwrap());
        assert_eq!(info.color_type, png::ColorType::Rgba);
        assert_eq!(data, t.rgba);
    }

    #[test]
    fn gray_png_round_trips() {
        let data: Vec<u8> = (0..12u8).collect();
        let (info, back) = decode_png(&encode_png_gray(&data, 4, 3).unwrap());
        assert_eq!(info.color_type, png::ColorType::Grayscale);
        assert_eq!(back, data);
        assert!(encode_png_gray(&data, 5, 3).is_err());
    }

    #[test]
    fn jpeg_quality_changes_size() {
        let img = test_image(128);
        let lo = encode(&img, ImageFormat::Jpeg, 20).unwrap();
        let hi = encode(&img, ImageFormat::Jpeg, 95).unwrap();
        assert_eq!(&lo[..2], &[0xFF, 0xD8]);
        assert_eq!(&hi[hi.len() - 2..], &[0xFF, 0xD9]);
        assert!(lo.len() < hi.len());
    }

    #[cfg(feature = "webp")]
    #[test]
    fn webp_is_lossy_and_valid() {
        let img = test_image(128);
        let lo = encode(&img, ImageFormat::Webp, 20).unwrap();
        let hi = encode(&img, ImageFormat::Webp, 95).unwrap();
        assert_eq!(&lo[..4], b"RIFF");
        assert_eq!(&lo[8..12], b"WEBP");
        assert_eq!(&lo[12..16], b"VP8 ", "lossy bitstream");
        assert!(lo.len() < hi.len());
        // libwebp decodes it back to the right size.
        let dec = webp::Decoder::new(&hi).decode().unwrap();
        assert_eq!((dec.width(), dec.height()), (128, 128));
    }

    #[test]
    fn bad_sizes_are_errors() {
        let img = Image {
            width: 0,
            height: 5,
            rgba: vec![],
        };
        assert!(matches!(
            encode(&img, ImageFormat::Jpeg, 50),
            Err(EncodeError::TooLarge { .. })
        ));
        let img = Image {
            width: 2,
            height: 2,
            rgba: vec![0; 3],
        };
        assert!(matches!(
            encode(&img, ImageFormat::Png, 50),
            Err(EncodeError::BadBuffer)
        ));
    }
}
