//! An RGB-D camera's depth image, aligned to the colour image, as a file: a 16-bit greyscale PNG
//! in millimetres (0 = no depth), what RealSense and Azure Kinect tools save, or a greyscale PFM
//! of 32-bit floats in metres (0 or NaN = no depth), what stereo tools save. The reader tells
//! them apart by their first bytes, not by the file's name.
//!
//! PFM: `Pf`, width, height and a scale, ASCII and whitespace-separated, one whitespace byte,
//! then the floats, rows bottom to top. A negative scale means little-endian; its magnitude must
//! be 1, the values being metres.

use std::fs::File;
use std::io::{BufRead, BufReader, BufWriter, Read, Write};
use std::path::Path;

use super::{SensorFileError, check_declared_size, io_error};
use crate::perception::{DepthEncoding, DepthImage};

const PNG_SIGNATURE: &[u8] = b"\x89PNG";
/// Longest PFM header read; a real one takes under 30 bytes.
const PFM_HEADER_MAX: usize = 256;

/// Reads the depth image a camera of `size` (width, height) took; another size, or more than
/// [`super::MAX_IMAGE_PIXELS`], is refused from the header, before a pixel is read.
pub fn read_depth(path: &Path, size: (u32, u32)) -> Result<DepthImage, SensorFileError> {
    let file = File::open(path).map_err(|e| io_error(path, e))?;
    let length = file.metadata().map_err(|e| io_error(path, e))?.len();
    let mut reader = BufReader::new(file);
    let start = reader.fill_buf().map_err(|e| io_error(path, e))?;
    let depth_error =
        |reason: String| SensorFileError::Depth { path: path.display().to_string(), reason };
    if start.starts_with(PNG_SIGNATURE) {
        read_depth_png(path, reader, size, depth_error)
    } else if start.starts_with(b"Pf") {
        read_pfm(path, reader, length, size, depth_error)
    } else if start.starts_with(b"PF") {
        Err(depth_error("it is a colour PFM; depth is one channel (`Pf`)".into()))
    } else {
        Err(depth_error("it starts with neither the PNG signature nor `Pf`".into()))
    }
}

fn read_depth_png(
    path: &Path,
    reader: BufReader<File>,
    size: (u32, u32),
    depth_error: impl Fn(String) -> SensorFileError,
) -> Result<DepthImage, SensorFileError> {
    let mut decoder = png::Decoder::new(reader);
    decoder.set_transformations(png::Transformations::IDENTITY);
    let mut reader = decoder.read_info().map_err(|e| depth_error(e.to_string()))?;
    let info = reader.info();
    check_declared_size(path, info.size(), Some(size))?;
    if (info.color_type, info.bit_depth) != (png::ColorType::Grayscale, png::BitDepth::Sixteen) {
        return Err(depth_error(format!(
            "it is {:?}-bit {:?}; depth in millimetres takes 16-bit greyscale",
            info.bit_depth as u8, info.color_type
        )));
    }
    let mut data = vec![0; reader.output_buffer_size()];
    let frame = reader.next_frame(&mut data).map_err(|e| depth_error(e.to_string()))?;
    data.truncate(frame.buffer_size());
    // PNG stores 16-bit samples big-endian; the conversion reads them where they lie.
    let encoding = DepthEncoding::Millimetres16 { big_endian: true };
    DepthImage::new(frame.width, frame.height, frame.line_size, encoding, data).map_err(depth_error)
}

/// The header's four fields and its length in bytes.
fn pfm_header(reader: &mut impl BufRead) -> Result<([String; 4], usize), String> {
    let mut fields: [String; 4] = Default::default();
    let mut field = 0;
    let mut length = 0;
    let mut byte = [0u8];
    while field < 4 {
        if length == PFM_HEADER_MAX {
            return Err(format!("its header runs past {PFM_HEADER_MAX} bytes"));
        }
        reader.read_exact(&mut byte).map_err(|_| "its header is cut short".to_string())?;
        length += 1;
        match byte[0] {
            // The whitespace after the scale is the header's last byte.
            b if b.is_ascii_whitespace() => field += usize::from(!fields[field].is_empty()),
            b if b.is_ascii_graphic() => fields[field].push(char::from(b)),
            b => return Err(format!("its header holds the byte {b:#04x}")),
        }
    }
    Ok((fields, length))
}

