//! PLY, binary little endian or ASCII, with float normals and uchar colours.

use std::io::{self, BufWriter, Write};

use super::{color_byte, invalid};
use crate::Mesh;

pub(super) fn write(mesh: &Mesh, w: &mut impl Write, ascii: bool) -> io::Result<()> {
    let mut w = BufWriter::new(w);
    let (normals, colors) = (!mesh.normals.is_empty(), !mesh.colors.is_empty());
    let format = if ascii {
        "ascii"
    } else {
        "binary_little_endian"
    };
    writeln!(w, "ply\nformat {format} 1.0\ncomment frep-mesh")?;
    writeln!(w, "element vertex {}", mesh.positions.len())?;
    writeln!(w, "property float x\nproperty float y\nproperty float z")?;
    if normals {
        writeln!(w, "property float nx\nproperty float ny\nproperty float nz")?;
    }
    if colors {
        writeln!(
            w,
            "property uchar red\nproperty uchar green\nproperty uchar blue"
        )?;
    }
    writeln!(w, "element face {}", mesh.triangles.len())?;
    writeln!(w, "property list uchar int vertex_indices\nend_header")?;
    for i in 0..mesh.positions.len() {
        let floats = std::iter::once(mesh.positions[i])
            .chain(mesh.normals.get(i).copied())
            .flatten();
        let bytes = mesh.colors.get(i).map(|c| c.map(color_byte));
        if ascii {
            let mut line: Vec<String> = floats.map(|f| f.to_string()).collect();
            line.extend(bytes.into_iter().flatten().map(|b| b.to_string()));
            writeln!(w, "{}", line.join(" "))?;
        } else {
            for f in floats {
                w.write_all(&f.to_le_bytes())?;
            }
            w.write_all(bytes.as_ref().map_or(&[][..], |b| &b[..]))?;
        }
    }
    for &[a, b, c] in &mesh.triangles {
        if ascii {
            writeln!(w, "3 {a} {b} {c}")?;
        } else {
            w.write_all(&[3])?;
            for i in [a, b, c] {
                w.write_all(&(i as i32).to_le_bytes())?;
            }
        }
    }
    w.flush()
}

#[derive(Clone, Copy, Debug, PartialEq)]
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
    fn parse(name: &str) -> io::Result<Scalar> {
        Ok(match name {
            "char" | "int8" => Scalar::I8,
            "uchar" | "uint8" => Scalar::U8,
            "short" | "int16" => Scalar::I16,
            "ushort" | "uint16" => Scalar::U16,
            "int" | "int32" => Scalar::I32,
            "uint" | "uint32" => Scalar::U32,
            "float" | "float32" => Scalar::F32,
            "double" | "float64" => Scalar::F64,
            _ => return Err(invalid(format!("unknown PLY type {name:?}"))),
        })
    }

    fn size(self) -> usize {
        match self {
            Scalar::I8 | Scalar::U8 => 1,
            Scalar::I16 | Scalar::U16 => 2,
            Scalar::I32 | Scalar::U32 | Scalar::F32 => 4,
            Scalar::F64 => 8,
        }
    }
}

struct Property {
    name: String,
    /// `Some(count type)` for a list property.
    list: Option<Scalar>,
    ty: Scalar,
}

struct Element {
    name: String,
    count: usize,
    properties: Vec<Property>,
}

/// The body after the header, read value by value.
enum Body<'a> {
    Ascii(std::str::SplitAsciiWhitespace<'a>),
    Binary {
        bytes: &'a [u8],
        pos: usize,
        big_endian: bool,
    },
}

impl Body<'_> {
    fn value(&mut self, ty: Scalar) -> io::Result<f64> {
        match self {
            Body::Ascii(tokens) => {
                let t = tokens
                    .next()
                    .ok_or_else(|| invalid("PLY body ends early"))?;
                t.parse()
                    .map_err(|_| invalid(format!("bad PLY value {t:?}")))
            }
            Body::Binary {
                bytes,
                pos,
                big_endian,
            } => {
                let n = ty.size();
                let raw = bytes
                    .get(*pos..*pos + n)
                    .ok_or_else(|| invalid("PLY body ends early"))?;
                *pos += n;
                let mut b = [0u8; 8];
                b[..n].copy_from_slice(raw);
                if *big_endian {
                    b[..n].reverse();
                }
                Ok(match ty {
                    Scalar::I8 => b[0] as i8 as f64,
                    Scalar::U8 => b[0] as f64,
                    Scalar::I16 => i16::from_le_bytes([b[0], b[1]]) as f64,
                    Scalar::U16 => u16::from_le_bytes([b[0], b[1]]) as f64,
                    Scalar::I32 => i32::from_le_bytes([b[0], b[1], b[2], b[3]]) as f64,
                    Scalar::U32 => u32::from_le_bytes([b[0], b[1], b[2], b[3]]) as f64,
                    Scalar::F32 => f32::from_le_bytes([b[0], b[1], b[2], b[3]]) as f64,
                    Scalar::F64 => f64::from_le_bytes(b),
                })
            }
        }
    }
}

