//! The legend under a picture: each marking's colour and what it means, in words, so a person
//! who never read the paper can read the picture. Letters come from a 3×5 pixel font drawn at
//! twice its size; the legend needs no font file and no text library.

use crate::hal::ColorImage;

/// Pixels per font pixel.
const SCALE: u32 = 2;
/// One line of the legend, in pixels.
const LINE: u32 = 7 * SCALE;
const MARGIN: u32 = 4;
const PAPER: [u8; 3] = [250, 250, 250];
const INK: [u8; 3] = [20, 20, 20];

/// `picture` with a white strip below it holding `key` (colour, words), two entries a line.
pub fn with_legend(picture: &ColorImage, key: &[([u8; 3], &str)]) -> ColorImage {
    let lines = key.len().div_ceil(2) as u32;
    let strip = MARGIN * 2 + lines * LINE;
    let mut out = ColorImage::new(picture.width, picture.height + strip);
    out.rgb[..picture.rgb.len()].copy_from_slice(&picture.rgb);
    fill(&mut out, 0, picture.height, picture.width, strip, PAPER);
    let column = picture.width / 2;
    for (n, (colour, words)) in key.iter().enumerate() {
        let x = MARGIN + (n as u32 % 2) * column;
        let y = picture.height + MARGIN + (n as u32 / 2) * LINE;
        fill(&mut out, x, y, 5 * SCALE, 5 * SCALE, *colour);
        write(&mut out, x + 7 * SCALE, y, words);
    }
    out
}

fn fill(image: &mut ColorImage, x: u32, y: u32, width: u32, height: u32, colour: [u8; 3]) {
    for row in y..(y + height).min(image.height) {
        for col in x..(x + width).min(image.width) {
            let at = (row as usize * image.width as usize + col as usize) * 3;
            image.rgb[at..at + 3].copy_from_slice(&colour);
        }
    }
}

/// Writes `text` (letters and spaces; other characters are left blank) from `(x, y)`.
fn write(image: &mut ColorImage, x: u32, y: u32, text: &str) {
    for (n, letter) in text.chars().enumerate() {
        let left = x + n as u32 * 4 * SCALE;
        for (row, bits) in glyph(letter).iter().enumerate() {
            for col in 0..3 {
                if bits & (0b100 >> col) != 0 {
                    let (px, py) = (left + col * SCALE, y + row as u32 * SCALE);
                    fill(image, px, py, SCALE, SCALE, INK);
                }
            }
        }
    }
}

/// The letter's five rows, three pixels each (the high bit is the left pixel).
fn glyph(letter: char) -> [u8; 5] {
    const LETTERS: [[u8; 5]; 26] = [
        [0b010, 0b101, 0b111, 0b101, 0b101],
        [0b110, 0b101, 0b110, 0b101, 0b110],
        [0b011, 0b100, 0b100, 0b100, 0b011],
        [0b110, 0b101, 0b101, 0b101, 0b110],
        [0b111, 0b100, 0b110, 0b100, 0b111],
        [0b111, 0b100, 0b110, 0b100, 0b100],
        [0b011, 0b100, 0b101, 0b101, 0b011],
        [0b101, 0b101, 0b111, 0b101, 0b101],
        [0b111, 0b010, 0b010, 0b010, 0b111],
        [0b001, 0b001, 0b001, 0b101, 0b010],
        [0b101, 0b101, 0b110, 0b101, 0b101],
        [0b100, 0b100, 0b100, 0b100, 0b111],
        [0b101, 0b111, 0b111, 0b101, 0b101],
        [0b110, 0b101, 0b101, 0b101, 0b101],
        [0b010, 0b101, 0b101, 0b101, 0b010],
        [0b110, 0b101, 0b110, 0b100, 0b100],
        [0b010, 0b101, 0b101, 0b110, 0b011],
        [0b110, 0b101, 0b110, 0b101, 0b101],
        [0b011, 0b100, 0b010, 0b001, 0b110],
        [0b111, 0b010, 0b010, 0b010, 0b010],
        [0b101, 0b101, 0b101, 0b101, 0b111],
        [0b101, 0b101, 0b101, 0b101, 0b010],
        [0b101, 0b101, 0b111, 0b111, 0b101],
        [0b101, 0b101, 0b010, 0b101, 0b101],
        [0b101, 0b101, 0b010, 0b010, 0b010],
        [0b111, 0b001, 0b010, 0b100, 0b111],
    ];
    match letter.to_ascii_lowercase() {
        c @ 'a'..='z' => LETTERS[(c as u8 - b'a') as usize],
        _ => [0; 5],
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn count(image: &ColorImage, colour: [u8; 3]) -> usize {
        image.rgb.chunks(3).filter(|px| *px == colour).count()
    }

    #[test]
    fn the_legend_sits_below_the_picture_with_each_colour_and_its_words() {
        let picture = ColorImage::new(200, 100);
        let key = [([255, 0, 0], "tag"), ([0, 0, 255], "plane"), ([0, 255, 0], "robot")];
        let out = with_legend(&picture, &key);
        assert_eq!(out.width, 200);
        assert_eq!(&out.rgb[..picture.rgb.len()], &picture.rgb[..], "the picture is untouched");
        assert_eq!(out.height, 100 + 2 * MARGIN + 2 * LINE, "two entries a line");
        for (colour, _) in key {
            assert_eq!(count(&out, colour), (5 * SCALE * 5 * SCALE) as usize);
        }
        let ink = count(&out, INK);
        let expected: u32 = "tagplanerobot"
            .chars()
            .map(|c| glyph(c).iter().map(|row| row.count_ones()).sum::<u32>())
            .sum();
        assert_eq!(ink, (expected * SCALE * SCALE) as usize, "every letter drawn, nothing else");
    }
}
