//! Point clouds as PLY: vertices `x y z` in the base frame, metres.
//!
//! The reader takes ASCII and binary (either endianness) files, any numeric type for x, y and z,
//! extra vertex properties (intensity, colour, normals) and other elements before or after the
//! vertices (faces, say), which it skips. Points with a non-finite coordinate (scanners write NaN
//! for "no return") are dropped. The writer writes `float` x, y, z only.
//!
//! Long because PLY's three encodings share one header parser here; the last sixth of the file
//! is the tests, one per kind of file scanners write.

use std::fs::File;
use std::io::{BufRead, BufReader, BufWriter, Read, Write};
use std::path::Path;

use nalgebra::Point3;

use super::{SensorFileError, io_error};
use crate::hal::PointCloud;

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PlyFormat {
    Ascii,
    BinaryLittleEndian,
    BinaryBigEndian,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Scalar {
    I8,
    U8,
    I16,
    U16,
    I32,
    U32,
    F32,
    F64,
}

impl Scalar {
    fn parse(name: &str) -> Option<Self> {
        Some(match name {
            "char" | "int8" => Self::I8,
            "uchar" | "uint8" => Self::U8,
            "short" | "int16" => Self::I16,
            "ushort" | "uint16" => Self::U16,
            "int" | "int32" => Self::I32,
            "uint" | "uint32" => Self::U32,
            "float" | "float32" => Self::F32,
            "double" | "float64" => Self::F64,
            _ => return None,
        })
    }

    fn size(self) -> usize {
        match self {
            Self::I8 | Self::U8 => 1,
            Self::I16 | Self::U16 => 2,
            Self::I32 | Self::U32 | Self::F32 => 4,
            Self::F64 => 8,
        }
    }

    /// Decodes one value from the front of `b` (at least `size()` bytes).
    fn decode(self, b: &[u8], little: bool) -> f64 {
        macro_rules! num {
            ($t:ty, $n:expr) => {{
                let bytes: [u8; $n] = b[..$n].try_into().expect("length checked by caller");
                if little { <$t>::from_le_bytes(bytes) } else { <$t>::from_be_bytes(bytes) }
            }};
        }
        match self {
            Self::I8 => f64::from(b[0] as i8),
            Self::U8 => f64::from(b[0]),
            Self::I16 => f64::from(num!(i16, 2)),
            Self::U16 => f64::from(num!(u16, 2)),
            Self::I32 => f64::from(num!(i32, 4)),
            Self::U32 => f64::from(num!(u32, 4)),
            Self::F32 => f64::from(num!(f32, 4)),
            Self::F64 => num!(f64, 8),
        }
    }
}

#[derive(Debug, Clone)]
enum Property {
    Scalar { name: String, ty: Scalar },
    List { count: Scalar, item: Scalar },
}

#[derive(Debug, Clone)]
struct Element {
    name: String,
    count: u64,
    properties: Vec<Property>,
}

impl Element {
    /// Bytes per instance when it has no list property.
    fn fixed_size(&self) -> Option<usize> {
        self.properties.iter().try_fold(0, |acc, p| match p {
            Property::Scalar { ty, .. } => Some(acc + ty.size()),
            Property::List { .. } => None,
        })
    }

    fn index_of(&self, wanted: &str) -> Option<usize> {
        self.properties
            .iter()
            .position(|p| matches!(p, Property::Scalar { name, .. } if name == wanted))
    }
}

struct Header {
    format: PlyFormat,
    elements: Vec<Element>,
}

fn read_header(reader: &mut impl BufRead) -> Result<Header, String> {
    let mut line = Vec::new();
    let mut next_line = |reader: &mut dyn BufRead| -> Result<String, String> {
        line.clear();
        let n = reader.read_until(b'\n', &mut line).map_err(|e| e.to_string())?;
        if n == 0 {
            return Err("the header has no end_header line".into());
        }
        String::from_utf8(line.clone()).map_err(|_| "the header is not text".to_string())
    };
    if next_line(reader)?.trim() != "ply" {
        return Err("it does not start with `ply`".into());
    }
    let mut format = None;
    let mut elements: Vec<Element> = Vec::new();
    loop {
        let text = next_line(reader)?;
        let words: Vec<&str> = text.split_whitespace().collect();
        match words.as_slice() {
            ["end_header"] => break,
            [] | ["comment", ..] | ["obj_info", ..] => {}
            ["format", kind, _version] => {
                format = Some(match *kind {
                    "ascii" => PlyFormat::Ascii,
                    "binary_little_endian" => PlyFormat::BinaryLittleEndian,
                    "binary_big_endian" => PlyFormat::BinaryBigEndian,
                    other => return Err(format!("unknown format `{other}`")),
                });
            }
            ["element", name, count] => elements.push(Element {
                name: (*name).to_string(),
                count: count.parse().map_err(|_| format!("element {name} has count `{count}`"))?,
                properties: Vec::new(),
            }),
            ["property", "list", count, item, _name] => {
                let element = elements.last_mut().ok_or("a property comes before any element")?;
                let count = Scalar::parse(count).ok_or(format!("unknown type `{count}`"))?;
                let item = Scalar::parse(item).ok_or(format!("unknown type `{item}`"))?;
                element.properties.push(Property::List { count, item });
            }
            ["property", ty, name] => {
                let element = elements.last_mut().ok_or("a property comes before any element")?;
                let ty = Scalar::parse(ty).ok_or(format!("unknown type `{ty}`"))?;
                element.properties.push(Property::Scalar { name: (*name).to_string(), ty });
            }
            _ => return Err(format!("cannot read header line `{}`", text.trim())),
        }
    }
    let format = format.ok_or("the header has no format line")?;
    Ok(Header { format, elements })
}

/// Reads a PLY file into a cloud.
pub fn read_ply(path: &Path) -> Result<PointCloud, SensorFileError> {
    let file = File::open(path).map_err(|e| io_error(path, e))?;
    read_ply_from(BufReader::with_capacity(1 << 16, file))
        .map_err(|reason| SensorFileError::Ply { path: path.display().to_string(), reason })
}

/// Reads PLY from any buffered reader; the error is a sentence saying what is wrong.
pub fn read_ply_from(mut reader: impl BufRead) -> Result<PointCloud, String> {
    let header = read_header(&mut reader)?;
    let vertex_at = header
        .elements
        .iter()
        .position(|e| e.name == "vertex")
        .ok_or("it has no vertex element")?;
    let vertex = &header.elements[vertex_at];
    let axes = ["x", "y", "z"].map(|a| vertex.index_of(a));
    let [Some(ix), Some(iy), Some(iz)] = axes else {
        return Err("its vertices lack an x, y or z property".into());
    };
    let mut points = Vec::with_capacity(vertex.count.min(1 << 24) as usize);
    let mut values = vec![0.0; vertex.properties.len()];
    let mut push = |values: &[f64]| {
        let p = Point3::new(values[ix] as f32, values[iy] as f32, values[iz] as f32);
        if p.iter().all(|c| c.is_finite()) {
            points.push(p);
        }
    };
    match header.format {
        PlyFormat::Ascii => {
            let mut lines = reader.lines();
            let mut next_record = |what: &str, i: u64| -> Result<String, String> {
                loop {
                    match lines.next() {
                        Some(Ok(line)) if line.trim().is_empty() => continue,
                        Some(Ok(line)) => return Ok(line),
                        Some(Err(e)) => return Err(e.to_string()),
                        None => {
                            return Err(format!(
                                "the file ends at {what} {i} of the header's count"
                            ));
                        }
                    }
                }
            };
            for element in &header.elements[..vertex_at] {
                for i in 0..element.count {
                    next_record(&element.name, i)?;
                }
            }
            for i in 0..vertex.count {
                let line = next_record("vertex", i)?;
                let mut tokens = line.split_whitespace();
                for (slot, property) in values.iter_mut().zip(&vertex.properties) {
                    let mut number = || -> Result<f64, String> {
                        let token =
                            tokens.next().ok_or(format!("vertex {i} has too few values"))?;
                        token
                            .parse::<f64>()
                            .map_err(|_| format!("vertex {i}: `{token}` is not a number"))
                    };
                    match property {
                        Property::Scalar { .. } => *slot = number()?,
                        Property::List { .. } => {
                            for _ in 0..number()? as u64 {
                                number()?;
                            }
                        }
                    }
                }
                push(&values);
            }
        }
        PlyFormat::BinaryLittleEndian | PlyFormat::BinaryBigEndian => {
            let little = header.format == PlyFormat::BinaryLittleEndian;
            for element in &header.elements[..vertex_at] {
                skip_binary_element(&mut reader, element, little)?;
            }
            read_binary_vertices(&mut reader, vertex, little, &mut values, &mut push)?;
        }
    }
    Ok(PointCloud { points })
}

fn read_exact(reader: &mut impl Read, buf: &mut [u8], what: &str) -> Result<(), String> {
    reader.read_exact(buf).map_err(|e| match e.kind() {
        std::io::ErrorKind::UnexpectedEof => format!("the file ends inside the {what} data"),
        _ => e.to_string(),
    })
}

fn skip_binary_element(
    reader: &mut impl BufRead,
    element: &Element,
    little: bool,
) -> Result<(), String> {
    if let Some(size) = element.fixed_size() {
        let total = size as u64 * element.count;
        let skipped = std::io::copy(&mut reader.take(total), &mut std::io::sink())
            .map_err(|e| e.to_string())?;
        return if skipped == total {
            Ok(())
        } else {
            Err(format!("the file ends inside the {} data", element.name))
        };
    }
    let mut buf = [0u8; 8];
    for _ in 0..element.count {
        for property in &element.properties {
            match property {
                Property::Scalar { ty, .. } => {
                    read_exact(reader, &mut buf[..ty.size()], &element.name)?
                }
                Property::List { count, item } => {
                    read_exact(reader, &mut buf[..count.size()], &element.name)?;
                    let n = count.decode(&buf, little) as u64;
                    let total = n * item.size() as u64;
                    let skipped = std::io::copy(&mut reader.take(total), &mut std::io::sink())
                        .map_err(|e| e.to_string())?;
                    if skipped != total {
                        return Err(format!("the file ends inside the {} data", element.name));
                    }
                }
            }
        }
    }
    Ok(())
}

fn read_binary_vertices(
    reader: &mut impl BufRead,
    vertex: &Element,
    little: bool,
    values: &mut [f64],
    push: &mut impl FnMut(&[f64]),
) -> Result<(), String> {
    let Some(size) = vertex.fixed_size() else {
        // Lists inside vertices are rare enough to read value by value.
        let mut buf = [0u8; 8];
        for _ in 0..vertex.count {
            for (slot, property) in values.iter_mut().zip(&vertex.properties) {
                match property {
                    Property::Scalar { ty, .. } => {
                        read_exact(reader, &mut buf[..ty.size()], "vertex")?;
                        *slot = ty.decode(&buf, little);
                    }
                    Property::List { count, item } => {
                        read_exact(reader, &mut buf[..count.size()], "vertex")?;
                        for _ in 0..count.decode(&buf, little) as u64 {
                            read_exact(reader, &mut buf[..item.size()], "vertex")?;
                        }
                    }
                }
            }
            push(values);
        }
        return Ok(());
    };
    let layout: Vec<(usize, Scalar)> = vertex
        .properties
        .iter()
        .scan(0, |offset, p| {
            let Property::Scalar { ty, .. } = p else { return None };
            let at = *offset;
            *offset += ty.size();
            Some((at, *ty))
        })
        .collect();
    // Read in blocks so memory stays at the cloud plus one block.
    let per_block = (1 << 16) / size.max(1) + 1;
    let mut block = vec![0u8; per_block * size];
    let mut remaining = vertex.count;
    while remaining > 0 {
        let n = remaining.min(per_block as u64) as usize;
        read_exact(reader, &mut block[..n * size], "vertex")?;
        for record in block[..n * size].chunks_exact(size) {
            for (slot, &(at, ty)) in values.iter_mut().zip(&layout) {
                *slot = ty.decode(&record[at..], little);
            }
            push(values);
        }
        remaining -= n as u64;
    }
    Ok(())
}

/// Writes `cloud` as PLY with `float` x, y, z.
pub fn write_ply_to(
    mut out: impl Write,
    cloud: &PointCloud,
    format: PlyFormat,
) -> std::io::Result<()> {
    let name = match format {
        PlyFormat::Ascii => "ascii",
        PlyFormat::BinaryLittleEndian => "binary_little_endian",
        PlyFormat::BinaryBigEndian => "binary_big_endian",
    };
    write!(
        out,
        "ply\nformat {name} 1.0\ncomment frame: robot base (x forward, y left, z up), metres\n\
         element vertex {}\nproperty float x\nproperty float y\nproperty float z\nend_header\n",
        cloud.len()
    )?;
    for p in &cloud.points {
        match format {
            PlyFormat::Ascii => writeln!(out, "{} {} {}", p.x, p.y, p.z)?,
            PlyFormat::BinaryLittleEndian => {
                for c in p.iter() {
                    out.write_all(&c.to_le_bytes())?;
                }
            }
            PlyFormat::BinaryBigEndian => {
                for c in p.iter() {
                    out.write_all(&c.to_be_bytes())?;
                }
            }
        }
    }
    out.flush()
}

/// Writes `cloud` to a PLY file.
pub fn write_ply(
    path: &Path,
    cloud: &PointCloud,
    format: PlyFormat,
) -> Result<(), SensorFileError> {
    let file = File::create(path).map_err(|e| io_error(path, e))?;
    write_ply_to(BufWriter::new(file), cloud, format).map_err(|e| io_error(path, e))
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    fn random_cloud(seed: u64, n: usize) -> PointCloud {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let points = (0..n)
            .map(|_| {
                Point3::new(
                    rng.random_range(-5.0..5.0),
                    rng.random_range(-5.0..5.0),
                    rng.random_range(0.0..3.0),
                )
            })
            .collect();
        PointCloud { points }
    }

    #[test]
    fn round_trips_in_every_format() {
        for seed in 0..20 {
            let cloud = random_cloud(seed, 500);
            for format in
                [PlyFormat::Ascii, PlyFormat::BinaryLittleEndian, PlyFormat::BinaryBigEndian]
            {
                let mut bytes = Vec::new();
                write_ply_to(&mut bytes, &cloud, format).unwrap();
                let back = read_ply_from(bytes.as_slice()).unwrap();
                // Rust prints the shortest decimal that parses back to the same f32.
                assert_eq!(back, cloud, "{format:?}");
            }
        }
    }

    #[test]
    fn skips_extra_properties_and_other_elements() {
        let ascii = "ply\r\nformat ascii 1.0\r\ncomment made elsewhere\r\nelement camera 1\r\n\
            property float fov\r\nelement vertex 2\r\nproperty uchar red\r\nproperty double z\r\n\
            property list uchar int idx\r\nproperty double x\r\nproperty float y\r\n\
            element face 1\r\nproperty list uchar int vertex_indices\r\nend_header\r\n\
            0.9\r\n255 3.0 2 7 8 1.0 2.0\r\n0 6 0 4 5\r\n3 0 1 2\r\n";
        let cloud = read_ply_from(ascii.as_bytes()).unwrap();
        assert_eq!(cloud.points, vec![Point3::new(1.0, 2.0, 3.0), Point3::new(4.0, 5.0, 6.0)]);

        let mut binary = b"ply\nformat binary_little_endian 1.0\nelement face 1\n\
            property list uchar int vertex_indices\nelement vertex 2\nproperty float x\n\
            property float y\nproperty float z\nproperty float intensity\nend_header\n"
            .to_vec();
        binary.push(3);
        for i in [0i32, 1, 2] {
            binary.extend_from_slice(&i.to_le_bytes());
        }
        for v in [1.0f32, 2.0, 3.0, 0.5, f32::NAN, 5.0, 6.0, 0.5] {
            binary.extend_from_slice(&v.to_le_bytes());
        }
        let cloud = read_ply_from(binary.as_slice()).unwrap();
        assert_eq!(cloud.points, vec![Point3::new(1.0, 2.0, 3.0)], "the NaN point is dropped");
    }

    #[test]
    fn says_what_is_wrong() {
        let cases: [(&[u8], &str); 5] = [
            (b"PNG....", "does not start with `ply`"),
            (b"ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nend_header\n1\n", "x, y or z"),
            (b"ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\nproperty float z\nend_header\n1 2 3\n", "ends at vertex 1"),
            (b"ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nproperty float z\nend_header\n1 2 zz\n", "`zz` is not a number"),
            (b"ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nend_header\n\0\0\0\0", "ends inside the vertex"),
        ];
        for (input, expected) in cases {
            let message = read_ply_from(input).unwrap_err();
            assert!(message.contains(expected), "{message:?} should say {expected:?}");
        }
    }
}
