//! Each artefact computed from a real model and decoded: images, the view
//! sheet and its index, the viewer's glb, every export format, the volume
//! and the shader.

use frep_artefact::compute::{self, Cancel, JobProgress};
use frep_artefact::{compile, ArtefactError, ArtefactLimits, CompileLimits, Compiled};
use frep_render::ImagePool;
use frep_wire::{
    ArtefactSpec, CameraView, ExportFormat, ImageEncoding, ShaderArtefact, ViewSetLayout,
};
use std::sync::Arc;

fn example(name: &str) -> Arc<Compiled> {
    let path = format!("{}/../../examples/{name}", env!("CARGO_MANIFEST_DIR"));
    let src = std::fs::read_to_string(path).expect("example model");
    compile(&src, None, &CompileLimits::default()).expect("compiles")
}

fn run(c: &Compiled, spec: &ArtefactSpec) -> Result<compute::Output, ArtefactError> {
    compute::compute(
        c,
        &[],
        spec,
        &ArtefactLimits::default(),
        &Cancel::new(),
        &JobProgress::new(),
        &ImagePool::default(),
    )
}

fn image(format: ImageEncoding) -> ArtefactSpec {
    ArtefactSpec::Image {
        camera: CameraView::default(),
        width: 64,
        height: 48,
        format,
        quality: 80,
        section: None,
    }
}

/// Decodes a PNG: (width, height, bytes per pixel, pixels).
fn png(bytes: &[u8]) -> (u32, u32, usize, Vec<u8>) {
    let mut r = png::Decoder::new(std::io::Cursor::new(bytes))
        .read_info()
        .expect("png header");
    let mut buf = vec![0; r.output_buffer_size().expect("size")];
    let info = r.next_frame(&mut buf).expect("png frame");
    buf.truncate(info.buffer_size());
    (info.width, info.height, info.color_type.samples(), buf)
}

/// Pixels of a decoded image of `width` pixels a row that differ from the
/// row's first pixel (the background is a vertical gradient; at zoom 1 the
/// model never reaches the left edge).
fn model_pixels(px: &[u8], channels: usize, width: u32) -> usize {
    px.chunks(channels * width as usize)
        .map(|row| {
            let bg = &row[..channels];
            row.chunks(channels).filter(|p| *p != bg).count()
        })
        .sum()
}

#[test]
fn png_image_shows_the_model() {
    let c = example("sphere.hf");
    let out = run(&c, &image(ImageEncoding::Png)).unwrap();
    assert_eq!(out.media_type, "image/png");
    let (w, h, ch, px) = png(&out.bytes);
    assert_eq!((w, h), (64, 48));
    let n = model_pixels(&px, ch, w);
    assert!(n > 64 * 48 / 10 && n < 64 * 48 / 2, "{n} model pixels");
}

/// The frame size from a JPEG's SOF marker, after checking SOI and EOI.
fn jpeg_size(b: &[u8]) -> (u32, u32) {
    assert_eq!(&b[..2], &[0xFF, 0xD8], "SOI");
    assert_eq!(&b[b.len() - 2..], &[0xFF, 0xD9], "EOI");
    let mut i = 2;
    while i + 9 < b.len() {
        assert_eq!(b[i], 0xFF, "marker at {i}");
        let m = b[i + 1];
        let len = u16::from_be_bytes([b[i + 2], b[i + 3]]) as usize;
        if (0xC0..=0xC3).contains(&m) {
            let h = u16::from_be_bytes([b[i + 5], b[i + 6]]) as u32;
            let w = u16::from_be_bytes([b[i + 7], b[i + 8]]) as u32;
            return (w, h);
        }
        i += 2 + len;
    }
    panic!("no SOF marker");
}

