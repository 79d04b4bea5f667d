//! Colour segmentation of only the red regions the laser saw: the raw segmented image of
//! [`super::segment_color`] wherever a tag's points could land, at a fraction of the pixels.
//!
//! Only the pixels laser points land on are ever read from the mask. So instead of testing every
//! pixel, the search starts from the pixels the cloud projects to (those of its points near
//! the target, where the tag search is concerned): each one whose own colour passes seeds its
//! tile (64 pixels, one mask word, by 8 rows); a seeded tile is segmented in full, and a
//! segmented tile holding any red segments its eight neighbours in turn. The result is every red
//! region some laser point lands on, whole, in a ring of at least 8 pixels that is segmented
//! too. The search for seeds, most of the work, runs on every core, a band of tile rows each;
//! the flood from them is short.
//!
//! That ring is wider than anything morphology reaches (closing by 2 and opening by 1 look 6
//! pixels away), and a hole is enclosed by one connected red region, so hole filling, closing,
//! opening and the blobs give, on and around those regions, exactly what they give on the full
//! segmentation. What is missing is red that no laser point falls on: no point can be kept on
//! it, except one on a pixel that only morphology made red in a region no point falls on the red
//! of, which a tag the laser sampled (at least ten of its points, by default) is not.

use std::ops::Range;

use rayon::prelude::*;

use super::hsv::HsvThresholds;
use super::mask::Mask;
use crate::hal::ColorImage;

/// Rows of a tile; its width is one mask word, 64 pixels.
const TILE_ROWS: usize = 8;

/// Tile rows a core scans for seeds at a time: 64 image rows, so a 768-row picture is 12
/// bands and two cores finish within a band of each other.
const SCAN_BAND: usize = 8;

/// The raw segmented image of `image` within the red regions that the set pixels of `seeds`
/// (where the cloud's points land) fall on, and the tiles around them; unset elsewhere.
pub fn segment_seeded(image: &ColorImage, thresholds: &HsvThresholds, seeds: &Mask) -> Mask {
    let (width, height) = (image.width as usize, image.height as usize);
    assert_eq!((seeds.width(), seeds.height()), (width, height), "seeds and image");
    let mut mask = Mask::new(width, height);
    let (cols, rows) = (width.div_ceil(64), height.div_ceil(TILE_ROWS));
    // Which tiles a passing seed falls in, a band of tile rows to a core, in the order one
    // scan row by row would find them; the flood then reaches the same tiles from them.
    let mut pending: Vec<usize> = (0..rows.div_ceil(SCAN_BAND))
        .into_par_iter()
        .map(|band| {
            let tile_rows = band * SCAN_BAND..((band + 1) * SCAN_BAND).min(rows);
            seeded_tiles(image, thresholds, seeds, tile_rows)
        })
        .collect::<Vec<Vec<usize>>>()
        .concat();
    let mut queued = vec![false; cols * rows];
    for &tile in &pending {
        queued[tile] = true;
    }
    while let Some(tile) = pending.pop() {
        let (col, row) = (tile % cols, tile / cols);
        let mut any = 0;
        for y in row * TILE_ROWS..((row + 1) * TILE_ROWS).min(height) {
            let word = thresholds.word_of(image, col, y);
            mask.row_mut(y)[col] = word;
            any |= word;
        }
        if any == 0 {
            continue;
        }
        for r in row.saturating_sub(1)..(row + 2).min(rows) {
            for c in col.saturating_sub(1)..(col + 2).min(cols) {
                let neighbour = r * cols + c;
                if !queued[neighbour] {
                    queued[neighbour] = true;
                    pending.push(neighbour);
                }
            }
        }
    }
    mask
}

/// The tiles of the tile rows `tile_rows` holding a seed whose own colour passes, in row
/// order. Row by row, so the image is read in order; a tile's seeds are tested until one passes.
fn seeded_tiles(
    image: &ColorImage,
    thresholds: &HsvThresholds,
    seeds: &Mask,
    tile_rows: Range<usize>,
) -> Vec<usize> {
    let (width, height) = (image.width as usize, image.height as usize);
    let cols = width.div_ceil(64);
    let mut seeded = Vec::new();
    let mut queued = vec![false; cols];
    for tile_row in tile_rows {
        queued.fill(false);
        for y in tile_row * TILE_ROWS..((tile_row + 1) * TILE_ROWS).min(height) {
            let row = &image.rgb[y * width * 3..(y + 1) * width * 3];
            for (col, &word) in seeds.row(y).iter().enumerate() {
                if word == 0 || queued[col] {
                    continue;
                }
                let mut bits = word;
                while bits != 0 {
                    let at = (col * 64 + bits.trailing_zeros() as usize) * 3;
                    if thresholds.contains([row[at], row[at + 1], row[at + 2]]) {
                        queued[col] = true;
                        seeded.push(tile_row * cols + col);
                        break;
                    }
                    bits &= bits - 1;
                }
            }
        }
    }
    seeded
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::perception::segment_color;

    const RED: [u8; 3] = [200, 20, 30];

    fn paint(image: &mut ColorImage, x: std::ops::Range<usize>, y: std::ops::Range<usize>) {
        for yy in y {
            for xx in x.clone() {
                let at = (yy * image.width as usize + xx) * 3;
                image.rgb[at..at + 3].copy_from_slice(&RED);
            }
        }
    }

    #[test]
    fn a_seeded_region_is_segmented_whole_and_an_unseen_one_not_at_all() {
        let mut image = ColorImage::new(400, 100);
        // A long diagonal-ish band crossing many tiles, and a patch no seed falls on.
        for step in 0..30 {
            paint(&mut image, 10 + step * 9..30 + step * 9, 5 + step * 3..9 + step * 3);
        }
        paint(&mut image, 350..380, 10..20);
        let thresholds = HsvThresholds::default();
        let full = segment_color(&image, &thresholds);
        let seeds = |pixels: &[(usize, usize)]| {
            let mut seeds = Mask::new(400, 100);
            for &(x, y) in pixels {
                seeds.set(x, y, true);
            }
            seeds
        };
        // One seed on the band's far end, and seeds on grey pixels, which seed nothing.
        let seeded = segment_seeded(&image, &thresholds, &seeds(&[(280, 93), (0, 0), (399, 99)]));
        for y in 0..100 {
            for x in 0..400 {
                let expected = full.get(x, y) && x < 340;
                assert_eq!(seeded.get(x, y), expected, "pixel ({x}, {y})");
            }
        }
        let unseeded = segment_seeded(&image, &thresholds, &seeds(&[(360, 50)]));
        assert_eq!(unseeded.count(), 0);
    }
}
