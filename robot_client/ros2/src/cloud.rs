//! `sensor_msgs/PointCloud2` to the cloud perception reads: float32 `x`, `y`, `z` wherever the
//! fields put them, any `point_step`, rows of any `row_step`; points that are not finite (an
//! unorganised driver's "no return") are dropped.

use nalgebra::Point3;
use pps_robot::hal::PointCloud;

use crate::input_error::InputError;
use crate::msg::builtin::Header;
use crate::msg::sensor::{PointCloud2, PointField};

/// The byte offsets of x, y and z within a point.
fn xyz_offsets(cloud: &PointCloud2) -> Result<[usize; 3], InputError> {
    let mut offsets = [0usize; 3];
    for (slot, name) in offsets.iter_mut().zip(["x", "y", "z"]) {
        let field = cloud
            .fields
            .iter()
            .find(|f| f.name == name && f.datatype == PointField::FLOAT32 && f.count >= 1)
            .ok_or(InputError::CloudField(name))?;
        let offset = field.offset as usize;
        if offset + 4 > cloud.point_step as usize {
            return Err(InputError::CloudShape(format!(
                "field `{name}` at byte {offset} runs past the point step {}",
                cloud.point_step
            )));
        }
        *slot = offset;
    }
    Ok(offsets)
}

/// The cloud's finite points, or why it cannot be read.
pub fn point_cloud(cloud: &PointCloud2) -> Result<PointCloud, InputError> {
    if cloud.is_bigendian {
        return Err(InputError::CloudBigEndian);
    }
    let [ox, oy, oz] = xyz_offsets(cloud)?;
    let (width, height) = (cloud.width as usize, cloud.height as usize);
    let (step, row_step) = (cloud.point_step as usize, cloud.row_step as usize);
    if height > 1 && row_step < width * step {
        return Err(InputError::CloudShape(format!(
            "row step {row_step} is shorter than {width} points of {step} bytes"
        )));
    }
    if width > 0 && height > 0 {
        let needed = row_step.max(width * step) * (height - 1) + width * step;
        if cloud.data.len() < needed {
            return Err(InputError::CloudShape(format!(
                "{} bytes of data for {height}×{width} points of {step} bytes ({needed} needed)",
                cloud.data.len()
            )));
        }
    }
    let read = |bytes: &[u8], at: usize| {
        f32::from_le_bytes([bytes[at], bytes[at + 1], bytes[at + 2], bytes[at + 3]])
    };
    let mut points = Vec::with_capacity(width * height);
    for row in 0..height {
        let row_bytes = &cloud.data[row * row_step..row * row_step + width * step];
        for point in row_bytes.chunks_exact(step) {
            let p = Point3::new(read(point, ox), read(point, oy), read(point, oz));
            if p.x.is_finite() && p.y.is_finite() && p.z.is_finite() {
                points.push(p);
            }
        }
    }
    Ok(PointCloud { points })
}

/// A cloud as one row of packed float32 x, y, z: what the simulated robot publishes.
pub fn cloud_message(cloud: &PointCloud, header: Header) -> PointCloud2 {
    let field = |name: &str, offset| PointField {
        name: name.into(),
        offset,
        datatype: PointField::FLOAT32,
        count: 1,
    };
    let mut data = Vec::with_capacity(cloud.len() * 12);
    for p in &cloud.points {
        for v in [p.x, p.y, p.z] {
            data.extend_from_slice(&v.to_le_bytes());
        }
    }
    PointCloud2 {
        header,
        height: 1,
        width: cloud.len() as u32,
        fields: vec![field("x", 0), field("y", 4), field("z", 8)],
        is_bigendian: false,
        point_step: 12,
        row_step: cloud.len() as u32 * 12,
        data,
        is_dense: true,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A cloud with fields in the order z, intensity, x, y and 4 bytes of padding: 20 bytes a
    /// point, as some drivers lay them out.
    fn shuffled(points: &[[f32; 3]]) -> PointCloud2 {
        let field = |name: &str, offset, datatype| PointField {
            name: name.into(),
            offset,
            datatype,
            count: 1,
        };
        let mut data = Vec::new();
        for p in points {
            data.extend_from_slice(&p[2].to_le_bytes());
            data.extend_from_slice(&7.0f32.to_le_bytes());
            data.extend_from_slice(&p[0].to_le_bytes());
            data.extend_from_slice(&p[1].to_le_bytes());
            data.extend_from_slice(&[0xAA; 4]);
        }
        PointCloud2 {
            height: 1,
            width: points.len() as u32,
            fields: vec![
                field("z", 0, PointField::FLOAT32),
                field("intensity", 4, PointField::FLOAT32),
                field("x", 8, PointField::FLOAT32),
                field("y", 12, PointField::FLOAT32),
            ],
            point_step: 20,
            row_step: 20 * points.len() as u32,
            data,
            ..PointCloud2::default()
        }
    }

    #[test]
    fn fields_in_any_order_and_any_point_step_are_read() {
        let cloud = point_cloud(&shuffled(&[[1.0, 2.0, 3.0], [-4.0, 5.5, 0.25]])).unwrap();
        assert_eq!(cloud.points, vec![Point3::new(1.0, 2.0, 3.0), Point3::new(-4.0, 5.5, 0.25)]);
    }

    #[test]
    fn points_that_are_not_finite_are_dropped() {
        let cloud = point_cloud(&shuffled(&[[f32::NAN, 0.0, 0.0], [1.0, 1.0, 1.0]])).unwrap();
        assert_eq!(cloud.points, vec![Point3::new(1.0, 1.0, 1.0)]);
    }

    #[test]
    fn what_we_publish_reads_back_the_same() {
        let original =
            PointCloud { points: vec![Point3::new(0.5, -0.25, 1.5), Point3::new(3.0, 2.0, 1.0)] };
        let back = point_cloud(&cloud_message(&original, Header::default())).unwrap();
        assert_eq!(back, original);
    }

    #[test]
    fn a_cloud_without_float32_xyz_is_refused_in_words() {
        let mut cloud = shuffled(&[[1.0, 2.0, 3.0]]);
        cloud.fields[3].datatype = PointField::FLOAT64;
        let refused = point_cloud(&cloud).unwrap_err();
        assert_eq!(refused, InputError::CloudField("y"));
        assert!(refused.to_string().contains("float32"));
        let mut short = shuffled(&[[1.0, 2.0, 3.0], [1.0, 2.0, 3.0]]);
        short.data.truncate(30);
        assert!(matches!(point_cloud(&short), Err(InputError::CloudShape(_))));
        let mut past = shuffled(&[[1.0, 2.0, 3.0]]);
        past.point_step = 12;
        past.row_step = 12;
        assert!(matches!(point_cloud(&past), Err(InputError::CloudShape(_))));
    }
}
