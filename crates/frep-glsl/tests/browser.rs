//! Generated shaders render in a real browser: headless Chromium with
//! SwiftShader (software WebGL2), driven by `tests/browser/run.mjs`
//! (playwright-core). For M1–M4 and the android robot: the first frame at
//! 64² completes within 60 s, its inside/outside mask (orthographic view
//! down −z) matches a CPU reference sampled densely along the same rays,
//! and editing a constant changes only the uniforms, the image following
//! without a recompile.
//!
//! Needs `node`, `/usr/lib/chromium/chromium` (or `FREP_CHROMIUM`) and
//! `npm ci --prefix crates/frep-glsl/tests/browser`; fails with a clear
//! message when one is missing unless `FREP_SKIP_BROWSER=1`.

use std::path::{Path, PathBuf};
use std::process::Command;

mod common;

use frep_core::eval::batch::BatchEval;
use frep_core::{Inputs, Model};
use frep_glsl::{fragment_shader, shader_for_model, vertex_shader, Camera, Shader, ShaderOptions};
use serde_json::{json, Value};

const SIZE: usize = 64;
const TIMEOUT_MS: u64 = 60_000;
const BACKGROUND: [f32; 3] = [0.0, 1.0, 1.0];

fn harness_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/browser")
}

fn examples_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples")
}

/// Whether the browser tools are present; panics with what to install
/// unless FREP_SKIP_BROWSER=1 (then false).
fn browser_available() -> bool {
    let chromium =
        std::env::var("FREP_CHROMIUM").unwrap_or_else(|_| "/usr/lib/chromium/chromium".into());
    let mut missing = Vec::new();
    if Command::new("node").arg("--version").output().is_err() {
        missing.push("node (apt-get install -y nodejs npm)".to_string());
    }
    if !Path::new(&chromium).exists() {
        missing.push(format!(
            "Chromium at {chromium} (apt-get install -y chromium, or set FREP_CHROMIUM)"
        ));
    }
    if !harness_dir().join("node_modules/playwright-core").exists() {
        missing.push(format!(
            "playwright-core (npm ci --prefix {})",
            harness_dir().display()
        ));
    }
    if missing.is_empty() {
        return true;
    }
    if std::env::var("FREP_SKIP_BROWSER").as_deref() == Ok("1") {
        eprintln!("note: browser test skipped (FREP_SKIP_BROWSER=1); missing: {missing:?}");
        return false;
    }
    panic!(
        "the browser test needs: {}. Install them, or set FREP_SKIP_BROWSER=1 to skip.",
        missing.join("; ")
    );
}

/// The box of a `-- bounds: x0,y0,z0,x1,y1,z1` line.
fn bounds_of(source: &str) -> ([f64; 3], [f64; 3]) {
    let line = source
        .lines()
        .find_map(|l| l.trim().strip_prefix("-- bounds:"))
        .expect("the example has a bounds line");
    let v: Vec<f64> = line.split(',').map(|t| t.trim().parse().unwrap()).collect();
    ([v[0], v[1], v[2]], [v[3], v[4], v[5]])
}

/// The orthographic view down −z over the box: (camera, centre x, centre y,
/// half height shown).
fn view(lo: [f64; 3], hi: [f64; 3]) -> (Camera, f64, f64, f64) {
    let (cx, cy, cz) = (
        0.5 * (lo[0] + hi[0]),
        0.5 * (lo[1] + hi[1]),
        0.5 * (lo[2] + hi[2]),
    );
    let h = 0.5 * (hi[0] - lo[0]).max(hi[1] - lo[1]) * 1.05;
    let cam = Camera {
        eye: [cx, cy, hi[2] + 2.0 * (hi[2] - lo[2])],
        target: [cx, cy, cz],
        up: [0.0, 1.0, 0.0],
        fov_y_deg: 40.0,
        ortho_half_height: Some(h),
    };
    (cam, cx, cy, h)
}

