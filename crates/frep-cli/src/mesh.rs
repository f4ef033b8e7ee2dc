//! `frep mesh`: polygonize a model and write the mesh.
//!
//! The box, the first of:
//! 1. `--bounds`, in hfp's `-b` forms: `v`, `min,max`, `xs,ys,zs`, `x0,y0,z0,x1,y1,z1`;
//! 2. the model file's `-- bounds: x0,y0,z0,x1,y1,z1` comment line;
//! 3. an automatic extent found by interval arithmetic. Cubes ±1, ±2, ±4, … ±1024 are tried
//!    until the solid lies strictly inside one; the box is then tightened and grown by 5 %;
//! 4. hfp's ±10, for an unbounded solid or none at all.

use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

use anyhow::{bail, Context};
use frep_mesh::export::{self, Format};
use frep_mesh::poly::bounds;
use frep_mesh::{polygonize, CancelToken, MeshSettings, Method, Progress, Resolution};

/// Options of `frep mesh`.
#[derive(clap::Args)]
pub struct Options {
    /// The HyperFun model (.hf).
    pub model: PathBuf,
    /// Output file; the extension picks the format.
    #[arg(short, long)]
    pub output: PathBuf,
    /// Bounding box in hfp's -b forms: v | min,max | xs,ys,zs | x0,y0,z0,x1,y1,z1.
    #[arg(short, long, allow_hyphen_values = true)]
    pub bounds: Option<String>,
    /// Octree depth: 2^depth cells along the longest side of the box (default 7).
    #[arg(short, long)]
    pub depth: Option<u8>,
    /// hfp-style grid instead of --depth: cells per axis, n or nx,ny,nz (2..=250).
    #[arg(short, long)]
    pub grid: Option<String>,
    /// dc (dual contouring, sharp features), watertight, or mc (uniform baseline).
    #[arg(short, long, default_value = "watertight")]
    pub method: String,
    /// The body to polygonize (default: my_model, else the first).
    #[arg(long)]
    pub body: Option<String>,
    /// Parameters `a[1], a[2], ...` as a comma-separated list.
    #[arg(long = "param", allow_hyphen_values = true)]
    pub params: Option<String>,
    /// Error-bounded simplification after meshing, as a fraction of the cell size.
    #[arg(long)]
    pub simplify: Option<f64>,
    /// Adaptive dual contouring (with --method dc): blocks of 2x2x2, 4x4x4, ... cells become one
    /// vertex where their collapse keeps the topology. That vertex must stay within this
    /// fraction of the cell size of all their crossings' tangent planes. E.g. 0.1: big polygons
    /// on flat regions, still a closed 2-manifold.
    #[arg(long)]
    pub adaptive: Option<f64>,
    /// No progress bar or box report.
    #[arg(short, long)]
    pub quiet: bool,
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
    if let Some(t) = o.adaptive {
        if method != Method::DualContouring {
            bail!("--adaptive needs --method dc");
        }
        if !(t >= 0.0 && t.is_finite()) {
            bail!("--adaptive takes a fraction of the cell size >= 0, not {t}");
        }
    }
    let (source, model) = match crate::load(&o.model, o.body)? {
        Ok(m) => m,
        Err(rendered) => {
            eprint!("{rendered}");
            return Ok(ExitCode::from(1));
        }
    };
    let inputs = crate::bounds::inputs(o.params.as_deref())?;
    let (bounds, origin) = crate::bounds::model_box(o.bounds.as_deref(), &source, &model, &inputs)?;
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
        adaptive: o.adaptive,
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
