//! Generated shaders validate with glslangValidator (GLSL ES 3.00) and have
//! the promised structure.

mod common;

use common::{assert_valid, exhaustive, m1, m2, m3, m4, validate_vert};
use frep_core::ops::{BinaryOp, UnaryOp};
use frep_core::{Graph, Node, NodeId, Tape};
use frep_glsl::{fragment_shader, vertex_shader, ShaderOptions, ShaderTarget};

/// Deepest parenthesis nesting of any line of the generated model functions.
fn max_nesting(src: &str) -> usize {
    src.lines()
        .filter(|l| {
            l.starts_with("  float t") || l.starts_with("  vec2 i") || l.starts_with("  vec4 d")
        })
        .map(|l| {
            let (mut d, mut m) = (0usize, 0usize);
            for c in l.chars() {
                match c {
                    '(' => {
                        d += 1;
                        m = m.max(d)
                    }
                    ')' => d = d.saturating_sub(1),
                    _ => {}
                }
            }
            m
        })
        .max()
        .unwrap_or(0)
}

/// Live nodes as the generator sees them (a Check's guard is not needed).
fn live(tape: &Tape, outs: &[NodeId]) -> Vec<bool> {
    let mut live = vec![false; tape.len()];
    for o in outs {
        live[o.index()] = true;
    }
    for i in (0..tape.len()).rev() {
        if live[i] {
            match tape.nodes[i] {
                Node::Check(_, v) => live[v.index()] = true,
                n => n.children().for_each(|c| live[c.index()] = true),
            }
        }
    }
    live
}

fn assert_statements(src: &str, tape: &Tape) {
    let live = live(tape, &tape.outputs[..1]);
    for (i, l) in live.iter().enumerate() {
        if *l {
            for decl in [
                format!("float t{i} = "),
                format!("vec2 i{i} = "),
                format!("vec4 d{i} = "),
            ] {
                assert!(
                    src.contains(&decl),
                    "no statement `{decl}` for node {i}: {:?}",
                    tape.nodes[i]
                );
            }
        }
    }
}

#[test]
fn exhaustive_tape_validates() {
    let tape = exhaustive();
    let sh = fragment_shader(&tape, &ShaderOptions::default());
    assert_valid("exhaustive", &sh.source);
    assert_statements(&sh.source, &tape);
    assert!(
        max_nesting(&sh.source) <= 3,
        "nesting {}",
        max_nesting(&sh.source)
    );
    for helper in [
        "hf_mod(",
        "iv_mod(",
        "du_mod(",
        "hf_pow(",
        "iv_pow(",
        "du_pow(",
        "hf_powi(",
        "iv_powi(",
        "du_powi(",
        "hf_blend(hf_ru(",
        "iv_blend(iv_ri(",
        "du_blend(du_ru(",
        "hf_nan()",
        "iv_all()",
        "du_nan()",
        "u_xextra[0]",
        "u_params[1]",
        "hf_truthy(",
        "iv_select(",
        "du_select(",
        "hf_atan2(",
        "iv_atan2(",
    ] {
        assert!(sh.source.contains(helper), "missing {helper}");
    }
    let names: Vec<&str> = sh.uniforms.iter().map(|u| u.name.as_str()).collect();
    for n in [
        "u_params",
        "u_xextra",
        "u_consts",
        "u_resolution",
        "u_inv_view_proj",
        "u_box_min",
        "u_box_max",
        "u_max_steps",
        "u_background",
    ] {
        assert!(names.contains(&n), "uniform {n} not listed");
        assert!(
            sh.source.contains(&format!(" {n}")),
            "uniform {n} not declared"
        );
    }
    assert_eq!(sh.stats.params, 2);
}

#[test]
fn vertex_shader_validates() {
    validate_vert(vertex_shader()).unwrap();
}

#[test]
fn benchmark_models_validate() {
    for (name, tape) in [("M1", m1()), ("M2", m2()), ("M3", m3()), ("M4", m4())] {
        let opts = ShaderOptions {
            box_min: [-1.0; 3],
            box_max: [1.0; 3],
            ..ShaderOptions::default()
        };
        let sh = fragment_shader(&tape, &opts);
        assert_valid(name, &sh.source);
        assert_statements(&sh.source, &tape);
        assert!(max_nesting(&sh.source) <= 3);
        println!(
            "{name}: tape {} nodes, {} statements per flavour, {} constants, shader {} bytes",
            sh.stats.tape_nodes,
            sh.stats.statements,
            sh.stats.consts,
            sh.source.len()
        );
        // Each field flavour is defined once and called from few places.
        assert_eq!(sh.source.matches("field(o + d * t)").count(), 1);
        assert_eq!(sh.source.matches("field_grad(").count(), 2);
        assert_eq!(sh.source.matches("field_iv(").count(), 2);
    }
}