fn read_pfm(
    path: &Path,
    mut reader: BufReader<File>,
    file_length: u64,
    size: (u32, u32),
    depth_error: impl Fn(String) -> SensorFileError,
) -> Result<DepthImage, SensorFileError> {
    let ([magic, width, height, scale], header_length) =
        pfm_header(&mut reader).map_err(&depth_error)?;
    if magic != "Pf" {
        return Err(depth_error(format!("it starts with `{magic}`, not `Pf`")));
    }
    let number = |text: &str, what: &str| {
        text.parse::<u32>()
            .map_err(|_| depth_error(format!("its {what} `{text}` is not a whole number")))
    };
    let (width, height) = (number(&width, "width")?, number(&height, "height")?);
    check_declared_size(path, (width, height), Some(size))?;
    let scale: f64 =
        scale.parse().map_err(|_| depth_error(format!("its scale `{scale}` is not a number")))?;
    if scale.abs() != 1.0 {
        return Err(depth_error(format!(
            "its scale is {scale}; it must be -1 (little-endian) or 1 (big-endian), the values \
             being metres"
        )));
    }
    let row = width as usize * 4;
    let needed = row * height as usize;
    let available = file_length.saturating_sub(header_length as u64);
    if available < needed as u64 {
        return Err(depth_error(format!(
            "{available} bytes of data for {width}×{height} floats ({needed} needed)"
        )));
    }
    let mut data = vec![0; needed];
    reader.read_exact(&mut data).map_err(|e| io_error(path, e))?;
    // Rows bottom to top in the file; top to bottom in an image.
    for v in 0..height as usize / 2 {
        let (top, bottom) = data.split_at_mut((height as usize - 1 - v) * row);
        top[v * row..(v + 1) * row].swap_with_slice(&mut bottom[..row]);
    }
    let encoding = DepthEncoding::Metres32 { big_endian: scale > 0.0 };
    DepthImage::new(width, height, row, encoding, data).map_err(depth_error)
}

/// Writes millimetres, row by row from the top, as a 16-bit greyscale PNG.
pub fn write_depth_png(
    path: &Path,
    (width, height): (u32, u32),
    millimetres: &[u16],
) -> Result<(), SensorFileError> {
    let file = File::create(path).map_err(|e| io_error(path, e))?;
    let to_io = |e: png::EncodingError| io_error(path, std::io::Error::other(e));
    let mut encoder = png::Encoder::new(BufWriter::new(file), width, height);
    encoder.set_color(png::ColorType::Grayscale);
    encoder.set_depth(png::BitDepth::Sixteen);
    let mut writer = encoder.write_header().map_err(to_io)?;
    let bytes: Vec<u8> = millimetres.iter().flat_map(|d| d.to_be_bytes()).collect();
    writer.write_image_data(&bytes).map_err(to_io)?;
    writer.finish().map_err(to_io)
}

/// Writes metres, row by row from the top, as a little-endian greyscale PFM.
pub fn write_depth_pfm(
    path: &Path,
    (width, height): (u32, u32),
    metres: &[f32],
) -> Result<(), SensorFileError> {
    let file = File::create(path).map_err(|e| io_error(path, e))?;
    let mut out = BufWriter::new(file);
    let mut write = || -> std::io::Result<()> {
        write!(out, "Pf\n{width} {height}\n-1\n")?;
        for row in metres.chunks(width.max(1) as usize).rev() {
            for m in row {
                out.write_all(&m.to_le_bytes())?;
            }
        }
        out.flush()
    };
    write().map_err(|e| io_error(path, e))
}

#[cfg(test)]
mod tests {
    use nalgebra::{Isometry3, Point3};

    use super::*;
    use crate::hal::{CameraCalibration, CameraIntrinsics, PointCloud};
    use crate::perception::{DepthRange, cloud_from_depth};

