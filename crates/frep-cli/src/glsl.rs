//! `frep glsl`: the WebGL2 ray-casting shader of a model.

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use anyhow::Context;
use frep_glsl::{shader_for_model, ShaderOptions};

use crate::bounds;

/// Writes the annotated shader to `out` and its uniforms to `out.json`
/// (`OUT.frag` gives `OUT.frag.json`). The box is read as every subcommand
/// reads it ([`bounds::model_box`]); `param` gives the default `u_params`.
pub fn run(
    path: &Path,
    body: Option<String>,
    out: &Path,
    bounds_arg: Option<String>,
    param: Option<String>,
) -> anyhow::Result<ExitCode> {
    let (source, model) = match crate::load(path, body)? {
        Ok(m) => m,
        Err(rendered) => {
            eprint!("{rendered}");
            return Ok(ExitCode::from(1));
        }
    };
    let inputs = bounds::inputs(param.as_deref())?;
    let (b, from) = bounds::model_box(bounds_arg.as_deref(), &source, &model, &inputs)?;
    let opts = ShaderOptions {
        box_min: [b[0], b[1], b[2]],
        box_max: [b[3], b[4], b[5]],
        params: inputs.params.clone(),
        ..Default::default()
    };
    let shader = shader_for_model(&model, &opts);
    std::fs::write(out, shader.annotated_source())
        .with_context(|| format!("cannot write {}", out.display()))?;
    let mut json = PathBuf::from(out).into_os_string();
    json.push(".json");
    let json = PathBuf::from(json);
    std::fs::write(&json, shader.uniforms_json())
        .with_context(|| format!("cannot write {}", json.display()))?;
    eprintln!(
        "{}: {} statements per field flavour, {} constants as uniforms, box [{}, {}] ({from})",
        out.display(),
        shader.stats.statements,
        shader.stats.consts,
        fmt3(opts.box_min),
        fmt3(opts.box_max)
    );
    Ok(ExitCode::SUCCESS)
}

fn fmt3(v: [f64; 3]) -> String {
    format!("{} {} {}", v[0], v[1], v[2])
}
