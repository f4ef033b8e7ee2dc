//! glTF 2.0 binary (`.glb`) with quantized attributes, optionally compressed with
//! `EXT_meshopt_compression`.
//!
//! Layout (both variants): one mesh with one indexed triangle primitive.
//! - `POSITION` as unnormalized `u16` (stride 8), under a node whose uniform scale and
//!   translation map the grid back onto the bounding box (`KHR_mesh_quantization`).
//! - `NORMAL` as normalized `i8` (stride 4).
//! - `COLOR_0` as normalized `u8` (stride 4), holding *linear* RGB as glTF requires. Mesh
//!   colours are sRGB and are converted both ways.
//! - Indices as `u16` when the vertices allow, else `u32`.
//!
//! The meshopt variant:
//! 1. reorders triangles for the vertex cache, and vertices for fetch order;
//! 2. stores each buffer view compressed in the GLB binary chunk. It uses attribute codec
//!    version 0 (whose header byte `0xa0` the extension specifies), triangle codec version 1,
//!    and the octahedral filter for normals.
//!
//! The parent buffer views point into a placeholder buffer without a URI, marked
//! `fallback: true`. So both extensions are required, as the specification allows for files
//! without uncompressed data.

use std::io::{self, Write};

use serde_json::{json, Value};

use super::{color_byte, invalid};
use crate::Mesh;

const MESHOPT: &str = "EXT_meshopt_compression";
const QUANTIZATION: &str = "KHR_mesh_quantization";
const ARRAY_BUFFER: u32 = 34962;
const ELEMENT_ARRAY_BUFFER: u32 = 34963;
const BYTE: u32 = 5120;
const UNSIGNED_BYTE: u32 = 5121;
const SHORT: u32 = 5122;
const UNSIGNED_SHORT: u32 = 5123;
const UNSIGNED_INT: u32 = 5125;
const FLOAT: u32 = 5126;

