//! What the service adds to the command line's time. Each model given gets a
//! 512² JPEG, timed three ways:
//! - rendered the CLI's way (`render_camera` + `encode`);
//! - through `Artefacts::get`, with a new key each round (another yaw);
//! - through a cached `get`.
//!
//! The first two are medians of alternating rounds.
//! `cargo run --release -p frep-artefact --example overhead -- FILES...`

use std::time::Instant;

use frep_artefact::{compile, ArtefactConfig, Artefacts, CompileLimits};
use frep_render::{encode, render_camera, CancelToken, ImageFormat, RenderSettings};
use frep_wire::{ArtefactSpec, CameraView, ImageEncoding};

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn main() {
    let rt = tokio::runtime::Runtime::new().expect("runtime");
    let dir = std::env::temp_dir().join(format!("frep-overhead-{}", std::process::id()));
    let service = Artefacts::new(ArtefactConfig::new(&dir)).expect("service");
    for path in std::env::args().skip(1) {
        let src = std::fs::read_to_string(&path).unwrap_or_default();
        let Ok(c) = compile(&src, None, &CompileLimits::default()) else {
            continue;
        };
        let (mut cli, mut srv) = (Vec::new(), Vec::new());
        let mut last_key = String::new();
        for round in 0..15 {
            let yaw = 30.0 + round as f64 * 0.5;
            let t = Instant::now();
            let s = RenderSettings {
                size: (512, 512),
                bounds: c.aabb(),
                quality: 75,
                inputs: c.inputs(&[]),
                yaw,
                ..Default::default()
            };
            let pool = service.image_pool();
            let img = render_camera(c.model(), &s, &s.camera(), &CancelToken::new(), pool)
                .expect("render");
            let bytes = encode(&img, ImageFormat::Jpeg, 75).expect("encode");
            pool.recycle(img);
            cli.push(t.elapsed().as_secs_f64() * 1e3);
            let spec = ArtefactSpec::Image {
                camera: CameraView {
                    yaw: yaw + 0.25,
                    ..CameraView::default()
                },
                width: 512,
                height: 512,
                format: ImageEncoding::Jpeg,
                quality: 75,
                section: None,
            };
            let t = Instant::now();
            let r = service
                .request(c.clone(), &[], spec, None)
                .expect("request");
            let body = rt.block_on(service.get(&r.key)).expect("get");
            srv.push(t.elapsed().as_secs_f64() * 1e3);
            assert!(body.bytes.len() > bytes.len() / 4);
            last_key = r.key;
        }
        // Let the last job's disk write finish, then time cached gets.
        while service.in_flight() > 0 {
            std::thread::sleep(std::time::Duration::from_millis(1));
        }
        let cached: Vec<f64> = (0..15)
            .map(|_| {
                let t = Instant::now();
                let b = rt.block_on(service.get(&last_key)).expect("cached");
                assert!(b.cached);
                t.elapsed().as_secs_f64() * 1e3
            })
            .collect();
        let (a, b) = (median(cli), median(srv));
        println!(
            "{:28} cli {a:7.2} ms  service {b:7.2} ms  ({:+.2} ms, {:+.1} %)  cached get {:.3} ms",
            path.rsplit('/').next().unwrap_or(&path),
            b - a,
            100.0 * (b - a) / a,
            median(cached)
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}
