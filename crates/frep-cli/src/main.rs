//! `frep`: the command line of the frep FRep modelling system.

mod bounds;
mod eval;
mod folder;
mod format;
mod glsl;
mod mesh;
mod render;
mod serve;

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use anyhow::Context;
use clap::{Parser, Subcommand};
use frep_core::{CompileOptions, Model};

#[derive(Parser)]
#[command(
    name = "frep",
    version,
    about = "FRep / HyperFun modelling from the command line"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Evaluate a model at points read from standard input, one per line:
    /// `x y z` followed by the model's a[] values when it takes any.
    Eval {
        /// The HyperFun model (.hf).
        model: PathBuf,
        /// The body to evaluate (default: my_model, else the first).
        #[arg(long)]
        body: Option<String>,
    },
    /// Polygonize a model and write the mesh (.stl, .obj, .ply, .glb or .3mf); prints
    /// triangles, vertices and time. Box: --bounds, else the file's `-- bounds:` comment,
    /// else the detected extent, else hfp's ±10.
    Mesh(mesh::Options),
    /// Check a model: print its diagnostics, or a summary.
    Check {
        /// The HyperFun model (.hf).
        model: PathBuf,
        /// The body to compile (default: my_model, else the first).
        #[arg(long)]
        body: Option<String>,
    },
    /// Write the WebGL2 (GLSL ES 3.00) ray-casting fragment shader of a
    /// model, annotated with its uniforms, and the uniforms as JSON
    /// (`OUT.json`). Every constant is a uniform: editing a number of the
    /// model only changes the JSON.
    Glsl {
        /// The HyperFun model (.hf).
        model: PathBuf,
        /// The fragment shader to write; the uniforms go to OUT.json.
        #[arg(short, long)]
        output: PathBuf,
        /// The body to compile (default: my_model, else the first).
        #[arg(long)]
        body: Option<String>,
        /// The box ray cast (`v`, `min,max`, `xs,ys,zs` or
        /// `x0,y0,z0,x1,y1,z1`; default: the model's `-- bounds:` line, else
        /// its detected extent, else [-10, 10]³).
        #[arg(long, allow_hyphen_values = true)]
        bounds: Option<String>,
        /// Default values of the parameters a[] (`u_params`), `a1,a2,…`.
        #[arg(long, allow_hyphen_values = true)]
        param: Option<String>,
    },
    /// Render an image of a model (or, with --views, a turntable view set).
    Render(render::RenderArgs),
    /// Sample a model on a grid: a PNG slice stack and an 8-bit 3D texture.
    Slices(render::SlicesArgs),
    /// Start the web server: the HTTP API, sessions and the studio, with
    /// the models in a SQLite database under --data (the examples loaded
    /// on first start).
    Serve(serve::ServeArgs),
}

/// Reads and compiles a model; a model error is printed with its source line
/// and caret and turned into exit status 1.
pub(crate) fn load(
    path: &Path,
    body: Option<String>,
) -> anyhow::Result<Result<(String, Model), String>> {
    let source =
        std::fs::read_to_string(path).with_context(|| format!("cannot read {}", path.display()))?;
    let opts = CompileOptions {
        body,
        ..Default::default()
    };
    Ok(match Model::compile_with(&source, &opts) {
        Ok(m) => Ok((source, m)),
        Err(d) => Err(d.render(&source, Some(&path.display().to_string()))),
    })
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Eval { model, body } => eval::run(&model, body),
        Command::Check { model, body } => eval::check(&model, body),
        Command::Glsl {
            model,
            output,
            body,
            bounds,
            param,
        } => glsl::run(&model, body, &output, bounds, param),
        Command::Render(args) => render::render(args),
        Command::Slices(args) => render::slices(args),
        Command::Mesh(options) => mesh::run(options),
        Command::Serve(args) => serve::run(args),
    };
    match result {
        Ok(code) => code,
        Err(e) => {
            eprintln!("frep: {e:#}");
            ExitCode::from(2)
        }
    }
}