/// sRGB to linear transfer function (IEC 61966-2-1).
fn srgb_to_linear(c: f32) -> f32 {
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

fn linear_to_srgb(c: f32) -> f32 {
    if c <= 0.0031308 {
        c * 12.92
    } else {
        1.055 * c.powf(1.0 / 2.4) - 0.055
    }
}

/// One buffer view before it is placed: raw (uncompressed) bytes and how to describe it.
struct View {
    bytes: Vec<u8>,
    /// Element stride for vertex attributes, `None` for indices.
    stride: Option<usize>,
    count: usize,
    filter: &'static str,
}

fn flat<const N: usize, T: Copy>(items: &[[T; N]], bytes: impl Fn(T) -> Vec<u8>) -> Vec<u8> {
    items.iter().flatten().flat_map(|&c| bytes(c)).collect()
}

/// Vertex order of first use in `indices` (what `meshopt_optimizeVertexFetch` computes),
/// rewriting `indices`; unused vertices are dropped. Returns new → old.
fn fetch_order(indices: &mut [u32], vertex_count: usize) -> Vec<u32> {
    let mut new_of_old = vec![u32::MAX; vertex_count];
    let mut old_of_new = Vec::with_capacity(vertex_count);
    for i in indices.iter_mut() {
        let slot = &mut new_of_old[*i as usize];
        if *slot == u32::MAX {
            *slot = old_of_new.len() as u32;
            old_of_new.push(*i);
        }
        *i = *slot;
    }
    old_of_new
}

fn pad4(v: &mut Vec<u8>, fill: u8) {
    while !v.len().is_multiple_of(4) {
        v.push(fill);
    }
}

pub(super) fn write(mesh: &Mesh, w: &mut impl Write, compress: bool) -> io::Result<()> {
    let (json, bin) = if mesh.triangles.is_empty() {
        // Accessors must not be empty, so an empty mesh is a scene with no nodes.
        let json = json!({
            "asset": {"version": "2.0", "generator": "frep-mesh"},
            "scene": 0,
            "scenes": [{"nodes": []}],
        });
        (json, Vec::new())
    } else {
        build(mesh, compress)?
    };
    let mut json = serde_json::to_vec(&json).map_err(invalid)?;
    pad4(&mut json, b' ');
    let mut total = 12 + 8 + json.len();
    if !bin.is_empty() {
        total += 8 + bin.len();
    }
    let total = u32::try_from(total)
        .map_err(|_| io::Error::new(io::ErrorKind::InvalidInput, "GLB over 4 GiB"))?;
    w.write_all(b"glTF")?;
    w.write_all(&2u32.to_le_bytes())?;
    w.write_all(&total.to_le_bytes())?;
    w.write_all(&(json.len() as u32).to_le_bytes())?;
    w.write_all(b"JSON")?;
    w.write_all(&json)?;
    if !bin.is_empty() {
        w.write_all(&(bin.len() as u32).to_le_bytes())?;
        w.write_all(b"BIN\0")?;
        w.write_all(&bin)?;
    }
    w.flush()
}

/// Builds the JSON document and the binary chunk (padded to 4 bytes).
fn build(mesh: &Mesh, compress: bool) -> io::Result<(Value, Vec<u8>)> {
    let mut indices: Vec<u32> = mesh.triangles.iter().flatten().copied().collect();
    let order: Vec<u32> = if compress {
        indices = meshopt::optimize_vertex_cache(&indices, mesh.positions.len());
        fetch_order(&mut indices, mesh.positions.len())
    } else {
        (0..mesh.positions.len() as u32).collect()
    };
    let pick = |v: &[[f32; 3]]| -> Vec<[f32; 3]> { order.iter().map(|&i| v[i as usize]).collect() };
    let positions = pick(&mesh.positions);
    let n = positions.len();
    let (quantized, lo, step) = quantize(positions);
    let qmin = [0, 1, 2].map(|k| quantized.iter().map(|q| q[k]).min().unwrap_or(0));
    let qmax = [0, 1, 2].map(|k| quantized.iter().map(|q| q[k]).max().unwrap_or(0));

    let mut views = vec![View {
        bytes: flat(&quantized, |c: u16| c.to_le_bytes().to_vec()),
        stride: Some(8),
        count: n,
        filter: "NONE",
    }];
    let mut attributes = serde_json::Map::new();
    let mut accessors = vec![json!({
        "bufferView": 0, "componentType": UNSIGNED_SHORT, "count": n, "type": "VEC3",
        "min": qmin, "max": qmax,
    })];
    attributes.insert("POSITION".into(), json!(0));

    if !mesh.normals.is_empty() {
        let (bytes, filter) = normal_bytes(&pick(&mesh.normals), compress);
        attributes.insert("NORMAL".into(), json!(accessors.len()));
        accessors.push(json!({
            "bufferView": views.len(), "componentType": BYTE, "normalized": true, "count": n, "type": "VEC3",
        }));
        views.push(View {
            bytes,
            stride: Some(4),
            count: n,
            filter,
        });
    }
    if !mesh.colors.is_empty() {
        let linear = |c: f32| color_byte(srgb_to_linear(c.clamp(0.0, 1.0)));
        let bytes = pick(&mesh.colors)
            .iter()
            .flat_map(|v| [linear(v[0]), linear(v[1]), linear(v[2]), 255])
            .collect();
        attributes.insert("COLOR_0".into(), json!(accessors.len()));
        accessors.push(json!({
            "bufferView": views.len(), "componentType": UNSIGNED_BYTE, "normalized": true, "count": n, "type": "VEC3",
        }));
        views.push(View {
            bytes,
            stride: Some(4),
            count: n,
            filter: "NONE",
        });
    }
    // glTF forbids the largest value of the index type (primitive restart in WebGL 2).
    let wide = n > 65535;
    let index_accessor = accessors.len();
    accessors.push(json!({
        "bufferView": views.len(), "componentType": if wide { UNSIGNED_INT } else { UNSIGNED_SHORT },
        "count": indices.len(), "type": "SCALAR",
    }));
    views.push(View {
        bytes: index_bytes(&indices, wide),
        stride: None,
        count: indices.len(),
        filter: "NONE",
    });

    let placed = place_views(&views, &indices, n, compress)?;
    let mut buffers = vec![json!({"byteLength": placed.bin.len()})];
    let mut used = vec![QUANTIZATION];
    if compress {
        buffers.push(
            json!({"byteLength": placed.raw_len, "extensions": {MESHOPT: {"fallback": true}}}),
        );
        used.push(MESHOPT);
    }
    let json = json!({
        "asset": {"version": "2.0", "generator": "frep-mesh"},
        "extensionsUsed": used,
        "extensionsRequired": used,
        "scene": 0,
        "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0, "translation": lo, "scale": [step, step, step]}],
        "meshes": [{"primitives": [{"attributes": attributes, "indices": index_accessor, "material": 0, "mode": 4}]}],
        "materials": [{"pbrMetallicRoughness": {"metallicFactor": 0.0, "roughnessFactor": 0.6}}],
        "accessors": accessors,
        "bufferViews": placed.buffer_views,
        "buffers": buffers,
    });
    Ok((json, placed.bin))
}

/// Positions on a `u16` grid with one uniform step, so that normals need no correction:
/// the grid coordinates (fourth one 0), the grid's origin and its step.
fn quantize(positions: Vec<[f32; 3]>) -> (Vec<[u16; 4]>, [f32; 3], f64) {
    let mesh_for_bounds = Mesh {
        positions,
        ..Mesh::default()
    };
    let (lo, hi) = mesh_for_bounds.bounds().unwrap_or(([0.0; 3], [0.0; 3]));
    let extent = (0..3)
        .map(|k| hi[k] as f64 - lo[k] as f64)
        .fold(0.0, f64::max);
    let step = if extent > 0.0 { extent / 65535.0 } else { 1.0 };
    let quantized = mesh_for_bounds
        .positions
        .iter()
        .map(|p| {
            let q = [0, 1, 2].map(|k| {
                ((p[k] as f64 - lo[k] as f64) / step)
                    .round()
                    .clamp(0.0, 65535.0) as u16
            });
            [q[0], q[1], q[2], 0]
        })
        .collect();
    (quantized, lo, step)
}

/// Normals as 4 bytes each: octahedral-filtered when compressed, else normalized `i8`.
/// Returns the bytes and the meshopt filter's name.
fn normal_bytes(normals: &[[f32; 3]], compress: bool) -> (Vec<u8>, &'static str) {
    if compress {
        let four: Vec<[f32; 4]> = normals.iter().map(|v| [v[0], v[1], v[2], 0.0]).collect();
        (
            flat(&meshopt::encode_filter_oct::<i8>(&four, 8), |c: i8| {
                vec![c as u8]
            }),
            "OCTAHEDRAL",
        )
    } else {
        let snorm = |c: f32| (c.clamp(-1.0, 1.0) * 127.0).round() as i8 as u8;
        (
            normals
                .iter()
                .flat_map(|v| [snorm(v[0]), snorm(v[1]), snorm(v[2]), 0])
                .collect(),
            "NONE",
        )
    }
}

/// Indices as little-endian `u32` when `wide`, else `u16`.
fn index_bytes(indices: &[u32], wide: bool) -> Vec<u8> {
    if wide {
        indices.iter().flat_map(|&i| i.to_le_bytes()).collect()
    } else {
        indices
            .iter()
            .flat_map(|&i| (i as u16).to_le_bytes())
            .collect()
    }
}

/// The views placed in the binary chunk.
struct Placed {
    /// The `bufferViews` entries.
    buffer_views: Vec<Value>,
    /// The binary chunk, padded to 4 bytes.
    bin: Vec<u8>,
    /// Length of the uncompressed layout (the fallback buffer's).
    raw_len: usize,
}

/// Places the views: raw bytes in the binary chunk (uncompressed), or compressed there with
/// the raw layout in the fallback buffer. `indices` index `n` vertices.
fn place_views(views: &[View], indices: &[u32], n: usize, compress: bool) -> io::Result<Placed> {
    let wide = n > 65535;
    let mut bin = Vec::new();
    let mut raw_offset = 0usize;
    let mut buffer_views = Vec::new();
    for view in views {
        let mut bv = json!({
            "buffer": if compress { 1 } else { 0 },
            "byteOffset": raw_offset,
            "byteLength": view.bytes.len(),
            "target": if view.stride.is_some() { ARRAY_BUFFER } else { ELEMENT_ARRAY_BUFFER },
        });
        if let Some(stride) = view.stride {
            bv["byteStride"] = json!(stride);
        }
        if compress {
            let (encoded, stride, mode) = match view.stride {
                Some(stride) => (
                    encode_attributes(&view.bytes, stride)?,
                    stride,
                    "ATTRIBUTES",
                ),
                None => {
                    let encoded = meshopt::encode_index_buffer(indices, n).map_err(invalid)?;
                    (encoded, if wide { 4 } else { 2 }, "TRIANGLES")
                }
            };
            let mut ext = json!({
                "buffer": 0, "byteOffset": bin.len(), "byteLength": encoded.len(),
                "byteStride": stride, "count": view.count, "mode": mode,
            });
            if view.filter != "NONE" {
                ext["filter"] = json!(view.filter);
            }
            bv["extensions"] = json!({ MESHOPT: ext });
            bin.extend_from_slice(&encoded);
        } else {
            bin.extend_from_slice(&view.bytes);
        }
        pad4(&mut bin, 0);
        raw_offset += view.bytes.len();
        raw_offset += (4 - raw_offset % 4) % 4;
        buffer_views.push(bv);
    }
    Ok(Placed {
        buffer_views,
        bin,
        raw_len: raw_offset,
    })
}

/// Compresses attribute bytes of the given stride (4 or 8) with attribute codec version 0.
fn encode_attributes(bytes: &[u8], stride: usize) -> io::Result<Vec<u8>> {
    // Version 0 is the bitstream EXT_meshopt_compression specifies (header 0xa0).
    const LEVEL: i32 = 2;
    let words: Vec<u32> = bytes
        .chunks_exact(4)
        .map(|c| u32::from_le_bytes([c[0], c[1], c[2], c[3]]))
        .collect();
    match stride {
        4 => meshopt::encode_vertex_buffer_level(&words, LEVEL, Some(0)),
        8 => {
            let pairs: Vec<[u32; 2]> = words.chunks_exact(2).map(|c| [c[0], c[1]]).collect();
            meshopt::encode_vertex_buffer_level(&pairs, LEVEL, Some(0))
        }
        _ => return Err(invalid(format!("unsupported stride {stride}"))),
    }
    .map_err(invalid)
}

// ---------------------------------------------------------------------------------------------
// Reading

/// Splits a GLB into its JSON document and binary chunk.
fn chunks(bytes: &[u8]) -> io::Result<(Value, &[u8])> {
    let u32_at = |o: usize| -> io::Result<u32> {
        let b = bytes
            .get(o..o + 4)
            .ok_or_else(|| invalid("GLB truncated"))?;
        Ok(u32::from_le_bytes([b[0], b[1], b[2], b[3]]))
    };
    if bytes.get(..4) != Some(b"glTF") || u32_at(4)? != 2 {
        return Err(invalid("not a glTF 2.0 binary"));
    }
    let (mut json, mut bin) = (None, &[][..]);
    let mut at = 12;
    let end = (u32_at(8)? as usize).min(bytes.len());
    while at + 8 <= end {
        let len = u32_at(at)? as usize;
        let data = bytes
            .get(at + 8..at + 8 + len)
            .ok_or_else(|| invalid("GLB chunk truncated"))?;
        match &bytes[at + 4..at + 8] {
            b"JSON" => json = Some(serde_json::from_slice(data).map_err(invalid)?),
            b"BIN\0" => bin = data,
            _ => {}
        }
        at += 8 + len;
    }
    Ok((json.ok_or_else(|| invalid("GLB without JSON chunk"))?, bin))
}

fn field(v: &Value, key: &str) -> io::Result<usize> {
    v[key]
        .as_u64()
        .map(|x| x as usize)
        .ok_or_else(|| invalid(format!("glTF: missing {key}")))
}

/// A document and its binary chunk, with views decoded on demand.
struct Doc<'a> {
    json: Value,
    bin: &'a [u8],
}

