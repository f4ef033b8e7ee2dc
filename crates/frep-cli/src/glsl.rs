//! `frep glsl`: the WebGL2 ray-casting shader of a model.

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use anyhow::{bail, Context};
use frep_glsl::{shader_for_model, ShaderOptions};

/// A box `x0,y0,z0,x1,y1,z1` (six numbers separated by commas and/or
/// spaces), lower corner first.
pub(crate) fn parse_bounds(text: &str) -> anyhow::Result<([f64; 3], [f64; 3])> {
    let nums: Vec<f64> = text
        .split(|c: char| c == ',' || c.is_whitespace())
        .filter(|t| !t.is_empty())
        .map(|t| {
            t.parse::<f64>()
                .with_context(|| format!("bounds: `{t}` is not a number"))
        })
        .collect::<Result<_, _>>()?;
    if nums.len() != 6 {
        bail!(
            "bounds: expected six numbers x0,y0,z0,x1,y1,z1, got {}",
            nums.len()
        );
    }
    let (lo, hi) = ([nums[0], nums[1], nums[2]], [nums[3], nums[4], nums[5]]);
    if (0..3).any(|k| lo[k] >= hi[k] || !lo[k].is_finite() || !hi[k].is_finite()) {
        bail!("bounds: the lower corner must be below the upper one on every axis: {text}");
    }
    Ok((lo, hi))
}

/// The box of a model's `-- bounds: x0,y0,z0,x1,y1,z1` comment line, if any.
pub(crate) fn bounds_comment(source: &str) -> Option<anyhow::Result<([f64; 3], [f64; 3])>> {
    source.lines().find_map(|l| {
        let rest = l.trim_start().strip_prefix("--")?.trim_start();
        let rest = rest.strip_prefix("bounds:")?;
        Some(parse_bounds(rest))
    })
}

/// Writes the annotated shader to `out` and its uniforms to `out.json`
/// (`OUT.frag` gives `OUT.frag.json`).
pub fn run(
    path: &Path,
    body: Option<String>,
    out: &Path,
    bounds: Option<String>,
) -> anyhow::Result<ExitCode> {
    let (source, model) = match crate::load(path, body)? {
        Ok(m) => m,
        Err(rendered) => {
            eprint!("{rendered}");
            return Ok(ExitCode::from(1));
        }
    };
    let mut opts = ShaderOptions::default();
    let bounds = match bounds {
        Some(b) => Some(parse_bounds(&b)?),
        None => bounds_comment(&source).transpose()?,
    };
    if let Some((lo, hi)) = bounds {
        opts.box_min = lo;
        opts.box_max = hi;
    }
    let shader = shader_for_model(&model, &opts);
    std::fs::write(out, shader.annotated_source())
        .with_context(|| format!("cannot write {}", out.display()))?;
    let mut json = PathBuf::from(out).into_os_string();
    json.push(".json");
    let json = PathBuf::from(json);
    std::fs::write(&json, shader.uniforms_json())
        .with_context(|| format!("cannot write {}", json.display()))?;
    eprintln!(
        "{}: {} statements per field flavour, {} constants as uniforms, box [{}, {}]",
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bounds_parse() {
        assert_eq!(
            parse_bounds("-1,-2,-3,1,2,3").unwrap(),
            ([-1.0, -2.0, -3.0], [1.0, 2.0, 3.0])
        );
        assert_eq!(
            parse_bounds(" -1, -1 -1 ,1,1,1 ").unwrap(),
            ([-1.0; 3], [1.0; 3])
        );
        assert!(parse_bounds("1,2,3").is_err());
        assert!(parse_bounds("1,1,1,-1,-1,-1").is_err());
        assert!(parse_bounds("a,1,1,2,2,2").is_err());
        let src =
            "-- description: x\n-- bounds: -0.85,-0.65,-1.05,0.85,0.65,1.1\nmy_model(x[3]) {}";
        assert_eq!(
            bounds_comment(src).unwrap().unwrap(),
            ([-0.85, -0.65, -1.05], [0.85, 0.65, 1.1])
        );
        assert!(bounds_comment("my_model(x[3]) {}").is_none());
    }
}
