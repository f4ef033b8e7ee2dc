//! Every format written and read back; glTF checked structurally and decoded by hand.

mod common;

use std::path::Path;

use common::{assert_same, cube, torus, uv_sphere, Tol};
use frep_mesh::export::{read, to_bytes};
use frep_mesh::{Format, Mesh};

const EXACT: Tol = Tol {
    position: 0.0,
    normal_dot: None,
    color: None,
    linear_color: false,
};

fn round_trip(mesh: &Mesh, format: Format) -> (Vec<u8>, Mesh) {
    let bytes = to_bytes(mesh, format).unwrap();
    let back = read(format, &mut bytes.as_slice()).unwrap_or_else(|e| panic!("{format:?}: {e}"));
    (bytes, back)
}

/// The tolerances each format promises for a mesh with extent `extent`.
fn tolerance(format: Format, extent: f32) -> Tol {
    let byte = 0.5 / 255.0 + 1e-6;
    match format {
        Format::StlBinary | Format::StlAscii => EXACT,
        Format::Obj => Tol {
            normal_dot: Some(0.99999),
            color: Some(1e-6),
            ..EXACT
        },
        Format::Ply | Format::PlyAscii => Tol {
            normal_dot: Some(0.99999),
            color: Some(byte),
            ..EXACT
        },
        Format::ThreeMf => Tol {
            color: Some(byte),
            ..EXACT
        },
        Format::Glb | Format::GlbMeshopt => Tol {
            // Half a grid step along each axis, plus float rounding.
            position: extent / 65535.0 * 0.5 * 3f32.sqrt() * 1.01 + extent * 1e-6,
            // 8-bit normals: within about 2.5 degrees (octahedral) or 1 degree (raw).
            normal_dot: Some(if format == Format::Glb { 0.9998 } else { 0.999 }),
            color: Some(byte),
            linear_color: true,
        },
    }
}

fn extent(m: &Mesh) -> f32 {
    let (lo, hi) = m.bounds().unwrap();
    (0..3).map(|k| hi[k] - lo[k]).fold(0.0, f32::max)
}

#[test]
fn every_format_round_trips_the_sphere() {
    let m = uv_sphere(1.5, 41, 40);
    for format in Format::ALL {
        let (_, back) = round_trip(&m, format);
        assert_same(&m, &back, tolerance(format, extent(&m)));
    }
}

#[test]
fn every_format_round_trips_a_plain_mesh() {
    let mut m = torus(20.0, 5.0, 30, 16);
    m.positions.iter_mut().for_each(|p| p[2] += 100.0);
    for format in Format::ALL {
        let (_, back) = round_trip(&m, format);
        assert!(back.normals.is_empty() || matches!(format, Format::StlBinary | Format::StlAscii));
        assert!(back.colors.is_empty(), "{format:?}");
        let tol = Tol {
            normal_dot: None,
            color: None,
            ..tolerance(format, extent(&m))
        };
        assert_same(&m, &back, tol);
    }
}

#[test]
fn wide_indices_round_trip_through_gltf() {
    // 74,702 vertices: more than u16 indices can address.
    let m = uv_sphere(1.0, 250, 300);
    assert!(m.positions.len() > 65535);
    for format in [Format::Glb, Format::GlbMeshopt] {
        let (bytes, back) = round_trip(&m, format);
        assert_same(&m, &back, tolerance(format, extent(&m)));
        let gltf = gltf::Gltf::from_slice_without_validation(&bytes).unwrap();
        let indices = gltf
            .meshes()
            .next()
            .unwrap()
            .primitives()
            .next()
            .unwrap()
            .indices()
            .unwrap();
        assert_eq!(indices.data_type(), gltf::accessor::DataType::U32);
    }
}

#[test]
fn empty_mesh_round_trips() {
    for format in Format::ALL {
        let (_, back) = round_trip(&Mesh::default(), format);
        assert_eq!(back, Mesh::default(), "{format:?}");
    }
}