/// CPU reference: per pixel (top row first), whether any of 256 samples
/// along the ray through the box has f >= 0.
fn reference_mask(model: &Model, lo: [f64; 3], hi: [f64; 3]) -> Vec<Vec<bool>> {
    let (_, cx, cy, h) = view(lo, hi);
    let mut ev = BatchEval::new(&model.point_tape());
    let inputs = Inputs {
        params: vec![0.0; model.a_dim],
        ..Default::default()
    };
    const N: usize = 256;
    let mut mask = vec![vec![false; SIZE]; SIZE];
    let (mut xs, mut ys, mut zs) = (vec![0.0; N], vec![0.0; N], vec![0.0; N]);
    let mut out = vec![0.0; N];
    for (row, mrow) in mask.iter_mut().enumerate() {
        let ndc_y = ((SIZE - 1 - row) as f64 + 0.5) / SIZE as f64 * 2.0 - 1.0;
        let y = cy + ndc_y * h;
        for (col, m) in mrow.iter_mut().enumerate() {
            let ndc_x = (col as f64 + 0.5) / SIZE as f64 * 2.0 - 1.0;
            let x = cx + ndc_x * h;
            if x < lo[0] || x > hi[0] || y < lo[1] || y > hi[1] {
                continue;
            }
            for k in 0..N {
                xs[k] = x;
                ys[k] = y;
                zs[k] = lo[2] + (hi[2] - lo[2]) * (k as f64 + 0.5) / N as f64;
            }
            ev.eval(&xs, &ys, &zs, &inputs, &mut out);
            *m = out.iter().any(|&f| f >= 0.0);
        }
    }
    mask
}

fn compile(source: &str) -> Model {
    Model::compile(source).unwrap_or_else(|d| panic!("{}", d.render(source, None)))
}

fn options(lo: [f64; 3], hi: [f64; 3]) -> ShaderOptions {
    let (cam, ..) = view(lo, hi);
    ShaderOptions {
        box_min: lo,
        box_max: hi,
        resolution: [SIZE as u32; 2],
        camera: Some(cam),
        background: BACKGROUND,
        ..Default::default()
    }
}

fn make_shader(model: &Model, lo: [f64; 3], hi: [f64; 3]) -> Shader {
    shader_for_model(model, &options(lo, hi))
}

fn uniform_values(sh: &Shader, name: &str) -> Vec<f32> {
    sh.uniforms
        .iter()
        .find(|u| u.name == name)
        .map(|u| u.values.clone())
        .unwrap_or_default()
}

/// Compares a browser mask with the reference: every differing pixel must
/// lie on the reference's silhouette (a 4-neighbour differs) and at most 3%
/// of the pixels may differ. Returns the number of differing pixels.
fn compare(name: &str, got: &[String], want: &[Vec<bool>]) -> usize {
    assert_eq!(got.len(), SIZE, "{name}: rows");
    let at = |r: isize, c: isize| -> Option<bool> {
        (r >= 0 && c >= 0 && (r as usize) < SIZE && (c as usize) < SIZE)
            .then(|| want[r as usize][c as usize])
    };
    let mut diff = 0;
    let mut pic = String::new();
    for (r, row) in got.iter().enumerate() {
        for (c, ch) in row.chars().enumerate() {
            assert_ne!(ch, 'M', "{name}: pixel ({r}, {c}) hit the step cap");
            let hit = ch == '#';
            let w = want[r][c];
            pic.push(match (hit, w) {
                (true, true) => '#',
                (false, false) => '.',
                (true, false) => '+',
                (false, true) => '-',
            });
            if hit != w {
                diff += 1;
                let (r, c) = (r as isize, c as isize);
                let edge = [(r - 1, c), (r + 1, c), (r, c - 1), (r, c + 1)]
                    .iter()
                    .any(|&(a, b)| at(a, b).is_some_and(|v| v != w));
                assert!(
                    edge,
                    "{name}: pixel ({r}, {c}) is {} in the browser, {} on the CPU, away from the silhouette",
                    if hit { "inside" } else { "outside" },
                    if w { "inside" } else { "outside" },
                );
            }
        }
        pic.push('\n');
    }
    assert!(
        diff * 100 <= 3 * SIZE * SIZE,
        "{name}: {diff} pixels differ from the CPU reference ('+' GPU only, '-' CPU only):\n{pic}"
    );
    diff
}

struct Case {
    name: String,
    /// None: only the first frame is checked (no CPU reference).
    model: Option<Model>,
    lo: [f64; 3],
    hi: [f64; 3],
    shader: Shader,
    /// A variant with edited constants: same source, other uniforms.
    edited: Option<(Model, Shader)>,
}

