//! `frep render` and `frep slices`.

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use anyhow::{bail, Context};
use frep_core::eval::batch::BatchEval;
use frep_core::{Inputs, Model};
use frep_render::{
    encode, render_camera, render_view_set, sample_grid, slice_files, view_set_files, Aabb,
    CancelToken, ImageFormat, ImagePool, ProgressivePlan, RenderLimits, RenderSettings,
    SliceOptions, ViewSetOptions,
};

use crate::bounds::{inputs, numbers};
use crate::folder::write_folder;

/// Options of `frep render`.
#[derive(clap::Args)]
pub struct RenderArgs {
    /// The HyperFun model (.hf).
    pub model: PathBuf,
    /// Output image (.png, .jpg, .webp); with --views, a folder.
    #[arg(short, long)]
    pub output: PathBuf,
    /// Image size `W,H` in pixels.
    #[arg(long, default_value = "512,512")]
    pub size: String,
    /// Turntable yaw in degrees (0: looking along +y).
    #[arg(long, default_value_t = 30.0, allow_hyphen_values = true)]
    pub yaw: f64,
    /// Pitch in degrees (90: looking straight down).
    #[arg(long, default_value_t = 20.0, allow_hyphen_values = true)]
    pub pitch: f64,
    /// Field of view in degrees (perspective).
    #[arg(long, default_value_t = 30.0)]
    pub fov: f64,
    /// Orthographic camera instead of perspective.
    #[arg(long)]
    pub ortho: bool,
    /// N views around the model: OUT is a folder with view_NNN images, a
    /// sprite sheet and index.json.
    #[arg(long)]
    pub views: Option<u32>,
    /// Pitches of the view rings for --views, e.g. `0,30` (default: --pitch).
    #[arg(long, allow_hyphen_values = true)]
    pub elevations: Option<String>,
    /// Model box `x0,y0,z0,x1,y1,z1` (default: the model's `-- bounds:`
    /// comment line, else its detected extent, else HyperFun's [-10,10]³).
    #[arg(long, allow_hyphen_values = true)]
    pub bounds: Option<String>,
    /// JPEG / WebP quality 1-100.
    #[arg(long, default_value_t = 85)]
    pub quality: u8,
    /// Parameter values `a[1],a[2],...`
    #[arg(long, allow_hyphen_values = true)]
    pub param: Option<String>,
    /// Ambient occlusion.
    #[arg(long)]
    pub ao: bool,
    /// Also write a quarter-resolution frame first, as OUT's name with
    /// `.coarse` before the extension.
    #[arg(long)]
    pub progressive: bool,
    /// The body to render (default: my_model, else the first).
    #[arg(long)]
    pub body: Option<String>,
}

/// Options of `frep slices`.
#[derive(clap::Args)]
pub struct SlicesArgs {
    /// The HyperFun model (.hf).
    pub model: PathBuf,
    /// Output folder: slice_NNN.png, volume.raw, volume.json.
    #[arg(short, long)]
    pub output: PathBuf,
    /// Model box `x0,y0,z0,x1,y1,z1` (default as for `frep render`).
    #[arg(long, allow_hyphen_values = true)]
    pub bounds: Option<String>,
    /// Grid resolution: N, or NX,NY,NZ.
    #[arg(long, default_value = "64")]
    pub grid: String,
    /// Parameter values `a[1],a[2],...`
    #[arg(long, allow_hyphen_values = true)]
    pub param: Option<String>,
    /// The body to sample (default: my_model, else the first).
    #[arg(long)]
    pub body: Option<String>,
}

fn load(path: &Path, body: Option<String>) -> anyhow::Result<Option<(String, Model)>> {
    match crate::load(path, body)? {
        Ok(m) => Ok(Some(m)),
        Err(rendered) => {
            eprint!("{rendered}");
            Ok(None)
        }
    }
}

fn model_box(
    arg: Option<&str>,
    source: &str,
    model: &Model,
    inputs: &Inputs,
) -> anyhow::Result<Aabb> {
    let (b, _) = crate::bounds::model_box(arg, source, model, inputs)?;
    Ok(Aabb::new([b[0], b[1], b[2]], [b[3], b[4], b[5]]))
}

