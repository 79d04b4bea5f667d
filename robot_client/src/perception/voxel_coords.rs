//! Which cube of a grid a point falls in: `floor(coordinate / size)` per axis.
//!
//! On the baseline x86-64 target `f32::floor` is a call into libm (rounding down is an SSE4.1
//! instruction), and the occupancy grid, the plane search's cells and the tag's fragment test
//! floor every coordinate of thousands of points; truncation corrected by one is inlined.

/// `x.floor() as i64`, to the same result for every `x` (NaN gives 0, out-of-range saturates).
#[inline]
pub(crate) fn floor_to_i64(x: f32) -> i64 {
    let truncated = x as i64;
    // Truncation rounds negative non-integers up; step them down.
    if (truncated as f32) > x { truncated.saturating_sub(1) } else { truncated }
}

/// The grid cube of edge `size` that `p` falls in.
#[inline]
pub(crate) fn cube_of(p: &nalgebra::Point3<f32>, size: f32) -> [i64; 3] {
    [p.x, p.y, p.z].map(|c| floor_to_i64(c / size))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rounds_down_like_floor() {
        let values = [
            0.0,
            -0.0,
            0.5,
            -0.5,
            1.0,
            -1.0,
            -1.5,
            2.999_999_8,
            -2.999_999_8,
            1e30,
            -1e30,
            f32::NAN,
            f32::INFINITY,
            f32::NEG_INFINITY,
            -9.223_372e18,
        ];
        for x in values {
            assert_eq!(floor_to_i64(x), x.floor() as i64, "{x}");
        }
        for i in -100_000..100_000 {
            let x = i as f32 * 0.013_7;
            assert_eq!(floor_to_i64(x), x.floor() as i64, "{x}");
        }
    }
}
