//! What several subcommands read the same way: the model box and the
//! parameters.
//!
//! The box is `--bounds` (hfp's `-b` forms: `v`, `min,max`, `xs,ys,zs`,
//! `x0,y0,z0,x1,y1,z1`), else the model file's `-- bounds: x0,y0,z0,x1,y1,z1`
//! comment line (the examples have one), else the model's extent found by
//! interval arithmetic, else hfp's default `[-10, 10]³`.

use anyhow::Context;
use frep_core::{Inputs, Model};
use frep_mesh::poly::bounds::{self, parse_box, BoxOrigin};

/// The box to work in, and where it came from (for messages): `--bounds`, else
/// [`frep_mesh::poly::bounds::model_box`] (the rule the server follows too).
pub fn model_box(
    arg: Option<&str>,
    source: &str,
    model: &Model,
    inputs: &Inputs,
) -> anyhow::Result<([f64; 6], &'static str)> {
    if let Some(b) = arg {
        let b = parse_box(b).map_err(|e| anyhow::anyhow!("--bounds: {e}"))?;
        return Ok((b, "--bounds"));
    }
    let (b, origin) = bounds::model_box(source, model, inputs);
    Ok((
        b,
        match origin {
            BoxOrigin::Comment => "the model's bounds comment",
            BoxOrigin::Extent => "detected extent",
            BoxOrigin::Default => "hfp default, no extent found",
        },
    ))
}

/// Comma-separated numbers of an option.
pub fn numbers(text: &str, option: &str) -> anyhow::Result<Vec<f64>> {
    text.split(',')
        .map(|t| {
            t.trim()
                .parse::<f64>()
                .with_context(|| format!("{option}: `{}` is not a number", t.trim()))
        })
        .collect()
}

/// The model's parameters `a[]` from `--param a1,a2,…`.
pub fn inputs(param: Option<&str>) -> anyhow::Result<Inputs> {
    Ok(match param {
        Some(p) => Inputs::with_params(&numbers(p, "--param")?),
        None => Inputs::default(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_the_bounds_comment() {
        let src =
            "-- description: x\n-- bounds: -1,-2,-3,1,2,3\nmy_model(x[3], a[1]) { my_model = 1; }";
        assert_eq!(
            bounds::bounds_from_source(src),
            Some([-1.0, -2.0, -3.0, 1.0, 2.0, 3.0])
        );
        assert_eq!(bounds::bounds_from_source("m(x[3], a[1]) { m = 1; }"), None);
    }

    #[test]
    fn falls_back_to_the_extent() {
        let src = "my_model(x[3], a[1]) { my_model = 4 - x[1]^2 - x[2]^2 - x[3]^2; }";
        let model = Model::compile(src).unwrap();
        let (b, origin) = model_box(None, src, &model, &Inputs::default()).unwrap();
        assert_eq!(origin, "detected extent");
        assert!(b[0] <= -2.0 && b[3] >= 2.0 && b[3] < 4.0, "{b:?}");
        let (b, _) = model_box(Some("3"), src, &model, &Inputs::default()).unwrap();
        assert_eq!(b, [-3.0, -3.0, -3.0, 3.0, 3.0, 3.0]);
        assert!(inputs(Some("1,x")).is_err());
    }
}