#[test]
fn malformed_meshes_are_rejected() {
    let mut m = cube();
    m.triangles.push([0, 1, 99]);
    for format in Format::ALL {
        let err = to_bytes(&m, format).unwrap_err();
        assert_eq!(err.kind(), std::io::ErrorKind::InvalidInput);
    }
    assert!(read(Format::Glb, &mut &b"glTF nonsense"[..]).is_err());
    assert!(read(Format::ThreeMf, &mut &b"PK"[..]).is_err());
    assert!(read(
        Format::Ply,
        &mut &b"ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nend_header\n1"[..]
    )
    .is_err());
}

#[test]
fn formats_by_extension() {
    let f = |p: &str| Format::from_path(Path::new(p));
    assert_eq!(f("a.stl"), Some(Format::StlBinary));
    assert_eq!(f("a.STL"), Some(Format::StlBinary));
    assert_eq!(f("dir/a.obj"), Some(Format::Obj));
    assert_eq!(f("a.ply"), Some(Format::Ply));
    assert_eq!(f("a.glb"), Some(Format::GlbMeshopt));
    assert_eq!(f("a.3mf"), Some(Format::ThreeMf));
    assert_eq!(f("a.gltf"), None);
    assert_eq!(f("noext"), None);
    for format in Format::ALL {
        assert_eq!(
            Format::from_path(Path::new(&format!("x.{}", format.extension())))
                .map(Format::extension),
            Some(format.extension())
        );
    }
}

#[test]
fn stl_ascii_and_binary_are_told_apart() {
    let m = cube();
    for (write, read_as) in [
        (Format::StlAscii, Format::StlBinary),
        (Format::StlBinary, Format::StlAscii),
    ] {
        let bytes = to_bytes(&m, write).unwrap();
        let back = read(read_as, &mut bytes.as_slice()).unwrap();
        assert_same(&m, &back, EXACT);
    }
    assert_eq!(to_bytes(&m, Format::StlBinary).unwrap().len(), 84 + 50 * 12);
}

