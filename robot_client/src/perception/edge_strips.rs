//! The strip a red thing's edge leaves in the picture once the thing is taken out of a region
//! by its colour (issue 34).
//!
//! Along its outline the camera mixes the thing's colour with what lies behind or beside it,
//! and the colour split reads each point as the mean of the pixels around its own; so a ring of
//! pixels as wide as that mixing and that mean has the colour of neither and stays behind.
//! Left in, the ring joins whatever the thing touched into a part too large to be a tag: a
//! flip switch's foam tube 2.8 cm across (357 points) and what stayed of the outline of a red
//! fabric touching it made one part 34 cm across (472 points). A tag seen at all is wider than
//! the ring wherever it is seen, so an opening of the rest's pixels by the square the mean
//! reads removes the ring and keeps the tag.
//!
//! Only a cloud dense in the picture has such rings: a depth camera's, one point a pixel. A
//! laser's beams mostly land pixels apart, or along scan lines, so that an opening would keep
//! none of them, and such a cloud is left as it is. A fine scan seen by a coarse camera (the
//! simulator's tilting laser, near) does fill the picture, and is treated as a depth camera's.

use super::mask::Mask;

/// Whether the points at `pixels` (`None`: outside the picture) cover the picture densely
/// enough for strips of it to be found: most of their pixels have a neighbour among them both
/// in their row and in their column, as the pixels of a depth camera's surfaces do.
pub(super) fn dense_in_the_picture(pixels: &[Option<(u32, u32)>], width: u32, height: u32) -> bool {
    let mask = mask_of(pixels, width, height);
    let seen = pixels.iter().flatten().count();
    let with_neighbours =
        pixels.iter().flatten().filter(|&&(x, y)| has_neighbours(&mask, x, y)).count();
    2 * with_neighbours > seen
}

/// Which of the points at `pixels` lie off every strip of the picture narrower than a square
/// `reach` pixels around a pixel, in a picture `width` by `height`; a point outside it does not.
pub(super) fn off_the_strips(
    pixels: &[Option<(u32, u32)>],
    width: u32,
    height: u32,
    reach: u32,
) -> Vec<bool> {
    let kept = mask_of(pixels, width, height).open(reach as usize);
    pixels.iter().map(|px| px.is_some_and(|(x, y)| kept.get(x as usize, y as usize))).collect()
}

fn mask_of(pixels: &[Option<(u32, u32)>], width: u32, height: u32) -> Mask {
    let mut mask = Mask::new(width as usize, height as usize);
    for &(x, y) in pixels.iter().flatten() {
        mask.set(x as usize, y as usize, true);
    }
    mask
}

/// Whether the pixels beside `(x, y)` in its row and in its column are set, one of each at
/// least: a laser's beams land pixels apart, or along scan lines whose pixels have neighbours
/// one way only, and so fewer than 2 % of its pixels have both.
fn has_neighbours(mask: &Mask, x: u32, y: u32) -> bool {
    let (x, y) = (x as usize, y as usize);
    let set = |xx: Option<usize>, yy: Option<usize>| match (xx, yy) {
        (Some(xx), Some(yy)) => xx < mask.width() && yy < mask.height() && mask.get(xx, yy),
        _ => false,
    };
    (set(x.checked_sub(1), Some(y)) || set(Some(x + 1), Some(y)))
        && (set(Some(x), y.checked_sub(1)) || set(Some(x), Some(y + 1)))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn pixels(set: impl Iterator<Item = (u32, u32)>) -> Vec<Option<(u32, u32)>> {
        set.map(Some).collect()
    }

    #[test]
    fn a_strip_narrower_than_the_square_goes_and_a_patch_stays() {
        // A 20 × 20 patch and, from its right side, a strip two pixels high and 50 long.
        let patch = (10..30).flat_map(|y| (10..30).map(move |x| (x, y)));
        let strip = (20..22).flat_map(|y| (30..80).map(move |x| (x, y)));
        let all = pixels(patch.chain(strip));
        let off = off_the_strips(&all, 100, 100, 1);
        for (px, off) in all.iter().flatten().zip(&off) {
            match px {
                (x, _) if *x < 30 => assert!(off, "the patch's {px:?} went"),
                (x, _) if *x > 30 => assert!(!off, "the strip's {px:?} stayed"),
                _ => {}
            }
        }
        assert!(!off_the_strips(&[None], 100, 100, 1)[0], "a point outside the picture");
    }

    #[test]
    fn a_depth_cameras_pixels_are_dense_and_a_lasers_are_not() {
        let square = |step_x: usize, step_y: usize| {
            pixels(
                (0..60)
                    .step_by(step_y)
                    .flat_map(move |y| (0..60).step_by(step_x).map(move |x| (x, y))),
            )
        };
        assert!(dense_in_the_picture(&square(1, 1), 100, 100), "a point a pixel");
        assert!(!dense_in_the_picture(&square(4, 4), 100, 100), "beams four pixels apart");
        assert!(!dense_in_the_picture(&square(1, 4), 100, 100), "scan lines four rows apart");
        assert!(!dense_in_the_picture(&square(4, 1), 100, 100), "scan lines four columns apart");
    }
}
