//! Times and sizes of frep-render's outputs (formerly `#[ignore]`d timing
//! tests in frep-render):
//! - a 512² image encoded in each format;
//! - a 12-view 256² view set encoded and written in each format;
//! - a 128³ volume sampled, encoded and written as slices.
//!
//! WebP rows appear only where frep-render is built with its `webp` feature.
//! This crate builds it without.
//!
//! Run: `cargo bench -p frep-bench --bench output`.

use std::path::PathBuf;
use std::time::Instant;

use frep_render::synthetic::{sphere_hits, Spheres};
use frep_render::{
    cast_tiled, encode, render_view_set, sample_grid, shade, slice_files, view_set_files, Aabb,
    Camera, CancelToken, Image, ImageFormat, Lighting, OutFile, SliceOptions, ViewSetOptions,
};

fn main() {
    encoders_512();
    view_set_12x256();
    volume_128();
}

/// Writes `files` into `dir` (created), as `frep` does.
fn write_files(dir: &std::path::Path, files: &[OutFile]) -> std::io::Result<()> {
    std::fs::create_dir_all(dir)?;
    files
        .iter()
        .try_for_each(|f| std::fs::write(dir.join(&f.name), &f.bytes))
}

/// A fresh temporary folder (removed first if left over).
fn temp_dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("frep-bench-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    d
}

/// Sizes and encode times of a 512² synthetic render in each format.
fn encoders_512() {
    let b = Aabb::new([-1.0; 3], [1.0; 3]);
    let cam = Camera::orbit(&b, 30.0, 20.0, Some(35.0));
    let t = Instant::now();
    let hits = cast_tiled(&Spheres::lattice_m2(), &cam, 512, 512, 32);
    let cast_ms = t.elapsed().as_secs_f64() * 1e3;
    let t = Instant::now();
    let lattice = shade(&hits, &Lighting::default());
    let shade_ms = t.elapsed().as_secs_f64() * 1e3;
    println!("512x512 100-sphere lattice: cast {cast_ms:.1} ms, shade {shade_ms:.1} ms");
    let sphere: Image = shade(
        &sphere_hits(&cam, 512, 512, [0.0; 3], 0.8, None),
        &Lighting::default(),
    );
    for (name, img) in [("one sphere", sphere), ("100-sphere lattice", lattice)] {
        println!("-- {name}");
        for (f, q) in [
            (ImageFormat::Png, 0u8),
            (ImageFormat::Jpeg, 50),
            (ImageFormat::Jpeg, 75),
            (ImageFormat::Jpeg, 90),
            (ImageFormat::Webp, 50),
            (ImageFormat::Webp, 75),
            (ImageFormat::Webp, 90),
        ] {
            if encode(&img, f, q).is_err() {
                continue;
            }
            let n = 10;
            let t = Instant::now();
            let mut len = 0;
            for _ in 0..n {
                len = encode(&img, f, q).expect("encoded above").len();
            }
            let ms = t.elapsed().as_secs_f64() * 1e3 / n as f64;
            println!("512x512 {f:?} q{q}: {len} bytes, {ms:.2} ms");
        }
    }
}

/// A 12-view 256² turntable of the 100-sphere lattice in each format.
fn view_set_12x256() {
    let b = Aabb::new([-1.0; 3], [1.0; 3]);
    let scene = Spheres::lattice_m2();
    let t = Instant::now();
    let opts = ViewSetOptions::default();
    let set = render_view_set(&b, &opts, &CancelToken::new(), |cam, w, h| {
        shade(&cast_tiled(&scene, cam, w, h, 32), &Lighting::default())
    })
    .expect("not cancelled");
    println!(
        "render 12 views 256x256: {:.0} ms",
        t.elapsed().as_secs_f64() * 1e3
    );
    for (format, quality) in [
        (ImageFormat::Jpeg, 75),
        (ImageFormat::Webp, 75),
        (ImageFormat::Png, 0),
    ] {
        let set = set.clone().with_format(format, quality);
        let dir = temp_dir(&format!("view-set-{}", format.extension()));
        let t = Instant::now();
        let written = view_set_files(&set).map(|files| write_files(&dir, &files));
        if !matches!(written, Ok(Ok(()))) {
            let _ = std::fs::remove_dir_all(&dir);
            continue;
        }
        let ms = t.elapsed().as_secs_f64() * 1e3;
        let size = |f: &str| std::fs::metadata(dir.join(f)).map_or(0, |m| m.len());
        let views: u64 = set.index.views.iter().map(|v| size(&v.file)).sum();
        println!(
            "{format:?} q{quality}: views {views} B, sheet {} B, index {} B, write {ms:.0} ms",
            size(&format!("sheet.{}", format.extension())),
            size("index.json")
        );
        let _ = std::fs::remove_dir_all(&dir);
    }
}

/// A sphere of radius 0.8 at the origin, `f ≥ 0` inside.
fn sphere(xs: &[f64], ys: &[f64], zs: &[f64], out: &mut [f64]) {
    for i in 0..out.len() {
        out[i] = 0.8 * 0.8 - (xs[i] * xs[i] + ys[i] * ys[i] + zs[i] * zs[i]);
    }
}

/// Sampling and writing a 128³ volume of a sphere.
fn volume_128() {
    let b = Aabb::new([-1.0; 3], [1.0; 3]);
    let t = Instant::now();
    let g = sample_grid(&b, [128; 3], &CancelToken::new(), sphere).expect("not cancelled");
    let sample_ms = t.elapsed().as_secs_f64() * 1e3;
    let dir = temp_dir("volume");
    let t = Instant::now();
    let (idx, files) = slice_files(&g, &SliceOptions::default()).expect("slices encoded");
    write_files(&dir, &files).expect("slices written");
    let write_ms = t.elapsed().as_secs_f64() * 1e3;
    let size = |f: &str| std::fs::metadata(dir.join(f)).map_or(0, |m| m.len());
    let pngs: u64 = idx.pngs.iter().map(|f| size(f)).sum();
    println!(
        "128^3 sphere: sample {sample_ms:.1} ms, write {write_ms:.1} ms (scale {}), 128 PNGs {pngs} B, raw {} B",
        idx.mapping.scale,
        size("volume.raw")
    );
    let _ = std::fs::remove_dir_all(&dir);
}