    /// The cloud a depth image gives, the simplest way to compare two depth images.
    fn cloud(depth: &DepthImage) -> PointCloud {
        let (width, height) = (depth.width(), depth.height());
        let calibration = CameraCalibration {
            intrinsics: CameraIntrinsics { width, height, fx: 1.0, fy: 1.0, cx: 0.0, cy: 0.0 },
            base_from_camera: Isometry3::identity(),
        };
        cloud_from_depth(depth, &calibration, &DepthRange::default()).unwrap()
    }

    #[test]
    fn png_millimetres_and_pfm_metres_read_back_as_written() {
        let dir = tempfile::tempdir().unwrap();
        let millimetres = [1000, 0, 2500, 3001, 9999, 150];
        let png = dir.path().join("depth.png");
        write_depth_png(&png, (3, 2), &millimetres).unwrap();
        let read = read_depth(&png, (3, 2)).unwrap();
        assert_eq!(read.encoding(), DepthEncoding::Millimetres16 { big_endian: true });
        let points = cloud(&read).points;
        assert_eq!(points.len(), 5, "the 0 is a hole");
        assert_eq!(points[0], Point3::new(0.5, 0.5, 1.0));
        assert_eq!(points[1], Point3::new(2.5 * 2.5, 0.5 * 2.5, 2.5));
        let metres: Vec<f32> = millimetres
            .iter()
            .map(|&mm| if mm == 0 { f32::NAN } else { f32::from(mm) * 1e-3 })
            .collect();
        let pfm = dir.path().join("depth.pfm");
        write_depth_pfm(&pfm, (3, 2), &metres).unwrap();
        let from_pfm = cloud(&read_depth(&pfm, (3, 2)).unwrap());
        assert_eq!(from_pfm, cloud(&read));
    }

    #[test]
    fn a_depth_image_unlike_the_camera_or_huge_is_refused_from_its_header() {
        let dir = tempfile::tempdir().unwrap();
        let pfm = dir.path().join("depth.pfm");
        std::fs::write(&pfm, b"Pf\n30000 30000\n-1\n\0\0\0\0").unwrap();
        let message = read_depth(&pfm, (30000, 30000)).unwrap_err().to_string();
        assert!(message.contains("declares 30000×30000 pixels, more than"), "{message}");
        let message = read_depth(&pfm, (640, 480)).unwrap_err().to_string();
        assert!(message.contains("30000×30000 pixels but the camera calibration is for 640×480"));
        let png = dir.path().join("depth.png");
        write_depth_png(&png, (3, 2), &[1000; 6]).unwrap();
        let message = read_depth(&png, (2, 3)).unwrap_err().to_string();
        assert!(message.contains("3×2 pixels but the camera calibration is for 2×3"));
    }

    #[test]
    fn what_is_not_depth_is_refused_in_words() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("depth");
        let refused = |bytes: &[u8], size| {
            std::fs::write(&path, bytes).unwrap();
            read_depth(&path, size).unwrap_err().to_string()
        };
        assert!(refused(b"ply\n", (1, 1)).contains("neither the PNG signature nor `Pf`"));
        assert!(refused(b"PF\n1 1\n-1\n", (1, 1)).contains("colour PFM"));
        assert!(refused(b"Pf\n2 1\n-1\n\0\0\0\0", (2, 1)).contains("4 bytes of data"));
        assert!(refused(b"Pf\n1 1\n-0.5\n\0\0\0\0", (1, 1)).contains("scale is -0.5"));
        assert!(refused(b"Pf\nx 1\n-1\n", (1, 1)).contains("width `x`"));
        assert!(refused(b"Pf\n1 1", (1, 1)).contains("cut short"));
        let colour = dir.path().join("image.png");
        crate::sensor_files::write_png(&colour, &crate::hal::ColorImage::new(2, 2)).unwrap();
        let message = read_depth(&colour, (2, 2)).unwrap_err().to_string();
        assert!(message.contains("8-bit Rgb; depth in millimetres takes 16-bit greyscale"));
    }
}
