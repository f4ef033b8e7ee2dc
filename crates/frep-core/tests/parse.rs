//! Parses every real model of the shared corpus and every conformance model.

use std::path::{Path, PathBuf};

use frep_core::ast::{Expr, Stmt};
use frep_core::parse;

/// The shared HyperFun corpus: `$FREP_HYPERFUN_CORPUS`, else
/// `<workspace>/../shared/hyperfun/corpus` (a checkout beside `shared/`), else
/// one level further up (a worktree under `wt/`).
fn corpus_dir() -> Option<PathBuf> {
    if let Some(dir) = std::env::var_os("FREP_HYPERFUN_CORPUS") {
        return Some(PathBuf::from(dir));
    }
    let manifest = Path::new(env!("CARGO_MANIFEST_DIR"));
    [
        "../../../shared/hyperfun/corpus",
        "../../../../shared/hyperfun/corpus",
    ]
    .iter()
    .map(|rel| manifest.join(rel))
    .find(|p| p.is_dir())
}

fn hf_files(dir: &Path) -> Vec<PathBuf> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "hf"))
        .collect();
    files.sort();
    files
}

fn parse_all(files: &[PathBuf]) {
    for f in files {
        let src = std::fs::read_to_string(f).unwrap_or_else(|e| panic!("{}: {e}", f.display()));
        if let Err(d) = parse(&src) {
            panic!("{}", d.render(&src, Some(&f.display().to_string())));
        }
    }
}

#[test]
fn corpus_parses() {
    let Some(dir) = corpus_dir() else {
        println!("the shared HyperFun corpus is absent: skipping corpus_parses");
        return;
    };
    let files = hf_files(&dir);
    assert_eq!(files.len(), 21, "{}", dir.display());
    parse_all(&files);
}

#[test]
fn conformance_models_parse() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/conformance");
    let files = hf_files(&dir);
    assert_eq!(
        files.len(),
        47,
        "the conformance models in {}",
        dir.display()
    );
    parse_all(&files);
}

#[test]
fn builtins_model_shape() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/conformance");
    let src = std::fs::read_to_string(dir.join("lang_builtins.hf")).expect("read");
    let p = parse(&src).expect("parse");
    let b = &p.bodies[0];
    assert_eq!(b.name.name, "my_model");
    assert_eq!(b.stmts.len(), 2);
    assert!(matches!(&b.stmts[0], Stmt::Assign { target, .. } if target.name == "u"));
    // `... + 2^-1 - -x[2]^2`: the last operator is the subtraction of (-x[2])^2.
    match &b.result {
        Expr::Binary { op, rhs, .. } => {
            assert_eq!(*op, frep_core::ast::BinaryOp::Sub);
            match &**rhs {
                Expr::Binary { op, lhs, .. } => {
                    assert_eq!(*op, frep_core::ast::BinaryOp::Pow);
                    assert!(matches!(
                        &**lhs,
                        Expr::Unary {
                            op: frep_core::ast::UnaryOp::Minus,
                            ..
                        }
                    ));
                }
                e => panic!("{e:?}"),
            }
        }
        e => panic!("{e:?}"),
    }
}

/// The debug form of a program without byte offsets (lines and columns kept).
fn without_offsets(p: &frep_core::ast::Program) -> String {
    let text = format!("{p:?}");
    let mut out = String::with_capacity(text.len());
    let mut rest = text.as_str();
    while let Some(i) = rest.find("start: ") {
        out.push_str(&rest[..i]);
        let after = &rest[i..];
        let j = after.find("line: ").unwrap_or(after.len());
        rest = &after[j..];
    }
    out.push_str(rest);
    out
}

#[test]
fn crlf_file_parses_like_lf() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/conformance");
    for name in ["lang_control.hf", "lang_bodies.hf", "attr_color.hf"] {
        let src = std::fs::read_to_string(dir.join(name)).expect("read");
        let crlf = src.replace('\n', "\r\n");
        let a = parse(&src).expect("LF");
        let b = parse(&crlf).expect("CRLF");
        assert_eq!(without_offsets(&a), without_offsets(&b), "{name}");
    }
}
