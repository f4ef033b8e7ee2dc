//! The studio's completion table, generated from the kernel's own library.
//!
//! `web/src/editor/library.json` lists every hf* function of
//! [`frep_core::library::all`] with its display name, parameter names and
//! kinds, and its one-line doc, so the browser's completion and signature
//! help can never drift from what the compiler accepts. This test fails when
//! the committed file differs from the table; `FREP_BLESS=1 cargo test -p
//! frep-core --test library_table` rewrites it.

use std::path::PathBuf;

use frep_core::library::{all, ParamKind};

/// A JSON string literal (the table holds plain text: quotes, backslashes
/// and control characters are all that need escaping).
fn json_str(s: &str) -> String {
    let mut out = String::with_capacity(s.len() + 2);
    out.push('"');
    for ch in s.chars() {
        match ch {
            '"' => out.push_str("\\\""),
            '\\' => out.push_str("\\\\"),
            '\n' => out.push_str("\\n"),
            c if (c as u32) < 0x20 => out.push_str(&format!("\\u{:04x}", c as u32)),
            c => out.push(c),
        }
    }
    out.push('"');
    out
}

/// The table as JSON: one object per function, sorted by name.
fn table_json() -> String {
    let mut fns: Vec<_> = all().iter().collect();
    fns.sort_by_key(|f| f.name);
    let mut out = String::from("{\n  \"generatedBy\": \"cargo test -p frep-core --test library_table\",\n  \"functions\": [\n");
    for (i, f) in fns.iter().enumerate() {
        let params: Vec<String> = f
            .params
            .iter()
            .zip(f.param_names)
            .map(|(k, n)| {
                let kind = match k {
                    ParamKind::Scalar => "scalar",
                    ParamKind::Array => "array",
                };
                format!("{{ \"name\": {}, \"kind\": \"{kind}\" }}", json_str(n))
            })
            .collect();
        out.push_str(&format!(
            "    {{\n      \"name\": {},\n      \"display\": {},\n      \"params\": [{}],\n      \"doc\": {}\n    }}{}\n",
            json_str(f.name),
            json_str(f.display),
            params.join(", "),
            json_str(f.doc),
            if i + 1 < fns.len() { "," } else { "" }
        ));
    }
    out.push_str("  ]\n}\n");
    out
}

#[test]
fn every_function_is_documented_consistently() {
    for f in all() {
        assert_eq!(
            f.display.to_ascii_lowercase(),
            f.name,
            "{}: display name",
            f.name
        );
        assert_eq!(
            f.param_names.len(),
            f.params.len(),
            "{}: parameter names",
            f.name
        );
        assert!(!f.doc.is_empty(), "{}: doc", f.name);
        assert!(
            f.param_names.iter().all(|n| !n.is_empty()),
            "{}: empty name",
            f.name
        );
    }
}

#[test]
fn committed_table_matches_the_library() {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../web/src/editor/library.json");
    let want = table_json();
    if std::env::var_os("FREP_BLESS").is_some() {
        std::fs::write(&path, &want).expect("write library.json");
        return;
    }
    let have = std::fs::read_to_string(&path).unwrap_or_default();
    assert!(
        have == want,
        "{} is stale: run `FREP_BLESS=1 cargo test -p frep-core --test library_table`",
        path.display()
    );
}