#[test]
fn jpeg_and_webp_images_have_their_size() {
    let c = example("m3_gyroid.hf");
    let out = run(&c, &image(ImageEncoding::Jpeg)).unwrap();
    assert_eq!(out.media_type, "image/jpeg");
    assert_eq!(jpeg_size(&out.bytes), (64, 48));
    let out = run(&c, &image(ImageEncoding::Webp)).unwrap();
    assert_eq!(out.media_type, "image/webp");
    assert_eq!(&out.bytes[..4], b"RIFF");
    assert_eq!(&out.bytes[8..12], b"WEBP");
}

#[test]
fn zoom_and_pan_move_the_model_in_the_picture() {
    let c = example("sphere.hf");
    let render = |camera: CameraView| {
        let spec = ArtefactSpec::Image {
            camera,
            width: 64,
            height: 64,
            format: ImageEncoding::Png,
            quality: 80,
            section: None,
        };
        png(&run(&c, &spec).unwrap().bytes)
    };
    // Panned far away: the background alone, pixel for pixel.
    let (_, _, ch, empty) = render(CameraView {
        pan: [1000.0, 0.0, 0.0],
        ..CameraView::default()
    });
    let at = |camera: CameraView| {
        let (_, _, _, px) = render(camera);
        px.chunks(ch)
            .zip(empty.chunks(ch))
            .filter(|(a, b)| a != b)
            .count()
    };
    let base = at(CameraView::default());
    assert!(base > 500, "{base}");
    let zoomed = at(CameraView {
        zoom: 2.0,
        ..CameraView::default()
    });
    assert!(
        zoomed as f64 > base as f64 * 1.8,
        "zoom 2: {zoomed} vs {base} pixels"
    );
    let panned = at(CameraView {
        pan: [0.0, 0.0, 3.0],
        ..CameraView::default()
    });
    assert!(panned < base / 4, "panned up: {panned} vs {base}");
    let ortho = at(CameraView {
        fov: None,
        ..CameraView::default()
    });
    assert!(ortho > 500, "orthographic: {ortho}");
}

#[test]
fn view_set_sheet_matches_its_index() {
    let c = example("m4_rblend10.hf");
    let settings = |index: bool| {
        let (views, elevations, width, height) = (4, vec![0.0, 30.0], 32, 24);
        let (format, quality, fov) = (ImageEncoding::Png, 80, Some(30.0));
        if index {
            ArtefactSpec::ViewSetIndex {
                views,
                elevations,
                width,
                height,
                format,
                quality,
                fov,
                section: None,
            }
        } else {
            ArtefactSpec::ViewSet {
                views,
                elevations,
                width,
                height,
                format,
                quality,
                fov,
                section: None,
            }
        }
    };
    let index = run(&c, &settings(true)).unwrap();
    assert_eq!(index.media_type, "application/json");
    let layout: ViewSetLayout = serde_json::from_slice(&index.bytes).unwrap();
    assert_eq!(layout.columns, 4);
    assert_eq!(layout.sheet_size, [128, 48]);
    let sheet = run(&c, &settings(false)).unwrap();
    let (w, h, ch, px) = png(&sheet.bytes);
    assert_eq!([w, h], layout.sheet_size);
    // Every view shows the model.
    for v in 0..8u32 {
        let (x0, y0) = ((v % 4) * 32, (v / 4) * 24);
        let mut n = 0;
        for y in y0..y0 + 24 {
            for x in x0..x0 + 32 {
                let i = (y * w + x) as usize * ch;
                let bg = (y * w + x0) as usize * ch;
                n += usize::from(px[i..i + ch] != px[bg..bg + ch]);
            }
        }
        assert!(n > 50, "view {v}: {n} model pixels");
    }
}

fn glb_triangles(bytes: &[u8]) -> usize {
    let g = gltf::Gltf::from_slice_without_validation(bytes).expect("glb parses");
    let mut tris = 0;
    for m in g.meshes() {
        for p in m.primitives() {
            let acc = p.indices().expect("indexed");
            tris += acc.count() / 3;
        }
    }
    tris
}

