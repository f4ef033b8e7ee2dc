//! Render time with and without a section plane (a quick measurement, not
//! a test): `cargo run --release -p frep-render --example section_time --
//! [SIZE] [REPS] [OUT_DIR]`. For each model (examples/sphere.hf,
//! examples/sake_pot.hf, or the files given in `FREP_MODELS`, comma
//! separated) at the default camera: the best of REPS renders whole, and
//! cut by a vertical plane through the box's centre whose cut face turns
//! to the camera. With OUT_DIR, both pictures are written as PNG.

use std::time::{Duration, Instant};

use frep_core::Model;
use frep_render::{
    encode, render, Aabb, CancelToken, ImageFormat, ImagePool, RenderSettings, Section,
};

fn bounds_of(src: &str) -> Aabb {
    let v: Vec<f64> = src
        .lines()
        .find_map(|l| l.trim().strip_prefix("-- bounds:"))
        .map(|l| l.split(',').filter_map(|s| s.trim().parse().ok()).collect())
        .unwrap_or_default();
    if v.len() == 6 {
        Aabb::new([v[0], v[1], v[2]], [v[3], v[4], v[5]])
    } else {
        Aabb::new([-10.0; 3], [10.0; 3])
    }
}

fn best(model: &Model, s: &RenderSettings, reps: usize) -> (Duration, frep_render::Image) {
    let mut best = Duration::MAX;
    let mut img = None;
    for _ in 0..reps.max(1) {
        let t = Instant::now();
        let i = render(model, s, &CancelToken::new(), &ImagePool::default()).expect("renders");
        best = best.min(t.elapsed());
        img = Some(i);
    }
    (best, img.expect("at least one render"))
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let size: u32 = args.first().and_then(|a| a.parse().ok()).unwrap_or(512);
    let reps: usize = args.get(1).and_then(|a| a.parse().ok()).unwrap_or(5);
    let out = args.get(2);
    let root = format!("{}/../../examples", env!("CARGO_MANIFEST_DIR"));
    let files: Vec<String> = match std::env::var("FREP_MODELS") {
        Ok(v) => v.split(',').map(str::to_string).collect(),
        Err(_) => vec![format!("{root}/sphere.hf"), format!("{root}/sake_pot.hf")],
    };
    for file in files {
        let src = std::fs::read_to_string(&file).expect("model file");
        let model = Model::compile(&src).expect("compiles");
        let whole = RenderSettings {
            size: (size, size),
            bounds: bounds_of(&src),
            ..Default::default()
        };
        let cam = whole.camera();
        let c = whole.bounds.center();
        // Vertical, through the centre, its normal towards the eye.
        let mut n = [cam.eye[0] - c[0], cam.eye[1] - c[1], 0.0];
        let len = (n[0] * n[0] + n[1] * n[1]).sqrt();
        n = n.map(|v| v / len);
        let cut = RenderSettings {
            section: Some(Section {
                normal: n,
                offset: n[0] * c[0] + n[1] * c[1],
            }),
            ..whole.clone()
        };
        let (tw, iw) = best(&model, &whole, reps);
        let (tc, ic) = best(&model, &cut, reps);
        let name = std::path::Path::new(&file)
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_default();
        println!(
            "{name} {size}²: whole {:.1} ms, cut {:.1} ms (best of {reps})",
            tw.as_secs_f64() * 1e3,
            tc.as_secs_f64() * 1e3
        );
        if let Some(dir) = out {
            for (tag, img) in [("whole", &iw), ("cut", &ic)] {
                let png = encode(img, ImageFormat::Png, 90).expect("encodes");
                std::fs::write(format!("{dir}/{name}-{tag}.png"), png).expect("writes");
            }
        }
    }
}
