//! `sensor_msgs/Image` to the colour image perception reads: rgb8 as it is, bgr8 swapped,
//! rows of any `step` (drivers pad rows to alignment).

use pps_robot::hal::ColorImage;

use crate::input_error::InputError;
use crate::msg::sensor::Image;

/// The image as `[r, g, b]` pixels, or why it cannot be read.
pub fn color_image(image: &Image) -> Result<ColorImage, InputError> {
    let swap = match image.encoding.as_str() {
        "rgb8" => false,
        "bgr8" => true,
        other => return Err(InputError::ImageEncoding(other.to_owned())),
    };
    let (width, height) = (image.width as usize, image.height as usize);
    if width == 0 || height == 0 {
        return Err(InputError::ImageShape(format!("it is {width}×{height}")));
    }
    let row = width * 3;
    let step = image.step as usize;
    if step < row {
        return Err(InputError::ImageShape(format!(
            "step {step} is shorter than a row of {width} pixels ({row} bytes)"
        )));
    }
    let needed = step * (height - 1) + row;
    if image.data.len() < needed {
        return Err(InputError::ImageShape(format!(
            "{} bytes of data for {height} rows of step {step} ({needed} needed)",
            image.data.len()
        )));
    }
    let mut rgb = Vec::with_capacity(row * height);
    for y in 0..height {
        rgb.extend_from_slice(&image.data[y * step..y * step + row]);
    }
    if swap {
        for pixel in rgb.chunks_exact_mut(3) {
            pixel.swap(0, 2);
        }
    }
    Ok(ColorImage { width: image.width, height: image.height, rgb })
}

/// A colour image as `rgb8`, rows unpadded: what the simulated robot publishes.
pub fn image_message(image: &ColorImage, header: crate::msg::builtin::Header) -> Image {
    Image {
        header,
        height: image.height,
        width: image.width,
        encoding: "rgb8".into(),
        is_bigendian: 0,
        step: image.width * 3,
        data: image.rgb.clone(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn image(encoding: &str, step: u32, data: Vec<u8>) -> Image {
        Image { height: 2, width: 2, encoding: encoding.into(), step, data, ..Image::default() }
    }

    #[test]
    fn rgb8_with_padded_rows_is_read_row_by_row() {
        let data = vec![1, 2, 3, 4, 5, 6, 0, 0, 7, 8, 9, 10, 11, 12, 0, 0];
        let read = color_image(&image("rgb8", 8, data)).unwrap();
        assert_eq!(read.rgb, vec![1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12]);
    }

    #[test]
    fn bgr8_is_swapped_to_rgb() {
        let data = vec![3, 2, 1, 6, 5, 4, 9, 8, 7, 12, 11, 10];
        let read = color_image(&image("bgr8", 6, data)).unwrap();
        assert_eq!(read.pixel(0, 0), [1, 2, 3]);
        assert_eq!(read.pixel(1, 1), [10, 11, 12]);
    }

    #[test]
    fn other_encodings_and_short_data_are_refused_in_words() {
        let refused = color_image(&image("mono16", 4, vec![0; 8])).unwrap_err();
        assert!(refused.to_string().contains("mono16"), "{refused}");
        let short = color_image(&image("rgb8", 6, vec![0; 11])).unwrap_err();
        assert!(matches!(short, InputError::ImageShape(_)), "{short}");
        let narrow = color_image(&image("rgb8", 5, vec![0; 12])).unwrap_err();
        assert!(matches!(narrow, InputError::ImageShape(_)), "{narrow}");
    }
}
