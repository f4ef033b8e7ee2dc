//! Times the model box of each HyperFun file given (the `-- bounds:` line,
//! else the detected extent) and a 256² render in it:
//! `cargo run --release -p frep-artefact --example extent -- FILES...`.

use std::time::Instant;

use frep_artefact::{compile, CompileLimits};
use frep_wire::{ArtefactSpec, CameraView, ImageEncoding};

fn main() {
    for path in std::env::args().skip(1) {
        let Ok(source) = std::fs::read_to_string(&path) else {
            eprintln!("{path}: cannot read");
            continue;
        };
        let t = Instant::now();
        let parsed = frep_core::Model::compile(&source);
        let compile_ms = t.elapsed().as_secs_f64() * 1e3;
        let nodes = parsed.map_or(0, |m| m.tape().len());
        let t = Instant::now();
        let c = match compile(&source, None, &CompileLimits::default()) {
            Ok(c) => c,
            Err(d) => {
                eprintln!("{path}: {}", d[0].message);
                continue;
            }
        };
        let box_ms = t.elapsed().as_secs_f64() * 1e3;
        let spec = ArtefactSpec::Image {
            camera: CameraView::default(),
            width: 256,
            height: 256,
            format: ImageEncoding::Png,
            quality: 90,
            section: None,
        };
        let t = Instant::now();
        let r = frep_artefact::compute(
            &c,
            &[],
            &spec,
            &Default::default(),
            &Default::default(),
            &Default::default(),
            &Default::default(),
        );
        let render_ms = t.elapsed().as_secs_f64() * 1e3;
        let name = path.rsplit('/').next().unwrap_or(&path);
        println!(
            "{name:50} {nodes:6} ops {:8} {:?} compile {compile_ms:7.1} ms, compile+box {box_ms:8.1} ms, render {render_ms:8.1} ms {}",
            c.bounds_origin().as_str(),
            c.bounds().map(|v| (v * 100.0).round() / 100.0),
            if r.is_ok() { "" } else { "FAILED" }
        );
    }
}
