//! Colour images as PNG. Reads any 8- or 16-bit grey, grey-alpha, RGB, RGBA or palette PNG into
//! 8-bit RGB, its size checked from the header before a pixel is decoded; writes 8-bit RGB.

use std::fs::File;
use std::io::BufReader;
use std::path::Path;

use super::{SensorFileError, check_declared_size, io_error};
use crate::hal::ColorImage;

/// Reads a PNG into 8-bit RGB.
pub fn read_png(path: &Path) -> Result<ColorImage, SensorFileError> {
    read_colour(path, None)
}

/// Reads a PNG that a camera of `size` (width, height) took into 8-bit RGB; another size is
/// refused from the header, before a pixel is decoded.
pub fn read_png_of_size(path: &Path, size: (u32, u32)) -> Result<ColorImage, SensorFileError> {
    read_colour(path, Some(size))
}

fn read_colour(path: &Path, expected: Option<(u32, u32)>) -> Result<ColorImage, SensorFileError> {
    let file = File::open(path).map_err(|e| io_error(path, e))?;
    let png_error =
        |reason: String| SensorFileError::Png { path: path.display().to_string(), reason };
    let mut decoder = png::Decoder::new(BufReader::new(file));
    // Palette and low bit depths become 8-bit channels; 16-bit keeps its high byte.
    decoder.set_transformations(png::Transformations::EXPAND | png::Transformations::STRIP_16);
    let mut reader = decoder.read_info().map_err(|e| png_error(e.to_string()))?;
    check_declared_size(path, reader.info().size(), expected)?;
    let mut buffer = vec![0; reader.output_buffer_size()];
    let frame = reader.next_frame(&mut buffer).map_err(|e| png_error(e.to_string()))?;
    buffer.truncate(frame.buffer_size());
    let (width, height) = (frame.width, frame.height);
    let pixels = width as usize * height as usize;
    let channels = match frame.color_type {
        png::ColorType::Grayscale => 1,
        png::ColorType::GrayscaleAlpha => 2,
        png::ColorType::Rgb => 3,
        png::ColorType::Rgba => 4,
        png::ColorType::Indexed => return Err(png_error("palette was not expanded".into())),
    };
    if frame.bit_depth != png::BitDepth::Eight || buffer.len() < pixels * channels {
        return Err(png_error(format!("unexpected bit depth {:?}", frame.bit_depth)));
    }
    let rgb = match channels {
        3 => buffer,
        _ => {
            let mut rgb = Vec::with_capacity(pixels * 3);
            for px in buffer.chunks_exact(channels) {
                if channels <= 2 {
                    rgb.extend_from_slice(&[px[0]; 3]);
                } else {
                    rgb.extend_from_slice(&px[..3]);
                }
            }
            rgb
        }
    };
    Ok(ColorImage { width, height, rgb })
}

/// Writes 8-bit RGB PNG.
pub fn write_png(path: &Path, image: &ColorImage) -> Result<(), SensorFileError> {
    let bytes = encode_png(image).map_err(|e| io_error(path, std::io::Error::other(e)))?;
    std::fs::write(path, bytes).map_err(|e| io_error(path, e))
}

/// The image as 8-bit RGB PNG bytes, compressed as hard as the encoder goes.
pub fn encode_png(image: &ColorImage) -> Result<Vec<u8>, png::EncodingError> {
    let mut bytes = Vec::new();
    let mut encoder = png::Encoder::new(&mut bytes, image.width, image.height);
    encoder.set_color(png::ColorType::Rgb);
    encoder.set_depth(png::BitDepth::Eight);
    encoder.set_compression(png::Compression::Best);
    encoder.set_filter(png::FilterType::Paeth);
    let mut writer = encoder.write_header()?;
    writer.write_image_data(&image.rgb)?;
    writer.finish()?;
    Ok(bytes)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn round_trips_rgb() {
        let mut image = ColorImage::new(7, 5);
        for (i, c) in image.rgb.iter_mut().enumerate() {
            *c = (i * 37 % 256) as u8;
        }
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("image.png");
        write_png(&path, &image).unwrap();
        assert_eq!(read_png(&path).unwrap(), image);
    }

    #[test]
    fn a_size_unlike_the_camera_is_refused() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("image.png");
        write_png(&path, &ColorImage::new(8, 6)).unwrap();
        let message = read_png_of_size(&path, (6, 8)).unwrap_err().to_string();
        assert!(message.contains("8×6 pixels but the camera calibration is for 6×8"), "{message}");
        assert_eq!(read_png_of_size(&path, (8, 6)).unwrap(), ColorImage::new(8, 6));
    }

    #[test]
    fn rejects_what_is_not_a_png() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("image.png");
        std::fs::write(&path, b"ply\nformat ascii 1.0\n").unwrap();
        let message = read_png(&path).unwrap_err().to_string();
        assert!(message.contains("not a PNG"), "{message}");
    }

    #[test]
    fn a_missing_file_is_named_with_its_reason_once() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("nowhere.png");
        // The command lines print an error with its chain of causes.
        let message = format!("{:#}", anyhow::Error::from(read_png(&path).unwrap_err()));
        let reason = std::fs::File::open(&path).unwrap_err().to_string();
        assert!(message.starts_with(&path.display().to_string()), "{message}");
        assert_eq!(message.matches(&reason).count(), 1, "{message}");
    }
}