impl Doc<'_> {
    fn buffer(&self, index: usize) -> io::Result<&[u8]> {
        let buffer = &self.json["buffers"][index];
        if index != 0 || buffer.get("uri").is_some() {
            return Err(invalid("glTF: only the GLB binary buffer is supported"));
        }
        Ok(self.bin)
    }

    fn slice(&self, v: &Value) -> io::Result<&[u8]> {
        let (offset, len) = (
            v["byteOffset"].as_u64().unwrap_or(0) as usize,
            field(v, "byteLength")?,
        );
        self.buffer(field(v, "buffer")?)?
            .get(offset..offset + len)
            .ok_or_else(|| invalid("glTF: view out of range"))
    }

    /// The bytes of a buffer view, decompressed when it uses `EXT_meshopt_compression`.
    fn view(&self, index: usize) -> io::Result<Vec<u8>> {
        let view = &self.json["bufferViews"][index];
        let Some(ext) = view["extensions"].get(MESHOPT) else {
            return Ok(self.slice(view)?.to_vec());
        };
        let data = self.slice(ext)?;
        let (stride, count) = (field(ext, "byteStride")?, field(ext, "count")?);
        let mut out = match (ext["mode"].as_str(), stride) {
            (Some("ATTRIBUTES"), _) => decode_attributes(data, stride, count)?,
            (Some("TRIANGLES"), 2) => bytes_of(
                meshopt::decode_index_buffer::<u16>(data, count),
                u16::to_le_bytes,
            )?,
            (Some("TRIANGLES"), 4) => bytes_of(
                meshopt::decode_index_buffer::<u32>(data, count),
                u32::to_le_bytes,
            )?,
            (Some("INDICES"), 2) => bytes_of(
                meshopt::decode_index_sequence::<u16>(data, count),
                u16::to_le_bytes,
            )?,
            (Some("INDICES"), 4) => bytes_of(
                meshopt::decode_index_sequence::<u32>(data, count),
                u32::to_le_bytes,
            )?,
            _ => return Err(invalid("glTF: unsupported meshopt mode")),
        };
        match (ext["filter"].as_str().unwrap_or("NONE"), stride) {
            ("NONE", _) => {}
            ("OCTAHEDRAL", 4) => {
                let mut v: Vec<[i8; 4]> = out
                    .chunks_exact(4)
                    .map(|c| [0, 1, 2, 3].map(|k| c[k] as i8))
                    .collect();
                meshopt::decode_filter_oct(&mut v);
                out = v.iter().flatten().map(|&c| c as u8).collect();
            }
            ("OCTAHEDRAL", 8) => {
                let mut v: Vec<[i16; 4]> = out
                    .chunks_exact(8)
                    .map(|c| [0, 1, 2, 3].map(|k| i16::from_le_bytes([c[2 * k], c[2 * k + 1]])))
                    .collect();
                meshopt::decode_filter_oct(&mut v);
                out = v.iter().flatten().flat_map(|c| c.to_le_bytes()).collect();
            }
            (f, _) => return Err(invalid(format!("glTF: unsupported meshopt filter {f}"))),
        }
        Ok(out)
    }

    /// An accessor's elements as floats (normalized integers mapped to [0, 1] or [-1, 1]).
    fn accessor(&self, index: usize) -> io::Result<Vec<Vec<f32>>> {
        let acc = &self.json["accessors"][index];
        if acc.get("sparse").is_some() {
            return Err(invalid("glTF: sparse accessors are not supported"));
        }
        let count = field(acc, "count")?;
        let ty = field(acc, "componentType")? as u32;
        let components = match acc["type"].as_str() {
            Some("SCALAR") => 1,
            Some("VEC2") => 2,
            Some("VEC3") => 3,
            Some("VEC4") => 4,
            _ => return Err(invalid("glTF: unsupported accessor type")),
        };
        let size = match ty {
            BYTE | UNSIGNED_BYTE => 1,
            SHORT | UNSIGNED_SHORT => 2,
            UNSIGNED_INT | FLOAT => 4,
            _ => return Err(invalid("glTF: unknown component type")),
        };
        let view_index = field(acc, "bufferView")?;
        let data = self.view(view_index)?;
        let stride = self.json["bufferViews"][view_index]["byteStride"]
            .as_u64()
            .map_or(size * components, |s| s as usize);
        let offset = acc["byteOffset"].as_u64().unwrap_or(0) as usize;
        let normalized = acc["normalized"].as_bool().unwrap_or(false);
        if count > 0 && offset + (count - 1) * stride + size * components > data.len() {
            return Err(invalid("glTF: accessor out of range"));
        }
        Ok((0..count)
            .map(|e| {
                (0..components)
                    .map(|c| {
                        let b = &data[offset + e * stride + c * size..];
                        let (value, scale) = match ty {
                            BYTE => (b[0] as i8 as f32, 127.0),
                            UNSIGNED_BYTE => (b[0] as f32, 255.0),
                            SHORT => (i16::from_le_bytes([b[0], b[1]]) as f32, 32767.0),
                            UNSIGNED_SHORT => (u16::from_le_bytes([b[0], b[1]]) as f32, 65535.0),
                            UNSIGNED_INT => {
                                (u32::from_le_bytes([b[0], b[1], b[2], b[3]]) as f32, 1.0)
                            }
                            _ => (f32::from_le_bytes([b[0], b[1], b[2], b[3]]), 1.0),
                        };
                        if normalized {
                            (value / scale).max(-1.0)
                        } else {
                            value
                        }
                    })
                    .collect()
            })
            .collect())
    }

    /// Integer indices read exactly (floats would round above 2^24).
    fn indices(&self, index: usize) -> io::Result<Vec<u32>> {
        let acc = &self.json["accessors"][index];
        let count = field(acc, "count")?;
        let data = self.view(field(acc, "bufferView")?)?;
        let offset = acc["byteOffset"].as_u64().unwrap_or(0) as usize;
        let read = |size: usize, f: fn(&[u8]) -> u32| -> io::Result<Vec<u32>> {
            let bytes = data
                .get(offset..offset + count * size)
                .ok_or_else(|| invalid("glTF: indices out of range"))?;
            Ok(bytes.chunks_exact(size).map(f).collect())
        };
        match field(acc, "componentType")? as u32 {
            UNSIGNED_BYTE => read(1, |b| b[0] as u32),
            UNSIGNED_SHORT => read(2, |b| u16::from_le_bytes([b[0], b[1]]) as u32),
            UNSIGNED_INT => read(4, |b| u32::from_le_bytes([b[0], b[1], b[2], b[3]])),
            _ => Err(invalid("glTF: bad index component type")),
        }
    }
}