fn parse_header(text: &str) -> io::Result<(String, Vec<Element>)> {
    let mut format = String::new();
    let mut elements: Vec<Element> = Vec::new();
    for line in text.lines().skip(1) {
        let tok: Vec<&str> = line.split_ascii_whitespace().collect();
        match tok.as_slice() {
            ["format", f, ..] => format = f.to_string(),
            ["element", name, count] => elements.push(Element {
                name: name.to_string(),
                count: count
                    .parse()
                    .map_err(|_| invalid("bad PLY element count"))?,
                properties: Vec::new(),
            }),
            ["property", "list", count, ty, name] => {
                let e = elements
                    .last_mut()
                    .ok_or_else(|| invalid("PLY property before element"))?;
                e.properties.push(Property {
                    name: name.to_string(),
                    list: Some(Scalar::parse(count)?),
                    ty: Scalar::parse(ty)?,
                });
            }
            ["property", ty, name] => {
                let e = elements
                    .last_mut()
                    .ok_or_else(|| invalid("PLY property before element"))?;
                e.properties.push(Property {
                    name: name.to_string(),
                    list: None,
                    ty: Scalar::parse(ty)?,
                });
            }
            _ => {}
        }
    }
    Ok((format, elements))
}

pub(super) fn read(bytes: &[u8]) -> io::Result<Mesh> {
    const END: &[u8] = b"end_header";
    let end = bytes
        .windows(END.len())
        .position(|w| w == END)
        .ok_or_else(|| invalid("no PLY header"))?;
    let header = std::str::from_utf8(&bytes[..end]).map_err(invalid)?;
    if !header.starts_with("ply") {
        return Err(invalid("not a PLY file"));
    }
    // The body starts after the newline (LF or CR LF) that ends the header.
    let mut body_start = end + END.len();
    while body_start < bytes.len() && bytes[body_start] != b'\n' {
        body_start += 1;
    }
    let body = bytes.get(body_start + 1..).unwrap_or_default();
    let (format, elements) = parse_header(header)?;
    let mut body = match format.as_str() {
        "ascii" => Body::Ascii(
            std::str::from_utf8(body)
                .map_err(invalid)?
                .split_ascii_whitespace(),
        ),
        "binary_little_endian" => Body::Binary {
            bytes: body,
            pos: 0,
            big_endian: false,
        },
        "binary_big_endian" => Body::Binary {
            bytes: body,
            pos: 0,
            big_endian: true,
        },
        _ => return Err(invalid(format!("unknown PLY format {format:?}"))),
    };
    let mut mesh = Mesh::default();
    for e in &elements {
        let slot = |name: &str| e.properties.iter().position(|p| p.name == name);
        let position = ["x", "y", "z"].map(slot);
        let normal = ["nx", "ny", "nz"].map(slot);
        let color = ["red", "green", "blue"].map(slot);
        let mut values = vec![0.0f64; e.properties.len()];
        for _ in 0..e.count {
            let mut indices = Vec::new();
            for (k, p) in e.properties.iter().enumerate() {
                match p.list {
                    None => values[k] = body.value(p.ty)?,
                    Some(count_ty) => {
                        let n = body.value(count_ty)? as usize;
                        let is_index = p.name == "vertex_indices" || p.name == "vertex_index";
                        for _ in 0..n {
                            let v = body.value(p.ty)?;
                            if is_index {
                                indices.push(v as u32);
                            }
                        }
                    }
                }
            }
            if e.name == "vertex" {
                let get = |s: [Option<usize>; 3]| s.map(|k| k.map_or(0.0, |k| values[k]));
                mesh.positions.push(get(position).map(|v| v as f32));
                if normal.iter().all(Option::is_some) {
                    mesh.normals.push(get(normal).map(|v| v as f32));
                }
                if color.iter().all(Option::is_some) {
                    let scale = match e.properties[color[0].unwrap_or(0)].ty {
                        Scalar::F32 | Scalar::F64 => 1.0,
                        _ => 255.0,
                    };
                    mesh.colors.push(get(color).map(|v| (v / scale) as f32));
                }
            } else if e.name == "face" {
                for k in 1..indices.len().saturating_sub(1) {
                    mesh.triangles
                        .push([indices[0], indices[k], indices[k + 1]]);
                }
            }
        }
    }
    Ok(mesh)
}
