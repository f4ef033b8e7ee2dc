//! The generated WebGL2 ray-casting shader of a model, with its uniform
//! table: frep-glsl's `shader_for_model` for the studio's viewer (its
//! camera, section plane and lighting; `ShaderTarget::Viewer`).
//! Every constant and parameter is a uniform, so a parameter change needs no
//! new shader, only `u_params`.

use frep_core::Inputs;
use frep_glsl::{shader_for_model, ShaderOptions, ShaderTarget};
use frep_wire::ShaderArtefact;

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
        target: ShaderTarget::Viewer,
        ..Default::default()
    };
    shader_for_model(compiled.model(), &opts).into_wire(b)
}
