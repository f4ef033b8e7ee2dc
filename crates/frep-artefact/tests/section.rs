//! The section plane in server images and view sets: a cut changes the
//! picture (the cut face shows), a plane that keeps nothing leaves the
//! background, and a plane that is not one is a bad request.

use frep_artefact::compute::{self, Cancel, JobProgress};
use frep_artefact::{compile, ArtefactError, ArtefactLimits, CompileLimits, Compiled};
use frep_render::ImagePool;
use frep_wire::{ArtefactSpec, CameraView, ImageEncoding, SectionPlane};
use std::sync::Arc;

fn sphere() -> Arc<Compiled> {
    let path = format!("{}/../../examples/sphere.hf", env!("CARGO_MANIFEST_DIR"));
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

fn image(section: Option<SectionPlane>) -> ArtefactSpec {
    ArtefactSpec::Image {
        camera: CameraView::default(),
        width: 64,
        height: 64,
        format: ImageEncoding::Png,
        quality: 80,
        section,
    }
}

fn view_set(section: Option<SectionPlane>) -> ArtefactSpec {
    ArtefactSpec::ViewSet {
        views: 4,
        elevations: vec![20.0],
        width: 32,
        height: 32,
        format: ImageEncoding::Png,
        quality: 80,
        fov: Some(30.0),
        section,
    }
}

/// RGB(A) pixels of a PNG.
fn pixels(bytes: &[u8]) -> (u32, usize, Vec<u8>) {
    let mut r = png::Decoder::new(std::io::Cursor::new(bytes))
        .read_info()
        .expect("png header");
    let mut buf = vec![0; r.output_buffer_size().expect("size")];
    let info = r.next_frame(&mut buf).expect("png frame");
    buf.truncate(info.buffer_size());
    (info.width, info.color_type.samples(), buf)
}

/// Pixels that differ from their row's first (the background).
fn model_pixels(bytes: &[u8]) -> usize {
    let (w, ch, px) = pixels(bytes);
    px.chunks(ch * w as usize)
        .map(|row| row.chunks(ch).filter(|p| *p != &row[..ch]).count())
        .sum()
}

/// Pixels that are orange (the cut face of a model without colours).
fn orange_pixels(bytes: &[u8]) -> usize {
    let (_, ch, px) = pixels(bytes);
    px.chunks(ch)
        .filter(|p| {
            let (r, g, b) = (i32::from(p[0]), i32::from(p[1]), i32::from(p[2]));
            r > g + 30 && g > b + 15
        })
        .count()
}

#[test]
fn a_cut_shows_its_face_in_images_and_view_sets() {
    let c = sphere();
    // A plane through the centre whose cut face turns to the default
    // camera (yaw 30, pitch 20: the eye is on the −y side, a little −x).
    let towards = Some(SectionPlane {
        normal: [-0.5, -0.866, 0.3],
        offset: 0.0,
    });
    let plain = run(&c, &image(None)).unwrap().bytes;
    let cut = run(&c, &image(towards)).unwrap().bytes;
    assert_ne!(plain, cut);
    assert_eq!(orange_pixels(&plain), 0);
    assert!(orange_pixels(&cut) > 200, "{}", orange_pixels(&cut));
    let set_plain = run(&c, &view_set(None)).unwrap().bytes;
    let set_cut = run(&c, &view_set(towards)).unwrap().bytes;
    assert_eq!(orange_pixels(&set_plain), 0);
    assert!(orange_pixels(&set_cut) > 50, "{}", orange_pixels(&set_cut));
}

#[test]
fn a_plane_keeping_nothing_leaves_the_background() {
    let c = sphere();
    let none = Some(SectionPlane {
        normal: [0.0, 0.0, 1.0],
        offset: -1e6,
    });
    assert!(model_pixels(&run(&c, &image(None)).unwrap().bytes) > 100);
    assert_eq!(model_pixels(&run(&c, &image(none)).unwrap().bytes), 0);
}

#[test]
fn a_plane_that_is_not_one_is_a_bad_request() {
    let c = sphere();
    for bad in [
        SectionPlane {
            normal: [0.0; 3],
            offset: 0.0,
        },
        SectionPlane {
            normal: [f64::NAN, 1.0, 0.0],
            offset: 0.0,
        },
    ] {
        for spec in [image(Some(bad)), view_set(Some(bad))] {
            let e = run(&c, &spec).unwrap_err();
            assert!(matches!(e, ArtefactError::BadRequest(_)), "{e:?}");
        }
    }
}
