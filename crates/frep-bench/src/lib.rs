//! Benchmarks of frep, and the anchor implementations they are compared with.
//!
//! - The benchmark models M1–M4 are defined once, in
//!   `shared/notes/rendering-and-meshing.md`.
//! - Their HyperFun sources live in the workspace's `examples/` folder
//!   (`m1_sphere.hf` … `m4_rblend10.hf`).
//! - The `anchors` module builds the same fields in fidget. It is behind the
//!   `anchors` feature, so that ordinary workspace builds do not compile fidget.
//! - `to_fidget` translates any compiled frep model into a fidget tree. So the
//!   `core` benchmark can run the same evaluations in both.

#![warn(missing_docs)]

pub mod alloc;

use frep_render::camera::Projection;
use frep_render::{Aabb, Camera};
#[cfg(feature = "anchors")]
pub mod anchors;
#[cfg(feature = "anchors")]
pub mod to_fidget;

/// The benchmark box: every model is measured on `[-1, 1]³`.
pub const BOX_MIN: f32 = -1.0;
/// Upper corner of the benchmark box, on every axis.
pub const BOX_MAX: f32 = 1.0;

/// Points of a regular `n × n × n` grid of cell centres over the benchmark
/// box, as three coordinate slices (the layout bulk evaluators take).
pub fn grid_points(n: usize) -> [Vec<f32>; 3] {
    let step = (BOX_MAX - BOX_MIN) / n as f32;
    let coord = |i: usize| BOX_MIN + (i as f32 + 0.5) * step;
    let total = n * n * n;
    let mut xs = Vec::with_capacity(total);
    let mut ys = Vec::with_capacity(total);
    let mut zs = Vec::with_capacity(total);
    for k in 0..n {
        for j in 0..n {
            for i in 0..n {
                xs.push(coord(i));
                ys.push(coord(j));
                zs.push(coord(k));
            }
        }
    }
    [xs, ys, zs]
}

/// The cells of a regular `n × n × n` subdivision of the benchmark box, as
/// `[lo, hi]` bounds per axis (what an interval evaluator prunes).
pub fn grid_boxes(n: usize) -> Vec<[[f32; 2]; 3]> {
    let step = (BOX_MAX - BOX_MIN) / n as f32;
    let span = |i: usize| [BOX_MIN + i as f32 * step, BOX_MIN + (i + 1) as f32 * step];
    let mut boxes = Vec::with_capacity(n * n * n);
    for k in 0..n {
        for j in 0..n {
            for i in 0..n {
                boxes.push([span(i), span(j), span(k)]);
            }
        }
    }
    boxes
}

/// The workspace's `examples/` folder.
pub const EXAMPLES_DIR: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../../examples");

/// The example models (file name, source) whose file names contain `filter`,
/// sorted by name. Where `filter` starts with `=`, the name must be the rest,
/// with or without `.hf`.
pub fn example_sources(filter: &str) -> Vec<(String, String)> {
    let mut files: Vec<String> = std::fs::read_dir(EXAMPLES_DIR)
        .expect("the workspace's examples folder")
        .filter_map(|e| e.ok())
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .filter(|n| {
            n.ends_with(".hf")
                && match filter.strip_prefix('=') {
                    Some(exact) => n == exact || n.strip_suffix(".hf") == Some(exact),
                    None => n.contains(filter),
                }
        })
        .collect();
    files.sort();
    files
        .into_iter()
        .map(|f| {
            let src =
                std::fs::read_to_string(format!("{EXAMPLES_DIR}/{f}")).expect("example source");
            (f, src)
        })
        .collect()
}

/// The box of an example's `-- bounds: x0,y0,z0,x1,y1,z1` line, if it has a well-formed one.
pub fn bounds_line(src: &str) -> Option<[f64; 6]> {
    let b = src
        .lines()
        .find_map(|l| l.trim().strip_prefix("-- bounds:"))?;
    let v: Vec<f64> = b
        .split(',')
        .map(|s| s.trim().parse().ok())
        .collect::<Option<_>>()?;
    v.try_into().ok()
}