fn bytes_of<T: Copy, const N: usize>(
    v: meshopt::Result<Vec<T>>,
    f: fn(T) -> [u8; N],
) -> io::Result<Vec<u8>> {
    Ok(v.map_err(invalid)?.into_iter().flat_map(f).collect())
}

fn decode_attributes(data: &[u8], stride: usize, count: usize) -> io::Result<Vec<u8>> {
    macro_rules! by_words {
        ($($n:literal)*) => {
            match stride {
                $(s if s == 4 * $n => bytes_of(
                    meshopt::decode_vertex_buffer::<[u32; $n]>(data, count),
                    |w: [u32; $n]| {
                        let mut b = [0u8; 4 * $n];
                        for (k, x) in w.iter().enumerate() {
                            b[4 * k..4 * k + 4].copy_from_slice(&x.to_le_bytes());
                        }
                        b
                    },
                ),)*
                _ => Err(invalid(format!("glTF: unsupported meshopt stride {stride}"))),
            }
        };
    }
    by_words!(1 2 3 4 5 6 7 8 9 10 11 12 13 14 15 16)
}

/// A node's transform as a column-major 4×4 matrix.
fn node_matrix(node: &Value) -> [f64; 16] {
    if let Some(m) = node["matrix"].as_array() {
        let mut out = [0.0; 16];
        for (o, v) in out.iter_mut().zip(m) {
            *o = v.as_f64().unwrap_or(0.0);
        }
        return out;
    }
    let get = |key: &str, default: &[f64]| -> Vec<f64> {
        node[key].as_array().map_or(default.to_vec(), |a| {
            a.iter().map(|v| v.as_f64().unwrap_or(0.0)).collect()
        })
    };
    let (t, r, s) = (
        get("translation", &[0.0; 3]),
        get("rotation", &[0.0, 0.0, 0.0, 1.0]),
        get("scale", &[1.0; 3]),
    );
    let (x, y, z, w) = (r[0], r[1], r[2], r[3]);
    let rot = [
        [
            1.0 - 2.0 * (y * y + z * z),
            2.0 * (x * y + z * w),
            2.0 * (x * z - y * w),
        ],
        [
            2.0 * (x * y - z * w),
            1.0 - 2.0 * (x * x + z * z),
            2.0 * (y * z + x * w),
        ],
        [
            2.0 * (x * z + y * w),
            2.0 * (y * z - x * w),
            1.0 - 2.0 * (x * x + y * y),
        ],
    ];
    let mut m = [0.0; 16];
    for col in 0..3 {
        for row in 0..3 {
            m[4 * col + row] = rot[col][row] * s[col];
        }
        m[12 + col] = t[col];
    }
    m[15] = 1.0;
    m
}