#[test]
fn deep_chain_is_flat() {
    // f = sin(f) * 1.01 + x, 100 levels deep: straight-line code only.
    let mut g = Graph::new();
    let x = g.x(0);
    let k = g.constant(1.01);
    let mut f = x;
    for _ in 0..100 {
        let s = g.unary(UnaryOp::Sin, f);
        let m = g.binary(BinaryOp::Mul, s, k);
        f = g.binary(BinaryOp::Add, m, x);
    }
    let tape = g.tape(&[f]);
    let sh = fragment_shader(&tape, &ShaderOptions::default());
    assert_valid("deep chain", &sh.source);
    assert_eq!(sh.stats.statements, tape.len());
    assert!(max_nesting(&sh.source) <= 3);
}

#[test]
fn constants_are_uniforms_and_shared() {
    let tape = m2();
    let sh = fragment_shader(&tape, &ShaderOptions::default());
    let consts = sh.uniforms.iter().find(|u| u.name == "u_consts").unwrap();
    let n = tape
        .nodes
        .iter()
        .filter(|n| n.const_value().is_some())
        .count();
    assert_eq!(sh.stats.consts, n);
    assert_eq!(consts.values.len(), n.div_ceil(4) * 4);
    assert!(consts.values.contains(&0.2f32));
    assert!(!sh.stats.consts_inlined);
    // No model constant appears as a literal in the model functions.
    for l in sh.source.lines().filter(|l| l.starts_with("  float t")) {
        assert!(!l.contains("0.2") && !l.contains("0.36"), "{l}");
    }
    // Changing only a constant's value keeps the source (no recompile).
    let mut tape2 = tape.clone();
    for n in tape2.nodes.iter_mut() {
        if let Some(v) = n.const_value() {
            *n = Node::constant(v * 1.5 + 0.01);
        }
    }
    let sh2 = fragment_shader(&tape2, &ShaderOptions::default());
    assert_eq!(sh.source, sh2.source);
    assert_ne!(sh.uniforms, sh2.uniforms);
}

#[test]
fn too_many_constants_are_inlined() {
    let tape = m4();
    let opts = ShaderOptions {
        max_uniform_consts: 3,
        ..ShaderOptions::default()
    };
    let sh = fragment_shader(&tape, &opts);
    assert!(sh.stats.consts_inlined);
    assert!(!sh.uniforms.iter().any(|u| u.name == "u_consts"));
    assert!(sh.source.contains("= 0.0625;"), "literal constants");
    assert_valid("inlined", &sh.source);
}

#[test]
fn viewer_target_validates() {
    for (name, tape) in [("M1", m1()), ("M3", m3()), ("M4", m4())] {
        let opts = ShaderOptions {
            box_min: [-1.0; 3],
            box_max: [1.0; 3],
            target: ShaderTarget::Viewer,
            ..ShaderOptions::default()
        };
        let sh = fragment_shader(&tape, &opts);
        assert_valid(name, &sh.source);
        assert!(sh.source.contains("#define HF_ATTRS 0"));
        // The same traversal as the standalone shader, one call site each.
        assert_eq!(sh.source.matches("field(o + d * t)").count(), 1);
        assert_eq!(sh.source.matches("hf_trace(o, d,").count(), 1);
        assert!(!sh.source.contains("u_inv_view_proj"));
        let names: Vec<&str> = sh.uniforms.iter().map(|u| u.name.as_str()).collect();
        for (u, _) in frep_glsl::SCENE_UNIFORMS {
            assert!(names.contains(&u), "uniform {u} not listed");
        }
        assert!(names.contains(&"u_consts"));
    }
}

#[test]
fn attributes_give_colour() {
    let mut g = Graph::new();
    let x = g.x(0);
    let y = g.x(1);
    let one = g.constant(1.0);
    let f = g.binary(BinaryOp::Sub, one, x);
    let r = g.unary(UnaryOp::Abs, y);
    let gr = g.constant(0.5);
    let b = g.unary(UnaryOp::Sin, x);
    let tape = g.tape(&[f, r, gr, b]);
    let sh = fragment_shader(&tape, &ShaderOptions::default());
    assert!(sh.stats.attributes);
    assert!(sh.source.contains("vec3 attrs(vec3 p)"));
    assert!(sh.source.contains("attrs(p)"));
    assert_valid("attrs", &sh.source);
    // Without attributes: the default material.
    let sh1 = fragment_shader(&g.tape(&[f]), &ShaderOptions::default());
    assert!(!sh1.source.contains("attrs("));
    // The studio's shader colours by attributes too.
    let viewer = ShaderOptions {
        target: ShaderTarget::Viewer,
        ..ShaderOptions::default()
    };
    let sh2 = fragment_shader(&tape, &viewer);
    assert!(sh2.source.contains("#define HF_ATTRS 1"));
    assert_valid("attrs viewer", &sh2.source);
}