#[test]
fn viewer_mesh_is_a_meshopt_glb_with_triangles() {
    let c = example("sphere.hf");
    let out = run(&c, &ArtefactSpec::Mesh { depth: 4 }).unwrap();
    assert_eq!(out.media_type, "model/gltf-binary");
    assert_eq!(&out.bytes[..4], b"glTF");
    let g = gltf::Gltf::from_slice_without_validation(&out.bytes).unwrap();
    assert!(g.extensions_used().any(|e| e == "EXT_meshopt_compression"));
    assert!(glb_triangles(&out.bytes) > 50);
}

#[test]
fn every_export_format_holds_the_mesh() {
    let c = example("m1_sphere.hf");
    let get = |format| {
        run(&c, &ArtefactSpec::Export { format, depth: 4 })
            .unwrap()
            .bytes
    };
    // Binary STL: 80-byte header, triangle count, 50 bytes each.
    let stl = get(ExportFormat::Stl);
    let n = u32::from_le_bytes([stl[80], stl[81], stl[82], stl[83]]) as usize;
    assert!(n > 50);
    assert_eq!(stl.len(), 84 + 50 * n);
    let obj = String::from_utf8(get(ExportFormat::Obj)).unwrap();
    assert!(obj.lines().filter(|l| l.starts_with("f ")).count() > 50);
    let ply = get(ExportFormat::Ply);
    let head = String::from_utf8_lossy(&ply[..ply.len().min(400)]).to_string();
    assert!(
        head.starts_with("ply\nformat binary_little_endian"),
        "{head}"
    );
    let faces: usize = head
        .lines()
        .find_map(|l| l.strip_prefix("element face "))
        .and_then(|n| n.trim().parse().ok())
        .unwrap();
    assert!(faces > 50);
    assert!(glb_triangles(&get(ExportFormat::Glb)) > 50);
    let mf = get(ExportFormat::ThreeMf);
    let mut zip = zip::ZipArchive::new(std::io::Cursor::new(mf)).expect("3mf is a zip");
    let mut model = String::new();
    std::io::Read::read_to_string(
        &mut zip.by_name("3D/3dmodel.model").expect("model part"),
        &mut model,
    )
    .unwrap();
    assert!(model.matches("<triangle ").count() > 50);
}

#[test]
fn slices_cross_the_surface() {
    let c = example("sphere.hf");
    let out = run(&c, &ArtefactSpec::Slices { grid: 16 }).unwrap();
    let v = out.volume.expect("layout");
    assert_eq!(v.dims, [16, 16, 16]);
    assert_eq!(v.bounds, c.bounds());
    assert!(v.scale > 0.0);
    let b = &out.bytes;
    assert_eq!(b.len(), 16 * 16 * 16);
    // Inside (> 128) at the centre, outside (< 128) at a corner, and the
    // surface crossed along x somewhere.
    let at = |i: usize, j: usize, k: usize| b[(k * 16 + j) * 16 + i];
    assert!(at(8, 8, 8) > 128 && at(0, 0, 0) < 128);
    let crossings = (0..16 * 16)
        .filter(|r| {
            let row = &b[r * 16..r * 16 + 16];
            row.windows(2).any(|w| (w[0] >= 128) != (w[1] >= 128))
        })
        .count();
    assert!(crossings > 20, "{crossings} rows cross");
}

#[test]
fn shader_has_its_uniform_table() {
    let c = example("m4_rblend10.hf");
    let out = run(&c, &ArtefactSpec::Shader).unwrap();
    let s: ShaderArtefact = serde_json::from_slice(&out.bytes).unwrap();
    assert!(s.source.starts_with("#version 300 es"));
    assert!(s.uniforms.iter().any(|u| u.name == "u_params"));
    assert!(s.source.contains("u_params"));
    assert_eq!(s.bounds, c.bounds());
    assert!(s.statements > 0);
}