/// Reads the first primitive of the first node with a mesh, applying that node's own
/// transform (not its parents'); expects triangles.
pub(super) fn read(bytes: &[u8]) -> io::Result<Mesh> {
    let (json, bin) = chunks(bytes)?;
    let doc = Doc { json, bin };
    let Some(node) = doc.json["nodes"]
        .as_array()
        .and_then(|n| n.iter().find(|n| n.get("mesh").is_some()))
    else {
        return Ok(Mesh::default());
    };
    let m = node_matrix(node);
    let prim = &doc.json["meshes"][field(node, "mesh")?]["primitives"][0];
    if prim["mode"].as_u64().unwrap_or(4) != 4 {
        return Err(invalid("glTF: only triangle lists are supported"));
    }
    let attr = &prim["attributes"];
    let mut mesh = Mesh::default();
    let positions = doc.accessor(field(attr, "POSITION")?)?;
    mesh.positions = positions
        .iter()
        .map(|p| {
            [0, 1, 2].map(|r| {
                (m[r] * p[0] as f64 + m[4 + r] * p[1] as f64 + m[8 + r] * p[2] as f64 + m[12 + r])
                    as f32
            })
        })
        .collect();
    if let Ok(normal) = field(attr, "NORMAL") {
        // Normals transform by the inverse transpose of the linear part.
        let a = |r: usize, c: usize| m[4 * c + r];
        let cof = |r: usize, c: usize| {
            let (r1, r2, c1, c2) = ((r + 1) % 3, (r + 2) % 3, (c + 1) % 3, (c + 2) % 3);
            a(r1, c1) * a(r2, c2) - a(r1, c2) * a(r2, c1)
        };
        mesh.normals = doc
            .accessor(normal)?
            .iter()
            .map(|n| {
                let v = [0, 1, 2].map(|r| (0..3).map(|c| cof(r, c) * n[c] as f64).sum::<f64>());
                let len = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
                v.map(|x| if len > 0.0 { (x / len) as f32 } else { 0.0 })
            })
            .collect();
    }
    if let Ok(color) = field(attr, "COLOR_0") {
        mesh.colors = doc
            .accessor(color)?
            .iter()
            .map(|c| [0, 1, 2].map(|k| linear_to_srgb(c[k])))
            .collect();
    }
    let indices = match field(prim, "indices") {
        Ok(i) => doc.indices(i)?,
        Err(_) => (0..mesh.positions.len() as u32).collect(),
    };
    mesh.triangles = indices
        .chunks_exact(3)
        .map(|t| [t[0], t[1], t[2]])
        .collect();
    Ok(mesh)
}