#[test]
fn three_mf_package_has_the_expected_parts() {
    let m = uv_sphere(1.0, 11, 12);
    let bytes = to_bytes(&m, Format::ThreeMf).unwrap();
    let mut zip = zip::ZipArchive::new(std::io::Cursor::new(bytes)).unwrap();
    let names: Vec<String> = zip.file_names().map(String::from).collect();
    for part in ["[Content_Types].xml", "_rels/.rels", "3D/3dmodel.model"] {
        assert!(
            names.iter().any(|n| n == part),
            "{part} missing from {names:?}"
        );
    }
    let file = zip.by_name("3D/3dmodel.model").unwrap();
    assert_eq!(file.compression(), zip::CompressionMethod::Deflated);
    let xml = std::io::read_to_string(file).unwrap();
    assert!(xml.contains(r#"unit="millimeter""#));
    assert_eq!(xml.matches("<vertex ").count(), m.positions.len());
    assert_eq!(xml.matches("<triangle ").count(), m.triangles.len());
    assert!(xml.contains("<m:colorgroup id=\"1\">"));
    let rels = std::io::read_to_string(zip.by_name("_rels/.rels").unwrap()).unwrap();
    assert!(rels.contains("Target=\"/3D/3dmodel.model\""));
}

/// Parses with the `gltf` crate and runs its validation, allowing only the report that the
/// required extensions are unknown to it.
fn parse_gltf(bytes: &[u8]) -> gltf::Gltf {
    use gltf::json::validation::Validate;
    let gltf = gltf::Gltf::from_slice_without_validation(bytes).unwrap();
    let root = gltf.document.as_json();
    let mut errors = Vec::new();
    root.validate(root, gltf::json::Path::new, &mut |path, error| {
        errors.push((path().to_string(), error))
    });
    errors.retain(|(path, e)| {
        !(path.starts_with("extensionsRequired")
            && *e == gltf::json::validation::Error::Unsupported)
    });
    assert!(errors.is_empty(), "{errors:?}");
    gltf
}

#[test]
fn glb_structure_and_quantization() {
    let m = uv_sphere(2.0, 31, 30);
    let bytes = to_bytes(&m, Format::Glb).unwrap();
    let gltf = parse_gltf(&bytes);
    let root = gltf.document.as_json();
    assert_eq!(root.extensions_required, vec!["KHR_mesh_quantization"]);
    assert_eq!(root.extensions_used, vec!["KHR_mesh_quantization"]);
    let prim = gltf.meshes().next().unwrap().primitives().next().unwrap();
    assert_eq!(prim.mode(), gltf::mesh::Mode::Triangles);
    let get = |s| prim.get(&s).unwrap();
    use gltf::accessor::{DataType, Dimensions};
    let pos = get(gltf::Semantic::Positions);
    assert_eq!(
        (pos.data_type(), pos.dimensions(), pos.normalized()),
        (DataType::U16, Dimensions::Vec3, false)
    );
    assert_eq!(pos.view().unwrap().stride(), Some(8));
    let normal = get(gltf::Semantic::Normals);
    assert_eq!(
        (normal.data_type(), normal.normalized()),
        (DataType::I8, true)
    );
    let color = get(gltf::Semantic::Colors(0));
    assert_eq!(
        (color.data_type(), color.normalized()),
        (DataType::U8, true)
    );
    assert_eq!(prim.indices().unwrap().data_type(), DataType::U16);
    // The node maps the grid back onto the box.
    let node = gltf.nodes().next().unwrap();
    let (t, _, s) = node.transform().decomposed();
    let (lo, hi) = m.bounds().unwrap();
    assert_eq!(t, lo);
    assert_eq!(hi[2] - lo[2], 4.0, "z has the largest extent");
    assert!((s[0] - 4.0 / 65535.0).abs() < 1e-9 && s[0] == s[1] && s[1] == s[2]);
    // Uncompressed: all data sits in the GLB binary chunk.
    let blob = gltf.blob.as_ref().unwrap();
    let view = pos.view().unwrap();
    let first = &blob[view.offset()..view.offset() + 6];
    let q = [0, 1, 2].map(|k| u16::from_le_bytes([first[2 * k], first[2 * k + 1]]));
    // Vertex 0 is the north pole (0, 0, 2).
    let expect = [0, 1].map(|k| ((0.0 - lo[k]) / s[k]).round() as u16);
    assert_eq!(q, [expect[0], expect[1], 65535]);
}

#[test]
fn glb_meshopt_decodes_to_the_uncompressed_views() {
    let m = uv_sphere(1.0, 31, 30);
    let bytes = to_bytes(&m, Format::GlbMeshopt).unwrap();
    let gltf = parse_gltf(&bytes);
    let root = gltf.document.as_json();
    let exts = vec![
        "KHR_mesh_quantization".to_string(),
        "EXT_meshopt_compression".into(),
    ];
    assert_eq!(root.extensions_used, exts);
    assert_eq!(root.extensions_required, exts);
    assert_eq!(gltf.buffers().count(), 2);
    let blob = gltf.blob.as_ref().unwrap();
    // Read the raw JSON for the extension objects (the gltf crate does not model them).
    let json: serde_json::Value = {
        let len = u32::from_le_bytes(bytes[12..16].try_into().unwrap()) as usize;
        serde_json::from_slice(&bytes[20..20 + len]).unwrap()
    };
    let fallback = &json["buffers"][1];
    assert!(fallback.get("uri").is_none());
    assert_eq!(
        fallback["extensions"]["EXT_meshopt_compression"]["fallback"],
        true
    );
    let views = json["bufferViews"].as_array().unwrap();
    let mut decoded = Vec::new();
    for view in views {
        assert_eq!(
            view["buffer"], 1,
            "parent views point to the fallback buffer"
        );
        let ext = &view["extensions"]["EXT_meshopt_compression"];
        assert_eq!(ext["buffer"], 0);
        let (offset, len) = (
            ext["byteOffset"].as_u64().unwrap() as usize,
            ext["byteLength"].as_u64().unwrap() as usize,
        );
        let (stride, count) = (
            ext["byteStride"].as_u64().unwrap() as usize,
            ext["count"].as_u64().unwrap() as usize,
        );
        assert_eq!(
            view["byteLength"].as_u64().unwrap() as usize,
            stride * count
        );
        let data = &blob[offset..offset + len];
        let raw: Vec<u8> = match ext["mode"].as_str().unwrap() {
            "ATTRIBUTES" => {
                assert_eq!(data[0], 0xa0, "attribute codec version 0");
                assert_eq!(view["byteStride"].as_u64().unwrap() as usize, stride);
                let words: Vec<[u8; 4]> = match stride {
                    4 => meshopt::decode_vertex_buffer::<[u8; 4]>(data, count).unwrap(),
                    8 => meshopt::decode_vertex_buffer::<[u8; 8]>(data, count)
                        .unwrap()
                        .iter()
                        .flat_map(|e| [[e[0], e[1], e[2], e[3]], [e[4], e[5], e[6], e[7]]])
                        .collect(),
                    _ => panic!("stride {stride}"),
                };
                let mut raw: Vec<u8> = words.concat();
                if ext["filter"] == "OCTAHEDRAL" {
                    let mut v: Vec<[i8; 4]> = raw
                        .chunks(4)
                        .map(|c| [0, 1, 2, 3].map(|k| c[k] as i8))
                        .collect();
                    meshopt::decode_filter_oct(&mut v);
                    raw = v.iter().flatten().map(|&c| c as u8).collect();
                }
                raw
            }
            "TRIANGLES" => {
                assert_eq!(data[0], 0xe1, "triangle codec version 1");
                assert_eq!(stride, 2);
                let idx = meshopt::decode_index_buffer::<u16>(data, count).unwrap();
                idx.iter().flat_map(|i| i.to_le_bytes()).collect()
            }
            mode => panic!("mode {mode}"),
        };
        decoded.push(raw);
    }
    // Rebuild the mesh from the hand-decoded views and compare with the input.
    let n = m.positions.len();
    let (lo, _) = m.bounds().unwrap();
    let step = extent(&m) / 65535.0;
    let back = Mesh {
        positions: decoded[0]
            .chunks(8)
            .map(|c| {
                [0, 1, 2]
                    .map(|k| lo[k] + step * u16::from_le_bytes([c[2 * k], c[2 * k + 1]]) as f32)
            })
            .collect(),
        normals: decoded[1]
            .chunks(4)
            .map(|c| {
                let v = [0, 1, 2].map(|k| c[k] as i8 as f32 / 127.0);
                let len = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
                v.map(|x| x / len)
            })
            .collect(),
        colors: decoded[2]
            .chunks(4)
            .map(|c| {
                [0, 1, 2].map(|k| {
                    let l = c[k] as f32 / 255.0;
                    if l <= 0.0031308 {
                        l * 12.92
                    } else {
                        1.055 * l.powf(1.0 / 2.4) - 0.055
                    }
                })
            })
            .collect(),
        triangles: decoded[3]
            .chunks(6)
            .map(|c| [0, 1, 2].map(|k| u16::from_le_bytes([c[2 * k], c[2 * k + 1]]) as u32))
            .collect(),
    };
    assert_eq!(back.positions.len(), n);
    assert_same(&m, &back, tolerance(Format::GlbMeshopt, 2.0));
}

/// Sizes of every format for a 20,000-triangle sphere with normals and colours, printed for
/// the record (`cargo test -p frep-mesh --test roundtrip sizes -- --nocapture`).
#[test]
fn sizes_for_a_20k_triangle_sphere() {
    let m = uv_sphere(1.0, 101, 100);
    assert_eq!(m.triangles.len(), 20_000);
    let mut sizes = Vec::new();
    for format in Format::ALL {
        let len = to_bytes(&m, format).unwrap().len();
        println!(
            "{format:?}: {len} bytes, {:.2} bytes/triangle",
            len as f64 / 20_000.0
        );
        sizes.push((format, len));
    }
    let size = |f| sizes.iter().find(|(g, _)| *g == f).unwrap().1;
    assert_eq!(size(Format::StlBinary), 84 + 50 * 20_000);
    assert!(size(Format::GlbMeshopt) < size(Format::Glb) / 2);
    assert!(
        size(Format::GlbMeshopt) < 8 * 20_000,
        "meshopt glTF under 8 bytes per triangle"
    );
}