/// The box of an example's `-- bounds:` line, else hfp's default `[-10, 10]³`.
pub fn example_box(src: &str) -> Aabb {
    let v = bounds_line(src).unwrap_or([-10.0, -10.0, -10.0, 10.0, 10.0, 10.0]);
    Aabb::new([v[0], v[1], v[2]], [v[3], v[4], v[5]])
}

/// Which of the anchor models M1–M4 (0..4) the example file `file` is (names `m1_` … `m4_`).
pub fn anchor_of(file: &str) -> Option<usize> {
    ["m1_", "m2_", "m3_", "m4_"]
        .iter()
        .position(|p| file.starts_with(p))
}

/// The cube of `bounds`' longest side around its centre (`[x0, y0, z0, x1, y1, z1]`), as
/// `(centre, half side)`: the box both sides of a benchmark work in.
pub fn cube_of(bounds: [f64; 6]) -> ([f64; 3], f64) {
    let c = [0, 1, 2].map(|k| 0.5 * (bounds[k] + bounds[k + 3]));
    let half = 0.5
        * (0..3)
            .map(|k| bounds[k + 3] - bounds[k])
            .fold(0.0f64, f64::max);
    (c, half)
}

/// The cube the render benchmark's `top` view covers for the example `file` (source `src`):
/// `[-1, 1]³` for M1–M4 (fidget's anchors, file names `m1_` … `m4_`), else the cube of the
/// example's `-- bounds:` box ([`cube_of`]), as `(centre, half side)`.
pub fn top_cube(file: &str, src: &str) -> ([f64; 3], f64) {
    match bounds_line(src) {
        Some(b) if anchor_of(file).is_none() => cube_of(b),
        _ => ([0.0; 3], 1.0),
    }
}

/// fidget's native 3D view of the cube `(centre, half side)`: orthographic, looking down −z,
/// the cube's square filling the image; and the cube as a box.
pub fn top_view((c, h): ([f64; 3], f64)) -> (Camera, Aabb) {
    let cam = Camera::look_at(
        [c[0], c[1], c[2] + 3.0 * h],
        c,
        [0.0, 1.0, 0.0],
        Projection::Orthographic { half_extent: h },
    );
    (cam, Aabb::new(c.map(|v| v - h), c.map(|v| v + h)))
}

/// Positional command-line arguments of the timing examples, with defaults.
pub struct Args(Vec<String>);

impl Args {
    /// The process's arguments after the program name.
    pub fn from_env() -> Self {
        Args(std::env::args().skip(1).collect())
    }

    /// Argument `i`, or `default` when absent.
    pub fn get(&self, i: usize, default: &str) -> String {
        self.0
            .get(i)
            .cloned()
            .unwrap_or_else(|| default.to_string())
    }

    /// Argument `i` parsed as a number, or `default` when absent; exits with a message when malformed.
    pub fn num<T: std::str::FromStr>(&self, i: usize, default: &str) -> T {
        let v = self.get(i, default);
        v.parse().unwrap_or_else(|_| {
            eprintln!("argument {} ({v:?}) is not a number", i + 1);
            std::process::exit(2)
        })
    }

    /// A rayon pool of `threads` threads.
    pub fn pool(threads: usize) -> rayon::ThreadPool {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .expect("a thread pool")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn grids_cover_the_box() {
        let [xs, ys, zs] = grid_points(4);
        assert_eq!(xs.len(), 64);
        assert_eq!((xs[0], ys[0], zs[0]), (-0.75, -0.75, -0.75));
        assert_eq!(xs[63], 0.75);
        let boxes = grid_boxes(2);
        assert_eq!(boxes.len(), 8);
        assert_eq!(boxes[0], [[-1.0, 0.0]; 3]);
        assert_eq!(boxes[7], [[0.0, 1.0]; 3]);
    }
}