/// `frep render`.
pub fn render(args: RenderArgs) -> anyhow::Result<ExitCode> {
    let Some((source, model)) = load(&args.model, args.body.clone())? else {
        return Ok(ExitCode::from(1));
    };
    let size = numbers(&args.size, "--size")?;
    let &[w, h] = size.as_slice() else {
        bail!("--size: expected W,H");
    };
    let max = f64::from(RenderLimits::default().max_side);
    if !(w >= 1.0 && h >= 1.0 && w <= max && h <= max) {
        bail!("--size: {w},{h} is outside 1..={max}");
    }
    let inputs = inputs(args.param.as_deref())?;
    let settings = RenderSettings {
        size: (w as u32, h as u32),
        yaw: args.yaw,
        pitch: args.pitch,
        fov: (!args.ortho).then_some(args.fov),
        bounds: model_box(args.bounds.as_deref(), &source, &model, &inputs)?,
        quality: args.quality.clamp(1, 100),
        ao: args.ao,
        inputs,
        ..Default::default()
    };
    // Nothing cancels a command-line render; the pool lets a view set's
    // renders reuse one another's bytes.
    let (cancel, pool) = (CancelToken::new(), ImagePool::default());
    if let Some(n) = args.views {
        // Views are JPEG unless the folder's name ends in another image
        // extension (e.g. `views.webp/`).
        let format = ImageFormat::from_path(&args.output).unwrap_or(ImageFormat::Jpeg);
        let opts = ViewSetOptions {
            views: n.max(1),
            elevations: match &args.elevations {
                Some(e) => numbers(e, "--elevations")?,
                None => vec![args.pitch],
            },
            size: settings.size,
            format,
            quality: settings.quality,
            fov_deg: settings.fov,
            start_yaw: args.yaw,
            sheet_columns: None,
        };
        let failed = std::sync::Mutex::new(None);
        let set = render_view_set(&settings.bounds, &opts, &cancel, |cam, w, h| {
            let s = RenderSettings {
                size: (w, h),
                ..settings.clone()
            };
            render_camera(&model, &s, cam, &cancel, &pool).unwrap_or_else(|e| {
                *failed.lock().unwrap_or_else(|p| p.into_inner()) = Some(e.to_string());
                frep_render::Image::filled(w, h, [0, 0, 0, 255])
            })
        });
        if let Some(e) = failed.into_inner().unwrap_or_else(|p| p.into_inner()) {
            bail!("{e}");
        }
        let set = set?;
        let files = view_set_files(&set)
            .with_context(|| format!("cannot write {}", args.output.display()))?;
        write_folder(&args.output, &files)?;
        return Ok(ExitCode::SUCCESS);
    }
    let format = ImageFormat::from_path(&args.output).with_context(|| {
        format!(
            "{}: the output must end in .png, .jpg or .webp",
            args.output.display()
        )
    })?;
    let cam = settings.camera();
    if args.progressive {
        let plan = ProgressivePlan::quarter_then_full(settings.size.0, settings.size.1);
        let step = plan.steps[0];
        if step.factor > 1 {
            let s = RenderSettings {
                size: (step.width, step.height),
                ..settings.clone()
            };
            let frame = render_camera(&model, &s, &cam, &cancel, &pool)?;
            let full = plan.to_full(&step, &frame);
            let stem = args
                .output
                .file_stem()
                .and_then(|s| s.to_str())
                .unwrap_or("out");
            let coarse = args
                .output
                .with_file_name(format!("{stem}.coarse.{}", format.extension()));
            write_image(&coarse, &encode(&full, format, settings.quality)?)?;
            pool.recycle(frame);
        }
    }
    let img = render_camera(&model, &settings, &cam, &cancel, &pool)?;
    write_image(&args.output, &encode(&img, format, settings.quality)?)?;
    Ok(ExitCode::SUCCESS)
}

fn write_image(path: &Path, bytes: &[u8]) -> anyhow::Result<()> {
    std::fs::write(path, bytes).with_context(|| format!("cannot write {}", path.display()))
}

/// `frep slices`.
pub fn slices(args: SlicesArgs) -> anyhow::Result<ExitCode> {
    let Some((source, model)) = load(&args.model, args.body.clone())? else {
        return Ok(ExitCode::from(1));
    };
    let inputs = inputs(args.param.as_deref())?;
    let bounds = model_box(args.bounds.as_deref(), &source, &model, &inputs)?;
    let g = numbers(&args.grid, "--grid")?;
    let n: [usize; 3] = match g.as_slice() {
        [n] => [*n as usize; 3],
        [a, b, c] => [*a as usize, *b as usize, *c as usize],
        _ => bail!("--grid: expected N or NX,NY,NZ"),
    };
    if n.iter().any(|&k| !(1..=2048).contains(&k)) {
        bail!("--grid: each size must be 1..=2048");
    }
    let tape = model.tape();
    // A batch is a grid of lines along x (see `sample_grid`): functions
    // of y and z are evaluated once per row, of x once per column.
    let grid = sample_grid(&bounds, n, &CancelToken::new(), |xs, ys, zs, out| {
        BatchEval::new(&tape).eval_lines(0, n[0], true, xs, ys, zs, &inputs, out)
    })?;
    let (index, files) = slice_files(&grid, &SliceOptions::default())
        .with_context(|| format!("cannot write {}", args.output.display()))?;
    write_folder(&args.output, &files)?;
    println!(
        "{}: {}x{}x{} samples, byte = 128 + 127 * f / {}",
        args.output.display(),
        n[0],
        n[1],
        n[2],
        index.mapping.scale
    );
    Ok(ExitCode::SUCCESS)
}
