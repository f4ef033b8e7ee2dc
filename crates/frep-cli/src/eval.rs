//! `frep eval` and `frep check`.

use std::io::{BufRead, Write};
use std::path::Path;
use std::process::ExitCode;

use anyhow::{bail, Context};
use frep_core::{Inputs, PointEval};

use crate::format::g17;

/// Evaluates the model at each point read from standard input.
pub fn run(path: &Path, body: Option<String>) -> anyhow::Result<ExitCode> {
    let (_, model) = match crate::load(path, body)? {
        Ok(m) => m,
        Err(rendered) => {
            eprint!("{rendered}");
            return Ok(ExitCode::from(1));
        }
    };
    let mut ev = PointEval::new(model.point_tape());
    let stdin = std::io::stdin();
    let stdout = std::io::stdout();
    let mut out = std::io::BufWriter::new(stdout.lock());
    let mut inputs = Inputs::default();
    for (n, line) in stdin.lock().lines().enumerate() {
        let line = line.context("cannot read standard input")?;
        let line = line.trim();
        if line.is_empty() || line.starts_with('#') {
            continue;
        }
        let nums: Vec<f64> = line
            .split_whitespace()
            .map(|t| {
                t.parse::<f64>()
                    .with_context(|| format!("line {}: `{t}` is not a number", n + 1))
            })
            .collect::<Result<_, _>>()?;
        if nums.len() < 3 {
            bail!(
                "line {}: expected `x y z` and then the {} parameter(s) a[]",
                n + 1,
                model.a_dim
            );
        }
        if nums.len() > 3 + model.a_dim {
            bail!(
                "line {}: {} values given; the model takes x y z and {} parameter(s)",
                n + 1,
                nums.len(),
                model.a_dim
            );
        }
        inputs.params.clear();
        inputs.params.extend_from_slice(&nums[3..]);
        match ev.eval(nums[0], nums[1], nums[2], &inputs) {
            Ok(v) => {
                write!(out, "{}", g17(v))?;
                for k in 1..ev.outputs() {
                    // Attributes of a point whose value succeeded succeed too:
                    // their errors are in the value's guard chain.
                    let s = ev.output(k).unwrap_or(f64::NAN);
                    write!(out, " {}", g17(s))?;
                }
                writeln!(out)?;
            }
            Err(e) => writeln!(out, "error {e}")?,
        }
    }
    out.flush()?;
    Ok(ExitCode::SUCCESS)
}

/// Prints the diagnostics of a model, or a summary of it.
pub fn check(path: &Path, body: Option<String>) -> anyhow::Result<ExitCode> {
    let (_, model) = match crate::load(path, body)? {
        Ok(m) => m,
        Err(rendered) => {
            eprint!("{rendered}");
            return Ok(ExitCode::from(1));
        }
    };
    let tape = model.tape();
    println!("{}: ok", path.display());
    println!(
        "  bodies:     {} ({})",
        model.bodies.len(),
        model.bodies.join(", ")
    );
    println!("  compiled:   {}", model.body);
    println!(
        "  inputs:     x[{}], a[{}]{}",
        model.x_dim,
        model.a_dim,
        if model.has_attributes {
            format!(", s[{}]", model.s_dim)
        } else {
            String::new()
        }
    );
    println!(
        "  graph:      {} nodes ({} in the value's tape)",
        model.graph.len(),
        tape.len()
    );
    println!("  parameters: {}", model.a_dim);
    Ok(ExitCode::SUCCESS)
}
