//! Shared helpers of the integration tests: the golden files and the corpus.
#![allow(dead_code)]

use std::path::{Path, PathBuf};

/// One golden point: inputs (x y z then a[]) and the expected outcome.
#[derive(Debug, Clone)]
pub struct GoldenPoint {
    pub inputs: Vec<f64>,
    pub expected: Expected,
    pub line: usize,
}

#[derive(Debug, Clone)]
pub enum Expected {
    Values(Vec<f64>),
    Error(String),
}

/// A golden file: the model it belongs to, the body, and its points.
#[derive(Debug, Clone)]
pub struct Golden {
    pub name: String,
    pub body: String,
    pub points: Vec<GoldenPoint>,
}

pub fn data_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data")
}

/// The corpus of real models written by others, read from `shared/` beside
/// the checkout (never copied into the project); None when absent.
pub fn corpus_dir() -> Option<PathBuf> {
    let d = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared/hyperfun/corpus");
    if d.is_dir() {
        Some(d)
    } else {
        eprintln!(
            "NOTE: the HyperFun corpus ({}) is absent on this machine: corpus checks are skipped",
            d.display()
        );
        None
    }
}

pub fn parse_golden(name: &str, text: &str) -> Golden {
    let mut body = "my_model".to_string();
    let mut points = Vec::new();
    for (i, line) in text.lines().enumerate() {
        let line = line.trim();
        if let Some(rest) = line.strip_prefix('#') {
            if let Some(pos) = rest.find("body:") {
                body = rest[pos + 5..].trim().to_string();
            }
            continue;
        }
        if line.is_empty() {
            continue;
        }
        let (lhs, rhs) = line.split_once('|').expect("golden line has '|'");
        let inputs = lhs
            .split_whitespace()
            .map(|t| t.parse().expect("number"))
            .collect();
        let rhs = rhs.trim();
        let expected = if let Some(msg) = rhs.strip_prefix("error ") {
            Expected::Error(msg.trim().to_string())
        } else {
            Expected::Values(
                rhs.split_whitespace()
                    .map(|t| t.parse().expect("number"))
                    .collect(),
            )
        };
        points.push(GoldenPoint {
            inputs,
            expected,
            line: i + 1,
        });
    }
    Golden {
        name: name.to_string(),
        body,
        points,
    }
}

/// Every golden file whose model is available: (model source, golden).
pub fn golden_models() -> Vec<(String, Golden)> {
    let mut out = Vec::new();
    let corpus = corpus_dir();
    let mut files: Vec<_> = std::fs::read_dir(data_dir().join("golden"))
        .expect("golden dir")
        .map(|e| e.expect("entry").path())
        .collect();
    files.sort();
    for path in files {
        let name = path.file_stem().unwrap().to_string_lossy().to_string();
        let conf = data_dir().join("conformance").join(format!("{name}.hf"));
        let src = if conf.exists() {
            std::fs::read_to_string(conf).unwrap()
        } else if let Some(c) = &corpus {
            match std::fs::read_to_string(c.join(format!("{name}.hf"))) {
                Ok(s) => s,
                Err(_) => continue,
            }
        } else {
            continue;
        };
        let text = std::fs::read_to_string(&path).unwrap();
        out.push((src, parse_golden(&name, &text)));
    }
    out
}

/// 1e-9 relative or 1e-12 absolute.
pub fn close(a: f64, b: f64) -> bool {
    a == b || (a - b).abs() <= 1e-12 || (a - b).abs() <= 1e-9 * a.abs().max(b.abs())
}

/// How many golden models must be found: every conformance model, plus every
/// corpus model when the corpus is present.
pub fn expected_golden_models() -> usize {
    let count = |d: &Path| {
        std::fs::read_dir(d)
            .map(|r| {
                r.filter(|e| {
                    e.as_ref()
                        .is_ok_and(|e| e.path().extension().is_some_and(|x| x == "hf"))
                })
                .count()
            })
            .unwrap_or(0)
    };
    count(&data_dir().join("conformance")) + corpus_dir().map_or(0, |c| count(&c))
}