#[test]
fn json_and_annotation() {
    let sh = fragment_shader(&m1(), &ShaderOptions::default());
    let j = sh.uniforms_json();
    assert!(j.starts_with("{\"uniforms\":["));
    assert!(j.contains("\"name\":\"u_consts\""));
    assert!(j.contains("\"type\":\"mat4\""));
    assert_eq!(j.matches('{').count(), j.matches('}').count());
    assert_eq!(j.matches('[').count(), j.matches(']').count());
    let a = sh.annotated_source();
    assert!(a.starts_with("#version 300 es\n// Uniforms"));
    assert!(a.contains("//   u_max_steps int = [512.0]"));
    assert_valid("annotated", &a);
}

#[test]
fn validator_rejects_bad_code() {
    if std::env::var("FREP_SKIP_GLSLANG").as_deref() == Ok("1") {
        return;
    }
    let bad = "#version 300 es\nprecision highp float;\nout vec4 c;\nvoid main() { c = vec4(undefined_name); }\n";
    assert!(common::validate_frag(bad).is_err());
    // GLSL ES 3.00 rules apply (no implicit int -> float conversion).
    let es = "#version 300 es\nprecision highp float;\nout vec4 c;\nvoid main() { float x = 1; c = vec4(x); }\n";
    assert!(common::validate_frag(es).is_err());
}

/// Writes the M1..M4 shaders to $FREP_GLSL_DUMP (a folder) when set.
#[test]
fn dump_when_asked() {
    let Ok(dir) = std::env::var("FREP_GLSL_DUMP") else {
        return;
    };
    for (name, tape) in [
        ("m1", m1()),
        ("m2", m2()),
        ("m3", m3()),
        ("m4", m4()),
        ("exhaustive", exhaustive()),
    ] {
        let opts = ShaderOptions {
            box_min: [-1.0; 3],
            box_max: [1.0; 3],
            ..ShaderOptions::default()
        };
        let sh = fragment_shader(&tape, &opts);
        std::fs::write(format!("{dir}/{name}.frag"), sh.annotated_source()).unwrap();
        std::fs::write(format!("{dir}/{name}.frag.json"), sh.uniforms_json()).unwrap();
    }
    std::fs::write(format!("{dir}/fullscreen.vert"), vertex_shader()).unwrap();
}

/// Every conformance model, example and corpus file compiles to a shader
/// that glslangValidator accepts (files the compiler rejects are skipped).
#[test]
fn hyperfun_files_validate() {
    let root = concat!(env!("CARGO_MANIFEST_DIR"), "/../..");
    let mut files = Vec::new();
    for dir in [
        format!("{root}/examples"),
        "/work/shared/hyperfun/conformance".to_string(),
        "/work/shared/hyperfun/corpus".to_string(),
    ] {
        match std::fs::read_dir(&dir) {
            Ok(rd) => {
                let mut v: Vec<_> = rd
                    .filter_map(|e| e.ok().map(|e| e.path()))
                    .filter(|p| p.extension().is_some_and(|e| e == "hf"))
                    .collect();
                v.sort();
                files.extend(v);
            }
            Err(_) => eprintln!("note: {dir} absent, skipped"),
        }
    }
    let mut failures = Vec::new();
    let (mut ok, mut skipped) = (0, 0);
    for f in &files {
        let src = std::fs::read_to_string(f).unwrap();
        let model = match frep_core::Model::compile(&src) {
            Ok(m) => m,
            Err(_) => {
                skipped += 1;
                continue;
            }
        };
        let t = std::time::Instant::now();
        let sh = frep_glsl::shader_for_model(&model, &ShaderOptions::default());
        let gen = t.elapsed();
        match common::validate_frag(&sh.source) {
            Ok(()) => ok += 1,
            Err(log) => failures.push(format!(
                "{}: {}",
                f.display(),
                log.lines().take(5).collect::<Vec<_>>().join(" | ")
            )),
        }
        if sh.stats.tape_nodes > 1000 {
            eprintln!(
                "{}: {} nodes, {} bytes, generated in {gen:?}",
                f.display(),
                sh.stats.tape_nodes,
                sh.source.len()
            );
        }
    }
    eprintln!(
        "{ok} shaders valid, {skipped} files not compiled, {} rejected",
        failures.len()
    );
    assert!(failures.is_empty(), "{}", failures.join("\n"));
    assert!(ok > 0);
}
