//! `frep mesh`: polygonize a model and write the mesh.
//!
//! The box: `--bounds` (hfp's `-b` forms: `v`, `min,max`, `xs,ys,zs`, `x0,y0,z0,x1,y1,z1`),
//! else the model file's `-- bounds: x0,y0,z0,x1,y1,z1` comment line, else an automatic
//! extent found by interval arithmetic (cubes ±1, ±2, ±4, … ±1024 until the solid lies
//! strictly inside one, then tightened and grown by 5 %), else hfp's ±10 (an unbounded
//! solid, or none at all).

use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

use anyhow::{bail, Context};
use frep_core::Inputs;
use frep_mesh::export::{self, Format};
use frep_mesh::poly::bounds;
use frep_mesh::{polygonize, CancelToken, MeshSettings, Method, Progress, Resolution};

/// Options of `frep mesh`.
pub struct Options {
    pub model: PathBuf,
    pub output: PathBuf,
    pub bounds: Option<String>,
    pub depth: Option<u8>,
    pub grid: Option<String>,
    pub method: String,
    pub body: Option<String>,
    pub params: Option<String>,
    pub simplify: Option<f64>,
    pub quiet: bool,
}

fn bounds_comment(source: &str) -> Option<[f64; 6]> {
    source
        .lines()
        .take_while(|l| l.trim_start().starts_with("--") || l.trim().is_empty())
        .find_map(|l| l.trim_start().strip_prefix("-- bounds:"))
        .and_then(|b| bounds::parse_box(b.trim()).ok())
}

pub fn run(o: Options) -> anyhow::Result<ExitCode> {
    let format = Format::from_path(&o.output).with_context(|| {
        format!(
            "{}: unknown extension (use .stl, .obj, .ply, .glb or .3mf)",
            o.output.display()
        )
    })?;
    let method = match o.method.as_str() {
        "dc" => Method::DualContouring,
        "watertight" | "wt" => Method::Watertight,
        "mc" => Method::MarchingCubes,
        m => bail!("unknown method {m:?} (dc, watertight or mc)"),
    };
    let (source, model) = match crate::load(&o.model, o.body)? {
        Ok(m) => m,
        Err(rendered) => {
            eprint!("{rendered}");
            return Ok(ExitCode::from(1));
        }
    };
    let params: Vec<f64> = match &o.params {
        None => Vec::new(),
        Some(p) => p
            .split(',')
            .map(|t| {
                t.trim()
                    .parse()
                    .with_context(|| format!("--param: `{t}` is not a number"))
            })
            .collect::<Result<_, _>>()?,
    };
    let inputs = Inputs::with_params(&params);
    let (bounds, origin) = match &o.bounds {
        Some(b) => (
            bounds::parse_box(b).map_err(anyhow::Error::msg)?,
            "--bounds",
        ),
        None => match bounds_comment(&source) {
            Some(b) => (b, "the model's bounds comment"),
            None => match bounds::detect(&model, &inputs) {
                Some(b) => (b, "detected extent"),
                None => (bounds::HFP_DEFAULT, "hfp default, no extent found"),
            },
        },
    };
    let resolution = match (&o.grid, o.depth) {
        (Some(_), Some(_)) => bail!("give --depth or --grid, not both"),
        (Some(g), None) => bounds::parse_grid(g, &bounds).map_err(anyhow::Error::msg)?,
        (None, d) => Resolution::Depth(d.unwrap_or(7)),
    };
    let settings = MeshSettings {
        bounds,
        resolution,
        method,
        simplify: o.simplify,
        colors: true,
        inputs,
        ..Default::default()
    };
    if !o.quiet {
        eprintln!("box {:?} ({origin}), {resolution:?}, {method:?}", bounds);
    }
    let progress = Arc::new(Progress::new());
    let done = Arc::new(AtomicBool::new(false));
    let bar = (!o.quiet).then(|| {
        let (p, d) = (progress.clone(), done.clone());
        std::thread::spawn(move || {
            let mut err = std::io::stderr();
            while !d.load(Ordering::Relaxed) {
                let f = p.fraction();
                let w = (f * 40.0).round() as usize;
                let _ = write!(
                    err,
                    "\r[{}{}] {:3.0}% ({} / {})",
                    "#".repeat(w),
                    " ".repeat(40 - w),
                    f * 100.0,
                    p.done(),
                    p.estimated()
                );
                let _ = err.flush();
                std::thread::sleep(Duration::from_millis(100));
            }
            let _ = write!(err, "\r{:70}\r", "");
        })
    });
    let start = Instant::now();
    let result = polygonize(&model, &settings, &progress, &CancelToken::new());
    let elapsed = start.elapsed();
    done.store(true, Ordering::Relaxed);
    if let Some(b) = bar {
        let _ = b.join();
    }
    let mesh = result.context("polygonizing")?;
    write_mesh(&mesh, format, &o.output)?;
    println!(
        "{} triangles, {} vertices, {:.3} s",
        mesh.triangles.len(),
        mesh.vertex_count(),
        elapsed.as_secs_f64()
    );
    Ok(ExitCode::SUCCESS)
}

fn write_mesh(mesh: &frep_mesh::Mesh, format: Format, path: &Path) -> anyhow::Result<()> {
    let file =
        std::fs::File::create(path).with_context(|| format!("cannot create {}", path.display()))?;
    let mut w = std::io::BufWriter::new(file);
    export::write(mesh, format, &mut w).with_context(|| format!("writing {}", path.display()))?;
    w.flush()
        .with_context(|| format!("writing {}", path.display()))?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_the_bounds_comment() {
        let src =
            "-- description: x\n-- bounds: -1,-2,-3,1,2,3\nmy_model(x[3], a[1]) { my_model = 1; }";
        assert_eq!(bounds_comment(src), Some([-1.0, -2.0, -3.0, 1.0, 2.0, 3.0]));
        assert_eq!(
            bounds_comment("my_model(x[3], a[1]) { my_model = 1; }"),
            None
        );
    }
}
