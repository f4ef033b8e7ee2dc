//! The generated WebGL2 ray-casting shader of a model (frep-glsl's
//! `shader_for_model`, as `frep glsl` calls it) with its uniform table:
//! every constant and parameter a uniform, so a parameter change needs no
//! new shader, only `u_params`.

use frep_core::Inputs;
use frep_glsl::{shader_for_model, ShaderOptions};
use frep_wire::{ShaderArtefact, ShaderUniform};

use crate::compiled::Compiled;

/// The shader of `compiled` framing its box, `u_params` defaulting to
/// `inputs`' parameters.
pub fn shader(compiled: &Compiled, inputs: &Inputs) -> ShaderArtefact {
    let b = compiled.bounds();
    let opts = ShaderOptions {
        box_min: [b[0], b[1], b[2]],
        box_max: [b[3], b[4], b[5]],
        params: inputs.params.clone(),
        extra_x: inputs.extra_x.clone(),
        ..Default::default()
    };
    let s = shader_for_model(compiled.model(), &opts);
    ShaderArtefact {
        source: s.source,
        uniforms: s
            .uniforms
            .into_iter()
            .map(|u| ShaderUniform {
                name: u.name,
                ty: u.ty,
                values: u.values,
                description: u.description,
            })
            .collect(),
        bounds: b,
        statements: s.stats.statements as u32,
    }
}