#[test]
fn limits_are_refused_before_any_work() {
    let c = example("sphere.hf");
    let limits = ArtefactLimits {
        max_image_pixels: 1000,
        max_mesh_depth: 3,
        max_volume_grid: 8,
        ..ArtefactLimits::default()
    };
    let refused = |spec: ArtefactSpec| {
        let (cancel, progress, pool) = (Cancel::new(), JobProgress::new(), ImagePool::default());
        compute::compute(&c, &[], &spec, &limits, &cancel, &progress, &pool).unwrap_err()
    };
    assert!(matches!(
        refused(image(ImageEncoding::Png)),
        ArtefactError::Limit {
            name: "image pixels",
            limit: 1000,
            got: 3072
        }
    ));
    assert!(matches!(
        refused(ArtefactSpec::Mesh { depth: 4 }),
        ArtefactError::Limit { .. }
    ));
    assert!(matches!(
        refused(ArtefactSpec::Slices { grid: 9 }),
        ArtefactError::Limit { .. }
    ));
    assert!(matches!(
        refused(ArtefactSpec::Slices { grid: 0 }),
        ArtefactError::BadRequest(_)
    ));
}

#[test]
fn a_cancelled_job_stops() {
    let c = example("m3_gyroid.hf");
    let cancel = Cancel::new();
    cancel.cancel();
    let r = compute::compute(
        &c,
        &[],
        &ArtefactSpec::Mesh { depth: 5 },
        &ArtefactLimits::default(),
        &cancel,
        &JobProgress::new(),
        &ImagePool::default(),
    );
    assert_eq!(r.unwrap_err(), ArtefactError::Cancelled);
}

#[test]
fn a_model_without_a_bounds_line_fills_the_frame() {
    // A corpus-like model: no `-- bounds:` line, off-centre, with noise.
    let src = "my_model(x[3], a[1]) {\n  my_model = 9 - ((x[1]-5)^2 + x[2]^2 + x[3]^2) + hfNoiseG(x, 1, 2, 0.5);\n}\n";
    let c = compile(src, None, &CompileLimits::default()).unwrap();
    assert_eq!(c.bounds_origin(), frep_artefact::BoxOrigin::Extent);
    let out = run(&c, &image(ImageEncoding::Png)).unwrap();
    let (w, h, ch, px) = png(&out.bytes);
    // About 12 % of a 64×48 frame (the box's bounding sphere fills its
    // height); in hfp's [-10, 10]³ about 2 %.
    let n = model_pixels(&px, ch, w);
    assert!(n * 100 > (w * h) as usize * 8, "{n} of {} pixels", w * h);
}

#[test]
fn corpus_models_without_bounds_lines_are_framed() {
    let dir = std::path::Path::new("/work/shared/hyperfun/corpus");
    let Ok(rd) = std::fs::read_dir(dir) else {
        eprintln!("no corpus here: skipped");
        return;
    };
    let mut framed = 0;
    for e in rd.flatten() {
        let Ok(src) = std::fs::read_to_string(e.path()) else {
            continue;
        };
        let Ok(c) = compile(&src, None, &CompileLimits::default()) else {
            continue;
        };
        if c.bounds_origin() != frep_artefact::BoxOrigin::Extent {
            continue;
        }
        let b = c.bounds();
        assert!((0..3).all(|k| b[k] < b[k + 3] && b[k].is_finite()), "{b:?}");
        // Some models are empty (the dice's cube minus a sphere holding it):
        // the interval bounds still give a box, and the picture shows nothing.
        let volume = run(&c, &ArtefactSpec::Slices { grid: 24 }).unwrap().bytes;
        if volume.iter().all(|&v| v < 128) {
            continue;
        }
        let out = run(&c, &image(ImageEncoding::Png)).unwrap();
        let (w, _, ch, px) = png(&out.bytes);
        let n = model_pixels(&px, ch, w);
        assert!(n > 64 * 48 / 50, "{}: {n} model pixels", e.path().display());
        framed += 1;
    }
    assert!(
        framed >= 10,
        "{framed} corpus models framed by their extent"
    );
}