#[test]
fn shaders_render_in_chromium() {
    if !browser_available() {
        return;
    }
    let dir = std::env::temp_dir().join(format!("frep-glsl-browser-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let mut cases = Vec::new();
    for name in [
        "m1_sphere",
        "m2_spheres100",
        "m3_gyroid",
        "m4_rblend10",
        "android_robot",
    ] {
        let source = std::fs::read_to_string(examples_dir().join(format!("{name}.hf"))).unwrap();
        let (lo, hi) = bounds_of(&source);
        let model = compile(&source);
        let shader = make_shader(&model, lo, hi);
        // M1 with another radius: editing a number changes the uniforms only.
        let edited = (name == "m1_sphere").then(|| {
            assert!(source.contains("0.8 -"), "M1 is 0.8 - sqrt(...)");
            let m = compile(&source.replace("0.8 -", "0.45 -"));
            let s = make_shader(&m, lo, hi);
            (m, s)
        });
        cases.push(Case {
            name: name.into(),
            model: Some(model),
            lo,
            hi,
            shader,
            edited,
        });
    }
    // Every operation of the graph (its field has NaN regions and blends
    // with a parameter of 0): the first frame must complete.
    let (lo, hi) = ([-2.0; 3], [2.0; 3]);
    cases.push(Case {
        name: "exhaustive".into(),
        model: None,
        lo,
        hi,
        shader: fragment_shader(&common::exhaustive(), &options(lo, hi)),
        edited: None,
    });
    let vert = dir.join("fullscreen.vert");
    std::fs::write(&vert, vertex_shader()).unwrap();
    let mut jobs = Vec::new();
    for c in &cases {
        let frag = dir.join(format!("{}.frag", c.name));
        let uniforms = dir.join(format!("{}.frag.json", c.name));
        std::fs::write(&frag, c.shader.annotated_source()).unwrap();
        std::fs::write(&uniforms, c.shader.uniforms_json()).unwrap();
        let mut frames = Vec::new();
        if let Some((_, e)) = &c.edited {
            assert_eq!(
                e.source, c.shader.source,
                "{}: editing a constant changed the shader source",
                c.name
            );
            let (a, b) = (
                uniform_values(e, "u_consts"),
                uniform_values(&c.shader, "u_consts"),
            );
            assert_ne!(a, b, "{}: the edit did not change u_consts", c.name);
            frames.push(json!({ "u_consts": a }));
        }
        jobs.push(json!({
            "name": c.name,
            "frag": frag,
            "uniforms": uniforms,
            "width": SIZE,
            "height": SIZE,
            "timeoutMs": TIMEOUT_MS,
            "frames": frames,
        }));
    }
    let spec = dir.join("jobs.json");
    std::fs::write(
        &spec,
        serde_json::to_string(&json!({ "vert": vert, "jobs": jobs })).unwrap(),
    )
    .unwrap();
    let out = Command::new("node")
        .arg(harness_dir().join("run.mjs"))
        .arg(&spec)
        .output()
        .expect("node runs");
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "driver failed: {}\n{stdout}",
        String::from_utf8_lossy(&out.stderr)
    );
    let results: Vec<Value> = stdout
        .lines()
        .map(|l| serde_json::from_str(l).expect("driver JSON line"))
        .collect();
    assert_eq!(results.len(), cases.len(), "driver output:\n{stdout}");
    let mut report =
        String::from("model            statements  link ms  first frame ms  hits  diff px\n");
    for (c, r) in cases.iter().zip(&results) {
        assert_eq!(r["name"], c.name.as_str());
        assert!(
            r["ok"] == true,
            "{}: no first frame: {}",
            c.name,
            r["error"]
        );
        let frames = r["frames"].as_array().unwrap();
        let mask = |k: usize| -> Vec<String> {
            frames[k]["mask"]
                .as_array()
                .unwrap()
                .iter()
                .map(|s| s.as_str().unwrap().to_string())
                .collect()
        };
        let diff = match &c.model {
            Some(model) => {
                let want = reference_mask(model, c.lo, c.hi);
                assert!(
                    want.iter().flatten().any(|&b| b),
                    "{}: empty reference",
                    c.name
                );
                compare(&c.name, &mask(0), &want).to_string()
            }
            None => "-".to_string(),
        };
        let ms = frames[0]["ms"].as_f64().unwrap();
        assert!(ms < TIMEOUT_MS as f64, "{}: first frame {ms} ms", c.name);
        report.push_str(&format!(
            "{:<16} {:>10} {:>8.0} {:>15.0} {:>5} {:>8}\n",
            c.name,
            c.shader.stats.statements,
            r["linkMs"].as_f64().unwrap(),
            ms,
            frames[0]["hits"],
            diff
        ));
        if let Some((m, _)) = &c.edited {
            let want_e = reference_mask(m, c.lo, c.hi);
            compare(&format!("{} edited", c.name), &mask(1), &want_e);
            assert_ne!(
                mask(0),
                mask(1),
                "{}: the edit did not change the image",
                c.name
            );
            report.push_str(&format!(
                "{:<16} uniform edit, same program: frame {:.0} ms, {} hits\n",
                "",
                frames[1]["ms"].as_f64().unwrap(),
                frames[1]["hits"]
            ));
        }
    }
    eprintln!("{report}renderer: {}", results[0]["renderer"]);
    let _ = std::fs::remove_dir_all(&dir);
}
